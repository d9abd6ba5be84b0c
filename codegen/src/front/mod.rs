//! The front end: scheme source (the DSL, parsed with syn) into the checked,
//! symbolic Scheme IR. Nothing here knows about tables, the Plan or targets.
//!
//! ```text
//! .tess text / scheme! tokens ─ dsl (syn) ─▶ SchemeAst ─ scheme ─▶ Scheme (names, types, affine checks)
//!                                                        sym: weight expressions, evaluated in f64
//! ```

pub mod dsl;
pub mod scheme;
pub mod sym;
