//! Adaptive tessellation *drawn*, GPU-driven: `GpuMesh::render_adaptive`
//! runs the classify / count / plan / scatter passes, whose plan pass also
//! writes `draw_indexed_indirect` arguments per bucket slot, then one
//! indirect draw of the generated `eval_adaptive_indirect_vs` per slot —
//! the host never reads the buckets back.
//!
//! The crack check is a picture from *inside* a closed surface (the camera
//! at the centre of `catmark_cube`, whose limit surface encloses it): every
//! pixel must be covered by the surface, so one background pixel is a hole
//! in the rasterized surface. With random per-edge factors (levels 1 … 16)
//! no background pixel shows, for a quad scheme, a triangle scheme on the
//! split cube, and the displaced cube with a texture seam on every edge;
//! per-face levels (the negative control: the two sides of an edge at
//! different levels, as a per-patch LOD gives them) show the background
//! through the T-junction cracks.

mod common;

use common::displacement;
use glam::Vec3;
use tessgen_runtime::adaptive::{self, Adaptive, Metric, Partitioning};
use tessgen_runtime::displace::Ownership;
use tessgen_runtime::gpu::{Gpu, GpuMesh};
use tessgen_runtime::render::{Camera, Image, RenderOptions};
use tessgen_runtime::{cpu, Mesh, Topology};

const SEED: u64 = 0x5eed_0a11;
const MAX_LEVEL: u32 = 16;
const BACKGROUND: [u8; 3] = [255, 0, 255];

fn positions(mesh: &Mesh) -> Vec<Vec3> {
    mesh.positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect()
}

/// Cameras inside the surface, off the centre (a crack that only bulges
/// radially is edge-on from the centre), 100° field of view, looking
/// along a few directions: every view ray leaves the closed surface.
fn inside_views(mesh: &Mesh) -> Vec<RenderOptions> {
    let p = positions(mesh);
    let lo = p.iter().fold(Vec3::splat(f32::MAX), |a, b| a.min(*b));
    let hi = p.iter().fold(Vec3::splat(f32::MIN), |a, b| a.max(*b));
    let centre = 0.5 * (lo + hi);
    let eye = centre + 0.12 * (hi - lo) * Vec3::new(1.0, -0.8, 0.6);
    [
        Vec3::new(1.0, 0.3, 0.2),
        Vec3::new(-0.4, 1.0, -0.7),
        Vec3::new(-1.0, -0.5, 0.4),
    ]
    .into_iter()
    .map(|d| RenderOptions {
        level: 1,
        width: 192,
        height: 192,
        camera: Camera {
            eye,
            target: eye + d,
            up: Vec3::new(0.0, 0.0, 1.0),
            fov_y: 100.0,
        },
        background: [1.0, 0.0, 1.0, 1.0],
        wireframe: false,
    })
    .collect()
}

fn random(edges: u32) -> Adaptive {
    Adaptive {
        metric: Metric::Buffer(adaptive::random_factors(edges, SEED, 1.0, 16.0)),
        partitioning: Partitioning::Integer,
        min: 1.0,
        max: MAX_LEVEL as f32,
    }
}

/// One factor per face (on each of its edges), 1 and 16 by turns: the two
/// sides of an edge between faces of different parity disagree, as a
/// per-patch LOD would make them.
fn per_face(faces: usize, sides: usize) -> Adaptive {
    let factors: Vec<f32> = (0..faces)
        .flat_map(|f| vec![if f % 2 == 0 { 1.0 } else { 16.0 }; sides])
        .collect();
    Adaptive {
        metric: Metric::PerFaceEdge(factors),
        ..random(1)
    }
}

fn holes(images: &[Image]) -> usize {
    images.iter().map(|i| i.count_color(BACKGROUND, 0)).sum()
}

#[test]
fn rendered_adaptive_quads_have_no_holes() {
    let gpu = Gpu::new().expect("adapter");
    let mesh = common::mesh("catmark_cube");
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let g = GpuMesh::new(&gpu, &topo, &positions(&mesh), "pccm").expect("gpu mesh");
    let (_, edges) = adaptive::edge_ids(&topo);
    let render = |a: &Adaptive| -> Vec<Image> {
        inside_views(&mesh)
            .iter()
            .map(|o| g.render_adaptive(o, &topo, a, MAX_LEVEL).expect("render"))
            .collect()
    };
    let ok = render(&random(edges));
    let bad = render(&per_face(topo.corners.len(), 4));
    println!(
        "| pccm | wgpu render, inside catmark_cube | random [1, 16] | {} background pixels | per-face levels: {} |",
        holes(&ok),
        holes(&bad)
    );
    assert_eq!(holes(&ok), 0, "holes in the adaptive surface");
    assert!(holes(&bad) > 0, "per-face levels showed no crack");
    // Something was drawn in colour (lit surface), not a cleared image.
    for img in &ok {
        assert!(img.count_color([255, 255, 255], 0) < (img.width * img.height) as usize);
    }
}

