//! The grid path of the `tri_cubic` form (the triangle schemes: pn, stpn,
//! phong): no row invariant, but lanes over the samples in storage order
//! (up to N = 64; lanes over each row's samples beyond), the grid walked
//! directly (the generated `grid_iu`/`grid_iv` walk every row per sample).
//! Border positions from the shared edge evaluator.
//!
//! `tests/tests/grid_path.rs` checks this against the per-sample path bit
//! for bit (every triangle scheme, levels 1–64).

use super::lanes::{edge_points, edge_run, store_lanes, LevelWeights, HALF, LANES};
use glam::Vec3;

/// A `tri_cubic` patch's grid: the surface everywhere, then the border
/// positions from the edge evaluator.
#[inline(always)]
pub(crate) fn tri_cubic_patch<const V: bool>(
    c: &[Vec3; 16],
    curve: &[u32; 12],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) {
    if !tri_cubic_flat::<V>(c, w, pos, nrm) {
        tri_cubic_interior::<V>(c, w, level, pos, nrm);
    }
    tri_border::<V>(c, curve, w, level, pos);
}

/// The net's x, y and z arrays.
#[inline(always)]
fn components(c: &[Vec3; 16]) -> [[f32; 16]; 3] {
    let mut comp = [[0.0f32; 16]; 3];
    for (k, p) in c.iter().enumerate() {
        (comp[0][k], comp[1][k], comp[2][k]) = (p.x, p.y, p.z);
    }
    comp
}

