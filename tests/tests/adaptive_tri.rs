//! Adaptive tessellation of the triangle schemes (pn, stpn, phong) on the
//! instanced path: the CPU (`adaptive::evaluate_cpu_adaptive`, generated
//! Rust) and wgpu (`GpuMesh::evaluate_adaptive`, generated WGSL on
//! llvmpipe in CI) run the same Plan functions — power-of-two edge levels
//! from `patch_edge_level` (three edges, face_edges at 3f + k), per-patch
//! buckets, and the triangle grid's snap in `eval_adaptive` (a boundary
//! sample `t` of edge k goes to `⌊t / (L / L_k)⌋` on the edge's own level,
//! through the shared edge evaluator).
//!
//! Checked: random per-edge factors on the split cube, torus (stpn also
//! with crease tags) and toroidal tet weld closed on both backends with the
//! input's Euler characteristic, wgpu positions equal the CPU's bit for
//! bit, the distance and screen metrics weld closed too, per-face factors
//! (the negative control) open the weld, and a mesh of the wrong domain is
//! a typed error.

mod common;

use glam::Vec3;
use std::sync::OnceLock;
use tessgen_runtime::adaptive::{
    self, Adaptive, AdaptiveError, AdaptiveTessellation, Metric, Partitioning,
};
use tessgen_runtime::gpu::{Gpu, GpuMesh};
use tessgen_runtime::grid::tri_grid_coords;
use tessgen_runtime::tags::TagFile;
use tessgen_runtime::trimesh::TriMesh;
use tessgen_runtime::{cpu, weld, Topology};

const SEED: u64 = 0x7e55_6e11;
const MAX_LEVEL: u32 = 32;

fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| Gpu::new().unwrap_or_else(|e| panic!("{e}")))
}

struct Case {
    diag: f32,
    tri: TriMesh,
    patches: cpu::Patches,
}

/// The split (`--split-quads`) triangle mesh of a shared quad mesh, with
/// the torus's crease tags for stpn when asked.
fn setup(scheme: &str, name: &str, tags: bool) -> Case {
    let mesh = common::mesh(name);
    let tags = tags.then(|| {
        let p = common::data(&format!("meshes/{name}_crease.tags"));
        let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        TagFile::parse(&text, mesh.num_vertices(), mesh.num_faces(), |f| {
            mesh.face(f)
        })
        .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    });
    let tri = cpu::tri_mesh(&mesh, true, tags.as_ref()).expect("split");
    let patches = cpu::construct_tri(&tri, cpu::scheme(scheme).expect("scheme")).expect("patches");
    Case {
        diag: common::bbox_diagonal(&mesh),
        tri,
        patches,
    }
}

fn random(c: &Case) -> Adaptive {
    let (_, edges) = c.tri.edge_ids();
    Adaptive {
        metric: Metric::Buffer(adaptive::random_factors(edges, SEED, 1.0, 24.0)),
        partitioning: Partitioning::Integer,
        min: 1.0,
        max: MAX_LEVEL as f32,
    }
}

fn run_cpu(c: &Case, a: &Adaptive) -> AdaptiveTessellation {
    adaptive::evaluate_cpu_adaptive(&c.patches, &c.tri, a, MAX_LEVEL).expect("cpu adaptive")
}

fn run_gpu(scheme: &str, c: &Case, a: &Adaptive) -> AdaptiveTessellation {
    let m = GpuMesh::new_tri(gpu(), &c.tri, scheme).expect("gpu mesh");
    m.evaluate_adaptive(&c.tri, a, MAX_LEVEL)
        .expect("evaluate_adaptive")
}

fn weld_soup(t: &AdaptiveTessellation) -> weld::WeldReport {
    let soup: Vec<Vec3> = t.triangles().into_iter().flatten().collect();
    weld::weld_triangles(&soup, 3, &[[0, 1, 2]])
}

