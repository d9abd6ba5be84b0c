//! Adaptive tessellation through the emitted GLSL and HLSL tessellation
//! shaders on Vulkan (lavapipe in CI): per-edge factors, integer and
//! fractional partitioning, captured as triangles by the harness's
//! geometry shader and welded bit for bit.
//!
//! * Random per-edge factors (seeded, deterministic, `edge_factors[edge id]`,
//!   `-DTESSGEN_METRIC_BUFFER`) on the closed shared meshes: the exact weld
//!   of the captured triangle soup is a closed 2-manifold, for every quad
//!   scheme, both languages, partitioning integer / fractional_odd (and
//!   fractional_even for pccm).
//! * The computed metrics (screen-space length, distance to the eye) weld
//!   closed too.
//! * Negative control: one random factor per *patch* (not per edge) opens
//!   the weld.
//!
//! Rows print as `| scheme | backend | mesh | partitioning | metric |
//! triangles | open edges |` (run with `--nocapture`) for docs/watertight.md.

mod common;

use glam::Vec3;
use tessgen_runtime::adaptive::{self, Adaptive, Metric, Partitioning};
use tessgen_runtime::vulkan::{Language, Options, VkMesh, Vulkan};
use tessgen_runtime::{cpu, weld, Topology};

const SEED: u64 = 0x7e55_6e11;

fn device() -> Vulkan {
    Vulkan::new().unwrap_or_else(|e| panic!("{e}"))
}

fn topo_positions(name: &str) -> (Topology, Vec<Vec3>) {
    let mesh = common::mesh(name);
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let positions = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    (topo, positions)
}

/// Tessellate adaptively and weld the captured triangles exactly:
/// `(triangles, open edges, closed)`, closed = no open and no overused
/// edge. Degenerate triangles (two corners on one position: near-coincident
/// fractional vertices at factors close to 1) are allowed and skipped.
fn run(
    vk: &Vulkan,
    scheme: &str,
    name: &str,
    language: Language,
    adaptive: Adaptive,
) -> (usize, usize, bool) {
    let (topo, positions) = topo_positions(name);
    let options = Options {
        adaptive: Some(adaptive),
        ..Options::new(language)
    };
    let m = VkMesh::new(vk, &topo, &positions, scheme, &options)
        .unwrap_or_else(|e| panic!("{scheme} {name} {language:?}: {e}"));
    let tris = m
        .evaluate_adaptive()
        .unwrap_or_else(|e| panic!("{scheme} {name} {language:?}: {e}"));
    assert!(
        tris.iter().flatten().all(|p| p.is_finite()),
        "{scheme} {name}: non-finite captured position"
    );
    let soup: Vec<Vec3> = tris.iter().flatten().copied().collect();
    let r = weld::weld_triangles(&soup, 3, &[[0, 1, 2]]);
    if r.degenerate_triangles > 0 {
        println!(
            "  ({scheme} {name} {language:?}: {} degenerate triangles skipped)",
            r.degenerate_triangles
        );
    }
    (
        tris.len(),
        r.open_edges,
        r.open_edges == 0 && r.overused_edges == 0,
    )
}

fn random(name: &str, partitioning: Partitioning) -> Adaptive {
    let (topo, _) = topo_positions(name);
    let (_, edges) = adaptive::edge_ids(&topo);
    Adaptive {
        metric: Metric::Buffer(adaptive::random_factors(edges, SEED, 1.0, 12.0)),
        partitioning,
        min: 1.0,
        max: 64.0,
    }
}

fn lang(l: Language) -> &'static str {
    match l {
        Language::Glsl => "glsl",
        Language::Hlsl => "hlsl",
    }
}

#[test]
fn random_edge_factors_weld_closed() {
    let vk = device();
    let cases: &[(&str, &[&str])] = &[
        ("regular", &["catmark_torus"]),
        ("pccm", &["catmark_cube", "catmark_toroidal_tet"]),
        ("acc", &["catmark_toroidal_tet"]),
        ("gregory", &["catmark_cube"]),
        ("gregory_osd", &["catmark_toroidal_tet"]),
    ];
    let mut bad = Vec::new();
    for language in [Language::Glsl, Language::Hlsl] {
        for (scheme, meshes) in cases {
            for name in *meshes {
                let mut parts = vec![Partitioning::Integer, Partitioning::FractionalOdd];
                if *scheme == "pccm" {
                    parts.push(Partitioning::FractionalEven);
                }
                let mut counts = Vec::new();
                for p in parts {
                    let (tris, open, closed) = run(&vk, scheme, name, language, random(name, p));
                    println!(
                        "| {scheme} | {} | {name} | {p:?} | random [1, 12] | {tris} | {open} |",
                        lang(language)
                    );
                    if open != 0 || !closed {
                        bad.push(format!("{scheme} {name} {language:?} {p:?}: {open} open"));
                    }
                    counts.push(tris);
                }
                // Fractional partitioning must actually change the pattern.
                assert_ne!(counts[0], counts[1], "{scheme} {name}: same triangle count");
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

#[test]
fn computed_metrics_weld_closed() {
    let vk = device();
    let view_proj = tessgen_runtime::render::Camera {
        eye: Vec3::new(2.5, 1.5, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y: 45.0,
    }
    .view_proj(1.0);
    let metrics = [
        (
            "screen 800x800, 12 px",
            Metric::Screen {
                view_proj,
                viewport: [800.0, 800.0],
                pixels_per_segment: 12.0,
            },
        ),
        (
            "distance, k = 6",
            Metric::Distance {
                eye: Vec3::new(2.5, 1.5, 3.0),
                scale: 6.0,
            },
        ),
    ];
    let mut bad = Vec::new();
    for language in [Language::Glsl, Language::Hlsl] {
        for (label, metric) in &metrics {
            for p in [Partitioning::Integer, Partitioning::FractionalOdd] {
                let a = Adaptive {
                    metric: metric.clone(),
                    partitioning: p,
                    min: 1.0,
                    max: 32.0,
                };
                let name = "catmark_toroidal_tet";
                let (tris, open, closed) = run(&vk, "pccm", name, language, a);
                println!(
                    "| pccm | {} | {name} | {p:?} | {label} | {tris} | {open} |",
                    lang(language)
                );
                if open != 0 || !closed {
                    bad.push(format!("{label} {language:?} {p:?}: {open} open"));
                }
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// Negative control: one random factor per patch for all its edges (what a
/// per-patch LOD would do). The two patches of an edge then tessellate it
/// differently: the weld opens. Proves the check above can fail.
#[test]
fn per_patch_factors_open_the_weld() {
    let vk = device();
    let name = "catmark_toroidal_tet";
    let (topo, _) = topo_positions(name);
    let faces = topo.corners.len() as u32;
    let per_face = adaptive::random_factors(faces, SEED, 1.0, 12.0);
    let factors: Vec<f32> = per_face.iter().flat_map(|&f| [f; 4]).collect();
    for language in [Language::Glsl, Language::Hlsl] {
        for p in [Partitioning::Integer, Partitioning::FractionalOdd] {
            let a = Adaptive {
                metric: Metric::PerFaceEdge(factors.clone()),
                partitioning: p,
                min: 1.0,
                max: 64.0,
            };
            let (tris, open, _) = run(&vk, "pccm", name, language, a);
            println!(
                "| pccm | {} | {name} | {p:?} | per-patch random [1, 12] (negative control) | {tris} | {open} |",
                lang(language)
            );
            assert!(
                open > 0,
                "{language:?} {p:?}: per-patch factors stayed closed"
            );
        }
    }
}
