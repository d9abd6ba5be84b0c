//! Rust printer: the Plan as plain Rust over `glam::Vec3`.
//!
//! Resources become slices: read-only mesh data and the table come in one
//! `&Inputs`, the array a stage writes is `out: &mut [Vec3]`, and control
//! points being evaluated are `cp: &[Vec3]`. Rust never contracts `a * b + c`
//! into an FMA, so the CPU path computes exactly the Plan's operations.

use super::dialect::{self, Dialect, Lines};
use super::{header_lines, resources_of};
use crate::plan::*;

pub struct Writer<'a> {
    plan: &'a Plan,
    out: String,
    indent: usize,
}

/// Print the whole plan as one Rust file.
pub fn write(plan: &Plan, command: &str) -> String {
    let mut w = Writer {
        plan,
        out: String::new(),
        indent: 0,
    };
    w.file(command);
    w.out
}

fn ty(plan: &Plan, t: &Ty) -> String {
    match t {
        Ty::F32 => "f32".into(),
        Ty::U32 => "u32".into(),
        Ty::Bool => "bool".into(),
        Ty::Vec3 => "Vec3".into(),
        Ty::Struct(i) => plan.common.structs[*i].name.clone(),
    }
}

fn f32_lit(x: f32) -> String {
    let s = format!("{x:?}f32");
    if x.is_sign_negative() {
        format!("({s})")
    } else {
        s
    }
}

/// Which slice parameters a function takes.
struct Params {
    inputs: bool,
    cp: bool,
    out: bool,
}

impl<'a> Writer<'a> {
    fn line(&mut self, s: &str) {
        for _ in 0..self.indent {
            self.out.push_str("    ");
        }
        self.out.push_str(s);
        self.out.push('\n');
    }

    fn doc(&mut self, doc: &str) {
        for l in crate::markdown::doc_text(doc).lines() {
            self.line(format!("/// {l}").trim_end());
        }
    }

    fn params(&self, module: &Module, f: &Function) -> Params {
        let (res, table) = resources_of(self.plan, module, f);
        let cp_read = res.contains(&(Resource::ControlPoints, false));
        let out = res.iter().any(|(_, w)| *w);
        let inputs = table
            || res
                .iter()
                .any(|(r, w)| !*w && *r != Resource::ControlPoints);
        Params {
            inputs,
            cp: cp_read,
            out,
        }
    }

    fn file(&mut self, command: &str) {
        for h in header_lines(command) {
            self.line(&format!("// {h}"));
        }
        self.line("//");
        self.line("// CPU kernels for every scheme, printed from the same Plan as the shaders.");
        self.line("// Include with `include!(concat!(env!(\"OUT_DIR\"), \"/rust/tessgen.rs\"));`.");
        self.line("");
        let plan = self.plan;
        self.module(&plan.common, None);
        for (m, e) in &plan.schemes {
            self.line("");
            self.module(m, Some(e));
        }
        self.line("");
        self.line("/// Every scheme in this file.");
        self.line("#[allow(dead_code)]");
        let list: Vec<String> = plan
            .schemes
            .iter()
            .map(|(m, _)| format!("&{}::KERNELS", m.name))
            .collect();
        self.line(&format!(
            "pub const SCHEMES: &[&common::SchemeKernels] = &[{}];",
            list.join(", ")
        ));
    }

    fn module(&mut self, m: &Module, entries: Option<&Entries>) {
        self.doc(&m.doc);
        // Locals carry the scheme's own output names (`R1_0_0` for g1cc's
        // `R1` at corner 0), which the language lets a scheme spell as it
        // likes: code generated from a valid scheme must build warning-free.
        self.line("#[allow(dead_code, unused_variables, unused_mut, unused_parens, unused_assignments, non_snake_case, clippy::all, clippy::pedantic)]");
        self.line(&format!("pub mod {} {{", m.name));
        self.indent += 1;
        self.line("use glam::Vec3;");
        if entries.is_some() {
            self.line("use super::common::*;");
        }
        for c in &m.consts {
            self.line("");
            self.doc(&c.doc);
            match &c.value {
                ConstValue::U32(x) => self.line(&format!("pub const {}: u32 = {x};", c.name)),
                ConstValue::U32Array(xs) => {
                    let body: Vec<String> = xs.iter().map(|x| x.to_string()).collect();
                    self.line(&format!(
                        "pub const {}: [u32; {}] = [{}];",
                        c.name,
                        xs.len(),
                        body.join(", ")
                    ));
                }
            }
        }
        for s in &m.structs {
            self.line("");
            self.line("#[derive(Clone, Copy, Debug, PartialEq)]");
            self.line(&format!("pub struct {} {{", s.name));
            for (n, t) in &s.fields {
                self.line(&format!("    pub {n}: {},", ty(self.plan, t)));
            }
            self.line("}");
        }
        if entries.is_none() {
            self.rust_support();
        }
        for (i, f) in m.functions.iter().enumerate() {
            // Tessellation-stage-only functions (no such stage here).
            if entries.is_some_and(|e| e.tess_only(i)) {
                continue;
            }
            self.line("");
            self.function(m, f);
        }
        if let Some(e) = entries {
            self.line("");
            self.kernels(m, e);
        }
        self.indent -= 1;
        self.line("}");
    }

