//! Lowering of the displacement step (spec/watertight.md Rules 4 and 5):
//! `eval_displaced(face, class, cp_base, iu, iv, level)` = `eval`, then
//! `p + scale · h(tc) · n` with the normal and the texture coordinate of the
//! *owner* on shared edges and corners.
//!
//! * **Normal (Rule 4)**: on a patch boundary every patch — the owner
//!   included — takes the normal from one call `eval(owner class, owner
//!   cp_base, owner's (iu, iv), level)`, the owner's own formula on the
//!   owner's control points at the owner's integer coordinates. All patches
//!   of an edge (corner) therefore run the same function on the same
//!   arguments: the same bits. The owner is read from
//!   [`Resource::Owners`], which the runtime fills per face (lowest adjacent
//!   face index owns). This needs every patch's control points in one global
//!   buffer: the CPU, WGSL and the GLSL compute evaluation have it as the
//!   control-point resource itself. The hardware tessellation stages
//!   (`.tese`, `ds_main`) see only their own patch's control points, so
//!   they call `eval_displaced_tess` (built with `TESSGEN_DISPLACE`): the
//!   own sample from the patch-local points, the owner's from
//!   `eval_global`, a copy of `eval` ([`global_variants`]) whose fetches read
//!   [`Resource::GlobalControlPoints`], the global buffer the compute patch
//!   stage filled before the draw. Same function and arguments in every
//!   patch of the edge, so the same bits.
//! * **Texture coordinate (Rule 5)**: 16 per quad patch, 12 per triangle
//!   (4 per corner either way), selected with the spec's branch-free
//!   `idx_k = e_k + 2·e_{k−1}` and interpolated with bilinear (quads) or
//!   barycentric (triangles) weights formed from integers; on an edge the
//!   sum collapses exactly to `l·a + r·b` of the edge owner's pair
//!   (`1·x = x`, `0·x = 0`, `x + 0 = x`), which both sides form with
//!   mirrored integers.
//! * **Triangles** (`pn`, `stpn`, `phong`): the same step on the domain
//!   `(level − iu − iv, iu, iv)`; the owner's barycentrics of a shared point
//!   are a permutation of ours, so the owner's coordinates are found through
//!   its edge index and mirrored edge parameter (as for quads), never by
//!   permuting float weights. Their tessellation stages see the hardware's
//!   float domain point (`eval_domain`): `eval_domain_displaced` sends a
//!   boundary point (a coordinate exactly 0) to the integer step above at
//!   its grid point, and displaces an interior point — which no other patch
//!   evaluates — with its own normal and the interior texture coordinates
//!   weighted by the raw barycentrics (`tessgen_height_at_domain`).
//! * **Height**: texel fetches and bilinear weights in the Plan (no hardware
//!   filtering), so every backend computes the same formula.
//!
//! Displacement off (`displace_info[0] == 0`) skips the whole step: the
//! sample is `eval`'s, bit for bit.

use crate::plan::build::*;
use crate::plan::{self, *};

fn boolu(e: Expr) -> Expr {
    Expr::Call(Builtin::U32FromBool, vec![e])
}

fn eq(a: Expr, b: Expr) -> Expr {
    bin(BinOp::Eq, a, b)
}

fn let_(f: &mut Function, name: &str, ty: Ty, e: Expr) -> LocalId {
    let id = f.local(name, ty);
    f.body.push(Stmt::Let(id, e));
    id
}

/// Texture-coordinate floats per face: 4 `(s, t)` pairs per corner
/// (quads 16 pairs = 32, triangles 12 pairs = 24; watertight.md Rule 5).
pub fn texcoord_stride(sides: u32) -> u32 {
    8 * sides
}

/// Owner-record u32 per face: 4 per edge and 4 per corner (quads 32,
/// triangles 24).
pub fn owner_stride(sides: u32) -> u32 {
    8 * sides
}

/// The integer barycentric weights, edge predicates and boundary test of a
/// facet's domain, shared by the texture-coordinate selection and the
/// owner-record lookup so both name the edges alike.
///
/// * quads: corner k at `(0,0), (1,0), (1,1), (0,1)`; edge k is
///   `v = 0`, `u = 1`, `v = 1`, `u = 0`;
/// * triangles: barycentric `(level − iu − iv, iu, iv)` of corners 0, 1, 2
///   (`runtime::trimesh`); edge k runs corner k → k+1 and is where corner
///   k+2's weight is zero: `iv = 0`, `iu + iv = level`, `iu = 0`.
fn edge_predicates(iu: LocalId, iv: LocalId, level: LocalId, sides: u32) -> Vec<Expr> {
    if sides == 4 {
        vec![
            eq(l(iv), u(0)),
            eq(l(iu), l(level)),
            eq(l(iv), l(level)),
            eq(l(iu), u(0)),
        ]
    } else {
        vec![
            eq(l(iv), u(0)),
            eq(add(l(iu), l(iv)), l(level)),
            eq(l(iu), u(0)),
        ]
    }
}

