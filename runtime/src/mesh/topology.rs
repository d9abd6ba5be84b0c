//! Half-edge topology, vertex 1-rings and face corner records.
//!
//! Everything is stored in plain flat `Vec<u32>`s (OpenSubdiv Far style) so that it can be
//! uploaded to the GPU as-is and indexed from generated shader code.
//!
//! # Conventions (`spec/regular.md` §2, `spec/pccm.md` §1)
//!
//! * **Half-edges.** Face `f` with vertices `a_0 … a_{k-1}` (OBJ order, counter-clockwise seen
//!   from outside) owns the half-edges `h = face_offsets[f] + i`, `i = 0..k`, where half-edge `h`
//!   runs `a_i → a_{i+1}`. So half-edge ids equal positions in [`Mesh::face_vertices`].
//! * **Vertex ring.** For a vertex `p` of valence `n`, the ring is `[p, p_0, …, p_{2n-1}]`:
//!   `p_{2j}` are the edge neighbours, `p_{2j+1}` the vertex diagonal to `p` in sector `j`,
//!   counter-clockwise seen from outside. Sector `j` is the face containing the outgoing
//!   half-edge `p → p_{2j}`; if that face is `(p, p_{2j}, x, y)` in its own order then
//!   `p_{2j+1} = x` and `p_{2j+2} = y`.
//! * **Canonical start.** Each ring is stored once. Sector 0 is the sector whose outgoing
//!   half-edge has the smallest id among `p`'s outgoing half-edges. Patches never keep a private,
//!   rotated copy; they address the shared ring by `(vertex, sector)` through [`Corner`].
//! * **Corners.** Corner `i` of quad `q^0 q^1 q^2 q^3` is `(q^i, j_i)` with `p_{2 j_i} = q^{i+1}`
//!   in `q^i`'s ring. `j_i` is found through half-edge identity (the half-edge `q^i → q^{i+1}`
//!   of *this* face is sector `j_i`'s outgoing half-edge), never by searching vertex ids: on tiny
//!   meshes a vertex can occur twice in one ring, so a search could pick the wrong sector.
//!
//! Half-edges are paired into edges by their (unordered) vertex pair, so two distinct edges between the same
//! two vertices (a multigraph, e.g. a 2×n torus grid) show up as a non-manifold edge.
//!
//! This version supports closed, manifold, consistently oriented meshes only; boundaries are
//! reported as [`TopologyError::BoundaryEdges`].

use std::collections::BTreeMap;

use thiserror::Error;

use crate::mesh::{Mesh, MeshError};

/// Marker for "no such element" in the flat `u32` arrays (e.g. [`Topology::twin`] of a
/// boundary half-edge).
pub const NONE: u32 = u32::MAX;

/// Options for [`Topology::build`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TopologyOptions {
    /// Largest vertex valence accepted. Generated code has per-valence tables and fixed-size
    /// arrays, so the limit must be known up front. Default 32.
    pub max_valence: u32,
    /// Reject faces that are not quads ([`TopologyError::NonQuad`]). Default `true`: all
    /// patch schemes here are quad schemes. With `false`, other polygons are accepted; their
    /// sectors still follow the ring formula (`p_{2j+1}` = the vertex after `p_{2j}` in the
    /// face), which for a triangle makes `p_{2j+1} == p_{2j+2}`.
    pub require_quads: bool,
}

impl Default for TopologyOptions {
    fn default() -> Self {
        TopologyOptions {
            max_valence: 32,
            require_quads: true,
        }
    }
}

/// One corner of a quad: the mesh vertex and the sector of that vertex's ring that this quad
/// occupies (so `ring_point(vertex, 2*sector) = q^{i+1}`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Corner {
    /// Mesh vertex `q^i`.
    pub vertex: u32,
    /// Sector index `j_i` in `vertex`'s canonical ring.
    pub sector: u32,
}

impl Corner {
    /// Placeholder used in [`Topology::corners`] for faces that are not quads.
    pub const INVALID: Corner = Corner {
        vertex: NONE,
        sector: NONE,
    };
}

/// Patch class of a face.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FaceClass {
    /// A quad whose four corners all have valence 4: the regular bicubic B-spline patch applies.
    Ordinary,
    /// Any other face (a corner of valence ≠ 4, or a non-quad when quads are not required).
    Extraordinary,
}

