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
use super::dialect::{self, Dialect, Lines};
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
    (abi::entry::REFINE, "compute"),
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
    accessors: RefCell<BTreeSet<(String, bool, Resource)>>,
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
        self.entry_items();
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

    /// The `load_*` / `store_*` helpers of the packed `vec3` buffers in
    /// use: the Plan's packed accessors ([`crate::lower::entries::packed_load`]),
    /// named after the variable they go through (`NAME` or `NAME_ro`).
    fn accessor_fns(&mut self) {
        use crate::lower::entries::{packed_load, packed_store, Offsets};
        let used: Vec<(String, bool, Resource)> = self.accessors.borrow().iter().cloned().collect();
        let module = self.module;
        for (var, store, r) in used {
            self.line("");
            let (f, written) = if store {
                let doc = format!("{var}[i] = v: the packed f32 triple at 3i.");
                let f = packed_store(r, &format!("store_{var}"), &doc, Offsets::Bound);
                (f, vec![r])
            } else {
                let doc = format!("{var}[i]: the packed f32 triple at 3i.");
                let f = packed_load(r, &format!("load_{var}"), &doc, Offsets::Bound);
                // The read-write variable where the helper is named after it.
                let w = if self.read_var(r, &[]) == var {
                    vec![]
                } else {
                    vec![r]
                };
                (f, w)
            };
            self.function_in(module, &f, &written);
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
        self.fn_head(f);
        let written: Vec<Resource> = resources_of(self.plan, m, f)
            .0
            .into_iter()
            .filter(|(_, w)| *w)
            .map(|(r, _)| r)
            .collect();
        self.body(m, f, &written);
    }

    /// `fn name(params) -> ret {`, naming `f`'s locals first.
    fn fn_head(&mut self, f: &Function) {
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
    }

    /// `f` with the buffers it writes given (the packed accessors, whose
    /// variable is chosen by name).
    fn function_in(&mut self, m: &Module, f: &Function, written: &[Resource]) {
        self.doc(&f.doc);
        self.fn_head(f);
        self.body(m, f, written);
    }

    fn body(&mut self, m: &Module, f: &Function, written: &[Resource]) {
        self.indent += 1;
        self.stmts(m, f, written, &f.body);
        self.indent -= 1;
        self.line("}");
    }

    /// The variable a read of `r` goes through in a function that writes
    /// `written` (itself or through its callees).
    fn read_var(&self, r: Resource, written: &[Resource]) -> String {
        match super::binding(r) {
            Some(b) if aliased(b) && !written.contains(&r) => read_only_name(b),
            Some(b) => b.name.to_string(),
            None => r.name().to_string(),
        }
    }

    fn stmts(&mut self, m: &Module, f: &Function, written: &[Resource], body: &[Stmt]) {
        let mut lines = Lines {
            out: std::mem::take(&mut self.out),
            indent: self.indent,
        };
        let cx = Cx {
            w: self,
            m,
            f,
            written,
        };
        dialect::stmts(&cx, body, &mut lines);
        self.out = lines.out;
    }

    fn expr(&self, m: &Module, f: &Function, written: &[Resource], e: &Expr) -> String {
        dialect::expr(
            &Cx {
                w: self,
                m,
                f,
                written,
            },
            e,
        )
    }

    /// The Plan's entry points ([`Entries::instanced`]) and the
    /// declarations between them: this printer adds the attributes, the
    /// builtin parameters and the `VsOut` struct, and spells the bodies.
    fn entry_items(&mut self) {
        self.section("Entry points");
        let entries = self.entries;
        for item in &entries.instanced {
            match item {
                EntryItem::Entry(e) => self.entry_point(e),
                EntryItem::Workgroup { resource, len, doc } => {
                    self.doc(doc);
                    self.line(&format!(
                        "var<workgroup> {}: array<u32, {len}>;",
                        resource.name()
                    ));
                }
                EntryItem::VertexOutput { doc } => {
                    self.doc(doc);
                    self.line("struct VsOut {");
                    self.line("    @builtin(position) clip_position: vec4<f32>,");
                    self.line("    @location(0) world_position: vec3<f32>,");
                    self.line("    @location(1) normal: vec3<f32>,");
                    self.line("    @location(2) @interpolate(flat, either) patch_class: u32,");
                    self.line("    @location(3) uv: vec2<f32>,");
                    self.line("}");
                }
            }
            self.line("");
        }
    }

    fn entry_point(&mut self, e: &EntryPoint) {
        let f = &e.body;
        self.doc(&f.doc);
        let inputs: Vec<&str> = e
            .inputs
            .iter()
            .map(|s| match s {
                StageIn::GlobalId | StageIn::GlobalIdY => {
                    "@builtin(global_invocation_id) gid: vec3<u32>"
                }
                StageIn::WorkgroupId => "@builtin(workgroup_id) wid: vec3<u32>",
                StageIn::LocalIndex => "@builtin(local_invocation_index) l: u32",
                StageIn::VertexIndex => "@builtin(vertex_index) vi: u32",
                StageIn::InstanceIndex => "@builtin(instance_index) inst: u32",
                _ => unreachable!("not a builtin input of an entry point"),
            })
            .collect();
        let (head, params, ret) = match e.kind {
            EntryKind::Compute { workgroup_size } => (
                format!("@compute @workgroup_size({workgroup_size})"),
                inputs.join(", "),
                "",
            ),
            EntryKind::Vertex => ("@vertex".into(), inputs.join(", "), " -> VsOut"),
            EntryKind::Fragment => (
                "@fragment".into(),
                "input: VsOut".into(),
                " -> @location(0) vec4<f32>",
            ),
        };
        self.line(&head);
        self.line(&format!("fn {}({params}){ret} {{", ident(&f.name)));
        self.name_locals(f);
        let module = self.module;
        let written: Vec<Resource> = resources_of(self.plan, module, f)
            .0
            .into_iter()
            .filter(|(_, w)| *w)
            .map(|(r, _)| r)
            .collect();
        self.indent += 1;
        self.stmts(module, f, &written, &f.body);
        if e.kind == EntryKind::Vertex {
            self.line("var out: VsOut;");
        }
        for (o, x) in &e.outputs {
            let v = self.expr(module, f, &written, x);
            match o {
                StageOut::Clip => self.line(&format!("out.clip_position = {v};")),
                StageOut::Position => self.line(&format!("out.world_position = {v};")),
                StageOut::Color => self.line(&format!("return vec4<f32>({v}, 1.0f);")),
                o => self.line(&format!("out.{} = {v};", varying(*o))),
            }
        }
        if e.kind == EntryKind::Vertex {
            self.line("return out;");
        }
        self.indent -= 1;
        self.line("}");
    }
}

