//! The GPU ABI every shader printer follows: one binding table, one uniform
//! block, one set of entry points. Printers spell these in their language;
//! they never invent their own layout, so `generated/README.md` can describe
//! all three targets with one table.
//!
//! Buffers of `vec3` are stored as tightly packed `f32` triples (12 bytes per
//! point): WGSL/std430 `vec3` arrays would pad to 16 bytes, and packed floats
//! are what engines already have in their vertex buffers.

use crate::plan::{Define, Entries, Module, Plan, Resource, StageOut};

/// What a binding holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Storage buffer of `u32`.
    U32Buffer,
    /// Storage buffer of packed `f32` triples (a `vec3` per element).
    Vec3Buffer,
    /// Storage buffer of `f32`.
    F32Buffer,
    /// The stencil table: 2-D `R32Float` texture, x = ring slot, y = row.
    Table,
    /// The [`PARAMS`] uniform block.
    Uniform,
}

/// One binding: set/group 0, this binding number (HLSL: register `t`/`u`/`b`
/// with the same number).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    pub binding: u32,
    pub name: &'static str,
    pub kind: Kind,
    /// The Plan resource it backs, if any.
    pub resource: Option<Resource>,
    /// Written by some stage (needs read-write access there).
    pub written: bool,
    pub doc: &'static str,
}

