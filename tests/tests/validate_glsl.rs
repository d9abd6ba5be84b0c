//! Every emitted GLSL file compiles with `glslangValidator -V` (Vulkan 1.1
//! SPIR-V) and the SPIR-V passes `spirv-val`: for the built-in schemes and
//! for a user scheme declared with `scheme!` whose local names collide with
//! GLSL keywords and with the shader's globals.
//!
//! The tools come from glslang-tools and spirv-tools (`scripts/test.sh`
//! installs them); a missing tool fails the test, it never skips.

use std::path::PathBuf;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use tessgen_codegen::{Builder, GeneratedFile, SchemeSource, Target};
use tessgen_macros::scheme;

fn glsl_files(builder: Builder) -> Vec<GeneratedFile> {
    let out = builder
        .target(Target::Glsl)
        .command("tessgen generate --out generated")
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    out.files
        .into_iter()
        .filter(|f| f.path.starts_with("glsl/"))
        .collect()
}

fn stage_of(path: &str) -> &'static str {
    if path.ends_with(".vert") {
        "vert"
    } else if path.ends_with(".tesc") {
        "tesc"
    } else if path.ends_with(".tese") {
        "tese"
    } else if path.ends_with(".comp") {
        "comp"
    } else {
        panic!("{path}: not a GLSL shader file name")
    }
}

static COUNTER: AtomicUsize = AtomicUsize::new(0);

fn temp_path(name: &str) -> PathBuf {
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!(
        "tessgen_glsl_{}_{n}_{}",
        std::process::id(),
        name.replace('/', "_")
    ))
}

