//! HLSL printer: the Plan as HLSL Shader Model 5.0, one file per scheme
//! (`hlsl/<scheme>.hlsl`), compiled to SPIR-V by glslang's HLSL front end
//! (`glslangValidator -D -V -e ENTRY -S STAGE`).
//!
//! Each file holds several entry points, listed in its header as lines
//! `// entry: NAME stage: vert|tesc|tese|comp` so any tool can compile it:
//!
//! * `vs_main`, `hs_main` (with the patch-constant function
//!   `hs_patch_constants`) and `ds_main`: the hardware tessellation
//!   pipeline. The patch stage runs once per patch in the patch-constant
//!   function and hands the control points to the domain shader as
//!   semantic-indexed patch constants (`HsConstants.cp[KMAX] : CONTROL_POINT`);
//! * `vertex_stage_main`, `patch_main`, `eval_main`: the compute entry points
//!   of [`abi::entry`].
//!
//! Resources: the Plan's functions are printed once and serve both
//! pipelines, so control points always travel as an array parameter
//! (`in float3 cp[KMAX]` read, `inout float3 cp_out[KMAX]` written, indexed
//! exactly as the Plan indexes the resource; the entry points pass
//! `cp_base = 0` and copy to or from the `control_points` buffer). Every
//! other resource is a global: `StructuredBuffer<…> name : register(tK)` to
//! read, `RWStructuredBuffer<…> name[_rw] : register(uK)` to write, with
//! `[[vk::binding(K, 0)]]` so the SPIR-V bindings are the [`abi::BINDINGS`]
//! numbers. `vec3` buffers are packed `float` triples read and written
//! through `fetch_<name>`/`store_<name>` helpers.
//!
//! Every entry body is the Plan's: `hs_patch_constants` prints
//! [`TessStages::hull`] (the control stage into a patch-local array, then
//! packed into the `float4` patch constants), `ds_main`
//! [`TessStages::unpack`] and [`TessStages::evaluation`], `patch_main`
//! [`Entries::compute_patch_local`]. This printer adds the entry points'
//! signatures, the `HsConstants`/`DsOut` structs with their semantics, the
//! declarations of the patch-local arrays and their constants ([`Named`]),
//! and the names of the stage inputs and outputs (`SV_DomainLocation`, the
//! factor slots).
//!
//! Spelling only: every Binary is printed fully parenthesised as in the
//! Plan, f32 literals with Rust's shortest round-trip digits and an `f`
//! suffix, u32 literals with `u`; functions flagged `precise` get `precise`
//! on their return type and every local (glslang turns it into
//! `NoContraction`).

use super::abi::{self, Kind};
use super::dialect::{self, Dialect, Lines};
use super::{called, header_lines, resources_of};
use crate::lower::entries::Offsets;
use crate::outdir::GeneratedFile;
use crate::plan::*;
use std::collections::HashSet;

mod spell;
use spell::Hx;

/// Entry points of every emitted HLSL file, with the glslang stage name
/// (`-S`) each compiles as. Each file's header lists the same pairs.
pub const ENTRY_POINTS: &[(&str, &str)] = &[
    (VS_MAIN, "vert"),
    (HS_MAIN, "tesc"),
    (DS_MAIN, "tese"),
    (abi::entry::VERTEX_STAGE, "comp"),
    (abi::entry::PATCH_STAGE, "comp"),
    (abi::entry::EVAL, "comp"),
    (abi::entry::REFINE, "comp"),
];

/// Vertex shader of the tessellation pipeline (one point per patch).
pub const VS_MAIN: &str = "vs_main";
/// Hull shader (tessellation control); its patch-constant function is
/// [`HS_PATCH_CONSTANTS`].
pub const HS_MAIN: &str = "hs_main";
/// Patch-constant function of [`HS_MAIN`]: the patch stage, once per patch.
pub const HS_PATCH_CONSTANTS: &str = "hs_patch_constants";
/// Domain shader (tessellation evaluation).
pub const DS_MAIN: &str = "ds_main";

