//! Snapshots of every HLSL file the generator emits for the built-in
//! schemes. Review every changed snapshot before accepting it
//! (`cargo insta review`); CI runs with INSTA_UPDATE=no.

use tessgen_codegen::{Builder, Target};

fn build() -> tessgen_codegen::Output {
    Builder::new()
        .builtin_schemes()
        .target(Target::Hlsl)
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

#[test]
fn hlsl_files_are_one_per_scheme() {
    let out = build();
    let hlsl: Vec<&str> = out
        .files
        .iter()
        .map(|f| f.path.as_str())
        .filter(|p| p.starts_with("hlsl/"))
        .collect();
    assert_eq!(
        hlsl,
        [
            "hlsl/regular.hlsl",
            "hlsl/pccm.hlsl",
            "hlsl/acc.hlsl",
            "hlsl/gregory.hlsl",
            "hlsl/gregory_osd.hlsl",
            "hlsl/pn.hlsl",
            "hlsl/stpn.hlsl",
            "hlsl/phong.hlsl",
            "hlsl/g1cc.hlsl"
        ]
    );
}

#[test]
fn hlsl_regular() {
    let out = build();
    insta::assert_snapshot!("hlsl_regular_hlsl", text(&out, "hlsl/regular.hlsl"));
}

#[test]
fn hlsl_pccm() {
    let out = build();
    insta::assert_snapshot!("hlsl_pccm_hlsl", text(&out, "hlsl/pccm.hlsl"));
}

#[test]
fn hlsl_acc() {
    let out = build();
    insta::assert_snapshot!("hlsl_acc_hlsl", text(&out, "hlsl/acc.hlsl"));
}

#[test]
fn hlsl_gregory() {
    let out = build();
    insta::assert_snapshot!("hlsl_gregory_hlsl", text(&out, "hlsl/gregory.hlsl"));
}

#[test]
fn hlsl_gregory_osd() {
    let out = build();
    insta::assert_snapshot!("hlsl_gregory_osd_hlsl", text(&out, "hlsl/gregory_osd.hlsl"));
}

#[test]
fn hlsl_pn() {
    let out = build();
    insta::assert_snapshot!("hlsl_pn_hlsl", text(&out, "hlsl/pn.hlsl"));
}

#[test]
fn hlsl_stpn() {
    let out = build();
    insta::assert_snapshot!("hlsl_stpn_hlsl", text(&out, "hlsl/stpn.hlsl"));
}

#[test]
fn hlsl_phong() {
    let out = build();
    insta::assert_snapshot!("hlsl_phong_hlsl", text(&out, "hlsl/phong.hlsl"));
}

#[test]
fn hlsl_g1cc() {
    let out = build();
    insta::assert_snapshot!("hlsl_g1cc_hlsl", text(&out, "hlsl/g1cc.hlsl"));
}
