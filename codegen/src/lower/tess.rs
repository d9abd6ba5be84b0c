//! The bodies of the hardware tessellation stages ([`TessStages`]): the
//! control stage (patch function, tessellation factors) and the evaluation
//! stage (integer grid point or raw domain point, the sample, the stage
//! outputs, the capture of harness builds), built once as Plan statements.
//!
//! The GLSL and HLSL printers print these bodies inside their entry points
//! (`.tesc`/`.tese` `main`, `hs_patch_constants`/`ds_main`) and add only
//! their API's declarations around them. Every choice that decides bits
//! lives here: how the integer grid point is recovered from the
//! tessellator's coordinate (`round(u·level)`), the adaptive fixed-point
//! level, which evaluator runs under which define, the capture layout
//! (`eval_main`'s), and how the factors are formed from the edges alone
//! (watertight.md Rules 2 and 3).

use crate::plan::abi::inside_edges;
use crate::plan::build::*;
use crate::plan::*;
use crate::plan::{common_fn, ADAPTIVE_LEVEL};

fn stage(s: StageIn) -> Expr {
    Expr::Stage(s)
}

fn param(name: &'static str) -> Expr {
    stage(StageIn::Param(name))
}

/// `params.first + patch in draw`: the patch's index into `patch_faces`.
fn patch_index() -> Expr {
    add(param("first"), stage(StageIn::PatchInDraw))
}

fn comment(s: &str) -> Stmt {
    Stmt::Comment(s.to_string())
}

/// `#ifdef TESSGEN_ADAPTIVE level = 2^16 #else level = params.level`.
fn level_stmt(level: LocalId, adaptive_doc: &str) -> Stmt {
    Stmt::IfDef(
        Define::Adaptive,
        vec![comment(adaptive_doc), Stmt::Let(level, u(ADAPTIVE_LEVEL))],
        vec![Stmt::Let(level, param("level"))],
    )
}

/// Both stage bodies of a scheme. `curve_const` is the scheme's
/// `EDGE_CURVE` constant.
pub fn stages(entries: &Entries, curve_const: usize) -> TessStages {
    let points = entries
        .patches
        .iter()
        .map(|p| p.control_points)
        .max()
        .unwrap_or(1)
        .max(1);
    TessStages {
        control: control(entries, curve_const, false),
        evaluation: evaluation(entries),
        hull: control(entries, curve_const, true),
        unpack: unpack(),
        store_cp: store_cp(),
        load_cp: load_cp(),
        points,
        slots: (3 * points).div_ceil(4),
    }
}

/// The body of the compute entry `vertex_stage_main` (GLSL, HLSL; see
/// [`Entries::compute_vertex`]).
pub fn compute_vertex(entries: &Entries) -> Function {
    let mut f = Function::new(
        "compute_vertex",
        "Vertex stage of vertices params.first .. params.first + params.count (valence 0 = unused vertex, skipped).",
    );
    let k = f.local("k", Ty::U32);
    let vertex = f.local("vertex", Ty::U32);
    f.body = vec![
        Stmt::Let(k, stage(StageIn::GlobalId)),
        Stmt::If(
            bin(BinOp::Lt, l(k), param("count")),
            vec![
                Stmt::Let(vertex, add(param("first"), l(k))),
                Stmt::If(
                    bin(BinOp::Ne, fetch(Resource::Valence, l(vertex)), u(0)),
                    vec![Stmt::Call(
                        FnRef::Local(entries.vertex_stage),
                        vec![l(vertex), fetch(Resource::VertexOutOffsets, l(vertex))],
                    )],
                    vec![],
                ),
            ],
            vec![],
        ),
    ];
    f
}