/// Print every scheme of the plan as one HLSL file each.
pub fn write(plan: &Plan, command: &str) -> Vec<GeneratedFile> {
    plan.schemes
        .iter()
        .map(|(m, e)| {
            let mut w = Writer::new(plan, m, e);
            w.file(command);
            GeneratedFile {
                path: format!("hlsl/{}.hlsl", m.name),
                contents: w.out.into_bytes(),
            }
        })
        .collect()
}

/// HLSL keywords, reserved words and intrinsics, whitespace-separated: a
/// Plan name equal to one of these gets a `_` appended.
const KEYWORDS: &str = "\
    AppendStructuredBuffer BlendState Buffer ByteAddressBuffer CompileShader ComputeShader \
    ConsumeStructuredBuffer DepthStencilState DepthStencilView DomainShader GeometryShader \
    HullShader InputPatch LineStream NULL OutputPatch PixelShader PointStream RWBuffer \
    RWByteAddressBuffer RWStructuredBuffer RWTexture1D RWTexture1DArray RWTexture2D \
    RWTexture2DArray RWTexture3D RasterizerState RenderTargetView SamplerComparisonState \
    SamplerState StructuredBuffer Texture1D Texture1DArray Texture2D Texture2DArray \
    Texture2DMS Texture2DMSArray Texture3D TextureCube TextureCubeArray TriangleStream \
    VertexShader asm asm_fragment auto bool break case catch cbuffer centroid char class \
    column_major compile compile_fragment const const_cast continue default delete discard do \
    double dword dynamic_cast else enum explicit export extern false float for friend fxgroup \
    goto groupshared half if in inline inout int interface line lineadj linear long matrix \
    min10float min12int min16float min16int min16uint mutable namespace new nointerpolation \
    noperspective operator out packoffset pass patch pixelfragment point precise private \
    protected public register reinterpret_cast return row_major sample sampler sampler1D \
    sampler2D sampler3D samplerCUBE samplerCube sampler_state shared short signed sizeof snorm \
    stateblock stateblock_state static static_cast string struct switch tbuffer technique \
    technique10 technique11 template texture this throw triangle triangleadj true try typedef \
    typename uint uniform union unorm unsigned using vector vertexfragment virtual void \
    volatile while abs acos all any asfloat asin asint asuint atan atan2 ceil clamp clip cos \
    cosh cross ddx ddy degrees determinant distance dot exp exp2 floor fma fmod frac frexp \
    fwidth isfinite isinf isnan ldexp length lerp lit log log10 log2 mad max min modf mul \
    normalize pow radians rcp reflect refract round rsqrt saturate sign sin sincos sinh \
    smoothstep sqrt step tan tanh transpose trunc";

/// `float3`, `uint2x4`, … are type keywords too.
fn is_vector_type(name: &str) -> bool {
    const SCALARS: &[&str] = &[
        "bool",
        "int",
        "uint",
        "dword",
        "half",
        "float",
        "double",
        "min16float",
        "min10float",
        "min16int",
        "min12int",
        "min16uint",
    ];
    SCALARS.iter().any(|s| {
        name.strip_prefix(s).is_some_and(|rest| {
            let b = rest.as_bytes();
            let dim = |c: u8| (b'1'..=b'4').contains(&c);
            (b.len() == 1 && dim(b[0])) || (b.len() == 3 && dim(b[0]) && b[1] == b'x' && dim(b[2]))
        })
    })
}

/// A Plan name as an HLSL identifier.
fn ident(name: &str) -> String {
    if KEYWORDS.split_whitespace().any(|k| k == name)
        || is_vector_type(name)
        || name.starts_with("gl_")
    {
        format!("{name}_")
    } else {
        name.to_string()
    }
}

fn f32_lit(x: f32) -> String {
    if !x.is_finite() {
        return format!("asfloat(0x{:08x}u)", x.to_bits());
    }
    let s = format!("{x:?}f");
    if x.is_sign_negative() {
        format!("({s})")
    } else {
        s
    }
}

/// Name of the read-only view of a binding, if it has one (every binding but
/// a write-only output).
fn read_view(b: &abi::Binding) -> Option<String> {
    (b.resource.is_some() || !b.written).then(|| b.name.to_string())
}

/// Name of the read-write view of a binding, if it is written.
fn write_view(b: &abi::Binding) -> Option<String> {
    b.written.then(|| match read_view(b) {
        Some(_) => format!("{}_rw", b.name),
        None => b.name.to_string(),
    })
}

