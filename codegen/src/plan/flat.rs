//! Flat indices of the 2-D resources for targets that hold them as
//! row-major slices (the Rust kernels: the stencil table, the displacement
//! map), formed as Plan expressions so a printer only indexes.

use super::build::*;
use super::*;

/// The row-major flat index of the texel that `e` reads: `row·TABLE_WIDTH +
/// column` for [`Expr::TableWeight`], `y·columns + x` for [`Expr::Texel`]
/// ([`Expr::Columns`]); `None` for any other expression.
pub fn flat_index(e: &Expr) -> Option<Expr> {
    match e {
        Expr::TableWeight(row, col) => Some(add(
            mul((**row).clone(), Expr::Named(Named::TableWidth)),
            (**col).clone(),
        )),
        Expr::Texel(r, x, y) => Some(add(mul((**y).clone(), Expr::Columns(*r)), (**x).clone())),
        _ => None,
    }
}
