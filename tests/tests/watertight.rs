//! Watertightness, bit for bit: exact-weld the CPU output of every closed
//! shared mesh and require a closed 2-manifold with the input's Euler
//! characteristic.

mod common;

use tessgen_runtime::{cpu, weld, Topology};

const LEVELS: &[u32] = &[1, 2, 3, 7, 8, 16, 33];

fn check(name: &str, scheme: &str) {
    check_levels(name, scheme, LEVELS);
}

fn check_levels(name: &str, scheme: &str, levels: &[u32]) {
    let mesh = common::mesh(name);
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let euler = topo.euler_characteristic();
    for &level in levels {
        let t = cpu::tessellate_mesh(&mesh, scheme, level).expect("tessellate");
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

/// ACC, Gregory and its OpenSubdiv variant on every closed shared mesh.
#[test]
fn acc_and_gregory_closed_meshes_weld_closed() {
    for scheme in ["acc", "gregory", "gregory_osd"] {
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
    let mut t = cpu::tessellate_mesh(&mesh, "pccm", 4).expect("tessellate");
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
    for scheme in ["pn", "phong"] {
        for name in common::CLOSED_MESHES {
            let mesh = common::mesh(name);
            let euler = Topology::build(&mesh, &cpu::topology_options())
                .expect("topology")
                .euler_characteristic();
            for &level in &[1, 2, 7, 8, 16] {
                let t = cpu::tessellate_any(&mesh, scheme, level, true).expect("tessellate");
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

/// Scheme selection errors: a triangle scheme on a quad mesh without
/// splitting, and a quad scheme handed triangles, are typed errors.
#[test]
fn scheme_facet_mismatch_is_a_typed_error() {
    let mesh = common::mesh("catmark_cube");
    match cpu::tessellate_any(&mesh, "pn", 4, false) {
        Err(cpu::TessError::TriMesh(e)) => {
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
