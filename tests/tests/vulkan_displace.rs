//! Displacement in the hardware tessellation stages (spec/watertight.md
//! Rules 4 and 5): the emitted GLSL `.tese` and HLSL `ds_main`, built with
//! `-DTESSGEN_DISPLACE`, run on lavapipe through the Vulkan harness
//! (`VkMesh::new_displaced`: the compute patch stage fills the global
//! control-point buffer the evaluation stage reads the owner patch's normal
//! from). On meshes whose every edge is a texture seam
//! (`catmark_cube_uv`, and `catmark_toroidal_tet` with a chart per face):
//!
//! * the displaced surface welds closed bit for bit;
//! * every captured position is within 1e-5 × bounding-box diagonal of
//!   the CPU's `tessellate_displaced` (the maximum is printed);
//! * scale 0 gives the plain (undisplaced) harness output bit for bit;
//! * negative control: without ownership (`Ownership::PerPatch`) the weld
//!   opens.
//!
//! Rows print as `| scheme | backend | mesh | level | open edges | max |Δp| /
//! diag |` (run with `--nocapture`) for docs/watertight.md.

mod common;

use glam::Vec3;
use tessgen_runtime::displace::{DisplaceMap, Displacement, Ownership};
use tessgen_runtime::vulkan::{Language, Options, VkMesh, Vulkan};
use tessgen_runtime::{cpu, weld, Mesh, Tessellation, Topology};

const SCHEMES: &[&str] = &["pccm", "acc", "gregory", "gregory_osd"];
const LEVELS: &[u32] = &[1, 3, 8];

/// The map of tests/tests/displace.rs: it jumps between the cells of the
/// 3×2 atlas, so the two sides of every seam read different heights.
fn map() -> DisplaceMap {
    DisplaceMap::from_fn(48, 32, |s, t| {
        let cell = (s * 3.0).floor() + 3.0 * (t * 2.0).floor();
        0.05 * cell + 0.1 * (9.0 * s).sin() * (7.0 * t).cos()
    })
}

fn displacement(ownership: Ownership, scale: f32) -> Displacement {
    Displacement {
        map: map(),
        scale,
        ownership,
    }
}

/// Every face its own chart (as in tests/tests/displace.rs).
fn per_face_charts(mut mesh: Mesh) -> Mesh {
    let nf = mesh.num_faces();
    let side = (nf as f32).sqrt().ceil() as usize;
    mesh.texcoords.clear();
    mesh.face_texcoords.clear();
    for f in 0..nf {
        let (cx, cy) = ((f % side) as f32, (f / side) as f32);
        let cell = 1.0 / side as f32;
        let m = cell / 16.0;
        let quad = [[m, m], [cell - m, m], [cell - m, cell - m], [m, cell - m]];
        for q in quad {
            mesh.face_texcoords.push(mesh.texcoords.len() as u32);
            mesh.texcoords.push([cx * cell + q[0], cy * cell + q[1]]);
        }
    }
    mesh
}

fn device() -> Vulkan {
    Vulkan::new().unwrap_or_else(|e| panic!("{e}"))
}

fn topo_positions(mesh: &Mesh) -> (Topology, Vec<Vec3>) {
    let topo = Topology::build(mesh, &cpu::topology_options()).expect("topology");
    let positions = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    (topo, positions)
}

fn displaced<'v>(
    vk: &'v Vulkan,
    mesh: &Mesh,
    scheme: &str,
    d: &Displacement,
    language: Language,
) -> VkMesh<'v> {
    let (topo, positions) = topo_positions(mesh);
    VkMesh::new_displaced(
        vk,
        mesh,
        &topo,
        &positions,
        scheme,
        d,
        &Options::new(language),
    )
    .unwrap_or_else(|e| panic!("{scheme} {}: {e}", language.name()))
}

/// Largest `|a − b|` over all samples; NaN (a sample never written) is
/// infinite.
fn max_diff(a: &Tessellation, b: &Tessellation) -> f32 {
    assert_eq!(a.positions.len(), b.positions.len());
    a.positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| {
            let d = (*p - *q).length();
            if d.is_nan() {
                f32::INFINITY
            } else {
                d
            }
        })
        .fold(0.0, f32::max)
}

