//! Declares a scheme of our own with `scheme!` and generates its Rust and
//! WGSL into OUT_DIR. A mistake in the scheme is a compile error of this
//! build script, pointing at the offending line.

use tessgen_codegen::{Builder, Target};
use tessgen_macros::scheme;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    // PCCM with a user-chosen tangent scale: σ_n = 0.6 for n ≠ 4 (σ_4 must
    // stay ½ so that t = e at valence 4 and boundaries with bicubic patches
    // stay bit-identical).
    let pccm_sigma = scheme! {
        /// PCCM c-patches with a user-chosen σ_n (0.6 for n ≠ 4).
        scheme pccm_sigma {
            facet quad;
            const c = cos(2 * pi / n);
            const s = sin(2 * pi / n);
            const sigma = if n == 4 { 0.5 } else { 0.6 };
            vertex {
                f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;
                e[j] = (f[j - 1] + f[j]) / 2;
                v = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5));
                t[j] = if n == 4 { e[j] } else { v + 4 * sigma / n * sum(k, cos(2 * pi * (k - j) / n) * e[k]) };
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
                b211[i] = (v(i) + 3 * t(i, 0)) / 4 + (1 + c(i)) / 4 * (t(i + 1, 1) - t(i, 0))
                    + (1 - c(i + 1)) / 8 * (t(i, 0) - v(i)) + kappa[i] * (f(i, 0) - e(i, 0));
                b121[i] = (v(i + 1) + 3 * t(i + 1, 1)) / 4 + (1 + c(i + 1)) / 4 * (t(i, 0) - t(i + 1, 1))
                    + (1 - c(i)) / 8 * (t(i + 1, 1) - v(i + 1)) + kappa[i] * (f(i + 1, 0) - e(i + 1, 1));
                out v[i] = v(i);
                out t0[i] = t(i, 0);
                out t1[i] = t(i, 1);
                out b211[i] = b211[i];
                out b121[i] = b121[i];
                out b112[i] = gstar + 3 / 16 * (b211[i] + b121[i] - b211[i - 1] - b121[i + 1])
                    + 1 / 16 * (b211[i + 1] + b121[i - 1] - b211[i + 2] - b121[i + 2]);
            }
        }
    };
    let out = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    if let Err(e) = Builder::new()
        .scheme(pccm_sigma)
        .target(Target::Rust)
        .target(Target::Wgsl)
        .out_dir(out)
        .command("examples/custom_scheme/build.rs")
        .write()
    {
        panic!("tessgen: {e}");
    }
}
