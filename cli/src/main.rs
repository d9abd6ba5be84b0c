//! `tessgen`: the command line over `tessgen-codegen` (scheme compiler and
//! code generation) and `tessgen-runtime` (OBJ meshes, topology, CPU
//! tessellation). One function per subcommand; all real work happens in the
//! libraries.

mod bench_cpu;
mod gpu_cmds;

use clap::{Args, Parser, Subcommand, ValueEnum};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use tessgen_codegen::outdir;
use tessgen_codegen::{Builder, GeneratedFile, SchemeSource, DEFAULT_MAX_VALENCE};
use tessgen_runtime::adaptive::Partitioning;
use tessgen_runtime::displace::{DisplaceError, DisplaceMap, Displacement, Ownership};
use tessgen_runtime::stats::{FeatureStats, MeshStats};
use tessgen_runtime::tags::TagFile;
use tessgen_runtime::tessellate::{
    self, AdaptiveRequest, EdgeMetric, Output as TessOutput, Request,
};
use tessgen_runtime::{cpu, kernels, weld, Mesh, MeshError, Topology, TopologyOptions};

/// Largest `--max-valence` accepted: the table has O(n²) rows of 2n + 1 columns.
const MAX_MAX_VALENCE: u32 = 128;
/// Largest `--level` accepted: a face becomes (N+1)² samples, held in memory and written as text.
const MAX_LEVEL: u32 = 1024;

/// Shader code generation and CPU tessellation for smooth surfaces over quad meshes.
#[derive(Parser, Debug)]
#[command(name = "tessgen", version, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    Generate(GenerateArgs),
    Table(TableArgs),
    Inspect(InspectArgs),
    Tessellate(TessellateArgs),
    Render(RenderArgs),
    Bench(BenchArgs),
    Compare(CompareArgs),
    Refine(refine::RefineArgs),
    View(view::ViewArgs),
}

/// Render a mesh's smooth surface offscreen to a PNG with the generated WGSL (ordinary patches orange, extraordinary blue).
#[derive(Args, Debug)]
pub(crate) struct RenderArgs {
    /// Input OBJ mesh, tags applied (non-quads and semi-sharp creases refined uniformly, holes left out).
    mesh: PathBuf,
    /// Patch scheme (regular, pccm, acc, gregory, gregory-osd, g1cc).
    #[arg(long, default_value = "pccm", value_parser = parse_scheme)]
    scheme: String,
    /// Tessellation level N of every base face (a refined face runs at N/2 per step).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=256))]
    level: u32,
    /// Output PNG.
    #[arg(long, value_name = "IMG.png")]
    out: PathBuf,
    /// Image size.
    #[arg(long, value_name = "WxH", default_value = "800x600")]
    size: String,
    /// Darken patch boundaries (wireframe of the base faces).
    #[arg(long)]
    wireframe: bool,
    /// Camera direction as azimuth,elevation in degrees around the mesh's bounding-box centre.
    #[arg(
        long,
        value_name = "AZ,EL",
        default_value = "35,25",
        allow_hyphen_values = true
    )]
    camera: String,
    /// Adaptive tessellation instead of --level, drawn GPU-driven (indirect draws of the level buckets the GPU builds): `random:SEED[:LO:HI]`, `distance:K` (from this render's eye) or `screen:PX` (projected length in this image over PX pixels per segment).
    #[arg(long, value_name = "METRIC", value_parser = parse_adaptive)]
    adaptive: Option<AdaptiveArg>,
    /// Largest adaptive factor, rounded down to a power of two (at most 64).
    #[arg(long, value_name = "F", default_value_t = 64.0, requires = "adaptive",
          value_parser = parse_max_factor)]
    max_factor: f32,
}

