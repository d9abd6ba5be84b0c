//! The sample grids of one patch, as the generated code lays them out:
//! a quad patch's `(N+1)²` samples row by row (`s = iv·(N+1) + iu`), a
//! triangle's `(N+1)(N+2)/2` samples in rows `iv = 0 ..= N` of `N + 1 − iv`
//! samples (codegen's `grid_len` / `grid_iu` / `grid_iv` / `grid_index`,
//! printed into every scheme). The tessellators, the welder and the OBJ
//! writer all index samples through these, so they live below all three.

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

/// Number of samples of one triangle at `level` N: `(N+1)(N+2)/2`.
///
/// Level 0 is degenerate (one sample with barycentrics `(0, 0, 0)`, no triangles); the
/// tessellators use levels `1..=`[`crate::cpu::MAX_LEVEL`].
pub fn tri_grid_len(level: u32) -> usize {
    let n = level as usize;
    (n + 1) * (n + 2) / 2
}

/// Local index of sample `(i, j)` (`i + j ≤ level`) in the row-by-row order: rows `0..j` hold
/// `Σ_{r<j} (N + 1 − r)` samples. Panics (in debug builds) if `i + j > level`.
pub fn tri_grid_index(level: u32, i: u32, j: u32) -> u32 {
    debug_assert!(i + j <= level, "sample ({i}, {j}) outside level {level}");
    let (n, i, j) = (u64::from(level), u64::from(i), u64::from(j));
    (j * (n + 1) - j * j.saturating_sub(1) / 2 + i) as u32
}

/// Integer barycentrics `(a, b, c) = (N − i − j, i, j)` of every sample, in index order; corner
/// `k`'s weight is the `k`-th entry over `N` (see [`crate::mesh::trimesh`] for why this convention).
///
/// Panics if the level is so large that local indices would not fit `u32`.
pub fn tri_grid_coords(level: u32) -> Vec<[u32; 3]> {
    assert_fits(level);
    let mut coords = Vec::with_capacity(tri_grid_len(level));
    for j in 0..=level {
        for i in 0..=level - j {
            coords.push([level - i - j, i, j]);
        }
    }
    coords
}

/// The `N²` triangles of the sample grid (local indices), counter-clockwise in the same sense
/// as the corner order 0 → 1 → 2, so a tessellated triangle keeps its facet's orientation and
/// the welded result of a consistently oriented mesh is consistently oriented. Per cell, row by
/// row: the upward triangle `[(i,j), (i+1,j), (i,j+1)]`, then (where it exists) the downward
/// one `[(i+1,j), (i+1,j+1), (i,j+1)]`.
///
/// Panics if the level is so large that local indices would not fit `u32`.
pub fn tri_grid_triangles(level: u32) -> Vec<[u32; 3]> {
    assert_fits(level);
    let idx = |i, j| tri_grid_index(level, i, j);
    let mut tris = Vec::with_capacity(level as usize * level as usize);
    for j in 0..level {
        let row = level - j;
        for i in 0..row {
            tris.push([idx(i, j), idx(i + 1, j), idx(i, j + 1)]);
            if i + 1 < row {
                tris.push([idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]);
            }
        }
    }
    tris
}

/// The `N + 1` samples on edge `edge` (0, 1 or 2), from corner `edge` to corner `edge + 1
/// (mod 3)`: the samples where the weight of corner `edge + 2 (mod 3)` is zero, in order of
/// decreasing weight of corner `edge`. The neighbour across the edge sees the same samples in
/// reverse order. Panics if `edge > 2`.
pub fn tri_grid_edge(level: u32, edge: usize) -> Vec<u32> {
    assert_fits(level);
    let n = level;
    let idx = |i, j| tri_grid_index(n, i, j);
    match edge {
        0 => (0..=n).map(|t| idx(t, 0)).collect(),
        1 => (0..=n).map(|t| idx(n - t, t)).collect(),
        2 => (0..=n).map(|t| idx(0, n - t)).collect(),
        _ => panic!("a triangle has edges 0, 1 and 2, not {edge}"),
    }
}

fn assert_fits(level: u32) {
    assert!(
        (tri_grid_len(level) as u64) < u64::from(u32::MAX),
        "triangle level {level} is too large for u32 sample indices"
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::trimesh::edge_uses;
    use std::collections::HashMap;

    #[test]
    fn grid_counts_and_coords() {
        for n in 0..12 {
            let coords = tri_grid_coords(n);
            assert_eq!(coords.len(), tri_grid_len(n));
            assert_eq!(tri_grid_triangles(n).len(), (n * n) as usize);
            let mut k = 0;
            for j in 0..=n {
                for i in 0..=n - j {
                    assert_eq!(tri_grid_index(n, i, j), k);
                    assert_eq!(coords[k as usize], [n - i - j, i, j]);
                    k += 1;
                }
            }
        }
        assert_eq!(tri_grid_coords(1), vec![[1, 0, 0], [0, 1, 0], [0, 0, 1]]);
        assert_eq!(tri_grid_triangles(1), vec![[0, 1, 2]]);
    }

    #[test]
    fn grid_triangles_are_ccw_and_edge_manifold() {
        for n in 1..12 {
            let coords = tri_grid_coords(n);
            // Corner k at the k-th unit vector of the plane z = 0 with corners
            // (0,0), (1,0), (0,1): barycentric (a,b,c) ↦ (b, c).
            let xy = |k: u32| {
                let [_, b, c] = coords[k as usize];
                (i64::from(b), i64::from(c))
            };
            let tris = tri_grid_triangles(n);
            let mut directed = HashMap::new();
            for t in &tris {
                let [(x0, y0), (x1, y1), (x2, y2)] = t.map(xy);
                assert_eq!(
                    (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0),
                    1,
                    "ccw, unit"
                );
                for e in 0..3 {
                    *directed.entry((t[e], t[(e + 1) % 3])).or_insert(0) += 1;
                }
            }
            assert!(directed.values().all(|&c| c == 1), "orientation");
            let uses = edge_uses(&tris);
            assert!(uses.values().all(|&c| c == 1 || c == 2));
            let boundary: Vec<_> = uses.iter().filter(|(_, &c)| c == 1).collect();
            assert_eq!(boundary.len() as u32, 3 * n);
            // Every boundary edge lies on one of the three sides.
            for (&(a, b), _) in boundary {
                let (ca, cb) = (coords[a as usize], coords[b as usize]);
                assert!((0..3).any(|k| ca[k] == 0 && cb[k] == 0));
            }
            // Euler characteristic of a disc.
            let v = tri_grid_len(n) as i64;
            assert_eq!(v - uses.len() as i64 + tris.len() as i64, 1);
        }
    }

    #[test]
    fn grid_edges_run_corner_to_corner() {
        for n in 1..12 {
            let coords = tri_grid_coords(n);
            for k in 0..3 {
                let edge = tri_grid_edge(n, k);
                assert_eq!(edge.len() as u32, n + 1);
                for (t, &s) in edge.iter().enumerate() {
                    let c = coords[s as usize];
                    let t = t as u32;
                    assert_eq!(c[k], n - t, "corner {k} weight decreases");
                    assert_eq!(c[(k + 1) % 3], t, "corner {} weight grows", (k + 1) % 3);
                    assert_eq!(c[(k + 2) % 3], 0, "opposite corner absent");
                }
            }
            // Corners: edge k starts where edge k-1 ends.
            for k in 0..3 {
                assert_eq!(
                    tri_grid_edge(n, k)[0],
                    *tri_grid_edge(n, (k + 2) % 3).last().unwrap()
                );
            }
        }
    }
}
