//! The entry points of targets without a hardware tessellator (WGSL), and
//! the compute `patch_main` body, built once as Plan functions
//! ([`Entries::instanced`], [`Entries::compute_patch`]).
//!
//! Every index formula, loop and dispatch of these entries is decided
//! here: which invocation takes which vertex, patch or sample, the strides
//! of `samples`, `patch_levels` and the bucket buffers (`backend::abi`), the
//! GPU-driven bucket compaction (count, plan, scatter) and its indirect
//! arguments. A printer only declares the entry (attributes, builtin
//! parameters, the vertex-output struct) and spells the statements.

use crate::plan::abi::{
    self, BUCKET_CHUNK, BUCKET_DISPATCH_WORDS, BUCKET_DRAW_WORDS, BUCKET_ENTRY_WORDS,
    BUCKET_HEADER_WORDS, BUCKET_SLOTS, INDIRECT_X, PATCH_LEVELS_WORDS, SAMPLE_FLOATS,
    WORKGROUP_SIZE,
};
use crate::plan::common_fn;

mod buckets;
use crate::plan::build::*;
use crate::plan::*;

fn param(name: &'static str) -> Expr {
    Expr::Stage(StageIn::Param(name))
}

fn stage(s: StageIn) -> Expr {
    Expr::Stage(s)
}

fn lt(a: Expr, b: Expr) -> Expr {
    bin(BinOp::Lt, a, b)
}

fn eq(a: Expr, b: Expr) -> Expr {
    bin(BinOp::Eq, a, b)
}

fn shl(a: Expr, b: Expr) -> Expr {
    bin(BinOp::Shl, a, b)
}

fn rem(a: Expr, b: Expr) -> Expr {
    bin(BinOp::Rem, a, b)
}

/// `if cond { return; }`.
fn return_if(cond: Expr) -> Stmt {
    Stmt::If(cond, vec![Stmt::ReturnVoid], vec![])
}

fn fetch_at(r: Resource, base: Expr, k: u32) -> Expr {
    fetch(r, add(base, u(k)))
}

/// `if (class == 0) {…} else if … else {…}` over the scheme's patch
/// classes, the last one unconditional (like `eval`'s dispatch); one class
/// needs no test.
pub fn class_chain(entries: &Entries, body: impl Fn(&PatchEntry) -> Stmt) -> Vec<Stmt> {
    let mut chain: Vec<Stmt> = Vec::new();
    for (c, p) in entries.patches.iter().enumerate().rev() {
        let s = body(p);
        chain = if chain.is_empty() {
            vec![s]
        } else {
            vec![Stmt::If(eq(param("class"), u(c as u32)), vec![s], chain)]
        };
    }
    chain
}

/// `var points = 0; <class chain: points = CONTROL_POINTS>`.
fn points_of_class(f: &mut Function, entries: &Entries) -> (LocalId, Vec<Stmt>) {
    let points = f.local("points", Ty::U32);
    let mut out = vec![Stmt::Var(points, u(0))];
    out.extend(class_chain(entries, |p| {
        Stmt::Assign(points, u(p.control_points))
    }));
    (points, out)
}

/// `samples[o + i] = result.<position|normal>.<x|y|z>`, the 6 floats of a
/// sample ([`SAMPLE_FLOATS`]), the layout the runtime reads back.
fn store_sample(o: LocalId, result: LocalId) -> Vec<Stmt> {
    debug_assert_eq!(SAMPLE_FLOATS, 6);
    (0..SAMPLE_FLOATS)
        .map(|i| {
            Stmt::Store(
                Resource::Samples,
                add(l(o), u(i)),
                Expr::Call(
                    Builtin::Component((i % 3) as u8),
                    vec![Expr::Field(Box::new(l(result)), (i / 3) as usize)],
                ),
            )
        })
        .collect()
}

fn compute(name: &str, doc: &str) -> Function {
    Function::new(name, doc)
}

fn entry(kind: EntryKind, inputs: Vec<StageIn>, body: Function) -> EntryItem {
    EntryItem::Entry(EntryPoint {
        kind,
        inputs,
        body,
        outputs: vec![],
    })
}

const COMPUTE: EntryKind = EntryKind::Compute {
    workgroup_size: WORKGROUP_SIZE,
};

