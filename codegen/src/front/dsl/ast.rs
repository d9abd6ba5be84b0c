//! Syntax tree of a scheme declaration, straight from the parser.
//!
//! Expressions stay `syn::Expr` here; [`crate::front::scheme`] resolves names and
//! types and turns them into the symbolic IR.

use proc_macro2::Span;
use syn::{Expr, Ident};

/// A parsed `scheme NAME { … }` block.
#[derive(Clone)]
pub struct SchemeAst {
    pub name: Ident,
    pub doc: String,
    pub facet: Ident,
    pub consts: Vec<ConstAst>,
    pub vertex: Vec<DefAst>,
    /// `sector crease { … }` / `sector corner { … }` blocks (docs/boundaries.md §3).
    pub sectors: Vec<SectorAst>,
    pub patches: Vec<PatchAst>,
}

/// `sector KIND { … }`: what a sector of a crease or corner vertex takes from
/// the shared crease data instead of the scheme's virtual-ring rule.
#[derive(Clone)]
pub struct SectorAst {
    pub kind: Ident,
    pub defs: Vec<DefAst>,
}

/// `const NAME = EXPR;` — a scalar function of the valence `n`.
#[derive(Clone)]
pub struct ConstAst {
    pub name: Ident,
    pub expr: Expr,
}

/// How a definition is exported.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DefKind {
    /// An output whose weights sum to 1 (vertex stage) or a patch-local value.
    Point,
    /// A vertex-stage output whose weights sum to 0 (tangent vector).
    Vector,
    /// `let`: a named sub-expression, never exported.
    Let,
    /// `out`: a control point of the patch form.
    Out,
    /// `sharp`: in a `sector` block, an override at the sector's two sharp
    /// edges only (positions 0 and m).
    Sharp,
}

/// `[kind] NAME[index] = EXPR;` or `[kind] NAME = EXPR;`
#[derive(Clone)]
pub struct DefAst {
    pub kind: DefKind,
    pub name: Ident,
    pub index: Option<Ident>,
    pub expr: Expr,
    pub span: Span,
}

/// `patch CLASS: FORM { … }`
#[derive(Clone)]
pub struct PatchAst {
    pub class: Ident,
    pub form: Ident,
    pub defs: Vec<DefAst>,
}
