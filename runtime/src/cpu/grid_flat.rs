//! The flat interior of a bicubic patch: lanes over the samples of the
//! whole grid in their storage order, not over the columns of a strip.
//!
//! The strip interior ([`super::grid_eval`]) runs every grid row once per
//! strip of 8 (or 16) columns, plus a 4-lane strip for the last columns: at
//! N = 9 the 10 columns take an 8-lane and a 4-lane step per row, 12 lanes
//! (and the issue slots of about 14) for 10 samples. Here a lane group is
//! `L` consecutive samples `s0 .. s0 + L` of the patch's row-major grid,
//! which may run across the end of a row: 100 samples at N = 9 are 13
//! groups of 8, all stores full and contiguous but the last.
//!
//! What each lane needs is the row curves of its column and the weights of
//! its row:
//!
//! * the row curves are computed once per patch for the lanes `j = 0 ..
//!   COLS` with the weights of column `j mod (N + 1)` ([`super::lanes::FlatWeights::
//!   wrap_l`]), so the curves of the columns `c0, c0 + 1, …` wrapped at the
//!   row's end are the `L` consecutive entries from `c0` (the column of the
//!   group's first sample) — a plain load, no gather;
//! * the row weights `l_v`, `r_v` of sample `s` are entry `s` of
//!   [`super::lanes::FlatWeights::row_l`] / `row_r`, made once per evaluation.
//!
//! Each lane then executes the operations of the strip lanes (the
//! generated `ordinary_surface` after its row curves) on the same inputs,
//! so every sample has the same bits; only which lane computes which
//! sample changed. Lanes past the last sample compute sample `(column,
//! N)` again (valid weights, never stored), so a parallel-tangent flag
//! from them is one a stored lane raises too.
//!
//! Grids wider than [`FLAT_MAX_WIDTH`] keep the strips: their rows are
//! long enough that the 4-lane remainder costs little, and the per-sample
//! row weights would grow as `N²`.

use super::lanes::{
    edge_lanes, row_curve_lanes, row_points, sample_curves, sample_lanes_of, store_lanes,
    LevelWeights, SampleHalf, FLAT_MAX_WIDTH, LANES, WRAP,
};
use glam::Vec3;

/// The `EDGE_CURVE` of a bicubic class whose edges are its boundary rows
/// and columns (every built-in quad scheme's ordinary class): the flat
/// interior then writes the border from its own row curves
/// ([`rows_border`]), or leaves it as the interior wrote it when those are
/// the same bits ([`border_is_interior`]).
pub(crate) const ROW_EDGES: [u32; 16] = [0, 4, 8, 12, 12, 13, 14, 15, 15, 11, 7, 3, 3, 2, 1, 0];