#[test]
fn displaced_tessellation_stages_weld_closed_and_match_the_cpu() {
    let vk = device();
    let meshes = [
        ("catmark_cube_uv", common::mesh("catmark_cube_uv")),
        (
            "catmark_toroidal_tet (charts)",
            per_face_charts(common::mesh("catmark_toroidal_tet")),
        ),
    ];
    let d = displacement(Ownership::LowestFace, 0.5);
    for (name, mesh) in &meshes {
        let diag = common::bbox_diagonal(mesh);
        for scheme in SCHEMES {
            for language in Language::ALL {
                let m = displaced(&vk, mesh, scheme, &d, language);
                for &level in LEVELS {
                    let t = m.evaluate(level).expect("evaluate");
                    let report = weld::weld(&t);
                    let cpu = cpu::tessellate_displaced(mesh, scheme, level, &d).unwrap();
                    let err = max_diff(&t, &cpu) / diag;
                    println!(
                        "| {scheme} | {} | {name} | {level} | {} | {err:.1e} |",
                        language.name(),
                        report.open_edges
                    );
                    assert!(
                        report.is_closed_manifold(),
                        "{name} {scheme} {} L{level}: {report:?}",
                        language.name()
                    );
                    assert!(
                        err <= 1e-5,
                        "{name} {scheme} {} L{level}: parity {err}",
                        language.name()
                    );
                    // Something moved: the displaced capture is not the plain one.
                    let plain = cpu::tessellate_mesh(mesh, scheme, level).unwrap();
                    assert!(max_diff(&t, &plain) > 0.01 * diag);
                }
            }
        }
    }
}

#[test]
fn scale_zero_is_the_plain_tessellation_stage_bit_for_bit() {
    let vk = device();
    let mesh = common::mesh("catmark_cube_uv");
    let (topo, positions) = topo_positions(&mesh);
    let d = displacement(Ownership::LowestFace, 0.0);
    for scheme in SCHEMES {
        for language in Language::ALL {
            let plain = VkMesh::new(&vk, &topo, &positions, scheme, &Options::new(language))
                .expect("plain mesh");
            let zero = displaced(&vk, &mesh, scheme, &d, language);
            for level in [1, 5] {
                let a = plain.evaluate(level).unwrap();
                let b = zero.evaluate(level).unwrap();
                assert_eq!(a, b, "{scheme} {} L{level}", language.name());
            }
        }
    }
}

#[test]
fn without_ownership_the_displaced_tessellation_stages_crack() {
    let vk = device();
    let mesh = common::mesh("catmark_cube_uv");
    let d = displacement(Ownership::PerPatch, 0.5);
    for scheme in SCHEMES {
        for language in Language::ALL {
            let m = displaced(&vk, &mesh, scheme, &d, language);
            for level in [1, 3, 8] {
                let report = weld::weld(&m.evaluate(level).unwrap());
                println!(
                    "negative control {scheme} {} L{level}: {} open edges",
                    language.name(),
                    report.open_edges
                );
                assert!(
                    report.open_edges > 0,
                    "{scheme} {} L{level}: {report:?}",
                    language.name()
                );
            }
        }
    }
}

/// With `TESSGEN_ADAPTIVE` the evaluation stage's `level` is the
/// tessellator's fixed-point denominator 2^16 and the displacement step
/// runs unchanged on those integer coordinates (texture-coordinate weights
/// `m/2^16`, `(2^16 − m)/2^16`, the owner's mirrored `2^16 − m`): random
/// per-edge factors, integer and fractional-odd partitioning, the captured
/// triangle soup welds closed across every seam; per-patch ownership opens.
#[test]
fn adaptive_displaced_tessellation_welds_closed() {
    use tessgen_runtime::adaptive::{self, Adaptive, Metric, Partitioning};
    let vk = device();
    let mesh = common::mesh("catmark_cube_uv");
    let (topo, positions) = topo_positions(&mesh);
    let (_, edges) = adaptive::edge_ids(&topo);
    let run = |scheme: &str, language, partitioning, ownership| {
        let options = Options {
            adaptive: Some(Adaptive {
                metric: Metric::Buffer(adaptive::random_factors(edges, 0x7e55_6e11, 1.0, 12.0)),
                partitioning,
                min: 1.0,
                max: 64.0,
            }),
            ..Options::new(language)
        };
        let d = displacement(ownership, 0.5);
        let m = VkMesh::new_displaced(&vk, &mesh, &topo, &positions, scheme, &d, &options)
            .unwrap_or_else(|e| panic!("{scheme}: {e}"));
        let tris = m.evaluate_adaptive().expect("adaptive capture").triangles();
        assert!(tris.iter().flatten().all(|p| p.is_finite()));
        let soup: Vec<Vec3> = tris.iter().flatten().copied().collect();
        let r = weld::weld_triangles(&soup, 3, &[[0, 1, 2]]);
        (tris.len(), r.open_edges, r.overused_edges)
    };
    for scheme in ["pccm", "gregory"] {
        for language in Language::ALL {
            for p in [Partitioning::Integer, Partitioning::FractionalOdd] {
                let (tris, open, over) = run(scheme, language, p, Ownership::LowestFace);
                println!(
                    "| {scheme} | {} | catmark_cube_uv | adaptive {p:?} | {tris} triangles | {open} |",
                    language.name()
                );
                assert_eq!((open, over), (0, 0), "{scheme} {} {p:?}", language.name());
            }
        }
        let (_, open, _) = run(
            scheme,
            Language::Glsl,
            Partitioning::Integer,
            Ownership::PerPatch,
        );
        println!("adaptive negative control {scheme} glsl: {open} open edges");
        assert!(open > 0, "{scheme}: per-patch ownership stayed closed");
    }
}