/// Why a mesh is not usable for patch generation. Vertex numbers are 0-based file indices
/// (OBJ index − 1); faces are 0-based in file order.
#[derive(Debug, Error)]
pub enum TopologyError {
    /// The mesh itself is invalid.
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    /// A face is not a quad while [`TopologyOptions::require_quads`] is set.
    #[error("face {face} has {arity} vertices; only quads are supported")]
    NonQuad {
        /// 0-based face index.
        face: usize,
        /// Its number of vertices.
        arity: usize,
    },
    /// An edge is shared by more than two faces. `a → b` is the direction of the first
    /// (lowest half-edge id) face using it.
    #[error("edge {a}-{b} is used by more than two faces")]
    NonManifoldEdge {
        /// First vertex.
        a: u32,
        /// Second vertex.
        b: u32,
    },
    /// Exactly two faces share the edge, but both traverse it as `a → b`: one of them is
    /// flipped. (Kept apart from [`TopologyError::NonManifoldEdge`] because it is fixable by
    /// reorienting faces.)
    #[error("edge {a}->{b} is traversed in the same direction by both of its faces (inconsistent orientation)")]
    InconsistentOrientation {
        /// Origin of both half-edges.
        a: u32,
        /// Destination of both half-edges.
        b: u32,
    },
    /// The faces around a vertex form more than one fan (e.g. two surfaces touching at a point).
    #[error("vertex {vertex} is non-manifold: its faces form more than one fan")]
    NonManifoldVertex {
        /// The vertex.
        vertex: u32,
    },
    /// The mesh has boundary edges (used by one face); only closed meshes are supported.
    #[error("mesh is not closed: {count} boundary edges, first {first:?}")]
    BoundaryEdges {
        /// Number of boundary edges.
        count: usize,
        /// Up to 8 of them as `(origin, destination)` in half-edge order.
        first: Vec<(u32, u32)>,
    },
    /// A vertex has more edges than [`TopologyOptions::max_valence`].
    #[error("vertex {vertex} has valence {valence}, more than the maximum {max}")]
    ValenceTooHigh {
        /// The vertex.
        vertex: u32,
        /// Its valence.
        valence: u32,
        /// The configured maximum.
        max: u32,
    },
    /// An interior vertex has fewer than 3 edges (the ring formulas need `n ≥ 3`).
    #[error("vertex {vertex} has valence {valence}; interior vertices need at least 3")]
    ValenceTooLow {
        /// The vertex.
        vertex: u32,
        /// Its valence.
        valence: u32,
    },
}

/// Half-edge structure plus canonical vertex rings and quad corner records of a [`Mesh`].
///
/// All arrays are flat; `H` = number of half-edges (= `mesh.face_vertices.len()`), `V` = number
/// of mesh vertices (unused ones included), `F` = number of faces.
#[derive(Debug, Clone, PartialEq)]
pub struct Topology {
    /// Copy of [`Mesh::face_offsets`] (len `F+1`): face `f` owns half-edges
    /// `face_offsets[f]..face_offsets[f+1]`.
    pub face_offsets: Vec<u32>,
    /// Origin vertex of each half-edge (len `H`; equals [`Mesh::face_vertices`]).
    pub origin: Vec<u32>,
    /// Face of each half-edge (len `H`).
    pub face: Vec<u32>,
    /// Next half-edge in the same face (len `H`).
    pub next: Vec<u32>,
    /// Previous half-edge in the same face (len `H`).
    pub prev: Vec<u32>,
    /// Opposite half-edge (len `H`), [`NONE`] on a boundary (never, for meshes this version
    /// accepts).
    pub twin: Vec<u32>,
    /// Valence (number of edges = number of faces) of each vertex (len `V`); 0 for vertices no
    /// face uses.
    pub valence: Vec<u32>,
    /// Prefix sums of `valence` (len `V+1`): vertex `v`'s sectors are
    /// `sector_offsets[v]..sector_offsets[v+1]` in [`Topology::sector_halfedge`].
    pub sector_offsets: Vec<u32>,
    /// Outgoing half-edge `p → p_{2j}` of each sector `j`, vertex by vertex, in ring order
    /// (len `H`; every half-edge is exactly one sector of its origin).
    pub sector_halfedge: Vec<u32>,
    /// Inverse of `sector_halfedge`: the sector index `j` that half-edge `h` is in the ring of
    /// `origin[h]` (len `H`).
    pub halfedge_sector: Vec<u32>,
    /// Vertex `v`'s ring is `ring[ring_offsets[v]..ring_offsets[v+1]]` (len `V+1`).
    pub ring_offsets: Vec<u32>,
    /// All rings, flat: `[p, p_0, …, p_{2n-1}]` (`2n+1` entries) per used vertex, starting at
    /// the canonical sector 0. Vertices no face uses have an empty ring (no entries at all, not
    /// even `p`), so `ring_offsets[v] == ring_offsets[v+1]` identifies them.
    pub ring: Vec<u32>,
    /// The four corners of each face (len `F`), in face order `q^0..q^3`; [`Corner::INVALID`]
    /// for non-quads (only possible with `require_quads = false`).
    pub corners: Vec<[Corner; 4]>,
    /// Patch class of each face (len `F`).
    pub classes: Vec<FaceClass>,
    /// Vertex `v`'s sectors are `vertex_sectors[v]..vertex_sectors[v+1]` in
    /// [`Topology::sectors`] (len `V+1`); empty for smooth vertices
    /// (docs/boundaries.md §2).
    pub vertex_sectors: Vec<u32>,
    /// Sector records, 5 u32 each: kind, faces m, positions written, first
    /// ring position, start of the partial ring in [`Topology::ring`].
    pub sectors: Vec<u32>,
    /// Valence of the per-valence constants at corner `i` of face `f`, at
    /// `4f + i` (the virtual valence at crease and corner vertices).
    pub corner_valence: Vec<u32>,
}

