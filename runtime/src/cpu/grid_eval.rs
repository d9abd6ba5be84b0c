//! The fast grid path: every patch's sample grid written straight into the
//! caller's buffers, with the per-patch and per-(patch, column) invariants
//! hoisted out of the per-sample work.
//!
//! The per-sample path ([`super::evaluate_per_sample_into`]) calls the
//! generated `eval` once per sample, which recomputes the four row curves
//! of a bicubic patch, the class dispatch and the border test for every
//! sample. Here, for a patch of the `bicubic` form (the ordinary class of
//! every quad scheme), the row curves of a column `iu` are computed once and
//! reused by all `N + 1` samples of that column (lanes over the samples in
//! storage order up to N = 64, [`super::grid_flat`]; strips of columns
//! beyond); each sample then executes
//! exactly the operations the generated `ordinary_surface` executes after
//! its row curves, in the same order (no FMA contraction, no reassociation:
//! Rust never contracts `a * b + c`, and LLVM vectorises these loops only
//! across samples, never within one sample's sums). A `tri_cubic` patch
//! (the triangle schemes, [`super::grid_tri`]) has no row invariant but the same lanes over the
//! samples of a row. Border samples get their positions from the shared
//! edge evaluator (`tessgen_edge`'s operations, lanes over `t`) in their
//! own loop, after the interior loop wrote the surface everywhere: the
//! generated `eval` also keeps the surface normal and replaces only the
//! position. The extraordinary forms have their own lanes: `cpatch`
//! (PCCM, [`super::grid_cpatch`]), `acc` ([`super::grid_acc`]) and
//! `gregory` (`gregory`, `gregory_osd`: [`super::grid_gregory`]) and
//! `gregory4` (`g1cc`, both classes: [`super::grid_gregory4`]). A form
//! none of these knows (a user scheme's) runs the generated `eval` per
//! sample, walking the grid row by row instead of decoding each sample
//! index.
//!
//! The grid weights `i/N`, `(N − i)/N` are made once per evaluation
//! ([`LevelWeights`]), with the generated conversion and division.
//!
//! The lane loops are written over fixed-width arrays so LLVM vectorises
//! them; an AVX2 copy or an AVX-512 copy (full bicubic strips of 16 columns) is
//! chosen at run time (`is_x86_feature_detected!`), and the baseline copy
//! (SSE2 on x86-64, whatever the target has elsewhere) computes the same
//! bits: all are IEEE single precision `+ − × ÷ √` lane by lane.
//!
//! `tests/tests/grid_path.rs` checks that this path and the per-sample path
//! give the same bits for every scheme, class and level 1–64.

use super::grid_acc::acc_patch;
use super::grid_cpatch::cpatch_patch;
use super::grid_flat::{bicubic_flat16, bicubic_flat8, ROW_EDGES};
use super::grid_gregory::gregory_patch;
use super::grid_gregory4::gregory4_patch;
use super::grid_tri::tri_cubic_patch;
#[cfg(target_arch = "x86_64")]
use super::grid_tri::tri_cubic_patch_avx2;
use super::lanes::{
    quad_border, row_curve_lanes, row_points, sample_lanes, store_lanes, LevelWeights, HALF, LANES,
};
use crate::kernels::common::SchemeKernels;
use glam::Vec3;

/// The wide strip of the AVX-512 copy (one ZMM register).
#[cfg(target_arch = "x86_64")]
const WIDE: usize = 16;

/// How one patch's grid is evaluated, chosen once per patch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Path {
    /// Bicubic form: hoisted row curves, vectorised over the columns.
    Bicubic,
    /// Cubic Bézier triangle: vectorised over the samples of a row.
    TriCubic,
    /// PCCM's c-patch: per piece net once, vectorised over each row's run
    /// of samples in a piece ([`super::grid_cpatch`]).
    CPatch,
    /// ACC's extraordinary form: row curves and `U` rows per column, `V`
    /// columns per row ([`super::grid_acc`]).
    Acc,
    /// The Gregory form: outer row curves per column, the blend per sample
    /// ([`super::grid_gregory`]).
    Gregory,
    /// The biquartic Gregory form (`g1cc`): the three twist-free row curves
    /// per column, the blends per sample ([`super::grid_gregory4`]).
    Gregory4,
    /// Any other form: the generated `eval` per sample.
    PerSample,
}

