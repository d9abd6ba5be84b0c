//! Exact-bit welding: the watertightness check.
//!
//! Tessellated grids are welded by the exact f32 bits of their positions
//! (no tolerance). If shared patch boundaries are bit-identical the result is
//! a closed 2-manifold whose Euler characteristic equals the input's; a single
//! one-ulp difference opens edges.

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

fn key(p: Vec3) -> [u32; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

/// Triangles of one `(level+1)²` grid (local indices), counter-clockwise in (u, v).
pub fn grid_triangles(level: u32) -> Vec<[u32; 3]> {
    let w = level + 1;
    let mut tris = Vec::with_capacity((2 * level * level) as usize);
    for j in 0..level {
        for i in 0..level {
            let a = j * w + i;
            tris.push([a, a + 1, a + w + 1]);
            tris.push([a, a + w + 1, a + w]);
        }
    }
    tris
}

/// Weld by exact position bits and count edge uses.
pub fn weld(t: &Tessellation) -> WeldReport {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let welded: Vec<u32> = t
        .positions
        .iter()
        .map(|p| {
            let n = ids.len() as u32;
            *ids.entry(key(*p)).or_insert(n)
        })
        .collect();
    let tris = grid_triangles(t.level);
    let per = t.grid_len() as u32;
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    let mut triangles = 0;
    let mut degenerate = 0;
    for f in 0..t.faces as u32 {
        for tri in &tris {
            let v = tri.map(|k| welded[(f * per + k) as usize]);
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
