//! The fast grid path (`cpu::evaluate`, `cpu::evaluate_into`: hoisted row
//! curves, SIMD over columns, border samples in their own loop; every copy
//! of its lane loops this machine runs: baseline, AVX2, AVX-512) and the per-sample path (`cpu::evaluate_per_sample_into`: the generated `eval`
//! at every sample) give the same bits, for every scheme, every patch
//! class and every level 1–64 (and 65, 71: the wide grids' strips); and construction per deformation
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

/// Both paths at every level 1..=64 and at 65 and 71, compared bit for bit (the first
/// differing sample is named).
fn same_bits(what: &str, patches: &cpu::Patches) {
    let mut grid = cpu::evaluate(patches, 1).expect("evaluate");
    // 1–64: the flat bicubic interior; 65 and 71: the column strips.
    for level in (1..=64u32).chain([65, 71]) {
        cpu::evaluate_into(patches, level, &mut grid).expect("grid path");
        let n = grid.positions.len();
        let (mut p, mut nrm) = (vec![Vec3::NAN; n], vec![Vec3::NAN; n]);
        cpu::evaluate_per_sample_into(patches, level, &mut p, &mut nrm).expect("per-sample path");
        // Every copy of the lane loops this machine runs (baseline, AVX2,
        // AVX-512), not only the detected one.
        let copies: Vec<(String, Vec<Vec3>, Vec<Vec3>)> = cpu::lane_copies()
            .into_iter()
            .map(|c| {
                let (mut bp, mut bn) = (vec![Vec3::NAN; n], vec![Vec3::NAN; n]);
                cpu::evaluate_slices_copy(c, patches, level, &mut bp, &mut bn).expect(c);
                (c.to_string(), bp, bn)
            })
            .collect();
        let mut pairs: Vec<(String, &Vec<Vec3>, &Vec<Vec3>)> = vec![
            ("position".into(), &grid.positions, &p),
            ("normal".into(), &grid.normals, &nrm),
        ];
        for (c, bp, bn) in &copies {
            pairs.push((format!("position ({c} copy)"), bp, &p));
            pairs.push((format!("normal ({c} copy)"), bn, &nrm));
        }
        for (name, a, b) in pairs {
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

/// Patches whose tangents are parallel (`tessgen_patch_normal`'s zero:
/// `eval` takes the normal one nudge inside): the fast path hands such a
/// patch to the generated `eval`, so both paths still agree bit for bit.
/// The torus squeezed onto a line is degenerate everywhere (its normals
/// stay zero, never NaN); squeezed onto a plane it is not (unit normals).
#[test]
fn degenerate_patches_grid_path_matches_per_sample_path() {
    // The torus is all ordinary (bicubic form); the cube all extraordinary
    // (every other quad form: cpatch, acc, gregory).
    for (mesh_name, schemes) in [
        ("catmark_torus", &["regular", "pccm", "gregory"][..]),
        (
            "catmark_cube",
            &["pccm", "acc", "gregory", "gregory_osd", "g1cc"][..],
        ),
    ] {
        degenerate_mesh(mesh_name, schemes);
    }
}

fn degenerate_mesh(mesh_name: &str, schemes: &[&str]) {
    let mesh = common::mesh(mesh_name);
    let (topo, positions) = common::topo_positions(&mesh);
    for (what, squeeze) in [
        ("a line", Vec3::new(1.0, 0.0, 0.0)),
        ("a plane", Vec3::new(1.0, 1.0, 0.0)),
    ] {
        let squeezed: Vec<Vec3> = positions.iter().map(|p| *p * squeeze).collect();
        for &name in schemes {
            let k = cpu::scheme(name).expect("scheme");
            let patches = cpu::construct(&topo, &squeezed, k).expect("construct");
            same_bits(
                &format!("{name} on {mesh_name} squeezed onto {what}"),
                &patches,
            );
            let t = cpu::evaluate(&patches, 8).expect("evaluate");
            for n in &t.normals {
                let len = n.length();
                assert!(
                    len == 0.0 || (len - 1.0).abs() < 1e-5,
                    "{name} onto {what}: {n}"
                );
            }
        }
    }
}

/// Control points with exact `+0.0` and `-0.0` components, mixed so that
/// a sum like `-0.0 · 1 + (+0.0) · 0` (`+0.0`) and the corner point it
/// stands for (`-0.0`) differ in sign: the border's corners and edges must
/// still be the edge evaluator's bits, the interior the surface's. (The
/// meshes alone have no negative zero in any control point.)
#[test]
fn signed_zero_control_points_keep_their_bits() {
    for name in kernels::scheme_names() {
        let k = cpu::scheme(name).expect("scheme");
        if k.sides != 4 {
            continue;
        }
        for mesh_name in ["catmark_torus", "catmark_toroidal_tet"] {
            let mesh = common::mesh(mesh_name);
            let (topo, positions) = common::topo_positions(&mesh);
            let mut patches = match cpu::construct(&topo, &positions, k) {
                Ok(p) => p,
                Err(cpu::TessError::ExtraordinaryFace { .. }) => continue,
                Err(e) => panic!("{name} on {mesh_name}: {e}"),
            };
            let mut zeros = 0usize;
            for (i, p) in patches.control_points.iter_mut().enumerate() {
                let mut a = p.to_array();
                for (c, v) in a.iter_mut().enumerate() {
                    // A fixed scramble of (point, component): a quarter
                    // each -0.0 and +0.0, half kept.
                    let h = (i as u32)
                        .wrapping_mul(2_654_435_761)
                        .wrapping_add(c as u32 * 40_503)
                        >> 13;
                    match h & 3 {
                        0 => *v = -0.0,
                        1 => *v = 0.0,
                        _ => continue,
                    }
                    zeros += 1;
                }
                *p = Vec3::from_array(a);
            }
            assert!(zeros > patches.control_points.len(), "{zeros}");
            same_bits(&format!("{name} on {mesh_name} with ±0.0"), &patches);
        }
    }
}

#[test]
fn every_quad_class_is_covered() {
    for name in ["pccm", "acc", "gregory", "gregory_osd", "g1cc"] {
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

/// Meshes for construction per deformation: both classes, crease and
/// corner vertices (boundaries, the tent, a single crease), valences 3 to
/// 6 and up.
const CONSTRUCTION_MESHES: &[&str] = &[
    "catmark_torus",
    "catmark_cube",
    "catmark_toroidal_tet",
    "catmark_righthanded",
    "catmark_single_crease",
    "catmark_tent",
    "catmark_xord_boundary",
    "catmark_xord_interior",
    "catmark_gregory_test1",
    "catmark_pawn",
    "catmark_car",
];

/// `positions` moved, every vertex differently (`phase` picks the
/// deformation), with a few exact zeros and negative zeros so the sums'
/// `0.0 + x` start is exercised.
fn deform(positions: &[Vec3], phase: f32) -> Vec<Vec3> {
    positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let t = i as f32 + phase;
            let q = *p + Vec3::new((t * 0.37).sin(), (t * 0.11).cos(), 0.25 + phase) * 0.1;
            match i % 97 {
                0 => Vec3::new(-0.0, q.y, -0.0),
                1 => Vec3::new(0.0, -0.0, q.z),
                _ => q,
            }
        })
        .collect()
}

/// `Construction::update` (both copies of the vertex stage's lane loops,
/// two successive deformations into the same buffers) against a fresh
/// `cpu::construct`, bit for bit.
fn check_update(name: &str, what: &str, topo: &tessgen_runtime::Topology, positions: &[Vec3]) {
    let k = cpu::scheme(name).expect("scheme");
    let prep = match cpu::Construction::new(topo, k) {
        Ok(p) => p,
        Err(cpu::TessError::ExtraordinaryFace { .. }) => return,
        Err(e) => panic!("{name} on {what}: {e}"),
    };
    for (copy, prep) in [
        ("detected", prep.clone()),
        ("baseline", prep.with_baseline_lanes()),
    ] {
        let mut patches = prep.construct(positions);
        for phase in [0.0f32, 1.5] {
            let moved = deform(positions, phase);
            prep.update(&moved, &mut patches).expect("update");
            let fresh = cpu::construct(topo, &moved, k).expect("construct");
            let ctx = format!("{name} on {what} ({copy} lanes, phase {phase})");
            assert_eq!(patches.face_class, fresh.face_class, "{ctx}");
            // Entries the construction writes are the fresh bits; the rows
            // no face reads stay 0 (the control points below show that no
            // face reads them).
            let (a, b) = (bits(&patches.vertex_out), bits(&fresh.vertex_out));
            assert_eq!(a.len(), b.len(), "{ctx}");
            let zero = bits(&[Vec3::ZERO])[0];
            if let Some(i) = (0..a.len()).find(|&i| {
                a[i] != if prep.writes_vertex_out(i) {
                    b[i]
                } else {
                    zero
                }
            }) {
                panic!(
                    "{ctx}: vertex stage output {i} (written: {}): {:?} vs {:?}",
                    prep.writes_vertex_out(i),
                    a[i],
                    b[i]
                );
            }
            let (a, b) = (bits(&patches.control_points), bits(&fresh.control_points));
            if let Some(i) = (0..a.len().max(b.len())).find(|&i| a.get(i) != b.get(i)) {
                panic!("{ctx}: control point {i}: {:?} vs {:?}", a.get(i), b.get(i));
            }
        }
    }
}

#[test]
fn construction_update_matches_fresh_construct() {
    for name in kernels::scheme_names() {
        if cpu::scheme(name).expect("scheme").sides != 4 {
            continue;
        }
        for mesh_name in CONSTRUCTION_MESHES {
            let mesh = common::mesh(mesh_name);
            let (topo, positions) = common::topo_positions(&mesh);
            check_update(name, mesh_name, &topo, &positions);
        }
    }
}

/// The large mesh: many blocks and chunks, partial chunks at every block's
/// valence groups.
#[test]
fn construction_update_matches_fresh_construct_big() {
    let mesh = common::mesh(common::BIG_MESH);
    let (topo, positions) = common::topo_positions(&mesh);
    for name in ["pccm", "acc", "gregory", "gregory_osd"] {
        check_update(name, common::BIG_MESH, &topo, &positions);
    }
}

/// On an almost all-ordinary mesh the construction skips the rows only
/// extraordinary faces read (PCCM's and ACC's `t`, Gregory's `r`: `n` of `3n + 1`
/// rows of most vertices), and still writes every row some face reads
/// (`check_update` compares the control points bit for bit).
#[test]
fn construction_skips_rows_no_face_reads() {
    let mesh = common::mesh(common::BIG_MESH);
    let (topo, _) = common::topo_positions(&mesh);
    for name in ["pccm", "acc", "gregory", "gregory_osd"] {
        let k = cpu::scheme(name).expect("scheme");
        let prep = cpu::Construction::new(&topo, k).expect("construction");
        let (_, total) = cpu::vertex_out_offsets(&topo, k);
        let skipped = (0..total as usize)
            .filter(|&i| !prep.writes_vertex_out(i))
            .count();
        // 4 of 13 rows of a valence-4 vertex; vertices next to an
        // extraordinary face compute all of theirs.
        assert!(
            skipped * 5 > total as usize && skipped * 3 < total as usize,
            "{name}: {skipped} of {total} entries skipped"
        );
        assert!(!prep.writes_vertex_out(total as usize), "{name}");
    }
}

/// Patches not made by the construction (another layout, or buffers of
/// the wrong length) are refused, not written out of place.
#[test]
fn construction_update_refuses_foreign_patches() {
    let k = cpu::scheme("pccm").expect("scheme");
    let (topo, positions) = common::topo_positions(&common::mesh("catmark_torus"));
    let prep = cpu::Construction::new(&topo, k).expect("construction");
    let mut patches = prep.construct(&positions);
    patches.vertex_out.pop();
    assert!(prep.update(&positions, &mut patches).is_err());
    let mut patches = prep.construct(&positions);
    patches.control_points.pop();
    assert!(prep.update(&positions, &mut patches).is_err());
    let mut patches = prep.construct(&positions);
    assert!(prep
        .update(&positions[..positions.len() - 1], &mut patches)
        .is_err());
}

/// The bit checks above run every copy this machine has: all three on an
/// x86-64 machine with AVX-512F (this project's machine class).
#[test]
fn every_detected_lane_copy_is_checked() {
    let copies = tessgen_runtime::cpu::lane_copies();
    println!("lane copies checked: {copies:?}");
    assert_eq!(copies.first(), Some(&"baseline"));
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            assert!(copies.contains(&"avx2"), "{copies:?}");
        }
        if std::arch::is_x86_feature_detected!("avx512f") {
            assert!(copies.contains(&"avx512"), "{copies:?}");
        }
    }
}

/// Leaving out the faces that emit nothing (`cpu::evaluate_emitting`, what
/// the CPU backend runs for holes and feature-adaptive depths) gives
/// exactly `evaluate` followed by `retain_faces`: same grids, same face
/// ids, same bits.
#[test]
fn evaluating_only_the_emitting_faces_changes_no_bit() {
    let mesh = common::mesh("catmark_toroidal_tet");
    let (topo, positions) = common::topo_positions(&mesh);
    let k = cpu::scheme("pccm").expect("scheme");
    let patches = cpu::construct(&topo, &positions, k).expect("construct");
    let faces = patches.face_class.len();
    for (what, emits) in [
        (
            "every third",
            (0..faces).map(|f| f % 3 != 0).collect::<Vec<_>>(),
        ),
        ("none", vec![false; faces]),
        ("all", vec![true; faces]),
    ] {
        for level in [1, 4, 9] {
            let mut all = cpu::evaluate(&patches, level).expect("evaluate");
            all.retain_faces(&emits);
            let some = cpu::evaluate_emitting(&patches, level, &emits).expect("emitting");
            assert_eq!(some.face_ids, all.face_ids, "{what} level {level}");
            assert_eq!(
                bits(&some.positions),
                bits(&all.positions),
                "{what} level {level}"
            );
            assert_eq!(
                bits(&some.normals),
                bits(&all.normals),
                "{what} level {level}"
            );
            assert_eq!(some.faces, emits.iter().filter(|&&e| e).count());
        }
    }
}

/// The open and tagged meshes (boundaries, creases, corners: sector
/// vertex outputs, one-face corners whose tangents are parallel): both
/// paths at every level, for every quad scheme the mesh runs as is.
#[test]
fn open_meshes_grid_path_matches_per_sample_path() {
    for mesh_name in ["catmark_tent", "catmark_xord_boundary", "catmark_car"] {
        let mesh = common::mesh(mesh_name);
        let (topo, positions) = common::topo_positions(&mesh);
        for name in kernels::scheme_names() {
            let k = cpu::scheme(name).expect("scheme");
            if k.sides != 4 {
                continue;
            }
            let patches = match cpu::construct(&topo, &positions, k) {
                Ok(p) => p,
                Err(cpu::TessError::ExtraordinaryFace { .. }) => continue,
                Err(e) => panic!("{name} on {mesh_name}: {e}"),
            };
            same_bits(&format!("{name} on {mesh_name}"), &patches);
        }
    }
}
