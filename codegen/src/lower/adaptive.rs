//! Lowering of adaptive tessellation for targets without a hardware
//! tessellator (the WGSL instanced path and the CPU): power-of-two edge
//! levels, per-patch buckets and snapped transitions, as Plan functions so
//! the CPU (generated Rust) and the GPU (generated WGSL) run one definition.
//!
//! * `tessgen_edge_level(factor, max_level)` (common): the smallest power
//!   of two ≥ the factor, clamped to `max_level`. A function of the factor
//!   alone; the factor (`tessgen_edge_factor_runtime`) is a function of the
//!   edge alone (its end points in canonical order, or its global id), so
//!   both patches of an edge get the same level.
//! * `tessgen_bucket_level(l0, l1, l2, l3)` (common): a patch's bucket, the
//!   largest of its four edge levels — one instanced draw (dispatch) per
//!   bucket and class.
//! * `patch_edge_level(face, class, cp_base, k, max_level)` (per scheme):
//!   the level of edge k of a patch, its end points read through
//!   `EDGE_CURVE` (the patch corners: shared control points, bit-identical
//!   in both patches, watertight.md Rule 1) — what the classify pass runs.
//! * `eval_adaptive(class, cp_base, iu, iv, level, l0, l1, l2, l3)` (per
//!   scheme): `eval` at grid point `(iu, iv)` of the patch's bucket `level`,
//!   a boundary sample `i` of edge k *snapped* onto the edge's own level
//!   `L_e` (a power of two dividing `level`): `⌊i / (level / L_e)⌋` at level
//!   `L_e`, which goes through the shared edge evaluator there. Both patches
//!   of an edge therefore produce exactly the edge's `L_e + 1` points,
//!   whatever their buckets; fine boundary triangles whose two boundary
//!   corners snapped onto one point are degenerate (zero area), and the rest
//!   stitch the two levels without T-junctions.
//! * `eval_adaptive_displaced(face, class, cp_base, iu, iv, level, l0..l3)`
//!   (per scheme): the same snap, then the displacement step of
//!   `eval_displaced` at the snapped point — on an edge the owner's normal
//!   and texture coordinate at the edge's own level, a snapped corner as the
//!   level-1 grid point — so displaced neighbours in different buckets
//!   still agree bit for bit. The WGSL adaptive entries call it.

use crate::plan::build::*;
use crate::plan::{self, *};

/// Float of the `adaptive` buffer that selects the metric at run time
/// (targets without a preprocessor).
pub const METRIC_SLOT: u32 = 25;
/// `adaptive[METRIC_SLOT]` values.
pub const METRIC_SCREEN: f64 = 0.0;
pub const METRIC_DISTANCE: f64 = 1.0;
pub const METRIC_BUFFER: f64 = 2.0;

/// Doubling steps of `tessgen_edge_level`: levels up to 2^16.
const LEVEL_STEPS: u32 = 16;

/// `tessgen_edge_level(factor, max_level) -> u32`.
pub fn edge_level_fn() -> Function {
    let mut f = Function::new(
        "tessgen_edge_level",
        "Power-of-two level of an edge: the smallest 2^k >= factor, clamped to max_level (a power \
         of two). A function of the factor alone, so both patches of an edge get the same level. \
         A bounded loop (16 doublings) instead of a while: every language prints it alike; a NaN \
         factor compares false and gives 1.",
    );
    let factor = f.param("factor", Ty::F32);
    let max_level = f.param("max_level", Ty::U32);
    f.ret = Some(Ty::U32);
    let lv = f.local("level", Ty::U32);
    let step = f.local("step", Ty::U32);
    f.body = vec![
        Stmt::Var(lv, u(1)),
        Stmt::For(
            step,
            u(0),
            u(LEVEL_STEPS),
            vec![Stmt::If(
                bin(
                    BinOp::And,
                    bin(BinOp::Lt, to_f32(l(lv)), l(factor)),
                    bin(BinOp::Lt, l(lv), l(max_level)),
                ),
                vec![Stmt::Assign(lv, mul(l(lv), u(2)))],
                vec![],
            )],
        ),
        Stmt::Return(l(lv)),
    ];
    f
}

