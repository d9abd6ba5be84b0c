//! The symbolic IR: weight expressions and point expressions of a scheme.
//!
//! A [`Sym`] is either scalar-valued (numbers, the valence, per-valence
//! constants, index arithmetic) or point-valued (the ring centre `p`, ring
//! points `p[k]`, vertex-stage outputs, corner data). Point-valued
//! expressions are always affine combinations; [`eval`] turns them into
//! weight vectors ([`Value::Point`]) keyed by whatever the points are in the
//! current stage (ring slots in the vertex stage, corner data in the patch
//! stage). Everything here is f64: precision is spent once, when the tables
//! are built, and rounded to f32 exactly once.

use std::collections::BTreeMap;

/// Scalar functions the language knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Cos,
    Sin,
    Sqrt,
}

impl Func {
    pub fn from_name(name: &str) -> Option<Func> {
        match name {
            "cos" => Some(Func::Cos),
            "sin" => Some(Func::Sin),
            "sqrt" => Some(Func::Sqrt),
            _ => None,
        }
    }
    /// Evaluate in f64. Sines and cosines within a few ulps of a multiple of
    /// ½ are snapped to it, so `cos(2π/4)` is exactly 0 and `cos(2π/3)`
    /// exactly −½ (pccm.md §2: exact values where they exist keep the
    /// valence-4 identities bit-exact).
    pub fn apply(self, x: f64) -> f64 {
        let snap = |y: f64| {
            let h = (2.0 * y).round() / 2.0;
            if (y - h).abs() < 1e-15 {
                h
            } else {
                y
            }
        };
        match self {
            Func::Cos => snap(x.cos()),
            Func::Sin => snap(x.sin()),
            Func::Sqrt => x.sqrt(),
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Func::Cos => "cos",
            Func::Sin => "sin",
            Func::Sqrt => "sqrt",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CmpOp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl CmpOp {
    pub fn apply(self, a: f64, b: f64) -> bool {
        match self {
            CmpOp::Eq => a == b,
            CmpOp::Ne => a != b,
            CmpOp::Lt => a < b,
            CmpOp::Le => a <= b,
            CmpOp::Gt => a > b,
            CmpOp::Ge => a >= b,
        }
    }
}

/// A symbolic expression. Index variables (`j`, `i`, summation variables)
/// are numbered per definition; `Var(k)` reads slot `k` of the environment.
#[derive(Clone, Debug, PartialEq)]
pub enum Sym {
    Num(f64),
    /// Triangle schemes: corner `corner`'s position `P(i)` or unit normal
    /// `N(i)`. Not linear stencils (pn.md): never evaluated symbolically.
    CornerInput {
        input: Input,
        corner: Box<Sym>,
    },
    /// `dot(a, b)` of two vectors (triangle schemes).
    Dot(Box<Sym>, Box<Sym>),
    /// `normalize(a)` (triangle schemes).
    Normalize(Box<Sym>),
    /// The vertex's own valence `n` (vertex stage and constants).
    Valence,
    /// `m`, the number of faces of the sector being evaluated (`sector`
    /// blocks only; docs/boundaries.md §3).
    SectorFaces,
    /// An index variable.
    Var(usize),
    /// A per-valence constant at the vertex's own valence (vertex stage).
    Const(usize),
    /// A per-valence constant at a corner's valence: `c(i + 1)`.
    CornerConst {
        konst: usize,
        corner: Box<Sym>,
    },
    /// A corner's valence: `n(i)`.
    CornerValence(Box<Sym>),
    Neg(Box<Sym>),
    Bin(BinOp, Box<Sym>, Box<Sym>),
    Func(Func, Box<Sym>),
    /// `if a OP b { x } else { y }` (constants and the vertex stage): decided
    /// when the row is evaluated, per valence, sector size and index binding
    /// (`if k < m { … }` inside `sum(k, …)` selects terms per `k`).
    If {
        op: CmpOp,
        a: Box<Sym>,
        b: Box<Sym>,
        then: Box<Sym>,
        other: Box<Sym>,
    },
    /// `sum(k, body)`: k over 0..n (vertex stage) or 0..4 (patch stage).
    Sum {
        var: usize,
        body: Box<Sym>,
    },
    /// The ring centre `p`.
    Center,
    /// A ring point `p[idx]`, idx taken mod 2n.
    Ring(Box<Sym>),
    /// Another definition of the same stage, `f[j - 1]` or `gstar`.
    Def {
        def: usize,
        index: Option<Box<Sym>>,
    },
    /// In a `sector` block's override of vertex definition `def`, a read of
    /// that same name: the scheme's own definition (the one the override
    /// replaces), evaluated on the virtual ring, e.g. `t[j] = if m < 3 { t[j] }
    /// else { … }`.
    Inherited {
        def: usize,
        index: Option<Box<Sym>>,
    },
    /// Vertex-stage output of a corner: `t(i, 1)` = output `t` at corner i,
    /// sector `j_i + 1`; `v(i)` for single outputs (offset `None`).
    CornerData {
        output: usize,
        corner: Box<Sym>,
        offset: Option<Box<Sym>>,
    },
}

/// Value of an expression: a scalar or an affine combination of points.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Scalar(f64),
    Point(BTreeMap<u64, f64>),
}

impl Value {
    pub fn scalar(&self) -> f64 {
        match self {
            Value::Scalar(x) => *x,
            Value::Point(_) => f64::NAN,
        }
    }
    pub fn point(self) -> BTreeMap<u64, f64> {
        match self {
            Value::Point(m) => m,
            Value::Scalar(_) => BTreeMap::new(),
        }
    }
    pub fn unit(key: u64) -> Value {
        Value::Point(BTreeMap::from([(key, 1.0)]))
    }
}

fn combine(a: BTreeMap<u64, f64>, b: BTreeMap<u64, f64>, sb: f64) -> BTreeMap<u64, f64> {
    let mut out = a;
    for (k, w) in b {
        *out.entry(k).or_insert(0.0) += sb * w;
    }
    out
}

fn scale(a: BTreeMap<u64, f64>, s: f64) -> BTreeMap<u64, f64> {
    a.into_iter().map(|(k, w)| (k, w * s)).collect()
}

/// Everything an evaluation needs from its stage.
pub trait Env {
    /// Valence `n` of the vertex being evaluated (vertex stage).
    fn valence(&self) -> f64;
    /// Range of `sum(k, …)`.
    fn sum_range(&self) -> u32;
    fn konst(&self, k: usize) -> f64;
    /// Patch stage only: a per-valence constant at a corner's valence (NaN
    /// elsewhere).
    fn corner_const(&self, _k: usize, _corner: i64) -> f64 {
        f64::NAN
    }
    /// Patch stage only: a corner's valence (NaN elsewhere).
    fn corner_valence(&self, _corner: i64) -> f64 {
        f64::NAN
    }
    fn center(&self) -> Value;
    fn ring(&self, idx: i64) -> Value;
    fn def(&self, def: usize, index: Option<i64>) -> Value;
    /// Patch stage only: a corner's vertex-stage output (NaN elsewhere).
    fn corner_data(&self, _output: usize, _corner: i64, _offset: Option<i64>) -> Value {
        Value::Scalar(f64::NAN)
    }
    /// [`Sym::Inherited`]: the scheme's own definition `def` where a sector
    /// override replaces it (`sector` blocks); NaN elsewhere.
    fn inherited(&self, _def: usize, _index: Option<i64>) -> Value {
        Value::Scalar(f64::NAN)
    }
    /// Faces `m` of the sector being evaluated (`sector` blocks); NaN elsewhere.
    fn sector_faces(&self) -> f64 {
        f64::NAN
    }
}

/// Evaluate `s` with index variables `vars` (slot `k` = value of `Var(k)`).
/// A per-corner input of a triangle scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Input {
    /// `P(i)`: the corner's position.
    Position,
    /// `N(i)`: the corner's unit normal.
    Normal,
    /// `Delta(i)`: the corner's crease vector Δ (pn.md §3; zero = smooth).
    Crease,
    /// `tension(i)`: θ of the corner's vertex.
    Tension,
    /// `sharpness(i)`: σ of the corner's vertex.
    Sharpness,
    /// `bias(i)`: β of the corner's vertex.
    Bias,
    /// `creased(i)`: 1 when the corner's vertex has a non-null Δ, else 0
    /// (exact, so products of two flags select crease edges exactly).
    Creased,
    /// `side(i)`: ±1, which of the vertex's two crease normals this
    /// triangle uses (a per-triangle-corner value, not per vertex).
    Side,
}

impl Input {
    /// Every input, in DSL order.
    pub const ALL: [Input; 8] = [
        Input::Position,
        Input::Normal,
        Input::Crease,
        Input::Tension,
        Input::Sharpness,
        Input::Bias,
        Input::Creased,
        Input::Side,
    ];

