//! Refined vertices as flat stencils over the base vertices.
//!
//! Every refined vertex is one row `Σ_k w_k · P[i_k]` over the *base* mesh
//! (the levels are composed in f64 when the table is built), so an animated
//! mesh refines with one pass over the table, on the CPU or on a GPU, and
//! every backend gets the same bits as long as it sums in the table's order
//! with one rounded multiply and one rounded add per term (no fused
//! multiply-add): row order, then ascending base vertex.

/// Rows of `(base vertex, weight)` in one flat layout (OpenSubdiv's `Far`
/// stencil tables have the same shape): row `r` uses
/// `indices[offsets[r]..offsets[r + 1]]` and the same range of `weights`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StencilTable {
    /// `rows + 1` offsets into `indices` / `weights`.
    pub offsets: Vec<u32>,
    /// Base vertex of each term, ascending within a row.
    pub indices: Vec<u32>,
    /// Weight of each term (f64 composition rounded once to f32).
    pub weights: Vec<f32>,
}

impl StencilTable {
    /// Number of refined vertices.
    pub fn rows(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Terms of row `r`.
    pub fn row(&self, r: usize) -> impl Iterator<Item = (u32, f32)> + '_ {
        let (a, b) = (self.offsets[r] as usize, self.offsets[r + 1] as usize);
        self.indices[a..b]
            .iter()
            .copied()
            .zip(self.weights[a..b].iter().copied())
    }

    /// Builds the table from f64 rows (already in base terms, sorted).
    pub(super) fn from_rows(rows: &[Vec<(u32, f64)>]) -> StencilTable {
        let mut t = StencilTable {
            offsets: Vec::with_capacity(rows.len() + 1),
            ..StencilTable::default()
        };
        t.offsets.push(0);
        for row in rows {
            for &(i, w) in row {
                t.indices.push(i);
                t.weights.push(w as f32);
            }
            t.offsets.push(t.indices.len() as u32);
        }
        t
    }

    /// The refined positions of `base` (one per row), in the reference order
    /// every backend reproduces, the vertex stage's summation
    /// (DESIGN.md Rule 1): `acc = 0`, then `acc = acc + pₖ·wₖ` per term.
    pub fn apply(&self, base: &[[f32; 3]]) -> Vec<[f32; 3]> {
        let mut out = vec![[0.0f32; 3]; self.rows()];
        self.apply_into(base, &mut out);
        out
    }

    /// [`StencilTable::apply`] into the caller's buffer (`out.len() == rows`);
    /// a base index out of range of `base` reads 0.
    pub fn apply_into(&self, base: &[[f32; 3]], out: &mut [[f32; 3]]) {
        for (r, o) in out.iter_mut().enumerate().take(self.rows()) {
            let mut acc = [0.0f32; 3];
            for (i, w) in self.row(r) {
                let p = base.get(i as usize).copied().unwrap_or([0.0; 3]);
                acc = [acc[0] + p[0] * w, acc[1] + p[1] * w, acc[2] + p[2] * w];
            }
            *o = acc;
        }
    }

    /// Largest number of terms in a row.
    pub fn max_row_len(&self) -> usize {
        self.offsets
            .windows(2)
            .map(|w| (w[1] - w[0]) as usize)
            .max()
            .unwrap_or(0)
    }
}

/// Composes `child` rows (over the parent level's vertices) with `parent`
/// rows (over the base): the child rows over the base, sorted, exact zeros
/// dropped. `scratch` is a dense accumulator the size of the base.
pub(super) fn compose(
    child: &[Vec<(u32, f64)>],
    parent: &[Vec<(u32, f64)>],
    base_vertices: usize,
) -> Vec<Vec<(u32, f64)>> {
    let mut dense = vec![0.0f64; base_vertices];
    let mut touched: Vec<u32> = Vec::new();
    child
        .iter()
        .map(|row| {
            for &(p, w) in row {
                for &(b, wb) in &parent[p as usize] {
                    if dense[b as usize] == 0.0 {
                        touched.push(b);
                    }
                    dense[b as usize] += w * wb;
                }
            }
            touched.sort_unstable();
            touched.dedup();
            let out = touched
                .iter()
                .filter(|&&b| dense[b as usize] != 0.0)
                .map(|&b| (b, dense[b as usize]))
                .collect();
            for &b in &touched {
                dense[b as usize] = 0.0;
            }
            touched.clear();
            out
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apply_sums_in_row_order() {
        let rows = vec![vec![(0, 0.5), (1, 0.5)], vec![(1, 1.0)]];
        let t = StencilTable::from_rows(&rows);
        assert_eq!(t.rows(), 2);
        let out = t.apply(&[[0.0, 2.0, 4.0], [2.0, 4.0, 8.0]]);
        assert_eq!(out, vec![[1.0, 3.0, 6.0], [2.0, 4.0, 8.0]]);
        assert_eq!(t.max_row_len(), 2);
    }

    #[test]
    fn compose_multiplies_and_merges() {
        let parent = vec![vec![(0, 1.0)], vec![(0, 0.5), (2, 0.5)]];
        let child = vec![vec![(0, 0.5), (1, 0.5)]];
        let c = compose(&child, &parent, 3);
        assert_eq!(c, vec![vec![(0, 0.75), (2, 0.25)]]);
    }
}
