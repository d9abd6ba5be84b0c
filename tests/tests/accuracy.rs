//! `tessgen compare`'s measurements: distance and normal deviation from the
//! exact Catmull-Clark limit, boundary smoothness, watertightness.

mod common;

use tessgen_runtime::accuracy::{compare, LimitError, LimitSamples};

#[test]
fn torus_schemes_are_the_limit_and_cube_is_close() {
    let torus = common::mesh("catmark_torus");
    let lim = LimitSamples::load(common::data("cc_limit/catmark_torus.bin")).expect("limit");
    for scheme in ["regular", "pccm"] {
        let a = compare(&torus, scheme, 8, Some(&lim)).expect("compare");
        let d = a.max_distance_pct.unwrap_or(f64::MAX);
        assert!(
            d < 1e-4,
            "{scheme}: {d} % of the quad size on the regular torus"
        );
        assert_eq!(a.open_edges, 0);
    }
    let cube = common::mesh("catmark_cube");
    let lim = LimitSamples::load(common::data("cc_limit/catmark_cube.bin")).expect("limit");
    let a = compare(&cube, "pccm", 8, Some(&lim)).expect("compare");
    let d = a.max_distance_pct.unwrap_or(f64::MAX);
    // c-patches approximate CC near valence-3 vertices: a few percent, not zero.
    assert!(d > 0.1 && d < 10.0, "cube distance {d} %");
    assert!(a.max_boundary_normal_spread_deg < 0.01);
    assert_eq!(a.open_edges, 0);
    // Without a reference only smoothness and watertightness are measured.
    let a = compare(&cube, "pccm", 4, None).expect("compare");
    assert!(a.max_distance_pct.is_none());
}

#[test]
fn bad_limit_files_are_typed_errors() {
    let dir = std::env::temp_dir().join(format!("tessgen-accuracy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let bad = dir.join("bad.bin");
    std::fs::write(&bad, b"NOTCCLIM and some more bytes to be long enough....").expect("write");
    assert!(matches!(
        LimitSamples::load(&bad),
        Err(LimitError::Format { .. })
    ));
    let mut short = std::fs::read(common::data("cc_limit/catmark_cube.bin")).expect("read");
    short.truncate(100);
    std::fs::write(&bad, &short).expect("write");
    assert!(matches!(
        LimitSamples::load(&bad),
        Err(LimitError::Format { .. })
    ));
    assert!(matches!(
        LimitSamples::load(dir.join("missing.bin")),
        Err(LimitError::Io { .. })
    ));
    let _ = std::fs::remove_dir_all(&dir);
}