/// How a function reaches the control points: as `cp` (read) or
/// `cp_out` (written, `inout`).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Cp {
    None,
    In,
    InOut,
}

impl Cp {
    fn name(self) -> &'static str {
        match self {
            Cp::InOut => "cp_out",
            _ => "cp",
        }
    }
}

/// What the printer needs while inside one function.
struct Ctx<'f> {
    m: &'f Module,
    f: &'f Function,
    /// HLSL name of every local.
    names: Vec<String>,
    cp: Cp,
    /// Spelling of [`StageIn::PatchInDraw`] (tessellation stage bodies).
    patch: &'static str,
}

pub struct Writer<'a> {
    plan: &'a Plan,
    module: &'a Module,
    entries: &'a Entries,
    out: String,
    indent: usize,
    /// Global names a local must not shadow.
    globals: HashSet<String>,
}

impl<'a> Writer<'a> {
    fn new(plan: &'a Plan, module: &'a Module, entries: &'a Entries) -> Self {
        let mut globals: HashSet<String> = [
            "params",
            "Params",
            "ParamsBlock",
            Named::Kmax.name(),
            Named::Kmax4.name(),
            Named::ControlPoints.name(),
            "load_patch_cp",
            "store_patch_cp",
            "cp",
            "cp_out",
            "VsOut",
            "HsControlPoint",
            "HsConstants",
            "DsOut",
            VS_MAIN,
            HS_MAIN,
            HS_PATCH_CONSTANTS,
            DS_MAIN,
            abi::entry::VERTEX_STAGE,
            abi::entry::PATCH_STAGE,
            abi::entry::EVAL,
            abi::entry::REFINE,
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for b in abi::BINDINGS {
            globals.extend(read_view(b));
            globals.extend(write_view(b));
            globals.insert(format!("fetch_{}", b.name));
            globals.insert(format!("store_{}", b.name));
        }
        for m in [&plan.common, module] {
            globals.extend(m.consts.iter().map(|c| ident(&c.name)));
            globals.extend(m.functions.iter().map(|f| ident(&f.name)));
            for s in &m.structs {
                globals.insert(ident(&s.name));
                globals.insert(format!("make_{}", s.name));
            }
        }
        Writer {
            plan,
            module,
            entries,
            out: String::new(),
            indent: 0,
            globals,
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
            Ty::F32 => "float".into(),
            Ty::U32 => "uint".into(),
            Ty::Bool => "bool".into(),
            Ty::Vec3 => "float3".into(),
            Ty::Struct(i) => ident(&self.plan.common.structs[*i].name),
        }
    }

    fn cp_of(&self, m: &Module, f: &Function) -> Cp {
        let (res, _) = resources_of(self.plan, m, f);
        if res.contains(&(Resource::ControlPoints, true)) {
            Cp::InOut
        } else if res.contains(&(Resource::ControlPoints, false)) {
            Cp::In
        } else {
            Cp::None
        }
    }

    fn file(&mut self, command: &str) {
        for h in header_lines(command) {
            self.line(&format!("// {h}"));
        }
        for (name, stage) in ENTRY_POINTS {
            self.line(&format!("// entry: {name} stage: {stage}"));
        }
        let scheme = self.module.name.clone();
        let text = format!(
            r#"//
// HLSL (Shader Model 5.0) for the `{scheme}` scheme. Compile each entry point
// above on its own, e.g. with glslang's HLSL front end:
//     glslangValidator -D -V -e ENTRY -S STAGE {scheme}.hlsl
// Tessellation pipeline: vs_main -> hs_main (patch stage in
// hs_patch_constants, once per patch) -> ds_main. Compute: vertex_stage_main,
// patch_main, eval_main, and refine_main before them for a refined mesh
// (docs/boundaries.md §8). All bindings are in set 0 (generated/README.md)."#
        );
        for l in text.lines() {
            self.line(l);
        }
        self.line("");
        self.bindings();
        self.line("");
        self.helpers();
        let plan = self.plan;
        self.line("");
        self.print_module(&plan.common);
        self.line("");
        self.print_module(self.module);
        self.line("");
        self.compute_entries();
        self.line("");
        self.tessellation_entries();
    }

    fn bindings(&mut self) {
        self.line("// ---- bindings (set 0; register number = binding number) ----");
        self.line("");
        self.line("// The Params uniform block. view_proj is column-major and used as");
        self.line(
            "// mul(view_proj, float4(p, 1)): clip = view_proj · p, as in the GLSL/WGSL targets.",
        );
        self.line("struct Params {");
        for (name, doc) in abi::PARAMS {
            let t = if *name == "view_proj" {
                "column_major float4x4"
            } else {
                "uint"
            };
            self.line(&format!(
                "    {t} {}; // offset {}: {doc}",
                ident(name),
                abi::params_offset(name)
            ));
        }
        self.line("};");
        for b in abi::BINDINGS {
            self.line("");
            self.line(&format!("// binding {}: {}", b.binding, b.doc));
            let attr = format!("[[vk::binding({}, 0)]]", b.binding);
            let k = b.binding;
            match b.kind {
                Kind::Uniform => self.line(&format!(
                    "{attr} cbuffer ParamsBlock : register(b{k}) {{ Params params; }};"
                )),
                Kind::Table => self.line(&format!(
                    "{attr} Texture2D<float> {} : register(t{k});",
                    b.name
                )),
                Kind::U32Buffer | Kind::Vec3Buffer | Kind::F32Buffer => {
                    let elem = if b.kind == Kind::U32Buffer {
                        "uint"
                    } else {
                        "float"
                    };
                    if let Some(n) = read_view(b) {
                        self.line(&format!(
                            "{attr} StructuredBuffer<{elem}> {n} : register(t{k});"
                        ));
                    }
                    if let Some(n) = write_view(b) {
                        self.line(&format!(
                            "{attr} RWStructuredBuffer<{elem}> {n} : register(u{k});"
                        ));
                    }
                }
            }
        }
        self.line("");
        self.line("// Most control points of any class of this scheme (size of every control-point array).");
        self.line(&format!(
            "static const uint {} = {}u;",
            Named::Kmax.name(),
            self.entries.tess.points
        ));
        self.line(
            "// vec4 slots of the packed per-patch control points (3·KMAX floats): per-patch",
        );
        self.line("// outputs are counted in 4-component locations (maxTessellationControlPerPatchOutputComponents / 4).");
        self.line(&format!(
            "static const uint {} = {}u;",
            Named::Kmax4.name(),
            self.entries.tess.slots
        ));
        self.line("// Control points per patch of each class (index = Params.class).");
        let ks: Vec<String> = self
            .entries
            .patches
            .iter()
            .map(|p| format!("{}u", p.control_points))
            .collect();
        self.line(&format!(
            "static const uint {}[{}] = {{{}}};",
            Named::ControlPoints.name(),
            ks.len().max(1),
            if ks.is_empty() {
                "0u".to_string()
            } else {
                ks.join(", ")
            }
        ));
    }

    /// Packed `float` triple access of the `vec3` buffers.
    fn helpers(&mut self) {
        self.line(
            "// ---- vec3 buffers: packed float triples, point i at floats 3i, 3i+1, 3i+2 ----",
        );
        for b in abi::BINDINGS.iter().filter(|b| b.kind == Kind::Vec3Buffer) {
            let Some(r) = abi::resource_of(b) else {
                continue;
            };
            let module = self.module;
            if read_view(b).is_some() {
                self.line("");
                let name = format!("fetch_{}", b.name);
                let f = crate::lower::entries::packed_load(r, &name, "", Offsets::Inline);
                self.function_with(module, &f, Cp::None);
            }
            if write_view(b).is_some() {
                self.line("");
                let name = format!("store_{}", b.name);
                let f = crate::lower::entries::packed_store(r, &name, "", Offsets::Inline);
                self.function_with(module, &f, Cp::None);
            }
        }
    }

    fn print_module(&mut self, m: &Module) {
        self.line(&format!("// ---- module `{}` ----", m.name));
        self.doc(&m.doc);
        for c in &m.consts {
            self.line("");
            self.doc(&c.doc);
            match &c.value {
                ConstValue::U32(x) => {
                    self.line(&format!("static const uint {} = {x}u;", ident(&c.name)))
                }
                ConstValue::U32Array(xs) => {
                    let body: Vec<String> = xs.iter().map(|x| format!("{x}u")).collect();
                    self.line(&format!(
                        "static const uint {}[{}] = {{{}}};",
                        ident(&c.name),
                        xs.len().max(1),
                        if body.is_empty() {
                            "0u".to_string()
                        } else {
                            body.join(", ")
                        }
                    ));
                }
            }
        }
        for s in &m.structs {
            self.line("");
            let name = ident(&s.name);
            self.line(&format!("struct {name} {{"));
            for (n, t) in &s.fields {
                self.line(&format!("    {} {};", self.ty(t), ident(n)));
            }
            self.line("};");
            // HLSL has no struct constructor expressions: one helper per struct.
            self.line("");
            let args: Vec<String> = s
                .fields
                .iter()
                .map(|(n, t)| format!("{} {}", self.ty(t), ident(n)))
                .collect();
            self.line(&format!("{name} make_{}({}) {{", s.name, args.join(", ")));
            self.line(&format!("    {name} s;"));
            for (n, _) in &s.fields {
                let n = ident(n);
                self.line(&format!("    s.{n} = {n};"));
            }
            self.line("    return s;");
            self.line("}");
        }
        // Only what an entry point here calls: `eval_displaced` (and the
        // functions built on it) evaluate owner patches at their cp_base in
        // one control-point array, but HLSL's evaluation reads a
        // patch-local array (`cp`); the domain shader displaces through
        // `eval_displaced_tess`, whose owner evaluation (`eval_global`)
        // reads the global buffer (TESSGEN_DISPLACE). The instanced path's
        // adaptive functions have no HLSL entry either.
        let used = self.used_functions();
        let common = std::ptr::eq(m, &self.plan.common);
        let skip: Vec<usize> = (0..m.functions.len())
            .filter(|&i| {
                let r = if common {
                    FnRef::Common(i)
                } else {
                    FnRef::Local(i)
                };
                !used.contains(&r)
            })
            .collect();
        for (i, f) in m.functions.iter().enumerate() {
            if skip.contains(&i) {
                continue;
            }
            self.line("");
            self.function(m, f);
        }
    }

    /// The functions the entry points of this file reach, as `FnRef`s
    /// (`Common(i)`, `Local(i)` of the scheme module): the Plan's stage
    /// bodies ([`TessStages`], the compute vertex stage, patch stage and
    /// evaluation), and everything those call.
    fn used_functions(&self) -> Vec<FnRef> {
        let e = self.entries;
        let mut todo: Vec<FnRef> = Vec::new();
        for body in [
            &e.tess.hull,
            &e.tess.unpack,
            &e.tess.evaluation,
            &e.compute_vertex,
            &e.compute_patch_local,
            &e.compute_eval,
            &e.compute_refine,
        ] {
            todo.extend(called(body));
        }
        let mut used = Vec::new();
        while let Some(r) = todo.pop() {
            if used.contains(&r) {
                continue;
            }
            used.push(r);
            todo.extend(match r {
                FnRef::Local(i) => called(&self.module.functions[i]),
                // Inside the common module, `Local` names a common function.
                FnRef::Common(i) => called(&self.plan.common.functions[i])
                    .into_iter()
                    .map(|c| match c {
                        FnRef::Local(j) | FnRef::Common(j) => FnRef::Common(j),
                    })
                    .collect(),
            });
        }
        used
    }

    /// HLSL names of a function's locals: escaped, never shadowing a global,
    /// unique within the function.
    fn local_names(&self, f: &Function) -> Vec<String> {
        let mut names: Vec<String> = Vec::with_capacity(f.locals.len());
        for (i, l) in f.locals.iter().enumerate() {
            let mut n = ident(&l.name);
            if self.globals.contains(&n) {
                n.push('_');
            }
            if names.contains(&n) {
                n = format!("{n}_{i}");
            }
            names.push(n);
        }
        names
    }

    fn function(&mut self, m: &Module, f: &Function) {
        self.function_with(m, f, self.cp_of(m, f))
    }

    /// `f`, reaching the control points as `cp` says (the packed accessors
    /// read the buffer itself: [`Cp::None`]).
    fn function_with(&mut self, m: &Module, f: &Function, cp: Cp) {
        self.doc(&f.doc);
        let cx = Ctx {
            m,
            f,
            names: self.local_names(f),
            cp,
            patch: "patch_id",
        };
        let mut args = Vec::new();
        match cx.cp {
            Cp::None => {}
            Cp::In => args.push("in float3 cp[KMAX]".to_string()),
            Cp::InOut => args.push("inout float3 cp_out[KMAX]".to_string()),
        }
        for id in &f.params {
            args.push(format!(
                "{} {}",
                self.ty(&f.locals[id.0].ty),
                cx.names[id.0]
            ));
        }
        let ret = f
            .ret
            .as_ref()
            .map(|t| self.ty(t))
            .unwrap_or_else(|| "void".into());
        let precise = if f.precise { "precise " } else { "" };
        self.line(&format!(
            "{precise}{ret} {}({}) {{",
            ident(&f.name),
            args.join(", ")
        ));
        self.indent += 1;
        self.stmts(&cx, &f.body);
        self.indent -= 1;
        self.line("}");
    }

    fn decl(&self, cx: &Ctx, id: &LocalId) -> String {
        let precise = if cx.f.precise { "precise " } else { "" };
        format!(
            "{precise}{} {}",
            self.ty(&cx.f.locals[id.0].ty),
            cx.names[id.0]
        )
    }

    fn stmts(&mut self, cx: &Ctx, body: &[Stmt]) {
        let mut lines = Lines {
            out: std::mem::take(&mut self.out),
            indent: self.indent,
        };
        dialect::stmts(&Hx { w: self, cx }, body, &mut lines);
        self.out = lines.out;
    }

    fn callee<'m>(&self, m: &'m Module, r: FnRef) -> (&'m Module, &'m Function)
    where
        'a: 'm,
    {
        match r {
            FnRef::Common(i) => (&self.plan.common, &self.plan.common.functions[i]),
            FnRef::Local(i) => (m, &m.functions[i]),
        }
    }

