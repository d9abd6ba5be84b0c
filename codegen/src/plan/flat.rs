//! Indices of the 2-D resources, formed as Plan expressions so a printer
//! only spells them: the texel of a stencil-table weight for the shading
//! languages, flat indices for targets that hold the resources as row-major
//! slices (the Rust kernels: the stencil table, the displacement map).

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

/// The texel `(x, y)` of the stencil texture that holds logical table
/// weight `(row, col)`: rows wrap into column blocks of `TABLE_BLOCK_ROWS`,
/// `x = col + TABLE_WIDTH·(row / TABLE_BLOCK_ROWS)`, `y = row %
/// TABLE_BLOCK_ROWS` (the layout [`crate::table::StencilTable::texture`]
/// writes).
pub fn table_texel(row: &Expr, col: &Expr) -> (Expr, Expr) {
    let block = Expr::Named(Named::TableBlockRows);
    let x = add(
        col.clone(),
        mul(
            Expr::Named(Named::TableWidth),
            bin(BinOp::Div, row.clone(), block.clone()),
        ),
    );
    (x, bin(BinOp::Rem, row.clone(), block))
}
