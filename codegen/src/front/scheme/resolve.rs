//! Name resolution and type checking: the Resolver walks a parsed scheme
//! (dsl AST) and builds the typed definitions of [`super::Scheme`].

use super::*;

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Stage {
    Const,
    Vertex,
    Patch,
}

#[derive(Default)]
pub(super) struct Resolver {
    /// Corners of the facet (4 until `facet` is read).
    tri: bool,
    consts: Vec<String>,
    vertex: Vec<VertexDef>,
    /// Patch definitions of the block being resolved.
    patch: Vec<PatchDef>,
    /// Index variables in scope: name → slot.
    scope: Vec<(String, usize)>,
    next_var: usize,
    /// Resolving a `sector` block: `m` names the sector's face count.
    sector: bool,
    /// The vertex definition the sector override being resolved replaces:
    /// reading its own name means the scheme's definition ([`Sym::Inherited`]).
    overriding: Option<usize>,
    /// The current `sector` block's `let` helpers, in order.
    locals: Vec<SectorLocal>,
}

/// A `let NAME = EXPR;` of a `sector` block: a single (not per-position)
/// value, inlined wherever a later definition of the block names it.
struct SectorLocal {
    name: String,
    expr: Sym,
    ty: Ty,
    span: Span,
    used: bool,
}

pub(super) fn err<T>(span: Span, msg: impl Into<String>) -> Result<T, SchemeError> {
    Err(SchemeError::new(span, msg))
}

pub(super) fn span_of(e: &Expr) -> Span {
    syn::spanned::Spanned::span(e)
}

pub(super) const RESERVED: &[&str] = &["n", "p", "pi", "sum", "cos", "sin", "sqrt"];

impl Resolver {
    pub(super) fn scheme(mut self, ast: &SchemeAst) -> Result<Scheme, SchemeError> {
        let facet = match ast.facet.to_string().as_str() {
            "quad" => Facet::Quad,
            "tri" => Facet::Tri,
            other => {
                return err(
                    ast.facet.span(),
                    format!("unknown facet `{other}` (expected `quad` or `tri`)"),
                )
            }
        };
        self.tri = facet == Facet::Tri;
        let mut consts = Vec::new();
        for c in &ast.consts {
            self.check_new_name(&c.name)?;
            let (expr, ty) = self.expr(&c.expr, Stage::Const)?;
            if !ty.is_scalar() {
                return err(
                    c.name.span(),
                    format!("constant `{}` must be a number", c.name),
                );
            }
            self.consts.push(c.name.to_string());
            consts.push(ConstDef {
                name: c.name.to_string(),
                expr,
            });
        }
        for d in &ast.vertex {
            let def = self.vertex_def(d)?;
            self.vertex.push(def);
        }
        if !self.tri && !self.vertex.iter().any(|d| d.exported()) {
            return err(ast.name.span(), "the vertex stage exports no output");
        }
        let mut sectors: Vec<SectorBlock> = Vec::new();
        for sa in &ast.sectors {
            if self.tri {
                return err(
                    sa.kind.span(),
                    "a `facet tri` scheme has no vertex stage, so no `sector` blocks",
                );
            }
            let block = self.sector_block(sa)?;
            if sectors.iter().any(|b| b.kind == block.kind) {
                return err(sa.kind.span(), format!("`sector {}` given twice", sa.kind));
            }
            sectors.push(block);
        }
        let mut patches = Vec::new();
        for p in &ast.patches {
            let pc = self.patch_block(p)?;
            if patches.iter().any(|q: &PatchClass| q.class == pc.class) {
                return err(
                    p.class.span(),
                    format!("patch class `{}` given twice", p.class),
                );
            }
            pc.check_boundary_degree(&patches, p.form.span())?;
            patches.push(pc);
        }
        Ok(Scheme {
            name: ast.name.to_string(),
            doc: ast.doc.clone(),
            facet,
            consts,
            vertex: self.vertex,
            sectors,
            patches,
        })
    }

