//! WGSL printer (WebGPU: no tessellation stage).
//!
//! Every scheme becomes one module, `wgsl/<scheme>.wgsl`, holding the common
//! module's structs, constants and functions, the scheme's functions, the
//! bindings of [`abi::BINDINGS`] (group 0) and five entry points:
//!
//! | entry point | stage | work |
//! |---|---|---|
//! | `vertex_stage_main` | compute | the vertex stage for vertices `first .. first + count` |
//! | `patch_main` | compute | the patch stage of `class` for patches `first .. first + count` |
//! | `eval_main` | compute | `(level+1)²` samples of each patch into `samples` |
//! | `eval_vs` | vertex | instanced evaluation: vertex index = grid point, instance = patch |
//! | `shade_fs` | fragment | two-sided Lambert, orange ordinary / blue extraordinary |
//!
//! Packed `vec3` buffers are `array<f32>` read and written through small
//! `load_*`/`store_*` helpers. A buffer the Plan writes (`vertex_out`,
//! `control_points`) is declared twice at its one ABI binding: `NAME` as
//! `read_write` for the functions that write it, `NAME_ro` as `read` for the
//! functions that only read it. WGSL allows two variables at one binding as
//! long as no entry point uses both, so `eval_vs` (a vertex shader, where
//! writable storage is not allowed) and `eval_main` read `control_points_ro`
//! while `patch_main` writes `control_points`, all at binding 8. WGSL
//! reserved words and names that would shadow a module-scope name get a
//! trailing `_` (the `Params` field `class` is spelled `class_`; its offset is
//! the ABI's).
//!
//! Like every printer this one only spells the Plan: binaries fully
//! parenthesised as given, f32 literals in Rust's shortest round-trip digits
//! with the `f` suffix. WGSL has no `precise`: the shared edge evaluator is
//! one function called from one place, printed like every other.

use super::abi::{self, Binding, Kind};
use super::binop;
use super::{header_lines, resources_of};
use crate::outdir::GeneratedFile;
use crate::plan::*;
use std::cell::RefCell;
use std::collections::{BTreeSet, HashSet};

/// Print every scheme of the plan as one WGSL module each.
pub fn write(plan: &Plan, command: &str) -> Vec<GeneratedFile> {
    plan.schemes
        .iter()
        .map(|(module, entries)| {
            let mut w = Writer::new(plan, module, entries);
            w.file(command);
            GeneratedFile {
                path: format!("wgsl/{}.wgsl", module.name),
                contents: w.out.into_bytes(),
            }
        })
        .collect()
}

/// Entry points of every emitted module, with their stages.
pub const ENTRY_POINTS: &[(&str, &str)] = &[
    (abi::entry::VERTEX_STAGE, "compute"),
    (abi::entry::PATCH_STAGE, "compute"),
    (abi::entry::EVAL, "compute"),
    ("eval_vs", "vertex"),
    ("shade_fs", "fragment"),
];

/// Entry points of adaptive tessellation on the instanced path, emitted for
/// every scheme with `Entries::adaptive` (quads and triangles).
pub const ADAPTIVE_ENTRY_POINTS: &[(&str, &str)] = &[
    ("adaptive_classify_main", "compute"),
    ("eval_adaptive_main", "compute"),
    ("eval_adaptive_vs", "vertex"),
    ("adaptive_count_main", "compute"),
    ("adaptive_plan_main", "compute"),
    ("adaptive_scatter_main", "compute"),
    ("eval_adaptive_indirect_main", "compute"),
    ("eval_adaptive_indirect_vs", "vertex"),
];

pub use super::abi::{BUCKET_CHUNK, BUCKET_SLOTS, INDIRECT_X};

/// WGSL keywords and reserved words (WGSL §15), then the predeclared types
/// and built-in functions this printer uses: never used as a plain name.
const RESERVED: &str = "\
    alias break case const const_assert continue continuing default diagnostic discard \
    else enable false fn for if let loop override requires return struct switch true var \
    while NULL Self abstract active alignas alignof as asm asm_fragment async attribute \
    auto await become cast catch class co_await co_return co_yield coherent column_major \
    common compile compile_fragment concept const_cast consteval constexpr constinit \
    crate debugger decltype delete demote demote_to_helper do dynamic_cast enum explicit \
    export extends extern external fallthrough filter final finally friend from fxgroup \
    get goto groupshared highp impl implements import inline instanceof interface layout \
    lowp macro macro_rules match mediump meta mod module move mut mutable namespace new \
    nil noexcept noinline nointerpolation non_coherent noncoherent noperspective null \
    nullptr of operator package packoffset partition pass patch pixelfragment precise \
    precision premerge priv protected pub public readonly ref regardless register \
    reinterpret_cast require resource restrict self set shared sizeof smooth snorm \
    static static_assert static_cast std subroutine super target template this \
    thread_local throw trait try type typedef typeid typename typeof union unless unorm \
    unsafe unsized use using varying virtual volatile wgsl where with writeonly yield \
    abs array bool cos cross dot f16 f32 i32 mat4x4 normalize ptr sin sqrt texture_2d \
    textureLoad u32 vec2 vec3 vec4";

/// A name WGSL accepts: reserved words get a trailing `_`; a leading `__`
/// (reserved to the implementation) is spelled apart.
fn ident(name: &str) -> String {
    let mut s = name.to_string();
    if s.starts_with("__") {
        s = format!("x{s}");
    }
    if RESERVED.split_whitespace().any(|w| w == s) {
        s.push('_');
    }
    s
}

fn f32_lit(x: f32) -> String {
    let s = format!("{x:?}f");
    if x.is_sign_negative() {
        format!("({s})")
    } else {
        s
    }
}

/// Name of a `Params` field in WGSL.
fn param(field: &str) -> String {
    format!("params.{}", ident(field))
}

/// The read-only alias of a written buffer.
fn read_only_name(b: &Binding) -> String {
    format!("{}_ro", b.name)
}

/// Whether a binding is declared twice (read-write, and read-only alias).
fn aliased(b: &Binding) -> bool {
    b.written && b.resource.is_some()
}

/// Whether a binding is a packed `vec3` buffer.
fn packed(b: &Binding) -> bool {
    b.kind == Kind::Vec3Buffer
}

/// Base colours of the rendering entry point.
const ORDINARY_RGB: &str = "vec3<f32>(1.0f, 0.55f, 0.1f)";
const EXTRAORDINARY_RGB: &str = "vec3<f32>(0.2f, 0.4f, 1.0f)";

