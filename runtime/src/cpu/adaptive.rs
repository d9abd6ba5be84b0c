//! Adaptive tessellation: per-edge factors that depend only on the edge.
//!
//! A crack-free adaptive tessellation needs both patches of an edge to hand
//! the tessellator the *same* factor bits (watertight.md Rule 3). The
//! emitted control stages compute it with the Plan function
//! `tessgen_edge_factor` from the edge's two end points (patch corners:
//! shared control points, bit-identical in both patches) in canonical order
//! (lower global vertex first), or read it from `edge_factors[edge id]`.
//! This module holds the host side: global edge ids, the `adaptive`
//! parameter buffer (binding 19, layout `abi::ADAPTIVE`) and the metric
//! options.

use crate::mesh::topology::Topology;
use crate::mesh::trimesh::TriMesh;
use glam::{Mat4, Vec3};

/// How the tessellator spaces the vertices of a fractional factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Partitioning {
    /// `equal_spacing` / `integer`: the factor is rounded up to an integer.
    #[default]
    Integer,
    /// `fractional_odd_spacing` / `fractional_odd`.
    FractionalOdd,
    /// `fractional_even_spacing` / `fractional_even`.
    FractionalEven,
}

impl Partitioning {
    /// The shader define that selects it (none for integer).
    pub fn define(self) -> Option<&'static str> {
        match self {
            Partitioning::Integer => None,
            Partitioning::FractionalOdd => Some(crate::abi::define::FRACTIONAL_ODD),
            Partitioning::FractionalEven => Some(crate::abi::define::FRACTIONAL_EVEN),
        }
    }
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "integer" => Some(Partitioning::Integer),
            "fractional-odd" | "fractional_odd" => Some(Partitioning::FractionalOdd),
            "fractional-even" | "fractional_even" => Some(Partitioning::FractionalEven),
            _ => None,
        }
    }
}

/// Where the per-edge factor comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Metric {
    /// Projected edge length in pixels over `pixels_per_segment`.
    Screen {
        view_proj: Mat4,
        viewport: [f32; 2],
        pixels_per_segment: f32,
    },
    /// `scale · |b − a| / |(a + b)/2 − eye|`.
    Distance { eye: Vec3, scale: f32 },
    /// Explicit factor per global edge id ([`edge_ids`]).
    Buffer(Vec<f32>),
    /// Negative control: an explicit factor per *face edge* `4f + k`, not
    /// shared between the two faces of an edge (e.g. one factor per patch).
    /// The two sides of an edge then get different vertex sets: cracks.
    PerFaceEdge(Vec<f32>),
}

/// Adaptive tessellation settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Adaptive {
    pub metric: Metric,
    pub partitioning: Partitioning,
    /// Factors are clamped to `[min, max]` (max at most the device's
    /// `maxTessellationGenerationLevel`).
    pub min: f32,
    pub max: f32,
}

impl Adaptive {
    /// The shader defines of this configuration.
    pub fn defines(&self) -> Vec<String> {
        let mut d = vec![crate::abi::define::ADAPTIVE.to_string()];
        match self.metric {
            Metric::Buffer(_) | Metric::PerFaceEdge(_) => {
                d.push(crate::abi::define::METRIC_BUFFER.into())
            }
            Metric::Distance { .. } => d.push(crate::abi::define::METRIC_DISTANCE.into()),
            Metric::Screen { .. } => {}
        }
        if let Some(p) = self.partitioning.define() {
            d.push(p.into());
        }
        d
    }

