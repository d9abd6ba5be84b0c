//! The flat vertex stage: the generated smooth-vertex path (DESIGN.md
//! Rule 1: every output row the sum over ring slots `0..2n` in ring order of
//! table weight × point, zero weights skipped) with its per-valence work
//! done once per topology instead of once per vertex per deformation.
//!
//! The generated `vertex_stage` reads, for every vertex and row, all
//! `2n + 1` table weights of that row, tests each against zero and fetches
//! the point through the ring for each non-zero one. Here the non-zero
//! weights of each valence's rows are listed once ([`FlatVertexStage::new`],
//! in slot order, from the same table cells), and per vertex the `2n + 1`
//! ring points are fetched once; each row then executes exactly the
//! generated additions `acc = acc + p_k · w_k` in the same order, so the
//! outputs are bit-identical (tests/tests/grid_path.rs). Crease and corner
//! vertices (a non-empty sector range) keep the generated kernel.

use crate::kernels::common::{SchemeKernels, TABLE_WIDTH};
use crate::mesh::topology::Topology;
use glam::{Vec3, Vec3A};

/// Largest ring of a smooth vertex: `2·MAX_VALENCE + 1` slots.
const MAX_SLOTS: usize = 2 * crate::kernels::common::MAX_VALENCE as usize + 1;

/// One non-zero term of a row: ring slot and table weight.
#[derive(Clone, Copy, Debug)]
struct Term {
    slot: u32,
    weight: f32,
}

/// Sparse per-valence rows of one scheme's smooth vertex stage.
#[derive(Clone, Debug, Default)]
pub(crate) struct FlatVertexStage {
    /// Per valence `n`: range of its rows in `rows` (empty if no smooth
    /// vertex of this valence exists).
    valence_rows: Vec<(u32, u32)>,
    /// Per row: range of its terms in `terms`.
    rows: Vec<(u32, u32)>,
    terms: Vec<Term>,
}

impl FlatVertexStage {
    /// The rows of every valence a smooth vertex of `topo` has, read from
    /// `table` where the generated kernel reads them.
    pub(crate) fn new(topo: &Topology, scheme: &SchemeKernels, table: &[f32]) -> Self {
        let mut flat = FlatVertexStage::default();
        let max_n = topo.valence.iter().copied().max().unwrap_or(0) as usize;
        flat.valence_rows = vec![(0, 0); max_n + 1];
        let mut needed = vec![false; max_n + 1];
        for (v, &n) in topo.valence.iter().enumerate() {
            if n > 0 && smooth(topo, v) {
                needed[n as usize] = true;
            }
        }
        for (n, _) in needed.iter().enumerate().filter(|(_, &x)| x) {
            let Some(&row_base) = scheme.row_base.get(n) else {
                continue;
            };
            let n32 = n as u32;
            let rows = scheme.rows_per_n * n32 + scheme.rows_fixed;
            let first = flat.rows.len() as u32;
            for r in 0..rows {
                let start = flat.terms.len() as u32;
                for k in 0..2 * n32 + 1 {
                    let cell = ((row_base + r) * TABLE_WIDTH + k) as usize;
                    let w = table.get(cell).copied().unwrap_or(0.0);
                    if w != 0.0f32 {
                        flat.terms.push(Term { slot: k, weight: w });
                    }
                }
                flat.rows.push((start, flat.terms.len() as u32));
            }
            flat.valence_rows[n] = (first, flat.rows.len() as u32);
        }
        flat
    }

    /// Whether vertex `v` takes the flat path (smooth, with its valence's
    /// rows listed).
    pub(crate) fn covers(&self, topo: &Topology, v: usize) -> bool {
        let n = topo.valence[v] as usize;
        smooth(topo, v)
            && 2 * n < MAX_SLOTS
            && self.valence_rows.get(n).is_some_and(|&(a, b)| b > a)
    }

    /// Vertex `v`'s outputs into `out` (its `rows_per_n·n + rows_fixed`
    /// points), from `positions`. Only for a vertex [`Self::covers`].
    #[inline]
    pub(crate) fn vertex(&self, topo: &Topology, positions: &[Vec3], v: usize, out: &mut [Vec3]) {
        let n = topo.valence[v] as usize;
        let ring_base = topo.ring_offsets[v] as usize;
        let slots = 2 * n + 1;
        // `Vec3A` (one SSE register) does the generated `Vec3` sum's three
        // component operations at once: the same IEEE `×` and `+` per
        // component, the fourth lane unused.
        let mut p = [Vec3A::ZERO; MAX_SLOTS];
        for (pk, &i) in p[..slots]
            .iter_mut()
            .zip(&topo.ring[ring_base..ring_base + slots])
        {
            *pk = Vec3A::from(positions[i as usize]);
        }
        let (first, last) = self.valence_rows[n];
        let rows = &self.rows[first as usize..last as usize];
        for (o, &(a, b)) in out.iter_mut().zip(rows) {
            let mut acc = Vec3A::new(0.0f32, 0.0f32, 0.0f32);
            for t in &self.terms[a as usize..b as usize] {
                acc += p[t.slot as usize] * t.weight;
            }
            *o = Vec3::from(acc);
        }
    }
}

/// A vertex without sectors (the generated kernel's smooth branch).
fn smooth(topo: &Topology, v: usize) -> bool {
    topo.vertex_sectors.get(v) == topo.vertex_sectors.get(v + 1)
}
