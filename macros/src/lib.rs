//! `scheme! { scheme NAME { … } }`: declare a tessgen patch scheme in Rust
//! source and have it checked when the crate compiles.
//!
//! The macro runs the very parser and checker that `.tess` files go through
//! ([`tessgen_codegen::dsl::parse_tokens`] and
//! [`tessgen_codegen::Scheme::from_ast`]), so a scheme accepted here is
//! accepted by [`tessgen_codegen::Builder`] and vice versa, with the same
//! error messages. Errors are reported at the offending token.

use proc_macro::TokenStream;

/// Declare a scheme in the scheme DSL (see `tessgen_codegen::dsl`) and check
/// it at compile time.
///
/// The invocation expands to an expression of type
/// `::tessgen_codegen::SchemeSource` whose origin is `scheme! in FILE:LINE`
/// and whose text is the scheme itself, ready for
/// [`Builder::scheme`](tessgen_codegen::Builder::scheme). The expansion names
/// `::tessgen_codegen`, so the calling crate (typically its build script,
/// through `[build-dependencies]`) must depend on `tessgen-codegen` as well.
///
/// Any parse error, undefined name, index-family misuse, ill-typed
/// expression or row that is not affine (weights not summing to 1, or 0 for
/// a `vector`) at some valence up to
/// [`DEFAULT_MAX_VALENCE`](tessgen_codegen::DEFAULT_MAX_VALENCE) becomes a
/// compile error at the offending token.
///
/// ```ignore
/// // build.rs
/// use tessgen_macros::scheme;
///
/// fn main() {
///     let out = std::env::var("OUT_DIR").unwrap();
///     tessgen_codegen::Builder::new()
///         .scheme(scheme! {
///             /// The bicubic B-spline on ordinary quads.
///             scheme my_regular {
///                 facet quad;
///                 vertex {
///                     f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;
///                     e[j] = (f[j - 1] + f[j]) / 2;
///                     v = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1]))
///                         / (n * (n + 5));
///                 }
///                 patch ordinary: bicubic {
///                     out b00[i] = v(i);
///                     out b10[i] = e(i, 0);
///                     out b01[i] = e(i, 1);
///                     out b11[i] = f(i, 0);
///                 }
///             }
///         })
///         .target(tessgen_codegen::Target::Rust)
///         .out_dir(out)
///         .write()
///         .expect("tessgen");
/// }
/// ```
///
/// A mistake fails the build where it is made:
///
/// ```text
/// error: row `f[0]` weights sum to 0.6666666666666666 at valence 3, expected 1 (a point)
///   --> build.rs:9:21
///    |
///  9 |                     f[j] = (4 * p + 2 * p[2 * j]) / 9;
///    |                     ^
/// ```
#[proc_macro]
pub fn scheme(input: TokenStream) -> TokenStream {
    let tokens = proc_macro2::TokenStream::from(input);
    match expand(tokens) {
        Ok(ts) => ts.into(),
        Err(e) => e.to_compile_error().into(),
    }
}

fn expand(input: proc_macro2::TokenStream) -> syn::Result<proc_macro2::TokenStream> {
    let ast = tessgen_codegen::dsl::parse_tokens(input.clone())?;
    tessgen_codegen::Scheme::from_ast(&ast, tessgen_codegen::DEFAULT_MAX_VALENCE)
        .map_err(|e| e.to_syn())?;
    let text = input.to_string();
    Ok(quote::quote! {
        ::tessgen_codegen::SchemeSource::new(
            ::core::concat!("scheme! in ", ::core::file!(), ":", ::core::line!()),
            #text,
        )
    })
}
