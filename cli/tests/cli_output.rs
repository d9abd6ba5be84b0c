//! The CLI's output formats: `tessellate --out X.glb|X.ply` (welded binary
//! meshes, streamed) and `compare --heatmap` (PNG heat maps).

mod common;

use common::*;

/// `--out` ending in `.glb` or `.ply` writes a welded binary mesh (the
/// extension chooses): streamed without `--check-watertight` to the same
/// bytes as the whole result written with it, uniform and adaptive, and a
/// file the size its header says (the closed cube at level 4: 6·4² + 2
/// welded vertices, 6·32 triangles).
#[test]
fn tessellate_writes_glb_and_ply_by_extension() {
    let tmp = TempDir::new("tess-binary");
    let cube = mesh("catmark_cube.obj");
    for ext in ["glb", "ply"] {
        for adaptive in [false, true] {
            let run = |check: bool| {
                let out = tmp.path().join(format!("cube-{adaptive}-{check}.{ext}"));
                let mut args: Vec<std::ffi::OsString> = vec![
                    "tessellate".into(),
                    cube.clone().into(),
                    "--scheme".into(),
                    "pccm".into(),
                    "--out".into(),
                    out.clone().into(),
                ];
                if adaptive {
                    args.extend([
                        "--adaptive".into(),
                        "random:7:1:8".into(),
                        "--max-factor".into(),
                        "8".into(),
                    ]);
                } else {
                    args.extend(["--level".into(), "4".into()]);
                }
                if check {
                    args.push("--check-watertight".into());
                }
                let o = tessgen(args);
                assert_ok(&o);
                std::fs::read(&out).unwrap()
            };
            let (streamed, whole) = (run(false), run(true));
            assert!(
                streamed == whole,
                "{ext} adaptive={adaptive}: streamed differs"
            );
            if !adaptive {
                match ext {
                    "glb" => {
                        assert_eq!(&streamed[..4], b"glTF");
                        let len = u32::from_le_bytes([
                            streamed[8],
                            streamed[9],
                            streamed[10],
                            streamed[11],
                        ]);
                        assert_eq!(len as usize, streamed.len());
                    }
                    _ => {
                        let text = String::from_utf8_lossy(&streamed[..400]);
                        assert!(text.contains("element vertex 98\n"), "{text}");
                        assert!(text.contains("element face 192\n"), "{text}");
                    }
                }
            }
        }
    }
}

/// `compare --heatmap`: two PNGs per scheme (distance, normal) of the asked
/// size, the surface drawn (pixels neither background white nor the bar's
/// column), one colour range for all schemes; the Markdown table still
/// prints.
#[test]
fn compare_writes_heat_maps() {
    let tmp = TempDir::new("heatmap");
    let cube = mesh("catmark_cube.obj");
    let reference = common::data("cc_limit");
    let out = tmp.path().join("cube.png");
    let o = tessgen([
        "compare".as_ref(),
        cube.as_os_str(),
        "--schemes".as_ref(),
        "pccm,acc".as_ref(),
        "--reference".as_ref(),
        reference.as_os_str(),
        "--heatmap".as_ref(),
        out.as_os_str(),
        "--size".as_ref(),
        "200x150".as_ref(),
    ]);
    assert_ok(&o);
    assert!(stdout(&o).contains("| catmark_cube | acc |"), "{}", all(&o));
    let mut ranges = Vec::new();
    for name in [
        "cube_pccm.png",
        "cube_pccm_normal.png",
        "cube_acc.png",
        "cube_acc_normal.png",
    ] {
        let img = image::open(tmp.path().join(name)).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (200, 150), "{name}");
        let drawn = img
            .enumerate_pixels()
            .filter(|(x, _, p)| *x < 200 - 96 && p.0 != [255, 255, 255])
            .count();
        assert!(drawn > 2000, "{name}: {drawn} surface pixels");
        ranges.push(name);
    }
    // One range per measure: both schemes' distance maps name the same max.
    let e = stderr(&o);
    let maxes: Vec<&str> = e
        .lines()
        .filter(|l| l.contains("heat map") && !l.contains("_normal"))
        .map(|l| {
            l.split("(0 .. ")
                .nth(1)
                .unwrap_or("")
                .split(')')
                .next()
                .unwrap_or("")
        })
        .collect();
    assert_eq!(maxes.len(), 2, "{e}");
    assert_eq!(maxes[0], maxes[1], "{e}");
}