impl Topology {
    /// Builds the topology and checks, in this order: the mesh itself, quads only (if
    /// required), edges (non-manifold, then orientation), boundary, vertex fans, valences.
    /// The first problem found is returned; within one check, the lowest face / half-edge /
    /// vertex wins, so errors are reproducible.
    pub fn build(mesh: &Mesh, opts: &TopologyOptions) -> Result<Topology, TopologyError> {
        // Guarantees indices in range and all counts (2H + V) below u32::MAX, which makes
        // every `as u32` below lossless.
        mesh.validate()?;
        let nv = mesh.num_vertices();
        let nf = mesh.num_faces();
        let nh = mesh.face_vertices.len();

        if opts.require_quads {
            if let Some(f) = (0..nf).find(|&f| mesh.face(f).len() != 4) {
                return Err(TopologyError::NonQuad {
                    face: f,
                    arity: mesh.face(f).len(),
                });
            }
        }

        // Half-edges inside faces.
        let origin = mesh.face_vertices.clone();
        let mut face = vec![0u32; nh];
        let mut next = vec![0u32; nh];
        let mut prev = vec![0u32; nh];
        for f in 0..nf {
            let (s, e) = (mesh.face_offsets[f], mesh.face_offsets[f + 1]);
            for h in s..e {
                face[h as usize] = f as u32;
                next[h as usize] = if h + 1 == e { s } else { h + 1 };
                prev[h as usize] = if h == s { e - 1 } else { h - 1 };
            }
        }
        let dest = |h: u32| origin[next[h as usize] as usize];

        // Twins: group half-edges by undirected vertex pair. Sorting (instead of hashing)
        // keeps the groups' internal order by half-edge id, so "first" is well defined.
        let mut keys: Vec<(u32, u32, u32)> = (0..nh as u32)
            .map(|h| {
                let (a, b) = (origin[h as usize], dest(h));
                (a.min(b), a.max(b), h)
            })
            .collect();
        keys.sort_unstable();
        let mut twin = vec![NONE; nh];
        let mut boundary: Vec<u32> = Vec::new();
        let mut non_manifold: Option<u32> = None;
        let mut flipped: Option<u32> = None;
        for group in keys.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let first = group[0].2;
            match group {
                [_] => boundary.push(first),
                [(_, _, h1), (_, _, h2)] => {
                    if origin[*h1 as usize] == origin[*h2 as usize] {
                        flipped = Some(flipped.map_or(first, |x| x.min(first)));
                    } else {
                        twin[*h1 as usize] = *h2;
                        twin[*h2 as usize] = *h1;
                    }
                }
                _ => non_manifold = Some(non_manifold.map_or(first, |x| x.min(first))),
            }
        }
        if let Some(h) = non_manifold {
            return Err(TopologyError::NonManifoldEdge {
                a: origin[h as usize],
                b: dest(h),
            });
        }
        if let Some(h) = flipped {
            return Err(TopologyError::InconsistentOrientation {
                a: origin[h as usize],
                b: dest(h),
            });
        }
        if !boundary.is_empty() {
            boundary.sort_unstable();
            return Err(TopologyError::BoundaryEdges {
                count: boundary.len(),
                first: boundary
                    .iter()
                    .take(8)
                    .map(|&h| (origin[h as usize], dest(h)))
                    .collect(),
            });
        }

        // Outgoing half-edges per vertex (counting sort, so each list is in increasing id
        // order and its first entry is the canonical sector 0).
        let mut valence = vec![0u32; nv];
        for &v in &origin {
            valence[v as usize] += 1;
        }
        let mut sector_offsets = Vec::with_capacity(nv + 1);
        sector_offsets.push(0u32);
        for &n in &valence {
            let last = sector_offsets[sector_offsets.len() - 1];
            sector_offsets.push(last + n);
        }
        let mut smallest_out = vec![NONE; nv];
        for h in (0..nh as u32).rev() {
            smallest_out[origin[h as usize] as usize] = h;
        }

