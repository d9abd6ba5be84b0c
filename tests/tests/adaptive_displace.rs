//! Adaptive tessellation *and* displacement on the instanced path (CPU:
//! `adaptive::evaluate_cpu_adaptive_displaced`; wgpu: `evaluate_adaptive`
//! on a mesh uploaded with displacement). Both run the Plan function
//! `eval_adaptive_displaced`: the snap of `eval_adaptive`, then the
//! displacement step with ownership at the snapped point, so the owner's
//! normal and texture coordinate on an edge are taken at the edge's own
//! level (a function of the edge alone) and a snapped corner at level 1.
//!
//! Checked, with random per-edge factors: quads (pccm, gregory) on
//! catmark_cube_uv (every edge a texture seam) and catmark_toroidal_tet (a
//! chart per face), triangles (pn, phong) on the same meshes split: 0 open
//! edges on the CPU and on wgpu, wgpu against the CPU, scale 0 equal to the
//! undisplaced adaptive tessellation bit for bit (both backends), and the
//! per-patch ownership negative control opens the weld.

mod common;

use common::{displacement, per_face_charts, seam_meshes as meshes};

use glam::Vec3;
use std::sync::OnceLock;
use tessgen_runtime::adaptive::{self, Adaptive, AdaptiveTessellation, Metric, Partitioning};
use tessgen_runtime::displace::{Displacement, Ownership};
use tessgen_runtime::gpu::{Gpu, GpuMesh};
use tessgen_runtime::trimesh::TriMesh;
use tessgen_runtime::{cpu, weld, Mesh, Topology};

const SEED: u64 = 0x7e55_6e11;
const MAX_LEVEL: u32 = 16;

fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    GPU.get_or_init(|| Gpu::new().unwrap_or_else(|e| panic!("{e}")))
}

/// One mesh prepared for a scheme: its edges' domain (quad topology or the
/// split triangle mesh), positions and CPU patches.
struct Case {
    mesh: Mesh,
    topo: Option<Topology>,
    tri: Option<TriMesh>,
    positions: Vec<Vec3>,
    patches: cpu::Patches,
    diag: f32,
}

impl Case {
    fn new(scheme: &str, mesh: Mesh) -> Case {
        let kernels = cpu::scheme(scheme).expect("scheme");
        let positions: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|p| Vec3::from_array(*p))
            .collect();
        let diag = common::bbox_diagonal(&mesh);
        let (topo, tri, patches) = if kernels.sides == 3 {
            let tri = cpu::tri_mesh(&mesh, true, None).expect("split");
            let patches = cpu::construct_tri(&tri, kernels).expect("patches");
            (None, Some(tri), patches)
        } else {
            let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
            let patches = cpu::construct(&topo, &positions, kernels).expect("patches");
            (Some(topo), None, patches)
        };
        Case {
            mesh,
            topo,
            tri,
            positions,
            patches,
            diag,
        }
    }

    fn edges(&self) -> adaptive::AdaptiveMesh<'_> {
        match (&self.topo, &self.tri) {
            (Some(t), _) => t.into(),
            (_, Some(t)) => t.into(),
            _ => unreachable!("a case has a topology or a triangle mesh"),
        }
    }

    fn random(&self) -> Adaptive {
        let (_, edges) = self.edges().edge_ids();
        Adaptive {
            metric: Metric::Buffer(adaptive::random_factors(edges, SEED, 1.0, 12.0)),
            partitioning: Partitioning::Integer,
            min: 1.0,
            max: MAX_LEVEL as f32,
        }
    }

    fn cpu(&self, a: &Adaptive, d: Option<&Displacement>) -> AdaptiveTessellation {
        match d {
            None => adaptive::evaluate_cpu_adaptive(&self.patches, self.edges(), a, MAX_LEVEL),
            Some(d) => {
                let data = match (&self.topo, &self.tri) {
                    (Some(t), _) => cpu::displacement_data(&self.mesh, t, &self.patches, d),
                    (_, Some(t)) => cpu::displacement_data_tri(&self.mesh, t, &self.patches, d),
                    _ => unreachable!(),
                }
                .expect("displacement data");
                adaptive::evaluate_cpu_adaptive_displaced(
                    &self.patches,
                    self.edges(),
                    a,
                    MAX_LEVEL,
                    &data,
                )
            }
        }
        .expect("cpu adaptive")
    }

    fn wgpu(&self, scheme: &str, a: &Adaptive, d: Option<&Displacement>) -> AdaptiveTessellation {
        self.gpu_mesh(scheme, d)
            .evaluate_adaptive(self.edges(), a, MAX_LEVEL)
            .expect("evaluate_adaptive")
    }

    /// The case uploaded for `scheme`, with displacement `d` if any.
    fn gpu_mesh(&self, scheme: &str, d: Option<&Displacement>) -> GpuMesh<'static> {
        let g = gpu();
        match (&self.topo, &self.tri, d) {
            (Some(t), _, None) => GpuMesh::new(g, t, &self.positions, scheme),
            (Some(t), _, Some(d)) => {
                GpuMesh::new_displaced(g, &self.mesh, t, &self.positions, scheme, d)
            }
            (_, Some(t), None) => GpuMesh::new_tri(g, t, scheme),
            (_, Some(t), Some(d)) => GpuMesh::new_tri_displaced(g, &self.mesh, t, scheme, d),
            _ => unreachable!(),
        }
        .expect("gpu mesh")
    }
}

