//! Every emitted HLSL file compiles, entry point by entry point, with
//! glslang's HLSL front end to SPIR-V that passes `spirv-val`:
//!
//! ```text
//! glslangValidator -D -V --target-env vulkan1.1 -e ENTRY -S STAGE FILE -o OUT.spv
//! spirv-val --target-env vulkan1.1 OUT.spv
//! ```
//!
//! The entry points and stages are read from the file's own header lines
//! (`// entry: NAME stage: STAGE`), as any other tool would. Also checked on
//! the SPIR-V (`spirv-dis`): every descriptor is in set 0 at its
//! `abi::BINDINGS` number, and `precise` reaches the shared edge evaluator
//! as `NoContraction`. The tools come from glslang-tools and spirv-tools
//! (scripts/test.sh installs them); a missing tool fails the test.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use tessgen_codegen::backend::{abi, hlsl};
use tessgen_codegen::{Builder, Output, SchemeSource, Target};
use tessgen_macros::scheme;

const TARGET_ENV: &str = "vulkan1.1";

/// The entry points every file must list.
const EXPECTED: &[(&str, &str)] = &[
    ("vs_main", "vert"),
    ("hs_main", "tesc"),
    ("ds_main", "tese"),
    ("vertex_stage_main", "comp"),
    ("patch_main", "comp"),
    ("eval_main", "comp"),
    ("refine_main", "comp"),
];

/// PCCM with a user-chosen sigma (the `scheme!` front end).
fn pccm_sigma() -> SchemeSource {
    scheme! {
        /// PCCM with a flat sigma = 0.6 at extraordinary vertices.
        scheme pccm_sigma {
            facet quad;

            const c = cos(2 * pi / n);
            const s = sin(2 * pi / n);
            const sigma = if n == 4 { 0.5 } else { 0.6 };

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
                gstar = sum(k, v(k) + 3 * e(k, 0) + 3 * e(k, 1) + 9 * f(k, 0)) / 64;
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
                out b112[i] = gstar
                    + 3 / 16 * (b211[i] + b121[i] - b211[i - 1] - b121[i + 1])
                    + 1 / 16 * (b211[i + 1] + b121[i - 1] - b211[i + 2] - b121[i + 2]);
            }
        }
    }
}

/// A scheme whose names are HLSL keywords (`point`, `triangle`, `line`,
/// `sample`) or the name of a global buffer (`valence`): the printer must
/// rename them, not emit them (glslang rejects a local named `line`).
fn hlsl_names() -> SchemeSource {
    scheme! {
        /// Bicubic patches whose definitions are named like HLSL keywords.
        scheme hlsl_names {
            facet quad;

            vertex {
                point[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;
                edge[j] = (point[j - 1] + point[j]) / 2;
                triangle = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5));
            }

            patch ordinary: bicubic {
                line = sum(k, triangle(k)) / 4;
                sample = (line + point(0, 0)) / 2;
                valence = (sample + line) / 2;
                out b00[i] = triangle(i);
                out b10[i] = edge(i, 0);
                out b01[i] = edge(i, 1);
                out b11[i] = (3 * point(i, 0) + valence) / 4;
            }
        }
    }
}

fn build(builder: Builder) -> Output {
    builder
        .target(Target::Hlsl)
        .command("tessgen generate --out generated")
        .compile()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Fail (never skip) when a tool is missing.
fn require(tool: &str) {
    let ok = Command::new(tool)
        .arg("--version")
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    assert!(
        ok,
        "`{tool}` not found or not working: install glslang-tools and spirv-tools \
         (scripts/test.sh installs them)"
    );
}

fn tmp(name: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!(
        "tessgen_validate_hlsl_{}_{n}_{name}",
        std::process::id()
    ))
}

fn run(cmd: &mut Command) -> Result<String, String> {
    let shown = format!("{cmd:?}");
    let out = cmd
        .output()
        .map_err(|e| format!("{shown}: cannot run: {e}"))?;
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    if out.status.success() {
        Ok(text)
    } else {
        Err(format!("{shown} failed ({}):\n{text}", out.status))
    }
}

/// `// entry: NAME stage: STAGE` lines of the file's header.
fn entries(text: &str) -> Vec<(String, String)> {
    text.lines()
        .take_while(|l| l.starts_with("//"))
        .filter_map(|l| {
            let rest = l.strip_prefix("// entry: ")?;
            let (name, stage) = rest.split_once(" stage: ")?;
            Some((name.trim().to_string(), stage.trim().to_string()))
        })
        .collect()
}

/// Compile one entry point to SPIR-V and validate it; the SPIR-V file.
fn compile(file: &Path, entry: &str, stage: &str) -> Result<PathBuf, String> {
    let spv = tmp(&format!("{entry}.spv"));
    run(Command::new("glslangValidator")
        .args([
            "-D",
            "-V",
            "--target-env",
            TARGET_ENV,
            "-e",
            entry,
            "-S",
            stage,
        ])
        .arg(file)
        .arg("-o")
        .arg(&spv))?;
    run(Command::new("spirv-val")
        .args(["--target-env", TARGET_ENV])
        .arg(&spv))?;
    Ok(spv)
}