    /// A `sector KIND { … }` block: every definition overrides an earlier
    /// vertex definition of the same name and shape, and may only read
    /// definitions declared before that one (so overrides cannot form a
    /// cycle through the definitions that use them) — and the definition it
    /// replaces, by its own name: that reads the scheme's definition
    /// ([`Sym::Inherited`]), whose expression only reads earlier ones.
    /// `let NAME = EXPR;` declares a block-local helper (a single number or
    /// point, no `[j]`) for the definitions after it; it is inlined, so the
    /// ordering rule applies to what it reads.
    fn sector_block(&mut self, sa: &dsl::SectorAst) -> Result<SectorBlock, SchemeError> {
        let kind = match sa.kind.to_string().as_str() {
            "crease" => SectorKind::Crease,
            "corner" => SectorKind::Corner,
            other => {
                return err(
                    sa.kind.span(),
                    format!("unknown sector kind `{other}`; expected `crease` or `corner`"),
                )
            }
        };
        self.locals.clear();
        // Index-variable slots are unique across the block: a helper inlined
        // inside a `sum` must not reuse the sum's slot.
        let mut next_var = SECTOR_VAR + 1;
        let mut overrides: Vec<SectorOverride> = Vec::new();
        for d in &sa.defs {
            let name = d.name.to_string();
            if d.kind == DefKind::Let {
                if d.index.is_some() {
                    return err(
                        d.name.span(),
                        format!("a `sector` block's `let {name}` is a single value: write `let {name} = …` (per-position values are overrides of vertex definitions)"),
                    );
                }
                if self.vertex.iter().any(|v| v.name == name) {
                    return err(
                        d.name.span(),
                        format!("`{name}` is a vertex definition; a `sector` block overrides it with `{name}{} = …`, not `let`", if self.vertex.iter().any(|v| v.name == name && v.indexed) { "[j]" } else { "" }),
                    );
                }
                if self.locals.iter().any(|l| l.name == name) {
                    return err(d.name.span(), format!("`{name}` is defined twice"));
                }
                if name == "m" {
                    return err(d.name.span(), "`m` is a reserved name (the sector's faces)");
                }
                self.check_new_name(&d.name)?;
                self.sector = true;
                self.next_var = next_var;
                let resolved = self.expr(&d.expr, Stage::Vertex);
                self.sector = false;
                next_var = self.next_var;
                let (expr, ty) = resolved?;
                self.locals.push(SectorLocal {
                    name,
                    expr,
                    ty,
                    span: d.name.span(),
                    used: false,
                });
                continue;
            }
            let Some(def) = self.vertex.iter().position(|v| v.name == name) else {
                return err(
                    d.name.span(),
                    format!("`{name}` is not a vertex definition of this scheme; a `sector` block only overrides them"),
                );
            };
            let (t_indexed, t_ty) = (self.vertex[def].indexed, self.vertex[def].ty);
            if t_indexed != d.index.is_some() {
                return err(
                    d.name.span(),
                    if t_indexed {
                        format!("`{name}` is a family over ring positions: write `{name}[j] = …`")
                    } else {
                        format!("`{name}` is a single output: write `{name} = …`")
                    },
                );
            }
            let sharp = d.kind == DefKind::Sharp;
            if sharp && !t_indexed {
                return err(
                    d.name.span(),
                    format!("`sharp` overrides a family at the sector's sharp edges; `{name}` is a single output"),
                );
            }
            if overrides.iter().any(|o| o.def == def && o.sharp == sharp) {
                return err(d.name.span(), format!("`{name}` is overridden twice"));
            }
            self.sector = true;
            self.overriding = Some(def);
            let resolved = self.with_index(d.index.as_ref(), SECTOR_VAR, |r| {
                r.next_var = next_var;
                r.expr(&d.expr, Stage::Vertex)
            });
            self.sector = false;
            self.overriding = None;
            next_var = self.next_var;
            let (expr, ty) = resolved?;
            if ty != t_ty {
                return err(
                    span_of(&d.expr),
                    format!(
                        "the override of `{name}` must be {}, found {}",
                        t_ty.describe(),
                        ty.describe()
                    ),
                );
            }
            if let Some(later) = sym::defs_read(&expr).into_iter().find(|&k| k >= def) {
                return err(
                    span_of(&d.expr),
                    format!(
                        "the override of `{name}` reads `{}`, which is not defined before `{name}`",
                        self.vertex[later].name
                    ),
                );
            }
            overrides.push(SectorOverride {
                def,
                sharp,
                expr,
                span: d.span,
            });
        }
        if let Some(l) = self.locals.iter().find(|l| !l.used) {
            return err(
                l.span,
                format!(
                    "`let {}` of `sector {}` is never used by a later definition of the block",
                    l.name, sa.kind
                ),
            );
        }
        self.locals.clear();
        Ok(SectorBlock { kind, overrides })
    }