pub struct Writer<'a> {
    plan: &'a Plan,
    module: &'a Module,
    entries: &'a Entries,
    out: String,
    indent: usize,
    /// Names declared at module scope; locals are renamed around them.
    globals: HashSet<String>,
    /// Names of the locals of the function being printed.
    locals: Vec<String>,
    /// `(variable, store)` of the `load_*` / `store_*` helpers in use.
    accessors: RefCell<BTreeSet<(String, bool)>>,
}

impl<'a> Writer<'a> {
    fn new(plan: &'a Plan, module: &'a Module, entries: &'a Entries) -> Self {
        let mut globals: HashSet<String> = HashSet::new();
        for m in [&plan.common, module] {
            globals.extend(m.functions.iter().map(|f| ident(&f.name)));
            globals.extend(m.consts.iter().map(|c| ident(&c.name)));
            globals.extend(m.structs.iter().map(|s| ident(&s.name)));
        }
        for b in abi::BINDINGS {
            for name in [b.name.to_string(), read_only_name(b)] {
                globals.insert(format!("load_{name}"));
                globals.insert(format!("store_{name}"));
                globals.insert(name);
            }
        }
        for g in ["Params", "VsOut"] {
            globals.insert(g.to_string());
        }
        globals.extend(ENTRY_POINTS.iter().map(|(n, _)| n.to_string()));
        globals.extend(ADAPTIVE_ENTRY_POINTS.iter().map(|(n, _)| n.to_string()));
        Writer {
            plan,
            module,
            entries,
            out: String::new(),
            indent: 0,
            globals,
            locals: Vec::new(),
            accessors: RefCell::new(BTreeSet::new()),
        }
    }

    fn line(&mut self, s: &str) {
        if s.is_empty() {
            self.out.push('\n');
            return;
        }
        for _ in 0..self.indent {
            self.out.push_str("    ");
        }
        self.out.push_str(s);
        self.out.push('\n');
    }

    fn doc(&mut self, doc: &str) {
        for l in doc.lines() {
            self.line(format!("// {l}").trim_end());
        }
    }

    fn ty(&self, t: &Ty) -> String {
        match t {
            Ty::F32 => "f32".into(),
            Ty::U32 => "u32".into(),
            Ty::Bool => "bool".into(),
            Ty::Vec3 => "vec3<f32>".into(),
            Ty::Struct(i) => ident(&self.plan.common.structs[*i].name),
        }
    }

    fn fn_name(&self, r: FnRef) -> String {
        let f = match r {
            FnRef::Common(i) => &self.plan.common.functions[i],
            FnRef::Local(i) => &self.module.functions[i],
        };
        ident(&f.name)
    }

    fn file(&mut self, command: &str) {
        for h in header_lines(command) {
            self.line(&format!("// {h}"));
        }
        self.line("//");
        self.line(&format!(
            "// Scheme `{}` for WebGPU: compute entry points vertex_stage_main, patch_main and",
            self.module.name
        ));
        self.line("// eval_main; instanced evaluation eval_vs (vertex) and shade_fs (fragment).");
        // Functions first, into their own buffer, to learn which accessors they use.
        let head = std::mem::take(&mut self.out);
        let plan = self.plan;
        let module = self.module;
        self.section("Common module");
        self.doc(&plan.common.doc);
        self.line("");
        self.module_items(&plan.common);
        self.section(&format!("Scheme `{}`", module.name));
        self.doc(&module.doc);
        self.line("");
        self.module_items(module);
        self.entry_points();
        self.adaptive_entry_points();
        let body = std::mem::replace(&mut self.out, head);
        self.section("Bindings");
        self.bindings();
        self.accessor_fns();
        self.out.push_str(&body);
    }

    fn section(&mut self, title: &str) {
        if !self.out.ends_with("\n\n") {
            self.line("");
        }
        self.line(&format!("// ---- {title} ----"));
        self.line("");
    }

    fn bindings(&mut self) {
        self.line(
            "// The uniform block (abi::PARAMS): view_proj at byte 0, then u32s from byte 64.",
        );
        self.line("struct Params {");
        for (k, (name, doc)) in abi::PARAMS.iter().enumerate() {
            let ty = if k == 0 { "mat4x4<f32>" } else { "u32" };
            self.line(&format!(
                "    // offset {}: {doc}",
                abi::params_offset(name)
            ));
            self.line(&format!("    {}: {ty},", ident(name)));
        }
        self.line("}");
        for b in abi::BINDINGS {
            self.line("");
            self.line(&format!("// {}", b.doc));
            let decl = |access: &str, name: &str| {
                let elem = match b.kind {
                    Kind::U32Buffer => "u32",
                    _ => "f32",
                };
                format!(
                    "@group(0) @binding({}) var<storage, {access}> {name}: array<{elem}>;",
                    b.binding
                )
            };
            match b.kind {
                Kind::Table => self.line(&format!(
                    "@group(0) @binding({}) var {}: texture_2d<f32>;",
                    b.binding, b.name
                )),
                Kind::Uniform => self.line(&format!(
                    "@group(0) @binding({}) var<uniform> {}: Params;",
                    b.binding, b.name
                )),
                _ if aliased(b) => {
                    self.line(&decl("read_write", b.name));
                    self.line(
                        "// The same buffer, read-only, for the functions that only read it; no entry",
                    );
                    self.line("// point uses both declarations.");
                    self.line(&decl("read", &read_only_name(b)));
                }
                _ => {
                    let access = if b.written { "read_write" } else { "read" };
                    self.line(&decl(access, b.name));
                }
            }
        }
    }

    /// The `load_*` / `store_*` helpers of the packed `vec3` buffers in use.
    fn accessor_fns(&mut self) {
        let used: Vec<(String, bool)> = self.accessors.borrow().iter().cloned().collect();
        for (var, store) in used {
            self.line("");
            if store {
                self.line(&format!("// {var}[i] = v: the packed f32 triple at 3i."));
                self.line(&format!("fn store_{var}(i: u32, v: vec3<f32>) {{"));
                self.line("    let o: u32 = (3u * i);");
                self.line(&format!("    {var}[o] = v.x;"));
                self.line(&format!("    {var}[(o + 1u)] = v.y;"));
                self.line(&format!("    {var}[(o + 2u)] = v.z;"));
            } else {
                self.line(&format!("// {var}[i]: the packed f32 triple at 3i."));
                self.line(&format!("fn load_{var}(i: u32) -> vec3<f32> {{"));
                self.line("    let o: u32 = (3u * i);");
                self.line(&format!(
                    "    return vec3<f32>({var}[o], {var}[(o + 1u)], {var}[(o + 2u)]);"
                ));
            }
            self.line("}");
        }
    }

