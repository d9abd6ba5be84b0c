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
//!   the CPU's displaced grids (the maximum is printed);
//! * scale 0 gives the plain (undisplaced) harness output bit for bit;
//! * negative control: without ownership (`Ownership::PerPatch`) the weld
//!   opens.
//!
//! Rows print as `| scheme | backend | mesh | level | open edges | max |Δp| /
//! diag |` (run with `--nocapture`) for docs/watertight.md.

mod common;

use common::{displacement, seam_meshes};

use glam::Vec3;
use tessgen_runtime::displace::{Displacement, Ownership};
use tessgen_runtime::tessellate::Request;
use tessgen_runtime::vulkan::{Language, Options, VkMesh, Vulkan};
use tessgen_runtime::{cpu, weld, Mesh, Tessellation, Topology};

const SCHEMES: &[&str] = &["pccm", "acc", "gregory", "gregory_osd"];
const LEVELS: &[u32] = &[1, 3, 8];

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
    let d = displacement(Ownership::LowestFace, 0.5);
    for (name, mesh) in &seam_meshes() {
        let diag = common::bbox_diagonal(mesh);
        for scheme in SCHEMES {
            for language in Language::ALL {
                let m = displaced(&vk, mesh, scheme, &d, language);
                for &level in LEVELS {
                    let t = m.evaluate(level).expect("evaluate");
                    let report = weld::weld(&t);
                    let cpu =
                        common::grid(mesh, &Request::uniform(scheme, level).displaced(&d)).unwrap();
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
                    let plain = common::grid(mesh, &Request::uniform(scheme, level)).unwrap();
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

const TRI_SCHEMES: &[&str] = &["pn", "stpn", "phong"];

/// A triangle scheme's displacing harness on the triangle split of `mesh`,
/// with the CPU's patches and displacement data of the same split (the
/// parity reference).
fn tri_displaced<'v>(
    vk: &'v Vulkan,
    mesh: &Mesh,
    scheme: &str,
    d: &Displacement,
    options: &Options,
) -> (
    VkMesh<'v>,
    cpu::Patches,
    tessgen_runtime::displace::DisplaceData,
) {
    let tri = cpu::tri_mesh(mesh, true, None).expect("triangle split");
    let kernels = cpu::scheme(scheme).expect("scheme");
    let patches = cpu::construct_tri(&tri, kernels).expect("patches");
    let data = cpu::displacement_data_tri(mesh, &tri, &patches, d).expect("displacement data");
    let m = VkMesh::new_tri_displaced(vk, mesh, &tri, scheme, d, options)
        .unwrap_or_else(|e| panic!("{scheme}: {e}"));
    (m, patches, data)
}

/// Triangle schemes (`pn`, `stpn`, `phong`) in the displacing evaluation
/// stage (`eval_domain_displaced_tess`): the tessellator's boundary
/// vertices take the integer step with the owner's normal (from the global
/// control-point buffer) and texture coordinate, its inner vertices their
/// own. On the triangle split of both seam meshes, GLSL and HLSL, levels
/// 1, 3, 8: the captured triangles weld closed, every captured vertex is
/// within 1e-5 × diag of the CPU's `eval_domain_displaced` at the same
/// domain point (the maximum is printed), and the surface moved.
#[test]
fn displaced_triangle_tessellation_stages_weld_closed_and_match_the_cpu() {
    let vk = device();
    let d = displacement(Ownership::LowestFace, 0.5);
    for (name, mesh) in &seam_meshes() {
        let diag = common::bbox_diagonal(mesh);
        for scheme in TRI_SCHEMES {
            for language in Language::ALL {
                let (m, patches, data) =
                    tri_displaced(&vk, mesh, scheme, &d, &Options::new(language));
                for &level in LEVELS {
                    let c = m.evaluate_triangles(level).expect("capture");
                    let report = c.weld();
                    let err = c
                        .max_deviation_displaced(&patches, &data)
                        .unwrap_or_else(|f| panic!("face {f}"))
                        / diag;
                    let moved = c
                        .max_deviation(&patches)
                        .unwrap_or_else(|f| panic!("face {f}"));
                    println!(
                        "| {scheme} | {} | {name} split | {level} | {} | {err:.1e} |",
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
                    assert!(
                        moved > 0.01 * diag,
                        "{name} {scheme} L{level}: not displaced"
                    );
                }
            }
        }
    }
}

/// Scale 0: the displacing triangle evaluation stage captures exactly the
/// plain stage's vertices, bit for bit.
#[test]
fn scale_zero_triangle_stage_is_the_plain_stage_bit_for_bit() {
    let vk = device();
    let mesh = common::mesh("catmark_cube_uv");
    let tri = cpu::tri_mesh(&mesh, true, None).expect("triangle split");
    let d = displacement(Ownership::LowestFace, 0.0);
    for scheme in TRI_SCHEMES {
        for language in Language::ALL {
            let plain = VkMesh::new_tri(&vk, &tri, scheme, &Options::new(language)).expect("plain");
            let (zero, _, _) = tri_displaced(&vk, &mesh, scheme, &d, &Options::new(language));
            for level in [1, 5] {
                let a = plain.evaluate_triangles(level).unwrap();
                let b = zero.evaluate_triangles(level).unwrap();
                assert_eq!(a, b, "{scheme} {} L{level}", language.name());
            }
        }
    }
}

/// Negative control: per-patch ownership in the triangle stages opens the
/// weld (every edge of the split cube but the diagonals is a seam).
#[test]
fn without_ownership_the_displaced_triangle_stages_crack() {
    let vk = device();
    let mesh = common::mesh("catmark_cube_uv");
    let d = displacement(Ownership::PerPatch, 0.5);
    for scheme in TRI_SCHEMES {
        for language in Language::ALL {
            let (m, _, _) = tri_displaced(&vk, &mesh, scheme, &d, &Options::new(language));
            for level in [1, 3, 8] {
                let report = m.evaluate_triangles(level).unwrap().weld();
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

/// Adaptive triangle stages with displacement: random per-edge factors,
/// integer and fractional-odd partitioning, the split cube (a seam on every
/// edge but the diagonals) welds closed and every captured vertex matches
/// the CPU's `eval_domain_displaced` at the fixed-point domain point;
/// per-patch ownership opens.
#[test]
fn adaptive_displaced_triangle_stages_weld_closed() {
    use tessgen_runtime::adaptive::{self, Adaptive, Metric, Partitioning};
    let vk = device();
    let mesh = common::mesh("catmark_cube_uv");
    let diag = common::bbox_diagonal(&mesh);
    let tri = cpu::tri_mesh(&mesh, true, None).expect("triangle split");
    let (_, edges) = tri.edge_ids();
    let options = |language, partitioning| Options {
        adaptive: Some(Adaptive {
            metric: Metric::Buffer(adaptive::random_factors(edges, 0x7e55_6e12, 1.0, 12.0)),
            partitioning,
            min: 1.0,
            max: 64.0,
        }),
        ..Options::new(language)
    };
    for scheme in ["pn", "phong"] {
        for language in Language::ALL {
            for p in [Partitioning::Integer, Partitioning::FractionalOdd] {
                let d = displacement(Ownership::LowestFace, 0.5);
                let (m, patches, data) =
                    tri_displaced(&vk, &mesh, scheme, &d, &options(language, p));
                let c = m.evaluate_adaptive().expect("adaptive capture");
                let r = c.weld();
                let err = c
                    .max_deviation_displaced(&patches, &data)
                    .unwrap_or_else(|f| panic!("face {f}"))
                    / diag;
                println!(
                    "| {scheme} | {} | catmark_cube_uv split | adaptive {p:?} | {} triangles | {} | {err:.1e} |",
                    language.name(),
                    c.triangle_count(),
                    r.open_edges
                );
                assert_eq!(
                    (r.open_edges, r.overused_edges),
                    (0, 0),
                    "{scheme} {} {p:?}",
                    language.name()
                );
                assert!(
                    err <= 1e-5,
                    "{scheme} {} {p:?}: parity {err}",
                    language.name()
                );
            }
        }
        let d = displacement(Ownership::PerPatch, 0.5);
        let (m, _, _) = tri_displaced(
            &vk,
            &mesh,
            scheme,
            &d,
            &options(Language::Glsl, Partitioning::Integer),
        );
        let open = m.evaluate_adaptive().unwrap().weld().open_edges;
        println!("adaptive triangle negative control {scheme} glsl: {open} open edges");
        assert!(open > 0, "{scheme}: per-patch ownership stayed closed");
    }
}
