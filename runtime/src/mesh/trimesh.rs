//! Triangle meshes for the per-facet triangle schemes (PN triangles, scalar-tagged PN, Phong
//! tessellation; math in `spec/pn.md`), and the sample pattern of one tessellated triangle.
//!
//! Those schemes are not stencils over a 1-ring: each facet needs only its 3 corner positions
//! `P_i` and one unit normal `N_i` per corner. So a [`TriMesh`] is flat, OpenSubdiv-Far-style
//! data — positions, per-vertex normals, counter-clockwise index triples — with no half-edge
//! structure. What [`TriMesh::from_mesh`] checks is what watertightness needs:
//!
//! * **One normal per vertex.** Neighbouring PN/Phong patches share an edge's boundary curve
//!   only if both sides build it from the same two `(P, N)` pairs. A vertex with different
//!   normals on different corners (split normals, a hard edge) gives two different curves and a
//!   crack, so it is an error ([`TriMeshError::SplitNormal`]), not something to average
//!   silently. [`TriOptions::recompute_normals`] is the way out: area-weighted normals.
//! * **Manifold, consistently oriented edges.** Every undirected edge is used by at most two
//!   triangles, in opposite directions, so "the other side of an edge" is well defined and the
//!   symmetric edge evaluation of `spec/watertight.md` rule 2 applies. Boundary edges (used
//!   once) are fine. Non-manifold *vertices* (two fans touching at a point) are accepted: every
//!   edge still has at most one neighbour, and the vertex still has one normal.
//!
//! Edges are identified by their two vertex indices, as in any index-triple mesh.
//!
//! # Tessellation domain of one triangle
//!
//! [`crate::grid::tri_grid_coords`], [`crate::grid::tri_grid_triangles`] and
//! [`crate::grid::tri_grid_edge`] fix the sample pattern that every triangle backend uses at
//! level `N` (the triangular analogue of the quad path's `(N+1)²` grid, see
//! [`crate::grid::grid_triangles`]):
//!
//! * samples `(i, j)` with `i + j ≤ N`, stored row by row: `j = 0..=N`, and in row `j`,
//!   `i = 0..=N−j` (index [`crate::grid::tri_grid_index`]);
//! * **barycentric convention** (fixed here, once, for positions, normals and any attribute):
//!   sample `(i, j)` has integer barycentrics `(a, b, c) = (N − i − j, i, j)`, and corner `k`
//!   of the triangle gets weight `a/N`, `b/N`, `c/N` for `k = 0, 1, 2`. So corner 0 is sample
//!   `(0, 0)`, corner 1 is `(N, 0)`, corner 2 is `(0, N)`; in `(u, v) = (i, j)/N` the weights
//!   are `(1 − u − v, u, v)`, which is the D3D11 domain-location convention that `spec/pn.md`
//!   §1 quotes (control point 0 ↔ `w`, 1 ↔ `u`, 2 ↔ `v`). Weights are meant to be formed from
//!   the integers (`b as f32 / N as f32`), never as `1 − u − v`, so that both triangles of a
//!   shared edge form the same pair bit for bit (`spec/watertight.md` rule 2);
//! * edge `k` runs from corner `k` to corner `k + 1 (mod 3)`; it is where the weight of corner
//!   `k + 2` is zero.

use std::collections::HashMap;

use glam::{DVec3, Vec3};
use thiserror::Error;

use crate::mesh::tags::{CreaseTags, TagError, TagFile};
use crate::mesh::{Mesh, MeshError};

/// A triangle mesh with one unit normal per vertex: the input of the triangle schemes.
///
/// Invariants after [`TriMesh::from_mesh`]: `normals.len() == positions.len()`,
/// `source_face.len() == triangles.len()`, every index `< positions.len()`, no triangle repeats
/// a vertex, every edge is used by at most two triangles in opposite directions, every vertex
/// that a triangle uses has a unit normal and every other vertex has the zero normal.
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    /// Vertex positions, same indices as the input [`Mesh`] (vertices no face uses are kept, so
    /// file-order indices stay valid).
    pub positions: Vec<Vec3>,
    /// Unit normal per vertex; zero for a vertex no triangle uses (it is never evaluated, and
    /// dropping it would renumber the vertices).
    pub normals: Vec<Vec3>,
    /// Counter-clockwise triangles (vertex indices), in input face order; a split quad gives two
    /// consecutive triangles.
    pub triangles: Vec<[u32; 3]>,
    /// For each triangle, the 0-based input face it came from (quads split in two share it).
    pub source_face: Vec<u32>,
    /// Where [`TriMesh::normals`] came from.
    pub normal_source: NormalSource,
    /// Scalar tags and side signs for `stpn` ([`crate::mesh::tags`]); neutral (plain PN) unless
    /// [`TriMesh::with_tags`] set them. Other schemes never read them.
    pub crease_tags: CreaseTags,
}

