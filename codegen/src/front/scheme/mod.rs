//! Scheme IR: a parsed scheme with every name resolved, every expression
//! typed, and every row checked for affine invariance.
//!
//! This is where scheme mistakes become errors that point at the offending
//! source: undefined names, index-family misuse, ill-typed arithmetic
//! (a point times a point), and rows whose weights do not sum to 1 (0 for
//! tangent vectors) at some valence.

use crate::front::dsl::{self, DefAst, DefKind, SchemeAst};
use crate::front::sym::{self, BinOp, CmpOp, Env, Func, Sym, Value};
use crate::plan::form::{Form, SlotKind};
use proc_macro2::Span;
use std::collections::BTreeMap;
use syn::{Expr, Ident};

mod resolve;
mod sector;
use resolve::*;
pub use sector::{
    max_sector_faces, phantom_point, virtual_valence, SectorBlock, SectorKind, SectorOverride,
};

/// Tolerance of the affine-invariance check (DESIGN.md "The stencil table").
pub const AFFINE_TOLERANCE: f64 = 1e-6;

/// A scheme error, located in the scheme source.
#[derive(Debug, Clone)]
pub struct SchemeError {
    pub message: String,
    pub span: Span,
}

impl SchemeError {
    pub fn new(span: Span, message: impl Into<String>) -> Self {
        SchemeError {
            message: message.into(),
            span,
        }
    }
    /// 1-based line and 0-based column in the scheme source.
    pub fn line_column(&self) -> (usize, usize) {
        let lc = self.span.start();
        (lc.line, lc.column)
    }
    pub fn to_syn(&self) -> syn::Error {
        syn::Error::new(self.span, &self.message)
    }
}

impl std::fmt::Display for SchemeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (l, c) = self.line_column();
        write!(f, "line {l}, column {}: {}", c + 1, self.message)
    }
}

impl std::error::Error for SchemeError {}

impl From<syn::Error> for SchemeError {
    fn from(e: syn::Error) -> Self {
        SchemeError::new(e.span(), e.to_string())
    }
}

/// Value type of an expression.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    /// Integer-valued scalar: usable as an index.
    Index,
    Scalar,
    Point,
}

impl Ty {
    fn is_scalar(self) -> bool {
        matches!(self, Ty::Index | Ty::Scalar)
    }
    fn describe(self) -> &'static str {
        match self {
            Ty::Index => "an integer",
            Ty::Scalar => "a number",
            Ty::Point => "a point",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Facet {
    Quad,
    /// Triangles: per-facet formulas over the corners' positions `P(i)` and
    /// normals `N(i)` (pn.md); no vertex stage and no stencil table.
    Tri,
}

impl Facet {
    pub fn sides(self) -> usize {
        match self {
            Facet::Quad => 4,
            Facet::Tri => 3,
        }
    }
}

/// Which faces a patch block applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Class {
    /// All four corners of valence 4.
    Ordinary,
    /// Some corner of valence ≠ 4.
    Extraordinary,
    /// Every face of a triangle scheme.
    Triangle,
}

impl Class {
    pub fn name(self) -> &'static str {
        match self {
            Class::Ordinary => "ordinary",
            Class::Extraordinary => "extraordinary",
            Class::Triangle => "triangle",
        }
    }
}

/// `const NAME = EXPR;`
#[derive(Clone, Debug)]
pub struct ConstDef {
    pub name: String,
    pub expr: Sym,
}

/// A vertex-stage definition.
#[derive(Clone, Debug)]
pub struct VertexDef {
    pub name: String,
    pub kind: DefKind,
    pub indexed: bool,
    pub ty: Ty,
    pub expr: Sym,
    pub span: Span,
}

impl VertexDef {
    /// Exported into the stencil table (everything but `let`).
    pub fn exported(&self) -> bool {
        matches!(self.kind, DefKind::Point | DefKind::Vector)
    }
}

