//! The common module: the shared evaluators every scheme module calls (the edge evaluator, the
//! cubic, normalisation, the tessellation-factor and adaptive-level functions).

use super::*;

/// The common module: the shared structs, table constants and evaluators
/// every scheme uses.
pub fn common_module(table: &StencilTable) -> Module {
    let mut m = Module {
        name: "common".into(),
        doc:
            "Shared by every scheme: the edge evaluator, the cubic de Casteljau step, table layout."
                .into(),
        ..Default::default()
    };
    m.add_const(
        "TABLE_WIDTH",
        "Columns of the stencil table: 2·MAX_VALENCE + 1 ring slots, then the sector region (2·(MAX_VALENCE / 2) + 2 partial-ring slots).",
        ConstValue::U32(table.width),
    );
    m.add_const(
        "TABLE_BLOCK_ROWS",
        "Rows per column block of the stencil texture: logical row r, column c is texel (c + TABLE_WIDTH·(r / TABLE_BLOCK_ROWS), r % TABLE_BLOCK_ROWS), so the texture stays within the 4096-texel side every backend supports.",
        ConstValue::U32(crate::table::TABLE_BLOCK_ROWS),
    );
    m.add_const(
        "TABLE_TEXTURE_WIDTH",
        "Width of the stencil texture in texels: TABLE_WIDTH per column block.",
        ConstValue::U32(table.texture_width()),
    );
    m.add_const(
        "TABLE_TEXTURE_HEIGHT",
        "Height of the stencil texture in texels (at most TABLE_BLOCK_ROWS).",
        ConstValue::U32(table.texture_height()),
    );
    m.add_const(
        "MAX_VALENCE",
        "Largest valence the table covers.",
        ConstValue::U32(table.max_valence),
    );
    m.structs.push(StructDecl {
        name: "Sample".into(),
        fields: vec![("position".into(), Ty::Vec3), ("normal".into(), Ty::Vec3)],
    });
    m.structs.push(StructDecl {
        name: "Curve".into(),
        fields: vec![("point".into(), Ty::Vec3), ("tangent".into(), Ty::Vec3)],
    });

    // normalize with a guard for degenerate (zero-length) normals.
    let mut f = Function::new(
        "tessgen_normalize",
        "Unit vector along `x`; a zero vector stays zero instead of becoming NaN.",
    );
    let x = f.param("x", Ty::Vec3);
    let len2 = f.local("len2", Ty::F32);
    f.ret = Some(Ty::Vec3);
    f.body = vec![
        Stmt::Let(len2, Expr::Call(Builtin::Dot, vec![l(x), l(x)])),
        Stmt::If(
            bin(BinOp::Gt, l(len2), f32c(0.0)),
            vec![Stmt::Return(div(
                l(x),
                Expr::Call(Builtin::Sqrt, vec![l(len2)]),
            ))],
            vec![],
        ),
        Stmt::Return(l(x)),
    ];
    m.functions.push(f);

    // One cubic de Casteljau step with its derivative.
    let mut f = Function::new(
        "tessgen_cubic",
        "Cubic Bézier point and derivative by symmetric de Casteljau: every lerp is `x·l + y·r`.",
    );
    let b: Vec<LocalId> = (0..4).map(|i| f.param(format!("b{i}"), Ty::Vec3)).collect();
    let (wl, wr) = (f.param("l", Ty::F32), f.param("r", Ty::F32));
    f.ret = Some(Ty::Struct(plan::common::CURVE));
    let c: Vec<LocalId> = (0..3).map(|i| f.local(format!("c{i}"), Ty::Vec3)).collect();
    let d: Vec<LocalId> = (0..2).map(|i| f.local(format!("d{i}"), Ty::Vec3)).collect();
    for i in 0..3 {
        f.body
            .push(Stmt::Let(c[i], lerp(l(b[i]), l(b[i + 1]), wl, wr)));
    }
    for i in 0..2 {
        f.body
            .push(Stmt::Let(d[i], lerp(l(c[i]), l(c[i + 1]), wl, wr)));
    }
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::CURVE,
        vec![
            lerp(l(d[0]), l(d[1]), wl, wr),
            mul(sub(l(d[1]), l(d[0])), f32c(3.0)),
        ],
    )));
    m.functions.push(f);

    // The shared edge evaluator.
    m.functions.push(edge_fn(4));
    m.functions.push(edge_factor_fn(false));
    m.functions.push(edge_factor_fn(true));
    m.functions.push(crate::lower::adaptive::edge_level_fn());
    m.functions.push(crate::lower::adaptive::bucket_level_fn());
    m.functions.push(crate::lower::refine::refine_vertex_fn());
    m.functions.push(patch_normal_fn());
    m
}

