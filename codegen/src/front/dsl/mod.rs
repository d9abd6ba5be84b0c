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
//!     sector KIND {                      // KIND = crease | corner (docs/boundaries.md §3):
//!         NAME = EXPR;                   // override a vertex definition in a sector of m faces
//!         sharp NAME[j] = EXPR;          // … only at its sharp edges (j = 0, j = m)
//!     }
//!     patch CLASS: FORM {                // CLASS = ordinary | extraordinary
//!         NAME[i] = EXPR;                // per-corner local (i mod 4)
//!         NAME = EXPR;                   // patch local
//!         out SLOT[i] = EXPR;            // the form's control points
//!     }
//! }
//! ```

pub mod ast;
pub mod parse;

pub use ast::*;
pub use parse::{parse_str, parse_tokens};