    fn check_new_name(&self, name: &Ident) -> Result<(), SchemeError> {
        let s = name.to_string();
        if RESERVED.contains(&s.as_str()) {
            return err(name.span(), format!("`{s}` is a reserved name"));
        }
        if self.consts.contains(&s)
            || self.vertex.iter().any(|d| d.name == s)
            || self.patch.iter().any(|d| d.name == s && !d.out)
        {
            return err(name.span(), format!("`{s}` is defined twice"));
        }
        Ok(())
    }

    fn with_index<T>(
        &mut self,
        index: Option<&Ident>,
        slot: usize,
        f: impl FnOnce(&mut Self) -> Result<T, SchemeError>,
    ) -> Result<T, SchemeError> {
        self.next_var = slot + 1;
        if let Some(id) = index {
            self.scope.push((id.to_string(), slot));
        }
        let r = f(self);
        self.scope.clear();
        r
    }

    fn vertex_def(&mut self, d: &DefAst) -> Result<VertexDef, SchemeError> {
        self.check_new_name(&d.name)?;
        let (expr, ty) = self.with_index(d.index.as_ref(), SECTOR_VAR, |r| {
            r.expr(&d.expr, Stage::Vertex)
        })?;
        if d.kind != DefKind::Let && ty != Ty::Point {
            return err(
                span_of(&d.expr),
                format!(
                    "vertex output `{}` must be a point (a combination of p, p[k] and other outputs), found {}; use `let` for numbers",
                    d.name,
                    ty.describe()
                ),
            );
        }
        Ok(VertexDef {
            name: d.name.to_string(),
            kind: d.kind,
            indexed: d.index.is_some(),
            ty,
            expr,
            span: d.span,
        })
    }