    fn module_items(&mut self, m: &Module) {
        for c in &m.consts {
            self.doc(&c.doc);
            match &c.value {
                ConstValue::U32(x) => self.line(&format!("const {}: u32 = {x}u;", ident(&c.name))),
                ConstValue::U32Array(xs) => {
                    let body: Vec<String> = xs.iter().map(|x| format!("{x}u")).collect();
                    self.line(&format!(
                        "var<private> {}: array<u32, {n}> = array<u32, {n}>({});",
                        ident(&c.name),
                        body.join(", "),
                        n = xs.len()
                    ));
                }
            }
            self.line("");
        }
        for s in &m.structs {
            self.line(&format!("struct {} {{", ident(&s.name)));
            for (n, t) in &s.fields {
                self.line(&format!("    {}: {},", ident(n), self.ty(t)));
            }
            self.line("}");
            self.line("");
        }
        for (i, f) in m.functions.iter().enumerate() {
            // Tessellation-stage-only functions (WGSL has no such stage).
            if std::ptr::eq(m, self.module) && self.entries.tess_only(i) {
                continue;
            }
            self.function(m, f);
            self.line("");
        }
    }

    /// Names of `f`'s locals: WGSL-safe, unique, not shadowing a global.
    fn name_locals(&mut self, f: &Function) {
        let mut names: Vec<String> = Vec::new();
        for l in &f.locals {
            let mut n = ident(&l.name);
            while self.globals.contains(&n) || names.contains(&n) {
                n.push('_');
            }
            names.push(n);
        }
        self.locals = names;
    }

    fn function(&mut self, m: &Module, f: &Function) {
        self.doc(&f.doc);
        if f.precise {
            self.line("// Shared-boundary arithmetic (`precise` in GLSL/HLSL; WGSL has no such qualifier).");
        }
        self.name_locals(f);
        let args: Vec<String> = f
            .params
            .iter()
            .map(|id| format!("{}: {}", self.locals[id.0], self.ty(&f.locals[id.0].ty)))
            .collect();
        let ret = f
            .ret
            .as_ref()
            .map(|t| format!(" -> {}", self.ty(t)))
            .unwrap_or_default();
        self.line(&format!(
            "fn {}({}){ret} {{",
            ident(&f.name),
            args.join(", ")
        ));
        let written: Vec<Resource> = resources_of(self.plan, m, f)
            .0
            .into_iter()
            .filter(|(_, w)| *w)
            .map(|(r, _)| r)
            .collect();
        self.indent += 1;
        self.stmts(m, f, &written, &f.body);
        self.indent -= 1;
        self.line("}");
    }

    /// The variable a read of `r` goes through in a function that writes
    /// `written` (itself or through its callees).
    fn read_var(&self, r: Resource, written: &[Resource]) -> String {
        let b = abi::binding_of(r);
        if aliased(b) && !written.contains(&r) {
            read_only_name(b)
        } else {
            b.name.to_string()
        }
    }

    fn stmts(&mut self, m: &Module, f: &Function, written: &[Resource], body: &[Stmt]) {
        for s in body {
            match s {
                Stmt::Let(id, e) | Stmt::Var(id, e) => {
                    let kw = if matches!(s, Stmt::Let(..)) {
                        "let"
                    } else {
                        "var"
                    };
                    let s = format!(
                        "{kw} {}: {} = {};",
                        self.locals[id.0],
                        self.ty(&f.locals[id.0].ty),
                        self.expr(m, f, written, e)
                    );
                    self.line(&s);
                }
                Stmt::Assign(id, e) => {
                    let s = format!("{} = {};", self.locals[id.0], self.expr(m, f, written, e));
                    self.line(&s);
                }
                Stmt::AssignField(id, k, e) => {
                    let field = self.field_name(&f.locals[id.0].ty, *k);
                    let s = format!(
                        "{}.{field} = {};",
                        self.locals[id.0],
                        self.expr(m, f, written, e)
                    );
                    self.line(&s);
                }
                Stmt::Store(r, i, v) => {
                    let (i, v) = (self.expr(m, f, written, i), self.expr(m, f, written, v));
                    let b = abi::binding_of(*r);
                    let s = if packed(b) {
                        self.accessors
                            .borrow_mut()
                            .insert((b.name.to_string(), true));
                        format!("store_{}({i}, {v});", b.name)
                    } else {
                        format!("{}[{i}] = {v};", b.name)
                    };
                    self.line(&s);
                }
                Stmt::If(c, a, b) => {
                    let s = format!("if {} {{", self.expr(m, f, written, c));
                    self.line(&s);
                    self.indent += 1;
                    self.stmts(m, f, written, a);
                    self.indent -= 1;
                    if b.is_empty() {
                        self.line("}");
                    } else {
                        self.line("} else {");
                        self.indent += 1;
                        self.stmts(m, f, written, b);
                        self.indent -= 1;
                        self.line("}");
                    }
                }
                // Only in the tessellation stage bodies (`Entries::tess`),
                // which this target has no stages for and never prints.
                Stmt::Call(..)
                | Stmt::Output(..)
                | Stmt::Comment(..)
                | Stmt::StorePatchSlot(..) => {
                    unreachable!("tessellation-stage statement outside Entries::tess")
                }
                // No preprocessor: always the default branch.
                Stmt::IfDef(_, _, b) => self.stmts(m, f, written, b),
                Stmt::For(id, a, b, body) => {
                    let v = self.locals[id.0].clone();
                    let s = format!(
                        "for (var {v}: {} = {}; {v} < {}; {v} = ({v} + 1u)) {{",
                        self.ty(&f.locals[id.0].ty),
                        self.expr(m, f, written, a),
                        self.expr(m, f, written, b)
                    );
                    self.line(&s);
                    self.indent += 1;
                    self.stmts(m, f, written, body);
                    self.indent -= 1;
                    self.line("}");
                }
                Stmt::Return(e) => {
                    let s = format!("return {};", self.expr(m, f, written, e));
                    self.line(&s);
                }
            }
        }
    }

    fn field_name(&self, t: &Ty, k: usize) -> String {
        match t {
            Ty::Struct(i) => ident(&self.plan.common.structs[*i].fields[k].0),
            _ => format!("field{k}"),
        }
    }

