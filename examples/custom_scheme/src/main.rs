//! Runs the generated kernels of the user scheme `pccm_sigma` (see build.rs)
//! on a mesh and checks the result is watertight.
//!
//! `cargo run -p tessgen-example-custom-scheme -- [MESH.obj] [LEVEL]`

use glam::Vec3;
use tessgen_runtime::{cpu::Tessellation, weld, FaceClass, Mesh, Topology, TopologyOptions};

mod generated {
    include!(concat!(env!("OUT_DIR"), "/rust/tessgen.rs"));
}
use generated::common::{Inputs, SchemeKernels};

/// The generated WGSL, ready for `wgpu::ShaderSource::Wgsl`.
pub const WGSL: &str = include_str!(concat!(env!("OUT_DIR"), "/wgsl/pccm_sigma.wgsl"));

/// The logical table rows the CPU kernels index, unwrapped from the
/// generated texture (rows wrap into column blocks of `TABLE_BLOCK_ROWS`).
fn table() -> Vec<f32> {
    use generated::common::{TABLE_BLOCK_ROWS, TABLE_TEXTURE_WIDTH, TABLE_WIDTH};
    let texture: Vec<f32> = include_bytes!(concat!(env!("OUT_DIR"), "/table/stencils.f32"))
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    tessgen_runtime::kernels::unwrap_table(
        &texture,
        TABLE_WIDTH,
        TABLE_TEXTURE_WIDTH,
        TABLE_BLOCK_ROWS,
    )
}

/// Vertex stage, patch stage and evaluation with the generated kernels,
/// sequentially (the runtime's `cpu` module does the same in parallel for
/// its built-in schemes).
fn tessellate(k: &SchemeKernels, topo: &Topology, positions: &[Vec3], level: u32) -> Tessellation {
    let table = table();
    let mut offsets = Vec::new();
    let mut total = 0;
    for &n in &topo.valence {
        offsets.push(total);
        total += if n > 0 {
            k.rows_per_n * n + k.rows_fixed
        } else {
            0
        };
    }
    let corner_vertex: Vec<u32> = topo
        .corners
        .iter()
        .flat_map(|c| c.map(|x| x.vertex))
        .collect();
    let corner_sector: Vec<u32> = topo
        .corners
        .iter()
        .flat_map(|c| c.map(|x| x.sector))
        .collect();
    let mut inputs = Inputs {
        positions,
        valence: &topo.valence,
        ring_offsets: &topo.ring_offsets,
        ring: &topo.ring,
        vertex_out_offsets: &offsets,
        vertex_out: &[],
        corner_vertex: &corner_vertex,
        corner_sector: &corner_sector,
        // Crease and corner vertices' sector records (none on a closed
        // untagged mesh) and each corner's constant valence.
        vertex_sectors: &topo.vertex_sectors,
        sectors: &topo.sectors,
        corner_valence: &topo.corner_valence,
        normals: &[],
        tags: &[],
        crease: &[],
        corner_side: &[],
        face_edges: &[],
        edge_factors: &[],
        adaptive: &[],
        table: &table,
        // Displacement (texture coordinates, owners, map) is not used here.
        ..Default::default()
    };
    let mut vertex_out = vec![Vec3::ZERO; total as usize];
    for (v, &n) in topo.valence.iter().enumerate() {
        if n > 0 {
            (k.vertex_stage)(&inputs, &mut vertex_out, v as u32, offsets[v]);
        }
    }
    inputs.vertex_out = &vertex_out;
    let per = ((level + 1) * (level + 1)) as usize;
    let mut t = Tessellation {
        level,
        faces: topo.corners.len(),
        sides: 4,
        positions: Vec::new(),
        normals: Vec::new(),
        face_ids: Vec::new(),
    };
    for (f, class) in topo.classes.iter().enumerate() {
        let want = if *class == FaceClass::Ordinary {
            "ordinary"
        } else {
            "extraordinary"
        };
        let c = k.classes.iter().position(|c| c.class == want).unwrap_or(0);
        let mut cp = vec![Vec3::ZERO; k.classes[c].control_points as usize];
        (k.classes[c].patch)(&inputs, &mut cp, f as u32, 0);
        for s in 0..per as u32 {
            let sample = (k.eval)(&cp, c as u32, 0, s % (level + 1), s / (level + 1), level);
            t.positions.push(sample.position);
            t.normals.push(sample.normal);
        }
    }
    t
}

fn run(path: &str, level: u32) -> Result<(Tessellation, weld::WeldReport), String> {
    let mesh = Mesh::from_obj_path(path).map_err(|e| e.to_string())?;
    let opts = TopologyOptions {
        max_valence: generated::common::MAX_VALENCE,
        require_quads: true,
    };
    let topo = Topology::build(&mesh, &opts).map_err(|e| e.to_string())?;
    let positions: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    let t = tessellate(&generated::pccm_sigma::KERNELS, &topo, &positions, level);
    let r = weld::weld(&t);
    Ok((t, r))
}

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let default = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/meshes/catmark_cube.obj"
    );
    let path = args.get(1).map(String::as_str).unwrap_or(default);
    let level = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(8);
    match run(path, level) {
        Ok((t, r)) => {
            println!(
                "pccm_sigma on {path}: {} faces, {} samples, welded {} vertices, {} open edges; WGSL module {} bytes",
                t.faces,
                t.positions.len(),
                r.vertices,
                r.open_edges,
                WGSL.len()
            );
            if r.is_closed_manifold() {
                std::process::ExitCode::SUCCESS
            } else {
                std::process::ExitCode::FAILURE
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn user_scheme_is_watertight_on_the_cube() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/data/meshes/catmark_cube.obj"
        );
        for level in [1, 3, 8] {
            let (_, r) = super::run(path, level).unwrap_or_else(|e| panic!("{e}"));
            assert!(
                r.is_closed_manifold(),
                "level {level}: {} open edges",
                r.open_edges
            );
            assert_eq!(r.euler, 2);
        }
        assert!(super::WGSL.contains("fn eval_vs"));
    }
}
