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
//! Open and tagged meshes (`docs/boundaries.md`): boundary half-edges have `twin = NONE`; the
//! mesh's `t` lines (or explicit [`Features`]) make edges sharp, sharp edges cut a crease or
//! corner vertex's fan into sectors ([`crate::mesh::sectors`]), and the vertex's ring holds
//! the sectors' partial rings. A closed untagged mesh gives exactly the arrays above.

use std::collections::BTreeMap;

use crate::mesh::features::{FeatureWarning, Features};
use crate::mesh::sectors::{self, HalfEdges};
pub use crate::mesh::sectors::{max_sector_faces, VertexRule, SECTOR_WORDS};
pub use crate::mesh::topology_error::{TopologyError, NONE};
use crate::mesh::Mesh;

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
    /// A quad whose four corners are all regular (smooth with valence 4 and no sharp edge,
    /// crease with a sector of 2 faces, corner with a sector of 1 face): the bicubic B-spline
    /// of the (phantom) grid applies.
    Ordinary,
    /// Any other face (a corner of valence ≠ 4, or a non-quad when quads are not required).
    Extraordinary,
}

/// Half-edge structure plus canonical vertex rings and quad corner records of a [`Mesh`].
///
/// All arrays are flat; `H` = number of half-edges (= `mesh.face_vertices.len()`), `V` = number
/// of mesh vertices (unused ones included), `F` = number of faces, `S` = number of sectors.
/// Ring positions, sectors and the canonical start follow `docs/boundaries.md` §2.
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
    /// Opposite half-edge (len `H`), [`NONE`] on a boundary.
    pub twin: Vec<u32>,
    /// Number of ring positions `n_layout` of each vertex (len `V`): the number of faces for
    /// an interior vertex, faces + 1 (its edge valence) for a boundary vertex; 0 for vertices
    /// no face uses.
    pub valence: Vec<u32>,
    /// Prefix sums of the number of outgoing half-edges (= faces) per vertex (len `V+1`):
    /// vertex `v`'s outgoing half-edges are `sector_offsets[v]..sector_offsets[v+1]` in
    /// [`Topology::sector_halfedge`]. Equal to the prefix sums of `valence` for closed meshes.
    pub sector_offsets: Vec<u32>,
    /// Outgoing half-edge `p → q_j` of each ring position `j < faces`, vertex by vertex, in
    /// ring order (len `H`; every half-edge is exactly one position of its origin).
    pub sector_halfedge: Vec<u32>,
    /// Inverse of `sector_halfedge`: the ring position `j` that half-edge `h` is in the ring of
    /// `origin[h]` (len `H`).
    pub halfedge_sector: Vec<u32>,
    /// Vertex `v`'s ring is `ring[ring_offsets[v]..ring_offsets[v+1]]` (len `V+1`).
    pub ring_offsets: Vec<u32>,
    /// All rings, flat. Smooth and dart vertices: `[p, p_0, …, p_{2n-1}]` (`2n+1` entries),
    /// starting at the canonical position 0. Crease and corner vertices: their sectors' partial
    /// rings `[p, q_0, d_0, …, d_{m−1}, q_m]` (`2m+2` entries each), concatenated in sector
    /// order. Vertices no face uses have an empty ring (no entries at all, not even `p`), so
    /// `ring_offsets[v] == ring_offsets[v+1]` identifies them.
    pub ring: Vec<u32>,
    /// The four corners of each face (len `F`), in face order `q^0..q^3`; [`Corner::INVALID`]
    /// for non-quads (only possible with `require_quads = false`). `sector` is the ring
    /// position of the face's edge `q^i → q^{i+1}`.
    pub corners: Vec<[Corner; 4]>,
    /// Patch class of each face (len `F`).
    pub classes: Vec<FaceClass>,
    /// Vertex `v`'s sectors are `vertex_sectors[v]..vertex_sectors[v+1]` (len `V+1`); none for
    /// smooth, dart and unused vertices.
    pub vertex_sectors: Vec<u32>,
    /// [`SECTOR_WORDS`] per sector `s` at `5s`: `[kind, m, count, j0, ring_base]` with
    /// kind 0 crease, 1 corner, `m` its faces,
    /// `count` the ring positions it writes (`m`, or `m + 1` for the last sector of a boundary
    /// vertex), `j0` its first ring position and `ring_base` the index into [`Topology::ring`]
    /// of its partial ring's `p` (len `5S`).
    pub sectors: Vec<u32>,
    /// Per face corner (`4f + i`, len `4F`): the valence whose per-valence constants the patch
    /// stage uses: the vertex valence at smooth and dart corners, the virtual valence
    /// `n'(m)` (4 if `m = 1`, else `2m`) of the face's sector at crease and corner corners;
    /// [`NONE`] for non-quads.
    pub corner_valence: Vec<u32>,
    /// Rule of each vertex (len `V`; [`VertexRule::Smooth`] for unused vertices).
    pub vertex_rule: Vec<VertexRule>,
    /// Per face (len `F`): the face has no limit surface and emits no patch (a hole, or with
    /// boundary rule 0 a face touching a boundary vertex).
    pub no_limit: Vec<bool>,
    /// Per half-edge (len `H`): its edge cuts fans into sectors (a boundary edge, or
    /// sharpness > 0; semi-sharp edges are applied as infinitely sharp). With boundary rule 0
    /// the boundary edges still bound the open fans (the faces there are `no_limit`).
    pub edge_sharp: Vec<bool>,
    /// The boundary half-edges (`twin = NONE`), in increasing id.
    pub boundary_halfedges: Vec<u32>,
    /// The features applied (the mesh's tags for [`Topology::build`]).
    pub features: Features,
    /// Tag warnings of [`Features::from_mesh`] (empty for [`Topology::build_with`]).
    pub warnings: Vec<FeatureWarning>,
}