/// The flat interior of a bicubic patch `g` at `level` (`COLS ≥`
/// [`wrapped_columns`]`(L, N + 1)`, `COLS` a multiple of `L`), every
/// sample's surface position and normal into `pos` / `nrm`; whether a
/// sample's tangents were parallel.
#[inline(always)]
pub(crate) fn bicubic_flat<const L: usize, const COLS: usize, const V: bool>(
    g: &[Vec3; 16],
    w: &LevelWeights,
    level: u32,
    border: bool,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let width = level as usize + 1;
    debug_assert!(wrapped_columns(L, width) <= COLS && COLS.is_multiple_of(L) && COLS <= WRAP);
    let f = &w.flat;
    // Row curves of the wrapped columns: [row][component] point and
    // tangent, every lane written (a constant trip count, so the arrays
    // need no clearing).
    let mut pt = [[[0.0f32; COLS]; 3]; 4];
    let mut tg = [[[0.0f32; COLS]; 3]; 4];
    // Per lane, the least `bits ^ −0.0` of the row-curve points: 0 only
    // if one of them is −0.0 (see `border_is_interior`).
    let mut zero = [u32::MAX; L];
    let mut j = 0usize;
    while j < COLS {
        let mut lu = [0.0f32; L];
        let mut ru = [0.0f32; L];
        lu.copy_from_slice(&f.wrap_l[j..j + L]);
        ru.copy_from_slice(&f.wrap_r[j..j + L]);
        for r in 0..4 {
            for c in 0..3 {
                let (mut p, mut t) = ([0.0f32; L], [0.0f32; L]);
                row_curve_lanes(row_points(g, r, c), &lu, &ru, &mut p, &mut t);
                for (z, x) in zero.iter_mut().zip(&p) {
                    *z = (*z).min(x.to_bits() ^ NEG_ZERO);
                }
                pt[r][c][j..j + L].copy_from_slice(&p);
                tg[r][c][j..j + L].copy_from_slice(&t);
            }
        }
        j += L;
    }
    let total = width * width;
    let mut degenerate = false;
    // With `V` (the AVX2 and AVX-512 copies) software-pipelined by one
    // group: the curves and cross product of group g + 1 are issued before
    // group g's square root, divisions and stores (`SampleHalf`), so the
    // core has independent multiplies to run while that chain waits.
    // Sample s0 is the group's first; c0 its column.
    let mut pending: Option<(SampleHalf<L>, usize)> = None;
    let (mut s0, mut c0) = (0usize, 0usize);
    while s0 < total {
        let mut lv = [0.0f32; L];
        let mut rv = [0.0f32; L];
        lv.copy_from_slice(&f.row_l[s0..s0 + L]);
        rv.copy_from_slice(&f.row_r[s0..s0 + L]);
        if !V {
            // The SSE2 baseline copy: 16 registers of 4 lanes hold one
            // group's work, not two (pipelined it ran 1.2–1.4× slower).
            let mut out = [[0.0f32; L]; 6];
            degenerate |= sample_lanes_of(&pt, &tg, c0, &lv, &rv, &mut out);
            store_group::<L, V>(&out, s0, total, pos, nrm);
        } else {
            let mut half = SampleHalf::<L>::default();
            sample_curves(&pt, &tg, c0, &lv, &rv, &mut half);
            if let Some((last, at)) = pending.replace((half, s0)) {
                degenerate |= finish::<L, V>(&last, at, total, pos, nrm);
            }
        }
        s0 += L;
        c0 += L;
        while c0 >= width {
            c0 -= width;
        }
    }
    if let Some((last, at)) = pending {
        degenerate |= finish::<L, V>(&last, at, total, pos, nrm);
    }
    if border && !border_is_interior(g, &zero) {
        rows_border::<L, COLS, V>(g, &pt, w, level, pos);
    }
    degenerate
}

/// Whether the interior already wrote the border's bits, so that
/// [`rows_border`] would only write them again.
///
/// Every border sample is one `cubic` whose weights are exactly `(1, 0)`
/// or `(0, 1)` in one direction:
///
/// * row `iv = 0` (`N`): the interior's `cubic(pt[0..4], 1, 0)` (`(0, 1)`)
///   at each column, which is `pt[0]` (`pt[3]`), the border's value;
/// * column `iu = 0` (`N`): the row curves at `(1, 0)` (`(0, 1)`) are
///   `g[r]` (`g[12 + r]`), so the interior's column is `cubic(g[0..4], l_v,
///   r_v)` (`cubic(g[12..16], …)`): the border's very operations.
///
/// `x·1 + y·0` is `x` for finite `x` and `y` except when `x` is `−0.0` and
/// `y·0` is `+0.0` (the sum is then `+0.0`). So the bits agree when every
/// control-point component is finite and small enough that no sum
/// overflows (below 2¹²⁶; a `cubic` point stays within its inputs' range)
/// and neither the control points nor the row-curve points hold a `−0.0`
/// (a row-curve point can underflow to `−0.0` from non-zero inputs, so
/// those are folded in as the row curves are made: `zero`, per lane the
/// least `bits ^ −0.0` of the points).
#[inline(always)]
fn border_is_interior<const L: usize>(g: &[Vec3; 16], zero: &[u32; L]) -> bool {
    // 2^126: the control points' largest magnitude, finite with room.
    const BOUND: u32 = 0x7e80_0000;
    // Integer min / max folds (no early exit), so the loops vectorise.
    let (mut magnitude, mut least) = (0u32, u32::MAX);
    for p in g {
        for x in p.to_array() {
            let b = x.to_bits();
            magnitude = magnitude.max(b & !NEG_ZERO);
            least = least.min(b ^ NEG_ZERO);
        }
    }
    for &z in zero {
        least = least.min(z);
    }
    magnitude < BOUND && least != 0
}

