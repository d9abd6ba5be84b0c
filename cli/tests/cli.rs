//! End-to-end tests of the `tessgen` binary.

use std::path::Path;

mod common;
use common::*;

#[test]
fn version_and_help() {
    let o = tessgen(["--version"]);
    assert_ok(&o);
    assert!(stdout(&o).starts_with("tessgen "), "{}", stdout(&o));
    let o = tessgen(["--help"]);
    assert_ok(&o);
    for cmd in ["generate", "table", "inspect", "tessellate"] {
        assert!(stdout(&o).contains(cmd), "{}", stdout(&o));
        let o = tessgen([cmd, "--help"]);
        assert_ok(&o);
        assert!(stdout(&o).contains("Usage: tessgen"), "{}", stdout(&o));
    }
    assert_exit(&tessgen(["no-such-command"]), 2);
}

#[test]
fn generate_then_check() {
    let tmp = TempDir::new("generate");
    let dir = tmp.path().join("out");
    let d = dir.to_str().unwrap();
    let o = tessgen(["generate", "--out", d]);
    assert_ok(&o);
    let header = std::fs::read_to_string(dir.join("rust/tessgen.rs")).unwrap();
    assert!(
        header.contains("Command: tessgen generate --out generated\n"),
        "{}",
        &header[..header.len().min(300)]
    );
    assert!(dir.join("table/stencils.f32").is_file());
    assert!(dir.join("table/stencils.json").is_file());

    let o = tessgen(["generate", "--check", "--out", d]);
    assert_ok(&o);
    assert!(stdout(&o).contains("is up to date ("), "{}", all(&o));

    // The README is generated too: editing it by hand is drift.
    let readme = dir.join("README.md");
    let good_readme = std::fs::read(&readme).unwrap();
    std::fs::write(&readme, "hand-written\n").unwrap();
    assert_exit(&tessgen(["generate", "--check", "--out", d]), 1);
    std::fs::write(&readme, &good_readme).unwrap();
    assert_ok(&tessgen(["generate", "--check", "--out", d]));

    // One byte changed.
    let table = dir.join("table/stencils.f32");
    let good = std::fs::read(&table).unwrap();
    let mut bad = good.clone();
    bad[100] ^= 1;
    std::fs::write(&table, &bad).unwrap();
    let o = tessgen(["generate", "--check", "--out", d]);
    assert_exit(&o, 1);
    assert!(all(&o).contains("differs"), "{}", all(&o));
    assert!(all(&o).contains("stencils.f32"), "{}", all(&o));
    assert!(!all(&o).contains("tessgen.rs"), "{}", all(&o));

    // Regenerating repairs it; then a removed file fails.
    assert_ok(&tessgen(["generate", "--out", d]));
    assert_eq!(std::fs::read(&table).unwrap(), good);
    std::fs::remove_file(dir.join("rust/tessgen.rs")).unwrap();
    let o = tessgen(["generate", "--check", "--out", d]);
    assert_exit(&o, 1);
    assert!(all(&o).contains("missing"), "{}", all(&o));
    assert!(all(&o).contains("tessgen.rs"), "{}", all(&o));

    // A file that is not generated fails too.
    assert_ok(&tessgen(["generate", "--out", d]));
    std::fs::write(dir.join("rust/old.rs"), "stale").unwrap();
    let o = tessgen(["generate", "--check", "--out", d]);
    assert_exit(&o, 1);
    assert!(all(&o).contains("old.rs"), "{}", all(&o));
}

#[test]
fn generate_records_non_default_options() {
    let tmp = TempDir::new("generate-options");
    let d = tmp.path().to_str().unwrap();
    let o = tessgen(["generate", "--out", d, "--max-valence", "8"]);
    assert_ok(&o);
    let rust = std::fs::read_to_string(tmp.path().join("rust/tessgen.rs")).unwrap();
    assert!(rust.contains("Command: tessgen generate --out generated --max-valence 8\n"));
    // The check must use the same options to pass.
    assert_ok(&tessgen([
        "generate",
        "--check",
        "--out",
        d,
        "--max-valence",
        "8",
    ]));
    assert_exit(&tessgen(["generate", "--check", "--out", d]), 1);
}

