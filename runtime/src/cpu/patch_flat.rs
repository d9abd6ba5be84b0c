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
    /// Whether [`GatherPlan::copy`] moves 16 bytes a point (x86_64, unless
    /// [`GatherPlan::force_baseline`]) rather than a `Vec3`.
    wide: bool,
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
            wide: cfg!(target_arch = "x86_64"),
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
            wide: false,
        }
    }

    /// The `vertex_out` entries the flat faces copy (each once per control
    /// point that copies it).
    pub(crate) fn sources(&self) -> impl Iterator<Item = u32> + '_ {
        self.source.iter().copied().filter(|&j| j != u32::MAX)
    }

    /// This plan with the plain `Vec3` copy loop even on x86_64.
    pub(crate) fn force_baseline(&mut self) {
        self.wide = false;
    }

    /// Control points `a..b` (all of flat faces) into `dst` (`b − a`
    /// long), copied from `vertex_out`.
    pub(crate) fn copy(&self, a: usize, b: usize, vertex_out: &[Vec3], dst: &mut [Vec3]) {
        let source = &self.source[a..b];
        let dst = &mut dst[..source.len()];
        #[cfg(target_arch = "x86_64")]
        if self.wide {
            copy_wide(source, vertex_out, dst);
            return;
        }
        for (o, &j) in dst.iter_mut().zip(source) {
            *o = vertex_out[j as usize];
        }
    }
}

/// `dst[k] = vertex_out[source[k]]` with one 16-byte load and one 16-byte
/// store per point: the load takes the next entry's `x` along, and the
/// store writes it over `dst[k + 1].x`, which the next point's store then
/// replaces. The bits are moved, never computed. The last point (whose 16
/// bytes would end past `dst`, possibly in another task's slice) and a
/// source at the very end of `vertex_out` are copied as `Vec3`.
///
/// This replaced an AVX2 loop of three 8-lane gathers and nine permutes
/// per eight points, which ran fewer instructions but took longer: the
/// copy reads `vertex_out` (4.3 MB on `righthanded_L3`) from beyond L2,
/// and one plain load per point keeps more of those reads in flight than
/// three gathers (pccm construction per deformation 1.85–1.93 →
/// 1.41–1.52 ms on a Zen 3, docs/performance-log.md).
#[cfg(target_arch = "x86_64")]
fn copy_wide(source: &[u32], vertex_out: &[Vec3], dst: &mut [Vec3]) {
    use std::arch::x86_64::{_mm_loadu_ps, _mm_storeu_ps};
    let n = source.len().min(dst.len());
    let Some(last) = n.checked_sub(1) else {
        return;
    };
    let end = vertex_out.len().saturating_sub(1);
    let from = vertex_out.as_ptr() as *const f32;
    let to = dst.as_mut_ptr() as *mut f32;
    for (k, &j) in source[..last].iter().enumerate() {
        let j = j as usize;
        if j < end {
            // SAFETY: `j + 1 < vertex_out.len()`, so the 16 bytes from
            // entry `j` lie inside `vertex_out`; `k + 1 < n ≤ dst.len()`,
            // so the 16 bytes from `dst[k]` lie inside `dst`. SSE is part
            // of x86_64.
            unsafe { _mm_storeu_ps(to.add(3 * k), _mm_loadu_ps(from.add(3 * j))) };
        } else {
            dst[k] = vertex_out[j];
        }
    }
    dst[last] = vertex_out[source[last] as usize];
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