/// `tessgen_bucket_level(l0, l1, l2, l3) -> u32`.
pub fn bucket_level_fn() -> Function {
    let mut f = Function::new(
        "tessgen_bucket_level",
        "Bucket of a patch: the largest of its four edge levels (all powers of two, so each \
         divides it). Patches of one bucket and class are one instanced draw.",
    );
    let ls: Vec<LocalId> = (0..4).map(|k| f.param(format!("l{k}"), Ty::U32)).collect();
    f.ret = Some(Ty::U32);
    let m = f.local("bucket", Ty::U32);
    f.body.push(Stmt::Var(m, l(ls[0])));
    for &lk in &ls[1..] {
        f.body.push(Stmt::If(
            bin(BinOp::Gt, l(lk), l(m)),
            vec![Stmt::Assign(m, l(lk))],
            vec![],
        ));
    }
    f.body.push(Stmt::Return(l(m)));
    f
}

/// `patch_edge_level(face, class, cp_base, k, max_level) -> u32` of a quad
/// (`sides` 4) or triangle (`sides` 3) scheme; `curve_const` is the
/// scheme's `EDGE_CURVE` constant, `points` entries per curve.
///
/// The classify pass and the buffers it fills (`patch_levels`,
/// `bucket_patches`) have four edge slots per patch whatever the domain, so
/// the printers emit one entry for both. A triangle's slot 3 is not an edge:
/// its level is 1, the smallest level, which leaves the bucket (the largest
/// of the four) unchanged and which the triangle `eval_adaptive` never reads.
pub fn patch_edge_level_fn(curve_const: usize, sides: u32, points: u32) -> Function {
    let mut f = Function::new(
        "patch_edge_level",
        if sides == 4 {
            format!(
                "Level of edge k (v_k -> v_(k+1)) of the patch of face `face`: its end points are the \
                 patch corners (EDGE_CURVE points 0 and {}: shared control points, the same bits in \
                 both patches), its vertices corner_vertex[4·face + k], [4·face + (k+1)%4], its id \
                 face_edges[4·face + k]; tessgen_edge_factor_runtime, then tessgen_edge_level.",
                points - 1
            )
        } else {
            "Level of edge k (v_k -> v_(k+1)) of the triangle patch of face `face`: its end points \
             are the patch corners (EDGE_CURVE points 0 and 3: shared control points, the same \
             bits in both patches), its vertices corner_vertex[3·face + k], [3·face + (k+1)%3], \
             its id face_edges[3·face + k]; tessgen_edge_factor_runtime, then \
             tessgen_edge_level. Slot k = 3 is not an edge (the classify buffers keep four slots \
             per patch): level 1, neutral for the bucket."
                .to_string()
        },
    );
    let face = f.param("face", Ty::U32);
    let class = f.param("class", Ty::U32);
    let cp = f.param("cp_base", Ty::U32);
    let k = f.param("k", Ty::U32);
    let max_level = f.param("max_level", Ty::U32);
    f.ret = Some(Ty::U32);
    let k1 = f.local("k1", Ty::U32);
    let curve = f.local("curve", Ty::U32);
    let a = f.local("a", Ty::Vec3);
    let b = f.local("b", Ty::Vec3);
    let va = f.local("va", Ty::U32);
    let vb = f.local("vb", Ty::U32);
    let edge = f.local("edge", Ty::U32);
    let factor = f.local("factor", Ty::F32);
    let corner = |c: usize| {
        fetch(
            Resource::ControlPoints,
            add(
                l(cp),
                Expr::ConstIndex(curve_const, Box::new(add(l(curve), u(c as u32)))),
            ),
        )
    };
    if sides != 4 {
        f.body.push(Stmt::If(
            bin(BinOp::Ge, l(k), u(sides)),
            vec![Stmt::Return(u(1))],
            vec![],
        ));
    }
    f.body.extend([
        Stmt::Let(k1, bin(BinOp::Rem, add(l(k), u(1)), u(sides))),
        Stmt::Let(
            curve,
            add(mul(l(class), u(points * sides)), mul(l(k), u(points))),
        ),
        Stmt::Let(a, corner(0)),
        Stmt::Let(b, corner(points as usize - 1)),
        Stmt::Let(
            va,
            fetch(Resource::CornerVertex, add(mul(l(face), u(sides)), l(k))),
        ),
        Stmt::Let(
            vb,
            fetch(Resource::CornerVertex, add(mul(l(face), u(sides)), l(k1))),
        ),
        Stmt::Let(
            edge,
            fetch(Resource::FaceEdges, add(mul(l(face), u(sides)), l(k))),
        ),
        Stmt::Let(
            factor,
            call(
                FnRef::Common(crate::plan::common_fn::EDGE_FACTOR_RUNTIME),
                vec![l(a), l(b), l(va), l(vb), l(edge)],
            ),
        ),
        Stmt::Return(call(
            FnRef::Common(crate::plan::common_fn::EDGE_LEVEL),
            vec![l(factor), l(max_level)],
        )),
    ]);
    f
}

