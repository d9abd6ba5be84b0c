//! Displacement mapping without cracks (spec/watertight.md Rules 4 and 5):
//! displaced surfaces weld closed bit for bit across texture seams on the
//! CPU and on wgpu, displacement off equals plain evaluation bit for bit,
//! and the negative control (every patch its own normal and texture
//! coordinates on its edges) opens the weld.

mod common;

use common::{displacement, per_face_charts};

use glam::Vec3;
use tessgen_runtime::displace::{DisplaceData, Displacement, Ownership};
use tessgen_runtime::tessellate::Request;
use tessgen_runtime::{cpu, weld, Mesh, Topology};

/// Quad schemes that apply to the cube (regular needs valence 4).
const SCHEMES: &[&str] = &["pccm", "acc", "gregory", "gregory_osd"];
const LEVELS: &[u32] = &[1, 2, 3, 7, 16];

fn cpu_displaced(mesh: &Mesh, scheme: &str, level: u32, d: &Displacement) -> cpu::Tessellation {
    common::grid(mesh, &Request::uniform(scheme, level).displaced(d))
        .expect("displaced tessellation")
}

fn max_offset(a: &cpu::Tessellation, b: &cpu::Tessellation) -> f32 {
    a.positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| (*p - *q).length())
        .fold(0.0, f32::max)
}

#[test]
fn obj_texture_coordinates_are_read_per_corner() {
    let mesh = common::mesh("catmark_cube_uv");
    assert_eq!(mesh.texcoords.len(), 24);
    assert_eq!(mesh.face_texcoords.len(), 24);
    // Face 1's corner 0 is vertex 3 with vt 5.
    let c = mesh.face_offsets[1] as usize;
    assert_eq!(mesh.face(1)[0], 2);
    assert_eq!(mesh.corner_texcoord(c), Some(mesh.texcoords[4]));
    // Without vt, displacement is a typed error naming the face and corner.
    let plain = common::mesh("catmark_cube");
    let err = common::grid(
        &plain,
        &Request::uniform("pccm", 2).displaced(&displacement(Ownership::LowestFace, 0.5)),
    )
    .unwrap_err();
    assert!(err.to_string().contains("face 0 corner 0"), "{err}");
}

#[test]
fn displacement_off_is_plain_evaluation_bit_for_bit() {
    let mesh = common::mesh("catmark_cube_uv");
    let topo = Topology::build(&mesh, &cpu::topology_options()).unwrap();
    let positions: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    for scheme in SCHEMES {
        let patches = cpu::construct(&topo, &positions, cpu::scheme(scheme).unwrap()).unwrap();
        for level in [1, 5, 16] {
            let plain = cpu::evaluate(&patches, level).unwrap();
            let off = cpu::evaluate_displaced(&patches, level, &DisplaceData::off()).unwrap();
            assert_eq!(plain, off, "{scheme} L{level}");
            // Scale 0 with real data is off too.
            let d = Displacement {
                scale: 0.0,
                ..displacement(Ownership::LowestFace, 0.5)
            };
            let data = cpu::displacement_data(&mesh, &topo, &patches, &d).unwrap();
            let zero = cpu::evaluate_displaced(&patches, level, &data).unwrap();
            assert_eq!(plain, zero, "{scheme} L{level} scale 0");
        }
    }
}

#[test]
fn displaced_cube_with_uv_seams_welds_closed_on_the_cpu() {
    let meshes = [
        ("catmark_cube_uv", common::mesh("catmark_cube_uv")),
        (
            "catmark_toroidal_tet (charts)",
            per_face_charts(common::mesh("catmark_toroidal_tet")),
        ),
    ];
    let d = displacement(Ownership::LowestFace, 0.5);
    for (name, mesh) in &meshes {
        for scheme in SCHEMES {
            for &level in LEVELS {
                let t = cpu_displaced(mesh, scheme, level, &d);
                let report = weld::weld(&t);
                assert!(
                    report.is_closed_manifold(),
                    "{name} {scheme} L{level}: {report:?}"
                );
                let plain = common::grid(mesh, &Request::uniform(scheme, level)).unwrap();
                let moved = max_offset(&t, &plain);
                assert!(moved > 0.01, "{name} {scheme} L{level}: moved {moved}");
                println!("cpu {name} {scheme} L{level}: closed, max displacement {moved:.3}");
                assert!(t.positions.iter().all(|p| p.is_finite()));
            }
        }
    }
}