/// Where the vertex normals of a [`TriMesh`] came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalSource {
    /// The OBJ's `vn` normals (normalised), one consistent normal per vertex.
    Obj,
    /// Area-weighted average of the incident triangles' normals (the OBJ had none, or
    /// [`TriOptions::recompute_normals`] asked for it).
    AreaWeighted,
}

/// How [`TriMesh::from_mesh`] treats its input.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TriOptions {
    /// Split every quad into two triangles along its `v0–v2` diagonal (see
    /// [`TriMesh::from_mesh`] for why that one). Off by default: feeding a quad mesh to a
    /// triangle scheme is usually a mistake, so it must be asked for.
    pub split_quads: bool,
    /// Ignore the OBJ's normals and use area-weighted ones. The way out for meshes with split
    /// normals (hard edges) or missing normals, which a watertight smooth scheme cannot use.
    pub recompute_normals: bool,
}

/// Why a mesh cannot be used as a [`TriMesh`]. Face numbers are 0-based input faces, vertex
/// numbers 0-based input vertices (file order).
#[derive(Debug, Error)]
pub enum TriMeshError {
    /// The input mesh itself is invalid (see [`Mesh::validate`]).
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// A face is not a triangle (and not a quad that may be split).
    #[error(
        "face {face} has {sides} sides; triangle schemes need triangles{}",
        if *.sides == 4 { " (split quads: --split-quads, `Request::split_quads`)" } else { "" }
    )]
    NotTriangle {
        /// 0-based input face.
        face: usize,
        /// Its number of vertices.
        sides: usize,
    },
    /// An edge is used by more than two triangles.
    #[error("edge {a}-{b} is used by more than two triangles (faces {faces:?})")]
    NonManifoldEdge {
        /// Smaller vertex index of the edge.
        a: u32,
        /// Larger vertex index of the edge.
        b: u32,
        /// The input faces of all triangles using it, ascending, without repeats.
        faces: Vec<usize>,
    },
    /// Two triangles traverse an edge in the same direction: their orientations disagree.
    #[error("faces {} and {} both run along edge {a}->{b}: inconsistent orientation", .faces[0], .faces[1])]
    InconsistentOrientation {
        /// First vertex of the directed edge both triangles use.
        a: u32,
        /// Second vertex of the directed edge.
        b: u32,
        /// The two input faces, in triangle order (equal only if one face is given twice
        /// with the same orientation).
        faces: [usize; 2],
    },
    /// The OBJ has normals, but a face corner has none.
    #[error(
        "face {face} corner {corner} has no normal but other corners do (drop the `vn` normals \
         for area-weighted ones, or set `TriOptions::recompute_normals`)"
    )]
    MissingNormal {
        /// 0-based input face.
        face: usize,
        /// 0-based corner within the face (file order).
        corner: usize,
    },
    /// A vertex has different normals on different corners (a hard edge / split normals).
    #[error(
        "vertex {vertex} has different normals in faces {} and {} (split normals; drop \
         the `vn` normals for area-weighted ones, or set `TriOptions::recompute_normals`)",
        .faces[0],
        .faces[1]
    )]
    SplitNormal {
        /// 0-based vertex.
        vertex: usize,
        /// The first face that gave the vertex a normal and the first that disagrees with it.
        faces: [usize; 2],
    },
    /// A vertex's normal is zero or non-finite: an OBJ normal of (near) zero length, or
    /// incident triangles whose area-weighted normals cancel (or that all have zero area).
    #[error("vertex {vertex} has no usable normal (zero or non-finite)")]
    DegenerateNormal {
        /// 0-based vertex.
        vertex: usize,
    },
}

