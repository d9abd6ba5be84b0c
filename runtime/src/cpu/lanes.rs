//! The lane primitives the grid path's forms share: the level's weights
//! (made once per evaluation, in the strips' and in the flat interiors'
//! lane orders), the generated curve and normal operations written lane
//! by lane over fixed-width arrays (so LLVM vectorises them across samples,
//! never inside one sample's sums), the stores that interleave lanes into
//! `Vec3`s, and the shared edge evaluator's border.
//!
//! Every function here executes the generated code's IEEE operations in the
//! generated order for each lane; `tests/tests/grid_path.rs` holds the
//! forms that use them to the per-sample path bit for bit.

use glam::Vec3;

/// Lane granularity the column strips are padded to (one AVX2 register).
/// Lane weights convert their integers through `i32` (levels are at most
/// `MAX_LEVEL` = 4096, so every integer is exact in f32 either way and the
/// bits are those of the generated `u32 as f32`): x86 has a packed
/// signed conversion, not an unsigned one, before AVX-512.
pub(crate) const LANES: usize = 8;
/// The narrower strip for a grid's last few columns (one SSE register).
pub(crate) const HALF: usize = 4;
/// `tessgen_patch_normal`'s threshold, from the ABI codegen declares
/// (tests/tests/grid_path.rs checks this path against the generated `eval`
/// on patches with parallel tangents).
use crate::abi::PARALLEL_SIN2;

/// The widest grid (`N + 1` columns) the flat interior takes.
pub(crate) const FLAT_MAX_WIDTH: usize = 65;

/// Lanes of the column weights wrapped at the row's end: the widest
/// row-curve array (`COLS` = 80 for 16 lanes at `N + 1` = 65).
pub(crate) const WRAP: usize = 80;

/// How far past the last sample a group may read the row weights.
const ROW_PAD: usize = 16;

/// The grid weights `l_i = (N − i)/N` and `r_i = i/N`, `i = 0 … N`, made
/// once per evaluation with the generated code's operations (an exact
/// integer-to-float conversion, then one division by `N as f32`), so the
/// columns, rows and edges of every patch read the same bits instead of
/// converting and dividing per lane. Entries past `N` repeat those at `N`:
/// padded lanes compute column `N` again and are never stored.
pub(crate) struct LevelWeights {
    pub(crate) l: Vec<f32>,
    pub(crate) r: Vec<f32>,
    /// The same weights in the flat interior's lane order.
    pub(crate) flat: FlatWeights,
}

impl LevelWeights {
    pub(crate) fn new(level: u32) -> LevelWeights {
        // Integers ≤ MAX_LEVEL convert exactly through i32 or u32 alike.
        let nf = level as f32;
        let len = level as usize + 1 + PAD;
        let at = |i: usize| (i as u32).min(level);
        let l: Vec<f32> = (0..len)
            .map(|i| ((level - at(i)) as i32 as f32) / nf)
            .collect();
        let r: Vec<f32> = (0..len).map(|i| (at(i) as i32 as f32) / nf).collect();
        let flat = FlatWeights::new(level, &l, &r);
        LevelWeights { l, r, flat }
    }

    /// `L` consecutive `l` weights from `i`.
    #[inline(always)]
    pub(crate) fn l_from<const L: usize>(&self, i: usize) -> [f32; L] {
        let mut v = [0.0f32; L];
        v.copy_from_slice(&self.l[i..i + L]);
        v
    }

    /// `L` consecutive `r` weights from `i`.
    #[inline(always)]
    pub(crate) fn r_from<const L: usize>(&self, i: usize) -> [f32; L] {
        let mut v = [0.0f32; L];
        v.copy_from_slice(&self.r[i..i + L]);
        v
    }
}

/// How far past `N` a lane group may read [`LevelWeights`] (the widest strip).
const PAD: usize = 16;