/// A patch-stage definition (local or `out`).
#[derive(Clone, Debug)]
pub struct PatchDef {
    pub name: String,
    pub out: bool,
    pub indexed: bool,
    pub ty: Ty,
    pub expr: Sym,
    pub span: Span,
}

/// One `patch CLASS: FORM { … }` block.
#[derive(Clone, Debug)]
pub struct PatchClass {
    pub class: Class,
    pub form: Form,
    pub defs: Vec<PatchDef>,
    /// For each form slot, the index into `defs` of its `out` definition.
    pub slots: Vec<usize>,
    /// For each single (once per patch) slot, the index of its definition.
    pub singles: Vec<usize>,
}

impl PatchClass {
    /// An edge between an ordinary and an extraordinary face is one curve
    /// that both evaluate with the one shared edge evaluator, so every
    /// class of a scheme needs boundaries of the same degree: refuse `self`
    /// (its form named at `span`) beside an `earlier` class with another.
    fn check_boundary_degree(&self, earlier: &[PatchClass], span: Span) -> Result<(), SchemeError> {
        let Some(q) = earlier
            .iter()
            .find(|q| q.form.curve_points() != self.form.curve_points())
        else {
            return Ok(());
        };
        err(
            span,
            format!(
                "form `{}` has {}-point boundary curves but class `{}` uses `{}` with {}: \
                 the two faces of an edge evaluate one shared curve, so every class of a \
                 scheme needs boundaries of the same degree",
                self.form.name(),
                self.form.curve_points(),
                q.class.name(),
                q.form.name(),
                q.form.curve_points()
            ),
        )
    }
}

/// A checked scheme.
#[derive(Clone, Debug)]
pub struct Scheme {
    pub name: String,
    pub doc: String,
    pub facet: Facet,
    pub consts: Vec<ConstDef>,
    pub vertex: Vec<VertexDef>,
    /// `sector` blocks (at most one per kind); a kind without a block takes
    /// every definition from the virtual ring (docs/boundaries.md §3).
    pub sectors: Vec<SectorBlock>,
    pub patches: Vec<PatchClass>,
}

/// Index variable of per-corner definitions in the patch stage.
pub const CORNER_VAR: usize = 0;
/// Index variable of per-sector definitions in the vertex stage.
pub const SECTOR_VAR: usize = 0;

impl Scheme {
    /// Parse, resolve and check scheme source text.
    pub fn from_source(text: &str, max_valence: u32) -> Result<Scheme, SchemeError> {
        let ast = dsl::parse_str(text)?;
        Scheme::from_ast(&ast, max_valence)
    }

    /// Resolve and check a parsed scheme (shared by the proc macro).
    pub fn from_ast(ast: &SchemeAst, max_valence: u32) -> Result<Scheme, SchemeError> {
        let scheme = Resolver::default().scheme(ast)?;
        scheme.check(ast, max_valence)?;
        Ok(scheme)
    }

    /// Exported vertex-stage outputs, in table order.
    pub fn outputs(&self) -> impl Iterator<Item = (usize, &VertexDef)> {
        self.vertex.iter().enumerate().filter(|(_, d)| d.exported())
    }

    /// Rows the vertex stage produces for valence n (`a·n + b`).
    pub fn rows_per_valence(&self, n: u32) -> u32 {
        self.outputs()
            .map(|(_, d)| if d.indexed { n } else { 1 })
            .sum()
    }

    /// `(a, b)` with `rows_per_valence(n) = a·n + b`.
    pub fn rows_linear(&self) -> (u32, u32) {
        let a = self.outputs().filter(|(_, d)| d.indexed).count() as u32;
        let b = self.outputs().filter(|(_, d)| !d.indexed).count() as u32;
        (a, b)
    }

    /// First row of output `def` within a valence-n block: `a·n + b`.
    pub fn output_offset(&self, def: usize) -> (u32, u32) {
        let (mut a, mut b) = (0, 0);
        for (i, d) in self.outputs() {
            if i == def {
                break;
            }
            if d.indexed {
                a += 1;
            } else {
                b += 1;
            }
        }
        (a, b)
    }