/// The binding table (group/set 0).
pub const BINDINGS: &[Binding] = &[
    Binding { binding: 0, name: "positions", kind: Kind::Vec3Buffer, resource: Some(Resource::Positions), written: false, doc: "control-mesh positions, 3 f32 per vertex" },
    Binding { binding: 1, name: "valence", kind: Kind::U32Buffer, resource: Some(Resource::Valence), written: false, doc: "valence per vertex (0 = unused vertex)" },
    Binding { binding: 2, name: "ring_offsets", kind: Kind::U32Buffer, resource: Some(Resource::RingOffsets), written: false, doc: "start of each vertex's ring in `ring`" },
    Binding { binding: 3, name: "ring", kind: Kind::U32Buffer, resource: Some(Resource::Ring), written: false, doc: "rings [p, p_0 .. p_{2n-1}] (vertex indices), canonical start, flat" },
    Binding { binding: 4, name: "vertex_out_offsets", kind: Kind::U32Buffer, resource: Some(Resource::VertexOutOffsets), written: false, doc: "start of each vertex's vertex-stage outputs in `vertex_out` (ROWS_PER_N·n + ROWS_FIXED points each)" },
    Binding { binding: 5, name: "vertex_out", kind: Kind::Vec3Buffer, resource: Some(Resource::VertexOut), written: true, doc: "vertex-stage outputs, 3 f32 per point (written by the vertex stage)" },
    Binding { binding: 6, name: "corner_vertex", kind: Kind::U32Buffer, resource: Some(Resource::CornerVertex), written: false, doc: "vertex of corner i of face f at 4f + i (3f + i for triangle schemes)" },
    Binding { binding: 7, name: "corner_sector", kind: Kind::U32Buffer, resource: Some(Resource::CornerSector), written: false, doc: "sector index j_i of corner i of face f at 4f + i" },
    Binding { binding: 8, name: "control_points", kind: Kind::Vec3Buffer, resource: Some(Resource::ControlPoints), written: true, doc: "patch control points, 3 f32 per point (written by the patch stage)" },
    Binding { binding: 9, name: "stencil_table", kind: Kind::Table, resource: None, written: false, doc: "the stencil table, R32Float, width TABLE_WIDTH" },
    Binding { binding: 10, name: "params", kind: Kind::Uniform, resource: None, written: false, doc: "the Params uniform block" },
    Binding { binding: 11, name: "patch_faces", kind: Kind::U32Buffer, resource: None, written: false, doc: "face index of each patch, patches sorted by class" },
    Binding { binding: 12, name: "samples", kind: Kind::F32Buffer, resource: None, written: true, doc: "evaluated samples, 6 f32 each (position xyz, normal xyz)" },
    Binding { binding: 13, name: "normals", kind: Kind::Vec3Buffer, resource: Some(Resource::Normals), written: false, doc: "unit normal per vertex, 3 f32 (triangle schemes)" },
    Binding { binding: 14, name: "tags", kind: Kind::F32Buffer, resource: Some(Resource::Tags), written: false, doc: "scalar tags, 4 f32 per vertex: tension, sharpness, bias, creased (1 when the crease vector is non-null) — scalar-tagged PN" },
    Binding { binding: 15, name: "crease", kind: Kind::Vec3Buffer, resource: Some(Resource::Crease), written: false, doc: "crease vector per vertex, 3 f32 (zero = smooth vertex) — scalar-tagged PN" },
    Binding { binding: 16, name: "corner_side", kind: Kind::F32Buffer, resource: Some(Resource::CornerSide), written: false, doc: "side sign ±1 of corner i of triangle f at 3f + i: which crease normal the triangle uses — scalar-tagged PN" },
    Binding { binding: 17, name: "face_edges", kind: Kind::U32Buffer, resource: Some(Resource::FaceEdges), written: false, doc: "global edge id of edge k (v_k -> v_{k+1}) of face f at 4f + k (triangles: 3f + k); both faces of an edge hold the same id (adaptive tessellation)" },
    Binding { binding: 18, name: "edge_factors", kind: Kind::F32Buffer, resource: Some(Resource::EdgeFactors), written: false, doc: "explicit tessellation factor per global edge id (adaptive, TESSGEN_METRIC_BUFFER)" },
    Binding { binding: 19, name: "adaptive", kind: Kind::F32Buffer, resource: Some(Resource::Adaptive), written: false, doc: "adaptive-tessellation parameters, ADAPTIVE_LEN f32 (layout in generated/README.md)" },
    Binding { binding: 21, name: "texcoords", kind: Kind::F32Buffer, resource: Some(Resource::TexCoords), written: false, doc: "displacement texture coordinates, 16 (s, t) pairs per quad patch (12 per triangle): pair 4k + j of face f at 32f + 2(4k + j) (triangles 24f + 2(4k + j)) (j: 0 interior, 1 edge k's owner at v_k, 2 edge k-1's owner at v_k, 3 vertex v_k's owner) — watertight.md Rule 5" },
    Binding { binding: 22, name: "owners", kind: Kind::U32Buffer, resource: Some(Resource::Owners), written: false, doc: "ownership records, 8 per quad at 32f + 4·slot (slots 0-3 edge k, 4-7 corner k; triangles 6 at 24f + 4·slot, slots 0-2 edge k, 3-5 corner k): owner's class, owner's first control point, owner's local edge/corner, 1 when the owner runs the edge the other way — watertight.md Rule 4" },
    Binding { binding: 23, name: "displace_info", kind: Kind::F32Buffer, resource: Some(Resource::DisplaceInfo), written: false, doc: "displacement parameters, 4 f32: scale (0 = off: eval_displaced returns eval's sample bit for bit), map width, map height, unused" },
    Binding { binding: 24, name: "displace_map", kind: Kind::Table, resource: Some(Resource::DisplaceMap), written: false, doc: "scalar displacement map, R32Float, read with exact texel fetches and bilinear weights formed in the shader" },
    Binding { binding: 25, name: "patch_levels", kind: Kind::U32Buffer, resource: None, written: true, doc: "adaptive classify output (WGSL instanced path), 5 u32 per patch p (class-sorted, as patch_faces) at 5p: the power-of-two levels of edges 0-3 (triangles: edges 0-2, slot 3 is 1) and the patch's bucket (their largest)" },
    Binding { binding: 26, name: "bucket_patches", kind: Kind::U32Buffer, resource: None, written: false, doc: "adaptive draw lists (WGSL instanced path), 6 u32 per entry: patch p (index into patch_faces), its first control point, the levels of its edges 0-3; entry params.first + i is instance / patch i of a bucket's draw; for eval_adaptive_indirect_main the GPU-built bucket_list (header of 4 u32 per bucket slot, then the entries)" },
    Binding { binding: 27, name: "bucket_list", kind: Kind::U32Buffer, resource: None, written: true, doc: "GPU-driven adaptive buckets (WGSL instanced path): written by adaptive_plan_main (the header) and adaptive_scatter_main (the entries): a header of 4 u32 per bucket slot 16r + j (class range r, bucket 2^j: count, first entry, first sample, x workgroups), then 6 u32 per entry as bucket_patches; bound as bucket_patches (26) for eval_adaptive_indirect_main" },
    Binding { binding: 28, name: "bucket_dispatch", kind: Kind::U32Buffer, resource: None, written: true, doc: "GPU-driven adaptive buckets: dispatch_workgroups_indirect arguments (x, y, 1), 3 u32 per bucket slot, written by adaptive_plan_main" },
    Binding { binding: 29, name: "bucket_draw", kind: Kind::U32Buffer, resource: None, written: true, doc: "GPU-driven adaptive buckets: draw_indexed_indirect arguments (index count of the bucket level's grid, instance count = the slot's patches, first index 0, base vertex 0, first instance 0), 5 u32 per bucket slot, written by adaptive_plan_main; a renderer draws slot b with eval_adaptive_indirect_vs" },
    Binding { binding: 30, name: "bucket_chunks", kind: Kind::U32Buffer, resource: None, written: true, doc: "GPU-driven adaptive buckets: per chunk of 256 patches (chunk c = patches 256c ..) two rows of one u32 per bucket slot s (S slots): at 2c·S + s the chunk's patches of slot s (written by adaptive_count_main), at (2c + 1)·S + s their first entry within the slot (written by adaptive_plan_main, read by adaptive_scatter_main); the counts are never overwritten, so a chunk a range does not touch stays 0 when the buffer is reused" },
    Binding { binding: 31, name: "vertex_sectors", kind: Kind::U32Buffer, resource: Some(Resource::VertexSectors), written: false, doc: "first sector of each vertex in `sectors` (one per vertex plus a final total); an empty range is a smooth vertex, which uses the per-valence rows (docs/boundaries.md §2)" },
    Binding { binding: 32, name: "sectors", kind: Kind::U32Buffer, resource: Some(Resource::Sectors), written: false, doc: "sector records of crease and corner vertices, SECTOR_WORDS u32 each: kind (0 crease, 1 corner; row block kind·SECTOR_MAX_FACES + m − 1), faces m, ring positions written (m, or m + 1 for the last sector of a boundary vertex), first ring position, start of its partial ring [p, q_0, d_0, .., q_m] in `ring`" },
    Binding { binding: 33, name: "corner_valence", kind: Kind::U32Buffer, resource: Some(Resource::CornerValence), written: false, doc: "valence whose per-valence constants corner i of face f uses, at 4f + i: the vertex valence, or the sector's virtual valence (4 for one face, 2m for m faces) at crease and corner vertices" },
    Binding { binding: 34, name: "refine_base", kind: Kind::Vec3Buffer, resource: Some(Resource::RefineBase), written: false, doc: "base-mesh positions of a refined mesh, 3 f32 per base vertex: the refinement stage's input (docs/boundaries.md §8)" },
    Binding { binding: 35, name: "refine_offsets", kind: Kind::U32Buffer, resource: Some(Resource::RefineOffsets), written: false, doc: "start of each refined vertex's stencil row in refine_indices / refine_weights (one per refined vertex plus a final total)" },
    Binding { binding: 36, name: "refine_indices", kind: Kind::U32Buffer, resource: Some(Resource::RefineIndices), written: false, doc: "base vertex of each stencil term, ascending within a row" },
    Binding { binding: 37, name: "refine_weights", kind: Kind::F32Buffer, resource: Some(Resource::RefineWeights), written: false, doc: "weight of each stencil term (rows sum to 1)" },
    Binding { binding: 38, name: "refined_positions", kind: Kind::Vec3Buffer, resource: None, written: true, doc: "refined positions, 3 f32 per refined vertex, written by refine_main: bind the buffer the vertex stage reads as positions (binding 0)" },
];

