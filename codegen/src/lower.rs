//! Lowering: Scheme IR → Plan.
//!
//! All operation order is decided here, once, for every backend:
//! * the vertex stage sums ring slots 0, 1, …, 2n in ring order with the f32
//!   table weights, skipping exact zeros (DESIGN.md Rule 1);
//! * the patch stage unrolls the scheme's per-corner definitions in source
//!   order, folding number arithmetic in f64 before it becomes an f32 literal;
//! * evaluation forms every weight pair from integer tessellation
//!   coordinates and evaluates shared boundaries through one edge evaluator
//!   (symmetric de Casteljau; `spec/watertight.md` Rule 2).

use crate::form::Form;
use crate::plan::build::*;
use crate::plan::{self, *};
use crate::scheme::{self, Class, Scheme, CORNER_VAR};
use crate::sym::{self, Sym};
use crate::table::{SchemeRows, StencilTable};
use std::collections::BTreeMap;

/// Indices of the common module's functions.
pub mod common_fn {
    pub const NORMALIZE: usize = 0;
    pub const CUBIC: usize = 1;
    pub const EDGE: usize = 2;
    pub const EDGE_FACTOR: usize = 3;
    /// `tessgen_edge_factor_runtime`: the metric chosen at run time.
    pub const EDGE_FACTOR_RUNTIME: usize = 4;
    /// `tessgen_edge_level`: power-of-two edge level of a factor.
    pub const EDGE_LEVEL: usize = 5;
    /// `tessgen_bucket_level`: a patch's bucket, the largest edge level.
    pub const BUCKET_LEVEL: usize = 6;
}

/// Name of the adaptive per-edge tessellation factor.
pub const EDGE_FACTOR_FN: &str = "tessgen_edge_factor";

/// Name of the adaptive per-edge factor with the metric chosen at run time.
pub const EDGE_FACTOR_RUNTIME_FN: &str = "tessgen_edge_factor_runtime";

/// Fixed-point denominator of the adaptive evaluation: the hardware
/// tessellator's domain coordinates are 16.16 fixed point, so `m / 2^16`
/// is exact in f32 and `2^16 − m` is the neighbour's coordinate.
pub const ADAPTIVE_LEVEL: u32 = 1 << 16;

/// Which patch edges feed a hardware tessellator's factors in adaptive
/// builds: `(outer, inner)`, `outer[s]` the edge (k: `v_k → v_{k+1}`) whose
/// factor goes to outer factor slot `s`, `inner[s]` the edges whose largest
/// factor is inside factor `s`.
///
/// Conventions (Vulkan and D3D alike): a triangle domain's outer slot `s` is
/// the edge where barycentric coordinate `s` is 0 — with `(x, y, z)`
/// weighing corners 0, 1, 2 that is edge 1 (`x = 0`), edge 2 (`y = 0`),
/// edge 0 (`z = 0`) — and its one inside factor is the largest of the three
/// edges. A quad domain's outer slots are the edges `a = 0, b = 0, a = 1,
/// b = 1` of its coordinates `(a, b)`, and inside factor 0 subdivides along
/// `a` (the edges `b = 0`, `b = 1`). HLSL takes `(u, v) = (a, b)`
/// (`first_is_u`), GLSL `(u, v) = (b, a)` (the axis swap that keeps the
/// winding counter-clockwise); our edges are 0: `v = 0`, 1: `u = 1`,
/// 2: `v = 1`, 3: `u = 0`. Every factor depends on its edge alone (Rule 3),
/// the inside ones only on the patch's own edges.
pub fn hw_factor_edges(sides: u32, first_is_u: bool) -> (Vec<usize>, Vec<Vec<usize>>) {
    if sides == 3 {
        return (vec![1, 2, 0], vec![vec![0, 1, 2]]);
    }
    let outer = if first_is_u {
        vec![3, 0, 1, 2]
    } else {
        vec![0, 3, 2, 1]
    };
    let sorted = |mut v: Vec<usize>| {
        v.sort_unstable();
        v
    };
    let inner = vec![
        sorted(vec![outer[1], outer[3]]),
        sorted(vec![outer[0], outer[2]]),
    ];
    (outer, inner)
}

