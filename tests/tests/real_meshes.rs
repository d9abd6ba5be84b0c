//! The open and tagged shared meshes (boundaries, infinitely sharp and
//! semi-sharp creases, `interpolateboundary`; docs/boundaries.md) on every
//! backend, checked the way the closed meshes are:
//!
//! * every open mesh × every quad scheme × CPU, wgpu, Vulkan GLSL, Vulkan
//!   HLSL at level [`LEVEL`]: the exact weld leaves exactly `N` open sample
//!   edges per base boundary edge (nothing overused or collapsed) and the
//!   input's Euler characteristic, every interior sharp (crease) edge comes
//!   out bit-identical from its two faces, and the GPU backends are within
//!   the closed meshes' parity bound of the CPU (tests/tests/gpu.rs,
//!   vulkan_watertight.rs: 1e-5 × bounding-box diagonal; how many samples
//!   are bit-identical is printed);
//! * adaptive, displaced and adaptive-displaced tessellation of creased
//!   open meshes weld closed except at the true boundary, on every backend;
//! * faces whose four corners are regular and touch no semi-sharp edge are
//!   the exact Catmull-Clark limit (OpenSubdiv's samples) to f32 noise;
//! * negative controls: ignoring the tags moves single_crease far from its
//!   limit; one ulp on a crease-edge sample opens exactly the four sample
//!   edges around it;
//! * bad tags are typed errors naming the OBJ line.
//!
//! Rows print with `--nocapture`.

mod common;

use glam::Vec3;
use tessgen_runtime::adaptive::{self, Metric, Partitioning};
use tessgen_runtime::displace::Ownership;
use tessgen_runtime::mesh::features::{is_semi_sharp, FeatureError};
use tessgen_runtime::tessellate::{
    AdaptiveRequest, Backend, EdgeMetric, Error, Output, Request, Session,
};
use tessgen_runtime::topology::NONE;
use tessgen_runtime::{
    cpu, weld, FaceClass, Mesh, TessError, Tessellation, Topology, TopologyError,
};

/// The open and tagged meshes of tests/data/meshes.
const OPEN_MESHES: &[&str] = &[
    "catmark_tent",
    "catmark_single_crease",
    "catmark_xord_boundary",
    "catmark_xord_interior",
    "catmark_fvar_bound3",
    "catmark_gregory_test1",
    "catmark_pawn",
    "catmark_car",
];

/// Quad schemes that apply to every face (`regular` is added where every
/// face is ordinary).
const SCHEMES: &[&str] = &["pccm", "acc", "gregory", "gregory_osd", "g1cc"];

const LEVEL: u32 = 4;

/// The Vulkan harness runs the whole matrix too: every open and tagged
/// mesh, every quad scheme (glslangValidator compiles every stage per mesh
/// and scheme, ~3 s each on lavapipe with two cores: about 2 minutes per
/// language for the 8 meshes).
const VULKAN_MESHES: &[&str] = OPEN_MESHES;

/// Whether `backend` must give the CPU's bits exactly for `scheme`. The
/// closed-mesh tests (gpu.rs, vulkan_watertight.rs) only bound the
/// difference (1e-5 × diagonal); on the open meshes the CPU, wgpu and GLSL
/// agree bit for bit for every scheme but `g1cc`, HLSL for all but the
/// Gregory schemes and `g1cc` (up to 5e-7 × diagonal on lavapipe: rounding
/// of the HLSL Gregory evaluation), which are held to the bound and must
/// weld on their own. `g1cc` on wgpu and GLSL (lavapipe, N = 4): bit for
/// bit on xord_boundary, xord_interior, fvar_bound3 and gregory_test1, but
/// some samples differ in the last bits on tent (3 of 225, normals only),
/// single_crease (9 of 2,000), pawn (285 of 14,700) and car (474 of
/// 39,375), at most 5.4e-7 × diagonal; not traced yet (the CPU's grid and
/// per-sample paths agree bit for bit on these meshes, grid_path.rs).
fn bit_exact(backend: Backend, scheme: &str) -> bool {
    match backend {
        Backend::VulkanHlsl => !(scheme.starts_with("gregory") || scheme == "g1cc"),
        Backend::Cpu => true,
        _ => scheme != "g1cc",
    }
}

/// Largest accepted |GPU − CPU| / bbox diagonal (as gpu.rs and
/// vulkan_watertight.rs assert on the closed meshes).
const PARITY: f64 = 1e-5;

fn topo(mesh: &Mesh) -> Topology {
    Topology::build(mesh, &cpu::topology_options()).expect("topology")
}