/// `tessgen_height_at(face, iu, iv, level) -> f32`: the height at the
/// interpolated texture coordinate (`height` = index of `tessgen_height`),
/// for a facet of `sides` corners (4: 16 coordinates per quad, 3: 12 per
/// triangle).
pub fn texcoord_fn(height: usize, sides: u32) -> Function {
    let doc = if sides == 4 {
        "Displacement texture coordinate at (iu, iv)/level of face `face` (watertight.md Rule 5): \
         corner k reads pair idx_k = e_k + 2·e_(k−1) of its 4 (interior, edge k's owner, \
         edge k−1's owner, vertex owner), weighted bilinearly with weights formed from integers. \
         On an edge the sum collapses exactly to the edge owner's two coordinates, at a corner \
         to the vertex owner's one. Returns the displacement height there (tessgen_height)."
    } else {
        "Displacement texture coordinate at barycentric (level − iu − iv, iu, iv)/level of \
         triangle `face` (watertight.md Rule 5, 12 per triangle): corner k reads pair \
         idx_k = e_k + 2·e_(k−1) of its 4 (interior, edge k's owner, edge k−1's owner, vertex \
         owner), with edge predicates e0 (iv = 0), e1 (iu + iv = level), e2 (iu = 0), weighted \
         by the barycentric weights, each formed from integers. On edge k corner k+2's weight \
         is an exact 0, so the sum collapses to the edge owner's two coordinates, at a corner \
         to the vertex owner's one. Returns the displacement height there (tessgen_height)."
    };
    let mut f = Function::new("tessgen_height_at", doc);
    f.precise = true;
    let face = f.param("face", Ty::U32);
    let iu = f.param("iu", Ty::U32);
    let iv = f.param("iv", Ty::U32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::F32);
    let lf = to_f32(l(level));
    // Quads: the four 1-D weights first (formed from integers), then the
    // edge predicates, then the bilinear weights; triangles: the edge
    // predicates, then the three barycentric weights.
    let lin = (sides == 4).then(|| {
        [
            let_(
                &mut f,
                "lu",
                Ty::F32,
                div(to_f32(sub(l(level), l(iu))), lf.clone()),
            ),
            let_(&mut f, "ru", Ty::F32, div(to_f32(l(iu)), lf.clone())),
            let_(
                &mut f,
                "lv",
                Ty::F32,
                div(to_f32(sub(l(level), l(iv))), lf.clone()),
            ),
            let_(&mut f, "rv", Ty::F32, div(to_f32(l(iv)), lf.clone())),
        ]
    });
    // Edge predicates, exact (integer comparisons).
    let e: Vec<LocalId> = edge_predicates(iu, iv, level, sides)
        .into_iter()
        .enumerate()
        .map(|(k, p)| let_(&mut f, &format!("e{k}"), Ty::U32, boolu(p)))
        .collect();
    let w: Vec<LocalId> = match lin {
        Some([lu, ru, lv, rv]) => vec![
            let_(&mut f, "w0", Ty::F32, mul(l(lu), l(lv))),
            let_(&mut f, "w1", Ty::F32, mul(l(ru), l(lv))),
            let_(&mut f, "w2", Ty::F32, mul(l(ru), l(rv))),
            let_(&mut f, "w3", Ty::F32, mul(l(lu), l(rv))),
        ],
        // Each barycentric weight from its own integer: on edge k the
        // opposite corner's is 0/level = 0 exactly and the edge's pair is
        // (level − t)/level, t/level, which the neighbour forms from the
        // mirrored integer.
        None => vec![
            let_(
                &mut f,
                "w0",
                Ty::F32,
                div(to_f32(sub(sub(l(level), l(iu)), l(iv))), lf.clone()),
            ),
            let_(&mut f, "w1", Ty::F32, div(to_f32(l(iu)), lf.clone())),
            let_(&mut f, "w2", Ty::F32, div(to_f32(l(iv)), lf)),
        ],
    };
    let n = sides as usize;
    let base = let_(
        &mut f,
        "base",
        Ty::U32,
        mul(l(face), u(texcoord_stride(sides))),
    );
    let mut at = Vec::new();
    for k in 0..n {
        // Pair (4k + idx_k), idx_k = e_k + 2·e_(k−1).
        let idx = let_(
            &mut f,
            &format!("p{k}"),
            Ty::U32,
            add(
                l(base),
                mul(
                    add(
                        u(4 * k as u32),
                        add(l(e[k]), mul(u(2), l(e[(k + n - 1) % n]))),
                    ),
                    u(2),
                ),
            ),
        );
        at.push(idx);
    }
    let mut comps = Vec::new();
    for (c, name) in ["s", "t"].iter().enumerate() {
        let term = |k: usize| {
            mul(
                l(w[k]),
                fetch(Resource::TexCoords, add(l(at[k]), u(c as u32))),
            )
        };
        let mut sum = add(term(0), term(1));
        for k in 2..n {
            sum = add(sum, term(k));
        }
        comps.push(l(let_(&mut f, name, Ty::F32, sum)));
    }
    f.body.push(Stmt::Return(call(FnRef::Local(height), comps)));
    f
}

