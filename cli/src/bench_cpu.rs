//! `tessgen bench --backend cpu`: construction per deformation and grid
//! evaluation on a rayon pool of `--threads` threads, each figure next to
//! baselines measured in the same run.
//!
//! Output buffers are allocated and first-touched before the timed runs
//! (the engine case: one reusable [`cpu::Tessellation`]), so the timings
//! are the evaluator's, not the allocator's or the kernel's page-fault
//! handler's. Each figure is the minimum of `--runs` timed runs after one
//! warm-up (the minimum is the least disturbed by other work on the
//! machine). Baselines, same pool, same buffers:
//!
//! * **fill floor**: a plain parallel fill of the same output (24 bytes a
//!   sample: position + normal), the write bandwidth a sample costs at
//!   least;
//! * **per-sample path**: [`cpu::evaluate_per_sample_into`], the generated
//!   `eval` called per sample (what `cpu::evaluate` ran before the grid
//!   path);
//! * **full construct**: [`cpu::construct()`], which also recomputes the
//!   topology-only layout, against [`cpu::Construction::update`].

use super::{BenchArgs, CmdResult};
use glam::Vec3;
use std::process::ExitCode;
use std::time::Instant;
use tessgen_runtime::cpu;
use tessgen_runtime::kernels::common::SchemeKernels;

/// Minimum seconds of `runs` timed calls of `f` after one warm-up call.
fn min_time(runs: usize, mut f: impl FnMut() -> Result<(), String>) -> Result<f64, String> {
    f()?;
    let mut best = f64::INFINITY;
    for _ in 0..runs {
        let t0 = Instant::now();
        f()?;
        best = best.min(t0.elapsed().as_secs_f64());
    }
    Ok(best)
}

/// The pool the bench runs on: `--threads N`, else rayon's default
/// (all cores, or `RAYON_NUM_THREADS`).
pub(crate) fn pool(threads: Option<u32>) -> Result<rayon::ThreadPool, String> {
    let mut b = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        b = b.num_threads(n as usize);
    }
    b.build().map_err(|e| format!("bench: thread pool: {e}"))
}

/// The uniform-grid CPU bench (see the module doc).
pub(crate) fn bench(
    args: &BenchArgs,
    topo: &tessgen_runtime::Topology,
    positions: &[Vec3],
    kernels: &'static SchemeKernels,
    pool: &rayon::ThreadPool,
) -> CmdResult {
    let runs = args.runs as usize;
    pool.install(|| -> CmdResult {
        let patches = if kernels.sides == 3 {
            // Triangle schemes run on the split quads (`--split-quads`);
            // their patch stage has no per-deformation split to time.
            let mesh = super::load_mesh(&args.mesh)?;
            let tri = cpu::tri_mesh(&mesh, true, None).map_err(|e| e.to_string())?;
            let t_full = min_time(runs, || {
                cpu::construct_tri(&tri, kernels)
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            })?;
            println!(
                "{} triangles (split quads); construct (patch stage, fresh buffers): {:.3} ms",
                tri.triangles.len(),
                t_full * 1e3
            );
            cpu::construct_tri(&tri, kernels).map_err(|e| e.to_string())?
        } else {
            let prep = cpu::Construction::new(topo, kernels).map_err(|e| e.to_string())?;
            let mut patches = prep.construct(positions);
            let t_update = min_time(runs, || {
                prep.update(positions, &mut patches)
                    .map_err(|e| e.to_string())
            })?;
            let t_full = min_time(runs, || {
                cpu::construct(topo, positions, kernels)
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            })?;
            println!(
                "construct per deformation (vertex + patch stage into the same buffers): {:.3} ms; full cpu::construct (layout too, fresh buffers): {:.3} ms",
                t_update * 1e3,
                t_full * 1e3
            );
            patches
        };
        let copies = cpu::lane_copies();
        // One column per copy of the lane loops this machine runs.
        let copy_heads: String = copies.iter().map(|c| format!(" {c} ns/sample |")).collect();
        println!("| N | samples | evaluate ms | ns/sample | samples/s | fill floor ns/sample | evaluate / floor | streaming fill floor ns/sample | evaluate / streaming floor | per-sample path ns/sample | per-sample / grid |{copy_heads}");
        println!("|---|---|---|---|---|---|---|---|---|---|---|{}", "---|".repeat(copies.len()));
        for &level in &args.levels {
            if level == 0 || level > cpu::MAX_LEVEL {
                return Err(format!("level {level} out of range 1..={}", cpu::MAX_LEVEL));
            }
            // Allocated and first-touched here, outside every timing.
            let mut t = cpu::evaluate(&patches, level).map_err(|e| e.to_string())?;
            let samples = t.positions.len();
            let per = t.grid_len();
            let t_grid = min_time(runs, || {
                cpu::evaluate_into(&patches, level, &mut t).map_err(|e| e.to_string())
            })?;
            let t_fill = min_time(runs, || {
                fill(&mut t.positions, &mut t.normals, per, level);
                Ok(())
            })?;
            let t_stream = min_time(runs, || {
                stream_fill(&mut t.positions, &mut t.normals, per, level);
                Ok(())
            })?;
            let t_per_sample = min_time(runs, || {
                cpu::evaluate_per_sample_into(&patches, level, &mut t.positions, &mut t.normals)
                    .map_err(|e| e.to_string())
            })?;
            let ns = |s: f64| s * 1e9 / samples as f64;
            // Each copy of the lane loops in the same run (the detected
            // one is what `evaluate` ran above).
            let mut per_copy = Vec::new();
            for c in &copies {
                let t_copy = min_time(runs, || {
                    cpu::evaluate_slices_copy(
                        c,
                        &patches,
                        level,
                        &mut t.positions,
                        &mut t.normals,
                    )
                    .map_err(|e| e.to_string())
                })?;
                per_copy.push(format!(" {:.2} |", ns(t_copy)));
            }
            println!(
                "| {level} | {samples} | {:.3} | {:.2} | {:.3e} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |{}",
                t_grid * 1e3,
                ns(t_grid),
                samples as f64 / t_grid,
                ns(t_fill),
                t_grid / t_fill,
                ns(t_stream),
                t_grid / t_stream,
                ns(t_per_sample),
                t_per_sample / t_grid,
                per_copy.concat(),
            );
        }
        Ok(ExitCode::SUCCESS)
    })
}

