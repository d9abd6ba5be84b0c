//! Headless rendering on the test adapter (lavapipe in CI).
//!
//! The reference image `tests/data/render/catmark_cube_l8.png` was rendered
//! by this test on Mesa's lavapipe. To refresh it after an intended change,
//! run `TESSGEN_UPDATE_REFERENCE=1 cargo test -p tessgen-tests --test render`,
//! look at the new PNG, and commit it.

mod common;

use glam::Vec3;
use tessgen_runtime::gpu::{Gpu, GpuMesh};
use tessgen_runtime::render::{Camera, Image, RenderOptions};
use tessgen_runtime::{cpu, Topology};

const ORANGE: [u8; 3] = [255, 140, 26];

fn render(gpu: &Gpu, name: &str, level: u32, w: u32, h: u32, wireframe: bool) -> Image {
    let mesh = common::mesh(name);
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let positions: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for p in &positions {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let g = GpuMesh::new(gpu, &topo, &positions, "pccm").expect("gpu mesh");
    let opts = RenderOptions {
        level,
        width: w,
        height: h,
        camera: Camera::framing(lo, hi, Vec3::new(0.57, 0.42, 0.7)),
        background: [1.0, 1.0, 1.0, 1.0],
        wireframe,
    };
    g.render(&opts).expect("render")
}

#[test]
fn cube_matches_reference_image() {
    let gpu = Gpu::new().expect("adapter");
    let img = render(&gpu, "catmark_cube", 8, 256, 256, false);
    let path = common::data("render/catmark_cube_l8.png");
    if std::env::var_os("TESSGEN_UPDATE_REFERENCE").is_some() {
        img.save_png(&path).expect("write reference");
    }
    let reference =
        Image::load_png(&path).expect("reference image (see the module docs to refresh it)");
    assert_eq!((img.width, img.height), (reference.width, reference.height));
    let bad = img.count_differing(&reference, 12);
    let total = (img.width * img.height) as usize;
    println!("cube level 8: {bad} of {total} pixels differ by more than 12/255");
    // Rasterisation details may move a few edge pixels between drivers.
    assert!(
        bad * 200 <= total,
        "{bad} of {total} pixels differ from the reference"
    );
    // The cube is all extraordinary (valence 3): blue, some lit, on white.
    assert!(
        img.count_color([255, 255, 255], 0) > total / 4,
        "background"
    );
    assert_eq!(
        img.count_color(ORANGE, 60),
        0,
        "no ordinary patch on the cube"
    );
}

#[test]
fn righthanded_shows_both_patch_colours() {
    let gpu = Gpu::new().expect("adapter");
    let img = render(&gpu, "catmark_righthanded", 6, 320, 240, false);
    // Lit colours vary; match hue loosely: orange = red high, blue low; blue = blue high, red low.
    let (mut orange, mut blue) = (0, 0);
    for p in img.rgba.chunks_exact(4) {
        let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
        if r > b + 60 && r > g {
            orange += 1;
        }
        if b > r + 60 && b > g {
            blue += 1;
        }
    }
    println!("righthanded: {orange} orange-ish and {blue} blue-ish pixels");
    assert!(orange > 500, "ordinary (orange) patches missing: {orange}");
    assert!(blue > 500, "extraordinary (blue) patches missing: {blue}");
}

#[test]
fn wireframe_darkens_patch_boundaries() {
    let gpu = Gpu::new().expect("adapter");
    let plain = render(&gpu, "catmark_righthanded", 6, 320, 240, false);
    let wire = render(&gpu, "catmark_righthanded", 6, 320, 240, true);
    let dark = |img: &Image| {
        img.rgba
            .chunks_exact(4)
            .filter(|p| p[0] < 50 && p[1] < 50 && p[2] < 60)
            .count()
    };
    let (a, b) = (dark(&plain), dark(&wire));
    println!("dark pixels: plain {a}, wireframe {b}");
    assert!(
        b > a + 500,
        "wireframe adds no dark boundary pixels ({a} → {b})"
    );
}