impl Topology {
    /// Builds the topology with the mesh's own tags ([`Features::from_mesh`]); see
    /// [`Topology::build_with`]. Tag warnings end up in [`Topology::warnings`].
    pub fn build(mesh: &Mesh, opts: &TopologyOptions) -> Result<Topology, TopologyError> {
        mesh.validate()?;
        let (features, warnings) = Features::from_mesh(mesh)?;
        let mut t = Topology::build_with(mesh, opts, &features)?;
        t.warnings = warnings;
        Ok(t)
    }

    /// Builds the topology with explicit features (the mesh's tags are not read) and checks,
    /// in this order: the mesh itself, the features, quads only (if required), edges
    /// (non-manifold, then orientation), vertex fans, valences, sector sizes.
    /// The first problem found is returned; within one check, the lowest face / half-edge /
    /// vertex wins, so errors are reproducible.
    pub fn build_with(
        mesh: &Mesh,
        opts: &TopologyOptions,
        features: &Features,
    ) -> Result<Topology, TopologyError> {
        // Guarantees indices in range and all counts (2H + V) below u32::MAX, which makes
        // every `as u32` below lossless.
        mesh.validate()?;
        features.validate(mesh)?;
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
        let mut boundary_halfedges: Vec<u32> = Vec::new();
        let mut non_manifold: Option<u32> = None;
        let mut flipped: Option<u32> = None;
        for group in keys.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let first = group[0].2;
            match group {
                [_] => boundary_halfedges.push(first),
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
        boundary_halfedges.sort_unstable();
        let edge_sharp: Vec<bool> = (0..nh as u32)
            .map(|h| twin[h as usize] == NONE || features.edge(origin[h as usize], dest(h)) > 0.0)
            .collect();

        // Outgoing half-edges per vertex: count, smallest id, outgoing boundary half-edges.
        let mut faces_at = vec![0u32; nv];
        let mut smallest_out = vec![NONE; nv];
        let mut boundary_out = vec![(NONE, 0u32); nv];
        for h in (0..nh as u32).rev() {
            let v = origin[h as usize] as usize;
            faces_at[v] += 1;
            smallest_out[v] = h;
            if twin[h as usize] == NONE {
                boundary_out[v] = (h, boundary_out[v].1 + 1);
            }
        }
        let mut sector_offsets = Vec::with_capacity(nv + 1);
        sector_offsets.push(0u32);
        for &n in &faces_at {
            let last = sector_offsets[sector_offsets.len() - 1];
            sector_offsets.push(last + n);
        }

        // Walk each fan counter-clockwise: the face of p → q_j is (p, q_j, d_j, q_{j+1}); its
        // half-edge q_{j+1} → p is prev(h), and the twin of that, p → q_{j+1}, is the next
        // position's half-edge (sectors.rs classifies, rotates and cuts the fan).
        let he = HalfEdges {
            prev: &prev,
            twin: &twin,
            sharp: &edge_sharp,
        };
        let mut fans = Vec::with_capacity(nv);
        for v in 0..nv {
            fans.push(if faces_at[v] == 0 {
                None
            } else {
                Some(sectors::fan(
                    &he,
                    features,
                    v as u32,
                    faces_at[v],
                    smallest_out[v],
                    boundary_out[v],
                )?)
            });
        }
        let valence: Vec<u32> = fans
            .iter()
            .map(|f| {
                f.as_ref()
                    .map_or(0, |f| f.halfedges.len() as u32 + u32::from(f.boundary))
            })
            .collect();

        for (v, fan) in fans.iter().enumerate() {
            let Some(fan) = fan else { continue };
            let n = valence[v];
            if n > opts.max_valence {
                return Err(TopologyError::ValenceTooHigh {
                    vertex: v as u32,
                    valence: n,
                    max: opts.max_valence,
                });
            }
            if !fan.boundary && n < 3 {
                return Err(TopologyError::ValenceTooLow {
                    vertex: v as u32,
                    valence: n,
                });
            }
        }
        let max_m = max_sector_faces(opts.max_valence);
        for (v, fan) in fans.iter().enumerate() {
            if let Some(&(_, m)) = fan
                .as_ref()
                .and_then(|f| f.sectors.iter().find(|&&(_, m)| m > max_m))
            {
                return Err(TopologyError::SectorTooLarge {
                    vertex: v as u32,
                    faces: m,
                    max: max_m,
                    needed: 2 * m,
                });
            }
        }

        // Ring positions, rings and sectors. q_j = dest(fan[j]), d_j = the vertex after q_j in
        // fan[j]'s face; q_faces = q_0 (interior) or the trailing boundary neighbour.
        let mut sector_halfedge = vec![NONE; nh];
        let mut halfedge_sector = vec![NONE; nh];
        let mut ring_offsets = Vec::with_capacity(nv + 1);
        let mut ring = Vec::with_capacity(2 * nh + nv);
        let mut vertex_sectors = Vec::with_capacity(nv + 1);
        let mut sectors_flat = Vec::new();
        let mut vertex_rule = vec![VertexRule::Smooth; nv];
        // per half-edge: faces of its sector at its origin (crease/corner only)
        let mut halfedge_m = vec![0u32; nh];
        ring_offsets.push(0u32);
        vertex_sectors.push(0u32);
        for v in 0..nv {
            if let Some(fan) = &fans[v] {
                vertex_rule[v] = fan.rule;
                let base = sector_offsets[v] as usize;
                for (j, &h) in fan.halfedges.iter().enumerate() {
                    sector_halfedge[base + j] = h;
                    halfedge_sector[h as usize] = j as u32;
                }
                let k = fan.halfedges.len();
                let q = |j: usize| {
                    if j < k {
                        dest(fan.halfedges[j])
                    } else if fan.boundary {
                        origin[prev[fan.halfedges[k - 1] as usize] as usize]
                    } else {
                        dest(fan.halfedges[0])
                    }
                };
                let d = |j: usize| origin[next[next[fan.halfedges[j] as usize] as usize] as usize];
                if fan.sectors.is_empty() {
                    ring.push(v as u32);
                    for j in 0..k {
                        ring.push(q(j));
                        ring.push(d(j));
                    }
                } else {
                    let last = fan.sectors.len() - 1;
                    for (i, &(j0, m)) in fan.sectors.iter().enumerate() {
                        let corner = fan.rule == VertexRule::Corner;
                        let count = m + u32::from(fan.boundary && i == last);
                        let kind = if corner {
                            sectors::SECTOR_KIND_CORNER
                        } else {
                            sectors::SECTOR_KIND_CREASE
                        };
                        sectors_flat.extend([kind, m, count, j0, ring.len() as u32]);
                        ring.push(v as u32);
                        for j in j0 as usize..(j0 + m) as usize {
                            ring.push(q(j));
                            ring.push(d(j));
                            halfedge_m[fan.halfedges[j] as usize] = m;
                        }
                        ring.push(q((j0 + m) as usize));
                    }
                }
            }
            ring_offsets.push(ring.len() as u32);
            vertex_sectors.push((sectors_flat.len() / SECTOR_WORDS) as u32);
        }

        // Corners, corner valences, classes.
        let mut corners = Vec::with_capacity(nf);
        let mut classes = Vec::with_capacity(nf);
        let mut corner_valence = Vec::with_capacity(4 * nf);
        for f in 0..nf {
            let (s, e) = (mesh.face_offsets[f], mesh.face_offsets[f + 1]);
            if e - s == 4 {
                let c = |i: u32| Corner {
                    vertex: origin[(s + i) as usize],
                    sector: halfedge_sector[(s + i) as usize],
                };
                let cs = [c(0), c(1), c(2), c(3)];
                let mut regular = true;
                for h in s..e {
                    let v = origin[h as usize] as usize;
                    let m = halfedge_m[h as usize];
                    let (n, ok) = match vertex_rule[v] {
                        VertexRule::Smooth => (valence[v], valence[v] == 4),
                        VertexRule::Dart => (valence[v], false),
                        VertexRule::Crease => (sectors::virtual_valence(m), m == 2),
                        VertexRule::Corner => (sectors::virtual_valence(m), m == 1),
                    };
                    corner_valence.push(n);
                    regular &= ok;
                }
                corners.push(cs);
                classes.push(if regular {
                    FaceClass::Ordinary
                } else {
                    FaceClass::Extraordinary
                });
            } else {
                corners.push([Corner::INVALID; 4]);
                classes.push(FaceClass::Extraordinary);
                corner_valence.extend([NONE; 4]);
            }
        }
        let is_boundary = |v: u32| fans[v as usize].as_ref().is_some_and(|f| f.boundary);
        let no_limit = (0..nf)
            .map(|f| {
                features.holes.contains(&(f as u32))
                    || (!features.boundary.boundary_sharp()
                        && mesh.face(f).iter().any(|&v| is_boundary(v)))
            })
            .collect();

        Ok(Topology {
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
            vertex_sectors,
            sectors: sectors_flat,
            corner_valence,
            vertex_rule,
            no_limit,
            edge_sharp,
            boundary_halfedges,
            features: features.clone(),
            warnings: Vec::new(),
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
    /// Meaningful for smooth and dart vertices (full rings); crease and corner vertices store
    /// partial rings (see [`Topology::sector_ring`]). Panics for unused vertices.
    pub fn ring_point(&self, v: u32, k: u32) -> u32 {
        let r = self.ring(v);
        let two_n = (r.len() - 1) as u32;
        r[1 + (k % two_n) as usize]
    }

    /// Vertex `v`'s sectors as indices into [`Topology::sectors`] (`s` → words `5s..5s+5`);
    /// empty for smooth, dart and unused vertices.
    pub fn vertex_sector_range(&self, v: u32) -> std::ops::Range<usize> {
        self.vertex_sectors[v as usize] as usize..self.vertex_sectors[v as usize + 1] as usize
    }

    /// Number of sectors (all vertices).
    pub fn num_sectors(&self) -> usize {
        self.sectors.len() / SECTOR_WORDS
    }

    /// Sector `s`'s words `[kind, m, count, j0, ring_base]`.
    pub fn sector(&self, s: usize) -> [u32; 5] {
        let w = &self.sectors[SECTOR_WORDS * s..SECTOR_WORDS * (s + 1)];
        [w[0], w[1], w[2], w[3], w[4]]
    }

    /// Faces `m` of sector `s`.
    pub fn sector_faces(&self, s: usize) -> u32 {
        self.sectors[SECTOR_WORDS * s + 1]
    }

    /// Sector `s`'s partial ring `[p, q_0, d_0, …, d_{m−1}, q_m]`.
    pub fn sector_ring(&self, s: usize) -> &[u32] {
        let base = self.sectors[SECTOR_WORDS * s + 4] as usize;
        let p = self.ring[base];
        // the ring of p ends at ring_offsets[p + 1]; the next sector of p starts at its base
        let end = if s + 1 < self.vertex_sectors[p as usize + 1] as usize {
            self.sectors[SECTOR_WORDS * (s + 1) + 4] as usize
        } else {
            self.ring_offsets[p as usize + 1] as usize
        };
        &self.ring[base..end]
    }

    /// Whether `v` is on the boundary (its fan is open).
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        self.valence[v as usize] as usize == self.sector_halfedges(v).len() + 1
    }

    /// Number of boundary edges.
    pub fn num_boundary_edges(&self) -> usize {
        self.boundary_halfedges.len()
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
#[path = "topology_tests.rs"]
mod tests;
