//! GLSL 450 printer (Vulkan flavour: `glslangValidator -V`).
//!
//! Every scheme becomes seven files, each with one `main`:
//!
//! | file | stage | work |
//! |---|---|---|
//! | `glsl/<scheme>.vert` | vertex | pass-through for the tessellation pipeline (one patch vertex per patch, no inputs) |
//! | `glsl/<scheme>.tesc` | tessellation control | the class's patch function, once per patch, into `patch out tcs_cp[]` |
//! | `glsl/<scheme>.tese` | tessellation evaluation | quads: `eval` at the integer grid point of `gl_TessCoord`; triangles: `eval_domain` at `gl_TessCoord` (grid point on the boundary, raw point inside) |
//! | `glsl/<scheme>_vertex_stage.comp` | compute | `vertex_stage_main` |
//! | `glsl/<scheme>_patch.comp` | compute | `patch_main` |
//! | `glsl/<scheme>_eval.comp` | compute | `eval_main` |
//! | `glsl/<scheme>_refine.comp` | compute | `refine_main` (refined meshes, before the vertex stage) |
//!
//! Bindings follow [`abi::BINDINGS`] (set 0); each file declares only the
//! bindings its entry point reaches, read-only unless that file writes them.
//! Packed `vec3` buffers are `float[]` read and written through small
//! `load_*`/`store_*` helpers; in the tessellation stages the control points
//! are the per-patch array `tcs_cp` instead of a buffer. GLSL keywords and
//! names that would shadow a global get a trailing `_` (the `Params` field
//! `class` is spelled `class_`; its offset is the ABI's).
//!
//! Like every printer this one only spells the Plan: binaries fully
//! parenthesised as given, f32 literals in Rust's shortest round-trip digits,
//! functions flagged `precise` get `precise` on their return value and locals.
//! The `.tesc`/`.tese` `main` bodies are the Plan's too ([`TessStages`]):
//! this printer names the stage inputs and outputs (`gl_TessCoord` with the
//! quad axis swap, `gl_PrimitiveID`, `gl_TessLevelOuter`/`Inner` slots,
//! `te_*`) and declares the stage I/O and the packed per-patch `tcs_cp`.

use super::abi::{self, Binding, Kind};
use super::dialect::{self, Dialect, Lines};
use super::{called, header_lines, resources_of};
use crate::lower::entries::Offsets;
use crate::outdir::GeneratedFile;
use crate::plan::*;
use std::collections::{BTreeMap, HashSet};

mod spell;
use spell::Cx;

/// Print every scheme of the plan as GLSL files.
pub fn write(plan: &Plan, command: &str) -> Vec<GeneratedFile> {
    let mut files = Vec::new();
    for (module, entries) in &plan.schemes {
        for stage in Stage::ALL {
            let mut w = Writer::new(plan, module, entries, stage);
            w.file(command);
            files.push(GeneratedFile {
                path: format!("glsl/{}{}", module.name, stage.suffix()),
                contents: w.out.into_bytes(),
            });
        }
    }
    files
}

/// Bindings a file declares: `binding → (read here, written here)`.
type Need = BTreeMap<u32, (bool, bool)>;

/// The shader a file holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Vert,
    Tesc,
    Tese,
    CompVertex,
    CompPatch,
    CompEval,
    CompRefine,
}

impl Stage {
    const ALL: [Stage; 7] = [
        Stage::Vert,
        Stage::Tesc,
        Stage::Tese,
        Stage::CompVertex,
        Stage::CompPatch,
        Stage::CompEval,
        Stage::CompRefine,
    ];
    fn suffix(self) -> &'static str {
        match self {
            Stage::Vert => ".vert",
            Stage::Tesc => ".tesc",
            Stage::Tese => ".tese",
            Stage::CompVertex => "_vertex_stage.comp",
            Stage::CompPatch => "_patch.comp",
            Stage::CompEval => "_eval.comp",
            Stage::CompRefine => "_refine.comp",
        }
    }
    /// Control points live in `tcs_cp`, not in a buffer.
    fn tess(self) -> bool {
        matches!(self, Stage::Tesc | Stage::Tese)
    }
    fn about(self) -> &'static str {
        match self {
            Stage::Vert => "Vertex shader of the tessellation pipeline: draw GL_PATCHES with patch size 1, one vertex per patch, no vertex inputs.",
            Stage::Tesc => "Tessellation control: the patch stage of the draw's class, once per patch, into the per-patch array tcs_cp.",
            Stage::Tese => "Tessellation evaluation: position and normal at the integer grid point of gl_TessCoord.",
            Stage::CompVertex => "Compute entry point vertex_stage_main: the vertex stage for vertices first .. first + count.",
            Stage::CompPatch => "Compute entry point patch_main: the patch stage for patches first .. first + count of one class.",
            Stage::CompEval => "Compute entry point eval_main: (level+1)² samples of each patch into `samples`.",
            Stage::CompRefine => "Compute entry point refine_main: the refinement stage for refined vertices first .. first + count (bind refined_positions to the buffer the vertex stage reads as positions).",
        }
    }
}