    /// The `adaptive` buffer (`binding::ADAPTIVE`): ADAPTIVE_LEN f32, layout `abi::ADAPTIVE`.
    pub fn params(&self) -> Vec<f32> {
        use crate::abi::adaptive as slot;
        let mut a = vec![0.0f32; ADAPTIVE_LEN];
        match &self.metric {
            Metric::Screen {
                view_proj,
                viewport,
                pixels_per_segment,
            } => {
                let vp = slot::VIEW_PROJ;
                a[vp..vp + 16].copy_from_slice(&view_proj.to_cols_array());
                a[slot::VIEWPORT] = viewport[0];
                a[slot::VIEWPORT + 1] = viewport[1];
                a[slot::PIXELS_PER_SEGMENT] = *pixels_per_segment;
            }
            Metric::Distance { eye, scale } => {
                a[slot::EYE..slot::EYE + 3].copy_from_slice(&eye.to_array());
                a[slot::DISTANCE_SCALE] = *scale;
            }
            Metric::Buffer(_) | Metric::PerFaceEdge(_) => {}
        }
        a[slot::MIN_FACTOR] = self.min;
        a[slot::MAX_FACTOR] = self.max;
        // The metric of `tessgen_edge_factor_runtime` (WGSL, Rust); the
        // GLSL/HLSL control stages select theirs with a define instead.
        a[METRIC_SLOT] = match self.metric {
            Metric::Screen { .. } => 0.0,
            Metric::Distance { .. } => 1.0,
            Metric::Buffer(_) | Metric::PerFaceEdge(_) => 2.0,
        };
        a
    }

    /// The `edge_factors` buffer (binding 18): the explicit factors, or
    /// empty for the computed metrics.
    pub fn edge_factors(&self) -> &[f32] {
        match &self.metric {
            Metric::Buffer(f) | Metric::PerFaceEdge(f) => f,
            _ => &[],
        }
    }
}

/// Floats in the `adaptive` buffer (from the ABI).
pub const ADAPTIVE_LEN: usize = crate::abi::ADAPTIVE_LEN;

/// Float of the `adaptive` buffer selecting the metric at run time (0
/// screen, 1 distance, 2 explicit buffer), `abi::ADAPTIVE`.
pub const METRIC_SLOT: usize = crate::abi::adaptive::METRIC;

/// Global edge id of edge k (`v_k → v_{k+1}`, half-edge `face_offsets[f] + k`)
/// of every face, at `4f + k` (`sides·f + k`): edges numbered in order of
/// their first half-edge, both half-edges of an edge get the same id.
/// Returns `(ids, number of edges)`.
pub fn edge_ids(topo: &Topology) -> (Vec<u32>, u32) {
    let halfedges = topo.twin.len();
    let mut id = vec![u32::MAX; halfedges];
    let mut next = 0u32;
    for h in 0..halfedges {
        if id[h] != u32::MAX {
            continue;
        }
        id[h] = next;
        let t = topo.twin[h] as usize;
        if t < halfedges {
            id[t] = next;
        }
        next += 1;
    }
    (id, next)
}

/// Deterministic pseudo-random factors in `[lo, hi]`, one per edge
/// (splitmix64 of `seed` and the edge id): for tests and the CLI's
/// `--adaptive random:SEED`.
pub fn random_factors(edges: u32, seed: u64, lo: f32, hi: f32) -> Vec<f32> {
    (0..edges as u64)
        .map(|e| {
            let mut z = seed
                .wrapping_add(e.wrapping_mul(0x9E37_79B9_7F4A_7C15))
                .wrapping_add(0x9E37_79B9_7F4A_7C15);
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            let t = (z >> 40) as f32 / (1u64 << 24) as f32;
            lo + (hi - lo) * t
        })
        .collect()
}

/// The mesh an instanced adaptive run (CPU or wgpu) tessellates: what
/// the generated `patch_edge_level` reads besides the control points — the
/// global edge id of every face edge and the corners' vertices. Quad
/// schemes run on a [`Topology`], triangle schemes (`pn`, `stpn`, `phong`)
/// on a [`TriMesh`] (e.g. `cpu::tri_mesh` with `--split-quads`); both
/// convert with `.into()`, so `evaluate_cpu_adaptive(&patches, &topo, …)`
/// and `evaluate_cpu_adaptive(&patches, &tri, …)` read alike.
#[derive(Clone, Copy, Debug)]
pub enum AdaptiveMesh<'a> {
    Quads(&'a Topology),
    Triangles(&'a TriMesh),
}

impl<'a> From<&'a Topology> for AdaptiveMesh<'a> {
    fn from(t: &'a Topology) -> Self {
        AdaptiveMesh::Quads(t)
    }
}