/// The level's weights in the flat interior's lane order, made once per
/// evaluation from [`LevelWeights`]'s `l`, `r` (copies, no arithmetic).
pub(crate) struct FlatWeights {
    /// `l` of column `j mod (N + 1)`, `j = 0 .. WRAP`.
    pub(crate) wrap_l: [f32; WRAP],
    /// `r` of column `j mod (N + 1)`.
    pub(crate) wrap_r: [f32; WRAP],
    /// `l` of row `s / (N + 1)` for every sample `s` of a grid, then
    /// [`ROW_PAD`] entries of row `N`; empty above [`FLAT_MAX_WIDTH`].
    pub(crate) row_l: Vec<f32>,
    /// `r` of row `s / (N + 1)`, likewise.
    pub(crate) row_r: Vec<f32>,
    /// The triangle grid's weights per sample `s` (row `iv`, `iu` along
    /// it, [`crate::grid`]'s order): `w0 = l[iu + iv]`, `w1 = r[iu]`,
    /// `w2 = r[iv]` (`grid_tri`'s lanes), then [`ROW_PAD`] copies of the
    /// last sample's; empty above [`FLAT_MAX_WIDTH`].
    pub(crate) tri: [Vec<f32>; 3],
}

impl FlatWeights {
    /// `l`, `r`: [`LevelWeights`]'s arrays (`N + 1` entries and padding).
    pub(crate) fn new(level: u32, l: &[f32], r: &[f32]) -> FlatWeights {
        let width = level as usize + 1;
        let (mut wrap_l, mut wrap_r) = ([0.0f32; WRAP], [0.0f32; WRAP]);
        for j in 0..WRAP {
            wrap_l[j] = l[j % width];
            wrap_r[j] = r[j % width];
        }
        let (row_l, row_r) = if width <= FLAT_MAX_WIDTH {
            let row = |s: usize| (s / width).min(width - 1);
            let len = width * width + ROW_PAD;
            (
                (0..len).map(|s| l[row(s)]).collect(),
                (0..len).map(|s| r[row(s)]).collect(),
            )
        } else {
            (Vec::new(), Vec::new())
        };
        let mut tri: [Vec<f32>; 3] = Default::default();
        if width <= FLAT_MAX_WIDTH {
            for iv in 0..width {
                for iu in 0..width - iv {
                    tri[0].push(l[iu + iv]);
                    tri[1].push(r[iu]);
                    tri[2].push(r[iv]);
                }
            }
            for t in tri.iter_mut() {
                let last = t[t.len() - 1];
                t.extend(std::iter::repeat_n(last, ROW_PAD));
            }
        }
        FlatWeights {
            wrap_l,
            wrap_r,
            row_l,
            row_r,
            tri,
        }
    }
}

/// The column strips of a grid `width` columns wide for the 8-lane forms:
/// `(first column, narrow)`, full strips of [`LANES`] and a last one of at
/// most [`HALF`] columns taking [`HALF`] lanes.
pub(crate) fn strips(width: usize) -> impl Iterator<Item = (usize, bool)> {
    let mut c0 = 0usize;
    std::iter::from_fn(move || {
        (c0 < width).then(|| {
            let narrow = width - c0 <= HALF;
            let at = c0;
            c0 += if narrow { HALF } else { LANES };
            (at, narrow)
        })
    })
}

/// Component `c` of row curve `r`'s control points `g[r], g[4 + r],
/// g[8 + r], g[12 + r]` (a bicubic patch, `4k + l`).
#[inline(always)]
pub(crate) fn row_points(g: &[Vec3; 16], r: usize, c: usize) -> [f32; 4] {
    [
        g[r].to_array()[c],
        g[4 + r].to_array()[c],
        g[8 + r].to_array()[c],
        g[12 + r].to_array()[c],
    ]
}

/// `tessgen_cubic(b0, b1, b2, b3, l, r)` of one component, per lane:
/// point `d0·l + d1·r` and tangent `(d1 − d0)·3`.
#[inline(always)]
pub(crate) fn row_curve_lanes<const L: usize>(
    b: [f32; 4],
    l: &[f32; L],
    r: &[f32; L],
    point: &mut [f32; L],
    tangent: &mut [f32; L],
) {
    for k in 0..L {
        (point[k], tangent[k]) = cubic(b[0], b[1], b[2], b[3], l[k], r[k]);
    }
}