    fn expr_ty(&self, m: &Module, f: &Function, e: &Expr) -> Option<Ty> {
        self.plan.expr_ty(m, f, e)
    }

    fn expr(&self, m: &Module, f: &Function, written: &[Resource], e: &Expr) -> String {
        match e {
            Expr::F32(x) => f32_lit(*x),
            Expr::U32(x) => format!("{x}u"),
            Expr::Local(id) => self.locals[id.0].clone(),
            Expr::ConstIndex(c, i) => format!(
                "{}[{}]",
                ident(&m.consts[*c].name),
                self.expr(m, f, written, i)
            ),
            Expr::Const(c) => ident(&m.consts[*c].name),
            Expr::Binary(op, a, b) => format!(
                "({} {} {})",
                self.expr(m, f, written, a),
                binop(*op),
                self.expr(m, f, written, b)
            ),
            Expr::Neg(a) => format!("(-{})", self.expr(m, f, written, a)),
            Expr::Call(b, xs) => {
                let a: Vec<String> = xs.iter().map(|x| self.expr(m, f, written, x)).collect();
                match b {
                    Builtin::F32FromU32 => format!("f32({})", a[0]),
                    Builtin::Sqrt => format!("sqrt({})", a[0]),
                    Builtin::Cos => format!("cos({})", a[0]),
                    Builtin::Sin => format!("sin({})", a[0]),
                    Builtin::Dot => format!("dot({}, {})", a[0], a[1]),
                    Builtin::Cross => format!("cross({}, {})", a[0], a[1]),
                    Builtin::Vec3 => format!("vec3<f32>({}, {}, {})", a[0], a[1], a[2]),
                    Builtin::Round => format!("round({})", a[0]),
                    Builtin::Floor => format!("floor({})", a[0]),
                    Builtin::U32FromF32 | Builtin::U32FromBool => format!("u32({})", a[0]),
                    Builtin::Max => format!("max({}, {})", a[0], a[1]),
                    Builtin::Component(k) => format!("{}.{}", a[0], ["x", "y", "z"][*k as usize]),
                }
            }
            Expr::CallFn(r, xs) => {
                let callee = match r {
                    FnRef::Common(i) => &self.plan.common.functions[*i],
                    FnRef::Local(i) => &m.functions[*i],
                };
                let a: Vec<String> = xs.iter().map(|x| self.expr(m, f, written, x)).collect();
                format!("{}({})", ident(&callee.name), a.join(", "))
            }
            Expr::Field(a, k) => {
                let t = self.expr_ty(m, f, a).unwrap_or(Ty::F32);
                format!(
                    "{}.{}",
                    self.expr(m, f, written, a),
                    self.field_name(&t, *k)
                )
            }
            Expr::Make(s, xs) => {
                let a: Vec<String> = xs.iter().map(|x| self.expr(m, f, written, x)).collect();
                format!(
                    "{}({})",
                    ident(&self.plan.common.structs[*s].name),
                    a.join(", ")
                )
            }
            Expr::Fetch(r, i) => {
                let idx = self.expr(m, f, written, i);
                let var = self.read_var(*r, written);
                if packed(abi::binding_of(*r)) {
                    let s = format!("load_{var}({idx})");
                    self.accessors.borrow_mut().insert((var, false));
                    s
                } else {
                    format!("{var}[{idx}]")
                }
            }
            Expr::TableWeight(row, col) => format!(
                "textureLoad(stencil_table, vec2<u32>({}, {}), 0u).x",
                self.expr(m, f, written, col),
                self.expr(m, f, written, row)
            ),
            // Only in the tessellation stage bodies (`Entries::tess`).
            Expr::Stage(_) | Expr::PatchSlot(..) => {
                unreachable!("tessellation-stage input outside Entries::tess")
            }
            Expr::Texel(r, x, y) => format!(
                "textureLoad({}, vec2<u32>({}, {}), 0u).x",
                r.name(),
                self.expr(m, f, written, x),
                self.expr(m, f, written, y)
            ),
        }
    }

    /// `if (params.class_ == 0u) { … } else if … else { … }` over the
    /// scheme's patch classes, the last one unconditional (like `eval`).
    fn class_chain(&mut self, body: &dyn Fn(&Self, &PatchEntry) -> String) {
        let stmts: Vec<String> = self.entries.patches.iter().map(|p| body(self, p)).collect();
        for line in super::class_chain_lines(&param("class"), &stmts) {
            self.line(&line);
        }
    }

    /// `var points: u32` = control points per patch of the draw's class.
    fn points_of_class(&mut self) {
        self.line("var points: u32 = 0u;");
        self.class_chain(&|_, p| format!("points = {}u;", p.control_points));
    }

    fn compute_head(&mut self, name: &str) {
        self.line(&format!(
            "@compute @workgroup_size({})",
            abi::WORKGROUP_SIZE
        ));
        self.line(&format!(
            "fn {name}(@builtin(global_invocation_id) gid: vec3<u32>) {{"
        ));
        self.indent += 1;
        self.line("let k: u32 = gid.x;");
    }

    /// Head of a chunk pass (`adaptive_count_main`, `adaptive_scatter_main`):
    /// a workgroup of [`BUCKET_CHUNK`] invocations per chunk of the class
    /// range `first .. first + count`; invocation l loads patch
    /// `p = BUCKET_CHUNK·c + l`'s bucket level into the shared tile (0
    /// outside the range), then the workgroup synchronises.
    fn chunk_head(&mut self, name: &str) {
        let first = param("first");
        let count = param("count");
        let chunk = BUCKET_CHUNK;
        self.line(&format!("@compute @workgroup_size({chunk})"));
        self.line(&format!(
            "fn {name}(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) l: u32) {{"
        ));
        self.indent += 1;
        self.line(&format!("let c: u32 = (({first} / {chunk}u) + wid.x);"));
        self.line(&format!("let p: u32 = (({chunk}u * c) + l);"));
        self.line("var lv: u32 = 0u;");
        self.line(&format!(
            "if ((p >= {first}) && (p < ({first} + {count}))) {{"
        ));
        self.line("    lv = patch_levels[((5u * p) + 4u)];");
        self.line("}");
        self.line("tessgen_bucket_tile[l] = lv;");
        self.line("workgroupBarrier();");
    }

    fn early_return(&mut self, cond: &str) {
        self.line(&format!("if {cond} {{"));
        self.line("    return;");
        self.line("}");
    }