impl<'a> From<&'a TriMesh> for AdaptiveMesh<'a> {
    fn from(t: &'a TriMesh) -> Self {
        AdaptiveMesh::Triangles(t)
    }
}

impl AdaptiveMesh<'_> {
    /// Faces (patches).
    pub fn faces(&self) -> usize {
        match self {
            AdaptiveMesh::Quads(t) => t.corners.len(),
            AdaptiveMesh::Triangles(t) => t.triangles.len(),
        }
    }

    /// Corners (edges) per face.
    pub fn sides(&self) -> u32 {
        match self {
            AdaptiveMesh::Quads(_) => 4,
            AdaptiveMesh::Triangles(_) => 3,
        }
    }

    /// Global edge ids at `sides·f + k` and the number of edges
    /// ([`edge_ids`], [`TriMesh::edge_ids`]).
    pub fn edge_ids(&self) -> (Vec<u32>, u32) {
        match self {
            AdaptiveMesh::Quads(t) => edge_ids(t),
            AdaptiveMesh::Triangles(t) => t.edge_ids(),
        }
    }

    /// Vertex of corner k of face f at `sides·f + k` (`corner_vertex`).
    pub fn corner_vertex(&self) -> Vec<u32> {
        match self {
            AdaptiveMesh::Quads(t) => crate::cpu::corner_arrays(t).0,
            AdaptiveMesh::Triangles(t) => t.triangles.iter().flatten().copied().collect(),
        }
    }
}

// ---- CPU: power-of-two buckets with snapped transitions ----

/// Errors of the adaptive tessellators (CPU and wgpu).
#[derive(Debug, thiserror::Error)]
pub enum AdaptiveError {
    #[error(transparent)]
    Tess(#[from] crate::cpu::TessError),
    #[error("explicit edge factors: the mesh has {expected} edges, {got} factors were given")]
    EdgeFactorCount { expected: usize, got: usize },
    #[error("largest adaptive level must be a power of two in 1..={max}, got {got}", max = crate::cpu::MAX_LEVEL)]
    MaxLevel { got: u32 },
    #[error("edge {edge}: factor {factor} is not a finite number")]
    BadFactor { edge: usize, factor: f32 },
    #[error("adaptive clamp range [{min}, {max}] is not a finite range with min <= max")]
    Clamp { min: f32, max: f32 },
    #[error("the patches have {patches} faces but the mesh given for their edges has {faces}")]
    MeshMismatch { patches: usize, faces: usize },
    #[error("scheme `{scheme}` tessellates {want}, but the mesh given for its edges has {got}")]
    Domain {
        scheme: String,
        want: &'static str,
        got: &'static str,
    },
    #[error(
        "the displacement data has {what} for {got} faces, the patches have {patches} faces \
         (build it from the same mesh and patches)"
    )]
    DisplaceMismatch {
        what: &'static str,
        got: usize,
        patches: usize,
    },
}

/// The power-of-two level of an edge: the smallest `2^k ≥ factor`, clamped
/// to `1..=max_level` (a power of two). A function of the factor alone, so
/// of the edge alone. This is the generated `tessgen_edge_level` (the Plan
/// function the WGSL classify pass runs too), not a host copy of it.
pub fn edge_level(factor: f32, max_level: u32) -> u32 {
    crate::kernels::common::tessgen_edge_level(factor, max_level)
}

/// The per-edge data of an adaptive run, checked: what the generated
/// `patch_edge_level` reads on the CPU (`Inputs`) and on the GPU (bindings
/// 17–19). Shared by [`evaluate_cpu_adaptive`] and
/// `gpu::GpuMesh::evaluate_adaptive`, so both see the same bits.
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeInputs {
    /// Edge id of edge k of face f at `sides·f + k` (`face_edges`, binding 17).
    pub face_edges: Vec<u32>,
    /// Explicit factors by edge id (`edge_factors`, binding 18); one zero
    /// for the computed metrics (wgpu rejects empty bindings).
    pub edge_factors: Vec<f32>,
    /// The `adaptive` buffer (binding 19), metric selector included.
    pub params: Vec<f32>,
}

