//! The Plan: one ordered list of statements per function, in a tiny typed
//! imperative IR that every printer walks without deciding anything.
//!
//! Every sum is written with explicit association (`((a + b) + c)` is a
//! nested [`Expr::Binary`]), every weight pair of a lerp is formed once from
//! integers, every memory access is a [`Resource`] fetch with an explicit
//! index. A printer's job is only to spell these in its language; if two
//! printers disagree on a result, the bug is in a printer.

pub mod abi;
pub mod flat;
pub mod form;
mod walk;
pub use walk::{binding, called, resources_of, walk, walk_expr, Node};

/// Value types.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Ty {
    F32,
    U32,
    Bool,
    Vec3,
    /// A struct declared in [`Module::structs`].
    Struct(usize),
}

mod resource;
pub use resource::Resource;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    And,
    Or,
    /// `u32` left shift.
    Shl,
    /// `u32` bitwise and.
    BitAnd,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Builtin {
    /// `f32` from `u32` (exact for the integers we convert).
    F32FromU32,
    Sqrt,
    Cos,
    Sin,
    Dot,
    Cross,
    /// `vec3(x, y, z)` from three f32.
    Vec3,
    /// Nearest integer of an f32 (as f32); only used on values within
    /// rounding error of an integer, where every language's tie rule agrees.
    Round,
    /// `floor(x)` of an f32.
    Floor,
    /// `u32` from a non-negative integral (or already floored) `f32`
    /// (truncation).
    U32FromF32,
    /// `u32` 1 from `true`, 0 from `false` (branch-free selections).
    U32FromBool,
    /// The larger of two f32 (inside tessellation factors; never NaN there:
    /// the factor functions clamp).
    Max,
    /// Component 0, 1 or 2 (`.x`, `.y`, `.z`) of a `vec3` (or `vec2`).
    Component(u8),
    /// Trailing zero bits of a `u32` (32 for 0): the WGSL bucket passes.
    CountTrailingZeros,
    /// Unit vector of a `vec3` (the built-in, unguarded; the fragment entry).
    Normalize,
    /// Absolute value of an f32.
    Abs,
    /// The smaller of two f32.
    Min,
    /// Screen-space derivative width of an f32 (fragment entries only).
    Fwidth,
    /// A `vec2` from two f32: only as a stage output ([`StageOut::Uv`]),
    /// never a local's type.
    Vec2,
    /// The clip-space position of a world point, the uniform block's
    /// `view_proj · (p, 1)` (a matrix–vector product, the language's own
    /// operator): only as the value of [`StageOut::Clip`], never a local.
    Project,
}

/// A value only the hardware tessellation stages have: [`Expr::Stage`] in
/// the bodies of [`TessStages`]. Each printer spells it in its API (which
/// builtin, which axis); the Plan says what it means.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StageIn {
    /// `f32` domain coordinate `k` of the tessellator's point. Quads: the
    /// patch's `(u, v)` for `k` = 0, 1 (u along `v0 → v1`, v along
    /// `v0 → v3`); the printer maps them to its API's axes (GLSL takes
    /// `(gl_TessCoord.y, gl_TessCoord.x)`: the axis swap that keeps the
    /// winding counter-clockwise under Vulkan's upper-left domain origin;
    /// HLSL `SV_DomainLocation` `(x, y)`). Triangles: the barycentric weight
    /// of corner `k` (`x, y, z` in both APIs).
    TessCoord(u8),
    /// `u32` index of the patch within the draw (`gl_PrimitiveID`; HLSL's
    /// hull passes its `SV_PrimitiveID` on as a patch constant).
    PatchInDraw,
    /// A `u32` field of the `Params` uniform block, by name
    /// (`backend::abi::PARAMS`).
    Param(&'static str),
    /// `u32` index of the compute invocation (`x` of the global invocation
    /// id): the compute entry bodies ([`Entries::compute_vertex`]).
    GlobalId,
    /// `u32` `y` of the global invocation id (two-row indirect dispatches).
    GlobalIdY,
    /// `u32` `x` of the workgroup id.
    WorkgroupId,
    /// `u32` index of the invocation within its workgroup.
    LocalIndex,
    /// `u32` vertex index of a vertex entry.
    VertexIndex,
    /// `u32` instance index of a vertex entry.
    InstanceIndex,
    /// A fragment entry's interpolated input: the vertex entry's output.
    Varying(StageOut),
}

