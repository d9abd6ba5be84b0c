//! The fast grid path (`cpu::evaluate`, `cpu::evaluate_into`: hoisted row
//! curves, SIMD over columns, border samples in their own loop; both its
//! AVX2 and its baseline copy) and the per-sample path (`cpu::evaluate_per_sample_into`: the generated `eval`
//! at every sample) give the same bits, for every scheme, every patch
//! class and every level 1–64; and construction per deformation
//! (`cpu::Construction::update`) gives the control points of a fresh
//! `cpu::construct`, bit for bit.

mod common;

use glam::Vec3;
use tessgen_runtime::tags::TagFile;
use tessgen_runtime::{cpu, kernels};

/// Meshes whose faces cover both classes of every quad scheme: the torus
/// is all ordinary, the cube all extraordinary, the toroidal tetrahedron
/// mixed.
const QUAD_MESHES: &[&str] = &["catmark_torus", "catmark_cube", "catmark_toroidal_tet"];

fn bits(v: &[Vec3]) -> Vec<[u32; 3]> {
    v.iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

/// Both paths at every level 1..=64, compared bit for bit (the first
/// differing sample is named).
fn same_bits(what: &str, patches: &cpu::Patches) {
    let mut grid = cpu::evaluate(patches, 1).expect("evaluate");
    for level in 1..=64u32 {
        cpu::evaluate_into(patches, level, &mut grid).expect("grid path");
        let n = grid.positions.len();
        let (mut p, mut nrm) = (vec![Vec3::NAN; n], vec![Vec3::NAN; n]);
        cpu::evaluate_per_sample_into(patches, level, &mut p, &mut nrm).expect("per-sample path");
        let (mut bp, mut bn) = (vec![Vec3::NAN; n], vec![Vec3::NAN; n]);
        cpu::evaluate_slices_baseline(patches, level, &mut bp, &mut bn).expect("baseline copy");
        for (name, a, b) in [
            ("position", &grid.positions, &p),
            ("normal", &grid.normals, &nrm),
            ("position (baseline copy)", &bp, &p),
            ("normal (baseline copy)", &bn, &nrm),
        ] {
            let (a, b) = (bits(a), bits(b));
            if let Some(s) = (0..n).find(|&s| a[s] != b[s]) {
                let per = grid.grid_len();
                panic!(
                    "{what} level {level}: {name} of sample {} of face {} (class {}) differs: grid {:?} per-sample {:?}",
                    s % per,
                    s / per,
                    patches.face_class[s / per],
                    a[s],
                    b[s]
                );
            }
        }
    }
}

#[test]
fn quad_schemes_grid_path_matches_per_sample_path() {
    for name in kernels::scheme_names() {
        let k = cpu::scheme(name).expect("scheme");
        if k.sides != 4 {
            continue;
        }
        for mesh_name in QUAD_MESHES {
            let mesh = common::mesh(mesh_name);
            let (topo, positions) = common::topo_positions(&mesh);
            let patches = match cpu::construct(&topo, &positions, k) {
                Ok(p) => p,
                // `regular` has no patch for extraordinary faces.
                Err(cpu::TessError::ExtraordinaryFace { .. }) => continue,
                Err(e) => panic!("{name} on {mesh_name}: {e}"),
            };
            same_bits(&format!("{name} on {mesh_name}"), &patches);
        }
    }
}

#[test]
fn every_quad_class_is_covered() {
    for name in ["pccm", "acc", "gregory", "gregory_osd"] {
        let k = cpu::scheme(name).expect("scheme");
        let mut seen = vec![false; k.classes.len()];
        for mesh_name in QUAD_MESHES {
            let mesh = common::mesh(mesh_name);
            let (topo, positions) = common::topo_positions(&mesh);
            let patches = cpu::construct(&topo, &positions, k).expect("construct");
            for &c in &patches.face_class {
                seen[c as usize] = true;
            }
        }
        assert!(seen.iter().all(|&s| s), "{name}: classes seen {seen:?}");
    }
}

#[test]
fn triangle_schemes_grid_path_matches_per_sample_path() {
    let torus = common::mesh("catmark_torus");
    let tags = {
        let p = common::data("meshes/catmark_torus_crease.tags");
        let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        TagFile::parse(&text, torus.num_vertices(), torus.num_faces(), |f| {
            torus.face(f)
        })
        .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    };
    for name in kernels::scheme_names() {
        let k = cpu::scheme(name).expect("scheme");
        if k.sides != 3 {
            continue;
        }
        for (mesh_name, tagged) in [("catmark_toroidal_tet", false), ("catmark_torus", true)] {
            let mesh = common::mesh(mesh_name);
            let tri = cpu::tri_mesh(&mesh, true, tagged.then_some(&tags)).expect("split");
            let patches = cpu::construct_tri(&tri, k).expect("patches");
            same_bits(&format!("{name} on {mesh_name}"), &patches);
        }
    }
}

#[test]
fn construction_update_matches_fresh_construct() {
    for name in kernels::scheme_names() {
        let k = cpu::scheme(name).expect("scheme");
        if k.sides != 4 {
            continue;
        }
        for mesh_name in QUAD_MESHES.iter().chain(&["catmark_righthanded"]) {
            let mesh = common::mesh(mesh_name);
            let (topo, positions) = common::topo_positions(&mesh);
            let prep = match cpu::Construction::new(&topo, k) {
                Ok(p) => p,
                Err(cpu::TessError::ExtraordinaryFace { .. }) => continue,
                Err(e) => panic!("{name} on {mesh_name}: {e}"),
            };
            // A deformation: every vertex moved differently.
            let moved: Vec<Vec3> = positions
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    *p + Vec3::new((i as f32 * 0.37).sin(), (i as f32 * 0.11).cos(), 0.25) * 0.1
                })
                .collect();
            let mut patches = prep.construct(&positions);
            prep.update(&moved, &mut patches).expect("update");
            let fresh = cpu::construct(&topo, &moved, k).expect("construct");
            assert_eq!(
                patches.face_class, fresh.face_class,
                "{name} on {mesh_name}"
            );
            assert_eq!(
                bits(&patches.vertex_out),
                bits(&fresh.vertex_out),
                "{name} on {mesh_name}: vertex stage"
            );
            assert_eq!(
                bits(&patches.control_points),
                bits(&fresh.control_points),
                "{name} on {mesh_name}: patch stage"
            );
        }
    }
}
