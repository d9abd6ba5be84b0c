//! `tessgen refine`: the uniform Catmull-Clark refinement the quad schemes
//! run on (docs/boundaries.md §8), written out for a host that keeps the
//! refined mesh itself or refines on its GPU (the emitted `refine_main`
//! indexes exactly this table: bindings 34–38 of generated/README.md): the
//! refined mesh as OBJ with its remaining tags, and the flat stencil table
//! over the base vertices.

use std::fmt::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use tessgen_runtime::mesh::features::Features;
use tessgen_runtime::mesh::refine::{self, Refinement};

use super::{load_mesh, CmdResult};

/// Refine a mesh by uniform Catmull-Clark steps (OpenSubdiv's Sdc rules, tags applied) and write `refined.obj` (the all-quad mesh with its remaining `t` tags), `stencils.bin` (every refined vertex as a row over the base vertices) and `refinement.json` (counts and the base face / sub-face / leaf of every refined face).
#[derive(Args, Debug)]
pub(crate) struct RefineArgs {
    /// Wavefront OBJ file (OpenSubdiv `t` tags applied).
    mesh: PathBuf,
    /// Steps; default: what the mesh needs (1 for non-quads, ⌈s⌉ for semi-sharp creases), at most 6.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=6))]
    levels: Option<u32>,
    /// Output directory.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
}

pub(crate) fn refine_cmd(args: &RefineArgs) -> CmdResult {
    let mesh = load_mesh(&args.mesh)?;
    let (features, warnings) =
        Features::from_mesh(&mesh).map_err(|e| format!("{}: {e}", args.mesh.display()))?;
    for w in &warnings {
        eprintln!("tessgen: warning: {w}");
    }
    let need = refine::need(&mesh, &features);
    let levels = args
        .levels
        .unwrap_or(need.levels().clamp(1, refine::MAX_REFINE_LEVELS));
    let r = refine::refine(
        &mesh,
        &features,
        levels,
        tessgen_runtime::cpu::topology_options().max_valence,
    )
    .map_err(|e| format!("{}: {e}", args.mesh.display()))?;
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let write = |name: &str, bytes: &[u8]| {
        let path = args.out.join(name);
        std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))
    };
    write("refined.obj", refined_obj(&r).as_bytes())?;
    write("stencils.bin", &stencils_bin(&r, mesh.num_vertices()))?;
    write(
        "refinement.json",
        manifest(&r, mesh.num_vertices()).as_bytes(),
    )?;
    eprintln!(
        "tessgen: {} faces, {} vertices → {} steps → {} quads, {} vertices ({} stencil terms, at most {} per row) → {}",
        mesh.num_faces(),
        mesh.num_vertices(),
        r.levels,
        r.mesh.num_faces(),
        r.mesh.num_vertices(),
        r.stencils.indices.len(),
        r.stencils.max_row_len(),
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// The refined mesh with `t` lines for what is left of the features.
fn refined_obj(r: &Refinement) -> String {
    let mut s = format!(
        "# tessgen {} refine: {} steps\n",
        env!("CARGO_PKG_VERSION"),
        r.levels
    );
    for p in &r.mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
    }
    for f in 0..r.mesh.num_faces() {
        let face = r.mesh.face(f);
        let _ = writeln!(
            s,
            "f {} {} {} {}",
            face[0] + 1,
            face[1] + 1,
            face[2] + 1,
            face[3] + 1
        );
    }
    let f = &r.features;
    let _ = writeln!(s, "t interpolateboundary 1/0/0 {}", f.boundary.tag_value());
    for (&(a, b), &x) in &f.edge_sharpness {
        let _ = writeln!(s, "t crease 2/1/0 {a} {b} {x}");
    }
    for (&v, &x) in &f.vertex_sharpness {
        let _ = writeln!(s, "t corner 1/1/0 {v} {x}");
    }
    if !f.holes.is_empty() {
        let holes: Vec<String> = f.holes.iter().map(u32::to_string).collect();
        let _ = writeln!(s, "t hole {}/0/0 {}", holes.len(), holes.join(" "));
    }
    s
}

/// `TGSTEN01`, then u32 rows, terms, base vertices, 0; then `offsets`
/// (rows + 1 u32), `indices` (terms u32), `weights` (terms f32), all
/// little-endian: row `r` is `Σ positions[indices[k]] · weights[k]` for
/// `k` in `offsets[r]..offsets[r+1]`, summed in that order from 0.
fn stencils_bin(r: &Refinement, base_vertices: usize) -> Vec<u8> {
    let t = &r.stencils;
    let mut out = b"TGSTEN01".to_vec();
    for x in [t.rows(), t.indices.len(), base_vertices, 0] {
        out.extend_from_slice(&(x as u32).to_le_bytes());
    }
    for x in t.offsets.iter().chain(&t.indices) {
        out.extend_from_slice(&x.to_le_bytes());
    }
    for w in &t.weights {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out
}

fn manifest(r: &Refinement, base_vertices: usize) -> String {
    let blocks: Vec<serde_json::Value> = r
        .blocks
        .iter()
        .map(|b| serde_json::json!([b.face, b.corner.map_or(-1i64, i64::from), b.depth]))
        .collect();
    let leaves: Vec<serde_json::Value> = r
        .leaves
        .iter()
        .map(|l| serde_json::json!([l.block, l.x, l.y]))
        .collect();
    let j = serde_json::json!({
        "levels": r.levels,
        "base_vertices": base_vertices,
        "refined_vertices": r.mesh.num_vertices(),
        "refined_faces": r.mesh.num_faces(),
        "stencil_terms": r.stencils.indices.len(),
        "max_row_len": r.stencils.max_row_len(),
        "blocks": "per output grid: [base face, sub-face corner or -1 for a base quad, depth]; a block is 2^depth x 2^depth refined faces",
        "block_list": blocks,
        "leaves": "per refined face: [block, x, y] (x along the block's u)",
        "leaf_list": leaves,
    });
    serde_json::to_string_pretty(&j).unwrap_or_default()
}
