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
use std::fmt::Write as _;

/// Render a tessellation as OBJ text (triangle patches via [`tri_to_obj`]):
/// [`ObjStream`] over one chunk, so a streamed file is byte for byte this.
pub fn to_obj(t: &Tessellation) -> String {
    obj_text(|stream| stream.write(t))
}

/// The text `write` puts into a fresh [`ObjStream`]: every `to_obj` is its
/// streamed writer over one chunk, so streamed and whole files are the same
/// bytes.
pub fn obj_text(write: impl FnOnce(&mut ObjStream<Vec<u8>>) -> std::io::Result<()>) -> String {
    let mut stream = ObjStream::new(Vec::new());
    // Writing into a Vec cannot fail, and the writers write UTF-8.
    let _ = write(&mut stream);
    String::from_utf8(stream.finish().unwrap_or_default()).unwrap_or_default()
}

/// OBJ output written chunk by chunk (`tessellate::Session::run_chunked`):
/// the header with the first chunk, then each grid as [`to_obj`] writes it,
/// named after its base face ([`Tessellation::face_of`]), vertex indices
/// continuing across chunks. Peak memory is one patch's text.
pub struct ObjStream<W: std::io::Write> {
    out: W,
    /// 1-based index of the next `v` line.
    next: u32,
    started: bool,
}

impl<W: std::io::Write> ObjStream<W> {
    pub fn new(out: W) -> Self {
        ObjStream {
            out,
            next: 1,
            started: false,
        }
    }

    /// Append the grids of `t` (one level and layout for the whole stream).
    pub fn write(&mut self, t: &Tessellation) -> std::io::Result<()> {
        let (header, tris) = layout(t.sides, t.level);
        let per = t.grid_len();
        self.write_patches(
            &header,
            (0..t.faces).map(|g| {
                (
                    format!("patch_{}", t.face_of(g)),
                    &t.positions[g * per..(g + 1) * per],
                    &t.normals[g * per..(g + 1) * per],
                    &tris[..],
                )
            }),
        )
    }

    /// Append patches in the grid layout ([`write_patch`]: `g <name>`, its
    /// `v`/`vn` lines and local triangles), `header` first if nothing was
    /// written yet. Peak memory is one patch's text.
    pub(crate) fn write_patches<'a>(
        &mut self,
        header: &str,
        patches: impl Iterator<Item = (String, &'a [Vec3], &'a [Vec3], &'a [[u32; 3]])>,
    ) -> std::io::Result<()> {
        self.write_patches_as(Floats::Shortest, header, patches)
    }

    /// [`ObjStream::write_patches`] with the coordinates spelled `floats`.
    pub(crate) fn write_patches_as<'a>(
        &mut self,
        floats: Floats,
        header: &str,
        patches: impl Iterator<Item = (String, &'a [Vec3], &'a [Vec3], &'a [[u32; 3]])>,
    ) -> std::io::Result<()> {
        if !self.started {
            writeln!(self.out, "{header}")?;
            self.started = true;
        }
        let mut s = String::new();
        for (name, positions, normals, tris) in patches {
            s.clear();
            write_patch_as(floats, &mut s, &name, positions, normals, tris, self.next);
            self.out.write_all(s.as_bytes())?;
            // OBJ indices here are u32: refuse to wrap past 2³² − 1 vertices.
            self.next = u32::try_from(positions.len())
                .ok()
                .and_then(|p| self.next.checked_add(p))
                .ok_or_else(|| {
                    std::io::Error::other("more than 2^32 - 1 OBJ vertices in one file")
                })?;
        }
        Ok(())
    }

    /// Append one patch of a triangle soup (the OBJ of adaptive results,
    /// `tessellate::Output::write_soup`): `g <name>`, three `v` lines per
    /// triangle (its own corners: what `--check-watertight` welds), then its
    /// `f a b c` lines, indices continuing across patches and chunks. The
    /// header line comes with the first patch, so a soup streamed patch by
    /// patch is byte for byte the whole one.
    pub fn write_soup_patch(&mut self, name: &str, tris: &[[Vec3; 3]]) -> std::io::Result<()> {
        if !self.started {
            writeln!(
                self.out,
                "# tessgen {} triangle soup",
                env!("CARGO_PKG_VERSION")
            )?;
            self.started = true;
        }
        let base = self.next;
        let next = u32::try_from(3 * tris.len())
            .ok()
            .and_then(|n| base.checked_add(n))
            .ok_or_else(|| std::io::Error::other("more than 2^32 - 1 OBJ vertices in one file"))?;
        let mut s = String::with_capacity(tris.len() * 120 + name.len() + 3);
        let _ = writeln!(s, "g {name}");
        for p in tris.iter().flatten() {
            let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
        }
        for k in 0..tris.len() as u32 {
            let a = base + 3 * k;
            let _ = writeln!(s, "f {} {} {}", a, a + 1, a + 2);
        }
        self.out.write_all(s.as_bytes())?;
        self.next = next;
        Ok(())
    }

    /// Bytes written as they are (a whole OBJ text of a non-grid result).
    pub fn raw(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.started = true;
        self.out.write_all(bytes)
    }

    /// The writer, flushed.
    pub fn finish(mut self) -> std::io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}

/// The header line and the per-patch triangles of a grid of `sides`
/// corners at `level` (quads: [`grid_triangles`]; triangles:
/// [`tri_grid_triangles`]).
fn layout(sides: u32, level: u32) -> (String, Vec<[u32; 3]>) {
    let version = env!("CARGO_PKG_VERSION");
    if sides == 3 {
        (
            format!("# tessgen {version} level {level} triangle patches"),
            tri_grid_triangles(level),
        )
    } else {
        (
            format!("# tessgen {version} level {level}"),
            grid_triangles(level),
        )
    }
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
    let (header, tris) = layout(3, level);
    write_patches(
        &header,
        positions,
        normals,
        positions.len() / per,
        per,
        &tris,
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
    write_patch_as(Floats::Shortest, s, name, positions, normals, tris, base)
}

/// How a patch's coordinates are spelled: Rust's shortest round-trip
/// `Display` (`1`, `0.5`: the grids), or `Debug` (`1.0`: the hardware
/// captures, as they always were). Both round-trip exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Floats {
    Shortest,
    Debug,
}

/// [`write_patch`] with the coordinates spelled `floats`.
fn write_patch_as(
    floats: Floats,
    s: &mut String,
    name: &str,
    positions: &[Vec3],
    normals: &[Vec3],
    tris: &[[u32; 3]],
    base: u32,
) {
    let _ = writeln!(s, "g {name}");
    for (tag, values) in [("v", positions), ("vn", normals)] {
        for p in values {
            let _ = match floats {
                Floats::Shortest => writeln!(s, "{tag} {} {} {}", p.x, p.y, p.z),
                Floats::Debug => writeln!(s, "{tag} {:?} {:?} {:?}", p.x, p.y, p.z),
            };
        }
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