/// The outputs of an instanced vertex entry from its `result` sample and
/// integer domain point: clip position, world position, normal, class,
/// `(iu, iv) / level`.
fn vertex_outputs(result: LocalId, iu: LocalId, iv: LocalId) -> Vec<(StageOut, Expr)> {
    let position = Expr::Field(Box::new(l(result)), 0);
    vec![
        (
            StageOut::Clip,
            Expr::Call(Builtin::Project, vec![position.clone()]),
        ),
        (StageOut::Position, position),
        (StageOut::Normal, Expr::Field(Box::new(l(result)), 1)),
        (StageOut::PatchClass, param("class")),
        (
            StageOut::Uv,
            div(
                Expr::Call(Builtin::Vec2, vec![to_f32(l(iu)), to_f32(l(iv))]),
                to_f32(param("level")),
            ),
        ),
    ]
}

/// The body of `patch_main` (WGSL, GLSL): invocation k builds patch
/// `params.first + k` with its class's patch function, its control points
/// from `params.cp_base + k·points`.
pub fn patch_main(entries: &Entries) -> Function {
    let mut f = compute(
        abi::entry::PATCH_STAGE,
        "Patch stage of the dispatch's class for patches first .. first + count; patch k\n\
         of the dispatch writes its control points from cp_base + k·(points per patch).",
    );
    let k = f.local("k", Ty::U32);
    let p = f.local("p", Ty::U32);
    let face = f.local("face", Ty::U32);
    f.body = vec![
        Stmt::Let(k, stage(StageIn::GlobalId)),
        return_if(bin(BinOp::Ge, l(k), param("count"))),
        Stmt::Let(p, add(param("first"), l(k))),
        Stmt::Let(face, fetch(Resource::PatchFaces, l(p))),
    ];
    f.body.extend(class_chain(entries, |pe| {
        Stmt::Call(
            FnRef::Local(pe.function),
            vec![
                l(face),
                add(param("cp_base"), mul(l(k), u(pe.control_points))),
            ],
        )
    }));
    f
}

/// Every WGSL entry point, in print order.
pub fn instanced(entries: &Entries) -> Vec<EntryItem> {
    let mut out = vec![entry(
        COMPUTE,
        vec![StageIn::GlobalId],
        entries.compute_refine.clone(),
    )];
    out.extend(uniform(entries));
    out.extend(adaptive(entries));
    out.extend(buckets::gpu_driven(entries));
    out
}

/// The sample function of the uniform entries and whether it takes the
/// face: quad schemes evaluate through the displacement step (a no-op, bit
/// for bit, while `displace_info[0] == 0`).
fn uniform_eval(entries: &Entries) -> (usize, bool) {
    match entries.eval_displaced {
        Some(d) => (d, true),
        None => (entries.eval, false),
    }
}