/// An output of a hardware tessellation stage: [`Stmt::Output`] in the
/// bodies of [`TessStages`]. Like [`StageIn`], the meaning is the Plan's,
/// the slot or variable is the printer's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StageOut {
    /// Control stage: `f32` tessellation factor of patch edge `k`
    /// (`v_k → v_{k+1}`). The printer puts it in its API's outer slot
    /// (`lower::hw_factor_edges`).
    EdgeFactor(u8),
    /// Control stage: `f32` inside factor subdividing along patch axis `d`
    /// (quads: 0 = u, 1 = v; triangles: the one inside factor, `d` = 0).
    InsideFactor(u8),
    /// Evaluation stage: the `vec3` world position.
    Position,
    /// Evaluation stage: the clip-space position ([`Builtin::Project`] of
    /// the world position).
    Clip,
    /// Evaluation stage: the `vec3` normal.
    Normal,
    /// Evaluation stage, capture builds that record triangles: the `vec3`
    /// domain point of the vertex.
    Domain,
    /// Evaluation stage, capture builds that record triangles: the `u32`
    /// patch (index into `patch_faces`) of the vertex.
    Patch,
    /// Instanced vertex entry: the `u32` patch class (flat).
    PatchClass,
    /// Instanced vertex entry: the `vec2` domain point `(u, v)`.
    Uv,
    /// Fragment entry: the `vec3` colour (opaque).
    Color,
}

/// The bodies of the hardware tessellation stages (GLSL `.tesc`/`.tese`
/// `main`, HLSL `hs_patch_constants`/`ds_main`), built once in the Plan so
/// the GLSL and HLSL printers print the same statements and only add their
/// API's declarations around them (stage I/O, attributes, the per-patch
/// storage). The packing of the control points into its `vec4` slots is
/// Plan code too ([`TessStages::store_cp`], [`TessStages::load_cp`], and
/// HLSL's patch-local copies [`TessStages::hull`], [`TessStages::unpack`]).
/// Targets without tessellation stages (WGSL, Rust) never print them.
#[derive(Clone, Debug, PartialEq)]
pub struct TessStages {
    /// Control stage, once per patch: the class's patch function into the
    /// patch's control points ([`Resource::ControlPoints`], cp_base 0), then
    /// the tessellation factors.
    pub control: Function,
    /// Evaluation stage, once per tessellator vertex: the sample, the stage
    /// outputs, and the capture of capture builds.
    pub evaluation: Function,
    /// `store_patch_cp(j, p)`: control point `j` into the packed per-patch
    /// storage, floats `3j .. 3j+2` of `vec4` slots (per-patch outputs are
    /// counted in 4-component locations, so `KMAX` `vec3` would take `KMAX`
    /// locations; ACC's 40 exceed lavapipe's 32).
    pub store_cp: Function,
    /// `load_patch_cp(j) -> vec3`: the inverse of [`TessStages::store_cp`].
    pub load_cp: Function,
    /// The HLSL hull's patch-constant body: [`TessStages::control`] into a
    /// zeroed patch-local array ([`Stmt::PatchLocal`]), then every slot of
    /// the packed per-patch storage zeroed and control point `j` stored
    /// into it for `j < KMAX` (targets whose control stage writes the
    /// packed storage directly, GLSL, print `control`).
    pub hull: Function,
    /// The HLSL domain stage's prologue: the patch-local array that
    /// [`TessStages::evaluation`] reads, filled from the packed per-patch
    /// storage.
    pub unpack: Function,
    /// `KMAX`: control points of the largest class (at least 1), the
    /// length of the per-patch control-point arrays.
    pub points: u32,
    /// `KMAX4`: `vec4` slots of the packed per-patch storage, ⌈3·KMAX / 4⌉.
    pub slots: u32,
}

/// Index of a local in [`Function::locals`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LocalId(pub usize);