    /// The Rust-only glue types: the inputs struct and the kernel registry.
    fn rust_support(&mut self) {
        let text = r#"
/// Everything the kernels read, as flat slices (the GPU binds the same
/// arrays as buffers and the table as a texture).
#[derive(Clone, Copy, Debug, Default)]
pub struct Inputs<'a> {
    pub positions: &'a [Vec3],
    pub valence: &'a [u32],
    pub ring_offsets: &'a [u32],
    pub ring: &'a [u32],
    pub vertex_out_offsets: &'a [u32],
    pub vertex_out: &'a [Vec3],
    pub corner_vertex: &'a [u32],
    pub corner_sector: &'a [u32],
    /// Crease and corner vertices (docs/boundaries.md §2): first sector of
    /// each vertex (plus a final total), empty range = smooth vertex.
    pub vertex_sectors: &'a [u32],
    /// Sector records, SECTOR_WORDS u32 each (kind, m, count, j0, ring base).
    pub sectors: &'a [u32],
    /// Valence of the per-valence constants at corner i of face f, at 4f + i.
    pub corner_valence: &'a [u32],
    /// Unit normal per vertex (triangle schemes; empty for quad schemes).
    pub normals: &'a [Vec3],
    /// Scalar-tagged PN: 4 f32 per vertex (tension, sharpness, bias, creased).
    pub tags: &'a [f32],
    /// Scalar-tagged PN: crease vector Δ per vertex.
    pub crease: &'a [Vec3],
    /// Scalar-tagged PN: side sign ±1 of corner i of triangle f at 3f + i.
    pub corner_side: &'a [f32],
    /// Adaptive tessellation: global edge id of edge k of face f at 4f + k
    /// (triangles: 3f + k).
    pub face_edges: &'a [u32],
    /// Adaptive tessellation: explicit factor per global edge id.
    pub edge_factors: &'a [f32],
    /// Adaptive tessellation parameters (generated/README.md).
    pub adaptive: &'a [f32],
    /// The stencil table, row-major, TABLE_WIDTH columns.
    pub table: &'a [f32],
    /// Displacement (quad schemes): 16 (s, t) pairs per face, owner's
    /// coordinates on edges and corners (watertight.md Rule 5).
    pub texcoords: &'a [f32],
    /// Displacement: 8 ownership records of 4 u32 per face (Rule 4).
    pub owners: &'a [u32],
    /// Displacement: scale (0 = off), map width, map height, unused.
    pub displace_info: &'a [f32],
    /// Displacement map texels, row-major, `displace_width` columns.
    pub displace_map: &'a [f32],
    pub displace_width: u32,
    /// Refinement (docs/boundaries.md §8): base-mesh positions.
    pub refine_base: &'a [Vec3],
    /// Refinement: start of each refined vertex's stencil row (plus a final total).
    pub refine_offsets: &'a [u32],
    /// Refinement: base vertex of each stencil term.
    pub refine_indices: &'a [u32],
    /// Refinement: weight of each stencil term.
    pub refine_weights: &'a [f32],
}

/// Patch stage of one facet class.
#[derive(Clone, Copy, Debug)]
pub struct ClassKernels {
    pub class: &'static str,
    pub form: &'static str,
    pub control_points: u32,
    /// `(inputs, out, face, cp_base)`
    pub patch: fn(&Inputs, &mut [Vec3], u32, u32),
}

/// Adaptive tessellation of a quad or triangle scheme (power-of-two edge
/// levels, buckets, snapped transitions): the functions the CPU runs and the
/// WGSL classify and evaluation entries call. Four edge slots whatever the
/// domain: a triangle's slot 3 has level 1 and is not read.
#[derive(Clone, Copy, Debug)]
pub struct AdaptiveKernels {
    /// `(inputs, cp, face, class, cp_base, k, max_level)`: level of edge k.
    pub edge_level: fn(&Inputs, &[Vec3], u32, u32, u32, u32, u32) -> u32,
    /// `(cp, class, cp_base, iu, iv, level, l0, l1, l2, l3)`: `eval` with
    /// boundary samples snapped onto the edges' own levels.
    pub eval: fn(&[Vec3], u32, u32, u32, u32, u32, u32, u32, u32, u32) -> Sample,
    /// `(inputs, cp, face, class, cp_base, iu, iv, level, l0, l1, l2, l3)`:
    /// the same snap, then the displacement step at the snapped point.
    #[allow(clippy::type_complexity)]
    pub eval_displaced: fn(&Inputs, &[Vec3], u32, u32, u32, u32, u32, u32, u32, u32, u32, u32) -> Sample,
}

/// Entry points of one scheme.
#[derive(Clone, Copy, Debug)]
pub struct SchemeKernels {
    pub name: &'static str,
    /// Vertex-stage outputs per vertex: rows_per_n·n + rows_fixed.
    pub rows_per_n: u32,
    pub rows_fixed: u32,
    /// `(inputs, out, vertex, out_base)`
    pub vertex_stage: fn(&Inputs, &mut [Vec3], u32, u32),
    pub classes: &'static [ClassKernels],
    /// `(cp, class, cp_base, iu, iv, level)`
    pub eval: fn(&[Vec3], u32, u32, u32, u32, u32) -> Sample,
    /// Triangle schemes: `(cp, class, cp_base, x, y, z, level)` at a
    /// hardware tessellator's barycentric domain point (what the GLSL/HLSL
    /// evaluation stages run), for parity checks of captured vertices.
    pub eval_domain: Option<fn(&[Vec3], u32, u32, f32, f32, f32, u32) -> Sample>,
    /// `(inputs, cp, face, class, cp_base, iu, iv, level)`: `eval` plus the
    /// displacement step (every built-in scheme: quads and triangles).
    pub eval_displaced: Option<fn(&Inputs, &[Vec3], u32, u32, u32, u32, u32, u32) -> Sample>,
    /// Triangle schemes: `(inputs, cp, face, class, cp_base, x, y, z,
    /// level)`, `eval_domain` plus the displacement step (what the
    /// displacing GLSL/HLSL evaluation stages run), for parity checks.
    pub eval_domain_displaced: Option<fn(&Inputs, &[Vec3], u32, u32, u32, f32, f32, f32, u32) -> Sample>,
    /// Adaptive tessellation on the instanced path (quad and triangle
    /// schemes).
    pub adaptive: AdaptiveKernels,
    /// Corners per facet: 4 (quads, (u, v) domain) or 3 (triangles,
    /// barycentric (level − iu − iv, iu, iv) of corners 0, 1, 2).
    pub sides: u32,
    /// Samples per patch at a level, and the (iu, iv) of sample s.
    pub grid_len: fn(u32) -> u32,
    pub grid_iu: fn(u32, u32) -> u32,
    pub grid_iv: fn(u32, u32) -> u32,
    /// The scheme's `EDGE_CURVE` (`[class][edge][4]`, `sides` edges per
    /// class): the runtime's grid evaluator runs the shared edge evaluator
    /// on these points for a whole border at once.
    pub edge_curve: &'static [u32],
    /// The scheme's `ROW_BASE` (first stencil-table row of each valence's
    /// vertex-stage block): the runtime's flat vertex stage reads the same
    /// weights in the same order for a whole deformation.
    pub row_base: &'static [u32],
}"#;
        for l in text.lines().skip(1) {
            if l.is_empty() {
                self.line("");
            } else {
                self.line(l);
            }
        }
    }

    fn kernels(&mut self, m: &Module, e: &Entries) {
        let (ra, rb) = {
            let get = |n: &str| {
                m.consts
                    .iter()
                    .find(|c| c.name == n)
                    .map(|c| match &c.value {
                        ConstValue::U32(x) => *x,
                        ConstValue::U32Array(_) => 0,
                    })
            };
            (
                get("ROWS_PER_N").unwrap_or(0),
                get("ROWS_FIXED").unwrap_or(0),
            )
        };
        self.line("/// Entry points of this scheme.");
        self.line("pub const KERNELS: SchemeKernels = SchemeKernels {");
        self.line(&format!("    name: \"{}\",", m.name));
        self.line(&format!("    rows_per_n: {ra},"));
        self.line(&format!("    rows_fixed: {rb},"));
        self.line(&format!(
            "    vertex_stage: {},",
            m.functions[e.vertex_stage].name
        ));
        self.line("    classes: &[");
        for p in &e.patches {
            self.line(&format!(
                "        ClassKernels {{ class: \"{}\", form: \"{}\", control_points: {}, patch: {} }},",
                p.class.name(),
                p.form.name(),
                p.control_points,
                m.functions[p.function].name
            ));
        }
        self.line("    ],");
        self.line(&format!("    eval: {},", m.functions[e.eval].name));
        match e.eval_domain {
            Some(d) => self.line(&format!("    eval_domain: Some({}),", m.functions[d].name)),
            None => self.line("    eval_domain: None,"),
        }
        match e.eval_displaced {
            Some(d) => self.line(&format!(
                "    eval_displaced: Some({}),",
                m.functions[d].name
            )),
            None => self.line("    eval_displaced: None,"),
        }
        match e.eval_domain_displaced {
            Some(d) => self.line(&format!(
                "    eval_domain_displaced: Some({}),",
                m.functions[d].name
            )),
            None => self.line("    eval_domain_displaced: None,"),
        }
        self.line(&format!(
            "    adaptive: AdaptiveKernels {{ edge_level: {}, eval: {}, eval_displaced: {} }},",
            m.functions[e.adaptive.edge_level].name,
            m.functions[e.adaptive.eval].name,
            m.functions[e.adaptive.eval_displaced].name
        ));
        self.line(&format!("    sides: {},", e.sides));
        for (field, g) in ["grid_len", "grid_iu", "grid_iv"].iter().zip(e.grid) {
            self.line(&format!("    {field}: {},", m.functions[g].name));
        }
        self.line("    edge_curve: &EDGE_CURVE,");
        self.line("    row_base: &ROW_BASE,");
        self.line("};");
    }

    fn function(&mut self, m: &Module, f: &Function) {
        self.doc(&f.doc);
        let p = self.params(m, f);
        let mut args = Vec::new();
        if p.inputs {
            args.push("inputs: &Inputs".to_string());
        }
        if p.out {
            args.push("out: &mut [Vec3]".to_string());
        }
        if p.cp {
            args.push("cp: &[Vec3]".to_string());
        }
        for id in &f.params {
            let loc = &f.locals[id.0];
            args.push(format!("{}: {}", loc.name, ty(self.plan, &loc.ty)));
        }
        let ret = f
            .ret
            .as_ref()
            .map(|t| format!(" -> {}", ty(self.plan, t)))
            .unwrap_or_default();
        self.line(&format!("pub fn {}({}){ret} {{", f.name, args.join(", ")));
        self.indent += 1;
        self.stmts(m, f, &f.body);
        self.indent -= 1;
        self.line("}");
    }

    fn stmts(&mut self, m: &Module, f: &Function, body: &[Stmt]) {
        let mut lines = Lines {
            out: std::mem::take(&mut self.out),
            indent: self.indent,
        };
        dialect::stmts(&Cx { w: self, m, f }, body, &mut lines);
        self.out = lines.out;
    }
}