fn open_edges(t: &AdaptiveTessellation) -> (usize, usize) {
    let soup: Vec<Vec3> = t.triangles().into_iter().flatten().collect();
    let r = weld::weld_triangles(&soup, 3, &[[0, 1, 2]]);
    (r.open_edges + r.overused_edges, r.triangles)
}

/// Samples whose position bits differ, and the largest position difference
/// over the diagonal (after checking that the levels agree).
fn parity(a: &AdaptiveTessellation, b: &AdaptiveTessellation, diag: f32) -> (usize, f32) {
    assert_eq!(a.edge_levels, b.edge_levels, "edge levels differ");
    assert_eq!(a.levels, b.levels, "buckets differ");
    let bits = |v: &Vec3| v.to_array().map(f32::to_bits);
    let mut n = 0;
    let mut err = 0f32;
    for (p, q) in a.positions.iter().zip(&b.positions) {
        if bits(p) != bits(q) {
            n += 1;
        }
        err = err.max((*p - *q).length() / diag);
    }
    (n, err)
}

fn bit_equal(a: &AdaptiveTessellation, b: &AdaptiveTessellation) -> bool {
    let bits = |v: &[Vec3]| -> Vec<[u32; 3]> {
        v.iter().map(|x| x.to_array().map(f32::to_bits)).collect()
    };
    a.levels == b.levels
        && a.offsets == b.offsets
        && bits(&a.positions) == bits(&b.positions)
        && bits(&a.normals) == bits(&b.normals)
}

/// Owned displacement welds closed on both backends, the wgpu samples
/// match the CPU's, the per-patch control opens the weld.
fn check(scheme: &str, exact_parity: bool) {
    let owned = displacement(Ownership::LowestFace, 0.5);
    let per_patch = displacement(Ownership::PerPatch, 0.5);
    for (name, mesh) in meshes() {
        let c = Case::new(scheme, mesh);
        let a = c.random();
        let cpu_t = c.cpu(&a, Some(&owned));
        let gpu_t = c.wgpu(scheme, &a, Some(&owned));
        let plain = c.cpu(&a, None);
        let moved = cpu_t
            .positions
            .iter()
            .zip(&plain.positions)
            .map(|(p, q)| (*p - *q).length())
            .fold(0f32, f32::max);
        let (cpu_open, tris) = open_edges(&cpu_t);
        let (gpu_open, _) = open_edges(&gpu_t);
        let (differ, err) = parity(&gpu_t, &cpu_t, c.diag);
        let (pp_cpu, _) = open_edges(&c.cpu(&a, Some(&per_patch)));
        let (pp_gpu, _) = open_edges(&c.wgpu(scheme, &a, Some(&per_patch)));
        let mut buckets = String::new();
        for (l, fs) in cpu_t.buckets() {
            buckets.push_str(&format!("{l}: {}, ", fs.len()));
        }
        println!(
            "| {scheme} | {name} | {} | {tris} | {cpu_open} / {gpu_open} | {pp_cpu} / {pp_gpu} | \
             {differ} ({err:.1e}) | {moved:.3} |",
            buckets.trim_end_matches(", ")
        );
        assert!(
            moved > 0.01,
            "{scheme} {name}: displacement did not move the surface"
        );
        assert_eq!(cpu_open, 0, "{scheme} {name}: CPU adaptive displaced open");
        assert_eq!(gpu_open, 0, "{scheme} {name}: wgpu adaptive displaced open");
        assert!(
            pp_cpu > 0 && pp_gpu > 0,
            "{scheme} {name}: control stayed closed"
        );
        if exact_parity {
            assert_eq!(differ, 0, "{scheme} {name}: wgpu != CPU ({err:e})");
        } else {
            assert!(err < 1e-6, "{scheme} {name}: wgpu vs CPU {err:e}");
        }
    }
}