/// The body of the compute entry `eval_main` (GLSL, HLSL; see
/// [`Entries::compute_eval`]): invocation `k` evaluates sample `k mod
/// grid_len(level)` of patch `params.first + k / grid_len(level)` (class
/// `params.class`, control points from `params.cp_base`) through
/// `eval_displaced_global` (displacement off: `eval`'s sample bit for bit)
/// into `samples[(params.out_base + k)·6 ..]`.
pub fn compute_eval(entries: &Entries) -> Function {
    let mut f = Function::new(
        "compute_eval",
        "grid_len(level) samples per patch of params.first .. + params.count, sample s of a patch at (iu, iv) = (grid_iu(s), grid_iv(s)), written as 6 floats (position xyz, normal xyz) at samples[(params.out_base + k)·6]; through the displacement step, a no-op bit for bit while displace_info[0] == 0.",
    );
    let [grid_len, grid_iu, grid_iv] = entries.grid;
    let k = f.local("k", Ty::U32);
    let level = f.local("level", Ty::U32);
    let spp = f.local("spp", Ty::U32);
    let patch = f.local("patch_index", Ty::U32);
    let s = f.local("s", Ty::U32);
    let iu = f.local("iu", Ty::U32);
    let iv = f.local("iv", Ty::U32);
    let points = f.local("points", Ty::U32);
    let face = f.local("face", Ty::U32);
    let result = f.local("result", Ty::Struct(common::SAMPLE));
    let at = f.local("at", Ty::U32);
    // Control points per patch of the draw's class: the last class
    // unconditional (like `eval`'s dispatch).
    let mut chain: Vec<Stmt> = Vec::new();
    for (c, p) in entries.patches.iter().enumerate().rev() {
        let set = Stmt::Assign(points, u(p.control_points));
        chain = if chain.is_empty() {
            vec![set]
        } else {
            vec![Stmt::If(
                bin(BinOp::Eq, param("class"), u(c as u32)),
                vec![set],
                chain,
            )]
        };
    }
    let eval = entries
        .tess_displaced
        .as_ref()
        .map(|t| t.eval_displaced_global)
        .unwrap_or(entries.eval);
    let mut body = vec![
        Stmt::Let(patch, div(l(k), l(spp))),
        Stmt::Let(s, bin(BinOp::Rem, l(k), l(spp))),
        Stmt::Let(iu, call(FnRef::Local(grid_iu), vec![l(s), l(level)])),
        Stmt::Let(iv, call(FnRef::Local(grid_iv), vec![l(s), l(level)])),
        Stmt::Var(points, u(0)),
    ];
    body.extend(chain);
    body.push(Stmt::Let(
        face,
        fetch(Resource::PatchFaces, add(param("first"), l(patch))),
    ));
    body.push(Stmt::Let(
        result,
        call(
            FnRef::Local(eval),
            vec![
                l(face),
                param("class"),
                add(param("cp_base"), mul(l(patch), l(points))),
                l(iu),
                l(iv),
                l(level),
            ],
        ),
    ));
    body.push(Stmt::Let(at, mul(add(param("out_base"), l(k)), u(6))));
    body.extend(sample_stores(at, result));
    f.body = vec![
        Stmt::Let(k, stage(StageIn::GlobalId)),
        Stmt::Let(level, param("level")),
        Stmt::Let(spp, call(FnRef::Local(grid_len), vec![l(level)])),
        Stmt::If(
            bin(BinOp::Lt, l(k), mul(param("count"), l(spp))),
            body,
            vec![],
        ),
    ];
    f
}