/// The schemes run on `topo`: the four general ones, and `regular` when
/// every face is ordinary.
fn schemes_for(topo: &Topology) -> Vec<&'static str> {
    let mut s = SCHEMES.to_vec();
    if topo.classes.iter().all(|&c| c == FaceClass::Ordinary) {
        s.push("regular");
    }
    s
}

/// Grid index of parameter `t` along local edge `k` of a `level` grid
/// (`accuracy::edge_sample`, the layout every backend's grid shares).
fn edge_sample(k: u32, t: u32, level: u32) -> usize {
    tessgen_runtime::accuracy::edge_sample(k, t, level) as usize
}

/// Interior sharp edges (creases, semi-sharp applied as sharp) as
/// `(half-edge, twin)` with the lower id first.
fn crease_halfedges(topo: &Topology) -> Vec<(u32, u32)> {
    (0..topo.num_halfedges() as u32)
        .filter(|&h| {
            let t = topo.twin[h as usize];
            topo.edge_sharp[h as usize] && t != NONE && h < t
        })
        .map(|h| (h, topo.twin[h as usize]))
        .collect()
}

/// Samples of crease edges whose bits differ between the two faces:
/// sample `t` of half-edge `h` is sample `N − t` of its twin. Needs every
/// face emitted (no holes), which holds for the shared meshes.
fn crease_mismatches(topo: &Topology, t: &Tessellation) -> usize {
    let (n, per) = (t.level, t.grid_len());
    let local = |h: u32| {
        let f = topo.face[h as usize] as usize;
        (f, h - topo.face_offsets[f])
    };
    let bits = |p: Vec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let mut bad = 0;
    for (h, tw) in crease_halfedges(topo) {
        let ((fa, ka), (fb, kb)) = (local(h), local(tw));
        for s in 0..=n {
            let a = t.positions[fa * per + edge_sample(ka, s, n)];
            let b = t.positions[fb * per + edge_sample(kb, n - s, n)];
            if bits(a) != bits(b) {
                bad += 1;
            }
        }
    }
    bad
}

/// What one uniform run gave.
struct Row {
    open: usize,
    crease_mismatches: usize,
    /// max |backend − CPU| / diag (0 on the CPU).
    parity: f64,
    /// Samples whose position bits differ from the CPU's.
    bit_diffs: usize,
}

fn max_parity(a: &Tessellation, b: &Tessellation, diag: f32) -> (f64, usize) {
    assert_eq!(a.positions.len(), b.positions.len());
    let mut worst = 0.0f64;
    let mut diffs = 0;
    for (p, q) in a.positions.iter().zip(&b.positions) {
        let d = ((*p - *q).length() / diag) as f64;
        worst = if d.is_nan() {
            f64::INFINITY
        } else {
            worst.max(d)
        };
        if p.to_array().map(f32::to_bits) != q.to_array().map(f32::to_bits) {
            diffs += 1;
        }
    }
    (worst, diffs)
}

