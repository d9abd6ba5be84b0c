//! Scheme errors on the text path (`.tess` files, `Scheme::from_source`):
//! each mistake is reported with a clear message at the offending line and
//! column. The proc-macro path shares parser and checker; its compile-fail
//! tests live in `macros/tests/ui`.

use tessgen_codegen::{builtin_schemes, Scheme, SchemeError};

const MAX: u32 = 32;

/// The vertex stage of `regular.tess`; [`scheme`] adds a line after it.
const VERTEX_OK: &str = concat!(
    "        f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;\n",
    "        e[j] = (f[j - 1] + f[j]) / 2;\n",
    "        v = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5));",
);

/// The ordinary patch block of `regular.tess`.
const BICUBIC_OK: &str = concat!(
    "    patch ordinary: bicubic {\n",
    "        out b00[i] = v(i);\n",
    "        out b10[i] = e(i, 0);\n",
    "        out b01[i] = e(i, 1);\n",
    "        out b11[i] = f(i, 0);\n",
    "    }",
);

/// `regular.tess` with `vertex_extra` appended to the vertex stage (line 7)
/// and `patch` as its patch blocks (from line 9).
fn scheme(vertex_extra: &str, patch: &str) -> String {
    format!(
        "scheme broken {{\n    facet quad;\n    vertex {{\n{VERTEX_OK}\n{vertex_extra}\n    }}\n{patch}\n}}\n"
    )
}

fn compile_err(text: &str) -> SchemeError {
    match Scheme::from_source(text, MAX) {
        Ok(s) => panic!("scheme `{}` compiled, expected an error:\n{text}", s.name),
        Err(e) => e,
    }
}

/// Assert that `text` fails with a message containing every `fragment`, at
/// the line and column where `at` (a substring occurring exactly once in
/// `text`) starts. Returns the error for further checks.
#[track_caller]
fn expect_err(text: &str, at: &str, fragments: &[&str]) -> SchemeError {
    let e = compile_err(text);
    let hits: Vec<(usize, &str)> = text.match_indices(at).collect();
    assert_eq!(hits.len(), 1, "marker {at:?} must occur once in:\n{text}");
    let offset = hits[0].0;
    let want_line = text[..offset].matches('\n').count() + 1;
    let want_col = offset - text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let numbered: String = text
        .lines()
        .enumerate()
        .map(|(i, l)| format!("{:3} | {l}\n", i + 1))
        .collect();
    assert_eq!(
        e.line_column(),
        (want_line, want_col),
        "error `{e}` should point at {at:?} (line {want_line}, column {}) in:\n{numbered}",
        want_col + 1
    );
    for f in fragments {
        assert!(e.message.contains(f), "message {:?} lacks {f:?}", e.message);
    }
    e
}

fn regular_with_extraordinary(extra: &str) -> String {
    scheme(
        "",
        &format!(
            "{BICUBIC_OK}
    patch extraordinary: cpatch {{
        out v[i] = v(i);
        out t0[i] = e(i, 0);
        out t1[i] = e(i, 1);
        out b211[i] = f(i, 0);
        out b121[i] = f(i, 0);
{extra}
    }}"
        ),
    )
}

// ---------------------------------------------------------------------------
// Sanity: the templates themselves compile.
// ---------------------------------------------------------------------------

#[test]
fn templates_compile() {
    let s = Scheme::from_source(&scheme("", BICUBIC_OK), MAX).unwrap();
    assert_eq!(s.name, "broken");
    let s = Scheme::from_source(
        &regular_with_extraordinary("        out b112[i] = f(i, 0);"),
        MAX,
    )
    .unwrap();
    assert_eq!(s.patches.len(), 2);
}

// ---------------------------------------------------------------------------
// Names
// ---------------------------------------------------------------------------

#[test]
fn undefined_name_in_vertex_stage() {
    let text = scheme("        g[j] = (f[j] + w) / 2;", BICUBIC_OK);
    expect_err(&text, "w) / 2", &["undefined name `w`"]);
}

#[test]
fn undefined_indexed_name() {
    let text = scheme("        g[j] = (f[j] + q[j]) / 2;", BICUBIC_OK);
    expect_err(&text, "q[j]", &["undefined name `q`"]);
}