/// Name of the single shared edge evaluator.
pub const EDGE_FN: &str = "tessgen_edge";

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
        "Columns of the stencil table (2·MAX_VALENCE + 1 ring slots).",
        ConstValue::U32(table.width),
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
    let mut f = Function::new(
        EDGE_FN,
        "Point `i/level` along the cubic boundary curve `b0..b3`. The two patches of an edge \
         call this with reversed points and `level - i`; both weights come from integers, so \
         every lerp is `x·l + y·r` on one side and `y·r + x·l` on the other: the same bits. \
         Corners return the corner point itself.",
    );
    f.precise = true;
    let b: Vec<LocalId> = (0..4).map(|i| f.param(format!("b{i}"), Ty::Vec3)).collect();
    let i = f.param("i", Ty::U32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::Vec3);
    let wl = f.local("l", Ty::F32);
    let wr = f.local("r", Ty::F32);
    // The lerps are written out here rather than calling tessgen_cubic, so
    // that `precise` on this function covers every operation of the path.
    let c: Vec<LocalId> = (0..3).map(|k| f.local(format!("c{k}"), Ty::Vec3)).collect();
    let d: Vec<LocalId> = (0..2).map(|k| f.local(format!("d{k}"), Ty::Vec3)).collect();
    f.body = vec![
        Stmt::If(
            bin(BinOp::Eq, l(i), u(0)),
            vec![Stmt::Return(l(b[0]))],
            vec![],
        ),
        Stmt::If(
            bin(BinOp::Eq, l(i), l(level)),
            vec![Stmt::Return(l(b[3]))],
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
    for k in 0..3 {
        f.body
            .push(Stmt::Let(c[k], lerp(l(b[k]), l(b[k + 1]), wl, wr)));
    }
    for k in 0..2 {
        f.body
            .push(Stmt::Let(d[k], lerp(l(c[k]), l(c[k + 1]), wl, wr)));
    }
    f.body.push(Stmt::Return(lerp(l(d[0]), l(d[1]), wl, wr)));
    m.functions.push(f);
    m.functions.push(edge_factor_fn(false));
    m.functions.push(edge_factor_fn(true));
    m.functions.push(crate::adaptive::edge_level_fn());
    m.functions.push(crate::adaptive::bucket_level_fn());
    m
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
fn edge_factor_fn(runtime: bool) -> Function {
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
            let metric = || fetch(Resource::Adaptive, u(crate::adaptive::METRIC_SLOT));
            Stmt::If(
                bin(BinOp::Eq, metric(), f32c(crate::adaptive::METRIC_BUFFER)),
                vec![Stmt::Assign(fac, fetch(Resource::EdgeFactors, l(edge)))],
                vec![Stmt::If(
                    bin(BinOp::Eq, metric(), f32c(crate::adaptive::METRIC_DISTANCE)),
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

fn f32c(x: f64) -> Expr {
    Expr::F32(x as f32)
}

/// Lower one scheme to its module.
pub fn scheme_module(s: &Scheme, rows: &SchemeRows) -> (Module, Entries) {
    let mut m = Module {
        name: s.name.clone(),
        doc: s.doc.clone(),
        ..Default::default()
    };
    let row_base = m.add_const(
        "ROW_BASE",
        "First stencil-table row of each valence's vertex-stage block (index = valence).",
        ConstValue::U32Array(rows.valence_row_base.clone()),
    );
    let const_row = m.add_const(
        "CONST_ROW_BASE",
        "Stencil-table row of valence 3's per-valence constants; valence n is row CONST_ROW_BASE + n - 3.",
        ConstValue::U32(rows.const_row_base),
    );
    let (ra, rb) = s.rows_linear();
    m.add_const(
        "ROWS_PER_N",
        "Vertex-stage outputs per vertex: ROWS_PER_N·n + ROWS_FIXED.",
        ConstValue::U32(ra),
    );
    m.add_const("ROWS_FIXED", "See ROWS_PER_N.", ConstValue::U32(rb));

    let vertex_stage = m.functions.len();
    m.functions.push(vertex_stage_fn(s, row_base, ra, rb));

    let mut patches = Vec::new();
    for pc in &s.patches {
        let idx = m.functions.len();
        m.functions.push(patch_fn(s, pc, const_row));
        patches.push(PatchEntry {
            class: pc.class,
            form: pc.form,
            control_points: pc.form.num_points() as u32,
            function: idx,
        });
    }
    // Boundary curves of every class, flattened: [class][edge][4].
    let mut curves = Vec::new();
    for pe in &patches {
        for e in 0..pe.form.sides() {
            curves.extend(pe.form.edge_curve(e).iter().map(|&x| x as u32));
        }
    }
    let curve_const = m.add_const(
        "EDGE_CURVE",
        "Control-point indices of each class's cubic boundary curves: [class][edge][4], edge k runs v_k → v_{k+1}.",
        ConstValue::U32Array(curves),
    );
    let mut surfaces = Vec::new();
    // Triangle forms: the surface at float barycentric weights, per class.
    let mut surfaces_at = Vec::new();
    for pe in &patches {
        let f = match pe.form {
            Form::Bicubic => bicubic_surface(pe.class),
            Form::CPatch => cpatch_surface(pe.class),
            Form::Acc => acc_surface(pe.class),
            Form::Gregory => gregory_surface(pe.class),
            Form::TriCubic => {
                let at = m.functions.len();
                m.functions.push(tri_cubic_surface_at(pe.class));
                surfaces_at.push(at);
                tri_cubic_surface(pe.class, at)
            }
        };
        surfaces.push(m.functions.len());
        m.functions.push(f);
    }
    let sides = s.facet.sides() as u32;
    let eval = m.functions.len();
    m.functions
        .push(eval_fn(&patches, &surfaces, curve_const, sides));
    let eval_domain = if sides == 3 && surfaces_at.len() == patches.len() {
        m.functions.push(eval_domain_fn(eval, &surfaces_at));
        Some(m.functions.len() - 1)
    } else {
        None
    };
    let grid = [
        m.functions.len(),
        m.functions.len() + 1,
        m.functions.len() + 2,
    ];
    m.functions.extend(grid_fns(sides));
    let grid_index = m.functions.len();
    m.functions.push(grid_index_fn(sides));
    // The displacement step (16 texture coordinates per quad patch, 12 per
    // triangle).
    let eval_displaced = {
        let height = m.functions.len();
        m.functions.push(crate::displace::height_fn());
        let texcoord = m.functions.len();
        m.functions
            .push(crate::displace::texcoord_fn(height, sides));
        let displace = m.functions.len();
        m.functions.push(crate::displace::displace_point_fn());
        let idx = m.functions.len();
        m.functions.push(crate::displace::eval_displaced_fn(
            &crate::displace::Callees {
                eval,
                owner_eval: eval,
                texcoord,
                displace,
            },
            sides,
        ));
        (idx, texcoord, displace, height)
    };
    // Adaptive tessellation on the instanced path (quad and triangle
    // schemes: the same signatures, the domain's snap inside).
    let adaptive = {
        let (_, texcoord, displace, _) = eval_displaced;
        let edge_level = m.functions.len();
        m.functions
            .push(crate::adaptive::patch_edge_level_fn(curve_const, sides));
        let eval_a = m.functions.len();
        m.functions
            .push(crate::adaptive::eval_adaptive_fn(eval, sides));
        let eval_ad = m.functions.len();
        m.functions
            .push(crate::adaptive::eval_adaptive_displaced_fn(
                crate::displace::Callees {
                    eval,
                    owner_eval: eval,
                    texcoord,
                    displace,
                },
                sides,
            ));
        AdaptiveEntries {
            edge_level,
            eval: eval_a,
            eval_displaced: eval_ad,
        }
    };
    // Triangles: the displacement step at the tessellator's float domain
    // point (integer path on the boundary, raw point inside); the CPU's
    // copy calls `eval_displaced` (the parity reference of the captures).
    let domain_displaced = eval_domain.map(|ed| {
        let (idx, _, displace, height_fn) = eval_displaced;
        let height = m.functions.len();
        m.functions
            .push(crate::displace::height_at_domain_fn(height_fn));
        let f = m.functions.len();
        m.functions.push(crate::displace::eval_domain_displaced_fn(
            &crate::displace::DomainCallees {
                boundary: idx,
                eval_domain: ed,
                height,
                displace,
            },
            "eval_domain_displaced",
            "eval_domain with the displacement step (watertight.md Rules 4 and 5): on the patch \
             boundary (a coordinate exactly 0) eval_displaced at the integer grid point \
             (round(y·level), round(z·level)), the owner's normal and texture coordinate like \
             every other patch of the edge; inside, the raw point displaced along its own normal \
             by the height at its interior texture coordinate (tessgen_height_at_domain).",
        ));
        (f, ed, height, displace)
    });
    // The tessellation stages' variant: own sample from the patch-local
    // control points, the owner's from the global buffer.
    let tess_displaced = {
        let (own_displaced, texcoord, displace, _) = eval_displaced;
        let start = m.functions.len();
        // `eval_displaced` on the global buffer, with `eval_global` and the
        // surface copies under it.
        let globals = crate::displace::global_variants(&mut m, own_displaced);
        let owner_eval = crate::displace::global_of(&globals, eval);
        let compute_eval = crate::displace::global_of(&globals, own_displaced);
        let idx = m.functions.len();
        m.functions.push(crate::displace::eval_displaced_tess_fn(
            &crate::displace::Callees {
                eval,
                owner_eval,
                texcoord,
                displace,
            },
            sides,
        ));
        let domain = domain_displaced.map(|(_, ed, height, displace)| {
            m.functions.push(crate::displace::eval_domain_displaced_fn(
                &crate::displace::DomainCallees {
                    boundary: idx,
                    eval_domain: ed,
                    height,
                    displace,
                },
                "eval_domain_displaced_tess",
                "eval_domain_displaced for the tessellation evaluation stage: the boundary through \
                 eval_displaced_tess (own sample from the patch-local control points, the owner's \
                 normal from the global control-point buffer), the interior displaced along its \
                 own normal.",
            ));
            m.functions.len() - 1
        });
        Some(TessDisplaced {
            eval_displaced: idx,
            eval_domain: domain,
            eval_displaced_global: compute_eval,
            functions: start..m.functions.len(),
        })
    };
    let eval_domain_displaced = domain_displaced.map(|d| d.0);
    let eval_displaced = Some(eval_displaced.0);
    let mut entries = Entries {
        vertex_stage,
        patches,
        eval,
        eval_domain,
        eval_displaced,
        eval_domain_displaced,
        tess_displaced,
        sides,
        grid,
        grid_index,
        adaptive,
        tess: TessStages {
            control: Function::new("", ""),
            evaluation: Function::new("", ""),
            store_cp: Function::new("", ""),
            load_cp: Function::new("", ""),
            points: 0,
            slots: 0,
        },
        compute_vertex: Function::new("", ""),
        compute_eval: Function::new("", ""),
        compute_patch: Function::new("", ""),
        instanced: Vec::new(),
    };
    // The hardware tessellation stages' bodies call the functions above.
    entries.tess = crate::tess::stages(&entries, curve_const);
    entries.compute_vertex = crate::tess::compute_vertex(&entries);
    entries.compute_eval = crate::tess::compute_eval(&entries);
    entries.compute_patch = crate::entries::patch_main(&entries);
    entries.instanced = crate::entries::instanced(&entries);
    (m, entries)
}

/// `grid_index(iu, iv, level)`, the inverse of `grid_iu`/`grid_iv` (see
/// [`Entries::grid_index`]).
fn grid_index_fn(sides: u32) -> Function {
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
fn grid_fns(sides: u32) -> Vec<Function> {
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

/// Cubic Bézier triangle + quadratic normal field (pn.md §2) at integer
/// barycentric coordinates `(level − iu − iv, iu, iv)` of corners 0, 1, 2:
/// the weights are formed from the integers here, then the float-weight
/// surface ([`tri_cubic_surface_at`]) does the arithmetic, so the grid path
/// and the tessellator's interior path share one operation order.
fn tri_cubic_surface(class: Class, at: usize) -> Function {
    let mut f = Function::new(
        format!("{}_surface", class.name()),
        "Cubic Bézier triangle at barycentric (level − iu − iv, iu, iv)/level of corners 0, 1, 2 \
         (weights formed from integers), evaluated by the float-weight surface.",
    );
    let (cp, iu, iv, level) = surface_params(&mut f);
    let nf = let_f32(&mut f, "nf", to_f32(l(level)));
    let w = [
        let_f32(
            &mut f,
            "w0",
            div(to_f32(sub(sub(l(level), l(iu)), l(iv))), l(nf)),
        ),
        let_f32(&mut f, "w1", div(to_f32(l(iu)), l(nf))),
        let_f32(&mut f, "w2", div(to_f32(l(iv)), l(nf))),
    ];
    f.body.push(Stmt::Return(call(
        FnRef::Local(at),
        vec![l(cp), l(w[0]), l(w[1]), l(w[2])],
    )));
    f
}

/// Cubic Bézier triangle + quadratic normal field (pn.md §2) at float
/// barycentric weights `(w0, w1, w2)` of corners 0, 1, 2: the integer grid
/// path calls it with weights formed from integers, the tessellation
/// evaluation stages with the hardware's raw domain point inside the patch.
fn tri_cubic_surface_at(class: Class) -> Function {
    let mut f = Function::new(
        format!("{}_surface_at", class.name()),
        "Cubic Bézier triangle at barycentric weights (w0, w1, w2) of corners 0, 1, 2: three de \
         Casteljau steps over the 10-point net; normal = normalize(Σ n_i w_i² + Σ nm_i w_i \
         w_{i+1}), the factor-free quadratic normal field of pn.md §2.",
    );
    let cp = f.param("cp_base", Ty::U32);
    let w = [
        f.param("w0", Ty::F32),
        f.param("w1", Ty::F32),
        f.param("w2", Ty::F32),
    ];
    f.ret = Some(Ty::Struct(plan::common::SAMPLE));
    let g = Form::TriCubic;
    // Net b[(e0, e1, e2)] with exponents of (w0, w1, w2) summing to 3.
    let mut net: BTreeMap<[u32; 3], LocalId> = BTreeMap::new();
    for c in 0..3usize {
        let (next, prev) = ((c + 1) % 3, (c + 2) % 3);
        let mut corner = [0u32; 3];
        corner[c] = 3;
        let mut toward_next = [0u32; 3];
        toward_next[c] = 2;
        toward_next[next] = 1;
        let mut toward_prev = [0u32; 3];
        toward_prev[c] = 2;
        toward_prev[prev] = 1;
        for (key, slot, name) in [
            (corner, 0, "b"),
            (toward_next, 1, "bn"),
            (toward_prev, 2, "bp"),
        ] {
            let id = let_vec(
                &mut f,
                &format!("{name}{c}"),
                cp_at(cp, g.storage_index(c, slot)),
            );
            net.insert(key, id);
        }
    }
    let centre = let_vec(&mut f, "center", cp_at(cp, g.single_index(0)));
    net.insert([1, 1, 1], centre);
    let mut cur = net;
    for deg in [2u32, 1, 0] {
        let mut next = BTreeMap::new();
        for a in (0..=deg).rev() {
            for b in (0..=deg - a).rev() {
                let c = deg - a - b;
                let e = add(
                    add(
                        mul(l(cur[&[a + 1, b, c]]), l(w[0])),
                        mul(l(cur[&[a, b + 1, c]]), l(w[1])),
                    ),
                    mul(l(cur[&[a, b, c + 1]]), l(w[2])),
                );
                let id = let_vec(&mut f, &format!("s{deg}_{a}{b}{c}"), e);
                next.insert([a, b, c], id);
            }
        }
        cur = next;
    }
    let pos = l(cur[&[0, 0, 0]]);
    // Normal field: n_i w_i² + nm_i w_i w_{i+1}.
    let mut terms = Vec::new();
    for c in 0..3usize {
        let next = (c + 1) % 3;
        terms.push(mul(cp_at(cp, g.storage_index(c, 3)), mul(l(w[c]), l(w[c]))));
        terms.push(mul(
            cp_at(cp, g.storage_index(c, 4)),
            mul(l(w[c]), l(w[next])),
        ));
    }
    let nsum = terms.into_iter().reduce(add).expect("six terms");
    let normal = call(FnRef::Common(common_fn::NORMALIZE), vec![nsum]);
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::SAMPLE,
        vec![pos, normal],
    )));
    f
}

fn vertex_stage_fn(s: &Scheme, row_base: usize, ra: u32, rb: u32) -> Function {
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

/// Per-corner values loaded once at the top of a patch function.
struct CornerLocals {
    /// Corner vertex (every facet).
    vertex: Vec<LocalId>,
    /// Valence, sector and vertex-stage output base (quad schemes only).
    n: Vec<LocalId>,
    sector: Vec<LocalId>,
    out_base: Vec<LocalId>,
}

/// Lowering state of one patch function.
struct PatchLower<'a> {
    s: &'a Scheme,
    f: Function,
    /// The `face` parameter.
    face: LocalId,
    corners: CornerLocals,
    /// Corners of the facet.
    sides: usize,
    /// `(input, corner)` → local (triangle schemes: `P(i)`, `N(i)`).
    inputs: BTreeMap<(sym::Input, usize), LocalId>,
    const_row: usize,
    /// `(const, corner)` → local.
    consts: BTreeMap<(usize, usize), LocalId>,
    valences: BTreeMap<usize, LocalId>,
    /// `(output, corner, offset)` → local.
    data: BTreeMap<(usize, usize, i64), LocalId>,
    /// `(def, corner or None)` → local.
    defs: BTreeMap<(usize, Option<usize>), LocalId>,
    /// Statements loading corner data and constants, emitted before the body.
    loads: Vec<Stmt>,
    body: Vec<Stmt>,
}

/// A lowered value: a number still foldable in f64, or an expression.
enum Val {
    Num(f64),
    Ex(Expr, bool),
}

impl Val {
    fn expr(self) -> Expr {
        match self {
            Val::Num(x) => f32c(x),
            Val::Ex(e, _) => e,
        }
    }
}

fn corner_of(s: &Sym, sides: usize) -> usize {
    match s {
        Sym::Num(x) => (*x as i64).rem_euclid(sides as i64) as usize,
        other => panic!("corner index did not fold to a number: {other:?}"),
    }
}

fn int_of(s: &Sym) -> i64 {
    match s {
        Sym::Num(x) => *x as i64,
        other => panic!("index did not fold to a number: {other:?}"),
    }
}

impl PatchLower<'_> {
    fn corner_const(&mut self, k: usize, c: usize) -> LocalId {
        if let Some(id) = self.consts.get(&(k, c)) {
            return *id;
        }
        let id = self
            .f
            .local(format!("{}_{c}", self.s.consts[k].name), Ty::F32);
        let row = sub(add(Expr::Const(self.const_row), l(self.corners.n[c])), u(3));
        self.loads.push(Stmt::Let(
            id,
            Expr::TableWeight(Box::new(row), Box::new(u(k as u32))),
        ));
        self.consts.insert((k, c), id);
        id
    }

    fn valence(&mut self, c: usize) -> LocalId {
        if let Some(id) = self.valences.get(&c) {
            return *id;
        }
        let id = self.f.local(format!("nf_{c}"), Ty::F32);
        self.loads.push(Stmt::Let(id, to_f32(l(self.corners.n[c]))));
        self.valences.insert(c, id);
        id
    }

    fn datum(&mut self, output: usize, c: usize, offset: Option<i64>) -> LocalId {
        let key = (output, c, offset.unwrap_or(i64::MIN));
        if let Some(id) = self.data.get(&key) {
            return *id;
        }
        let def = &self.s.vertex[output];
        let name = match offset {
            Some(o) if o >= 0 => format!("{}_{c}_{o}", def.name),
            Some(o) => format!("{}_{c}_m{}", def.name, -o),
            None => format!("{}_{c}", def.name),
        };
        let id = self.f.local(name, Ty::Vec3);
        let (a, b) = self.s.output_offset(output);
        let n = self.corners.n[c];
        // out_base + a·n + b (+ (sector + offset) mod n for families)
        let mut idx = add(l(self.corners.out_base[c]), add(mul(u(a), l(n)), u(b)));
        if let Some(o) = offset {
            let o = o.rem_euclid(1 << 20) as u32; // offsets are small; keep the sum non-negative
            let sector = if o == 0 {
                l(self.corners.sector[c])
            } else {
                bin(BinOp::Rem, add(l(self.corners.sector[c]), u(o)), l(n))
            };
            idx = add(idx, sector);
        }
        self.loads
            .push(Stmt::Let(id, fetch(Resource::VertexOut, idx)));
        self.data.insert(key, id);
        id
    }

    /// Corner `c`'s position or normal, loaded once.
    fn input(&mut self, input: sym::Input, c: usize) -> LocalId {
        if let Some(id) = self.inputs.get(&(input, c)) {
            return *id;
        }
        let vertex = l(self.corners.vertex[c]);
        // Scalar tags sit in one flat f32 array, TAGS_PER_VERTEX per vertex
        // (tension, sharpness, bias, creased); the side sign is per
        // triangle corner, at 3·face + corner like `corner_vertex`.
        let tag = |k: u32| fetch(Resource::Tags, add(mul(vertex.clone(), u(4)), u(k)));
        let (name, ty, value) = match input {
            sym::Input::Position => ("pos", Ty::Vec3, fetch(Resource::Positions, vertex.clone())),
            sym::Input::Normal => ("nrm", Ty::Vec3, fetch(Resource::Normals, vertex.clone())),
            sym::Input::Crease => ("crease", Ty::Vec3, fetch(Resource::Crease, vertex.clone())),
            sym::Input::Tension => ("tension", Ty::F32, tag(0)),
            sym::Input::Sharpness => ("sharpness", Ty::F32, tag(1)),
            sym::Input::Bias => ("bias", Ty::F32, tag(2)),
            sym::Input::Creased => ("creased", Ty::F32, tag(3)),
            sym::Input::Side => (
                "side",
                Ty::F32,
                fetch(
                    Resource::CornerSide,
                    add(mul(l(self.face), u(self.sides as u32)), u(c as u32)),
                ),
            ),
        };
        let id = self.f.local(format!("{name}_{c}"), ty);
        self.loads.push(Stmt::Let(id, value));
        self.inputs.insert((input, c), id);
        id
    }

    fn def_local(&mut self, def: usize, corner: Option<usize>) -> LocalId {
        match self.defs.get(&(def, corner)) {
            Some(id) => *id,
            None => panic!("definition {def} used before it is lowered"),
        }
    }

    fn lower(&mut self, s: &Sym) -> Val {
        match s {
            Sym::Num(x) => Val::Num(*x),
            Sym::Neg(a) => match self.lower(a) {
                Val::Num(x) => Val::Num(-x),
                Val::Ex(e, p) => Val::Ex(Expr::Neg(Box::new(e)), p),
            },
            Sym::Bin(op, a, b) => {
                let (a, b) = (self.lower(a), self.lower(b));
                match (a, b) {
                    (Val::Num(x), Val::Num(y)) => Val::Num(match op {
                        sym::BinOp::Add => x + y,
                        sym::BinOp::Sub => x - y,
                        sym::BinOp::Mul => x * y,
                        sym::BinOp::Div => x / y,
                    }),
                    (a, b) => {
                        let point = matches!(a, Val::Ex(_, true)) || matches!(b, Val::Ex(_, true));
                        let pop = match op {
                            sym::BinOp::Add => BinOp::Add,
                            sym::BinOp::Sub => BinOp::Sub,
                            sym::BinOp::Mul => BinOp::Mul,
                            sym::BinOp::Div => BinOp::Div,
                        };
                        Val::Ex(bin(pop, a.expr(), b.expr()), point)
                    }
                }
            }
            Sym::Func(fun, a) => match self.lower(a) {
                Val::Num(x) => Val::Num(fun.apply(x)),
                Val::Ex(e, p) => {
                    let b = match fun {
                        sym::Func::Cos => Builtin::Cos,
                        sym::Func::Sin => Builtin::Sin,
                        sym::Func::Sqrt => Builtin::Sqrt,
                    };
                    Val::Ex(Expr::Call(b, vec![e]), p)
                }
            },
            Sym::CornerConst { konst, corner } => {
                let id = self.corner_const(*konst, corner_of(corner, self.sides));
                Val::Ex(l(id), false)
            }
            Sym::CornerValence(c) => {
                let id = self.valence(corner_of(c, self.sides));
                Val::Ex(l(id), false)
            }
            Sym::Def { def, index } => {
                let corner = index.as_ref().map(|i| corner_of(i, self.sides));
                let id = self.def_local(*def, corner);
                let point = self.f.locals[id.0].ty == Ty::Vec3;
                Val::Ex(l(id), point)
            }
            Sym::CornerData {
                output,
                corner,
                offset,
            } => {
                let id = self.datum(
                    *output,
                    corner_of(corner, self.sides),
                    offset.as_ref().map(|o| int_of(o)),
                );
                Val::Ex(l(id), true)
            }
            Sym::Sum { var, body } => {
                // Unrolled over the corners, left to right: ((a + b) + c) + d.
                let mut acc: Option<Val> = None;
                for k in 0..self.sides as i64 {
                    let term = self.lower(&sym::substitute(body, *var, k));
                    acc = Some(match acc {
                        None => term,
                        Some(Val::Num(x)) if matches!(term, Val::Num(_)) => {
                            Val::Num(x + if let Val::Num(y) = term { y } else { 0.0 })
                        }
                        Some(a) => {
                            let point =
                                matches!(a, Val::Ex(_, true)) || matches!(term, Val::Ex(_, true));
                            Val::Ex(add(a.expr(), term.expr()), point)
                        }
                    });
                }
                acc.unwrap_or(Val::Num(0.0))
            }
            Sym::CornerInput { input, corner } => {
                let id = self.input(*input, corner_of(corner, self.sides));
                Val::Ex(l(id), input.is_vector())
            }
            Sym::Dot(a, b) => {
                let (a, b) = (self.lower(a).expr(), self.lower(b).expr());
                Val::Ex(Expr::Call(Builtin::Dot, vec![a, b]), false)
            }
            Sym::Normalize(a) => {
                let a = self.lower(a).expr();
                Val::Ex(call(FnRef::Common(common_fn::NORMALIZE), vec![a]), true)
            }
            Sym::Var(_)
            | Sym::Valence
            | Sym::Const(_)
            | Sym::If { .. }
            | Sym::Center
            | Sym::Ring(_) => panic!("not a patch-stage expression: {s:?}"),
        }
    }
}

fn patch_fn(s: &Scheme, pc: &scheme::PatchClass, const_row: usize) -> Function {
    let mut f = Function::new(
        format!("{}_patch", pc.class.name()),
        format!(
            "Patch stage of `{}` for {} {}: the {} control points of a {} patch from the \
             corners' {}, written from `cp_base`.",
            s.name,
            pc.class.name(),
            if s.facet == scheme::Facet::Tri {
                "triangles"
            } else {
                "quads"
            },
            pc.form.num_points(),
            pc.form.name(),
            if s.facet == scheme::Facet::Tri {
                "positions and normals"
            } else {
                "vertex-stage outputs"
            }
        ),
    );
    let face = f.param("face", Ty::U32);
    let cp_base = f.param("cp_base", Ty::U32);
    let sides = pc.form.sides();
    let tri = s.facet == scheme::Facet::Tri;
    let mut head = Vec::new();
    let mut corners = CornerLocals {
        vertex: Vec::new(),
        n: Vec::new(),
        sector: Vec::new(),
        out_base: Vec::new(),
    };
    for c in 0..sides {
        let vtx = f.local(format!("vertex_{c}"), Ty::U32);
        let slot = add(mul(l(face), u(sides as u32)), u(c as u32));
        corners.vertex.push(vtx);
        if tri {
            // Triangle schemes read positions and normals at the corner
            // vertices, loaded on first use.
            head.push(Stmt::Let(vtx, fetch(Resource::CornerVertex, slot)));
            continue;
        }
        let n = f.local(format!("n_{c}"), Ty::U32);
        let sector = f.local(format!("sector_{c}"), Ty::U32);
        let out_base = f.local(format!("out_base_{c}"), Ty::U32);
        head.push(Stmt::Let(vtx, fetch(Resource::CornerVertex, slot.clone())));
        head.push(Stmt::Let(sector, fetch(Resource::CornerSector, slot)));
        head.push(Stmt::Let(n, fetch(Resource::Valence, l(vtx))));
        head.push(Stmt::Let(
            out_base,
            fetch(Resource::VertexOutOffsets, l(vtx)),
        ));
        corners.n.push(n);
        corners.sector.push(sector);
        corners.out_base.push(out_base);
    }
    let mut pl = PatchLower {
        s,
        f,
        face,
        corners,
        sides,
        inputs: BTreeMap::new(),
        const_row,
        consts: BTreeMap::new(),
        valences: BTreeMap::new(),
        data: BTreeMap::new(),
        defs: BTreeMap::new(),
        loads: Vec::new(),
        body: Vec::new(),
    };
    for (di, d) in pc.defs.iter().enumerate() {
        let corners: Vec<Option<usize>> = if d.indexed {
            (0..sides).map(Some).collect()
        } else {
            vec![None]
        };
        for c in corners {
            let expr = match c {
                Some(c) => sym::substitute(&d.expr, CORNER_VAR, c as i64),
                None => d.expr.clone(),
            };
            let value = pl.lower(&expr).expr();
            if d.out {
                let idx = match pc.singles.iter().position(|&k| k == di) {
                    Some(k) => pc.form.single_index(k),
                    None => {
                        let slot = pc.slots.iter().position(|&k| k == di).unwrap_or(0);
                        pc.form.storage_index(c.unwrap_or(0), slot)
                    }
                } as u32;
                pl.body.push(Stmt::Store(
                    Resource::ControlPoints,
                    add(l(cp_base), u(idx)),
                    value,
                ));
            } else {
                let ty = if d.ty == scheme::Ty::Point {
                    Ty::Vec3
                } else {
                    Ty::F32
                };
                let name = match c {
                    Some(c) => format!("{}_{c}", d.name),
                    None => d.name.clone(),
                };
                let id = pl.f.local(name, ty);
                pl.body.push(Stmt::Let(id, value));
                pl.defs.insert((di, c), id);
            }
        }
    }
    let mut f = pl.f;
    f.body = head;
    f.body.extend(pl.loads);
    f.body.extend(pl.body);
    f
}

/// Integer-formed weight pair `((level - i)/level, i/level)`.
fn weights(
    f: &mut Function,
    name: &str,
    i: LocalId,
    level: LocalId,
) -> (LocalId, LocalId, Vec<Stmt>) {
    let wl = f.local(format!("l{name}"), Ty::F32);
    let wr = f.local(format!("r{name}"), Ty::F32);
    let st = vec![
        Stmt::Let(wl, div(to_f32(sub(l(level), l(i))), to_f32(l(level)))),
        Stmt::Let(wr, div(to_f32(l(i)), to_f32(l(level)))),
    ];
    (wl, wr, st)
}

fn surface_params(f: &mut Function) -> (LocalId, LocalId, LocalId, LocalId) {
    let cp = f.param("cp_base", Ty::U32);
    let iu = f.param("iu", Ty::U32);
    let iv = f.param("iv", Ty::U32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::Struct(plan::common::SAMPLE));
    (cp, iu, iv, level)
}

/// A `Curve` field: 0 = point, 1 = derivative.
fn field(id: LocalId, k: usize) -> Expr {
    Expr::Field(Box::new(l(id)), k)
}

/// Bind `e` to a new `vec3` local.
fn let_vec(f: &mut Function, name: &str, e: Expr) -> LocalId {
    let id = f.local(name, Ty::Vec3);
    f.body.push(Stmt::Let(id, e));
    id
}

/// Bind `e` to a new `f32` local.
fn let_f32(f: &mut Function, name: &str, e: Expr) -> LocalId {
    let id = f.local(name, Ty::F32);
    f.body.push(Stmt::Let(id, e));
    id
}

/// Tensor-product cubic Bézier over `grid[k][l]` (k along u): symmetric de
/// Casteljau along u on each of the four rows, then along v on the row
/// points (position, ∂/∂v) and, if `with_du`, on the row derivatives
/// (∂/∂u). Returns `(position, du, dv)`; `du` is the zero vector without
/// `with_du` (nothing is emitted for it).
fn tensor_cubic(
    f: &mut Function,
    prefix: &str,
    grid: &[[Expr; 4]; 4],
    (lu, ru): (LocalId, LocalId),
    (lv, rv): (LocalId, LocalId),
    with_du: bool,
) -> (Expr, Expr, Expr) {
    let mut rows = Vec::new();
    for row in 0..4 {
        let id = f.local(format!("{prefix}row{row}"), Ty::Struct(plan::common::CURVE));
        f.body.push(Stmt::Let(
            id,
            call(
                FnRef::Common(common_fn::CUBIC),
                grid.iter()
                    .map(|column| column[row].clone())
                    .chain([l(lu), l(ru)])
                    .collect(),
            ),
        ));
        rows.push(id);
    }
    let along_v = f.local(format!("{prefix}along_v"), Ty::Struct(plan::common::CURVE));
    let mut passes = vec![(along_v, 0)];
    let along_u = with_du.then(|| {
        let id = f.local(format!("{prefix}along_u"), Ty::Struct(plan::common::CURVE));
        passes.push((id, 1));
        id
    });
    for (id, k) in passes {
        f.body.push(Stmt::Let(
            id,
            call(
                FnRef::Common(common_fn::CUBIC),
                vec![
                    field(rows[0], k),
                    field(rows[1], k),
                    field(rows[2], k),
                    field(rows[3], k),
                    l(lv),
                    l(rv),
                ],
            ),
        ));
    }
    let du = match along_u {
        Some(id) => field(id, 0),
        None => Expr::Call(Builtin::Vec3, vec![f32c(0.0), f32c(0.0), f32c(0.0)]),
    };
    (field(along_v, 0), du, field(along_v, 1))
}

/// Quadratic Bézier by symmetric de Casteljau (`x·l + y·r` at every step).
fn quadratic(f: &mut Function, name: &str, b: [Expr; 3], wl: LocalId, wr: LocalId) -> Expr {
    let [b0, b1, b2] = b;
    let q0 = let_vec(f, &format!("{name}_0"), lerp(b0, b1.clone(), wl, wr));
    let q1 = let_vec(f, &format!("{name}_1"), lerp(b1, b2, wl, wr));
    lerp(l(q0), l(q1), wl, wr)
}

/// Normalised cross product through the guarded common normalize.
fn unit_cross(a: Expr, b: Expr) -> Expr {
    call(
        FnRef::Common(common_fn::NORMALIZE),
        vec![Expr::Call(Builtin::Cross, vec![a, b])],
    )
}

/// Stored control point `k` of the patch at `cp`.
fn cp_at(cp: LocalId, k: usize) -> Expr {
    fetch(Resource::ControlPoints, add(l(cp), u(k as u32)))
}

/// The 16 stored points of a [`Form::Bicubic`] layout as a grid `[k][l]`.
fn bicubic_grid(cp: LocalId) -> [[Expr; 4]; 4] {
    std::array::from_fn(|k| std::array::from_fn(|row| cp_at(cp, 4 * k + row)))
}

fn bicubic_surface(class: Class) -> Function {
    let mut f = Function::new(
        format!("{}_surface", class.name()),
        "Bicubic Bézier patch at (iu, iv)/level: symmetric de Casteljau along u on each of the \
         four rows, then along v on the row points (position, ∂/∂v) and on the row \
         derivatives (∂/∂u); normal = normalize(∂u × ∂v).",
    );
    let (cp, iu, iv, level) = surface_params(&mut f);
    let (lu, ru, st) = weights(&mut f, "u", iu, level);
    f.body.extend(st);
    let (lv, rv, st) = weights(&mut f, "v", iv, level);
    f.body.extend(st);
    let (pos, du, dv) = tensor_cubic(&mut f, "", &bicubic_grid(cp), (lu, ru), (lv, rv), true);
    let normal = unit_cross(du, dv);
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::SAMPLE,
        vec![pos, normal],
    )));
    f
}

/// ACC (acc.md §5): position from the bicubic geometry patch, normal from
/// the tangent patches, `normalize(U × V)`.
fn acc_surface(class: Class) -> Function {
    let mut f = Function::new(
        format!("{}_surface", class.name()),
        "ACC patch at (iu, iv)/level (acc.md §5): position from the bicubic geometry patch \
         (points 0..16); normal = normalize(U × V) from the tangent patches U (quadratic in u, \
         cubic in v) and V (cubic in u, quadratic in v), whose 24 coefficients are stored per \
         corner in the corner's own frame (points 16..40) and mapped back with its signs here.",
    );
    let (cp, iu, iv, level) = surface_params(&mut f);
    let (lu, ru, st) = weights(&mut f, "u", iu, level);
    f.body.extend(st);
    let (lv, rv, st) = weights(&mut f, "v", iv, level);
    f.body.extend(st);
    let (pos, _, _) = tensor_cubic(&mut f, "", &bicubic_grid(cp), (lu, ru), (lv, rv), false);
    let pos = let_vec(&mut f, "position", pos);
    // U[a][b] (3×4) and V[a][b] (4×3) as expressions over stored points.
    let mut uc: [[Option<Expr>; 4]; 4] = Default::default();
    let mut vc: [[Option<Expr>; 4]; 4] = Default::default();
    for corner in 0..4 {
        for slot in 4..10 {
            let t = Form::acc_tangent_slot(corner, slot);
            let mut e = cp_at(cp, Form::Acc.storage_index(corner, slot));
            if t.negate {
                e = Expr::Neg(Box::new(e));
            }
            let dst = if t.in_v { &mut vc } else { &mut uc };
            dst[t.a][t.b] = Some(e);
        }
    }
    let take = |m: &mut [[Option<Expr>; 4]; 4], a: usize, b: usize| {
        m[a][b]
            .take()
            .expect("every ACC tangent coefficient is stored once")
    };
    // U: quadratic along u per v-row, then cubic along v.
    let mut urows = Vec::new();
    for b in 0..4 {
        let q = quadratic(
            &mut f,
            &format!("urow{b}"),
            [
                take(&mut uc, 0, b),
                take(&mut uc, 1, b),
                take(&mut uc, 2, b),
            ],
            lu,
            ru,
        );
        urows.push(let_vec(&mut f, &format!("urow{b}"), q));
    }
    let tu = f.local("tangent_u", Ty::Struct(plan::common::CURVE));
    f.body.push(Stmt::Let(
        tu,
        call(
            FnRef::Common(common_fn::CUBIC),
            vec![
                l(urows[0]),
                l(urows[1]),
                l(urows[2]),
                l(urows[3]),
                l(lv),
                l(rv),
            ],
        ),
    ));
    // V: quadratic along v per u-column, then cubic along u.
    let mut vcols = Vec::new();
    for a in 0..4 {
        let q = quadratic(
            &mut f,
            &format!("vcol{a}"),
            [
                take(&mut vc, a, 0),
                take(&mut vc, a, 1),
                take(&mut vc, a, 2),
            ],
            lv,
            rv,
        );
        vcols.push(let_vec(&mut f, &format!("vcol{a}"), q));
    }
    let tv = f.local("tangent_v", Ty::Struct(plan::common::CURVE));
    f.body.push(Stmt::Let(
        tv,
        call(
            FnRef::Common(common_fn::CUBIC),
            vec![
                l(vcols[0]),
                l(vcols[1]),
                l(vcols[2]),
                l(vcols[3]),
                l(lu),
                l(ru),
            ],
        ),
    ));
    let normal = unit_cross(field(tu, 0), field(tv, 0));
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::SAMPLE,
        vec![l(pos), normal],
    )));
    f
}

