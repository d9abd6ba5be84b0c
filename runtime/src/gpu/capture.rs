//! A hardware tessellator's output captured as triangles.
//!
//! For a quad domain the tessellator's vertices are exactly the integer
//! grid `(i, j)/level`, so a capture can be indexed like the CPU
//! [`crate::Tessellation`]. For a triangle domain they are not: inner ring
//! `k` of a level-`N` triangle has `N − 2k` segments per side (the
//! barycentric lattice row at that depth has `N − 3k`), so the Vulkan
//! harness records the triangles the tessellator actually emitted
//! ([`TriangleCapture`]): per vertex the position, normal, raw domain point
//! and patch. Welding that soup by exact position bits is the
//! watertightness check; evaluating the CPU surface at each captured domain
//! point is the parity check.

use crate::check::weld::{weld_triangles, WeldReport};
use glam::Vec3;
use std::collections::HashMap;

/// The fixed-point denominator of adaptive evaluation (`2^16`, from the
/// generated ABI, codegen's `plan::ADAPTIVE_LEVEL`): the hardware tessellator's domain coordinates
/// are 16.16 fixed point, so the evaluation stages of adaptive builds pass
/// `round(coordinate · 2^16)` and level `2^16` to `eval` / `eval_domain`.
pub const ADAPTIVE_LEVEL: u32 = crate::abi::ADAPTIVE_LEVEL;

/// Floats per captured vertex: position xyz, normal xyz, domain xyz, patch
/// (its u32 bits).
pub const VERTEX_FLOATS: usize = 10;

/// One patch's captured vertices (each distinct domain point once, sorted by
/// its coordinates) and triangles (local indices, as the tessellator wound
/// them, sorted).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CapturedPatch {
    /// Triangle patches: barycentric `(x, y, z)` of corners 0, 1, 2, as the
    /// tessellator gave it. Quad patches (adaptive draws): `(u, v, 0)` in
    /// the patch's own convention.
    pub domain: Vec<[f32; 3]>,
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

/// Every patch's captured triangles, in face order of the triangle mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleCapture {
    pub level: u32,
    /// Patch `k` is face `first_face + k`: 0 for a whole capture, the
    /// window's first face for one chunk of a streamed capture
    /// (`VkMesh::evaluate_triangles_faces`).
    pub first_face: usize,
    pub patches: Vec<CapturedPatch>,
}

/// A capture that does not fit the mesh (a harness or driver bug).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CaptureError {
    #[error(
        "captured triangle {triangle}: patch index {patch} is outside the {patches} patches drawn"
    )]
    Patch {
        triangle: usize,
        patch: u32,
        patches: usize,
    },
    #[error("captured triangle {triangle}: its vertices name different patches ({a} and {b}); raw vertices {raw:?}")]
    MixedPatches {
        triangle: usize,
        a: u32,
        b: u32,
        raw: Vec<f32>,
    },
    #[error("captured triangle {triangle}: domain point {domain:?} is not finite")]
    Domain { triangle: usize, domain: [f32; 3] },
    #[error("patch of face {face}: no triangle was captured")]
    Empty { face: usize },
}

fn bits(d: [f32; 3]) -> [u32; 3] {
    d.map(f32::to_bits)
}

impl TriangleCapture {
    /// Group a raw capture (`VERTEX_FLOATS` floats per vertex, three vertices
    /// per triangle, in any order) by patch. `patch_faces[p]` is the face of
    /// patch `p`; `faces` the number of faces (every face must get triangles).
    pub fn from_raw(
        level: u32,
        raw: &[f32],
        patch_faces: &[u32],
        faces: usize,
    ) -> Result<TriangleCapture, CaptureError> {
        Self::from_raw_window(level, raw, patch_faces, 0..faces)
    }

