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
