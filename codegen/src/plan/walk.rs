//! The one traversal of Plan code ([`walk()`]), which the analyses
//! (`Function::resources`, `reads_table`, `called`) and the tests share.

use super::*;

/// A statement or an expression met by [`walk()`].
#[derive(Clone, Copy, Debug)]
pub enum Node<'a> {
    Stmt(&'a Stmt),
    Expr(&'a Expr),
}

/// The one traversal of Plan code: every statement of `body` (nested
/// blocks too), then each of its expressions and their subexpressions, in
/// source order, parents before children. Analyses that need "every fetch",
/// "every call" and the like are a match over [`Node`] instead of another
/// hand-written recursion over every variant.
pub fn walk<'a>(body: &'a [Stmt], f: &mut dyn FnMut(Node<'a>)) {
    for s in body {
        f(Node::Stmt(s));
        match s {
            Stmt::Let(_, e)
            | Stmt::Var(_, e)
            | Stmt::Assign(_, e)
            | Stmt::Return(e)
            | Stmt::AssignField(_, _, e)
            | Stmt::Output(_, e) => walk_expr(e, f),
            Stmt::Store(_, i, v) | Stmt::StoreFloat(_, i, v) => {
                walk_expr(i, f);
                walk_expr(v, f);
            }
            Stmt::If(c, a, b) => {
                walk_expr(c, f);
                walk(a, f);
                walk(b, f);
            }
            Stmt::IfDef(_, a, b) => {
                walk(a, f);
                walk(b, f);
            }
            Stmt::For(_, a, b, body) => {
                walk_expr(a, f);
                walk_expr(b, f);
                walk(body, f);
            }
            Stmt::ForStep(_, a, b, step, body) => {
                walk_expr(a, f);
                walk_expr(b, f);
                walk_expr(step, f);
                walk(body, f);
            }
            Stmt::Call(_, xs) => xs.iter().for_each(|x| walk_expr(x, f)),
            Stmt::StorePatchSlot(a, b, v) => {
                walk_expr(a, f);
                walk_expr(b, f);
                walk_expr(v, f);
            }
            Stmt::StorePatchCp(j, v) => {
                walk_expr(j, f);
                walk_expr(v, f);
            }
            Stmt::ClearPatchSlot(a) => walk_expr(a, f),
            Stmt::Comment(_) | Stmt::ReturnVoid | Stmt::Barrier(_) | Stmt::PatchLocal => {}
        }
    }
}

/// [`walk()`] over one expression.
pub fn walk_expr<'a>(e: &'a Expr, f: &mut dyn FnMut(Node<'a>)) {
    f(Node::Expr(e));
    match e {
        Expr::Fetch(_, a)
        | Expr::Float(_, a)
        | Expr::ConstIndex(_, a)
        | Expr::NamedIndex(_, a)
        | Expr::PatchCp(a)
        | Expr::Neg(a)
        | Expr::Field(a, _) => walk_expr(a, f),
        Expr::Binary(_, a, b)
        | Expr::TableWeight(a, b)
        | Expr::Texel(_, a, b)
        | Expr::PatchSlot(a, b) => {
            walk_expr(a, f);
            walk_expr(b, f);
        }
        Expr::Call(_, xs) | Expr::CallFn(_, xs) | Expr::Make(_, xs) => {
            xs.iter().for_each(|x| walk_expr(x, f))
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

// Queries over a whole function and what it calls, built on the walk.

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

/// The ABI binding of `r`; `None` for workgroup memory. The bucket
/// buffers back no Plan resource in `abi::BINDINGS` (`resource: None`), so
/// they are found by name, like `abi::binding_of` finds `patch_faces`.
pub fn binding(r: Resource) -> Option<&'static abi::Binding> {
    match r {
        Resource::BucketTile => None,
        Resource::PatchLevels
        | Resource::BucketPatches
        | Resource::BucketList
        | Resource::BucketDispatch
        | Resource::BucketDraw
        | Resource::BucketChunks => abi::BINDINGS.iter().find(|b| b.name == r.name()),
        r => Some(abi::binding_of(r)),
    }
}

/// Functions called by `f` ([`Function::called`]).
pub fn called(f: &Function) -> Vec<FnRef> {
    f.called()
}

#[cfg(test)]
mod tests {
    use super::super::build::*;
    use super::*;

    /// `walk` reaches statements and expressions inside every kind of
    /// block, so the analyses built on it (resources, table reads, calls)
    /// see nested code.
    #[test]
    fn walk_reaches_nested_blocks() {
        let mut func = Function::new("f", "");
        let i = func.local("i", Ty::U32);
        let store = Stmt::Store(Resource::Samples, l(i), Expr::F32(0.0));
        let call = Stmt::Call(FnRef::Common(3), vec![fetch(Resource::Valence, l(i))]);
        func.body = vec![Stmt::IfDef(
            Define::Capture,
            vec![],
            vec![Stmt::ForStep(
                i,
                u(0),
                u(4),
                u(1),
                vec![Stmt::If(
                    bin(
                        BinOp::Lt,
                        Expr::TableWeight(Box::new(u(0)), Box::new(u(1))),
                        f(1.0),
                    ),
                    vec![store],
                    vec![call],
                )],
            )],
        )];
        assert_eq!(
            func.resources(),
            vec![(Resource::Valence, false), (Resource::Samples, true)]
        );
        assert!(func.reads_table());
        assert_eq!(func.called(), vec![FnRef::Common(3)]);
    }
}