/// The write floor: every position and normal of every grid set, one grid
/// per task as the evaluators split the work.
fn fill(positions: &mut [Vec3], normals: &mut [Vec3], per: usize, level: u32) {
    use rayon::prelude::*;
    let v = Vec3::splat(level as f32);
    positions
        .par_chunks_mut(per)
        .zip(normals.par_chunks_mut(per))
        .for_each(|(p, n)| {
            p.fill(v);
            n.fill(v);
        });
}

/// The write floor without reads for ownership: the same fill with
/// streaming (non-temporal) stores, which write whole cache lines without
/// first reading them — what the memory bus allows for the output alone.
/// (SSE's `movntps` is part of x86-64; elsewhere a plain fill.)
fn stream_fill(positions: &mut [Vec3], normals: &mut [Vec3], per: usize, level: u32) {
    use rayon::prelude::*;
    let v = level as f32;
    let put = |dst: &mut [Vec3]| {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_set1_ps, _mm_stream_ps};
            let n = dst.len() * 3;
            let d = dst.as_mut_ptr() as *mut f32;
            let head = ((16 - (d as usize) % 16) % 16 / 4).min(n);
            let body = (n - head) / 4 * 4;
            // SAFETY: `dst` holds `n` floats (`Vec3` is three `f32`s,
            // `#[repr(C)]`); every index is `< n`; `d + head` is 16-byte
            // aligned as `_mm_stream_ps` requires.
            unsafe {
                for i in (0..head).chain(head + body..n) {
                    *d.add(i) = v;
                }
                let x = _mm_set1_ps(v);
                let mut i = head;
                while i < head + body {
                    _mm_stream_ps(d.add(i), x);
                    i += 4;
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        dst.fill(Vec3::splat(v));
    };
    // Tasks of about 256 KiB, one store fence each (as the streamed
    // evaluation).
    let group = ((256 << 10) / (per.max(1) * 24)).max(1);
    positions
        .par_chunks_mut(per * group)
        .zip(normals.par_chunks_mut(per * group))
        .for_each(|(p, n)| {
            put(p);
            put(n);
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `sfence` has no operands and no preconditions.
            unsafe {
                std::arch::x86_64::_mm_sfence()
            };
        });
}
