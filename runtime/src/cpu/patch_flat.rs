//! The flat patch stage: faces whose generated patch kernel only copies
//! vertex-stage outputs (the ordinary class of every built-in quad scheme:
//! the 16 bicubic control points are the corners' `v`, `e` and `f` outputs)
//! become one pre-indexed copy per control point.
//!
//! Which outputs a kernel copies is not read from its source but observed:
//! [`GatherPlan::new`] runs every face's generated kernel on probe
//! `vertex_out` arrays whose entries can each be told apart and named by
//! their bits (the index is in the mantissa of `x`, pseudo-random mantissas
//! in `y` and `z`, a second probe with other bits, and a third of `-0.0`
//! everywhere, which any arithmetic identity such as `v + 0.0` would turn
//! into `+0.0`). A face is flat only if every one of its control points is,
//! in all three probes, exactly the bits of one and the same entry; then
//! the copy gives the kernel's bits for every input. Every other face
//! (extraordinary, or a user scheme that computes) keeps its kernel.

use super::grid_eval::Isa;
use crate::kernels::common::{Inputs, SchemeKernels};
use glam::Vec3;

/// Control points that are plain copies of `vertex_out` entries.
#[derive(Clone, Debug)]
pub(crate) struct GatherPlan {
    /// Per face: whether its control points are copies.
    pub(crate) flat: Vec<bool>,
    /// Per control point of a flat face: its `vertex_out` entry (unused
    /// entries of kernel faces hold `u32::MAX`).
    source: Vec<u32>,
    /// Length of the `vertex_out` the sources index (every source of a
    /// flat face is below it, and below 2^23).
    vertex_outputs: usize,
    isa: Isa,
}

/// Mantissa bits (23) the probe's `x` holds an index in.
const INDEX_BITS: u32 = 23;

impl GatherPlan {
    /// Probes every face's kernel (see the module doc). `inputs` are the
    /// construction's topology arrays; its `vertex_out` is replaced by the
    /// probes. Returns no flat face if `vertex_out` is too long to name
    /// every entry.
    pub(crate) fn new(
        inputs: &Inputs,
        scheme: &SchemeKernels,
        face_class: &[u32],
        cp_offsets: &[u32],
        vertex_outputs: usize,
    ) -> Self {
        let faces = face_class.len();
        let points = cp_offsets.last().copied().unwrap_or(0) as usize;
        let mut plan = GatherPlan {
            flat: vec![false; faces],
            source: vec![u32::MAX; points],
            vertex_outputs,
            isa: Isa::detect(),
        };
        if vertex_outputs >= 1 << INDEX_BITS {
            return GatherPlan::none(faces);
        }
        let probes = [probe(vertex_outputs, 1), probe(vertex_outputs, 2)];
        let zeros = vec![Vec3::splat(-0.0); vertex_outputs];
        let mut outs: Vec<Vec<Vec3>> = Vec::with_capacity(3);
        for vo in probes.iter().chain([&zeros]) {
            let probe_inputs = Inputs {
                vertex_out: vo,
                ..*inputs
            };
            let mut cp = vec![Vec3::NAN; points];
            for f in 0..faces {
                let patch = scheme.classes[face_class[f] as usize].patch;
                patch(&probe_inputs, &mut cp, f as u32, cp_offsets[f]);
            }
            outs.push(cp);
        }
        for f in 0..faces {
            let range = cp_offsets[f] as usize..cp_offsets[f + 1] as usize;
            let sources: Option<Vec<u32>> = range
                .clone()
                .map(|k| {
                    let j = (outs[0][k].x.to_bits() & ((1 << INDEX_BITS) - 1)) as usize;
                    let same = |a: Vec3, b: Vec3| bits(a) == bits(b);
                    (j < vertex_outputs
                        && same(outs[0][k], probes[0][j])
                        && same(outs[1][k], probes[1][j])
                        && same(outs[2][k], zeros[j]))
                    .then_some(j as u32)
                })
                .collect();
            if let Some(s) = sources {
                plan.flat[f] = true;
                plan.source[range].copy_from_slice(&s);
            }
        }
        plan
    }

    /// A plan with no flat face (every face runs its kernel).
    pub(crate) fn none(faces: usize) -> Self {
        GatherPlan {
            flat: vec![false; faces],
            source: Vec::new(),
            vertex_outputs: 0,
            isa: Isa::Baseline,
        }
    }

    /// This plan with the plain copy loop even where AVX2 is available.
    pub(crate) fn force_baseline(&mut self) {
        self.isa = Isa::Baseline;
    }

    /// Control points `a..b` (all of flat faces) into `dst` (`b − a`
    /// long), copied from `vertex_out`.
    pub(crate) fn copy(&self, a: usize, b: usize, vertex_out: &[Vec3], dst: &mut [Vec3]) {
        let source = &self.source[a..b];
        let dst = &mut dst[..source.len()];
        #[cfg(target_arch = "x86_64")]
        if self.isa.has_avx2() && vertex_out.len() >= self.vertex_outputs {
            // SAFETY: AVX2 was detected; every source is below
            // `vertex_outputs` ≤ `vertex_out.len()` and below 2^23.
            unsafe { copy_avx2(source, vertex_out, dst) };
            return;
        }
        for (o, &j) in dst.iter_mut().zip(source) {
            *o = vertex_out[j as usize];
        }
    }
}

