//! Evaluation entry functions: `eval` (the boundary branch to the one shared edge evaluator, then
//! the class's surface) and `eval_domain` (triangles at the tessellator's point).

use super::*;

pub(crate) fn eval_fn(
    patches: &[PatchEntry],
    surfaces: &[usize],
    curve_const: usize,
    sides: u32,
    edge_fn: FnRef,
) -> Function {
    let mut f = Function::new(
        "eval",
        "Position and normal at (iu, iv)/level of a patch of facet class `class` (index into \
         the scheme's patch classes). Samples on the patch boundary take their position from \
         the one shared edge evaluator, whose curve and parameter both patches of an edge \
         form identically; the normal comes from the patch, and where the patch's tangents are \
         parallel (tessgen_patch_normal's zero) from one nudge inside it.",
    );
    let class = f.param("class", Ty::U32);
    let cp = f.param("cp_base", Ty::U32);
    let iu = f.param("iu", Ty::U32);
    let iv = f.param("iv", Ty::U32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::Struct(plan::common::SAMPLE));
    let sample = f.local("sample", Ty::Struct(plan::common::SAMPLE));
    // class dispatch: if class == 0 { … } else if … (last one unconditional)
    let dispatch = |target: LocalId, args: Vec<Expr>| -> Vec<Stmt> {
        let mut chain: Vec<Stmt> = vec![Stmt::Assign(
            target,
            call(FnRef::Local(*surfaces.last().unwrap_or(&0)), args.clone()),
        )];
        for k in (0..patches.len().saturating_sub(1)).rev() {
            chain = vec![Stmt::If(
                bin(BinOp::Eq, l(class), u(k as u32)),
                vec![Stmt::Assign(
                    target,
                    call(FnRef::Local(surfaces[k]), args.clone()),
                )],
                chain,
            )];
        }
        chain
    };
    let zero_sample = || {
        Expr::Make(
            plan::common::SAMPLE,
            vec![
                Expr::Call(Builtin::Vec3, vec![f32c(0.0), f32c(0.0), f32c(0.0)]),
                Expr::Call(Builtin::Vec3, vec![f32c(0.0), f32c(0.0), f32c(0.0)]),
            ],
        )
    };
    f.body.push(Stmt::Var(sample, zero_sample()));
    f.body
        .extend(dispatch(sample, vec![l(cp), l(iu), l(iv), l(level)]));
    if sides == 4 {
        // A degenerate sample (tessgen_patch_normal's zero: parallel
        // tangents) takes the normal one nudge inside the patch, at
        // (NUDGE·iu ± 1, NUDGE·iv ± 1) / (NUDGE·level): + at 0 and inside,
        // − at level.
        let inner = f.local("inner", Ty::Struct(plan::common::SAMPLE));
        let nudged = |i: LocalId| {
            sub(
                add(mul(l(i), u(plan::NUDGE)), u(1)),
                mul(
                    u(2),
                    Expr::Call(Builtin::U32FromBool, vec![bin(BinOp::Eq, l(i), l(level))]),
                ),
            )
        };
        let mut fix = vec![Stmt::Var(inner, zero_sample())];
        fix.extend(dispatch(
            inner,
            vec![l(cp), nudged(iu), nudged(iv), mul(l(level), u(plan::NUDGE))],
        ));
        fix.push(Stmt::AssignField(sample, 1, field(inner, 1)));
        let normal = field(sample, 1);
        f.body.push(Stmt::If(
            bin(
                BinOp::Eq,
                Expr::Call(Builtin::Dot, vec![normal.clone(), normal]),
                f32c(0.0),
            ),
            fix,
            vec![],
        ));
    }
    let edge = f.local("edge", Ty::U32);
    let t = f.local("t", Ty::U32);
    let (on_boundary, select) = if sides == 4 {
        (
            bin(
                BinOp::Or,
                bin(
                    BinOp::Or,
                    bin(BinOp::Eq, l(iu), u(0)),
                    bin(BinOp::Eq, l(iu), l(level)),
                ),
                bin(
                    BinOp::Or,
                    bin(BinOp::Eq, l(iv), u(0)),
                    bin(BinOp::Eq, l(iv), l(level)),
                ),
            ),
            vec![
                // Edge 0 (v = 0, t = u), edge 1 (u = 1, t = v), edge 2 (v = 1, t = 1 - u),
                // edge 3 (u = 0, t = 1 - v), all from integers.
                Stmt::Var(edge, u(3)),
                Stmt::Var(t, sub(l(level), l(iv))),
                Stmt::If(
                    bin(BinOp::Eq, l(iv), u(0)),
                    vec![Stmt::Assign(edge, u(0)), Stmt::Assign(t, l(iu))],
                    vec![Stmt::If(
                        bin(BinOp::Eq, l(iu), l(level)),
                        vec![Stmt::Assign(edge, u(1)), Stmt::Assign(t, l(iv))],
                        vec![Stmt::If(
                            bin(BinOp::Eq, l(iv), l(level)),
                            vec![
                                Stmt::Assign(edge, u(2)),
                                Stmt::Assign(t, sub(l(level), l(iu))),
                            ],
                            vec![],
                        )],
                    )],
                ),
            ],
        )
    } else {
        // Barycentric (level − iu − iv, iu, iv) of corners 0, 1, 2: edge 0
        // (corner 0 → 1, iv = 0, t = iu), edge 1 (1 → 2, iu + iv = level,
        // t = iv), edge 2 (2 → 0, iu = 0, t = level − iv).
        (
            bin(
                BinOp::Or,
                bin(
                    BinOp::Or,
                    bin(BinOp::Eq, l(iv), u(0)),
                    bin(BinOp::Eq, l(iu), u(0)),
                ),
                bin(BinOp::Eq, add(l(iu), l(iv)), l(level)),
            ),
            vec![
                Stmt::Var(edge, u(2)),
                Stmt::Var(t, sub(l(level), l(iv))),
                Stmt::If(
                    bin(BinOp::Eq, l(iv), u(0)),
                    vec![Stmt::Assign(edge, u(0)), Stmt::Assign(t, l(iu))],
                    vec![Stmt::If(
                        bin(BinOp::Eq, add(l(iu), l(iv)), l(level)),
                        vec![Stmt::Assign(edge, u(1)), Stmt::Assign(t, l(iv))],
                        vec![],
                    )],
                ),
            ],
        )
    };
    // Cubic boundaries (4 points) or quartic ones (5, Form::Gregory4):
    // every class of a scheme has the same.
    let points = patches.first().map_or(4, |p| p.form.curve_points());
    let base = f.local("curve", Ty::U32);
    let b: Vec<LocalId> = (0..points)
        .map(|i| f.local(format!("b{i}"), Ty::Vec3))
        .collect();
    let mut boundary = select;
    let pts = points as u32;
    boundary.push(Stmt::Let(
        base,
        add(mul(l(class), u(pts * sides)), mul(l(edge), u(pts))),
    ));
    for (k, bk) in b.iter().enumerate() {
        boundary.push(Stmt::Let(
            *bk,
            fetch(
                Resource::ControlPoints,
                add(
                    l(cp),
                    Expr::ConstIndex(curve_const, Box::new(add(l(base), u(k as u32)))),
                ),
            ),
        ));
    }
    boundary.push(Stmt::AssignField(
        sample,
        0,
        call(
            edge_fn,
            b.iter().map(|x| l(*x)).chain([l(t), l(level)]).collect(),
        ),
    ));
    // The boundary path can be compiled out (GLSL/HLSL only) as a negative
    // control: the watertightness check must then find cracks.
    f.body.push(Stmt::IfDef(
        plan::Define::NoBoundaryPath,
        vec![],
        vec![Stmt::If(on_boundary, boundary, vec![])],
    ));
    f.body.push(Stmt::Return(l(sample)));
    f
}

