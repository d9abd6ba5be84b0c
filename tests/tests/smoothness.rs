//! Lemma 1 of the PCCM paper, measured on the generated CPU kernels:
//! C¹ inside a c-patch, C¹ c-patch|bicubic, G¹ c-patch|c-patch (C² between
//! bicubics): normals of adjacent patches agree at shared boundary samples to
//! < 0.01° in f32. And on the all-regular torus the surface is the uniform
//! bicubic B-spline, i.e. the exact Catmull-Clark limit.

mod common;

use glam::{DVec3, Vec3};
use tessgen_runtime::tessellate::{Error, Request};
use tessgen_runtime::{cpu, FaceClass, Topology};

const LEVEL: u32 = 8;

/// Grid index of parameter `t` (of `level`) along local edge `k`.
fn edge_sample(k: u32, t: u32, level: u32) -> u32 {
    let (i, j) = match k {
        0 => (t, 0),
        1 => (level, t),
        2 => (level - t, level),
        _ => (0, level - t),
    };
    j * (level + 1) + i
}

/// Worst normal angle between the two patches of every shared edge, split by
/// the kinds of patches meeting there.
fn boundary_normal_angles(name: &str, scheme: &str) -> [f64; 3] {
    let mesh = common::mesh(name);
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let t = common::grid(&mesh, &Request::uniform(scheme, LEVEL)).expect("tessellate");
    let per = t.grid_len() as u32;
    // [bicubic|bicubic, c-patch|bicubic, c-patch|c-patch]
    let mut worst = [0.0f64; 3];
    for h in 0..topo.twin.len() as u32 {
        let g = topo.twin[h as usize];
        if g < h {
            continue;
        }
        let (fa, fb) = (topo.face[h as usize], topo.face[g as usize]);
        let (ka, kb) = (
            h - topo.face_offsets[fa as usize],
            g - topo.face_offsets[fb as usize],
        );
        let extra = [fa, fb]
            .iter()
            .filter(|f| topo.classes[**f as usize] == FaceClass::Extraordinary)
            .count();
        for s in 0..=LEVEL {
            let a = t.normals[(fa * per + edge_sample(ka, s, LEVEL)) as usize];
            let b = t.normals[(fb * per + edge_sample(kb, LEVEL - s, LEVEL)) as usize];
            let pa = t.positions[(fa * per + edge_sample(ka, s, LEVEL)) as usize];
            let pb = t.positions[(fb * per + edge_sample(kb, LEVEL - s, LEVEL)) as usize];
            assert_eq!(pa, pb, "{name}: edge {h}/{g} sample {s} positions differ");
            worst[extra] = worst[extra].max(common::angle_deg(a, b));
        }
    }
    worst
}

#[test]
fn normals_agree_across_patch_boundaries() {
    for name in common::CLOSED_MESHES {
        let w = boundary_normal_angles(name, "pccm");
        println!("{name}: worst normal angle bicubic|bicubic {:.2e}°, c-patch|bicubic {:.2e}°, c-patch|c-patch {:.2e}°", w[0], w[1], w[2]);
        for (kind, a) in ["bicubic|bicubic", "c-patch|bicubic", "c-patch|c-patch"]
            .iter()
            .zip(w)
        {
            assert!(a < 0.01, "{name}: {kind} normals differ by {a}°");
        }
    }
}

/// ACC's tangent-patch normals and the true normals of Gregory (both
/// variants) and g1cc are continuous across every patch edge (acc.md §4,
/// gregory.md §3, docs/g1cc.md): the two sides agree up to f32 rounding
/// (< 0.05°) at every shared sample.
#[test]
fn acc_and_gregory_normals_agree_across_patch_boundaries() {
    for scheme in ["acc", "gregory", "gregory_osd", "g1cc"] {
        for name in common::CLOSED_MESHES {
            let w = boundary_normal_angles(name, scheme);
            println!("{scheme} {name}: worst normal angle ordinary|ordinary {:.2e}°, extraordinary|ordinary {:.2e}°, extraordinary|extraordinary {:.2e}°", w[0], w[1], w[2]);
            for a in w {
                assert!(a < 0.05, "{scheme} {name}: normals differ by {a}°");
            }
        }
    }
}

/// Normal of the bicubic net `cp[4k + l]` at (u, v), in f64.
fn bicubic_normal(cp: &[Vec3], u: f64, v: f64) -> DVec3 {
    let b = |t: f64| {
        let s = 1.0 - t;
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
    };
    let db = |t: f64| {
        let s = 1.0 - t;
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * t * s,
            6.0 * t * s - 3.0 * t * t,
            3.0 * t * t,
        ]
    };
    let (bu, bv, dbu, dbv) = (b(u), b(v), db(u), db(v));
    let (mut pu, mut pv) = (DVec3::ZERO, DVec3::ZERO);
    for k in 0..4 {
        for l in 0..4 {
            let p = cp[4 * k + l].as_dvec3();
            pu += p * dbu[k] * bv[l];
            pv += p * bu[k] * dbv[l];
        }
    }
    pu.cross(pv).normalize()
}

