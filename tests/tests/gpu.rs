//! The wgpu path on whatever adapter is present (Mesa's lavapipe in CI):
//! GPU equals CPU within f32 tolerance, GPU output is watertight bit for bit,
//! `update_positions` equals a fresh build, and forced-small device limits
//! split the work without changing a bit.

mod common;

use glam::Vec3;
use std::sync::OnceLock;
use tessgen_runtime::gpu::{Gpu, GpuMesh, Limits};
use tessgen_runtime::{cpu, weld, Topology};

fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| match Gpu::new() {
        Ok(g) => {
            println!(
                "adapter: {} ({:?}, {})",
                g.info.name, g.info.device_type, g.info.driver_info
            );
            g
        }
        Err(e) => panic!("{e}"),
    })
}

fn load(name: &str) -> (Topology, Vec<Vec3>, f32) {
    let mesh = common::mesh(name);
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let positions = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    (topo, positions, common::bbox_diagonal(&mesh))
}

/// The watertightness matrix's levels (docs/watertight.md), as for the
/// GLSL/HLSL harness.
const LEVELS: &[u32] = &[1, 2, 3, 7, 8, 16, 33, 64];

#[test]
fn gpu_matches_cpu_and_is_watertight() {
    check_meshes("pccm", common::CLOSED_MESHES, LEVELS);
}

/// ACC, Gregory, the OpenSubdiv Gregory variant and g1cc through the same
/// WGSL path.
#[test]
fn gpu_acc_and_gregory_match_cpu_and_are_watertight() {
    for scheme in ["acc", "gregory", "gregory_osd", "g1cc"] {
        check_meshes(scheme, common::CLOSED_MESHES, LEVELS);
    }
}

/// `regular` applies to the all-valence-4 torus only.
#[test]
fn gpu_regular_torus_matches_cpu_and_is_watertight() {
    check_meshes("regular", &["catmark_torus"], LEVELS);
}

/// The 27,776-quad mesh, at fewer levels to keep CI quick.
#[test]
fn gpu_matches_cpu_on_the_big_mesh() {
    check_meshes("pccm", &[common::BIG_MESH], &[1, 2, 7, 8]);
}

fn check_meshes(scheme: &str, names: &[&str], levels: &[u32]) {
    for name in names {
        let (topo, positions, diag) = load(name);
        let euler = topo.euler_characteristic();
        let kernels = cpu::scheme(scheme).expect("scheme");
        let patches = cpu::construct(&topo, &positions, kernels).expect("construct");
        let g = GpuMesh::new(gpu(), &topo, &positions, scheme)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        for &level in levels {
            let c = cpu::evaluate(&patches, level).expect("cpu");
            let t = g.evaluate(level).unwrap_or_else(|e| panic!("{name}: {e}"));
            let (mut dp, mut da) = (0.0f64, 0.0f64);
            for k in 0..c.positions.len() {
                dp = dp.max(((t.positions[k] - c.positions[k]).length() / diag) as f64);
                da = da.max(common::angle_deg(t.normals[k], c.normals[k]));
            }
            let r = weld::weld(&t);
            println!("{scheme} {name} level {level}: max |gpu - cpu| = {dp:.2e} × diagonal, normals {da:.2e}°, open edges {}", r.open_edges);
            assert!(
                dp <= 1e-5,
                "{scheme} {name} level {level}: positions differ by {dp} × diagonal"
            );
            assert!(
                da <= 0.05,
                "{scheme} {name} level {level}: normals differ by {da}°"
            );
            assert!(
                r.is_closed_manifold(),
                "{scheme} {name} level {level}: GPU output has {} open edges",
                r.open_edges
            );
            assert_eq!(
                r.euler, euler,
                "{scheme} {name} level {level}: Euler characteristic"
            );
        }
    }
}