    pub fn patch(&self, class: Class) -> Option<&PatchClass> {
        self.patches.iter().find(|p| p.class == class)
    }

    /// Per-valence constants at valence n, in declaration order.
    pub fn const_values(&self, n: u32) -> Vec<f64> {
        let mut vals = Vec::with_capacity(self.consts.len());
        for c in &self.consts {
            let env = ConstEnv {
                n: n as f64,
                consts: &vals,
            };
            let x = sym::eval(&c.expr, &env, &mut Vec::new()).scalar();
            vals.push(x);
        }
        vals
    }

    /// Every exported vertex-stage row at valence n, in table order, as
    /// `(output def, sector, weights over [p, p_0 .. p_{2n-1}])`.
    pub fn vertex_rows(&self, n: u32) -> Vec<(usize, u32, Vec<f64>)> {
        let env = VertexEnv::new(self, n);
        let mut out = Vec::new();
        for (i, d) in self.outputs() {
            let count = if d.indexed { n } else { 1 };
            for j in 0..count {
                let row = env.row(i, j);
                out.push((i, j, row));
            }
        }
        out
    }

    fn check(&self, ast: &SchemeAst, max_valence: u32) -> Result<(), SchemeError> {
        if max_valence < 4 {
            return Err(SchemeError::new(
                ast.name.span(),
                "max valence must be at least 4",
            ));
        }
        if self.facet == Facet::Tri {
            // Triangle schemes are per-facet formulas over positions and
            // normals, not stencils: there are no weights to sum.
            return Ok(());
        }
        for n in 3..=max_valence {
            let vals = self.const_values(n);
            for (c, x) in ast.consts.iter().zip(&vals) {
                if !x.is_finite() {
                    return Err(SchemeError::new(
                        c.name.span(),
                        format!("constant `{}` is not finite at valence {n} ({x})", c.name),
                    ));
                }
            }
            let env = VertexEnv::new(self, n);
            for (i, d) in self.outputs() {
                let count = if d.indexed { n } else { 1 };
                for j in 0..count {
                    self.check_row(i, j, &env.row(i, j), d.span, &format!("at valence {n}"))?;
                }
            }
        }
        self.check_sectors(max_valence)?;
        for (pc, past) in self.patches.iter().zip(&ast.patches) {
            self.check_patch(pc, past, max_valence)?;
        }
        Ok(())
    }

    /// Every sector row of every kind and size the table holds: finite,
    /// summing to 1 (points) or 0 (vectors), like the per-valence rows.
    fn check_sectors(&self, max_valence: u32) -> Result<(), SchemeError> {
        for kind in SectorKind::ALL {
            for m in 1..=max_sector_faces(max_valence) {
                for (i, j, row) in self.sector_rows(kind, m) {
                    let span = self
                        .sectors
                        .iter()
                        .find(|b| b.kind == kind)
                        .and_then(|b| b.overrides.iter().find(|o| o.def == i))
                        .map_or(self.vertex[i].span, |o| o.span);
                    let at = format!("in a {} sector of {m} faces", kind.name());
                    self.check_row(i, j, &row, span, &at)?;
                }
            }
        }
        Ok(())
    }

    /// One vertex-stage row of output `def` at position `j`: finite, and
    /// summing to 1 (a point) or 0 (a tangent vector) within
    /// [`AFFINE_TOLERANCE`]; `at` says where (valence or sector) for the error.
    fn check_row(
        &self,
        def: usize,
        j: u32,
        row: &[f64],
        span: Span,
        at: &str,
    ) -> Result<(), SchemeError> {
        let d = &self.vertex[def];
        let label = if d.indexed {
            format!("{}[{j}]", d.name)
        } else {
            d.name.clone()
        };
        if row.iter().any(|w| !w.is_finite()) {
            return Err(SchemeError::new(
                span,
                format!("row `{label}` has a non-finite weight {at}"),
            ));
        }
        let want = if d.kind == DefKind::Vector { 0.0 } else { 1.0 };
        let sum: f64 = row.iter().sum();
        if (sum - want).abs() > AFFINE_TOLERANCE {
            return Err(SchemeError::new(
                span,
                format!(
                    "row `{label}` weights sum to {sum} {at}, expected {want} ({})",
                    if want == 0.0 {
                        "a tangent vector"
                    } else {
                        "a point"
                    }
                ),
            ));
        }
        Ok(())
    }