#[test]
fn adaptive_displaced_quads_weld_closed_on_cpu_and_wgpu() {
    println!("| scheme | mesh | buckets (level: patches) | triangles | open cpu / wgpu | per-patch open cpu / wgpu | wgpu ≠ cpu (max / diag) | largest displacement |");
    check("pccm", true);
    // Gregory's interior normal rounds differently on llvmpipe (as in the
    // uniform displaced path), and a displaced position contains h·n.
    check("gregory", false);
}

#[test]
fn adaptive_displaced_triangles_weld_closed_on_cpu_and_wgpu() {
    check("pn", true);
    check("phong", true);
}

/// Scale 0 (real texture coordinates and owners) is the undisplaced
/// adaptive tessellation bit for bit, on the CPU and on wgpu — corners
/// included, which the displaced variant hands on at level 1.
#[test]
fn scale_zero_is_undisplaced_adaptive_bit_for_bit() {
    let zero = displacement(Ownership::LowestFace, 0.0);
    for scheme in ["pccm", "gregory", "pn", "phong"] {
        let c = Case::new(scheme, common::mesh("catmark_cube_uv"));
        let a = c.random();
        let plain = c.cpu(&a, None);
        assert!(bit_equal(&plain, &c.cpu(&a, Some(&zero))), "{scheme} cpu");
        let gpu_plain = c.wgpu(scheme, &a, None);
        assert!(
            bit_equal(&gpu_plain, &c.wgpu(scheme, &a, Some(&zero))),
            "{scheme} wgpu"
        );
    }
}

/// Displacement data of another mesh is a typed error, not a panic.
#[test]
fn displacement_data_of_another_mesh_is_an_error() {
    let c = Case::new("pccm", common::mesh("catmark_cube_uv"));
    let other = Case::new(
        "pccm",
        per_face_charts(common::mesh("catmark_toroidal_tet")),
    );
    let d = displacement(Ownership::LowestFace, 0.5);
    let (Some(t), Some(_)) = (&other.topo, &c.topo) else {
        unreachable!()
    };
    let data = cpu::displacement_data(&other.mesh, t, &other.patches, &d).expect("data");
    let err = adaptive::evaluate_cpu_adaptive_displaced(
        &c.patches,
        c.edges(),
        &c.random(),
        MAX_LEVEL,
        &data,
    )
    .unwrap_err();
    assert!(err.to_string().contains("24 faces"), "{err}");
}

/// The CPU adaptive walk runs in parallel over faces (per-face slices of
/// the output): one thread and four give the same bits, undisplaced and
/// displaced.
#[test]
fn cpu_adaptive_output_does_not_depend_on_the_thread_count() {
    let d = displacement(Ownership::LowestFace, 0.5);
    let pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap_or_else(|e| panic!("{e}"))
    };
    for scheme in ["gregory", "pn"] {
        let c = Case::new(
            scheme,
            per_face_charts(common::mesh("catmark_toroidal_tet")),
        );
        let a = c.random();
        for disp in [None, Some(&d)] {
            let one = pool(1).install(|| c.cpu(&a, disp));
            let four = pool(4).install(|| c.cpu(&a, disp));
            assert!(bit_equal(&one, &four), "{scheme} {}", disp.is_some());
        }
    }
}