/// The bits of `−0.0`: `x.to_bits() ^ NEG_ZERO` is 0 only for `x = −0.0`.
const NEG_ZERO: u32 = 0x8000_0000;

/// The second half of the group from sample `s0` ([`SampleHalf::finish`])
/// and its stores ([`store_group`]); whether a lane's tangents were
/// parallel. A function, not a closure, so that it is inlined into (and
/// compiled for) the caller's target features.
#[inline(always)]
fn finish<const L: usize, const V: bool>(
    half: &SampleHalf<L>,
    s0: usize,
    total: usize,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let mut out = [[0.0f32; L]; 6];
    let degenerate = half.finish(&mut out);
    store_group::<L, V>(&out, s0, total, pos, nrm);
    degenerate
}

/// The group from sample `s0` (positions `out[0..3]`, normals
/// `out[3..6]`): its first `min(L, total − s0)` lanes stored.
#[inline(always)]
fn store_group<const L: usize, const V: bool>(
    out: &[[f32; L]; 6],
    s0: usize,
    total: usize,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) {
    let m = (total - s0).min(L);
    store_lanes::<L, V>(&out[0], &out[1], &out[2], &mut pos[s0..s0 + m]);
    store_lanes::<L, V>(&out[3], &out[4], &out[5], &mut nrm[s0..s0 + m]);
}

/// The border positions of a bicubic patch whose `EDGE_CURVE` is
/// [`ROW_EDGES`], after the interior wrote the surface everywhere, with the
/// generated `eval`'s bits:
///
/// * edge 0 (`iv = 0`, `t = iu`) is `tessgen_edge(g0, g4, g8, g12, iu)`,
///   the very operations of row curve 0 at column `iu` (`pt[0]`);
/// * edge 2 (`iv = N`, `t = N − iu`) is `tessgen_edge(g15, g11, g7, g3, N
///   − iu)`; its weights are `l_(N−iu) = r_iu` and `r_(N−iu) = l_iu` (the
///   same integers over the same divisor), so each of its products and
///   sums is one of row curve 3's at `iu` with the operands swapped: IEEE
///   `+` and `×` commute, so the bits are `pt[3]`'s;
/// * edges 1 and 3 (`iu = N`, `iu = 0`, rows `1 … N − 1`) likewise are the
///   forward de Casteljau of `g12 … g15` and `g0 … g3` at each row's
///   `l_v`, `r_v`: one lane per row, both columns in one pass;
/// * the four corners are the corner points themselves (the edge
///   evaluator's ends).
///
/// So no curve is evaluated twice and the rows go out as contiguous
/// stores.
#[inline(always)]
fn rows_border<const L: usize, const COLS: usize, const V: bool>(
    g: &[Vec3; 16],
    pt: &[[[f32; COLS]; 3]; 4],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
) {
    let n = level as usize;
    let width = n + 1;
    for (row, curve) in [(0usize, 0usize), (n, 3)] {
        let mut c = 0usize;
        while c < width {
            let m = (width - c).min(L);
            let lanes = |k: usize| {
                let mut v = [0.0f32; L];
                v.copy_from_slice(&pt[curve][k][c..c + L]);
                v
            };
            let base = row * width + c;
            store_lanes::<L, V>(&lanes(0), &lanes(1), &lanes(2), &mut pos[base..base + m]);
            c += L;
        }
    }
    pos[0] = g[0];
    pos[n] = g[12];
    pos[n * width] = g[3];
    pos[n * width + n] = g[15];
    // Rows 1 … N − 1 of columns 0 and N.
    let comps = |k0: usize| {
        [
            [g[k0].x, g[k0 + 1].x, g[k0 + 2].x, g[k0 + 3].x],
            [g[k0].y, g[k0 + 1].y, g[k0 + 2].y, g[k0 + 3].y],
            [g[k0].z, g[k0 + 1].z, g[k0 + 2].z, g[k0 + 3].z],
        ]
    };
    let (first, last) = (comps(0), comps(12));
    let mut iv = 1usize;
    while iv < n {
        let (lv, rv) = (w.l_from::<LANES>(iv), w.r_from::<LANES>(iv));
        let mut a = [[0.0f32; LANES]; 3];
        let mut b = [[0.0f32; LANES]; 3];
        for c in 0..3 {
            edge_lanes(&first[c], &lv, &rv, &mut a[c]);
            edge_lanes(&last[c], &lv, &rv, &mut b[c]);
        }
        let m = (n - iv).min(LANES);
        for k in 0..m {
            let s = (iv + k) * width;
            pos[s] = Vec3::new(a[0][k], a[1][k], a[2][k]);
            pos[s + n] = Vec3::new(b[0][k], b[1][k], b[2][k]);
        }
        iv += LANES;
    }
}

