//! The grid path of the `gregory4` form (both classes of `g1cc`): a
//! biquartic Bézier net whose four twist points are rational blends of two
//! points each, plus the derivative terms of that blend in the tangents —
//! [`super::grid_gregory`] on a 5×5 net.
//!
//! What is invariant where, for the generated `*_surface` of the form: the
//! net's rows 0, 2 and 4 (v-index) hold no twist point, so their quartic
//! curves along u depend on the column only; rows 1 and 3 hold the four
//! blends, whose weights depend on `(iu, iv)`. Per strip of columns the
//! three fixed row curves and the u-factors of the blends' Bernstein
//! weights are computed once; per sample, lane by lane and in the generated
//! order, the blends, rows 1 and 3, the de Casteljau steps along v, and
//! `du`, `dv` with their four blend terms. Border positions come from the
//! quartic shared edge evaluator `tessgen_edge4` ([`quad_border4`]).
//!
//! `tests/tests/grid_path.rs` checks this against the per-sample path bit
//! for bit.

use super::grid_gregory::{twist_blends, TwistBlends, TwistColumns, TwistRow};
use super::lanes::{patch_normal, store_lanes, strips, LevelWeights, HALF, LANES};
use glam::Vec3;

/// Per corner `k`: the storage indices of its twist pair `(fp, fm)`
/// (`7k + 4`, `7k + 5`).
const TWIST: [(usize, usize); 4] = [(4, 5), (11, 12), (18, 19), (25, 26)];

/// The net's rows without a twist point, `a = 0..=4` along u (storage
/// indices, the generated `*_surface`'s `row0`, `row2`, `row4`).
const ROW0: [usize; 5] = [0, 1, 3, 9, 7];
const ROW2: [usize; 5] = [24, 27, 28, 13, 10];
const ROW4: [usize; 5] = [21, 23, 17, 15, 14];
/// Rows 1 and 3: the points at `a = 0, 2, 4`; `a = 1, 3` are the blends of
/// corners 0, 1 (row 1) and 3, 2 (row 3).
const ROW1: [usize; 3] = [2, 6, 8];
const ROW3: [usize; 3] = [22, 20, 16];

/// `tessgen_quartic(b0, …, b4, l, r)` of one component: (point, tangent),
/// the generated operations.
#[inline(always)]
fn quartic(b: [f32; 5], l: f32, r: f32) -> (f32, f32) {
    let c0 = (b[0] * l) + (b[1] * r);
    let c1 = (b[1] * l) + (b[2] * r);
    let c2 = (b[2] * l) + (b[3] * r);
    let c3 = (b[3] * l) + (b[4] * r);
    let d0 = (c0 * l) + (c1 * r);
    let d1 = (c1 * l) + (c2 * r);
    let d2 = (c2 * l) + (c3 * r);
    let e0 = (d0 * l) + (d1 * r);
    let e1 = (d1 * l) + (d2 * r);
    ((e0 * l) + (e1 * r), (e1 - e0) * 4.0f32)
}

/// A `gregory4` patch's grid: the surface everywhere, then the border
/// positions. Whether a sample's tangents were parallel (the caller then
/// redoes the patch per sample, as for the other forms).
#[inline(always)]
pub(crate) fn gregory4_patch<const V: bool>(
    cp: &[Vec3; 29],
    curve: &[u32; 20],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let width = level as usize + 1;
    let mut degenerate = false;
    for (c0, narrow) in strips(width) {
        degenerate |= if narrow {
            gregory4_strip::<HALF, V>(cp, w, level, c0, pos, nrm)
        } else {
            gregory4_strip::<LANES, V>(cp, w, level, c0, pos, nrm)
        };
    }
    quad_border4(cp, curve, w, level, pos);
    degenerate
}

/// One component of a point per lane.
type Lanes<const L: usize> = [[f32; L]; 3];

