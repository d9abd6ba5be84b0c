//! Watertightness, bit for bit: exact-weld the CPU output of every closed
//! shared mesh and require a closed 2-manifold with the input's Euler
//! characteristic.

mod common;

use tessgen_runtime::tags::{TagError, TagFile};
use tessgen_runtime::tessellate::{Error, Request};
use tessgen_runtime::{cpu, weld, Topology};

const LEVELS: &[u32] = &[1, 2, 3, 7, 8, 16, 33, 64];

fn check(name: &str, scheme: &str) {
    check_levels(name, scheme, LEVELS);
}

fn check_levels(name: &str, scheme: &str, levels: &[u32]) {
    let mesh = common::mesh(name);
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let euler = topo.euler_characteristic();
    for &level in levels {
        let t = common::grid(&mesh, &Request::uniform(scheme, level)).expect("tessellate");
        let r = weld::weld(&t);
        assert!(
            r.is_closed_manifold(),
            "{name} {scheme} level {level}: {} open edges, {} overused, {} degenerate",
            r.open_edges,
            r.overused_edges,
            r.degenerate_triangles
        );
        assert_eq!(
            r.euler, euler,
            "{name} {scheme} level {level}: Euler characteristic"
        );
    }
}

#[test]
fn pccm_closed_meshes_weld_closed() {
    for name in common::CLOSED_MESHES {
        check(name, "pccm");
    }
}

/// The 27,776-quad mesh at the levels that keep CI quick (N = 8 is
/// already 2.2M samples).
#[test]
fn pccm_big_mesh_welds_closed() {
    check_levels(common::BIG_MESH, "pccm", &[1, 2, 3, 7, 8]);
}

/// ACC, Gregory, its OpenSubdiv variant and g1cc (quartic boundaries) on
/// every closed shared mesh.
#[test]
fn acc_and_gregory_closed_meshes_weld_closed() {
    for scheme in ["acc", "gregory", "gregory_osd", "g1cc"] {
        for name in common::CLOSED_MESHES {
            check(name, scheme);
        }
    }
}

#[test]
fn regular_torus_welds_closed() {
    check("catmark_torus", "regular");
}

/// Negative control: moving one boundary sample by one ulp must open edges,
/// so the check above can fail.
#[test]
fn one_ulp_opens_the_weld() {
    let mesh = common::mesh("catmark_cube");
    let mut t = common::grid(&mesh, &Request::uniform("pccm", 4)).expect("tessellate");
    assert!(weld::weld(&t).is_closed_manifold());
    // Sample (i, j) = (2, 0) of face 0 lies on edge 0, shared with a neighbour.
    let p = &mut t.positions[2];
    p.x = f32::from_bits(p.x.to_bits() + 1);
    let r = weld::weld(&t);
    assert!(!r.is_closed_manifold());
    assert_eq!(
        r.open_edges, 4,
        "the moved sample splits two edge segments on each side"
    );
}

/// Triangle schemes on the closed shared meshes split into triangles (each
/// quad along its v0–v2 diagonal, area-weighted vertex normals): PN and
/// Phong edges depend only on the edge's two vertices, so exact welding
/// must close every edge, and the Euler characteristic is the quad mesh's.
#[test]
fn pn_and_phong_split_meshes_weld_closed() {
    for scheme in ["pn", "stpn", "phong"] {
        for name in common::CLOSED_MESHES {
            let mesh = common::mesh(name);
            let euler = Topology::build(&mesh, &cpu::topology_options())
                .expect("topology")
                .euler_characteristic();
            for &level in &[1, 2, 7, 8, 16] {
                let t = common::grid(&mesh, &Request::uniform(scheme, level).split_quads(true))
                    .expect("tessellate");
                assert_eq!(t.sides, 3);
                let r = weld::weld(&t);
                assert!(
                    r.is_closed_manifold(),
                    "{name} {scheme} level {level}: {} open edges, {} overused, {} degenerate",
                    r.open_edges,
                    r.overused_edges,
                    r.degenerate_triangles
                );
                assert_eq!(
                    r.euler, euler,
                    "{name} {scheme} level {level}: Euler characteristic"
                );
            }
        }
    }
}