/// The shared edge evaluator of boundary curves with `points` control
/// points: `tessgen_edge` (cubic, in the common module) or `tessgen_edge4`
/// (quartic, [`Form::Gregory4`]: emitted
/// in the modules of the schemes that have such boundaries). Symmetric de
/// Casteljau with integer-formed weights, `precise`: the two patches of an
/// edge get the same bits (watertight.md Rules 1–2).
pub(crate) fn edge_fn(points: usize) -> Function {
    let degree = points - 1;
    let (name, what) = if degree == 3 {
        (
            EDGE_FN.to_string(),
            "cubic boundary curve `b0..b3`".to_string(),
        )
    } else {
        (
            format!("{EDGE_FN}{degree}"),
            format!("degree-{degree} boundary curve `b0..b{degree}`"),
        )
    };
    let mut f = Function::new(
        name,
        format!(
            "Point `i/level` along the {what}. The two patches of an edge \
             call this with reversed points and `level - i`; both weights come from integers, so \
             every lerp is `x·l + y·r` on one side and `y·r + x·l` on the other: the same bits. \
             Corners return the corner point itself."
        ),
    );
    f.precise = true;
    let b: Vec<LocalId> = (0..points)
        .map(|i| f.param(format!("b{i}"), Ty::Vec3))
        .collect();
    let i = f.param("i", Ty::U32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::Vec3);
    let wl = f.local("l", Ty::F32);
    let wr = f.local("r", Ty::F32);
    f.body = vec![
        Stmt::If(
            bin(BinOp::Eq, l(i), u(0)),
            vec![Stmt::Return(l(b[0]))],
            vec![],
        ),
        Stmt::If(
            bin(BinOp::Eq, l(i), l(level)),
            vec![Stmt::Return(l(b[degree]))],
            vec![],
        ),
        Stmt::Let(wr, div(to_f32(l(i)), to_f32(l(level)))),
        // Negative control (GLSL/HLSL only): `l = 1 − r` in float, the form
        // watertight.md Rule 2 forbids; the two sides then disagree.
        Stmt::IfDef(
            plan::Define::AsymmetricEdgeWeights,
            vec![Stmt::Let(wl, sub(f32c(1.0), l(wr)))],
            vec![Stmt::Let(
                wl,
                div(to_f32(sub(l(level), l(i))), to_f32(l(level))),
            )],
        ),
    ];
    // The lerps are written out here rather than calling tessgen_cubic, so
    // that `precise` on this function covers every operation of the path.
    // Level k of the triangle is named c, d, e, …
    let mut prev = b;
    for (k, letter) in ('c'..).take(degree - 1).enumerate() {
        let next: Vec<LocalId> = (0..degree - k)
            .map(|j| f.local(format!("{letter}{j}"), Ty::Vec3))
            .collect();
        for (j, id) in next.iter().enumerate() {
            f.body
                .push(Stmt::Let(*id, lerp(l(prev[j]), l(prev[j + 1]), wl, wr)));
        }
        prev = next;
    }
    f.body
        .push(Stmt::Return(lerp(l(prev[0]), l(prev[1]), wl, wr)));
    f
}