/// Gregory patch (gregory.md §4): each interior point is the rational blend
/// of its pair `F⁺, F⁻`; both weights come from the integer coordinates and
/// the corner's 0/0 is guarded to ½, ½ (its Bernstein weight is 0 there).
/// Normals use the exact derivatives: the frozen-grid Bézier derivative plus
/// `Σ B_i B_j ∂b_ij`, so the golden values and the G¹ proof both apply.
fn gregory_surface(class: Class) -> Function {
    let mut f = Function::new(
        format!("{}_surface", class.name()),
        "Gregory patch at (iu, iv)/level (gregory.md §4): blend the four interior pairs with \
         integer-formed weights (guarded at the corners), evaluate the 16-point Bézier grid by \
         symmetric de Casteljau, add the blend's own derivative terms, normal = normalize(∂u × ∂v).",
    );
    let (cp, iu, iv, level) = surface_params(&mut f);
    let (lu, ru, st) = weights(&mut f, "u", iu, level);
    f.body.extend(st);
    let (lv, rv, st) = weights(&mut f, "v", iv, level);
    f.body.extend(st);
    let g = Form::Gregory;
    // Boundary points of the grid from P, E⁺, E⁻ (slots 0..3 sit where the
    // bicubic layout puts b00, b10, b01).
    let mut grid: [[Expr; 4]; 4] = std::array::from_fn(|_| std::array::from_fn(|_| f32c(0.0)));
    for corner in 0..4 {
        for slot in 0..3 {
            let k = Form::Bicubic.storage_index(corner, slot);
            grid[k / 4][k % 4] = cp_at(cp, g.storage_index(corner, slot));
        }
    }
    // Interior pair weights, as integers: (w⁺, w⁻) per corner (gregory.md §4).
    let pairs: [(Expr, Expr); 4] = [
        (l(iu), l(iv)),
        (l(iv), sub(l(level), l(iu))),
        (sub(l(level), l(iu)), sub(l(level), l(iv))),
        (sub(l(level), l(iv)), l(iu)),
    ];
    // d(w⁺)/du, d(w⁺)/dv, d(w⁻)/du, d(w⁻)/dv in parameter units.
    const DW: [[f32; 4]; 4] = [
        [1.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, -1.0, 0.0],
        [-1.0, 0.0, 0.0, -1.0],
        [0.0, -1.0, 1.0, 0.0],
    ];
    let nf = let_f32(&mut f, "nf", to_f32(l(level)));
    let mut corr_u: Vec<Expr> = Vec::new();
    let mut corr_v: Vec<Expr> = Vec::new();
    for (corner, (wp, wm)) in pairs.into_iter().enumerate() {
        let fp = let_vec(
            &mut f,
            &format!("fp{corner}"),
            cp_at(cp, g.storage_index(corner, 3)),
        );
        let fm = let_vec(
            &mut f,
            &format!("fm{corner}"),
            cp_at(cp, g.storage_index(corner, 4)),
        );
        let wpi = f.local(format!("wp{corner}"), Ty::U32);
        let wmi = f.local(format!("wm{corner}"), Ty::U32);
        f.body.push(Stmt::Let(wpi, wp));
        f.body.push(Stmt::Let(wmi, wm));
        let sum = f.local(format!("ws{corner}"), Ty::U32);
        f.body.push(Stmt::Let(sum, add(l(wpi), l(wmi))));
        // Blend weights (guarded): a = w⁺/s, b = w⁻/s; and the derivative
        // factor 1/s² in parameter units (s/level)².
        let a = f.local(format!("a{corner}"), Ty::F32);
        let b = f.local(format!("b{corner}"), Ty::F32);
        let inv2 = f.local(format!("inv_s2_{corner}"), Ty::F32);
        f.body.push(Stmt::Var(a, f32c(0.5)));
        f.body.push(Stmt::Var(b, f32c(0.5)));
        f.body.push(Stmt::Var(inv2, f32c(0.0)));
        let sf = f.local(format!("sf{corner}"), Ty::F32);
        f.body.push(Stmt::If(
            bin(BinOp::Gt, l(sum), u(0)),
            vec![
                Stmt::Assign(a, div(to_f32(l(wpi)), to_f32(l(sum)))),
                Stmt::Assign(b, div(to_f32(l(wmi)), to_f32(l(sum)))),
                Stmt::Let(sf, div(to_f32(l(sum)), l(nf))),
                Stmt::Assign(inv2, div(f32c(1.0), mul(l(sf), l(sf)))),
            ],
            vec![],
        ));
        let k = Form::Bicubic.storage_index(corner, 3);
        let x = let_vec(
            &mut f,
            &format!("x{corner}"),
            add(mul(l(fp), l(a)), mul(l(fm), l(b))),
        );
        grid[k / 4][k % 4] = l(x);
        // ∂X/∂t = (w⁺'·w⁻ − w⁻'·w⁺)(F⁺ − F⁻)/s², weights in parameter units.
        let wpf = let_f32(&mut f, &format!("wpf{corner}"), div(to_f32(l(wpi)), l(nf)));
        let wmf = let_f32(&mut f, &format!("wmf{corner}"), div(to_f32(l(wmi)), l(nf)));
        let diff = let_vec(&mut f, &format!("dfm{corner}"), sub(l(fp), l(fm)));
        // Bernstein weight of this slot: B_i(u)·B_j(v), i, j ∈ {1, 2}.
        let (i, j) = (k / 4, k % 4);
        let bern = |t_l: LocalId, t_r: LocalId, idx: usize| -> Expr {
            // B_1 = 3·r·l², B_2 = 3·r²·l with l = 1 − t, r = t.
            if idx == 1 {
                mul(mul(f32c(3.0), l(t_r)), mul(l(t_l), l(t_l)))
            } else {
                mul(mul(f32c(3.0), mul(l(t_r), l(t_r))), l(t_l))
            }
        };
        let bw = let_f32(
            &mut f,
            &format!("bw{corner}"),
            mul(bern(lu, ru, i), bern(lv, rv, j)),
        );
        for (dir, out) in [(0usize, &mut corr_u), (1usize, &mut corr_v)] {
            // w⁺'·w⁻ − w⁻'·w⁺ with w' ∈ {−1, 0, 1}: written without the
            // zero and unit factors.
            let terms: Vec<Expr> = [(DW[corner][dir], wmf), (-DW[corner][2 + dir], wpf)]
                .into_iter()
                .filter(|(c, _)| *c != 0.0)
                .map(|(c, w)| {
                    if c > 0.0 {
                        l(w)
                    } else {
                        Expr::Neg(Box::new(l(w)))
                    }
                })
                .collect();
            let num = terms.into_iter().reduce(add).unwrap_or(f32c(0.0));
            out.push(mul(l(diff), mul(mul(num, l(inv2)), l(bw))));
        }
    }
    let (pos, du, dv) = tensor_cubic(&mut f, "", &grid, (lu, ru), (lv, rv), true);
    let sum4 = |v: Vec<Expr>| {
        v.into_iter()
            .reduce(add)
            .expect("four interior corrections")
    };
    let du = let_vec(&mut f, "du", add(du, sum4(corr_u)));
    let dv = let_vec(&mut f, "dv", add(dv, sum4(corr_v)));
    let normal = unit_cross(l(du), l(dv));
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::SAMPLE,
        vec![pos, normal],
    )));
    f
}

