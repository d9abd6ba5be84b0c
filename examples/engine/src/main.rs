//! `cargo run -p tessgen-example-engine [MESH.obj] [LEVEL] [FRAMES]`: the
//! frame loop of `lib.rs`, its frame times printed.

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let path = args.next().unwrap_or_else(|| {
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/data/meshes/catmark_cube.obj"
        )
        .into()
    });
    let level = args.next().and_then(|s| s.parse().ok()).unwrap_or(16);
    let frames = args.next().and_then(|s| s.parse().ok()).unwrap_or(60);
    let obj = std::fs::read_to_string(&path).map_err(|e| format!("{path}: {e}"))?;
    let r = tessgen_example_engine::run(&obj, "pccm", level, frames, (640, 480))?;
    let mut ms = r.frame_ms.clone();
    ms.sort_by(f64::total_cmp);
    println!(
        "{}: {frames} frames of {} samples at level {level}: median {:.2} ms, min {:.2} ms; {} pipelines after the first frame, {} at the end",
        r.adapter,
        r.samples_per_frame,
        ms[ms.len() / 2],
        ms[0],
        r.pipelines.0,
        r.pipelines.1
    );
    Ok(())
}