/// `tessgen_height(s, t) -> f32`: bilinear over exact texel fetches.
pub fn height_fn() -> Function {
    let mut f = Function::new(
        "tessgen_height",
        "Displacement height at texture coordinate (s, t): texel centres at (i + 0.5)/width, \
         clamped to the map, bilinear weights formed here from exact texel fetches (never \
         hardware filtering, whose sub-texel precision differs between devices).",
    );
    let s = f.param("s", Ty::F32);
    let t = f.param("t", Ty::F32);
    f.ret = Some(Ty::F32);
    let w = let_(
        &mut f,
        "width",
        Ty::F32,
        fetch(Resource::DisplaceInfo, u(1)),
    );
    let h = let_(
        &mut f,
        "height",
        Ty::F32,
        fetch(Resource::DisplaceInfo, u(2)),
    );
    let coord = |f: &mut Function, name: &str, c: LocalId, size: LocalId| {
        let x = f.local(name, Ty::F32);
        f.body
            .push(Stmt::Var(x, sub(mul(l(c), l(size)), Expr::F32(0.5))));
        f.body.push(Stmt::If(
            bin(BinOp::Lt, l(x), Expr::F32(0.0)),
            vec![Stmt::Assign(x, Expr::F32(0.0))],
            vec![],
        ));
        f.body.push(Stmt::If(
            bin(BinOp::Gt, l(x), sub(l(size), Expr::F32(1.0))),
            vec![Stmt::Assign(x, sub(l(size), Expr::F32(1.0)))],
            vec![],
        ));
        let fl = let_(
            f,
            &format!("{name}f"),
            Ty::F32,
            Expr::Call(Builtin::Floor, vec![l(x)]),
        );
        let i0 = let_(
            f,
            &format!("{name}0"),
            Ty::U32,
            Expr::Call(Builtin::U32FromF32, vec![l(fl)]),
        );
        let n = let_(
            f,
            &format!("{name}n"),
            Ty::U32,
            Expr::Call(Builtin::U32FromF32, vec![l(size)]),
        );
        let i1 = f.local(format!("{name}1"), Ty::U32);
        f.body.push(Stmt::Var(i1, add(l(i0), u(1))));
        f.body.push(Stmt::If(
            bin(BinOp::Ge, l(i1), l(n)),
            vec![Stmt::Assign(i1, l(i0))],
            vec![],
        ));
        let fr = let_(f, &format!("f{name}"), Ty::F32, sub(l(x), l(fl)));
        (i0, i1, fr)
    };
    let (x0, x1, fx) = coord(&mut f, "x", s, w);
    let (y0, y1, fy) = coord(&mut f, "y", t, h);
    let texel =
        |x: LocalId, y: LocalId| Expr::Texel(Resource::DisplaceMap, Box::new(l(x)), Box::new(l(y)));
    let gx = let_(&mut f, "gx", Ty::F32, sub(Expr::F32(1.0), l(fx)));
    let gy = let_(&mut f, "gy", Ty::F32, sub(Expr::F32(1.0), l(fy)));
    let a = let_(
        &mut f,
        "a",
        Ty::F32,
        add(mul(texel(x0, y0), l(gx)), mul(texel(x1, y0), l(fx))),
    );
    let b = let_(
        &mut f,
        "b",
        Ty::F32,
        add(mul(texel(x0, y1), l(gx)), mul(texel(x1, y1), l(fx))),
    );
    f.body
        .push(Stmt::Return(add(mul(l(a), l(gy)), mul(l(b), l(fy)))));
    f
}