/// Parity with the CPU after checking that the levels agree: positions
/// whose bits differ (those on a patch boundary among them), normals whose
/// bits differ, and the largest position difference over the diagonal.
fn parity(g: &AdaptiveTessellation, c: &AdaptiveTessellation, diag: f32) -> [f32; 4] {
    assert_eq!(g.sides, 3);
    assert_eq!(g.edge_levels, c.edge_levels, "edge levels differ");
    assert_eq!(g.levels, c.levels, "buckets differ");
    assert_eq!(g.offsets, c.offsets);
    let bits = |v: &Vec3| v.to_array().map(f32::to_bits);
    let (mut pos, mut boundary, mut nrm, mut err) = (0, 0, 0, 0f32);
    for (f, &l) in g.levels.iter().enumerate() {
        for (s, abc) in tri_grid_coords(l).iter().enumerate() {
            let at = g.offsets[f] + s;
            if bits(&g.positions[at]) != bits(&c.positions[at]) {
                pos += 1;
                if abc.contains(&0) {
                    boundary += 1;
                }
            }
            if bits(&g.normals[at]) != bits(&c.normals[at]) {
                nrm += 1;
            }
            err = err.max((g.positions[at] - c.positions[at]).length() / diag);
        }
    }
    [pos as f32, boundary as f32, nrm as f32, err]
}