    /// Patch-stage rows depend on the four corner valences; they are checked
    /// on every tuple of a grid of valences (3..=8 and the maximum for each
    /// corner; only valence 4 for ordinary patches), which covers every
    /// formula branch the constants can take while staying cheap enough
    /// for a proc macro.
    fn check_patch(
        &self,
        pc: &PatchClass,
        past: &dsl::PatchAst,
        max: u32,
    ) -> Result<(), SchemeError> {
        let mut set: Vec<u32> = (3..=8.min(max)).collect();
        if max > 8 {
            set.push(max);
        }
        let set = if pc.class == Class::Ordinary {
            vec![4]
        } else {
            set
        };
        let mut tuples = Vec::new();
        for &a in &set {
            for &b in &set {
                for &c in &set {
                    for &d in &set {
                        tuples.push([a, b, c, d]);
                    }
                }
            }
        }
        for vals in tuples {
            let env = PatchEnv::new(self, pc, vals);
            for (slot_i, &def_i) in pc.slots.iter().enumerate() {
                let d = &pc.defs[def_i];
                for corner in 0..4 {
                    let lin = env.def(def_i, Some(corner)).point();
                    let mut sum = 0.0;
                    for (key, w) in &lin {
                        if !w.is_finite() {
                            return Err(SchemeError::new(
                                d.span,
                                format!("`out {}[{corner}]` has a non-finite weight at valences {vals:?}", d.name),
                            ));
                        }
                        let (output, _, _) = unpack_corner_key(*key);
                        if self.vertex[output].kind != DefKind::Vector {
                            sum += w;
                        }
                    }
                    let (want, what) = match pc.form.slot_kind(slot_i) {
                        SlotKind::Point => (1.0, "a point"),
                        SlotKind::Vector => (0.0, "a tangent vector"),
                    };
                    if (sum - want).abs() > AFFINE_TOLERANCE {
                        return Err(SchemeError::new(
                            d.span,
                            format!(
                                "control point `{}[{corner}]` ({} slot {}) weights sum to {sum} at corner valences {vals:?}, expected {want} ({what})",
                                d.name,
                                pc.form.name(),
                                pc.form.slots()[slot_i]
                            ),
                        ));
                    }
                }
            }
        }
        let _ = past;
        Ok(())
    }
}

/// Keys of corner data in patch-stage weight vectors.
pub fn corner_key(output: usize, corner: usize, sector_offset: u32) -> u64 {
    ((output as u64) << 32) | ((corner as u64) << 24) | sector_offset as u64
}

pub fn unpack_corner_key(key: u64) -> (usize, usize, u32) {
    (
        (key >> 32) as usize,
        ((key >> 24) & 0xff) as usize,
        (key & 0xff_ffff) as u32,
    )
}

struct ConstEnv<'a> {
    n: f64,
    consts: &'a [f64],
}

impl Env for ConstEnv<'_> {
    fn valence(&self) -> f64 {
        self.n
    }
    fn sum_range(&self) -> u32 {
        self.n as u32
    }
    fn konst(&self, k: usize) -> f64 {
        self.consts.get(k).copied().unwrap_or(f64::NAN)
    }
    fn center(&self) -> Value {
        Value::Scalar(f64::NAN)
    }
    fn ring(&self, _: i64) -> Value {
        Value::Scalar(f64::NAN)
    }
    fn def(&self, _: usize, _: Option<i64>) -> Value {
        Value::Scalar(f64::NAN)
    }
}

/// Evaluates vertex-stage definitions at one valence; results are memoised
/// so `e[j] = (f[j-1] + f[j]) / 2` costs one lookup per reference.
struct VertexEnv<'a> {
    scheme: &'a Scheme,
    n: u32,
    consts: Vec<f64>,
    memo: std::cell::RefCell<BTreeMap<(usize, u32), Value>>,
}