/// Check an adaptive configuration against the mesh and lay out its
/// per-edge data: `max_level` a power of two in `1..=MAX_LEVEL`, explicit
/// factors one per edge ([`Metric::Buffer`]) or per face edge
/// ([`Metric::PerFaceEdge`]) and finite, the clamp range finite.
pub fn edge_inputs<'m>(
    mesh: impl Into<AdaptiveMesh<'m>>,
    a: &Adaptive,
    max_level: u32,
) -> Result<EdgeInputs, AdaptiveError> {
    let mesh = mesh.into();
    if !max_level.is_power_of_two() || max_level > crate::cpu::MAX_LEVEL {
        return Err(AdaptiveError::MaxLevel { got: max_level });
    }
    let (mut ids, mut edges) = mesh.edge_ids();
    if let Metric::PerFaceEdge(_) = &a.metric {
        // Negative control: every face edge its own id.
        edges = ids.len() as u32;
        ids = (0..edges).collect();
    }
    check_settings(a, edges as usize)?;
    let factors = a.edge_factors();
    Ok(EdgeInputs {
        face_edges: ids,
        edge_factors: if factors.is_empty() {
            vec![0.0]
        } else {
            factors.to_vec()
        },
        params: a.params(),
    })
}

/// The checks of an adaptive configuration that do not need the mesh: the
/// clamp range finite and ordered, explicit factors (if the metric has
/// them) `edges` of them and finite. [`edge_inputs`] makes them, and a
/// renderer that changes the metric per frame makes them again.
pub fn check_settings(a: &Adaptive, edges: usize) -> Result<(), AdaptiveError> {
    if !(a.min.is_finite() && a.max.is_finite() && a.min <= a.max) {
        return Err(AdaptiveError::Clamp {
            min: a.min,
            max: a.max,
        });
    }
    let factors = a.edge_factors();
    if let Metric::Buffer(_) | Metric::PerFaceEdge(_) = &a.metric {
        if factors.len() != edges {
            return Err(AdaptiveError::EdgeFactorCount {
                expected: edges,
                got: factors.len(),
            });
        }
        if let Some((edge, &factor)) = factors.iter().enumerate().find(|(_, f)| !f.is_finite()) {
            return Err(AdaptiveError::BadFactor { edge, factor });
        }
    }
    Ok(())
}

/// A tessellation with one power-of-two level per patch (its *bucket*: the
/// largest level of its edges) and one level per edge (CPU:
/// [`evaluate_cpu_adaptive`]; wgpu: `gpu::GpuMesh::evaluate_adaptive`, the
/// same layout bit for bit).
///
/// Face `f` is the `grid_len(levels[f])` samples of its domain's grid from
/// `offsets[f]`: quads an `(L + 1)²` grid in the usual order
/// (`iv·(L+1) + iu`), triangles (`sides` 3) the triangle grid row by row
/// (`crate::grid::tri_grid_index`, barycentric `(L − iu − iv, iu, iv)`).
/// Its interior samples are at `(iu, iv)/L`; a boundary sample `i` of edge
/// `k`, whose own level is `L_e = edge_levels[sides·f + k] ≤ L`,
/// is *snapped* to the edge's coarser point `⌊i / (L / L_e)⌋` and evaluated
/// there through the shared edge evaluator at level `L_e` (the generated
/// `eval_adaptive`) — exactly the
/// points the neighbour produces for that edge, whatever its bucket. Fine
/// boundary triangles whose two boundary corners snapped to one point are
/// degenerate (skipped by the weld); the rest stitch the levels without
/// T-junctions. On a GPU each bucket is one instanced draw of its level's
/// grid.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AdaptiveTessellation {
    /// Corners per face: 4 (quad grids) or 3 (triangle grids).
    pub sides: u32,
    pub levels: Vec<u32>,
    pub edge_levels: Vec<u32>,
    pub offsets: Vec<usize>,
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// Face of each grid when some faces emit nothing (holes, faces
    /// without a limit surface: docs/boundaries.md §5); empty means grid `g`
    /// is face `g`. `levels` and `offsets` are per grid; `edge_levels`
    /// stays per face (`sides·f + k` over every face), as the factors of
    /// a hole's edges still decide its emitting neighbours' samples.
    pub face_ids: Vec<u32>,
}