/// One grid row's samples for `LANES` columns: `along_v = cubic(row
/// points, lv, rv)` (point and tangent), `along_u = cubic(row tangents,
/// lv, rv)` (point), glam's cross `along_u.point × along_v.tangent` and
/// `tessgen_patch_normal`. Inputs are the four rows' components
/// (`px[r]` = x of row r's point, `tx[r]` = x of its tangent); `out` is
/// position x, y, z, normal x, y, z. Whether a lane's tangents were
/// parallel (its normal is then zero, as the generated surface's).
#[inline(always)]
pub(crate) fn sample_lanes<const L: usize>(
    pt: &[[[f32; L]; 3]; 4],
    tg: &[[[f32; L]; 3]; 4],
    l: f32,
    r: f32,
    out: &mut [[f32; L]; 6],
) -> bool {
    sample_lanes_of(pt, tg, 0, &[l; L], &[r; L], out)
}

/// [`sample_lanes`] with each lane's own row weights `l[k]`, `r[k]` (the
/// flat interior's lanes run across rows), lane `k` reading entry `o + k`
/// of row curves `C` entries long.
#[inline(always)]
pub(crate) fn sample_lanes_of<const L: usize, const C: usize>(
    pt: &[[[f32; C]; 3]; 4],
    tg: &[[[f32; C]; 3]; 4],
    o: usize,
    l: &[f32; L],
    r: &[f32; L],
    out: &mut [[f32; L]; 6],
) -> bool {
    // One check here instead of one per load.
    assert!(o + L <= C);
    let mut degenerate = false;
    for k in 0..L {
        let (p, tu, tv) = sample_curves_at(pt, tg, o + k, l[k], r[k]);
        let (n, parallel) = patch_normal(tu, tv);
        degenerate |= parallel;
        for c in 0..3 {
            out[c][k] = p[c];
            out[3 + c][k] = n[c];
        }
    }
    degenerate
}

/// One sample's curves along `v` at entry `j` of the row curves: the
/// position, the tangent along `u` (the point of the tangent curves) and
/// the tangent along `v`.
#[inline(always)]
fn sample_curves_at<const C: usize>(
    pt: &[[[f32; C]; 3]; 4],
    tg: &[[[f32; C]; 3]; 4],
    j: usize,
    l: f32,
    r: f32,
) -> ([f32; 3], [f32; 3], [f32; 3]) {
    let along = |a: &[[[f32; C]; 3]; 4], c: usize| {
        cubic(a[0][c][j], a[1][c][j], a[2][c][j], a[3][c][j], l, r)
    };
    let (x, tvx) = along(pt, 0);
    let (y, tvy) = along(pt, 1);
    let (z, tvz) = along(pt, 2);
    let (ux, _) = along(tg, 0);
    let (uy, _) = along(tg, 1);
    let (uz, _) = along(tg, 2);
    ([x, y, z], [ux, uy, uz], [tvx, tvy, tvz])
}

/// A lane group of samples between the two halves of its work: positions,
/// the cross product `c` of the tangents, `c·c` and the parallel-tangent
/// threshold `PARALLEL_SIN2·(a·a)·(b·b)`. The second half
/// ([`SampleHalf::finish`]: `√(c·c)`, three divisions, the selects) is
/// one long dependency chain behind the first; a loop that runs the first
/// half of the next group before finishing this one gives the core
/// independent multiplies to issue while the square root and divisions
/// wait (the flat interior's AVX2 and AVX-512 copies, `grid_flat`). Each
/// sample's operations and their order are [`sample_lanes_of`]'s either
/// way. (The SSE2 copy keeps the fused [`sample_lanes_of`]: with 16
/// registers of 4 lanes the stored halves spill, 1.2× slower.)
#[derive(Clone, Copy)]
pub(crate) struct SampleHalf<const L: usize> {
    pos: [[f32; L]; 3],
    c: [[f32; L]; 3],
    c2: [f32; L],
    limit: [f32; L],
}

impl<const L: usize> Default for SampleHalf<L> {
    fn default() -> Self {
        SampleHalf {
            pos: [[0.0; L]; 3],
            c: [[0.0; L]; 3],
            c2: [0.0; L],
            limit: [0.0; L],
        }
    }
}