/// The path of every class of `kernels` (index = class).
pub(crate) fn class_paths(kernels: &SchemeKernels) -> Vec<Path> {
    kernels
        .classes
        .iter()
        .map(|c| {
            if kernels.sides == 4 && c.form == "bicubic" && c.control_points == 16 {
                Path::Bicubic
            } else if kernels.sides == 3 && c.form == "tri_cubic" && c.control_points == 16 {
                Path::TriCubic
            } else if kernels.sides == 4 && c.form == "cpatch" && c.control_points == 24 {
                Path::CPatch
            } else if kernels.sides == 4 && c.form == "acc" && c.control_points == 40 {
                Path::Acc
            } else if kernels.sides == 4 && c.form == "gregory" && c.control_points == 20 {
                Path::Gregory
            } else if kernels.sides == 4
                && c.form == "gregory4"
                && c.control_points == 29
                && kernels.edge_curve.len() == 20 * kernels.classes.len()
            {
                Path::Gregory4
            } else {
                Path::PerSample
            }
        })
        .collect()
}

/// The SIMD flavour of this machine, detected once per evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Isa {
    Baseline,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    /// AVX-512F: full bicubic strips of [`WIDE`] columns compiled with
    /// 512-bit registers; everything else is the AVX2 code (compiled with
    /// AVX-512 enabled, the 8-lane loops ran 1.4–1.7× slower). The same
    /// IEEE operations per lane, so the same bits.
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl Isa {
    pub(crate) fn detect() -> Isa {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx2")
            {
                return Isa::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Isa::Avx2;
            }
        }
        Isa::Baseline
    }

    /// Whether AVX2 is available (the AVX2 and the AVX-512 copies): the
    /// construction's lane loops, which have no wider copy, use it.
    pub(crate) fn has_avx2(self) -> bool {
        self != Isa::Baseline
    }

    /// The copy named `name` (`baseline`, `avx2`, `avx512`) if this
    /// machine runs it: what the tests and the bench pin.
    pub(crate) fn named(name: &str) -> Option<Isa> {
        let best = Isa::detect();
        match name {
            "baseline" => Some(Isa::Baseline),
            #[cfg(target_arch = "x86_64")]
            "avx2" if best != Isa::Baseline => Some(Isa::Avx2),
            #[cfg(target_arch = "x86_64")]
            "avx512" if best == Isa::Avx512 => Some(Isa::Avx512),
            _ => None,
        }
    }
}

