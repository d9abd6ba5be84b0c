//! OBJ output of tessellated grids — the same layout from every backend.
//!
//! Per base face, in input order: `g patch_<face>`, then `(N+1)²` `v` lines
//! and `(N+1)²` `vn` lines, row-major `j·(N+1) + i` for `u = i/N`, `v = j/N`,
//! then the grid's triangles `f a//a b//b c//c`. Coordinates use Rust's
//! shortest round-trip formatting, so equal f32 values print identical text.
//!
//! Triangle patches ([`tri_to_obj`]) use the same layout with the
//! `(N+1)(N+2)/2` samples of [`crate::grid::tri_grid_coords`] per patch
//! (row by row, `(i, j)` with `i + j ≤ N`) and the `N²` triangles of
//! [`crate::grid::tri_grid_triangles`].

use crate::cpu::Tessellation;
use crate::grid::grid_triangles;
use crate::grid::{tri_grid_len, tri_grid_triangles};
use glam::Vec3;
use std::fmt::Write;

/// Render a tessellation as OBJ text (triangle patches via [`tri_to_obj`]).
pub fn to_obj(t: &Tessellation) -> String {
    if t.sides == 3 {
        return tri_to_obj(&t.positions, &t.normals, t.level);
    }
    let header = format!("# tessgen {} level {}", env!("CARGO_PKG_VERSION"), t.level);
    write_patches(
        &header,
        &t.positions,
        &t.normals,
        t.faces,
        t.grid_len(),
        &grid_triangles(t.level),
    )
}

/// Render a triangle-patch tessellation at `level` as OBJ text: `positions`
/// and `normals` hold [`tri_grid_len`]`(level)` samples per patch, patch after
/// patch (`g patch_<k>` names the `k`-th patch, i.e. the `k`-th triangle of
/// the [`crate::mesh::trimesh::TriMesh`], not the input face).
///
/// # Panics
///
/// If `positions` and `normals` differ in length or are not whole patches:
/// a caller bug, and writing a misaligned file would hide it.
pub fn tri_to_obj(positions: &[Vec3], normals: &[Vec3], level: u32) -> String {
    let per = tri_grid_len(level);
    assert!(
        positions.len() == normals.len() && positions.len().checked_rem(per) == Some(0),
        "{} positions and {} normals are not whole triangle patches of {per} samples",
        positions.len(),
        normals.len()
    );
    let header = format!(
        "# tessgen {} level {} triangle patches",
        env!("CARGO_PKG_VERSION"),
        level
    );
    write_patches(
        &header,
        positions,
        normals,
        positions.len() / per,
        per,
        &tri_grid_triangles(level),
    )
}

/// One patch: `g <name>`, its `v` and `vn` lines, then its triangles with
/// 1-based indices from `base` (`f a//a …`). Shared by every grid layout
/// (also [`crate::tessellate::refined::PolygonGrids::to_obj`]).
pub(crate) fn write_patch(
    s: &mut String,
    name: &str,
    positions: &[Vec3],
    normals: &[Vec3],
    tris: &[[u32; 3]],
    base: u32,
) {
    let _ = writeln!(s, "g {name}");
    for p in positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for n in normals {
        let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
    }
    for tri in tris {
        let [a, b, c] = tri.map(|k| k + base);
        let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
    }
}

/// The common writer: a header comment, then per patch a group, its `v` and
/// `vn` lines and its triangles (1-based, `f a//a …`).
fn write_patches(
    header: &str,
    positions: &[Vec3],
    normals: &[Vec3],
    faces: usize,
    per: usize,
    tris: &[[u32; 3]],
) -> String {
    let mut s = String::with_capacity(positions.len() * 64);
    let _ = writeln!(s, "{header}");
    for f in 0..faces {
        write_patch(
            &mut s,
            &format!("patch_{f}"),
            &positions[f * per..(f + 1) * per],
            &normals[f * per..(f + 1) * per],
            tris,
            (f * per) as u32 + 1,
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    #[test]
    fn triangle_patches_round_trip_through_the_reader() {
        let level = 3;
        let per = tri_grid_len(level);
        let positions: Vec<Vec3> = (0..2 * per)
            .map(|k| Vec3::new(k as f32 * 0.5, (k % 3) as f32, -0.25))
            .collect();
        let normals = vec![Vec3::Z; positions.len()];
        let text = tri_to_obj(&positions, &normals, level);
        assert!(text.starts_with("# tessgen "));
        assert_eq!(text.matches("\ng patch_").count(), 2);
        let mesh = Mesh::from_obj_str(&text).unwrap();
        assert_eq!(mesh.num_vertices(), 2 * per);
        assert_eq!(mesh.num_faces(), 2 * 9);
        assert_eq!(mesh.normals.len(), 2 * per);
        let tris = tri_grid_triangles(level);
        for (f, tri) in tris.iter().enumerate() {
            assert_eq!(mesh.face(f), tri);
            assert_eq!(mesh.face(9 + f), tri.map(|k| k + per as u32));
        }
        for (p, q) in mesh.positions.iter().zip(&positions) {
            assert_eq!(Vec3::from(*p), *q);
        }
        // Every corner names the normal with its own index.
        assert_eq!(mesh.face_normals, mesh.face_vertices);
    }
}