    /// The DSL spelling: `name(corner)`.
    pub fn dsl_name(self) -> &'static str {
        match self {
            Input::Position => "P",
            Input::Normal => "N",
            Input::Crease => "Delta",
            Input::Tension => "tension",
            Input::Sharpness => "sharpness",
            Input::Bias => "bias",
            Input::Creased => "creased",
            Input::Side => "side",
        }
    }

    /// A vector (`P`, `N`, `Delta`) or a scalar.
    pub fn is_vector(self) -> bool {
        matches!(self, Input::Position | Input::Normal | Input::Crease)
    }
}

pub fn eval(s: &Sym, env: &dyn Env, vars: &mut Vec<f64>) -> Value {
    use Value::*;
    match s {
        Sym::Num(x) => Scalar(*x),
        // Non-linear triangle-scheme terms have no weight-vector value.
        Sym::CornerInput { .. } | Sym::Dot(..) | Sym::Normalize(_) => Scalar(f64::NAN),
        Sym::Valence => Scalar(env.valence()),
        Sym::SectorFaces => Scalar(env.sector_faces()),
        Sym::Var(k) => Scalar(vars.get(*k).copied().unwrap_or(f64::NAN)),
        Sym::Const(k) => Scalar(env.konst(*k)),
        Sym::CornerConst { konst, corner } => {
            let c = eval_index(corner, env, vars);
            Scalar(env.corner_const(*konst, c))
        }
        Sym::CornerValence(corner) => {
            let c = eval_index(corner, env, vars);
            Scalar(env.corner_valence(c))
        }
        Sym::Neg(a) => match eval(a, env, vars) {
            Scalar(x) => Scalar(-x),
            Point(m) => Point(scale(m, -1.0)),
        },
        Sym::Bin(op, a, b) => {
            let (a, b) = (eval(a, env, vars), eval(b, env, vars));
            match (op, a, b) {
                (BinOp::Add, Scalar(x), Scalar(y)) => Scalar(x + y),
                (BinOp::Sub, Scalar(x), Scalar(y)) => Scalar(x - y),
                (BinOp::Mul, Scalar(x), Scalar(y)) => Scalar(x * y),
                (BinOp::Div, Scalar(x), Scalar(y)) => Scalar(x / y),
                (BinOp::Add, Point(x), Point(y)) => Point(combine(x, y, 1.0)),
                (BinOp::Sub, Point(x), Point(y)) => Point(combine(x, y, -1.0)),
                (BinOp::Mul, Scalar(s), Point(m)) | (BinOp::Mul, Point(m), Scalar(s)) => {
                    Point(scale(m, s))
                }
                (BinOp::Div, Point(m), Scalar(s)) => Point(scale(m, 1.0 / s)),
                // Ill-typed combinations are rejected by the type checker.
                _ => Scalar(f64::NAN),
            }
        }
        Sym::Func(f, a) => Scalar(f.apply(eval(a, env, vars).scalar())),
        Sym::If {
            op,
            a,
            b,
            then,
            other,
        } => {
            let (a, b) = (eval(a, env, vars).scalar(), eval(b, env, vars).scalar());
            if op.apply(a, b) {
                eval(then, env, vars)
            } else {
                eval(other, env, vars)
            }
        }
        Sym::Sum { var, body } => {
            let n = env.sum_range();
            let mut acc: Option<Value> = None;
            for k in 0..n {
                set_var(vars, *var, k as f64);
                let v = eval(body, env, vars);
                acc = Some(match (acc, v) {
                    (None, v) => v,
                    (Some(Scalar(x)), Scalar(y)) => Scalar(x + y),
                    (Some(Point(x)), Point(y)) => Point(combine(x, y, 1.0)),
                    _ => Scalar(f64::NAN),
                });
            }
            acc.unwrap_or(Scalar(0.0))
        }
        Sym::Center => env.center(),
        Sym::Ring(idx) => env.ring(eval_index(idx, env, vars)),
        Sym::Def { def, index } => {
            let idx = index.as_ref().map(|i| eval_index(i, env, vars));
            env.def(*def, idx)
        }
        Sym::Inherited { def, index } => {
            let idx = index.as_ref().map(|i| eval_index(i, env, vars));
            env.inherited(*def, idx)
        }
        Sym::CornerData {
            output,
            corner,
            offset,
        } => {
            let c = eval_index(corner, env, vars);
            let o = offset.as_ref().map(|o| eval_index(o, env, vars));
            env.corner_data(*output, c, o)
        }
    }
}

