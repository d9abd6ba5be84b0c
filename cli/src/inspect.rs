//! `tessgen inspect`: the topology report of a mesh (valences, boundaries, creases, corners,
//! holes, sectors, tag warnings, and what tessellation does with each feature).

use super::*;

pub(crate) fn inspect(args: &InspectArgs) -> CmdResult {
    let mesh = load_mesh(&args.mesh)?;
    let stats = MeshStats::of(&mesh);
    let options = TopologyOptions {
        require_quads: false,
        ..cpu::topology_options()
    };
    let topology = Topology::build(&mesh, &options).map_err(|e| e.to_string());
    let features = topology
        .as_ref()
        .ok()
        .map(|t| FeatureStats::of(t, stats.non_quads));
    let path = args.mesh.display().to_string();
    if args.json {
        let report = InspectReport {
            mesh: &path,
            stats: &stats,
            extraordinary_fraction: stats.extraordinary_fraction(),
            topology_ok: topology.is_ok(),
            topology_error: topology.as_ref().err().map(String::as_str),
            features: features.as_ref(),
        };
        let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        println!("{text}");
        return Ok(ExitCode::SUCCESS);
    }
    let s = &stats;
    println!("mesh: {path}");
    println!("vertices: {} ({} unused)", s.vertices, s.unused_vertices);
    println!(
        "faces: {} ({} quads, {} non-quads)",
        s.faces, s.quads, s.non_quads
    );
    println!(
        "edges: {} ({} boundary, {} non-manifold)",
        s.edges, s.boundary_edges, s.non_manifold_edges
    );
    if s.boundary_edges > 0 {
        let first: Vec<String> = s
            .first_boundary_edges
            .iter()
            .map(|(a, b)| format!("{a}->{b}"))
            .collect();
        let more = if s.boundary_edges > first.len() {
            " …"
        } else {
            ""
        };
        println!(
            "boundary edges: {} ({}{more})",
            s.boundary_edges,
            first.join(", ")
        );
    }
    println!("euler characteristic: {}", s.euler_characteristic);
    let histogram: Vec<String> = s
        .valence_histogram
        .iter()
        .map(|(n, count)| format!("{n}:{count}"))
        .collect();
    println!("valence: {}", histogram.join(" "));
    println!(
        "extraordinary faces: {} of {} (eqs {:.3})",
        s.extraordinary_faces,
        s.faces,
        s.extraordinary_fraction()
    );
    let tags: Vec<String> = s.tags.iter().map(|(t, n)| format!("{t}:{n}")).collect();
    println!(
        "tags: {}",
        if tags.is_empty() {
            "none".to_string()
        } else {
            tags.join(" ")
        }
    );
    match &topology {
        Ok(_) if s.non_quads > 0 => println!(
            "topology: ok, {} non-quad faces (the quad schemes run on one Catmull-Clark step)",
            s.non_quads
        ),
        Ok(t) if t.num_boundary_edges() == 0 && t.num_sectors() == 0 => {
            println!("topology: ok (closed, manifold, quads)")
        }
        Ok(t) => println!(
            "topology: ok (manifold, quads; {} boundary edges, {} sectors)",
            t.num_boundary_edges(),
            t.num_sectors()
        ),
        Err(e) => println!("topology: {e}"),
    }
    if let Some(f) = features.as_ref().filter(|f| {
        !(f.tessellation.is_empty() && f.warnings.is_empty() && f.sectors_by_faces.is_empty())
    }) {
        print_features(f);
    }
    Ok(ExitCode::SUCCESS)
}

/// The feature part of `inspect` (open or tagged meshes only, so closed untagged output is
/// unchanged).
fn print_features(f: &FeatureStats) {
    println!("boundary rule: {}", f.boundary_rule);
    println!("boundary edges: {}", f.boundary_edges);
    println!(
        "crease edges: {} ({} infinitely sharp, {} semi-sharp)",
        f.crease_edges_infinite + f.crease_edges_semi_sharp,
        f.crease_edges_infinite,
        f.crease_edges_semi_sharp
    );
    println!(
        "vertices: {} corners ({} tagged), {} creases, {} darts",
        f.corners, f.tagged_corners, f.creases, f.darts
    );
    println!(
        "holes: {} ({} faces without limit)",
        f.holes, f.no_limit_faces
    );
    println!("non-quad faces: {}", f.non_quad_faces);
    let sizes: Vec<String> = f
        .sectors_by_faces
        .iter()
        .map(|(m, n)| format!("{m}:{n}"))
        .collect();
    println!(
        "sectors by faces: {}",
        if sizes.is_empty() {
            "none".into()
        } else {
            sizes.join(" ")
        }
    );
    for line in &f.tessellation {
        println!("tessellation: {line}");
    }
    for w in &f.warnings {
        println!("warning: {w}");
    }
}

/// What `inspect --json` prints.
#[derive(Serialize)]
struct InspectReport<'a> {
    mesh: &'a str,
    #[serde(flatten)]
    stats: &'a MeshStats,
    extraordinary_fraction: f64,
    topology_ok: bool,
    topology_error: Option<&'a str>,
    /// Sharp features and sectors (absent when the topology is rejected).
    features: Option<&'a FeatureStats>,
}
