//! The emitted WGSL on a second WebGPU implementation: Dawn (Chrome's
//! WebGPU, the npm package `webgpu`, i.e. dawn.node) compiles every
//! built-in scheme's module with no error and no warning, and builds a
//! pipeline for every entry point under WebGPU's default limits
//! (`tests/dawn/check.mjs`). naga and wgpu check the same files in
//! `validate_wgsl.rs`; Dawn's compiler (Tint) is a separate code base.
//!
//! Dawn runs on its null backend (`DAWN_OPTS=backend=null`): it validates
//! shaders and pipelines fully without a GPU. Its Vulkan backend does not
//! accept Mesa's lavapipe (no `shaderUniform*ArrayDynamicIndexing`), so
//! CI cannot run the cube end to end on Dawn.
//!
//! Compatibility mode (`featureLevel: 'compatibility'`) is checked too:
//! the entries that need core WebGPU are exactly those `generated/README.md`
//! lists (storage buffers in the vertex stage; 256-invocation workgroups),
//! and every other entry, the fragment entry included, builds there.
//!
//! A planted WGSL error fails the check (the negative control).
//!
//! Node.js and the package come from `scripts/test.sh` (`npm ci` in
//! `tests/dawn`); a missing one fails the test, it never skips.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use tessgen_codegen::{Builder, Target};

/// The entries that need core WebGPU, per file, and why
/// (`generated/README.md` says the same).
const CORE_ONLY: &[(&str, &str)] = &[
    ("eval_vs", "storage buffers used in vertex stage"),
    ("eval_adaptive_vs", "storage buffers used in vertex stage"),
    (
        "eval_adaptive_indirect_vs",
        "storage buffers used in vertex stage",
    ),
    ("adaptive_count_main", "workgroup_size(256"),
    ("adaptive_scatter_main", "workgroup_size(256"),
];

fn dawn_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("dawn")
}

#[test]
fn every_wgsl_entry_point_builds_on_dawn() {
    let dir = dawn_dir();
    assert!(
        dir.join("node_modules/webgpu").is_dir(),
        "Dawn is not installed: run `npm ci --prefix tests/dawn` (scripts/test.sh does)"
    );
    let out = Builder::new()
        .builtin_schemes()
        .target(Target::Wgsl)
        .command("tessgen generate --out generated")
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    let wgsl = std::env::temp_dir().join(format!("tessgen-dawn-{}", std::process::id()));
    std::fs::create_dir_all(&wgsl).expect("temp dir");
    let mut names = Vec::new();
    for f in out.files.iter().filter(|f| f.path.ends_with(".wgsl")) {
        let name = Path::new(&f.path).file_name().expect("file name");
        std::fs::write(wgsl.join(name), &f.contents).expect("write wgsl");
        names.push(name.to_string_lossy().into_owned());
    }
    assert_eq!(names.len(), 9, "{names:?}");
    let run = Command::new("node")
        .arg(dir.join("check.mjs"))
        .arg("--compat")
        .arg(&wgsl)
        .env("DAWN_OPTS", "backend=null")
        .output()
        .unwrap_or_else(|e| panic!("node: {e} (scripts/test.sh installs Node.js)"));
    let _ = std::fs::remove_dir_all(&wgsl);
    let stdout = String::from_utf8_lossy(&run.stdout);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        run.status.success(),
        "Dawn found errors or warnings:\n{stdout}\n{stderr}"
    );
    let entries = names.len() * 14;
    assert!(
        stdout.contains(&format!("core: {entries} entry points, 0 failures")),
        "{stdout}\n{stderr}"
    );
    // Compatibility mode: exactly the listed entries fail, for the listed
    // reasons.
    let listed: BTreeSet<(String, String)> = stdout
        .lines()
        .skip_while(|l| !l.starts_with("compat:"))
        .skip(1)
        .filter_map(|l| {
            let mut w = l.split_whitespace();
            let file = w.next()?.to_string();
            let _stage = w.next()?;
            let entry = w.next()?.trim_end_matches(':').to_string();
            let (_, reason) = CORE_ONLY.iter().find(|(e, _)| *e == entry)?;
            assert!(
                l.contains(reason),
                "{file} {entry} fails for another reason: {l}"
            );
            Some((file, entry))
        })
        .collect();
    let expected: BTreeSet<(String, String)> = names
        .iter()
        .flat_map(|n| {
            CORE_ONLY
                .iter()
                .map(move |(e, _)| (n.clone(), e.to_string()))
        })
        .collect();
    let failing = stdout
        .lines()
        .skip_while(|l| !l.starts_with("compat:"))
        .skip(1)
        .count();
    assert_eq!(listed, expected, "{stdout}");
    assert_eq!(
        failing,
        expected.len(),
        "an unlisted entry fails in compatibility mode:\n{stdout}"
    );
}

/// The negative control: a WGSL file with a planted type error makes the
/// check fail and name the file, so a clean run means something.
#[test]
fn a_planted_wgsl_error_fails_the_check() {
    let dir = dawn_dir();
    assert!(
        dir.join("node_modules/webgpu").is_dir(),
        "Dawn is not installed: run `npm ci --prefix tests/dawn` (scripts/test.sh does)"
    );
    let wgsl = std::env::temp_dir().join(format!("tessgen-dawn-bad-{}", std::process::id()));
    std::fs::create_dir_all(&wgsl).expect("temp dir");
    std::fs::write(
        wgsl.join("planted.wgsl"),
        "@compute @workgroup_size(64)\nfn main_cs() { let x: u32 = 1.0f; }\n",
    )
    .expect("write wgsl");
    let run = Command::new("node")
        .arg(dir.join("check.mjs"))
        .arg(&wgsl)
        .env("DAWN_OPTS", "backend=null")
        .output()
        .unwrap_or_else(|e| panic!("node: {e} (scripts/test.sh installs Node.js)"));
    let _ = std::fs::remove_dir_all(&wgsl);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(!run.status.success(), "a planted error passed:\n{stdout}");
    assert!(
        stdout.contains("planted.wgsl"),
        "the failure names the file:\n{stdout}"
    );
    assert!(stdout.contains("error"), "{stdout}");
}