fn uniform(entries: &Entries) -> Vec<EntryItem> {
    let [grid_len, grid_iu, grid_iv] = entries.grid.map(FnRef::Local);
    let mut items = Vec::new();

    let mut f = compute(
        abi::entry::VERTEX_STAGE,
        "Vertex stage for vertices first .. first + count (valence 0: unused vertex).",
    );
    let k = f.local("k", Ty::U32);
    let vertex = f.local("vertex", Ty::U32);
    f.body = vec![
        Stmt::Let(k, stage(StageIn::GlobalId)),
        return_if(bin(BinOp::Ge, l(k), param("count"))),
        Stmt::Let(vertex, add(param("first"), l(k))),
        return_if(eq(fetch(Resource::Valence, l(vertex)), u(0))),
        Stmt::Call(
            FnRef::Local(entries.vertex_stage),
            vec![l(vertex), fetch(Resource::VertexOutOffsets, l(vertex))],
        ),
    ];
    items.push(entry(COMPUTE, vec![StageIn::GlobalId], f));
    items.push(entry(
        COMPUTE,
        vec![StageIn::GlobalId],
        entries.compute_patch.clone(),
    ));

    let mut f = compute(
        abi::entry::EVAL,
        "grid_len(level) samples of each patch of the dispatch, sample s at the domain point\n\
         (grid_iu(s), grid_iv(s)), into samples[(out_base + k)·6 ..]: position xyz, normal xyz.",
    );
    let (k, spp, patch, s, iu, iv) = grid_locals(&mut f);
    f.body = vec![
        Stmt::Let(k, stage(StageIn::GlobalId)),
        Stmt::Let(spp, call(grid_len, vec![param("level")])),
        return_if(bin(BinOp::Ge, l(k), mul(param("count"), l(spp)))),
    ];
    f.body
        .extend(split_sample(k, spp, patch, s, iu, iv, grid_iu, grid_iv));
    let (result, body) = sample_at(&mut f, entries, l(patch), iu, iv);
    f.body.extend(body);
    let out = sample_out(&mut f, add(param("out_base"), l(k)), result);
    f.body.extend(out);
    items.push(entry(COMPUTE, vec![StageIn::GlobalId], f));

    items.push(EntryItem::VertexOutput {
        doc: "Output of the instanced evaluation. `patch_class` is flat with `either` sampling:\n\
              every vertex of a draw has the same class, so any provoking vertex gives it, and\n\
              WebGPU's compatibility mode has no `first` (plain `flat`)."
            .into(),
    });

    let mut f = Function::new(
        "eval_vs",
        "Instanced tessellation: an index buffer over the grid_len(level) grid vertices, shared\n\
         by all patches (vertex index vi = sample vi of grid_iu/grid_iv), one instance per patch of the\n\
         draw's class: instance inst is patch inst of the draw, its control points from\n\
         cp_base + inst·(points per patch). Draw instances 0 .. count.",
    );
    let iu = f.local("iu", Ty::U32);
    let iv = f.local("iv", Ty::U32);
    f.body = vec![
        Stmt::Let(
            iu,
            call(grid_iu, vec![stage(StageIn::VertexIndex), param("level")]),
        ),
        Stmt::Let(
            iv,
            call(grid_iv, vec![stage(StageIn::VertexIndex), param("level")]),
        ),
    ];
    let inst = stage(StageIn::InstanceIndex);
    let (result, body) = sample_at(&mut f, entries, inst, iu, iv);
    f.body.extend(body);
    items.push(EntryItem::Entry(EntryPoint {
        kind: EntryKind::Vertex,
        inputs: vec![StageIn::VertexIndex, StageIn::InstanceIndex],
        body: f,
        outputs: vertex_outputs(result, iu, iv),
    }));

    items.push(shade_fs(entries));
    items
}

/// The sample of patch `index` of the draw at `(iu, iv)`: its class's
/// control-point count, its face where the evaluator takes one, `result`.
fn sample_at(
    f: &mut Function,
    entries: &Entries,
    index: Expr,
    iu: LocalId,
    iv: LocalId,
) -> (LocalId, Vec<Stmt>) {
    let (eval, takes_face) = uniform_eval(entries);
    let (points, mut body) = points_of_class(f, entries);
    let mut args = vec![];
    if takes_face {
        let face = f.local("face", Ty::U32);
        body.push(Stmt::Let(
            face,
            fetch(Resource::PatchFaces, add(param("first"), index.clone())),
        ));
        args.push(l(face));
    }
    args.extend([
        param("class"),
        add(param("cp_base"), mul(index, l(points))),
        l(iu),
        l(iv),
        param("level"),
    ]);
    let result = f.local("result", Ty::Struct(common::SAMPLE));
    body.push(Stmt::Let(result, call(FnRef::Local(eval), args)));
    (result, body)
}

/// `k`, `spp`, `patch_index`, `s`, `iu`, `iv` of an evaluation dispatch.
fn grid_locals(f: &mut Function) -> (LocalId, LocalId, LocalId, LocalId, LocalId, LocalId) {
    (
        f.local("k", Ty::U32),
        f.local("spp", Ty::U32),
        f.local("patch_index", Ty::U32),
        f.local("s", Ty::U32),
        f.local("iu", Ty::U32),
        f.local("iv", Ty::U32),
    )
}

/// Invocation k of an evaluation dispatch is sample `k mod spp` of patch
/// `k / spp` of the dispatch, at `(grid_iu(s), grid_iv(s))`.
#[allow(clippy::too_many_arguments)]
fn split_sample(
    k: LocalId,
    spp: LocalId,
    patch: LocalId,
    s: LocalId,
    iu: LocalId,
    iv: LocalId,
    grid_iu: FnRef,
    grid_iv: FnRef,
) -> Vec<Stmt> {
    vec![
        Stmt::Let(patch, div(l(k), l(spp))),
        Stmt::Let(s, rem(l(k), l(spp))),
        Stmt::Let(iu, call(grid_iu, vec![l(s), param("level")])),
        Stmt::Let(iv, call(grid_iv, vec![l(s), param("level")])),
    ]
}

