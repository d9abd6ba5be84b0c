//! [`Resource`]: the global data Plan functions read and write, by element.

use super::Ty;

/// Global data a function reads or writes. Every backend binds these in its
/// own way (slices, storage buffers, textures, patch inputs); the Plan only
/// says which element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Resource {
    /// `vec3` control-mesh position, by vertex.
    Positions,
    /// `u32` valence, by vertex.
    Valence,
    /// `u32` start of a vertex's ring in [`Resource::Ring`], by vertex.
    RingOffsets,
    /// `u32` vertex indices of every ring `[p, p_0 … p_{2n-1}]`, flat.
    Ring,
    /// `u32` start of a vertex's vertex-stage outputs, by vertex.
    VertexOutOffsets,
    /// `vec3` vertex-stage outputs, flat (written by the vertex stage).
    VertexOut,
    /// `u32` corner vertex, by `4·face + corner`.
    CornerVertex,
    /// `u32` corner sector index `j_i`, by `4·face + corner`.
    CornerSector,
    /// `vec3` patch control points (written by the patch stage).
    ControlPoints,
    /// The same `control_points` buffer (same binding), read as the global
    /// buffer of every patch even in the tessellation stages, where
    /// [`Resource::ControlPoints`] is the patch's own array (`tcs_cp`, HLSL
    /// `cp`). The displacing evaluation stage reads the *owner* patch's
    /// control points through it (watertight.md Rule 4); the buffer must
    /// have been filled by the compute patch stage (`patch_main`; HLSL's
    /// writes it through this resource, copying its patch-local array:
    /// [`Entries::compute_patch_local`](super::Entries::compute_patch_local)).
    GlobalControlPoints,
    /// `vec3` unit normal, by vertex (triangle schemes).
    Normals,
    /// `f32` scalar tags, 4 per vertex: tension θ, sharpness σ, bias β,
    /// creased (1 when Δ ≠ 0) — scalar-tagged PN (pn.md §3).
    Tags,
    /// `vec3` crease vector Δ, by vertex (scalar-tagged PN).
    Crease,
    /// `f32` side sign ±1, by `3·face + corner` (scalar-tagged PN).
    CornerSide,
    /// `u32` global edge id of edge k (`v_k → v_{k+1}`) of face f, by
    /// `4·face + k` (adaptive tessellation: both faces of an edge hold the
    /// same id).
    FaceEdges,
    /// `f32` explicit tessellation factor, by global edge id (adaptive
    /// tessellation, `TESSGEN_METRIC_BUFFER`).
    EdgeFactors,
    /// `f32` adaptive-tessellation parameters (layout: `abi::ADAPTIVE`).
    Adaptive,
    /// `f32` texture coordinates for displacement, 16 `(s, t)` pairs per quad
    /// patch (watertight.md Rule 5): pair `4k + j` of face `f` at
    /// `32f + 2(4k + j)`, corner `k`, `j` = 0 interior, 1 the owner of edge
    /// `k`'s coordinate of `v_k`, 2 the owner of edge `k − 1`'s coordinate of
    /// `v_k`, 3 the owner of vertex `v_k`'s coordinate.
    TexCoords,
    /// `u32` ownership records for displacement (watertight.md Rule 4): per
    /// face 8 records of 4 (slots 0–3 edge `k`, 4–7 corner `k`) at
    /// `32f + 4·slot`: the owner patch's class, its first control point, its
    /// local edge (corner) index, and 1 when it runs the edge the other way.
    Owners,
    /// `f32` displacement parameters: scale (0 = displacement off), map
    /// width, map height (texels, as f32), unused.
    DisplaceInfo,
    /// The scalar displacement map, a 2-D `R32Float` texture read with
    /// [`Expr::Texel`](super::Expr::Texel) (exact texel fetches, bilinear
    /// weights in the Plan).
    DisplaceMap,
    /// `u32` face of the draw's patch `p`, by `params.first + p` (written by
    /// the host: patches sorted by class). Read by the tessellation stage
    /// bodies ([`TessStages`](super::TessStages)).
    PatchFaces,
    /// `f32` captured samples, 6 per sample (position xyz, normal xyz),
    /// written by the evaluation stage of capture builds
    /// ([`Define::Capture`](super::Define::Capture),
    /// [`TessStages`](super::TessStages)).
    Samples,
    /// `u32` adaptive classify output, `abi::PATCH_LEVELS_WORDS` per patch
    /// (the WGSL instanced entries, [`Entries::instanced`](super::Entries::instanced)).
    PatchLevels,
    /// `u32` adaptive draw lists, `abi::BUCKET_ENTRY_WORDS` per entry.
    BucketPatches,
    /// `u32` GPU-driven bucket header and entries (written on the GPU).
    BucketList,
    /// `u32` GPU-driven indirect dispatch arguments.
    BucketDispatch,
    /// `u32` GPU-driven indexed indirect draw arguments.
    BucketDraw,
    /// `u32` GPU-driven per-chunk slot counts and offsets.
    BucketChunks,
    /// `u32` workgroup-shared array of one chunk's bucket levels (declared
    /// by [`EntryItem::Workgroup`](super::EntryItem::Workgroup); no binding).
    BucketTile,
    /// `u32` first sector of each vertex in [`Resource::Sectors`], by vertex
    /// (plus a final total); an empty range = a smooth vertex
    /// (docs/boundaries.md §2).
    VertexSectors,
    /// `u32` sector records, `abi::SECTOR_WORDS` per sector: kind (0
    /// crease, 1 corner), faces m, ring positions written, first ring
    /// position, start of its partial ring in [`Resource::Ring`].
    Sectors,
    /// `u32` valence whose per-valence constants corner `i` of face `f`
    /// uses (the virtual valence at crease and corner vertices), by
    /// `4·face + corner`.
    CornerValence,
    /// `vec3` base-mesh positions of a refined mesh, by base vertex (the
    /// refinement stage's input; docs/boundaries.md §8).
    RefineBase,
    /// `u32` start of each refined vertex's stencil row in
    /// [`Resource::RefineIndices`] / [`Resource::RefineWeights`], by refined
    /// vertex (plus a final total).
    RefineOffsets,
    /// `u32` base vertex of each stencil term, flat.
    RefineIndices,
    /// `f32` weight of each stencil term, flat.
    RefineWeights,
    /// `vec3` refined positions, by refined vertex (written by the
    /// refinement stage): the host binds the buffer the vertex stage reads
    /// as [`Resource::Positions`].
    RefinedPositions,
}