    /// [`TriangleCapture::from_raw`] of the patches of the faces `faces`
    /// only (a streamed window: `first_face` = its start; a triangle of a
    /// patch outside it is [`CaptureError::Patch`]).
    pub fn from_raw_window(
        level: u32,
        raw: &[f32],
        patch_faces: &[u32],
        faces: std::ops::Range<usize>,
    ) -> Result<TriangleCapture, CaptureError> {
        let first_face = faces.start;
        // Per face: domain bits → (domain, position, normal), triangles.
        type Acc = (
            HashMap<[u32; 3], ([f32; 3], Vec3, Vec3)>,
            Vec<[[u32; 3]; 3]>,
        );
        let mut acc: Vec<Acc> = vec![Default::default(); faces.len()];
        for (t, tri) in raw.chunks_exact(3 * VERTEX_FLOATS).enumerate() {
            let vs: Vec<&[f32]> = tri.chunks_exact(VERTEX_FLOATS).collect();
            let patch = vs[0][9].to_bits();
            for v in &vs[1..] {
                if v[9].to_bits() != patch {
                    return Err(CaptureError::MixedPatches {
                        triangle: t,
                        a: patch,
                        b: v[9].to_bits(),
                        raw: tri.to_vec(),
                    });
                }
            }
            let face = *patch_faces.get(patch as usize).ok_or(CaptureError::Patch {
                triangle: t,
                patch,
                patches: patch_faces.len(),
            })? as usize;
            let (verts, tris) = face
                .checked_sub(first_face)
                .and_then(|k| acc.get_mut(k))
                .ok_or(CaptureError::Patch {
                    triangle: t,
                    patch,
                    patches: patch_faces.len(),
                })?;
            let mut key = [[0u32; 3]; 3];
            for (k, v) in vs.iter().enumerate() {
                let domain = [v[6], v[7], v[8]];
                if !domain.iter().all(|x| x.is_finite()) {
                    return Err(CaptureError::Domain {
                        triangle: t,
                        domain,
                    });
                }
                key[k] = bits(domain);
                verts.entry(key[k]).or_insert((
                    domain,
                    Vec3::new(v[0], v[1], v[2]),
                    Vec3::new(v[3], v[4], v[5]),
                ));
            }
            tris.push(key);
        }
        let mut patches = Vec::with_capacity(faces.len());
        for (k, (verts, tris)) in acc.into_iter().enumerate() {
            if tris.is_empty() {
                return Err(CaptureError::Empty {
                    face: first_face + k,
                });
            }
            // Deterministic order: by (z, y, x) of the domain point (the
            // coordinates are non-negative, so their bits sort like them).
            let mut keys: Vec<[u32; 3]> = verts.keys().copied().collect();
            keys.sort_by_key(|k| [k[2], k[1], k[0]]);
            let index: HashMap<[u32; 3], u32> = keys
                .iter()
                .enumerate()
                .map(|(i, k)| (*k, i as u32))
                .collect();
            let mut p = CapturedPatch::default();
            for k in &keys {
                let (d, pos, n) = verts[k];
                p.domain.push(d);
                p.positions.push(pos);
                p.normals.push(n);
            }
            p.triangles = tris.iter().map(|t| t.map(|k| index[&k])).collect();
            p.triangles.sort();
            patches.push(p);
        }
        Ok(TriangleCapture {
            level,
            first_face,
            patches,
        })
    }

    /// Parity with the CPU: evaluate the generated Rust at every captured
    /// vertex's domain point, as the evaluation stage did (triangles:
    /// `eval_domain(x, y, z, level)`; quads: `eval(round(u·level),
    /// round(v·level), level)`), and return the largest distance `|captured −
    /// CPU|` over all vertices (NaN if either side is NaN). `patches` are the CPU's patches of the
    /// same mesh (patch `k` of the capture is face `k`). `Err` names the
    /// first face whose CPU patch is missing or whose scheme cannot
    /// evaluate a raw triangle domain point.
    pub fn max_deviation(&self, patches: &crate::cpu::Patches) -> Result<f32, usize> {
        let k = patches.scheme;
        let level = self.level;
        self.max_deviation_from(|face, d| {
            if k.sides == 3 {
                return crate::cpu::eval_domain(patches, face, d, level);
            }
            let class = *patches.face_class.get(face)?;
            let (a, b) = (
                *patches.cp_offsets.get(face)? as usize,
                *patches.cp_offsets.get(face + 1)? as usize,
            );
            let [iu, iv] = quad_grid_point(d, level);
            Some((k.eval)(
                patches.control_points.get(a..b)?,
                class,
                0,
                iu,
                iv,
                level,
            ))
        })
    }

    /// [`Self::max_deviation`] of a displacing build
    /// (`TESSGEN_DISPLACE`): the CPU runs the same displacement step at
    /// the same point (triangles: `eval_domain_displaced(x, y, z, level)`;
    /// quads: `eval_displaced(round(u·level), round(v·level), level)`),
    /// with `data` built for `patches`' layout
    /// ([`crate::cpu::displacement_data`], [`crate::cpu::displacement_data_tri`]).
    pub fn max_deviation_displaced(
        &self,
        patches: &crate::cpu::Patches,
        data: &crate::cpu::displace::DisplaceData,
    ) -> Result<f32, usize> {
        let k = patches.scheme;
        let level = self.level;
        self.max_deviation_from(|face, d| {
            if k.sides == 3 {
                return crate::cpu::eval_domain_displaced(patches, data, face, d, level);
            }
            let [iu, iv] = quad_grid_point(d, level);
            crate::cpu::eval_displaced_at(patches, data, face, iu, iv, level)
        })
    }

    /// The largest `|captured − cpu(face, domain)|` over all vertices.
    fn max_deviation_from(
        &self,
        cpu: impl Fn(usize, [f32; 3]) -> Option<crate::kernels::common::Sample>,
    ) -> Result<f32, usize> {
        let mut worst = 0.0f32;
        for (k, p) in self.patches.iter().enumerate() {
            let face = self.first_face + k;
            for (d, pos) in p.domain.iter().zip(&p.positions) {
                let s = cpu(face, *d).ok_or(face)?;
                let dev = (s.position - *pos).length();
                if dev.is_nan() {
                    // A NaN on either side is no agreement.
                    return Ok(f32::NAN);
                }
                worst = worst.max(dev);
            }
        }
        Ok(worst)
    }

