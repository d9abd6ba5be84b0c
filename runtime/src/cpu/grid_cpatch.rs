//! The grid path of the `cpatch` form (PCCM's extraordinary class): four
//! quartic triangles per patch, split by the patch diagonals.
//!
//! The generated `extraordinary_surface` picks the piece of each sample,
//! builds that piece's 15-point quartic net from the 24 control points and
//! runs four de Casteljau steps with the sample's barycentric weights. The
//! net depends on the piece only, so here it is built once per piece (the
//! same `Vec3` operations, so the same bits) and the de Casteljau steps run
//! lane by lane over each row's run of samples in that piece, in the
//! generated order. Border positions come from the shared edge evaluator
//! ([`super::lanes::quad_border`]), as for the bicubic form.
//!
//! `tests/tests/grid_path.rs` checks this against the per-sample path bit
//! for bit (the cube: every face extraordinary; levels 1–64).

use super::lanes::{patch_normal, quad_border, store_lanes, LevelWeights, HALF, LANES};
use glam::Vec3;

/// One piece's quartic net, by component: `[c][index]` with the generated
/// names in the order `n400 n310 n301 n220 n211 n202 n130 n121 n112 n103
/// n040 n031 n022 n013 n004`.
type Net = [[f32; 15]; 3];

/// Piece `piece`'s net from the patch's 24 points (`cp[6p .. 6p + 6]` =
/// vertex, two edge tangents, three face points of corner `p`), spelled as
/// the generated `extraordinary_surface` spells it.
fn piece_net(cp: &[Vec3; 24], piece: usize) -> Net {
    let (ca, cb, cprev) = (piece * 6, ((piece + 1) % 4) * 6, ((piece + 3) % 4) * 6);
    let (va, t0a, t1a) = (cp[ca], cp[ca + 1], cp[ca + 2]);
    let (b211a, b121a, b112a) = (cp[ca + 3], cp[ca + 4], cp[ca + 5]);
    let (vb, t0b, t1b) = (cp[cb], cp[cb + 1], cp[cb + 2]);
    let (b211b, b112b) = (cp[cb + 3], cp[cb + 5]);
    let (b121p, b112p) = (cp[cprev + 4], cp[cprev + 5]);
    let n004 = (((cp[5] + cp[11]) + cp[17]) + cp[23]) / 4.0f32;
    let n013 = (b112a + b112b) / 2.0f32;
    let n022 = (b121a + b211b) / 2.0f32;
    let n031 = (((vb * 2.0f32) + (t1b * 3.0f32)) + (t0b * 3.0f32)) / 8.0f32;
    let n040 = vb;
    let n103 = (b112a + b112p) / 2.0f32;
    let n112 = b112a;
    let n121 = b121a;
    let n130 = (vb + (t1b * 3.0f32)) / 4.0f32;
    let n202 = (b211a + b121p) / 2.0f32;
    let n211 = b211a;
    let n220 = (t0a + t1b) / 2.0f32;
    let n301 = (((va * 2.0f32) + (t0a * 3.0f32)) + (t1a * 3.0f32)) / 8.0f32;
    let n310 = (va + (t0a * 3.0f32)) / 4.0f32;
    let n400 = va;
    let pts = [
        n400, n310, n301, n220, n211, n202, n130, n121, n112, n103, n040, n031, n022, n013, n004,
    ];
    let mut net = [[0.0f32; 15]; 3];
    for (k, p) in pts.iter().enumerate() {
        (net[0][k], net[1][k], net[2][k]) = (p.x, p.y, p.z);
    }
    net
}

/// A `cpatch` patch's grid: the surface everywhere, then the border
/// positions. Whether a sample's tangents were parallel (the generated
/// `eval` then takes that normal from a nudge inside: the caller redoes the
/// patch per sample).
#[inline(always)]
pub(crate) fn cpatch_patch<const V: bool>(
    cp: &[Vec3; 24],
    curve: &[u32; 16],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let nets: [Net; 4] = std::array::from_fn(|piece| piece_net(cp, piece));
    let n = level as i64;
    let width = level as usize + 1;
    let mut degenerate = false;
    for iv in 0..=n {
        // The generated piece choice, as column ranges [lo, hi) of row iv:
        // 0: iv ≤ iu ∧ iu + iv ≤ N, 1: iv ≤ iu ∧ iu + iv > N,
        // 2: iu < iv ∧ iu + iv ≥ N, 3: iu < iv ∧ iu + iv < N.
        let ranges = [
            (iv, n - iv + 1),
            (iv.max(n - iv + 1), n + 1),
            (n - iv, iv),
            (0, iv.min(n - iv)),
        ];
        let row = iv as usize * width;
        for (piece, &(lo, hi)) in ranges.iter().enumerate() {
            let mut o = lo;
            while o < hi {
                let left = (hi - o) as usize;
                let (p, q) = (row + o as usize, row + o as usize + left.min(LANES));
                let run = Run {
                    net: &nets[piece],
                    piece,
                    level,
                    iv: iv as u32,
                    o: o as u32,
                    hi: hi as u32,
                };
                let (pos, nrm) = (&mut pos[p..q], &mut nrm[p..q]);
                degenerate |= if left <= HALF {
                    cpatch_lanes::<HALF, V>(&run, w, pos, nrm)
                } else {
                    cpatch_lanes::<LANES, V>(&run, w, pos, nrm)
                };
                o += if left <= HALF { HALF } else { LANES } as i64;
            }
        }
    }
    quad_border::<V, 24>(cp, curve, w, level, pos);
    degenerate
}

