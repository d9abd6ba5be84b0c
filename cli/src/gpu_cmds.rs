//! `render` and `bench`: the commands that run the generated WGSL on a GPU
//! (plus the CPU half of `bench`), thin layers over `tessgen_runtime::gpu`
//! and `tessgen_runtime::render`.

use super::{load_mesh, Backend, BenchArgs, CmdResult, RenderArgs};
use std::process::ExitCode;
use tessgen_runtime::cpu;

pub(crate) fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("--size {s:?}: expected WxH, e.g. 800x600"))?;
    let w: u32 = w
        .trim()
        .parse()
        .map_err(|_| format!("--size {s:?}: bad width"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|_| format!("--size {s:?}: bad height"))?;
    if !(1..=8192).contains(&w) || !(1..=8192).contains(&h) {
        return Err(format!(
            "--size {s:?}: width and height must be in 1..=8192"
        ));
    }
    Ok((w, h))
}

pub(crate) fn parse_camera(s: &str) -> Result<glam::Vec3, String> {
    let (a, e) = s
        .split_once(',')
        .ok_or_else(|| format!("--camera {s:?}: expected AZ,EL in degrees"))?;
    let az: f32 = a
        .trim()
        .parse()
        .map_err(|_| format!("--camera {s:?}: bad azimuth"))?;
    let el: f32 = e
        .trim()
        .parse()
        .map_err(|_| format!("--camera {s:?}: bad elevation"))?;
    let (az, el) = (az.to_radians(), el.to_radians());
    Ok(glam::Vec3::new(
        el.cos() * az.sin(),
        el.sin(),
        el.cos() * az.cos(),
    ))
}

/// Topology and positions of a closed quad mesh, for the GPU commands.
fn gpu_input(
    path: &std::path::Path,
) -> Result<(tessgen_runtime::Topology, Vec<glam::Vec3>), String> {
    let mesh = load_mesh(path)?;
    let topo = tessgen_runtime::Topology::build(&mesh, &cpu::topology_options())
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok((
        topo,
        mesh.positions
            .iter()
            .map(|p| glam::Vec3::from_array(*p))
            .collect(),
    ))
}

/// What `render` and `view` draw: the mesh with its tags applied, refined
/// into one mesh where it needs it (non-quads, semi-sharp creases: uniform
/// steps, [`Request::one_mesh`](tessgen_runtime::tessellate::Request::one_mesh),
/// so the patches meet without T-junctions), its topology marking holes;
/// the per-patch level that keeps the base faces' sample density; the
/// notes on what is not applied exactly.
pub(crate) struct SurfaceInput {
    pub topo: tessgen_runtime::Topology,
    pub positions: Vec<glam::Vec3>,
    /// The mesh evaluated (refined or the input): its `vt` for displacement.
    pub mesh: tessgen_runtime::Mesh,
    /// Uniform refinement steps before the patches (0: none).
    pub steps: u32,
    /// The level of a patch for the requested level of a base face.
    pub level: u32,
    pub notes: Vec<String>,
}

impl SurfaceInput {
    /// The level of a patch for level `n` of a base face (a refined face
    /// is 2^-steps of it).
    pub fn leaf_level(&self, n: u32) -> u32 {
        (n >> self.steps).max(1)
    }
}