/// Layout of the `adaptive` buffer (binding 19): `(name, first float,
/// count, meaning)`; [`rust_module`] names the slots for the runtime. A
/// storage buffer rather than a second uniform block so every printer binds
/// it like any other `f32` buffer.
pub const ADAPTIVE: &[(&str, u32, u32, &str)] = &[
    ("VIEW_PROJ", 0, 16, "view_proj, column-major (element (row r, column c) at 4c + r): the screen-space metric projects both edge end points with it"),
    ("EYE", 16, 3, "eye position (distance metric)"),
    ("DISTANCE_SCALE", 19, 1, "distance metric scale k: factor = k · ‖b − a‖ / ‖(a + b)/2 − eye‖"),
    ("VIEWPORT", 20, 2, "viewport width, height in pixels (screen-space metric)"),
    ("PIXELS_PER_SEGMENT", 22, 1, "target pixels per segment (screen-space metric): factor = projected length / this"),
    ("MIN_FACTOR", 23, 1, "smallest factor (clamp; NaN becomes this)"),
    ("MAX_FACTOR", 24, 1, "largest factor (clamp; at most the device's maxTessellationGenerationLevel)"),
    ("METRIC", 25, 1, "metric of tessgen_edge_factor_runtime (WGSL, Rust: no preprocessor): 0 screen space, 1 distance, 2 edge_factors buffer"),
];

/// Floats in the `adaptive` buffer.
pub const ADAPTIVE_LEN: u32 = 26;

/// The Plan resource binding `b` holds: its own, or for a buffer whose
/// binding keeps one view (`resource: None`: host-filled or output-only,
/// such as `refined_positions`) the resource of the same name.
pub fn resource_of(b: &Binding) -> Option<Resource> {
    b.resource
        .or_else(|| Resource::ALL.into_iter().find(|r| r.name() == b.name))
}

/// Binding of a Plan resource.
pub fn binding_of(r: Resource) -> &'static Binding {
    // The global view of the control points is the same buffer.
    let r = match r {
        Resource::GlobalControlPoints => Resource::ControlPoints,
        // Host-filled or output-only buffers whose binding has no Plan
        // resource of its own (`resource: None` keeps their one view).
        Resource::PatchFaces | Resource::Samples | Resource::RefinedPositions => {
            return BINDINGS
                .iter()
                .find(|b| b.name == r.name())
                .unwrap_or(&BINDINGS[0]);
        }
        r => r,
    };
    BINDINGS
        .iter()
        .find(|b| b.resource == Some(r))
        .unwrap_or(&BINDINGS[0])
}

/// Fields of the `Params` uniform block, all `u32` except the matrix, in
/// order (std140/WGSL uniform layout: the matrix first at offset 0, then
/// scalars from byte 64).
pub const PARAMS: &[(&str, &str)] = &[
    ("view_proj", "mat4x4<f32> (column-major): clip = view_proj · position, used by the vertex/domain stages"),
    ("first", "first item of this dispatch/draw (vertex for the vertex stage, patch index into patch_faces otherwise)"),
    ("count", "number of items in this dispatch/draw"),
    ("class", "facet class of this dispatch/draw (index into the scheme's patch classes)"),
    ("cp_base", "first control point (in points) of this class's patches; patch k of the draw uses cp_base + k·CONTROL_POINTS[class]"),
    ("level", "tessellation level N: (N+1)² samples per patch, (u, v) = (iu, iv)/N"),
    ("out_base", "first sample written by eval_main"),
    ("flags", "shade_fs options: bit 0 (FLAG_WIREFRAME) darkens patch boundaries (wireframe overlay), bit 1 (FLAG_PLAIN) colours every class alike; other bits 0"),
    ("pad1", "padding"),
];

/// Byte offset of a `Params` field.
pub fn params_offset(field: &str) -> u32 {
    let i = PARAMS.iter().position(|(n, _)| *n == field).unwrap_or(0) as u32;
    if i == 0 {
        0
    } else {
        64 + 4 * (i - 1)
    }
}

/// Size of the `Params` block in bytes.
pub const PARAMS_SIZE: u32 = 64 + 4 * 8;

/// Workgroup size of every compute entry point (but the bucket compaction
/// passes, whose workgroup is one chunk: [`BUCKET_CHUNK`]).
pub const WORKGROUP_SIZE: u32 = 64;

/// `f32` per evaluated sample in `samples` (binding 12): position xyz, normal xyz.
pub const SAMPLE_FLOATS: u32 = 6;
/// `u32` per patch in `patch_levels` (binding 25): the levels of edges 0–3, then the bucket.
pub const PATCH_LEVELS_WORDS: u32 = 5;
/// The word of a `patch_levels` record holding the patch's bucket (the
/// largest of its edge levels); the edge levels come first.
pub const PATCH_LEVELS_BUCKET: u32 = 4;
/// `u32` per entry of `bucket_patches` / `bucket_list` (bindings 26, 27): patch,
/// first control point, the levels of edges 0–3.
pub const BUCKET_ENTRY_WORDS: u32 = 6;
/// `u32` words per sector record in `sectors` (binding 32): kind (0 crease,
/// 1 corner), faces m, ring positions written, first ring position,
/// partial-ring start.
pub const SECTOR_WORDS: u32 = 5;
/// `u32` per bucket slot in the header of `bucket_list` (binding 27): count,
/// first entry, first sample, x workgroups.
pub const BUCKET_HEADER_WORDS: u32 = 4;
/// `u32` per bucket slot in `bucket_dispatch` (binding 28): `dispatch_workgroups_indirect` x, y, z.
pub const BUCKET_DISPATCH_WORDS: u32 = 3;
/// `u32` per bucket slot in `bucket_draw` (binding 29): `draw_indexed_indirect` arguments.
pub const BUCKET_DRAW_WORDS: u32 = 5;

