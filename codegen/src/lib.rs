//! tessgen compiler: scheme DSL → symbolic IR → stencil table → Plan → printers.
//!
//! ```text
//! scheme source (DSL) ─ parse (syn) ─▶ Scheme IR (symbolic, checked)   [dsl, scheme, sym]
//! Scheme IR           ─ per valence ─▶ StencilTable (f64 → f32 rows)   [table]
//! Scheme IR           ─ lower ──────▶ Plan (ordered statements)        [lower, plan, form]
//! Plan                ─ print ──────▶ Rust | …                         [backend]
//! ```
//!
//! Math lives in the scheme declaration and the IR, order lives in the
//! Plan, syntax lives in the printers.

pub mod adaptive;
pub mod backend;
pub mod builder;
pub mod displace;
pub mod dsl;
pub mod entries;
pub mod form;
pub mod lower;
pub mod outdir;
pub mod plan;
pub mod scheme;
pub mod sym;
pub mod table;
pub mod tess;

pub use backend::Target;
pub use builder::{builtin_schemes, BuildError, Builder, GeneratedFile, Output, SchemeSource};
pub use scheme::{Class, Scheme, SchemeError};
pub use table::{StencilTable, DEFAULT_MAX_VALENCE};