/// `dst[k] = vertex_out[source[k]]`, eight points at a time: three
/// gathers (x, y, z of the eight) re-interleaved into the `Vec3` layout by
/// lane permutes and blends, then three 32-byte stores; the bits are moved,
/// never computed.
///
/// # Safety
/// AVX2 must be available; every `source[k]` below `vertex_out.len()` and
/// below 2^23 (so `3·source[k] + 2` fits i32); `dst.len() == source.len()`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn copy_avx2(source: &[u32], vertex_out: &[Vec3], dst: &mut [Vec3]) {
    use std::arch::x86_64::*;
    let base = vertex_out.as_ptr() as *const f32;
    let full = source.len() / 8 * 8;
    let out = dst.as_mut_ptr() as *mut f32;
    let perm = |a: [i32; 8]| unsafe { _mm256_loadu_si256(a.as_ptr() as *const __m256i) };
    // Output register r holds floats 8r..8r+8 of the eight points: float
    // i is component i % 3 of point i / 3.
    let px = [
        perm([0, 0, 0, 1, 0, 0, 2, 0]),
        perm([0, 3, 0, 0, 4, 0, 0, 5]),
        perm([0, 0, 6, 0, 0, 7, 0, 0]),
    ];
    let py = [
        perm([0, 0, 0, 0, 1, 0, 0, 2]),
        perm([0, 0, 3, 0, 0, 4, 0, 0]),
        perm([5, 0, 0, 6, 0, 0, 7, 0]),
    ];
    let pz = [
        perm([0, 0, 0, 0, 0, 1, 0, 0]),
        perm([2, 0, 0, 3, 0, 0, 4, 0]),
        perm([0, 5, 0, 0, 6, 0, 0, 7]),
    ];
    for k in (0..full).step_by(8) {
        // SAFETY: see the function's contract; `k + 8 <= len`.
        unsafe {
            let vi = _mm256_loadu_si256(source.as_ptr().add(k) as *const __m256i);
            let v3 = _mm256_add_epi32(_mm256_add_epi32(vi, vi), vi);
            let x = _mm256_i32gather_ps::<4>(base, v3);
            let y = _mm256_i32gather_ps::<4>(base.add(1), v3);
            let z = _mm256_i32gather_ps::<4>(base.add(2), v3);
            // Blend masks: which floats of register r are y (then z).
            let o0 = _mm256_blend_ps::<0b0010_0100>(
                _mm256_blend_ps::<0b1001_0010>(
                    _mm256_permutevar8x32_ps(x, px[0]),
                    _mm256_permutevar8x32_ps(y, py[0]),
                ),
                _mm256_permutevar8x32_ps(z, pz[0]),
            );
            let o1 = _mm256_blend_ps::<0b0100_1001>(
                _mm256_blend_ps::<0b0010_0100>(
                    _mm256_permutevar8x32_ps(x, px[1]),
                    _mm256_permutevar8x32_ps(y, py[1]),
                ),
                _mm256_permutevar8x32_ps(z, pz[1]),
            );
            let o2 = _mm256_blend_ps::<0b1001_0010>(
                _mm256_blend_ps::<0b0100_1001>(
                    _mm256_permutevar8x32_ps(x, px[2]),
                    _mm256_permutevar8x32_ps(y, py[2]),
                ),
                _mm256_permutevar8x32_ps(z, pz[2]),
            );
            let o = out.add(3 * k);
            _mm256_storeu_ps(o, o0);
            _mm256_storeu_ps(o.add(8), o1);
            _mm256_storeu_ps(o.add(16), o2);
        }
    }
    for (o, &j) in dst[full..].iter_mut().zip(&source[full..]) {
        *o = vertex_out[j as usize];
    }
}

fn bits(v: Vec3) -> [u32; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

/// `len` entries, each nameable by its bits: entry `i` has `i` in the
/// mantissa of `x` (exponent chosen by `seed`) and hashed mantissas in `y`
/// and `z`.
fn probe(len: usize, seed: u32) -> Vec<Vec3> {
    let mantissa = |i: u32, salt: u32| {
        let mut h = i.wrapping_mul(0x9e37_79b9) ^ salt.wrapping_mul(0x85eb_ca6b);
        h ^= h >> 15;
        h = h.wrapping_mul(0x2c1b_3c6d);
        h ^= h >> 12;
        h & ((1 << INDEX_BITS) - 1)
    };
    let exponent = |e: u32| e << INDEX_BITS;
    (0..len as u32)
        .map(|i| {
            Vec3::new(
                f32::from_bits(exponent(127 + seed) | i),
                f32::from_bits(exponent(120 + seed) | mantissa(i, 2 * seed)),
                f32::from_bits(exponent(130 - seed) | mantissa(i, 2 * seed + 1)),
            )
        })
        .collect()
}