    /// `samples[o ..]` = the sample `result`: position xyz, normal xyz (the
    /// layout every evaluation entry writes and the runtime reads back).
    fn store_sample(&mut self) {
        let comps = [
            "position.x",
            "position.y",
            "position.z",
            "normal.x",
            "normal.y",
            "normal.z",
        ];
        for (i, c) in comps.iter().enumerate() {
            self.line(&format!("samples[(o + {i}u)] = result.{c};"));
        }
    }

    fn end_fn(&mut self) {
        self.indent -= 1;
        self.line("}");
        self.line("");
    }

    fn entry_points(&mut self) {
        let first = param("first");
        let count = param("count");
        let level = param("level");
        let class = param("class");
        let cp_base = param("cp_base");
        let sample_ty = self.ty(&Ty::Struct(common::SAMPLE));
        let eval = self.fn_name(FnRef::Local(self.entries.eval));
        // Quad schemes evaluate through the displacement step (a no-op, bit
        // for bit, while displace_info[0] == 0), which takes the face.
        let (eval, face_arg) = match self.entries.eval_displaced {
            Some(d) => (self.fn_name(FnRef::Local(d)), "face, "),
            None => (eval, ""),
        };
        self.section("Entry points");

        self.line(
            "// Vertex stage for vertices first .. first + count (valence 0: unused vertex).",
        );
        self.compute_head(abi::entry::VERTEX_STAGE);
        self.early_return(&format!("(k >= {count})"));
        self.line(&format!("let vertex: u32 = ({first} + k);"));
        self.early_return("(valence[vertex] == 0u)");
        self.line(&format!(
            "{}(vertex, vertex_out_offsets[vertex]);",
            self.fn_name(FnRef::Local(self.entries.vertex_stage))
        ));
        self.end_fn();

        self.line(
            "// Patch stage of the dispatch's class for patches first .. first + count; patch k",
        );
        self.line(
            "// of the dispatch writes its control points from cp_base + k·(points per patch).",
        );
        self.compute_head(abi::entry::PATCH_STAGE);
        self.early_return(&format!("(k >= {count})"));
        self.line(&format!("let p: u32 = ({first} + k);"));
        self.line("let face: u32 = patch_faces[p];");
        self.class_chain(&|w, p| {
            format!(
                "{}(face, ({cp_base} + (k * {}u)));",
                w.fn_name(FnRef::Local(p.function)),
                p.control_points
            )
        });
        self.end_fn();

        let [grid_len, grid_iu, grid_iv] = self.entries.grid.map(|g| self.fn_name(FnRef::Local(g)));
        self.line("// grid_len(level) samples of each patch of the dispatch, sample s at the domain point");
        self.line("// (grid_iu(s), grid_iv(s)), into samples[(out_base + k)·6 ..]: position xyz, normal xyz.");
        self.compute_head(abi::entry::EVAL);
        self.line(&format!("let spp: u32 = {grid_len}({level});"));
        self.early_return(&format!("(k >= ({count} * spp))"));
        self.line("let patch_index: u32 = (k / spp);");
        self.line("let s: u32 = (k % spp);");
        self.line(&format!("let iu: u32 = {grid_iu}(s, {level});"));
        self.line(&format!("let iv: u32 = {grid_iv}(s, {level});"));
        self.points_of_class();
        if !face_arg.is_empty() {
            self.line(&format!(
                "let face: u32 = patch_faces[({first} + patch_index)];"
            ));
        }
        self.line(&format!(
            "let result: {sample_ty} = {eval}({face_arg}{class}, ({cp_base} + (patch_index * points)), iu, iv, {level});"
        ));
        self.line(&format!("let o: u32 = (({} + k) * 6u);", param("out_base")));
        self.store_sample();
        self.end_fn();

        self.line("// Output of the instanced evaluation.");
        self.line("struct VsOut {");
        self.line("    @builtin(position) clip_position: vec4<f32>,");
        self.line("    @location(0) world_position: vec3<f32>,");
        self.line("    @location(1) normal: vec3<f32>,");
        self.line("    @location(2) @interpolate(flat) patch_class: u32,");
        self.line("    @location(3) uv: vec2<f32>,");
        self.line("}");
        self.line("");
        self.line("// Instanced tessellation: an index buffer over the grid_len(level) grid vertices, shared");
        self.line(
            "// by all patches (vertex index vi = sample vi of grid_iu/grid_iv), one instance per patch of the",
        );
        self.line(
            "// draw's class: instance inst is patch inst of the draw, its control points from",
        );
        self.line("// cp_base + inst·(points per patch). Draw instances 0 .. count.");
        self.line("@vertex");
        self.line(
            "fn eval_vs(@builtin(vertex_index) vi: u32, @builtin(instance_index) inst: u32) -> VsOut {",
        );
        self.indent += 1;
        self.line(&format!("let iu: u32 = {grid_iu}(vi, {level});"));
        self.line(&format!("let iv: u32 = {grid_iv}(vi, {level});"));
        self.points_of_class();
        if !face_arg.is_empty() {
            self.line(&format!("let face: u32 = patch_faces[({first} + inst)];"));
        }
        self.line(&format!(
            "let result: {sample_ty} = {eval}({face_arg}{class}, ({cp_base} + (inst * points)), iu, iv, {level});"
        ));
        self.line("var out: VsOut;");
        self.line("out.clip_position = (params.view_proj * vec4<f32>(result.position, 1.0f));");
        self.line("out.world_position = result.position;");
        self.line("out.normal = result.normal;");
        self.line(&format!("out.patch_class = {class};"));
        self.line(&format!(
            "out.uv = (vec2<f32>(f32(iu), f32(iv)) / f32({level}));"
        ));
        self.line("return out;");
        self.end_fn();

        self.line(
            "// Two-sided Lambert under a fixed light; ordinary classes orange, the others blue.",
        );
        self.line("@fragment");
        self.line("fn shade_fs(input: VsOut) -> @location(0) vec4<f32> {");
        self.indent += 1;
        self.line(&format!("var base: vec3<f32> = {EXTRAORDINARY_RGB};"));
        let ordinary: Vec<usize> = self
            .entries
            .patches
            .iter()
            .enumerate()
            .filter(|(_, p)| p.class.name() == "ordinary")
            .map(|(k, _)| k)
            .collect();
        for k in ordinary {
            self.line(&format!("if (input.patch_class == {k}u) {{"));
            self.line(&format!("    base = {ORDINARY_RGB};"));
            self.line("}");
        }
        let normalize = self.fn_name(FnRef::Common(crate::lower::common_fn::NORMALIZE));
        self.line(&format!("let n: vec3<f32> = {normalize}(input.normal);"));
        self.line("let light: vec3<f32> = normalize(vec3<f32>(0.3f, 0.5f, 0.8f));");
        self.line("let lambert: f32 = abs(dot(n, light));");
        self.line("var color: vec3<f32> = (base * (0.2f + (0.8f * lambert)));");
        self.line("// Wireframe overlay of patch boundaries (params.flags bit 0).");
        self.line("if ((params.flags & 1u) != 0u) {");
        self.line("    let edge: f32 = min(min(input.uv.x, (1.0f - input.uv.x)), min(input.uv.y, (1.0f - input.uv.y)));");
        self.line("    if (edge < (1.5f * fwidth(edge))) {");
        self.line("        color = (color * 0.15f);");
        self.line("    }");
        self.line("}");
        self.line("return vec4<f32>(color, 1.0f);");
        self.indent -= 1;
        self.line("}");
    }