/// Bucket slots per class range in the GPU-driven adaptive buffers: slot
/// `16·r + j` holds the patches of class range r whose bucket is `2^j`
/// (levels up to 2^15).
pub const BUCKET_SLOTS: u32 = 16;

/// `Params.flags` bit: `shade_fs` darkens patch boundaries (a wireframe of
/// the base faces).
pub const FLAG_WIREFRAME: u32 = 1;

/// `Params.flags` bit: `shade_fs` colours every patch class alike (grey)
/// instead of ordinary orange / extraordinary blue.
pub const FLAG_PLAIN: u32 = 2;

// The `Params.flags` documentation names the bits by number.
const _: () = assert!(FLAG_WIREFRAME == 1 << 0 && FLAG_PLAIN == 1 << 1);
/// Largest x workgroup count of one GPU-driven evaluation dispatch
/// (WebGPU allows 65,535 per dimension): a bucket needing more runs as
/// y = ⌈workgroups / INDIRECT_X⌉ rows of x = ⌈workgroups / y⌉.
pub const INDIRECT_X: u32 = 32768;
/// Patches per chunk (and workgroup size) of the GPU-driven bucket
/// compaction (`adaptive_count_main`, `adaptive_scatter_main`): chunk c
/// holds patches `256c .. 256c + 256` of `patch_faces`; `bucket_chunks`
/// holds two rows per chunk, its slot counts and their offsets.
pub const BUCKET_CHUNK: u32 = 256;

/// Entry points, by name, that every shader target provides (where its
/// pipeline model has the stage).
pub mod entry {
    /// Compute: vertex stage for vertices `first .. first + count`.
    pub const VERTEX_STAGE: &str = "vertex_stage_main";
    /// Compute: patch stage for patches `first .. first + count` of `class`.
    pub const PATCH_STAGE: &str = "patch_main";
    /// Compute: evaluate `(level+1)²` samples of each patch into `samples`.
    pub const EVAL: &str = "eval_main";
    /// Compute: refinement stage for refined vertices `first .. first + count`.
    pub const REFINE: &str = "refine_main";
}

/// Binding of the Vulkan harness's own geometry-shader triangle capture
/// (the runtime writes that GLSL, no emitted shader declares it). Declared
/// here, outside [`BINDINGS`], so that no ABI binding is ever given its
/// number: the harness binds it next to the ABI's bindings in one set.
pub const HARNESS_TRIANGLES: u32 = 20;

/// Element type of a binding as the runtime and a host see it (the
/// element stride of a buffer is 4 bytes for every kind: `vec3` buffers are
/// packed `f32` triples).
pub const ELEMENT_BYTES: u32 = 4;

/// Texture format of every texture binding (the stencil table and the
/// displacement map): one 32-bit float channel, read with exact texel
/// loads. Not filterable in WebGPU, so a bind group layout declares it
/// `sampleType: "unfilterable-float"`.
pub const TEXTURE_FORMAT: &str = "R32Float";

/// How an entry point accesses a binding: the WGSL variable it uses is
/// declared `read` or `read_write` (an explicit bind group layout must
/// say the same: `read-only-storage` or `storage`). Bindings 5 and 8 are
/// declared twice in WGSL, `read_write` for the stage that writes them and
/// `read` (`vertex_out_ro`, `control_points_ro`) for the stages after it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Access {
    /// Read-only storage, the uniform block or a texture.
    Read,
    /// Read-write storage.
    ReadWrite,
}

/// Pipeline stage of an entry point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    Compute,
    Vertex,
    Fragment,
}

impl Stage {
    pub fn name(self) -> &'static str {
        match self {
            Stage::Compute => "compute",
            Stage::Vertex => "vertex",
            Stage::Fragment => "fragment",
        }
    }
}

/// One WGSL entry point: its stage, workgroup size, the bindings it uses
/// (exactly those: with `layout: "auto"` a bind group must hold these and no
/// others) and how invocations map onto work items.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EntryPoint {
    pub name: &'static str,
    pub stage: Stage,
    /// `@workgroup_size(x)` of a compute entry (0 for vertex/fragment).
    pub workgroup_size: u32,
    /// `(binding, access)`, by binding number. For `patch_main` these are
    /// only the bindings every scheme's patch stage uses; the scheme's own
    /// come from [`patch_main_bindings`].
    pub bindings: &'static [(u32, Access)],
    /// The invocation → work-item mapping and the dispatch/draw size.
    pub invocation: &'static str,
}

const R: Access = Access::Read;
const RW: Access = Access::ReadWrite;

/// The displacement bindings `eval_displaced` reads: bound by every
/// evaluation entry even with displacement off (scale 0 in `displace_info`).
const DISPLACE: [(u32, Access); 4] = [(21, R), (22, R), (23, R), (24, R)];