#[test]
fn generate_reports_bad_scheme_files() {
    let tmp = TempDir::new("scheme-file");
    let d = tmp.path().join("out");
    let missing = tmp.path().join("missing.tess");
    let o = tessgen([
        "generate".as_ref(),
        "--out".as_ref(),
        d.as_os_str(),
        "--scheme-file".as_ref(),
        missing.as_os_str(),
    ]);
    assert_exit(&o, 1);
    assert!(stderr(&o).contains("missing.tess"), "{}", all(&o));

    let broken = tmp.path().join("broken.tess");
    std::fs::write(&broken, "scheme broken {\n  facet quad;\n  oops\n}\n").unwrap();
    let o = tessgen([
        "generate".as_ref(),
        "--out".as_ref(),
        d.as_os_str(),
        "--scheme-file".as_ref(),
        broken.as_os_str(),
    ]);
    assert_exit(&o, 1);
    assert!(stderr(&o).contains("broken.tess"), "{}", all(&o));
    assert!(!d.exists(), "nothing is written when compilation fails");
}

#[test]
fn table_writes_both_files() {
    let tmp = TempDir::new("table");
    let dir = tmp.path().join("t");
    let o = tessgen(["table", "--out", dir.to_str().unwrap()]);
    assert_ok(&o);
    let bytes = std::fs::metadata(dir.join("stencils.f32")).unwrap().len();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("stencils.json")).unwrap()).unwrap();
    let height = json["height"].as_u64().unwrap();
    let width = json["width"].as_u64().unwrap();
    // The file is the texture: the logical rows wrapped into column blocks
    // of block_rows, zero-padded in the last block.
    let (tw, th, b) = (
        json["texture_width"].as_u64().unwrap(),
        json["texture_height"].as_u64().unwrap(),
        json["block_rows"].as_u64().unwrap(),
    );
    assert_eq!(tw * th * 4, bytes);
    assert_eq!(b, 4096);
    assert_eq!(tw, width * height.div_ceil(b));
    assert_eq!(th, height.min(b));
    assert_eq!(json["max_valence"], 32);
    // 65 ring slots, then the sector region (2·16 + 2 partial-ring slots).
    assert_eq!(width, 99);
    assert_eq!(json["sector_column"], 65);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);

    let o = tessgen([
        "table",
        "--out",
        dir.to_str().unwrap(),
        "--max-valence",
        "5",
    ]);
    assert_ok(&o);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("stencils.json")).unwrap()).unwrap();
    // 11 ring slots + sectors of up to 5 / 2 = 2 faces (6 slots).
    assert_eq!(json["width"], 17);
    assert_exit(
        &tessgen([
            "table",
            "--out",
            dir.to_str().unwrap(),
            "--max-valence",
            "3",
        ]),
        2,
    );
}

#[test]
fn inspect_cube() {
    let o = tessgen(["inspect".as_ref(), mesh("catmark_cube.obj").as_os_str()]);
    assert_ok(&o);
    let out = stdout(&o);
    assert!(out.contains("valence: 3:8\n"), "{out}");
    assert!(out.contains("eqs 1.000"), "{out}");
    assert!(out.contains("vertices: 8"), "{out}");
    assert!(out.contains("faces: 6 (6 quads, 0 non-quads)"), "{out}");
    assert!(out.contains("euler characteristic: 2"), "{out}");
    assert!(out.contains("topology: ok"), "{out}");

    let o = tessgen([
        "inspect".as_ref(),
        "--json".as_ref(),
        mesh("catmark_cube.obj").as_os_str(),
    ]);
    assert_ok(&o);
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(j["vertices"], 8);
    assert_eq!(j["faces"], 6);
    assert_eq!(j["quads"], 6);
    assert_eq!(j["edges"], 12);
    assert_eq!(j["boundary_edges"], 0);
    assert_eq!(j["euler_characteristic"], 2);
    assert_eq!(j["valence_histogram"], serde_json::json!({"3": 8}));
    assert_eq!(j["extraordinary_fraction"], 1.0);
    assert_eq!(j["topology_ok"], true);
    assert!(j["topology_error"].is_null());
}

#[test]
fn inspect_open_mesh_reports_instead_of_failing() {
    let tent = mesh("catmark_tent.obj");
    let o = tessgen(["inspect".as_ref(), tent.as_os_str()]);
    assert_ok(&o);
    let out = stdout(&o);
    assert!(out.contains("12 boundary"), "{out}");
    assert!(
        out.contains("topology: ok (manifold, quads; 12 boundary edges, 12 sectors)"),
        "{out}"
    );
    assert!(out.contains("interpolateboundary:1"), "{out}");
    assert!(out.contains("boundary rule: 2"), "{out}");
    assert!(out.contains("tessellation: boundaries (rule 2)"), "{out}");

    let o = tessgen(["inspect".as_ref(), "--json".as_ref(), tent.as_os_str()]);
    assert_ok(&o);
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(j["boundary_edges"], 12);
    assert_eq!(j["first_boundary_edges"][0], serde_json::json!([0, 1]));
    assert_eq!(j["euler_characteristic"], 1);
    assert_eq!(j["tags"]["interpolateboundary"], 1);
    assert_eq!(j["topology_ok"], true);
    assert!(j["topology_error"].is_null());
    assert_eq!(j["features"]["boundary_edges"], 12);
    assert_eq!(j["features"]["creases"], 12);
    assert_eq!(
        j["features"]["sectors_by_faces"],
        serde_json::json!({"1": 4, "2": 8})
    );
}