/// Time construction and evaluation per level (warm-up excluded; the CPU backend reports the minimum of the runs, the least disturbed by other load, the GPU backends the median), like Table 4 of the PCCM paper.
#[derive(Args, Debug)]
struct BenchArgs {
    /// Input OBJ mesh (closed, all quads).
    mesh: PathBuf,
    /// Patch scheme (regular, pccm, acc, gregory, gregory-osd, g1cc).
    #[arg(long, default_value = "pccm", value_parser = parse_scheme)]
    scheme: String,
    /// Comma-separated tessellation levels.
    #[arg(long, default_value = "5,9,17,33", value_delimiter = ',')]
    levels: Vec<u32>,
    /// Where the kernels run.
    #[arg(long, value_enum, default_value_t = Backend::Cpu)]
    backend: Backend,
    /// Timed runs per level (after one warm-up run).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    runs: u32,
    /// CPU backend: threads of the rayon pool the bench runs on (default:
    /// rayon's, i.e. every core or `RAYON_NUM_THREADS`).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Bench the instanced adaptive path instead: per largest level L of `--levels` (rounded down to a power of two), uniform evaluation at L against adaptive evaluation with this metric (`random:SEED[:LO:HI]`, `distance:K`, `screen:PX`), on the CPU or on wgpu (host-built lists and GPU-driven buckets), in the same run.
    #[arg(long, value_name = "METRIC", value_parser = parse_adaptive)]
    adaptive: Option<AdaptiveArg>,
}

/// Generate the kernels of every target and the stencil table into a directory, or check that it is up to date.
///
/// The command line recorded in each file's header is normalised to
/// `tessgen generate --out generated` plus any non-default options, so that
/// `--check` compares equal whatever DIR is. With `--check` nothing is
/// written: every generated file must exist in DIR with the same bytes and
/// DIR must hold no other file (its README.md is generated too); each mismatch is
/// printed and the exit code is 1.
#[derive(Args, Debug)]
struct GenerateArgs {
    /// Output directory (the repository keeps its copy in `generated`).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Compare DIR with what would be generated instead of writing; exit 1 on any difference.
    #[arg(long)]
    check: bool,
    /// Largest vertex valence of the stencil table.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_VALENCE,
          value_parser = clap::value_parser!(u32).range(4..=i64::from(MAX_MAX_VALENCE)))]
    max_valence: u32,
    /// Extra scheme file (.tess) compiled next to the built-in schemes; repeat for several.
    #[arg(long = "scheme-file", value_name = "PATH")]
    scheme_files: Vec<PathBuf>,
}

/// Write only the stencil table of the built-in schemes: DIR/stencils.f32 and DIR/stencils.json.
///
/// stencils.f32 is the stencil texture, little-endian f32, row-major: the
/// logical `height × width` rows wrapped into column blocks of 4096 rows;
/// stencils.json is the manifest saying what every row is and the texture size.
#[derive(Args, Debug)]
struct TableArgs {
    /// Output directory (created if missing).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Largest vertex valence of the stencil table.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_VALENCE,
          value_parser = clap::value_parser!(u32).range(4..=i64::from(MAX_MAX_VALENCE)))]
    max_valence: u32,
}

/// Print statistics of an OBJ mesh and whether its topology can be tessellated.
///
/// Reports vertices, faces, quads, edges, boundary edges, Euler
/// characteristic, valence histogram, extraordinary-face fraction ("eqs")
/// and tag counts. Problems of the mesh (boundaries, non-manifold edges,
/// valences too high) are reported, not fatal: the exit code is 0 whenever
/// the OBJ file can be read. Vertex indices are 0-based.
#[derive(Args, Debug)]
struct InspectArgs {
    /// Wavefront OBJ file.
    #[arg(value_name = "MESH")]
    mesh: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Where the generated kernels run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Backend {
    /// The Rust kernels compiled into this binary, in parallel on the CPU.
    Cpu,
    /// The generated WGSL on the GPU through wgpu (any adapter; TESSGEN_ADAPTER picks one).
    Wgpu,
    /// The emitted GLSL tessellation shaders (.vert/.tesc/.tese) in a Vulkan tessellation pipeline (tessellate only; needs glslangValidator and a Vulkan driver, e.g. lavapipe; TESSGEN_VK_DEVICE picks a device).
    Glsl,
    /// The emitted HLSL hull/domain shaders (compiled by glslangValidator -D) in a Vulkan tessellation pipeline (tessellate only).
    Hlsl,
}

impl Backend {
    fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Wgpu => "wgpu",
            Backend::Glsl => "glsl",
            Backend::Hlsl => "hlsl",
        }
    }
}