#[test]
fn rendered_adaptive_triangles_have_no_holes() {
    let gpu = Gpu::new().expect("adapter");
    let mesh = common::mesh("catmark_cube");
    let tri = cpu::tri_mesh(&mesh, true, None).expect("split");
    let g = GpuMesh::new_tri(&gpu, &tri, "pn").expect("gpu mesh");
    let (_, edges) = tri.edge_ids();
    let render = |a: &Adaptive| -> Vec<Image> {
        inside_views(&mesh)
            .iter()
            .map(|o| g.render_adaptive(o, &tri, a, MAX_LEVEL).expect("render"))
            .collect()
    };
    let ok = render(&random(edges));
    let bad = render(&per_face(tri.triangles.len(), 3));
    println!(
        "| pn | wgpu render, inside catmark_cube split | random [1, 16] | {} background pixels | per-face levels: {} |",
        holes(&ok),
        holes(&bad)
    );
    assert_eq!(holes(&ok), 0, "holes in the adaptive surface");
    assert!(holes(&bad) > 0, "per-face levels showed no crack");
}

/// Displaced across a texture seam on every edge: ownership keeps the
/// drawn surface closed; per-patch ownership opens it.
#[test]
fn rendered_adaptive_displaced_cube_has_no_holes() {
    let gpu = Gpu::new().expect("adapter");
    let mesh = common::mesh("catmark_cube_uv");
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let (_, edges) = adaptive::edge_ids(&topo);
    let render = |ownership| -> Vec<Image> {
        let d = displacement(ownership, 0.3);
        let g = GpuMesh::new_displaced(&gpu, &mesh, &topo, &positions(&mesh), "pccm", &d)
            .expect("gpu mesh");
        inside_views(&mesh)
            .iter()
            .map(|o| {
                g.render_adaptive(o, &topo, &random(edges), MAX_LEVEL)
                    .expect("render")
            })
            .collect()
    };
    let ok = render(Ownership::LowestFace);
    let bad = render(Ownership::PerPatch);
    println!(
        "| pccm displaced | wgpu render, inside catmark_cube_uv | random [1, 16] | {} background pixels | per-patch ownership: {} |",
        holes(&ok),
        holes(&bad)
    );
    assert_eq!(holes(&ok), 0, "holes in the displaced adaptive surface");
    assert!(holes(&bad) > 0, "per-patch ownership showed no crack");
}

/// Hole faces (`t hole`) are built (their points shape the neighbours) but
/// not drawn, uniform and adaptive: from inside the cube the background
/// shows through exactly where a hole is, and nowhere without one.
#[test]
fn rendered_hole_faces_show_the_background() {
    use tessgen_runtime::tessellate::Request;
    let gpu = Gpu::new().expect("adapter");
    let plain = common::mesh("catmark_cube");
    let mut holed = plain.clone();
    holed.tags.push(tessgen_runtime::mesh::Tag {
        name: "hole".into(),
        ints: vec![0],
        ..Default::default()
    });
    // Six views along the axes: one of them faces the hole.
    let mut views = inside_views(&plain);
    let base = views[0];
    views = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z]
        .into_iter()
        .map(|d| {
            let mut o = base;
            o.camera.target = o.camera.eye + d;
            o.camera.up = if d.z == 0.0 { Vec3::Z } else { Vec3::X };
            o.level = 8;
            o
        })
        .collect();
    let draw = |mesh: &Mesh| -> (Vec<Image>, Vec<Image>) {
        let req = Request::uniform("pccm", 8);
        let v = req.validate(mesh).expect("validate");
        let topo = v.topology().expect("quads");
        let g = GpuMesh::new(&gpu, topo, &positions(mesh), "pccm").expect("gpu mesh");
        let (_, edges) = adaptive::edge_ids(topo);
        let uniform = views.iter().map(|o| g.render(o).expect("render")).collect();
        let adaptive = views
            .iter()
            .map(|o| {
                g.render_adaptive(o, topo, &random(edges), MAX_LEVEL)
                    .expect("render")
            })
            .collect();
        (uniform, adaptive)
    };
    let (u0, a0) = draw(&plain);
    let (u1, a1) = draw(&holed);
    println!(
        "| pccm | inside catmark_cube, face 0 a hole | background pixels: uniform {} → {}, adaptive {} → {} |",
        holes(&u0),
        holes(&u1),
        holes(&a0),
        holes(&a1)
    );
    assert_eq!(
        (holes(&u0), holes(&a0)),
        (0, 0),
        "closed cube shows background"
    );
    // The hole is about one sixth of the surface: most of one view.
    let frame = (base.width * base.height) as usize;
    assert!(holes(&u1) > frame / 4, "uniform: the hole face was drawn");
    assert!(holes(&a1) > frame / 4, "adaptive: the hole face was drawn");
}