#[test]
fn without_ownership_the_displaced_surface_cracks() {
    let mesh = common::mesh("catmark_cube_uv");
    let d = displacement(Ownership::PerPatch, 0.5);
    for scheme in SCHEMES {
        for level in [2, 7] {
            let report = weld::weld(&cpu_displaced(&mesh, scheme, level, &d));
            println!(
                "negative control {scheme} L{level}: {} open edges",
                report.open_edges
            );
            assert!(report.open_edges > 0, "{scheme} L{level}: {report:?}");
        }
    }
}

mod wgpu_path {
    use super::*;
    use tessgen_runtime::gpu::{Gpu, GpuMesh};

    #[test]
    fn displaced_surfaces_weld_closed_on_wgpu_and_match_the_cpu() {
        let gpu = match Gpu::new() {
            Ok(g) => g,
            Err(e) => panic!("{e}"),
        };
        let meshes = [
            common::mesh("catmark_cube_uv"),
            per_face_charts(common::mesh("catmark_toroidal_tet")),
        ];
        for mesh in &meshes {
            let topo = Topology::build(mesh, &cpu::topology_options()).unwrap();
            let positions: Vec<Vec3> = mesh
                .positions
                .iter()
                .map(|p| Vec3::from_array(*p))
                .collect();
            let diag = common::bbox_diagonal(mesh);
            for scheme in SCHEMES {
                for (ownership, closed) in
                    [(Ownership::LowestFace, true), (Ownership::PerPatch, false)]
                {
                    let d = displacement(ownership, 0.5);
                    let gm = GpuMesh::new_displaced(&gpu, mesh, &topo, &positions, scheme, &d)
                        .expect("gpu mesh");
                    for level in [1, 3, 8] {
                        let g = gm.evaluate(level).expect("evaluate");
                        let report = weld::weld(&g);
                        if closed {
                            assert!(report.is_closed_manifold(), "{scheme} L{level}: {report:?}");
                        } else if level > 1 {
                            assert!(report.open_edges > 0, "{scheme} L{level}: {report:?}");
                        }
                        let c = cpu_displaced(mesh, scheme, level, &d);
                        let err = max_offset(&g, &c) / diag;
                        println!(
                            "wgpu {} faces {scheme} {ownership:?} L{level}: {} open edges, GPU vs CPU {err:.1e} x diag",
                            mesh.num_faces(),
                            report.open_edges
                        );
                        assert!(err < 1e-5, "{scheme} L{level}: GPU vs CPU {err:e}");
                    }
                }
            }
        }
    }
}

/// Each half of the ownership is needed: owned texture coordinates with
/// each patch's own boundary normals, and owned normals with each patch's
/// own texture coordinates, both crack.
#[test]
fn normal_and_texcoord_ownership_are_each_needed() {
    let mesh = common::mesh("catmark_cube_uv");
    let topo = Topology::build(&mesh, &cpu::topology_options()).unwrap();
    let positions: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    for scheme in SCHEMES {
        let patches = cpu::construct(&topo, &positions, cpu::scheme(scheme).unwrap()).unwrap();
        let data =
            |o| cpu::displacement_data(&mesh, &topo, &patches, &displacement(o, 0.5)).unwrap();
        let (owned, own) = (data(Ownership::LowestFace), data(Ownership::PerPatch));
        let own_normals = DisplaceData {
            owners: own.owners.clone(),
            ..owned.clone()
        };
        let own_texcoords = DisplaceData {
            texcoords: own.texcoords.clone(),
            ..owned.clone()
        };
        for level in [2, 7] {
            let open = |d: &DisplaceData| {
                weld::weld(&cpu::evaluate_displaced(&patches, level, d).unwrap()).open_edges
            };
            let (n, t) = (open(&own_normals), open(&own_texcoords));
            println!(
                "{scheme} L{level}: per-patch normals {n} open edges, per-patch texcoords {t}"
            );
            assert!(t > 0, "{scheme} L{level}");
            assert!(n > 0, "{scheme} L{level}");
        }
    }
}