#[test]
fn update_positions_equals_a_fresh_build() {
    let (topo, positions, _) = load("catmark_righthanded");
    let g = GpuMesh::new(gpu(), &topo, &positions, "pccm").expect("gpu mesh");
    let moved: Vec<Vec3> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| *p + Vec3::new((i as f32 * 0.37).sin(), (i as f32 * 0.11).cos(), 0.25) * 0.05)
        .collect();
    g.update_positions(&moved).expect("update");
    let updated = g.evaluate(8).expect("evaluate");
    let fresh = GpuMesh::new(gpu(), &topo, &moved, "pccm")
        .expect("fresh")
        .evaluate(8)
        .expect("evaluate");
    assert_eq!(
        updated, fresh,
        "update_positions must equal a fresh build bit for bit"
    );
    let before = GpuMesh::new(gpu(), &topo, &positions, "pccm")
        .expect("gpu")
        .evaluate(8)
        .expect("evaluate");
    assert_ne!(
        updated.positions, before.positions,
        "the update must change the surface"
    );
}

#[test]
fn forced_small_limits_split_without_changing_results() {
    let (topo, positions, _) = load("catmark_righthanded");
    let normal = GpuMesh::new(gpu(), &topo, &positions, "pccm")
        .expect("gpu")
        .evaluate(7)
        .expect("evaluate");
    let small = Limits {
        // one workgroup of 64 threads per dispatch
        max_workgroups_per_dimension: 1,
        max_texture_dimension_2d: gpu().limits.max_texture_dimension_2d,
        max_storage_buffer_binding_size: gpu().limits.max_storage_buffer_binding_size,
    };
    let split = GpuMesh::with_limits(gpu(), &topo, &positions, "pccm", small)
        .expect("gpu")
        .evaluate(7)
        .expect("evaluate");
    assert_eq!(normal, split);
    // 128 KiB bindings: control points still fit, samples are read back in 6 chunks.
    let tiny_binding = Limits {
        max_storage_buffer_binding_size: 128 * 1024,
        ..gpu().limits
    };
    let split = GpuMesh::with_limits(gpu(), &topo, &positions, "pccm", tiny_binding)
        .expect("gpu")
        .evaluate(7)
        .expect("evaluate");
    assert_eq!(normal, split);
    let tiny_texture = Limits {
        max_texture_dimension_2d: 64,
        ..gpu().limits
    };
    assert!(matches!(
        GpuMesh::with_limits(gpu(), &topo, &positions, "pccm", tiny_texture),
        Err(tessgen_runtime::gpu::GpuError::TableTooLarge { .. })
    ));
}

/// PN and Phong on the closed shared meshes split into triangles: the WGSL
/// patch stage and triangle-domain evaluation equal the CPU and weld closed.
#[test]
fn gpu_triangle_schemes_match_cpu_and_are_watertight() {
    use tessgen_runtime::trimesh::{TriMesh, TriOptions};
    for scheme in ["pn", "stpn", "phong"] {
        let kernels = cpu::scheme(scheme).expect("scheme");
        for name in common::CLOSED_MESHES {
            let mesh = common::mesh(name);
            let diag = common::bbox_diagonal(&mesh) as f64;
            let tri = TriMesh::from_mesh(
                &mesh,
                &TriOptions {
                    split_quads: true,
                    ..Default::default()
                },
            )
            .expect("split");
            let euler = tri.euler_characteristic();
            let patches = cpu::construct_tri(&tri, kernels).expect("construct");
            let g = GpuMesh::new_tri(gpu(), &tri, scheme).unwrap_or_else(|e| panic!("{name}: {e}"));
            for &level in LEVELS {
                let c = cpu::evaluate(&patches, level).expect("cpu");
                let t = g.evaluate(level).unwrap_or_else(|e| panic!("{name}: {e}"));
                assert_eq!(t.positions.len(), c.positions.len());
                let (mut dp, mut da) = (0.0f64, 0.0f64);
                for k in 0..c.positions.len() {
                    dp = dp.max((t.positions[k] - c.positions[k]).length() as f64 / diag);
                    da = da.max(common::angle_deg(t.normals[k], c.normals[k]));
                }
                let r = weld::weld(&t);
                println!("{scheme} {name} level {level}: max |gpu - cpu| = {dp:.2e} × diagonal, normals {da:.2e}°, open edges {}", r.open_edges);
                assert!(
                    dp <= 1e-5,
                    "{scheme} {name} level {level}: positions differ by {dp}"
                );
                assert!(
                    da <= 0.05,
                    "{scheme} {name} level {level}: normals differ by {da}°"
                );
                assert!(
                    r.is_closed_manifold(),
                    "{scheme} {name} level {level}: {} open edges",
                    r.open_edges
                );
                assert_eq!(
                    r.euler, euler,
                    "{scheme} {name} level {level}: Euler characteristic"
                );
            }
        }
    }
}