#[test]
fn undefined_name_in_patch_stage() {
    let patch = BICUBIC_OK.replace("out b11[i] = f(i, 0);", "out b11[i] = g(i, 0) + h;");
    let text = scheme("", &patch);
    // `g(…)` is the first unknown thing the checker meets.
    expect_err(&text, "g(i, 0)", &["undefined function `g`"]);
    let patch = BICUBIC_OK.replace("out b11[i] = f(i, 0);", "out b11[i] = f(i, 0) + 0 * h;");
    expect_err(&scheme("", &patch), "h;", &["undefined name `h`"]);
}

#[test]
fn undefined_name_in_const() {
    let text = scheme("", BICUBIC_OK).replace(
        "    facet quad;\n",
        "    facet quad;\n    const sigma = m / 2;\n",
    );
    expect_err(&text, "m / 2", &["undefined name `m`"]);
}

#[test]
fn undefined_function() {
    let text = scheme("        let w = tan(2 * pi / n);", BICUBIC_OK);
    expect_err(&text, "tan(", &["undefined function `tan`"]);
}

#[test]
fn vertex_output_read_as_function_in_vertex_stage() {
    // `f(j)` is the patch-stage spelling; in the vertex stage it is `f[j]`.
    let text = scheme("        g[j] = (f(j) + p) / 2;", BICUBIC_OK);
    expect_err(
        &text,
        "f(j)",
        &["`f` is a family over sectors: write `f[j]`"],
    );
}

// ---------------------------------------------------------------------------
// Index families
// ---------------------------------------------------------------------------

#[test]
fn family_without_index_in_vertex_stage() {
    let text = scheme("        g[j] = (f + p) / 2;", BICUBIC_OK);
    expect_err(
        &text,
        "f + p",
        &["`f` is a family over sectors", "`f[j]`", "index misuse"],
    );
}

#[test]
fn single_output_indexed_in_vertex_stage() {
    let text = scheme("        g[j] = (v[j] + p) / 2;", BICUBIC_OK);
    expect_err(
        &text,
        "v[j] + p",
        &["`v` is a single output, not a family", "index misuse"],
    );
}

#[test]
fn family_read_at_corner_without_offset_in_patch_stage() {
    let patch = BICUBIC_OK.replace("out b10[i] = e(i, 0);", "out b10[i] = e(i);");
    let text = scheme("", &patch);
    expect_err(
        &text,
        "e(i);",
        &[
            "`e` is a family over sectors",
            "`e(corner, sector_offset)`",
            "index misuse",
        ],
    );
}

#[test]
fn single_output_read_with_offset_in_patch_stage() {
    let patch = BICUBIC_OK.replace("out b00[i] = v(i);", "out b00[i] = v(i, 0);");
    let text = scheme("", &patch);
    expect_err(
        &text,
        "v(i, 0)",
        &[
            "`v` is a single vertex output",
            "`v(corner)`",
            "index misuse",
        ],
    );
}

#[test]
fn vertex_output_bracketed_in_patch_stage() {
    let patch = BICUBIC_OK.replace("out b10[i] = e(i, 0);", "out b10[i] = e[i];");
    let text = scheme("", &patch);
    expect_err(
        &text,
        "e[i]",
        &["`e(i, offset)`", "not `e[…]`", "index misuse"],
    );
}

#[test]
fn vertex_output_unread_in_patch_stage() {
    let patch = BICUBIC_OK.replace("out b00[i] = v(i);", "out b00[i] = v;");
    let text = scheme("", &patch);
    expect_err(&text, "v;", &["vertex output `v` must be read at a corner"]);
}

#[test]
fn patch_local_family_without_index() {
    let patch = BICUBIC_OK.replace(
        "out b11[i] = f(i, 0);",
        "m[i] = f(i, 0);\n        out b11[i] = m;",
    );
    let text = scheme("", &patch);
    expect_err(
        &text,
        "m;",
        &["`m` is per corner: write `m[i]`", "index misuse"],
    );
}

#[test]
fn patch_local_single_indexed() {
    let patch = BICUBIC_OK.replace(
        "out b11[i] = f(i, 0);",
        "m = f(0, 0);\n        out b11[i] = m[i];",
    );
    let text = scheme("", &patch);
    expect_err(
        &text,
        "m[i]",
        &["`m` is not per corner: write `m`", "index misuse"],
    );
}