impl Resource {
    pub fn ty(self) -> Ty {
        match self {
            Resource::Positions
            | Resource::VertexOut
            | Resource::ControlPoints
            | Resource::GlobalControlPoints
            | Resource::Normals
            | Resource::Crease
            | Resource::RefineBase
            | Resource::RefinedPositions => Ty::Vec3,
            Resource::Tags
            | Resource::CornerSide
            | Resource::EdgeFactors
            | Resource::Adaptive
            | Resource::TexCoords
            | Resource::DisplaceInfo
            | Resource::DisplaceMap
            | Resource::Samples
            | Resource::RefineWeights => Ty::F32,
            _ => Ty::U32,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Resource::Positions => "positions",
            Resource::Valence => "valence",
            Resource::RingOffsets => "ring_offsets",
            Resource::Ring => "ring",
            Resource::VertexOutOffsets => "vertex_out_offsets",
            Resource::VertexOut => "vertex_out",
            Resource::CornerVertex => "corner_vertex",
            Resource::CornerSector => "corner_sector",
            Resource::ControlPoints | Resource::GlobalControlPoints => "control_points",
            Resource::Normals => "normals",
            Resource::Tags => "tags",
            Resource::Crease => "crease",
            Resource::CornerSide => "corner_side",
            Resource::FaceEdges => "face_edges",
            Resource::EdgeFactors => "edge_factors",
            Resource::Adaptive => "adaptive",
            Resource::TexCoords => "texcoords",
            Resource::Owners => "owners",
            Resource::DisplaceInfo => "displace_info",
            Resource::DisplaceMap => "displace_map",
            Resource::PatchFaces => "patch_faces",
            Resource::Samples => "samples",
            Resource::PatchLevels => "patch_levels",
            Resource::BucketPatches => "bucket_patches",
            Resource::BucketList => "bucket_list",
            Resource::BucketDispatch => "bucket_dispatch",
            Resource::BucketDraw => "bucket_draw",
            Resource::BucketChunks => "bucket_chunks",
            Resource::BucketTile => "tessgen_bucket_tile",
            Resource::VertexSectors => "vertex_sectors",
            Resource::Sectors => "sectors",
            Resource::CornerValence => "corner_valence",
            Resource::RefineBase => "refine_base",
            Resource::RefineOffsets => "refine_offsets",
            Resource::RefineIndices => "refine_indices",
            Resource::RefineWeights => "refine_weights",
            Resource::RefinedPositions => "refined_positions",
        }
    }
    pub const ALL: [Resource; 28] = [
        Resource::Positions,
        Resource::Valence,
        Resource::RingOffsets,
        Resource::Ring,
        Resource::VertexOutOffsets,
        Resource::VertexOut,
        Resource::CornerVertex,
        Resource::CornerSector,
        Resource::ControlPoints,
        Resource::Normals,
        Resource::Tags,
        Resource::Crease,
        Resource::CornerSide,
        Resource::FaceEdges,
        Resource::EdgeFactors,
        Resource::Adaptive,
        Resource::TexCoords,
        Resource::Owners,
        Resource::DisplaceInfo,
        Resource::DisplaceMap,
        Resource::VertexSectors,
        Resource::Sectors,
        Resource::CornerValence,
        Resource::RefineBase,
        Resource::RefineOffsets,
        Resource::RefineIndices,
        Resource::RefineWeights,
        Resource::RefinedPositions,
    ];
}