/// `eval_adaptive(class, cp_base, iu, iv, level, l0, l1, l2, l3) -> Sample`
/// of a quad (`sides` 4) or triangle (`sides` 3) scheme; `eval` is the
/// scheme's `eval`.
pub fn eval_adaptive_fn(eval: usize, sides: u32) -> Function {
    let callee = Callee::Eval(eval);
    if sides == 3 {
        return eval_adaptive_tri_fn(callee);
    }
    eval_adaptive_quad_fn(callee)
}

/// `eval_adaptive_displaced(face, class, cp_base, iu, iv, level, l0, l1,
/// l2, l3) -> Sample` of a quad (`sides` 4) or triangle (`sides` 3) scheme:
/// the snap of [`eval_adaptive_fn`], then `eval_displaced`'s body
/// ([`crate::lower::displace::displacement_step`], on the callees `c`) at the
/// snapped point. The step is inlined rather than a call to
/// `eval_displaced` because the HLSL printer leaves `eval_displaced` out
/// (its evaluation reads a patch-local array) but prints every other
/// function; like `eval_adaptive` it is dead code there.
///
/// Why this is watertight whatever the two neighbours' buckets: after the
/// snap a boundary sample of edge k is the grid point `(t', l_k)` of that
/// edge at the edge's own level `l_k` — a function of the edge alone — so
/// `eval_displaced`'s boundary path sees the same edge, the same parameter
/// (mirrored by the neighbour) and the same level in both patches: the
/// owner's normal is `eval(owner, owner's (iu, iv) at l_k)` — the owner is
/// evaluated at the *edge's* level, which need not be its own bucket — and
/// the texture coordinate is the edge owner's pair weighted
/// `(l_k − t')/l_k, t'/l_k`. A corner, though, is reached from every patch
/// around the vertex through whichever edge its snap picked, so at
/// different levels; every corner weight is an exact 0 or 1 whatever the
/// level, but rather than rely on each scheme's formulas for that, a
/// snapped corner is handed on as the level-1 grid point (`su/sl`, `sv/sl`
/// at level 1): every patch around the vertex then makes the identical
/// call (the vertex owner's `eval` at its corner at level 1, its single
/// texture coordinate). The position there is the corner point itself in
/// either form (the shared edge evaluator returns it for `i = 0` and
/// `i = level`).
pub fn eval_adaptive_displaced_fn(c: crate::lower::displace::Callees, sides: u32) -> Function {
    let callee = Callee::Displaced(c);
    if sides == 3 {
        return eval_adaptive_tri_fn(callee);
    }
    eval_adaptive_quad_fn(callee)
}

/// What the snap of `eval_adaptive` hands its point to.
#[derive(Clone, Copy)]
enum Callee {
    /// `eval(class, cp_base, su, sv, sl)`: `eval_adaptive`.
    Eval(usize),
    /// `eval_displaced`'s step on `(face, class, cp_base, su, sv, sl)`,
    /// corners at level 1: `eval_adaptive_displaced` (which takes `face`
    /// first).
    Displaced(crate::lower::displace::Callees),
}