/// Every open mesh and scheme on `backend` at [`LEVEL`]: boundary-only
/// open edges, Euler characteristic, crease edges bit-identical, parity
/// with the CPU. Failures are collected and reported together.
fn matrix(backend: Backend, meshes: &[&str]) {
    let mut session = Session::new();
    let mut bad = Vec::new();
    let mut rows = 0;
    println!("| backend | mesh | scheme | N | boundary edges | crease edges | open edges | crease mismatches | max |Δp| / diag | samples ≠ CPU bits |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for name in meshes {
        let mesh = common::mesh(name);
        let topo = topo(&mesh);
        let diag = common::bbox_diagonal(&mesh);
        let boundary = topo.num_boundary_edges();
        let creases = crease_halfedges(&topo).len();
        assert!(boundary > 0, "{name} is not open");
        assert!(
            topo.no_limit.iter().all(|&x| !x),
            "{name}: faces without a limit"
        );
        for scheme in schemes_for(&topo) {
            let request = Request::uniform(scheme, LEVEL);
            let cpu_t = common::grid(&mesh, &request)
                .unwrap_or_else(|e| panic!("{name} {scheme} cpu: {e}"));
            let t = if backend == Backend::Cpu {
                cpu_t.clone()
            } else {
                match session.tessellate(&mesh, &request.clone().on(backend)) {
                    Ok(Output::Grid(t)) => t,
                    Ok(other) => {
                        panic!("{name} {scheme} {}: not a grid: {other:?}", backend.name())
                    }
                    Err(e) => {
                        bad.push(format!("{name} {scheme} {}: {e}", backend.name()));
                        continue;
                    }
                }
            };
            let r = weld::weld(&t);
            let (parity, bit_diffs) = max_parity(&t, &cpu_t, diag);
            let row = Row {
                open: r.open_edges,
                crease_mismatches: crease_mismatches(&topo, &t),
                parity,
                bit_diffs,
            };
            rows += 1;
            println!(
                "| {} | {name} | {scheme} | {LEVEL} | {boundary} | {creases} | {} | {} | {:.1e} | {} / {} |",
                backend.name(),
                row.open,
                row.crease_mismatches,
                row.parity,
                row.bit_diffs,
                t.positions.len()
            );
            let what = format!("{name} {scheme} {} N={LEVEL}", backend.name());
            if row.open != LEVEL as usize * boundary
                || r.overused_edges != 0
                || r.degenerate_triangles != 0
            {
                bad.push(format!(
                    "{what}: {} open edges (expected {} = N × {boundary} boundary edges), {} overused, {} degenerate",
                    row.open,
                    LEVEL as usize * boundary,
                    r.overused_edges,
                    r.degenerate_triangles
                ));
            }
            if r.euler != topo.euler_characteristic() {
                bad.push(format!(
                    "{what}: Euler characteristic {} (mesh {})",
                    r.euler,
                    topo.euler_characteristic()
                ));
            }
            if row.crease_mismatches != 0 {
                bad.push(format!(
                    "{what}: {} crease-edge samples differ between the two faces",
                    row.crease_mismatches
                ));
            }
            if bit_exact(backend, scheme) && row.bit_diffs != 0 {
                bad.push(format!(
                    "{what}: {} samples differ from the CPU's bits",
                    row.bit_diffs
                ));
            }
            if row.parity > PARITY {
                bad.push(format!(
                    "{what}: {:.2e} × diagonal from the CPU",
                    row.parity
                ));
            }
        }
    }
    assert!(rows > 0);
    assert!(bad.is_empty(), "{bad:#?}");
}

/// The CPU on every open mesh and scheme (also proves the matrix's
/// reference is sound).
#[test]
fn cpu_open_meshes_weld_to_their_boundary() {
    matrix(Backend::Cpu, OPEN_MESHES);
}

#[test]
fn wgpu_open_meshes_match_the_cpu_and_weld_to_their_boundary() {
    matrix(Backend::Wgpu, OPEN_MESHES);
}

#[test]
fn glsl_open_meshes_match_the_cpu_and_weld_to_their_boundary() {
    matrix(Backend::VulkanGlsl, VULKAN_MESHES);
}

#[test]
fn hlsl_open_meshes_match_the_cpu_and_weld_to_their_boundary() {
    matrix(Backend::VulkanHlsl, VULKAN_MESHES);
}

// ---------------------------------------------------------------------------
// Adaptive and displaced tessellation of creased open meshes.

/// The creased open meshes of the adaptive/displaced checks: an interior
/// crease line plus a boundary, and extraordinary boundary vertices.
const CREASED: &[&str] = &["catmark_single_crease", "catmark_xord_boundary"];
const ADAPTIVE_SCHEMES: &[&str] = &["pccm", "gregory"];
const MAX_FACTOR: f32 = 16.0;
const SEED: u64 = 0x7e55_6e11;

/// Random per-edge factors in [1, 12] (explicit, so the expected open
/// edges are known).
fn factors(topo: &Topology) -> Vec<f32> {
    let (_, edges) = adaptive::edge_ids(topo);
    adaptive::random_factors(edges, SEED, 1.0, 12.0)
}

/// Open sample edges the true boundary must keep in an adaptive run: the
/// segments of every boundary edge, `edge_level` (the instanced path's
/// power of two) or, on a hardware tessellator with integer partitioning,
/// the factor rounded up.
fn expected_adaptive_open(topo: &Topology, f: &[f32], backend: Backend) -> usize {
    let (ids, _) = adaptive::edge_ids(topo);
    topo.boundary_halfedges
        .iter()
        .map(|&h| {
            let x = f[ids[h as usize] as usize].clamp(1.0, MAX_FACTOR);
            if backend.hardware_tessellator() {
                x.ceil() as usize
            } else {
                adaptive::edge_level(x, MAX_FACTOR as u32) as usize
            }
        })
        .sum()
}