/// Columns `c0 .. c0 + L` (clamped to the grid) of a `gregory4` patch's grid.
#[inline(always)]
fn gregory4_strip<const L: usize, const V: bool>(
    cp: &[Vec3; 29],
    w: &LevelWeights,
    level: u32,
    c0: usize,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let width = level as usize + 1;
    let n = level as usize;
    let nf = level as f32;
    // Padded lanes repeat column N.
    let (lu, ru) = (w.l_from::<L>(c0), w.r_from::<L>(c0));
    let iu: [f32; L] = std::array::from_fn(|k| (c0 + k).min(n) as i32 as f32);
    let niu: [f32; L] = std::array::from_fn(|k| (n - (c0 + k).min(n)) as i32 as f32);
    // The u-factors of the Bernstein products: B₁ = (4·ru)·((lu·lu)·lu)
    // (corners 0 and 3, a = 1) and B₃ = (4·((ru·ru)·ru))·lu (1 and 2, a = 3).
    let ua: [f32; L] = std::array::from_fn(|k| (4.0f32 * ru[k]) * ((lu[k] * lu[k]) * lu[k]));
    let ub: [f32; L] = std::array::from_fn(|k| (4.0f32 * ((ru[k] * ru[k]) * ru[k])) * lu[k]);
    // The fixed rows' curves along u, point and tangent per component.
    let fixed = |idx: [usize; 5]| {
        let mut p: Lanes<L> = [[0.0; L]; 3];
        let mut t: Lanes<L> = [[0.0; L]; 3];
        for c in 0..3 {
            let b = idx.map(|i| cp[i].to_array()[c]);
            for k in 0..L {
                (p[c][k], t[c][k]) = quartic(b, lu[k], ru[k]);
            }
        }
        (p, t)
    };
    let (p0, t0) = fixed(ROW0);
    let (p2, t2) = fixed(ROW2);
    let (p4, t4) = fixed(ROW4);
    let comp = |i: usize| cp[i].to_array();
    let fp: [[f32; 3]; 4] = TWIST.map(|(p, _)| comp(p));
    let fm: [[f32; 3]; 4] = TWIST.map(|(_, m)| comp(m));
    let dfm: [Vec3; 4] = TWIST.map(|(p, m)| cp[p] - cp[m]);
    let r1 = ROW1.map(comp);
    let r3 = ROW3.map(comp);
    let cols = TwistColumns {
        iu,
        niu,
        lu,
        ru,
        ua,
        ub,
    };
    let m = (width - c0).min(L);
    let mut degenerate = false;
    for iv in 0..width {
        let (lv, rv) = (w.l[iv], w.r[iv]);
        let ivf = iv as i32 as f32;
        let nivf = (n - iv) as i32 as f32;
        // The v-factors: B₁ (corners 0, 1, b = 1), B₃ (2, 3, b = 3).
        let va = (4.0f32 * rv) * ((lv * lv) * lv);
        let vb = (4.0f32 * ((rv * rv) * rv)) * lv;
        let mut out = [[0.0f32; L]; 6];
        // Stage 1: the blends and their derivative factors.
        let row = TwistRow {
            ivf,
            nivf,
            lv,
            rv,
            va,
            vb,
        };
        let TwistBlends { a, b, su, sv } = twist_blends(&cols, &row, nf);
        // Stage 2, per component and lane: the blends, rows 1 and 3, the
        // de Casteljau steps along v, du and dv.
        let mut du = [[0.0f32; L]; 3];
        let mut dv = [[0.0f32; L]; 3];
        for c in 0..3 {
            let d = dfm.map(|p| p.to_array()[c]);
            let (f, g) = (fp.map(|p| p[c]), fm.map(|p| p[c]));
            for k in 0..L {
                let (l, r) = (lu[k], ru[k]);
                let x = |j: usize| (f[j] * a[j][k]) + (g[j] * b[j][k]);
                let (p1, t1) = quartic([r1[0][c], x(0), r1[1][c], x(1), r1[2][c]], l, r);
                let (p3, t3) = quartic([r3[0][c], x(3), r3[1][c], x(2), r3[2][c]], l, r);
                let (pv, tv) = quartic([p0[c][k], p1, p2[c][k], p3, p4[c][k]], lv, rv);
                let (pu, _) = quartic([t0[c][k], t1, t2[c][k], t3, t4[c][k]], lv, rv);
                du[c][k] = pu
                    + ((((d[0] * su[0][k]) + (d[1] * su[1][k])) + (d[2] * su[2][k]))
                        + (d[3] * su[3][k]));
                dv[c][k] = tv
                    + ((((d[0] * sv[0][k]) + (d[1] * sv[1][k])) + (d[2] * sv[2][k]))
                        + (d[3] * sv[3][k]));
                out[c][k] = pv;
            }
        }
        // Stage 3: the normal.
        for k in 0..L {
            let (nn, parallel) = patch_normal(
                [du[0][k], du[1][k], du[2][k]],
                [dv[0][k], dv[1][k], dv[2][k]],
            );
            degenerate |= parallel;
            (out[3][k], out[4][k], out[5][k]) = (nn[0], nn[1], nn[2]);
        }
        let base = iv * width + c0;
        store_lanes::<L, V>(&out[0], &out[1], &out[2], &mut pos[base..base + m]);
        store_lanes::<L, V>(&out[3], &out[4], &out[5], &mut nrm[base..base + m]);
    }
    degenerate
}

/// Border positions of a `gregory4` patch from the quartic shared edge
/// evaluator `tessgen_edge4`, with the generated `eval`'s edge choice (as
/// [`super::lanes::quad_border`]): `iv = 0` is edge 0 (`t = iu`), else
/// `iu = N` edge 1 (`t = iv`), else `iv = N` edge 2 (`t = N − iu`), else
/// `iu = 0` edge 3 (`t = N − iv`). `curve` is the class's 20 `EDGE_CURVE`
/// entries (five points per edge). O(N) per patch: plain scalar code.
fn quad_border4(
    cp: &[Vec3; 29],
    curve: &[u32; 20],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
) {
    let n = level as usize;
    let width = n + 1;
    let edge = |e: usize, t: usize| -> Vec3 {
        let b: [Vec3; 5] = std::array::from_fn(|i| cp[curve[5 * e + i] as usize]);
        if t == 0 {
            return b[0];
        }
        if t == n {
            return b[4];
        }
        let (l, r) = (w.l[t], w.r[t]);
        let c = |k: usize| quartic(b.map(|p| p.to_array()[k]), l, r).0;
        Vec3::new(c(0), c(1), c(2))
    };
    for (t, p) in pos.iter_mut().enumerate().take(width) {
        *p = edge(0, t);
    }
    for t in 1..=n {
        pos[t * width + n] = edge(1, t);
        pos[n * width + (n - t)] = edge(2, t);
    }
    for t in 1..n {
        pos[(n - t) * width] = edge(3, t);
    }
}
