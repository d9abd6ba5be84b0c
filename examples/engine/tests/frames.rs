//! The engine example's frame loop runs (on lavapipe in CI): every frame
//! submits, the surface lands in the engine's target (pixels off the white
//! clear colour), and the samples per frame are the mesh's grids.

#[test]
fn the_frame_loop_draws_the_surface() {
    let obj = include_str!("../../../tests/data/meshes/catmark_cube.obj");
    let r = tessgen_example_engine::run(obj, "pccm", 8, 3, (160, 120)).expect("frame loop");
    assert_eq!(r.frame_ms.len(), 3);
    assert_eq!(r.samples_per_frame, 6 * 81);
    assert_eq!(r.pixels.len(), 160 * 120 * 4);
    let drawn = r
        .pixels
        .chunks_exact(4)
        .filter(|p| p[..3] != [255, 255, 255])
        .count();
    assert!(drawn > 1000, "{drawn} pixels of surface");
}