/// `tessgen_patch_normal(a, b)`: the unit normal `a × b / |a × b|` of a quad
/// patch from its two tangents, or the zero vector where they are parallel
/// (`|a × b|² ≤ PARALLEL_SIN2 · |a|²·|b|²`, a zero tangent included). Where
/// a patch degenerates — the one-face corner of an edge-only boundary,
/// whose two boundary curves leave it collinear — the cross product is
/// rounding noise pointing anywhere (up to 180° off); the zero tells
/// `eval` to take the normal one nudge inside the patch instead, which is
/// the one-sided limit the surface has there. Elsewhere the bits are
/// `tessgen_normalize(a × b)`'s.
fn patch_normal_fn() -> Function {
    let mut f = Function::new(
        "tessgen_patch_normal",
        "Unit normal from a quad patch's tangents a, b; the zero vector where they are parallel \
         (|a × b|² ≤ PARALLEL_SIN2·|a|²·|b|²), so eval takes it just inside the patch.",
    );
    let a = f.param("a", Ty::Vec3);
    let b = f.param("b", Ty::Vec3);
    let c = f.local("c", Ty::Vec3);
    let c2 = f.local("c2", Ty::F32);
    let ab = f.local("ab", Ty::F32);
    f.ret = Some(Ty::Vec3);
    f.body = vec![
        Stmt::Let(c, Expr::Call(Builtin::Cross, vec![l(a), l(b)])),
        Stmt::Let(c2, Expr::Call(Builtin::Dot, vec![l(c), l(c)])),
        Stmt::Let(
            ab,
            mul(
                Expr::Call(Builtin::Dot, vec![l(a), l(a)]),
                Expr::Call(Builtin::Dot, vec![l(b), l(b)]),
            ),
        ),
        Stmt::If(
            bin(BinOp::Le, l(c2), mul(f32c(plan::PARALLEL_SIN2), l(ab))),
            vec![Stmt::Return(Expr::Call(
                Builtin::Vec3,
                vec![f32c(0.0), f32c(0.0), f32c(0.0)],
            ))],
            vec![],
        ),
        Stmt::Return(div(l(c), Expr::Call(Builtin::Sqrt, vec![l(c2)]))),
    ];
    f
}

