//! The engine example's frame loop on lavapipe in CI: 100 frames of an
//! animated mesh (the control mesh moves every frame, so the patches are
//! rebuilt on the GPU every frame), no pipeline created after the first
//! frame, the surface in the engine's target (pixels off the white clear
//! colour), the samples per frame the mesh's grids; the frame times are
//! printed (`cargo test -p tessgen-example-engine -- --nocapture`).

#[test]
fn a_hundred_animated_frames_create_no_pipeline_after_the_first() {
    let obj = include_str!("../../../tests/data/meshes/catmark_cube.obj");
    let r = tessgen_example_engine::run(obj, "pccm", 8, 100, (160, 120)).expect("frame loop");
    assert_eq!(r.frame_ms.len(), 100);
    let (after_first, at_end) = r.pipelines;
    assert!(after_first > 0, "the first frame's pipelines are counted");
    assert_eq!(
        at_end, after_first,
        "pipelines created after the first frame"
    );
    assert_eq!(r.samples_per_frame, 6 * 81);
    assert_eq!(r.pixels.len(), 160 * 120 * 4);
    let drawn = r
        .pixels
        .chunks_exact(4)
        .filter(|p| p[..3] != [255, 255, 255])
        .count();
    assert!(drawn > 1000, "{drawn} pixels of surface");
    let mut ms = r.frame_ms.clone();
    ms.sort_by(f64::total_cmp);
    println!(
        "{}: 100 frames of {} samples, median {:.2} ms, min {:.2} ms, {} pipelines",
        r.adapter, r.samples_per_frame, ms[50], ms[0], at_end
    );
}