/// The interior of a `tri_cubic` patch with lanes over the samples in
/// storage order, across rows (as the bicubic form's flat interior,
/// `super::grid_flat`): the rows of a triangle grid shrink to one sample,
/// so lanes per row leave most of the last rows' registers empty (N = 9:
/// 55 samples in 10 rows took 12 lane groups, now 7). Each lane reads its
/// own `w0`, `w1`, `w2` ([`super::lanes::FlatWeights::tri`]) and runs
/// the row lanes' operations. `false` (nothing written) above
/// `FLAT_MAX_WIDTH` columns.
#[inline(always)]
fn tri_cubic_flat<const V: bool>(
    c: &[Vec3; 16],
    w: &LevelWeights,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let [w0s, w1s, w2s] = &w.flat.tri;
    if w0s.is_empty() {
        return false;
    }
    let comp = components(c);
    let total = pos.len();
    let mut s0 = 0usize;
    while s0 < total {
        let lanes = |a: &[f32]| {
            let mut v = [0.0f32; LANES];
            v.copy_from_slice(&a[s0..s0 + LANES]);
            v
        };
        let (w0, w1, w2) = (lanes(w0s), lanes(w1s), lanes(w2s));
        let mut out = [[0.0f32; LANES]; 6];
        for (ca, oa) in comp.iter().zip(out.iter_mut()) {
            tri_point_lanes(ca, &w0, &w1, &w2, oa);
        }
        tri_normal_lanes(c, &w0, &w1, &w2, &mut out);
        let m = (total - s0).min(LANES);
        store_lanes::<LANES, V>(&out[0], &out[1], &out[2], &mut pos[s0..s0 + m]);
        store_lanes::<LANES, V>(&out[3], &out[4], &out[5], &mut nrm[s0..s0 + m]);
        s0 += LANES;
    }
    true
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn tri_cubic_patch_avx2(
    c: &[Vec3; 16],
    curve: &[u32; 12],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) {
    tri_cubic_patch::<true>(c, curve, w, level, pos, nrm)
}

/// The generated `triangle_surface` at every grid point of a `tri_cubic`
/// patch `c` (16 points): per row `iv` (`w2 = iv/N` shared), lanes over
/// `iu` with `w0 = (N − iu − iv)/N`, `w1 = iu/N`; the three de Casteljau
/// steps over the 10-point net and the quadratic normal field, then
/// `tessgen_normalize` — lane by lane, the generated order.
#[inline(always)]
fn tri_cubic_interior<const V: bool>(
    c: &[Vec3; 16],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) {
    // The net's x, y and z, once per patch.
    let comp = components(c);
    let mut base = 0usize;
    for iv in 0..=level {
        let m = (level - iv) as usize + 1;
        let (dst_p, dst_n) = (&mut pos[base..base + m], &mut nrm[base..base + m]);
        let mut o = 0usize;
        while o < m {
            if m - o <= HALF {
                tri_cubic_chunk::<HALF, V>(c, &comp, w, iv, o, dst_p, dst_n);
                o += HALF;
            } else {
                tri_cubic_chunk::<LANES, V>(c, &comp, w, iv, o, dst_p, dst_n);
                o += LANES;
            }
        }
        base += m;
    }
}

/// Samples `o .. o + L` (clamped to the row) of row `iv` of a `tri_cubic`
/// patch's grid; `dst_p`, `dst_n` are the row.
#[inline(always)]
fn tri_cubic_chunk<const L: usize, const V: bool>(
    c: &[Vec3; 16],
    comp: &[[f32; 16]; 3],
    w: &LevelWeights,
    iv: u32,
    o: usize,
    dst_p: &mut [Vec3],
    dst_n: &mut [Vec3],
) {
    let m = dst_p.len();
    // w2 = iv/N; per lane iu = o + k: w1 = iu/N, w0 = ((N − iu) − iv)/N =
    // l[iu + iv] (the same integer, the same division). Lanes past the row
    // read further weights and are not stored.
    let w2 = [w.r[iv as usize]; L];
    let w0 = w.l_from::<L>(o + iv as usize);
    let w1 = w.r_from::<L>(o);
    let mut out = [[0.0f32; L]; 6];
    for (ca, oa) in comp.iter().zip(out.iter_mut()) {
        tri_point_lanes(ca, &w0, &w1, &w2, oa);
    }
    tri_normal_lanes(c, &w0, &w1, &w2, &mut out);
    let n = (m - o).min(L);
    store_lanes::<L, V>(&out[0], &out[1], &out[2], &mut dst_p[o..o + n]);
    store_lanes::<L, V>(&out[3], &out[4], &out[5], &mut dst_n[o..o + n]);
}

/// One component of `triangle_surface_at`'s point, per lane: the 10-point
/// net `b0 bn0 bp0 b1 bn1 bp1 b2 bn2 bp2 center` (slots 0 1 2 5 6 7 10 11 12
/// 15), three steps of `(x·w0 + y·w1) + z·w2`.
#[inline(always)]
fn tri_point_lanes<const L: usize>(
    c: &[f32; 16],
    w0: &[f32; L],
    w1: &[f32; L],
    w2: &[f32; L],
    out: &mut [f32; L],
) {
    let (b0, bn0, bp0) = (c[0], c[1], c[2]);
    let (b1, bn1, bp1) = (c[5], c[6], c[7]);
    let (b2, bn2, bp2) = (c[10], c[11], c[12]);
    let center = c[15];
    for k in 0..L {
        let (w0, w1, w2) = (w0[k], w1[k], w2[k]);
        let t = |x: f32, y: f32, z: f32| ((x * w0) + (y * w1)) + (z * w2);
        let s2_200 = t(b0, bn0, bp0);
        let s2_110 = t(bn0, bp1, center);
        let s2_101 = t(bp0, center, bn2);
        let s2_020 = t(bp1, b1, bn1);
        let s2_011 = t(center, bn1, bp2);
        let s2_002 = t(bn2, bp2, b2);
        let s1_100 = t(s2_200, s2_110, s2_101);
        let s1_010 = t(s2_110, s2_020, s2_011);
        let s1_001 = t(s2_101, s2_011, s2_002);
        out[k] = t(s1_100, s1_010, s1_001);
    }
}

/// `triangle_surface_at`'s normal per lane: `tessgen_normalize` of
/// `((((n3·(w0·w0) + n4·(w0·w1)) + n8·(w1·w1)) + n9·(w1·w2)) + n13·(w2·w2))
/// + n14·(w2·w0)`, into `out[3..6]`.
#[inline(always)]
fn tri_normal_lanes<const L: usize>(
    c: &[Vec3; 16],
    w0: &[f32; L],
    w1: &[f32; L],
    w2: &[f32; L],
    out: &mut [[f32; L]; 6],
) {
    let (n3, n4, n8, n9, n13, n14) = (c[3], c[4], c[8], c[9], c[13], c[14]);
    for k in 0..L {
        let (w0, w1, w2) = (w0[k], w1[k], w2[k]);
        let (q00, q01, q11, q12, q22, q20) = (w0 * w0, w0 * w1, w1 * w1, w1 * w2, w2 * w2, w2 * w0);
        let f = |a: f32, b: f32, c: f32, d: f32, e: f32, g: f32| {
            (((((a * q00) + (b * q01)) + (c * q11)) + (d * q12)) + (e * q22)) + (g * q20)
        };
        let x = f(n3.x, n4.x, n8.x, n9.x, n13.x, n14.x);
        let y = f(n3.y, n4.y, n8.y, n9.y, n13.y, n14.y);
        let z = f(n3.z, n4.z, n8.z, n9.z, n13.z, n14.z);
        let len2 = ((x * x) + (y * y)) + (z * z);
        let len = len2.sqrt();
        let ok = len2 > 0.0f32;
        out[3][k] = if ok { x / len } else { x };
        out[4][k] = if ok { y / len } else { y };
        out[5][k] = if ok { z / len } else { z };
    }
}

/// Border positions of a triangle patch from the shared edge evaluator,
/// with the generated `eval`'s edge choice: `iv = 0` is edge 0 (`t = iu`),
/// else `iu + iv = N` edge 1 (`t = iv`), else `iu = 0` edge 2 (`t = N − iv`).
/// `curve` is the class's 12 `EDGE_CURVE` entries.
#[inline(always)]
fn tri_border<const V: bool>(
    c: &[Vec3; 16],
    curve: &[u32; 12],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
) {
    let n = level as usize;
    let b = |e: usize| edge_points(c, curve, e);
    // First sample of row iv: Σ_{r<iv} (N + 1 − r).
    let row = |iv: usize| iv * (n + 1) - iv * iv.saturating_sub(1) / 2;
    edge_run::<V>(&b(0), w, level, 0..=level, |t, p| pos[t] = p);
    edge_run::<V>(&b(1), w, level, 1..=level, |iv, p| {
        pos[row(iv) + (n - iv)] = p
    });
    edge_run::<V>(&b(2), w, level, 1..=level.saturating_sub(1), |t, p| {
        pos[row(n - t)] = p
    });
}
