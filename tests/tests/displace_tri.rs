//! Displacement for the triangle schemes (`pn`, `stpn`, `phong`;
//! spec/watertight.md Rules 4 and 5 with 12 texture coordinates per
//! triangle): on the triangle split of meshes whose every edge is a texture
//! seam, the displaced surface welds closed bit for bit on the CPU and on
//! wgpu, wgpu matches the CPU, scale 0 is the plain evaluation bit for bit,
//! and without ownership the weld opens.

mod common;

use common::{displacement, seam_meshes as meshes};

use tessgen_runtime::displace::{DisplaceData, Displacement, Ownership};
use tessgen_runtime::tessellate::Request;
use tessgen_runtime::{cpu, weld, Mesh};

const SCHEMES: &[&str] = &["pn", "stpn", "phong"];
const LEVELS: &[u32] = &[1, 3, 8];

fn cpu_displaced(mesh: &Mesh, scheme: &str, level: u32, d: &Displacement) -> cpu::Tessellation {
    common::grid(
        mesh,
        &Request::uniform(scheme, level)
            .split_quads(true)
            .displaced(d),
    )
    .expect("displaced tessellation")
}

fn max_offset(a: &cpu::Tessellation, b: &cpu::Tessellation) -> f32 {
    assert_eq!(a.positions.len(), b.positions.len());
    a.positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| (*p - *q).length())
        .fold(0.0, f32::max)
}

#[test]
fn displaced_triangle_schemes_weld_closed_on_the_cpu() {
    let d = displacement(Ownership::LowestFace, 0.5);
    for (name, mesh) in &meshes() {
        for scheme in SCHEMES {
            for &level in LEVELS {
                let t = cpu_displaced(mesh, scheme, level, &d);
                assert_eq!(t.sides, 3);
                let report = weld::weld(&t);
                assert!(
                    report.is_closed_manifold(),
                    "{name} {scheme} L{level}: {report:?}"
                );
                let plain =
                    common::grid(mesh, &Request::uniform(scheme, level).split_quads(true)).unwrap();
                let moved = max_offset(&t, &plain);
                assert!(moved > 0.01, "{name} {scheme} L{level}: moved {moved}");
                assert!(t.positions.iter().all(|p| p.is_finite()));
                println!("cpu {name} {scheme} L{level}: closed, max displacement {moved:.3}");
            }
        }
    }
}

#[test]
fn triangle_displacement_off_is_plain_evaluation_bit_for_bit() {
    let mesh = common::mesh("catmark_cube_uv");
    let tri = cpu::tri_mesh(&mesh, true, None).unwrap();
    for scheme in SCHEMES {
        let patches = cpu::construct_tri(&tri, cpu::scheme(scheme).unwrap()).unwrap();
        for level in [1, 3, 8] {
            let plain = cpu::evaluate(&patches, level).unwrap();
            let off = cpu::evaluate_displaced(&patches, level, &DisplaceData::off()).unwrap();
            assert_eq!(plain, off, "{scheme} L{level}");
            let d = Displacement {
                scale: 0.0,
                ..displacement(Ownership::LowestFace, 0.5)
            };
            let data = cpu::displacement_data_tri(&mesh, &tri, &patches, &d).unwrap();
            assert_eq!(data.texcoords.len(), 24 * tri.triangles.len());
            assert_eq!(data.owners.len(), 24 * tri.triangles.len());
            let zero = cpu::evaluate_displaced(&patches, level, &data).unwrap();
            assert_eq!(plain, zero, "{scheme} L{level} scale 0");
        }
    }
}

#[test]
fn without_ownership_displaced_triangles_crack() {
    let d = displacement(Ownership::PerPatch, 0.5);
    for (name, mesh) in &meshes() {
        for scheme in SCHEMES {
            for level in [3, 8] {
                let report = weld::weld(&cpu_displaced(mesh, scheme, level, &d));
                println!(
                    "negative control {name} {scheme} L{level}: {} open edges",
                    report.open_edges
                );
                assert!(
                    report.open_edges > 0,
                    "{name} {scheme} L{level}: {report:?}"
                );
            }
        }
    }
}

