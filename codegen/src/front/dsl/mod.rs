//! The scheme language: a small Rust-like DSL parsed with `syn`.
//!
//! One parser serves both front ends: the `scheme! { … }` proc macro (which
//! hands us its token stream) and build-time/CLI loading of `.tess` files
//! (which hands us text). Both end in [`parse_tokens`], so a scheme that
//! compiles in one place compiles in the other with the same errors.
//!
//! ```text
//! scheme NAME {
//!     facet quad;
//!     const NAME = EXPR;                 // per-valence constant, a function of n
//!     vertex {                           // rows over the ring [p, p[0] .. p[2n-1]]
//!         NAME[j] = EXPR;                // family indexed by sector j (mod n)
//!         NAME = EXPR;                   // single output
//!         vector NAME[j] = EXPR;         // a tangent: weights sum to 0
//!         let NAME = EXPR;               // named sub-expression, not exported
//!     }
//!     sector crease {                    // or `corner`: a crease/corner sector of m faces
//!         NAME = EXPR;                   // override of a vertex definition, every position
//!         sharp NAME[j] = EXPR;          // override at the sharp edges j = 0 and j = m only
//!         let NAME = EXPR;               // block-local helper (one value, no [j]), inlined
//!     }                                  // `m`, and `NAME` inside NAME's override = the
//!                                        // scheme's own NAME (docs/boundaries.md §3)
//!     patch CLASS: FORM {                // CLASS = ordinary | extraordinary
//!         NAME[i] = EXPR;                // per-corner local (i mod 4)
//!         NAME = EXPR;                   // patch local
//!         out SLOT[i] = EXPR;            // the form's control points
//!     }
//! }
//! ```
//!
//! `if A OP B { X } else { Y }` (constants and vertex/sector stages) compares
//! numbers and is decided where the row is evaluated: per valence, sector
//! size `m` and binding of the index variables, so inside `sum(k, …)` a
//! condition on `k` selects terms, e.g. `(if k < m { 1 } else { 0 }) * …` sums
//! over a sector's faces only.

pub mod ast;
pub mod parse;

pub use ast::*;
pub use parse::{parse_str, parse_tokens};