/// The ACC *geometry* patch alone is only C⁰ where an extraordinary vertex
/// is involved (acc.md §3, §6): its true normals jump across such edges,
/// which is why ACC shades with the tangent patches. Measured in f64 from
/// the generated geometry points (the first 16 of both ACC classes).
#[test]
fn acc_geometry_patch_alone_is_not_smooth() {
    let mut overall = 0.0f64;
    for name in common::CLOSED_MESHES {
        let mesh = common::mesh(name);
        let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
        let positions: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|p| Vec3::from_array(*p))
            .collect();
        let kernels = cpu::scheme("acc").expect("acc");
        let patches = cpu::construct(&topo, &positions, kernels).expect("construct");
        let cp = |f: u32| &patches.control_points[patches.cp_offsets[f as usize] as usize..];
        let uv = |k: u32, t: f64| match k {
            0 => (t, 0.0),
            1 => (1.0, t),
            2 => (1.0 - t, 1.0),
            _ => (0.0, 1.0 - t),
        };
        let mut worst = 0.0f64;
        for h in 0..topo.twin.len() as u32 {
            let g = topo.twin[h as usize];
            if g < h {
                continue;
            }
            let (fa, fb) = (topo.face[h as usize], topo.face[g as usize]);
            let (ka, kb) = (
                h - topo.face_offsets[fa as usize],
                g - topo.face_offsets[fb as usize],
            );
            for s in 1..LEVEL {
                let t = s as f64 / LEVEL as f64;
                let (ua, va) = uv(ka, t);
                let (ub, vb) = uv(kb, 1.0 - t);
                let a = bicubic_normal(cp(fa), ua, va);
                let b = bicubic_normal(cp(fb), ub, vb);
                worst = worst.max(a.cross(b).length().atan2(a.dot(b)).to_degrees());
            }
        }
        println!("acc geometry patch {name}: worst true-normal jump across edges {worst:.2}°");
        overall = overall.max(worst);
    }
    assert!(
        overall > 1.0,
        "the ACC geometry patch should show a normal jump near extraordinary vertices, worst {overall}°"
    );
}

/// Quartic triangle piece `i` of a c-patch, rebuilt in f64 from the 24
/// coefficients the generated patch stage produced (pccm.md §4.4), so the
/// two pieces meeting at a diagonal can be evaluated on it.
fn piece_net(cp: &[Vec3], i: usize) -> std::collections::HashMap<(u32, u32, u32), DVec3> {
    let c = |corner: usize, k: usize| cp[6 * (corner % 4) + k].as_dvec3();
    let (a, b, p) = (i, i + 1, i + 3);
    let mut n = std::collections::HashMap::new();
    n.insert((4, 0, 0), c(a, 0));
    n.insert((0, 4, 0), c(b, 0));
    n.insert((3, 1, 0), (c(a, 0) + 3.0 * c(a, 1)) / 4.0);
    n.insert((1, 3, 0), (c(b, 0) + 3.0 * c(b, 2)) / 4.0);
    n.insert((2, 2, 0), (c(a, 1) + c(b, 2)) / 2.0);
    n.insert((2, 1, 1), c(a, 3));
    n.insert((1, 2, 1), c(a, 4));
    n.insert((1, 1, 2), c(a, 5));
    n.insert(
        (3, 0, 1),
        (2.0 * c(a, 0) + 3.0 * c(a, 1) + 3.0 * c(a, 2)) / 8.0,
    );
    n.insert(
        (0, 3, 1),
        (2.0 * c(b, 0) + 3.0 * c(b, 2) + 3.0 * c(b, 1)) / 8.0,
    );
    n.insert((2, 0, 2), (c(a, 3) + c(p, 4)) / 2.0);
    n.insert((0, 2, 2), (c(a, 4) + c(b, 3)) / 2.0);
    n.insert((1, 0, 3), (c(a, 5) + c(p, 5)) / 2.0);
    n.insert((0, 1, 3), (c(a, 5) + c(b, 5)) / 2.0);
    n.insert((0, 0, 4), (c(0, 5) + c(1, 5) + c(2, 5) + c(3, 5)) / 4.0);
    n
}

