//! The vertex stage: one function summing every vertex-stage output over the ring slots in
//! ring order with the f32 table weights (DESIGN.md Rule 1).

use super::*;

pub(crate) fn vertex_stage_fn(s: &Scheme, row_base: usize, ra: u32, rb: u32) -> Function {
    let mut f = Function::new(
        "vertex_stage",
        format!(
            "Vertex stage of `{}`: every output row of this vertex's valence, each the sum over \
             ring slots 0..2n in ring order (stored once per vertex, canonical start) of \
             table weight × point, zero weights skipped. Writes ROWS_PER_N·n + ROWS_FIXED points \
             from `out_base`.",
            s.name
        ),
    );
    let vertex = f.param("vertex", Ty::U32);
    let out_base = f.param("out_base", Ty::U32);
    let n = f.local("n", Ty::U32);
    let ring_base = f.local("ring_base", Ty::U32);
    let base = f.local("row_base", Ty::U32);
    let rows = f.local("rows", Ty::U32);
    let slots = f.local("slots", Ty::U32);
    let r = f.local("r", Ty::U32);
    let acc = f.local("acc", Ty::Vec3);
    let k = f.local("k", Ty::U32);
    let w = f.local("w", Ty::F32);
    f.body = vec![
        Stmt::Let(n, fetch(Resource::Valence, l(vertex))),
        Stmt::Let(ring_base, fetch(Resource::RingOffsets, l(vertex))),
        Stmt::Let(base, Expr::ConstIndex(row_base, Box::new(l(n)))),
        Stmt::Let(rows, add(mul(u(ra), l(n)), u(rb))),
        Stmt::Let(slots, add(mul(u(2), l(n)), u(1))),
        Stmt::For(
            r,
            u(0),
            l(rows),
            vec![
                Stmt::Var(
                    acc,
                    Expr::Call(Builtin::Vec3, vec![f32c(0.0), f32c(0.0), f32c(0.0)]),
                ),
                Stmt::For(
                    k,
                    u(0),
                    l(slots),
                    vec![
                        Stmt::Let(
                            w,
                            Expr::TableWeight(Box::new(add(l(base), l(r))), Box::new(l(k))),
                        ),
                        Stmt::If(
                            bin(BinOp::Ne, l(w), f32c(0.0)),
                            vec![Stmt::Assign(
                                acc,
                                add(
                                    l(acc),
                                    mul(
                                        fetch(
                                            Resource::Positions,
                                            fetch(Resource::Ring, add(l(ring_base), l(k))),
                                        ),
                                        l(w),
                                    ),
                                ),
                            )],
                            vec![],
                        ),
                    ],
                ),
                Stmt::Store(Resource::VertexOut, add(l(out_base), l(r)), l(acc)),
            ],
        ),
    ];
    f
}