#[test]
fn const_without_corner_in_patch_stage() {
    let text =
        regular_with_extraordinary("        out b112[i] = f(i, 0) + sigma * (f(i, 0) - v(i));")
            .replace(
                "    facet quad;\n",
                "    facet quad;\n    const sigma = 1 / n;\n",
            );
    expect_err(
        &text,
        "sigma * (",
        &["`sigma` is per valence", "`sigma(i)`"],
    );
}

#[test]
fn out_control_point_without_index() {
    let patch = BICUBIC_OK.replace("out b11[i] = f(i, 0);", "out b11 = f(0, 0);");
    let text = scheme("", &patch);
    expect_err(
        &text,
        "b11 =",
        &["control point `b11` is per corner", "`out b11[i] = …`"],
    );
}

// ---------------------------------------------------------------------------
// Types
// ---------------------------------------------------------------------------

#[test]
fn point_times_point() {
    let text = scheme("        g[j] = p * p[2 * j];", BICUBIC_OK);
    expect_err(&text, "p * p[2 * j]", &["cannot multiply two points"]);
}

#[test]
fn point_times_point_in_patch_stage() {
    let patch = BICUBIC_OK.replace("out b11[i] = f(i, 0);", "out b11[i] = f(i, 0) * v(i);");
    let text = scheme("", &patch);
    expect_err(&text, "f(i, 0) * v(i)", &["cannot multiply two points"]);
}

#[test]
fn divide_by_point() {
    let text = scheme("        g[j] = 1 / p;", BICUBIC_OK);
    expect_err(&text, "1 / p", &["cannot divide by a point"]);
}

#[test]
fn point_plus_number() {
    let text = scheme("        g[j] = p + 1;", BICUBIC_OK);
    expect_err(
        &text,
        "p + 1",
        &["cannot combine a point and an integer with `+`"],
    );
}

#[test]
fn non_integer_index() {
    let text = scheme("        g[j] = p[j / 2];", BICUBIC_OK);
    expect_err(
        &text,
        "j / 2",
        &["an index must be integer arithmetic", "found a number"],
    );
}

#[test]
fn point_as_index() {
    let text = scheme("        g[j] = p[p];", BICUBIC_OK);
    expect_err(
        &text,
        "p];",
        &["an index must be integer arithmetic", "found a point"],
    );
}

#[test]
fn vertex_output_that_is_a_number() {
    let text = scheme("        g = 2 * n;", BICUBIC_OK);
    expect_err(
        &text,
        "2 * n;",
        &[
            "vertex output `g` must be a point",
            "found an integer",
            "use `let`",
        ],
    );
}

#[test]
fn function_of_a_point() {
    let text = scheme("        g[j] = cos(p) * p;", BICUBIC_OK);
    expect_err(&text, "p) * p", &["`cos` takes a number, found a point"]);
}

// ---------------------------------------------------------------------------
// Affine invariance
// ---------------------------------------------------------------------------

#[test]
fn vertex_row_not_summing_to_one() {
    let text = scheme("", BICUBIC_OK).replace(
        "f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;",
        "f[j] = (4 * p + 2 * p[2 * j]) / 9;",
    );
    let e = expect_err(
        &text,
        "f[j] = (4",
        &["row `f[0]`", "at valence 3", "expected 1", "a point"],
    );
    assert!(e.message.contains("0.666666"), "{}", e.message);
}

#[test]
fn vertex_row_wrong_only_at_high_valence() {
    let text = scheme(
        "        g = if n < 7 { p } else { (p + p[0]) / 3 };",
        BICUBIC_OK,
    );
    expect_err(&text, "g = if", &["row `g`", "at valence 7", "expected 1"]);
}

#[test]
fn vertex_row_wrong_at_the_maximum_valence_only() {
    // Rows are checked at every valence up to the requested maximum.
    let text = scheme("        g = if n < 32 { p } else { 2 * p };", BICUBIC_OK);
    Scheme::from_source(&text, 31).unwrap();
    let e = Scheme::from_source(&text, 32).unwrap_err();
    assert!(e.message.contains("at valence 32"), "{}", e.message);
}

#[test]
fn vector_row_not_summing_to_zero() {
    let text = scheme("        vector d[j] = p[2 * j] + p;", BICUBIC_OK);
    expect_err(
        &text,
        "vector d[j]",
        &[
            "row `d[0]`",
            "weights sum to 2",
            "expected 0",
            "a tangent vector",
        ],
    );
}