/// Tolerance for "identical after normalisation" between two OBJ normals of one vertex, per
/// component. Exporters write the same normal with different rounding (or once per face);
/// 1e-6 absorbs that but not a real hard edge.
pub const NORMAL_MATCH_TOLERANCE: f64 = 1e-6;

/// An area-weighted normal whose length is below this fraction of the summed lengths of its
/// terms is rounding noise (the incident triangles cancel), not a direction.
const CANCELLATION_RATIO: f64 = 1e-12;

impl TriMesh {
    /// Builds the triangle mesh of `mesh`.
    ///
    /// Checks, in this order (the first failure is returned): the mesh's own invariants
    /// ([`Mesh::validate`]); face sizes, splitting quads if `opts.split_quads`; edges (manifold,
    /// consistently oriented), reporting the first offending edge in triangle order; normals.
    ///
    /// **Quads** are split along the fixed diagonal `v0–v2` into `[v0, v1, v2]` and
    /// `[v0, v2, v3]`. Fixed rather than chosen by shape (shorter diagonal, flatter fold)
    /// because a shape-based choice can flip when a coordinate moves by one ulp, or between
    /// tools, and the output must be a pure function of the file's face lists, reproducible for
    /// golden values and snapshots. The diagonal is interior to the face, so it never affects a
    /// neighbour's edge; and it is the same diagonal as the quad grid's cells
    /// ([`crate::grid::grid_triangles`], corner `(0,0)` to `(1,1)`).
    ///
    /// **Polygons with more than 4 sides** are rejected even with splitting: a fan or any
    /// other fixed triangulation folds over on non-convex polygons, and choosing a good one is
    /// the modeller's business.
    ///
    /// **Normals**: if no face corner has an OBJ normal (`vn` lines that no face references do
    /// not count), or `opts.recompute_normals`, they are area-weighted (see
    /// [`NormalSource::AreaWeighted`]). Otherwise every corner must have one
    /// ([`TriMeshError::MissingNormal`]), each must have a usable length
    /// ([`TriMeshError::DegenerateNormal`]), and all corners of a vertex must agree after
    /// normalisation within [`NORMAL_MATCH_TOLERANCE`] ([`TriMeshError::SplitNormal`]); the
    /// vertex gets the normalised normal of its first corner in face order.
    pub fn from_mesh(mesh: &Mesh, opts: &TriOptions) -> Result<TriMesh, TriMeshError> {
        mesh.validate()?;
        let (triangles, source_face) = triangulate(mesh, opts.split_quads)?;
        check_edges(&triangles, &source_face)?;
        let positions: Vec<Vec3> = mesh.positions.iter().map(|&p| Vec3::from(p)).collect();
        let (normals, normal_source) = if opts.recompute_normals || !mesh.has_normals() {
            (
                area_weighted_normals(&positions, &triangles)?,
                NormalSource::AreaWeighted,
            )
        } else {
            (obj_normals(mesh)?, NormalSource::Obj)
        };
        let crease_tags = CreaseTags::neutral(positions.len(), triangles.len());
        Ok(TriMesh {
            positions,
            normals,
            triangles,
            source_face,
            normal_source,
            crease_tags,
        })
    }

    /// This mesh with the scalar tags of a parsed tag file ([`crate::mesh::tags`]): explicit sides
    /// where the file names them, the geometric default elsewhere.
    pub fn with_tags(mut self, file: &TagFile) -> Result<TriMesh, TagError> {
        self.crease_tags = CreaseTags::resolve(
            crate::mesh::tags::Triangulation {
                positions: &self.positions,
                triangles: &self.triangles,
                source_face: &self.source_face,
            },
            file,
        )?;
        Ok(self)
    }

