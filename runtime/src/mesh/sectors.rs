//! Vertex rules, canonical fans and sectors of open and tagged meshes (`docs/boundaries.md` §2).
//!
//! [`crate::mesh::topology::Topology::build_with`] walks each vertex's fan of outgoing
//! half-edges here, classifies the vertex (smooth, dart, crease, corner), rotates the fan to its
//! canonical start and cuts crease / corner fans into sectors at the sharp edges.

use crate::mesh::features::{BoundaryRule, Features};
use crate::mesh::topology_error::{TopologyError, NONE};

/// `u32` words per sector in [`crate::mesh::topology::Topology::sectors`]:
/// `[kind, m, count, j0, ring_base]` (the generated ABI's `SECTOR_WORDS`).
pub const SECTOR_WORDS: usize = crate::abi::SECTOR_WORDS as usize;

/// Largest sector (in faces) that a stencil table of `max_valence` holds:
/// `SECTOR_MAX_FACES = max_valence / 2` (a sector of `m ≥ 2` faces uses the virtual valence
/// `2m`), and never more than [`crate::abi::VIRTUAL_VALENCE`] covers (64 faces, the CLI's
/// largest `--max-valence` of 128): a larger sector is a typed error, not an index past it.
pub fn max_sector_faces(max_valence: u32) -> u32 {
    (max_valence / 2).min(crate::abi::VIRTUAL_VALENCE.len() as u32 - 1)
}

/// Sector kind word of a crease sector (the vertex stage reads row block
/// `kind · SECTOR_MAX_FACES + m − 1`).
pub const SECTOR_KIND_CREASE: u32 = 0;
/// See [`SECTOR_KIND_CREASE`].
pub const SECTOR_KIND_CORNER: u32 = 1;

/// The virtual valence `n'(m)` of a sector of `m` faces (`docs/boundaries.md` §3: 4 for one
/// face, `2m` otherwise), as the scheme language defines it (`abi::VIRTUAL_VALENCE`); `m` is
/// at most `max_sector_faces(max_valence)` ≤ 64.
pub fn virtual_valence(m: u32) -> u32 {
    crate::abi::VIRTUAL_VALENCE[m as usize]
}

/// Vertex rule (`docs/boundaries.md` §2, first match wins: corner, crease, dart, smooth).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum VertexRule {
    /// No incident sharp edge (also used for vertices no face uses).
    #[default]
    Smooth,
    /// Exactly one incident sharp edge: the smooth rule on the full ring (irregular).
    Dart,
    /// Two incident sharp edges (a regular boundary vertex is here).
    Crease,
    /// Vertex sharpness > 0, three or more sharp edges, or (edge-and-corner) a boundary vertex
    /// with one face.
    Corner,
}

impl VertexRule {
    /// Whether the vertex's ring is cut into sectors (crease and corner).
    pub fn has_sectors(self) -> bool {
        matches!(self, VertexRule::Crease | VertexRule::Corner)
    }
}

/// One vertex's fan after classification.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Fan {
    pub rule: VertexRule,
    /// Whether the vertex is on the boundary (its fan is open).
    pub boundary: bool,
    /// Outgoing half-edges in ccw order, from the canonical start (ring position `j` = `fan[j]`).
    pub halfedges: Vec<u32>,
    /// Sectors `(j0, m)` in ccw order (empty for smooth / dart).
    pub sectors: Vec<(u32, u32)>,
}

/// Half-edge arrays the fan walk reads.
pub(crate) struct HalfEdges<'a> {
    pub prev: &'a [u32],
    pub twin: &'a [u32],
    /// Per half-edge: its edge cuts fans (boundary edge, or sharpness > 0).
    pub sharp: &'a [bool],
}

