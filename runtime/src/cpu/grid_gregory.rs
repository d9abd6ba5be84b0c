//! The grid path of the `gregory` form (the extraordinary class of
//! `gregory` and `gregory_osd`): a bicubic Bézier patch whose four interior
//! points are rational blends of two face points each, plus the derivative
//! terms of that blend in the tangents.
//!
//! What is invariant where, for the generated `extraordinary_surface`: the
//! outer rows 0 and 3 (their four points are fixed) depend on the column
//! only; the blend weights of corner `k` depend on the integers
//! `(wp, wm)` — `iu`, `iv`, `N − iu`, `N − iv` in the generated pairing —,
//! so rows 1 and 2 change with every sample. Per strip of columns the outer
//! row curves and the u-factors of the blend's Bernstein weights are
//! computed once; per sample, lane by lane and in the generated order, the
//! blend (`a = wp/ws`, `b = wm/ws`, `1/(ws/N)²`, or `½, ½, 0` at `ws = 0`:
//! a select), the interior points `fp·a + fm·b`, the inner row curves, the
//! de Casteljau steps along v, and `du`, `dv` with their four blend terms.
//! `wp/N` and `wm/N` are the level's weights themselves (`ru`, `rv`, `lu`,
//! `lv`: the same integers over the same divisor). Border positions come
//! from the shared edge evaluator ([`super::lanes::quad_border`]).
//!
//! `tests/tests/grid_path.rs` checks this against the per-sample path bit
//! for bit (the cube: every face extraordinary; levels 1–64).

use super::lanes::{
    cubic, patch_normal, quad_border, row_curve_lanes, store_lanes, strips, LevelWeights, HALF,
    LANES,
};
use glam::Vec3;

/// Per corner `k`: the indices of its face points `(fp, fm)`.
const FACE_POINTS: [(usize, usize); 4] = [(3, 4), (8, 9), (13, 14), (18, 19)];

/// The per-strip column data of a Gregory-type grid path (lanes over the
/// columns): the integers `iu`, `N − iu` as f32, the level's weights, and
/// the u-factors of the twist slots' Bernstein weights — `ua` for corners
/// 0 and 3, `ub` for corners 1 and 2.
pub(crate) struct TwistColumns<const L: usize> {
    pub(crate) iu: [f32; L],
    pub(crate) niu: [f32; L],
    pub(crate) lu: [f32; L],
    pub(crate) ru: [f32; L],
    pub(crate) ua: [f32; L],
    pub(crate) ub: [f32; L],
}

/// One grid row's data: `iv`, `N − iv` as f32, the weights, and the
/// v-factors of the Bernstein weights (`va` corners 0 and 1, `vb` 2 and 3).
pub(crate) struct TwistRow {
    pub(crate) ivf: f32,
    pub(crate) nivf: f32,
    pub(crate) lv: f32,
    pub(crate) rv: f32,
    pub(crate) va: f32,
    pub(crate) vb: f32,
}

/// Per corner and lane of a twist pair (`gregory` and `gregory4` alike):
/// the blend weights `a`, `b` and the scalar factors `su`, `sv` of the
/// corner's derivative terms.
pub(crate) struct TwistBlends<const L: usize> {
    pub(crate) a: [[f32; L]; 4],
    pub(crate) b: [[f32; L]; 4],
    pub(crate) su: [[f32; L]; 4],
    pub(crate) sv: [[f32; L]; 4],
}

/// Stage 1 of the Gregory-type grid paths, per corner and lane: the
/// integer weights, the blend (a select at ws = 0), the Bernstein weight
/// and the two scalar factors of the corner's derivative terms, as the
/// generated code groups them: ((±w/N · inv_s2) · bw). `nf` is N as f32.
#[inline(always)]
pub(crate) fn twist_blends<const L: usize>(
    c: &TwistColumns<L>,
    r: &TwistRow,
    nf: f32,
) -> TwistBlends<L> {
    let mut t = TwistBlends {
        a: [[0.0f32; L]; 4],
        b: [[0.0f32; L]; 4],
        su: [[0.0f32; L]; 4],
        sv: [[0.0f32; L]; 4],
    };
    for j in 0..4 {
        for k in 0..L {
            // (wp, wm, wp/N, wm/N, Bernstein weight) of corner j.
            let (wp, wm, wpf, wmf, bw) = match j {
                0 => (c.iu[k], r.ivf, c.ru[k], r.rv, c.ua[k] * r.va),
                1 => (r.ivf, c.niu[k], r.rv, c.lu[k], c.ub[k] * r.va),
                2 => (c.niu[k], r.nivf, c.lu[k], r.lv, c.ub[k] * r.vb),
                _ => (r.nivf, c.iu[k], r.lv, c.ru[k], c.ua[k] * r.vb),
            };
            // The integers are exact in f32, so their f32 sum is the
            // generated `(wp + wm) as f32`.
            let ws = wp + wm;
            let some = ws > 0.0f32;
            t.a[j][k] = if some { wp / ws } else { 0.5f32 };
            t.b[j][k] = if some { wm / ws } else { 0.5f32 };
            let sf = ws / nf;
            let inv = if some { 1.0f32 / (sf * sf) } else { 0.0f32 };
            (t.su[j][k], t.sv[j][k]) = match j {
                0 => ((wmf * inv) * bw, ((-wpf) * inv) * bw),
                1 => ((wpf * inv) * bw, (wmf * inv) * bw),
                2 => (((-wmf) * inv) * bw, (wpf * inv) * bw),
                _ => (((-wpf) * inv) * bw, ((-wmf) * inv) * bw),
            };
        }
    }
    t
}