impl Callee {
    fn name(self) -> &'static str {
        match self {
            Callee::Eval(_) => "eval_adaptive",
            Callee::Displaced(_) => "eval_adaptive_displaced",
        }
    }

    /// The function with its leading parameters: `face` for the displaced
    /// variant.
    fn function(self, doc: &str) -> (Function, Option<LocalId>) {
        let (mut f, face) = match self {
            Callee::Eval(_) => (Function::new(self.name(), doc), None),
            Callee::Displaced(_) => {
                let mut f = Function::new(
                    self.name(),
                    format!(
                        "{doc} Then eval_displaced at the snapped point (watertight.md Rules 4–5): \
                         on an edge the owner's normal and texture coordinate at the edge's own \
                         level l_k, the same call from both patches whatever their buckets; a \
                         snapped corner as the level-1 grid point, the same call from every \
                         patch around the vertex. displace_info[0] == 0 gives eval_adaptive's \
                         sample bit for bit."
                    ),
                );
                let face = f.param("face", Ty::U32);
                (f, Some(face))
            }
        };
        f.ret = Some(Ty::Struct(plan::common::SAMPLE));
        (f, face)
    }

    /// The statements after the snap, on `(su, sv, sl)`.
    fn finish(self, f: &mut Function, face: Option<LocalId>, sides: u32, at: [LocalId; 5]) {
        let [class, cp, su, sv, sl] = at;
        match (self, face) {
            (Callee::Displaced(c), Some(face)) => {
                let edge = |x: LocalId| {
                    bin(
                        BinOp::Or,
                        bin(BinOp::Eq, l(x), u(0)),
                        bin(BinOp::Eq, l(x), l(sl)),
                    )
                };
                // A corner (both coordinates 0 or sl; quads and triangles
                // alike): the level-1 grid point.
                f.body.push(Stmt::If(
                    bin(BinOp::And, edge(su), edge(sv)),
                    vec![
                        Stmt::Assign(su, div(l(su), l(sl))),
                        Stmt::Assign(sv, div(l(sv), l(sl))),
                        Stmt::Assign(sl, u(1)),
                    ],
                    vec![],
                ));
                crate::lower::displace::displacement_step(
                    f,
                    &c,
                    sides,
                    [face, class, cp, su, sv, sl],
                );
            }
            (Callee::Eval(e), _) => f.body.push(Stmt::Return(call(
                FnRef::Local(e),
                vec![l(class), l(cp), l(su), l(sv), l(sl)],
            ))),
            (Callee::Displaced(c), None) => f.body.push(Stmt::Return(call(
                FnRef::Local(c.eval),
                vec![l(class), l(cp), l(su), l(sv), l(sl)],
            ))),
        }
    }
}

fn eval_adaptive_quad_fn(callee: Callee) -> Function {
    let sides = 4;
    let (mut f, face) = callee.function(
        "Sample (iu, iv) of a patch drawn at its bucket `level` whose edges have the power-of-two \
         levels l0..l3 (edge k: v = 0, u = 1, v = 1, u = 0; each divides `level`). Interior \
         samples are eval at (iu, iv)/level; boundary sample i of edge k is snapped onto the \
         edge's own level: floor(i / (level / l_k)) at level l_k, evaluated by the shared edge \
         evaluator there, so both patches of an edge produce exactly its l_k + 1 points whatever \
         their buckets (no T-junctions; triangles that collapse are degenerate).",
    );
    let class = f.param("class", Ty::U32);
    let cp = f.param("cp_base", Ty::U32);
    let iu = f.param("iu", Ty::U32);
    let iv = f.param("iv", Ty::U32);
    let level = f.param("level", Ty::U32);
    let ls: Vec<LocalId> = (0..4).map(|k| f.param(format!("l{k}"), Ty::U32)).collect();
    let su = f.local("su", Ty::U32);
    let sv = f.local("sv", Ty::U32);
    let sl = f.local("sl", Ty::U32);
    // i / (level / l_k): the coarser point of edge k.
    let snap = |i: LocalId, k: usize| div(l(i), div(l(level), l(ls[k])));
    let on_edge = |k: usize, u_: Expr, v_: Expr| {
        vec![
            Stmt::Assign(su, u_),
            Stmt::Assign(sv, v_),
            Stmt::Assign(sl, l(ls[k])),
        ]
    };
    f.body = vec![
        Stmt::Var(su, l(iu)),
        Stmt::Var(sv, l(iv)),
        Stmt::Var(sl, l(level)),
        Stmt::If(
            bin(BinOp::Eq, l(iv), u(0)),
            on_edge(0, snap(iu, 0), u(0)),
            vec![Stmt::If(
                bin(BinOp::Eq, l(iu), l(level)),
                on_edge(1, l(ls[1]), snap(iv, 1)),
                vec![Stmt::If(
                    bin(BinOp::Eq, l(iv), l(level)),
                    on_edge(2, snap(iu, 2), l(ls[2])),
                    vec![Stmt::If(
                        bin(BinOp::Eq, l(iu), u(0)),
                        on_edge(3, u(0), snap(iv, 3)),
                        vec![],
                    )],
                )],
            )],
        ),
    ];
    callee.finish(&mut f, face, sides, [class, cp, su, sv, sl]);
    f
}

