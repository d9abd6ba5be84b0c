//! The refinement stage (docs/boundaries.md §8): every refined vertex of a
//! mesh that went through uniform Catmull-Clark steps is one stencil row over
//! the *base* vertices, applied before the vertex stage so that an animated
//! mesh refines on the GPU.
//!
//! The sum is the vertex stage's (DESIGN.md Rule 1): `acc = 0`, then
//! `acc = acc + p[i_k]·w_k` for the row's terms in table order, one rounded
//! multiply and one rounded add per term. The runtime's reference
//! (`StencilTable::apply`) sums the same way, so every backend refines to the
//! CPU's bits; the function is `precise` so that GLSL and HLSL drivers may not
//! fuse the multiply-adds.

use crate::plan::build::*;
use crate::plan::*;

/// `refine_vertex(v)`: refined vertex `v` from the base positions, stored
/// into `refined_positions` (the buffer the vertex stage then reads as
/// `positions`).
pub fn refine_vertex_fn() -> Function {
    let mut f = Function::new(
        "tessgen_refine_vertex",
        "Refined vertex `v`: the sum over its stencil row (refine_offsets[v] .. refine_offsets[v + 1]) \
         of base point × weight, in row order from a zero vector, one rounded multiply and one \
         rounded add per term, into refined_positions[v] (docs/boundaries.md §8).",
    );
    f.precise = true;
    let v = f.param("v", Ty::U32);
    let first = f.local("first", Ty::U32);
    let end = f.local("end", Ty::U32);
    let acc = f.local("acc", Ty::Vec3);
    let j = f.local("j", Ty::U32);
    f.body = vec![
        Stmt::Let(first, fetch(Resource::RefineOffsets, l(v))),
        Stmt::Let(end, fetch(Resource::RefineOffsets, add(l(v), u(1)))),
        Stmt::Var(
            acc,
            Expr::Call(
                Builtin::Vec3,
                vec![Expr::F32(0.0), Expr::F32(0.0), Expr::F32(0.0)],
            ),
        ),
        Stmt::For(
            j,
            l(first),
            l(end),
            vec![Stmt::Assign(
                acc,
                add(
                    l(acc),
                    mul(
                        fetch(Resource::RefineBase, fetch(Resource::RefineIndices, l(j))),
                        fetch(Resource::RefineWeights, l(j)),
                    ),
                ),
            )],
        ),
        Stmt::Store(Resource::RefinedPositions, l(v), l(acc)),
    ];
    f
}

/// The body of the compute entry `refine_main` (every GPU target):
/// invocation `k` refines vertex `params.first + k` for `k < params.count`.
pub fn refine_main() -> Function {
    let mut f = Function::new(
        crate::plan::abi::entry::REFINE,
        "Refinement stage for refined vertices first .. first + count: each its stencil row over \
         the base positions, into refined_positions (bound to the buffer the vertex stage reads as \
         positions).",
    );
    let k = f.local("k", Ty::U32);
    f.body = vec![
        Stmt::Let(k, Expr::Stage(StageIn::GlobalId)),
        Stmt::If(
            bin(BinOp::Lt, l(k), Expr::Stage(StageIn::Param("count"))),
            vec![Stmt::Call(
                FnRef::Common(common_fn::REFINE_VERTEX),
                vec![add(Expr::Stage(StageIn::Param("first")), l(k))],
            )],
            vec![],
        ),
    ];
    f
}
