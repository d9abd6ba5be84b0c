//! The library-only rows of docs/errors.md: errors that no `tessgen`
//! command can provoke (API misuse, hand-built inputs, device limits forced
//! small), each provoked here with a minimal input and its exact message
//! checked. The rows the CLI reaches are run by the binary in
//! cli/tests/errors.rs.

mod common;

use glam::Vec3;
use tessgen_runtime::adaptive::{self, Adaptive, AdaptiveError, Metric, Partitioning};
use tessgen_runtime::capture::{CaptureError, TriangleCapture, VERTEX_FLOATS};
use tessgen_runtime::cpu::{self, Construction, MAX_LEVEL};
use tessgen_runtime::displace::{DisplaceError, DisplaceMap, Ownership};
use tessgen_runtime::gpu::{Gpu, GpuError, GpuMesh, Limits};
use tessgen_runtime::tessellate::{AdaptiveRequest, EdgeMetric, Error, Request};
use tessgen_runtime::trimesh::{TriMesh, TriOptions};
use tessgen_runtime::upload::{Upload, UploadError};
use tessgen_runtime::vulkan::{Language, Options, VkError, VkMesh, Vulkan};
use tessgen_runtime::{kernels, TessError, Topology};

fn cube() -> (tessgen_runtime::Topology, Vec<Vec3>) {
    common::topo_positions(&common::mesh("catmark_cube"))
}

fn pccm() -> &'static kernels::common::SchemeKernels {
    cpu::scheme("pccm").expect("pccm")
}

#[test]
fn tess_error_unknown_scheme() {
    let e = cpu::scheme("loop").expect_err("no such scheme");
    assert!(matches!(e, TessError::UnknownScheme { .. }), "{e:?}");
    assert_eq!(
        e.to_string(),
        format!(
            "unknown scheme `loop` (available: {})",
            kernels::scheme_names().join(", ")
        )
    );
}

#[test]
fn tess_error_level() {
    let (topo, positions) = cube();
    let patches = cpu::construct(&topo, &positions, pccm()).expect("construct");
    for level in [0, MAX_LEVEL + 1] {
        let e = cpu::evaluate(&patches, level).expect_err("bad level");
        assert!(matches!(e, TessError::Level(l) if l == level), "{e:?}");
    }
    assert_eq!(
        cpu::evaluate(&patches, 0).expect_err("level 0").to_string(),
        "tessellation level must be in 1..=4096, got 0"
    );
}

#[test]
fn tess_error_output_length() {
    let (topo, positions) = cube();
    let patches = cpu::construct(&topo, &positions, pccm()).expect("construct");
    let (mut p, mut n) = (vec![Vec3::ZERO; 5], vec![Vec3::ZERO; 54]);
    let e = cpu::evaluate_per_sample_into(&patches, 2, &mut p, &mut n).expect_err("short");
    assert!(
        matches!(e, TessError::OutputLength { want: 54, got: 5 }),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "output buffers hold 5 samples, the grids need 54"
    );
}

#[test]
fn tess_error_layout() {
    let (topo, positions) = cube();
    let c = Construction::new(&topo, pccm()).expect("construction");
    let mut patches = c.construct(&positions);
    let e = c
        .update(&positions[..3], &mut patches)
        .expect_err("too few positions");
    assert!(matches!(e, TessError::Layout), "{e:?}");
    assert_eq!(
        e.to_string(),
        "these patches were not made by this construction (scheme or layout differs, or too few positions)"
    );
    let (torus, torus_positions) = common::topo_positions(&common::mesh("catmark_torus"));
    let mut other = cpu::construct(&torus, &torus_positions, pccm()).expect("torus");
    assert!(matches!(
        c.update(&positions, &mut other),
        Err(TessError::Layout)
    ));
}

/// The front door refuses a largest adaptive factor that is no range (a
/// NaN once reached the hardware tessellator as level 65536).
#[test]
fn front_door_adaptive_clamp() {
    let mesh = common::mesh("catmark_cube");
    for (max_factor, text) in [
        (
            f32::NAN,
            "adaptive clamp range [1, NaN] is not a finite range with min <= max",
        ),
        (
            f32::INFINITY,
            "adaptive clamp range [1, inf] is not a finite range with min <= max",
        ),
        (
            0.5,
            "adaptive clamp range [1, 0.5] is not a finite range with min <= max",
        ),
    ] {
        let request = Request::adaptive(
            "pccm",
            AdaptiveRequest {
                metric: EdgeMetric::Random {
                    seed: 1,
                    lo: 1.0,
                    hi: 4.0,
                },
                partitioning: Partitioning::Integer,
                max_factor,
            },
        );
        match request.validate(&mesh) {
            Err(e @ Error::Adaptive(AdaptiveError::Clamp { .. })) => {
                assert_eq!(e.to_string(), text)
            }
            Err(e) => panic!("{max_factor}: {e:?}"),
            Ok(_) => panic!("{max_factor}: accepted"),
        }
    }
}