fn buckets(t: &AdaptiveTessellation) -> String {
    t.buckets()
        .iter()
        .map(|(l, f)| format!("{l}: {}", f.len()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A closed weld with the input surface's Euler characteristic.
fn closed(r: &weld::WeldReport, tri: &TriMesh) -> bool {
    r.open_edges == 0 && r.overused_edges == 0 && r.euler == tri.euler_characteristic()
}

#[test]
fn random_edge_factors_weld_closed_on_cpu_and_wgpu_and_agree() {
    let mut bad = Vec::new();
    let mut cases: Vec<(&str, &str, bool)> = Vec::new();
    for scheme in ["pn", "stpn", "phong"] {
        for name in ["catmark_cube", "catmark_torus", "catmark_toroidal_tet"] {
            cases.push((scheme, name, false));
        }
    }
    cases.push(("stpn", "catmark_torus", true));
    for (scheme, name, tags) in cases {
        let c = setup(scheme, name, tags);
        let a = random(&c);
        let cpu = run_cpu(&c, &a);
        let g = run_gpu(scheme, &c, &a);
        let [pos, boundary, nrm, err] = parity(&g, &cpu, c.diag);
        let (rc, rg) = (weld_soup(&cpu), weld_soup(&g));
        let mesh = if tags {
            format!("{name} (split, crease tags)")
        } else {
            format!("{name} (split)")
        };
        println!(
            "| {scheme} | {mesh} | random [1, 24] | {} | {} | {} | {} / {} | {pos} / {nrm} ({boundary} on edges), {err:.1e} |",
            buckets(&g),
            rg.triangles,
            rg.degenerate_triangles,
            rc.open_edges,
            rg.open_edges,
        );
        let mut distinct = cpu.edge_levels.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert!(distinct.len() > 2, "{scheme} {name}: levels {distinct:?}");
        assert_eq!(cpu.edge_levels.len(), 3 * c.tri.triangles.len());
        if !closed(&rc, &c.tri) || !closed(&rg, &c.tri) || pos != 0.0 || err != 0.0 {
            bad.push(format!(
                "{scheme} {mesh}: cpu {rc:?}, wgpu {rg:?}, {pos} positions != cpu ({boundary} on edges), {err:e}"
            ));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// The computed metrics (edge length over eye distance, projected length)
/// from the patch corners: closed on both backends, and equal.
#[test]
fn distance_and_screen_metrics_weld_closed() {
    let c = setup("pn", "catmark_toroidal_tet", false);
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
            ..random(&c)
        };
        let cpu = run_cpu(&c, &a);
        let g = run_gpu("pn", &c, &a);
        let [pos, _, nrm, _] = parity(&g, &cpu, c.diag);
        let (rc, rg) = (weld_soup(&cpu), weld_soup(&g));
        println!(
            "| pn | catmark_toroidal_tet (split) | {what} | {} | {} | {} | {} / {} | {pos} / {nrm} |",
            buckets(&g),
            rg.triangles,
            rg.degenerate_triangles,
            rc.open_edges,
            rg.open_edges
        );
        assert!(g.levels.iter().any(|&l| l > 1), "{what}: all level 1");
        assert!(closed(&rc, &c.tri), "{what}: cpu {rc:?}");
        assert!(closed(&rg, &c.tri), "{what}: wgpu {rg:?}");
        assert_eq!(pos, 0.0, "{what}: wgpu positions != cpu");
    }
}

/// Negative control: one random factor per *triangle*, used for its three
/// edges (`Metric::PerFaceEdge`: the two sides of an edge see different
/// levels, as a per-patch LOD would give them) — the snapped patches no
/// longer agree on the edge's points, on either backend.
#[test]
fn per_face_levels_open_the_weld() {
    let c = setup("pn", "catmark_toroidal_tet", false);
    let faces = c.tri.triangles.len();
    let factors: Vec<f32> = adaptive::random_factors(faces as u32, SEED, 1.0, 24.0)
        .into_iter()
        .flat_map(|f| [f; 3])
        .collect();
    let a = Adaptive {
        metric: Metric::PerFaceEdge(factors),
        ..random(&c)
    };
    let (rc, rg) = (
        weld_soup(&run_cpu(&c, &a)),
        weld_soup(&run_gpu("pn", &c, &a)),
    );
    println!(
        "| pn | catmark_toroidal_tet (split) | per-face levels (negative control) | {} | {} / {} open |",
        rg.triangles, rc.open_edges, rg.open_edges
    );
    assert!(rc.open_edges > 0, "cpu: per-face levels stayed closed");
    assert_eq!(rc, rg, "the negative control differs between cpu and wgpu");
}

/// Negative control for the snap itself: the same buckets, but every
/// patch a plain triangle grid at its bucket level (`eval` at `(iu, iv)/L`,
/// no snapping onto the edges' own levels) — neighbours in different
/// buckets put different points on their shared edge: T-junctions, open.
#[test]
fn buckets_without_snapping_open_the_weld() {
    let c = setup("pn", "catmark_toroidal_tet", false);
    let t = run_cpu(&c, &random(&c));
    let k = c.patches.scheme;
    let mut plain = t.clone();
    for (f, &l) in t.levels.iter().enumerate() {
        let cp = &c.patches.control_points
            [c.patches.cp_offsets[f] as usize..c.patches.cp_offsets[f + 1] as usize];
        for s in 0..(k.grid_len)(l) {
            let (iu, iv) = ((k.grid_iu)(s, l), (k.grid_iv)(s, l));
            plain.positions[t.offsets[f] + s as usize] =
                (k.eval)(cp, c.patches.face_class[f], 0, iu, iv, l).position;
        }
    }
    let r = weld_soup(&plain);
    println!(
        "| pn | catmark_toroidal_tet (split) | buckets without snapping (negative control) | {} | {} open |",
        r.triangles, r.open_edges
    );
    assert!(r.open_edges > 0, "unsnapped buckets stayed closed");
}

/// The mesh given for the edges must match the scheme's domain and the
/// patches: typed errors, no panic.
#[test]
fn wrong_domain_is_a_typed_error() {
    let c = setup("phong", "catmark_cube", false);
    let mesh = common::mesh("catmark_cube");
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let e = adaptive::evaluate_cpu_adaptive(&c.patches, &topo, &random(&c), MAX_LEVEL);
    assert!(
        matches!(
            e,
            Err(AdaptiveError::Domain {
                want: "triangles",
                got: "quads",
                ..
            })
        ),
        "{:?}",
        e.err()
    );
    // Another triangle mesh (the torus's split) for the cube's patches.
    let other = setup("phong", "catmark_torus", false);
    let e = adaptive::evaluate_cpu_adaptive(&c.patches, &other.tri, &random(&other), MAX_LEVEL);
    assert!(
        matches!(
            e,
            Err(AdaptiveError::MeshMismatch {
                patches: 12,
                faces: 64
            })
        ),
        "{:?}",
        e.err()
    );
}