/// The 6 floats of `result` (position xyz, normal xyz) into `samples[at ..
/// at + 6]`: the compute evaluation's and the capture's sample layout.
fn sample_stores(at: LocalId, result: LocalId) -> Vec<Stmt> {
    [(0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (1, 2)]
        .into_iter()
        .enumerate()
        .map(|(i, (field, c))| {
            let index = if i == 0 {
                l(at)
            } else {
                add(l(at), u(i as u32))
            };
            Stmt::Store(
                Resource::Samples,
                index,
                Expr::Call(
                    Builtin::Component(c),
                    vec![Expr::Field(Box::new(l(result)), field)],
                ),
            )
        })
        .collect()
}

/// The `vec4` slot and component of float `k` of the packed control points.
fn slot(k: Expr) -> (Expr, Expr) {
    (div(k.clone(), u(4)), bin(BinOp::Rem, k, u(4)))
}

fn store_cp() -> Function {
    let mut f = Function::new(
        "store_patch_cp",
        "Control point j into the packed per-patch storage: floats 3j .. 3j+2 of the vec4 slots.",
    );
    let j = f.param("j", Ty::U32);
    let p = f.param("p", Ty::Vec3);
    let k = f.local("k", Ty::U32);
    f.body.push(Stmt::Let(k, mul(u(3), l(j))));
    for c in 0..3u8 {
        let at = if c == 0 { l(k) } else { add(l(k), u(c as u32)) };
        let (s, comp) = slot(at);
        f.body.push(Stmt::StorePatchSlot(
            s,
            comp,
            Expr::Call(Builtin::Component(c), vec![l(p)]),
        ));
    }
    f
}

fn load_cp() -> Function {
    let mut f = Function::new(
        "load_patch_cp",
        "Control point j from the packed per-patch storage (the inverse of store_patch_cp).",
    );
    let j = f.param("j", Ty::U32);
    f.ret = Some(Ty::Vec3);
    let k = f.local("k", Ty::U32);
    f.body.push(Stmt::Let(k, mul(u(3), l(j))));
    let xs = (0..3u32)
        .map(|c| {
            let at = if c == 0 { l(k) } else { add(l(k), u(c)) };
            let (s, comp) = slot(at);
            Expr::PatchSlot(Box::new(s), Box::new(comp))
        })
        .collect();
    f.body.push(Stmt::Return(Expr::Call(Builtin::Vec3, xs)));
    f
}

/// `float3 cp[KMAX]` zeroed: the patch-local array a patch function
/// fills (the components a class with fewer points leaves are defined).
fn zeroed_patch_local(f: &mut Function) -> Vec<Stmt> {
    let i = f.local("i", Ty::U32);
    let zero = Expr::Call(Builtin::Vec3, vec![f32c(0.0), f32c(0.0), f32c(0.0)]);
    vec![
        Stmt::PatchLocal,
        Stmt::For(
            i,
            u(0),
            Expr::Named(Named::Kmax),
            vec![Stmt::Store(Resource::ControlPoints, l(i), zero)],
        ),
    ]
}

/// The domain stage's patch-local array ([`TessStages::unpack`]): point
/// `j` from the packed per-patch storage for `j < KMAX`.
fn unpack() -> Function {
    let mut f = Function::new(
        "tess_unpack",
        "The patch's control points from the packed per-patch storage into the patch-local array.",
    );
    let j = f.local("j", Ty::U32);
    f.body = vec![
        Stmt::PatchLocal,
        Stmt::For(
            j,
            u(0),
            Expr::Named(Named::Kmax),
            vec![Stmt::Store(
                Resource::ControlPoints,
                l(j),
                Expr::PatchCp(Box::new(l(j))),
            )],
        ),
    ];
    f
}

/// The body of `patch_main` for targets whose patch functions write a
/// patch-local array (HLSL; see [`Entries::compute_patch_local`]).
pub fn compute_patch_local(entries: &Entries) -> Function {
    let mut f = Function::new(
        "compute_patch_local",
        "Patch stage of patches params.first .. params.first + params.count, all of class params.class: the class's patch function fills a patch-local array (cp_base 0), copied to control_points from params.cp_base + k·CONTROL_POINTS[class].",
    );
    let k = f.local("k", Ty::U32);
    let face = f.local("face", Ty::U32);
    let points = f.local("points", Ty::U32);
    let cp_base = f.local("cp_base", Ty::U32);
    let j = f.local("j", Ty::U32);
    f.body = vec![
        Stmt::Let(k, stage(StageIn::GlobalId)),
        Stmt::If(
            bin(BinOp::Ge, l(k), param("count")),
            vec![Stmt::ReturnVoid],
            vec![],
        ),
        Stmt::Let(face, fetch(Resource::PatchFaces, add(param("first"), l(k)))),
        Stmt::Let(
            points,
            Expr::NamedIndex(Named::ControlPoints, Box::new(param("class"))),
        ),
    ];
    let zero = zeroed_patch_local(&mut f);
    f.body.extend(zero);
    f.body.extend(class_calls(entries, face));
    f.body.push(Stmt::Let(
        cp_base,
        add(param("cp_base"), mul(l(k), l(points))),
    ));
    f.body.push(Stmt::For(
        j,
        u(0),
        l(points),
        vec![Stmt::Store(
            Resource::GlobalControlPoints,
            add(l(cp_base), l(j)),
            fetch(Resource::ControlPoints, l(j)),
        )],
    ));
    f
}

/// `if (class == 0) {…} else if … else {…}` over the classes, each
/// calling its patch function on `face` at cp_base 0, the last class
/// unconditional (like `eval`'s dispatch).
fn class_calls(entries: &Entries, face: LocalId) -> Vec<Stmt> {
    let mut chain: Vec<Stmt> = Vec::new();
    for (k, p) in entries.patches.iter().enumerate().rev() {
        let call = Stmt::Call(FnRef::Local(p.function), vec![l(face), u(0)]);
        chain = if chain.is_empty() {
            vec![call]
        } else {
            vec![Stmt::If(
                bin(BinOp::Eq, param("class"), u(k as u32)),
                vec![call],
                chain,
            )]
        };
    }
    chain
}

/// The control stage (`local`: [`TessStages::hull`], through a patch-local
/// array copied into the packed storage).
fn control(entries: &Entries, curve_const: usize, local: bool) -> Function {
    let sides = entries.sides;
    let mut f = Function::new(
        "tess_control",
        "The patch stage of the draw's class, once per patch, into the patch's control points (cp_base 0), then the tessellation factors.",
    );
    let face = f.local("face", Ty::U32);
    if local {
        let zero = zeroed_patch_local(&mut f);
        f.body.extend(zero);
    }
    f.body
        .push(Stmt::Let(face, fetch(Resource::PatchFaces, patch_index())));
    f.body.extend(class_calls(entries, face));
    f.body.push(comment(
        "One factor per edge that depends only on the edge, so both patches of an edge get the\n\
         same parameters (watertight.md Rule 3): the uniform level, or in adaptive builds a\n\
         factor per edge.",
    ));
    // Adaptive: edge k's factor from its two corners (EDGE_CURVE's end
    // points, shared control points), their global vertices and the global
    // edge id.
    let mut adaptive = vec![comment(if sides == 3 {
        "Adaptive: edge k's factor from its two corners (EDGE_CURVE's end points, shared\n\
         control points), their global vertices and the global edge id, all data of the edge\n\
         alone. Inside factor: the largest of the three."
    } else {
        "Adaptive: edge k's factor from its two corners (EDGE_CURVE's end points, shared\n\
         control points), their global vertices and the global edge id, all data of the edge\n\
         alone. Inside factors: the larger of the two edges running in that direction."
    })];
    let mut factors = Vec::new();
    for k in 0..sides {
        let fk = f.local(format!("f_{k}"), Ty::F32);
        let pts = entries.curve_points();
        let curve = add(mul(param("class"), u(pts * sides)), u(pts * k));
        let corner = |c: u32| add(mul(l(face), u(sides)), u(c));
        adaptive.push(Stmt::Let(
            fk,
            call(
                FnRef::Common(common_fn::EDGE_FACTOR),
                vec![
                    fetch(
                        Resource::ControlPoints,
                        Expr::ConstIndex(curve_const, Box::new(curve.clone())),
                    ),
                    fetch(
                        Resource::ControlPoints,
                        Expr::ConstIndex(curve_const, Box::new(add(curve, u(pts - 1)))),
                    ),
                    fetch(Resource::CornerVertex, corner(k)),
                    fetch(Resource::CornerVertex, corner((k + 1) % sides)),
                    fetch(Resource::FaceEdges, corner(k)),
                ],
            ),
        ));
        factors.push(fk);
    }
    let inside = if sides == 3 { 1 } else { 2 };
    let mut uniform = Vec::new();
    for (k, fk) in factors.iter().enumerate() {
        adaptive.push(Stmt::Output(StageOut::EdgeFactor(k as u8), l(*fk)));
        uniform.push(Stmt::Output(
            StageOut::EdgeFactor(k as u8),
            to_f32(param("level")),
        ));
    }
    for d in 0..inside {
        let mut es = inside_edges(sides, d).into_iter();
        let first = es.next().map(|e| l(factors[e])).unwrap_or(f32c(1.0));
        let max = es.fold(first, |acc, e| {
            Expr::Call(Builtin::Max, vec![acc, l(factors[e])])
        });
        adaptive.push(Stmt::Output(StageOut::InsideFactor(d), max));
        uniform.push(Stmt::Output(
            StageOut::InsideFactor(d),
            to_f32(param("level")),
        ));
    }
    f.body
        .push(Stmt::IfDef(Define::Adaptive, adaptive, uniform));
    if local {
        let j4 = f.local("j4", Ty::U32);
        let j = f.local("j", Ty::U32);
        f.body.push(Stmt::For(
            j4,
            u(0),
            Expr::Named(Named::Kmax4),
            vec![Stmt::ClearPatchSlot(l(j4))],
        ));
        f.body.push(Stmt::For(
            j,
            u(0),
            Expr::Named(Named::Kmax),
            vec![Stmt::StorePatchCp(
                l(j),
                fetch(Resource::ControlPoints, l(j)),
            )],
        ));
    }
    f
}

fn f32c(x: f32) -> Expr {
    Expr::F32(x)
}

fn evaluation(entries: &Entries) -> Function {
    let mut f = Function::new(
        "tess_evaluation",
        "Position and normal at the tessellator's domain point; capture builds also record it.",
    );
    let level = f.local("level", Ty::U32);
    let result = f.local("result", Ty::Struct(common::SAMPLE));
    let tc = |k: u8| stage(StageIn::TessCoord(k));
    let outputs = |result: LocalId| {
        vec![
            Stmt::Output(
                StageOut::Clip,
                Expr::Call(Builtin::Project, vec![Expr::Field(Box::new(l(result)), 0)]),
            ),
            Stmt::Output(StageOut::Position, Expr::Field(Box::new(l(result)), 0)),
            Stmt::Output(StageOut::Normal, Expr::Field(Box::new(l(result)), 1)),
        ]
    };
    if let Some(d) = entries.eval_domain {
        f.body.push(comment(
            "Triangles: eval_domain takes the raw barycentric domain point (x, y, z) of corners\n\
             (0, 1, 2). On the outer ring (a coordinate exactly 0; an integer level puts vertex i\n\
             at i/level in fixed point) it rounds to the integer grid point and takes the shared\n\
             edge evaluator, so the two patches of an edge compute the same bits (watertight.md\n\
             Rules 2 and 3). Inside, the hardware's inner rings (ring k: level − 2k segments per\n\
             side) are not the barycentric lattice, so it evaluates the surface at the raw point.",
        ));
        f.body.push(level_stmt(
            level,
            "Adaptive (any partitioning): the tessellator's coordinates are 16.16 fixed point, so\n\
             on an edge round(y·2^16), round(z·2^16) are exact and the neighbour, whose\n\
             tessellator mirrors the edge's points (1 − t is exact in fixed point), hands the\n\
             shared edge evaluator exactly the swapped integer pair.",
        ));
        let eval = Stmt::Let(
            result,
            call(
                FnRef::Local(d),
                vec![param("class"), u(0), tc(0), tc(1), tc(2), l(level)],
            ),
        );
        match entries.tess_displaced.as_ref().and_then(|t| t.eval_domain) {
            Some(dd) => {
                let face = f.local("face", Ty::U32);
                f.body.push(Stmt::IfDef(
                    Define::Displace,
                    vec![
                        comment(
                            "Displaced: on the boundary the integer step with the owner's normal (from the\n\
                             global control-point buffer, filled by patch_main before the draw) and texture\n\
                             coordinate; inside, the raw point along its own normal (watertight.md Rules 4\n\
                             and 5).",
                        ),
                        Stmt::Let(face, fetch(Resource::PatchFaces, patch_index())),
                        Stmt::Let(
                            result,
                            call(
                                FnRef::Local(dd),
                                vec![
                                    l(face),
                                    param("class"),
                                    u(0),
                                    tc(0),
                                    tc(1),
                                    tc(2),
                                    l(level),
                                ],
                            ),
                        ),
                    ],
                    vec![eval],
                ));
            }
            None => f.body.push(eval),
        }
        f.body.extend(outputs(result));
        f.body.push(Stmt::IfDef(
            Define::Capture,
            vec![
                comment(
                    "Capture: the domain point and the patch of every vertex, for a harness that\n\
                     records the output triangles (inner vertices are not grid points).",
                ),
                Stmt::Output(
                    StageOut::Domain,
                    Expr::Call(Builtin::Vec3, vec![tc(0), tc(1), tc(2)]),
                ),
                Stmt::Output(StageOut::Patch, patch_index()),
            ],
            vec![],
        ));
        return f;
    }
    let iu = f.local("iu", Ty::U32);
    let iv = f.local("iv", Ty::U32);
    let at = f.local("at", Ty::U32);
    f.body.push(comment(
        "The grid point as integers: an integer level puts vertex i at i/level (fixed point),\n\
         so rounding recovers i exactly. eval and the shared edge evaluator form every weight\n\
         from these integers (watertight.md Rules 2 and 3), so the two patches of an edge\n\
         compute the same bits.",
    ));
    if entries.sides == 4 {
        f.body.push(level_stmt(
            level,
            "Adaptive (any partitioning): the coordinate on the tessellator's 16.16 fixed-point\n\
             grid, iu = u·2^16 (exact in f32). Both weights of every lerp are then formed from\n\
             integers (m/2^16, (2^16 − m)/2^16): interior points evaluate at the hardware\n\
             coordinate itself, and on an edge the neighbour, whose tessellator mirrors the\n\
             edge's points (1 − t is exact in fixed point), passes the shared edge evaluator\n\
             exactly the swapped pair.",
        ));
    } else {
        f.body.push(Stmt::Let(level, param("level")));
    }
    // Triangles without eval_domain: eval takes barycentric
    // (level − iu − iv, iu, iv) of corners (0, 1, 2), iu from y, iv from z.
    let (cu, cv) = if entries.sides == 3 { (1, 2) } else { (0, 1) };
    let grid = |c: u8| {
        Expr::Call(
            Builtin::U32FromF32,
            vec![Expr::Call(
                Builtin::Round,
                vec![mul(tc(c), to_f32(l(level)))],
            )],
        )
    };
    f.body.push(Stmt::Let(iu, grid(cu)));
    f.body.push(Stmt::Let(iv, grid(cv)));
    let eval = Stmt::Let(
        result,
        call(
            FnRef::Local(entries.eval),
            vec![param("class"), u(0), l(iu), l(iv), l(level)],
        ),
    );
    match &entries.tess_displaced {
        Some(t) => {
            let face = f.local("face", Ty::U32);
            f.body.push(Stmt::IfDef(
                Define::Displace,
                vec![
                    comment(
                        "Displaced: this patch's sample from its own control points (cp_base 0), the\n\
                         owner's normal on the boundary from the global control-point buffer, filled\n\
                         by patch_main before the draw (watertight.md Rules 4 and 5).",
                    ),
                    Stmt::Let(face, fetch(Resource::PatchFaces, patch_index())),
                    Stmt::Let(
                        result,
                        call(
                            FnRef::Local(t.eval_displaced),
                            vec![l(face), param("class"), u(0), l(iu), l(iv), l(level)],
                        ),
                    ),
                ],
                vec![eval],
            ));
        }
        None => f.body.push(eval),
    }
    f.body.extend(outputs(result));
    // Grid capture: the sample at eval_main's layout, patch p of the draw
    // being patch out_base + p, sample grid_index(iu, iv), 6 floats.
    let mut grid_capture = vec![
        comment(
            "Capture: the sample at eval_main's layout, patch p of the draw being patch\n\
             out_base + p, sample grid_index(iu, iv), 6 floats (position, normal).",
        ),
        Stmt::Let(
            at,
            mul(
                add(
                    mul(
                        add(param("out_base"), stage(StageIn::PatchInDraw)),
                        call(FnRef::Local(entries.grid[0]), vec![l(level)]),
                    ),
                    call(
                        FnRef::Local(entries.grid_index),
                        vec![l(iu), l(iv), l(level)],
                    ),
                ),
                u(6),
            ),
        ),
    ];
    grid_capture.extend(sample_stores(at, result));
    let capture = if entries.sides == 4 {
        // Adaptive patterns are not a grid: like the triangle capture,
        // export the domain point and the patch.
        vec![Stmt::IfDef(
            Define::Adaptive,
            vec![
                comment(
                    "Adaptive capture: the domain point (u, v, 0) and the patch of every vertex,\n\
                     for a harness that records the output triangles.",
                ),
                Stmt::Output(
                    StageOut::Domain,
                    Expr::Call(Builtin::Vec3, vec![tc(0), tc(1), f32c(0.0)]),
                ),
                Stmt::Output(StageOut::Patch, patch_index()),
            ],
            grid_capture,
        )]
    } else {
        grid_capture
    };
    f.body.push(Stmt::IfDef(Define::Capture, capture, vec![]));
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::abi::{factor_slot, hw_factor_edges};

    /// Every inside factor the Plan forms is one of the API's inside slots,
    /// in both axis conventions (GLSL swaps u and v), and every edge feeds
    /// exactly one outer slot: the printers' slot look-up always succeeds.
    #[test]
    fn inside_and_edge_factors_have_a_slot() {
        for sides in [3u32, 4] {
            for first_is_u in [false, true] {
                let (outer, inner) = hw_factor_edges(sides, first_is_u);
                let mut seen = outer.clone();
                seen.sort_unstable();
                assert_eq!(seen, (0..sides as usize).collect::<Vec<_>>());
                let dirs = if sides == 3 { 1 } else { 2 };
                assert_eq!(inner.len(), dirs as usize);
                for d in 0..dirs {
                    assert!(
                        inner.contains(&inside_edges(sides, d)),
                        "sides {sides} d {d}"
                    );
                    let o = StageOut::InsideFactor(d);
                    assert!(factor_slot(sides, o, first_is_u).is_some());
                }
                for k in 0..sides as u8 {
                    let o = StageOut::EdgeFactor(k);
                    assert!(factor_slot(sides, o, first_is_u).is_some());
                }
            }
        }
    }
}