/// `o = sample · SAMPLE_FLOATS`, then the sample's floats from `o`.
fn sample_out(f: &mut Function, sample: Expr, result: LocalId) -> Vec<Stmt> {
    let o = f.local("o", Ty::U32);
    let mut out = vec![Stmt::Let(o, mul(sample, u(SAMPLE_FLOATS)))];
    out.extend(store_sample(o, result));
    out
}

/// Base colours of the rendering entry point.
const ORDINARY_RGB: [f32; 3] = [1.0, 0.55, 0.1];
const EXTRAORDINARY_RGB: [f32; 3] = [0.2, 0.4, 1.0];
/// `shade_fs` with `FLAG_PLAIN`: every class this grey.
const PLAIN_RGB: [f32; 3] = [0.75, 0.75, 0.72];

fn rgb(c: [f32; 3]) -> Expr {
    Expr::Call(Builtin::Vec3, c.map(f).to_vec())
}

fn shade_fs(entries: &Entries) -> EntryItem {
    let mut fs = Function::new(
        "shade_fs",
        "Two-sided Lambert under a fixed light; ordinary classes orange, the others blue (grey with FLAG_PLAIN).",
    );
    let base = fs.local("base", Ty::Vec3);
    let n = fs.local("n", Ty::Vec3);
    let light = fs.local("light", Ty::Vec3);
    let lambert = fs.local("lambert", Ty::F32);
    let color = fs.local("color", Ty::Vec3);
    let edge = fs.local("edge", Ty::F32);
    let varying = |o: StageOut| stage(StageIn::Varying(o));
    let uv = |c: u8| Expr::Call(Builtin::Component(c), vec![varying(StageOut::Uv)]);
    let min = |a: Expr, b: Expr| Expr::Call(Builtin::Min, vec![a, b]);
    fs.body.push(Stmt::Var(base, rgb(EXTRAORDINARY_RGB)));
    for (k, p) in entries.patches.iter().enumerate() {
        if p.class.name() == "ordinary" {
            fs.body.push(Stmt::If(
                eq(varying(StageOut::PatchClass), u(k as u32)),
                vec![Stmt::Assign(base, rgb(ORDINARY_RGB))],
                vec![],
            ));
        }
    }
    let flag = |bit: u32| bin(BinOp::Ne, bin(BinOp::BitAnd, param("flags"), u(bit)), u(0));
    fs.body.push(Stmt::If(
        flag(crate::plan::abi::FLAG_PLAIN),
        vec![Stmt::Assign(base, rgb(PLAIN_RGB))],
        vec![],
    ));
    fs.body.extend([
        Stmt::Let(
            n,
            call(
                FnRef::Common(common_fn::NORMALIZE),
                vec![varying(StageOut::Normal)],
            ),
        ),
        Stmt::Let(
            light,
            Expr::Call(Builtin::Normalize, vec![rgb([0.3, 0.5, 0.8])]),
        ),
        Stmt::Let(
            lambert,
            Expr::Call(
                Builtin::Abs,
                vec![Expr::Call(Builtin::Dot, vec![l(n), l(light)])],
            ),
        ),
        Stmt::Var(color, mul(l(base), add(f(0.2), mul(f(0.8), l(lambert))))),
        Stmt::Comment(
            "Wireframe overlay of patch boundaries (params.flags & FLAG_WIREFRAME).".into(),
        ),
        Stmt::If(
            flag(crate::plan::abi::FLAG_WIREFRAME),
            vec![
                Stmt::Let(
                    edge,
                    min(
                        min(uv(0), sub(f(1.0), uv(0))),
                        min(uv(1), sub(f(1.0), uv(1))),
                    ),
                ),
                Stmt::If(
                    lt(
                        l(edge),
                        mul(f(1.5), Expr::Call(Builtin::Fwidth, vec![l(edge)])),
                    ),
                    vec![Stmt::Assign(color, mul(l(color), f(0.15)))],
                    vec![],
                ),
            ],
            vec![],
        ),
    ]);
    EntryItem::Entry(EntryPoint {
        kind: EntryKind::Fragment,
        inputs: vec![],
        body: fs,
        outputs: vec![(StageOut::Color, l(color))],
    })
}

