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