/// `eval_domain(class, cp_base, x, y, z, level)`: the tessellation
/// evaluation stages' evaluation of a triangle patch at the hardware's
/// barycentric domain point `(x, y, z)` of corners 0, 1, 2.
///
/// On the patch boundary (a coordinate exactly 0) the point is on the outer
/// ring, which `equal_spacing` / `integer` partitioning at an integer level
/// places at exactly `i/level` (fixed point, so the zero is exact); there the
/// integer grid point `(round(y·level), round(z·level))` goes through `eval`
/// and its shared edge evaluator, the same bits as the neighbour patch and as
/// the CPU/WGSL grid. Strictly inside, the hardware pattern is not the
/// barycentric lattice (inner ring k of a level-N triangle has N − 2k
/// segments per side, the lattice row at that depth N − 3k), so rounding
/// would move the vertex; the surface is evaluated at the raw point instead.
/// Interior points are private to the patch, so this costs no
/// watertightness.
pub(crate) fn eval_domain_fn(eval: usize, surfaces_at: &[usize]) -> Function {
    let mut f = Function::new(
        "eval_domain",
        "Position and normal at the tessellator's barycentric domain point (x, y, z) of corners \
         0, 1, 2. On the patch boundary (a coordinate exactly 0: the outer ring, where the \
         tessellator puts vertex i at exactly i/level) the integer grid point (round(y·level), \
         round(z·level)) goes through eval and the shared edge evaluator, so both patches of an \
         edge compute the same bits. Strictly inside, the hardware's inner rings are not the \
         barycentric lattice (inner ring k of a level-N triangle has N − 2k segments per side), \
         so the surface is evaluated at the raw point.",
    );
    let class = f.param("class", Ty::U32);
    let cp = f.param("cp_base", Ty::U32);
    let x = f.param("x", Ty::F32);
    let y = f.param("y", Ty::F32);
    let z = f.param("z", Ty::F32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::Struct(plan::common::SAMPLE));
    let iu = f.local("iu", Ty::U32);
    let iv = f.local("iv", Ty::U32);
    let sample = f.local("sample", Ty::Struct(plan::common::SAMPLE));
    let round_to_u32 = |c: LocalId| {
        Expr::Call(
            Builtin::U32FromF32,
            vec![Expr::Call(
                Builtin::Round,
                vec![mul(l(c), to_f32(l(level)))],
            )],
        )
    };
    let on_boundary = bin(
        BinOp::Or,
        bin(
            BinOp::Or,
            bin(BinOp::Eq, l(x), f32c(0.0)),
            bin(BinOp::Eq, l(y), f32c(0.0)),
        ),
        bin(BinOp::Eq, l(z), f32c(0.0)),
    );
    f.body.push(Stmt::If(
        on_boundary,
        vec![
            Stmt::Let(iu, round_to_u32(y)),
            Stmt::Let(iv, round_to_u32(z)),
            Stmt::Return(call(
                FnRef::Local(eval),
                vec![l(class), l(cp), l(iu), l(iv), l(level)],
            )),
        ],
        vec![],
    ));
    let args = vec![l(cp), l(x), l(y), l(z)];
    let mut chain: Vec<Stmt> = vec![Stmt::Assign(
        sample,
        call(
            FnRef::Local(*surfaces_at.last().unwrap_or(&0)),
            args.clone(),
        ),
    )];
    for k in (0..surfaces_at.len().saturating_sub(1)).rev() {
        chain = vec![Stmt::If(
            bin(BinOp::Eq, l(class), u(k as u32)),
            vec![Stmt::Assign(
                sample,
                call(FnRef::Local(surfaces_at[k]), args.clone()),
            )],
            chain,
        )];
    }
    f.body.push(Stmt::Var(
        sample,
        Expr::Make(
            plan::common::SAMPLE,
            vec![
                Expr::Call(Builtin::Vec3, vec![f32c(0.0), f32c(0.0), f32c(0.0)]),
                Expr::Call(Builtin::Vec3, vec![f32c(0.0), f32c(0.0), f32c(0.0)]),
            ],
        ),
    ));
    f.body.extend(chain);
    f.body.push(Stmt::Return(l(sample)));
    f
}