/// GLSL 4.50 keywords and reserved words, plus the built-in functions and
/// types this printer calls: never used as a plain name.
const RESERVED: &[&str] = &[
    "active",
    "asm",
    "atomic_uint",
    "attribute",
    "bool",
    "break",
    "buffer",
    "bvec2",
    "bvec3",
    "bvec4",
    "case",
    "cast",
    "centroid",
    "class",
    "coherent",
    "common",
    "const",
    "continue",
    "cos",
    "cross",
    "default",
    "discard",
    "dmat2",
    "dmat3",
    "dmat4",
    "do",
    "dot",
    "double",
    "dvec2",
    "dvec3",
    "dvec4",
    "else",
    "enum",
    "extern",
    "external",
    "false",
    "filter",
    "fixed",
    "flat",
    "float",
    "floatBitsToUint",
    "for",
    "fvec2",
    "fvec3",
    "fvec4",
    "goto",
    "half",
    "highp",
    "hvec2",
    "hvec3",
    "hvec4",
    "if",
    "iimage2D",
    "image2D",
    "in",
    "inline",
    "inout",
    "input",
    "int",
    "interface",
    "invariant",
    "isampler2D",
    "isampler3D",
    "ivec2",
    "ivec3",
    "ivec4",
    "layout",
    "long",
    "lowp",
    "main",
    "mat2",
    "mat3",
    "mat4",
    "mediump",
    "namespace",
    "noinline",
    "noperspective",
    "out",
    "output",
    "partition",
    "patch",
    "precise",
    "precision",
    "public",
    "readonly",
    "resource",
    "restrict",
    "return",
    "round",
    "sample",
    "sampler1D",
    "sampler2D",
    "sampler3D",
    "samplerCube",
    "shared",
    "short",
    "sin",
    "sizeof",
    "smooth",
    "sqrt",
    "static",
    "struct",
    "subroutine",
    "superp",
    "switch",
    "template",
    "texelFetch",
    "this",
    "true",
    "typedef",
    "uimage2D",
    "uint",
    "uintBitsToFloat",
    "uniform",
    "union",
    "unsigned",
    "usampler2D",
    "using",
    "uvec2",
    "uvec3",
    "uvec4",
    "varying",
    "vec2",
    "vec3",
    "vec4",
    "void",
    "volatile",
    "while",
    "writeonly",
];

/// A name GLSL accepts: keywords get a trailing `_`, `gl_` prefixes and
/// double underscores (reserved to the implementation) are spelled apart.
fn ident(name: &str) -> String {
    let mut s = name.to_string();
    while s.contains("__") {
        s = s.replace("__", "_x_");
    }
    if s.starts_with("gl_") {
        s = format!("x{s}");
    }
    if RESERVED.contains(&s.as_str()) {
        s.push('_');
    }
    s
}

/// `vertex_out_offsets` → `VertexOutOffsets` (buffer block names).
fn block_name(name: &str) -> String {
    name.split('_')
        .map(|w| {
            let mut c = w.chars();
            match c.next() {
                Some(first) => first.to_ascii_uppercase().to_string() + c.as_str(),
                None => String::new(),
            }
        })
        .collect()
}

fn f32_lit(x: f32) -> String {
    if !x.is_finite() {
        return format!("uintBitsToFloat({:#010x}u)", x.to_bits());
    }
    let s = format!("{x:?}");
    if x.is_sign_negative() {
        format!("({s})")
    } else {
        s
    }
}