    /// Adaptive tessellation (quad and triangle schemes): a classify pass writing every
    /// patch's edge levels and bucket, then one dispatch (`eval_adaptive_main`)
    /// or instanced draw (`eval_adaptive_vs`) per (class, bucket) over the
    /// bucket's entries in `bucket_patches`. The semantics are the Plan's
    /// `patch_edge_level`, `tessgen_bucket_level` and `eval_adaptive`; these
    /// entries only index buffers.
    fn adaptive_entry_points(&mut self) {
        let a = self.entries.adaptive;
        let first = param("first");
        let count = param("count");
        let level = param("level");
        let class = param("class");
        let cp_base = param("cp_base");
        let sample_ty = self.ty(&Ty::Struct(common::SAMPLE));
        let edge_level = self.fn_name(FnRef::Local(a.edge_level));
        // Through the displacement step (a no-op, bit for bit, while
        // displace_info[0] == 0), which takes the face, as the uniform entries.
        let eval = self.fn_name(FnRef::Local(a.eval_displaced));
        let bucket = self.fn_name(FnRef::Common(crate::lower::common_fn::BUCKET_LEVEL));
        let [grid_len, grid_iu, grid_iv] = self.entries.grid.map(|g| self.fn_name(FnRef::Local(g)));
        self.line("");
        self.line(
            "// Adaptive classify: for patches first .. first + count of the dispatch's class, the",
        );
        self.line("// power-of-two level of each edge (patch_edge_level, largest level = params.level) and the");
        self.line("// patch's bucket into patch_levels[5p ..] (p = first + k, the class-sorted patch index).");
        self.compute_head("adaptive_classify_main");
        self.early_return(&format!("(k >= {count})"));
        self.line(&format!("let p: u32 = ({first} + k);"));
        self.line("let face: u32 = patch_faces[p];");
        self.points_of_class();
        self.line(&format!("let cp: u32 = ({cp_base} + (k * points));"));
        for e in 0..4 {
            self.line(&format!(
                "let l{e}: u32 = {edge_level}(face, {class}, cp, {e}u, {level});"
            ));
        }
        for e in 0..4 {
            self.line(&format!("patch_levels[((5u * p) + {e}u)] = l{e};"));
        }
        self.line(&format!(
            "patch_levels[((5u * p) + 4u)] = {bucket}(l0, l1, l2, l3);"
        ));
        self.end_fn();

        let entry = |w: &mut Self, index: &str| {
            w.line(&format!("let e: u32 = (6u * ({first} + {index}));"));
            w.line("let cp: u32 = bucket_patches[(e + 1u)];");
            w.line("let face: u32 = patch_faces[bucket_patches[e]];");
            w.line(&format!(
                "let result: {sample_ty} = {eval}(face, {class}, cp, iu, iv, {level}, bucket_patches[(e + 2u)], bucket_patches[(e + 3u)], bucket_patches[(e + 4u)], bucket_patches[(e + 5u)]);"
            ));
        };
        self.line("// One bucket of one class at its level params.level: grid_len(level) samples of each of");
        self.line(
            "// the entries first .. first + count of bucket_patches, snapped and displaced by",
        );
        self.line("// eval_adaptive_displaced (displacement off: eval_adaptive bit for bit), into");
        self.line("// samples[(out_base + k)·6 ..]: position xyz, normal xyz.");
        self.compute_head("eval_adaptive_main");
        self.line(&format!("let spp: u32 = {grid_len}({level});"));
        self.early_return(&format!("(k >= ({count} * spp))"));
        self.line("let patch_index: u32 = (k / spp);");
        self.line("let s: u32 = (k % spp);");
        self.line(&format!("let iu: u32 = {grid_iu}(s, {level});"));
        self.line(&format!("let iv: u32 = {grid_iv}(s, {level});"));
        entry(self, "patch_index");
        self.line(&format!("let o: u32 = (({} + k) * 6u);", param("out_base")));
        self.store_sample();
        self.end_fn();

        self.line("// Instanced adaptive draw of one bucket of one class: the level-params.level grid index");
        self.line("// buffer, instance inst = entry first + inst of bucket_patches, through eval_adaptive_displaced.");
        self.line("@vertex");
        self.line(
            "fn eval_adaptive_vs(@builtin(vertex_index) vi: u32, @builtin(instance_index) inst: u32) -> VsOut {",
        );
        self.indent += 1;
        self.line(&format!("let iu: u32 = {grid_iu}(vi, {level});"));
        self.line(&format!("let iv: u32 = {grid_iv}(vi, {level});"));
        self.line(&format!("let e: u32 = (6u * ({first} + inst));"));
        self.adaptive_vs_tail(&sample_ty, &eval);
        self.gpu_driven_entry_points(&sample_ty, &eval);
    }

    /// The rest of an adaptive vertex entry after `iu`, `iv` and the entry
    /// offset `e` into `bucket_patches`: the snapped, displaced sample
    /// (`eval`) and the `VsOut` of `eval_vs`.
    fn adaptive_vs_tail(&mut self, sample_ty: &str, eval: &str) {
        let (class, level) = (param("class"), param("level"));
        self.line("let cp: u32 = bucket_patches[(e + 1u)];");
        self.line("let face: u32 = patch_faces[bucket_patches[e]];");
        self.line(&format!(
            "let result: {sample_ty} = {eval}(face, {class}, cp, iu, iv, {level}, bucket_patches[(e + 2u)], bucket_patches[(e + 3u)], bucket_patches[(e + 4u)], bucket_patches[(e + 5u)]);"
        ));
        self.line("var out: VsOut;");
        self.line("out.clip_position = (params.view_proj * vec4<f32>(result.position, 1.0f));");
        self.line("out.world_position = result.position;");
        self.line("out.normal = result.normal;");
        self.line(&format!("out.patch_class = {class};"));
        self.line(&format!(
            "out.uv = (vec2<f32>(f32(iu), f32(iv)) / f32({level}));"
        ));
        self.line("return out;");
        self.indent -= 1;
        self.line("}");
        self.line("");
    }

