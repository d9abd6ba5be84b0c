//! Tests of [`super`]: closed meshes keep their canonical rings and corners; errors are
//! typed and reproducible.
use super::*;
use crate::mesh::MeshError;
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
fn boundaries_are_accepted() {
    // a lone quad: 4 boundary edges, 4 one-face corners (edge-and-corner)
    let t = build_str(&obj(4, &[&[0, 1, 2, 3]])).unwrap();
    assert_eq!(t.boundary_halfedges, vec![0, 1, 2, 3]);
    assert!(t.twin.iter().all(|&h| h == NONE));
    assert_eq!(t.valence, vec![2; 4]);
    assert_eq!(t.vertex_rule, vec![VertexRule::Corner; 4]);
    assert_eq!(t.classes, vec![FaceClass::Ordinary]);
    assert_eq!(t.corner_valence, vec![4; 4]);
    // vertex 0: [p, q_0, d_0, q_1] = [0, 1, 2, 3], writes positions 0 and 1
    assert_eq!(t.ring(0), &[0, 1, 2, 3]);
    assert_eq!(t.sector(0), [1, 1, 2, 0, 0]);
}

#[test]
fn open_meshes_build() {
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
        let t = build(&load(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(t.num_boundary_edges(), n, "{name}");
        assert_eq!(t.twin.iter().filter(|&&h| h == NONE).count(), n, "{name}");
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
            TopologyError::Mesh(MeshError::FaceIndexOutOfRange {
                face: 0,
                line: None,
                index: 99
            })
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