/// Tessellate an OBJ mesh with a scheme's generated kernels and write the sampled patches as OBJ.
///
/// Every quad face becomes a `g patch_<face>` group of (N+1)² vertices with
/// normals and 2N² triangles, in input face order; a triangle or n-gon becomes
/// one `g patch_<face>_<corner>` group per quad sub-face at level N/2 (N must
/// be even). Boundaries, creases, corners and holes follow the mesh's
/// OpenSubdiv `t` tags (docs/boundaries.md). A one-line summary goes to stderr.
#[derive(Args, Debug)]
struct TessellateArgs {
    /// Wavefront OBJ file (manifold; quads, triangles, n-gons; OpenSubdiv `t` tags).
    #[arg(value_name = "MESH")]
    mesh: PathBuf,
    /// Patch scheme: regular, pccm, acc, gregory, gregory-osd, g1cc (quads; `regular` only handles faces whose corners all have valence 4), pn, stpn, phong (triangles).
    #[arg(long, value_parser = parse_scheme)]
    scheme: String,
    /// Triangle schemes (pn, stpn, phong): split each quad along its v0–v2 diagonal first.
    #[arg(long)]
    split_quads: bool,
    /// Quad schemes: at most K Catmull-Clark steps to apply semi-sharp creases exactly. Only the faces around the crease are refined (feature-adaptive); a leaf of step k runs at level N/2^k, so a level that is not a power of two allows as many steps as its power of two. The regular scheme refines uniformly, at most 2 steps (16x the patches). 0 applies creases as infinitely sharp. Default: as many as the sharpest crease needs (up to 6).
    #[arg(long, value_name = "K", default_value_t = tessgen_runtime::tessellate::refined::DEFAULT_CREASE_REFINEMENT,
          value_parser = clap::value_parser!(u32).range(0..=6))]
    crease_refinement: u32,
    /// Quad schemes with an extraordinary class, uniform level: K Catmull-Clark steps around extraordinary vertices first (OpenSubdiv's isolation level), so the scheme approximates only the faces next to them, 2^-K of the size (feature-adaptive: the rest of the mesh is not refined). 0: the scheme approximates every extraordinary face.
    #[arg(long, value_name = "K", default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=6))]
    isolate: u32,
    /// stpn: crease tags (`tag V [tension T] [sharpness S] [bias B] [delta X Y Z]`, `side F V ±1`; 1-based indices). Without it stpn is plain PN.
    #[arg(long, value_name = "FILE")]
    tags: Option<PathBuf>,
    /// Tessellation level: each face is sampled on an (N+1)×(N+1) grid (triangles: (N+1)(N+2)/2 samples).
    #[arg(long, value_name = "N", required_unless_present = "adaptive",
          value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_LEVEL)))]
    level: Option<u32>,
    /// Adaptive tessellation with per-edge factors: `random:SEED[:LO:HI]` (seeded random factor per edge, default 1..12), `distance:K` (K · edge length / distance of its midpoint to the eye), `screen:PX` (projected length in a 1024×1024 view over PX pixels per segment). The eye looks at the mesh from 2.5 bounding-box diagonals (azimuth 30°, elevation 20°). Every scheme on every backend (triangle schemes on a triangle mesh or with --split-quads, stpn with --tags). glsl/hlsl: the hardware tessellator's triangles; cpu/wgpu: power-of-two edge levels, patches bucketed by level, snapped transitions (quad and triangle grids). Writes an OBJ triangle soup.
    #[arg(long, value_name = "METRIC", value_parser = parse_adaptive)]
    adaptive: Option<AdaptiveArg>,
    /// Partitioning of the adaptive factors: integer, fractional-odd, fractional-even.
    #[arg(long, value_name = "MODE", default_value = "integer", value_parser = parse_partitioning)]
    partitioning: Partitioning,
    /// Largest adaptive factor (clamp; the device allows up to maxTessellationGenerationLevel, 64 on lavapipe).
    #[arg(long, value_name = "F", default_value_t = 64.0, value_parser = parse_max_factor)]
    max_factor: f32,
    /// Output file; its extension chooses the format: `.glb` (glTF 2.0 binary) or `.ply` (binary PLY), one indexed mesh welded by exact position bits (watertight; triangles the weld collapses left out), or anything else OBJ (grids per patch, adaptive results as a triangle soup). All stream to disk chunk by chunk.
    #[arg(long, value_name = "OUT.obj|OUT.glb|OUT.ply")]
    out: PathBuf,
    /// Where the generated kernels run.
    #[arg(long, value_enum, default_value_t = Backend::Cpu)]
    backend: Backend,
    /// Weld the result by exact position bits, print the report, exit 1 unless it is a closed 2-manifold.
    #[arg(long)]
    check_watertight: bool,
    /// Displace along the normal by a scalar map (PNG, luminance in [0, 1], bottom row at vt v = 0), sampled at the OBJ's per-corner texture coordinates (`f v/vt`) with edge/corner ownership, so texture seams stay closed. Every scheme on every backend (triangle schemes pn, stpn, phong with --split-quads for quad meshes, without --tags; glsl/hlsl build the evaluation stage with TESSGEN_DISPLACE), with or without --adaptive (the owner's normal and texture coordinate at each edge's own level).
    #[arg(long, value_name = "MAP.png")]
    displace: Option<PathBuf>,
    /// Displacement scale: position + scale · height · normal.
    #[arg(long, value_name = "S", default_value_t = 1.0, requires = "displace")]
    displace_scale: f32,
    /// Negative control: every patch uses its own normal and texture coordinates on its edges (no ownership); seams crack.
    #[arg(long, requires = "displace")]
    displace_per_patch: bool,
}