    /// GPU-driven buckets: the lists of `bucket_patches` and the indirect
    /// dispatch arguments built on the GPU from `patch_levels`, so nothing
    /// is read back before the evaluation. Per class range r (slots
    /// `16r + j`, bucket `2^j`), a stable parallel compaction over chunks of
    /// [`BUCKET_CHUNK`] patches (chunk c = patches `256c ..`, a workgroup
    /// each): `adaptive_count_main` counts each chunk's patches per bucket
    /// into `bucket_chunks`, `adaptive_plan_main` (one workgroup) turns the
    /// chunk counts into each chunk's offset within its slot (one invocation
    /// per slot, a scan over the chunks), then prefix-sums the slots into
    /// first entry and first sample and writes the indirect arguments, and
    /// `adaptive_scatter_main` writes every patch at the sum of its slot's
    /// first entry, its chunk's offset and its rank among the chunk's
    /// earlier patches of the same bucket. The entries come out in patch
    /// order — the order the host lists have — without atomics, and no
    /// invocation loops over more than one chunk's patches (the plan's
    /// scan: over the chunks).
    /// `eval_adaptive_indirect_main` runs one indirect dispatch per slot.
    /// `bucket_list` (written here) is bound as `bucket_patches` for the
    /// evaluation: a header of 4 u32 per slot (count, first entry, first
    /// sample, x workgroups), then the entries.
    fn gpu_driven_entry_points(&mut self, sample_ty: &str, eval: &str) {
        let first = param("first");
        let count = param("count");
        let level = param("level");
        let class = param("class");
        let cp_base = param("cp_base");
        let out_base = param("out_base");
        let slots = BUCKET_SLOTS;
        let chunk = BUCKET_CHUNK;
        let [grid_len, grid_iu, grid_iv] = self.entries.grid.map(|g| self.fn_name(FnRef::Local(g)));
        self.line(
            "// One chunk's bucket levels (0 = no patch of the dispatch's class range), shared by the",
        );
        self.line("// workgroup of adaptive_count_main / adaptive_scatter_main.");
        self.line(&format!(
            "var<workgroup> tessgen_bucket_tile: array<u32, {chunk}>;"
        ));
        self.line("");
        self.line(
            "// GPU-driven buckets 1: for the class range of patches first .. first + count, workgroup w is",
        );
        self.line(&format!(
            "// chunk c = first / {chunk} + w (patches {chunk}c ..); invocation l < {slots} counts the chunk's patches of"
        ));
        self.line("// the range whose bucket (patch_levels[5p + 4]) is 2^l into bucket_chunks[2c·level + out_base + l]");
        self.line("// (level = the number of slots; row c: the counts, then the offsets).");
        self.chunk_head("adaptive_count_main");
        self.line(&format!("if (l < {slots}u) {{"));
        self.indent += 1;
        self.line("var n: u32 = 0u;");
        self.line(&format!(
            "for (var m: u32 = 0u; m < {chunk}u; m = m + 1u) {{"
        ));
        self.line("    if (tessgen_bucket_tile[m] == (1u << l)) {");
        self.line("        n = (n + 1u);");
        self.line("    }");
        self.line("}");
        self.line(&format!(
            "bucket_chunks[(((2u * c) * {level}) + ({out_base} + l))] = n;"
        ));
        self.indent -= 1;
        self.line("}");
        self.end_fn();

        self.line("// GPU-driven buckets 2 (one workgroup): invocation s (and s + 64, …) < count scans slot s's");
        self.line("// chunk counts (bucket_chunks[2c·count + s], chunk rows c < first) into each chunk's offset within");
        self.line("// the slot (exclusive prefix, at 2c·count + count + s) and the total into the slot's header; then");
        self.line("// invocation 0, for slots 0 .. count, writes the first entry and first sample (prefix sums of");
        self.line("// count and count·grid_len(2^(slot % 16))), the indirect dispatch arguments");
        self.line(&format!(
            "// (y = ⌈workgroups / {INDIRECT_X}⌉ rows of x = ⌈workgroups / y⌉) and the indexed indirect draw arguments"
        ));
        self.line("// (the level's grid, one instance per patch) into bucket_list, bucket_dispatch and bucket_draw.");
        self.line(&format!(
            "@compute @workgroup_size({})",
            abi::WORKGROUP_SIZE
        ));
        self.line("fn adaptive_plan_main(@builtin(local_invocation_index) l: u32) {");
        self.indent += 1;
        self.line(&format!(
            "for (var s: u32 = l; s < {count}; s = s + {}u) {{",
            abi::WORKGROUP_SIZE
        ));
        self.indent += 1;
        self.line("var n: u32 = 0u;");
        self.line(&format!(
            "for (var c: u32 = 0u; c < {first}; c = c + 1u) {{"
        ));
        self.line(&format!("    let at: u32 = (((2u * c) * {count}) + s);"));
        self.line(&format!("    bucket_chunks[(at + {count})] = n;"));
        self.line("    n = (n + bucket_chunks[at]);");
        self.line("}");
        self.line("bucket_list[(4u * s)] = n;");
        self.indent -= 1;
        self.line("}");
        self.line("storageBarrier();");
        self.early_return("(l != 0u)");
        self.line("var entry: u32 = 0u;");
        self.line("var first_sample: u32 = 0u;");
        self.line(&format!(
            "for (var b: u32 = 0u; b < {count}; b = b + 1u) {{"
        ));
        self.indent += 1;
        self.line("let n: u32 = bucket_list[(4u * b)];");
        self.line(&format!(
            "let spp: u32 = {grid_len}((1u << (b % {slots}u)));"
        ));
        self.line(&format!(
            "let groups: u32 = (((n * spp) + {}u) / {}u);",
            abi::WORKGROUP_SIZE - 1,
            abi::WORKGROUP_SIZE
        ));
        // As few rows y as the x limit allows, then the narrowest x for
        // them: fewer than y idle workgroups (x = min(groups, limit) would
        // leave up to limit − 1 of them in the last row).
        self.line(&format!(
            "let y: u32 = ((groups + {}u) / {INDIRECT_X}u);",
            INDIRECT_X - 1
        ));
        self.line("var x: u32 = 0u;");
        self.line("if (y > 0u) {");
        self.line("    x = ((groups + (y - 1u)) / y);");
        self.line("}");
        self.line("bucket_list[((4u * b) + 1u)] = entry;");
        self.line("bucket_list[((4u * b) + 2u)] = first_sample;");
        self.line("bucket_list[((4u * b) + 3u)] = x;");
        self.line("bucket_dispatch[(3u * b)] = x;");
        self.line("bucket_dispatch[((3u * b) + 1u)] = y;");
        self.line("bucket_dispatch[((3u * b) + 2u)] = 1u;");
        // The level's grid: 2·L² (quads) or L² (triangles) triangles.
        let per_cell = if self.entries.sides == 4 { 6 } else { 3 };
        self.line(&format!("let lb: u32 = (1u << (b % {slots}u));"));
        self.line(&format!(
            "bucket_draw[(5u * b)] = ({per_cell}u * (lb * lb));"
        ));
        self.line("bucket_draw[((5u * b) + 1u)] = n;");
        self.line("bucket_draw[((5u * b) + 2u)] = 0u;");
        self.line("bucket_draw[((5u * b) + 3u)] = 0u;");
        self.line("bucket_draw[((5u * b) + 4u)] = 0u;");
        self.line("entry = (entry + n);");
        self.line("first_sample = (first_sample + (n * spp));");
        self.indent -= 1;
        self.line("}");
        self.end_fn();

        self.line(
            "// GPU-driven buckets 3: for the class range of patches first .. first + count, chunk c as in 1;",
        );
        self.line("// the chunk's patch p of bucket 2^j goes to entry (first entry of slot out_base + j) + (the chunk's");
        self.line("// offset in bucket_chunks) + (its rank among the chunk's earlier patches of bucket 2^j), at");
        self.line("// bucket_list[4·level + 6·entry ..] (level = the number of slots, the header's length / 4):");
        self.line("// patch, first control point, edge levels.");
        self.chunk_head("adaptive_scatter_main");
        self.line("let j: u32 = countTrailingZeros(lv);");
        self.line(&format!("if ((j < {slots}u) && (lv == (1u << j))) {{"));
        self.indent += 1;
        self.points_of_class();
        self.line("var rank: u32 = 0u;");
        self.line("for (var m: u32 = 0u; m < l; m = m + 1u) {");
        self.line("    if (tessgen_bucket_tile[m] == lv) {");
        self.line("        rank = (rank + 1u);");
        self.line("    }");
        self.line("}");
        self.line(&format!("let slot: u32 = ({out_base} + j);"));
        self.line(&format!(
            "let at: u32 = ((4u * {level}) + (6u * ((bucket_list[((4u * slot) + 1u)] + bucket_chunks[((((2u * c) + 1u) * {level}) + slot)]) + rank)));"
        ));
        self.line("bucket_list[at] = p;");
        self.line(&format!(
            "bucket_list[(at + 1u)] = ({cp_base} + ((p - {first}) * points));"
        ));
        for e in 0..4 {
            self.line(&format!(
                "bucket_list[(at + {}u)] = patch_levels[((5u * p) + {e}u)];",
                e + 2
            ));
        }
        self.indent -= 1;
        self.line("}");
        self.end_fn();

        self.line("// GPU-driven buckets 4, one indirect dispatch per slot out_base (class, level = its bucket):");
        self.line("// the slot's header in bucket_patches (count, first entry, first sample, x workgroups),");
        self.line("// entries after the header (first = the number of slots), samples from the slot's first sample.");
        self.line(&format!(
            "@compute @workgroup_size({})",
            abi::WORKGROUP_SIZE
        ));
        self.line(
            "fn eval_adaptive_indirect_main(@builtin(global_invocation_id) gid: vec3<u32>) {",
        );
        self.indent += 1;
        self.line(&format!("let h: u32 = (4u * {out_base});"));
        self.line(&format!(
            "let k: u32 = (gid.x + ((gid.y * bucket_patches[(h + 3u)]) * {}u));",
            abi::WORKGROUP_SIZE
        ));
        self.line(&format!("let spp: u32 = {grid_len}({level});"));
        self.early_return("(k >= (bucket_patches[h] * spp))");
        self.line("let patch_index: u32 = (k / spp);");
        self.line("let s: u32 = (k % spp);");
        self.line(&format!("let iu: u32 = {grid_iu}(s, {level});"));
        self.line(&format!("let iv: u32 = {grid_iv}(s, {level});"));
        self.line(&format!(
            "let e: u32 = ((4u * {first}) + (6u * (bucket_patches[(h + 1u)] + patch_index)));"
        ));
        self.line("let cp: u32 = bucket_patches[(e + 1u)];");
        self.line("let face: u32 = patch_faces[bucket_patches[e]];");
        self.line(&format!(
            "let result: {sample_ty} = {eval}(face, {class}, cp, iu, iv, {level}, bucket_patches[(e + 2u)], bucket_patches[(e + 3u)], bucket_patches[(e + 4u)], bucket_patches[(e + 5u)]);"
        ));
        self.line("let o: u32 = ((bucket_patches[(h + 2u)] + k) * 6u);");
        self.store_sample();
        self.end_fn();

        self.line("// GPU-driven buckets 4, drawn: one draw_indexed_indirect per slot out_base (bucket_draw's");
        self.line("// arguments) of the slot's level grid, instance inst = entry inst of the slot (header in");
        self.line("// bucket_patches, entries after it: first = the number of slots).");
        self.line("@vertex");
        self.line(
            "fn eval_adaptive_indirect_vs(@builtin(vertex_index) vi: u32, @builtin(instance_index) inst: u32) -> VsOut {",
        );
        self.indent += 1;
        self.line(&format!("let h: u32 = (4u * {out_base});"));
        self.line(&format!("let iu: u32 = {grid_iu}(vi, {level});"));
        self.line(&format!("let iv: u32 = {grid_iv}(vi, {level});"));
        self.line(&format!(
            "let e: u32 = ((4u * {first}) + (6u * (bucket_patches[(h + 1u)] + inst)));"
        ));
        self.adaptive_vs_tail(sample_ty, eval);
    }
}