/// A function by absolute reference: `Local` is the scheme module.
fn absolute(in_common: bool, r: FnRef) -> FnRef {
    match (in_common, r) {
        (true, FnRef::Local(i)) => FnRef::Common(i),
        _ => r,
    }
}

/// Name of a `Params` field in GLSL.
fn param(field: &str) -> String {
    format!("params.{}", ident(field))
}

pub struct Writer<'a> {
    plan: &'a Plan,
    module: &'a Module,
    entries: &'a Entries,
    stage: Stage,
    out: String,
    indent: usize,
    /// Names declared at file scope; locals are renamed around them.
    globals: HashSet<String>,
    /// Names of the locals of the function being printed.
    locals: Vec<String>,
    /// Whether `roots` gives the `TESSGEN_DISPLACE` build's entry (the
    /// displacing evaluation stage) instead of the default one.
    displace: bool,
}

impl<'a> Writer<'a> {
    fn new(plan: &'a Plan, module: &'a Module, entries: &'a Entries, stage: Stage) -> Self {
        let mut globals: HashSet<String> = HashSet::new();
        let modules = [&plan.common, module];
        for m in modules {
            globals.extend(m.functions.iter().map(|f| ident(&f.name)));
            globals.extend(m.consts.iter().map(|c| ident(&c.name)));
            globals.extend(m.structs.iter().map(|s| ident(&s.name)));
        }
        for b in abi::BINDINGS {
            globals.insert(b.name.to_string());
            globals.insert(block_name(b.name));
            globals.insert(format!("load_{}", b.name));
            globals.insert(format!("store_{}", b.name));
        }
        for g in [
            "tcs_cp",
            "KMAX",
            "KMAX4",
            "load_patch_cp",
            "store_patch_cp",
            "te_normal",
            "te_position",
            "Params",
        ] {
            globals.insert(g.to_string());
        }
        Writer {
            plan,
            module,
            entries,
            stage,
            out: String::new(),
            indent: 0,
            globals,
            locals: Vec::new(),
            displace: false,
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

    fn function(&self, r: FnRef) -> (&'a Module, &'a Function) {
        match r {
            FnRef::Common(i) => (&self.plan.common, &self.plan.common.functions[i]),
            FnRef::Local(i) => (self.module, &self.module.functions[i]),
        }
    }

    fn ty(&self, t: &Ty) -> String {
        match t {
            Ty::F32 => "float".into(),
            Ty::U32 => "uint".into(),
            Ty::Bool => "bool".into(),
            Ty::Vec3 => "vec3".into(),
            Ty::Struct(i) => ident(&self.plan.common.structs[*i].name),
        }
    }

    /// Plan functions the entry point of this file starts from.
    fn roots(&self) -> Vec<FnRef> {
        match self.stage {
            Stage::Vert => vec![],
            Stage::Tesc | Stage::CompPatch => {
                let mut r: Vec<FnRef> = self
                    .entries
                    .patches
                    .iter()
                    .map(|p| FnRef::Local(p.function))
                    .collect();
                if self.stage == Stage::Tesc {
                    r.push(FnRef::Common(crate::plan::common_fn::EDGE_FACTOR));
                }
                r
            }
            Stage::Tese => match (self.entries.eval_domain, &self.entries.tess_displaced) {
                (
                    Some(_),
                    Some(TessDisplaced {
                        eval_domain: Some(dd),
                        ..
                    }),
                ) if self.displace => vec![FnRef::Local(*dd)],
                (Some(d), _) => vec![FnRef::Local(d)],
                (None, Some(t)) if self.displace => vec![
                    FnRef::Local(t.eval_displaced),
                    FnRef::Local(self.entries.grid[0]),
                    FnRef::Local(self.entries.grid_index),
                ],
                (None, _) => vec![
                    FnRef::Local(self.entries.eval),
                    FnRef::Local(self.entries.grid[0]),
                    FnRef::Local(self.entries.grid_index),
                ],
            },
            Stage::CompEval => called(&self.entries.compute_eval),
            Stage::CompVertex => vec![FnRef::Local(self.entries.vertex_stage)],
            Stage::CompRefine => called(&self.entries.compute_refine),
        }
    }

    /// Every function reachable from the roots, in Plan order (common module
    /// first), each after the functions it calls.
    fn reachable(&self) -> Vec<FnRef> {
        fn mark(w: &Writer, r: FnRef, seen: &mut Vec<FnRef>) {
            if seen.contains(&r) {
                return;
            }
            seen.push(r);
            let in_common = matches!(r, FnRef::Common(_));
            for c in called(w.function(r).1) {
                mark(w, absolute(in_common, c), seen);
            }
        }
        fn emit(w: &Writer, r: FnRef, reach: &[FnRef], order: &mut Vec<FnRef>) {
            if order.contains(&r) || !reach.contains(&r) {
                return;
            }
            let in_common = matches!(r, FnRef::Common(_));
            for c in called(w.function(r).1) {
                emit(w, absolute(in_common, c), reach, order);
            }
            order.push(r);
        }
        let mut reach = Vec::new();
        for r in self.roots() {
            mark(self, r, &mut reach);
        }
        let all = (0..self.plan.common.functions.len())
            .map(FnRef::Common)
            .chain((0..self.module.functions.len()).map(FnRef::Local));
        let mut order = Vec::new();
        for r in all {
            emit(self, r, &reach, &mut order);
        }
        order
    }

    /// Bindings this file declares: `binding → (read here, written here)`.
    fn bindings(&self) -> BTreeMap<u32, (bool, bool)> {
        let mut need: BTreeMap<u32, (bool, bool)> = BTreeMap::new();
        if self.stage == Stage::Vert {
            return need;
        }
        let by_name = |n: &str| {
            abi::BINDINGS
                .iter()
                .find(|b| b.name == n)
                .map(|b| b.binding)
                .unwrap_or(0)
        };
        let mut add = |b: u32, w: bool| {
            let e = need.entry(b).or_insert((false, false));
            if w {
                e.1 = true;
            } else {
                e.0 = true;
            }
        };
        for r in self.roots() {
            let (_, f) = self.function(r);
            let (res, table) = resources_of(self.plan, self.module, f);
            for (r, w) in res {
                if self.stage.tess() && r == Resource::ControlPoints {
                    continue;
                }
                add(abi::binding_of(r).binding, w);
            }
            if table {
                add(by_name("stencil_table"), false);
            }
        }
        add(by_name("params"), false);
        match self.stage {
            Stage::CompVertex => {
                add(by_name("valence"), false);
                add(by_name("vertex_out_offsets"), false);
            }
            Stage::Tesc | Stage::CompPatch => {
                add(by_name("patch_faces"), false);
                if self.stage == Stage::Tesc {
                    // The adaptive factors' edge ids and end-point vertices.
                    add(by_name("face_edges"), false);
                    add(by_name("corner_vertex"), false);
                }
            }
            Stage::CompEval => {
                // The entry body's own: samples (written), patch_faces.
                for (r, w) in self.entries.compute_eval.resources() {
                    add(abi::binding_of(r).binding, w);
                }
            }
            Stage::Tese => {
                if self.displace {
                    // The patch's face, for its texture coordinates and owners.
                    add(by_name("patch_faces"), false);
                }
            }
            Stage::Vert | Stage::CompRefine => {}
        }
        need
    }

    /// The `TESSGEN_DISPLACE` build's additions to the evaluation stage:
    /// bindings and functions beyond the default build's (quad schemes).
    fn displace_extras(&mut self) -> Option<(Need, Vec<FnRef>)> {
        if self.stage != Stage::Tese || self.entries.tess_displaced.is_none() {
            return None;
        }
        let (need, fns) = (self.bindings(), self.reachable());
        self.displace = true;
        let (need_d, fns_d) = (self.bindings(), self.reachable());
        self.displace = false;
        let extra = need_d
            .into_iter()
            .filter(|(b, _)| !need.contains_key(b))
            .collect();
        let fns = fns_d.into_iter().filter(|r| !fns.contains(r)).collect();
        Some((extra, fns))
    }

    fn file(&mut self, command: &str) {
        for h in header_lines(command) {
            self.line(&format!("// {h}"));
        }
        self.line("//");
        let about = if self.stage == Stage::Tese && self.entries.eval_domain.is_some() {
            "Tessellation evaluation: position and normal at gl_TessCoord (the integer grid point on the patch boundary)."
        } else {
            self.stage.about()
        };
        self.line(&format!("// Scheme `{}`. {about}", self.module.name));
        self.line("");
        self.line("#version 450");
        if self.stage == Stage::Vert {
            self.line("");
            self.line("void main() {");
            self.line("    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);");
            self.line("}");
            return;
        }
        self.line("");
        match self.stage {
            Stage::Tesc => self.line("layout(vertices = 1) out;"),
            Stage::Tese if self.entries.sides == 3 => {
                self.line(
                    "// Triangle schemes: gl_TessCoord is barycentric; (x, y, z) weigh corners",
                );
                self.line("// (0, 1, 2) and `ccw` follows the corner order. Partitioning: integer");
                self.line("// (equal_spacing) unless the build defines TESSGEN_FRACTIONAL_ODD or");
                self.line("// TESSGEN_FRACTIONAL_EVEN (adaptive builds).");
                self.out.push_str(&format!(
                    "#if defined({})\nlayout(triangles, fractional_odd_spacing, ccw) in;\n#elif defined({})\nlayout(triangles, fractional_even_spacing, ccw) in;\n#else\n",
                    Define::FractionalOdd.name(),
                    Define::FractionalEven.name()
                ));
                self.line("layout(triangles, equal_spacing, ccw) in;");
                self.out.push_str("#endif\n");
            }
            Stage::Tese => {
                self.line(
                    "// Vulkan's default domain origin is the upper left corner, so `ccw` winds",
                );
                self.line("// counter-clockwise with the domain's y axis pointing down, i.e. clockwise in");
                self.line("// (gl_TessCoord.x, gl_TessCoord.y). The patch's (u, v) (u along v0 -> v1, v along");
                self.line(
                    "// v0 -> v3) is taken as (gl_TessCoord.y, gl_TessCoord.x): swapping the axes",
                );
                self.line("// reverses the winding, so the triangles wind counter-clockwise in (u, v), like");
                self.line("// the control face. (A pipeline created with");
                self.line("// VK_TESSELLATION_DOMAIN_ORIGIN_LOWER_LEFT would need `cw` here.)");
                self.line("// Partitioning: integer (equal_spacing) unless the build defines");
                self.line("// TESSGEN_FRACTIONAL_ODD or TESSGEN_FRACTIONAL_EVEN (adaptive builds only: the");
                self.line("// uniform path rounds the coordinate to i/level).");
                self.out.push_str(&format!(
                    "#if defined({})\nlayout(quads, fractional_odd_spacing, ccw) in;\n#elif defined({})\nlayout(quads, fractional_even_spacing, ccw) in;\n#else\n",
                    Define::FractionalOdd.name(),
                    Define::FractionalEven.name()
                ));
                self.line("layout(quads, equal_spacing, ccw) in;");
                self.out.push_str("#endif\n");
            }
            _ => self.line(&format!(
                "layout(local_size_x = {}, local_size_y = 1, local_size_z = 1) in;",
                abi::WORKGROUP_SIZE
            )),
        }
        let plan = self.plan;
        let module = self.module;
        self.line("");
        for m in [&plan.common, module] {
            self.consts(m);
        }
        for s in &plan.common.structs {
            self.line(&format!("struct {} {{", ident(&s.name)));
            for (n, t) in &s.fields {
                self.line(&format!("    {} {};", self.ty(t), ident(n)));
            }
            self.line("};");
            self.line("");
        }
        let need = self.bindings();
        for b in abi::BINDINGS {
            if let Some((_, written)) = need.get(&b.binding) {
                self.binding(b, *written);
            }
        }
        if self.stage.tess() {
            let dir = if self.stage == Stage::Tesc {
                "out"
            } else {
                "in"
            };
            self.line(
                "// Control points of this patch, written once by the control stage, packed:",
            );
            self.line(
                "// point j at floats 3j .. 3j+2 of KMAX4 vec4s. Per-patch outputs are counted",
            );
            self.line(
                "// in 4-component locations (maxTessellationControlPerPatchOutputComponents / 4),",
            );
            self.line("// so KMAX vec3 would take KMAX locations.");
            self.line(&format!("const uint KMAX = {}u;", self.entries.tess.points));
            self.line(&format!("const uint KMAX4 = {}u;", self.entries.tess.slots));
            self.line(&format!(
                "layout(location = 0) patch {dir} vec4 tcs_cp[KMAX4];"
            ));
            self.line("");
            // The Plan's packing of the control points into tcs_cp.
            let tess = &self.entries.tess;
            if self.stage == Stage::Tesc {
                self.plan_function(module, &tess.store_cp);
                self.line("");
            }
            self.plan_function(module, &tess.load_cp);
            self.line("");
        }
        if self.stage == Stage::Tese {
            self.line("layout(location = 0) out vec3 te_normal;");
            self.line("layout(location = 1) out vec3 te_position;");
            self.line("");
            self.out
                .push_str(&format!("#ifdef {}\n", Define::Capture.name()));
            if self.entries.sides == 3 {
                // Triangles: the hardware's inner vertices are not grid
                // points, so a capture harness records the output triangles
                // (a geometry shader) and needs their domain point and patch.
                self.line(
                    "// Capture: the domain point and the patch (params.first + gl_PrimitiveID) of",
                );
                self.line("// every vertex, for a harness that records the output triangles.");
                self.line("layout(location = 2) out vec3 te_domain;");
                self.line("layout(location = 3) flat out uint te_patch;");
            } else if let Some(b) = abi::BINDINGS.iter().find(|b| b.name == "samples") {
                // Capture builds bind the samples buffer (written from this stage).
                self.binding(b, true);
            }
            self.out.push_str("#endif\n");
            if self.entries.sides == 4 {
                // Adaptive patterns are not a grid: like the triangle
                // capture, export the domain point and the patch.
                self.out.push_str(&format!(
                    "#if defined({}) && defined({})\n",
                    Define::Capture.name(),
                    Define::Adaptive.name()
                ));
                self.line("// Adaptive capture: the domain point (u, v, 0) and the patch of every vertex,");
                self.line("// for a harness that records the output triangles.");
                self.line("layout(location = 2) out vec3 te_domain;");
                self.line("layout(location = 3) flat out uint te_patch;");
                self.out.push_str("#endif\n");
            }
            self.line("");
        }
        self.helpers(&need);
        let extras = self.displace_extras();
        if let Some((extra, _)) = &extras {
            self.out
                .push_str(&format!("#ifdef {}\n", Define::Displace.name()));
            self.line(
                "// Displacement: the global control-point buffer, filled by the compute patch",
            );
            self.line("// stage (patch_main) before the draw, for the owner's evaluation, and the");
            self.line("// displacement data (watertight.md Rules 4 and 5).");
            for b in abi::BINDINGS {
                if let Some((_, written)) = extra.get(&b.binding) {
                    self.binding(b, *written);
                }
            }
            self.helpers(extra);
            self.out.push_str("#endif\n");
            self.line("");
        }
        for r in self.reachable() {
            let (m, f) = self.function(r);
            self.plan_function(m, f);
            self.line("");
        }
        if let Some((_, fns)) = &extras {
            self.out
                .push_str(&format!("#ifdef {}\n", Define::Displace.name()));
            for r in fns {
                let (m, f) = self.function(*r);
                self.plan_function(m, f);
                self.line("");
            }
            self.out.push_str("#endif\n");
        }
        self.main();
    }

    fn consts(&mut self, m: &Module) {
        for c in &m.consts {
            self.doc(&c.doc);
            match &c.value {
                ConstValue::U32(x) => self.line(&format!("const uint {} = {x}u;", ident(&c.name))),
                ConstValue::U32Array(xs) => {
                    let body: Vec<String> = xs.iter().map(|x| format!("{x}u")).collect();
                    self.line(&format!(
                        "const uint {}[{n}] = uint[{n}]({});",
                        ident(&c.name),
                        body.join(", "),
                        n = xs.len()
                    ));
                }
            }
            self.line("");
        }
    }

    fn binding(&mut self, b: &Binding, written: bool) {
        self.line(&format!("// binding {}: {}", b.binding, b.doc));
        let access = if written { "" } else { "readonly " };
        let elem = match b.kind {
            Kind::U32Buffer => "uint",
            Kind::Vec3Buffer | Kind::F32Buffer => "float",
            Kind::Table => {
                self.line(&format!(
                    "layout(set = 0, binding = {}) uniform sampler2D {};",
                    b.binding, b.name
                ));
                self.line("");
                return;
            }
            Kind::Uniform => {
                self.line(&format!(
                    "layout(std140, set = 0, binding = {}) uniform Params {{",
                    b.binding
                ));
                for (i, (field, _)) in abi::PARAMS.iter().enumerate() {
                    let t = if i == 0 { "mat4" } else { "uint" };
                    self.line(&format!(
                        "    layout(offset = {}) {t} {};",
                        abi::params_offset(field),
                        ident(field)
                    ));
                }
                self.line(&format!("}} {};", b.name));
                self.line("");
                return;
            }
        };
        self.line(&format!(
            "layout(std430, set = 0, binding = {}) {access}buffer {} {{ {elem} {}[]; }};",
            b.binding,
            block_name(b.name),
            b.name
        ));
        self.line("");
    }

    /// `load_*` / `store_*` for the packed `vec3` buffers this file binds.
    fn helpers(&mut self, need: &BTreeMap<u32, (bool, bool)>) {
        for b in abi::BINDINGS {
            if b.kind != Kind::Vec3Buffer {
                continue;
            }
            let Some(&(read, written)) = need.get(&b.binding) else {
                continue;
            };
            let (n, Some(r)) = (b.name, abi::resource_of(b)) else {
                continue;
            };
            let module = self.module;
            if read {
                let f = crate::lower::entries::packed_load(
                    r,
                    &format!("load_{n}"),
                    "",
                    Offsets::Inline,
                );
                self.plan_function(module, &f);
                self.line("");
            }
            if written {
                let f = crate::lower::entries::packed_store(
                    r,
                    &format!("store_{n}"),
                    "",
                    Offsets::Inline,
                );
                self.plan_function(module, &f);
                self.line("");
            }
        }
    }

    fn main(&mut self) {
        self.line("void main() {");
        self.indent += 1;
        match self.stage {
            Stage::Vert => {}
            // The Plan's stage bodies: this printer adds only the API's
            // names for the stage inputs and outputs (`Expr::Stage`,
            // `Stmt::Output`).
            Stage::Tesc | Stage::Tese => {
                let entries = self.entries;
                let body = if self.stage == Stage::Tesc {
                    &entries.tess.control
                } else {
                    &entries.tess.evaluation
                };
                self.name_locals(body);
                self.stmts(self.module, body, &body.body);
            }
            Stage::CompVertex => {
                let body = &self.entries.compute_vertex;
                self.name_locals(body);
                self.stmts(self.module, body, &body.body);
            }
            Stage::CompPatch => {
                let body = &self.entries.compute_patch;
                self.name_locals(body);
                self.stmts(self.module, body, &body.body);
            }
            Stage::CompEval => {
                let body = &self.entries.compute_eval;
                self.name_locals(body);
                self.stmts(self.module, body, &body.body);
            }
            Stage::CompRefine => {
                let body = &self.entries.compute_refine;
                self.name_locals(body);
                self.stmts(self.module, body, &body.body);
            }
        }
        self.indent -= 1;
        self.line("}");
    }

    /// Names of `f`'s locals: GLSL-safe, unique, not shadowing a global.
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

    fn plan_function(&mut self, m: &Module, f: &Function) {
        self.doc(&f.doc);
        self.name_locals(f);
        let precise = if f.precise { "precise " } else { "" };
        let args: Vec<String> = f
            .params
            .iter()
            .map(|id| format!("{} {}", self.ty(&f.locals[id.0].ty), self.locals[id.0]))
            .collect();
        let ret = match &f.ret {
            Some(t) => format!("{precise}{}", self.ty(t)),
            None => "void".into(),
        };
        self.line(&format!("{ret} {}({}) {{", ident(&f.name), args.join(", ")));
        self.indent += 1;
        self.stmts(m, f, &f.body);
        self.indent -= 1;
        self.line("}");
    }

    fn decl(&self, f: &Function, id: LocalId) -> String {
        let precise = if f.precise { "precise " } else { "" };
        format!(
            "{precise}{} {}",
            self.ty(&f.locals[id.0].ty),
            self.locals[id.0]
        )
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