impl AdaptiveTessellation {
    /// Face of grid `g` (docs/boundaries.md §5).
    pub fn face_of(&self, g: usize) -> usize {
        self.face_ids.get(g).map_or(g, |&f| f as usize)
    }

    /// Keeps only the grids of faces with `keep[face]`, recording their
    /// faces in [`AdaptiveTessellation::face_ids`] (the adaptive form of
    /// [`crate::Tessellation::retain_faces`]).
    pub fn retain_faces(&mut self, keep: &[bool]) {
        let (mut ids, mut levels, mut offsets) = (Vec::new(), Vec::new(), vec![0usize]);
        let (mut pos, mut nrm) = (Vec::new(), Vec::new());
        for g in 0..self.levels.len() {
            let f = self.face_of(g);
            if keep.get(f).copied().unwrap_or(true) {
                let (a, b) = (self.offsets[g], self.offsets[g + 1]);
                ids.push(f as u32);
                levels.push(self.levels[g]);
                pos.extend_from_slice(&self.positions[a..b]);
                nrm.extend_from_slice(&self.normals[a..b]);
                offsets.push(pos.len());
            }
        }
        self.face_ids = ids;
        self.levels = levels;
        self.offsets = offsets;
        self.positions = pos;
        self.normals = nrm;
    }

    /// Every face's grid triangles as world positions (a triangle soup for
    /// [`crate::check::weld::weld_triangles`] or OBJ output): the quad grid's
    /// ([`crate::grid::grid_triangles`]) or the triangle grid's
    /// ([`crate::grid::tri_grid_triangles`], the uniform triangle path's).
    pub fn triangles(&self) -> Vec<[Vec3; 3]> {
        let mut out = Vec::new();
        let mut local: std::collections::BTreeMap<u32, Vec<[u32; 3]>> = Default::default();
        for g in 0..self.levels.len() {
            self.grid_triangles(g, &mut local, &mut out);
        }
        out
    }

    /// The triangles of one grid at `level` over its local sample indices
    /// ([`crate::grid`]'s layout for this domain).
    pub fn local_triangles(&self, level: u32) -> Vec<[u32; 3]> {
        if self.sides == 3 {
            crate::grid::tri_grid_triangles(level)
        } else {
            crate::grid::grid_triangles(level)
        }
    }

    /// Append grid `g`'s triangles as world positions to `out`; `local`
    /// keeps each level's local triangles, built on first use.
    pub fn grid_triangles(
        &self,
        g: usize,
        local: &mut std::collections::BTreeMap<u32, Vec<[u32; 3]>>,
        out: &mut Vec<[Vec3; 3]>,
    ) {
        let (l, base) = (self.levels[g], self.offsets[g]);
        let tris = local.entry(l).or_insert_with(|| self.local_triangles(l));
        out.extend(
            tris.iter()
                .map(|t| t.map(|k| self.positions[base + k as usize])),
        );
    }

    /// Faces per bucket level, ascending: one instanced draw each.
    pub fn buckets(&self) -> std::collections::BTreeMap<u32, Vec<u32>> {
        let mut b: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
        for (f, &l) in self.levels.iter().enumerate() {
            b.entry(l).or_default().push(f as u32);
        }
        b
    }
}

/// CPU adaptive tessellation of constructed patches from explicit
/// `factors` per global edge id ([`edge_ids`], [`TriMesh::edge_ids`]):
/// [`evaluate_cpu_adaptive`] with [`Metric::Buffer`], factors clamped to
/// `[1, max_level]` (which does not change their power-of-two levels).
pub fn evaluate_cpu<'m>(
    patches: &crate::cpu::Patches,
    topo: impl Into<AdaptiveMesh<'m>>,
    factors: &[f32],
    max_level: u32,
) -> Result<AdaptiveTessellation, AdaptiveError> {
    let a = Adaptive {
        metric: Metric::Buffer(factors.to_vec()),
        partitioning: Partitioning::Integer,
        min: 1.0,
        max: max_level as f32,
    };
    evaluate_cpu_adaptive(patches, topo, &a, max_level)
}