/// Word `k` of entry `e` of `bucket_patches`.
fn entry_word(e: LocalId, k: u32) -> Expr {
    if k == 0 {
        fetch(Resource::BucketPatches, l(e))
    } else {
        fetch_at(Resource::BucketPatches, l(e), k)
    }
}

/// From entry offset `e` of `bucket_patches`: `cp`, `face` and the snapped,
/// displaced sample `result` through `eval_adaptive_displaced` with the
/// entry's four edge levels.
fn adaptive_sample(
    f: &mut Function,
    entries: &Entries,
    e: LocalId,
    iu: LocalId,
    iv: LocalId,
) -> (LocalId, Vec<Stmt>) {
    let cp = f.local("cp", Ty::U32);
    let face = f.local("face", Ty::U32);
    let result = f.local("result", Ty::Struct(common::SAMPLE));
    let mut args = vec![l(face), param("class"), l(cp), l(iu), l(iv), param("level")];
    args.extend((2..BUCKET_ENTRY_WORDS).map(|k| entry_word(e, k)));
    let body = vec![
        Stmt::Let(cp, entry_word(e, 1)),
        Stmt::Let(face, fetch(Resource::PatchFaces, entry_word(e, 0))),
        Stmt::Let(
            result,
            call(FnRef::Local(entries.adaptive.eval_displaced), args),
        ),
    ];
    (result, body)
}

/// Adaptive tessellation (quad and triangle schemes): a classify pass
/// writing every patch's edge levels and bucket, then one dispatch
/// (`eval_adaptive_main`) or instanced draw (`eval_adaptive_vs`) per
/// (class, bucket) over the bucket's entries in `bucket_patches`. The
/// semantics are the Plan's `patch_edge_level`, `tessgen_bucket_level` and
/// `eval_adaptive`; these entries only index buffers.
fn adaptive(entries: &Entries) -> Vec<EntryItem> {
    let a = entries.adaptive;
    let [grid_len, grid_iu, grid_iv] = entries.grid.map(FnRef::Local);
    let mut items = Vec::new();

    let mut f = compute(
        "adaptive_classify_main",
        "Adaptive classify: for patches first .. first + count of the dispatch's class, the\n\
         power-of-two level of each edge (patch_edge_level, largest level = params.level) and the\n\
         patch's bucket into patch_levels[5p ..] (p = first + k, the class-sorted patch index).",
    );
    let k = f.local("k", Ty::U32);
    let p = f.local("p", Ty::U32);
    let face = f.local("face", Ty::U32);
    f.body = vec![
        Stmt::Let(k, stage(StageIn::GlobalId)),
        return_if(bin(BinOp::Ge, l(k), param("count"))),
        Stmt::Let(p, add(param("first"), l(k))),
        Stmt::Let(face, fetch(Resource::PatchFaces, l(p))),
    ];
    let (points, chain) = points_of_class(&mut f, entries);
    f.body.extend(chain);
    let cp = f.local("cp", Ty::U32);
    f.body
        .push(Stmt::Let(cp, add(param("cp_base"), mul(l(k), l(points)))));
    let levels: Vec<LocalId> = (0..4).map(|e| f.local(format!("l{e}"), Ty::U32)).collect();
    for (e, le) in levels.iter().enumerate() {
        f.body.push(Stmt::Let(
            *le,
            call(
                FnRef::Local(a.edge_level),
                vec![l(face), param("class"), l(cp), u(e as u32), param("level")],
            ),
        ));
    }
    let record = || mul(u(PATCH_LEVELS_WORDS), l(p));
    for (e, le) in levels.iter().enumerate() {
        f.body.push(Stmt::Store(
            Resource::PatchLevels,
            add(record(), u(e as u32)),
            l(*le),
        ));
    }
    f.body.push(Stmt::Store(
        Resource::PatchLevels,
        add(record(), u(4)),
        call(
            FnRef::Common(common_fn::BUCKET_LEVEL),
            levels.iter().map(|x| l(*x)).collect(),
        ),
    ));
    items.push(entry(COMPUTE, vec![StageIn::GlobalId], f));

    let mut f = compute(
        "eval_adaptive_main",
        "One bucket of one class at its level params.level: grid_len(level) samples of each of\n\
         the entries first .. first + count of bucket_patches, snapped and displaced by\n\
         eval_adaptive_displaced (displacement off: eval_adaptive bit for bit), into\n\
         samples[(out_base + k)·6 ..]: position xyz, normal xyz.",
    );
    let (k, spp, patch, s, iu, iv) = grid_locals(&mut f);
    f.body = vec![
        Stmt::Let(k, stage(StageIn::GlobalId)),
        Stmt::Let(spp, call(grid_len, vec![param("level")])),
        return_if(bin(BinOp::Ge, l(k), mul(param("count"), l(spp)))),
    ];
    f.body
        .extend(split_sample(k, spp, patch, s, iu, iv, grid_iu, grid_iv));
    let e = f.local("e", Ty::U32);
    f.body.push(Stmt::Let(
        e,
        mul(u(BUCKET_ENTRY_WORDS), add(param("first"), l(patch))),
    ));
    let (result, body) = adaptive_sample(&mut f, entries, e, iu, iv);
    f.body.extend(body);
    let out = sample_out(&mut f, add(param("out_base"), l(k)), result);
    f.body.extend(out);
    items.push(entry(COMPUTE, vec![StageIn::GlobalId], f));

    let mut f = Function::new(
        "eval_adaptive_vs",
        "Instanced adaptive draw of one bucket of one class: the level-params.level grid index\n\
         buffer, instance inst = entry first + inst of bucket_patches, through eval_adaptive_displaced.",
    );
    let (iu, iv, e) = vs_head(&mut f, grid_iu, grid_iv);
    f.body.push(Stmt::Let(
        e,
        mul(
            u(BUCKET_ENTRY_WORDS),
            add(param("first"), stage(StageIn::InstanceIndex)),
        ),
    ));
    items.push(adaptive_vs(f, entries, iu, iv, e));
    items
}

