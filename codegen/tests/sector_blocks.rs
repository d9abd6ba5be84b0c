//! `sector crease|corner { … }` blocks (docs/boundaries.md §3): what the
//! language lets a sector override express — `if` on index variables inside
//! `sum` (terms of the sector only), block-local `let` helpers, an override
//! reading the definition it replaces — their errors, and the built-in
//! schemes' exact crease tangents (boundary.md §3.2–§3.3).

use tessgen_codegen::scheme::SectorKind;
use tessgen_codegen::{builtin_schemes, Scheme, SchemeError};

const MAX: u32 = 32;

/// `regular.tess` with `blocks` (sector blocks) after its vertex stage.
fn scheme(blocks: &str) -> String {
    format!(
        "scheme s {{
    facet quad;
    vertex {{
        f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;
        e[j] = (f[j - 1] + f[j]) / 2;
        v = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5));
    }}
{blocks}
    patch ordinary: bicubic {{
        out b00[i] = v(i);
        out b10[i] = e(i, 0);
        out b01[i] = e(i, 1);
        out b11[i] = f(i, 0);
    }}
}}
"
    )
}

fn compile(text: &str) -> Scheme {
    Scheme::from_source(text, MAX).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The row of output `name` at position `j` of a sector.
fn row(s: &Scheme, kind: SectorKind, m: u32, name: &str, j: u32) -> Vec<f64> {
    s.sector_rows(kind, m)
        .into_iter()
        .find(|(d, jj, _)| s.vertex[*d].name == name && *jj == j)
        .map(|(_, _, w)| w)
        .unwrap_or_else(|| panic!("no row {name}[{j}] at m = {m}"))
}

#[track_caller]
fn close(got: &[f64], want: &[f64], tol: f64) {
    assert_eq!(got.len(), want.len());
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g - w).abs() <= tol,
            "slot {k}: {g} vs {w}\n{got:?}\n{want:?}"
        );
    }
}

/// Fails with a message containing every fragment, at the line and column
/// where `at` (occurring once) starts.
#[track_caller]
fn expect_err(text: &str, at: &str, fragments: &[&str]) -> SchemeError {
    let e = match Scheme::from_source(text, MAX) {
        Ok(_) => panic!("compiled, expected an error:\n{text}"),
        Err(e) => e,
    };
    let hits: Vec<_> = text.match_indices(at).collect();
    assert_eq!(hits.len(), 1, "marker {at:?} must occur once");
    let off = hits[0].0;
    let line = text[..off].matches('\n').count() + 1;
    let col = off - text[..off].rfind('\n').map_or(0, |i| i + 1);
    assert_eq!(
        e.line_column(),
        (line, col),
        "error `{e}` at the wrong place"
    );
    for f in fragments {
        assert!(e.message.contains(f), "message {:?} lacks {f:?}", e.message);
    }
    e
}

#[test]
fn if_on_the_summation_index_selects_the_sector_terms() {
    // Mean of the sector's diagonals d_0 .. d_{m-1} (slots 2, 4, …): the sum
    // runs over the virtual ring (k < n' = 2m, or 4 at m = 1), the `if`
    // keeps k < m.
    let s = compile(&scheme(
        "    sector crease {
        v = sum(k, (if k < m { 1 } else { 0 }) * p[2 * k + 1]) / m;
    }",
    ));
    for m in 1..=5u32 {
        let mut want = vec![0.0; 2 * m as usize + 2];
        for k in 0..m as usize {
            want[2 + 2 * k] = 1.0 / m as f64;
        }
        close(&row(&s, SectorKind::Crease, m, "v", 0), &want, 1e-15);
    }
}

#[test]
fn sector_let_helpers_are_inlined_inside_sums() {
    // `dq` holds a sum; it is used inside another sum: their index
    // variables must not share a slot.
    let s = compile(&scheme(
        "    sector crease {
        let w = 1 / m;
        let dq = sum(k, (if k < m { 1 } else { 0 }) * (p[2 * k + 1] - p)) * w;
        v = sum(i, (if i < m { 1 } else { 0 }) * (p[2 * i] + dq)) * w;
    }",
    ));
    for m in 1..=4u32 {
        // mean(q_0 .. q_{m-1}) + mean(d_0 .. d_{m-1}) - p
        let mut want = vec![0.0; 2 * m as usize + 2];
        want[0] = -1.0;
        for k in 0..m as usize {
            want[1 + 2 * k] = 1.0 / m as f64;
            want[2 + 2 * k] = 1.0 / m as f64;
        }
        close(&row(&s, SectorKind::Crease, m, "v", 0), &want, 1e-15);
    }
}

#[test]
fn an_override_reads_the_definition_it_replaces() {
    let plain = compile(&scheme(""));
    let s = compile(&scheme(
        "    sector corner {
        v = if m < 3 { v } else { p };
        e[j] = if m < 2 { e[j] } else { (2 * p + p[2 * j]) / 3 };
    }",
    ));
    for m in 1..=2u32 {
        // Bit for bit the scheme's own rows on the virtual ring.
        for (a, b) in s
            .sector_rows(SectorKind::Corner, m)
            .iter()
            .zip(plain.sector_rows(SectorKind::Corner, m))
        {
            if s.vertex[a.0].name == "v" || m == 1 {
                assert_eq!(a.2, b.2, "m = {m} {}", s.vertex[a.0].name);
            }
        }
    }
    let mut want = vec![0.0; 8];
    want[0] = 1.0;
    close(&row(&s, SectorKind::Corner, 3, "v", 0), &want, 0.0);
    let mut want = vec![0.0; 6];
    want[0] = 2.0 / 3.0;
    want[3] = 1.0 / 3.0;
    close(&row(&s, SectorKind::Corner, 2, "e", 1), &want, 1e-15);
}