#[test]
fn vector_row_summing_to_zero_is_fine() {
    let text = scheme("        vector d[j] = p[2 * j] - p;", BICUBIC_OK);
    Scheme::from_source(&text, MAX).unwrap();
}

#[test]
fn patch_out_not_affine() {
    let patch = BICUBIC_OK.replace("out b10[i] = e(i, 0);", "out b10[i] = e(i, 0) + e(i, 1);");
    let text = scheme("", &patch);
    expect_err(
        &text,
        "out b10[i]",
        &[
            "control point `b10[0]`",
            "bicubic slot b10",
            "weights sum to 2",
            "[4, 4, 4, 4]",
            "expected 1",
        ],
    );
}

#[test]
fn patch_out_not_affine_at_some_valence() {
    // Affine at valence 4 only: caught on an extraordinary corner tuple.
    let text = regular_with_extraordinary("        out b112[i] = (n(i) - 3) * f(i, 0);");
    expect_err(
        &text,
        "out b112[i]",
        &[
            "control point `b112[0]`",
            "cpatch slot b112",
            "corner valences [3, 3, 3, 3]",
            "expected 1",
        ],
    );
}

#[test]
fn patch_out_through_a_local_not_affine() {
    let patch = BICUBIC_OK.replace(
        "out b11[i] = f(i, 0);",
        "m[i] = f(i, 0) - v(i);\n        out b11[i] = m[i];",
    );
    let text = scheme("", &patch);
    expect_err(
        &text,
        "out b11[i]",
        &["control point `b11[0]`", "weights sum to 0"],
    );
}

#[test]
fn non_finite_constant() {
    let text = scheme("", BICUBIC_OK).replace(
        "    facet quad;\n",
        "    facet quad;\n    const z = 1 / (n - 5);\n",
    );
    expect_err(&text, "z =", &["constant `z` is not finite at valence 5"]);
}

// ---------------------------------------------------------------------------
// Patch blocks
// ---------------------------------------------------------------------------

#[test]
fn missing_form_slot() {
    let patch = BICUBIC_OK.replace("        out b11[i] = f(i, 0);\n", "");
    let text = scheme("", &patch);
    expect_err(
        &text,
        "bicubic {",
        &["form `bicubic` needs `out b11[i] = …`"],
    );
}

#[test]
fn unknown_slot() {
    let patch = BICUBIC_OK.replace("out b11[i] = f(i, 0);", "out b22[i] = f(i, 0);");
    let text = scheme("", &patch);
    expect_err(
        &text,
        "b22",
        &[
            "`b22` is not a control point of form `bicubic`",
            "b00, b10, b01, b11",
        ],
    );
}

/// A bicubic ordinary class beside a biquartic extraordinary one: their
/// shared edges would be a cubic on one side and a quartic on the other.
#[test]
fn classes_with_boundaries_of_different_degree() {
    let gregory4 = concat!(
        "    patch extraordinary: gregory4 {\n",
        "        out p[i] = v(i);\n",
        "        out ep[i] = e(i, 0);\n",
        "        out em[i] = e(i, 1);\n",
        "        out m[i] = (e(i, 0) + e(i + 1, 1)) * 0.5;\n",
        "        out fp[i] = f(i, 0);\n",
        "        out fm[i] = f(i, 0);\n",
        "        out g[i] = f(i, 0);\n",
        "        out center = (f(0, 0) + f(2, 0)) * 0.5;\n",
        "    }",
    );
    // The biquartic class alone compiles: the check is about the pair.
    let alone = scheme("", &gregory4.replace("extraordinary", "ordinary"));
    Scheme::from_source(&alone, MAX).unwrap_or_else(|e| panic!("{e}"));
    let text = scheme("", &format!("{BICUBIC_OK}\n{gregory4}"));
    expect_err(
        &text,
        "gregory4",
        &[
            "form `gregory4` has 5-point boundary curves but class `ordinary` uses `bicubic` with 4",
            "boundaries of the same degree",
        ],
    );
}

#[test]
fn unknown_form() {
    let text = scheme("", &BICUBIC_OK.replace("bicubic", "bspline"));
    expect_err(
        &text,
        "bspline",
        &[
            "unknown patch form `bspline`",
            "`bicubic`, `cpatch`, `acc`, `gregory`, `gregory4` or `tri_cubic`",
        ],
    );
}

