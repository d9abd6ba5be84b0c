//! Adaptive tessellation through the emitted GLSL and HLSL tessellation
//! shaders on Vulkan (lavapipe in CI): per-edge factors, integer and
//! fractional partitioning, captured as triangles by the harness's
//! geometry shader, welded bit for bit and compared with the CPU.
//!
//! * Random per-edge factors (seeded, deterministic, `edge_factors[edge id]`,
//!   `-DTESSGEN_METRIC_BUFFER`) on the closed shared meshes: the exact weld
//!   of the captured triangle soup is a closed 2-manifold, for every quad
//!   scheme and (on the triangle splits) every triangle scheme, both
//!   languages, partitioning integer / fractional_odd (and fractional_even
//!   for pccm).
//! * The computed metrics (screen-space length, distance to the eye) weld
//!   closed too.
//! * Parity: every captured vertex carries its patch and fixed-point domain
//!   point; the generated Rust evaluates the same point at level 2^16
//!   (`TriangleCapture::max_deviation`): within 1e-5 × bbox diagonal
//!   (GLSL bit for bit).
//! * Negative control: one random factor per *patch* (not per edge) opens
//!   the weld.
//!
//! Rows print as `| scheme | backend | mesh | partitioning | metric |
//! triangles | open edges | parity / diag |` (run with `--nocapture`) for
//! docs/watertight.md.

mod common;

use glam::Vec3;
use tessgen_runtime::adaptive::{self, Adaptive, Metric, Partitioning};
use tessgen_runtime::tags::TagFile;
use tessgen_runtime::trimesh::TriMesh;
use tessgen_runtime::vulkan::{Language, Options, VkMesh, Vulkan};
use tessgen_runtime::{cpu, Topology};

const SEED: u64 = 0x7e55_6e11;
/// Largest accepted |hardware − CPU| / bbox diagonal.
const PARITY: f64 = 1e-5;

fn device() -> Vulkan {
    Vulkan::new().unwrap_or_else(|e| panic!("{e}"))
}

/// A test mesh for a scheme: the quad topology, or (triangle schemes) the
/// split along each quad's v0–v2 diagonal, with `stpn`'s crease tags when
/// `tags`.
enum Built {
    Quad(Box<Topology>, Vec<Vec3>),
    Tri(TriMesh),
}

struct Case {
    built: Built,
    patches: cpu::Patches,
    diag: f32,
    /// Global edges (the length of an explicit factor buffer).
    edges: u32,
    /// Sides per face (the length of a per-face-edge buffer is sides · faces).
    sides: usize,
    faces: usize,
}

fn case(scheme: &str, name: &str, tags: bool) -> Case {
    let mesh = common::mesh(name);
    let diag = common::bbox_diagonal(&mesh);
    let kernels = cpu::scheme(scheme).expect("scheme");
    if kernels.sides == 4 {
        let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
        let positions: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|p| Vec3::from_array(*p))
            .collect();
        let patches = cpu::construct(&topo, &positions, kernels).expect("construct");
        let edges = adaptive::edge_ids(&topo).1;
        let faces = topo.corners.len();
        return Case {
            built: Built::Quad(Box::new(topo), positions),
            patches,
            diag,
            edges,
            sides: 4,
            faces,
        };
    }
    let file = tags.then(|| {
        let text = std::fs::read_to_string(common::data("meshes/catmark_torus_crease.tags"))
            .expect("tags file");
        TagFile::parse(&text, mesh.num_vertices(), mesh.num_faces(), |f| {
            mesh.face(f)
        })
        .expect("tags")
    });
    let tri = cpu::tri_mesh(&mesh, true, file.as_ref()).expect("triangle split");
    let patches = cpu::construct_tri(&tri, kernels).expect("construct_tri");
    let (edges, faces) = (tri.edge_ids().1, tri.triangles.len());
    Case {
        built: Built::Tri(tri),
        patches,
        diag,
        edges,
        sides: 3,
        faces,
    }
}

/// One adaptive run's figures.
struct Run {
    triangles: usize,
    open: usize,
    /// No open and no overused edge.
    closed: bool,
    /// max |captured − CPU| / bbox diagonal.
    parity: f64,
}