/// Every definition `s` reads directly (`Sym::Def`), in any order. A
/// [`Sym::Inherited`] read is not listed (its indices are walked): it is the
/// overridden definition's own expression, which reads only earlier ones.
pub fn defs_read(s: &Sym) -> Vec<usize> {
    fn walk(s: &Sym, out: &mut Vec<usize>) {
        match s {
            Sym::Def { def, index } => {
                out.push(*def);
                if let Some(i) = index {
                    walk(i, out);
                }
            }
            Sym::Inherited { index, .. } => {
                if let Some(i) = index {
                    walk(i, out);
                }
            }
            Sym::Neg(a) | Sym::Func(_, a) | Sym::Normalize(a) | Sym::Ring(a) => walk(a, out),
            Sym::CornerValence(a) => walk(a, out),
            Sym::CornerConst { corner, .. } | Sym::CornerInput { corner, .. } => walk(corner, out),
            Sym::Bin(_, a, b) | Sym::Dot(a, b) => {
                walk(a, out);
                walk(b, out);
            }
            Sym::If {
                a, b, then, other, ..
            } => {
                for x in [a, b, then, other] {
                    walk(x, out);
                }
            }
            Sym::Sum { body, .. } => walk(body, out),
            Sym::CornerData { corner, offset, .. } => {
                walk(corner, out);
                if let Some(o) = offset {
                    walk(o, out);
                }
            }
            Sym::Num(_)
            | Sym::Valence
            | Sym::SectorFaces
            | Sym::Var(_)
            | Sym::Const(_)
            | Sym::Center => {}
        }
    }
    let mut out = Vec::new();
    walk(s, &mut out);
    out
}

