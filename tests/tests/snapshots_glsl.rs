//! Snapshots of every GLSL file the generator emits for the built-in schemes.
//! Review every changed snapshot before accepting it (`cargo insta review`);
//! CI runs with INSTA_UPDATE=no.

use tessgen_codegen::{Builder, Target};

fn build() -> tessgen_codegen::Output {
    Builder::new()
        .builtin_schemes()
        .target(Target::Glsl)
        .command("tessgen generate --out generated")
        .compile()
        .unwrap_or_else(|e| panic!("{e}"))
}

fn text(out: &tessgen_codegen::Output, path: &str) -> String {
    let f = out
        .file(path)
        .unwrap_or_else(|| panic!("{path} not emitted"));
    String::from_utf8(f.contents.clone()).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Snapshot name of an emitted path: `glsl/pccm_eval.comp` → `glsl_pccm_eval_comp`.
fn name(path: &str) -> String {
    path.replace(['/', '.'], "_")
}

const FILES: &[&str] = &[
    "glsl/regular.vert",
    "glsl/regular.tesc",
    "glsl/regular.tese",
    "glsl/regular_vertex_stage.comp",
    "glsl/regular_patch.comp",
    "glsl/regular_eval.comp",
    "glsl/regular_refine.comp",
    "glsl/pccm.vert",
    "glsl/pccm.tesc",
    "glsl/pccm.tese",
    "glsl/pccm_vertex_stage.comp",
    "glsl/pccm_patch.comp",
    "glsl/pccm_eval.comp",
    "glsl/pccm_refine.comp",
    "glsl/acc.vert",
    "glsl/acc.tesc",
    "glsl/acc.tese",
    "glsl/acc_vertex_stage.comp",
    "glsl/acc_patch.comp",
    "glsl/acc_eval.comp",
    "glsl/acc_refine.comp",
    "glsl/gregory.vert",
    "glsl/gregory.tesc",
    "glsl/gregory.tese",
    "glsl/gregory_vertex_stage.comp",
    "glsl/gregory_patch.comp",
    "glsl/gregory_eval.comp",
    "glsl/gregory_refine.comp",
    "glsl/gregory_osd.vert",
    "glsl/gregory_osd.tesc",
    "glsl/gregory_osd.tese",
    "glsl/gregory_osd_vertex_stage.comp",
    "glsl/gregory_osd_patch.comp",
    "glsl/gregory_osd_eval.comp",
    "glsl/gregory_osd_refine.comp",
    "glsl/pn.vert",
    "glsl/pn.tesc",
    "glsl/pn.tese",
    "glsl/pn_vertex_stage.comp",
    "glsl/pn_patch.comp",
    "glsl/pn_eval.comp",
    "glsl/pn_refine.comp",
    "glsl/stpn.vert",
    "glsl/stpn.tesc",
    "glsl/stpn.tese",
    "glsl/stpn_vertex_stage.comp",
    "glsl/stpn_patch.comp",
    "glsl/stpn_eval.comp",
    "glsl/stpn_refine.comp",
    "glsl/phong.vert",
    "glsl/phong.tesc",
    "glsl/phong.tese",
    "glsl/phong_vertex_stage.comp",
    "glsl/phong_patch.comp",
    "glsl/phong_eval.comp",
    "glsl/phong_refine.comp",
    "glsl/g1cc.vert",
    "glsl/g1cc.tesc",
    "glsl/g1cc.tese",
    "glsl/g1cc_vertex_stage.comp",
    "glsl/g1cc_patch.comp",
    "glsl/g1cc_eval.comp",
    "glsl/g1cc_refine.comp",
];

#[test]
fn glsl_emits_seven_files_per_scheme() {
    let out = build();
    let mut emitted: Vec<&str> = out
        .files
        .iter()
        .map(|f| f.path.as_str())
        .filter(|p| p.starts_with("glsl/"))
        .collect();
    emitted.sort_unstable();
    let mut expected = FILES.to_vec();
    expected.sort_unstable();
    assert_eq!(emitted, expected);
}

#[test]
fn glsl_regular() {
    let out = build();
    for path in FILES.iter().filter(|p| p.starts_with("glsl/regular")) {
        insta::assert_snapshot!(name(path), text(&out, path));
    }
}

#[test]
fn glsl_pccm() {
    let out = build();
    for path in FILES.iter().filter(|p| p.starts_with("glsl/pccm")) {
        insta::assert_snapshot!(name(path), text(&out, path));
    }
}

/// The seven files of one scheme (the prefix alone would let `gregory` catch
/// `gregory_osd`).
fn files_of(scheme: &str) -> Vec<String> {
    [
        ".vert",
        ".tesc",
        ".tese",
        "_vertex_stage.comp",
        "_patch.comp",
        "_eval.comp",
        "_refine.comp",
    ]
    .iter()
    .map(|suffix| format!("glsl/{scheme}{suffix}"))
    .collect()
}

#[test]
fn glsl_acc() {
    let out = build();
    for path in files_of("acc") {
        insta::assert_snapshot!(name(&path), text(&out, &path));
    }
}

#[test]
fn glsl_gregory() {
    let out = build();
    for path in files_of("gregory") {
        insta::assert_snapshot!(name(&path), text(&out, &path));
    }
}

#[test]
fn glsl_gregory_osd() {
    let out = build();
    for path in files_of("gregory_osd") {
        insta::assert_snapshot!(name(&path), text(&out, &path));
    }
}

#[test]
fn glsl_pn() {
    let out = build();
    for path in files_of("pn") {
        insta::assert_snapshot!(name(&path), text(&out, &path));
    }
}

#[test]
fn glsl_stpn() {
    let out = build();
    for path in files_of("stpn") {
        insta::assert_snapshot!(name(&path), text(&out, &path));
    }
}

#[test]
fn glsl_phong() {
    let out = build();
    for path in files_of("phong") {
        insta::assert_snapshot!(name(&path), text(&out, &path));
    }
}

#[test]
fn glsl_g1cc() {
    let out = build();
    for path in FILES.iter().filter(|p| p.starts_with("glsl/g1cc")) {
        insta::assert_snapshot!(name(path), text(&out, path));
    }
}
