//! A scheme declared outside codegen with `scheme!` flows through every
//! printer and gets reviewed as snapshots, like the built-in ones (README
//! "Adding a scheme"). `bilinear` is the flat bilinear patch of each quad in
//! bicubic Bézier form: the smallest scheme that exercises every stage.
//! (The shader validation of user schemes is in validate_{wgsl,glsl,hlsl}.rs.)

use tessgen_codegen::{Builder, SchemeSource};
use tessgen_macros::scheme;

fn bilinear() -> SchemeSource {
    scheme! {
        /// Bilinear quads as bicubic Bézier patches (flat, C0): a minimal user scheme.
        scheme bilinear {
            facet quad;
            vertex {
                v = p;
                e[j] = (2 * p + p[2 * j]) / 3;
                f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;
            }
            patch ordinary: bicubic {
                out b00[i] = v(i);
                out b10[i] = e(i, 0);
                out b01[i] = e(i, 1);
                out b11[i] = f(i, 0);
            }
            patch extraordinary: bicubic {
                out b00[i] = v(i);
                out b10[i] = e(i, 0);
                out b01[i] = e(i, 1);
                out b11[i] = f(i, 0);
            }
        }
    }
}

#[test]
fn user_scheme_every_emitted_file() {
    let out = Builder::new()
        .scheme(bilinear())
        .all_targets()
        .command("tessgen generate --out generated")
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    let paths: Vec<&str> = out.files.iter().map(|f| f.path.as_str()).collect();
    insta::assert_debug_snapshot!("user_scheme_files", paths);
    for f in &out.files {
        if f.path.starts_with("table/") {
            continue; // thousands of rows; the layout is snapshotted below
        }
        let text =
            String::from_utf8(f.contents.clone()).unwrap_or_else(|e| panic!("{}: {e}", f.path));
        let name = format!("user_scheme__{}", f.path.replace(['/', '.'], "_"));
        insta::assert_snapshot!(name, text);
    }
    let rows: Vec<String> = out
        .table
        .rows
        .iter()
        .filter(|r| r.valence <= 4)
        .map(|r| {
            let w: Vec<String> = (0..r.length)
                .map(|c| format!("{:?}", out.table.weight(r.row, c)))
                .collect();
            let label = match r.sector {
                Some(j) => format!("{}[{j}]", r.output),
                None => r.output.clone(),
            };
            format!("{} n={} {label} [{}]", r.row, r.valence, w.join(", "))
        })
        .collect();
    insta::assert_snapshot!("user_scheme_table_n3_n4", rows.join("\n"));
}