impl<const L: usize> SampleHalf<L> {
    /// The second half: unit normals into `out[3..6]` (positions into
    /// `out[0..3]`); whether a lane's tangents were parallel. The end of
    /// [`patch_normal`] spelled out per lane: written through a shared
    /// helper returning `[f32; 3]`, LLVM left this loop scalar.
    #[inline(always)]
    pub(crate) fn finish(&self, out: &mut [[f32; L]; 6]) -> bool {
        let mut degenerate = false;
        #[allow(clippy::needless_range_loop)] // lane k of eight arrays
        for k in 0..L {
            let parallel = self.c2[k] <= self.limit[k];
            let len = self.c2[k].sqrt();
            degenerate |= parallel;
            for c in 0..3 {
                out[c][k] = self.pos[c][k];
                out[3 + c][k] = if parallel { 0.0 } else { self.c[c][k] / len };
            }
        }
        degenerate
    }
}

/// The first half of [`sample_lanes_of`]'s work into `half`: both curves
/// along `v`, the cross product of the tangents and its two norms.
#[inline(always)]
pub(crate) fn sample_curves<const L: usize, const C: usize>(
    pt: &[[[f32; C]; 3]; 4],
    tg: &[[[f32; C]; 3]; 4],
    o: usize,
    l: &[f32; L],
    r: &[f32; L],
    half: &mut SampleHalf<L>,
) {
    // One check here instead of one per load.
    assert!(o + L <= C);
    for k in 0..L {
        let ([x, y, z], tu, tv) = sample_curves_at(pt, tg, o + k, l[k], r[k]);
        let (c, c2, limit) = normal_terms(tu, tv);
        half.pos[0][k] = x;
        half.pos[1][k] = y;
        half.pos[2][k] = z;
        half.c[0][k] = c[0];
        half.c[1][k] = c[1];
        half.c[2][k] = c[2];
        half.c2[k] = c2;
        half.limit[k] = limit;
    }
}

/// `tessgen_cubic(b0, b1, b2, b3, l, r)` of one component of one lane:
/// (point, tangent), the generated operations.
#[inline(always)]
pub(crate) fn cubic(b0: f32, b1: f32, b2: f32, b3: f32, l: f32, r: f32) -> (f32, f32) {
    let c0 = (b0 * l) + (b1 * r);
    let c1 = (b1 * l) + (b2 * r);
    let c2 = (b2 * l) + (b3 * r);
    let d0 = (c0 * l) + (c1 * r);
    let d1 = (c1 * l) + (c2 * r);
    ((d0 * l) + (d1 * r), (d1 - d0) * 3.0f32)
}

/// The point of [`cubic`] alone.
#[inline(always)]
pub(crate) fn cubic_point(b0: f32, b1: f32, b2: f32, b3: f32, l: f32, r: f32) -> f32 {
    cubic(b0, b1, b2, b3, l, r).0
}

/// `tessgen_patch_normal(a, b)` of one lane: glam's `a × b` (`(a.y·b.z −
/// b.y·a.z, a.z·b.x − b.z·a.x, a.x·b.y − b.x·a.y)`) over `√(c·c)`, or zero
/// when `c·c ≤ PARALLEL_SIN2·(a·a)·(b·b)` (parallel tangents; reported).
/// Selects, not branches, so the lanes stay vectorised.
#[inline(always)]
pub(crate) fn patch_normal(a: [f32; 3], b: [f32; 3]) -> ([f32; 3], bool) {
    let (c, c2, limit) = normal_terms(a, b);
    let parallel = c2 <= limit;
    let len = c2.sqrt();
    let n = [
        if parallel { 0.0 } else { c[0] / len },
        if parallel { 0.0 } else { c[1] / len },
        if parallel { 0.0 } else { c[2] / len },
    ];
    (n, parallel)
}