        // Walk each fan counter-clockwise: the face of p → p_{2j} is (p, p_{2j}, x, y); its
        // half-edge y → p is prev(h), and the twin of that, p → y = p_{2j+2}, is the next
        // sector's half-edge. In a closed edge-manifold mesh this rotation is a permutation of
        // p's outgoing half-edges; one cycle covering all of them means a single fan.
        let mut sector_halfedge = vec![NONE; nh];
        let mut halfedge_sector = vec![NONE; nh];
        for v in 0..nv {
            let n = valence[v];
            if n == 0 {
                continue;
            }
            let base = sector_offsets[v] as usize;
            let start = smallest_out[v];
            let mut h = start;
            for j in 0..n {
                if j > 0 && h == start {
                    return Err(TopologyError::NonManifoldVertex { vertex: v as u32 });
                }
                sector_halfedge[base + j as usize] = h;
                halfedge_sector[h as usize] = j;
                h = twin[prev[h as usize] as usize];
            }
            if h != start {
                // Cannot happen for a permutation, but never loop or index blindly.
                return Err(TopologyError::NonManifoldVertex { vertex: v as u32 });
            }
        }

        for (v, &n) in valence.iter().enumerate() {
            if n > opts.max_valence {
                return Err(TopologyError::ValenceTooHigh {
                    vertex: v as u32,
                    valence: n,
                    max: opts.max_valence,
                });
            }
            if n > 0 && n < 3 {
                return Err(TopologyError::ValenceTooLow {
                    vertex: v as u32,
                    valence: n,
                });
            }
        }

        // Rings: p_{2j} = dest(s_j), p_{2j+1} = the vertex after p_{2j} in s_j's face.
        // (p_{2j+2} = dest(s_{j+1}) equals the vertex before p in s_j's face by the walk above.)
        let mut ring_offsets = Vec::with_capacity(nv + 1);
        let mut ring = Vec::with_capacity(2 * nh + nv);
        ring_offsets.push(0u32);
        for v in 0..nv {
            let (s, e) = (sector_offsets[v] as usize, sector_offsets[v + 1] as usize);
            if e > s {
                ring.push(v as u32);
                for &h in &sector_halfedge[s..e] {
                    let h1 = next[h as usize];
                    ring.push(origin[h1 as usize]);
                    ring.push(origin[next[h1 as usize] as usize]);
                }
            }
            ring_offsets.push(ring.len() as u32);
        }

        let mut corners = Vec::with_capacity(nf);
        let mut classes = Vec::with_capacity(nf);
        for f in 0..nf {
            let (s, e) = (mesh.face_offsets[f], mesh.face_offsets[f + 1]);
            if e - s == 4 {
                let c = |i: u32| Corner {
                    vertex: origin[(s + i) as usize],
                    sector: halfedge_sector[(s + i) as usize],
                };
                let cs = [c(0), c(1), c(2), c(3)];
                let regular = cs.iter().all(|c| valence[c.vertex as usize] == 4);
                corners.push(cs);
                classes.push(if regular {
                    FaceClass::Ordinary
                } else {
                    FaceClass::Extraordinary
                });
            } else {
                corners.push([Corner::INVALID; 4]);
                classes.push(FaceClass::Extraordinary);
            }
        }

