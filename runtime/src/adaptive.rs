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

use crate::topology::Topology;
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
            Partitioning::FractionalOdd => Some("TESSGEN_FRACTIONAL_ODD"),
            Partitioning::FractionalEven => Some("TESSGEN_FRACTIONAL_EVEN"),
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
        let mut d = vec!["TESSGEN_ADAPTIVE".to_string()];
        match self.metric {
            Metric::Buffer(_) | Metric::PerFaceEdge(_) => d.push("TESSGEN_METRIC_BUFFER".into()),
            Metric::Distance { .. } => d.push("TESSGEN_METRIC_DISTANCE".into()),
            Metric::Screen { .. } => {}
        }
        if let Some(p) = self.partitioning.define() {
            d.push(p.into());
        }
        d
    }

    /// The `adaptive` buffer (binding 19): 25 f32, layout `abi::ADAPTIVE`.
    pub fn params(&self) -> Vec<f32> {
        let mut a = vec![0.0f32; ADAPTIVE_LEN];
        match &self.metric {
            Metric::Screen {
                view_proj,
                viewport,
                pixels_per_segment,
            } => {
                a[..16].copy_from_slice(&view_proj.to_cols_array());
                a[20] = viewport[0];
                a[21] = viewport[1];
                a[22] = *pixels_per_segment;
            }
            Metric::Distance { eye, scale } => {
                a[16..19].copy_from_slice(&eye.to_array());
                a[19] = *scale;
            }
            Metric::Buffer(_) | Metric::PerFaceEdge(_) => {}
        }
        a[23] = self.min;
        a[24] = self.max;
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

/// Floats in the `adaptive` buffer (`abi::ADAPTIVE_LEN`).
pub const ADAPTIVE_LEN: usize = 25;

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

// ---- CPU: power-of-two buckets with snapped transitions ----

/// Errors of the CPU adaptive tessellator.
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
}

/// The power-of-two level of an edge: the smallest `2^k ≥ factor`, clamped
/// to `1..=max_level` (a power of two). A function of the factor alone, so
/// of the edge alone.
pub fn edge_level(factor: f32, max_level: u32) -> u32 {
    let mut l = 1u32;
    while (l as f32) < factor && l < max_level {
        l *= 2;
    }
    l
}

/// A tessellation with one power-of-two level per patch (its *bucket*: the
/// largest level of its four edges) and one level per edge.
///
/// Face `f` is an `(levels[f] + 1)²` grid in the usual order (`iv·(L+1) + iu`)
/// from `offsets[f]`. Its interior samples are at `(iu, iv)/L`; a boundary
/// sample `i` of edge `k`, whose own level is `L_e = edge_levels[4f + k] ≤ L`,
/// is *snapped* to the edge's coarser point `⌊i / (L / L_e)⌋` and evaluated
/// there through the shared edge evaluator at level `L_e` — exactly the
/// points the neighbour produces for that edge, whatever its bucket. Fine
/// boundary triangles whose two boundary corners snapped to one point are
/// degenerate (skipped by the weld); the rest stitch the levels without
/// T-junctions. On a GPU each bucket is one instanced draw of its level's
/// grid.
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveTessellation {
    pub levels: Vec<u32>,
    pub edge_levels: Vec<u32>,
    pub offsets: Vec<usize>,
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
}

impl AdaptiveTessellation {
    /// Every face's grid triangles as world positions (a triangle soup for
    /// [`crate::weld::weld_triangles`] or OBJ output).
    pub fn triangles(&self) -> Vec<[Vec3; 3]> {
        let mut out = Vec::new();
        for (f, &l) in self.levels.iter().enumerate() {
            let base = self.offsets[f];
            for t in crate::weld::grid_triangles(l) {
                out.push(t.map(|k| self.positions[base + k as usize]));
            }
        }
        out
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

/// The grid point `(iu, iv)` of a face at bucket level `level`, with its
/// boundary samples snapped to the edges' own levels: `(iu', iv', level')`
/// to evaluate. Edge k is `v = 0, u = 1, v = 1, u = 0` for k = 0..3.
pub fn snap(iu: u32, iv: u32, level: u32, edge_levels: [u32; 4]) -> (u32, u32, u32) {
    let s = |k: usize| level / edge_levels[k];
    if iv == 0 {
        let le = edge_levels[0];
        (iu / s(0), 0, le)
    } else if iu == level {
        let le = edge_levels[1];
        (le, iv / s(1), le)
    } else if iv == level {
        let le = edge_levels[2];
        (iu / s(2), le, le)
    } else if iu == 0 {
        let le = edge_levels[3];
        (0, iv / s(3), le)
    } else {
        (iu, iv, level)
    }
}

/// CPU adaptive tessellation of constructed quad patches: `factors` per
/// global edge id ([`edge_ids`]), each edge's level [`edge_level`], each
/// patch's bucket the largest of its edges, boundary samples [`snap`]ped.
pub fn evaluate_cpu(
    patches: &crate::cpu::Patches,
    topo: &Topology,
    factors: &[f32],
    max_level: u32,
) -> Result<AdaptiveTessellation, AdaptiveError> {
    let kernels = patches.scheme;
    if kernels.sides != 4 {
        return Err(crate::cpu::facet_error(kernels).into());
    }
    if !max_level.is_power_of_two() || max_level > crate::cpu::MAX_LEVEL {
        return Err(AdaptiveError::MaxLevel { got: max_level });
    }
    let (ids, edges) = edge_ids(topo);
    if factors.len() != edges as usize {
        return Err(AdaptiveError::EdgeFactorCount {
            expected: edges as usize,
            got: factors.len(),
        });
    }
    if let Some((edge, &factor)) = factors.iter().enumerate().find(|(_, f)| !f.is_finite()) {
        return Err(AdaptiveError::BadFactor { edge, factor });
    }
    let faces = patches.face_class.len();
    let edge_levels: Vec<u32> = ids
        .iter()
        .map(|&e| edge_level(factors[e as usize], max_level))
        .collect();
    let levels: Vec<u32> = (0..faces)
        .map(|f| {
            edge_levels[4 * f..4 * f + 4]
                .iter()
                .copied()
                .max()
                .unwrap_or(1)
        })
        .collect();
    let mut offsets = Vec::with_capacity(faces + 1);
    let mut total = 0usize;
    for &l in &levels {
        offsets.push(total);
        total += ((l + 1) * (l + 1)) as usize;
    }
    offsets.push(total);
    let mut positions = vec![Vec3::ZERO; total];
    let mut normals = vec![Vec3::ZERO; total];
    for f in 0..faces {
        let cp = &patches.control_points
            [patches.cp_offsets[f] as usize..patches.cp_offsets[f + 1] as usize];
        let class = patches.face_class[f];
        let l = levels[f];
        let el = [0, 1, 2, 3].map(|k| edge_levels[4 * f + k]);
        for s in 0..(l + 1) * (l + 1) {
            let (iu, iv) = ((kernels.grid_iu)(s, l), (kernels.grid_iv)(s, l));
            let (u, v, lv) = snap(iu, iv, l, el);
            let r = (kernels.eval)(cp, class, 0, u, v, lv);
            positions[offsets[f] + s as usize] = r.position;
            normals[offsets[f] + s as usize] = r.normal;
        }
    }
    Ok(AdaptiveTessellation {
        levels,
        edge_levels,
        offsets,
        positions,
        normals,
    })
}