/// Tessellate adaptively, weld the captured triangles exactly and compare
/// every captured vertex with the CPU. Degenerate triangles (two corners
/// on one position: near-coincident fractional vertices at factors close
/// to 1) are allowed and skipped.
fn run(vk: &Vulkan, scheme: &str, c: &Case, language: Language, adaptive: Adaptive) -> Run {
    let options = Options {
        adaptive: Some(adaptive),
        ..Options::new(language)
    };
    let m = match &c.built {
        Built::Quad(topo, positions) => VkMesh::new(vk, topo, positions, scheme, &options),
        Built::Tri(tri) => VkMesh::new_tri(vk, tri, scheme, &options),
    }
    .unwrap_or_else(|e| panic!("{scheme} {language:?}: {e}"));
    let cap = m
        .evaluate_adaptive()
        .unwrap_or_else(|e| panic!("{scheme} {language:?}: {e}"));
    assert!(
        cap.patches
            .iter()
            .all(|p| p.positions.iter().all(|x| x.is_finite())),
        "{scheme} {language:?}: non-finite captured position"
    );
    let r = cap.weld();
    if r.degenerate_triangles > 0 {
        println!(
            "  ({scheme} {language:?}: {} degenerate triangles skipped)",
            r.degenerate_triangles
        );
    }
    let dev = cap
        .max_deviation(&c.patches)
        .unwrap_or_else(|face| panic!("{scheme}: face {face} has no CPU patch"));
    Run {
        triangles: cap.triangle_count(),
        open: r.open_edges,
        closed: r.open_edges == 0 && r.overused_edges == 0,
        parity: if dev.is_nan() {
            f64::INFINITY
        } else {
            dev as f64 / c.diag as f64
        },
    }
}

fn random(c: &Case, partitioning: Partitioning) -> Adaptive {
    Adaptive {
        metric: Metric::Buffer(adaptive::random_factors(c.edges, SEED, 1.0, 12.0)),
        partitioning,
        min: 1.0,
        max: 64.0,
    }
}

/// `mesh` or `mesh (split)` / `mesh (split, crease tags)` for the tables.
fn label(c: &Case, name: &str, tags: bool) -> String {
    match (c.sides, tags) {
        (4, _) => name.to_string(),
        (_, false) => format!("{name} (split)"),
        (_, true) => format!("{name} (split, crease tags)"),
    }
}

