//! Snapshots of every WGSL module the generator emits for the built-in
//! schemes. Review every changed snapshot before accepting it (`cargo insta
//! review`); CI runs with INSTA_UPDATE=no.

use tessgen_codegen::{Builder, Target};

fn build() -> tessgen_codegen::Output {
    Builder::new()
        .builtin_schemes()
        .target(Target::Wgsl)
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

/// Exactly one module per scheme, nothing else under `wgsl/`.
#[test]
fn wgsl_files() {
    let out = build();
    let mut paths: Vec<&str> = out
        .files
        .iter()
        .map(|f| f.path.as_str())
        .filter(|p| p.starts_with("wgsl/"))
        .collect();
    paths.sort();
    assert_eq!(
        paths,
        [
            "wgsl/acc.wgsl",
            "wgsl/g1cc.wgsl",
            "wgsl/gregory.wgsl",
            "wgsl/gregory_osd.wgsl",
            "wgsl/pccm.wgsl",
            "wgsl/phong.wgsl",
            "wgsl/pn.wgsl",
            "wgsl/regular.wgsl",
            "wgsl/stpn.wgsl"
        ]
    );
}

#[test]
fn wgsl_regular() {
    insta::assert_snapshot!("wgsl_regular_wgsl", text(&build(), "wgsl/regular.wgsl"));
}

#[test]
fn wgsl_pccm() {
    insta::assert_snapshot!("wgsl_pccm_wgsl", text(&build(), "wgsl/pccm.wgsl"));
}

#[test]
fn wgsl_acc() {
    insta::assert_snapshot!("wgsl_acc_wgsl", text(&build(), "wgsl/acc.wgsl"));
}

#[test]
fn wgsl_gregory() {
    insta::assert_snapshot!("wgsl_gregory_wgsl", text(&build(), "wgsl/gregory.wgsl"));
}

#[test]
fn wgsl_gregory_osd() {
    insta::assert_snapshot!(
        "wgsl_gregory_osd_wgsl",
        text(&build(), "wgsl/gregory_osd.wgsl")
    );
}

#[test]
fn wgsl_pn() {
    insta::assert_snapshot!("wgsl_pn_wgsl", text(&build(), "wgsl/pn.wgsl"));
}

#[test]
fn wgsl_stpn() {
    insta::assert_snapshot!("wgsl_stpn_wgsl", text(&build(), "wgsl/stpn.wgsl"));
}

#[test]
fn wgsl_phong() {
    insta::assert_snapshot!("wgsl_phong_wgsl", text(&build(), "wgsl/phong.wgsl"));
}

#[test]
fn wgsl_g1cc() {
    insta::assert_snapshot!("wgsl_g1cc_wgsl", text(&build(), "wgsl/g1cc.wgsl"));
}