impl<'a> VertexEnv<'a> {
    fn new(scheme: &'a Scheme, n: u32) -> Self {
        VertexEnv {
            scheme,
            n,
            consts: scheme.const_values(n),
            memo: Default::default(),
        }
    }

    fn value(&self, def: usize, j: u32) -> Value {
        if let Some(v) = self.memo.borrow().get(&(def, j)) {
            return v.clone();
        }
        let mut vars = Vec::new();
        sym::set_var(&mut vars, SECTOR_VAR, j as f64);
        let v = sym::eval(&self.scheme.vertex[def].expr, self, &mut vars);
        self.memo.borrow_mut().insert((def, j), v.clone());
        v
    }

    fn row(&self, def: usize, j: u32) -> Vec<f64> {
        let mut row = vec![0.0; 2 * self.n as usize + 1];
        for (slot, w) in self.value(def, j).point() {
            row[slot as usize] += w;
        }
        row
    }
}

impl Env for VertexEnv<'_> {
    fn valence(&self) -> f64 {
        self.n as f64
    }
    fn sum_range(&self) -> u32 {
        self.n
    }
    fn konst(&self, k: usize) -> f64 {
        self.consts.get(k).copied().unwrap_or(f64::NAN)
    }
    fn center(&self) -> Value {
        Value::unit(0)
    }
    fn ring(&self, idx: i64) -> Value {
        Value::unit(1 + idx.rem_euclid(2 * self.n as i64) as u64)
    }
    fn def(&self, def: usize, index: Option<i64>) -> Value {
        let j = index
            .map(|j| j.rem_euclid(self.n as i64) as u32)
            .unwrap_or(0);
        self.value(def, j)
    }
}

/// Evaluates patch-stage definitions for given corner valences: points are
/// weight vectors over corner data keys ([`corner_key`]).
pub struct PatchEnv<'a> {
    scheme: &'a Scheme,
    class: &'a PatchClass,
    valences: [u32; 4],
    consts: [Vec<f64>; 4],
}

impl<'a> PatchEnv<'a> {
    pub fn new(scheme: &'a Scheme, class: &'a PatchClass, valences: [u32; 4]) -> Self {
        let consts = valences.map(|n| scheme.const_values(n));
        PatchEnv {
            scheme,
            class,
            valences,
            consts,
        }
    }

    fn corner(c: i64) -> usize {
        c.rem_euclid(4) as usize
    }
}

impl Env for PatchEnv<'_> {
    fn valence(&self) -> f64 {
        f64::NAN
    }
    fn sum_range(&self) -> u32 {
        4
    }
    fn konst(&self, _: usize) -> f64 {
        f64::NAN
    }
    fn corner_const(&self, k: usize, corner: i64) -> f64 {
        self.consts[Self::corner(corner)]
            .get(k)
            .copied()
            .unwrap_or(f64::NAN)
    }
    fn corner_valence(&self, corner: i64) -> f64 {
        self.valences[Self::corner(corner)] as f64
    }
    fn center(&self) -> Value {
        Value::Scalar(f64::NAN)
    }
    fn ring(&self, _: i64) -> Value {
        Value::Scalar(f64::NAN)
    }
    fn def(&self, def: usize, index: Option<i64>) -> Value {
        let mut vars = Vec::new();
        if let Some(i) = index {
            sym::set_var(&mut vars, CORNER_VAR, Self::corner(i) as f64);
        }
        sym::eval(&self.class.defs[def].expr, self, &mut vars)
    }
    fn corner_data(&self, output: usize, corner: i64, offset: Option<i64>) -> Value {
        let c = Self::corner(corner);
        let n = self.valences[c] as i64;
        let off = offset.map(|o| o.rem_euclid(n) as u32).unwrap_or(0);
        let _ = &self.scheme;
        Value::unit(corner_key(output, c, off))
    }
}