    /// Number of vertices, including vertices no triangle uses.
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.triangles.len()
    }

    /// The corner positions of triangle `t`, in its (ccw) order. Panics if `t` is out of range.
    pub fn triangle_positions(&self, t: usize) -> [Vec3; 3] {
        self.triangles[t].map(|v| self.positions[v as usize])
    }

    /// The corner normals of triangle `t`, in its (ccw) order. Panics if `t` is out of range.
    pub fn triangle_normals(&self, t: usize) -> [Vec3; 3] {
        self.triangles[t].map(|v| self.normals[v as usize])
    }

    /// Number of distinct undirected edges.
    pub fn num_edges(&self) -> usize {
        edge_uses(&self.triangles).len()
    }

    /// Global edge id of edge k (`v_k → v_{k+1}`) of every triangle, at
    /// `3t + k`, numbered in order of first use; the two triangles of an
    /// edge get the same id. Returns `(ids, number of edges)`: the
    /// `face_edges` buffer of adaptive tessellation (the triangle
    /// counterpart of [`crate::cpu::adaptive::edge_ids`]).
    pub fn edge_ids(&self) -> (Vec<u32>, u32) {
        let mut ids = Vec::with_capacity(3 * self.triangles.len());
        let mut seen: std::collections::HashMap<(u32, u32), u32> = Default::default();
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let next = seen.len() as u32;
                ids.push(*seen.entry((a.min(b), a.max(b))).or_insert(next));
            }
        }
        (ids, seen.len() as u32)
    }

    /// Number of boundary edges (used by one triangle).
    pub fn num_boundary_edges(&self) -> usize {
        edge_uses(&self.triangles)
            .values()
            .filter(|&&c| c == 1)
            .count()
    }

    /// Closed surface: every edge used by exactly two triangles (the constructor already
    /// excludes more than two).
    pub fn is_closed(&self) -> bool {
        edge_uses(&self.triangles).values().all(|&c| c == 2)
    }

    /// `V − E + F` over the vertices that some triangle uses (unused vertices are not part of
    /// the surface), as in [`crate::check::stats::MeshStats`], so a quad mesh and its split agree.
    pub fn euler_characteristic(&self) -> i64 {
        let mut used = vec![false; self.positions.len()];
        for &v in self.triangles.iter().flatten() {
            used[v as usize] = true;
        }
        let v = used.iter().filter(|&&u| u).count() as i64;
        v - self.num_edges() as i64 + self.triangles.len() as i64
    }
}

/// Undirected edge → number of triangles using it.
pub(crate) fn edge_uses(triangles: &[[u32; 3]]) -> HashMap<(u32, u32), u32> {
    let mut uses = HashMap::with_capacity(triangles.len() * 3 / 2);
    for t in triangles {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses
}

/// Faces → triangles (see [`TriMesh::from_mesh`] for the quad rule).
fn triangulate(mesh: &Mesh, split_quads: bool) -> Result<(Vec<[u32; 3]>, Vec<u32>), TriMeshError> {
    let mut triangles = Vec::with_capacity(mesh.num_faces());
    let mut source_face = Vec::with_capacity(mesh.num_faces());
    for f in 0..mesh.num_faces() {
        // Mesh::validate bounds the face count by u32::MAX.
        let tag = f as u32;
        match *mesh.face(f) {
            [a, b, c] => {
                triangles.push([a, b, c]);
                source_face.push(tag);
            }
            [a, b, c, d] if split_quads => {
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
                source_face.extend([tag, tag]);
            }
            ref other => {
                return Err(TriMeshError::NotTriangle {
                    face: f,
                    sides: other.len(),
                })
            }
        }
    }
    Ok((triangles, source_face))
}

/// One use of an undirected edge: the triangle and the direction it runs along the edge.
type EdgeUse = (usize, (u32, u32));

/// Every undirected edge used at most twice, and twice only in opposite directions.
fn check_edges(triangles: &[[u32; 3]], source_face: &[u32]) -> Result<(), TriMeshError> {
    // Undirected edge → its uses, in triangle order.
    let mut uses: HashMap<(u32, u32), Vec<EdgeUse>> =
        HashMap::with_capacity(triangles.len() * 3 / 2);
    for (t, tri) in triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            uses.entry((a.min(b), a.max(b)))
                .or_default()
                .push((t, (a, b)));
        }
    }
    let face = |t: usize| source_face[t] as usize;
    // Walk the triangles in order so the reported edge does not depend on hash order.
    for tri in triangles {
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            let key = (a.min(b), a.max(b));
            let Some(list) = uses.get(&key) else {
                continue;
            };
            match list[..] {
                [_] => {}
                [(t0, d0), (t1, d1)] => {
                    if d0 == d1 {
                        return Err(TriMeshError::InconsistentOrientation {
                            a: d0.0,
                            b: d0.1,
                            faces: [face(t0), face(t1)],
                        });
                    }
                }
                _ => {
                    let mut faces: Vec<usize> = list.iter().map(|&(t, _)| face(t)).collect();
                    faces.sort_unstable();
                    faces.dedup();
                    return Err(TriMeshError::NonManifoldEdge {
                        a: key.0,
                        b: key.1,
                        faces,
                    });
                }
            }
        }
    }
    Ok(())
}