/// The `VsOut` field of a vertex output.
fn varying(o: StageOut) -> &'static str {
    match o {
        StageOut::Position => "world_position",
        StageOut::Normal => "normal",
        StageOut::PatchClass => "patch_class",
        StageOut::Uv => "uv",
        _ => unreachable!("not an output of the instanced vertex entries"),
    }
}

/// The WGSL dialect, for one function: `written` are the buffers the
/// function writes (itself or through its callees), which decides the
/// variable a read goes through.
struct Cx<'c, 'a> {
    w: &'c Writer<'a>,
    m: &'c Module,
    f: &'c Function,
    written: &'c [Resource],
}

impl Dialect for Cx<'_, '_> {
    fn builtin_override(&self, b: Builtin, a: &[String]) -> Option<String> {
        (b == Builtin::Project).then(|| format!("(params.view_proj * vec4<f32>({}, 1.0f))", a[0]))
    }
    fn plan(&self) -> &Plan {
        self.w.plan
    }
    fn module(&self) -> &Module {
        self.m
    }
    fn function(&self) -> &Function {
        self.f
    }
    fn ident(&self, name: &str) -> String {
        ident(name)
    }
    fn local(&self, id: LocalId) -> String {
        self.w.locals[id.0].clone()
    }
    fn f32_lit(&self, x: f32) -> String {
        f32_lit(x)
    }
    fn f32_ty(&self) -> &'static str {
        "f32"
    }
    fn u32_ty(&self) -> &'static str {
        "u32"
    }
    fn vec2_ty(&self) -> &'static str {
        "vec2<f32>"
    }
    fn vec3_ty(&self) -> &'static str {
        "vec3<f32>"
    }
    fn decl(&self, id: LocalId, mutable: bool) -> String {
        let kw = if mutable { "var" } else { "let" };
        let ty = self.w.ty(&self.f.locals[id.0].ty);
        format!("{kw} {}: {ty}", self.local(id))
    }
    fn special_stmt(&self, s: &Stmt, out: &mut Lines) {
        let x = |e: &Expr| dialect::expr(self, e);
        match s {
            Stmt::Store(r, i, v) => {
                let (i, v) = (x(i), x(v));
                let s = if let Some(b) = super::binding(*r).filter(|b| packed(b)) {
                    self.w
                        .accessors
                        .borrow_mut()
                        .insert((b.name.to_string(), true, *r));
                    format!("store_{}({i}, {v});", b.name)
                } else {
                    format!("{}[{i}] = {v};", self.w.read_var(*r, self.written))
                };
                out.line(&s);
            }
            Stmt::StoreFloat(r, i, v) => out.line(&format!(
                "{}[{}] = {};",
                self.w.read_var(*r, self.written),
                x(i),
                x(v)
            )),
            Stmt::Barrier(Barrier::Workgroup) => out.line("workgroupBarrier();"),
            Stmt::Barrier(Barrier::Storage) => out.line("storageBarrier();"),
            // Only in the tessellation stage bodies (`Entries::tess`),
            // which this target has no stages for and never prints.
            _ => unreachable!("tessellation-stage statement outside Entries::tess"),
        }
    }
    fn special(&self, e: &Expr) -> String {
        let x = |e: &Expr| dialect::expr(self, e);
        match e {
            Expr::Fetch(r, i) => {
                let idx = x(i);
                let var = self.w.read_var(*r, self.written);
                if super::binding(*r).is_some_and(packed) {
                    let s = format!("load_{var}({idx})");
                    self.w.accessors.borrow_mut().insert((var, false, *r));
                    s
                } else {
                    format!("{var}[{idx}]")
                }
            }
            Expr::TableWeight(row, col) => {
                let (tx, ty) = crate::plan::flat::table_texel(row, col);
                format!(
                    "textureLoad(stencil_table, vec2<u32>({}, {}), 0u).x",
                    x(&tx),
                    x(&ty)
                )
            }
            Expr::Float(r, i) => format!("{}[{}]", self.w.read_var(*r, self.written), x(i)),
            Expr::Stage(StageIn::Param(n)) => param(n),
            Expr::Stage(StageIn::GlobalId) => "gid.x".into(),
            Expr::Stage(StageIn::GlobalIdY) => "gid.y".into(),
            Expr::Stage(StageIn::WorkgroupId) => "wid.x".into(),
            Expr::Stage(StageIn::LocalIndex) => "l".into(),
            Expr::Stage(StageIn::VertexIndex) => "vi".into(),
            Expr::Stage(StageIn::InstanceIndex) => "inst".into(),
            Expr::Stage(StageIn::Varying(o)) => format!("input.{}", varying(*o)),
            Expr::Texel(r, a, b) => format!(
                "textureLoad({}, vec2<u32>({}, {}), 0u).x",
                r.name(),
                x(a),
                x(b)
            ),
            // Only in the tessellation stage bodies (`Entries::tess`).
            _ => unreachable!("tessellation-stage input outside Entries::tess"),
        }
    }
}