/// One patch's grid (`(N+1)²` quad samples or `(N+1)(N+2)/2` triangle
/// samples, [`crate::grid`]'s order) into `pos` and `nrm`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn patch_grid(
    kernels: &SchemeKernels,
    path: Path,
    isa: Isa,
    weights: &LevelWeights,
    cp: &[Vec3],
    class: u32,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) {
    let w = weights;
    match path {
        Path::Bicubic => {
            let mut g = [Vec3::ZERO; 16];
            g.copy_from_slice(&cp[..16]);
            let mut curve = [0u32; 16];
            curve.copy_from_slice(&kernels.edge_curve[class as usize * 16..][..16]);
            let degenerate = match isa {
                Isa::Baseline => bicubic_patch::<LANES, false>(&g, &curve, w, level, pos, nrm),
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `Isa::Avx2` is only produced after
                // `is_x86_feature_detected!("avx2")`.
                Isa::Avx2 => unsafe { bicubic_patch_avx2(&g, &curve, w, level, pos, nrm) },
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `Isa::Avx512` is only produced after
                // `is_x86_feature_detected!("avx512f")` and `("avx2")`.
                Isa::Avx512 => unsafe { bicubic_patch_avx512(&g, &curve, w, level, pos, nrm) },
            };
            // A sample with parallel tangents takes its normal from one
            // nudge inside the patch (the generated `eval`): rare enough to
            // redo the whole patch per sample.
            if degenerate {
                per_sample(kernels, cp, class, level, pos, nrm);
            }
        }
        Path::TriCubic => {
            let mut c = [Vec3::ZERO; 16];
            c.copy_from_slice(&cp[..16]);
            let mut curve = [0u32; 12];
            curve.copy_from_slice(&kernels.edge_curve[class as usize * 12..][..12]);
            match isa {
                Isa::Baseline => tri_cubic_patch::<false>(&c, &curve, w, level, pos, nrm),
                #[cfg(target_arch = "x86_64")]
                // SAFETY: as above.
                // (The AVX-512 copy runs the AVX2 code: rows of at most N + 1
                // samples gain nothing from 16 lanes, and the code compiled
                // with AVX-512 enabled ran 1.5–1.7× slower.)
                Isa::Avx2 | Isa::Avx512 => unsafe {
                    tri_cubic_patch_avx2(&c, &curve, w, level, pos, nrm)
                },
            }
        }
        Path::CPatch => {
            let lanes = FormLanes::<24> {
                base: cpatch_patch::<false>,
                #[cfg(target_arch = "x86_64")]
                avx2: cpatch_patch_avx2,
            };
            quad_form(lanes, kernels, isa, w, cp, class, level, pos, nrm)
        }
        Path::Acc => {
            let lanes = FormLanes::<40> {
                base: acc_patch::<false>,
                #[cfg(target_arch = "x86_64")]
                avx2: acc_patch_avx2,
            };
            quad_form(lanes, kernels, isa, w, cp, class, level, pos, nrm)
        }
        Path::Gregory => {
            let lanes = FormLanes::<20> {
                base: gregory_patch::<false>,
                #[cfg(target_arch = "x86_64")]
                avx2: gregory_patch_avx2,
            };
            quad_form(lanes, kernels, isa, w, cp, class, level, pos, nrm)
        }
        Path::Gregory4 => {
            let mut g = [Vec3::ZERO; 29];
            g.copy_from_slice(&cp[..29]);
            let mut curve = [0u32; 20];
            curve.copy_from_slice(&kernels.edge_curve[class as usize * 20..][..20]);
            let degenerate = match isa {
                Isa::Baseline => gregory4_patch::<false>(&g, &curve, w, level, pos, nrm),
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `Isa::Avx2` and `Isa::Avx512` are only produced
                // after `is_x86_feature_detected!("avx2")`.
                Isa::Avx2 | Isa::Avx512 => unsafe {
                    gregory4_patch_avx2(&g, &curve, w, level, pos, nrm)
                },
            };
            if degenerate {
                per_sample(kernels, cp, class, level, pos, nrm);
            }
        }
        Path::PerSample => per_sample(kernels, cp, class, level, pos, nrm),
    }
}

/// [`gregory4_patch`] compiled with AVX2 enabled (the AVX2 and AVX-512
/// copies: rows of at most N + 1 samples gain nothing from 16 lanes).
///
/// # Safety
/// AVX2 must be available.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn gregory4_patch_avx2(
    g: &[Vec3; 29],
    curve: &[u32; 20],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    gregory4_patch::<true>(g, curve, w, level, pos, nrm)
}

/// One patch of a quad form with its own lanes (`P` control points):
/// `(points, EDGE_CURVE entries, weights, level, positions, normals)`,
/// whether a sample's tangents were parallel.
type FormFn<const P: usize> =
    fn(&[Vec3; P], &[u32; 16], &LevelWeights, u32, &mut [Vec3], &mut [Vec3]) -> bool;

/// [`FormFn`] compiled with a target feature.
#[cfg(target_arch = "x86_64")]
type UnsafeFormFn<const P: usize> =
    unsafe fn(&[Vec3; P], &[u32; 16], &LevelWeights, u32, &mut [Vec3], &mut [Vec3]) -> bool;

/// A quad form's two compiled copies: the baseline one and the AVX2 one
/// (which the AVX-512 copy runs too: only full bicubic strips gain from
/// 16 lanes).
struct FormLanes<const P: usize> {
    base: FormFn<P>,
    /// # Safety
    /// AVX2 must be available.
    #[cfg(target_arch = "x86_64")]
    avx2: UnsafeFormFn<P>,
}

/// A patch of an extraordinary quad form (`cpatch`, `acc`, `gregory`) on
/// its lanes, in the copy `isa` names; a patch with a degenerate sample is
/// redone by the generated `eval` per sample, as the bicubic form's.
#[allow(clippy::too_many_arguments)]
fn quad_form<const P: usize>(
    lanes: FormLanes<P>,
    kernels: &SchemeKernels,
    isa: Isa,
    w: &LevelWeights,
    cp: &[Vec3],
    class: u32,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) {
    let mut g = [Vec3::ZERO; P];
    g.copy_from_slice(&cp[..P]);
    let mut curve = [0u32; 16];
    curve.copy_from_slice(&kernels.edge_curve[class as usize * 16..][..16]);
    let degenerate = match isa {
        Isa::Baseline => (lanes.base)(&g, &curve, w, level, pos, nrm),
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `Isa::Avx2` and `Isa::Avx512` are only produced after
        // `is_x86_feature_detected!("avx2")`.
        Isa::Avx2 | Isa::Avx512 => unsafe { (lanes.avx2)(&g, &curve, w, level, pos, nrm) },
    };
    if degenerate {
        per_sample(kernels, cp, class, level, pos, nrm);
    }
}