/// [`patch_normal`]'s products: `c = a × b`, `c·c` and the parallel
/// threshold `PARALLEL_SIN2·((a·a)·(b·b))`.
#[inline(always)]
fn normal_terms(a: [f32; 3], b: [f32; 3]) -> ([f32; 3], f32, f32) {
    let cx = (a[1] * b[2]) - (b[1] * a[2]);
    let cy = (a[2] * b[0]) - (b[2] * a[0]);
    let cz = (a[0] * b[1]) - (b[0] * a[1]);
    let c2 = ((cx * cx) + (cy * cy)) + (cz * cz);
    let aa = ((a[0] * a[0]) + (a[1] * a[1])) + (a[2] * a[2]);
    let bb = ((b[0] * b[0]) + (b[1] * b[1])) + (b[2] * b[2]);
    ([cx, cy, cz], c2, PARALLEL_SIN2 * (aa * bb))
}

/// The first `dst.len()` (≤ L) lanes of (x, y, z) into `dst`. With `V`
/// (only in the copies compiled with AVX2 enabled) each full group of 8
/// lanes is interleaved in registers by [`interleave8`]; otherwise full
/// chunks interleave through an array, then one copy. Data movement only:
/// the bits are the lanes'.
#[inline(always)]
pub(crate) fn store_lanes<const L: usize, const V: bool>(
    x: &[f32; L],
    y: &[f32; L],
    z: &[f32; L],
    dst: &mut [Vec3],
) {
    #[cfg(target_arch = "x86_64")]
    if V && L.is_multiple_of(8) && dst.len() == L {
        for c in 0..L / 8 {
            let (xs, ys, zs) = (
                &x[c * 8..c * 8 + 8],
                &y[c * 8..c * 8 + 8],
                &z[c * 8..c * 8 + 8],
            );
            let d = &mut dst[c * 8..c * 8 + 8];
            // SAFETY: `V` is true only in the AVX2 and AVX-512 copies, which
            // run after `is_x86_feature_detected!("avx2")`; the three
            // sources hold 8 floats each and `d` 8 `Vec3`s (24 floats).
            unsafe {
                interleave8(
                    xs.as_ptr(),
                    ys.as_ptr(),
                    zs.as_ptr(),
                    d.as_mut_ptr() as *mut f32,
                )
            };
        }
        return;
    }
    if dst.len() == L {
        let mut v = [Vec3::ZERO; L];
        for k in 0..L {
            v[k] = Vec3::new(x[k], y[k], z[k]);
        }
        dst.copy_from_slice(&v);
    } else {
        for (k, d) in dst.iter_mut().enumerate().take(L) {
            *d = Vec3::new(x[k], y[k], z[k]);
        }
    }
}

/// Eight lanes of x, y and z as eight packed `(x, y, z)` triples (24
/// floats at `dst`): six in-lane shuffles and three cross-lane permutes,
/// where LLVM's own interleave of `[Vec3; 8]` went through the stack.
///
/// # Safety
/// AVX must be available; `x`, `y`, `z` must be readable for 8 floats and
/// `dst` writable for 24.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn interleave8(x: *const f32, y: *const f32, z: *const f32, dst: *mut f32) {
    use std::arch::x86_64::*;
    let (x, y, z) = (_mm256_loadu_ps(x), _mm256_loadu_ps(y), _mm256_loadu_ps(z));
    // Per 128-bit half (lanes 0–3 shown):
    let xy = _mm256_shuffle_ps::<0b10_00_10_00>(x, y); // x0 x2 y0 y2
    let yz = _mm256_shuffle_ps::<0b11_01_11_01>(y, z); // y1 y3 z1 z3
    let zx = _mm256_shuffle_ps::<0b11_01_10_00>(z, x); // z0 z2 x1 x3
    let r03 = _mm256_shuffle_ps::<0b10_00_10_00>(xy, zx); // x0 y0 z0 x1
    let r14 = _mm256_shuffle_ps::<0b11_01_10_00>(yz, xy); // y1 z1 x2 y2
    let r25 = _mm256_shuffle_ps::<0b11_01_11_01>(zx, yz); // z2 x3 y3 z3
    _mm256_storeu_ps(dst, _mm256_permute2f128_ps::<0x20>(r03, r14));
    _mm256_storeu_ps(dst.add(8), _mm256_permute2f128_ps::<0x30>(r25, r03));
    _mm256_storeu_ps(dst.add(16), _mm256_permute2f128_ps::<0x31>(r14, r25));
}