/// `iu`, `iv` of vertex `vi` of the level's grid, and the entry offset `e`
/// (declared, not yet bound).
fn vs_head(f: &mut Function, grid_iu: FnRef, grid_iv: FnRef) -> (LocalId, LocalId, LocalId) {
    let iu = f.local("iu", Ty::U32);
    let iv = f.local("iv", Ty::U32);
    let e = f.local("e", Ty::U32);
    f.body.push(Stmt::Let(
        iu,
        call(grid_iu, vec![stage(StageIn::VertexIndex), param("level")]),
    ));
    f.body.push(Stmt::Let(
        iv,
        call(grid_iv, vec![stage(StageIn::VertexIndex), param("level")]),
    ));
    (iu, iv, e)
}

/// The rest of an adaptive vertex entry after `iu`, `iv` and the entry
/// offset `e`: the snapped, displaced sample and the outputs of `eval_vs`.
fn adaptive_vs(
    mut f: Function,
    entries: &Entries,
    iu: LocalId,
    iv: LocalId,
    e: LocalId,
) -> EntryItem {
    let (result, body) = adaptive_sample(&mut f, entries, e, iu, iv);
    f.body.extend(body);
    EntryItem::Entry(EntryPoint {
        kind: EntryKind::Vertex,
        inputs: vec![StageIn::VertexIndex, StageIn::InstanceIndex],
        body: f,
        outputs: vertex_outputs(result, iu, iv),
    })
}

/// How a packed accessor forms the float offsets of element `i`: bound
/// once to a local (`let o = 3·i`, the WGSL helpers) or spelled in every
/// index (`3·i`, `3·i + 1`, …; the GLSL and HLSL helpers). The same floats;
/// two forms because the emitted text of both targets is kept as it was.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Offsets {
    Bound,
    Inline,
}

/// The offsets of the three floats of element `i`, and the statements
/// that bind them.
fn packed_offsets(f: &mut Function, i: LocalId, offsets: Offsets) -> (Vec<Stmt>, [Expr; 3]) {
    let base = mul(u(3), l(i));
    let (pre, base) = match offsets {
        Offsets::Bound => {
            let o = f.local("o", Ty::U32);
            (vec![Stmt::Let(o, base)], l(o))
        }
        Offsets::Inline => (vec![], base),
    };
    let at = [base.clone(), add(base.clone(), u(1)), add(base, u(2))];
    (pre, at)
}

