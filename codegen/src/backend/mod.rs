//! Printers: one writer per target, each walking the same [`Plan`](crate::plan::Plan)
//! and only spelling it. No printer computes, reorders or simplifies.

pub mod abi;
pub mod docs;
pub mod glsl;
pub mod hlsl;
pub mod rust;
pub mod wgsl;

use crate::plan::{FnRef, Function, Module, Plan, Resource};

/// An emission target.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Target {
    /// Rust source for the CPU path (glam `Vec3`).
    Rust,
    /// WGSL: compute construction + instanced vertex evaluation + compute evaluation.
    Wgsl,
    /// GLSL 450: vert/tesc/tese and compute shaders.
    Glsl,
    /// HLSL SM 5.0: hull/domain and compute shaders.
    Hlsl,
}

impl Target {
    pub const ALL: [Target; 4] = [Target::Rust, Target::Wgsl, Target::Glsl, Target::Hlsl];
    pub fn name(self) -> &'static str {
        match self {
            Target::Rust => "rust",
            Target::Wgsl => "wgsl",
            Target::Glsl => "glsl",
            Target::Hlsl => "hlsl",
        }
    }
    pub fn from_name(s: &str) -> Option<Target> {
        Target::ALL.into_iter().find(|t| t.name() == s)
    }
}

/// Resources a function touches, including through the functions it calls
/// (transitively), as `(resource, written)`, plus whether the stencil table
/// is read. Printers use this to decide which bindings/parameters a
/// function needs.
pub fn resources_of(plan: &Plan, module: &Module, f: &Function) -> (Vec<(Resource, bool)>, bool) {
    let mut res = f.resources();
    let mut table = f.reads_table();
    for callee in called(f) {
        let g = match callee {
            FnRef::Common(i) => &plan.common.functions[i],
            FnRef::Local(i) => &module.functions[i],
        };
        let (r, t) = if matches!(callee, FnRef::Common(_)) {
            resources_of(plan, &plan.common, g)
        } else {
            resources_of(plan, module, g)
        };
        for x in r {
            if !res.contains(&x) {
                res.push(x);
            }
        }
        table |= t;
    }
    res.sort();
    (res, table)
}

/// Functions called by `f`.
pub fn called(f: &Function) -> Vec<FnRef> {
    use crate::plan::{Expr, Stmt};
    fn expr(e: &Expr, out: &mut Vec<FnRef>) {
        match e {
            Expr::CallFn(r, xs) => {
                if !out.contains(r) {
                    out.push(*r);
                }
                xs.iter().for_each(|x| expr(x, out));
            }
            Expr::Call(_, xs) | Expr::Make(_, xs) => xs.iter().for_each(|x| expr(x, out)),
            Expr::Fetch(_, a) | Expr::ConstIndex(_, a) | Expr::Neg(a) | Expr::Field(a, _) => {
                expr(a, out)
            }
            Expr::Binary(_, a, b)
            | Expr::TableWeight(a, b)
            | Expr::Texel(_, a, b)
            | Expr::PatchSlot(a, b) => {
                expr(a, out);
                expr(b, out);
            }
            _ => {}
        }
    }
    fn stmts(s: &[Stmt], out: &mut Vec<FnRef>) {
        for s in s {
            match s {
                Stmt::Let(_, e) | Stmt::Var(_, e) | Stmt::Assign(_, e) | Stmt::Return(e) => {
                    expr(e, out)
                }
                Stmt::AssignField(_, _, e) => expr(e, out),
                Stmt::Store(_, i, v) => {
                    expr(i, out);
                    expr(v, out);
                }
                Stmt::If(c, a, b) => {
                    expr(c, out);
                    stmts(a, out);
                    stmts(b, out);
                }
                Stmt::IfDef(_, a, b) => {
                    stmts(a, out);
                    stmts(b, out);
                }
                Stmt::For(_, a, b, body) => {
                    expr(a, out);
                    expr(b, out);
                    stmts(body, out);
                }
                Stmt::Call(r, xs) => {
                    if !out.contains(r) {
                        out.push(*r);
                    }
                    xs.iter().for_each(|x| expr(x, out));
                }
                Stmt::Output(_, e) => expr(e, out),
                Stmt::Comment(_) => {}
                Stmt::StorePatchSlot(a, b, v) => {
                    expr(a, out);
                    expr(b, out);
                    expr(v, out);
                }
            }
        }
    }
    let mut out = Vec::new();
    stmts(&f.body, &mut out);
    out
}

/// Operator spelling: identical in Rust, WGSL, GLSL and HLSL (all C-family).
pub fn binop(op: crate::plan::BinOp) -> &'static str {
    use crate::plan::BinOp;
    match op {
        BinOp::Add => "+",
        BinOp::Sub => "-",
        BinOp::Mul => "*",
        BinOp::Div => "/",
        BinOp::Rem => "%",
        BinOp::Eq => "==",
        BinOp::Ne => "!=",
        BinOp::Lt => "<",
        BinOp::Le => "<=",
        BinOp::Gt => ">",
        BinOp::Ge => ">=",
        BinOp::And => "&&",
        BinOp::Or => "||",
    }
}

/// The largest of the adaptive factors `f[e]` of `edges` (an inside
/// factor, [`crate::lower::hw_factor_edges`]): `max(max(f[a], f[b]), f[c])`,
/// the same spelling in GLSL and HLSL.
pub fn max_of_factors(edges: &[usize]) -> String {
    let mut it = edges.iter();
    let mut s = it.next().map(|e| format!("f[{e}]")).unwrap_or_default();
    for e in it {
        s = format!("max({s}, f[{e}])");
    }
    s
}

/// Lines of a dispatch over a scheme's patch classes, in C-family syntax
/// (WGSL, GLSL, HLSL): `if (class == 0u) { s0 } else if … else { sN }`, the
/// last class unconditional, like the Plan's own `eval` dispatch. One
/// statement per class; a single class needs no test.
pub fn class_chain_lines(class: &str, stmts: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    for (k, s) in stmts.iter().enumerate() {
        if stmts.len() == 1 {
            out.push(s.clone());
        } else if k == 0 {
            out.push(format!("if ({class} == {k}u) {{"));
            out.push(format!("    {s}"));
        } else if k + 1 < stmts.len() {
            out.push(format!("}} else if ({class} == {k}u) {{"));
            out.push(format!("    {s}"));
        } else {
            out.push("} else {".into());
            out.push(format!("    {s}"));
            out.push("}".into());
        }
    }
    out
}

/// The header every generated file starts with (after the target's comment
/// marker): generator version and the command that made it.
pub fn header_lines(command: &str) -> Vec<String> {
    // One line, whatever the caller passed: a newline would end the comment.
    let command: String = command
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    vec![
        format!(
            "Generated by tessgen {} — do not edit.",
            env!("CARGO_PKG_VERSION")
        ),
        format!("Command: {command}"),
    ]
}
