//! The instanced refinement pattern: one index buffer over the
//! `(N+1) × (N+1)` grid of a patch, shared by every patch instance.
//!
//! The index order is laid out for a FIFO post-transform vertex cache as in
//! the SIGGRAPH 2009 course notes ("prefetch the first row"): the grid is cut
//! into vertical strips narrow enough that two rows of a strip fit in the
//! cache; each strip starts with degenerate triangles that load its first row
//! in order, then emits its cells row by row. Every row is then transformed
//! once per strip, and only the columns shared by two strips twice.

/// Vertex id of grid point `(i, j)` (`u = i/N`, `v = j/N`): `j·(N+1) + i`.
pub fn grid_vertex(level: u32, i: u32, j: u32) -> u32 {
    j * (level + 1) + i
}

/// Triangle list (counter-clockwise in (u, v)) in plain scanline order.
pub fn scanline_indices(level: u32) -> Vec<u32> {
    let mut out = Vec::with_capacity((6 * level * level) as usize);
    for j in 0..level {
        for i in 0..level {
            cell(&mut out, level, i, j);
        }
    }
    out
}

fn cell(out: &mut Vec<u32>, level: u32, i: u32, j: u32) {
    let a = grid_vertex(level, i, j);
    let b = grid_vertex(level, i + 1, j);
    let c = grid_vertex(level, i + 1, j + 1);
    let d = grid_vertex(level, i, j + 1);
    out.extend_from_slice(&[a, b, c, a, c, d]);
}

/// Triangle list ordered for a FIFO vertex cache of `cache_size` entries.
/// Degenerate (zero-area) triangles prefetch each strip's first row.
pub fn cache_friendly_indices(level: u32, cache_size: u32) -> Vec<u32> {
    // Two rows of (width + 1) vertices must fit: 2·(w + 1) ≤ cache.
    let width = (cache_size / 2).saturating_sub(1).max(1);
    let strips = level.div_ceil(width);
    // Equal strip widths keep the duplicated columns to the minimum.
    let mut out = Vec::with_capacity((6 * level * level + 3 * (level + 1) * strips) as usize);
    let mut i0 = 0;
    for s in 0..strips {
        let i1 = (level * (s + 1)).div_ceil(strips).min(level);
        // Prefetch the strip's first row, left to right, as degenerate triangles.
        let row: Vec<u32> = (i0..=i1).map(|i| grid_vertex(level, i, 0)).collect();
        for pair in row.chunks(2) {
            let (x, y) = (pair[0], *pair.get(1).unwrap_or(&pair[0]));
            out.extend_from_slice(&[x, y, y]);
        }
        for j in 0..level {
            for i in i0..i1 {
                cell(&mut out, level, i, j);
            }
        }
        i0 = i1;
    }
    out
}

/// Average transform-to-vertex ratio of `indices` through a FIFO cache:
/// vertex shader invocations divided by distinct vertices.
pub fn fifo_atvr(indices: &[u32], cache_size: usize) -> f64 {
    let mut cache = std::collections::VecDeque::with_capacity(cache_size + 1);
    let mut transforms = 0usize;
    let mut distinct = std::collections::HashSet::new();
    for &v in indices {
        distinct.insert(v);
        if !cache.contains(&v) {
            transforms += 1;
            cache.push_back(v);
            if cache.len() > cache_size {
                cache.pop_front();
            }
        }
    }
    transforms as f64 / distinct.len().max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cells(indices: &[u32]) -> std::collections::BTreeSet<[u32; 3]> {
        indices
            .chunks(3)
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .map(|t| {
                // rotate so the smallest index is first (keeps orientation)
                let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
                [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
            })
            .collect()
    }

    #[test]
    fn cache_order_covers_the_same_triangles() {
        for level in [1, 2, 5, 16, 33, 64] {
            let a = cells(&scanline_indices(level));
            let b = cells(&cache_friendly_indices(level, 20));
            assert_eq!(a, b, "level {level}");
            assert_eq!(a.len() as u32, 2 * level * level);
        }
    }

    #[test]
    fn atvr_16x16_fifo20() {
        let scan = fifo_atvr(&scanline_indices(16), 20);
        let fast = fifo_atvr(&cache_friendly_indices(16, 20), 20);
        println!("16x16 grid, FIFO 20: scanline ATVR {scan:.3}, prefetch-first-row ATVR {fast:.3}");
        assert!(fast <= 1.06, "ATVR {fast}");
        assert!(
            (scan - 1.88).abs() < 0.01,
            "scanline ATVR {scan} (course notes: 1.88)"
        );
    }
}