/// `$name`: the lanes `$lanes::<true>` of a `$p`-point form compiled with
/// AVX2 enabled (the AVX2 and AVX-512 copies of [`FormLanes`]).
macro_rules! avx2_copy {
    ($name:ident, $lanes:ident, $p:literal) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        unsafe fn $name(
            g: &[Vec3; $p],
            curve: &[u32; 16],
            w: &LevelWeights,
            level: u32,
            pos: &mut [Vec3],
            nrm: &mut [Vec3],
        ) -> bool {
            $lanes::<true>(g, curve, w, level, pos, nrm)
        }
    };
}

avx2_copy!(cpatch_patch_avx2, cpatch_patch, 24);
avx2_copy!(acc_patch_avx2, acc_patch, 40);
avx2_copy!(gregory_patch_avx2, gregory_patch, 20);

/// The generated `eval` at every grid point, row by row.
fn per_sample(
    kernels: &SchemeKernels,
    cp: &[Vec3],
    class: u32,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) {
    let mut s = 0usize;
    for iv in 0..=level {
        let row = if kernels.sides == 3 {
            level - iv
        } else {
            level
        };
        for iu in 0..=row {
            let out = (kernels.eval)(cp, class, 0, iu, iv, level);
            pos[s] = out.position;
            nrm[s] = out.normal;
            s += 1;
        }
    }
}

/// A bicubic patch's grid: the surface everywhere, then the border
/// positions from the edge evaluator. Whether a sample's tangents were
/// parallel (`tessgen_patch_normal`'s zero normal).
#[inline(always)]
fn bicubic_patch<const W: usize, const V: bool>(
    g: &[Vec3; 16],
    curve: &[u32; 16],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    // Edges that are the boundary rows and columns: the flat interior
    // writes the border from its row curves.
    let rows = *curve == ROW_EDGES;
    if let Some(degenerate) = bicubic_flat_interior::<W, V>(g, w, level, rows, pos, nrm) {
        if !rows {
            quad_border::<V, 16>(g, curve, w, level, pos);
        }
        return degenerate;
    }
    let degenerate = bicubic_strips::<W, V>(g, w, level, pos, nrm);
    quad_border::<V, 16>(g, curve, w, level, pos);
    degenerate
}

/// The flat interior (`super::grid_flat`) for grids up to
/// `FLAT_MAX_WIDTH` columns, 16 lanes in the AVX-512 copy once a row has a
/// full 16; with `border` also the border (`ROW_EDGES` classes only).
#[inline(always)]
fn bicubic_flat_interior<const W: usize, const V: bool>(
    g: &[Vec3; 16],
    w: &LevelWeights,
    level: u32,
    border: bool,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> Option<bool> {
    #[cfg(target_arch = "x86_64")]
    if W > LANES && level as usize + 1 > W {
        // SAFETY: W > LANES only in the AVX-512 copy (behind `Isa::Avx512`).
        if let Some(degenerate) = unsafe { bicubic_flat_wide(g, w, level, border, pos, nrm) } {
            return Some(degenerate);
        }
    }
    bicubic_flat8::<V>(g, w, level, border, pos, nrm)
}

/// The AVX-512 copy: compiled for AVX2 like [`bicubic_patch_avx2`],
/// except that full strips of [`WIDE`] columns call
/// [`bicubic_strip_wide`], the one loop compiled with 512-bit registers.
/// (The whole patch compiled with AVX-512 enabled ran the 8-lane strips and
/// the border 1.45× slower at N = 9 than the AVX2 copy.)
///
/// # Safety
/// AVX-512F and AVX2 must be available.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn bicubic_patch_avx512(
    g: &[Vec3; 16],
    curve: &[u32; 16],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    bicubic_patch::<WIDE, true>(g, curve, w, level, pos, nrm)
}

