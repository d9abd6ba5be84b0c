//! Adaptive tessellation on the WGSL instanced path (wgpu, llvmpipe in CI):
//! the classify pass computes every patch's power-of-two edge levels on the
//! GPU, patches are evaluated bucketed by (class, level), boundary samples
//! snapped onto the edges' own levels (`eval_adaptive`). Checked: random
//! per-edge factors weld closed for every quad scheme, the wgpu output
//! equals the CPU adaptive output (the same generated functions in Rust)
//! in the same buckets at the same snapped points, bit for bit (Gregory:
//! on the patch boundary; its rational interior may differ by an ulp), the
//! distance and screen metrics weld closed too, per-face
//! levels (the negative control) open the weld, and bad input is a typed
//! error.

mod common;

use glam::Vec3;
use std::sync::OnceLock;
use tessgen_runtime::adaptive::{
    self, Adaptive, AdaptiveError, AdaptiveTessellation, Metric, Partitioning,
};
use tessgen_runtime::gpu::{Gpu, GpuError, GpuMesh};
use tessgen_runtime::{cpu, weld, Topology};

const SEED: u64 = 0x7e55_6e11;
const MAX_LEVEL: u32 = 32;

fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| Gpu::new().unwrap_or_else(|e| panic!("{e}")))
}

struct Case {
    diag: f32,
    topo: Topology,
    positions: Vec<Vec3>,
    patches: cpu::Patches,
}

fn setup(scheme: &str, name: &str) -> Option<Case> {
    let mesh = common::mesh(name);
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let positions: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    // `regular` refuses extraordinary faces: only the torus applies.
    let patches = cpu::construct(&topo, &positions, cpu::scheme(scheme).ok()?).ok()?;
    Some(Case {
        diag: common::bbox_diagonal(&mesh),
        topo,
        positions,
        patches,
    })
}

fn buffer_metric(c: &Case, lo: f32, hi: f32) -> Adaptive {
    let (_, edges) = adaptive::edge_ids(&c.topo);
    Adaptive {
        metric: Metric::Buffer(adaptive::random_factors(edges, SEED, lo, hi)),
        partitioning: Partitioning::Integer,
        min: 1.0,
        max: MAX_LEVEL as f32,
    }
}

fn run_gpu(scheme: &str, c: &Case, a: &Adaptive) -> AdaptiveTessellation {
    let m = GpuMesh::new(gpu(), &c.topo, &c.positions, scheme).expect("gpu mesh");
    m.evaluate_adaptive(&c.topo, a, MAX_LEVEL)
        .expect("evaluate_adaptive")
}

fn weld_soup(t: &AdaptiveTessellation) -> weld::WeldReport {
    let soup: Vec<Vec3> = t.triangles().into_iter().flatten().collect();
    weld::weld_triangles(&soup, 3, &[[0, 1, 2]])
}

/// Parity with the CPU after checking that the levels agree: samples whose
/// bits differ (positions or normals), those of them on a patch boundary
/// (which must be none: the weld depends on them), and the largest position
/// difference over the bounding-box diagonal.
fn parity(g: &AdaptiveTessellation, c: &AdaptiveTessellation, diag: f32) -> (usize, usize, f32) {
    assert_eq!(g.edge_levels, c.edge_levels, "edge levels differ");
    assert_eq!(g.levels, c.levels, "buckets differ");
    assert_eq!(g.offsets, c.offsets);
    let bits = |v: &Vec3| v.to_array().map(f32::to_bits);
    let (mut diff, mut boundary, mut err) = (0, 0, 0f32);
    for (f, &l) in g.levels.iter().enumerate() {
        for s in 0..(l + 1) * (l + 1) {
            let (iu, iv) = (s % (l + 1), s / (l + 1));
            let at = g.offsets[f] + s as usize;
            let same = bits(&g.positions[at]) == bits(&c.positions[at])
                && bits(&g.normals[at]) == bits(&c.normals[at]);
            if !same {
                diff += 1;
                if iu == 0 || iv == 0 || iu == l || iv == l {
                    boundary += 1;
                }
            }
            err = err.max((g.positions[at] - c.positions[at]).length() / diag);
        }
    }
    (diff, boundary, err)
}

fn buckets(t: &AdaptiveTessellation) -> String {
    t.buckets()
        .iter()
        .map(|(l, f)| format!("{l}: {}", f.len()))
        .collect::<Vec<_>>()
        .join(", ")
}

