//! Exact-bit welding: the watertightness check.
//!
//! Tessellated grids are welded by the exact f32 bits of their positions
//! (no tolerance). If shared patch boundaries are bit-identical the result is
//! a closed 2-manifold whose Euler characteristic equals the input's; a single
//! one-ulp difference opens edges.
//!
//! The same count works for any per-face sample pattern: [`weld`] for the quad
//! grids of a [`Tessellation`], [`weld_triangles`] for triangle patches
//! (with [`crate::grid::tri_grid_triangles`]) or anything else with a
//! fixed number of samples per face and one local triangle list.

use crate::cpu::Tessellation;
use glam::Vec3;
use std::collections::HashMap;

/// What welding found.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WeldReport {
    pub vertices: usize,
    pub edges: usize,
    pub triangles: usize,
    /// Undirected edges used by exactly one triangle (cracks).
    pub open_edges: usize,
    /// Undirected edges used by more than two triangles.
    pub overused_edges: usize,
    /// Triangles that collapsed (two corners welded together).
    pub degenerate_triangles: usize,
    pub euler: i64,
}

impl WeldReport {
    /// Closed 2-manifold: every edge used exactly twice, nothing collapsed.
    pub fn is_closed_manifold(&self) -> bool {
        self.open_edges == 0 && self.overused_edges == 0 && self.degenerate_triangles == 0
    }
}

impl WeldReport {
    /// Open sample edges beyond `expected` (the true boundary's, from
    /// [`open_base_edges`] × level): cracks. Open edges of a boundary are
    /// always there, so any surplus is a crack, never a compensation.
    pub fn cracks(&self, expected: usize) -> usize {
        self.open_edges.saturating_sub(expected)
    }
}

/// Base half-edges whose edge stays open in a watertight tessellation of
/// `topo`: the mesh boundary's half-edges of faces that emit a grid, and
/// those next to a face that emits nothing (a hole; docs/boundaries.md §5).
/// At a uniform level `N` each contributes exactly `N` open sample edges.
pub fn open_base_halfedges(topo: &crate::mesh::topology::Topology) -> Vec<usize> {
    let emits = |f: u32| !topo.no_limit.get(f as usize).copied().unwrap_or(false);
    (0..topo.twin.len())
        .filter(|&h| {
            let t = topo.twin[h];
            emits(topo.face[h])
                && (t == crate::mesh::topology::NONE || !emits(topo.face[t as usize]))
        })
        .collect()
}

/// The number of [`open_base_halfedges`].
pub fn open_base_edges(topo: &crate::mesh::topology::Topology) -> usize {
    open_base_halfedges(topo).len()
}

fn key(p: Vec3) -> [u32; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

/// Weld a tessellation (quad or triangle patches) by exact position bits and
/// count edge uses.
pub fn weld(t: &Tessellation) -> WeldReport {
    weld_faces(&t.positions, t.faces, t.grid_len(), &t.local_triangles())
}

/// Weld per-face sample patches by exact position bits and count edge uses.
///
/// `positions` holds `per_face` samples per face, face after face; every face
/// is triangulated by the same `local_tris` (indices `< per_face`). For
/// triangle patches at level `N` that is
/// `weld_triangles(&positions, tri_grid_len(N), &tri_grid_triangles(N))`
/// (see [`crate::mesh::trimesh`]).
///
/// # Panics
///
/// If `per_face` is 0 or does not divide `positions.len()`, or a local index
/// is `>= per_face`: these are caller bugs (the pattern does not match the
/// buffer), and a report over misaligned faces would be meaningless.
pub fn weld_triangles(positions: &[Vec3], per_face: usize, local_tris: &[[u32; 3]]) -> WeldReport {
    assert!(
        positions.len().checked_rem(per_face) == Some(0),
        "{} positions are not whole faces of {per_face} samples",
        positions.len()
    );
    assert!(
        local_tris
            .iter()
            .flatten()
            .all(|&k| (k as usize) < per_face),
        "a local triangle index is outside the {per_face} samples of a face"
    );
    weld_faces(positions, positions.len() / per_face, per_face, local_tris)
}

/// The shared core: `faces` faces of `per` samples each, triangulated by `tris`.
fn weld_faces(positions: &[Vec3], faces: usize, per: usize, tris: &[[u32; 3]]) -> WeldReport {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let welded: Vec<u32> = positions
        .iter()
        .map(|p| {
            let n = ids.len() as u32;
            *ids.entry(key(*p)).or_insert(n)
        })
        .collect();
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    let mut triangles = 0;
    let mut degenerate = 0;
    for f in 0..faces {
        for tri in tris {
            let v = tri.map(|k| welded[f * per + k as usize]);
            triangles += 1;
            if v[0] == v[1] || v[1] == v[2] || v[0] == v[2] {
                degenerate += 1;
                continue;
            }
            for e in 0..3 {
                let (a, b) = (v[e], v[(e + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
    }
    let open_edges = edges.values().filter(|&&c| c == 1).count();
    let overused_edges = edges.values().filter(|&&c| c > 2).count();
    let euler = ids.len() as i64 - edges.len() as i64 + (triangles - degenerate) as i64;
    WeldReport {
        vertices: ids.len(),
        edges: edges.len(),
        triangles,
        open_edges,
        overused_edges,
        degenerate_triangles: degenerate,
        euler,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{tri_grid_coords, tri_grid_len, tri_grid_triangles};

    /// Two triangles sharing the edge (1,0,0)-(0,1,0), sampled by integer
    /// barycentrics with only the non-zero terms summed: the shared edge
    /// welds, the square is a disc.
    #[test]
    fn two_triangles_weld_to_a_disc() {
        let corners = [
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
        ];
        for n in 1..6 {
            let mut positions = Vec::new();
            for c in &corners {
                for w in tri_grid_coords(n) {
                    let mut p = Vec3::ZERO;
                    for k in 0..3 {
                        if w[k] != 0 {
                            p += c[k] * (w[k] as f32 / n as f32);
                        }
                    }
                    positions.push(p);
                }
            }
            let r = weld_triangles(&positions, tri_grid_len(n), &tri_grid_triangles(n));
            assert_eq!(r.open_edges as u32, 4 * n, "level {n}");
            assert_eq!(r.overused_edges, 0);
            assert_eq!(r.euler, 1);
            assert_eq!(r.triangles as u32, 2 * n * n);
        }
    }

    #[test]
    #[should_panic(expected = "not whole faces")]
    fn misaligned_buffer_panics() {
        weld_triangles(&[Vec3::ZERO; 4], 3, &[[0, 1, 2]]);
    }
}
