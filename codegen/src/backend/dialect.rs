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
    /// Memory, stage inputs and the other expressions each target spells
    /// its own way: [`Expr::Fetch`], [`Expr::Float`], [`Expr::TableWeight`],
    /// [`Expr::Texel`], [`Expr::Stage`], [`Expr::PatchSlot`].
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
        Expr::Fetch(..)
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
    }
}