#[test]
fn random_edge_factors_weld_closed_on_wgpu_and_equal_the_cpu() {
    let mut bad = Vec::new();
    for scheme in ["regular", "pccm", "acc", "gregory", "gregory_osd"] {
        for name in ["catmark_cube", "catmark_torus", "catmark_toroidal_tet"] {
            let Some(c) = setup(scheme, name) else {
                continue;
            };
            let a = buffer_metric(&c, 1.0, 24.0);
            let g = run_gpu(scheme, &c, &a);
            let cpu = adaptive::evaluate_cpu_adaptive(&c.patches, &c.topo, &a, MAX_LEVEL)
                .expect("cpu adaptive");
            let (diff, boundary, err) = parity(&g, &cpu, c.diag);
            let r = weld_soup(&g);
            println!(
                "| {scheme} | wgpu | {name} | {} | {} | {} | {} | {diff} ({boundary} on edges), {err:.1e} |",
                buckets(&g),
                r.triangles,
                r.degenerate_triangles,
                r.open_edges
            );
            let mut distinct = g.edge_levels.clone();
            distinct.sort_unstable();
            distinct.dedup();
            assert!(distinct.len() > 2, "{scheme} {name}: levels {distinct:?}");
            // pccm, acc, regular: equal bit for bit. Gregory's rational
            // interior blend may round differently on llvmpipe (as in the
            // uniform wgpu path); its boundary samples may not.
            let exact = !scheme.starts_with("gregory");
            if r.open_edges != 0
                || r.overused_edges != 0
                || boundary != 0
                || (exact && diff != 0)
                || err > 1e-6
            {
                bad.push(format!(
                    "{scheme} {name}: {r:?}, {diff} samples != cpu ({boundary} on edges), {err:e}"
                ));
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// The computed metrics (edge length over eye distance, projected length)
/// run on the GPU from the patch corners; closed, and equal to the CPU.
#[test]
fn distance_and_screen_metrics_weld_closed_on_wgpu() {
    let c = setup("pccm", "catmark_toroidal_tet").expect("pccm");
    let eye = Vec3::new(2.0, 1.5, 4.0);
    let view_proj = tessgen_runtime::render::Camera {
        eye,
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y: 45.0,
    }
    .view_proj(1.0);
    for (what, metric) in [
        ("distance, k = 24", Metric::Distance { eye, scale: 24.0 }),
        (
            "screen, 800x800, 12 px/segment",
            Metric::Screen {
                view_proj,
                viewport: [800.0, 800.0],
                pixels_per_segment: 12.0,
            },
        ),
    ] {
        let a = Adaptive {
            metric,
            partitioning: Partitioning::Integer,
            min: 1.0,
            max: MAX_LEVEL as f32,
        };
        let g = run_gpu("pccm", &c, &a);
        let cpu = adaptive::evaluate_cpu_adaptive(&c.patches, &c.topo, &a, MAX_LEVEL)
            .expect("cpu adaptive");
        let (diff, _, _) = parity(&g, &cpu, c.diag);
        let r = weld_soup(&g);
        println!(
            "| pccm | wgpu | catmark_toroidal_tet | {what} | {} | {} | {} | {} | {diff} |",
            buckets(&g),
            r.triangles,
            r.degenerate_triangles,
            r.open_edges
        );
        assert!(g.levels.iter().any(|&l| l > 1), "{what}: all level 1");
        assert_eq!((r.open_edges, r.overused_edges), (0, 0), "{what}: {r:?}");
        assert_eq!(diff, 0, "{what}: wgpu != cpu");
    }
}

/// Negative control: one random factor per *face edge* (the two sides of
/// an edge see different factors, as a per-patch LOD would give them): the
/// snapped patches no longer agree on the edge's points.
#[test]
fn per_face_levels_open_the_weld_on_wgpu() {
    let c = setup("pccm", "catmark_toroidal_tet").expect("pccm");
    let faces = c.patches.face_class.len();
    let factors: Vec<f32> = adaptive::random_factors(faces as u32, SEED, 1.0, 24.0)
        .into_iter()
        .flat_map(|f| [f; 4])
        .collect();
    let a = Adaptive {
        metric: Metric::PerFaceEdge(factors),
        ..buffer_metric(&c, 1.0, 24.0)
    };
    let r = weld_soup(&run_gpu("pccm", &c, &a));
    println!(
        "| pccm | wgpu | catmark_toroidal_tet | per-face levels (negative control) | {} | {} open |",
        r.triangles, r.open_edges
    );
    assert!(r.open_edges > 0, "per-face levels stayed closed");
}

#[test]
fn bad_adaptive_input_is_a_typed_error() {
    let c = setup("pccm", "catmark_cube").expect("pccm");
    let m = GpuMesh::new(gpu(), &c.topo, &c.positions, "pccm").expect("gpu mesh");
    let good = buffer_metric(&c, 1.0, 24.0);
    let Metric::Buffer(factors) = &good.metric else {
        unreachable!()
    };
    let short = Adaptive {
        metric: Metric::Buffer(factors[1..].to_vec()),
        ..good.clone()
    };
    let mut nan = factors.clone();
    nan[5] = f32::NAN;
    let nan = Adaptive {
        metric: Metric::Buffer(nan),
        ..good.clone()
    };
    let cases: [(&Adaptive, u32, &str); 3] = [
        (&short, MAX_LEVEL, "EdgeFactorCount"),
        (&nan, MAX_LEVEL, "BadFactor"),
        (&good, 48, "MaxLevel"),
    ];
    for (a, max, want) in cases {
        let g = m.evaluate_adaptive(&c.topo, a, max);
        let ok = matches!(
            (&g, want),
            (
                Err(GpuError::Adaptive(AdaptiveError::EdgeFactorCount {
                    expected: 12,
                    got: 11,
                })),
                "EdgeFactorCount",
            ) | (
                Err(GpuError::Adaptive(AdaptiveError::BadFactor { edge: 5, .. })),
                "BadFactor",
            ) | (
                Err(GpuError::Adaptive(AdaptiveError::MaxLevel { got: 48 })),
                "MaxLevel",
            )
        );
        assert!(ok, "wgpu, {want}: {:?}", g.err());
        let e = adaptive::evaluate_cpu_adaptive(&c.patches, &c.topo, a, max)
            .expect_err("cpu accepted bad input");
        assert!(format!("{e:?}").starts_with(want), "cpu, {want}: {e:?}");
    }
    // A triangle scheme given the quad topology for its edges: a typed
    // error naming both domains (tests/tests/adaptive_tri.rs runs them).
    let mesh = common::mesh("catmark_cube");
    let tri = cpu::tri_mesh(&mesh, true, None).expect("split");
    let t = GpuMesh::new_tri(gpu(), &tri, "pn").expect("pn mesh");
    let e = t.evaluate_adaptive(&c.topo, &good, MAX_LEVEL);
    assert!(
        matches!(
            e,
            Err(GpuError::Adaptive(AdaptiveError::Domain {
                want: "triangles",
                got: "quads",
                ..
            }))
        ),
        "{:?}",
        e.err()
    );
}