/// Scalar-tagged PN with the crease loop of catmark_torus_crease.tags: the
/// WGSL patch stage reads the tags, side signs and crease vectors like the
/// CPU and welds closed.
#[test]
fn gpu_stpn_creased_torus_matches_cpu_and_is_watertight() {
    use tessgen_runtime::tags::TagFile;
    let mesh = common::mesh("catmark_torus");
    let text = std::fs::read_to_string(common::data("meshes/catmark_torus_crease.tags"))
        .expect("tags file");
    let tags = TagFile::parse(&text, mesh.num_vertices(), mesh.num_faces(), |f| {
        mesh.face(f)
    })
    .expect("tags");
    let tri = cpu::tri_mesh(&mesh, true, Some(&tags)).expect("tri");
    let diag = common::bbox_diagonal(&mesh) as f64;
    let patches = cpu::construct_tri(&tri, cpu::scheme("stpn").expect("stpn")).expect("construct");
    let g = GpuMesh::new_tri(gpu(), &tri, "stpn").expect("gpu");
    for &level in LEVELS {
        let c = cpu::evaluate(&patches, level).expect("cpu");
        let t = g.evaluate(level).expect("gpu");
        let dp = c
            .positions
            .iter()
            .zip(&t.positions)
            .map(|(a, b)| (*a - *b).length() as f64 / diag)
            .fold(0.0, f64::max);
        let r = weld::weld(&t);
        println!("stpn creased torus level {level}: max |gpu - cpu| = {dp:.2e} × diagonal, open edges {}", r.open_edges);
        assert!(dp <= 1e-5, "level {level}: {dp}");
        assert!(
            r.is_closed_manifold(),
            "level {level}: {} open edges",
            r.open_edges
        );
    }
}

/// A quad scheme refuses a triangle mesh and a triangle scheme a quad
/// topology, with the typed facet error.
#[test]
fn gpu_facet_mismatch_is_a_typed_error() {
    let (topo, positions, _) = load("catmark_cube");
    assert!(matches!(
        GpuMesh::new(gpu(), &topo, &positions, "pn"),
        Err(tessgen_runtime::gpu::GpuError::Tess(
            cpu::TessError::WrongFacet {
                want: "triangles",
                ..
            }
        ))
    ));
}

/// The front door on wgpu runs the same upload and readback as `GpuMesh`
/// (quads, and split quads for a triangle scheme), bit for bit, and one
/// `Session` serves both requests with one device.
#[test]
fn front_door_on_wgpu_is_gpu_mesh_bit_for_bit() {
    use tessgen_runtime::tessellate::{Backend, Request, Session};
    let mesh = common::mesh("catmark_cube");
    let (topo, positions, _) = load("catmark_cube");
    let mut session = Session::new();
    let quads = session
        .tessellate(&mesh, &Request::uniform("pccm", 4).on(Backend::Wgpu))
        .expect("front door")
        .into_grid()
        .expect("grid");
    let direct = GpuMesh::new(gpu(), &topo, &positions, "pccm")
        .and_then(|m| m.evaluate(4))
        .expect("GpuMesh");
    assert_eq!(bits(&quads), bits(&direct));
    let tris = session
        .tessellate(
            &mesh,
            &Request::uniform("pn", 3)
                .split_quads(true)
                .on(Backend::Wgpu),
        )
        .expect("front door")
        .into_grid()
        .expect("grid");
    let tri = cpu::tri_mesh(&mesh, true, None).expect("split");
    let direct = GpuMesh::new_tri(gpu(), &tri, "pn")
        .and_then(|m| m.evaluate(3))
        .expect("GpuMesh");
    assert_eq!(bits(&tris), bits(&direct));
}

fn bits(t: &tessgen_runtime::Tessellation) -> Vec<u32> {
    t.positions
        .iter()
        .chain(&t.normals)
        .flat_map(|v| v.to_array())
        .map(f32::to_bits)
        .collect()
}