fn cpatch_surface(class: Class) -> Function {
    let mut f = Function::new(
        format!("{}_surface", class.name()),
        "C-patch at (iu, iv)/level (pccm.md §5.2): pick the quartic piece from integer \
         comparisons, form its barycentric weights from integers, build its 15-point net from \
         the 24 coefficients (§4.4), three de Casteljau steps, normal from the last three points.",
    );
    let (cp, iu, iv, level) = surface_params(&mut f);
    let piece = f.local("piece", Ty::U32);
    let la = f.local("la", Ty::F32);
    let lb = f.local("lb", Ty::F32);
    let lc = f.local("lc", Ty::F32);
    let nf = f.local("nf", Ty::F32);
    let diag = f.local("sum_uv", Ty::U32);
    let lvl = |x| l(x);
    f.body.push(Stmt::Let(nf, to_f32(l(level))));
    f.body.push(Stmt::Let(diag, add(l(iu), l(iv))));
    let bary = |a: Expr, b: Expr, c: Expr| -> Vec<Stmt> {
        vec![
            Stmt::Assign(la, div(to_f32(a), l(nf))),
            Stmt::Assign(lb, div(to_f32(b), l(nf))),
            Stmt::Assign(lc, div(to_f32(c), l(nf))),
        ]
    };
    let two = |x: Expr| mul(u(2), x);
    // piece 0: (1-u-v, u-v, 2v); 1: (u-v, u+v-1, 2-2u); 2: (u+v-1, v-u, 2-2v); 3: (v-u, 1-u-v, 2u)
    let p0 = bary(sub(l(level), l(diag)), sub(l(iu), l(iv)), two(l(iv)));
    let p1 = bary(
        sub(l(iu), l(iv)),
        sub(l(diag), l(level)),
        two(sub(lvl(level), l(iu))),
    );
    let p2 = bary(
        sub(l(diag), l(level)),
        sub(l(iv), l(iu)),
        two(sub(lvl(level), l(iv))),
    );
    let p3 = bary(sub(l(iv), l(iu)), sub(l(level), l(diag)), two(l(iu)));
    f.body.push(Stmt::Var(piece, u(0)));
    f.body.push(Stmt::Var(la, f32c(0.0)));
    f.body.push(Stmt::Var(lb, f32c(0.0)));
    f.body.push(Stmt::Var(lc, f32c(0.0)));
    let set = |p: u32, mut b: Vec<Stmt>| {
        b.insert(0, Stmt::Assign(piece, u(p)));
        b
    };
    f.body.push(Stmt::If(
        bin(BinOp::Le, l(iv), l(iu)),
        vec![Stmt::If(
            bin(BinOp::Le, l(diag), l(level)),
            set(0, p0),
            set(1, p1),
        )],
        vec![Stmt::If(
            bin(BinOp::Ge, l(diag), l(level)),
            set(2, p2),
            set(3, p3),
        )],
    ));
    // Corners of the piece: a = piece, b = piece + 1, p = piece - 1 (mod 4).
    let ca = f.local("ca", Ty::U32);
    let cb = f.local("cb", Ty::U32);
    let cpv = f.local("cprev", Ty::U32);
    f.body.push(Stmt::Let(ca, add(l(cp), mul(l(piece), u(6)))));
    f.body.push(Stmt::Let(
        cb,
        add(l(cp), mul(bin(BinOp::Rem, add(l(piece), u(1)), u(4)), u(6))),
    ));
    f.body.push(Stmt::Let(
        cpv,
        add(l(cp), mul(bin(BinOp::Rem, add(l(piece), u(3)), u(4)), u(6))),
    ));
    let at = |base: LocalId, k: u32| fetch(Resource::ControlPoints, add(l(base), u(k)));
    let coef = |f: &mut Function, name: &str, e: Expr| {
        let id = f.local(name, Ty::Vec3);
        f.body.push(Stmt::Let(id, e));
        id
    };
    let va = coef(&mut f, "va", at(ca, 0));
    let t0a = coef(&mut f, "t0a", at(ca, 1));
    let t1a = coef(&mut f, "t1a", at(ca, 2));
    let b211a = coef(&mut f, "b211a", at(ca, 3));
    let b121a = coef(&mut f, "b121a", at(ca, 4));
    let b112a = coef(&mut f, "b112a", at(ca, 5));
    let vb = coef(&mut f, "vb", at(cb, 0));
    let t0b = coef(&mut f, "t0b", at(cb, 1));
    let t1b = coef(&mut f, "t1b", at(cb, 2));
    let b211b = coef(&mut f, "b211b", at(cb, 3));
    let b112b = coef(&mut f, "b112b", at(cb, 5));
    let b121p = coef(&mut f, "b121p", at(cpv, 4));
    let b112p = coef(&mut f, "b112p", at(cpv, 5));
    let centre = add(
        add(
            add(
                fetch(Resource::ControlPoints, add(l(cp), u(5))),
                fetch(Resource::ControlPoints, add(l(cp), u(11))),
            ),
            fetch(Resource::ControlPoints, add(l(cp), u(17))),
        ),
        fetch(Resource::ControlPoints, add(l(cp), u(23))),
    );
    // The 15-point net b_klm (k toward V_a, l toward V_b, m toward the centre).
    let mut net: BTreeMap<(u32, u32, u32), Expr> = BTreeMap::new();
    let half = |a: LocalId, b: LocalId| div(add(l(a), l(b)), f32c(2.0));
    net.insert((4, 0, 0), l(va));
    net.insert((0, 4, 0), l(vb));
    net.insert(
        (3, 1, 0),
        div(add(l(va), mul(l(t0a), f32c(3.0))), f32c(4.0)),
    );
    net.insert(
        (1, 3, 0),
        div(add(l(vb), mul(l(t1b), f32c(3.0))), f32c(4.0)),
    );
    net.insert((2, 2, 0), half(t0a, t1b));
    net.insert((2, 1, 1), l(b211a));
    net.insert((1, 2, 1), l(b121a));
    net.insert((1, 1, 2), l(b112a));
    net.insert(
        (3, 0, 1),
        div(
            add(
                add(mul(l(va), f32c(2.0)), mul(l(t0a), f32c(3.0))),
                mul(l(t1a), f32c(3.0)),
            ),
            f32c(8.0),
        ),
    );
    net.insert(
        (0, 3, 1),
        div(
            add(
                add(mul(l(vb), f32c(2.0)), mul(l(t1b), f32c(3.0))),
                mul(l(t0b), f32c(3.0)),
            ),
            f32c(8.0),
        ),
    );
    net.insert((2, 0, 2), half(b211a, b121p));
    net.insert((0, 2, 2), half(b121a, b211b));
    net.insert((1, 0, 3), half(b112a, b112p));
    net.insert((0, 1, 3), half(b112a, b112b));
    net.insert((0, 0, 4), div(centre, f32c(4.0)));
    let mut cur: BTreeMap<(u32, u32, u32), LocalId> = BTreeMap::new();
    for (k, e) in net {
        let id = f.local(format!("n{}{}{}", k.0, k.1, k.2), Ty::Vec3);
        f.body.push(Stmt::Let(id, e));
        cur.insert(k, id);
    }
    for deg in (1..4u32).rev() {
        let mut next = BTreeMap::new();
        for kk in (0..=deg).rev() {
            for ll in (0..=deg - kk).rev() {
                let mm = deg - kk - ll;
                let e = add(
                    add(
                        mul(l(cur[&(kk + 1, ll, mm)]), l(la)),
                        mul(l(cur[&(kk, ll + 1, mm)]), l(lb)),
                    ),
                    mul(l(cur[&(kk, ll, mm + 1)]), l(lc)),
                );
                let id = f.local(format!("s{deg}_{kk}{ll}{mm}"), Ty::Vec3);
                f.body.push(Stmt::Let(id, e));
                next.insert((kk, ll, mm), id);
            }
        }
        cur = next;
    }
    let (qa, qb, qc) = (cur[&(1, 0, 0)], cur[&(0, 1, 0)], cur[&(0, 0, 1)]);
    let pos = add(add(mul(l(qa), l(la)), mul(l(qb), l(lb))), mul(l(qc), l(lc)));
    let normal = call(
        FnRef::Common(common_fn::NORMALIZE),
        vec![Expr::Call(
            Builtin::Cross,
            vec![sub(l(qb), l(qa)), sub(l(qc), l(qa))],
        )],
    );
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::SAMPLE,
        vec![pos, normal],
    )));
    f
}