/// Normalises in f64 (an f32 normal's squared length cannot overflow or underflow there);
/// `None` for a zero or non-finite vector.
fn unit(v: DVec3) -> Option<DVec3> {
    let len = v.length();
    (len.is_finite() && len > 0.0).then(|| v / len)
}

/// One consistent OBJ normal per vertex (see [`TriMesh::from_mesh`]).
fn obj_normals(mesh: &Mesh) -> Result<Vec<Vec3>, TriMeshError> {
    // Per vertex: its normalised normal and the face that gave it.
    let mut first: Vec<Option<(DVec3, usize)>> = vec![None; mesh.num_vertices()];
    for f in 0..mesh.num_faces() {
        let start = mesh.face_offsets[f] as usize;
        for (corner, &v) in mesh.face(f).iter().enumerate() {
            let Some(n) = mesh.corner_normal(start + corner) else {
                return Err(TriMeshError::MissingNormal { face: f, corner });
            };
            let vertex = v as usize;
            // validate() proved the index is in range.
            let raw = Vec3::from(mesh.normals[n as usize]).as_dvec3();
            let n = unit(raw).ok_or(TriMeshError::DegenerateNormal { vertex })?;
            match first[vertex] {
                None => first[vertex] = Some((n, f)),
                Some((m, g)) => {
                    if (n - m).abs().max_element() > NORMAL_MATCH_TOLERANCE {
                        return Err(TriMeshError::SplitNormal {
                            vertex,
                            faces: [g, f],
                        });
                    }
                }
            }
        }
    }
    Ok(first
        .iter()
        .map(|n| n.map_or(Vec3::ZERO, |(n, _)| n.as_vec3()))
        .collect())
}