fn adaptive_request<'a>(scheme: &str, f: &[f32]) -> Request<'a> {
    Request::adaptive(
        scheme,
        AdaptiveRequest {
            metric: EdgeMetric::Given(Metric::Buffer(f.to_vec())),
            partitioning: Partitioning::Integer,
            max_factor: MAX_FACTOR,
        },
    )
}

/// Adaptive, displaced (uniform [`LEVEL`]) and adaptive-displaced runs of
/// the creased meshes on `backend`: only the true boundary stays open.
/// Displacement needs texture coordinates: every face is its own chart
/// (so every edge is also a texture seam).
fn adaptive_and_displaced(backend: Backend, meshes: &[&str]) {
    let mut session = Session::new();
    let mut bad = Vec::new();
    println!("| backend | mesh | scheme | run | triangles | degenerate | open edges | expected |");
    println!("|---|---|---|---|---|---|---|---|");
    for name in meshes {
        let mesh = common::per_face_charts(common::mesh(name));
        let topo = topo(&mesh);
        // Adaptive runs tessellate the mesh they run (refined uniformly by
        // the semi-sharp creases' steps): explicit factors are per edge of
        // that mesh.
        let run = adaptive_request("pccm", &[])
            .validate(&mesh)
            .expect("validate")
            .topology()
            .expect("quads")
            .clone();
        let f = factors(&run);
        let d = common::displacement(Ownership::LowestFace, 0.05 * common::bbox_diagonal(&mesh));
        let uniform_open = LEVEL as usize * topo.num_boundary_edges();
        let adaptive_open = expected_adaptive_open(&run, &f, backend);
        for scheme in ADAPTIVE_SCHEMES {
            let runs: [(&str, Request, usize); 3] = [
                ("adaptive", adaptive_request(scheme, &f), adaptive_open),
                (
                    "displaced",
                    Request::uniform(scheme, LEVEL).displaced(&d),
                    uniform_open,
                ),
                (
                    "adaptive displaced",
                    adaptive_request(scheme, &f).displaced(&d),
                    adaptive_open,
                ),
            ];
            for (what, request, expected) in runs {
                let out = match session.tessellate(&mesh, &request.on(backend)) {
                    Ok(o) => o,
                    Err(e) => {
                        bad.push(format!("{name} {scheme} {what} {}: {e}", backend.name()));
                        continue;
                    }
                };
                let all_finite = out.triangles().iter().flatten().all(|p| p.is_finite());
                let r = out.weld();
                println!(
                    "| {} | {name} | {scheme} | {what} | {} | {} | {} | {expected} |",
                    backend.name(),
                    r.triangles,
                    r.degenerate_triangles,
                    r.open_edges
                );
                // The instanced path's snapped transitions and the
                // tessellator's fan corners leave collapsed triangles in
                // adaptive output (skipped by the weld, as in
                // adaptive_cpu.rs / vulkan_adaptive.rs); uniform grids have none.
                let degenerate_ok = what != "displaced" || r.degenerate_triangles == 0;
                if !all_finite
                    || r.open_edges != expected
                    || r.overused_edges != 0
                    || !degenerate_ok
                {
                    bad.push(format!(
                        "{name} {scheme} {what} {}: {} open (expected {expected}), {} overused, {} degenerate, finite {all_finite}",
                        backend.name(),
                        r.open_edges,
                        r.overused_edges,
                        r.degenerate_triangles
                    ));
                }
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

#[test]
fn cpu_adaptive_and_displaced_creased_meshes_open_only_at_the_boundary() {
    adaptive_and_displaced(Backend::Cpu, CREASED);
}

#[test]
fn wgpu_adaptive_and_displaced_creased_meshes_open_only_at_the_boundary() {
    adaptive_and_displaced(Backend::Wgpu, CREASED);
}

#[test]
fn glsl_adaptive_and_displaced_creased_meshes_open_only_at_the_boundary() {
    adaptive_and_displaced(Backend::VulkanGlsl, CREASED);
}

/// HLSL on single_crease only (the file's time budget; GLSL runs both).
#[test]
fn hlsl_adaptive_and_displaced_creased_mesh_opens_only_at_the_boundary() {
    adaptive_and_displaced(Backend::VulkanHlsl, &CREASED[..1]);
}

/// Negative control of the displaced check: with every patch using its
/// own normal and texture coordinates on its edges, the creased mesh opens
/// beyond its boundary.
#[test]
fn per_patch_displacement_opens_the_creased_mesh() {
    let mesh = common::per_face_charts(common::mesh("catmark_single_crease"));
    let boundary = topo(&mesh).num_boundary_edges();
    let d = common::displacement(Ownership::PerPatch, 0.05 * common::bbox_diagonal(&mesh));
    let t = common::grid(&mesh, &Request::uniform("pccm", LEVEL).displaced(&d)).expect("displaced");
    let open = weld::weld(&t).open_edges;
    println!(
        "per-patch ownership: {open} open edges, boundary alone {}",
        LEVEL as usize * boundary
    );
    assert!(open > LEVEL as usize * boundary, "{open}");
}

// ---------------------------------------------------------------------------
// Regular faces are the exact limit.

/// Faces whose patch must be the exact Catmull-Clark limit: all four
/// corners regular ([`FaceClass::Ordinary`]; infinitely sharp creases and
/// boundaries included, by the phantom rule) and no corner on a semi-sharp
/// edge or semi-sharp corner (tessgen applies those as infinitely sharp;
/// OpenSubdiv's limit is the semi-sharp one). A semi-sharp edge changes the
/// subdivision rules only at its two end vertices, so a face none of whose
/// corners is such an end keeps the plain rules on its whole neighbourhood
/// at every level.
fn exact_faces(mesh: &Mesh, topo: &Topology) -> Vec<usize> {
    let mut semi = std::collections::BTreeSet::new();
    for (&(a, b), &s) in &topo.features.edge_sharpness {
        if is_semi_sharp(s) {
            semi.insert(a);
            semi.insert(b);
        }
    }
    for (&v, &s) in &topo.features.vertex_sharpness {
        if is_semi_sharp(s) {
            semi.insert(v);
        }
    }
    (0..mesh.num_faces())
        .filter(|&f| {
            topo.classes[f] == FaceClass::Ordinary && mesh.face(f).iter().all(|v| !semi.contains(v))
        })
        .collect()
}

/// Distance of `faces` of `t` (at the limit file's level) from the limit
/// samples: the max in % of the local quad size (mean edge length of the
/// base face, as check/accuracy.rs measures), and the max in f32 units of
/// the sample's own magnitude (`|Δ| / (ε · ‖p‖∞)`: f32 rounding of the
/// coordinates themselves, which on the small faces of large meshes is
/// more than 1e-3 % of the quad).
fn distance(
    mesh: &Mesh,
    t: &Tessellation,
    n: usize,
    lim: &[[Vec3; 2]],
    faces: &[usize],
) -> (f64, f64) {
    let per = n * n;
    assert_eq!(t.grid_len(), per);
    let (mut pct, mut ulps) = (0.0f64, 0.0f64);
    let nan_max = |a: f64, b: f64| if b.is_nan() { f64::INFINITY } else { a.max(b) };
    for &f in faces {
        let face = mesh.face(f);
        let size: f64 = (0..face.len())
            .map(|k| {
                let a = Vec3::from_array(mesh.positions[face[k] as usize]);
                let b = Vec3::from_array(mesh.positions[face[(k + 1) % face.len()] as usize]);
                (b - a).length() as f64
            })
            .sum::<f64>()
            / face.len() as f64;
        for s in 0..per {
            let p = lim[f * per + s][0];
            let d = (t.positions[f * per + s] - p).as_dvec3().length();
            pct = nan_max(pct, d / size * 100.0);
            ulps = nan_max(
                ulps,
                d / (f32::EPSILON as f64 * p.abs().max_element() as f64),
            );
        }
    }
    (pct, ulps)
}

/// f32 noise: within 1e-3 % of the quad size, or (large coordinates on
/// small quads: pawn, car) within [`EXACT_ULPS`] f32 units of the
/// coordinates' magnitude.
const EXACT_PCT: f64 = 1e-3;
const EXACT_ULPS: f64 = 8.0;

#[test]
fn regular_faces_are_the_limit_to_f32_noise() {
    let mut bad = Vec::new();
    println!("| mesh | scheme | exact faces / faces | max dist % | max dist / (ε‖p‖∞) | all faces max dist % |");
    println!("|---|---|---|---|---|---|");
    for name in [
        "catmark_single_crease",
        "catmark_tent",
        "catmark_pawn",
        "catmark_car",
    ] {
        let mesh = common::mesh(name);
        let topo = topo(&mesh);
        let faces = exact_faces(&mesh, &topo);
        assert!(!faces.is_empty(), "{name}: no exact face");
        let (n, lim) = common::cc_limit(name);
        let all: Vec<usize> = (0..mesh.num_faces()).collect();
        for scheme in ["pccm", "gregory"] {
            let t =
                common::grid(&mesh, &Request::uniform(scheme, (n - 1) as u32)).expect("tessellate");
            let (pct, ulps) = distance(&mesh, &t, n, &lim, &faces);
            let (all_pct, _) = distance(&mesh, &t, n, &lim, &all);
            println!(
                "| {name} | {scheme} | {} / {} | {pct:.2e} | {ulps:.1} | {all_pct:.2e} |",
                faces.len(),
                mesh.num_faces()
            );
            if pct > EXACT_PCT && ulps > EXACT_ULPS {
                bad.push(format!(
                    "{name} {scheme}: regular faces {pct:e} % of the quad size, {ulps} ε‖p‖ from the limit"
                ));
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

// ---------------------------------------------------------------------------
// Negative controls.

/// RMS distance from the tagged limit, % of quad size (`tessgen compare`).
fn rms_pct(mesh: &Mesh, limit: &str) -> f64 {
    let lim = tessgen_runtime::accuracy::LimitSamples::load(common::data(&format!(
        "cc_limit/{limit}.bin"
    )))
    .expect("limit");
    tessgen_runtime::accuracy::compare(mesh, "pccm", 8, Some(&lim))
        .expect("compare")
        .rms_distance_pct
        .expect("rms")
}

/// With its tags dropped, single_crease is the smooth surface: far from
/// the creased limit (so the accuracy check sees the tags), and close to
/// the smooth limit OpenSubdiv gives without them.
#[test]
fn ignoring_the_tags_moves_single_crease_off_its_limit() {
    let tagged = common::mesh("catmark_single_crease");
    let mut plain = tagged.clone();
    plain.tags.clear();
    let on = rms_pct(&tagged, "catmark_single_crease");
    let off = rms_pct(&plain, "catmark_single_crease");
    let off_smooth = rms_pct(&plain, "catmark_single_crease.smooth");
    println!("single_crease pccm rms % of quad size: tags {on:.3e}, tags ignored {off:.3e} (vs smooth limit {off_smooth:.3e})");
    assert!(
        off > 3.0,
        "tags ignored: rms {off} % from the creased limit"
    );
    // The same mesh is the smooth limit to f32 noise: the 3 % are the tags.
    assert!(
        off_smooth < 1e-3,
        "tags ignored vs smooth limit: rms {off_smooth} %"
    );
}

/// One ulp on one crease-edge sample of one face (the crease's other face
/// keeps the true bits): the crease check finds that one sample and the
/// weld opens exactly the four sample edges around it (two on each side),
/// on top of the true boundary.
#[test]
fn one_ulp_on_a_crease_edge_opens_it() {
    let mesh = common::mesh("catmark_single_crease");
    let topo = topo(&mesh);
    let creases = crease_halfedges(&topo);
    assert_eq!(creases.len(), 36, "single_crease: interior crease edges");
    let mut t = common::grid(&mesh, &Request::uniform("pccm", LEVEL)).expect("tessellate");
    let boundary = LEVEL as usize * topo.num_boundary_edges();
    assert_eq!(weld::weld(&t).open_edges, boundary);
    assert_eq!(crease_mismatches(&topo, &t), 0);
    // The infinitely sharp crease edge 1–22 (the first tag line).
    let (h, _) = *creases
        .iter()
        .find(|&&(h, _)| {
            let (a, b) = (topo.origin[h as usize], topo.dest(h));
            (a.min(b), a.max(b)) == (1, 22)
        })
        .expect("crease 1-22");
    let f = topo.face[h as usize] as usize;
    let k = h - topo.face_offsets[f];
    let s = f * t.grid_len() + edge_sample(k, LEVEL / 2, LEVEL);
    let p = &mut t.positions[s];
    p.x = f32::from_bits(p.x.to_bits() + 1);
    assert_eq!(crease_mismatches(&topo, &t), 1);
    let r = weld::weld(&t);
    assert_eq!(r.open_edges, boundary + 4, "{r:?}");
}

// ---------------------------------------------------------------------------
// Bad input.

/// A 2 × 2 grid of quads (vertices 0..9, row by row), then `tag` on the
/// line returned.
fn grid_obj(tag: &str) -> (String, usize) {
    let mut s = String::from("# 2x2 grid\n");
    for j in 0..3 {
        for i in 0..3 {
            s.push_str(&format!("v {i} {j} 0\n"));
        }
    }
    for [a, b, c, d] in [[1, 2, 5, 4], [2, 3, 6, 5], [4, 5, 8, 7], [5, 6, 9, 8]] {
        s.push_str(&format!("f {a} {b} {c} {d}\n"));
    }
    let line = s.lines().count() + 1;
    s.push_str(tag);
    s.push('\n');
    (s, line)
}

#[test]
fn bad_tags_are_typed_errors_naming_the_line() {
    type Check = fn(&FeatureError) -> bool;
    let cases: &[(&str, Check)] = &[
        ("t crease 2/1/0 0 99 10", |e| {
            matches!(e, FeatureError::UnknownVertex { vertex: 99, .. })
        }),
        ("t corner 1/1/0 -1 2", |e| {
            matches!(e, FeatureError::UnknownVertex { vertex: -1, .. })
        }),
        (
            "t crease 2/1/0 0 1 nan",
            |e| matches!(e, FeatureError::BadSharpness { value, .. } if value.is_nan()),
        ),
        (
            "t crease 2/1/0 0 1 -1",
            |e| matches!(e, FeatureError::BadSharpness { value, .. } if *value == -1.0),
        ),
        ("t corner 1/1/0 4 inf", |e| {
            matches!(e, FeatureError::BadSharpness { .. })
        }),
        ("t crease 1/1/0 0 10", |e| {
            matches!(
                e,
                FeatureError::WrongCounts {
                    ints: 1,
                    floats: 1,
                    ..
                }
            )
        }),
        ("t corner 2/3/0 0 1 1 2 3", |e| {
            matches!(
                e,
                FeatureError::WrongCounts {
                    ints: 2,
                    floats: 3,
                    ..
                }
            )
        }),
        ("t crease 2/1/0 0 4 10", |e| {
            matches!(e, FeatureError::NotAnEdge { a: 0, b: 4, .. })
        }),
        ("t hole 1/0/0 4", |e| {
            matches!(e, FeatureError::HoleOutOfRange { face: 4, .. })
        }),
        ("t interpolateboundary 1/0/0 3", |e| {
            matches!(e, FeatureError::BadBoundaryRule { value: 3, .. })
        }),
    ];
    for (tag, check) in cases {
        let (obj, line) = grid_obj(tag);
        let mesh = Mesh::from_obj_str(&obj).unwrap_or_else(|e| panic!("{tag}: {e}"));
        let e = Topology::build(&mesh, &cpu::topology_options()).expect_err(tag);
        let TopologyError::Features(fe) = &e else {
            panic!("{tag}: not a tag error: {e}")
        };
        assert!(check(fe), "{tag}: {fe:?}");
        assert_eq!(fe_line(fe), line, "{tag}");
        assert!(
            e.to_string().contains(&format!("line {line}")),
            "{tag}: {e}"
        );
        // The front door refuses it the same way, before any device.
        let e = tessgen_runtime::tessellate::tessellate(
            &mesh,
            &Request::uniform("pccm", 2).on(Backend::Wgpu),
        )
        .expect_err(tag);
        assert!(
            // (Display, not ==: the NaN case is not equal to itself.)
            matches!(&e, Error::Tess(TessError::Topology(TopologyError::Features(x))) if x.to_string() == fe.to_string()),
            "{tag}: {e}"
        );
        assert!(
            e.to_string().contains(&format!("line {line}")),
            "{tag}: {e}"
        );
        println!("{tag}: {e}");
    }
    // Malformed tag lines stop at the OBJ reader, with their line.
    for tag in [
        "t crease 2/1/0 0 1",
        "t crease 2/1 0 1 10",
        "t crease 2/1/0 0 x 10",
        "t crease 2/1/0 0 1 sharp",
        "t",
    ] {
        let (obj, line) = grid_obj(tag);
        let e = Mesh::from_obj_str(&obj).expect_err(tag);
        assert!(
            matches!(e, tessgen_runtime::MeshError::Obj { line: Some(l), .. } if l == line),
            "{tag}: {e:?}"
        );
        assert!(
            e.to_string().contains(&format!("line {line}")),
            "{tag}: {e}"
        );
        println!("{tag}: {e}");
    }
}

fn fe_line(e: &FeatureError) -> usize {
    match e {
        FeatureError::UnknownVertex { line, .. }
        | FeatureError::NotAnEdge { line, .. }
        | FeatureError::BadSharpness { line, .. }
        | FeatureError::WrongCounts { line, .. }
        | FeatureError::HoleOutOfRange { line, .. }
        | FeatureError::BadBoundaryRule { line, .. } => *line,
    }
}

/// Holes (`t hole`): the hole faces emit no grid, every other face keeps
/// its grid bit for bit (a hole's vertices still shape its neighbours, as
/// in OpenSubdiv), the grids name their base faces, and the welded result
/// is open exactly along the true boundary and the holes' edges.
#[test]
fn hole_faces_emit_nothing_and_change_no_neighbour() {
    let name = "catmark_single_crease";
    let plain = common::mesh(name);
    // Two holes on the crease line's faces and one at the mesh boundary.
    let holes = [20u32, 21, 0];
    let mut holed = plain.clone();
    holed.tags.push(tessgen_runtime::mesh::Tag {
        name: "hole".into(),
        ints: holes.iter().map(|&f| i64::from(f)).collect(),
        ..Default::default()
    });
    let topo_h = topo(&holed);
    assert_eq!(topo_h.no_limit.iter().filter(|&&n| n).count(), holes.len());
    let mut session = Session::new();
    for backend in [Backend::Cpu, Backend::Wgpu, Backend::VulkanGlsl] {
        for scheme in ["pccm", "gregory"] {
            let req = Request::uniform(scheme, LEVEL).on(backend);
            let full = session.tessellate(&plain, &req).expect("plain");
            let out = session.tessellate(&holed, &req).expect("holed");
            let (Some(a), Some(b)) = (full.grid(), out.grid()) else {
                panic!("grid outputs");
            };
            assert_eq!(b.faces, a.faces - holes.len(), "{backend:?} {scheme}");
            let per = b.grid_len();
            for g in 0..b.faces {
                let f = b.face_of(g);
                assert!(
                    !holes.contains(&(f as u32)),
                    "{backend:?} {scheme}: hole {f} drawn"
                );
                assert_eq!(
                    &b.positions[g * per..(g + 1) * per],
                    &a.positions[f * per..(f + 1) * per],
                    "{backend:?} {scheme}: face {f} changed by the holes"
                );
            }
            let r = out.weld();
            let boundary = out.boundary_open_edges(&topo_h);
            assert!(boundary > LEVEL as usize * topo(&plain).num_boundary_edges());
            assert_eq!(r.cracks(boundary), 0, "{backend:?} {scheme}: {r:?}");
            assert_eq!(r.open_edges, boundary, "{backend:?} {scheme}");
            assert_eq!((r.overused_edges, r.degenerate_triangles), (0, 0));
        }
    }
    // Adaptive tessellation leaves them out too, on every adaptive path
    // (CPU and wgpu instanced grids, the hardware tessellator's capture):
    // the same result as without the holes, minus the hole faces' patches.
    let req = |backend| common::random_adaptive("pccm", 1, 1.0, 4.0, 8.0).on(backend);
    for backend in [Backend::Cpu, Backend::Wgpu, Backend::VulkanGlsl] {
        let req = req(backend);
        let v = req.validate(&holed).expect("holed adaptive");
        let drop = v.topology().expect("quads").no_limit.clone();
        assert!(drop.iter().filter(|&&d| d).count() >= holes.len());
        let full = session.tessellate(&plain, &req).expect("plain adaptive");
        let out = session.run(&v).expect("holed adaptive");
        match (&full, &out) {
            (Output::Instanced(a), Output::Instanced(b)) => {
                let mut kept = a.clone();
                kept.retain_faces(&drop.iter().map(|&d| !d).collect::<Vec<_>>());
                assert_eq!(&kept, b, "{backend:?}: holed adaptive != plain minus holes");
                assert!((0..b.levels.len()).all(|g| !drop[b.face_of(g)]));
            }
            (Output::Captured(a), Output::Captured(b)) => {
                assert_eq!(a.patches.len(), b.patches.len());
                for (f, (pa, pb)) in a.patches.iter().zip(&b.patches).enumerate() {
                    if drop[f] {
                        assert!(pb.triangles.is_empty(), "{backend:?}: hole {f} drawn");
                    } else {
                        assert_eq!(pa, pb, "{backend:?}: face {f} changed by the holes");
                    }
                }
            }
            _ => panic!("{backend:?}: unexpected adaptive outputs"),
        }
        let r = out.weld();
        let boundary = v.expected_open_edges(&out);
        let plain_boundary = req
            .validate(&plain)
            .expect("plain")
            .expected_open_edges(&full);
        assert!(boundary > plain_boundary, "{backend:?}: {boundary}");
        assert_eq!(r.cracks(boundary), 0, "{backend:?}: {r:?}");
        assert_eq!(r.open_edges, boundary, "{backend:?}");
        assert_eq!(r.overused_edges, 0, "{backend:?}");
    }
}