/// The adaptive tessellation factor of one patch edge, from data that
/// depends only on the edge: its two end points (patch corners, shared
/// control points that both patches compute bit for bit, watertight.md
/// Rule 1) taken in a canonical order (lower global vertex index first),
/// and for the explicit metric the edge's global id. Both patches of the
/// edge therefore pass the hardware the same factor bits, which is what
/// makes their boundary vertex sets equal (Rule 3).
///
/// `runtime = false`: `tessgen_edge_factor`, the metric a define (GLSL/HLSL
/// tessellation control stages). `runtime = true`:
/// `tessgen_edge_factor_runtime`, the same statements with the metric chosen
/// at run time by `adaptive[25]` (0 screen, 1 distance, 2 buffer) — for the
/// targets without a preprocessor (WGSL, Rust), which would otherwise only
/// ever see the screen-space default branch.
pub(crate) fn edge_factor_fn(runtime: bool) -> Function {
    let mut f = Function::new(
        if runtime {
            EDGE_FACTOR_RUNTIME_FN
        } else {
            EDGE_FACTOR_FN
        },
        if runtime {
            "Tessellation factor of the patch edge from corner `a` (global vertex `va`) to corner `b` \
         (vertex `vb`), global edge id `edge`, as tessgen_edge_factor but with the metric chosen \
         at run time by adaptive[25]: 2 = edge_factors[edge], 1 = edge length over distance to the \
         eye, otherwise the projected length in pixels over the target pixels per segment (WGSL \
         and Rust have no preprocessor). Canonical end-point order, clamped to [min, max], NaN \
         becomes min."
        } else {
            "Tessellation factor of the patch edge from corner `a` (global vertex `va`) to corner `b` \
         (vertex `vb`), global edge id `edge`. The end points are put in canonical order (lower \
         vertex index first) and the metric sees only them, so both patches of the edge compute \
         the same bits. Metric: `edge_factors[edge]` (TESSGEN_METRIC_BUFFER), edge length over \
         distance to the eye (TESSGEN_METRIC_DISTANCE), or by default the projected length in \
         pixels over the target pixels per segment. Clamped to [min, max] of the `adaptive` \
         buffer; NaN becomes min."
        },
    );
    f.precise = true;
    let a = f.param("a", Ty::Vec3);
    let b = f.param("b", Ty::Vec3);
    let va = f.param("va", Ty::U32);
    let vb = f.param("vb", Ty::U32);
    let edge = f.param("edge", Ty::U32);
    f.ret = Some(Ty::F32);
    let p = f.local("p", Ty::Vec3);
    let q = f.local("q", Ty::Vec3);
    let fac = f.local("factor", Ty::F32);
    let ad = |k: u32| fetch(Resource::Adaptive, u(k));
    // Row r of the column-major view_proj, as a vec3 and its w column.
    let row = |r: u32| Expr::Call(Builtin::Vec3, vec![ad(r), ad(4 + r), ad(8 + r)]);
    let dot = |x: Expr, y: Expr| Expr::Call(Builtin::Dot, vec![x, y]);
    let sqrt = |x: Expr| Expr::Call(Builtin::Sqrt, vec![x]);
    let clip = |r: u32, pt: LocalId| add(dot(row(r), l(pt)), ad(12 + r));

    // Distance metric.
    let d = f.local("d", Ty::Vec3);
    let mid = f.local("mid", Ty::Vec3);
    let dist = f.local("dist", Ty::F32);
    let eye = Expr::Call(Builtin::Vec3, vec![ad(16), ad(17), ad(18)]);
    let distance = vec![
        Stmt::Let(d, sub(l(q), l(p))),
        Stmt::Let(mid, mul(add(l(p), l(q)), f32c(0.5))),
        Stmt::Let(dist, sqrt(dot(sub(l(mid), eye.clone()), sub(l(mid), eye)))),
        Stmt::If(
            bin(BinOp::Gt, l(dist), f32c(0.0)),
            vec![Stmt::Assign(
                fac,
                div(mul(ad(19), sqrt(dot(l(d), l(d)))), l(dist)),
            )],
            vec![Stmt::Assign(fac, ad(24))],
        ),
    ];
    // Screen-space metric.
    let wp = f.local("wp", Ty::F32);
    let wq = f.local("wq", Ty::F32);
    let dx = f.local("dx", Ty::F32);
    let dy = f.local("dy", Ty::F32);
    let screen = vec![
        Stmt::Let(wp, clip(3, p)),
        Stmt::Let(wq, clip(3, q)),
        Stmt::If(
            bin(
                BinOp::And,
                bin(BinOp::Gt, l(wp), f32c(0.0)),
                bin(BinOp::Gt, l(wq), f32c(0.0)),
            ),
            vec![
                Stmt::Let(
                    dx,
                    mul(
                        sub(div(clip(0, q), l(wq)), div(clip(0, p), l(wp))),
                        mul(ad(20), f32c(0.5)),
                    ),
                ),
                Stmt::Let(
                    dy,
                    mul(
                        sub(div(clip(1, q), l(wq)), div(clip(1, p), l(wp))),
                        mul(ad(21), f32c(0.5)),
                    ),
                ),
                Stmt::Assign(
                    fac,
                    div(sqrt(add(mul(l(dx), l(dx)), mul(l(dy), l(dy)))), ad(22)),
                ),
            ],
            // An end point behind the eye: the finest factor.
            vec![Stmt::Assign(fac, ad(24))],
        ),
    ];
    f.body = vec![
        Stmt::Var(p, l(a)),
        Stmt::Var(q, l(b)),
        Stmt::If(
            bin(BinOp::Lt, l(vb), l(va)),
            vec![Stmt::Assign(p, l(b)), Stmt::Assign(q, l(a))],
            vec![],
        ),
        Stmt::Var(fac, f32c(1.0)),
        if runtime {
            let metric = || fetch(Resource::Adaptive, u(crate::lower::adaptive::METRIC_SLOT));
            Stmt::If(
                bin(
                    BinOp::Eq,
                    metric(),
                    f32c(crate::lower::adaptive::METRIC_BUFFER),
                ),
                vec![Stmt::Assign(fac, fetch(Resource::EdgeFactors, l(edge)))],
                vec![Stmt::If(
                    bin(
                        BinOp::Eq,
                        metric(),
                        f32c(crate::lower::adaptive::METRIC_DISTANCE),
                    ),
                    distance,
                    screen,
                )],
            )
        } else {
            Stmt::IfDef(
                plan::Define::MetricBuffer,
                vec![Stmt::Assign(fac, fetch(Resource::EdgeFactors, l(edge)))],
                vec![Stmt::IfDef(plan::Define::MetricDistance, distance, screen)],
            )
        },
        // `factor >= min` is false for NaN: NaN becomes min.
        Stmt::If(
            bin(BinOp::Ge, l(fac), ad(23)),
            vec![],
            vec![Stmt::Assign(fac, ad(23))],
        ),
        Stmt::If(
            bin(BinOp::Gt, l(fac), ad(24)),
            vec![Stmt::Assign(fac, ad(24))],
            vec![],
        ),
        Stmt::Return(l(fac)),
    ];
    f
}