    fn patch_block(&mut self, p: &dsl::PatchAst) -> Result<PatchClass, SchemeError> {
        let class = match (p.class.to_string().as_str(), self.tri) {
            ("ordinary", false) => Class::Ordinary,
            ("extraordinary", false) => Class::Extraordinary,
            ("triangle", true) => Class::Triangle,
            (other, false) => {
                return err(
                    p.class.span(),
                    format!(
                        "unknown patch class `{other}`; expected `ordinary` or `extraordinary`"
                    ),
                )
            }
            (other, true) => {
                return err(
                    p.class.span(),
                    format!(
                    "unknown patch class `{other}`; a `facet tri` scheme has one class, `triangle`"
                ),
                )
            }
        };
        let form = Form::from_name(&p.form.to_string()).ok_or_else(|| {
            SchemeError::new(
                p.form.span(),
                format!("unknown patch form `{}`; expected {}", p.form, Form::NAMES),
            )
        })?;
        if (form.sides() == 3) != self.tri {
            return err(
                p.form.span(),
                format!(
                    "form `{}` is for {} facets",
                    form.name(),
                    if form.sides() == 3 { "`tri`" } else { "`quad`" }
                ),
            );
        }
        self.patch.clear();
        let mut slots: Vec<Option<usize>> = vec![None; form.slots().len()];
        let mut singles: Vec<Option<usize>> = vec![None; form.single_slots().len()];
        for d in &p.defs {
            let out = d.kind == DefKind::Out;
            if out {
                let name = d.name.to_string();
                if let Some(k) = form.single_slots().iter().position(|s| *s == name) {
                    if singles[k].is_some() {
                        return err(d.name.span(), format!("`out {name}` given twice"));
                    }
                    if d.index.is_some() {
                        return err(
                            d.name.span(),
                            format!("control point `{name}` exists once per patch: write `out {name} = …`"),
                        );
                    }
                    singles[k] = Some(self.patch.len());
                } else {
                    let Some(slot) = form.slots().iter().position(|s| *s == name) else {
                        return err(
                            d.name.span(),
                            format!(
                                "`{name}` is not a control point of form `{}` (its slots: {})",
                                form.name(),
                                form.slots()
                                    .iter()
                                    .chain(form.single_slots())
                                    .copied()
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        );
                    };
                    if slots[slot].is_some() {
                        return err(d.name.span(), format!("`out {name}` given twice"));
                    }
                    if d.index.is_none() {
                        return err(
                            d.name.span(),
                            format!(
                                "control point `{name}` is per corner: write `out {name}[i] = …`"
                            ),
                        );
                    }
                    slots[slot] = Some(self.patch.len());
                }
            } else {
                self.check_new_name(&d.name)?;
            }
            let (expr, ty) = self.with_index(d.index.as_ref(), CORNER_VAR, |r| {
                r.expr(&d.expr, Stage::Patch)
            })?;
            if out && ty != Ty::Point {
                return err(
                    span_of(&d.expr),
                    format!(
                        "control point `{}` must be a point, found {}",
                        d.name,
                        ty.describe()
                    ),
                );
            }
            self.patch.push(PatchDef {
                name: d.name.to_string(),
                out,
                indexed: d.index.is_some(),
                ty,
                expr,
                span: d.span,
            });
        }
        let mut single_defs = Vec::new();
        for (i, s) in singles.iter().enumerate() {
            match s {
                Some(k) => single_defs.push(*k),
                None => {
                    return err(
                        p.form.span(),
                        format!(
                            "form `{}` needs `out {} = …`",
                            form.name(),
                            form.single_slots()[i]
                        ),
                    )
                }
            }
        }
        let mut filled = Vec::new();
        for (i, s) in slots.iter().enumerate() {
            match s {
                Some(k) => filled.push(*k),
                None => {
                    return err(
                        p.form.span(),
                        format!(
                            "form `{}` needs `out {}[i] = …`",
                            form.name(),
                            form.slots()[i]
                        ),
                    )
                }
            }
        }
        Ok(PatchClass {
            class,
            form,
            defs: std::mem::take(&mut self.patch),
            slots: filled,
            singles: single_defs,
        })
    }

    fn lookup_var(&self, name: &str) -> Option<usize> {
        self.scope
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, s)| *s)
    }

    fn index(&mut self, e: &Expr, stage: Stage) -> Result<Sym, SchemeError> {
        let (s, ty) = self.expr(e, stage)?;
        if ty != Ty::Index {
            return err(
                span_of(e),
                format!(
                    "an index must be integer arithmetic on index variables, found {}",
                    ty.describe()
                ),
            );
        }
        Ok(s)
    }

    fn expr(&mut self, e: &Expr, stage: Stage) -> Result<(Sym, Ty), SchemeError> {
        let span = span_of(e);
        match e {
            Expr::Paren(p) => self.expr(&p.expr, stage),
            Expr::Group(g) => self.expr(&g.expr, stage),
            Expr::Lit(l) => match &l.lit {
                syn::Lit::Int(i) => {
                    let x: f64 = i.base10_parse::<u64>()? as f64;
                    Ok((Sym::Num(x), Ty::Index))
                }
                syn::Lit::Float(f) => Ok((Sym::Num(f.base10_parse::<f64>()?), Ty::Scalar)),
                _ => err(span, "only numbers are allowed here"),
            },
            Expr::Unary(u) => match u.op {
                syn::UnOp::Neg(_) => {
                    let (a, ty) = self.expr(&u.expr, stage)?;
                    Ok((Sym::Neg(Box::new(a)), ty))
                }
                _ => err(span, "only unary minus is supported"),
            },
            Expr::Binary(b) => self.binary(b, stage),
            Expr::Path(p) => {
                let Some(id) = p.path.get_ident() else {
                    return err(span, "expected a plain name");
                };
                self.name(id, stage)
            }
            Expr::Index(ix) => self.indexed(ix, stage),
            Expr::Call(c) => self.call(c, stage),
            Expr::If(i) => self.if_expr(i, stage),
            Expr::Block(b) if b.block.stmts.len() == 1 => match &b.block.stmts[0] {
                syn::Stmt::Expr(e, None) => self.expr(e, stage),
                _ => err(span, "a block must hold a single expression"),
            },
            _ => err(span, "unsupported expression in a scheme"),
        }
    }

    fn binary(&mut self, b: &syn::ExprBinary, stage: Stage) -> Result<(Sym, Ty), SchemeError> {
        let span = span_of(&Expr::Binary(b.clone()));
        let op = match b.op {
            syn::BinOp::Add(_) => BinOp::Add,
            syn::BinOp::Sub(_) => BinOp::Sub,
            syn::BinOp::Mul(_) => BinOp::Mul,
            syn::BinOp::Div(_) => BinOp::Div,
            _ => {
                return err(
                    span,
                    "only + - * / are supported (comparisons only in `if`)",
                )
            }
        };
        let (l, lt) = self.expr(&b.left, stage)?;
        let (r, rt) = self.expr(&b.right, stage)?;
        use Ty::*;
        let ty = match (op, lt, rt) {
            (BinOp::Add | BinOp::Sub | BinOp::Mul, Index, Index) => Index,
            (BinOp::Add | BinOp::Sub, Point, Point) => Point,
            (_, a, b) if a.is_scalar() && b.is_scalar() => Scalar,
            (BinOp::Mul, a, Point) if a.is_scalar() => Point,
            (BinOp::Mul | BinOp::Div, Point, b) if b.is_scalar() => Point,
            (BinOp::Mul, Point, Point) => {
                return err(
                    span,
                    "cannot multiply two points (a weight must be a number)",
                )
            }
            (BinOp::Div, _, Point) => return err(span, "cannot divide by a point"),
            (_, a, b) => {
                return err(
                    span,
                    format!(
                        "cannot combine {} and {} with `{}`",
                        a.describe(),
                        b.describe(),
                        op_str(op)
                    ),
                )
            }
        };
        Ok((Sym::Bin(op, Box::new(l), Box::new(r)), ty))
    }

    fn name(&mut self, id: &Ident, stage: Stage) -> Result<(Sym, Ty), SchemeError> {
        let s = id.to_string();
        if let Some(slot) = self.lookup_var(&s) {
            return Ok((Sym::Var(slot), Ty::Index));
        }
        if self.sector && stage == Stage::Vertex {
            if let Some(l) = self.locals.iter_mut().find(|l| l.name == s) {
                l.used = true;
                return Ok((l.expr.clone(), l.ty));
            }
        }
        match (s.as_str(), stage) {
            ("pi", _) => return Ok((Sym::Num(std::f64::consts::PI), Ty::Scalar)),
            ("n", Stage::Const | Stage::Vertex) => return Ok((Sym::Valence, Ty::Index)),
            ("m", Stage::Vertex) if self.sector => return Ok((Sym::SectorFaces, Ty::Index)),
            ("n", Stage::Patch) => {
                return err(
                    id.span(),
                    "in the patch stage valences are per corner: write `n(i)`",
                )
            }
            ("p", Stage::Vertex) => return Ok((Sym::Center, Ty::Point)),
            _ => {}
        }
        if let Some(k) = self.consts.iter().position(|c| *c == s) {
            return match stage {
                Stage::Patch => err(
                    id.span(),
                    format!("`{s}` is per valence: in the patch stage write `{s}(i)` for corner i's value"),
                ),
                _ => Ok((Sym::Const(k), Ty::Scalar)),
            };
        }
        match stage {
            Stage::Vertex => {
                if let Some(k) = self.vertex.iter().position(|d| d.name == s) {
                    let d = &self.vertex[k];
                    if d.indexed {
                        return err(
                            id.span(),
                            format!(
                                "`{s}` is a family over sectors: write `{s}[j]` (index misuse)"
                            ),
                        );
                    }
                    let sym = if self.overriding == Some(k) {
                        Sym::Inherited {
                            def: k,
                            index: None,
                        }
                    } else {
                        Sym::Def {
                            def: k,
                            index: None,
                        }
                    };
                    return Ok((sym, d.ty));
                }
            }
            Stage::Patch => {
                if let Some(k) = self.patch.iter().position(|d| d.name == s && !d.out) {
                    let d = &self.patch[k];
                    if d.indexed {
                        return err(
                            id.span(),
                            format!("`{s}` is per corner: write `{s}[i]` (index misuse)"),
                        );
                    }
                    return Ok((
                        Sym::Def {
                            def: k,
                            index: None,
                        },
                        d.ty,
                    ));
                }
                if self.vertex.iter().any(|d| d.name == s && d.exported()) {
                    return err(
                        id.span(),
                        format!("vertex output `{s}` must be read at a corner: `{s}(i)` or `{s}(i, offset)`"),
                    );
                }
            }
            Stage::Const => {}
        }
        if stage == Stage::Patch {
            if s == "p" {
                return err(id.span(), "`p` is the ring centre of the vertex stage; the patch stage reads vertex outputs at corners, e.g. `v(i)`");
            }
            if self.patch.iter().any(|d| d.name == s && d.out) {
                return err(id.span(), format!("`{s}` is an `out` control point and cannot be read; define a local and output it"));
            }
            if self.vertex.iter().any(|d| d.name == s) {
                return err(
                    id.span(),
                    format!("`{s}` is a vertex-stage `let` and is not exported to the patch stage"),
                );
            }
        }
        err(
            id.span(),
            format!(
                "undefined name `{s}` (definitions are visible after the line that defines them)"
            ),
        )
    }

    fn indexed(&mut self, ix: &syn::ExprIndex, stage: Stage) -> Result<(Sym, Ty), SchemeError> {
        let Expr::Path(p) = ix.expr.as_ref() else {
            return err(span_of(&ix.expr), "only names can be indexed");
        };
        let Some(id) = p.path.get_ident() else {
            return err(span_of(&ix.expr), "expected a plain name");
        };
        let s = id.to_string();
        if s == "p" && stage == Stage::Vertex {
            let idx = self.index(&ix.index, stage)?;
            return Ok((Sym::Ring(Box::new(idx)), Ty::Point));
        }
        match stage {
            Stage::Vertex => {
                if let Some(k) = self.vertex.iter().position(|d| d.name == s) {
                    if !self.vertex[k].indexed {
                        return err(id.span(), format!("`{s}` is a single output, not a family: write `{s}` (index misuse)"));
                    }
                    let ty = self.vertex[k].ty;
                    let index = Some(Box::new(self.index(&ix.index, stage)?));
                    let sym = if self.overriding == Some(k) {
                        Sym::Inherited { def: k, index }
                    } else {
                        Sym::Def { def: k, index }
                    };
                    return Ok((sym, ty));
                }
            }
            Stage::Patch => {
                if let Some(k) = self.patch.iter().position(|d| d.name == s && !d.out) {
                    if !self.patch[k].indexed {
                        return err(
                            id.span(),
                            format!("`{s}` is not per corner: write `{s}` (index misuse)"),
                        );
                    }
                    let ty = self.patch[k].ty;
                    let idx = self.index(&ix.index, stage)?;
                    return Ok((
                        Sym::Def {
                            def: k,
                            index: Some(Box::new(idx)),
                        },
                        ty,
                    ));
                }
                if self.vertex.iter().any(|d| d.name == s && d.exported()) {
                    return err(
                        id.span(),
                        format!("vertex output `{s}` is read at a corner with `{s}(i, offset)`, not `{s}[…]` (index misuse)"),
                    );
                }
            }
            Stage::Const => {}
        }
        err(id.span(), format!("undefined name `{s}`"))
    }

    fn call(&mut self, c: &syn::ExprCall, stage: Stage) -> Result<(Sym, Ty), SchemeError> {
        let Expr::Path(p) = c.func.as_ref() else {
            return err(span_of(&c.func), "only named functions can be called");
        };
        let Some(id) = p.path.get_ident() else {
            return err(span_of(&c.func), "expected a plain function name");
        };
        let s = id.to_string();
        let args: Vec<&Expr> = c.args.iter().collect();
        if let Some(f) = Func::from_name(&s) {
            if args.len() != 1 {
                return err(id.span(), format!("`{s}` takes one argument"));
            }
            let (a, ty) = self.expr(args[0], stage)?;
            if !ty.is_scalar() {
                return err(
                    span_of(args[0]),
                    format!("`{s}` takes a number, found {}", ty.describe()),
                );
            }
            return Ok((Sym::Func(f, Box::new(a)), Ty::Scalar));
        }
        if s == "sum" {
            if args.len() != 2 {
                return err(id.span(), "`sum` is written `sum(k, body)`");
            }
            let Expr::Path(vp) = args[0] else {
                return err(
                    span_of(args[0]),
                    "the first argument of `sum` names its index variable",
                );
            };
            let Some(var) = vp.path.get_ident() else {
                return err(span_of(args[0]), "expected a plain index variable name");
            };
            if stage == Stage::Const {
                return err(id.span(), "`sum` is not available in constants");
            }
            let slot = self.next_var;
            self.next_var += 1;
            self.scope.push((var.to_string(), slot));
            let body = self.expr(args[1], stage);
            self.scope.pop();
            let (body, ty) = body?;
            return Ok((
                Sym::Sum {
                    var: slot,
                    body: Box::new(body),
                },
                ty,
            ));
        }
        if s == "dot" || s == "normalize" {
            if !self.tri {
                return err(
                    id.span(),
                    format!("`{s}` is only available in `facet tri` schemes (quad schemes are linear stencils)"),
                );
            }
            let want = if s == "dot" { 2 } else { 1 };
            if args.len() != want {
                return err(id.span(), format!("`{s}` takes {want} argument(s)"));
            }
            let mut xs = Vec::new();
            for a in &args {
                let (x, ty) = self.expr(a, stage)?;
                if ty != Ty::Point {
                    return err(
                        span_of(a),
                        format!("`{s}` takes vectors, found {}", ty.describe()),
                    );
                }
                xs.push(x);
            }
            let mut xs = xs.into_iter();
            let a = Box::new(xs.next().expect("argument count checked"));
            return Ok(match xs.next() {
                Some(b) => (Sym::Dot(a, Box::new(b)), Ty::Scalar),
                None => (Sym::Normalize(a), Ty::Point),
            });
        }
        if stage == Stage::Patch && self.tri {
            let input = sym::Input::ALL
                .into_iter()
                .find(|i| i.dsl_name() == s.as_str());
            if let Some(input) = input {
                if args.len() != 1 {
                    return err(id.span(), format!("`{s}(corner)` takes one argument"));
                }
                let c = self.index(args[0], stage)?;
                return Ok((
                    Sym::CornerInput {
                        input,
                        corner: Box::new(c),
                    },
                    if input.is_vector() {
                        Ty::Point
                    } else {
                        Ty::Scalar
                    },
                ));
            }
        }
        if stage == Stage::Patch {
            if s == "n" {
                if args.len() != 1 {
                    return err(id.span(), "`n(corner)` takes one argument");
                }
                let c = self.index(args[0], stage)?;
                return Ok((Sym::CornerValence(Box::new(c)), Ty::Index));
            }
            if let Some(k) = self.consts.iter().position(|c| *c == s) {
                if args.len() != 1 {
                    return err(id.span(), format!("`{s}(corner)` takes one argument"));
                }
                let c = self.index(args[0], stage)?;
                return Ok((
                    Sym::CornerConst {
                        konst: k,
                        corner: Box::new(c),
                    },
                    Ty::Scalar,
                ));
            }
            if let Some(k) = self.vertex.iter().position(|d| d.name == s && d.exported()) {
                let indexed = self.vertex[k].indexed;
                let want = if indexed { 2 } else { 1 };
                if args.len() != want {
                    return err(
                        id.span(),
                        if indexed {
                            format!("`{s}` is a family over sectors: read it as `{s}(corner, sector_offset)` (index misuse)")
                        } else {
                            format!("`{s}` is a single vertex output: read it as `{s}(corner)` (index misuse)")
                        },
                    );
                }
                let corner = self.index(args[0], stage)?;
                let offset = if indexed {
                    Some(Box::new(self.index(args[1], stage)?))
                } else {
                    None
                };
                return Ok((
                    Sym::CornerData {
                        output: k,
                        corner: Box::new(corner),
                        offset,
                    },
                    Ty::Point,
                ));
            }
        }
        if stage == Stage::Vertex {
            if self.vertex.iter().any(|d| d.name == s && d.indexed) {
                return err(id.span(), format!("`{s}` is a family over sectors: write `{s}[j]`, not `{s}(…)` (index misuse)"));
            }
            if s == "n" || self.consts.contains(&s) || self.vertex.iter().any(|d| d.name == s) {
                return err(
                    id.span(),
                    format!("in the vertex stage `{s}` is read as plain `{s}`, not called"),
                );
            }
        }
        err(id.span(), format!("undefined function `{s}`"))
    }

    fn if_expr(&mut self, i: &syn::ExprIf, stage: Stage) -> Result<(Sym, Ty), SchemeError> {
        let span = span_of(&Expr::If(i.clone()));
        if stage != Stage::Vertex && stage != Stage::Const {
            return err(
                span,
                "`if` is decided per valence and only allowed in constants and the vertex stage",
            );
        }
        let Expr::Binary(cond) = i.cond.as_ref() else {
            return err(
                span_of(&i.cond),
                "an `if` condition compares two numbers, e.g. `n == 4`",
            );
        };
        let op = match cond.op {
            syn::BinOp::Eq(_) => CmpOp::Eq,
            syn::BinOp::Ne(_) => CmpOp::Ne,
            syn::BinOp::Lt(_) => CmpOp::Lt,
            syn::BinOp::Le(_) => CmpOp::Le,
            syn::BinOp::Gt(_) => CmpOp::Gt,
            syn::BinOp::Ge(_) => CmpOp::Ge,
            _ => {
                return err(
                    span_of(&i.cond),
                    "an `if` condition compares two numbers, e.g. `n == 4`",
                )
            }
        };
        let (a, at) = self.expr(&cond.left, stage)?;
        let (b, bt) = self.expr(&cond.right, stage)?;
        if !at.is_scalar() || !bt.is_scalar() {
            return err(
                span_of(&i.cond),
                "an `if` condition compares numbers, not points",
            );
        }
        let then_expr = Expr::Block(syn::ExprBlock {
            attrs: vec![],
            label: None,
            block: i.then_branch.clone(),
        });
        let (t, tt) = self.expr(&then_expr, stage)?;
        let Some((_, other)) = &i.else_branch else {
            return err(span, "`if` needs an `else` branch");
        };
        let (o, ot) = self.expr(other, stage)?;
        let ty = match (tt, ot) {
            (a, b) if a == b => a,
            (a, b) if a.is_scalar() && b.is_scalar() => Ty::Scalar,
            (a, b) => {
                return err(
                    span,
                    format!(
                        "`if` branches differ: {} and {}",
                        a.describe(),
                        b.describe()
                    ),
                )
            }
        };
        Ok((
            Sym::If {
                op,
                a: Box::new(a),
                b: Box::new(b),
                then: Box::new(t),
                other: Box::new(o),
            },
            ty,
        ))
    }
}

pub(super) fn op_str(op: BinOp) -> &'static str {
    match op {
        BinOp::Add => "+",
        BinOp::Sub => "-",
        BinOp::Mul => "*",
        BinOp::Div => "/",
    }
}