#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    F32(f32),
    U32(u32),
    Local(LocalId),
    /// Element of a module constant array: `CONST[index]`.
    ConstIndex(usize, Box<Expr>),
    /// A scalar module constant.
    Const(usize),
    Binary(BinOp, Box<Expr>, Box<Expr>),
    Neg(Box<Expr>),
    Call(Builtin, Vec<Expr>),
    /// Call of another function of the module (or the common module).
    CallFn(FnRef, Vec<Expr>),
    Field(Box<Expr>, usize),
    /// Construct a struct from its fields, in order.
    Make(usize, Vec<Expr>),
    Fetch(Resource, Box<Expr>),
    /// Stencil table weight at logical `(row, column)`; the texture texel it
    /// reads is [`flat::table_texel`].
    TableWeight(Box<Expr>, Box<Expr>),
    /// Texel `(x, y)` (u32 column, row) of a 2-D texture resource, fetched
    /// exactly (no filtering): [`Resource::DisplaceMap`].
    Texel(Resource, Box<Expr>, Box<Expr>),
    /// A tessellation-stage input ([`TessStages`] bodies only).
    Stage(StageIn),
    /// `f32` component `comp` of `vec4` slot `slot` of the patch's packed
    /// control points, the per-patch storage between the tessellation
    /// stages ([`TessStages::load_cp`] only).
    PatchSlot(Box<Expr>, Box<Expr>),
    /// `f32` number `k` of the packed storage of a `vec3` resource (3 per
    /// element): the packed accessors only (`crate::lower::entries::packed_load`).
    Float(Resource, Box<Expr>),
    /// A `u32` constant of the patch-local arrays ([`Named`]), declared by
    /// the printers that have them.
    Named(Named),
    /// Element `index` of a named constant array: `CONTROL_POINTS[class]`.
    NamedIndex(Named, Box<Expr>),
    /// `u32` columns of a 2-D texture resource held as a row-major slice
    /// (Rust: `inputs.displace_width`): [`flat::flat_index`] only.
    Columns(Resource),
    /// `vec3` control point `j` of the packed per-patch storage between the
    /// tessellation stages, through [`TessStages::load_cp`] (the domain
    /// stage's unpacking into its patch-local array, [`TessStages::unpack`]).
    PatchCp(Box<Expr>),
}

/// The constants of the patch-local control-point arrays
/// ([`Stmt::PatchLocal`]): printed as declarations by the targets whose
/// patch functions take such an array (HLSL), from [`TessStages::points`],
/// [`TessStages::slots`] and the classes' control-point counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Named {
    /// `KMAX`: the length of every patch-local control-point array.
    Kmax,
    /// `KMAX4`: the `vec4` slots of the packed per-patch storage.
    Kmax4,
    /// `CONTROL_POINTS[class]`: control points per patch of each class.
    ControlPoints,
    /// `TABLE_WIDTH`: columns of the stencil table held as a row-major
    /// slice (Rust; [`flat::flat_index`]).
    TableWidth,
    /// `TABLE_BLOCK_ROWS`: rows per column block of the stencil texture
    /// ([`flat::table_texel`]).
    TableBlockRows,
}

impl Named {
    /// The declared name.
    pub fn name(self) -> &'static str {
        match self {
            Named::Kmax => "KMAX",
            Named::Kmax4 => "KMAX4",
            Named::ControlPoints => "CONTROL_POINTS",
            Named::TableWidth => "TABLE_WIDTH",
            Named::TableBlockRows => "TABLE_BLOCK_ROWS",
        }
    }
}

/// Reference to a function: in the scheme's own module or the common one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FnRef {
    Common(usize),
    Local(usize),
}

/// A build-time switch of the emitted GLSL and HLSL: a preprocessor
/// define a harness passes to the shader compiler (`-DNAME`). Targets
/// without a preprocessor (WGSL, Rust) always print the default branch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Define {
    /// Negative control for watertightness tests: samples on the patch
    /// boundary keep the patch's own surface formula instead of taking the
    /// one shared edge evaluator, so the check must then find cracks.
    NoBoundaryPath,
    /// Negative control: the shared edge evaluator forms its left weight as
    /// `1 − r` in float instead of from integers (watertight.md Rule 2's
    /// forbidden form), so the two patches of an edge round differently.
    AsymmetricEdgeWeights,
    /// The tessellation evaluation stage also writes every sample into the
    /// `samples` buffer, at the layout of `eval_main` (harness builds).
    Capture,
    /// Adaptive tessellation (GLSL/HLSL tessellation pipeline): the control
    /// stage sets one factor per edge from `tessgen_edge_factor` instead of
    /// the uniform level, and the evaluation stage reads the hardware
    /// coordinate on the 2^-16 fixed-point grid (`level` = 65536).
    Adaptive,
    /// Adaptive metric: explicit factors from `edge_factors[face_edges[4f + k]]`.
    MetricBuffer,
    /// Adaptive metric: edge length over distance to the eye.
    MetricDistance,
    /// Partitioning `fractional_odd` (default: `integer` / `equal_spacing`).
    FractionalOdd,
    /// Partitioning `fractional_even`.
    FractionalEven,
    /// The tessellation evaluation stage displaces its sample
    /// ([`TessDisplaced`]): it then also binds the global control-point
    /// buffer (filled by the compute patch stage before the draw), the
    /// owners, texture coordinates, displacement parameters and map.
    Displace,
}