/// Columns `c0 .. c0 + WIDE` of a bicubic patch's grid in one ZMM
/// register per lane array.
///
/// # Safety
/// AVX-512F and AVX2 must be available (only [`bicubic_patch_avx512`],
/// behind `Isa::Avx512`, calls it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2")]
unsafe fn bicubic_strip_wide(
    g: &[Vec3; 16],
    w: &LevelWeights,
    level: u32,
    c0: usize,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    bicubic_strip::<WIDE, true>(g, w, level, c0, pos, nrm)
}

/// [`bicubic_flat16`] in ZMM registers.
///
/// # Safety
/// AVX-512F and AVX2 must be available (only the AVX-512 copy calls it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2")]
unsafe fn bicubic_flat_wide(
    g: &[Vec3; 16],
    w: &LevelWeights,
    level: u32,
    border: bool,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> Option<bool> {
    bicubic_flat16::<true>(g, w, level, border, pos, nrm)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn bicubic_patch_avx2(
    g: &[Vec3; 16],
    curve: &[u32; 16],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    bicubic_patch::<LANES, true>(g, curve, w, level, pos, nrm)
}

/// The generated `ordinary_surface` at every grid point of a bicubic patch
/// `g` (16 points, `4k + l`): per strip of `LANES` columns, the row curves
/// `row_k = cubic(g[k], g[4+k], g[8+k], g[12+k], lu, ru)` once per column,
/// then per grid row `along_v = cubic(row points, lv, rv)`, `along_u =
/// cubic(row tangents, lv, rv)`, position `along_v.point`, normal
/// `normalize(along_u.point × along_v.tangent)` — lane by lane. A strip's
/// writes (`LANES` samples of each row) stay in cache. Grids up to
/// `FLAT_MAX_WIDTH` columns take the flat interior instead
/// (`super::grid_flat`: the same operations per sample, lanes across
/// rows); this is the path of wider ones.
#[inline(always)]
pub(crate) fn bicubic_strips<const W: usize, const V: bool>(
    g: &[Vec3; 16],
    w: &LevelWeights,
    level: u32,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let width = level as usize + 1;
    let mut c0 = 0usize;
    let mut degenerate = false;
    while c0 < width {
        // Full strips of W columns, then of 8; a last one of at most 4
        // takes 4 lanes, so little work goes to padding (N = 9: 8 + 4
        // lanes for 10 columns, with W = 16 too; W = 16, N = 33:
        // 16 + 16 + 4).
        let left = width - c0;
        if left <= HALF {
            degenerate |= bicubic_strip::<HALF, V>(g, w, level, c0, pos, nrm);
            c0 += HALF;
        } else if W > LANES && left >= W {
            // SAFETY: W > LANES only in the AVX-512 copy
            // (`bicubic_patch_avx512`, behind `Isa::Avx512`).
            #[cfg(target_arch = "x86_64")]
            {
                degenerate |= unsafe { bicubic_strip_wide(g, w, level, c0, pos, nrm) };
            }
            #[cfg(not(target_arch = "x86_64"))]
            {
                degenerate |= bicubic_strip::<W, V>(g, w, level, c0, pos, nrm);
            }
            c0 += W;
        } else {
            degenerate |= bicubic_strip::<LANES, V>(g, w, level, c0, pos, nrm);
            c0 += LANES;
        }
    }
    degenerate
}

/// Columns `c0 .. c0 + L` (clamped to the grid) of a bicubic patch's grid.
#[inline(always)]
fn bicubic_strip<const L: usize, const V: bool>(
    g: &[Vec3; 16],
    w: &LevelWeights,
    level: u32,
    c0: usize,
    pos: &mut [Vec3],
    nrm: &mut [Vec3],
) -> bool {
    let width = level as usize + 1;
    // Padded lanes repeat column N.
    let (lu, ru) = (w.l_from::<L>(c0), w.r_from::<L>(c0));
    // Row curves of the strip: [row][component] point and tangent.
    let mut pt = [[[0.0f32; L]; 3]; 4];
    let mut tg = [[[0.0f32; L]; 3]; 4];
    for r in 0..4 {
        for c in 0..3 {
            row_curve_lanes(row_points(g, r, c), &lu, &ru, &mut pt[r][c], &mut tg[r][c]);
        }
    }
    let m = (width - c0).min(L);
    let mut degenerate = false;
    for iv in 0..=level as usize {
        let (lv, rv) = (w.l[iv], w.r[iv]);
        let mut out = [[0.0f32; L]; 6];
        degenerate |= sample_lanes(&pt, &tg, lv, rv, &mut out);
        let base = iv * width + c0;
        store_lanes::<L, V>(&out[0], &out[1], &out[2], &mut pos[base..base + m]);
        store_lanes::<L, V>(&out[3], &out[4], &out[5], &mut nrm[base..base + m]);
    }
    degenerate
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::lanes::FLAT_MAX_WIDTH;

    /// A patch with a spread of values. Seeds `0 (mod 4)`: exact zeros of
    /// both signs among them (the border's corners must stay the corner
    /// points' bits); `1`: no zeros, so the flat interior's own border is
    /// its interior (`grid_flat::border_is_interior`); `2`: row 0's points
    /// the smallest negative subnormal, whose row-curve points underflow
    /// to `−0.0` at some columns (the border pass must then run); `3`: an
    /// infinity in row 1 (likewise).
    fn patch(seed: u32) -> [Vec3; 16] {
        let mut g = [Vec3::ZERO; 16];
        let mut h = seed.wrapping_mul(2_654_435_761) | 1;
        for p in g.iter_mut() {
            let mut a = [0.0f32; 3];
            for v in a.iter_mut() {
                h ^= h << 13;
                h ^= h >> 17;
                h ^= h << 5;
                let value = (h >> 8) as f32 / 65_536.0 - 128.0;
                *v = match (seed % 4, h % 7) {
                    (0, 0) => -0.0,
                    (0, 1) => 0.0,
                    (_, _) if value == 0.0 => 1.0,
                    _ => value,
                };
            }
            *p = Vec3::from_array(a);
        }
        match seed % 4 {
            2 => {
                for r in [0, 4, 8, 12] {
                    g[r] = Vec3::splat(f32::from_bits(0x8000_0001));
                }
            }
            3 => g[5].y = f32::INFINITY,
            _ => {}
        }
        g
    }

    /// Writes one patch's grid (positions, normals); whether it was
    /// degenerate, `None` when the path does not take the level.
    type Grid<'a> = &'a dyn Fn(&mut [Vec3], &mut [Vec3]) -> Option<bool>;

    fn bits(v: &[Vec3]) -> Vec<[u32; 3]> {
        v.iter()
            .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .collect()
    }

    /// The flat interior with its own border, and with the edge
    /// evaluator's border, against the column strips with the edge
    /// evaluator's border: the same bits at every level the flat interior
    /// takes, and `None` beyond.
    #[inline(always)]
    fn flat_equals_strips<const V: bool>() {
        for seed in 0..24 {
            let g = patch(seed);
            for level in 1..=(FLAT_MAX_WIDTH as u32 + 2) {
                let w = LevelWeights::new(level);
                let n = ((level + 1) * (level + 1)) as usize;
                let run = |f: Grid| {
                    let (mut p, mut q) = (vec![Vec3::NAN; n], vec![Vec3::NAN; n]);
                    f(&mut p, &mut q).map(|d| (bits(&p), bits(&q), d))
                };
                let strips = run(&|p, q| {
                    let d = bicubic_strips::<LANES, V>(&g, &w, level, p, q);
                    quad_border::<V, 16>(&g, &ROW_EDGES, &w, level, p);
                    Some(d)
                });
                let own = run(&|p, q| bicubic_flat8::<V>(&g, &w, level, true, p, q));
                let edge = run(&|p, q| {
                    let d = bicubic_flat8::<V>(&g, &w, level, false, p, q)?;
                    quad_border::<V, 16>(&g, &ROW_EDGES, &w, level, p);
                    Some(d)
                });
                if level as usize + 1 > FLAT_MAX_WIDTH {
                    assert!(own.is_none() && edge.is_none(), "level {level}");
                    continue;
                }
                assert_eq!(own, strips, "seed {seed} level {level}: own border");
                assert_eq!(edge, strips, "seed {seed} level {level}: edge border");
            }
        }
    }

    #[test]
    fn flat_interior_equals_strips_baseline() {
        flat_equals_strips::<false>();
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn flat_equals_strips_avx2() {
        flat_equals_strips::<true>();
    }

    #[test]
    #[cfg(target_arch = "x86_64")]
    fn flat_interior_equals_strips_avx2() {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: AVX2 was detected.
            unsafe { flat_equals_strips_avx2() };
        }
    }
}