/// `command` (`render`, `view`) names the command in errors.
pub(crate) fn surface_input(
    command: &str,
    path: &std::path::Path,
    scheme: &str,
    level: u32,
    adaptive: Option<f32>,
) -> Result<SurfaceInput, String> {
    use tessgen_runtime::tessellate::{AdaptiveRequest, EdgeMetric, Request};
    let mesh = load_mesh(path)?;
    let at = |e: String| format!("{}: {e}", path.display());
    // Before validation, whose triangle-scheme errors suggest options
    // `render` and `view` do not have (--split-quads).
    let quads = |k: &tessgen_runtime::kernels::common::SchemeKernels| k.sides == 4;
    if !tessgen_runtime::kernels::scheme(scheme).is_some_and(quads) {
        return Err(at(format!("`{command}` takes quad schemes, not {scheme}")));
    }
    let request = match adaptive {
        None => Request::uniform(scheme, level),
        // The metric is resolved on the refined topology below; only the
        // refinement of an adaptive request matters here.
        Some(max_factor) => Request::adaptive(
            scheme,
            AdaptiveRequest {
                metric: EdgeMetric::Random {
                    seed: 0,
                    lo: 1.0,
                    hi: 1.0,
                },
                partitioning: tessgen_runtime::adaptive::Partitioning::Integer,
                max_factor,
            },
        ),
    }
    .one_mesh(true);
    let v = request.validate(&mesh).map_err(|e| at(e.to_string()))?;
    let topo = v
        .topology()
        .cloned()
        .ok_or_else(|| at(format!("`{command}` takes quad schemes, not {scheme}")))?;
    let run = v.run_mesh();
    Ok(SurfaceInput {
        topo,
        positions: run
            .positions
            .iter()
            .map(|p| glam::Vec3::from_array(*p))
            .collect(),
        mesh: run.clone(),
        steps: v.refined().map_or(0, |r| r.refinement.levels),
        level: v.refined().map_or(level, |r| r.leaf_level.max(1)),
        notes: v.notes().to_vec(),
    })
}