impl Define {
    /// The preprocessor name.
    pub fn name(self) -> &'static str {
        match self {
            Define::NoBoundaryPath => "TESSGEN_NO_BOUNDARY_PATH",
            Define::Capture => "TESSGEN_CAPTURE",
            Define::AsymmetricEdgeWeights => "TESSGEN_ASYMMETRIC_EDGE_WEIGHTS",
            Define::Adaptive => "TESSGEN_ADAPTIVE",
            Define::MetricBuffer => "TESSGEN_METRIC_BUFFER",
            Define::MetricDistance => "TESSGEN_METRIC_DISTANCE",
            Define::FractionalOdd => "TESSGEN_FRACTIONAL_ODD",
            Define::FractionalEven => "TESSGEN_FRACTIONAL_EVEN",
            Define::Displace => "TESSGEN_DISPLACE",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum Stmt {
    /// Immutable binding.
    Let(LocalId, Expr),
    /// Mutable binding.
    Var(LocalId, Expr),
    Assign(LocalId, Expr),
    /// `local.field = value`.
    AssignField(LocalId, usize, Expr),
    Store(Resource, Expr, Expr),
    If(Expr, Vec<Stmt>, Vec<Stmt>),
    /// `for local in start..end` over u32.
    For(LocalId, Expr, Expr, Vec<Stmt>),
    Return(Expr),
    /// `#ifdef define` first branch `#else` second branch `#endif` in GLSL
    /// and HLSL; the second (default) branch alone elsewhere.
    IfDef(Define, Vec<Stmt>, Vec<Stmt>),
    /// Call of a function without a result (or whose result is unused).
    Call(FnRef, Vec<Expr>),
    /// A tessellation-stage output ([`TessStages`] bodies only).
    Output(StageOut, Expr),
    /// A comment line (or lines) for the reader of the emitted code.
    Comment(String),
    /// `slot`, `comp`, value: write [`Expr::PatchSlot`]
    /// ([`TessStages::store_cp`] only).
    StorePatchSlot(Expr, Expr, Expr),
    /// Return from a function (an entry point) without a value.
    ReturnVoid,
    /// `for local = start; local < end; local += step` over u32: the strided
    /// loops of the workgroup passes (invocation `l` takes items `l`, `l +
    /// 64`, …). Printers spell the increment without parentheses.
    ForStep(LocalId, Expr, Expr, Expr, Vec<Stmt>),
    /// A barrier of the workgroup's invocations.
    Barrier(Barrier),
    /// Write [`Expr::Float`] `k` of a packed `vec3` resource
    /// (`crate::lower::entries::packed_store` only).
    StoreFloat(Resource, Expr, Expr),
    /// Declare the patch-local array of `KMAX` control points that
    /// [`Resource::ControlPoints`] names in this body, for targets whose
    /// patch functions take the control points as an array (HLSL):
    /// [`Entries::compute_patch_local`], [`TessStages::hull`],
    /// [`TessStages::unpack`].
    PatchLocal,
    /// `j`, `p`: control point `j` into the packed per-patch storage,
    /// through [`TessStages::store_cp`] ([`TessStages::hull`] only).
    StorePatchCp(Expr, Expr),
    /// Zero `vec4` slot `slot` of the packed per-patch storage
    /// ([`TessStages::hull`] only: the components no control point fills
    /// are defined too).
    ClearPatchSlot(Expr),
}

/// What a [`Stmt::Barrier`] orders.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Barrier {
    /// Workgroup-shared memory ([`Resource::BucketTile`]).
    Workgroup,
    /// Storage buffers, between the invocations of one workgroup.
    Storage,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Local {
    pub name: String,
    pub ty: Ty,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Function {
    pub name: String,
    pub doc: String,
    pub params: Vec<LocalId>,
    pub ret: Option<Ty>,
    pub locals: Vec<Local>,
    pub body: Vec<Stmt>,
    /// Shared-boundary arithmetic: printers mark it `precise` (GLSL/HLSL)
    /// so no backend contracts or reorders it.
    pub precise: bool,
}

impl Function {
    pub fn new(name: impl Into<String>, doc: impl Into<String>) -> Self {
        Function {
            name: name.into(),
            doc: doc.into(),
            params: vec![],
            ret: None,
            locals: vec![],
            body: vec![],
            precise: false,
        }
    }
    /// A new local. Names are unique within a function (a clash, e.g. a
    /// scheme output named like a lowering temporary, gets a `_k` suffix),
    /// so every printer can use them as they are.
    pub fn local(&mut self, name: impl Into<String>, ty: Ty) -> LocalId {
        let mut name = name.into();
        if self.locals.iter().any(|l| l.name == name) {
            name = format!("{name}_{}", self.locals.len());
        }
        self.locals.push(Local { name, ty });
        LocalId(self.locals.len() - 1)
    }
    pub fn param(&mut self, name: impl Into<String>, ty: Ty) -> LocalId {
        let id = self.local(name, ty);
        self.params.push(id);
        id
    }
    /// Resources this function reads (`false`) or writes (`true`).
    pub fn resources(&self) -> Vec<(Resource, bool)> {
        let mut out = Vec::new();
        let mut add = |r: Resource, w: bool| {
            if !out.contains(&(r, w)) {
                out.push((r, w));
            }
        };
        walk(&self.body, &mut |n| match n {
            Node::Expr(Expr::Fetch(r, _) | Expr::Texel(r, ..) | Expr::Float(r, _)) => {
                add(*r, false)
            }
            Node::Stmt(Stmt::Store(r, ..) | Stmt::StoreFloat(r, ..)) => add(*r, true),
            _ => {}
        });
        out.sort();
        out
    }
    /// Whether the function reads the stencil table.
    pub fn reads_table(&self) -> bool {
        let mut table = false;
        walk(&self.body, &mut |n| {
            table |= matches!(n, Node::Expr(Expr::TableWeight(..)));
        });
        table
    }
    /// Functions this function calls, in order of first call.
    pub fn called(&self) -> Vec<FnRef> {
        let mut out = Vec::new();
        walk(&self.body, &mut |n| {
            if let Node::Expr(Expr::CallFn(r, _)) | Node::Stmt(Stmt::Call(r, _)) = n {
                if !out.contains(r) {
                    out.push(*r);
                }
            }
        });
        out
    }
}

/// A module-level constant (scalar or array of u32).
#[derive(Clone, Debug, PartialEq)]
pub struct ConstDecl {
    pub name: String,
    pub doc: String,
    pub value: ConstValue,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ConstValue {
    U32(u32),
    U32Array(Vec<u32>),
}

#[derive(Clone, Debug, PartialEq)]
pub struct StructDecl {
    pub name: String,
    pub fields: Vec<(String, Ty)>,
}

/// A unit of emitted code: the common module (shared evaluators) or one
/// scheme's module.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Module {
    pub name: String,
    pub doc: String,
    pub consts: Vec<ConstDecl>,
    pub structs: Vec<StructDecl>,
    pub functions: Vec<Function>,
}

impl Module {
    pub fn add_const(&mut self, name: &str, doc: &str, value: ConstValue) -> usize {
        self.consts.push(ConstDecl {
            name: name.into(),
            doc: doc.into(),
            value,
        });
        self.consts.len() - 1
    }
    pub fn function_index(&self, name: &str) -> Option<usize> {
        self.functions.iter().position(|f| f.name == name)
    }
}

/// Where the stages of a scheme are, for printers that emit entry points
/// and for runtimes that call them.
#[derive(Clone, Debug, PartialEq)]
pub struct Entries {
    /// `vertex_stage(vertex, out_base)`.
    pub vertex_stage: usize,
    /// Per facet class present: `(class name, form name, control points,
    /// patch function (face, cp_base))`.
    pub patches: Vec<PatchEntry>,
    /// `eval(class, cp_base, iu, iv, level) -> Sample`.
    pub eval: usize,
    /// Triangle schemes: `eval_domain(class, cp_base, x, y, z, level) ->
    /// Sample` at the tessellator's barycentric domain point: the integer
    /// grid path through `eval` on the patch boundary, the surface at the
    /// raw point inside (the hardware's inner rings are not the lattice).
    pub eval_domain: Option<usize>,
    /// `eval_displaced(face, class, cp_base, iu, iv, level) -> Sample`:
    /// `eval`, then the displacement step (every built-in scheme).
    pub eval_displaced: Option<usize>,
    /// Triangle schemes: `eval_domain_displaced(face, class, cp_base, x, y,
    /// z, level) -> Sample`, `eval_domain` with the displacement step
    /// (`eval_displaced` at the grid point on the boundary), reading every
    /// patch from one control-point array: the CPU's reference of what the
    /// displacing triangle evaluation stages compute.
    pub eval_domain_displaced: Option<usize>,
    /// The displacement step of the tessellation evaluation stages.
    pub tess_displaced: Option<TessDisplaced>,
    /// Corners per facet: 4 (quad domain) or 3 (triangle domain).
    pub sides: u32,
    /// `grid_len(level)`, `grid_iu(s, level)`, `grid_iv(s, level)`: the
    /// samples of one patch at `level` and the integer domain coordinates of
    /// sample `s` (quads: `(level+1)²`, `s = iv·(level+1) + iu`; triangles:
    /// `(level+1)(level+2)/2`, row `iv` holding `iu = 0 ..= level − iv`).
    pub grid: [usize; 3],
    /// `grid_index(iu, iv, level)`: the inverse of `grid_iu`/`grid_iv`, the
    /// flat sample index of an integer domain point (the tessellation
    /// evaluation stages write their captured samples there).
    pub grid_index: usize,
    /// Adaptive tessellation without a hardware tessellator (every quad
    /// and triangle scheme): see `crate::lower::adaptive`.
    pub adaptive: AdaptiveEntries,
    /// The bodies of the hardware tessellation stages (GLSL, HLSL).
    pub tess: TessStages,
    /// The body of the compute entry `vertex_stage_main` (GLSL, HLSL):
    /// the vertex stage of vertex `params.first + k` for invocation `k <
    /// params.count`, skipping unused vertices (valence 0).
    pub compute_vertex: Function,
    /// The body of the compute entry `eval_main` (GLSL, HLSL): sample `k
    /// mod grid_len(level)` of patch `params.first + k / grid_len(level)`
    /// through `eval_displaced_global` into `samples` (see
    /// `crate::lower::tess::compute_eval`).
    pub compute_eval: Function,
    /// The body of the compute entry `patch_main` (WGSL, GLSL): the class's
    /// patch function for patch `params.first + k`, control points from
    /// `params.cp_base + k·points` (see `crate::lower::entries::patch_main`).
    pub compute_patch: Function,
    /// The body of `patch_main` for targets whose patch functions write a
    /// patch-local array (HLSL): the class's patch function into a zeroed
    /// array (cp_base 0), copied to the global buffer
    /// ([`Resource::GlobalControlPoints`]) from `params.cp_base +
    /// k·CONTROL_POINTS[class]` (see `crate::lower::tess::compute_patch_local`).
    pub compute_patch_local: Function,
    /// The body of the compute entry `refine_main` (every GPU target): the
    /// refinement stage of refined vertex `params.first + k` for
    /// invocation `k < params.count` (see `crate::lower::refine`).
    pub compute_refine: Function,
    /// The WGSL module's entry points and the declarations between them,
    /// in order (targets without a tessellator: compute construction,
    /// instanced evaluation, adaptive buckets; see `crate::lower::entries`).
    pub instanced: Vec<EntryItem>,
}

impl Entries {
    /// Points of each boundary curve in `EDGE_CURVE` (the stride of its
    /// `[class][edge]` entries): 4 for cubic boundaries, 5 for quartic ones
    /// (every class of a scheme agrees; the front end checks it).
    pub fn curve_points(&self) -> u32 {
        self.patches
            .first()
            .map_or(4, |p| p.form.curve_points() as u32)
    }
}

/// How an entry point is invoked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EntryKind {
    /// A compute entry with a one-dimensional workgroup of this size.
    Compute { workgroup_size: u32 },
    /// A vertex entry whose outputs are [`EntryPoint::outputs`].
    Vertex,
    /// A fragment entry reading the vertex outputs ([`StageIn::Varying`]).
    Fragment,
}

/// An entry point: its kind, the builtin inputs it declares (in parameter
/// order; [`StageIn::GlobalId`] stands for the whole global invocation id,
/// whose `y` is [`StageIn::GlobalIdY`]), its body (name and doc are the
/// entry's) and, for vertex and fragment entries, its stage outputs,
/// written after the body.
#[derive(Clone, Debug, PartialEq)]
pub struct EntryPoint {
    pub kind: EntryKind,
    pub inputs: Vec<StageIn>,
    pub body: Function,
    pub outputs: Vec<(StageOut, Expr)>,
}

/// One module-scope item of [`Entries::instanced`], in print order.
#[derive(Clone, Debug, PartialEq)]
pub enum EntryItem {
    Entry(EntryPoint),
    /// A workgroup-shared `u32` array of `len` elements.
    Workgroup {
        resource: Resource,
        len: u32,
        doc: String,
    },
    /// The declaration of the vertex entries' outputs (and the fragment
    /// entry's inputs): position, normal, patch class, uv.
    VertexOutput {
        doc: String,
    },
}

/// The per-scheme functions of adaptive tessellation on the instanced path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AdaptiveEntries {
    /// `patch_edge_level(face, class, cp_base, k, max_level) -> u32`.
    pub edge_level: usize,
    /// `eval_adaptive(class, cp_base, iu, iv, level, l0, l1, l2, l3) -> Sample`.
    pub eval: usize,
    /// `eval_adaptive_displaced(face, class, cp_base, iu, iv, level, l0, l1,
    /// l2, l3) -> Sample`: the same snap, then `eval_displaced` at the
    /// snapped point (what the WGSL adaptive entries call; with
    /// displacement off, `eval_adaptive`'s sample bit for bit).
    pub eval_displaced: usize,
}

/// The displacing evaluation of the hardware tessellation stages (`.tese`,
/// HLSL `ds_main`, built with [`Define::Displace`]). The stage evaluates its
/// own sample from its patch-local control points, but the owner's normal
/// on the boundary (watertight.md Rule 4) needs `eval` of *another* patch:
/// that call goes to `eval_global`, a copy of `eval` (and of the surface
/// functions it calls) whose control-point fetches read
/// [`Resource::GlobalControlPoints`].
#[derive(Clone, Debug, PartialEq)]
pub struct TessDisplaced {
    /// `eval_displaced_tess(face, class, cp_base, iu, iv, level) -> Sample`:
    /// `eval_displaced` with the own sample from `eval` (patch-local) and
    /// the owner's from `eval_global`.
    pub eval_displaced: usize,
    /// Triangle schemes: `eval_domain_displaced_tess(face, class, cp_base,
    /// x, y, z, level) -> Sample`, what the displacing evaluation stage
    /// calls at the tessellator's domain point (`eval_displaced_tess` on
    /// the boundary).
    pub eval_domain: Option<usize>,
    /// `eval_displaced_global(face, class, cp_base, iu, iv, level) ->
    /// Sample`: `eval_displaced` reading every patch from the global
    /// control-point buffer ([`Resource::GlobalControlPoints`]), what the
    /// GLSL/HLSL compute evaluation ([`Entries::compute_eval`]) calls. HLSL
    /// passes functions that read [`Resource::ControlPoints`] a patch-local
    /// array, so the compute entry needs the global copy there.
    pub eval_displaced_global: usize,
    /// Functions only GLSL/HLSL use (`eval_global`, its surface copies,
    /// `eval_displaced_global`, `eval_displaced_tess`): Rust and WGSL do
    /// not print them.
    pub functions: std::ops::Range<usize>,
}

impl Entries {
    /// Whether scheme-module function `i` serves only the tessellation
    /// stages ([`TessDisplaced::functions`]).
    pub fn tess_only(&self, i: usize) -> bool {
        self.tess_displaced
            .as_ref()
            .is_some_and(|t| t.functions.contains(&i))
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct PatchEntry {
    pub class: crate::Class,
    pub form: crate::plan::form::Form,
    pub control_points: u32,
    pub function: usize,
}

/// The complete lowered program: common module + one module per scheme.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub common: Module,
    pub schemes: Vec<(Module, Entries)>,
}

impl Plan {
    /// The function `r` refers to, from within module `m`.
    pub fn callee<'a>(&'a self, m: &'a Module, r: FnRef) -> &'a Function {
        match r {
            FnRef::Common(i) => &self.common.functions[i],
            FnRef::Local(i) => &m.functions[i],
        }
    }

