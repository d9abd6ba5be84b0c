//! `tessgen compare`: each scheme against the exact Catmull-Clark limit
//! (the accuracy table of docs/accuracy.md) and, with `--heatmap`, where on
//! the surface it deviates.

use crate::{gpu_cmds, load_mesh, parse_scheme, CmdResult};
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;
use tessgen_runtime::tessellate::Request;
use tessgen_runtime::Mesh;

/// Compare schemes with the exact Catmull-Clark limit: distance (% of local quad size), normal deviation, boundary smoothness (shading-normal spread, and the geometric normal jump: a finite-difference estimate from tessellated positions), watertightness.
#[derive(Args, Debug)]
pub(crate) struct CompareArgs {
    /// Input OBJ mesh (OpenSubdiv tags applied; non-quads and semi-sharp creases through the refinement, as `tessellate` runs them).
    mesh: PathBuf,
    /// Comma-separated schemes (regular, pccm, acc, gregory, gregory-osd, g1cc).
    #[arg(long, default_value = "pccm", value_delimiter = ',', value_parser = parse_scheme)]
    schemes: Vec<String>,
    /// Level for the smoothness and watertightness columns (the limit comparison uses the reference's grid; the geometric normal jump is always estimated at level 128).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=256))]
    level: u32,
    /// At most K Catmull-Clark steps for semi-sharp creases (as `tessellate --crease-refinement`; default: as many as the crease needs).
    #[arg(long, value_name = "K", default_value_t = tessgen_runtime::tessellate::refined::DEFAULT_CREASE_REFINEMENT,
          value_parser = clap::value_parser!(u32).range(0..=6))]
    crease_refinement: u32,
    /// Catmull-Clark steps around extraordinary vertices before the scheme takes over (as `tessellate --isolate`).
    #[arg(long, value_name = "K", default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=6))]
    isolate: u32,
    /// Limit samples: a CCLIM001 .bin file, or a directory holding NAME.bin for a mesh NAME.obj.
    #[arg(long, value_name = "DIR|FILE")]
    reference: Option<PathBuf>,
    /// Print JSON instead of a Markdown table.
    #[arg(long)]
    json: bool,
    /// Also write heat maps of each scheme's deviation from the limit (needs --reference): OUT.png coloured by distance (% of the local quad size) and OUT_normal.png by normal angle (degrees), one colour range for all schemes (0 to the 99th percentile of their samples; above it saturates); with several schemes OUT_SCHEME.png and OUT_SCHEME_normal.png.
    #[arg(long, value_name = "OUT.png", requires = "reference")]
    heatmap: Option<PathBuf>,
    /// Heat map view direction: azimuth and elevation in degrees.
    #[arg(
        long,
        value_name = "AZ,EL",
        default_value = "35,25",
        requires = "heatmap"
    )]
    camera: String,
    /// Heat map size in pixels.
    #[arg(
        long,
        value_name = "WxH",
        default_value = "480x360",
        requires = "heatmap"
    )]
    size: String,
}

pub(crate) fn compare(args: &CompareArgs) -> CmdResult {
    use tessgen_runtime::accuracy::{self, LimitError, LimitSamples};
    let mesh = load_mesh(&args.mesh)?;
    let limit = match &args.reference {
        None => None,
        Some(r) => {
            let path = if r.is_dir() {
                let stem = args
                    .mesh
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default();
                r.join(format!("{stem}.bin"))
            } else {
                r.clone()
            };
            let lim = LimitSamples::load(&path).map_err(|e| e.to_string())?;
            if lim.faces != mesh.num_faces() {
                return Err(LimitError::FaceCount {
                    path: path.display().to_string(),
                    file: lim.faces,
                    mesh: mesh.num_faces(),
                }
                .to_string());
            }
            Some(lim)
        }
    };
    let mut rows = Vec::new();
    let mut failed = false;
    if let (Some(out), Some(lim)) = (&args.heatmap, limit.as_ref()) {
        failed |= heatmaps(args, &mesh, lim, out)?;
    }
    for scheme in &args.schemes {
        let request = Request::uniform(scheme, args.level)
            .crease_refinement(args.crease_refinement)
            .isolate(args.isolate);
        match accuracy::compare_with(&mesh, &request, limit.as_ref()) {
            Ok(r) => rows.push(r),
            Err(e) => {
                // The other schemes' rows still print; the exit code is 1.
                eprintln!("tessgen: error: {scheme}: {e}");
                failed = true;
            }
        }
    }
    let name = args
        .mesh
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    if args.json {
        let text = serde_json::to_string_pretty(&rows).map_err(|e| e.to_string())?;
        println!("{text}");
    } else {
        print!("{}", accuracy::markdown(&name, &rows));
    }
    Ok(if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// `compare --heatmap`: every scheme's deviation, one colour range per
/// measure for all of them, two PNGs per scheme. Whether a scheme failed
/// (its error printed; the others still drawn).
fn heatmaps(
    args: &CompareArgs,
    mesh: &Mesh,
    lim: &tessgen_runtime::accuracy::LimitSamples,
    out: &std::path::Path,
) -> Result<bool, String> {
    use tessgen_runtime::heatmap::{self, HeatOptions, Unit};
    let view = gpu_cmds::parse_camera(&args.camera)?;
    let (width, height) = gpu_cmds::parse_size(&args.size)?;
    let mut failed = false;
    let mut devs = Vec::new();
    for scheme in &args.schemes {
        let request = Request::uniform(scheme, args.level)
            .crease_refinement(args.crease_refinement)
            .isolate(args.isolate);
        match tessgen_runtime::accuracy::deviation(mesh, &request, lim) {
            Ok(d) => devs.push((scheme, d)),
            Err(e) => {
                eprintln!("tessgen: error: {scheme}: {e}");
                failed = true;
            }
        }
    }
    // One colour range per measure for every scheme: the 99th percentile
    // of all their samples (the few above it saturate).
    let dmax = heatmap::quantile(devs.iter().map(|(_, d)| &d.distance_pct[..]), 0.99);
    let nmax = heatmap::quantile(devs.iter().map(|(_, d)| &d.normal_deg[..]), 0.99);
    let stem = out.with_extension("");
    let name = |scheme: &str, what: &str| {
        let mut s = stem.as_os_str().to_owned();
        if args.schemes.len() > 1 {
            s.push(format!("_{scheme}"));
        }
        s.push(what);
        s.push(".png");
        PathBuf::from(s)
    };
    for (scheme, d) in &devs {
        for (values, max, unit, what) in [
            (&d.distance_pct, dmax, Unit::Percent, ""),
            (&d.normal_deg, nmax, Unit::Degrees, "_normal"),
        ] {
            let opts = HeatOptions {
                width,
                height,
                max,
                unit,
                view,
            };
            let img = heatmap::render(&d.grid, values, &opts);
            let path = name(scheme, what);
            image::save_buffer(
                &path,
                &img.rgb,
                img.width,
                img.height,
                image::ExtendedColorType::Rgb8,
            )
            .map_err(|e| format!("{}: {e}", path.display()))?;
            eprintln!(
                "tessgen: {scheme}: heat map (0 .. {max:.3}) → {}",
                path.display()
            );
        }
    }
    Ok(failed)
}