/// `tessgen_displace(p, n, d) -> p + n·d`, `precise`.
pub fn displace_point_fn() -> Function {
    let mut f = Function::new(
        "tessgen_displace",
        "The displaced point p + n·d, in one `precise` function so no backend contracts it \
         differently for the patches of one edge.",
    );
    f.precise = true;
    let p = f.param("p", Ty::Vec3);
    let n = f.param("n", Ty::Vec3);
    let d = f.param("d", Ty::F32);
    f.ret = Some(Ty::Vec3);
    f.body.push(Stmt::Return(add(l(p), mul(l(n), l(d)))));
    f
}

/// Indices (in the scheme module) of the functions `eval_displaced` calls.
#[derive(Clone, Copy, Debug)]
pub struct Callees {
    /// The patch's own sample.
    pub eval: usize,
    /// The owner's sample on the boundary: `eval` itself where every
    /// patch's control points are in one buffer (CPU, compute entries), the
    /// global-buffer copy `eval_global` in the tessellation stages.
    pub owner_eval: usize,
    pub texcoord: usize,
    pub displace: usize,
}

/// `eval_displaced(face, class, cp_base, iu, iv, level) -> Sample` of a
/// facet with `sides` corners (4 quads, 3 triangles).
pub fn eval_displaced_fn(c: &Callees, sides: u32) -> Function {
    displaced_fn(
        c,
        sides,
        "eval_displaced",
        "`eval`, then displacement along the normal by scale · h(tc) (watertight.md Rules 4–5). \
         On the patch boundary the normal is the owner's: `eval` of the owner patch at the \
         owner's integer coordinates, the same call from every patch of the edge or corner; \
         the texture coordinate is the owner's (tessgen_height_at). Interiors use the patch's \
         own. displace_info[0] == 0 returns eval's sample unchanged. The returned normal is the \
         undisplaced surface's.",
    )
}

/// `eval_displaced_tess(face, class, cp_base, iu, iv, level) -> Sample`:
/// the tessellation evaluation stages' displacement step. `cp_base` indexes
/// the patch's own control points (0 in `tcs_cp` / HLSL `cp`); the owner's
/// normal comes from `eval_global`, which reads the global control-point
/// buffer at the owner record's `cp_base`.
pub fn eval_displaced_tess_fn(c: &Callees, sides: u32) -> Function {
    displaced_fn(
        c,
        sides,
        "eval_displaced_tess",
        "eval_displaced for the tessellation evaluation stage: the patch's own sample from its \
         patch-local control points (`eval`, cp_base into the patch's array), the owner's normal \
         on the boundary from `eval_global` on the global control-point buffer (filled by the \
         compute patch stage), the same call and arguments as in every other patch of the edge \
         or corner (watertight.md Rule 4).",
    )
}

