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
//! `gregory` (`gregory`, `gregory_osd`: [`super::grid_gregory`]). A form
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
use super::grid_flat::{bicubic_flat16, bicubic_flat8, FlatWeights, ROW_EDGES};
use super::grid_gregory::gregory_patch;
use super::grid_tri::tri_cubic_patch;
#[cfg(target_arch = "x86_64")]
use super::grid_tri::tri_cubic_patch_avx2;
use crate::kernels::common::SchemeKernels;
use glam::Vec3;

/// Lane granularity the column strips are padded to (one AVX2 register).
/// Lane weights convert their integers through `i32` (levels are at most
/// `MAX_LEVEL` = 4096, so every integer is exact in f32 either way and the
/// bits are those of the generated `u32 as f32`): x86 has a packed
/// signed conversion, not an unsigned one, before AVX-512.
pub(crate) const LANES: usize = 8;
/// The wide strip of the AVX-512 copy (one ZMM register).
#[cfg(target_arch = "x86_64")]
const WIDE: usize = 16;
/// The narrower strip for a grid's last few columns (one SSE register).
pub(crate) const HALF: usize = 4;
/// `tessgen_patch_normal`'s threshold, from the ABI codegen declares
/// (tests/tests/grid_path.rs checks this path against the generated `eval`
/// on patches with parallel tangents).
use crate::abi::PARALLEL_SIN2;

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
    /// Any other form: the generated `eval` per sample.
    PerSample,
}

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
        Path::PerSample => per_sample(kernels, cp, class, level, pos, nrm),
    }
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
        let (l, r) = (l[k], r[k]);
        let c0 = (b[0] * l) + (b[1] * r);
        let c1 = (b[1] * l) + (b[2] * r);
        let c2 = (b[2] * l) + (b[3] * r);
        let d0 = (c0 * l) + (c1 * r);
        let d1 = (c1 * l) + (c2 * r);
        point[k] = (d0 * l) + (d1 * r);
        tangent[k] = (d1 - d0) * 3.0f32;
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
fn sample_lanes<const L: usize>(
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
        let (l, r) = (l[k], r[k]);
        let along = |a: &[[[f32; C]; 3]; 4], c: usize| {
            let j = o + k;
            cubic(a[0][c][j], a[1][c][j], a[2][c][j], a[3][c][j], l, r)
        };
        let (x, tvx) = along(pt, 0);
        let (y, tvy) = along(pt, 1);
        let (z, tvz) = along(pt, 2);
        let (ux, _) = along(tg, 0);
        let (uy, _) = along(tg, 1);
        let (uz, _) = along(tg, 2);
        let ([nx, ny, nz], parallel) = patch_normal([ux, uy, uz], [tvx, tvy, tvz]);
        degenerate |= parallel;
        out[0][k] = x;
        out[1][k] = y;
        out[2][k] = z;
        out[3][k] = nx;
        out[4][k] = ny;
        out[5][k] = nz;
    }
    degenerate
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
    let cx = (a[1] * b[2]) - (b[1] * a[2]);
    let cy = (a[2] * b[0]) - (b[2] * a[0]);
    let cz = (a[0] * b[1]) - (b[0] * a[1]);
    let c2 = ((cx * cx) + (cy * cy)) + (cz * cz);
    let aa = ((a[0] * a[0]) + (a[1] * a[1])) + (a[2] * a[2]);
    let bb = ((b[0] * b[0]) + (b[1] * b[1])) + (b[2] * b[2]);
    let parallel = c2 <= PARALLEL_SIN2 * (aa * bb);
    let len = c2.sqrt();
    let n = [
        if parallel { 0.0 } else { cx / len },
        if parallel { 0.0 } else { cy / len },
        if parallel { 0.0 } else { cz / len },
    ];
    (n, parallel)
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
        let (l, r) = (l[k], r[k]);
        let c0 = (b[0] * l) + (b[1] * r);
        let c1 = (b[1] * l) + (b[2] * r);
        let c2 = (b[2] * l) + (b[3] * r);
        let d0 = (c0 * l) + (c1 * r);
        let d1 = (c1 * l) + (c2 * r);
        out[k] = (d0 * l) + (d1 * r);
    }
}