#[test]
fn inspect_unreadable_file_fails() {
    let tmp = TempDir::new("inspect-bad");
    let bad = tmp.path().join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nv 1 2 x\nf 1 2 3\n").unwrap();
    let o = tessgen(["inspect".as_ref(), bad.as_os_str()]);
    assert_exit(&o, 1);
    assert!(stderr(&o).contains("line 3"), "{}", all(&o));
    let o = tessgen(["inspect".as_ref(), tmp.path().join("none.obj").as_os_str()]);
    assert_exit(&o, 1);
    assert!(stderr(&o).contains("none.obj"), "{}", all(&o));
}

fn count_lines(text: &str, prefix: &str) -> usize {
    text.lines().filter(|l| l.starts_with(prefix)).count()
}

#[test]
fn tessellate_cube_pccm() {
    let tmp = TempDir::new("tess");
    let out = tmp.path().join("cube.obj");
    let cube = mesh("catmark_cube.obj");
    let o = tessgen([
        "tessellate".as_ref(),
        cube.as_os_str(),
        "--scheme".as_ref(),
        "pccm".as_ref(),
        "--level".as_ref(),
        "3".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        "--check-watertight".as_ref(),
    ]);
    assert_ok(&o);
    assert!(stderr(&o).contains("6 faces"), "{}", all(&o));
    assert!(stdout(&o).contains("closed 2-manifold"), "{}", all(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(count_lines(&text, "g patch_"), 6);
    assert_eq!(count_lines(&text, "v "), 6 * 16);
    assert_eq!(count_lines(&text, "vn "), 6 * 16);
    assert_eq!(count_lines(&text, "f "), 6 * 18);

    // The output is itself a readable mesh (3·6·18 corners, 96 unwelded vertices).
    let o = tessgen(["inspect".as_ref(), "--json".as_ref(), out.as_os_str()]);
    assert_ok(&o);
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(j["vertices"], 96);
    assert_eq!(j["faces"], 108);
}

#[test]
fn tessellate_wgpu_backend_writes_the_same_format() {
    let tmp = TempDir::new("tess-wgpu");
    let cube = mesh("catmark_righthanded.obj");
    let run = |backend: &str| {
        let out = tmp.path().join(format!("{backend}.obj"));
        let o = tessgen([
            "tessellate".as_ref(),
            cube.as_os_str(),
            "--scheme".as_ref(),
            "pccm".as_ref(),
            "--level".as_ref(),
            "5".as_ref(),
            "--backend".as_ref(),
            backend.as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
            "--check-watertight".as_ref(),
        ]);
        assert_ok(&o);
        assert!(stdout(&o).contains("closed 2-manifold"), "{}", all(&o));
        std::fs::read_to_string(&out).unwrap()
    };
    let cpu = run("cpu");
    // wgpu, and the GLSL and HLSL tessellation shaders on the Vulkan harness.
    for backend in ["wgpu", "glsl", "hlsl"] {
        let gpu = run(backend);
        assert_eq!(cpu.lines().count(), gpu.lines().count(), "{backend}");
        // Same layout line by line: groups, then v, vn and f lines in the same places.
        for (a, b) in cpu.lines().zip(gpu.lines()) {
            assert_eq!(a.split(' ').next(), b.split(' ').next(), "{backend}");
            if a.starts_with("f ") || a.starts_with("g ") {
                assert_eq!(a, b, "{backend}");
            }
        }
    }
}

/// Triangle schemes on the hardware tessellator at a level whose inner
/// rings are not the barycentric lattice: the OBJ holds the tessellator's
/// own triangles (per patch `g`, `v`, `vn`, `f` as for every backend), and
/// welds closed.
#[test]
fn tessellate_triangle_scheme_on_the_hardware_tessellator() {
    let tmp = TempDir::new("tess-tri-hw");
    let cube = mesh("catmark_cube.obj");
    for backend in ["glsl", "hlsl"] {
        let out = tmp.path().join(format!("{backend}.obj"));
        let o = tessgen([
            "tessellate".as_ref(),
            cube.as_os_str(),
            "--scheme".as_ref(),
            "pn".as_ref(),
            "--split-quads".as_ref(),
            "--level".as_ref(),
            "7".as_ref(),
            "--backend".as_ref(),
            backend.as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
            "--check-watertight".as_ref(),
        ]);
        assert_ok(&o);
        assert!(stdout(&o).contains("closed 2-manifold"), "{}", all(&o));
        let text = std::fs::read_to_string(&out).unwrap();
        let count = |p: &str| text.lines().filter(|l| l.starts_with(p)).count();
        // 12 patches; level 7: rings of 7, 5, 3, 1 segments per side,
        // 3·(7+5+3+1) = 48 vertices and 1.5·49 − 0.5 = 73 triangles each.
        assert_eq!(count("g patch_"), 12, "{backend}");
        assert_eq!(count("v "), 12 * 48, "{backend}");
        assert_eq!(count("vn "), 12 * 48, "{backend}");
        assert_eq!(count("f "), 12 * 73, "{backend}");
    }
}

/// `--adaptive`: random per-edge factors and the screen-space metric weld
/// closed through the GLSL and HLSL tessellation shaders and on the
/// instanced path (cpu, wgpu); the output is a triangle soup (3 `v` lines
/// per `f`), streamed without `--check-watertight` to the same bytes; bad metrics and fractional partitioning on the instanced path
/// name what is wrong.
#[test]
fn tessellate_adaptive() {
    let tmp = TempDir::new("tess-adaptive");
    let torus = mesh("catmark_torus.obj");
    let out = tmp.path().join("adaptive.obj");
    let run = |backend: &str, metric: &str, partitioning: &str| {
        tessgen([
            "tessellate".as_ref(),
            torus.as_os_str(),
            "--scheme".as_ref(),
            "pccm".as_ref(),
            "--backend".as_ref(),
            backend.as_ref(),
            "--adaptive".as_ref(),
            metric.as_ref(),
            "--partitioning".as_ref(),
            partitioning.as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
            "--check-watertight".as_ref(),
        ])
    };
    for (backend, metric, partitioning) in [
        ("glsl", "random:7:1:9", "fractional-odd"),
        ("hlsl", "screen:8", "integer"),
    ] {
        let o = run(backend, metric, partitioning);
        assert_ok(&o);
        assert!(stdout(&o).contains("closed 2-manifold"), "{}", all(&o));
        let text = std::fs::read_to_string(&out).unwrap();
        let f = count_lines(&text, "f ");
        assert!(f > 64, "{backend} {metric}: {f} triangles");
        assert_eq!(count_lines(&text, "v "), 3 * f);
    }
    // The CPU and wgpu (the WGSL instanced path): power-of-two buckets with
    // snapped transitions, every metric.
    for (backend, metric) in [
        ("cpu", "random:7"),
        ("cpu", "screen:8"),
        ("wgpu", "random:7"),
        ("wgpu", "distance:24"),
    ] {
        let o = run(backend, metric, "integer");
        assert_ok(&o);
        assert!(stdout(&o).contains("closed 2-manifold"), "{}", all(&o));
        let text = std::fs::read_to_string(&out).unwrap();
        assert_eq!(count_lines(&text, "v "), 3 * count_lines(&text, "f "));
        // Without --check-watertight the CPU streams the soup to disk chunk
        // by chunk (the GPU writes its whole result): the same bytes.
        let streamed = tmp.path().join("streamed.obj");
        let o = tessgen([
            "tessellate".as_ref(),
            torus.as_os_str(),
            "--scheme".as_ref(),
            "pccm".as_ref(),
            "--backend".as_ref(),
            backend.as_ref(),
            "--adaptive".as_ref(),
            metric.as_ref(),
            "--out".as_ref(),
            streamed.as_os_str(),
        ]);
        assert_ok(&o);
        assert!(
            stderr(&o).contains(" triangles (pccm adaptive"),
            "{}",
            all(&o)
        );
        assert!(
            std::fs::read(&streamed).unwrap() == text.as_bytes(),
            "{backend} {metric}: streamed soup differs"
        );
    }
    let o = run("wgpu", "random:7", "fractional-odd");
    assert_ne!(o.status.code(), Some(0));
    assert!(stderr(&o).contains("integer only"), "{}", all(&o));
    let o = run("glsl", "random:x", "integer");
    assert_ne!(o.status.code(), Some(0));
    assert!(stderr(&o).contains("not a seed"), "{}", all(&o));
    let o = run("glsl", "random:1", "fractional");
    assert_ne!(o.status.code(), Some(0));
    assert!(stderr(&o).contains("unknown partitioning"), "{}", all(&o));
    // A factor above the device's maxTessellationGenerationLevel is clamped
    // by the tessellator, and the capture is sized for the clamped one.
    let o = tessgen([
        "tessellate".as_ref(),
        torus.as_os_str(),
        "--scheme".as_ref(),
        "pccm".as_ref(),
        "--backend".as_ref(),
        "glsl".as_ref(),
        "--adaptive".as_ref(),
        "random:1:1:1000".as_ref(),
        "--max-factor".as_ref(),
        "1000".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        "--check-watertight".as_ref(),
    ]);
    assert_ok(&o);
    assert!(stdout(&o).contains("closed 2-manifold"), "{}", all(&o));
}

/// `--adaptive` with triangle schemes (`--split-quads`): per-edge factors
/// through the triangle tessellation shaders and on the instanced path
/// (cpu, wgpu: power-of-two buckets, the triangle grid's snap) weld closed,
/// stpn with its crease tags too.
#[test]
fn tessellate_adaptive_triangle_schemes() {
    let tmp = TempDir::new("tess-adaptive-tri");
    let torus = mesh("catmark_torus.obj");
    let tags = mesh("catmark_torus_crease.tags");
    let out = tmp.path().join("adaptive_tri.obj");
    for (scheme, backend, metric, partitioning, with_tags) in [
        ("stpn", "glsl", "random:7:1:9", "fractional-odd", true),
        ("pn", "hlsl", "screen:8", "integer", false),
        ("pn", "cpu", "random:7", "integer", false),
        ("stpn", "wgpu", "random:7", "integer", true),
        ("phong", "wgpu", "distance:24", "integer", false),
    ] {
        let mut args: Vec<&std::ffi::OsStr> = vec![
            "tessellate".as_ref(),
            torus.as_os_str(),
            "--scheme".as_ref(),
            scheme.as_ref(),
            "--split-quads".as_ref(),
            "--backend".as_ref(),
            backend.as_ref(),
            "--adaptive".as_ref(),
            metric.as_ref(),
            "--partitioning".as_ref(),
            partitioning.as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
            "--check-watertight".as_ref(),
        ];
        if with_tags {
            args.extend(["--tags".as_ref(), tags.as_os_str()]);
        }
        let o = tessgen(args);
        assert_ok(&o);
        assert!(
            stdout(&o).contains("closed 2-manifold"),
            "{scheme} {backend}: {}",
            all(&o)
        );
        let text = std::fs::read_to_string(&out).unwrap();
        let f = count_lines(&text, "f ");
        assert!(f > 64, "{scheme} {backend}: {f} triangles");
        assert_eq!(count_lines(&text, "v "), 3 * f);
    }
}

/// `--scheme stpn --tags FILE`: the creased torus welds closed on every
/// backend; tags for another scheme, and a bad tag line, are errors that
/// name the file and line.
#[test]
fn tessellate_stpn_with_tags() {
    let tmp = TempDir::new("tess-stpn");
    let torus = mesh("catmark_torus.obj");
    let tags = mesh("catmark_torus_crease.tags");
    let out = tmp.path().join("stpn.obj");
    let run = |scheme: &str, backend: &str, tags: &Path| {
        tessgen([
            "tessellate".as_ref(),
            torus.as_os_str(),
            "--scheme".as_ref(),
            scheme.as_ref(),
            "--split-quads".as_ref(),
            "--tags".as_ref(),
            tags.as_os_str(),
            "--level".as_ref(),
            "3".as_ref(),
            "--backend".as_ref(),
            backend.as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
            "--check-watertight".as_ref(),
        ])
    };
    for backend in ["cpu", "wgpu", "glsl", "hlsl"] {
        let o = run("stpn", backend, &tags);
        assert_ok(&o);
        assert!(
            stdout(&o).contains("closed 2-manifold"),
            "{backend}: {}",
            all(&o)
        );
    }
    let o = run("pn", "cpu", &tags);
    assert_exit(&o, 1);
    assert!(stderr(&o).contains("only `stpn` reads them"), "{}", all(&o));
    let bad = tmp.path().join("bad.tags");
    std::fs::write(&bad, "# ok\ntag 1 sharpness 3\n").unwrap();
    let o = run("stpn", "cpu", &bad);
    assert_exit(&o, 1);
    assert!(
        stderr(&o).contains("bad.tags: tags line 2: sharpness 3 is outside [0, 1]"),
        "{}",
        all(&o)
    );
}

#[test]
fn tessellate_errors() {
    let tmp = TempDir::new("tess-errors");
    let out = tmp.path().join("out.obj");
    let cube = mesh("catmark_cube.obj");
    let run = |input: &Path, scheme: &str, level: &str| {
        tessgen([
            "tessellate".as_ref(),
            input.as_os_str(),
            "--scheme".as_ref(),
            scheme.as_ref(),
            "--level".as_ref(),
            level.as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ])
    };

    // `regular` has no patch for the cube's valence-3 corners.
    let o = run(&cube, "regular", "3");
    assert_ne!(o.status.code(), Some(0));
    assert!(stderr(&o).contains("face 0"), "{}", all(&o));
    assert!(!out.exists());

    // Malformed OBJ: the message names the line.
    let bad = tmp.path().join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 2 x\nv 0 1 0\nf 1 2 3\n").unwrap();
    let o = run(&bad, "pccm", "3");
    assert_ne!(o.status.code(), Some(0));
    assert!(stderr(&o).contains("line 2"), "{}", all(&o));

    // Level 0, unknown scheme, unknown backend.
    let o = run(&cube, "pccm", "0");
    assert_ne!(o.status.code(), Some(0));
    assert!(stderr(&o).contains("--level"), "{}", all(&o));
    assert_ne!(run(&cube, "loop", "3").status.code(), Some(0));
    let o = tessgen([
        "tessellate".as_ref(),
        cube.as_os_str(),
        "--scheme".as_ref(),
        "pccm".as_ref(),
        "--level".as_ref(),
        "2".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        "--backend".as_ref(),
        "metal".as_ref(),
    ]);
    // Not a backend: clap rejects it.
    assert_ne!(o.status.code(), Some(0));

    // An open mesh tessellates (its boundary stays open); a bad tag is an
    // error naming its line, and nothing is written.
    let o = run(&mesh("catmark_tent.obj"), "pccm", "2");
    assert_ok(&o);
    std::fs::remove_file(&out).unwrap();
    let bad = tmp.path().join("bad_tag.obj");
    let text =
        std::fs::read_to_string(mesh("catmark_cube.obj")).unwrap() + "t crease 2/1/0 0 99 10\n";
    std::fs::write(&bad, &text).unwrap();
    let line = text.lines().count();
    let o = run(&bad, "pccm", "2");
    assert_exit(&o, 1);
    assert!(stderr(&o).contains(&format!("line {line}")), "{}", all(&o));
    assert!(!out.exists());

    // Unwritable output.
    let o = tessgen([
        "tessellate".as_ref(),
        cube.as_os_str(),
        "--scheme".as_ref(),
        "pccm".as_ref(),
        "--level".as_ref(),
        "2".as_ref(),
        "--out".as_ref(),
        tmp.path().join("no/such/dir/x.obj").as_os_str(),
    ]);
    assert_exit(&o, 1);
    assert!(stderr(&o).contains("x.obj"), "{}", all(&o));
}

#[test]
fn compare_reports_a_table_and_json() {
    let torus = mesh("catmark_torus.obj");
    let reference =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/cc_limit");
    let o = tessgen([
        "compare".as_ref(),
        torus.as_os_str(),
        "--schemes".as_ref(),
        "pccm,regular".as_ref(),
        "--reference".as_ref(),
        reference.as_os_str(),
    ]);
    assert_ok(&o);
    assert!(
        stdout(&o).contains("| catmark_torus | pccm | 8 |"),
        "{}",
        all(&o)
    );
    assert!(
        stdout(&o).contains("| catmark_torus | regular | 8 |"),
        "{}",
        all(&o)
    );
    let o = tessgen(["compare".as_ref(), torus.as_os_str(), "--json".as_ref()]);
    assert_ok(&o);
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(j[0]["open_edges"], 0);
    // A scheme that cannot handle the mesh fails the command but still reports the others.
    let cube = mesh("catmark_cube.obj");
    let o = tessgen([
        "compare".as_ref(),
        cube.as_os_str(),
        "--schemes".as_ref(),
        "pccm,regular".as_ref(),
    ]);
    assert_exit(&o, 1);
    assert!(
        stdout(&o).contains("| catmark_cube | pccm |"),
        "{}",
        all(&o)
    );
    assert!(stderr(&o).contains("face 0"), "{}", all(&o));
}

#[test]
fn tessellate_with_displacement_across_uv_seams() {
    let tmp = TempDir::new("tess-displace");
    let cube = mesh("catmark_cube_uv.obj");
    let map = cube
        .parent()
        .and_then(|p| p.parent())
        .map(|d| d.join("displace").join("atlas_seams.png"))
        .unwrap();
    for (backend, per_patch, closed) in [
        ("cpu", false, true),
        ("wgpu", false, true),
        ("glsl", false, true),
        ("hlsl", false, true),
        ("cpu", true, false),
        ("glsl", true, false),
    ] {
        let out = tmp.path().join(format!("cube_{backend}_{per_patch}.obj"));
        let mut args: Vec<&std::ffi::OsStr> = vec![
            "tessellate".as_ref(),
            cube.as_os_str(),
            "--scheme".as_ref(),
            "acc".as_ref(),
            "--level".as_ref(),
            "5".as_ref(),
            "--backend".as_ref(),
            backend.as_ref(),
            "--displace".as_ref(),
            map.as_os_str(),
            "--displace-scale".as_ref(),
            "0.4".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
            "--check-watertight".as_ref(),
        ];
        if per_patch {
            args.push("--displace-per-patch".as_ref());
        }
        let o = tessgen(args);
        if closed {
            assert_ok(&o);
            assert!(stdout(&o).contains("closed 2-manifold"), "{}", all(&o));
        } else {
            assert!(stdout(&o).contains("NOT watertight"), "{}", all(&o));
        }
    }
    // A mesh without texture coordinates is a typed error naming the corner.
    let out = tmp.path().join("plain.obj");
    let o = tessgen([
        "tessellate".as_ref(),
        mesh("catmark_cube.obj").as_os_str(),
        "--scheme".as_ref(),
        "pccm".as_ref(),
        "--level".as_ref(),
        "2".as_ref(),
        "--displace".as_ref(),
        map.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(!o.status.success());
    assert!(all(&o).contains("face 0 corner 0"), "{}", all(&o));
}

#[test]
fn tessellate_triangle_schemes_with_displacement() {
    let tmp = TempDir::new("tess-displace-tri");
    let cube = mesh("catmark_cube_uv.obj");
    let map = cube
        .parent()
        .and_then(|p| p.parent())
        .map(|d| d.join("displace").join("atlas_seams.png"))
        .unwrap();
    for (scheme, backend, per_patch, closed) in [
        ("pn", "cpu", false, true),
        ("pn", "wgpu", false, true),
        ("phong", "cpu", false, true),
        ("pn", "glsl", false, true),
        ("phong", "hlsl", false, true),
        ("pn", "cpu", true, false),
        ("pn", "glsl", true, false),
    ] {
        let out = tmp
            .path()
            .join(format!("cube_{scheme}_{backend}_{per_patch}.obj"));
        let mut args: Vec<&std::ffi::OsStr> = vec![
            "tessellate".as_ref(),
            cube.as_os_str(),
            "--scheme".as_ref(),
            scheme.as_ref(),
            "--split-quads".as_ref(),
            "--level".as_ref(),
            "5".as_ref(),
            "--backend".as_ref(),
            backend.as_ref(),
            "--displace".as_ref(),
            map.as_os_str(),
            "--displace-scale".as_ref(),
            "0.4".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
            "--check-watertight".as_ref(),
        ];
        if per_patch {
            args.push("--displace-per-patch".as_ref());
        }
        let o = tessgen(args);
        if closed {
            assert_ok(&o);
            assert!(stdout(&o).contains("closed 2-manifold"), "{}", all(&o));
        } else {
            assert!(stdout(&o).contains("NOT watertight"), "{}", all(&o));
        }
    }
}

/// `--adaptive … --displace MAP` on every backend (the instanced path on
/// cpu and wgpu, the tessellation stages on glsl and hlsl): the displaced
/// cube with a texture seam on every edge welds closed with random
/// per-edge factors, quads and split triangles; the per-patch control
/// does not.
#[test]
fn tessellate_adaptive_with_displacement() {
    let tmp = TempDir::new("tess-adaptive-displace");
    let cube = mesh("catmark_cube_uv.obj");
    let map = cube
        .parent()
        .and_then(|p| p.parent())
        .map(|d| d.join("displace").join("atlas_seams.png"))
        .unwrap();
    let run = |scheme: &str, backend: &str, per_patch: bool| {
        let out = tmp
            .path()
            .join(format!("{scheme}_{backend}_{per_patch}.obj"));
        let mut args: Vec<&std::ffi::OsStr> = vec![
            "tessellate".as_ref(),
            cube.as_os_str(),
            "--scheme".as_ref(),
            scheme.as_ref(),
            "--split-quads".as_ref(),
            "--backend".as_ref(),
            backend.as_ref(),
            "--adaptive".as_ref(),
            "random:7:1:12".as_ref(),
            "--max-factor".as_ref(),
            "16".as_ref(),
            "--displace".as_ref(),
            map.as_os_str(),
            "--displace-scale".as_ref(),
            "0.4".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
            "--check-watertight".as_ref(),
        ];
        if per_patch {
            args.push("--displace-per-patch".as_ref());
        }
        tessgen(args)
    };
    for (scheme, backend) in [
        ("acc", "cpu"),
        ("acc", "wgpu"),
        ("pn", "cpu"),
        ("pn", "wgpu"),
        ("acc", "glsl"),
        ("acc", "hlsl"),
        ("pn", "glsl"),
        ("phong", "hlsl"),
    ] {
        let o = run(scheme, backend, false);
        assert_ok(&o);
        assert!(stdout(&o).contains("closed 2-manifold"), "{}", all(&o));
    }
    for (scheme, backend) in [
        ("acc", "cpu"),
        ("acc", "wgpu"),
        ("acc", "glsl"),
        ("pn", "hlsl"),
    ] {
        let o = run(scheme, backend, true);
        assert!(stdout(&o).contains("NOT watertight"), "{}", all(&o));
    }
}

/// PNG width and height from the IHDR chunk (bytes 16..24).
fn png_size(path: &Path) -> (u32, u32) {
    let b = std::fs::read(path).expect("png written");
    assert_eq!(&b[1..4], b"PNG", "{} is not a PNG", path.display());
    let be = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    (be(16), be(20))
}

/// `render`, uniform and `--adaptive` (GPU-driven buckets drawn with
/// indirect draws, every metric), writes a PNG of the asked size;
/// `--max-factor` needs `--adaptive`.
#[test]
fn render_uniform_and_adaptive() {
    let tmp = TempDir::new("render");
    let cube = mesh("catmark_cube.obj");
    for (k, extra) in [
        vec!["--level", "4"],
        vec!["--adaptive", "random:3:1:16", "--max-factor", "16"],
        vec!["--adaptive", "distance:8"],
        vec!["--adaptive", "screen:12", "--wireframe"],
    ]
    .into_iter()
    .enumerate()
    {
        let out = tmp.path().join(format!("r{k}.png"));
        let mut args: Vec<&std::ffi::OsStr> = vec![
            "render".as_ref(),
            cube.as_os_str(),
            "--size".as_ref(),
            "96x64".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ];
        args.extend(extra.iter().map(|s| std::ffi::OsStr::new(*s)));
        let o = tessgen(args);
        assert_ok(&o);
        assert_eq!(png_size(&out), (96, 64), "{extra:?}");
    }
    let o = tessgen([
        "render".as_ref(),
        cube.as_os_str(),
        "--max-factor".as_ref(),
        "8".as_ref(),
        "--out".as_ref(),
        tmp.path().join("x.png").as_os_str(),
    ]);
    assert_exit(&o, 2);
}

/// `bench`: the uniform table on cpu (with the same-run fill floor and
/// per-sample path) and wgpu, and with `--adaptive` the
/// adaptive table (cpu: uniform vs adaptive; wgpu: uniform vs host lists
/// vs GPU-driven buckets), one row per level with numbers in every
/// column; glsl/hlsl are refused. Times are printed, never asserted.
#[test]
fn bench_uniform_and_adaptive() {
    let cube = mesh("catmark_cube.obj");
    let cube = cube.to_str().unwrap();
    for (backend, adaptive, columns) in [
        // cpu: N, samples, ms, ns/sample, samples/s, fill floor, ratio,
        // streaming fill floor, ratio, per-sample path, ratio (the same-run
        // baselines of docs/performance.md), then ns/sample of each copy
        // of the lane loops this machine runs.
        ("cpu", None, 11 + tessgen_runtime::cpu::lane_copies().len()),
        ("wgpu", None, 5),
        ("cpu", Some("random:3:1:4"), 8),
        ("wgpu", Some("random:3:1:4"), 9),
    ] {
        let mut args = vec![
            "bench",
            cube,
            "--levels",
            "2,4",
            "--runs",
            "1",
            "--backend",
            backend,
        ];
        if let Some(m) = adaptive {
            args.extend(["--adaptive", m]);
        }
        let o = tessgen(&args);
        assert_ok(&o);
        let out = stdout(&o);
        for level in ["2", "4"] {
            let row = out
                .lines()
                .find(|l| l.starts_with(&format!("| {level} |")))
                .unwrap_or_else(|| panic!("{backend} {adaptive:?}: no row for {level}:\n{out}"));
            let cells: Vec<&str> = row.trim_matches('|').split('|').map(str::trim).collect();
            assert_eq!(cells.len(), columns, "{row}");
            for c in &cells {
                assert!(
                    c.parse::<f64>().is_ok(),
                    "{backend} {adaptive:?}: `{c}` in {row}"
                );
            }
        }
    }
    let o = tessgen(["bench", cube, "--backend", "glsl"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("not supported"), "{}", stderr(&o));
}