    // ---- entry points: signatures and stage I/O around the Plan's bodies ----

    fn compute_entries(&mut self) {
        let wg = abi::WORKGROUP_SIZE;
        self.line("// ---- compute entry points ----");
        self.line("");
        self.line("// Vertex stage of vertices params.first .. params.first + params.count");
        self.line("// (valence 0 = unused vertex, skipped).");
        self.line(&format!("[numthreads({wg}, 1, 1)]"));
        self.line(&format!(
            "void {}(uint3 global_id : SV_DispatchThreadID) {{",
            abi::entry::VERTEX_STAGE
        ));
        self.indent += 1;
        let entries = self.entries;
        self.tess_body(&entries.compute_vertex, "patch_id", None, &[]);
        self.indent -= 1;
        self.line("}");

        self.line("");
        self.line("// Patch stage of patches params.first .. params.first + params.count, all of");
        self.line("// class params.class: the class's patch function fills a patch-local array");
        self.line("// (cp_base 0), copied to control_points from params.cp_base + k·CONTROL_POINTS[class].");
        self.line(&format!("[numthreads({wg}, 1, 1)]"));
        self.line(&format!(
            "void {}(uint3 global_id : SV_DispatchThreadID) {{",
            abi::entry::PATCH_STAGE
        ));
        self.indent += 1;
        self.tess_body(&entries.compute_patch_local, "patch_id", None, &[]);
        self.indent -= 1;
        self.line("}");

        self.line("");
        self.line(
            "// Evaluation: grid_len(level) samples per patch of params.first .. + params.count,",
        );
        self.line("// sample s of a patch at (iu, iv) = (grid_iu(s), grid_iv(s)), through the");
        self.line("// displacement step (eval_displaced_global: every patch from the global");
        self.line(
            "// control-point buffer), written as 6 floats at samples[(params.out_base + k)·6].",
        );
        self.line(&format!("[numthreads({wg}, 1, 1)]"));
        self.line(&format!(
            "void {}(uint3 global_id : SV_DispatchThreadID) {{",
            abi::entry::EVAL
        ));
        self.indent += 1;
        self.tess_body(&entries.compute_eval, "patch_id", None, &[]);
        self.indent -= 1;
        self.line("}");

        self.line("");
        self.line(
            "// Refinement stage of refined vertices params.first .. params.first + params.count:",
        );
        self.line(
            "// each its stencil row over refine_base, into refined_positions (bind the buffer",
        );
        self.line("// the vertex stage reads as positions). Run before vertex_stage_main.");
        self.line(&format!("[numthreads({wg}, 1, 1)]"));
        self.line(&format!(
            "void {}(uint3 global_id : SV_DispatchThreadID) {{",
            abi::entry::REFINE
        ));
        self.indent += 1;
        self.tess_body(&entries.compute_refine, "patch_id", None, &[]);
        self.indent -= 1;
        self.line("}");
    }