/// A copy of local function `root` (and of every local function it calls
/// that reads the control points) whose control-point fetches read
/// [`Resource::GlobalControlPoints`]; the copies are appended to `m`, named
/// `<name>_global`. Returns `(original, copy)` for every function copied
/// (callees first; `root`'s copy last).
pub fn global_variants(m: &mut Module, root: usize) -> Vec<(usize, usize)> {
    fn reads_cp(m: &Module, i: usize, seen: &mut Vec<usize>) -> bool {
        if seen.contains(&i) {
            return false;
        }
        seen.push(i);
        let f = &m.functions[i];
        f.resources().contains(&(Resource::ControlPoints, false))
            || crate::plan::called(f).into_iter().any(|c| match c {
                FnRef::Local(j) => reads_cp(m, j, seen),
                FnRef::Common(_) => false,
            })
    }
    fn expr(e: &mut Expr, map: &[(usize, usize)]) {
        match e {
            Expr::Fetch(r, i) => {
                if *r == Resource::ControlPoints {
                    *r = Resource::GlobalControlPoints;
                }
                expr(i, map);
            }
            Expr::CallFn(r, xs) => {
                if let FnRef::Local(j) = r {
                    if let Some(&(_, k)) = map.iter().find(|(a, _)| a == j) {
                        *r = FnRef::Local(k);
                    }
                }
                xs.iter_mut().for_each(|x| expr(x, map));
            }
            Expr::Call(_, xs) | Expr::Make(_, xs) => xs.iter_mut().for_each(|x| expr(x, map)),
            Expr::ConstIndex(_, a)
            | Expr::NamedIndex(_, a)
            | Expr::PatchCp(a)
            | Expr::Neg(a)
            | Expr::Field(a, _)
            | Expr::Float(_, a) => expr(a, map),
            Expr::Binary(_, a, b)
            | Expr::TableWeight(a, b)
            | Expr::Texel(_, a, b)
            | Expr::PatchSlot(a, b) => {
                expr(a, map);
                expr(b, map);
            }
            Expr::F32(_)
            | Expr::U32(_)
            | Expr::Local(_)
            | Expr::Const(_)
            | Expr::Stage(_)
            | Expr::Named(_)
            | Expr::Columns(_) => {}
        }
    }
    fn stmts(s: &mut [Stmt], map: &[(usize, usize)]) {
        for s in s {
            match s {
                Stmt::Let(_, e)
                | Stmt::Var(_, e)
                | Stmt::Assign(_, e)
                | Stmt::Return(e)
                | Stmt::AssignField(_, _, e) => expr(e, map),
                Stmt::Store(_, i, v) | Stmt::StoreFloat(_, i, v) => {
                    expr(i, map);
                    expr(v, map);
                }
                Stmt::If(c, a, b) => {
                    expr(c, map);
                    stmts(a, map);
                    stmts(b, map);
                }
                Stmt::IfDef(_, a, b) => {
                    stmts(a, map);
                    stmts(b, map);
                }
                Stmt::For(_, a, b, body) => {
                    expr(a, map);
                    expr(b, map);
                    stmts(body, map);
                }
                Stmt::Call(r, xs) => {
                    if let FnRef::Local(j) = r {
                        if let Some(&(_, k)) = map.iter().find(|(a, _)| a == j) {
                            *r = FnRef::Local(k);
                        }
                    }
                    xs.iter_mut().for_each(|x| expr(x, map));
                }
                Stmt::Output(_, e) => expr(e, map),
                Stmt::Comment(_) | Stmt::ReturnVoid | Stmt::Barrier(_) | Stmt::PatchLocal => {}
                Stmt::StorePatchCp(j, v) => {
                    expr(j, map);
                    expr(v, map);
                }
                Stmt::ClearPatchSlot(a) => expr(a, map),
                Stmt::StorePatchSlot(a, b, v) => {
                    expr(a, map);
                    expr(b, map);
                    expr(v, map);
                }
                Stmt::ForStep(_, a, b, step, body) => {
                    expr(a, map);
                    expr(b, map);
                    expr(step, map);
                    stmts(body, map);
                }
            }
        }
    }
    // Every local function reachable from root that reads control points,
    // callees first (so printers that print in module order see them first).
    fn collect(m: &Module, i: usize, out: &mut Vec<usize>) {
        if out.contains(&i) || !reads_cp(m, i, &mut Vec::new()) {
            return;
        }
        for c in crate::plan::called(&m.functions[i]) {
            if let FnRef::Local(j) = c {
                collect(m, j, out);
            }
        }
        out.push(i);
    }
    let mut order = Vec::new();
    collect(m, root, &mut order);
    let base = m.functions.len();
    let map: Vec<(usize, usize)> = order
        .iter()
        .enumerate()
        .map(|(k, &i)| (i, base + k))
        .collect();
    for &i in &order {
        let mut g = m.functions[i].clone();
        g.name = format!("{}_global", g.name);
        g.doc = format!(
            "{} (Copy reading the global control-point buffer: how the displacing tessellation \
             stages evaluate the owner patch, and how the GLSL/HLSL compute evaluation reads \
             every patch.)",
            g.doc
        );
        stmts(&mut g.body, &map);
        m.functions.push(g);
    }
    map
}

/// The copy of `f` in a [`global_variants`] map (`f` itself if it reads no
/// control points).
pub fn global_of(map: &[(usize, usize)], f: usize) -> usize {
    map.iter()
        .find(|(a, _)| *a == f)
        .map(|&(_, k)| k)
        .unwrap_or(f)
}

fn displaced_fn(c: &Callees, sides: u32, name: &str, doc: &str) -> Function {
    let mut f = Function::new(name, doc);
    let face = f.param("face", Ty::U32);
    let class = f.param("class", Ty::U32);
    let cp = f.param("cp_base", Ty::U32);
    let iu = f.param("iu", Ty::U32);
    let iv = f.param("iv", Ty::U32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::Struct(plan::common::SAMPLE));
    displacement_step(&mut f, c, sides, [face, class, cp, iu, iv, level]);
    f
}

