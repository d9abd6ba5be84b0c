//! `scheme!` expands to a `SchemeSource` that the build-time path accepts.

use tessgen_codegen::{Builder, Class, Scheme, SchemeSource, Target, DEFAULT_MAX_VALENCE};
use tessgen_macros::scheme;

/// PCCM with a user-chosen σ away from valence 4 (pccm.tess uses the
/// closed form); at n = 4 the tangents are still the bicubic edge points.
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

#[test]
fn origin_names_this_file_and_line() {
    let src = pccm_sigma();
    assert!(
        src.origin.starts_with("scheme! in ") && src.origin.contains("expand.rs:"),
        "origin: {}",
        src.origin
    );
    let line: u32 = src.origin.rsplit(':').next().unwrap().parse().unwrap();
    assert!(line > 0, "origin: {}", src.origin);
}

#[test]
fn text_reparses_to_the_same_scheme() {
    let src = pccm_sigma();
    let s = Scheme::from_source(&src.text, DEFAULT_MAX_VALENCE)
        .unwrap_or_else(|e| panic!("{e}\n--- text ---\n{}", src.text));
    assert_eq!(s.name, "pccm_sigma");
    assert_eq!(
        s.doc,
        "PCCM with a flat sigma = 0.6 at extraordinary vertices."
    );
    assert_eq!(
        s.consts.iter().map(|c| c.name.as_str()).collect::<Vec<_>>(),
        ["c", "s", "sigma"]
    );
    let outputs: Vec<&str> = s.outputs().map(|(_, d)| d.name.as_str()).collect();
    assert_eq!(outputs, ["f", "e", "v", "t"]);
    assert!(s.patch(Class::Ordinary).is_some());
    assert!(s.patch(Class::Extraordinary).is_some());
    // sigma is the user's, not PCCM's closed form.
    assert_eq!(s.const_values(5)[2], 0.6);
    assert_eq!(s.const_values(4)[2], 0.5);
}

#[test]
fn builder_compiles_the_macro_scheme() {
    let out = Builder::new()
        .scheme(pccm_sigma())
        .target(Target::Rust)
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.schemes.len(), 1);
    assert_eq!(out.schemes[0].name, "pccm_sigma");
    let rust = out.file("rust/tessgen.rs").expect("Rust output");
    assert!(!rust.contents.is_empty());
    assert!(out.file("table/stencils.f32").is_some());
}

#[test]
fn macro_scheme_sits_beside_the_builtins() {
    let out = Builder::new()
        .builtin_schemes()
        .scheme(pccm_sigma())
        .target(Target::Rust)
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = out.schemes.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "regular",
            "pccm",
            "acc",
            "gregory",
            "gregory_osd",
            "pn",
            "stpn",
            "phong",
            "g1cc",
            "pccm_sigma"
        ]
    );
}

#[test]
fn macro_and_file_paths_agree_on_rows() {
    // The same scheme through the macro and through text gives the same
    // vertex-stage weights (a `.tess` copy of the macro body).
    let src = pccm_sigma();
    let via_text = Scheme::from_source(&src.text, 16).unwrap();
    let pccm = tessgen_codegen::builtin_schemes()
        .into_iter()
        .find(|s| s.text.contains("scheme pccm"))
        .unwrap()
        .compile(16)
        .unwrap();
    // Same stencils where sigma is irrelevant (f, e, v) and at n = 4 (t = e).
    for n in [3, 4, 5, 8] {
        let a = via_text.vertex_rows(n);
        let b = pccm.vertex_rows(n);
        assert_eq!(a.len(), b.len());
        for ((da, ja, ra), (db, jb, rb)) in a.iter().zip(&b) {
            assert_eq!((da, ja), (db, jb));
            let name = &via_text.vertex[*da].name;
            if name != "t" || n == 4 {
                for (x, y) in ra.iter().zip(rb) {
                    assert!((x - y).abs() < 1e-12, "{name}[{ja}] at n = {n}");
                }
            }
        }
    }
}

#[test]
fn small_bicubic_only_scheme() {
    let src = scheme! {
        scheme tiny {
            facet quad;
            vertex {
                f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;
                e[j] = (f[j - 1] + f[j]) / 2;
                v = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5));
            }
            patch ordinary: bicubic {
                out b00[i] = v(i);
                out b10[i] = e(i, 0);
                out b01[i] = e(i, 1);
                out b11[i] = f(i, 0);
            }
        }
    };
    let s = src.compile(DEFAULT_MAX_VALENCE).unwrap();
    assert_eq!(s.name, "tiny");
    assert_eq!(s.rows_linear(), (2, 1));
}
