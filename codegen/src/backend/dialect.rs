//! The one spelling layer of the printers: how a Plan expression reads in a
//! C-like language, written once. A target is a [`Dialect`]: its type
//! names, literals, identifier rules and builtin names, plus the few
//! expressions only it spells its own way (memory, stage inputs). The walk
//! over the expression tree, the operator spelling, full parenthesisation,
//! calls, fields, constructors and the shading-language builtins live here,
//! so WGSL, GLSL, HLSL and Rust cannot drift apart in how they print the
//! same Plan, and a new target (MSL, say) is one more `impl Dialect`.
//!
//! An implementor is the printer's context for one function (module,
//! function, local names); [`expr`] calls back into it for the leaves.

use super::binop;
use crate::plan::*;

/// One target's spelling of Plan expressions, for one function.
pub trait Dialect: Sized {
    /// The whole plan (callees, struct declarations).
    fn plan(&self) -> &Plan;
    /// The module of the function being printed.
    fn module(&self) -> &Module;
    /// The function being printed.
    fn function(&self) -> &Function;
    /// A name the target accepts (reserved words renamed).
    fn ident(&self, name: &str) -> String;
    /// Name of local `id` in the function being printed.
    fn local(&self, id: LocalId) -> String;
    /// An `f32` literal.
    fn f32_lit(&self, x: f32) -> String;
    /// A `u32` literal.
    fn u32_lit(&self, x: u32) -> String {
        format!("{x}u")
    }
    /// Type names of the builtin constructors and casts.
    fn f32_ty(&self) -> &'static str;
    fn u32_ty(&self) -> &'static str;
    fn vec2_ty(&self) -> &'static str;
    fn vec3_ty(&self) -> &'static str;
    /// The target's own spelling of a builtin, where it is not the common
    /// shading-language one of [`builtin`] (`None`: the common one).
    fn builtin_override(&self, _b: Builtin, _a: &[String]) -> Option<String> {
        None
    }
    /// `CONST[index]`.
    fn const_index(&self, name: String, index: String) -> String {
        format!("{name}[{index}]")
    }
    /// Call of Plan function `callee` (found through `r`) with the spelled
    /// arguments: targets that pass hidden arguments (HLSL's patch-local
    /// arrays, Rust's inputs) add them here.
    fn call(&self, _r: FnRef, callee: &Function, args: Vec<String>) -> String {
        format!("{}({})", self.ident(&callee.name), args.join(", "))
    }
    /// A value of struct `s` from its fields, in order.
    fn make(&self, s: usize, args: Vec<String>) -> String {
        let name = &self.plan().common.structs[s].name;
        format!("{}({})", self.ident(name), args.join(", "))
    }
    /// The binding part of a declaration, before ` = value` (`let x: T`,
    /// `var x: T`, `T x`); `mutable` for [`Stmt::Var`].
    fn decl(&self, id: LocalId, mutable: bool) -> String;
    /// The head of an `if`.
    fn if_head(&self, c: &Expr) -> String {
        format!("if {} {{", expr(self, c))
    }
    /// The head of a loop over `v = start; v < end` by `step` (`None`: the
    /// unit step of [`Stmt::For`], `Some`: [`Stmt::ForStep`]): C's `for`
    /// with the mutable declaration of `v` (WGSL, GLSL).
    fn for_head(&self, id: LocalId, start: String, end: String, step: Option<String>) -> String {
        let v = self.local(id);
        let next = match step {
            None => format!("({v} + 1u)"),
            Some(step) => format!("{v} + {step}"),
        };
        let decl = self.decl(id, true);
        format!("for ({decl} = {start}; {v} < {end}; {v} = {next}) {{")
    }
    /// Whether `#ifdef` reaches the compiler (GLSL, HLSL); otherwise
    /// [`Stmt::IfDef`] prints its default branch alone.
    fn preprocessor(&self) -> bool {
        false
    }
    /// The statements each target spells its own way: memory writes
    /// ([`Stmt::Store`], [`Stmt::StoreFloat`], [`Stmt::StorePatchSlot`],
    /// [`Stmt::StorePatchCp`], [`Stmt::ClearPatchSlot`]), patch-local
    /// arrays ([`Stmt::PatchLocal`]), stage outputs and barriers.
    fn special_stmt(&self, s: &Stmt, out: &mut Lines);
    /// Memory, stage inputs and the other expressions each target spells
    /// its own way: [`Expr::Fetch`], [`Expr::Float`], [`Expr::TableWeight`],
    /// [`Expr::Texel`], [`Expr::Stage`], [`Expr::PatchSlot`],
    /// [`Expr::PatchCp`], [`Expr::Columns`].
    fn special(&self, e: &Expr) -> String;
}