/// The split torus with a sharp crease loop (tests/data/meshes/
/// catmark_torus_crease.tags: σ = 1 and Δ on the outer-top ring, bias on
/// every other crease vertex, tension on the inner-top ring).
fn creased_torus() -> (tessgen_runtime::Mesh, TagFile) {
    let mesh = common::mesh("catmark_torus");
    let text = std::fs::read_to_string(common::data("meshes/catmark_torus_crease.tags"))
        .expect("tags file");
    let tags = TagFile::parse(&text, mesh.num_vertices(), mesh.num_faces(), |f| {
        mesh.face(f)
    })
    .expect("valid tags");
    (mesh, tags)
}

/// Scalar-tagged PN with a crease loop: the crease edges' control points
/// use only N and the crease normal, every other edge is shared by two
/// triangles of one sector, so exact welding closes every edge (positions);
/// the normal field is continuous across smooth edges (< 0.05°) and jumps
/// across the crease (σ = 1: the two sides' normals are the top and the
/// outer face directions, about 90° apart).
#[test]
fn stpn_creased_torus_welds_closed_and_jumps_only_at_the_crease() {
    use std::collections::HashMap;
    use tessgen_runtime::grid::tri_grid_edge;
    let (mesh, tags) = creased_torus();
    let tri = cpu::tri_mesh(&mesh, true, Some(&tags)).expect("tri mesh");
    let creased = |v: u32| tri.crease_tags.crease[v as usize] != glam::Vec3::ZERO;
    let crease_edges = tri
        .triangles
        .iter()
        .flat_map(|t| (0..3).map(move |e| (t[e], t[(e + 1) % 3])))
        .filter(|&(a, b)| creased(a) && creased(b))
        .count();
    assert_eq!(crease_edges, 16, "8 crease edges, seen from both sides");
    let patches = cpu::construct_tri(&tri, cpu::scheme("stpn").expect("stpn")).expect("construct");
    for &level in &[1, 2, 7, 8, 16] {
        let t = cpu::evaluate(&patches, level).expect("evaluate");
        let r = weld::weld(&t);
        assert!(
            r.is_closed_manifold(),
            "stpn creased torus level {level}: {} open edges",
            r.open_edges
        );
        assert_eq!(r.euler, 0, "torus");
        if level == 1 {
            continue;
        }
        // Normals at the interior samples of every edge, keyed by position bits.
        let mut at: HashMap<[u32; 3], Vec<(bool, glam::Vec3)>> = HashMap::new();
        let grid = t.grid_len();
        for (f, tv) in tri.triangles.iter().enumerate() {
            for e in 0..3 {
                let crease = creased(tv[e]) && creased(tv[(e + 1) % 3]);
                let idx = tri_grid_edge(level, e);
                for &k in &idx[1..idx.len() - 1] {
                    let s = f * grid + k as usize;
                    let key = t.positions[s].to_array().map(f32::to_bits);
                    at.entry(key).or_default().push((crease, t.normals[s]));
                }
            }
        }
        let (mut smooth, mut jump_min, mut jump_max) = (0.0f64, f64::MAX, 0.0f64);
        for v in at.values() {
            assert_eq!(
                v.len(),
                2,
                "level {level}: every edge sample is shared by two triangles"
            );
            assert_eq!(v[0].0, v[1].0);
            let a = common::angle_deg(v[0].1, v[1].1);
            if v[0].0 {
                jump_min = jump_min.min(a);
                jump_max = jump_max.max(a);
            } else {
                smooth = smooth.max(a);
            }
        }
        println!("stpn creased torus level {level}: smooth edges max {smooth:.2e}°, crease jump {jump_min:.1}°..{jump_max:.1}°");
        assert!(
            smooth < 0.05,
            "level {level}: smooth edges' normals differ by {smooth}°"
        );
        assert!(
            jump_min > 45.0,
            "level {level}: crease jump only {jump_min}°"
        );
    }
    // Without the tags the same mesh is plain PN: smooth everywhere.
    let plain = common::grid(&mesh, &Request::uniform("stpn", 8).split_quads(true)).expect("plain");
    let pn = common::grid(&mesh, &Request::uniform("pn", 8).split_quads(true)).expect("pn");
    let d = plain
        .positions
        .iter()
        .zip(&pn.positions)
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0f32, f32::max);
    assert!(d < 1e-5, "neutral stpn vs pn: {d}");
}