/// Random per-edge factors over `cases`: closed, parity within
/// [`PARITY`], and fractional partitioning changes the pattern.
fn random_cases(cases: &[(&str, &[&str], bool)]) {
    let vk = device();
    let mut bad = Vec::new();
    for (scheme, meshes, tags) in cases {
        for name in *meshes {
            let c = case(scheme, name, *tags);
            for language in [Language::Glsl, Language::Hlsl] {
                let mut parts = vec![Partitioning::Integer, Partitioning::FractionalOdd];
                if *scheme == "pccm" {
                    parts.push(Partitioning::FractionalEven);
                }
                let mut counts = Vec::new();
                for p in parts {
                    let r = run(&vk, scheme, &c, language, random(&c, p));
                    println!(
                        "| {scheme} | {} | {} | {p:?} | random [1, 12] | {} | {} | {:.1e} |",
                        language.name(),
                        label(&c, name, *tags),
                        r.triangles,
                        r.open,
                        r.parity
                    );
                    if r.open != 0 || !r.closed {
                        bad.push(format!(
                            "{scheme} {name} {language:?} {p:?}: {} open",
                            r.open
                        ));
                    }
                    if r.parity > PARITY {
                        bad.push(format!(
                            "{scheme} {name} {language:?} {p:?}: parity {:.2e} × diag",
                            r.parity
                        ));
                    }
                    counts.push(r.triangles);
                }
                // Fractional partitioning must actually change the pattern.
                assert_ne!(counts[0], counts[1], "{scheme} {name}: same triangle count");
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

#[test]
fn random_edge_factors_weld_closed() {
    random_cases(&[
        ("regular", &["catmark_torus"], false),
        ("pccm", &["catmark_cube", "catmark_toroidal_tet"], false),
        ("acc", &["catmark_toroidal_tet"], false),
        ("gregory", &["catmark_cube"], false),
        ("gregory_osd", &["catmark_toroidal_tet"], false),
    ]);
}

/// Triangle schemes on the triangle splits: three outer factors per patch
/// (one per edge, canonical order), the inside factor the largest of them;
/// the evaluation stage hands `eval_domain` the raw barycentric point at
/// level 2^16.
#[test]
fn triangle_schemes_random_edge_factors_weld_closed() {
    let all: &[&str] = &["catmark_cube", "catmark_torus", "catmark_toroidal_tet"];
    random_cases(&[
        ("pn", all, false),
        ("phong", all, false),
        ("stpn", &["catmark_cube", "catmark_toroidal_tet"], false),
        ("stpn", &["catmark_torus"], true),
    ]);
}

#[test]
fn computed_metrics_weld_closed() {
    let vk = device();
    let eye = Vec3::new(2.5, 1.5, 3.0);
    let view_proj = tessgen_runtime::render::Camera {
        eye,
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y: 45.0,
    }
    .view_proj(1.0);
    let metrics = [
        (
            "screen, 800×800, 12 px/segment",
            Metric::Screen {
                view_proj,
                viewport: [800.0, 800.0],
                pixels_per_segment: 12.0,
            },
        ),
        ("distance, k = 6", Metric::Distance { eye, scale: 6.0 }),
    ];
    let name = "catmark_toroidal_tet";
    let mut bad = Vec::new();
    for scheme in ["pccm", "pn"] {
        let c = case(scheme, name, false);
        for language in [Language::Glsl, Language::Hlsl] {
            for (metric_label, metric) in &metrics {
                for p in [Partitioning::Integer, Partitioning::FractionalOdd] {
                    let a = Adaptive {
                        metric: metric.clone(),
                        partitioning: p,
                        min: 1.0,
                        max: 32.0,
                    };
                    let r = run(&vk, scheme, &c, language, a);
                    println!(
                        "| {scheme} | {} | {} | {p:?} | {metric_label} | {} | {} | {:.1e} |",
                        language.name(),
                        label(&c, name, false),
                        r.triangles,
                        r.open,
                        r.parity
                    );
                    if r.open != 0 || !r.closed || r.parity > PARITY {
                        bad.push(format!(
                            "{scheme} {metric_label} {language:?} {p:?}: {} open, parity {:.2e}",
                            r.open, r.parity
                        ));
                    }
                }
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// Negative control: one random factor per patch for all its edges (what a
/// per-patch LOD would do). The two patches of an edge then tessellate it
/// differently: the weld opens. Proves the check above can fail, for a
/// quad and a triangle scheme.
#[test]
fn per_patch_factors_open_the_weld() {
    let vk = device();
    let name = "catmark_toroidal_tet";
    for scheme in ["pccm", "pn"] {
        let c = case(scheme, name, false);
        let per_face = adaptive::random_factors(c.faces as u32, SEED, 1.0, 12.0);
        let factors: Vec<f32> = per_face
            .iter()
            .flat_map(|&f| std::iter::repeat_n(f, c.sides))
            .collect();
        for language in [Language::Glsl, Language::Hlsl] {
            for p in [Partitioning::Integer, Partitioning::FractionalOdd] {
                let a = Adaptive {
                    metric: Metric::PerFaceEdge(factors.clone()),
                    partitioning: p,
                    min: 1.0,
                    max: 64.0,
                };
                let r = run(&vk, scheme, &c, language, a);
                println!(
                    "| {scheme} | {} | {} | {p:?} | per-patch random [1, 12] (negative control) | {} | {} | {:.1e} |",
                    language.name(),
                    label(&c, name, false),
                    r.triangles,
                    r.open,
                    r.parity
                );
                assert!(
                    r.open > 0,
                    "{scheme} {language:?} {p:?}: per-patch factors stayed closed"
                );
            }
        }
    }
}