    /// An entry body of the Plan ([`TessStages`], the compute bodies) inside
    /// its entry point; `patch` spells [`StageIn::PatchInDraw`] there, `cp`
    /// (default: as the body uses it) names the patch-local array, and
    /// `taken` holds the names of an earlier body in the same scope. Returns
    /// the local names used.
    fn tess_body(
        &mut self,
        f: &Function,
        patch: &'static str,
        cp: Option<Cp>,
        taken: &[String],
    ) -> Vec<String> {
        let module = self.module;
        let mut names = self.local_names(f);
        // The entry point's own names.
        for n in names.iter_mut() {
            while ["c", "o", "uv", "ctrl", "patch_id"].contains(&n.as_str()) || taken.contains(n) {
                n.push('_');
            }
        }
        let cx = Ctx {
            m: module,
            f,
            names,
            cp: cp.unwrap_or_else(|| self.cp_of(module, f)),
            patch,
        };
        self.stmts(&cx, &f.body);
        cx.names
    }

    /// The Plan's packing function `f` ([`TessStages::store_cp`],
    /// [`TessStages::load_cp`]) with the patch constants `c` as its first
    /// parameter ([`Expr::PatchSlot`] is `c.cp[slot][comp]`).
    fn patch_slot_function(&mut self, f: &Function, c: &str) {
        self.doc(&f.doc);
        let mut names = self.local_names(f);
        for n in names.iter_mut() {
            while n == "c" {
                n.push('_');
            }
        }
        let mut args = vec![c.to_string()];
        for id in &f.params {
            args.push(format!("{} {}", self.ty(&f.locals[id.0].ty), names[id.0]));
        }
        let ret = f
            .ret
            .as_ref()
            .map(|t| self.ty(t))
            .unwrap_or_else(|| "void".into());
        self.line(&format!("{ret} {}({}) {{", ident(&f.name), args.join(", ")));
        let cx = Ctx {
            m: self.module,
            f,
            names,
            cp: Cp::None,
            patch: "patch_id",
        };
        self.indent += 1;
        self.stmts(&cx, &f.body);
        self.indent -= 1;
        self.line("}");
    }