/// Every WGSL entry point, in the order the printer emits them. Checked
/// against naga's reflection of every emitted module by the tests
/// (`tests/tests/validate_wgsl.rs`), so this cannot drift from the shaders.
pub const WGSL_ENTRIES: &[EntryPoint] = &[
    EntryPoint {
        name: entry::REFINE,
        stage: Stage::Compute,
        workgroup_size: WORKGROUP_SIZE,
        bindings: &[(10, R), (34, R), (35, R), (36, R), (37, R), (38, RW)],
        invocation: "invocation `k = global_invocation_id.x` refines vertex `params.first + k` for `k < params.count` (its stencil row over `refine_base` into `refined_positions`); dispatch x = ⌈count / WORKGROUP_SIZE⌉; run before `vertex_stage_main`, with `refined_positions` bound to the buffer bound as `positions` there",
    },
    EntryPoint {
        name: entry::VERTEX_STAGE,
        stage: Stage::Compute,
        workgroup_size: WORKGROUP_SIZE,
        bindings: &[(0, R), (1, R), (2, R), (3, R), (4, R), (5, RW), (9, R), (10, R), (31, R), (32, R)],
        invocation: "invocation `k = global_invocation_id.x` runs vertex `params.first + k` for `k < params.count` (valence 0: skipped); dispatch x = ⌈count / WORKGROUP_SIZE⌉",
    },
    EntryPoint {
        name: entry::PATCH_STAGE,
        stage: Stage::Compute,
        workgroup_size: WORKGROUP_SIZE,
        bindings: &[(10, R), (11, R)],
        invocation: "invocation `k = global_invocation_id.x` builds patch `params.first + k` (index into `patch_faces`) of class `params.class` for `k < params.count`, its control points at `params.cp_base + k·CONTROL_POINTS[class]`; dispatch x = ⌈count / WORKGROUP_SIZE⌉",
    },
    EntryPoint {
        name: entry::EVAL,
        stage: Stage::Compute,
        workgroup_size: WORKGROUP_SIZE,
        bindings: &[(8, R), (10, R), (11, R), (12, RW), DISPLACE[0], DISPLACE[1], DISPLACE[2], DISPLACE[3]],
        invocation: "invocation `k = global_invocation_id.x` < `params.count · spp` (spp = `grid_len(params.level)` samples per patch) evaluates sample `s = k % spp` (domain point `grid_iu(s)`, `grid_iv(s)`) of patch `params.first + k / spp`, whose control points start at `params.cp_base + (k / spp)·CONTROL_POINTS[class]`, into `samples[SAMPLE_FLOATS·(params.out_base + k) ..]`; dispatch x = ⌈count·spp / WORKGROUP_SIZE⌉",
    },
    EntryPoint {
        name: "eval_vs",
        stage: Stage::Vertex,
        workgroup_size: 0,
        bindings: &[(8, R), (10, R), (11, R), DISPLACE[0], DISPLACE[1], DISPLACE[2], DISPLACE[3]],
        invocation: "vertex index = sample `s` of the grid, instance `i` = patch `params.first + i`, control points at `params.cp_base + i·CONTROL_POINTS[class]`; draw `params.count` instances",
    },
    EntryPoint {
        name: "shade_fs",
        stage: Stage::Fragment,
        workgroup_size: 0,
        bindings: &[(10, R)],
        invocation: "fragment shader for `eval_vs` and the adaptive vertex shaders",
    },
    EntryPoint {
        name: "adaptive_classify_main",
        stage: Stage::Compute,
        workgroup_size: WORKGROUP_SIZE,
        bindings: &[(6, R), (8, R), (10, R), (11, R), (17, R), (18, R), (19, R), (25, RW)],
        invocation: "invocation `k` classifies patch `p = params.first + k` (`k < params.count`) into `patch_levels[PATCH_LEVELS_WORDS·p ..]`",
    },
    EntryPoint {
        name: "eval_adaptive_main",
        stage: Stage::Compute,
        workgroup_size: WORKGROUP_SIZE,
        bindings: &[(8, R), (10, R), (11, R), (12, RW), DISPLACE[0], DISPLACE[1], DISPLACE[2], DISPLACE[3], (26, R)],
        invocation: "as `eval_main`, patch `k / spp` of the dispatch being entry `params.first + k / spp` of `bucket_patches`",
    },
    EntryPoint {
        name: "eval_adaptive_vs",
        stage: Stage::Vertex,
        workgroup_size: 0,
        bindings: &[(8, R), (10, R), (11, R), DISPLACE[0], DISPLACE[1], DISPLACE[2], DISPLACE[3], (26, R)],
        invocation: "as `eval_vs`, instance `i` being entry `params.first + i` of `bucket_patches`",
    },
    EntryPoint {
        name: "adaptive_count_main",
        stage: Stage::Compute,
        workgroup_size: BUCKET_CHUNK,
        bindings: &[(10, R), (25, RW), (30, RW)],
        invocation: "workgroup `c` counts the patches of chunk `c` (BUCKET_CHUNK patches) per bucket slot",
    },
    EntryPoint {
        name: "adaptive_plan_main",
        stage: Stage::Compute,
        workgroup_size: WORKGROUP_SIZE,
        bindings: &[(10, R), (27, RW), (28, RW), (29, RW), (30, RW)],
        invocation: "one workgroup: the bucket headers, offsets and indirect arguments",
    },
    EntryPoint {
        name: "adaptive_scatter_main",
        stage: Stage::Compute,
        workgroup_size: BUCKET_CHUNK,
        bindings: &[(10, R), (25, RW), (27, RW), (30, RW)],
        invocation: "workgroup `c` writes the entries of chunk `c`'s patches into `bucket_list`",
    },
    EntryPoint {
        name: "eval_adaptive_indirect_main",
        stage: Stage::Compute,
        workgroup_size: WORKGROUP_SIZE,
        bindings: &[(8, R), (10, R), (11, R), (12, RW), DISPLACE[0], DISPLACE[1], DISPLACE[2], DISPLACE[3], (26, R)],
        invocation: "`dispatch_workgroups_indirect` from `bucket_dispatch` slot `params.first`; `bucket_list` bound at binding 26",
    },
    EntryPoint {
        name: "eval_adaptive_indirect_vs",
        stage: Stage::Vertex,
        workgroup_size: 0,
        bindings: &[(8, R), (10, R), (11, R), DISPLACE[0], DISPLACE[1], DISPLACE[2], DISPLACE[3], (26, R)],
        invocation: "`draw_indexed_indirect` from `bucket_draw` slot `params.first`; `bucket_list` bound at binding 26",
    },
];