#[test]
fn unknown_patch_class() {
    let text = scheme("", &BICUBIC_OK.replace("ordinary", "regular"));
    expect_err(
        &text,
        "regular: bicubic",
        &[
            "unknown patch class `regular`",
            "`ordinary` or `extraordinary`",
        ],
    );
}

#[test]
fn valence_n_in_patch_stage() {
    let patch = BICUBIC_OK.replace("out b00[i] = v(i);", "out b00[i] = v(i) * n / 4;");
    let text = scheme("", &patch);
    expect_err(&text, "n / 4", &["valences are per corner", "`n(i)`"]);
}

#[test]
fn if_in_patch_stage() {
    let patch = BICUBIC_OK.replace(
        "out b00[i] = v(i);",
        "out b00[i] = if n(i) == 4 { v(i) } else { f(i, 0) };",
    );
    let text = scheme("", &patch);
    expect_err(
        &text,
        "if n(i)",
        &[
            "`if` is decided per valence",
            "only allowed in constants and the vertex stage",
        ],
    );
}

#[test]
fn unknown_facet() {
    let text = scheme("", BICUBIC_OK).replace("facet quad;", "facet hex;");
    expect_err(&text, "hex;", &["unknown facet `hex`", "`quad` or `tri`"]);
}

#[test]
fn out_in_vertex_stage() {
    let text = scheme("        out g = p;", BICUBIC_OK);
    expect_err(&text, "out g", &["`out` is only valid in a `patch` block"]);
}

#[test]
fn vector_in_patch_stage() {
    let patch = BICUBIC_OK.replace(
        "out b11[i] = f(i, 0);",
        "out b11[i] = f(i, 0);\n        vector d[i] = f(i, 0) - v(i);",
    );
    let text = scheme("", &patch);
    expect_err(
        &text,
        "vector d[i]",
        &["`vector` marks vertex-stage outputs"],
    );
}

// ---------------------------------------------------------------------------
// Duplicates and reserved names
// ---------------------------------------------------------------------------

#[test]
fn duplicate_vertex_definition() {
    let text = scheme("        f = p;", BICUBIC_OK);
    expect_err(&text, "f = p;", &["`f` is defined twice"]);
}

#[test]
fn duplicate_const() {
    let text = scheme("", BICUBIC_OK).replace(
        "    facet quad;\n",
        "    facet quad;\n    const c = cos(2 * pi / n);\n    const s = sin(2 * pi / n);\n    const c = 1;\n",
    );
    expect_err(&text, "c = 1;", &["`c` is defined twice"]);
}

#[test]
fn const_and_vertex_output_share_a_name() {
    let text =
        scheme("", BICUBIC_OK).replace("    facet quad;\n", "    facet quad;\n    const v = 1;\n");
    expect_err(&text, "v = (n * n", &["`v` is defined twice"]);
}

#[test]
fn duplicate_patch_local() {
    let patch = BICUBIC_OK.replace(
        "out b11[i] = f(i, 0);",
        "m[i] = f(i, 0);\n        m = v(0);\n        out b11[i] = m[i];",
    );
    let text = scheme("", &patch);
    expect_err(&text, "m = v(0)", &["`m` is defined twice"]);
}

#[test]
fn patch_local_shadowing_vertex_output() {
    let patch = BICUBIC_OK.replace(
        "out b11[i] = f(i, 0);",
        "e[i] = f(i, 0);\n        out b11[i] = e[i];",
    );
    let text = scheme("", &patch);
    expect_err(&text, "e[i] = f", &["`e` is defined twice"]);
}

#[test]
fn duplicate_out() {
    let patch = BICUBIC_OK.replace(
        "out b11[i] = f(i, 0);",
        "out b11[i] = f(i, 0);\n        out b10 [i] = e(i, 0);",
    );
    let text = scheme("", &patch);
    expect_err(&text, "b10 [i]", &["`out b10` given twice"]);
}

#[test]
fn duplicate_patch_class() {
    let text = scheme(
        "",
        &format!(
            "{BICUBIC_OK}\n{}",
            BICUBIC_OK.replace("ordinary:", "ordinary :")
        ),
    );
    expect_err(
        &text,
        "ordinary : bicubic",
        &["patch class `ordinary` given twice"],
    );
}

#[test]
fn reserved_name() {
    let text = scheme("        sum = p;", BICUBIC_OK);
    expect_err(&text, "sum = p;", &["`sum` is a reserved name"]);
}

// ---------------------------------------------------------------------------
// Syntax and tokens
// ---------------------------------------------------------------------------