/// Normal of piece `i` at domain point (u, v) (pccm.md §5.2).
fn piece_normal(cp: &[Vec3], i: usize, u: f64, v: f64) -> DVec3 {
    let bary = match i {
        0 => [1.0 - u - v, u - v, 2.0 * v],
        1 => [u - v, u + v - 1.0, 2.0 - 2.0 * u],
        2 => [u + v - 1.0, v - u, 2.0 - 2.0 * v],
        _ => [v - u, 1.0 - u - v, 2.0 * u],
    };
    let mut net = piece_net(cp, i);
    for deg in (1..4u32).rev() {
        let mut next = std::collections::HashMap::new();
        for k in 0..=deg {
            for l in 0..=deg - k {
                let m = deg - k - l;
                let p = net[&(k + 1, l, m)] * bary[0]
                    + net[&(k, l + 1, m)] * bary[1]
                    + net[&(k, l, m + 1)] * bary[2];
                next.insert((k, l, m), p);
            }
        }
        net = next;
    }
    let (qa, qb, qc) = (net[&(1, 0, 0)], net[&(0, 1, 0)], net[&(0, 0, 1)]);
    (qb - qa).cross(qc - qa).normalize()
}

#[test]
fn c_patch_pieces_join_smoothly_along_diagonals() {
    for name in common::CLOSED_MESHES {
        let mesh = common::mesh(name);
        let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
        let positions: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|p| Vec3::from_array(*p))
            .collect();
        let kernels = cpu::scheme("pccm").expect("pccm");
        let patches = cpu::construct(&topo, &positions, kernels).expect("construct");
        let mut worst = 0.0f64;
        for f in 0..topo.classes.len() {
            if topo.classes[f] != FaceClass::Extraordinary {
                continue;
            }
            let cp = &patches.control_points
                [patches.cp_offsets[f] as usize..patches.cp_offsets[f + 1] as usize];
            // Diagonal V_i–C is shared by pieces i and i-1; sample it (excluding the centre and corner).
            for i in 0..4usize {
                let corner = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][i];
                for s in 1..10 {
                    let t = s as f64 / 10.0 * 0.5;
                    let (u, v) = (
                        corner.0 + (0.5 - corner.0) * t * 2.0,
                        corner.1 + (0.5 - corner.1) * t * 2.0,
                    );
                    let a = piece_normal(cp, i, u, v);
                    let b = piece_normal(cp, (i + 3) % 4, u, v);
                    let ang = a.cross(b).length().atan2(a.dot(b)).to_degrees();
                    worst = worst.max(ang);
                }
            }
        }
        println!("{name}: worst normal angle across c-patch diagonals {worst:.2e}°");
        assert!(
            worst < 0.01,
            "{name}: pieces of a c-patch differ by {worst}° on a diagonal"
        );
    }
}

/// On the all-valence-4 torus, regular and pccm are the uniform bicubic
/// B-spline = the Catmull-Clark limit surface (cc_limit ground truth).
#[test]
fn regular_torus_is_the_catmull_clark_limit() {
    let mesh = common::mesh("catmark_torus");
    let diag = common::bbox_diagonal(&mesh) as f64;
    let (n, limit) = common::cc_limit("catmark_torus");
    for scheme in ["regular", "pccm", "acc", "gregory", "gregory_osd", "g1cc"] {
        let t = common::grid(&mesh, &Request::uniform(scheme, (n - 1) as u32)).expect("tessellate");
        assert_eq!(t.positions.len(), limit.len());
        let (mut dp, mut da) = (0.0f64, 0.0f64);
        for (k, [p, nrm]) in limit.iter().enumerate() {
            dp = dp.max((t.positions[k] - *p).as_dvec3().length() / diag);
            da = da.max(common::angle_deg(t.normals[k], *nrm));
        }
        println!(
            "torus {scheme}: max position error {dp:.2e} × diagonal, max normal angle {da:.2e}°"
        );
        assert!(
            dp < 1e-6,
            "{scheme}: torus position off the CC limit by {dp} × diagonal"
        );
        assert!(
            da < 1e-3,
            "{scheme}: torus normal off the CC limit by {da}°"
        );
    }
}

#[test]
fn regular_scheme_rejects_extraordinary_faces() {
    let mesh = common::mesh("catmark_cube");
    match common::grid(&mesh, &Request::uniform("regular", 4)) {
        Err(Error::Tess(cpu::TessError::ExtraordinaryFace { face, scheme })) => {
            assert_eq!(face, 0);
            assert_eq!(scheme, "regular");
        }
        other => panic!("expected ExtraordinaryFace, got {other:?}"),
    }
    assert!(matches!(
        common::grid(&mesh, &Request::uniform("nope", 4)),
        Err(Error::UnknownScheme { .. })
    ));
    assert!(matches!(
        common::grid(&mesh, &Request::uniform("pccm", 0)),
        Err(Error::Level { level: 0 })
    ));
}