/// The WGSL variables that declare binding `b`: `(name, access)`. A
/// buffer one stage writes and later stages read (a Plan resource that is
/// written: `vertex_out`, `control_points`) is declared twice, `read_write`
/// under its name and `read` as `<name>_ro`, so the reading stages need no
/// writable binding (WebGPU forbids writable storage in vertex shaders);
/// other written buffers are `read_write` only.
pub fn wgsl_views(b: &Binding) -> Vec<(String, Access)> {
    match (b.written, b.resource.is_some()) {
        (true, true) => vec![(b.name.to_string(), RW), (format!("{}_ro", b.name), R)],
        (true, false) => vec![(b.name.to_string(), RW)],
        _ => vec![(b.name.to_string(), R)],
    }
}

/// The WGSL entry point called `name`.
pub fn wgsl_entry(name: &str) -> Option<&'static EntryPoint> {
    WGSL_ENTRIES.iter().find(|e| e.name == name)
}

/// Every binding `patch_main` of this scheme uses: [`WGSL_ENTRIES`]'
/// fixed part (Params, `patch_faces`) plus what the scheme's patch
/// functions read and write, derived from the Plan (the same
/// [`super::resources_of`] the printers declare from), and the stencil
/// table when a patch function reads per-valence constants.
pub fn patch_main_bindings(plan: &Plan, module: &Module, entries: &Entries) -> Vec<(u32, Access)> {
    let mut out: Vec<(u32, Access)> = wgsl_entry(entry::PATCH_STAGE)
        .map(|e| e.bindings.to_vec())
        .unwrap_or_default();
    let mut add = |b: u32, a: Access| {
        if let Some(x) = out.iter_mut().find(|x| x.0 == b) {
            x.1 = x.1.max(a);
        } else {
            out.push((b, a));
        }
    };
    for p in &entries.patches {
        let (res, table) = super::resources_of(plan, module, &module.functions[p.function]);
        for (r, written) in res {
            add(binding_of(r).binding, if written { RW } else { R });
        }
        if table {
            add(binding_number("stencil_table"), R);
        }
    }
    out.sort();
    out
}

/// The bindings of WGSL entry `e` for the scheme of `module`.
pub fn entry_bindings(
    plan: &Plan,
    module: &Module,
    entries: &Entries,
    e: &EntryPoint,
) -> Vec<(u32, Access)> {
    if e.name == entry::PATCH_STAGE {
        patch_main_bindings(plan, module, entries)
    } else {
        e.bindings.to_vec()
    }
}

/// Number of the binding called `name` (0 for an unknown name: the
/// callers here pass names of [`BINDINGS`]).
pub fn binding_number(name: &str) -> u32 {
    BINDINGS
        .iter()
        .find(|b| b.name == name)
        .map_or(0, |b| b.binding)
}

/// Every preprocessor define the GLSL/HLSL builds understand.
pub const DEFINES: &[Define] = &[
    Define::NoBoundaryPath,
    Define::AsymmetricEdgeWeights,
    Define::Capture,
    Define::Adaptive,
    Define::MetricBuffer,
    Define::MetricDistance,
    Define::FractionalOdd,
    Define::FractionalEven,
    Define::Displace,
];

/// Largest workgroup count per dispatch dimension that WebGPU guarantees
/// (`maxComputeWorkgroupsPerDimension`): a dispatch needing more is split
/// (see `generated/README.md`).
pub const WEBGPU_MAX_WORKGROUPS_PER_DIMENSION: u32 = 65535;

