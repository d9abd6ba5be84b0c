//! tessgen compiler: scheme DSL → symbolic IR → stencil table → Plan → printers.
//!
//! ```text
//! scheme source (DSL) ─ parse (syn) ─▶ Scheme IR (symbolic, checked)   [front: dsl, scheme, sym]
//! Scheme IR           ─ per valence ─▶ StencilTable (f64 → f32 rows)   [table]
//! Scheme IR           ─ lower ──────▶ Plan (ordered statements)        [lower, plan, form]
//! Plan                ─ print ──────▶ Rust | …                         [backend]
//! ```
//!
//! Math lives in the scheme declaration and the IR, order lives in the
//! Plan, syntax lives in the printers.

pub mod backend;
pub mod builder;
pub mod error;
pub mod front;
pub mod lower;
mod markdown;
pub mod outdir;
pub mod plan;
pub mod table;

/// The front end's modules at their long-standing public paths
/// (`tessgen_codegen::scheme`, …), used by the `scheme!` macro and by users.
pub use front::{dsl, scheme, sym};

pub use backend::Target;
pub use builder::{builtin_schemes, BuildError, Builder, GeneratedFile, Output, SchemeSource};
pub use scheme::{Class, Scheme, SchemeError};
pub use table::{StencilTable, DEFAULT_MAX_VALENCE};