/// Border positions of a quad patch from the shared edge evaluator, with
/// the generated `eval`'s edge choice: `iv = 0` is edge 0 (`t = iu`), else
/// `iu = N` edge 1 (`t = iv`), else `iv = N` edge 2 (`t = N − iu`), else
/// `iu = 0` edge 3 (`t = N − iv`). `curve` is the class's 16 `EDGE_CURVE`
/// entries (four points per edge).
#[inline(always)]
pub(crate) fn quad_border<const V: bool, const P: usize>(
    g: &[Vec3; P],
    curve: &[u32; 16],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
) {
    let n = level as usize;
    let width = n + 1;
    let b = |e: usize| edge_points(g, curve, e);
    edge_run::<V>(&b(0), w, level, 0..=level, |t, p| pos[t] = p);
    edge_run::<V>(&b(1), w, level, 1..=level, |t, p| pos[t * width + n] = p);
    edge_run::<V>(&b(2), w, level, 1..=level, |t, p| {
        pos[n * width + (n - t)] = p
    });
    edge_run::<V>(&b(3), w, level, 1..=level.saturating_sub(1), |t, p| {
        pos[(n - t) * width] = p
    });
}

/// The four curve points of edge `e` (`EDGE_CURVE` entries `4e .. 4e + 4`
/// of the class) of a 16-point patch. (Spelled out: `array::map` is not
/// always inlined here, and costs a call per edge.)
#[inline(always)]
pub(crate) fn edge_points<const P: usize, const C: usize>(
    g: &[Vec3; P],
    curve: &[u32; C],
    e: usize,
) -> [Vec3; 4] {
    let k = |i: usize| g[curve[e * 4 + i] as usize];
    [k(0), k(1), k(2), k(3)]
}

/// `tessgen_edge(b0, b1, b2, b3, t, level)` for every `t` of `ts`, lane by
/// lane (chunks of `LANES` values of `t`, the weights read from `w`), each
/// handed to `put(t, point)`. The edge evaluator returns the corner points
/// themselves at `t = 0` and `t = level`; those lanes are overwritten with
/// them after the de Casteljau steps, which is the generated select.
#[inline(always)]
pub(crate) fn edge_run<const V: bool>(
    b: &[Vec3; 4],
    w: &LevelWeights,
    level: u32,
    ts: std::ops::RangeInclusive<u32>,
    mut put: impl FnMut(usize, Vec3),
) {
    let (first, last) = (*ts.start() as usize, *ts.end() as usize);
    let level = level as usize;
    let comp = [
        [b[0].x, b[1].x, b[2].x, b[3].x],
        [b[0].y, b[1].y, b[2].y, b[3].y],
        [b[0].z, b[1].z, b[2].z, b[3].z],
    ];
    let mut t0 = first;
    while t0 <= last {
        let (l, r) = (w.l_from::<LANES>(t0), w.r_from::<LANES>(t0));
        let mut out = [[0.0f32; LANES]; 3];
        for (o, bc) in out.iter_mut().zip(&comp) {
            edge_lanes(bc, &l, &r, o);
        }
        let mut v = [Vec3::ZERO; LANES];
        store_lanes::<LANES, V>(&out[0], &out[1], &out[2], &mut v);
        if t0 == 0 {
            v[0] = b[0];
        }
        if (t0..t0 + LANES).contains(&level) {
            v[level - t0] = b[3];
        }
        let m = (last - t0 + 1).min(LANES);
        for (k, p) in v.iter().take(m).enumerate() {
            put(t0 + k, *p);
        }
        t0 += LANES;
    }
}

/// One component of `tessgen_edge`'s symmetric de Casteljau per lane, with
/// `r = t/level`, `l = (level − t)/level` from [`LevelWeights`].
#[inline(always)]
pub(crate) fn edge_lanes(b: &[f32; 4], l: &[f32; LANES], r: &[f32; LANES], out: &mut [f32; LANES]) {
    for k in 0..LANES {
        out[k] = cubic_point(b[0], b[1], b[2], b[3], l[k], r[k]);
    }
}