/// The Rust dialect, for one function: method-call builtins, `as` casts,
/// slices indexed by `usize`, hidden slice arguments.
struct Cx<'c, 'a> {
    w: &'c Writer<'a>,
    m: &'c Module,
    f: &'c Function,
}

impl Dialect for Cx<'_, '_> {
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
        name.to_string()
    }
    fn local(&self, id: LocalId) -> String {
        self.f.locals[id.0].name.clone()
    }
    fn f32_lit(&self, x: f32) -> String {
        f32_lit(x)
    }
    fn u32_lit(&self, x: u32) -> String {
        format!("{x}u32")
    }
    fn f32_ty(&self) -> &'static str {
        "f32"
    }
    fn u32_ty(&self) -> &'static str {
        "u32"
    }
    fn vec2_ty(&self) -> &'static str {
        "Vec2"
    }
    fn vec3_ty(&self) -> &'static str {
        "Vec3"
    }
    fn builtin_override(&self, b: Builtin, a: &[String]) -> Option<String> {
        Some(match b {
            Builtin::F32FromU32 => format!("({} as f32)", a[0]),
            Builtin::Sqrt => format!("{}.sqrt()", a[0]),
            Builtin::Cos => format!("{}.cos()", a[0]),
            Builtin::Sin => format!("{}.sin()", a[0]),
            Builtin::Dot => format!("{}.dot({})", a[0], a[1]),
            Builtin::Cross => format!("{}.cross({})", a[0], a[1]),
            Builtin::Vec3 => format!("Vec3::new({}, {}, {})", a[0], a[1], a[2]),
            Builtin::Round => format!("{}.round_ties_even()", a[0]),
            Builtin::Floor => format!("{}.floor()", a[0]),
            Builtin::U32FromF32 | Builtin::U32FromBool => format!("({} as u32)", a[0]),
            Builtin::Max => format!("{}.max({})", a[0], a[1]),
            Builtin::Component(_) => return None,
            Builtin::CountTrailingZeros => format!("{}.trailing_zeros()", a[0]),
            Builtin::Normalize => format!("{}.normalize()", a[0]),
            Builtin::Abs => format!("{}.abs()", a[0]),
            Builtin::Min => format!("{}.min({})", a[0], a[1]),
            // Only in the GPU entry points (`Entries::instanced`).
            Builtin::Fwidth | Builtin::Vec2 | Builtin::Project => {
                unreachable!("a shader builtin outside Entries::instanced")
            }
        })
    }
    fn const_index(&self, name: String, index: String) -> String {
        format!("{name}[({index}) as usize]")
    }
    /// Functions take the slices they reach first: inputs, out, cp.
    fn call(&self, r: FnRef, callee: &Function, args: Vec<String>) -> String {
        let module = match r {
            FnRef::Common(_) => &self.w.plan.common,
            FnRef::Local(_) => self.m,
        };
        let p = self.w.params(module, callee);
        let mut a = Vec::new();
        if p.inputs {
            a.push("inputs".to_string());
        }
        if p.out {
            a.push("out".to_string());
        }
        if p.cp {
            a.push("cp".to_string());
        }
        a.extend(args);
        format!("{}({})", callee.name, a.join(", "))
    }
    fn make(&self, s: usize, args: Vec<String>) -> String {
        let sd = &self.w.plan.common.structs[s];
        let parts: Vec<String> = sd
            .fields
            .iter()
            .zip(args)
            .map(|((name, _), x)| format!("{name}: {x}"))
            .collect();
        format!("{} {{ {} }}", sd.name, parts.join(", "))
    }
    fn decl(&self, id: LocalId, mutable: bool) -> String {
        let l = &self.f.locals[id.0];
        let kw = if mutable { "let mut" } else { "let" };
        format!("{kw} {}: {}", l.name, ty(self.w.plan, &l.ty))
    }
    fn for_head(&self, id: LocalId, start: String, end: String, step: Option<String>) -> String {
        // Strided loops are only in the GPU entry points.
        assert!(step.is_none(), "a strided loop outside Entries::instanced");
        format!("for {} in ({start})..({end}) {{", self.local(id))
    }
    fn special_stmt(&self, s: &Stmt, out: &mut Lines) {
        let x = |e: &Expr| dialect::expr(self, e);
        match s {
            Stmt::Store(_, i, v) => out.line(&format!("out[({}) as usize] = {};", x(i), x(v))),
            // Only in the tessellation stage bodies (`Entries::tess`), the
            // GPU entry points and the packed accessors of the shaders.
            _ => unreachable!("a shader statement in the Rust module"),
        }
    }
    fn special(&self, e: &Expr) -> String {
        let x = |e: &Expr| dialect::expr(self, e);
        match e {
            Expr::Fetch(r, i) => {
                let idx = x(i);
                match r {
                    Resource::ControlPoints => format!("cp[({idx}) as usize]"),
                    other => format!("inputs.{}[({idx}) as usize]", other.name()),
                }
            }
            // The 2-D resources are row-major slices: the Plan's flat index.
            Expr::Texel(..) | Expr::TableWeight(..) => {
                let name = match e {
                    Expr::Texel(r, ..) => r.name(),
                    _ => "table",
                };
                let i = crate::plan::flat::flat_index(e).expect("a texel read");
                format!("inputs.{name}[({}) as usize]", x(&i))
            }
            Expr::Columns(Resource::DisplaceMap) => "inputs.displace_width".into(),
            // Only in the tessellation stage bodies (`Entries::tess`) and
            // the packed accessors of the shader printers.
            _ => unreachable!("tessellation-stage input outside Entries::tess"),
        }
    }
}