/// GPU-driven buckets (`evaluate_adaptive_gpu_driven`: counts, prefix sums,
/// lists and indirect dispatch arguments built on the GPU, no readback
/// before the evaluation) give the host-list path's tessellation bit for
/// bit — undisplaced and displaced, quads (two classes on toroidal_tet)
/// and triangles — and weld closed.
#[test]
fn gpu_driven_buckets_match_the_host_lists_bit_for_bit() {
    let d = displacement(Ownership::LowestFace, 0.5);
    for scheme in ["pccm", "gregory", "pn"] {
        for (name, mesh) in meshes() {
            let c = Case::new(scheme, mesh);
            let a = c.random();
            for disp in [None, Some(&d)] {
                let m = c.gpu_mesh(scheme, disp);
                let host = m
                    .evaluate_adaptive_host_lists(c.edges(), &a, MAX_LEVEL)
                    .expect("host lists");
                let driven = m
                    .evaluate_adaptive_gpu_driven(c.edges(), &a, MAX_LEVEL)
                    .expect("gpu-driven");
                assert_eq!(driven.edge_levels, host.edge_levels, "{scheme} {name}");
                assert!(
                    bit_equal(&driven, &host),
                    "{scheme} {name} {}",
                    disp.is_some()
                );
                assert_eq!(open_edges(&driven).0, 0, "{scheme} {name}");
            }
        }
    }
}

/// The GPU-driven compaction runs a workgroup per chunk of 256 patches:
/// on meshes with many chunks, and class ranges that start inside a chunk
/// (the chunk is shared by two ranges' dispatches), it still gives the
/// host-list tessellation bit for bit. catmark_righthanded (434 quads;
/// pn on its 868-triangle split) and big/catmark_righthanded_L3 (27,776
/// quads, 109 chunks), random factors in [1, 2.4] (buckets 2 and 4 about
/// evenly, so every chunk has both), largest level 4; and pccm on
/// righthanded_L3 with factors in [5, 8], so the level-8 bucket needs more
/// than 32,768 workgroups and its indirect dispatch runs in two rows.
#[test]
fn gpu_driven_buckets_match_the_host_lists_across_chunks() {
    for (scheme, name, hi, level) in [
        ("pccm", "catmark_righthanded", 2.4, 4),
        ("pn", "catmark_righthanded", 2.4, 4),
        ("gregory", common::BIG_MESH, 2.4, 4),
        ("pccm", common::BIG_MESH, 8.0, 8),
    ] {
        let c = Case::new(scheme, common::mesh(name));
        let (_, edges) = c.edges().edge_ids();
        let lo = if level == 8 { 5.0 } else { 1.0 };
        let a = Adaptive {
            metric: Metric::Buffer(adaptive::random_factors(edges, SEED, lo, hi)),
            partitioning: Partitioning::Integer,
            min: 1.0,
            max: level as f32,
        };
        let m = c.gpu_mesh(scheme, None);
        let patches: u32 = m.classes.iter().map(|r| r.count).sum();
        assert!(
            patches > 256,
            "{scheme} {name}: {patches} patches, one chunk"
        );
        let host = m
            .evaluate_adaptive_host_lists(c.edges(), &a, level)
            .expect("host lists");
        let driven = m
            .evaluate_adaptive_gpu_driven(c.edges(), &a, level)
            .expect("gpu-driven");
        let buckets: Vec<usize> = [1, 2, 4, 8]
            .iter()
            .map(|&l| driven.levels.iter().filter(|&&x| x == l).count())
            .collect();
        println!(
            "{scheme} {name}: {patches} patches, ranges {:?}, buckets 1/2/4/8: {buckets:?}",
            m.classes
                .iter()
                .map(|r| (r.first, r.count))
                .collect::<Vec<_>>()
        );
        if level == 8 {
            // The largest bucket's evaluation: more than 32,768 workgroups of 64.
            assert!(buckets[3] * 81 > 32_768 * 64, "{buckets:?}");
        }
        assert_eq!(driven.levels, host.levels, "{scheme} {name}");
        assert_eq!(driven.edge_levels, host.edge_levels, "{scheme} {name}");
        assert!(bit_equal(&driven, &host), "{scheme} {name}");
        assert_eq!(open_edges(&driven).0, 0, "{scheme} {name}");
        // The samples buffer is kept between calls: a smaller run into the
        // larger buffer, holding the first run's samples, is still exact.
        let smaller = m
            .evaluate_adaptive_gpu_driven(c.edges(), &a, level / 2)
            .expect("gpu-driven, reused buffer");
        let host_smaller = m
            .evaluate_adaptive_host_lists(c.edges(), &a, level / 2)
            .expect("host lists");
        assert!(bit_equal(&smaller, &host_smaller), "{scheme} {name} reused");
    }
}