/// A `gregory` patch's grid: the surface everywhere, then the border
/// positions. Whether a sample's tangents were parallel (the caller then
/// redoes the patch per sample, as for the other forms).
#[inline(always)]
pub(crate) fn gregory_patch<const V: bool>(
    cp: &[Vec3; 20],
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
            gregory_strip::<HALF, V>(cp, w, level, c0, pos, nrm)
        } else {
            gregory_strip::<LANES, V>(cp, w, level, c0, pos, nrm)
        };
    }
    quad_border::<V, 20>(cp, curve, w, level, pos);
    degenerate
}

/// One component of a point per lane.
type Lanes<const L: usize> = [[f32; L]; 3];

/// Columns `c0 .. c0 + L` (clamped to the grid) of a `gregory` patch's grid.
#[inline(always)]
fn gregory_strip<const L: usize, const V: bool>(
    cp: &[Vec3; 20],
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
    // The u-factors of the Bernstein products: (3·ru)·(lu·lu) (corners 0
    // and 3) and (3·(ru·ru))·lu (corners 1 and 2).
    let ua: [f32; L] = std::array::from_fn(|k| (3.0f32 * ru[k]) * (lu[k] * lu[k]));
    let ub: [f32; L] = std::array::from_fn(|k| (3.0f32 * (ru[k] * ru[k])) * lu[k]);
    // The outer row curves: row 0 = cubic(cp0, cp1, cp7, cp5), row 3 =
    // cubic(cp15, cp17, cp11, cp10), point and tangent per component.
    let outer = |idx: [usize; 4]| {
        let mut p: Lanes<L> = [[0.0; L]; 3];
        let mut t: Lanes<L> = [[0.0; L]; 3];
        for c in 0..3 {
            let b = idx.map(|i| cp[i].to_array()[c]);
            row_curve_lanes(b, &lu, &ru, &mut p[c], &mut t[c]);
        }
        (p, t)
    };
    let (p0, t0) = outer([0, 1, 7, 5]);
    let (p3, t3) = outer([15, 17, 11, 10]);
    let comp = |i: usize| cp[i].to_array();
    let fp: [[f32; 3]; 4] = FACE_POINTS.map(|(p, _)| comp(p));
    let fm: [[f32; 3]; 4] = FACE_POINTS.map(|(_, m)| comp(m));
    let dfm: [Vec3; 4] = FACE_POINTS.map(|(p, m)| cp[p] - cp[m]);
    let (c2, c6, c16, c12) = (comp(2), comp(6), comp(16), comp(12));
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
        // The v-factors: (3·rv)·(lv·lv) (corners 0, 1), (3·(rv·rv))·lv (2, 3).
        let va = (3.0f32 * rv) * (lv * lv);
        let vb = (3.0f32 * (rv * rv)) * lv;
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
        // Stage 2, per component and lane: the interior points, the inner
        // row curves (row 1 = cubic(cp2, x0, x1, cp6), row 2 = cubic(cp16,
        // x3, x2, cp12)), the de Casteljau steps along v, du and dv.
        let mut du = [[0.0f32; L]; 3];
        let mut dv = [[0.0f32; L]; 3];
        for c in 0..3 {
            let d = dfm.map(|p| p.to_array()[c]);
            let (f, g) = (fp.map(|p| p[c]), fm.map(|p| p[c]));
            for k in 0..L {
                let (l, r) = (lu[k], ru[k]);
                let x = |j: usize| (f[j] * a[j][k]) + (g[j] * b[j][k]);
                let (p1, t1) = cubic(c2[c], x(0), x(1), c6[c], l, r);
                let (p2, t2) = cubic(c16[c], x(3), x(2), c12[c], l, r);
                let (pv, tv) = cubic(p0[c][k], p1, p2, p3[c][k], lv, rv);
                let (pu, _) = cubic(t0[c][k], t1, t2, t3[c][k], lv, rv);
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