/// The body of `eval_displaced` on the locals `[face, class, cp_base, iu,
/// iv, level]` of `f` (parameters, or the snapped point of
/// `eval_adaptive_displaced`): `eval`, the displacement step, `return`.
/// One lowering for every displacing function, so they cannot drift apart.
pub fn displacement_step(f: &mut Function, c: &Callees, sides: u32, at: [LocalId; 6]) {
    let [face, class, cp, iu, iv, level] = at;
    let sample = f.local("sample", Ty::Struct(plan::common::SAMPLE));
    f.body.push(Stmt::Var(
        sample,
        call(
            FnRef::Local(c.eval),
            vec![l(class), l(cp), l(iu), l(iv), l(level)],
        ),
    ));
    let scale = let_(f, "scale", Ty::F32, fetch(Resource::DisplaceInfo, u(0)));
    let mut on = Vec::new();
    let n = f.local("n", Ty::Vec3);
    on.push(Stmt::Var(n, Expr::Field(Box::new(l(sample)), 1)));
    // Boundary: slot 0..sides = edge k at t (from v_k), sides..2·sides =
    // corner k.
    let slot = f.local("slot", Ty::U32);
    let t = f.local("t", Ty::U32);
    let rec = f.local("rec", Ty::U32);
    let oclass = f.local("owner_class", Ty::U32);
    let ocp = f.local("owner_cp", Ty::U32);
    let ok = f.local("owner_k", Ty::U32);
    let ot = f.local("ot", Ty::U32);
    let ou = f.local("ou", Ty::U32);
    let ov = f.local("ov", Ty::U32);
    let os = f.local("owner_sample", Ty::Struct(plan::common::SAMPLE));
    // Our edge and the parameter t along it (from v_k), as `eval` picks
    // them: quads edge 0 (v = 0, t = u), 1 (u = 1, t = v), 2 (v = 1,
    // t = level − u), 3 (u = 0, t = level − v); triangles edge 0 (iv = 0,
    // t = iu), 1 (iu + iv = level, t = iv), 2 (iu = 0, t = level − iv).
    let mut boundary = if sides == 4 {
        vec![
            Stmt::Var(slot, u(3)),
            Stmt::Var(t, sub(l(level), l(iv))),
            Stmt::If(
                eq(l(iv), u(0)),
                vec![Stmt::Assign(slot, u(0)), Stmt::Assign(t, l(iu))],
                vec![Stmt::If(
                    eq(l(iu), l(level)),
                    vec![Stmt::Assign(slot, u(1)), Stmt::Assign(t, l(iv))],
                    vec![Stmt::If(
                        eq(l(iv), l(level)),
                        vec![
                            Stmt::Assign(slot, u(2)),
                            Stmt::Assign(t, sub(l(level), l(iu))),
                        ],
                        vec![],
                    )],
                )],
            ),
        ]
    } else {
        vec![
            Stmt::Var(slot, u(2)),
            Stmt::Var(t, sub(l(level), l(iv))),
            Stmt::If(
                eq(l(iv), u(0)),
                vec![Stmt::Assign(slot, u(0)), Stmt::Assign(t, l(iu))],
                vec![Stmt::If(
                    eq(add(l(iu), l(iv)), l(level)),
                    vec![Stmt::Assign(slot, u(1)), Stmt::Assign(t, l(iv))],
                    vec![],
                )],
            ),
        ]
    };
    // Owner edge k at parameter ot, in the owner's integer coordinates.
    // Quads: k = 0 (ot, 0), 1 (level, ot), 2 (level − ot, level),
    // 3 (0, level − ot). Triangles (the owner's barycentrics are a
    // permutation of ours, so go through its edge): k = 0 (ot, 0),
    // 1 (level − ot, ot), 2 (0, level − ot).
    let owner_coords = if sides == 4 {
        vec![
            Stmt::Var(ou, l(ot)),
            Stmt::Var(ov, u(0)),
            Stmt::If(
                eq(l(ok), u(1)),
                vec![Stmt::Assign(ou, l(level)), Stmt::Assign(ov, l(ot))],
                vec![Stmt::If(
                    eq(l(ok), u(2)),
                    vec![
                        Stmt::Assign(ou, sub(l(level), l(ot))),
                        Stmt::Assign(ov, l(level)),
                    ],
                    vec![Stmt::If(
                        eq(l(ok), u(3)),
                        vec![
                            Stmt::Assign(ou, u(0)),
                            Stmt::Assign(ov, sub(l(level), l(ot))),
                        ],
                        vec![],
                    )],
                )],
            ),
        ]
    } else {
        vec![
            Stmt::Var(ou, l(ot)),
            Stmt::Var(ov, u(0)),
            Stmt::If(
                eq(l(ok), u(1)),
                vec![
                    Stmt::Assign(ou, sub(l(level), l(ot))),
                    Stmt::Assign(ov, l(ot)),
                ],
                vec![Stmt::If(
                    eq(l(ok), u(2)),
                    vec![
                        Stmt::Assign(ou, u(0)),
                        Stmt::Assign(ov, sub(l(level), l(ot))),
                    ],
                    vec![],
                )],
            ),
        ]
    };
    boundary.extend([
        // Corners: the start (t = 0) or end (t = level) of the edge.
        Stmt::If(
            eq(l(t), u(0)),
            vec![Stmt::Assign(slot, add(l(slot), u(sides)))],
            vec![Stmt::If(
                eq(l(t), l(level)),
                vec![Stmt::Assign(
                    slot,
                    add(bin(BinOp::Rem, add(l(slot), u(1)), u(sides)), u(sides)),
                )],
                vec![],
            )],
        ),
        Stmt::Let(
            rec,
            add(mul(l(face), u(owner_stride(sides))), mul(l(slot), u(4))),
        ),
        Stmt::Let(oclass, fetch(Resource::Owners, l(rec))),
        Stmt::Let(ocp, fetch(Resource::Owners, add(l(rec), u(1)))),
        Stmt::Let(ok, fetch(Resource::Owners, add(l(rec), u(2)))),
        // The owner's parameter along its edge k: mirrored when it runs
        // the edge the other way, 0 at its corner k.
        Stmt::Var(ot, l(t)),
        Stmt::If(
            eq(fetch(Resource::Owners, add(l(rec), u(3))), u(1)),
            vec![Stmt::Assign(ot, sub(l(level), l(t)))],
            vec![],
        ),
        Stmt::If(
            bin(BinOp::Ge, l(slot), u(sides)),
            vec![Stmt::Assign(ot, u(0))],
            vec![],
        ),
    ]);
    boundary.extend(owner_coords);
    boundary.extend([
        Stmt::Let(
            os,
            call(
                FnRef::Local(c.owner_eval),
                vec![l(oclass), l(ocp), l(ou), l(ov), l(level)],
            ),
        ),
        Stmt::Assign(n, Expr::Field(Box::new(l(os)), 1)),
    ]);
    let p = edge_predicates(iu, iv, level, sides);
    let on_boundary = if sides == 4 {
        bin(
            BinOp::Or,
            bin(BinOp::Or, p[3].clone(), p[1].clone()),
            bin(BinOp::Or, p[0].clone(), p[2].clone()),
        )
    } else {
        bin(
            BinOp::Or,
            bin(BinOp::Or, p[0].clone(), p[2].clone()),
            p[1].clone(),
        )
    };
    on.push(Stmt::If(on_boundary, boundary, vec![]));
    let hgt = f.local("h", Ty::F32);
    on.push(Stmt::Let(
        hgt,
        call(
            FnRef::Local(c.texcoord),
            vec![l(face), l(iu), l(iv), l(level)],
        ),
    ));
    on.push(Stmt::AssignField(
        sample,
        0,
        call(
            FnRef::Local(c.displace),
            vec![
                Expr::Field(Box::new(l(sample)), 0),
                l(n),
                mul(l(scale), l(hgt)),
            ],
        ),
    ));
    f.body.push(Stmt::If(
        bin(BinOp::Ne, l(scale), Expr::F32(0.0)),
        on,
        vec![],
    ));
    f.body.push(Stmt::Return(l(sample)));
}

