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
#[derive(Clone, Debug, Default)]
pub(crate) struct GatherPlan {
    /// Per face: whether its control points are copies.
    pub(crate) flat: Vec<bool>,
    /// Per control point of a flat face: its `vertex_out` entry (unused
    /// entries of kernel faces hold `u32::MAX`).
    pub(crate) source: Vec<u32>,
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
        };
        if vertex_outputs >= 1 << INDEX_BITS {
            return plan;
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