#[test]
fn missing_semicolon() {
    let text = scheme("", BICUBIC_OK).replace("/ 9;", "/ 9");
    let e = compile_err(&text);
    assert!(e.message.contains("expected `;`"), "{e}");
    // syn reports the token where `;` was expected: the start of the next
    // definition, one line below the missing semicolon.
    assert_eq!(e.line_column(), (5, 8), "{e}\n{text}");
}

// Tokenizer errors all read "cannot tokenize scheme source: cannot parse
// string into token stream" (proc_macro2's LexError carries no detail); the
// location is what tells them apart.

#[test]
fn unterminated_string() {
    let text = scheme("        let w = \"oops;", BICUBIC_OK);
    expect_err(&text, "\"oops", &["cannot tokenize scheme source"]);
}

#[test]
fn stray_character() {
    let text = scheme("        g[j] = p ` p[j];", BICUBIC_OK);
    expect_err(&text, "` p[j]", &["cannot tokenize scheme source"]);
}

#[test]
fn unterminated_block_comment() {
    let text = scheme("        /* unterminated", BICUBIC_OK);
    expect_err(&text, "/* unterminated", &["cannot tokenize scheme source"]);
}

#[test]
fn unbalanced_parenthesis() {
    let text = scheme("", BICUBIC_OK).replace(
        "e[j] = (f[j - 1] + f[j]) / 2;",
        "e[j] = (f[j - 1] + f[j] / 2;",
    );
    // Reported at the `}` that closes the vertex block while `(` is open.
    expect_err(&text, "}\n    patch", &["cannot tokenize scheme source"]);
}

#[test]
fn unknown_item() {
    let text =
        scheme("", BICUBIC_OK).replace("    facet quad;\n", "    facet quad;\n    valence 3;\n");
    expect_err(
        &text,
        "valence 3",
        &["expected `facet`, `const`, `vertex`, `sector` or `patch`"],
    );
}

#[test]
fn missing_patch_block() {
    let text = scheme("", "");
    expect_err(&text, "broken", &["at least one `patch` block"]);
}

#[test]
fn unsupported_expression() {
    let text = scheme("        g[j] = p[2 * j] % 2;", BICUBIC_OK);
    expect_err(&text, "p[2 * j] %", &["only + - * / are supported"]);
}

// ---------------------------------------------------------------------------
// Built-in schemes
// ---------------------------------------------------------------------------

#[test]
fn builtin_schemes_compile_at_spot_valences() {
    for src in builtin_schemes() {
        for max in [4, 5, 8, 9, 16, 32, 64] {
            let s = src
                .compile(max)
                .unwrap_or_else(|e| panic!("{} at max valence {max}: {e}", src.origin));
            assert!(!s.name.is_empty());
            // Triangle schemes have no vertex stage (pn.md).
            let tri = s.facet == tessgen_codegen::scheme::Facet::Tri;
            assert_eq!(s.vertex_rows(max).is_empty(), tri, "{}", src.origin);
        }
    }
}

#[test]
fn max_valence_below_four_is_rejected() {
    for src in builtin_schemes() {
        let e = Scheme::from_source(&src.text, 3).unwrap_err();
        assert!(e.message.contains("max valence must be at least 4"), "{e}");
    }
}

#[test]
fn builtin_error_display_has_line_and_column() {
    let text = scheme("        g[j] = (f + p) / 2;", BICUBIC_OK);
    let e = compile_err(&text);
    let (l, c) = e.line_column();
    assert_eq!(
        e.to_string(),
        format!("line {l}, column {}: {}", c + 1, e.message)
    );
}

#[test]
fn control_point_that_is_a_number() {
    let patch = BICUBIC_OK.replace("out b00[i] = v(i);", "out b00[i] = 1;");
    let text = scheme("", &patch);
    expect_err(
        &text,
        "1;",
        &["control point `b00` must be a point", "found an integer"],
    );
}

#[test]
fn if_without_else() {
    let text = scheme("        g = if n == 4 { p };", BICUBIC_OK);
    expect_err(&text, "if n == 4", &["`if` needs an `else` branch"]);
}

#[test]
fn sum_in_a_constant() {
    let text = scheme("", BICUBIC_OK).replace(
        "    facet quad;\n",
        "    facet quad;\n    const z = sum(k, k);\n",
    );
    expect_err(&text, "sum(k, k)", &["`sum` is not available in constants"]);
}