/// Every edge of `topo` at factor 2, clamped to `[min, max]`.
fn factor_two(topo: &Topology, min: f32, max: f32) -> Adaptive {
    Adaptive {
        metric: Metric::Buffer(vec![2.0; adaptive::edge_ids(topo).1 as usize]),
        partitioning: Partitioning::Integer,
        min,
        max,
    }
}

#[test]
fn adaptive_error_clamp() {
    let (topo, positions) = cube();
    let patches = cpu::construct(&topo, &positions, pccm()).expect("construct");
    let a = factor_two(&topo, 4.0, 2.0);
    let e = adaptive::evaluate_cpu_adaptive(&patches, &topo, &a, 4).expect_err("min > max");
    assert!(
        matches!(e, AdaptiveError::Clamp { min, max } if min == 4.0 && max == 2.0),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "adaptive clamp range [4, 2] is not a finite range with min <= max"
    );
}

#[test]
fn adaptive_error_displace_mismatch() {
    let (topo, positions) = cube();
    let patches = cpu::construct(&topo, &positions, pccm()).expect("construct");
    // Displacement data of another mesh (the 32-face torus, one chart per face).
    let torus = common::per_face_charts(common::mesh("catmark_torus"));
    let (torus_topo, torus_positions) = common::topo_positions(&torus);
    let torus_patches = cpu::construct(&torus_topo, &torus_positions, pccm()).expect("torus");
    let d = common::displacement(Ownership::LowestFace, 0.1);
    let data = cpu::displacement_data(&torus, &torus_topo, &torus_patches, &d).expect("torus data");
    let a = factor_two(&topo, 1.0, 4.0);
    let e = adaptive::evaluate_cpu_adaptive_displaced(&patches, &topo, &a, 4, &data)
        .expect_err("data of another mesh");
    match &e {
        AdaptiveError::DisplaceMismatch { got, patches, .. } => {
            assert_eq!((*got, *patches), (32, 6), "{e}")
        }
        other => panic!("{other:?}"),
    }
    assert!(
        e.to_string().ends_with(
            "for 32 faces, the patches have 6 faces (build it from the same mesh and patches)"
        ),
        "{e}"
    );
}

#[test]
fn displace_error_bad_map() {
    for (w, h, texels, reason) in [
        (0, 4, vec![], "empty"),
        (
            8193,
            1,
            vec![0.0; 8193],
            "larger than 8192 texels on a side",
        ),
        (2, 2, vec![0.0; 3], "texel count is not width·height"),
        (1, 1, vec![f32::NAN], "a texel is not finite"),
    ] {
        let e = DisplaceMap::new(w, h, texels).expect_err(reason);
        assert!(matches!(e, DisplaceError::BadMap { .. }), "{e:?}");
        assert_eq!(e.to_string(), format!("displacement map {w}x{h}: {reason}"));
    }
}

#[test]
fn build_error_no_scheme_and_no_out_dir() {
    use tessgen_codegen::{BuildError, Builder};
    let Err(e) = Builder::new().compile() else {
        panic!("compiled without a scheme")
    };
    assert!(matches!(e, BuildError::NoScheme), "{e:?}");
    assert_eq!(e.to_string(), "no scheme given");
    let e = Builder::new()
        .builtin_schemes()
        .write()
        .expect_err("no out dir");
    assert!(matches!(e, BuildError::NoOutDir), "{e:?}");
    assert_eq!(e.to_string(), "no output directory given");
}

#[test]
fn upload_error_tess_and_position_count() {
    let (topo, positions) = cube();
    match Upload::quad(&topo, &positions, "pn") {
        Err(e @ UploadError::Tess(TessError::WrongFacet { .. })) => assert_eq!(
            e.to_string(),
            "scheme `pn` works on triangles; give it a triangle mesh (or split quads: `--split-quads`)"
        ),
        other => panic!("{:?}", other.err()),
    }
    match Upload::quad(&topo, &positions[..7], "pccm") {
        Err(e @ UploadError::PositionCount { .. }) => {
            assert_eq!(e.to_string(), "positions: expected 8, got 7")
        }
        other => panic!("{:?}", other.err()),
    }
}