pub(crate) fn render(args: &RenderArgs) -> CmdResult {
    use tessgen_runtime::render::{Camera, RenderOptions};
    let (w, h) = parse_size(&args.size)?;
    let dir = parse_camera(&args.camera)?;
    let SurfaceInput {
        topo,
        positions,
        level,
        notes,
        ..
    } = surface_input(
        "render",
        &args.mesh,
        &args.scheme,
        args.level,
        args.adaptive.as_ref().map(|_| args.max_factor),
    )?;
    crate::warn_notes(&notes);
    let (mut lo, mut hi) = (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN));
    for p in &positions {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let gpu = tessgen_runtime::gpu::Gpu::new().map_err(|e| e.to_string())?;
    let mesh = tessgen_runtime::gpu::GpuMesh::new(&gpu, &topo, &positions, &args.scheme)
        .map_err(|e| format!("{}: {e}", args.mesh.display()))?;
    let opts = RenderOptions {
        level,
        width: w,
        height: h,
        camera: Camera::framing(lo, hi, dir),
        background: [1.0, 1.0, 1.0, 1.0],
        wireframe: args.wireframe,
    };
    let img = match &args.adaptive {
        None => mesh.render(&opts),
        Some(arg) => {
            use tessgen_runtime::adaptive::{self, Adaptive, Metric, Partitioning};
            let max_level = crate::power_of_two_level(args.max_factor);
            let (_, edges) = adaptive::edge_ids(&topo);
            let metric = match arg.clone() {
                crate::AdaptiveArg::Random { seed, lo, hi } => {
                    Metric::Buffer(adaptive::random_factors(edges, seed, lo, hi))
                }
                crate::AdaptiveArg::Distance(k) => Metric::Distance {
                    eye: opts.camera.eye,
                    scale: k,
                },
                crate::AdaptiveArg::Screen(px) => Metric::Screen {
                    view_proj: opts.camera.view_proj(w as f32 / h as f32),
                    viewport: [w as f32, h as f32],
                    pixels_per_segment: px,
                },
            };
            let a = Adaptive {
                metric,
                partitioning: Partitioning::Integer,
                min: 1.0,
                max: max_level as f32,
            };
            mesh.render_adaptive(&opts, &topo, &a, max_level)
        }
    }
    .map_err(|e| e.to_string())?;
    img.save_png(&args.out).map_err(|e| e.to_string())?;
    eprintln!(
        "tessgen: rendered {} patches {} on {} → {} ({w}x{h})",
        topo.corners.len(),
        match args.adaptive {
            None => format!("at level {level}"),
            Some(_) => format!(
                "adaptively (levels up to {}, GPU-driven indirect draws)",
                crate::power_of_two_level(args.max_factor)
            ),
        },
        gpu.info.name,
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

pub(crate) fn bench(args: &BenchArgs) -> CmdResult {
    use std::time::Instant;
    let (topo, positions) = gpu_input(&args.mesh)?;
    let runs = args.runs as usize;
    let kernels = cpu::scheme(&args.scheme).map_err(|e| e.to_string())?;
    if kernels.sides == 3 && (args.backend == Backend::Wgpu || args.adaptive.is_some()) {
        return Err(format!(
            "bench: triangle scheme `{}` is benched on --backend cpu at uniform levels only \
             (on the mesh's quads split into triangles)",
            args.scheme
        ));
    }
    let gpu = match args.backend {
        Backend::Wgpu => Some(tessgen_runtime::gpu::Gpu::new().map_err(|e| e.to_string())?),
        Backend::Cpu => None,
        Backend::Glsl | Backend::Hlsl => {
            return Err(format!(
                "bench: --backend {} is not supported (cpu or wgpu)",
                args.backend.name()
            ))
        }
    };
    // The pool the CPU figures come from, and its real size (the label
    // once said "2 threads" when RAYON_NUM_THREADS=1 limited the pool).
    let pool = crate::bench_cpu::pool(args.threads)?;
    let device = gpu
        .as_ref()
        .map(|g| g.info.name.clone())
        .unwrap_or_else(|| {
            format!(
                "CPU, {} threads of {} cores",
                pool.current_num_threads(),
                cores()
            )
        });
    let stat = if gpu.is_none() && args.adaptive.is_none() {
        "minimum"
    } else {
        "median"
    };
    println!("# tessgen bench: {} ({} faces), scheme {}, backend {} ({device}), {stat} of {runs} runs after 1 warm-up", args.mesh.display(), topo.corners.len(), args.scheme, args.backend.name());
    if let Some(metric) = &args.adaptive {
        return pool
            .install(|| bench_adaptive(args, metric, &topo, &positions, kernels, gpu.as_ref()));
    }
    let Some(g) = &gpu else {
        return crate::bench_cpu::bench(args, &topo, &positions, kernels, &pool);
    };
    println!("| N | samples | construct ms | evaluate ms | samples/s |");
    println!("|---|---|---|---|---|");
    let mesh = tessgen_runtime::gpu::GpuMesh::new(g, &topo, &positions, &args.scheme)
        .map_err(|e| e.to_string())?;
    for &level in &args.levels {
        let (mut tc, mut te) = (Vec::new(), Vec::new());
        let mut samples = 0;
        for run in 0..=runs {
            let t0 = Instant::now();
            mesh.construct().map_err(|e| e.to_string())?;
            mesh.wait().map_err(|e| e.to_string())?;
            let t1 = Instant::now();
            let t = mesh.evaluate(level).map_err(|e| e.to_string())?;
            let t2 = Instant::now();
            samples = t.positions.len();
            if run > 0 {
                tc.push((t1 - t0).as_secs_f64());
                te.push((t2 - t1).as_secs_f64());
            }
        }
        let (c, e) = (median(tc), median(te));
        println!(
            "| {level} | {samples} | {:.3} | {:.3} | {:.3e} |",
            c * 1e3,
            e * 1e3,
            samples as f64 / (c + e)
        );
    }
    println!("(wgpu: evaluate includes the readback of positions and normals to the CPU)");
    Ok(ExitCode::SUCCESS)
}

/// Median seconds of `runs` timed calls of `f` after one warm-up call,
/// and the value of the last call.
fn timed<T>(runs: usize, mut f: impl FnMut() -> Result<T, String>) -> Result<(f64, T), String> {
    let mut out = f()?;
    let mut ts = Vec::new();
    for _ in 0..runs {
        let t0 = std::time::Instant::now();
        out = f()?;
        ts.push(t0.elapsed().as_secs_f64());
    }
    Ok((median(ts), out))
}

/// `bench --adaptive METRIC`: per largest level L, uniform evaluation at L
/// (the baseline, every patch at L) and the instanced adaptive path with
/// the metric's per-edge factors clamped to [1, L] — on the CPU
/// (`adaptive::evaluate_cpu_adaptive`), or on wgpu both ways the runtime
/// has: host-built lists (classify, read back, lists on the CPU, one
/// dispatch per bucket) and GPU-driven buckets (classify, count, plan,
/// scatter, indirect dispatches, nothing read back before the
/// evaluation). Every column includes the readback of the samples; the
/// control points are built once, outside the timings.
fn bench_adaptive(
    args: &BenchArgs,
    metric: &crate::AdaptiveArg,
    topo: &tessgen_runtime::Topology,
    positions: &[glam::Vec3],
    kernels: &'static tessgen_runtime::kernels::common::SchemeKernels,
    gpu: Option<&tessgen_runtime::gpu::Gpu>,
) -> CmdResult {
    use tessgen_runtime::adaptive::{self, Adaptive, Partitioning};
    let runs = args.runs as usize;
    let edges = adaptive::edge_ids(topo).1;
    let adaptive_at = |level: u32| Adaptive {
        metric: crate::adaptive_metric(edges, positions, Some(metric)),
        partitioning: Partitioning::Integer,
        min: 1.0,
        max: level as f32,
    };
    let levels: Vec<u32> = args
        .levels
        .iter()
        .map(|&l| crate::power_of_two_level(l as f32))
        .collect();
    match gpu {
        None => {
            let patches = cpu::construct(topo, positions, kernels).map_err(|e| e.to_string())?;
            println!("| L | uniform samples | adaptive samples | uniform ms | adaptive ms | uniform samples/s | adaptive samples/s | adaptive / uniform time |");
            println!("|---|---|---|---|---|---|---|---|");
            for level in levels {
                let a = adaptive_at(level);
                let (tu, u) = timed(runs, || {
                    cpu::evaluate(&patches, level).map_err(|e| e.to_string())
                })?;
                let (ta, t) = timed(runs, || {
                    adaptive::evaluate_cpu_adaptive(&patches, topo, &a, level)
                        .map_err(|e| e.to_string())
                })?;
                let (nu, na) = (u.positions.len(), t.positions.len());
                println!(
                    "| {level} | {nu} | {na} | {:.3} | {:.3} | {:.3e} | {:.3e} | {:.3} |",
                    tu * 1e3,
                    ta * 1e3,
                    nu as f64 / tu,
                    na as f64 / ta,
                    ta / tu
                );
            }
        }
        Some(g) => {
            let mesh = tessgen_runtime::gpu::GpuMesh::new(g, topo, positions, &args.scheme)
                .map_err(|e| e.to_string())?;
            mesh.construct().map_err(|e| e.to_string())?;
            mesh.wait().map_err(|e| e.to_string())?;
            println!("| L | uniform samples | adaptive samples | uniform ms | host lists ms | GPU-driven ms | host lists / uniform | GPU-driven / uniform | GPU-driven / host lists |");
            println!("|---|---|---|---|---|---|---|---|---|");
            for level in levels {
                let a = adaptive_at(level);
                let (tu, u) = timed(runs, || mesh.evaluate(level).map_err(|e| e.to_string()))?;
                let (th, h) = timed(runs, || {
                    mesh.evaluate_adaptive_host_lists(topo, &a, level)
                        .map_err(|e| e.to_string())
                })?;
                // The GPU-driven buffers hold every patch at L: past the
                // binding limit only the host lists run (as evaluate_adaptive
                // would choose).
                let driven = timed(runs, || {
                    mesh.evaluate_adaptive_gpu_driven(topo, &a, level)
                        .map_err(|e| e.to_string())
                });
                let (driven_ms, vs_uniform, vs_host) = match driven {
                    Ok((td, d)) => {
                        if h.positions.len() != d.positions.len() {
                            return Err("bench: the two adaptive paths disagree".into());
                        }
                        (
                            format!("{:.3}", td * 1e3),
                            format!("{:.3}", td / tu),
                            format!("{:.3}", td / th),
                        )
                    }
                    Err(e) => {
                        eprintln!("tessgen bench: L = {level}, GPU-driven: {e}");
                        ("—".into(), "—".into(), "—".into())
                    }
                };
                println!(
                    "| {level} | {} | {} | {:.3} | {:.3} | {driven_ms} | {:.3} | {vs_uniform} | {vs_host} |",
                    u.positions.len(),
                    h.positions.len(),
                    tu * 1e3,
                    th * 1e3,
                    th / tu,
                );
            }
            println!(
                "(wgpu: every column includes the readback of positions and normals to the CPU)"
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn cores() -> usize {
    std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
}