/// `e` in dialect `d`: every binary parenthesised as the Plan associates
/// it, nothing reordered or simplified.
pub fn expr<D: Dialect>(d: &D, e: &Expr) -> String {
    match e {
        Expr::F32(x) => d.f32_lit(*x),
        Expr::U32(x) => d.u32_lit(*x),
        Expr::Local(id) => d.local(*id),
        Expr::Const(c) => d.ident(&d.module().consts[*c].name),
        Expr::ConstIndex(c, i) => d.const_index(d.ident(&d.module().consts[*c].name), expr(d, i)),
        Expr::Binary(op, a, b) => format!("({} {} {})", expr(d, a), binop(*op), expr(d, b)),
        Expr::Neg(a) => format!("(-{})", expr(d, a)),
        Expr::Call(b, xs) => builtin(d, *b, &args(d, xs)),
        Expr::CallFn(r, xs) => {
            let callee = match r {
                FnRef::Common(i) => &d.plan().common.functions[*i],
                FnRef::Local(i) => &d.module().functions[*i],
            };
            d.call(*r, callee, args(d, xs))
        }
        Expr::Field(a, k) => {
            let t = d.plan().expr_ty(d.module(), d.function(), a);
            let field = match t {
                Some(Ty::Struct(i)) => d.ident(&d.plan().common.structs[i].fields[*k].0),
                _ => format!("field{k}"),
            };
            format!("{}.{field}", expr(d, a))
        }
        Expr::Make(s, xs) => d.make(*s, args(d, xs)),
        Expr::Named(n) => d.ident(n.name()),
        Expr::NamedIndex(n, i) => d.const_index(d.ident(n.name()), expr(d, i)),
        Expr::Fetch(..)
        | Expr::PatchCp(..)
        | Expr::Columns(_)
        | Expr::Float(..)
        | Expr::TableWeight(..)
        | Expr::Texel(..)
        | Expr::Stage(_)
        | Expr::PatchSlot(..) => d.special(e),
    }
}

fn args<D: Dialect>(d: &D, xs: &[Expr]) -> Vec<String> {
    xs.iter().map(|x| expr(d, x)).collect()
}

/// A builtin with spelled arguments `a`: the target's override, else the
/// spelling WGSL, GLSL and HLSL share (functions by their common names,
/// casts and constructors by the target's type names, swizzles).
pub fn builtin<D: Dialect>(d: &D, b: Builtin, a: &[String]) -> String {
    if let Some(s) = d.builtin_override(b, a) {
        return s;
    }
    let call = |name: &str| format!("{name}({})", a.join(", "));
    match b {
        Builtin::F32FromU32 => call(d.f32_ty()),
        Builtin::U32FromF32 | Builtin::U32FromBool => call(d.u32_ty()),
        Builtin::Vec3 => call(d.vec3_ty()),
        Builtin::Vec2 => call(d.vec2_ty()),
        Builtin::Component(k) => format!("{}.{}", a[0], ["x", "y", "z"][k as usize]),
        Builtin::Sqrt => call("sqrt"),
        Builtin::Cos => call("cos"),
        Builtin::Sin => call("sin"),
        Builtin::Dot => call("dot"),
        Builtin::Cross => call("cross"),
        Builtin::Round => call("round"),
        Builtin::Floor => call("floor"),
        Builtin::Max => call("max"),
        Builtin::Min => call("min"),
        Builtin::Abs => call("abs"),
        Builtin::Normalize => call("normalize"),
        Builtin::Fwidth => call("fwidth"),
        Builtin::CountTrailingZeros => call("countTrailingZeros"),
        // Each shader dialect spells the matrix product (an override);
        // nothing else reaches a stage output.
        Builtin::Project => unreachable!("Builtin::Project is spelled by each shader dialect"),
    }
}

