//! Shared helpers for the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;
use tessgen_runtime::Mesh;

/// The closed meshes of the shared test set (copied into tests/data/meshes).
pub const CLOSED_MESHES: &[&str] = &[
    "catmark_cube",
    "catmark_torus",
    "catmark_toroidal_tet",
    "catmark_righthanded",
];

/// The large closed mesh of the shared set (catmark_righthanded refined
/// three times, 27,776 quads); checked at fewer levels to keep CI fast.
pub const BIG_MESH: &str = "big/catmark_righthanded_L3";

pub fn data(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(path)
}

pub fn mesh(name: &str) -> Mesh {
    let p = data(&format!("meshes/{name}.obj"));
    Mesh::from_obj_path(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

pub fn json(path: &str) -> serde_json::Value {
    let p = data(path);
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Angle between two vectors in degrees, computed in f64 with
/// `atan2(|a × b|, a · b)` (acos has a 0.02° noise floor on f32 data).
pub fn angle_deg(a: glam::Vec3, b: glam::Vec3) -> f64 {
    let a = a.as_dvec3();
    let b = b.as_dvec3();
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// Exact Catmull-Clark limit samples (`tests/data/cc_limit/<mesh>.bin`):
/// `(n, samples)` with `samples[face][j][i] = (position, normal)` at
/// `u = i/(n-1)`, `v = j/(n-1)`.
pub fn cc_limit(name: &str) -> (usize, Vec<[glam::Vec3; 2]>) {
    let p = data(&format!("cc_limit/{name}.bin"));
    let b = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    assert_eq!(&b[..8], b"CCLIM001");
    let word = |k: usize| {
        u32::from_le_bytes([b[8 + 4 * k], b[9 + 4 * k], b[10 + 4 * k], b[11 + 4 * k]]) as usize
    };
    let (faces, n, k) = (word(0), word(1), word(2));
    assert_eq!(k, 6);
    let f: Vec<f32> = b[32..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    assert_eq!(f.len(), faces * n * n * 6);
    let samples = f
        .chunks_exact(6)
        .map(|c| {
            [
                glam::Vec3::new(c[0], c[1], c[2]),
                glam::Vec3::new(c[3], c[4], c[5]),
            ]
        })
        .collect();
    (n, samples)
}

/// The quad topology of `mesh` (CPU options, tags applied) and its
/// positions as `Vec3`: what `cpu::construct` takes.
pub fn topo_positions(mesh: &Mesh) -> (tessgen_runtime::Topology, Vec<glam::Vec3>) {
    let topo = tessgen_runtime::Topology::build(mesh, &tessgen_runtime::cpu::topology_options())
        .expect("topology");
    let positions = mesh
        .positions
        .iter()
        .map(|p| glam::Vec3::from_array(*p))
        .collect();
    (topo, positions)
}

/// Bounding-box diagonal of a mesh.
pub fn bbox_diagonal(mesh: &Mesh) -> f32 {
    let (mut lo, mut hi) = (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN));
    for p in &mesh.positions {
        lo = lo.min(glam::Vec3::from_array(*p));
        hi = hi.max(glam::Vec3::from_array(*p));
    }
    (hi - lo).length()
}

/// The displacement tests' map: it jumps between the cells of a 3×2 atlas
/// and varies inside them, so the two sides of every texture seam read
/// different heights (a crack shows unless ownership holds).
pub fn seam_map() -> tessgen_runtime::displace::DisplaceMap {
    tessgen_runtime::displace::DisplaceMap::from_fn(48, 32, |s, t| {
        let cell = (s * 3.0).floor() + 3.0 * (t * 2.0).floor();
        0.05 * cell + 0.1 * (9.0 * s).sin() * (7.0 * t).cos()
    })
}

/// A displacement by [`seam_map`].
pub fn displacement(
    ownership: tessgen_runtime::displace::Ownership,
    scale: f32,
) -> tessgen_runtime::displace::Displacement {
    tessgen_runtime::displace::Displacement {
        map: seam_map(),
        scale,
        ownership,
    }
}

/// Every face of `mesh` its own chart (cell f of a square atlas), so every
/// edge is a texture seam (after a triangle split, every edge but the
/// quads' diagonals).
pub fn per_face_charts(mut mesh: Mesh) -> Mesh {
    let nf = mesh.num_faces();
    let side = (nf as f32).sqrt().ceil() as usize;
    mesh.texcoords.clear();
    mesh.face_texcoords.clear();
    for f in 0..nf {
        let (cx, cy) = ((f % side) as f32, (f / side) as f32);
        let cell = 1.0 / side as f32;
        let m = cell / 16.0;
        let quad = [[m, m], [cell - m, m], [cell - m, cell - m], [m, cell - m]];
        for q in quad.iter().take(mesh.face(f).len()) {
            mesh.face_texcoords.push(mesh.texcoords.len() as u32);
            mesh.texcoords.push([cx * cell + q[0], cy * cell + q[1]]);
        }
    }
    mesh
}

/// The seam meshes of the displacement tests: `catmark_cube_uv` (a seam on
/// every edge) and `catmark_toroidal_tet` with a chart per face.
pub fn seam_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("catmark_cube_uv", mesh("catmark_cube_uv")),
        (
            "catmark_toroidal_tet (charts)",
            per_face_charts(mesh("catmark_toroidal_tet")),
        ),
    ]
}

/// The front door's per-face grids for a uniform CPU request (the CPU
/// always answers one with grids).
pub fn grid(
    mesh: &Mesh,
    request: &tessgen_runtime::tessellate::Request<'_>,
) -> Result<tessgen_runtime::Tessellation, tessgen_runtime::tessellate::Error> {
    tessgen_runtime::tessellate::tessellate(mesh, request)
        .map(|o| o.into_grid().expect("a uniform CPU request gives grids"))
}

/// The shared mesh `name` with its faces `faces` (0-based) tagged as
/// holes (`t hole`).
pub fn holed(name: &str, faces: &[i64]) -> Mesh {
    let mut m = mesh(name);
    m.tags.push(tessgen_runtime::mesh::Tag {
        name: "hole".into(),
        ints: faces.to_vec(),
        floats: vec![],
        strings: vec![],
        line: 0,
    });
    m
}

/// An adaptive request for `scheme` with random per-edge factors in
/// `[lo, hi]` (seeded, integer partitioning), factors clamped to
/// `max_factor`: what most adaptive tests run.
pub fn random_adaptive(
    scheme: &str,
    seed: u64,
    lo: f32,
    hi: f32,
    max_factor: f32,
) -> tessgen_runtime::tessellate::Request<'static> {
    use tessgen_runtime::tessellate::{AdaptiveRequest, EdgeMetric, Request};
    Request::adaptive(
        scheme,
        AdaptiveRequest {
            metric: EdgeMetric::Random { seed, lo, hi },
            partitioning: tessgen_runtime::adaptive::Partitioning::Integer,
            max_factor,
        },
    )
}