/// CPU adaptive tessellation of constructed patches (quad schemes on a
/// [`Topology`], triangle schemes on a [`TriMesh`]) with any metric,
/// through the generated Rust — the same Plan functions the WGSL classify
/// and evaluation entries run: each edge's level from
/// `patch_edge_level` (factor of the edge's end points or id, then the
/// smallest power of two ≥ it, clamped to `max_level`), each patch's bucket
/// `tessgen_bucket_level` (the largest of its edges), every sample
/// `eval_adaptive` (boundary samples snapped onto the edge's own level).
/// `a.partitioning` is ignored: levels are powers of two.
pub fn evaluate_cpu_adaptive<'m>(
    patches: &crate::cpu::Patches,
    mesh: impl Into<AdaptiveMesh<'m>>,
    a: &Adaptive,
    max_level: u32,
) -> Result<AdaptiveTessellation, AdaptiveError> {
    adaptive_cpu(patches, mesh.into(), a, max_level, None)
}

/// [`evaluate_cpu_adaptive`] through the displacement step
/// (`eval_adaptive_displaced`: the same snap, then `p + scale · h(tc) · n`
/// with the owner's normal and texture coordinate on shared edges and
/// corners, evaluated at the edge's own level, see `crate::cpu::displace`).
/// `data` must be built for these patches in the CPU layout
/// ([`crate::cpu::displacement_data`], [`crate::cpu::displacement_data_tri`]);
/// with a zero scale the result is [`evaluate_cpu_adaptive`]'s, bit for
/// bit.
pub fn evaluate_cpu_adaptive_displaced<'m>(
    patches: &crate::cpu::Patches,
    mesh: impl Into<AdaptiveMesh<'m>>,
    a: &Adaptive,
    max_level: u32,
    data: &crate::cpu::displace::DisplaceData,
) -> Result<AdaptiveTessellation, AdaptiveError> {
    adaptive_cpu(patches, mesh.into(), a, max_level, Some(data))
}

/// The CPU adaptive walk of [`evaluate_cpu_adaptive`]: [`AdaptiveRun::new`]
/// then every face ([`AdaptiveRun::evaluate`] over all of them).
fn adaptive_cpu(
    patches: &crate::cpu::Patches,
    mesh: AdaptiveMesh<'_>,
    a: &Adaptive,
    max_level: u32,
    displace: Option<&crate::cpu::displace::DisplaceData>,
) -> Result<AdaptiveTessellation, AdaptiveError> {
    let run = AdaptiveRun::new(patches, mesh, a, max_level, displace)?;
    let mut t = AdaptiveTessellation::default();
    run.evaluate(0..run.faces(), &mut t)?;
    t.face_ids.clear();
    Ok(t)
}

/// A CPU adaptive run, classified: every face's four level slots (the
/// metric of each edge through the generated `patch_edge_level`), its
/// bucket and the sample offset of its grid, computed once for the whole
/// mesh (a few words per face) — after which any window of faces is
/// evaluated on its own ([`AdaptiveRun::evaluate`]), so a streaming caller
/// (`tessellate::Session::run_chunked`) holds one window's samples at a
/// time. Each sample is a pure function of its face and grid point: a
/// window's samples are the whole run's, bit for bit.
pub struct AdaptiveRun<'p> {
    patches: &'p crate::cpu::Patches,
    displace: Option<&'p crate::cpu::displace::DisplaceData>,
    corner_vertex: Vec<u32>,
    inputs: EdgeInputs,
    /// Four level slots per face, as the WGSL classify pass writes them (a
    /// triangle's slot 3 is 1 and unread).
    slots: Vec<[u32; 4]>,
    /// Bucket level per face (the largest of its edges').
    levels: Vec<u32>,
    /// `sides` real edge levels per face.
    edge_levels: Vec<u32>,
    /// Where each face's grid starts in the whole result (`faces + 1`).
    offsets: Vec<usize>,
    /// What the kernels read when there is no displacement.
    off: crate::cpu::displace::DisplaceData,
}

