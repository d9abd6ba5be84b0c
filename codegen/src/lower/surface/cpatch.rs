//! The PCCM c-patch: 24 coefficients, four quartic triangles.

use super::*;

pub(crate) fn cpatch_surface(class: Class) -> Function {
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
    let normal = patch_normal(sub(l(qb), l(qa)), sub(l(qc), l(qa)));
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::SAMPLE,
        vec![pos, normal],
    )));
    f
}
