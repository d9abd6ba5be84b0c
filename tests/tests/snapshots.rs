//! Snapshots of everything the generator emits for the built-in schemes.
//! Review every changed snapshot before accepting it (`cargo insta review`);
//! CI runs with INSTA_UPDATE=no.

use std::fmt::Write;
use tessgen_codegen::{Builder, Target};

fn build() -> tessgen_codegen::Output {
    Builder::new()
        .builtin_schemes()
        .target(Target::Rust)
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
fn rust_kernels() {
    let out = build();
    insta::assert_snapshot!("rust_tessgen_rs", text(&out, "rust/tessgen.rs"));
}

/// The table for valences 3..=5 as readable text (the full table is
/// thousands of rows; these valences exercise every formula branch,
/// including the `n == 4` special case of `t`).
#[test]
fn stencil_table_small_valences() {
    let out = build();
    let t = &out.table;
    let mut s = String::new();
    for r in &t.rows {
        if r.valence > 5 {
            continue;
        }
        let w: Vec<String> = (0..r.length)
            .map(|c| format!("{:?}", t.weight(r.row, c)))
            .collect();
        let label = match r.sector {
            Some(j) => format!("{}[{j}]", r.output),
            None => r.output.clone(),
        };
        let _ = writeln!(
            s,
            "{:>5} {:<8} n={} {:<12} mask={} [{}]",
            r.row,
            r.scheme,
            r.valence,
            label,
            r.nonzero,
            w.join(", ")
        );
    }
    insta::assert_snapshot!("stencil_table_n3_to_n5", s);
}

/// Sector rows (crease and corner vertices, docs/boundaries.md §3) of
/// sectors up to 3 faces, over the partial ring [p, q0, d0, .., qm]: m = 1
/// and 2 are the exact phantom-grid points, m = 3 the first reflected
/// virtual ring, with the exact crease tangents (boundary.md §3.2–§3.3) in
/// the interior positions of acc t, gregory/gregory_osd e and pccm t.
#[test]
fn stencil_sector_rows_small() {
    let out = build();
    let t = &out.table;
    let mut s = String::new();
    for r in &t.sector_rows {
        if r.faces.unwrap_or(0) > 3 {
            continue;
        }
        let w: Vec<String> = (0..r.length)
            .map(|c| format!("{:?}", t.sector_weight(r.row, c)))
            .collect();
        let label = match r.sector {
            Some(j) => format!("{}[{j}]", r.output),
            None => r.output.clone(),
        };
        let _ = writeln!(
            s,
            "{:>5} {:<12} {:<6} m={} {:<8} mask={} [{}]",
            r.row,
            r.scheme,
            r.kind.unwrap_or(""),
            r.faces.unwrap_or(0),
            label,
            r.nonzero,
            w.join(", ")
        );
    }
    insta::assert_snapshot!("stencil_sector_rows_m1_to_m3", s);
}

/// The manifest's header and per-scheme layout (the per-row list is covered
/// by the text snapshot above and by tests).
#[test]
fn stencil_manifest_layout() {
    let out = build();
    let m: serde_json::Value =
        serde_json::from_str(&text(&out, "table/stencils.json")).unwrap_or_else(|e| panic!("{e}"));
    let mut head = m.clone();
    if let Some(o) = head.as_object_mut() {
        o.remove("rows");
        o.remove("sector_rows");
    }
    insta::assert_json_snapshot!("stencil_manifest_layout", head);
    let rows = m["rows"].as_array().map(|r| r.len()).unwrap_or(0);
    let sector_rows = m["sector_rows"].as_array().map(|r| r.len()).unwrap_or(0);
    assert_eq!(
        rows.max(sector_rows) as u32,
        m["height"].as_u64().unwrap_or(0) as u32
    );
    let bytes = out
        .file("table/stencils.f32")
        .map(|f| f.contents.len())
        .unwrap_or(0);
    // The file is the texture: the logical rows wrapped into column blocks.
    let get = |k: &str| m[k].as_u64().unwrap_or(0);
    let blocks = get("height").div_ceil(get("block_rows"));
    assert!(blocks > 1, "the table wraps (it outgrew one block)");
    assert_eq!(get("texture_width"), blocks * get("width"));
    assert_eq!(get("texture_height"), get("block_rows"));
    assert_eq!(
        bytes as u64,
        get("texture_width") * get("texture_height") * 4
    );
}
