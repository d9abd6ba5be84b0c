//! The patch stage: a scheme's per-corner definitions unrolled in source order into one patch
//! function per facet class, reading each corner by (vertex, sector).

use super::*;

/// Per-corner values loaded once at the top of a patch function.
pub(crate) struct CornerLocals {
    /// Corner vertex (every facet).
    vertex: Vec<LocalId>,
    /// Valence, sector and vertex-stage output base (quad schemes only).
    n: Vec<LocalId>,
    sector: Vec<LocalId>,
    out_base: Vec<LocalId>,
}

impl PatchLower<'_> {
    /// Corner `c`'s shape valence (`corner_valence[4·face + c]`): the valence
    /// of its per-valence constants and of `n(i)`, the virtual valence at a
    /// crease or corner vertex (docs/boundaries.md §2). Loaded on first use,
    /// so schemes without constants do not bind it.
    fn shape(&mut self, c: usize) -> LocalId {
        if let Some(id) = self.shapes.get(&c) {
            return *id;
        }
        let id = self.f.local(format!("shape_{c}"), Ty::U32);
        let slot = add(mul(l(self.face), u(self.sides as u32)), u(c as u32));
        self.loads
            .push(Stmt::Let(id, fetch(Resource::CornerValence, slot)));
        self.shapes.insert(c, id);
        id
    }
}

/// Lowering state of one patch function.
pub(crate) struct PatchLower<'a> {
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
    /// corner → its `corner_valence` local.
    shapes: BTreeMap<usize, LocalId>,
    /// `(output, corner, offset)` → local.
    data: BTreeMap<(usize, usize, i64), LocalId>,
    /// `(def, corner or None)` → local.
    defs: BTreeMap<(usize, Option<usize>), LocalId>,
    /// Statements loading corner data and constants, emitted before the body.
    loads: Vec<Stmt>,
    body: Vec<Stmt>,
}

/// A lowered value: a number still foldable in f64, or an expression.
pub(crate) enum Val {
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

pub(crate) fn corner_of(s: &Sym, sides: usize) -> usize {
    match s {
        Sym::Num(x) => (*x as i64).rem_euclid(sides as i64) as usize,
        other => panic!("corner index did not fold to a number: {other:?}"),
    }
}

pub(crate) fn int_of(s: &Sym) -> i64 {
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
        let shape = self.shape(c);
        let row = sub(add(Expr::Const(self.const_row), l(shape)), u(3));
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
        let shape = self.shape(c);
        let id = self.f.local(format!("nf_{c}"), Ty::F32);
        self.loads.push(Stmt::Let(id, to_f32(l(shape))));
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
            | Sym::SectorFaces
            | Sym::Const(_)
            | Sym::If { .. }
            | Sym::Inherited { .. }
            | Sym::Center
            | Sym::Ring(_) => panic!("not a patch-stage expression: {s:?}"),
        }
    }
}

pub(crate) fn patch_fn(s: &Scheme, pc: &scheme::PatchClass, const_row: usize) -> Function {
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
        shapes: BTreeMap::new(),
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