/// `tessgen_height_at_domain(face, x, y, z) -> f32`: the height at a
/// triangle's *interior* float barycentric point (the hardware
/// tessellator's inner vertices, which are not grid points): corner k's
/// interior pair (idx_k = 0) weighted by the raw barycentrics. Only
/// interior points come here, so no other patch computes the same point.
pub fn height_at_domain_fn(height: usize) -> Function {
    let mut f = Function::new(
        "tessgen_height_at_domain",
        "Displacement height at an interior barycentric point (x, y, z) of triangle `face` (the \
         tessellator's inner vertices, not grid points): each corner's interior texture \
         coordinate (pair 4k of its 4), weighted by the raw barycentrics. The boundary never \
         comes here (eval_domain_displaced takes the integer path there, watertight.md Rule 5).",
    );
    f.precise = true;
    let face = f.param("face", Ty::U32);
    let w = [
        f.param("x", Ty::F32),
        f.param("y", Ty::F32),
        f.param("z", Ty::F32),
    ];
    f.ret = Some(Ty::F32);
    let base = let_(&mut f, "base", Ty::U32, mul(l(face), u(texcoord_stride(3))));
    let mut comps = Vec::new();
    for (c, name) in ["s", "t"].iter().enumerate() {
        let term = |k: usize| {
            mul(
                l(w[k]),
                fetch(
                    Resource::TexCoords,
                    add(l(base), u(8 * k as u32 + c as u32)),
                ),
            )
        };
        let sum = add(add(term(0), term(1)), term(2));
        comps.push(l(let_(&mut f, name, Ty::F32, sum)));
    }
    f.body.push(Stmt::Return(call(FnRef::Local(height), comps)));
    f
}