/// Printed lines: four spaces per indentation level, empty lines bare,
/// preprocessor lines at column 0.
pub struct Lines {
    pub out: String,
    pub indent: usize,
}

impl Lines {
    pub fn line(&mut self, s: &str) {
        if !s.is_empty() {
            for _ in 0..self.indent {
                self.out.push_str("    ");
            }
            self.out.push_str(s);
        }
        self.out.push('\n');
    }
    /// A line at column 0.
    pub fn raw(&mut self, s: &str) {
        self.out.push_str(s);
        self.out.push('\n');
    }
    /// `// ` comment lines.
    pub fn doc(&mut self, doc: &str) {
        for l in doc.lines() {
            self.line(format!("// {l}").trim_end());
        }
    }
    fn block<D: Dialect>(&mut self, d: &D, body: &[Stmt]) {
        self.indent += 1;
        stmts(d, body, self);
        self.indent -= 1;
    }
}

/// `body` in dialect `d`, the statements in Plan order.
pub fn stmts<D: Dialect>(d: &D, body: &[Stmt], out: &mut Lines) {
    let x = |e: &Expr| expr(d, e);
    for s in body {
        match s {
            Stmt::Let(id, e) | Stmt::Var(id, e) => {
                let decl = d.decl(*id, matches!(s, Stmt::Var(..)));
                out.line(&format!("{decl} = {};", x(e)));
            }
            Stmt::Assign(id, e) => out.line(&format!("{} = {};", d.local(*id), x(e))),
            Stmt::AssignField(id, k, e) => {
                let field = match &d.function().locals[id.0].ty {
                    Ty::Struct(i) => d.ident(&d.plan().common.structs[*i].fields[*k].0),
                    _ => format!("field{k}"),
                };
                out.line(&format!("{}.{field} = {};", d.local(*id), x(e)));
            }
            Stmt::If(c, a, b) => {
                out.line(&d.if_head(c));
                out.block(d, a);
                if !b.is_empty() {
                    out.line("} else {");
                    out.block(d, b);
                }
                out.line("}");
            }
            Stmt::IfDef(def, a, b) if d.preprocessor() => {
                let (open, first, second) = if a.is_empty() {
                    (format!("#ifndef {}", def.name()), b, &a[..])
                } else {
                    (format!("#ifdef {}", def.name()), a, &b[..])
                };
                out.raw(&open);
                stmts(d, first, out);
                if !second.is_empty() {
                    out.raw("#else");
                    stmts(d, second, out);
                }
                out.raw("#endif");
            }
            // No preprocessor: always the default branch.
            Stmt::IfDef(_, _, b) => stmts(d, b, out),
            Stmt::For(id, a, b, body) => {
                out.line(&d.for_head(*id, x(a), x(b), None));
                out.block(d, body);
                out.line("}");
            }
            Stmt::ForStep(id, a, b, step, body) => {
                out.line(&d.for_head(*id, x(a), x(b), Some(x(step))));
                out.block(d, body);
                out.line("}");
            }
            Stmt::Return(e) => out.line(&format!("return {};", x(e))),
            Stmt::ReturnVoid => out.line("return;"),
            Stmt::Call(r, xs) => out.line(&format!("{};", x(&Expr::CallFn(*r, xs.clone())))),
            Stmt::Comment(c) => out.doc(c),
            Stmt::Store(..)
            | Stmt::StoreFloat(..)
            | Stmt::StorePatchSlot(..)
            | Stmt::StorePatchCp(..)
            | Stmt::ClearPatchSlot(_)
            | Stmt::PatchLocal
            | Stmt::Output(..)
            | Stmt::Barrier(_) => d.special_stmt(s, out),
        }
    }
}
