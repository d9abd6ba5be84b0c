//! Mesh-level statistics computed from a [`Mesh`] alone, without building the
//! half-edge [`Topology`](crate::Topology).
//!
//! `tessgen inspect` must report on meshes that topology rejects (open
//! meshes, non-manifold edges, too-high valences), so everything here works on
//! any valid polygon mesh. For closed manifold meshes the numbers agree with
//! the `Topology` ones (checked by the tests below).

use crate::Mesh;
use serde::Serialize;
use std::collections::BTreeMap;

/// How many boundary edges are listed by name.
pub const FIRST_BOUNDARY_EDGES: usize = 8;

/// What `tessgen inspect` reports about a mesh.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshStats {
    /// All vertices, unused ones included.
    pub vertices: usize,
    /// Vertices no face uses.
    pub unused_vertices: usize,
    pub faces: usize,
    /// Faces with exactly 4 vertices.
    pub quads: usize,
    pub non_quads: usize,
    /// Undirected edges (distinct unordered vertex pairs of consecutive face vertices).
    pub edges: usize,
    /// Edges used by exactly one face.
    pub boundary_edges: usize,
    /// Up to [`FIRST_BOUNDARY_EDGES`] boundary edges as `(origin, destination)` in
    /// half-edge order (0-based vertex indices), as `Topology::boundary_halfedges` lists them.
    pub first_boundary_edges: Vec<(u32, u32)>,
    /// Edges used by more than two faces.
    pub non_manifold_edges: usize,
    /// `V - E + F` over used vertices.
    pub euler_characteristic: i64,
    /// Valence (number of incident edges) → number of vertices, used vertices only.
    pub valence_histogram: BTreeMap<u32, usize>,
    /// Faces that are not quads or have a corner of valence ≠ 4.
    pub extraordinary_faces: usize,
    /// Tag name → number of `t` lines with it.
    pub tags: BTreeMap<String, usize>,
}

impl MeshStats {
    /// Compute the statistics of a (valid) mesh.
    pub fn of(mesh: &Mesh) -> MeshStats {
        let nv = mesh.num_vertices();
        let nf = mesh.num_faces();
        // Half-edge h of face f runs face_vertices[h] -> next vertex of the same face.
        let mut keys: Vec<(u32, u32, usize)> = Vec::with_capacity(mesh.face_vertices.len());
        let mut halfedges: Vec<(u32, u32)> = Vec::with_capacity(mesh.face_vertices.len());
        for f in 0..nf {
            let face = mesh.face(f);
            for (i, &a) in face.iter().enumerate() {
                let b = face[(i + 1) % face.len()];
                keys.push((a.min(b), a.max(b), halfedges.len()));
                halfedges.push((a, b));
            }
        }
        keys.sort_unstable();
        let mut degree = vec![0u32; nv];
        let mut edges = 0;
        let mut boundary = Vec::new();
        let mut non_manifold_edges = 0;
        for group in keys.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let (a, b, first) = group[0];
            edges += 1;
            degree[a as usize] += 1;
            degree[b as usize] += 1;
            match group.len() {
                1 => boundary.push(first),
                2 => {}
                _ => non_manifold_edges += 1,
            }
        }
        boundary.sort_unstable();
        let used = degree.iter().filter(|&&d| d > 0).count();
        let mut valence_histogram = BTreeMap::new();
        for &d in degree.iter().filter(|&&d| d > 0) {
            *valence_histogram.entry(d).or_insert(0) += 1;
        }
        let quads = (0..nf).filter(|&f| mesh.face(f).len() == 4).count();
        let extraordinary_faces = (0..nf)
            .filter(|&f| {
                let face = mesh.face(f);
                face.len() != 4 || face.iter().any(|&v| degree[v as usize] != 4)
            })
            .count();
        let mut tags = BTreeMap::new();
        for t in &mesh.tags {
            *tags.entry(t.name.clone()).or_insert(0) += 1;
        }
        MeshStats {
            vertices: nv,
            unused_vertices: nv - used,
            faces: nf,
            quads,
            non_quads: nf - quads,
            edges,
            boundary_edges: boundary.len(),
            first_boundary_edges: boundary
                .iter()
                .take(FIRST_BOUNDARY_EDGES)
                .map(|&h| halfedges[h])
                .collect(),
            non_manifold_edges,
            euler_characteristic: used as i64 - edges as i64 + nf as i64,
            valence_histogram,
            extraordinary_faces,
            tags,
        }
    }

    /// Extraordinary faces / faces (the PCCM paper's "eqs" column); 0 without faces.
    pub fn extraordinary_fraction(&self) -> f64 {
        if self.faces == 0 {
            0.0
        } else {
            self.extraordinary_faces as f64 / self.faces as f64
        }
    }
}

