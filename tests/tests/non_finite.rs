//! No silent non-finite output (issue: reliability): inputs whose size
//! would overflow f32 evaluation are refused naming the vertex
//! (`MeshError::TooLarge`), the largest accepted sizes evaluate to finite
//! samples with unit normals, any NaN or infinite sample that still comes
//! out is `Error::NonFiniteSample` naming its face, and degenerate faces get
//! finite samples with a defined (unit or zero) normal.

mod common;

use glam::Vec3;
use tessgen_runtime::mesh::{MeshError, MAX_COORDINATE, MAX_EXTENT};
use tessgen_runtime::tessellate::{Error, Output, Request, Session};
use tessgen_runtime::{Mesh, Tessellation};

const QUAD_SCHEMES: &[&str] = &["pccm", "acc", "gregory", "gregory_osd", "g1cc"];

fn cpu(mesh: &Mesh, scheme: &str, level: u32) -> Result<Output, Error> {
    let request = Request::uniform(scheme, level);
    let v = request.validate(mesh)?;
    Session::new().run(&v)
}

fn transformed(name: &str, f: impl Fn([f32; 3]) -> [f32; 3]) -> Mesh {
    let mut m = common::mesh(name);
    for p in &mut m.positions {
        *p = f(*p);
    }
    m
}

/// The example: a cube with one vertex at 1e30 tessellated with
/// exit 0 and 130 `nan` lines; now refused before any evaluation.
#[test]
fn a_vertex_far_out_is_refused_by_name() {
    let mut cube = common::mesh("catmark_cube");
    cube.positions[3] = [1e30, 1e30, 1e30];
    for scheme in QUAD_SCHEMES.iter().chain(&["pn"]) {
        match cpu(&cube, scheme, 4) {
            Err(Error::Mesh(e @ MeshError::TooLarge { vertex: 3, .. })) => {
                let text = e.to_string();
                assert!(text.contains("vertex 3"), "{text}");
                assert!(text.contains("bounding box"), "{text}");
            }
            other => panic!("{scheme}: {other:?}"),
        }
    }
    // Far from the origin with a small extent: the stencil sums' rounding
    // alone would overflow the normals.
    let moved = transformed("catmark_cube", |p| p.map(|c| c + 4.0 * MAX_COORDINATE));
    match cpu(&moved, "pccm", 4) {
        Err(Error::Mesh(MeshError::TooLarge { what, .. })) => assert!(what.contains("coordinate")),
        other => panic!("{other:?}"),
    }
}

/// The largest accepted sizes: every sample finite, every normal of unit
/// length (a zero normal would be the silent overflow this bound prevents).
#[test]
fn the_largest_accepted_meshes_evaluate_finite() {
    for name in [
        "catmark_cube",
        "catmark_toroidal_tet",
        "catmark_righthanded",
    ] {
        let m = common::mesh(name);
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in &m.positions {
            lo = lo.min(Vec3::from(*p));
            hi = hi.max(Vec3::from(*p));
        }
        let scale = 0.99 * MAX_EXTENT / (hi - lo).max_element();
        let big = transformed(name, |p| p.map(|c| c * scale));
        for scheme in QUAD_SCHEMES {
            let out = cpu(&big, scheme, 8).unwrap_or_else(|e| panic!("{name} {scheme}: {e}"));
            let t = out.grid().expect("grid");
            let worst = t
                .normals
                .iter()
                .map(|n| (n.length() - 1.0).abs())
                .fold(0.0f32, f32::max);
            assert!(worst < 1e-5, "{name} {scheme}: |n| off by {worst}");
        }
    }
}

/// The front door's last check: a NaN or infinity in any output is found
/// with its face (here planted into grids, since a valid mesh no longer
/// produces one).
#[test]
fn a_non_finite_sample_is_found_with_its_face() {
    let cube = common::mesh("catmark_cube");
    let Output::Grid(t) = cpu(&cube, "pccm", 4).expect("cube") else {
        panic!("not a grid")
    };
    assert_eq!(Output::Grid(t.clone()).first_non_finite(), None);
    let per = t.grid_len();
    for (face, k, value) in [
        (0, 0, f32::NAN),
        (3, 7, f32::INFINITY),
        (5, per - 1, f32::NAN),
    ] {
        let mut bad: Tessellation = t.clone();
        bad.normals[face * per + k].y = value;
        assert_eq!(
            Output::Grid(bad).first_non_finite(),
            Some((face, face * per + k))
        );
    }
    let mut bad = t.clone();
    bad.positions[2 * per + 1].x = f32::NAN;
    assert_eq!(Output::Grid(bad).first_non_finite(), Some((2, 2 * per + 1)));
}

/// Degenerate faces: a cube whose top face collapsed to a point (its four
/// corners coincident) and one whose face has three collinear corners. The
/// samples stay finite and every normal is defined: unit length, or the
/// zero vector where the surface's two derivatives are parallel (the
/// guarded normalize; never NaN).
#[test]
fn degenerate_faces_give_defined_normals() {
    let cube = common::mesh("catmark_cube");
    let face = cube.face(0).to_vec();
    let mut collapsed = cube.clone();
    let c = face
        .iter()
        .map(|&v| Vec3::from(cube.positions[v as usize]))
        .sum::<Vec3>()
        / 4.0;
    for &v in &face {
        collapsed.positions[v as usize] = c.to_array();
    }
    let mut collinear = cube.clone();
    let (a, b) = (
        Vec3::from(cube.positions[face[0] as usize]),
        Vec3::from(cube.positions[face[2] as usize]),
    );
    collinear.positions[face[1] as usize] = ((a + b) / 2.0).to_array();
    for (what, mesh) in [("collapsed", &collapsed), ("collinear", &collinear)] {
        for scheme in QUAD_SCHEMES {
            let out = cpu(mesh, scheme, 8).unwrap_or_else(|e| panic!("{what} {scheme}: {e}"));
            let t = out.grid().expect("grid");
            let mut zero = 0;
            for (p, n) in t.positions.iter().zip(&t.normals) {
                assert!(p.is_finite() && n.is_finite(), "{what} {scheme}");
                if *n == Vec3::ZERO {
                    zero += 1;
                } else {
                    assert!((n.length() - 1.0).abs() < 1e-5, "{what} {scheme}: {n}");
                }
            }
            println!(
                "{what} {scheme}: {zero} zero normals of {}",
                t.normals.len()
            );
        }
    }
}