/// Tags are rejected, with a typed error, by every scheme that does not read
/// them, and a triangle with three crease corners names its face.
#[test]
fn crease_tag_errors_are_typed() {
    let (mesh, tags) = creased_torus();
    assert!(matches!(
        common::grid(
            &mesh,
            &Request::uniform("pn", 2).split_quads(true).tagged(&tags)
        ),
        Err(Error::TagsUnused { .. })
    ));
    let text = "tag 5 delta 0 1 0\ntag 6 delta 0 1 0\ntag 2 delta 0 1 0\n";
    let three = TagFile::parse(text, mesh.num_vertices(), mesh.num_faces(), |f| {
        mesh.face(f)
    })
    .expect("parses");
    match common::grid(
        &mesh,
        &Request::uniform("stpn", 2).split_quads(true).tagged(&three),
    ) {
        Err(Error::Tess(cpu::TessError::Tags(TagError::ThreeCreaseCorners { face }))) => {
            assert_eq!(face, 1)
        }
        other => panic!("expected ThreeCreaseCorners, got {other:?}"),
    }
    // Flipping the side of one face at a crease vertex (1-based vertex 4)
    // splits its sector: one of the two signs disagrees with the rest.
    let face = (0..mesh.num_faces())
        .find(|&f| mesh.face(f).contains(&3))
        .expect("a face at vertex 4");
    let errors: Vec<TagError> = ["1", "-1"]
        .iter()
        .filter_map(|s| {
            let mut text =
                std::fs::read_to_string(common::data("meshes/catmark_torus_crease.tags"))
                    .expect("tags file");
            text.push_str(&format!("side {} 4 {s}\n", face + 1));
            let file = TagFile::parse(&text, mesh.num_vertices(), mesh.num_faces(), |f| {
                mesh.face(f)
            })
            .expect("parses");
            cpu::tri_mesh(&mesh, true, Some(&file)).err()
        })
        .map(|e| match e {
            cpu::TessError::Tags(t) => t,
            other => panic!("expected a tag error, got {other:?}"),
        })
        .collect();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        matches!(errors[0], TagError::InconsistentSide { vertex: 4, .. }),
        "{:?}",
        errors[0]
    );
}

/// Scheme selection errors: a triangle scheme on a quad mesh without
/// splitting, and a quad scheme handed triangles, are typed errors.
#[test]
fn scheme_facet_mismatch_is_a_typed_error() {
    let mesh = common::mesh("catmark_cube");
    match common::grid(&mesh, &Request::uniform("pn", 4).split_quads(false)) {
        Err(Error::Tess(cpu::TessError::TriMesh(e))) => {
            assert!(e.to_string().contains("face 0"), "{e}")
        }
        other => panic!("expected a TriMesh error, got {other:?}"),
    }
    let tri = tessellate_runtime_tri(&mesh);
    let quad_scheme = cpu::scheme("pccm").expect("pccm");
    assert!(matches!(
        cpu::construct_tri(&tri, quad_scheme),
        Err(cpu::TessError::WrongFacet { want: "quads", .. })
    ));
}

fn tessellate_runtime_tri(mesh: &tessgen_runtime::Mesh) -> tessgen_runtime::trimesh::TriMesh {
    tessgen_runtime::trimesh::TriMesh::from_mesh(
        mesh,
        &tessgen_runtime::trimesh::TriOptions {
            split_quads: true,
            ..Default::default()
        },
    )
    .expect("split")
}