/// What `tessgen inspect` reports about a mesh's sharp features and sectors, from a built
/// [`Topology`](crate::Topology) (`docs/boundaries.md`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FeatureStats {
    /// `interpolateboundary` value: 0 none, 1 edge-and-corner, 2 edge-only.
    pub boundary_rule: u32,
    pub boundary_edges: usize,
    /// Tagged edges with sharpness ≥ 10.
    pub crease_edges_infinite: usize,
    /// Tagged edges with 0 < sharpness < 10 (applied as infinitely sharp).
    pub crease_edges_semi_sharp: usize,
    /// Vertices with the corner rule (tagged, three or more sharp edges, one-face boundary).
    pub corners: usize,
    /// Of those, with a `t corner` tag (any sharpness > 0).
    pub tagged_corners: usize,
    /// Vertices with the crease rule.
    pub creases: usize,
    /// Vertices with exactly one sharp edge.
    pub darts: usize,
    pub holes: usize,
    /// Faces without a limit surface (holes; with rule 0 the faces at the boundary).
    pub no_limit_faces: usize,
    pub non_quad_faces: usize,
    /// Sector size (faces) → number of sectors.
    pub sectors_by_faces: BTreeMap<u32, usize>,
    /// One line per feature present: what tessellation does with it.
    pub tessellation: Vec<String>,
    /// Every tag warning, with its line.
    pub warnings: Vec<String>,
}

impl FeatureStats {
    /// The feature statistics of a built topology (`non_quad_faces` from [`MeshStats`]).
    pub fn of(t: &crate::Topology, non_quad_faces: usize) -> FeatureStats {
        use crate::topology::VertexRule;
        let f = &t.features;
        let (infinite, semi) = f.crease_counts();
        let rule = |r: VertexRule| {
            t.vertex_rule
                .iter()
                .zip(&t.valence)
                .filter(|&(&x, &n)| x == r && n > 0)
                .count()
        };
        let mut sectors_by_faces = BTreeMap::new();
        for s in 0..t.num_sectors() {
            *sectors_by_faces.entry(t.sector_faces(s)).or_insert(0) += 1;
        }
        let mut out = FeatureStats {
            boundary_rule: f.boundary.tag_value(),
            boundary_edges: t.num_boundary_edges(),
            crease_edges_infinite: infinite,
            crease_edges_semi_sharp: semi,
            corners: rule(VertexRule::Corner),
            tagged_corners: f.vertex_sharpness.len(),
            creases: rule(VertexRule::Crease),
            darts: rule(VertexRule::Dart),
            holes: f.holes.len(),
            no_limit_faces: t.no_limit.iter().filter(|&&x| x).count(),
            non_quad_faces,
            sectors_by_faces,
            tessellation: Vec::new(),
            warnings: t.warnings.iter().map(ToString::to_string).collect(),
        };
        let mut say = |what: &str| out.tessellation.push(what.to_string());
        if t.num_boundary_edges() > 0 {
            say(match f.boundary {
                crate::mesh::features::BoundaryRule::None => {
                    "boundaries (rule 0): faces touching the boundary have no limit and emit nothing"
                }
                crate::mesh::features::BoundaryRule::EdgeAndCorner => {
                    "boundaries (rule 1): sharp, one-face boundary vertices interpolated as corners"
                }
                crate::mesh::features::BoundaryRule::EdgeOnly => {
                    "boundaries (rule 2): sharp, one-face boundary vertices are creases (irregular)"
                }
            });
        }
        if infinite > 0 {
            say("infinitely sharp creases: sectors with crease rules");
        }
        if semi > 0
            || f.vertex_sharpness
                .values()
                .any(|&s| crate::mesh::features::is_semi_sharp(s))
        {
            let max = f
                .edge_sharpness
                .values()
                .chain(f.vertex_sharpness.values())
                .copied()
                .filter(|&s| crate::mesh::features::is_semi_sharp(s))
                .fold(0.0f32, f32::max);
            say(&format!(
                "semi-sharp creases/corners (sharpness up to {}): applied exactly by {} \
                 Catmull-Clark steps of the faces around them (feature-adaptive); tessellate \
                 takes at most --crease-refinement (default {}) and as many as the level allows \
                 (any power of two; otherwise the power of two in it), and applies what is left \
                 as infinitely sharp",
                max,
                max.ceil(),
                crate::mesh::refine::DEFAULT_CREASE_REFINEMENT
            ));
        }
        if out.corners > 0 {
            say("corners: interpolated (corner sectors)");
        }
        if out.darts > 0 {
            say("darts: smooth rule on the full ring (irregular, approximate)");
        }
        if out.holes > 0 {
            say("holes: no patch emitted, vertices still shape the neighbours");
        }
        if non_quad_faces > 0 {
            say(
                "non-quad faces: one uniform Catmull-Clark step makes every face a quad; base quads \
                 keep one (N+1)^2 grid, each n-gon gives one (N/2+1)^2 grid per corner sub-face \
                 (N must be even)",
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Topology, TopologyOptions};
    use std::path::PathBuf;

    fn meshes() -> Vec<(String, Mesh)> {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/meshes");
        let mut out = Vec::new();
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "obj") {
                let name = path.display().to_string();
                out.push((name, Mesh::from_obj_path(&path).unwrap()));
            }
        }
        assert!(out.len() >= 5, "test meshes not found in {}", dir.display());
        out.sort_by(|a, b| a.0.cmp(&b.0));
        out
    }