#[test]
fn vertex_stage_without_outputs() {
    let text = "scheme lonely {\n    facet quad;\n    vertex {\n        let w = 2;\n    }\n    patch ordinary: bicubic {\n        out b00[i] = 0;\n    }\n}\n";
    expect_err(text, "lonely", &["the vertex stage exports no output"]);
}

#[test]
fn index_variable_out_of_scope() {
    // `j` only exists in a definition indexed by `[j]`.
    let text = scheme("        g = p[2 * j];", BICUBIC_OK);
    expect_err(&text, "j];", &["undefined name `j`"]);
}

// The cases below are located correctly but their messages only say
// "undefined name/function"; they assert the location and the name so that
// a more specific message can replace the wording without breaking them.

#[test]
fn forward_reference_in_vertex_stage() {
    // Definitions are read in order: `e` is defined after `f`.
    let text = scheme("", BICUBIC_OK).replace("f[j] = (4 * p", "f[j] = (4 * e[j]");
    expect_err(&text, "e[j] +", &["`e`"]);
}

#[test]
fn out_slot_read_back_in_patch_stage() {
    let patch = BICUBIC_OK.replace("out b10[i] = e(i, 0);", "out b10[i] = b00[i];");
    let text = scheme("", &patch);
    expect_err(&text, "b00[i];", &["`b00`"]);
}

#[test]
fn ring_in_patch_stage() {
    let patch = BICUBIC_OK.replace("out b00[i] = v(i);", "out b00[i] = p;");
    let text = scheme("", &patch);
    expect_err(&text, "p;", &["`p`"]);
}

#[test]
fn vertex_let_in_patch_stage() {
    let patch = BICUBIC_OK.replace("out b00[i] = v(i);", "out b00[i] = w;");
    let text = scheme("        let w = p;", &patch);
    expect_err(&text, "w;", &["`w`"]);
}

#[test]
fn patch_stage_spellings_in_vertex_stage() {
    let text = scheme("        g = n(0) * p;", BICUBIC_OK);
    expect_err(&text, "n(0)", &["`n`"]);
    let text = scheme("        g = c(0) * p;", BICUBIC_OK)
        .replace("    facet quad;\n", "    facet quad;\n    const c = 1;\n");
    expect_err(&text, "c(0)", &["`c`"]);
}

/// A small triangle scheme with `body` as its patch block contents.
fn tri_scheme(body: &str) -> String {
    format!(
        "scheme broken {{\n    facet tri;\n    patch triangle: tri_cubic {{\n{body}\n    }}\n}}\n"
    )
}

const TRI_OK: &str = concat!(
    "        out b[i] = P(i);\n",
    "        out bn[i] = (2 * P(i) + P(i + 1)) / 3;\n",
    "        out bp[i] = (2 * P(i) + P(i - 1)) / 3;\n",
    "        out center = sum(k, P(k)) / 3;\n",
    "        out n[i] = N(i);\n",
    "        out nm[i] = N(i) + N(i + 1);",
);

#[test]
fn triangle_scheme_compiles() {
    let s = Scheme::from_source(&tri_scheme(TRI_OK), MAX).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.facet.sides(), 3);
}

#[test]
fn triangle_scheme_with_a_vertex_block() {
    let text = "scheme broken {\n    facet tri;\n    vertex {\n        v = p;\n    }\n    patch triangle: tri_cubic {\n        out b[i] = P(i);\n    }\n}\n";
    expect_err(text, "tri;", &["`facet tri` scheme has no `vertex` block"]);
}

#[test]
fn quad_form_in_a_triangle_scheme() {
    let text = tri_scheme(TRI_OK).replace("tri_cubic", "bicubic");
    expect_err(&text, "bicubic", &["form `bicubic` is for `quad` facets"]);
}

#[test]
fn quad_class_in_a_triangle_scheme() {
    let text = tri_scheme(TRI_OK).replace("patch triangle", "patch ordinary");
    expect_err(
        &text,
        "ordinary",
        &["a `facet tri` scheme has one class, `triangle`"],
    );
}

#[test]
fn single_slot_written_per_corner() {
    let text = tri_scheme(&TRI_OK.replace("out center = ", "out center[i] = "));
    expect_err(&text, "center", &["exists once per patch"]);
}