impl<'p> AdaptiveRun<'p> {
    /// Check the run (the mesh is the patches' and of their domain, the
    /// factors and clamp finite, `max_level` a power of two, displacement
    /// data built for these patches) and classify every face.
    pub fn new(
        patches: &'p crate::cpu::Patches,
        mesh: AdaptiveMesh<'_>,
        a: &Adaptive,
        max_level: u32,
        displace: Option<&'p crate::cpu::displace::DisplaceData>,
    ) -> Result<Self, AdaptiveError> {
        use rayon::prelude::*;
        let kernels = patches.scheme;
        check_mesh(kernels, &mesh, patches.face_class.len())?;
        let inputs = edge_inputs(mesh, a, max_level)?;
        let corner_vertex = mesh.corner_vertex();
        let sides = kernels.sides as usize;
        let faces = patches.face_class.len();
        if let Some(data) = displace.filter(|d| d.info[0] != 0.0) {
            let stride = 8 * sides;
            for (what, len) in [
                ("texture coordinates", data.texcoords.len()),
                ("owner records", data.owners.len()),
            ] {
                if len != stride * faces {
                    return Err(AdaptiveError::DisplaceMismatch {
                        what,
                        got: len / stride,
                        patches: faces,
                    });
                }
            }
        }
        let mut run = AdaptiveRun {
            patches,
            displace,
            corner_vertex,
            inputs,
            slots: Vec::new(),
            levels: Vec::new(),
            edge_levels: Vec::new(),
            offsets: Vec::with_capacity(faces + 1),
            off: crate::cpu::displace::DisplaceData::off(),
        };
        let ak = kernels.adaptive;
        let slots: Vec<[u32; 4]> = {
            let inputs = run.kernel_inputs();
            (0..faces)
                .into_par_iter()
                .map(|f| {
                    [0, 1, 2, 3].map(|k| {
                        (ak.edge_level)(
                            &inputs,
                            run.control_points(f),
                            f as u32,
                            patches.face_class[f],
                            0,
                            k,
                            max_level,
                        )
                    })
                })
                .collect()
        };
        run.levels = slots
            .iter()
            .map(|e| crate::kernels::common::tessgen_bucket_level(e[0], e[1], e[2], e[3]))
            .collect();
        run.edge_levels = slots
            .iter()
            .flat_map(|e| e[..sides].iter().copied())
            .collect();
        run.slots = slots;
        let mut total = 0usize;
        for &l in &run.levels {
            run.offsets.push(total);
            total += (kernels.grid_len)(l) as usize;
        }
        run.offsets.push(total);
        Ok(run)
    }

    /// Faces of the run (one grid each, holes included).
    pub fn faces(&self) -> usize {
        self.levels.len()
    }

    /// Where each face's grid starts in the whole result (`faces + 1`
    /// entries, the last the total): a streaming caller cuts its windows
    /// by these.
    pub fn offsets(&self) -> &[usize] {
        &self.offsets
    }