    /// Wherever topology accepts a mesh, the mesh-level numbers are its numbers (for open
    /// meshes the boundary edges are the ones it lists, in the same order).
    #[test]
    fn agrees_with_topology() {
        let opts = TopologyOptions {
            max_valence: 64,
            require_quads: false,
        };
        let (mut closed, mut open) = (0, 0);
        for (name, mesh) in meshes() {
            let s = MeshStats::of(&mesh);
            let t = Topology::build(&mesh, &opts)
                .unwrap_or_else(|e| panic!("{name}: unexpected topology error {e}"));
            assert_eq!(s.non_manifold_edges, 0, "{name}");
            assert_eq!(s.edges, t.num_edges(), "{name}");
            assert_eq!(s.euler_characteristic, t.euler_characteristic(), "{name}");
            assert_eq!(s.valence_histogram, t.valence_histogram(), "{name}");
            assert_eq!(s.boundary_edges, t.num_boundary_edges(), "{name}");
            let first: Vec<(u32, u32)> = t
                .boundary_halfedges
                .iter()
                .take(FIRST_BOUNDARY_EDGES)
                .map(|&h| (t.origin[h as usize], t.dest(h)))
                .collect();
            assert_eq!(s.first_boundary_edges, first, "{name}");
            if s.boundary_edges == 0 && mesh.tags.is_empty() {
                closed += 1;
                assert_eq!(
                    s.extraordinary_fraction(),
                    t.extraordinary_fraction(),
                    "{name}"
                );
            } else {
                open += 1;
            }
        }
        assert!(closed > 0 && open > 0, "closed {closed}, open {open}");
    }

    #[test]
    fn cube_and_tent() {
        let all = meshes();
        let get = |n: &str| {
            let (_, m) = all.iter().find(|(p, _)| p.ends_with(n)).unwrap();
            MeshStats::of(m)
        };
        let cube = get("catmark_cube.obj");
        assert_eq!(
            (cube.vertices, cube.faces, cube.quads, cube.edges),
            (8, 6, 6, 12)
        );
        assert_eq!(cube.euler_characteristic, 2);
        assert_eq!(cube.valence_histogram, BTreeMap::from([(3, 8)]));
        assert_eq!(cube.extraordinary_fraction(), 1.0);
        let tent = get("catmark_tent.obj");
        assert_eq!(tent.boundary_edges, 12);
        assert_eq!(tent.euler_characteristic, 1);
        assert_eq!(tent.tags.get("interpolateboundary"), Some(&1));
    }

    #[test]
    fn feature_stats() {
        let all = meshes();
        let get = |n: &str| {
            let (_, m) = all.iter().find(|(p, _)| p.ends_with(n)).unwrap();
            let t = Topology::build(m, &TopologyOptions::default()).unwrap();
            FeatureStats::of(&t, MeshStats::of(m).non_quads)
        };
        let sc = get("catmark_single_crease.obj");
        assert_eq!(
            (
                sc.boundary_rule,
                sc.boundary_edges,
                sc.crease_edges_infinite,
                sc.crease_edges_semi_sharp
            ),
            (1, 48, 4, 32)
        );
        assert_eq!((sc.corners, sc.creases, sc.darts, sc.holes), (22, 53, 0, 0));
        assert_eq!(sc.sectors_by_faces, BTreeMap::from([(1, 40), (2, 80)]));
        assert_eq!(sc.warnings.len(), 32);
        assert!(sc
            .tessellation
            .iter()
            .any(|l| l.contains("semi-sharp")
                && l.contains("applied exactly by 6 Catmull-Clark steps")));
        let tent = get("catmark_tent.obj");
        assert_eq!(tent.boundary_rule, 2);
        assert!(tent.tessellation[0].contains("rule 2"));
        let cube = get("catmark_cube.obj");
        assert!(cube.tessellation.is_empty() && cube.warnings.is_empty());
        assert!(cube.sectors_by_faces.is_empty());
    }

    #[test]
    fn non_quads_and_non_manifold_edges() {
        // Three triangles sharing edge 0-1, one unused vertex.
        let p = vec![[0.0, 0.0, 0.0]; 6];
        let m = Mesh::from_raw(p, &[vec![0, 1, 2], vec![1, 0, 3], vec![0, 1, 4]]).unwrap();
        let s = MeshStats::of(&m);
        assert_eq!((s.quads, s.non_quads, s.unused_vertices), (0, 3, 1));
        assert_eq!((s.edges, s.non_manifold_edges, s.boundary_edges), (7, 1, 6));
        assert_eq!(s.extraordinary_faces, 3);
    }
}