#[test]
fn missing_single_slot() {
    let text = tri_scheme(&TRI_OK.replace("        out center = sum(k, P(k)) / 3;\n", ""));
    expect_err(&text, "tri_cubic", &["needs `out center = …`"]);
}

#[test]
fn dot_of_a_number() {
    let text =
        tri_scheme(&TRI_OK.replace("out n[i] = N(i);", "out n[i] = normalize(dot(N(i), N(i)));"));
    expect_err(
        &text,
        "dot(N(i), N(i))",
        &["`normalize` takes vectors, found a number"],
    );
}

#[test]
fn dot_in_a_quad_scheme() {
    let text = scheme("        w = p * dot(p, p);", BICUBIC_OK);
    expect_err(&text, "dot", &["only available in `facet tri` schemes"]);
}

/// Crease-tag inputs (scalar-tagged PN): scalars where a point is needed,
/// the wrong number of arguments, and use in a quad scheme are errors at
/// the offending call.
#[test]
fn crease_tag_inputs_are_typed() {
    let text = tri_scheme(&TRI_OK.replace("out n[i] = N(i);", "out n[i] = sharpness(i);"));
    expect_err(&text, "sharpness(i)", &["a number"]);
    let text = tri_scheme(&TRI_OK.replace(
        "out n[i] = N(i);",
        "out n[i] = normalize(N(i) + Delta(i, 1));",
    ));
    expect_err(
        &text,
        "Delta(i, 1)",
        &["`Delta(corner)` takes one argument"],
    );
    let text = tri_scheme(&TRI_OK.replace(
        "out n[i] = N(i);",
        "out n[i] = normalize(N(i) + side(i) * tension(i) * Delta(i));",
    ));
    Scheme::from_source(&text, MAX).unwrap_or_else(|e| panic!("{e}"));
    let text = scheme("        w = p * side(0);", BICUBIC_OK);
    expect_err(&text, "side(0)", &["`side`"]);
}

/// `regular.tess` with `sector` blocks `sectors` after its vertex stage.
fn with_sectors(sectors: &str) -> String {
    format!(
        "scheme broken {{\n    facet quad;\n    vertex {{\n{VERTEX_OK}\n    }}\n{sectors}\n{BICUBIC_OK}\n}}\n"
    )
}

#[test]
fn sector_blocks_compile_and_override() {
    let text = with_sectors(
        "    sector crease {\n        v = (p[0] + 4 * p + p[2 * m]) / 6;\n        sharp e[j] = (2 * p + p[2 * j]) / 3;\n    }",
    );
    let s = Scheme::from_source(&text, MAX).unwrap_or_else(|e| panic!("{}", e.message));
    // v of a crease sector of 3 faces: the crease limit over [p, q0, .., q3].
    let rows = s.sector_rows(tessgen_codegen::scheme::SectorKind::Crease, 3);
    let (_, _, v) = rows
        .iter()
        .find(|(d, _, _)| s.vertex[*d].name == "v")
        .expect("v row");
    let want = [4.0 / 6.0, 1.0 / 6.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0 / 6.0];
    for (a, b) in v.iter().zip(want) {
        assert!((a - b).abs() < 1e-15, "{v:?}");
    }
}

#[test]
fn sector_errors_point_at_the_line() {
    expect_err(
        &with_sectors("    sector hinge {\n        v = p;\n    }"),
        "hinge",
        &["unknown sector kind `hinge`", "crease", "corner"],
    );
    expect_err(
        &with_sectors("    sector crease {\n        w = p;\n    }"),
        "w = p",
        &["`w` is not a vertex definition"],
    );
    expect_err(
        &with_sectors("    sector corner {\n        sharp v = p;\n    }"),
        "v = p",
        &["`sharp`", "single output"],
    );
    // An override may read only definitions declared before the one it
    // overrides: `f` before `e` (no cycles through the overrides).
    expect_err(
        &with_sectors("    sector crease {\n        f[j] = e[j];\n    }"),
        "e[j];",
        &["reads `e`", "not defined before `f`"],
    );
    // The weight-sum check covers sector rows.
    expect_err(
        &with_sectors("    sector crease {\n        v = 2 * p;\n    }"),
        "v = 2 * p",
        &["weights sum to 2", "crease sector of 1 faces"],
    );
    // `m` only means something in a sector block.
    expect_err(
        &scheme("        let g = m;", BICUBIC_OK),
        "m;",
        &["undefined name `m`"],
    );
}