/// `--adaptive`: which per-edge metric.
#[derive(Clone, Debug)]
pub(crate) enum AdaptiveArg {
    Random { seed: u64, lo: f32, hi: f32 },
    Distance(f32),
    Screen(f32),
}

fn parse_adaptive(s: &str) -> Result<AdaptiveArg, String> {
    let parts: Vec<&str> = s.split(':').collect();
    let num = |x: &str| -> Result<f32, String> {
        x.parse::<f32>()
            .ok()
            .filter(|v| v.is_finite() && *v > 0.0)
            .ok_or_else(|| format!("`{x}` is not a positive number"))
    };
    match parts.as_slice() {
        ["random", seed] | ["random", seed, _, _] => {
            let seed = seed
                .parse::<u64>()
                .map_err(|_| format!("`{seed}` is not a seed (unsigned integer)"))?;
            let (lo, hi) = if let ["random", _, lo, hi] = parts.as_slice() {
                (num(lo)?, num(hi)?)
            } else {
                (1.0, 12.0)
            };
            if lo > hi {
                return Err(format!("random:{seed}:{lo}:{hi}: LO is above HI"));
            }
            Ok(AdaptiveArg::Random { seed, lo, hi })
        }
        ["distance", k] => Ok(AdaptiveArg::Distance(num(k)?)),
        ["screen", px] => Ok(AdaptiveArg::Screen(num(px)?)),
        _ => Err(format!(
            "unknown adaptive metric `{s}` (random:SEED[:LO:HI], distance:K, screen:PX)"
        )),
    }
}

/// `--max-factor`: factors are clamped to `[1, F]`, so F is a finite number ≥ 1.
fn parse_max_factor(s: &str) -> Result<f32, String> {
    s.parse::<f32>()
        .ok()
        .filter(|f| f.is_finite() && *f >= 1.0)
        .ok_or_else(|| format!("`{s}` is not a number ≥ 1"))
}

fn parse_partitioning(s: &str) -> Result<Partitioning, String> {
    Partitioning::parse(s).ok_or_else(|| {
        format!("unknown partitioning `{s}` (integer, fractional-odd, fractional-even)")
    })
}

/// A command's outcome: `Ok(code)` once it has reported (code 1 for a failed
/// check), `Err(message)` for an error to print.
type CmdResult = Result<ExitCode, String>;

