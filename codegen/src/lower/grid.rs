//! The sample grid of one patch (`grid_len`, `grid_iu`, `grid_iv`, `grid_index`): quads
//! `(N+1)²` row by row, triangles in rows of `N + 1 − iv` samples.

use super::*;

/// `grid_index(iu, iv, level)`, the inverse of `grid_iu`/`grid_iv` (see
/// [`Entries::grid_index`]).
pub(crate) fn grid_index_fn(sides: u32) -> Function {
    let mut f = Function::new(
        "grid_index",
        if sides == 4 {
            "Flat index of the sample at integer domain point (iu, iv): iv·(level+1) + iu (the inverse of grid_iu, grid_iv)."
        } else {
            "Flat index of the sample at integer domain point (iu, iv): the rows below iv hold Σ_{r<iv} (level+1−r) = iv·(2·level+3−iv)/2 samples, then iu (the inverse of grid_iu, grid_iv)."
        },
    );
    let iu = f.param("iu", Ty::U32);
    let iv = f.param("iv", Ty::U32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::U32);
    let below = if sides == 4 {
        mul(l(iv), add(l(level), u(1)))
    } else {
        div(mul(l(iv), sub(add(mul(u(2), l(level)), u(3)), l(iv))), u(2))
    };
    f.body = vec![Stmt::Return(add(below, l(iu)))];
    f
}

/// `grid_len`, `grid_iu`, `grid_iv` of the facet's domain (see
/// [`Entries::grid`]): entry points of every backend map a flat sample index
/// through these instead of spelling the domain themselves.
pub(crate) fn grid_fns(sides: u32) -> Vec<Function> {
    let mut len = Function::new(
        "grid_len",
        if sides == 4 {
            "Samples of one quad patch at `level`: (level+1)²."
        } else {
            "Samples of one triangle patch at `level`: (level+1)(level+2)/2."
        },
    );
    let level = len.param("level", Ty::U32);
    len.ret = Some(Ty::U32);
    let side = add(l(level), u(1));
    len.body = vec![Stmt::Return(if sides == 4 {
        mul(side.clone(), side)
    } else {
        div(mul(side, add(l(level), u(2))), u(2))
    })];
    let mut out = vec![len];
    for (name, want_iv) in [("grid_iu", false), ("grid_iv", true)] {
        let mut f = Function::new(
            name,
            if sides == 4 {
                "Integer domain coordinate of sample `s` = iv·(level+1) + iu."
            } else {
                "Integer domain coordinate of sample `s`: rows iv = 0..=level of level+1−iv samples each (iu = 0..=level−iv), found by walking the rows."
            },
        );
        let smp = f.param("s", Ty::U32);
        let level = f.param("level", Ty::U32);
        f.ret = Some(Ty::U32);
        if sides == 4 {
            let side = add(l(level), u(1));
            f.body = vec![Stmt::Return(bin(
                if want_iv { BinOp::Div } else { BinOp::Rem },
                l(smp),
                side,
            ))];
        } else {
            let row = f.local("row", Ty::U32);
            let rest = f.local("rest", Ty::U32);
            let r = f.local("r", Ty::U32);
            let row_len = sub(add(l(level), u(1)), l(row));
            f.body = vec![
                Stmt::Var(row, u(0)),
                Stmt::Var(rest, l(smp)),
                // Once `rest` fits in the current row it stays put: the
                // row length only changes when a row is skipped.
                Stmt::For(
                    r,
                    u(0),
                    l(level),
                    vec![Stmt::If(
                        bin(BinOp::Ge, l(rest), row_len.clone()),
                        vec![
                            Stmt::Assign(rest, sub(l(rest), row_len)),
                            Stmt::Assign(row, add(l(row), u(1))),
                        ],
                        vec![],
                    )],
                ),
                Stmt::Return(l(if want_iv { row } else { rest })),
            ];
        }
        out.push(f);
    }
    out
}