#[test]
fn sector_let_with_an_index_is_an_error() {
    let text = scheme(
        "    sector crease {
        let w[j] = p[2 * j];
        v = p;
    }",
    );
    expect_err(&text, "w[j]", &["`let w` is a single value"]);
}

#[test]
fn sector_let_named_like_a_vertex_definition_is_an_error() {
    let text = scheme(
        "    sector crease {
        let e = p;
    }",
    );
    expect_err(
        &text,
        "e = p;",
        &["`e` is a vertex definition", "`e[j] = …`, not `let`"],
    );
}

#[test]
fn unused_sector_let_is_an_error() {
    let text = scheme(
        "    sector crease {
        let wq = 1 / m;
        v = p;
    }",
    );
    expect_err(&text, "wq", &["`let wq` of `sector crease` is never used"]);
}

#[test]
fn sector_let_is_local_to_its_block() {
    let text = scheme(
        "    sector crease {
        let wq = 1 / m;
        v = (1 - wq) * p + wq * p[0];
    }
    sector corner {
        v = (1 - wq) * p + wq * p[0];
    }",
    );
    let at = text.rfind("wq) * p + wq").unwrap();
    let Err(e) = Scheme::from_source(&text, MAX) else {
        panic!("compiled, expected an error:\n{text}");
    };
    assert!(e.message.contains("undefined name `wq`"), "{e}");
    let line = text[..at].matches('\n').count() + 1;
    assert_eq!(e.line_column().0, line);
}

#[test]
fn override_reading_a_later_definition_is_an_error() {
    let text = scheme(
        "    sector crease {
        f[j] = (p + e[j]) / 2;
    }",
    );
    expect_err(
        &text,
        "(p + e[j]) / 2",
        &["the override of `f` reads `e`, which is not defined before `f`"],
    );
}

#[test]
fn m_outside_a_sector_block_is_an_error() {
    let text = scheme("").replace("/ 9;", "/ (9 * m / m);");
    expect_err(&text, "m / m", &["undefined name `m`"]);
}

/// The built-in scheme `name`'s source with its crease block's exact
/// tangents (everything from the `// m ≥ 3` comment to the end of the
/// override) removed: the construction before they were adopted.
fn without_exact_tangents(name: &str) -> (Scheme, Scheme) {
    let src = builtin_schemes()
        .into_iter()
        .find(|s| s.origin.ends_with(&format!("/{name}.tess")))
        .expect("builtin")
        .text;
    let start = src.find("        // m ≥ 3: the exact").expect("marker");
    let end = start + src[start..].find("        };\n").expect("end") + "        };\n".len();
    let old = format!("{}{}", &src[..start], &src[end..]);
    (compile(&src), compile(&old))
}

#[test]
fn builtin_exact_crease_tangents_leave_the_regular_sizes_bit_for_bit() {
    for name in ["acc", "gregory", "gregory_osd", "pccm"] {
        let (new, old) = without_exact_tangents(name);
        for kind in SectorKind::ALL {
            for m in 1..=16 {
                let (a, b) = (new.sector_rows(kind, m), old.sector_rows(kind, m));
                assert_eq!(a.len(), b.len());
                let same = a.iter().zip(&b).all(|(x, y)| x == y);
                let should = kind == SectorKind::Corner || m <= 2;
                assert_eq!(same, should, "{name} {} m = {m}", kind.name());
            }
        }
    }
}

#[test]
fn builtin_exact_crease_tangents_match_boundary_md() {
    // boundary.md §3.3, k = 3: the across mask over [p, q0, d0, q1, d1, q2, d2, q3].
    let x3 = [
        -0.580090, -0.309980, 0.082479, 0.435068, 0.164957, 0.435068, 0.082479, -0.309980,
    ];
    let pi = std::f64::consts::PI;
    let (acc, _) = without_exact_tangents("acc");
    let t0 = row(&acc, SectorKind::Crease, 3, "t", 0);
    let t1 = row(&acc, SectorKind::Crease, 3, "t", 1);
    // T_0 = T_along = (q0 - q3)/2; T_1 = cos(π/3) T_along + sin(π/3) X.
    let mut along = vec![0.0; 8];
    along[1] = 0.5;
    along[7] = -0.5;
    close(&t0, &along, 1e-15);
    let x: Vec<f64> = t1
        .iter()
        .zip(&t0)
        .map(|(t, a)| (t - (pi / 3.0).cos() * a) / (pi / 3.0).sin())
        .collect();
    close(&x, &x3, 1e-6);
    // The other schemes carry the same tangents: gregory's `let t` through
    // e = v + t/3, pccm t and gregory_osd e = v + T/3.
    for (name, out) in [("gregory", "e"), ("gregory_osd", "e"), ("pccm", "t")] {
        let (s, _) = without_exact_tangents(name);
        for m in 3..=6 {
            let v = row(&s, SectorKind::Crease, m, "v", 0);
            for j in 0..=m {
                let want: Vec<f64> = row(&acc, SectorKind::Crease, m, "t", j)
                    .iter()
                    .zip(&v)
                    .map(|(t, v)| v + t / 3.0)
                    .collect();
                close(&row(&s, SectorKind::Crease, m, out, j), &want, 1e-14);
            }
        }
    }
}
