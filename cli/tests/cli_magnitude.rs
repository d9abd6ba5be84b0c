//! A mesh too large for f32 evaluation (the reliability issue's cube with a
//! vertex at 1e30, which used to exit 0 with `nan` lines): exit 1, a message
//! naming the vertex, and no output file.

mod common;
use common::*;

#[test]
fn a_vertex_at_1e30_is_refused_and_nothing_is_written() {
    let tmp = TempDir::new("magnitude");
    let text = std::fs::read_to_string(mesh("catmark_cube.obj")).expect("cube");
    let mut first = true;
    let far: String = text
        .lines()
        .map(|l| {
            if first && l.starts_with("v ") {
                first = false;
                "v 1e30 1e30 1e30".to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let input = tmp.path().join("far.obj");
    std::fs::write(&input, far).expect("write");
    let out = tmp.path().join("out.obj");
    for backend in ["cpu", "wgpu"] {
        let o = tessgen([
            "tessellate".as_ref(),
            input.as_os_str(),
            "--scheme".as_ref(),
            "pccm".as_ref(),
            "--level".as_ref(),
            "4".as_ref(),
            "--backend".as_ref(),
            backend.as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        assert_exit(&o, 1);
        let e = stderr(&o);
        assert!(e.contains("vertex 0 at (1e30, 1e30, 1e30)"), "{e}");
        assert!(e.contains("too large to evaluate in f32"), "{e}");
        assert!(!out.exists(), "{backend}: wrote {}", out.display());
    }
}