/// Area-weighted vertex normals: for each vertex, the sum over its triangles of
/// `(P1 − P0) × (P2 − P0)` (twice the area times the unit normal, so big triangles count more
/// and slivers barely at all), normalised. Summed in f64 in triangle order, so the result is
/// deterministic and the f32 inputs' products are exact.
fn area_weighted_normals(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
) -> Result<Vec<Vec3>, TriMeshError> {
    let mut sum = vec![DVec3::ZERO; positions.len()];
    // Sum of the terms' lengths, to tell a cancelled sum from a real direction.
    let mut scale = vec![0.0f64; positions.len()];
    let mut used = vec![false; positions.len()];
    for tri in triangles {
        let [p0, p1, p2] = tri.map(|v| positions[v as usize].as_dvec3());
        let c = (p1 - p0).cross(p2 - p0);
        let len = c.length();
        for &v in tri {
            sum[v as usize] += c;
            scale[v as usize] += len;
            used[v as usize] = true;
        }
    }
    sum.iter()
        .zip(&scale)
        .zip(&used)
        .enumerate()
        .map(|(vertex, ((&s, &scale), &used))| {
            if !used {
                return Ok(Vec3::ZERO);
            }
            match unit(s) {
                Some(n) if s.length() > CANCELLATION_RATIO * scale => Ok(n.as_vec3()),
                _ => Err(TriMeshError::DegenerateNormal { vertex }),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::NO_NORMAL;

    fn tri_opts() -> TriOptions {
        TriOptions::default()
    }

    fn split() -> TriOptions {
        TriOptions {
            split_quads: true,
            ..TriOptions::default()
        }
    }

    /// A unit tetrahedron, outward-oriented.
    fn tet() -> Mesh {
        Mesh::from_raw(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            &[vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![0, 3, 2]],
        )
        .unwrap()
    }

    #[test]
    fn tet_area_weighted() {
        let t = TriMesh::from_mesh(&tet(), &tri_opts()).unwrap();
        assert_eq!(t.normal_source, NormalSource::AreaWeighted);
        assert_eq!(t.num_triangles(), 4);
        assert_eq!(t.source_face, vec![0, 1, 2, 3]);
        assert!(t.is_closed());
        assert_eq!(t.num_edges(), 6);
        assert_eq!(t.euler_characteristic(), 2);
        let centroid = t.positions.iter().sum::<Vec3>() / 4.0;
        for (p, n) in t.positions.iter().zip(&t.normals) {
            assert!((n.length() - 1.0).abs() < 1e-6);
            assert!(n.dot(*p - centroid) > 0.0);
        }
        // Vertex 0 touches three faces with equal area, normals -x, -y, -z.
        let e = -Vec3::ONE.normalize();
        assert!((t.normals[0] - e).abs().max_element() < 1e-7);
        assert_eq!(t.triangle_positions(2)[1], Vec3::Y);
    }

    #[test]
    fn quad_split_and_refusal() {
        let quad = Mesh::from_raw(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [5.0, 5.0, 5.0],
            ],
            &[vec![0, 1, 2, 3]],
        )
        .unwrap();
        assert!(matches!(
            TriMesh::from_mesh(&quad, &tri_opts()),
            Err(TriMeshError::NotTriangle { face: 0, sides: 4 })
        ));
        let t = TriMesh::from_mesh(&quad, &split()).unwrap();
        assert_eq!(t.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(t.source_face, vec![0, 0]);
        assert_eq!(t.num_boundary_edges(), 4);
        assert!(!t.is_closed());
        assert_eq!(t.euler_characteristic(), 1, "unused vertex 4 not counted");
        assert_eq!(
            t.normals[4],
            Vec3::ZERO,
            "unused vertex keeps a zero normal"
        );
        assert_eq!(t.normals[0], Vec3::Z);
    }

    #[test]
    fn obj_normal_degenerate_and_split() {
        let mut m = tet();
        m.normals = vec![[0.0, 0.0, 0.0], [0.0, 0.0, 2.0], [0.0, 0.0, 1.0]];
        m.face_normals = vec![1; m.face_vertices.len()];
        let t = TriMesh::from_mesh(&m, &tri_opts()).unwrap();
        assert_eq!(t.normal_source, NormalSource::Obj);
        assert!(t.normals.iter().all(|&n| n == Vec3::Z));
        // Same direction, different vn index: not a split.
        m.face_normals[4] = 2;
        assert!(TriMesh::from_mesh(&m, &tri_opts()).is_ok());
        m.face_normals[4] = 0; // face 1 corner 1 = vertex 1
        assert!(matches!(
            TriMesh::from_mesh(&m, &tri_opts()),
            Err(TriMeshError::DegenerateNormal { vertex: 1 })
        ));
        m.normals[0] = [0.0, 1.0, 0.0];
        assert!(matches!(
            TriMesh::from_mesh(&m, &tri_opts()),
            Err(TriMeshError::SplitNormal {
                vertex: 1,
                faces: [0, 1]
            })
        ));
        m.face_normals[5] = NO_NORMAL;
        assert!(matches!(
            TriMesh::from_mesh(&m, &tri_opts()),
            Err(TriMeshError::SplitNormal { .. })
        ));
        m.face_normals[4] = 1;
        assert!(matches!(
            TriMesh::from_mesh(&m, &tri_opts()),
            Err(TriMeshError::MissingNormal { face: 1, corner: 2 })
        ));
        let opts = TriOptions {
            recompute_normals: true,
            ..TriOptions::default()
        };
        let t = TriMesh::from_mesh(&m, &opts).unwrap();
        assert_eq!(t.normal_source, NormalSource::AreaWeighted);
    }

    #[test]
    fn cancelling_area_normals_are_degenerate() {
        // Two triangles glued back to back: every vertex's area normals cancel exactly.
        let m = Mesh::from_raw(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[vec![0, 1, 2], vec![0, 2, 1]],
        )
        .unwrap();
        assert!(matches!(
            TriMesh::from_mesh(&m, &tri_opts()),
            Err(TriMeshError::DegenerateNormal { vertex: 0 })
        ));
    }
}
