//! Cubic Bézier triangle surfaces (PN, scalar-tagged PN, Phong): at an integer grid point and at
//! the tessellator's raw barycentric point.

use super::*;

/// Cubic Bézier triangle + quadratic normal field (pn.md §2) at integer
/// barycentric coordinates `(level − iu − iv, iu, iv)` of corners 0, 1, 2:
/// the weights are formed from the integers here, then the float-weight
/// surface ([`tri_cubic_surface_at`]) does the arithmetic, so the grid path
/// and the tessellator's interior path share one operation order.
pub(crate) fn tri_cubic_surface(class: Class, at: usize) -> Function {
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
pub(crate) fn tri_cubic_surface_at(class: Class) -> Function {
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