fn run(tool: &str, args: &[&str]) -> Result<(), String> {
    let out = Command::new(tool).args(args).output().map_err(|e| {
        format!(
            "cannot run `{tool}` ({e}); install it (apt-get install glslang-tools spirv-tools, \
             or run scripts/test.sh)"
        )
    })?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "`{tool} {}` failed ({}):\n{}{}",
            args.join(" "),
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// Compile one file to SPIR-V and validate it; `Err` carries the tools' output.
fn validate(file: &GeneratedFile) -> Result<(), String> {
    let stage = stage_of(&file.path);
    let src = temp_path(&file.path);
    let spv = temp_path(&format!("{}.spv", file.path));
    std::fs::write(&src, &file.contents).map_err(|e| format!("{}: {e}", src.display()))?;
    let (s, o) = (src.to_string_lossy(), spv.to_string_lossy());
    let result = run(
        "glslangValidator",
        &["-V", "--target-env", "vulkan1.1", "-S", stage, &s, "-o", &o],
    )
    .and_then(|()| run("spirv-val", &["--target-env", "vulkan1.1", &o]));
    let _ = std::fs::remove_file(&src);
    let _ = std::fs::remove_file(&spv);
    result.map_err(|e| format!("{}:\n{e}", file.path))
}

/// Validate every file (in parallel) and report all failures together.
fn validate_all(files: &[GeneratedFile]) {
    let errors: Vec<String> = std::thread::scope(|s| {
        let handles: Vec<_> = files.iter().map(|f| s.spawn(|| validate(f))).collect();
        handles
            .into_iter()
            .filter_map(|h| h.join().unwrap_or_else(|_| Err("panicked".into())).err())
            .collect()
    });
    assert!(
        errors.is_empty(),
        "{} of {} GLSL files failed validation:\n\n{}",
        errors.len(),
        files.len(),
        errors.join("\n\n")
    );
}

fn expected_paths(schemes: &[&str]) -> Vec<String> {
    let mut v = Vec::new();
    for s in schemes {
        for suffix in [
            ".vert",
            ".tesc",
            ".tese",
            "_vertex_stage.comp",
            "_patch.comp",
            "_eval.comp",
            "_refine.comp",
        ] {
            v.push(format!("glsl/{s}{suffix}"));
        }
    }
    v.sort();
    v
}

#[test]
fn builtin_schemes_validate() {
    let files = glsl_files(Builder::new().builtin_schemes());
    let mut paths: Vec<String> = files.iter().map(|f| f.path.clone()).collect();
    paths.sort();
    assert_eq!(
        paths,
        expected_paths(&[
            "acc",
            "g1cc",
            "gregory",
            "gregory_osd",
            "pccm",
            "phong",
            "pn",
            "regular",
            "stpn"
        ])
    );
    validate_all(&files);
}

/// A user scheme (PCCM with renamed locals) whose local names are a GLSL
/// keyword (`sample`) or globals of the emitted shaders (`params`, the
/// uniform block; `valence`, a buffer): the printer must rename them.
fn user_scheme() -> SchemeSource {
    scheme! {
        /// PCCM with local names that are not valid as-is in GLSL.
        scheme pccm_user {
            facet quad;
            const c = cos(2 * pi / n);
            const s = sin(2 * pi / n);
            const sigma = (c + 5 + sqrt((c + 9) * (c + 1))) / 16;
            vertex {
                f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;
                e[j] = (f[j - 1] + f[j]) / 2;
                v = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5));
                t[j] = if n == 4 {
                    e[j]
                } else {
                    v + 4 * sigma / n * sum(k, cos(2 * pi * (k - j) / n) * e[k])
                };
            }
            patch ordinary: bicubic {
                out b00[i] = v(i);
                out b10[i] = e(i, 0);
                out b01[i] = e(i, 1);
                out b11[i] = f(i, 0);
            }
            patch extraordinary: cpatch {
                sample = sum(k, v(k) + 3 * e(k, 0) + 3 * e(k, 1) + 9 * f(k, 0)) / 64;
                params = sample;
                valence = params;
                kappa[i] = 3 / (4 * (s(i) + s(i + 1)));
                b310[i] = (v(i) + 3 * t(i, 0)) / 4;
                b130[i] = (v(i + 1) + 3 * t(i + 1, 1)) / 4;
                b211[i] = b310[i]
                    + (1 + c(i)) / 4 * (t(i + 1, 1) - t(i, 0))
                    + (1 - c(i + 1)) / 8 * (t(i, 0) - v(i))
                    + kappa[i] * (f(i, 0) - e(i, 0));
                b121[i] = b130[i]
                    + (1 + c(i + 1)) / 4 * (t(i, 0) - t(i + 1, 1))
                    + (1 - c(i)) / 8 * (t(i + 1, 1) - v(i + 1))
                    + kappa[i] * (f(i + 1, 0) - e(i + 1, 1));
                out v[i] = v(i);
                out t0[i] = t(i, 0);
                out t1[i] = t(i, 1);
                out b211[i] = b211[i];
                out b121[i] = b121[i];
                out b112[i] = valence
                    + 3 / 16 * (b211[i] + b121[i] - b211[i - 1] - b121[i + 1])
                    + 1 / 16 * (b211[i + 1] + b121[i - 1] - b211[i + 2] - b121[i + 2]);
            }
        }
    }
}

#[test]
fn user_scheme_validates() {
    let files = glsl_files(Builder::new().scheme(user_scheme()));
    let mut paths: Vec<String> = files.iter().map(|f| f.path.clone()).collect();
    paths.sort();
    assert_eq!(paths, expected_paths(&["pccm_user"]));
    // The colliding names were renamed, not printed as-is.
    let tesc = files
        .iter()
        .find(|f| f.path == "glsl/pccm_user.tesc")
        .map(|f| String::from_utf8_lossy(&f.contents).into_owned())
        .unwrap_or_default();
    for renamed in [
        "vec3 sample_ = ",
        "vec3 params_ = sample_;",
        "vec3 valence_ = params_;",
    ] {
        assert!(
            tesc.contains(renamed),
            "`{renamed}` missing in pccm_user.tesc"
        );
    }
    validate_all(&files);
}

/// A negative control: the validation must be able to fail.
#[test]
fn validation_rejects_broken_glsl() {
    let bad = GeneratedFile {
        path: "glsl/broken.comp".into(),
        contents: b"#version 450\nlayout(local_size_x = 64) in;\nvoid main() { uint x = 1.0; }\n"
            .to_vec(),
    };
    assert!(validate(&bad).is_err());
}