    /// Empties the patches of faces with `drop[face]` (holes, faces
    /// without a limit surface: docs/boundaries.md §5), keeping patch `k`
    /// the `k`-th face so the layout and the boundary count stay indexed
    /// by face.
    pub fn clear_patches(&mut self, drop: &[bool]) {
        let drop = drop.get(self.first_face..).unwrap_or_default();
        for (p, _) in self.patches.iter_mut().zip(drop).filter(|(_, &d)| d) {
            *p = CapturedPatch::default();
        }
    }

    pub fn vertex_count(&self) -> usize {
        self.patches.iter().map(|p| p.positions.len()).sum()
    }

    pub fn triangle_count(&self) -> usize {
        self.patches.iter().map(|p| p.triangles.len()).sum()
    }

    /// Weld every captured triangle by exact position bits (see
    /// [`crate::check::weld`]): 0 open edges means the hardware's output is a
    /// closed surface.
    pub fn weld(&self) -> WeldReport {
        let soup: Vec<Vec3> = self.triangles().into_iter().flatten().collect();
        weld_triangles(&soup, 3, &[[0, 1, 2]])
    }

    /// Every captured triangle as world positions, patch by patch (a
    /// triangle soup for OBJ output or [`weld_triangles`]).
    pub fn triangles(&self) -> Vec<[Vec3; 3]> {
        self.patches
            .iter()
            .flat_map(|p| {
                p.triangles
                    .iter()
                    .map(move |t| t.map(|k| p.positions[k as usize]))
            })
            .collect()
    }

    /// OBJ text in the layout of [`crate::check::obj`]: per patch `g patch_<k>`
    /// (the `k`-th triangle of the triangle mesh), its `v` and `vn` lines
    /// (the captured vertices, sorted by domain point) and its triangles
    /// `f a//a b//b c//c` as the tessellator emitted them.
    pub fn to_obj(&self) -> String {
        crate::check::obj::obj_text(|stream| self.write_obj(stream))
    }

    /// [`TriangleCapture::to_obj`] appended to an OBJ stream (the header
    /// with the stream's first chunk, patches named by face, vertex indices
    /// continuing), so a streamed capture is byte for byte the whole one.
    pub fn write_obj<W: std::io::Write>(
        &self,
        stream: &mut crate::check::obj::ObjStream<W>,
    ) -> std::io::Result<()> {
        let header = format!(
            "# tessgen {} level {} triangle patches (hardware tessellator pattern)",
            env!("CARGO_PKG_VERSION"),
            self.level
        );
        stream.write_patches_as(
            crate::check::obj::Floats::Debug,
            &header,
            self.patches.iter().enumerate().map(|(k, p)| {
                (
                    format!("patch_{}", self.first_face + k),
                    &p.positions[..],
                    &p.normals[..],
                    &p.triangles[..],
                )
            }),
        )
    }
}

/// A quad domain point `(u, v, ·)` on the integer grid of `level`, as the
/// evaluation stage rounds it.
fn quad_grid_point(d: [f32; 3], level: u32) -> [u32; 2] {
    let to_int = |x: f32| (x * level as f32).round() as u32;
    [to_int(d[0]), to_int(d[1])]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vertex(p: [f32; 3], d: [f32; 3], patch: u32) -> Vec<f32> {
        let mut v = vec![p[0], p[1], p[2], 0.0, 0.0, 1.0, d[0], d[1], d[2]];
        v.push(f32::from_bits(patch));
        v
    }

    /// Two patches sharing an edge, captured in scrambled order: grouped per
    /// face, shared vertices once, and the pair welds to a disc (4 open edges).
    #[test]
    fn groups_by_patch_and_welds() {
        let tri = |ps: [[f32; 3]; 3], patch| -> Vec<f32> {
            let ds = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
            (0..3).flat_map(|k| vertex(ps[k], ds[k], patch)).collect()
        };
        let mut raw = tri([[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]], 0);
        raw.extend(tri([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], 1));
        // patch 0 is face 1, patch 1 is face 0
        let c = TriangleCapture::from_raw(1, &raw, &[1, 0], 2).expect("capture");
        assert_eq!(c.patches[0].positions[0], Vec3::ZERO);
        assert_eq!(c.vertex_count(), 6);
        assert_eq!(c.triangle_count(), 2);
        let r = c.weld();
        assert_eq!(r.open_edges, 4);
        assert_eq!(r.vertices, 4);
        assert!(c.to_obj().contains("g patch_1"));
    }

    #[test]
    fn typed_errors() {
        let raw: Vec<f32> = (0..3)
            .flat_map(|_| vertex([0.0; 3], [0.0, 0.5, 0.5], 7))
            .collect();
        assert_eq!(
            TriangleCapture::from_raw(1, &raw, &[0], 1),
            Err(CaptureError::Patch {
                triangle: 0,
                patch: 7,
                patches: 1
            })
        );
        assert_eq!(
            TriangleCapture::from_raw(1, &[], &[0], 1),
            Err(CaptureError::Empty { face: 0 })
        );
    }
}