/// Split quads inherit their corners' `vt`; a missing one is reported at
/// the source face and its corner in file order.
#[test]
fn triangle_texture_coordinates_come_from_the_source_faces() {
    let mesh = common::mesh("catmark_cube_uv");
    let tri = cpu::tri_mesh(&mesh, true, None).unwrap();
    let patches = cpu::construct_tri(&tri, cpu::scheme("pn").unwrap()).unwrap();
    let data = cpu::displacement_data_tri(
        &mesh,
        &tri,
        &patches,
        &displacement(Ownership::PerPatch, 0.5),
    )
    .unwrap();
    // Triangle 1 = [v0, v2, v3] of face 0: its interior coordinates are
    // face 0's corners 0, 2, 3; per-patch ownership repeats them per corner.
    let c = mesh.face_offsets[0] as usize;
    for (k, corner) in [0, 2, 3].into_iter().enumerate() {
        let want = mesh.corner_texcoord(c + corner).unwrap();
        for j in 0..4 {
            let at = 24 + 2 * (4 * k + j);
            assert_eq!(
                [data.texcoords[at], data.texcoords[at + 1]],
                want,
                "k {k} j {j}"
            );
        }
    }
    let plain = common::mesh("catmark_cube");
    let err = common::grid(
        &plain,
        &Request::uniform("pn", 2)
            .split_quads(true)
            .displaced(&displacement(Ownership::LowestFace, 0.5)),
    )
    .unwrap_err();
    assert!(err.to_string().contains("face 0 corner 0"), "{err}");
}

mod wgpu_path {
    use super::*;
    use tessgen_runtime::gpu::{Gpu, GpuMesh};

    #[test]
    fn displaced_triangles_weld_closed_on_wgpu_and_match_the_cpu() {
        let gpu = Gpu::new().unwrap_or_else(|e| panic!("{e}"));
        for (name, mesh) in &meshes() {
            let tri = cpu::tri_mesh(mesh, true, None).unwrap();
            let diag = common::bbox_diagonal(mesh);
            for scheme in SCHEMES {
                for (ownership, closed) in
                    [(Ownership::LowestFace, true), (Ownership::PerPatch, false)]
                {
                    let d = displacement(ownership, 0.5);
                    let gm =
                        GpuMesh::new_tri_displaced(&gpu, mesh, &tri, scheme, &d).expect("gpu mesh");
                    for &level in LEVELS {
                        let g = gm.evaluate(level).expect("evaluate");
                        let report = weld::weld(&g);
                        if closed {
                            assert!(
                                report.is_closed_manifold(),
                                "{name} {scheme} L{level}: {report:?}"
                            );
                        } else if level > 1 {
                            assert!(
                                report.open_edges > 0,
                                "{name} {scheme} L{level}: {report:?}"
                            );
                        }
                        let c = cpu_displaced(mesh, scheme, level, &d);
                        let err = max_offset(&g, &c) / diag;
                        println!(
                            "wgpu {name} {scheme} {ownership:?} L{level}: {} open edges, GPU vs CPU {err:.1e} x diag",
                            report.open_edges
                        );
                        assert!(err < 1e-5, "{name} {scheme} L{level}: GPU vs CPU {err:e}");
                    }
                }
            }
        }
    }
}

/// Each half of the ownership is needed for triangles too: owned normals
/// with each patch's own texture coordinates crack on every seam; owned
/// texture coordinates with each patch's own boundary normal crack where
/// the two patches' normals differ in the last bits (none at level 3 on
/// this mesh, some at level 8: docs/watertight.md has the counts).
#[test]
fn triangle_ownership_halves() {
    let mesh = common::mesh("catmark_cube_uv");
    let tri = cpu::tri_mesh(&mesh, true, None).unwrap();
    for scheme in SCHEMES {
        let patches = cpu::construct_tri(&tri, cpu::scheme(scheme).unwrap()).unwrap();
        let data =
            |o| cpu::displacement_data_tri(&mesh, &tri, &patches, &displacement(o, 0.5)).unwrap();
        let (owned, own) = (data(Ownership::LowestFace), data(Ownership::PerPatch));
        let own_normals = DisplaceData {
            owners: own.owners.clone(),
            ..owned.clone()
        };
        let own_texcoords = DisplaceData {
            texcoords: own.texcoords.clone(),
            ..owned.clone()
        };
        for level in [3, 8] {
            let open = |d: &DisplaceData| {
                weld::weld(&cpu::evaluate_displaced(&patches, level, d).unwrap()).open_edges
            };
            let (n, t) = (open(&own_normals), open(&own_texcoords));
            println!(
                "{scheme} L{level}: per-patch normals {n} open edges, per-patch texcoords {t}"
            );
            assert!(t > 0, "{scheme} L{level}");
            if level == 8 {
                assert!(n > 0, "{scheme} L{level}");
            }
        }
    }
}