/// Walks vertex `v`'s fan ccw (`h → twin(prev(h))`) from `start` (its leading boundary
/// half-edge when `boundary`, else any outgoing half-edge) and checks that it covers all
/// `faces` outgoing half-edges.
fn walk(
    he: &HalfEdges<'_>,
    v: u32,
    start: u32,
    faces: u32,
    boundary: bool,
) -> Result<Vec<u32>, TopologyError> {
    let bad = || TopologyError::NonManifoldVertex { vertex: v };
    let mut fan = Vec::with_capacity(faces as usize);
    let mut h = start;
    loop {
        if fan.len() as u32 == faces {
            // All outgoing half-edges seen: a closed fan must be back at the start, an open one
            // must have ended on its trailing boundary edge.
            return if !boundary && h == start {
                Ok(fan)
            } else {
                Err(bad())
            };
        }
        if !fan.is_empty() && h == start {
            // a closed cycle that misses some of v's half-edges: several fans
            return Err(bad());
        }
        fan.push(h);
        let t = he.twin[he.prev[h as usize] as usize];
        if t == NONE {
            // reached the trailing boundary edge
            return if boundary && fan.len() as u32 == faces {
                Ok(fan)
            } else {
                Err(bad())
            };
        }
        h = t;
    }
}

/// Classifies vertex `v` (with `faces > 0` outgoing half-edges, `smallest` the smallest id
/// among them, `boundary_out` its outgoing boundary half-edges: the smallest one and how many)
/// and lays out its fan.
pub(crate) fn fan(
    he: &HalfEdges<'_>,
    features: &Features,
    v: u32,
    faces: u32,
    smallest: u32,
    boundary_out: (u32, u32),
) -> Result<Fan, TopologyError> {
    let (first_boundary, num_boundary) = boundary_out;
    if num_boundary > 1 {
        return Err(TopologyError::NonManifoldVertex { vertex: v });
    }
    let boundary = num_boundary == 1;
    let mut halfedges = walk(
        he,
        v,
        if boundary { first_boundary } else { smallest },
        faces,
        boundary,
    )?;
    let sharp = |h: u32| he.sharp[h as usize];
    // the trailing boundary edge (y → p) is sharp too
    let s = halfedges.iter().filter(|&&h| sharp(h)).count() + usize::from(boundary);
    let rule = if features.vertex(v) > 0.0
        || s >= 3
        || (boundary && faces == 1 && features.boundary == BoundaryRule::EdgeAndCorner)
    {
        VertexRule::Corner
    } else if s == 2 {
        VertexRule::Crease
    } else if s == 1 {
        VertexRule::Dart
    } else {
        VertexRule::Smooth
    };
    if !rule.has_sectors() {
        // smooth / dart: the walk already started at the smallest id
        return Ok(Fan {
            rule,
            boundary,
            halfedges,
            sectors: Vec::new(),
        });
    }
    if !boundary {
        // interior crease / corner: start at the sharp edge with the smallest half-edge id
        // (the smallest id overall when no edge is sharp)
        let start = (0..halfedges.len())
            .filter(|&j| sharp(halfedges[j]))
            .min_by_key(|&j| halfedges[j])
            .unwrap_or(0);
        halfedges.rotate_left(start);
    }
    // cut at the sharp positions; position 0 is one when any edge is sharp
    let mut cuts: Vec<u32> = (0..faces)
        .filter(|&j| sharp(halfedges[j as usize]))
        .collect();
    if cuts.first() != Some(&0) {
        // a corner by vertex sharpness with no sharp edge: one sector, the whole fan
        cuts.insert(0, 0);
    }
    cuts.push(faces);
    let sectors = cuts.windows(2).map(|w| (w[0], w[1] - w[0])).collect();
    Ok(Fan {
        rule,
        boundary,
        halfedges,
        sectors,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::features::FeatureError;
    use crate::mesh::topology::{FaceClass, Topology, TopologyError, TopologyOptions};
    use crate::mesh::Mesh;
    use std::collections::BTreeSet;
    use std::path::Path;

    const OPEN: [&str; 8] = [
        "catmark_tent",
        "catmark_single_crease",
        "catmark_xord_boundary",
        "catmark_xord_interior",
        "catmark_fvar_bound3",
        "catmark_gregory_test1",
        "catmark_pawn",
        "catmark_car",
    ];

    fn load(name: &str) -> Mesh {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../tests/data/meshes")
            .join(format!("{name}.obj"));
        Mesh::from_obj_path(path).unwrap()
    }

    fn build(mesh: &Mesh) -> Topology {
        Topology::build(mesh, &TopologyOptions::default()).unwrap()
    }

    /// Face `f` read from half-edge `h`'s corner: `(p, a, b, c)`.
    fn face_from(mesh: &Mesh, t: &Topology, h: u32) -> [u32; 4] {
        let f = t.face[h as usize] as usize;
        let fv = mesh.face(f);
        let i = (h - mesh.face_offsets[f]) as usize;
        [fv[i], fv[(i + 1) % 4], fv[(i + 2) % 4], fv[(i + 3) % 4]]
    }

    /// Every property of docs/boundaries.md §2 that can be checked against the mesh's own
    /// face arrays and the half-edge walk.
    fn check_sectors(name: &str, mesh: &Mesh, t: &Topology, max_valence: u32) {
        let nh = mesh.face_vertices.len() as u32;
        for h in 0..nh {
            let tw = t.twin[h as usize];
            if tw != NONE {
                assert_eq!(t.twin[tw as usize], h, "{name}");
                assert_eq!(t.origin[tw as usize], t.dest(h), "{name}");
            }
            let v = t.origin[h as usize];
            assert_eq!(
                t.sector_halfedges(v)[t.halfedge_sector[h as usize] as usize],
                h,
                "{name}"
            );
        }
        for v in 0..mesh.num_vertices() as u32 {
            let out = t.sector_halfedges(v);
            let faces = out.len();
            let boundary = out.iter().any(|&h| t.twin[h as usize] == NONE);
            assert_eq!(t.is_boundary_vertex(v), boundary, "{name} v{v}");
            let n = t.valence[v as usize] as usize;
            if faces == 0 {
                assert_eq!(n, 0);
                assert!(t.ring(v).is_empty());
                continue;
            }
            assert_eq!(n, faces + usize::from(boundary), "{name} v{v}");
            // consecutive positions are the ccw walk
            for j in 0..faces - 1 {
                assert_eq!(
                    out[j + 1],
                    t.twin[t.prev[out[j] as usize] as usize],
                    "{name} v{v}"
                );
            }
            let rule = t.vertex_rule[v as usize];
            let sharp = |h: u32| t.edge_sharp[h as usize];
            let nsharp = out.iter().filter(|&&h| sharp(h)).count() + usize::from(boundary);
            let range = t.vertex_sector_range(v);
            if !rule.has_sectors() {
                assert!(!boundary, "{name} v{v}");
                assert!(range.is_empty());
                assert_eq!(nsharp, usize::from(rule == VertexRule::Dart), "{name} v{v}");
                assert_eq!(out[0], *out.iter().min().unwrap(), "{name} v{v}");
                assert_eq!(t.ring(v).len(), 2 * n + 1);
                continue;
            }
            if rule == VertexRule::Crease {
                assert_eq!(nsharp, 2, "{name} v{v}");
            }
            // canonical start
            if boundary {
                assert_eq!(t.twin[out[0] as usize], NONE, "{name} v{v}");
            } else if nsharp > 0 {
                let first = out.iter().copied().filter(|&h| sharp(h)).min().unwrap();
                assert_eq!(out[0], first, "{name} v{v}");
            }
            // positions written exactly once, sectors in ccw order, rings concatenated
            let mut written = vec![0u32; n];
            let mut ring_len = 0;
            let mut next_j0 = 0;
            let mut sum = 0;
            for s in range.clone() {
                let [kind_word, m_word, count, j0, base] = t.sector(s);
                let m = t.sector_faces(s);
                assert_eq!(j0, next_j0, "{name} v{v}");
                next_j0 = j0 + m;
                assert_eq!(base, t.ring_offsets[v as usize] + ring_len, "{name} v{v}");
                ring_len += 2 * m + 2;
                let kind = u32::from(rule == VertexRule::Corner);
                assert_eq!(kind_word, kind, "{name} v{v}");
                assert_eq!(m_word, m, "{name} v{v}");
                assert!(m <= max_valence / 2, "{name} v{v}");
                let last = s + 1 == range.end;
                assert_eq!(count, m + u32::from(boundary && last), "{name} v{v}");
                for j in j0..j0 + count {
                    written[j as usize] += 1;
                }
                sum += count;
                // face i of the sector is (p, q_i, d_i, q_{i+1}) in its own ccw order
                let r = t.sector_ring(s);
                assert_eq!(r[0], v);
                for i in 0..m as usize {
                    let h = out[j0 as usize + i];
                    assert_eq!(
                        face_from(mesh, t, h),
                        [v, r[1 + 2 * i], r[2 + 2 * i], r[3 + 2 * i]],
                        "{name} v{v} sector {s} face {i}"
                    );
                    // inner edges smooth, bounding edges sharp
                    if i > 0 {
                        assert!(!sharp(h), "{name} v{v}");
                    }
                }
                if nsharp >= 2 {
                    assert!(sharp(out[j0 as usize]), "{name} v{v}");
                }
            }
            assert_eq!(sum as usize, n, "{name} v{v}");
            assert!(written.iter().all(|&w| w == 1), "{name} v{v}: {written:?}");
            assert_eq!(next_j0 as usize, faces);
            assert_eq!(
                t.ring(v).len(),
                ring_len as usize,
                "{name} v{v}: rings concatenated"
            );
        }
        for f in 0..mesh.num_faces() {
            let mut regular = true;
            for i in 0..4 {
                let c = t.corners[f][i];
                let h = mesh.face_offsets[f] + i as u32;
                assert_eq!(c.vertex, mesh.face(f)[i]);
                // corner_sector points at the face's own edge
                assert_eq!(t.sector_halfedges(c.vertex)[c.sector as usize], h, "{name}");
                let v = c.vertex;
                let rule = t.vertex_rule[v as usize];
                let cv = t.corner_valence[4 * f + i];
                if rule.has_sectors() {
                    let s = t
                        .vertex_sector_range(v)
                        .find(|&s| {
                            let [_, _, _, j0, _] = t.sector(s);
                            (j0..j0 + t.sector_faces(s)).contains(&c.sector)
                        })
                        .unwrap();
                    let m = t.sector_faces(s);
                    assert_eq!(cv, if m == 1 { 4 } else { 2 * m }, "{name}");
                    regular &= m == if rule == VertexRule::Crease { 2 } else { 1 };
                } else {
                    assert_eq!(cv, t.valence[v as usize], "{name}");
                    regular &= rule == VertexRule::Smooth && cv == 4;
                }
            }
            assert_eq!(t.classes[f] == FaceClass::Ordinary, regular, "{name} f{f}");
        }
    }

    /// Per mesh: boundary edges, sharp interior (crease) edges, smooth / dart / crease /
    /// corner vertices, sectors, ordinary faces.
    fn counts(t: &Topology) -> [usize; 8] {
        let rule = |r| {
            t.vertex_rule
                .iter()
                .zip(&t.valence)
                .filter(|(&x, &n)| x == r && n > 0)
                .count()
        };
        let crease_edges = (0..t.num_halfedges())
            .filter(|&h| t.edge_sharp[h] && t.twin[h] != NONE && (t.twin[h] as usize) > h)
            .count();
        [
            t.num_boundary_edges(),
            crease_edges,
            rule(VertexRule::Smooth),
            rule(VertexRule::Dart),
            rule(VertexRule::Crease),
            rule(VertexRule::Corner),
            t.num_sectors(),
            t.classes
                .iter()
                .filter(|&&c| c == FaceClass::Ordinary)
                .count(),
        ]
    }

    #[test]
    fn open_meshes() {
        let mut got = Vec::new();
        for name in OPEN {
            let mesh = load(name);
            let t = build(&mesh);
            check_sectors(name, &mesh, &t, 32);
            got.push((name, counts(&t)));
        }
        // [boundary, crease, smooth, dart, crease, corner, sectors, ordinary]
        let expected: [(&str, [usize; 8]); 8] = [
            ("catmark_tent", [12, 0, 4, 0, 12, 0, 12, 5]),
            ("catmark_single_crease", [48, 36, 30, 0, 53, 22, 120, 80]),
            ("catmark_xord_boundary", [44, 0, 0, 0, 18, 26, 44, 0]),
            ("catmark_xord_interior", [142, 0, 9, 0, 71, 71, 142, 0]),
            ("catmark_fvar_bound3", [12, 0, 1, 0, 6, 6, 12, 0]),
            ("catmark_gregory_test1", [4, 0, 6, 0, 4, 0, 4, 0]),
            ("catmark_pawn", [24, 120, 457, 0, 144, 0, 264, 552]),
            ("catmark_car", [60, 314, 1256, 24, 358, 4, 664, 887]),
        ];
        assert_eq!(got, expected);
    }

    /// The sectors of a vertex as a set of (partial ring, faces).
    fn sector_set(t: &Topology, v: u32) -> BTreeSet<(Vec<u32>, Vec<u32>)> {
        t.vertex_sector_range(v)
            .map(|s| {
                let [_, _, _, j0, _] = t.sector(s);
                let faces = (j0..j0 + t.sector_faces(s))
                    .map(|j| t.face[t.sector_halfedges(v)[j as usize] as usize])
                    .collect();
                (t.sector_ring(s).to_vec(), faces)
            })
            .collect()
    }

    /// `shared/spec/boundary_reference.json` `vertices` (0-based): mesh, vertex, rule, and per
    /// sector (faces, ring).
    #[test]
    fn reference_vertices() {
        type Sector = (&'static [u32], &'static [u32]);
        let cases: [(&str, u32, VertexRule, &[Sector]); 12] = [
            (
                "catmark_tent",
                0,
                VertexRule::Crease,
                &[(&[0], &[0, 1, 5, 4])],
            ),
            (
                "catmark_tent",
                1,
                VertexRule::Crease,
                &[(&[1, 0], &[1, 2, 6, 5, 4, 0])],
            ),
            (
                "catmark_tent",
                2,
                VertexRule::Crease,
                &[(&[2, 1], &[2, 3, 7, 6, 5, 1])],
            ),
            (
                "catmark_single_crease",
                0,
                VertexRule::Corner,
                &[(&[0], &[0, 1, 22, 21])],
            ),
            (
                "catmark_single_crease",
                21,
                VertexRule::Crease,
                &[(&[0, 20], &[21, 0, 1, 22, 43, 42])],
            ),
            (
                "catmark_single_crease",
                42,
                VertexRule::Crease,
                &[(&[20, 40], &[42, 21, 22, 43, 64, 63])],
            ),
            (
                "catmark_single_crease",
                1,
                VertexRule::Corner,
                &[(&[1], &[1, 2, 23, 22]), (&[0], &[1, 22, 21, 0])],
            ),
            (
                "catmark_single_crease",
                22,
                VertexRule::Crease,
                &[
                    (&[1, 21], &[22, 1, 2, 23, 44, 43]),
                    (&[20, 0], &[22, 43, 42, 21, 0, 1]),
                ],
            ),
            (
                "catmark_xord_boundary",
                0,
                VertexRule::Crease,
                &[(&[0, 1, 2], &[0, 1, 2, 3, 4, 5, 6, 7])],
            ),
            (
                "catmark_xord_boundary",
                1,
                VertexRule::Corner,
                &[(&[0], &[1, 2, 3, 0])],
            ),
            (
                "catmark_xord_boundary",
                3,
                VertexRule::Crease,
                &[(&[1, 0], &[3, 4, 5, 0, 1, 2])],
            ),
            (
                "catmark_xord_boundary",
                30,
                VertexRule::Crease,
                &[(
                    &[12, 13, 14, 15, 16, 17],
                    &[30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43],
                )],
            ),
        ];
        for (name, v, rule, sectors) in cases {
            let t = build(&load(name));
            assert_eq!(t.vertex_rule[v as usize], rule, "{name} v{v}");
            let want: BTreeSet<(Vec<u32>, Vec<u32>)> = sectors
                .iter()
                .map(|(f, r)| (r.to_vec(), f.to_vec()))
                .collect();
            assert_eq!(sector_set(&t, v), want, "{name} v{v}");
        }
        // interior crease 22 of single_crease: the sector starting at the smaller sharp
        // half-edge comes first, and both sectors have 2 faces (n' = 4)
        let t = build(&load("catmark_single_crease"));
        let r = t.vertex_sector_range(22);
        assert_eq!(r.len(), 2);
        assert_eq!(t.sector(r.start)[3], 0);
        assert_eq!(t.sector(r.start + 1)[3], 2);
        assert_eq!(t.sector(r.start)[1], 2);
    }

    #[test]
    fn warnings_reach_topology() {
        let t = build(&load("catmark_single_crease"));
        // 36 crease lines, 4 with sharpness 10: 32 semi-sharp warnings naming their lines
        assert_eq!(t.warnings.len(), 32);
        assert!(
            t.warnings[0].to_string().contains("line 190"),
            "{}",
            t.warnings[0]
        );
        assert!(build(&load("catmark_cube")).warnings.is_empty());
    }

    fn quad_grid(n: u32, tags: &str) -> String {
        let mut s = String::new();
        for j in 0..=n {
            for i in 0..=n {
                s += &format!("v {i} {j} 0\n");
            }
        }
        for j in 0..n {
            for i in 0..n {
                let v = |di: u32, dj: u32| (j + dj) * (n + 1) + i + di + 1;
                s += &format!("f {} {} {} {}\n", v(0, 0), v(1, 0), v(1, 1), v(0, 1));
            }
        }
        s + tags
    }

    #[test]
    fn errors_name_the_tag_line() {
        // 3x3 grid: 16 v lines, 9 f lines, the tag is line 26
        let mesh = Mesh::from_obj_str(&quad_grid(3, "t crease 2/1/0 0 5 10\n")).unwrap();
        let e = Topology::build(&mesh, &TopologyOptions::default()).unwrap_err();
        assert!(
            matches!(
                e,
                TopologyError::Features(FeatureError::NotAnEdge {
                    line: 26,
                    a: 0,
                    b: 5
                })
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("line 26"), "{e}");
        let mesh = Mesh::from_obj_str(&quad_grid(3, "\nt hole 1/0/0 9\n")).unwrap();
        let e = Topology::build(&mesh, &TopologyOptions::default()).unwrap_err();
        assert!(e.to_string().contains("line 27"), "{e}");
        // explicit features are checked too
        let mesh = Mesh::from_obj_str(&quad_grid(3, "")).unwrap();
        let f = Features::new().with_corner(16, 10.0);
        let e = Topology::build_with(&mesh, &TopologyOptions::default(), &f).unwrap_err();
        assert!(
            matches!(
                e,
                TopologyError::Features(FeatureError::UnknownVertex { line: 0, .. })
            ),
            "{e:?}"
        );
    }

    #[test]
    fn errors_open_meshes() {
        // three quads on edge 0-1 of an open strip
        let mesh = Mesh::from_raw(
            vec![[0.0; 3]; 8],
            &[vec![0, 1, 2, 3], vec![1, 0, 4, 5], vec![0, 1, 6, 7]],
        )
        .unwrap();
        let e = Topology::build(&mesh, &TopologyOptions::default()).unwrap_err();
        assert!(
            matches!(e, TopologyError::NonManifoldEdge { a: 0, b: 1 }),
            "{e:?}"
        );
        // two quads touching at vertex 0 only: two open fans
        let mesh =
            Mesh::from_raw(vec![[0.0; 3]; 7], &[vec![0, 1, 2, 3], vec![0, 4, 5, 6]]).unwrap();
        let e = Topology::build(&mesh, &TopologyOptions::default()).unwrap_err();
        assert!(
            matches!(e, TopologyError::NonManifoldVertex { vertex: 0 }),
            "{e:?}"
        );
        // a sector of 6 faces needs --max-valence 12
        let mesh = load("catmark_xord_boundary");
        let opts = TopologyOptions {
            max_valence: 10,
            ..Default::default()
        };
        let e = Topology::build(&mesh, &opts).unwrap_err();
        assert!(
            matches!(
                e,
                TopologyError::SectorTooLarge {
                    vertex: 30,
                    faces: 6,
                    max: 5,
                    needed: 12
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("--max-valence 12"), "{e}");
        // valence 7 (edge valence of a 6-face boundary vertex) needs --max-valence 7
        let opts = TopologyOptions {
            max_valence: 6,
            ..Default::default()
        };
        let e = Topology::build(&mesh, &opts).unwrap_err();
        assert!(
            matches!(
                e,
                TopologyError::ValenceTooHigh {
                    vertex: 30,
                    valence: 7,
                    max: 6
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("--max-valence 7"), "{e}");
        // non-quads: the message says what is missing
        let mesh = Mesh::from_raw(vec![[0.0; 3]; 3], &[vec![0, 1, 2]]).unwrap();
        let e = Topology::build(&mesh, &TopologyOptions::default()).unwrap_err();
        assert!(e.to_string().contains("one Catmull-Clark step"), "{e}");
    }

    #[test]
    fn boundary_rules_and_holes() {
        let text = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../tests/data/meshes/catmark_fvar_bound3.obj"),
        )
        .unwrap();
        let none = Mesh::from_obj_str(
            &text.replace("interpolateboundary 1/0/0 1", "interpolateboundary 1/0/0 0"),
        )
        .unwrap();
        let t = build(&none);
        assert_eq!(t.features.boundary, BoundaryRule::None);
        assert!(
            t.no_limit.iter().all(|&x| x),
            "every face touches the boundary"
        );
        check_sectors("fvar_bound3 rule 0", &none, &t, 32);
        // edge-only: the one-face boundary vertices are creases
        let only = Mesh::from_obj_str(
            &text.replace("interpolateboundary 1/0/0 1", "interpolateboundary 1/0/0 2"),
        )
        .unwrap();
        let t = build(&only);
        assert_eq!(counts(&t)[4..6], [12, 0]);
        assert!(t.no_limit.iter().all(|&x| !x));
        // holes keep the topology, only no_limit changes
        let mesh = load("catmark_fvar_bound3");
        let plain = build(&mesh);
        let f = Features::new().with_hole(2);
        let t = Topology::build_with(&mesh, &TopologyOptions::default(), &f).unwrap();
        assert_eq!(t.no_limit, vec![false, false, true, false, false, false]);
        assert_eq!(
            (&t.ring, &t.sectors, &t.classes),
            (&plain.ring, &plain.sectors, &plain.classes)
        );
    }

    #[test]
    fn closed_meshes_have_no_sectors() {
        for name in [
            "catmark_cube",
            "catmark_torus",
            "catmark_toroidal_tet",
            "catmark_righthanded",
        ] {
            let mesh = load(name);
            let t = build(&mesh);
            check_sectors(name, &mesh, &t, 32);
            assert_eq!(t.num_sectors(), 0);
            assert!(t.vertex_sectors.iter().all(|&s| s == 0));
            assert!(t.vertex_rule.iter().all(|&r| r == VertexRule::Smooth));
            assert!(t.boundary_halfedges.is_empty() && t.warnings.is_empty());
            assert!(t.no_limit.iter().all(|&x| !x));
            for f in 0..mesh.num_faces() {
                for i in 0..4 {
                    let v = t.corners[f][i].vertex;
                    assert_eq!(t.corner_valence[4 * f + i], t.valence[v as usize]);
                }
            }
        }
    }

    #[test]
    fn closed_meshes_with_tags() {
        let cube = load("catmark_cube");
        let plain = build(&cube);
        // a dart at each end of one sharp edge: full rings, same layout, irregular
        let f = Features::new().with_crease(0, 1, 10.0);
        let t = Topology::build_with(&cube, &TopologyOptions::default(), &f).unwrap();
        check_sectors("cube dart", &cube, &t, 32);
        assert_eq!(t.vertex_rule[0], VertexRule::Dart);
        assert_eq!(t.vertex_rule[1], VertexRule::Dart);
        assert_eq!((&t.ring, &t.corners), (&plain.ring, &plain.corners));
        // a corner by vertex sharpness: one sector of all 3 faces, q_3 = q_0
        let f = Features::new().with_corner(0, 10.0);
        let t = Topology::build_with(&cube, &TopologyOptions::default(), &f).unwrap();
        check_sectors("cube corner", &cube, &t, 32);
        assert_eq!(t.ring(0), &[0, 1, 3, 2, 4, 6, 7, 1]);
        assert_eq!(t.sector(0), [1, 3, 3, 0, 0]);
        assert_eq!(t.corner_valence[0], 6);
        // a crease loop around the torus: crease vertices with two 2-face sectors, still
        // all ordinary
        let torus = load("catmark_torus");
        let plain = build(&torus);
        let mut f = Features::new();
        let start = 0u32;
        let mut h = start;
        loop {
            let b = plain.dest(h);
            f.set_crease(plain.origin[h as usize], b, 10.0);
            let j = plain.halfedge_sector[plain.twin[h as usize] as usize];
            h = plain.sector_halfedges(b)[((j + 2) % 4) as usize];
            if h == start {
                break;
            }
        }
        let t = Topology::build_with(&torus, &TopologyOptions::default(), &f).unwrap();
        check_sectors("torus loop", &torus, &t, 32);
        let creases = t
            .vertex_rule
            .iter()
            .filter(|&&r| r == VertexRule::Crease)
            .count();
        assert_eq!(creases, f.edge_sharpness.len());
        assert!(creases >= 4);
        assert_eq!(t.num_sectors(), 2 * creases);
        assert!(t.classes.iter().all(|&c| c == FaceClass::Ordinary));
        assert!(t.corner_valence.iter().all(|&n| n == 4));
    }
}