        // Closed untagged meshes have no crease or corner vertices: no
        // sectors, and every corner uses its vertex's own valence.
        let vertex_sectors = vec![0u32; valence.len() + 1];
        let corner_valence = corners
            .iter()
            .flat_map(|c| {
                c.map(|k| {
                    if k.vertex == NONE {
                        0
                    } else {
                        valence[k.vertex as usize]
                    }
                })
            })
            .collect();
        Ok(Topology {
            vertex_sectors,
            sectors: Vec::new(),
            corner_valence,
            face_offsets: mesh.face_offsets.clone(),
            origin,
            face,
            next,
            prev,
            twin,
            valence,
            sector_offsets,
            sector_halfedge,
            halfedge_sector,
            ring_offsets,
            ring,
            corners,
            classes,
        })
    }

    /// Number of vertices (including unused ones).
    pub fn num_vertices(&self) -> usize {
        self.valence.len()
    }

    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.classes.len()
    }

    /// Number of half-edges.
    pub fn num_halfedges(&self) -> usize {
        self.origin.len()
    }

    /// Number of undirected edges (twin pairs plus boundary half-edges).
    pub fn num_edges(&self) -> usize {
        let boundary = self.twin.iter().filter(|&&t| t == NONE).count();
        (self.num_halfedges() + boundary) / 2
    }

    /// Destination vertex of half-edge `h`.
    pub fn dest(&self, h: u32) -> u32 {
        self.origin[self.next[h as usize] as usize]
    }

    /// Vertex `v`'s ring `[p, p_0, …, p_{2n-1}]`; empty for unused vertices.
    pub fn ring(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.ring[self.ring_offsets[v] as usize..self.ring_offsets[v + 1] as usize]
    }

    /// Ring point `p_k` of vertex `v`, `k` taken mod `2n` (so `ring_point(v, 2n) == p_0`).
    /// Panics for unused vertices.
    pub fn ring_point(&self, v: u32, k: u32) -> u32 {
        let r = self.ring(v);
        let two_n = (r.len() - 1) as u32;
        r[1 + (k % two_n) as usize]
    }

    /// Vertex `v`'s sector half-edges (`p → p_{2j}` for `j = 0..n`).
    pub fn sector_halfedges(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.sector_halfedge[self.sector_offsets[v] as usize..self.sector_offsets[v + 1] as usize]
    }

    /// Index of the first face that is not [`FaceClass::Ordinary`].
    pub fn first_extraordinary_face(&self) -> Option<usize> {
        self.classes
            .iter()
            .position(|&c| c == FaceClass::Extraordinary)
    }

    /// Fraction of faces that are extraordinary (0 for a face-less topology).
    pub fn extraordinary_fraction(&self) -> f64 {
        if self.classes.is_empty() {
            return 0.0;
        }
        let n = self
            .classes
            .iter()
            .filter(|&&c| c == FaceClass::Extraordinary)
            .count();
        n as f64 / self.classes.len() as f64
    }

    /// Valence → number of vertices with it, over used vertices (valence 0 is not listed).
    pub fn valence_histogram(&self) -> BTreeMap<u32, usize> {
        let mut h = BTreeMap::new();
        for &n in self.valence.iter().filter(|&&n| n > 0) {
            *h.entry(n).or_insert(0) += 1;
        }
        h
    }

    /// `V - E + F` counting only used vertices (2 for a sphere, 0 for a torus, 2 − 2g).
    pub fn euler_characteristic(&self) -> i64 {
        let used = self.valence.iter().filter(|&&n| n > 0).count();
        used as i64 - self.num_edges() as i64 + self.num_faces() as i64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::{Path, PathBuf};

    fn mesh_path(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../tests/data/meshes")
            .join(format!("{name}.obj"))
    }

    fn load(name: &str) -> Mesh {
        Mesh::from_obj_path(mesh_path(name)).unwrap()
    }

    fn build(mesh: &Mesh) -> Result<Topology, TopologyError> {
        Topology::build(mesh, &TopologyOptions::default())
    }

    fn build_str(text: &str) -> Result<Topology, TopologyError> {
        build(&Mesh::from_obj_str(text).unwrap())
    }

    /// OBJ text from 0-based faces; positions are dummies (topology ignores them).
    fn obj(num_vertices: usize, faces: &[&[u32]]) -> String {
        let mut s = String::new();
        for i in 0..num_vertices {
            s += &format!("v {i} {} 0\n", i * i);
        }
        for f in faces {
            s += "f";
            for v in *f {
                s += &format!(" {}", v + 1);
            }
            s += "\n";
        }
        s
    }

    const CUBE: [[u32; 4]; 6] = [
        [0, 1, 3, 2],
        [2, 3, 5, 4],
        [4, 5, 7, 6],
        [6, 7, 1, 0],
        [1, 7, 5, 3],
        [6, 0, 2, 4],
    ];

    fn cube_faces(offset: u32) -> Vec<Vec<u32>> {
        CUBE.iter()
            .map(|f| f.iter().map(|&v| v + offset).collect())
            .collect()
    }

    /// Every structural property the rest of tessgen relies on, checked against the mesh's
    /// own face arrays (not against `next`/`prev`, which `build` produced itself).
    fn check_invariants(mesh: &Mesh, t: &Topology) {
        let nh = mesh.face_vertices.len();
        assert_eq!(t.num_halfedges(), nh);
        assert_eq!(t.origin, mesh.face_vertices);
        for h in 0..nh as u32 {
            let tw = t.twin[h as usize];
            assert_ne!(tw, NONE);
            assert_eq!(t.twin[tw as usize], h);
            assert_eq!(t.origin[tw as usize], t.dest(h));
            assert_eq!(t.dest(tw), t.origin[h as usize]);
            // sector tables are inverse to each other
            let v = t.origin[h as usize];
            let j = t.halfedge_sector[h as usize];
            assert_eq!(t.sector_halfedges(v)[j as usize], h);
        }
        for v in 0..mesh.num_vertices() as u32 {
            let n = t.valence[v as usize];
            let ring = t.ring(v);
            let sectors = t.sector_halfedges(v);
            assert_eq!(sectors.len(), n as usize);
            if n == 0 {
                assert!(ring.is_empty());
                continue;
            }
            assert_eq!(ring.len(), 2 * n as usize + 1);
            assert_eq!(ring[0], v);
            // canonical start: smallest outgoing half-edge id
            let min_out = (0..nh as u32)
                .filter(|&h| t.origin[h as usize] == v)
                .min()
                .unwrap();
            assert_eq!(sectors[0], min_out);
            for j in 0..n {
                // sector property: face of p -> p_{2j} is (p, p_{2j}, p_{2j+1}, p_{2j+2})
                let h = sectors[j as usize];
                let f = t.face[h as usize] as usize;
                let fv = mesh.face(f);
                let k = fv.len();
                let i = (h - mesh.face_offsets[f]) as usize;
                assert_eq!(fv[i], v);
                assert_eq!(fv[(i + 1) % k], t.ring_point(v, 2 * j));
                assert_eq!(fv[(i + 2) % k], t.ring_point(v, 2 * j + 1));
                assert_eq!(fv[(i + k - 1) % k], t.ring_point(v, 2 * j + 2));
            }
        }
        for f in 0..mesh.num_faces() {
            let q = mesh.face(f);
            if q.len() != 4 {
                assert_eq!(t.corners[f], [Corner::INVALID; 4]);
                continue;
            }
            for i in 0..4 {
                let c = t.corners[f][i];
                assert_eq!(c.vertex, q[i]);
                assert_eq!(t.ring_point(c.vertex, 2 * c.sector), q[(i + 1) % 4]);
                assert_eq!(t.ring_point(c.vertex, 2 * c.sector + 1), q[(i + 2) % 4]);
                assert_eq!(t.ring_point(c.vertex, 2 * c.sector + 2), q[(i + 3) % 4]);
                // the sector is this face's half-edge, not just any matching vertex
                assert_eq!(
                    t.sector_halfedges(c.vertex)[c.sector as usize],
                    mesh.face_offsets[f] + i as u32
                );
            }
            let ordinary = q.iter().all(|&v| t.valence[v as usize] == 4);
            assert_eq!(t.classes[f] == FaceClass::Ordinary, ordinary);
        }
    }

    #[test]
    fn real_closed_meshes() {
        // (mesh, valence histogram from meshes/README.md, Euler characteristic)
        type Case = (&'static str, &'static [(u32, usize)], i64);
        let cases: [Case; 4] = [
            ("catmark_cube", &[(3, 8)], 2),
            ("catmark_torus", &[(4, 32)], 0),
            ("catmark_toroidal_tet", &[(4, 12), (6, 8)], -4),
            ("catmark_righthanded", &[(3, 56), (4, 332), (5, 48)], 2),
        ];
        for (name, hist, euler) in cases {
            let mesh = load(name);
            let t = build(&mesh).unwrap_or_else(|e| panic!("{name}: {e}"));
            let expected: BTreeMap<u32, usize> = hist.iter().copied().collect();
            assert_eq!(t.valence_histogram(), expected, "{name}");
            assert_eq!(t.euler_characteristic(), euler, "{name}");
            assert_eq!(t.num_edges() * 2, t.num_halfedges(), "{name}");
            check_invariants(&mesh, &t);
        }
    }

    #[test]
    fn face_classes() {
        let torus = build(&load("catmark_torus")).unwrap();
        assert!(torus.classes.iter().all(|&c| c == FaceClass::Ordinary));
        assert_eq!(torus.first_extraordinary_face(), None);
        assert_eq!(torus.extraordinary_fraction(), 0.0);
        let cube = build(&load("catmark_cube")).unwrap();
        assert_eq!(cube.first_extraordinary_face(), Some(0));
        assert_eq!(cube.extraordinary_fraction(), 1.0);
        let rh = build(&load("catmark_righthanded")).unwrap();
        let f = rh.first_extraordinary_face().unwrap();
        assert!(rh.classes[..f].iter().all(|&c| c == FaceClass::Ordinary));
        let frac = rh.extraordinary_fraction();
        assert!(frac > 0.0 && frac < 1.0);
    }

    #[test]
    fn cube_ring_by_hand() {
        // Vertex 0 is in faces 0 (0,1,3,2), 3 (6,7,1,0) and 5 (6,0,2,4). Its outgoing
        // half-edges are 0 (0->1, face 0), 15 (0->6, face 3) and 21 (0->2, face 5).
        // Sector 0 starts at half-edge 0: face 0 read from 0 is (0,1,3,2) -> p0=1, p1=3, p2=2.
        // Next sector: 0->2 (half-edge 21), face 5 from 0 is (0,2,4,6) -> p3=4, p4=6.
        // Then 0->6 (half-edge 15), face 3 from 0 is (0,6,7,1) -> p5=7, back to p0=1.
        let t = build_str(&obj(8, &CUBE.iter().map(|f| &f[..]).collect::<Vec<_>>())).unwrap();
        assert_eq!(t.ring(0), &[0, 1, 3, 2, 4, 6, 7]);
        assert_eq!(t.sector_halfedges(0), &[0, 21, 15]);
        assert_eq!(
            t.corners[5][1],
            Corner {
                vertex: 0,
                sector: 1
            }
        );
    }

    /// A 12-vertex torus, the quotient of the square grid by the lattice spanned by (2,2) and
    /// (3,-3): vertex (i,j) is (5i + j) mod 12. Every vertex has valence 4, there are no
    /// multi-edges, but the diagonal vertices (1,1) and (-1,-1) are the same vertex: each ring
    /// contains one vertex twice (pccm.md §1's "tiny mesh" case).
    fn skew_torus() -> Mesh {
        let faces: Vec<Vec<u32>> = (0..12u32)
            .map(|j| vec![j, (j + 5) % 12, (j + 6) % 12, (j + 1) % 12])
            .collect();
        let positions = (0..12).map(|i| [i as f32, 0.0, 0.0]).collect();
        Mesh::from_raw(positions, &faces).unwrap()
    }

    #[test]
    fn repeated_vertex_in_ring() {
        let mesh = skew_torus();
        let t = build(&mesh).unwrap();
        check_invariants(&mesh, &t);
        assert_eq!(t.valence_histogram(), BTreeMap::from([(4, 12)]));
        assert_eq!(t.euler_characteristic(), 0);
        assert!(t.classes.iter().all(|&c| c == FaceClass::Ordinary));
        let ring = t.ring(0);
        let mut seen = ring[1..].to_vec();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(
            seen.len(),
            ring.len() - 2,
            "exactly one repeated ring vertex"
        );
    }

    #[test]
    fn small_torus_grid() {
        // 3x3 torus: all rings distinct, but each quad's 16-point 1-ring repeats vertices.
        let id = |i: u32, j: u32| (i % 3) * 3 + j % 3;
        let faces: Vec<Vec<u32>> = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
            .collect();
        let mesh = Mesh::from_raw((0..9).map(|i| [i as f32, 0.0, 0.0]).collect(), &faces).unwrap();
        let t = build(&mesh).unwrap();
        check_invariants(&mesh, &t);
        assert_eq!(t.euler_characteristic(), 0);
    }

    #[test]
    fn unused_vertex_has_empty_ring() {
        let mut text = obj(8, &CUBE.iter().map(|f| &f[..]).collect::<Vec<_>>());
        text = format!("v 5 5 5\n{text}")
            .lines()
            .map(|l| {
                // shift face indices by one for the extra leading vertex
                if let Some(rest) = l.strip_prefix("f ") {
                    let shifted: Vec<String> = rest
                        .split_whitespace()
                        .map(|w| (w.parse::<u32>().unwrap() + 1).to_string())
                        .collect();
                    format!("f {}\n", shifted.join(" "))
                } else {
                    format!("{l}\n")
                }
            })
            .collect();
        let mesh = Mesh::from_obj_str(&text).unwrap();
        let t = build(&mesh).unwrap();
        assert_eq!(t.valence[0], 0);
        assert!(t.ring(0).is_empty());
        assert!(t.sector_halfedges(0).is_empty());
        assert_eq!(t.valence_histogram(), BTreeMap::from([(3, 8)]));
        assert_eq!(t.euler_characteristic(), 2);
        check_invariants(&mesh, &t);
    }

    #[test]
    fn error_non_quad() {
        // tetrahedron: closed, all triangles
        let tet: [&[u32]; 4] = [&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[2, 0, 3]];
        let e = build_str(&obj(4, &tet)).unwrap_err();
        assert!(
            matches!(e, TopologyError::NonQuad { face: 0, arity: 3 }),
            "{e:?}"
        );
        // accepted when quads are not required
        let mesh = Mesh::from_obj_str(&obj(4, &tet)).unwrap();
        let opts = TopologyOptions {
            require_quads: false,
            ..Default::default()
        };
        let t = Topology::build(&mesh, &opts).unwrap();
        check_invariants(&mesh, &t);
        assert_eq!(t.euler_characteristic(), 2);
        assert_eq!(t.valence_histogram(), BTreeMap::from([(3, 4)]));
        assert!(t.classes.iter().all(|&c| c == FaceClass::Extraordinary));
    }

    #[test]
    fn error_non_manifold_edge() {
        // three quads on edge 0-1
        let faces: [&[u32]; 3] = [&[0, 1, 2, 3], &[1, 0, 4, 5], &[0, 1, 6, 7]];
        let e = build_str(&obj(8, &faces)).unwrap_err();
        assert!(
            matches!(e, TopologyError::NonManifoldEdge { a: 0, b: 1 }),
            "{e:?}"
        );
    }

    #[test]
    fn error_inconsistent_orientation() {
        // cube with face 0 reversed: its half-edge 0 (2 -> 3) runs the same way as face 1's.
        let mut faces = CUBE;
        faces[0] = [2, 3, 1, 0];
        let e = build_str(&obj(8, &faces.iter().map(|f| &f[..]).collect::<Vec<_>>())).unwrap_err();
        assert!(
            matches!(e, TopologyError::InconsistentOrientation { a: 2, b: 3 }),
            "{e:?}"
        );
    }

    #[test]
    fn error_boundary() {
        let e = build_str(&obj(4, &[&[0, 1, 2, 3]])).unwrap_err();
        match e {
            TopologyError::BoundaryEdges { count, first } => {
                assert_eq!(count, 4);
                assert_eq!(first, vec![(0, 1), (1, 2), (2, 3), (3, 0)]);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn boundary_meshes_are_rejected() {
        let cases = [
            ("catmark_tent", 12),
            ("catmark_single_crease", 48),
            ("catmark_gregory_test1", 4),
            ("catmark_fvar_bound3", 12),
            ("catmark_xord_interior", 142),
            ("catmark_xord_boundary", 44),
            ("catmark_car", 60),
            ("catmark_pawn", 24),
        ];
        for (name, n) in cases {
            let mesh = load(name);
            match build(&mesh) {
                Err(TopologyError::BoundaryEdges { count, first }) => {
                    assert_eq!(count, n, "{name}");
                    assert_eq!(first.len(), n.min(8), "{name}");
                }
                other => panic!("{name}: {other:?}"),
            }
        }
    }

    #[test]
    fn error_non_manifold_vertex() {
        // two cubes sharing vertex 0 only
        let mut faces = cube_faces(0);
        let second: Vec<Vec<u32>> = cube_faces(7)
            .into_iter()
            .map(|f| f.into_iter().map(|v| if v == 7 { 0 } else { v }).collect())
            .collect();
        faces.extend(second);
        let mesh = Mesh::from_raw((0..15).map(|i| [i as f32, 0.0, 0.0]).collect(), &faces).unwrap();
        let e = build(&mesh).unwrap_err();
        assert!(
            matches!(e, TopologyError::NonManifoldVertex { vertex: 0 }),
            "{e:?}"
        );
    }

    #[test]
    fn error_valence_too_low() {
        // "pillow": two quads glued along all four edges; every vertex has valence 2
        let e = build_str(&obj(4, &[&[0, 1, 2, 3], &[3, 2, 1, 0]])).unwrap_err();
        assert!(
            matches!(
                e,
                TopologyError::ValenceTooLow {
                    vertex: 0,
                    valence: 2
                }
            ),
            "{e:?}"
        );
    }

    #[test]
    fn error_valence_too_high() {
        let mesh = load("catmark_toroidal_tet");
        let opts = TopologyOptions {
            max_valence: 5,
            ..Default::default()
        };
        let e = Topology::build(&mesh, &opts).unwrap_err();
        let first6 = build(&mesh)
            .unwrap()
            .valence
            .iter()
            .position(|&n| n == 6)
            .unwrap();
        assert!(
            matches!(e, TopologyError::ValenceTooHigh { vertex, valence: 6, max: 5 } if vertex as usize == first6),
            "{e:?}"
        );
    }

    #[test]
    fn error_mesh_wrapped() {
        let mut mesh = load("catmark_cube");
        mesh.face_vertices[0] = 99;
        let e = build(&mesh).unwrap_err();
        assert!(
            matches!(
                e,
                TopologyError::Mesh(MeshError::FaceIndexOutOfRange { face: 0, index: 99 })
            ),
            "{e:?}"
        );
        // `?` converts loader errors too
        fn load_and_build(text: &str) -> Result<Topology, TopologyError> {
            build(&Mesh::from_obj_str(text)?)
        }
        assert!(matches!(
            load_and_build("# empty\n"),
            Err(TopologyError::Mesh(MeshError::Empty))
        ));
    }

    #[test]
    fn check_order_quads_before_edges() {
        // a lone triangle: non-quad is reported before its boundary
        let e = build_str(&obj(3, &[&[0, 1, 2]])).unwrap_err();
        assert!(matches!(e, TopologyError::NonQuad { face: 0, arity: 3 }));
    }
}