/// Every HLSL file of `out`: the header lists exactly the expected entry
/// points, and each compiles and validates. Returns the SPIR-V per
/// `(file, entry)`; panics with every tool message on failure.
fn validate(out: &Output) -> Vec<(String, String, PathBuf)> {
    require("glslangValidator");
    require("spirv-val");
    let expected: BTreeSet<(String, String)> = EXPECTED
        .iter()
        .map(|(e, s)| (e.to_string(), s.to_string()))
        .collect();
    let mut failures = Vec::new();
    let mut modules = Vec::new();
    let files: Vec<_> = out
        .files
        .iter()
        .filter(|f| f.path.starts_with("hlsl/"))
        .collect();
    assert_eq!(
        files.len(),
        out.schemes.len(),
        "one HLSL file per scheme expected"
    );
    for f in files {
        assert!(f.path.ends_with(".hlsl"), "{}: not an .hlsl file", f.path);
        let text = String::from_utf8(f.contents.clone()).expect("UTF-8");
        let listed = entries(&text);
        let set: BTreeSet<(String, String)> = listed.iter().cloned().collect();
        assert_eq!(set.len(), listed.len(), "{}: entry listed twice", f.path);
        assert_eq!(set, expected, "{}: entry points in the header", f.path);
        let file = tmp(f.path.trim_start_matches("hlsl/"));
        std::fs::write(&file, &f.contents).expect("write temp file");
        for (entry, stage) in &listed {
            match compile(&file, entry, stage) {
                Ok(spv) => modules.push((f.path.clone(), entry.clone(), spv)),
                Err(e) => failures.push(format!("{} {entry} ({stage}): {e}", f.path)),
            }
        }
        let _ = std::fs::remove_file(&file);
    }
    assert!(
        failures.is_empty(),
        "{} HLSL entry points failed:\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
    modules
}

fn cleanup(modules: &[(String, String, PathBuf)]) {
    for (_, _, spv) in modules {
        let _ = std::fs::remove_file(spv);
    }
}

#[test]
fn printer_lists_the_expected_entry_points() {
    assert_eq!(hlsl::ENTRY_POINTS, EXPECTED);
}

#[test]
fn builtin_schemes_compile_and_validate() {
    let out = build(Builder::new().builtin_schemes());
    let modules = validate(&out);
    // regular, pccm, acc, gregory, gregory_osd, pn, stpn, phong, g1cc: every entry point of each.
    assert_eq!(modules.len(), 9 * EXPECTED.len());
    cleanup(&modules);
}

#[test]
fn user_schemes_compile_and_validate() {
    let out = build(Builder::new().scheme(pccm_sigma()).scheme(hlsl_names()));
    let names = out
        .file("hlsl/hlsl_names.hlsl")
        .expect("hlsl_names emitted");
    let text = String::from_utf8(names.contents.clone()).expect("UTF-8");
    for renamed in ["float3 line_ =", "float3 sample_ =", "float3 valence_ ="] {
        assert!(text.contains(renamed), "`{renamed}` not in:\n{text}");
    }
    let modules = validate(&out);
    assert_eq!(modules.len(), 2 * EXPECTED.len());
    cleanup(&modules);
}

/// `OpName` of every id, from `spirv-dis` output.
fn names(dis: &str) -> Vec<(String, String)> {
    dis.lines()
        .filter_map(|l| {
            let rest = l.trim().strip_prefix("OpName ")?;
            let (id, name) = rest.split_once(' ')?;
            Some((id.to_string(), name.trim_matches('"').to_string()))
        })
        .collect()
}

/// `(id, value)` of every `OpDecorate ID DECORATION VALUE`.
fn decorations(dis: &str, decoration: &str) -> Vec<(String, u32)> {
    dis.lines()
        .filter_map(|l| {
            let rest = l.trim().strip_prefix("OpDecorate ")?;
            let mut it = rest.split_whitespace();
            let id = it.next()?;
            (it.next()? == decoration).then_some(())?;
            Some((id.to_string(), it.next()?.parse().ok()?))
        })
        .collect()
}

#[test]
fn spirv_bindings_are_the_abi_bindings_and_edges_are_precise() {
    require("spirv-dis");
    let out = build(Builder::new().builtin_schemes());
    let modules = validate(&out);
    let mut problems = Vec::new();
    for (file, entry, spv) in &modules {
        let dis = run(Command::new("spirv-dis").arg(spv)).unwrap_or_else(|e| panic!("{e}"));
        let names = names(&dis);
        let sets = decorations(&dis, "DescriptorSet");
        let bindings = decorations(&dis, "Binding");
        // vs_main reads nothing; every other entry point reads Params —
        // except the vertex stage of a triangle scheme, which has no
        // outputs (pn.md: no vertex stage), so the compiler drops it all.
        let empty_vertex_stage = entry == "vertex_stage_main"
            && (file.ends_with("pn.hlsl") || file.ends_with("phong.hlsl"));
        // (`stpn.hlsl` ends with `pn.hlsl`.)
        assert!(
            entry == "vs_main" || empty_vertex_stage || !bindings.is_empty(),
            "{file} {entry}: no descriptor bindings at all"
        );
        for (id, k) in &bindings {
            let name = names
                .iter()
                .find(|(i, _)| i == id)
                .map(|(_, n)| n.as_str())
                .unwrap_or("");
            // The cbuffer's instance is anonymous in SPIR-V; RW views are `NAME_rw`.
            let name = if name.is_empty() {
                "params"
            } else {
                name.trim_end_matches("_rw")
            };
            match abi::BINDINGS.iter().find(|b| b.name == name) {
                Some(b) if b.binding == *k => {}
                Some(b) => problems.push(format!(
                    "{file} {entry}: `{name}` at binding {k}, abi says {}",
                    b.binding
                )),
                None => problems.push(format!("{file} {entry}: unknown binding `{name}` ({k})")),
            }
            if !sets.iter().any(|(i, s)| i == id && *s == 0) {
                problems.push(format!("{file} {entry}: `{name}` not in descriptor set 0"));
            }
        }
        // The shared edge evaluator is `precise`: its arithmetic must not be
        // contracted in either evaluation path.
        if (entry == "ds_main" || entry == "eval_main") && !dis.contains("NoContraction") {
            problems.push(format!("{file} {entry}: no NoContraction decoration"));
        }
    }
    cleanup(&modules);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