/// A built-in scheme name; `gregory-osd` and `gregory_osd` are the same.
pub(crate) fn parse_scheme(name: &str) -> Result<String, String> {
    match kernels::scheme(name) {
        Some(k) => Ok(k.name.to_string()),
        None => Err(format!(
            "unknown scheme `{name}` (available: {})",
            kernels::scheme_names()
                .iter()
                .map(|n| n.replace('_', "-"))
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

mod inspect;
use inspect::inspect;
mod compare;
mod refine;
mod stream;
mod view;
use compare::{compare, CompareArgs};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Generate(args) => generate(args),
        Command::Table(args) => table(args),
        Command::Inspect(args) => inspect(args),
        Command::Refine(args) => refine::refine_cmd(args),
        Command::Tessellate(args) => tessellate(args),
        Command::Render(args) => gpu_cmds::render(args),
        Command::View(args) => view::view(args),
        Command::Bench(args) => gpu_cmds::bench(args),
        Command::Compare(args) => compare(args),
    };
    result.unwrap_or_else(|message| {
        eprintln!("tessgen: error: {message}");
        ExitCode::FAILURE
    })
}

fn generate(args: &GenerateArgs) -> CmdResult {
    let mut builder = Builder::new().builtin_schemes();
    for path in &args.scheme_files {
        builder = builder.scheme(SchemeSource::from_file(path).map_err(|e| e.to_string())?);
    }
    let output = builder
        .all_targets()
        .max_valence(args.max_valence)
        .command(generate_command_line(args, "generated"))
        .compile()
        .map_err(|e| e.to_string())?;
    let dir = &args.out;
    let label = dir_label(dir);
    if args.check {
        let mismatches = outdir::check(dir, &output.files, &[]).map_err(|e| e.to_string())?;
        for m in &mismatches {
            println!("{}: {}", m.kind(), dir.join(m.path()).display());
        }
        if mismatches.is_empty() {
            println!("{label} is up to date ({} files)", output.files.len());
            return Ok(ExitCode::SUCCESS);
        }
        let again = generate_command_line(args, &quote(&dir.display().to_string()));
        eprintln!(
            "tessgen: {label} is out of date ({} {}); run `{again}`",
            mismatches.len(),
            if mismatches.len() == 1 {
                "mismatch"
            } else {
                "mismatches"
            }
        );
        return Ok(ExitCode::FAILURE);
    }
    let written = outdir::write(dir, &output.files).map_err(|e| e.to_string())?;
    for path in &written {
        println!("wrote {}", dir.join(path).display());
    }
    println!(
        "{label}: {} files, {} changed",
        output.files.len(),
        written.len()
    );
    for path in outdir::extra_files(dir, &output.files, &[]).map_err(|e| e.to_string())? {
        eprintln!(
            "tessgen: warning: {} is not generated by this command (stale?)",
            dir.join(path).display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn table(args: &TableArgs) -> CmdResult {
    let output = Builder::new()
        .builtin_schemes()
        .max_valence(args.max_valence)
        .compile()
        .map_err(|e| e.to_string())?;
    let t = &output.table;
    let files = [
        GeneratedFile {
            path: "stencils.f32".into(),
            contents: t.to_le_bytes(),
        },
        GeneratedFile {
            path: "stencils.json".into(),
            contents: t.manifest_json().into_bytes(),
        },
    ];
    outdir::write(&args.out, &files).map_err(|e| e.to_string())?;
    let schemes: Vec<&str> = output.schemes.iter().map(|s| s.name.as_str()).collect();
    for f in &files {
        println!("wrote {}", args.out.join(&f.path).display());
    }
    println!(
        "stencil table: {} rows × {} f32 in a {} × {} texture (valences 3..={}, schemes {})",
        t.height(),
        t.width,
        t.texture_width(),
        t.texture_height(),
        t.max_valence,
        schemes.join(", ")
    );
    Ok(ExitCode::SUCCESS)
}

/// `--adaptive`: per-edge factors through the front door — the hardware
/// tessellator's triangles (glsl, hlsl) or the instanced path's grids (cpu,
/// wgpu) as an OBJ triangle soup per patch (`g patch_<face>`, `v` per
/// triangle corner, `f` per triangle: [`TessOutput::write_soup`]), streamed
/// to disk window by window, welded exactly with `--check-watertight` (which
/// holds the whole result).
fn tessellate_adaptive(
    mesh: &Mesh,
    args: &TessellateArgs,
    validated: &tessellate::Validated<'_>,
) -> CmdResult {
    let summary = |triangles: usize, ms: f64| {
        eprintln!(
            "tessgen: {} faces → {triangles} triangles ({} adaptive, {:?}, {} backend) in {ms:.2} ms → {}",
            mesh.num_faces(),
            args.scheme,
            args.partitioning,
            args.backend.name(),
            args.out.display()
        )
    };
    if !args.check_watertight {
        let w = stream::write_streamed(validated, &args.mesh, &args.out, true)?;
        summary(w.triangles, w.ms);
        return Ok(ExitCode::SUCCESS);
    }
    let start = Instant::now();
    let out = tessellate::Session::new()
        .run(validated)
        .map_err(|e| format!("{}: {e}", args.mesh.display()))?;
    let tris = out.triangles();
    // An open mesh keeps one open sample edge per segment of each base
    // boundary edge (its own adaptive level, on the instanced path).
    let boundary = validated.expected_open_edges(&out);
    let elapsed = start.elapsed();
    let kept = stream::write_whole(&out, &args.out, true)?;
    summary(
        kept.map_or(tris.len(), |k| k as usize),
        elapsed.as_secs_f64() * 1e3,
    );
    let soup: Vec<glam::Vec3> = tris.iter().flatten().copied().collect();
    let r = weld::weld_triangles(&soup, 3, &[[0, 1, 2]]);
    println!(
        "weld: {} vertices, {} edges, {} triangles, euler {}",
        r.vertices, r.edges, r.triangles, r.euler
    );
    if r.open_edges == 0 && r.overused_edges == 0 {
        println!(
            "watertight: closed 2-manifold ({} degenerate triangles)",
            r.degenerate_triangles
        );
        Ok(ExitCode::SUCCESS)
    } else if boundary > 0 && r.overused_edges == 0 && r.cracks(boundary) == 0 {
        println!(
            "watertight: {} open edges, all on the mesh boundary, no cracks ({} degenerate triangles)",
            r.open_edges, r.degenerate_triangles
        );
        Ok(ExitCode::SUCCESS)
    } else {
        println!(
            "NOT watertight: {} open edges ({} beyond the mesh boundary's {boundary}), {} edges used by more than two triangles",
            r.open_edges,
            r.cracks(boundary),
            r.overused_edges
        );
        Ok(ExitCode::FAILURE)
    }
}

/// The metric of `--adaptive`: random factors for `edges` edges, or the
/// distance/screen metric of [`edge_metric`] (`bench`, which builds its
/// adaptive settings itself).
pub(crate) fn adaptive_metric(
    edges: u32,
    positions: &[glam::Vec3],
    adaptive: Option<&AdaptiveArg>,
) -> tessgen_runtime::adaptive::Metric {
    use tessgen_runtime::adaptive;
    let screen = AdaptiveArg::Screen(8.0);
    match edge_metric(positions, adaptive.unwrap_or(&screen)) {
        EdgeMetric::Random { seed, lo, hi } => {
            adaptive::Metric::Buffer(adaptive::random_factors(edges, seed, lo, hi))
        }
        EdgeMetric::Given(m) => m,
    }
}

/// `--adaptive` for the front door: random factors (drawn there, per edge
/// of the mesh the scheme runs on), or the distance/screen metric with the
/// eye at 2.5 bounding-box diagonals from the mesh centre (azimuth 30°,
/// elevation 20°), looking at the centre.
pub(crate) fn edge_metric(positions: &[glam::Vec3], adaptive: &AdaptiveArg) -> EdgeMetric {
    use glam::Vec3;
    use tessgen_runtime::adaptive::Metric;
    let (lo, hi) = positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(a, b), p| (a.min(*p), b.max(*p)),
    );
    let (center, diag) = ((lo + hi) * 0.5, (hi - lo).length().max(1e-6));
    let (az, el) = (30f32.to_radians(), 20f32.to_radians());
    let eye = center + Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos()) * 2.5 * diag;
    match *adaptive {
        AdaptiveArg::Random { seed, lo, hi } => EdgeMetric::Random { seed, lo, hi },
        AdaptiveArg::Distance(k) => EdgeMetric::Given(Metric::Distance { eye, scale: k }),
        AdaptiveArg::Screen(px) => EdgeMetric::Given(Metric::Screen {
            view_proj: tessgen_runtime::render::Camera {
                eye,
                target: center,
                up: Vec3::Y,
                fov_y: 45.0,
            }
            .view_proj(1.0),
            viewport: [1024.0, 1024.0],
            pixels_per_segment: px,
        }),
    }
}

/// `--max-factor` rounded down to a power of two, within 1 ..= MAX_LEVEL:
/// the instanced path's largest bucket level (the front door's rule).
pub(crate) fn power_of_two_level(max_factor: f32) -> u32 {
    tessellate::power_of_two_level(max_factor)
}

/// `--displace MAP [--displace-scale S] [--displace-per-patch]`.
fn displacement_arg(path: &std::path::Path, args: &TessellateArgs) -> Result<Displacement, String> {
    Ok(Displacement {
        map: DisplaceMap::from_png(path).map_err(|e| match e {
            // Already names the path.
            DisplaceError::Image { .. } => e.to_string(),
            _ => format!("{}: {e}", path.display()),
        })?,
        scale: args.displace_scale,
        ownership: if args.displace_per_patch {
            Ownership::PerPatch
        } else {
            Ownership::LowestFace
        },
    })
}

/// `--backend` as the runtime's backend; glsl and hlsl need the `vulkan` feature.
fn runtime_backend(backend: Backend) -> Result<tessellate::Backend, String> {
    match backend {
        Backend::Cpu => Ok(tessellate::Backend::Cpu),
        Backend::Wgpu => Ok(tessellate::Backend::Wgpu),
        #[cfg(feature = "vulkan")]
        Backend::Glsl => Ok(tessellate::Backend::VulkanGlsl),
        #[cfg(feature = "vulkan")]
        Backend::Hlsl => Ok(tessellate::Backend::VulkanHlsl),
        #[cfg(not(feature = "vulkan"))]
        other => Err(format!(
            "--backend {} needs tessgen built with the `vulkan` feature",
            other.name()
        )),
    }
}

fn tessellate(args: &TessellateArgs) -> CmdResult {
    let mesh = load_mesh(&args.mesh)?;
    let tags = match &args.tags {
        Some(path) => Some(load_tags(path, &mesh)?),
        None => None,
    };
    let displacement = match &args.displace {
        Some(path) => Some(displacement_arg(path, args)?),
        None => None,
    };
    let mut request = match &args.adaptive {
        Some(metric) => {
            let positions: Vec<glam::Vec3> = mesh
                .positions
                .iter()
                .map(|p| glam::Vec3::from_array(*p))
                .collect();
            Request::adaptive(
                &args.scheme,
                AdaptiveRequest {
                    metric: edge_metric(&positions, metric),
                    partitioning: args.partitioning,
                    max_factor: args.max_factor,
                },
            )
        }
        None => Request::uniform(&args.scheme, args.level.unwrap_or(1)),
    }
    .on(runtime_backend(args.backend)?)
    .split_quads(args.split_quads)
    .crease_refinement(args.crease_refinement)
    .isolate(args.isolate);
    if let Some(t) = &tags {
        request = request.tagged(t);
    }
    if let Some(d) = &displacement {
        request = request.displaced(d);
    }
    let validated = request
        .validate(&mesh)
        .map_err(|e| format!("{}: {e}", args.mesh.display()))?;
    warn_notes(validated.notes());
    if args.adaptive.is_some() {
        return tessellate_adaptive(&mesh, args, &validated);
    }
    let level = args.level.unwrap_or(1);
    let per_face = u64::from(level + 1).pow(2);
    let samples = mesh.num_faces() as u64 * per_face;
    if samples > u64::from(u32::MAX) {
        return Err(format!(
            "{}: {} faces at level {} make {samples} samples, more than 2^32 - 1",
            args.mesh.display(),
            mesh.num_faces(),
            level
        ));
    }
    if !args.check_watertight {
        // Nothing needs the whole result: stream it to disk.
        let w = stream::write_streamed(&validated, &args.mesh, &args.out, false)?;
        let summary = match w.other {
            None => format!(
                "{} faces × {} samples = {} samples",
                w.faces,
                w.samples.checked_div(w.faces).unwrap_or(0),
                w.samples
            ),
            Some((patches, vertices, triangles)) => {
                format!("{patches} patches, {vertices} vertices, {triangles} triangles")
            }
        };
        eprintln!(
            "tessgen: {summary} ({} level {}, {} backend) in {:.2} ms → {}",
            args.scheme,
            level,
            args.backend.name(),
            w.ms,
            args.out.display()
        );
        return Ok(ExitCode::SUCCESS);
    }
    let start = Instant::now();
    let out = tessellate::Session::new()
        .run(&validated)
        .map_err(|e| format!("{}: {e}", args.mesh.display()))?;
    let elapsed = start.elapsed();
    let summary = match &out {
        TessOutput::Grid(t) => format!(
            "{} faces × {} samples = {} samples",
            t.faces,
            t.grid_len(),
            t.positions.len()
        ),
        // Triangle schemes on glsl/hlsl: the tessellator's own triangles
        // (its inner vertices are not a grid), in the same OBJ conventions.
        _ => {
            let (patches, vertices, triangles) = out.counts();
            format!("{patches} patches, {vertices} vertices, {triangles} triangles")
        }
    };
    let r = args.check_watertight.then(|| out.weld());
    stream::write_whole(&out, &args.out, false)?;
    eprintln!(
        "tessgen: {summary} ({} level {}, {} backend) in {:.2} ms → {}",
        args.scheme,
        level,
        args.backend.name(),
        elapsed.as_secs_f64() * 1e3,
        args.out.display()
    );
    let Some(r) = r else {
        return Ok(ExitCode::SUCCESS);
    };
    let input_euler = MeshStats::of(&mesh).euler_characteristic;
    println!(
        "weld: {} vertices, {} edges, {} triangles, euler {} (input mesh {})",
        r.vertices, r.edges, r.triangles, r.euler, input_euler
    );
    // An open mesh keeps N open sample edges per base boundary edge: those
    // are the true boundary, anything beyond them is a crack.
    let boundary = validated.expected_open_edges(&out);
    if boundary > 0
        && r.overused_edges == 0
        && r.degenerate_triangles == 0
        && r.cracks(boundary) == 0
    {
        println!(
            "watertight: {} open edges, all on the mesh boundary ({} base edges × level {level}), no cracks",
            r.open_edges,
            boundary / level as usize
        );
        return Ok(ExitCode::SUCCESS);
    }
    if r.is_closed_manifold() {
        println!("watertight: closed 2-manifold");
        if r.euler != input_euler {
            eprintln!("tessgen: warning: the welded surface's euler characteristic differs from the input's");
        }
        Ok(ExitCode::SUCCESS)
    } else {
        println!(
            "NOT watertight: {} open edges ({} cracks beyond the {boundary} of the mesh boundary), {} edges used by more than two triangles, {} degenerate triangles",
            r.open_edges, r.cracks(boundary), r.overused_edges, r.degenerate_triangles
        );
        Ok(ExitCode::FAILURE)
    }
}

/// Prints every tag or feature the tessellation does not apply as written
/// (tag warnings, refinement notes: [`tessellate::Validated::notes`]):
/// never silently.
pub(crate) fn warn_notes(notes: &[String]) {
    const SHOWN: usize = 4;
    for w in notes.iter().take(SHOWN) {
        eprintln!("tessgen: warning: {w}");
    }
    if notes.len() > SHOWN {
        eprintln!(
            "tessgen: warning: … and {} more tag warnings (all listed by `tessgen inspect`)",
            notes.len() - SHOWN
        );
    }
}

/// The `generate` command line for `out`, without `--check`: recorded in
/// file headers (with `out = "generated"`) and suggested after a failed check.
fn generate_command_line(args: &GenerateArgs, out: &str) -> String {
    let mut line = format!("tessgen generate --out {out}");
    if args.max_valence != DEFAULT_MAX_VALENCE {
        line.push_str(&format!(" --max-valence {}", args.max_valence));
    }
    for path in &args.scheme_files {
        line.push_str(" --scheme-file ");
        line.push_str(&quote(&path.display().to_string()));
    }
    line
}

/// `s` as one shell word when it needs quoting; always a single line, so it is
/// safe inside a generated file's `//` header comment.
fn quote(s: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "-_./+:=@%,".contains(c);
    if !s.is_empty() && s.chars().all(plain) {
        s.to_string()
    } else {
        format!("{s:?}")
    }
}

/// `dir` as `name/` for messages.
fn dir_label(dir: &Path) -> String {
    let s = dir.display().to_string();
    format!("{}/", s.trim_end_matches('/'))
}

/// A tag file for `mesh` (stpn), errors naming the file and line.
fn load_tags(path: &Path, mesh: &Mesh) -> Result<TagFile, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    TagFile::parse(&text, mesh.num_vertices(), mesh.num_faces(), |f| {
        mesh.face(f)
    })
    .map_err(|e| format!("{}: {e}", path.display()))
}

fn load_mesh(path: &Path) -> Result<Mesh, String> {
    Mesh::from_obj_path(path).map_err(|e| match e {
        // Already names the path.
        MeshError::Io { .. } => e.to_string(),
        _ => format!("{}: {e}", path.display()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_is_well_formed() {
        Cli::command().debug_assert();
    }

    #[test]
    fn command_line_is_normalised() {
        let parse = |argv: &[&str]| match Cli::parse_from(argv).command {
            Command::Generate(a) => a,
            other => panic!("{other:?}"),
        };
        let a = parse(&["tessgen", "generate", "--out", "/tmp/x", "--check"]);
        assert_eq!(
            generate_command_line(&a, "generated"),
            "tessgen generate --out generated"
        );
        let a = parse(&[
            "tessgen",
            "generate",
            "--out",
            "x",
            "--max-valence",
            "8",
            "--scheme-file",
            "a b.tess",
            "--scheme-file",
            "c.tess",
        ]);
        assert_eq!(
            generate_command_line(&a, "generated"),
            "tessgen generate --out generated --max-valence 8 --scheme-file \"a b.tess\" --scheme-file c.tess"
        );
        assert_eq!(quote("a\nb"), "\"a\\nb\"");
    }
}