/// Row-curve lanes a flat interior of `width` columns reads with `lanes`
/// lanes: a group starts at sample `s0 = lanes·g`, in column `s0 mod
/// width`, a multiple of `d = gcd(lanes, width)`, so the last column a
/// group starts in is `width − d` and the group reads up to `width − d +
/// lanes` wrapped columns. (At N = 9, 10 columns, groups start in columns
/// 0, 2, …, 8: 16 wrapped columns, not the 17 a start in column 9 would
/// need, so the row curves take two lane groups instead of three.)
pub(crate) const fn wrapped_columns(lanes: usize, width: usize) -> usize {
    let (mut a, mut b) = (lanes, width);
    while b != 0 {
        (a, b) = (b, a % b);
    }
    width - a + lanes
}

/// The flat interior with 8 lanes, its `COLS` chosen from the grid width,
/// and with `border` the border ([`rows_border`]); `None` (nothing
/// written) when the grid is wider than [`FLAT_MAX_WIDTH`].
#[inline(always)]
pub(crate) fn bicubic_flat8<const V: bool>(
    g: &[Vec3; 16],
    w: &LevelWeights,
    level: u32,
    border: bool,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> Option<bool> {
    let width = level as usize + 1;
    if width > FLAT_MAX_WIDTH {
        return None;
    }
    Some(match wrapped_columns(8, width) {
        0..=16 => bicubic_flat::<8, 16, V>(g, w, level, border, pos, nrm),
        17..=24 => bicubic_flat::<8, 24, V>(g, w, level, border, pos, nrm),
        25..=40 => bicubic_flat::<8, 40, V>(g, w, level, border, pos, nrm),
        _ => bicubic_flat::<8, 72, V>(g, w, level, border, pos, nrm),
    })
}

/// The flat interior with 16 lanes (the AVX-512 copy), likewise.
#[inline(always)]
pub(crate) fn bicubic_flat16<const V: bool>(
    g: &[Vec3; 16],
    w: &LevelWeights,
    level: u32,
    border: bool,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> Option<bool> {
    let width = level as usize + 1;
    if width > FLAT_MAX_WIDTH {
        return None;
    }
    Some(match wrapped_columns(16, width) {
        0..=32 => bicubic_flat::<16, 32, V>(g, w, level, border, pos, nrm),
        33..=48 => bicubic_flat::<16, 48, V>(g, w, level, border, pos, nrm),
        _ => bicubic_flat::<16, 80, V>(g, w, level, border, pos, nrm),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every lane group of every flat grid reads inside the wrapped
    /// columns [`wrapped_columns`] counts, and on grids with groups
    /// starting in every reachable column the count is reached (the bound
    /// is the exact one, not a loose one).
    #[test]
    fn wrapped_columns_is_the_furthest_read() {
        for lanes in [8usize, 16] {
            for width in 1..=FLAT_MAX_WIDTH {
                let total = width * width;
                let furthest = (0..total)
                    .step_by(lanes)
                    .map(|s0| s0 % width + lanes)
                    .max()
                    .unwrap_or(0);
                let bound = wrapped_columns(lanes, width);
                assert!(furthest <= bound, "{lanes} lanes, width {width}");
                if total >= lanes * width {
                    assert_eq!(furthest, bound, "{lanes} lanes, width {width}");
                }
            }
        }
    }
}