/// `name(i) -> vec3`: element `i` of the packed `vec3` resource `r`, the
/// floats `3i .. 3i + 2` (`abi`: packed triples, 12 bytes per point).
pub fn packed_load(r: Resource, name: &str, doc: &str, offsets: Offsets) -> Function {
    let mut f = Function::new(name, doc);
    let i = f.param("i", Ty::U32);
    f.ret = Some(Ty::Vec3);
    let (mut body, at) = packed_offsets(&mut f, i, offsets);
    body.push(Stmt::Return(Expr::Call(
        Builtin::Vec3,
        at.map(|k| Expr::Float(r, Box::new(k))).to_vec(),
    )));
    f.body = body;
    f
}

/// `name(i, v)`: element `i` of the packed `vec3` resource `r` = `v`.
pub fn packed_store(r: Resource, name: &str, doc: &str, offsets: Offsets) -> Function {
    let mut f = Function::new(name, doc);
    let i = f.param("i", Ty::U32);
    let v = f.param("v", Ty::Vec3);
    let (mut body, at) = packed_offsets(&mut f, i, offsets);
    for (c, k) in at.into_iter().enumerate() {
        body.push(Stmt::StoreFloat(
            r,
            k,
            Expr::Call(Builtin::Component(c as u8), vec![l(v)]),
        ));
    }
    f.body = body;
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::wgsl::{ADAPTIVE_ENTRY_POINTS, ENTRY_POINTS};
    use crate::{builtin_schemes, StencilTable};

    fn plan() -> Plan {
        let schemes: Vec<crate::Scheme> = builtin_schemes()
            .iter()
            .map(|s| s.compile(5).expect("built-in scheme"))
            .collect();
        let table = StencilTable::build(&schemes, 5);
        crate::lower::plan(&schemes, &table)
    }

    /// The entry-point list the WGSL printer publishes (and the runtime
    /// and `validate_wgsl` rely on) is the Plan's, in order, with the
    /// Plan's stages.
    #[test]
    fn published_entry_points_are_the_plans() {
        let published: Vec<(&str, &str)> = ENTRY_POINTS
            .iter()
            .chain(ADAPTIVE_ENTRY_POINTS)
            .copied()
            .collect();
        for (module, entries) in &plan().schemes {
            let planned: Vec<(&str, &str)> = entries
                .instanced
                .iter()
                .filter_map(|i| match i {
                    EntryItem::Entry(e) => Some((
                        e.body.name.as_str(),
                        match e.kind {
                            EntryKind::Compute { .. } => "compute",
                            EntryKind::Vertex => "vertex",
                            EntryKind::Fragment => "fragment",
                        },
                    )),
                    _ => None,
                })
                .collect();
            assert_eq!(planned, published, "scheme {}", module.name);
        }
    }

    /// Every builtin input an entry body reads is one it declares, so the
    /// printers' parameter lists are complete.
    #[test]
    fn entry_inputs_are_declared() {
        for (_, entries) in &plan().schemes {
            for item in &entries.instanced {
                let EntryItem::Entry(e) = item else { continue };
                let mut used = Vec::new();
                let mut note = |n: Node| {
                    if let Node::Expr(Expr::Stage(s)) = n {
                        used.push(*s);
                    }
                };
                walk(&e.body.body, &mut note);
                for (_, x) in &e.outputs {
                    walk_expr(x, &mut note);
                }
                for s in used {
                    let declared = match s {
                        StageIn::Param(_) => true,
                        StageIn::GlobalIdY => e.inputs.contains(&StageIn::GlobalId),
                        StageIn::Varying(_) => e.kind == EntryKind::Fragment,
                        s => e.inputs.contains(&s),
                    };
                    assert!(declared, "{}: {s:?} not declared", e.body.name);
                }
            }
        }
    }

    /// The two forms of the packed accessors address the same floats.
    #[test]
    fn packed_accessor_forms_agree() {
        for offsets in [Offsets::Bound, Offsets::Inline] {
            let f = packed_load(Resource::Positions, "load", "", offsets);
            assert_eq!(f.resources(), vec![(Resource::Positions, false)]);
            let f = packed_store(Resource::VertexOut, "store", "", offsets);
            assert_eq!(f.resources(), vec![(Resource::VertexOut, true)]);
        }
    }
}