/// One captured vertex: position, normal, domain point, patch (as bits).
fn vertex(domain: [f32; 3], patch: u32) -> Vec<f32> {
    let mut v = vec![0.0; VERTEX_FLOATS];
    v[6..9].copy_from_slice(&domain);
    v[9] = f32::from_bits(patch);
    v
}

#[test]
fn capture_error_mixed_patches_and_domain() {
    let mut raw = vertex([0.0, 0.0, 0.0], 0);
    raw.extend(vertex([1.0, 0.0, 0.0], 1));
    raw.extend(vertex([0.0, 1.0, 0.0], 0));
    let e = TriangleCapture::from_raw(1, &raw, &[0, 1], 2).expect_err("mixed");
    assert!(
        matches!(
            e,
            CaptureError::MixedPatches {
                triangle: 0,
                a: 0,
                b: 1,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(
        e.to_string().starts_with(
            "captured triangle 0: its vertices name different patches (0 and 1); raw vertices ["
        ),
        "{e}"
    );
    let mut raw = vertex([0.0, 0.0, 0.0], 0);
    raw.extend(vertex([f32::NAN, 0.0, 0.0], 0));
    raw.extend(vertex([0.0, 1.0, 0.0], 0));
    let e = TriangleCapture::from_raw(1, &raw, &[0], 1).expect_err("NaN domain");
    assert!(
        matches!(e, CaptureError::Domain { triangle: 0, .. }),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "captured triangle 0: domain point [NaN, 0.0, 0.0] is not finite"
    );
}

// ---- wgpu (any adapter: lavapipe), limits forced small ----

fn gpu() -> &'static Gpu {
    static GPU: std::sync::OnceLock<Gpu> = std::sync::OnceLock::new();
    GPU.get_or_init(|| Gpu::new().unwrap_or_else(|e| panic!("{e}")))
}

/// A lost device (here `Device::destroy`, which lavapipe honours like a
/// driver reset) is a typed error naming the adapter, from evaluation and
/// from any later use, never a panic or a result of zeros.
#[test]
fn gpu_error_device_lost() {
    let own = Gpu::new().unwrap_or_else(|e| panic!("{e}"));
    let (topo, positions) = cube();
    let m = GpuMesh::new(&own, &topo, &positions, "pccm").expect("gpu mesh");
    m.evaluate(2).expect("a live device evaluates");
    own.device.destroy();
    for attempt in 0..2 {
        let e = m.evaluate(2).expect_err("the device is gone");
        let GpuError::DeviceLost { adapter, .. } = &e else {
            panic!("attempt {attempt}: {e:?}");
        };
        assert_eq!(adapter, &own.info.name);
        let text = e.to_string();
        assert!(
            text.starts_with(&format!(
                "the GPU device ({}) was lost: destroyed",
                own.info.name
            )),
            "{text}"
        );
        assert!(text.ends_with("nothing was written"), "{text}");
    }
    let e = GpuMesh::new(&own, &topo, &positions, "pccm")
        .err()
        .expect("no new mesh on a lost device");
    assert!(matches!(e, GpuError::DeviceLost { .. }), "{e:?}");
}

#[test]
fn gpu_error_buffer_too_large() {
    let (topo, positions) = cube();
    let limits = Limits {
        max_storage_buffer_binding_size: 128 * 1024,
        ..gpu().limits
    };
    let m = GpuMesh::with_limits(gpu(), &topo, &positions, "pccm", limits).expect("fits");
    let e = m
        .evaluate(128)
        .expect_err("one patch's samples exceed 128 KiB");
    assert!(matches!(e, GpuError::BufferTooLarge { .. }), "{e:?}");
    assert_eq!(
        e.to_string(),
        format!(
            "samples of one patch needs 399384 bytes in one binding, more than \
             max_storage_buffer_binding_size = 131072 of {}",
            gpu().info.name
        )
    );
}

#[test]
fn gpu_error_too_many_chunks() {
    let mesh = common::mesh("catmark_righthanded");
    let (topo, positions) = common::topo_positions(&mesh);
    let limits = Limits {
        max_workgroups_per_dimension: 1,
        ..gpu().limits
    };
    let m = GpuMesh::with_limits(gpu(), &topo, &positions, "pccm", limits).expect("gpu mesh");
    let a = factor_two(&topo, 1.0, 4.0);
    let e = m
        .evaluate_adaptive_gpu_driven(&topo, &a, 4)
        .expect_err("434 patches need 2 chunks");
    assert!(
        matches!(
            e,
            GpuError::TooManyChunks {
                patches: 434,
                chunks: 2,
                max: 1,
                ..
            }
        ),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        format!(
            "434 patches need 2 workgroups of 256 in one dispatch of the GPU-driven buckets, \
             more than max_workgroups_per_dimension = 1 of {}",
            gpu().info.name
        )
    );
}

/// The refinement stencils of the non-quad mesh, one row short.
fn short_stencils() -> (
    tessgen_runtime::Topology,
    Vec<Vec3>,
    tessgen_runtime::mesh::refine::StencilTable,
) {
    let mesh = common::mesh("catmark_nonquads");
    let request = Request::uniform("pccm", 4);
    let v = request.validate(&mesh).expect("validate");
    let part = v.parts().last().expect("parts");
    let r = part.refined().expect("refined");
    let mut stencils = r.refinement.stencils.clone();
    stencils.offsets.pop();
    let base = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    (part.topology().expect("quads").clone(), base, stencils)
}

#[test]
fn gpu_error_upload() {
    let (topo, base, short) = short_stencils();
    match GpuMesh::new_refined(gpu(), &topo, &base, &short, "pccm", None) {
        Err(e @ GpuError::Upload(UploadError::Refinement { .. })) => {
            assert!(
                e.to_string()
                    .starts_with("refinement: the stencil table has "),
                "{e}"
            )
        }
        other => panic!("{:?}", other.err()),
    }
}

// ---- the Vulkan harness (lavapipe) ----

#[test]
fn vk_error_misuse() {
    let vk = Vulkan::new().unwrap_or_else(|e| panic!("{e}"));
    let glsl = Options::new(Language::Glsl);
    let (topo, positions) = cube();
    // Refused before any shader is built.
    match VkMesh::new(&vk, &topo, &positions, "pn", &glsl) {
        Err(VkError::Tess(TessError::WrongFacet { .. })) => {}
        other => panic!("{:?}", other.err()),
    }
    match VkMesh::new(&vk, &topo, &positions[..7], "pccm", &glsl) {
        Err(e @ VkError::PositionCount { .. }) => {
            assert_eq!(e.to_string(), "positions: expected 8, got 7")
        }
        other => panic!("{:?}", other.err()),
    }
    let edges = adaptive::edge_ids(&topo).1 as usize;
    let adaptive = Options {
        adaptive: Some(Adaptive {
            metric: Metric::Buffer(vec![2.0; edges - 1]),
            partitioning: Partitioning::Integer,
            min: 1.0,
            max: 4.0,
        }),
        ..glsl.clone()
    };
    match VkMesh::new(&vk, &topo, &positions, "pccm", &adaptive) {
        Err(e @ VkError::EdgeFactorCount { .. }) => assert_eq!(
            e.to_string(),
            "explicit edge factors: the mesh has 12 edges, 11 factors were given"
        ),
        other => panic!("{:?}", other.err()),
    }
    let (rtopo, base, short) = short_stencils();
    match VkMesh::new_refined(&vk, &rtopo, &base, &short, "pccm", None, &glsl) {
        Err(VkError::Upload(UploadError::Refinement { .. })) => {}
        other => panic!("{:?}", other.err()),
    }
    // A quad mesh asked for triangles, or for an adaptive capture it was
    // not built for; a triangle mesh asked for grids.
    let quads = VkMesh::new(&vk, &topo, &positions, "pccm", &glsl).expect("quads");
    match quads.evaluate_triangles(2) {
        Err(e @ VkError::QuadDomain { .. }) => assert_eq!(
            e.to_string(),
            "scheme `pccm` has a quad domain: evaluate_triangles is for triangle schemes"
        ),
        other => panic!("{:?}", other.err()),
    }
    match quads.evaluate_adaptive() {
        Err(VkError::AdaptiveNotGrid) => {}
        other => panic!("{:?}", other.err()),
    }
    let tri = TriMesh::from_mesh(
        &common::mesh("catmark_cube"),
        &TriOptions {
            split_quads: true,
            ..Default::default()
        },
    )
    .expect("split");
    let triangles = VkMesh::new_tri(&vk, &tri, "pn", &glsl).expect("triangles");
    match triangles.evaluate(2) {
        Err(e @ VkError::TriangleDomain { .. }) => assert_eq!(
            e.to_string(),
            "scheme `pn` has a triangle domain: the hardware's inner vertices are not grid \
             points, so capture its triangles with evaluate_triangles"
        ),
        other => panic!("{:?}", other.err()),
    }
}