    /// Type of `e` inside function `f` of module `m`, where a printer needs
    /// it (struct field names): locals, struct constructors, calls, fields.
    pub fn expr_ty(&self, m: &Module, f: &Function, e: &Expr) -> Option<Ty> {
        match e {
            Expr::Local(id) => Some(f.locals[id.0].ty.clone()),
            Expr::Make(s, _) => Some(Ty::Struct(*s)),
            Expr::CallFn(r, _) => self.callee(m, *r).ret.clone(),
            Expr::Field(a, k) => match self.expr_ty(m, f, a)? {
                Ty::Struct(s) => Some(self.common.structs[s].fields[*k].1.clone()),
                _ => None,
            },
            _ => None,
        }
    }
}

/// Indices of the common module's functions.
pub mod common_fn {
    pub const NORMALIZE: usize = 0;
    pub const CUBIC: usize = 1;
    pub const EDGE: usize = 2;
    pub const EDGE_FACTOR: usize = 3;
    /// `tessgen_edge_factor_runtime`: the metric chosen at run time.
    pub const EDGE_FACTOR_RUNTIME: usize = 4;
    /// `tessgen_edge_level`: power-of-two edge level of a factor.
    pub const EDGE_LEVEL: usize = 5;
    /// `tessgen_bucket_level`: a patch's bucket, the largest edge level.
    pub const BUCKET_LEVEL: usize = 6;
    /// `tessgen_refine_vertex`: one refined vertex's stencil row.
    pub const REFINE_VERTEX: usize = 7;
    /// `tessgen_patch_normal`: a quad patch's unit normal, zero where its
    /// tangents are parallel (`eval` then takes it from just inside).
    pub const PATCH_NORMAL: usize = 8;
}

/// Below this `|a × b|² / (|a|²·|b|²)` (`sin²` of the tangents' angle,
/// `sin` ≈ 1e-4) a quad patch's tangents count as parallel: the cross
/// product is rounding noise in any direction. Far above the noise of f32
/// tangents (`sin` ≈ 1e-6 even on meshes far from the origin) and far below
/// a genuine sample one nudge away (`sin` ≳ 2e-4 at level 256).
pub const PARALLEL_SIN2: f64 = 1e-8;

/// The nudge of a degenerate sample: `eval` takes its normal at
/// `(16·iu ± 1, 16·iv ± 1) / (16·level)`, one sixteenth of a sample step
/// into the patch (exact integers: `16·level` ≤ 2²⁰ < 2²⁴).
pub const NUDGE: u32 = 16;

/// Name of the adaptive per-edge tessellation factor.
pub const EDGE_FACTOR_FN: &str = "tessgen_edge_factor";

/// Name of the adaptive per-edge factor with the metric chosen at run time.
pub const EDGE_FACTOR_RUNTIME_FN: &str = "tessgen_edge_factor_runtime";

/// Fixed-point denominator of the adaptive evaluation: the hardware
/// tessellator's domain coordinates are 16.16 fixed point, so `m / 2^16`
/// is exact in f32 and `2^16 − m` is the neighbour's coordinate.
pub const ADAPTIVE_LEVEL: u32 = 1 << 16;

/// Name of the single shared edge evaluator.
pub const EDGE_FN: &str = "tessgen_edge";

/// Fixed indices into the common module, used by scheme modules.
pub mod common {
    /// `Sample { position, normal }`.
    pub const SAMPLE: usize = 0;
    /// `Curve { point, tangent }`.
    pub const CURVE: usize = 1;
    /// Module constants.
    pub const TABLE_WIDTH: usize = 0;
    pub const MAX_VALENCE: usize = 1;
}

/// Small builder helpers for lowering code.
pub mod build {
    use super::*;
    pub fn f(x: f32) -> Expr {
        Expr::F32(x)
    }
    pub fn u(x: u32) -> Expr {
        Expr::U32(x)
    }
    pub fn l(id: LocalId) -> Expr {
        Expr::Local(id)
    }
    pub fn bin(op: BinOp, a: Expr, b: Expr) -> Expr {
        Expr::Binary(op, Box::new(a), Box::new(b))
    }
    pub fn add(a: Expr, b: Expr) -> Expr {
        bin(BinOp::Add, a, b)
    }
    pub fn sub(a: Expr, b: Expr) -> Expr {
        bin(BinOp::Sub, a, b)
    }
    pub fn mul(a: Expr, b: Expr) -> Expr {
        bin(BinOp::Mul, a, b)
    }
    pub fn div(a: Expr, b: Expr) -> Expr {
        bin(BinOp::Div, a, b)
    }
    pub fn to_f32(a: Expr) -> Expr {
        Expr::Call(Builtin::F32FromU32, vec![a])
    }
    pub fn fetch(r: Resource, i: Expr) -> Expr {
        Expr::Fetch(r, Box::new(i))
    }
    pub fn call(f: FnRef, args: Vec<Expr>) -> Expr {
        Expr::CallFn(f, args)
    }
    /// Symmetric lerp `x·l + y·r` (watertight.md Rule 2).
    pub fn lerp(x: Expr, y: Expr, wl: LocalId, wr: LocalId) -> Expr {
        add(mul(x, l(wl)), mul(y, l(wr)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_names_are_unique() {
        let mut f = Function::new("f", "");
        let a = f.local("sector_0", Ty::U32);
        let b = f.local("sector_0", Ty::Vec3);
        assert_ne!(f.locals[a.0].name, f.locals[b.0].name);
        assert_eq!(f.locals[b.0].name, "sector_0_1");
    }
}