    fn tessellation_entries(&mut self) {
        let tri = self.entries.sides == 3;
        let (domain, edges, uv_ty) = if tri {
            ("tri", 3, "float3")
        } else {
            ("quad", 4, "float2")
        };
        let factor_doc = if tri {
            "// Per-patch outputs. Tess factors: edges[k] is the edge opposite corner k\n\
             // (barycentric coordinate k = 0), i.e. our edges 1 (v1 -> v2), 2 (v2 -> v0),\n\
             // 0 (v0 -> v1); inside is the one inside factor."
        } else {
            "// Per-patch outputs. Tess factors: edges[0] is the u = 0 edge, [1] v = 0,\n\
             // [2] u = 1, [3] v = 1 (D3D and Vulkan alike), i.e. our edges 3, 0, 1, 2;\n\
             // inside[0] subdivides along u (our edges 0 and 2), inside[1] along v."
        };
        let inside_decl = if tri {
            "float inside : SV_InsideTessFactor;"
        } else {
            "float inside[2] : SV_InsideTessFactor;"
        };
        let partitioning = format!(
            "// Partitioning: integer unless the build defines TESSGEN_FRACTIONAL_ODD or\n\
             // TESSGEN_FRACTIONAL_EVEN (adaptive builds only).\n\
             #if defined({})\n[partitioning(\"fractional_odd\")]\n#elif defined({})\n[partitioning(\"fractional_even\")]\n#else\n[partitioning(\"integer\")]\n#endif",
            Define::FractionalOdd.name(),
            Define::FractionalEven.name()
        );
        let capture = Define::Capture.name();
        let ds_out_capture = if tri {
            format!("#ifdef {capture}\n")
        } else {
            format!(
                "#if defined({capture}) && defined({})\n",
                Define::Adaptive.name()
            )
        };
        let domain_doc = if tri {
            "// SV_DomainLocation is barycentric, (x, y, z) weighing corners (0, 1, 2)."
        } else {
            "// SV_DomainLocation (x, y) is the patch's (u, v) as is: u along v0 -> v1,\n\
             // v along v0 -> v3, corner k at (0,0), (1,0), (1,1), (0,1)."
        };
        let text = format!(
            r#"// ---- tessellation pipeline: {VS_MAIN} -> {HS_MAIN} -> {DS_MAIN} ----
// Draw params.count patches of class params.class (patch list, 1 control
// point per patch, no vertex buffer); patch p of the draw is face
// patch_faces[params.first + p]. The stage bodies are the Plan's; the
// control points travel packed, point j at floats 3j .. 3j+2 of KMAX4
// float4 patch constants.

struct VsOut {{
    float4 position : SV_Position;
}};

VsOut {VS_MAIN}(uint vertex_id : SV_VertexID) {{
    VsOut o;
    o.position = float4(0.0f, 0.0f, 0.0f, 1.0f);
    return o;
}}

struct HsControlPoint {{
    float4 position : SV_Position;
}};

{factor_doc}
struct HsConstants {{
    float edges[{edges}] : SV_TessFactor;
    {inside_decl}
    // Control point j at floats 3j .. 3j+2 of the packed array.
    float4 cp[KMAX4] : CONTROL_POINT;
    // glslang's HLSL front end reads a domain shader's SV_PrimitiveID as a
    // user input, so the hull passes the patch index on as a constant.
    uint patch_id : PATCH_ID;
}};
"#
        );
        for l in text.lines() {
            self.line(l);
        }
        let entries = self.entries;
        self.patch_slot_function(&entries.tess.store_cp, "inout HsConstants c");
        self.line("");
        self.patch_slot_function(&entries.tess.load_cp, "HsConstants c");
        self.line("");
        self.line("// The patch stage, once per patch, and the tessellation factors.");
        self.line(&format!(
            "HsConstants {HS_PATCH_CONSTANTS}(uint patch_id : SV_PrimitiveID) {{"
        ));
        self.indent += 1;
        self.line("HsConstants c;");
        self.tess_body(&entries.tess.hull, "patch_id", None, &[]);
        self.indent -= 1;
        let text = format!(
            r#"    c.patch_id = patch_id;
    return c;
}}

[domain("{domain}")]
{partitioning}
[outputtopology("triangle_ccw")]
[outputcontrolpoints(1)]
[patchconstantfunc("{HS_PATCH_CONSTANTS}")]
HsControlPoint {HS_MAIN}(InputPatch<VsOut, 1> ip, uint id : SV_OutputControlPointID) {{
    HsControlPoint o;
    o.position = ip[0].position;
    return o;
}}

struct DsOut {{
    float4 position : SV_Position;
    float3 normal : NORMAL;
    float3 world : WORLD_POSITION;
{ds_out_capture}    // Capture: the domain point and the patch of every vertex, for a harness
    // that records the output triangles.
    float3 domain : TESSGEN_DOMAIN;
    nointerpolation uint patch_index : TESSGEN_PATCH;
#endif
}};

{domain_doc}
[domain("{domain}")]
DsOut {DS_MAIN}(HsConstants c, {uv_ty} uv : SV_DomainLocation, const OutputPatch<HsControlPoint, 1> ctrl) {{"#
        );
        for l in text.lines() {
            self.line(l);
        }
        self.indent += 1;
        // The array the evaluation reads, filled from the patch constants.
        let taken = self.tess_body(&entries.tess.unpack, "c.patch_id", Some(Cp::In), &[]);
        self.line("DsOut o;");
        self.tess_body(&entries.tess.evaluation, "c.patch_id", None, &taken);
        self.line("return o;");
        self.indent -= 1;
        self.line("}");
    }
}