/// One lane group of a row: samples `iu = o .. min(o + L, hi)` of row
/// `iv`, all in piece `piece` (whose net is `net`).
struct Run<'a> {
    net: &'a Net,
    piece: usize,
    level: u32,
    iv: u32,
    o: u32,
    hi: u32,
}

/// The samples of `run` (lanes past `hi` repeat `hi − 1` and are not
/// stored): the piece's barycentric weights, four de Casteljau steps,
/// position and `tessgen_patch_normal(s1_010 − s1_100, s1_001 − s1_100)`.
#[inline(always)]
fn cpatch_lanes<const L: usize, const V: bool>(
    run: &Run<'_>,
    w: &LevelWeights,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let &Run {
        net,
        piece,
        level,
        iv,
        o,
        hi,
    } = run;
    let mut la = [0.0f32; L];
    let mut lb = [0.0f32; L];
    let mut lc = [0.0f32; L];
    for k in 0..L {
        let iu = (o + k as u32).min(hi - 1);
        let sum = iu + iv;
        // The generated integers of each piece (all in 0 ..= N inside it),
        // then `x as f32 / nf`: `r[x]` of the level's weights, made with
        // those operations (scalar divisions per lane cost more here than
        // the table reads).
        let (a, b, c) = match piece {
            0 => (level - sum, iu - iv, 2 * iv),
            1 => (iu - iv, sum - level, 2 * (level - iu)),
            2 => (sum - level, iv - iu, 2 * (level - iv)),
            _ => (iv - iu, level - sum, 2 * iu),
        };
        la[k] = w.r[a as usize];
        lb[k] = w.r[b as usize];
        lc[k] = w.r[c as usize];
    }
    // s1 points (100, 010, 001) and the position, per component.
    let mut s1 = [[[0.0f32; L]; 3]; 3];
    let mut out = [[0.0f32; L]; 6];
    for c in 0..3 {
        let n = &net[c];
        for k in 0..L {
            let (a, b, cc) = (la[k], lb[k], lc[k]);
            let t = |x: f32, y: f32, z: f32| ((x * a) + (y * b)) + (z * cc);
            // n400 n310 n301 n220 n211 n202 n130 n121 n112 n103 n040 n031 n022 n013 n004
            //  0    1    2    3    4    5    6    7    8    9    10   11   12   13   14
            let s3_300 = t(n[0], n[1], n[2]);
            let s3_210 = t(n[1], n[3], n[4]);
            let s3_201 = t(n[2], n[4], n[5]);
            let s3_120 = t(n[3], n[6], n[7]);
            let s3_111 = t(n[4], n[7], n[8]);
            let s3_102 = t(n[5], n[8], n[9]);
            let s3_030 = t(n[6], n[10], n[11]);
            let s3_021 = t(n[7], n[11], n[12]);
            let s3_012 = t(n[8], n[12], n[13]);
            let s3_003 = t(n[9], n[13], n[14]);
            let s2_200 = t(s3_300, s3_210, s3_201);
            let s2_110 = t(s3_210, s3_120, s3_111);
            let s2_101 = t(s3_201, s3_111, s3_102);
            let s2_020 = t(s3_120, s3_030, s3_021);
            let s2_011 = t(s3_111, s3_021, s3_012);
            let s2_002 = t(s3_102, s3_012, s3_003);
            let s1_100 = t(s2_200, s2_110, s2_101);
            let s1_010 = t(s2_110, s2_020, s2_011);
            let s1_001 = t(s2_101, s2_011, s2_002);
            s1[0][c][k] = s1_100;
            s1[1][c][k] = s1_010;
            s1[2][c][k] = s1_001;
            out[c][k] = t(s1_100, s1_010, s1_001);
        }
    }
    let mut degenerate = false;
    for k in 0..L {
        // tessgen_patch_normal(s1_010 − s1_100, s1_001 − s1_100).
        let d = |p: usize, c: usize| s1[p][c][k] - s1[0][c][k];
        let (n, parallel) = patch_normal([d(1, 0), d(1, 1), d(1, 2)], [d(2, 0), d(2, 1), d(2, 2)]);
        degenerate |= parallel && o + (k as u32) < hi;
        (out[3][k], out[4][k], out[5][k]) = (n[0], n[1], n[2]);
    }
    store_lanes::<L, V>(&out[0], &out[1], &out[2], pos);
    store_lanes::<L, V>(&out[3], &out[4], &out[5], nrm);
    degenerate
}