fn eval_fn(patches: &[PatchEntry], surfaces: &[usize], curve_const: usize, sides: u32) -> Function {
    let mut f = Function::new(
        "eval",
        "Position and normal at (iu, iv)/level of a patch of facet class `class` (index into \
         the scheme's patch classes). Samples on the patch boundary take their position from \
         the one shared edge evaluator, whose curve and parameter both patches of an edge \
         form identically; the normal comes from the patch.",
    );
    let class = f.param("class", Ty::U32);
    let cp = f.param("cp_base", Ty::U32);
    let iu = f.param("iu", Ty::U32);
    let iv = f.param("iv", Ty::U32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::Struct(plan::common::SAMPLE));
    let sample = f.local("sample", Ty::Struct(plan::common::SAMPLE));
    let args = vec![l(cp), l(iu), l(iv), l(level)];
    // class dispatch: if class == 0 { … } else if … (last one unconditional)
    let mut chain: Vec<Stmt> = vec![Stmt::Assign(
        sample,
        call(FnRef::Local(*surfaces.last().unwrap_or(&0)), args.clone()),
    )];
    for k in (0..patches.len().saturating_sub(1)).rev() {
        chain = vec![Stmt::If(
            bin(BinOp::Eq, l(class), u(k as u32)),
            vec![Stmt::Assign(
                sample,
                call(FnRef::Local(surfaces[k]), args.clone()),
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
    let base = f.local("curve", Ty::U32);
    let b: Vec<LocalId> = (0..4).map(|i| f.local(format!("b{i}"), Ty::Vec3)).collect();
    let mut boundary = select;
    boundary.push(Stmt::Let(
        base,
        add(mul(l(class), u(4 * sides)), mul(l(edge), u(4))),
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
            FnRef::Common(common_fn::EDGE),
            vec![l(b[0]), l(b[1]), l(b[2]), l(b[3]), l(t), l(level)],
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
fn eval_domain_fn(eval: usize, surfaces_at: &[usize]) -> Function {
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

/// Lower every scheme against one stencil table.
pub fn plan(schemes: &[Scheme], table: &StencilTable) -> Plan {
    let common = common_module(table);
    let schemes = schemes
        .iter()
        .zip(&table.schemes)
        .map(|(s, rows)| scheme_module(s, rows))
        .collect();
    Plan { common, schemes }
}