/// What `eval_domain_displaced` calls.
#[derive(Clone, Copy, Debug)]
pub struct DomainCallees {
    /// The integer-grid displacing evaluation of the boundary:
    /// `eval_displaced` (one global control-point array: CPU, compute) or
    /// `eval_displaced_tess` (tessellation stages).
    pub boundary: usize,
    /// `eval_domain`: the undisplaced sample at the raw point.
    pub eval_domain: usize,
    /// `tessgen_height_at_domain`.
    pub height: usize,
    /// `tessgen_displace`.
    pub displace: usize,
}

/// `eval_domain_displaced(face, class, cp_base, x, y, z, level) -> Sample`
/// (named `name`): `eval_domain` with the displacement step, for the
/// triangle tessellation stages (and the CPU's parity reference of what
/// they capture).
pub fn eval_domain_displaced_fn(c: &DomainCallees, name: &str, doc: &str) -> Function {
    let mut f = Function::new(name, doc);
    let face = f.param("face", Ty::U32);
    let class = f.param("class", Ty::U32);
    let cp = f.param("cp_base", Ty::U32);
    let x = f.param("x", Ty::F32);
    let y = f.param("y", Ty::F32);
    let z = f.param("z", Ty::F32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::Struct(plan::common::SAMPLE));
    let grid = |c: LocalId| {
        Expr::Call(
            Builtin::U32FromF32,
            vec![Expr::Call(
                Builtin::Round,
                vec![mul(l(c), to_f32(l(level)))],
            )],
        )
    };
    let zero = |c: LocalId| eq(l(c), Expr::F32(0.0));
    let iu = f.local("iu", Ty::U32);
    let iv = f.local("iv", Ty::U32);
    f.body.push(Stmt::If(
        bin(BinOp::Or, bin(BinOp::Or, zero(x), zero(y)), zero(z)),
        vec![
            Stmt::Let(iu, grid(y)),
            Stmt::Let(iv, grid(z)),
            Stmt::Return(call(
                FnRef::Local(c.boundary),
                vec![l(face), l(class), l(cp), l(iu), l(iv), l(level)],
            )),
        ],
        vec![],
    ));
    let sample = f.local("sample", Ty::Struct(plan::common::SAMPLE));
    f.body.push(Stmt::Var(
        sample,
        call(
            FnRef::Local(c.eval_domain),
            vec![l(class), l(cp), l(x), l(y), l(z), l(level)],
        ),
    ));
    let scale = let_(
        &mut f,
        "scale",
        Ty::F32,
        fetch(Resource::DisplaceInfo, u(0)),
    );
    let h = f.local("h", Ty::F32);
    f.body.push(Stmt::If(
        bin(BinOp::Ne, l(scale), Expr::F32(0.0)),
        vec![
            Stmt::Let(
                h,
                call(FnRef::Local(c.height), vec![l(face), l(x), l(y), l(z)]),
            ),
            Stmt::AssignField(
                sample,
                0,
                call(
                    FnRef::Local(c.displace),
                    vec![
                        Expr::Field(Box::new(l(sample)), 0),
                        Expr::Field(Box::new(l(sample)), 1),
                        mul(l(scale), l(h)),
                    ],
                ),
            ),
        ],
        vec![],
    ));
    f.body.push(Stmt::Return(l(sample)));
    f
}
