//! The grid path of the `acc` form (ACC's extraordinary class, acc.md §5):
//! a bicubic geometry patch (points 0..16) for the position, and the
//! normal from two tangent patches, `U` quadratic in u × cubic in v and `V`
//! cubic in u × quadratic in v (points 16..40, each corner's coefficients
//! in its own frame, signs mapped back as the generated code maps them).
//!
//! What is invariant where, for the generated `extraordinary_surface`:
//! the four geometry row curves and `U`'s four u-quadratics depend on the
//! column only, `V`'s four v-quadratics on the row only. So per strip of
//! columns the row curves and the `U` rows are computed once, per grid row
//! the `V` columns once (the generated `Vec3` operations), and each
//! sample then runs, lane by lane, the remaining de Casteljau steps in the
//! generated order: `along_v = cubic(row points, lv, rv)`, `tangent_u =
//! cubic(U rows, lv, rv)`, `tangent_v = cubic(V columns, lu, ru)`, normal
//! `tessgen_patch_normal(tangent_u, tangent_v)`. Border positions come from
//! the shared edge evaluator ([`super::lanes::quad_border`]).
//!
//! `tests/tests/grid_path.rs` checks this against the per-sample path bit
//! for bit (the cube: every face extraordinary; levels 1–64).

use super::lanes::{
    cubic_point, patch_normal, quad_border, row_curve_lanes, store_lanes, strips, LevelWeights,
    HALF, LANES,
};
use glam::Vec3;

/// `U`'s u-quadratics: row `k` is `(a·lu + b·ru)·lu + (b·lu + c·ru)·ru`
/// with points `(a, b, c)`; a `true` flag negates the stored point (the
/// generated `-cp[..]`).
const U_ROWS: [[(usize, bool); 3]; 4] = [
    [(16, false), (18, false), (26, true)],
    [(17, false), (19, false), (27, true)],
    [(39, false), (31, true), (29, true)],
    [(38, false), (30, true), (28, true)],
];

/// `V`'s v-quadratics, column `k`, spelled like [`U_ROWS`] with `lv, rv`.
const V_COLS: [[(usize, bool); 3]; 4] = [
    [(20, false), (36, true), (34, true)],
    [(21, false), (37, true), (35, true)],
    [(23, false), (25, false), (33, true)],
    [(22, false), (24, false), (32, true)],
];

/// Point `(i, negate)` of the patch, as the generated code reads it.
#[inline(always)]
fn point(cp: &[Vec3; 40], (i, negate): (usize, bool)) -> Vec3 {
    if negate {
        -cp[i]
    } else {
        cp[i]
    }
}

/// An `acc` patch's grid: the surface everywhere, then the border
/// positions. Whether a sample's tangents were parallel (the generated
/// `eval` then takes that normal from a nudge inside: the caller redoes the
/// patch per sample).
#[inline(always)]
pub(crate) fn acc_patch<const V: bool>(
    cp: &[Vec3; 40],
    curve: &[u32; 16],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let width = level as usize + 1;
    let mut degenerate = false;
    for (c0, narrow) in strips(width) {
        degenerate |= if narrow {
            acc_strip::<HALF, V>(cp, w, level, c0, pos, nrm)
        } else {
            acc_strip::<LANES, V>(cp, w, level, c0, pos, nrm)
        };
    }
    quad_border::<V, 40>(cp, curve, w, level, pos);
    degenerate
}

/// Columns `c0 .. c0 + L` (clamped to the grid) of an `acc` patch's grid.
#[inline(always)]
fn acc_strip<const L: usize, const V: bool>(
    cp: &[Vec3; 40],
    w: &LevelWeights,
    level: u32,
    c0: usize,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let width = level as usize + 1;
    // Padded lanes repeat column N.
    let (lu, ru) = (w.l_from::<L>(c0), w.r_from::<L>(c0));
    // Geometry row curves (points only: the position is all they give)
    // and U's rows, per [row][component].
    let mut pt = [[[0.0f32; L]; 3]; 4];
    let mut urow = [[[0.0f32; L]; 3]; 4];
    for r in 0..4 {
        let b = [cp[r], cp[4 + r], cp[8 + r], cp[12 + r]];
        let q = U_ROWS[r].map(|p| point(cp, p));
        for c in 0..3 {
            let comp = |v: &[Vec3]| -> [f32; 4] {
                let mut o = [0.0f32; 4];
                for (o, p) in o.iter_mut().zip(v) {
                    *o = p.to_array()[c];
                }
                o
            };
            let mut tangent = [0.0f32; L];
            row_curve_lanes(comp(&b), &lu, &ru, &mut pt[r][c], &mut tangent);
            let [a, bb, cc, _] = comp(&q);
            for k in 0..L {
                let (l, rr) = (lu[k], ru[k]);
                let q0 = (a * l) + (bb * rr);
                let q1 = (bb * l) + (cc * rr);
                urow[r][c][k] = (q0 * l) + (q1 * rr);
            }
        }
    }
    let m = (width - c0).min(L);
    let mut degenerate = false;
    for iv in 0..width {
        let (lv, rv) = (w.l[iv], w.r[iv]);
        // V's columns of this row, as the generated `vcolK`.
        let vcol: [Vec3; 4] = std::array::from_fn(|k| {
            let [a, b, c] = V_COLS[k].map(|p| point(cp, p));
            let q0 = (a * lv) + (b * rv);
            let q1 = (b * lv) + (c * rv);
            (q0 * lv) + (q1 * rv)
        });
        let mut out = [[0.0f32; L]; 6];
        for k in 0..L {
            let (l, r) = (lu[k], ru[k]);
            let along = |a: &[[[f32; L]; 3]; 4], c: usize, l: f32, r: f32| {
                cubic_point(a[0][c][k], a[1][c][k], a[2][c][k], a[3][c][k], l, r)
            };
            let across = |c: usize| {
                let v = |i: usize| vcol[i].to_array()[c];
                cubic_point(v(0), v(1), v(2), v(3), l, r)
            };
            let tu = [
                along(&urow, 0, lv, rv),
                along(&urow, 1, lv, rv),
                along(&urow, 2, lv, rv),
            ];
            let tv = [across(0), across(1), across(2)];
            let (n, parallel) = patch_normal(tu, tv);
            degenerate |= parallel;
            out[0][k] = along(&pt, 0, lv, rv);
            out[1][k] = along(&pt, 1, lv, rv);
            out[2][k] = along(&pt, 2, lv, rv);
            (out[3][k], out[4][k], out[5][k]) = (n[0], n[1], n[2]);
        }
        let base = iv * width + c0;
        store_lanes::<L, V>(&out[0], &out[1], &out[2], &mut pos[base..base + m]);
        store_lanes::<L, V>(&out[3], &out[4], &out[5], &mut nrm[base..base + m]);
    }
    degenerate
}
