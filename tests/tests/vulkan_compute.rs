//! The emitted GLSL and HLSL *compute* entries, run for real: the Vulkan
//! harness (`VkMesh::evaluate_compute`) runs the vertex stage, the patch
//! stage (`<scheme>_patch.comp` / HLSL `patch_main`) into the global
//! control-point buffer and the evaluation (`<scheme>_eval.comp` / HLSL
//! `eval_main`, one Plan body, `Entries::compute_eval`) into the samples,
//! then reads the grid back in the CPU's layout. For every built-in scheme
//! (quads on `catmark_toroidal_tet`, `regular` on `catmark_torus`, triangle
//! schemes on the cube's split), both languages, levels 1, 3, 8:
//!
//! * the grid welds closed bit for bit, and
//! * every sample is within 1e-5 × bounding-box diagonal of the CPU's
//!   `cpu::evaluate` (the maximum is printed).
//!
//! With displacement (the seam meshes, quads and split triangles) the
//! compute evaluation displaces through `eval_displaced_global`: closed
//! across every texture seam, within 1e-5 × diag of
//! the CPU front door's displaced grids, and per-patch ownership opens.
//!
//! Rows print as `| scheme | backend | mesh | level | open edges | max |Δp|
//! / diag |` (run with `--nocapture`) for docs/watertight.md.

mod common;

use common::{displacement, seam_meshes};
use glam::Vec3;
use tessgen_runtime::displace::{Displacement, Ownership};
use tessgen_runtime::tessellate::Request;
use tessgen_runtime::vulkan::{Language, Options, VkMesh, Vulkan};
use tessgen_runtime::{cpu, weld, Mesh, Tessellation, Topology};

const LEVELS: &[u32] = &[1, 3, 8];

fn device() -> Vulkan {
    Vulkan::new().unwrap_or_else(|e| panic!("{e}"))
}

fn positions(mesh: &Mesh) -> Vec<Vec3> {
    mesh.positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect()
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

/// `scheme` on `mesh` (triangle schemes: its split) for the compute
/// entries, plain or displaced by `d`.
fn upload<'v>(
    vk: &'v Vulkan,
    mesh: &Mesh,
    scheme: &str,
    d: Option<&Displacement>,
    language: Language,
) -> VkMesh<'v> {
    let options = Options::new(language);
    let kernels = cpu::scheme(scheme).expect("scheme");
    let m = if kernels.sides == 4 {
        let topo = Topology::build(mesh, &cpu::topology_options()).expect("topology");
        let p = positions(mesh);
        match d {
            None => VkMesh::new(vk, &topo, &p, scheme, &options),
            Some(d) => VkMesh::new_displaced(vk, mesh, &topo, &p, scheme, d, &options),
        }
    } else {
        let tri = cpu::tri_mesh(mesh, true, None).expect("triangle split");
        match d {
            None => VkMesh::new_tri(vk, &tri, scheme, &options),
            Some(d) => VkMesh::new_tri_displaced(vk, mesh, &tri, scheme, d, &options),
        }
    };
    m.unwrap_or_else(|e| panic!("{scheme} {}: {e}", language.name()))
}

#[test]
fn compute_entries_weld_closed_and_match_the_cpu() {
    let vk = device();
    for scheme in tessgen_runtime::kernels::scheme_names() {
        let kernels = cpu::scheme(scheme).expect("scheme");
        let name = match (scheme, kernels.sides) {
            ("regular", _) => "catmark_torus",
            (_, 3) => "catmark_cube",
            _ => "catmark_toroidal_tet",
        };
        let mesh = common::mesh(name);
        let diag = common::bbox_diagonal(&mesh);
        for language in Language::ALL {
            let mut m = upload(&vk, &mesh, scheme, None, language);
            for &level in LEVELS {
                let t = m.evaluate_compute(level).expect("compute evaluation");
                let cpu = common::grid(&mesh, &Request::uniform(scheme, level).split_quads(true))
                    .expect("cpu");
                let report = weld::weld(&t);
                let err = max_diff(&t, &cpu) / diag;
                println!(
                    "| {scheme} | {} compute | {name} | {level} | {} | {err:.1e} |",
                    language.name(),
                    report.open_edges
                );
                assert!(
                    report.is_closed_manifold(),
                    "{scheme} {} L{level}: {report:?}",
                    language.name()
                );
                assert!(
                    err <= 1e-5,
                    "{scheme} {} L{level}: parity {err}",
                    language.name()
                );
            }
        }
    }
}

#[test]
fn displaced_compute_entries_weld_closed_and_match_the_cpu() {
    let vk = device();
    let d = displacement(Ownership::LowestFace, 0.5);
    for (name, mesh) in &seam_meshes() {
        let diag = common::bbox_diagonal(mesh);
        for scheme in ["pccm", "gregory", "pn", "phong"] {
            for language in Language::ALL {
                let mut m = upload(&vk, mesh, scheme, Some(&d), language);
                for &level in LEVELS {
                    let t = m.evaluate_compute(level).expect("compute evaluation");
                    let cpu = common::grid(
                        mesh,
                        &Request::uniform(scheme, level)
                            .split_quads(true)
                            .displaced(&d),
                    )
                    .expect("cpu");
                    let report = weld::weld(&t);
                    let err = max_diff(&t, &cpu) / diag;
                    println!(
                        "| {scheme} | {} compute, displaced | {name} | {level} | {} | {err:.1e} |",
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
                    let plain =
                        common::grid(mesh, &Request::uniform(scheme, level).split_quads(true))
                            .expect("cpu");
                    assert!(max_diff(&t, &plain) > 0.01 * diag, "not displaced");
                }
            }
        }
    }
}

/// Negative control: per-patch ownership in the compute evaluation opens
/// the weld of the cube (a seam on every edge).
#[test]
fn without_ownership_the_displaced_compute_entries_crack() {
    let vk = device();
    let mesh = common::mesh("catmark_cube_uv");
    let d = displacement(Ownership::PerPatch, 0.5);
    for scheme in ["pccm", "pn"] {
        for language in Language::ALL {
            let mut m = upload(&vk, &mesh, scheme, Some(&d), language);
            let open = weld::weld(&m.evaluate_compute(3).unwrap()).open_edges;
            println!(
                "compute negative control {scheme} {} L3: {open} open edges",
                language.name()
            );
            assert!(open > 0, "{scheme} {}: stayed closed", language.name());
        }
    }
}