/// The ABI as a Rust module, for a runtime's `build.rs` to write into
/// `OUT_DIR` and `include!`: binding numbers by name, the Params layout, the
/// strides, workgroup sizes, bucket constants, the `adaptive` slots, the
/// define names and every WGSL entry's binding list (per scheme for
/// `patch_main`). A runtime that names these instead of typing numbers
/// fails to compile when the ABI changes under it (a renamed or removed
/// binding, field or slot), and follows a renumbering without an edit.
pub fn rust_module(plan: &Plan) -> String {
    use crate::markdown::doc_text;
    use std::fmt::Write;
    let mut s = String::new();
    let w = &mut s;
    let _ = writeln!(
        w,
        "// The GPU ABI, printed by tessgen_codegen::backend::abi::rust_module. Do not edit.\n"
    );
    let _ = writeln!(
        w,
        "/// Binding numbers (group/set 0) by name.\npub mod binding {{"
    );
    for b in BINDINGS {
        let _ = writeln!(
            w,
            "    /// {}\n    pub const {}: u32 = {};",
            doc_text(b.doc),
            b.name.to_uppercase(),
            b.binding
        );
    }
    let _ = writeln!(w, "    /// Not an ABI binding: the Vulkan harness's own geometry-shader triangle capture.\n    pub const TRIANGLES: u32 = {HARNESS_TRIANGLES};");
    let _ = writeln!(w, "}}\n");
    let _ = writeln!(
        w,
        "/// The compute entry points every GPU target provides, by name.\npub mod entry {{"
    );
    for (name, value, doc) in [
        (
            "REFINE",
            entry::REFINE,
            "Refinement stage (refined meshes), before the vertex stage.",
        ),
        ("VERTEX_STAGE", entry::VERTEX_STAGE, "Vertex stage."),
        ("PATCH_STAGE", entry::PATCH_STAGE, "Patch stage."),
        ("EVAL", entry::EVAL, "Uniform evaluation into `samples`."),
    ] {
        let _ = writeln!(w, "    /// {doc}\n    pub const {name}: &str = {value:?};");
    }
    let _ = writeln!(w, "}}\n");
    let _ = writeln!(w, "/// Size of the Params uniform block in bytes.\npub const PARAMS_SIZE: u64 = {PARAMS_SIZE};");
    let _ = writeln!(
        w,
        "/// Byte offsets of the Params fields (`u32` but the matrix).\npub mod params {{"
    );
    for (name, doc) in PARAMS {
        let _ = writeln!(
            w,
            "    /// {}\n    pub const {}: usize = {};",
            doc_text(doc),
            name.to_uppercase(),
            params_offset(name)
        );
    }
    let _ = writeln!(w, "}}\n");
    let consts: &[(&str, &str, u32)] = &[
        ("WORKGROUP_SIZE", "Workgroup size of the compute entry points (but the bucket compaction passes: BUCKET_CHUNK).", WORKGROUP_SIZE),
        ("SAMPLE_FLOATS", "`f32` per evaluated sample: position xyz, normal xyz.", SAMPLE_FLOATS),
        ("PATCH_LEVELS_WORDS", "`u32` per patch in `patch_levels`.", PATCH_LEVELS_WORDS),
        ("PATCH_LEVELS_BUCKET", "The word of a `patch_levels` record holding the patch's bucket.", PATCH_LEVELS_BUCKET),
        ("BUCKET_ENTRY_WORDS", "`u32` per entry of `bucket_patches` / `bucket_list`.", BUCKET_ENTRY_WORDS),
        ("BUCKET_HEADER_WORDS", "`u32` per bucket slot in the header of `bucket_list`.", BUCKET_HEADER_WORDS),
        ("BUCKET_DISPATCH_WORDS", "`u32` per bucket slot in `bucket_dispatch`.", BUCKET_DISPATCH_WORDS),
        ("BUCKET_DRAW_WORDS", "`u32` per bucket slot in `bucket_draw`.", BUCKET_DRAW_WORDS),
        ("BUCKET_SLOTS", "Bucket slots per class range of the GPU-driven buckets.", BUCKET_SLOTS),
        ("FLAG_WIREFRAME", "`Params.flags` bit: `shade_fs` darkens patch boundaries (wireframe overlay).", FLAG_WIREFRAME),
        ("FLAG_PLAIN", "`Params.flags` bit: `shade_fs` colours every patch class alike (grey).", FLAG_PLAIN),
        ("INDIRECT_X", "Largest x workgroup count of one GPU-driven evaluation dispatch.", INDIRECT_X),
        ("BUCKET_CHUNK", "Patches per chunk (and workgroup size) of the bucket compaction.", BUCKET_CHUNK),
        ("SECTOR_WORDS", "`u32` per sector record in `sectors`: kind (0 crease, 1 corner), faces m, ring positions written, first ring position, partial-ring start.", SECTOR_WORDS),
        ("ELEMENT_BYTES", "Bytes per buffer element (`u32`, `f32`; vec3 buffers are packed f32 triples).", ELEMENT_BYTES),
    ];
    for (name, doc, v) in consts {
        let _ = writeln!(w, "/// {doc}\npub const {name}: u32 = {v};");
    }
    // The corner_valence rule, from the scheme language's own function, for
    // every sector size a topology can hold (max_valence up to 128).
    let vv: Vec<String> = (0..=64u32)
        .map(|m| {
            if m == 0 {
                0
            } else {
                crate::front::scheme::virtual_valence(m)
            }
            .to_string()
        })
        .collect();
    let _ = writeln!(
        w,
        "/// Virtual valence n'(m) of a crease or corner sector of `m` faces, index `m` (0 unused):\n/// the valence of its per-valence constants, `corner_valence` (docs/boundaries.md §3).\npub const VIRTUAL_VALENCE: [u32; 65] = [{}];",
        vv.join(", ")
    );
    let _ = writeln!(
        w,
        "/// `tessgen_patch_normal`'s threshold: tangents a, b count as parallel where\n/// |a × b|² ≤ PARALLEL_SIN2·|a|²·|b|² (the CPU fast path applies the same test).\npub const PARALLEL_SIN2: f32 = {:?};",
        crate::plan::PARALLEL_SIN2 as f32
    );
    let _ = writeln!(
        w,
        "/// Fixed-point denominator of adaptive hardware tessellation: the evaluation stage reads the\n/// tessellator's coordinate on the 2^-16 grid (`level` = this).\npub const ADAPTIVE_LEVEL: u32 = {};",
        crate::plan::ADAPTIVE_LEVEL
    );
    let _ = writeln!(
        w,
        "/// Per scheme: the `vec4` slots of the packed per-patch control points between the\n/// tessellation stages (KMAX4 = ⌈3·KMAX / 4⌉, `TessStages::slots`).\npub const TESS_PATCH_SLOTS: &[(&str, u32)] = &["
    );
    for (m, e) in &plan.schemes {
        let _ = writeln!(w, "    ({:?}, {}),", m.name, e.tess.slots);
    }
    let _ = writeln!(w, "];");
    let _ = writeln!(
        w,
        "/// Bytes per evaluated sample.\npub const SAMPLE_BYTES: u64 = {};",
        SAMPLE_FLOATS * ELEMENT_BYTES
    );
    let _ = writeln!(
        w,
        "/// Floats in the `adaptive` buffer.\npub const ADAPTIVE_LEN: usize = {ADAPTIVE_LEN};"
    );
    let _ = writeln!(
        w,
        "/// First float of each slot of the `adaptive` buffer.\npub mod adaptive {{"
    );
    for (name, first, count, doc) in ADAPTIVE {
        let _ = writeln!(
            w,
            "    /// {} ({count} f32)\n    pub const {name}: usize = {first};",
            doc_text(doc)
        );
    }
    let _ = writeln!(w, "}}\n");
    let _ = writeln!(
        w,
        "/// Preprocessor defines of the GLSL/HLSL builds.\npub mod define {{"
    );
    for d in DEFINES {
        let name = d.name();
        let _ = writeln!(
            w,
            "    pub const {}: &str = {name:?};",
            name.trim_start_matches("TESSGEN_")
        );
    }
    let _ = writeln!(w, "}}\n");
    let _ = writeln!(w, "/// How a WGSL entry point accesses a binding.\n#[derive(Clone, Copy, Debug, PartialEq, Eq)]\npub enum Access {{\n    Read,\n    ReadWrite,\n}}\n");
    let _ = writeln!(w, "/// An entry's bindings: `(binding, access)` by binding number.\npub type Bindings = &'static [(u32, Access)];\n");
    let _ = writeln!(w, "/// Every WGSL entry point: `(name, workgroup size (0: not compute), bindings)`; `patch_main`'s are per scheme in [`PATCH_MAIN`].");
    let _ = writeln!(w, "pub const WGSL_ENTRIES: &[(&str, u32, Bindings)] = &[");
    let list = |b: &[(u32, Access)]| {
        b.iter()
            .map(|(n, a)| format!("({n}, Access::{a:?})"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for e in WGSL_ENTRIES {
        let _ = writeln!(
            w,
            "    ({:?}, {}, &[{}]),",
            e.name,
            e.workgroup_size,
            list(e.bindings)
        );
    }
    let _ = writeln!(w, "];\n");
    let _ = writeln!(
        w,
        "/// `patch_main`'s bindings per scheme.\npub const PATCH_MAIN: &[(&str, Bindings)] = &["
    );
    for (m, e) in &plan.schemes {
        let _ = writeln!(
            w,
            "    ({:?}, &[{}]),",
            m.name,
            list(&patch_main_bindings(plan, m, e))
        );
    }
    let _ = writeln!(w, "];");
    s
}

// Tessellation factor slots of the hardware tessellators (Vulkan, D3D).

/// Which patch edges feed a hardware tessellator's factors in adaptive
/// builds: `(outer, inner)`, `outer[s]` the edge (k: `v_k → v_{k+1}`) whose
/// factor goes to outer factor slot `s`, `inner[s]` the edges whose largest
/// factor is inside factor `s`.
///
/// Conventions (Vulkan and D3D alike): a triangle domain's outer slot `s` is
/// the edge where barycentric coordinate `s` is 0 — with `(x, y, z)`
/// weighing corners 0, 1, 2 that is edge 1 (`x = 0`), edge 2 (`y = 0`),
/// edge 0 (`z = 0`) — and its one inside factor is the largest of the three
/// edges. A quad domain's outer slots are the edges `a = 0, b = 0, a = 1,
/// b = 1` of its coordinates `(a, b)`, and inside factor 0 subdivides along
/// `a` (the edges `b = 0`, `b = 1`). HLSL takes `(u, v) = (a, b)`
/// (`first_is_u`), GLSL `(u, v) = (b, a)` (the axis swap that keeps the
/// winding counter-clockwise); our edges are 0: `v = 0`, 1: `u = 1`,
/// 2: `v = 1`, 3: `u = 0`. Every factor depends on its edge alone (Rule 3),
/// the inside ones only on the patch's own edges.
pub fn hw_factor_edges(sides: u32, first_is_u: bool) -> (Vec<usize>, Vec<Vec<usize>>) {
    if sides == 3 {
        return (vec![1, 2, 0], vec![vec![0, 1, 2]]);
    }
    let outer = if first_is_u {
        vec![3, 0, 1, 2]
    } else {
        vec![0, 3, 2, 1]
    };
    let sorted = |mut v: Vec<usize>| {
        v.sort_unstable();
        v
    };
    let inner = vec![
        sorted(vec![outer[1], outer[3]]),
        sorted(vec![outer[0], outer[2]]),
    ];
    (outer, inner)
}

/// The patch edges (k: `v_k → v_{k+1}`) whose largest factor is the inside
/// factor along patch axis `d` ([`StageOut::InsideFactor`]): quads, along
/// `u` (d = 0) the edges `v = 0` and `v = 1` (0 and 2), along `v` the
/// edges 1 and 3; triangles, all three. Printers find the API slot of that
/// set in [`crate::plan::abi::hw_factor_edges`].
pub fn inside_edges(sides: u32, d: u8) -> Vec<usize> {
    match (sides, d) {
        (3, _) => vec![0, 1, 2],
        (_, 0) => vec![0, 2],
        _ => vec![1, 3],
    }
}

/// The index of factor output `o` in an API's outer (edge factors) or
/// inner (inside factors) array, `first_is_u` as in
/// [`crate::plan::abi::hw_factor_edges`] (HLSL: true, GLSL: false); `None` for
/// an output that is not a factor. Every factor has a slot (the test
/// below), so printers only spell the index.
pub fn factor_slot(sides: u32, o: StageOut, first_is_u: bool) -> Option<usize> {
    let (outer, inner) = crate::plan::abi::hw_factor_edges(sides, first_is_u);
    match o {
        StageOut::EdgeFactor(k) => outer.iter().position(|&x| x == k as usize),
        StageOut::InsideFactor(d) => inner.iter().position(|x| *x == inside_edges(sides, d)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No two ABI bindings share a number, and none takes the harness's.
    #[test]
    fn binding_numbers_are_unique() {
        let mut seen: Vec<u32> = BINDINGS.iter().map(|b| b.binding).collect();
        seen.push(HARNESS_TRIANGLES);
        let n = seen.len();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), n);
    }

    /// Every entry list names ABI bindings only, in binding order.
    #[test]
    fn entry_lists_name_abi_bindings() {
        for e in WGSL_ENTRIES {
            for (b, _) in e.bindings {
                assert!(BINDINGS.iter().any(|x| x.binding == *b), "{}: {b}", e.name);
            }
            assert!(e.bindings.windows(2).all(|w| w[0].0 < w[1].0), "{}", e.name);
        }
    }

    /// Params offsets are consecutive u32s after the matrix and fill PARAMS_SIZE.
    #[test]
    fn params_layout() {
        let last = PARAMS[PARAMS.len() - 1].0;
        assert_eq!(params_offset(last) + 4, PARAMS_SIZE);
        let mut slots: Vec<(u32, u32)> = ADAPTIVE.iter().map(|a| (a.1, a.2)).collect();
        slots.sort_unstable();
        assert_eq!(slots.last().map(|(f, c)| f + c), Some(ADAPTIVE_LEN));
    }
}