/// `eval_adaptive(class, cp_base, iu, iv, level, l0, l1, l2, l3) -> Sample`
/// of a triangle scheme: the triangle grid's snap.
///
/// Sample `(iu, iv)` of the bucket's triangle grid has the integer
/// barycentric coordinates `(level − iu − iv, iu, iv)`; its boundary samples
/// lie on edge 0 (`iv = 0`, parameter `t = iu`), edge 1 (`iu + iv = level`,
/// `t = iv`) or edge 2 (`iu = 0`, `t = level − iv`) — the conventions of
/// the triangle `eval`, tested in that order, so a corner belongs to the
/// edge it starts (`t = 0`) or, corner 1, to edge 0's end. A boundary sample
/// is snapped to `t' = ⌊t / (level / l_k)⌋` on its edge's own level `l_k`
/// and handed to `eval` as the grid point of that edge at parameter `t'` on
/// level `l_k`: edge 0 `(t', 0)`, edge 1 `(l_k − t', t')`, edge 2
/// `(0, l_k − t')`. `eval` then runs its shared edge evaluator with
/// `(t', l_k)` — or, at a corner, the corner's own edge — exactly what the
/// neighbour computes for the same point from its side (`(l_k − t', l_k)`
/// on the reversed curve, symmetric de Casteljau, Rule 2). The floor runs
/// along each edge's own direction, so only edge k's points collapse into
/// corner k: a fine triangle whose corners snap together is degenerate
/// (skipped by the weld), none folds over another.
fn eval_adaptive_tri_fn(callee: Callee) -> Function {
    let sides = 3;
    let (mut f, face) = callee.function(
        "Sample (iu, iv) (barycentric (level - iu - iv, iu, iv)) of a triangle patch drawn at its \
         bucket `level` whose edges have the power-of-two levels l0, l1, l2 (edge 0: iv = 0, t = \
         iu; edge 1: iu + iv = level, t = iv; edge 2: iu = 0, t = level - iv; each level divides \
         `level`; l3 is the unused fourth slot of the classify buffers). Interior samples are \
         eval at (iu, iv)/level; boundary sample t of edge k is snapped onto the edge's own \
         level: t' = floor(t / (level / l_k)), evaluated as that edge's point at level l_k by \
         the shared edge evaluator, so both patches of an edge produce exactly its l_k + 1 \
         points whatever their buckets (no T-junctions; triangles that collapse are \
         degenerate).",
    );
    let class = f.param("class", Ty::U32);
    let cp = f.param("cp_base", Ty::U32);
    let iu = f.param("iu", Ty::U32);
    let iv = f.param("iv", Ty::U32);
    let level = f.param("level", Ty::U32);
    let ls: Vec<LocalId> = (0..4).map(|k| f.param(format!("l{k}"), Ty::U32)).collect();
    let su = f.local("su", Ty::U32);
    let sv = f.local("sv", Ty::U32);
    let sl = f.local("sl", Ty::U32);
    let t = f.local("t", Ty::U32);
    // t / (level / l_k): the coarser point of edge k.
    let snap = |t: Expr, k: usize| div(t, div(l(level), l(ls[k])));
    let on_edge = |k: usize, t_: Expr, u_: Expr, v_: Expr| {
        vec![
            Stmt::Assign(t, t_),
            Stmt::Assign(su, u_),
            Stmt::Assign(sv, v_),
            Stmt::Assign(sl, l(ls[k])),
        ]
    };
    f.body = vec![
        Stmt::Var(su, l(iu)),
        Stmt::Var(sv, l(iv)),
        Stmt::Var(sl, l(level)),
        Stmt::Var(t, u(0)),
        Stmt::If(
            bin(BinOp::Eq, l(iv), u(0)),
            on_edge(0, snap(l(iu), 0), l(t), u(0)),
            vec![Stmt::If(
                bin(BinOp::Eq, add(l(iu), l(iv)), l(level)),
                on_edge(1, snap(l(iv), 1), sub(l(ls[1]), l(t)), l(t)),
                vec![Stmt::If(
                    bin(BinOp::Eq, l(iu), u(0)),
                    on_edge(2, snap(sub(l(level), l(iv)), 2), u(0), sub(l(ls[2]), l(t))),
                    vec![],
                )],
            )],
        ),
    ];
    callee.finish(&mut f, face, sides, [class, cp, su, sv, sl]);
    f
}