    /// The grids of `faces` (clamped to the run's faces) into `t`, its
    /// buffers reused when large enough: `levels` and `offsets` of just
    /// those faces (`face_ids` = the range), `edge_levels` of every face
    /// (a hole's edges still decide its neighbours' samples), in parallel
    /// over faces (rayon, as `cpu::evaluate`). Room for the samples is
    /// reserved first: [`crate::cpu::TessError::OutOfMemory`], never an
    /// abort.
    pub fn evaluate(
        &self,
        faces: std::ops::Range<usize>,
        t: &mut AdaptiveTessellation,
    ) -> Result<(), AdaptiveError> {
        use crate::kernels::common::Sample;
        use rayon::prelude::*;
        let faces = crate::cpu::clamp_window(faces, self.faces());
        let base = self.offsets[faces.start];
        let total = self.offsets[faces.end] - base;
        crate::cpu::reserve_samples(&mut t.positions, &mut t.normals, total)?;
        t.positions.resize(total, Vec3::ZERO);
        t.normals.resize(total, Vec3::ZERO);
        t.sides = self.patches.scheme.sides;
        t.levels.clear();
        t.levels.extend_from_slice(&self.levels[faces.clone()]);
        t.offsets.clear();
        t.offsets.extend(
            self.offsets[faces.start..=faces.end]
                .iter()
                .map(|&o| o - base),
        );
        t.edge_levels.clone_from(&self.edge_levels);
        t.face_ids.clear();
        t.face_ids.extend(faces.clone().map(|f| f as u32));
        let (patches, kernels) = (self.patches, self.patches.scheme);
        let ak = kernels.adaptive;
        let inputs = self.kernel_inputs();
        // One disjoint pair of slices per face (grids of different sizes),
        // written in place: no intermediate sample buffer.
        let mut grids: Vec<(usize, &mut [Vec3], &mut [Vec3])> = Vec::with_capacity(faces.len());
        let (mut pos, mut nrm) = (t.positions.as_mut_slice(), t.normals.as_mut_slice());
        for f in faces {
            let len = self.offsets[f + 1] - self.offsets[f];
            let (p, p_tail) = pos.split_at_mut(len);
            let (n, n_tail) = nrm.split_at_mut(len);
            grids.push((f, p, n));
            (pos, nrm) = (p_tail, n_tail);
        }
        grids.into_par_iter().for_each(|(f, pos, nrm)| {
            let (class, l, e) = (patches.face_class[f], self.levels[f], self.slots[f]);
            for (s, (p, n)) in pos.iter_mut().zip(nrm.iter_mut()).enumerate() {
                let s = s as u32;
                let (iu, iv) = ((kernels.grid_iu)(s, l), (kernels.grid_iv)(s, l));
                let r: Sample = match self.displace {
                    None => (ak.eval)(
                        self.control_points(f),
                        class,
                        0,
                        iu,
                        iv,
                        l,
                        e[0],
                        e[1],
                        e[2],
                        e[3],
                    ),
                    Some(_) => (ak.eval_displaced)(
                        &inputs,
                        &patches.control_points,
                        f as u32,
                        class,
                        patches.cp_offsets[f],
                        iu,
                        iv,
                        l,
                        e[0],
                        e[1],
                        e[2],
                        e[3],
                    ),
                };
                (*p, *n) = (r.position, r.normal);
            }
        });
        Ok(())
    }

    fn control_points(&self, f: usize) -> &[Vec3] {
        let p = self.patches;
        &p.control_points[p.cp_offsets[f] as usize..p.cp_offsets[f + 1] as usize]
    }

    /// What the generated adaptive functions read.
    fn kernel_inputs(&self) -> crate::kernels::common::Inputs<'_> {
        crate::kernels::common::Inputs {
            corner_vertex: &self.corner_vertex,
            face_edges: &self.inputs.face_edges,
            edge_factors: &self.inputs.edge_factors,
            adaptive: &self.inputs.params,
            ..crate::cpu::displace_inputs(self.displace.unwrap_or(&self.off))
        }
    }
}

/// The mesh given for the edges must be the one the patches were built
/// from: the scheme's domain, then the face count (the generated functions
/// index `corner_vertex` and `face_edges` by face).
pub(crate) fn check_mesh(
    kernels: &crate::kernels::common::SchemeKernels,
    mesh: &AdaptiveMesh<'_>,
    patches: usize,
) -> Result<(), AdaptiveError> {
    let name = |s: u32| if s == 3 { "triangles" } else { "quads" };
    if mesh.sides() != kernels.sides {
        return Err(AdaptiveError::Domain {
            scheme: kernels.name.into(),
            want: name(kernels.sides),
            got: name(mesh.sides()),
        });
    }
    if mesh.faces() != patches {
        return Err(AdaptiveError::MeshMismatch {
            patches,
            faces: mesh.faces(),
        });
    }
    Ok(())
}