pub fn set_var(vars: &mut Vec<f64>, k: usize, x: f64) {
    if vars.len() <= k {
        vars.resize(k + 1, f64::NAN);
    }
    vars[k] = x;
}

/// Evaluate an index expression; indices are integers by construction
/// (the type checker only admits integer arithmetic in index position).
pub fn eval_index(s: &Sym, env: &dyn Env, vars: &mut Vec<f64>) -> i64 {
    eval(s, env, vars).scalar().round() as i64
}

/// Substitute index variable `var` by the integer `value` and fold what
/// becomes constant. Used to unroll per-corner definitions.
pub fn substitute(s: &Sym, var: usize, value: i64) -> Sym {
    let sub = |x: &Sym| Box::new(substitute(x, var, value));
    let out = match s {
        Sym::Var(k) if *k == var => Sym::Num(value as f64),
        Sym::Num(_)
        | Sym::Valence
        | Sym::SectorFaces
        | Sym::Var(_)
        | Sym::Const(_)
        | Sym::Center => s.clone(),
        Sym::CornerConst { konst, corner } => Sym::CornerConst {
            konst: *konst,
            corner: sub(corner),
        },
        Sym::CornerValence(c) => Sym::CornerValence(sub(c)),
        Sym::CornerInput { input, corner } => Sym::CornerInput {
            input: *input,
            corner: sub(corner),
        },
        Sym::Dot(a, b) => Sym::Dot(sub(a), sub(b)),
        Sym::Normalize(a) => Sym::Normalize(sub(a)),
        Sym::Neg(a) => Sym::Neg(sub(a)),
        Sym::Bin(op, a, b) => Sym::Bin(*op, sub(a), sub(b)),
        Sym::Func(f, a) => Sym::Func(*f, sub(a)),
        Sym::If {
            op,
            a,
            b,
            then,
            other,
        } => Sym::If {
            op: *op,
            a: sub(a),
            b: sub(b),
            then: sub(then),
            other: sub(other),
        },
        Sym::Sum { var: v, body } => Sym::Sum {
            var: *v,
            body: sub(body),
        },
        Sym::Ring(i) => Sym::Ring(sub(i)),
        Sym::Def { def, index } => Sym::Def {
            def: *def,
            index: index.as_deref().map(sub),
        },
        Sym::Inherited { def, index } => Sym::Inherited {
            def: *def,
            index: index.as_deref().map(sub),
        },
        Sym::CornerData {
            output,
            corner,
            offset,
        } => Sym::CornerData {
            output: *output,
            corner: sub(corner),
            offset: offset.as_deref().map(sub),
        },
    };
    fold_index(out)
}

/// Fold integer arithmetic on literals (`0 + 1` → `1`) so unrolled corner
/// indices become plain numbers.
fn fold_index(s: Sym) -> Sym {
    if let Sym::Bin(op, a, b) = &s {
        if let (Sym::Num(x), Sym::Num(y)) = (a.as_ref(), b.as_ref()) {
            return Sym::Num(match op {
                BinOp::Add => x + y,
                BinOp::Sub => x - y,
                BinOp::Mul => x * y,
                BinOp::Div => x / y,
            });
        }
    }
    if let Sym::Neg(a) = &s {
        if let Sym::Num(x) = a.as_ref() {
            return Sym::Num(-x);
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::Func;

    #[test]
    fn trig_snaps_to_exact_values() {
        let pi = std::f64::consts::PI;
        assert_eq!(Func::Cos.apply(2.0 * pi / 4.0), 0.0);
        assert_eq!(Func::Cos.apply(2.0 * pi / 3.0), -0.5);
        assert_eq!(Func::Cos.apply(2.0 * pi / 6.0), 0.5);
        assert_eq!(Func::Sin.apply(2.0 * pi / 4.0), 1.0);
        assert_eq!(Func::Cos.apply(2.0 * pi / 5.0), (2.0 * pi / 5.0).cos());
    }
}
