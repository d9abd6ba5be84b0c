//! The 20-point Gregory patch with its rational interior blend.

use super::*;

/// Gregory patch (gregory.md §4): each interior point is the rational blend
/// of its pair `F⁺, F⁻`; both weights come from the integer coordinates and
/// the corner's 0/0 is guarded to ½, ½ (its Bernstein weight is 0 there).
/// Normals use the exact derivatives: the frozen-grid Bézier derivative plus
/// `Σ B_i B_j ∂b_ij`, so the golden values and the G¹ proof both apply.
pub(crate) fn gregory_surface(class: Class) -> Function {
    let mut f = Function::new(
        format!("{}_surface", class.name()),
        "Gregory patch at (iu, iv)/level (gregory.md §4): blend the four interior pairs with \
         integer-formed weights (guarded at the corners), evaluate the 16-point Bézier grid by \
         symmetric de Casteljau, add the blend's own derivative terms, normal = tessgen_patch_normal(∂u, ∂v).",
    );
    let (cp, iu, iv, level) = surface_params(&mut f);
    let (lu, ru, st) = weights(&mut f, "u", iu, level);
    f.body.extend(st);
    let (lv, rv, st) = weights(&mut f, "v", iv, level);
    f.body.extend(st);
    let g = Form::Gregory;
    // Boundary points of the grid from P, E⁺, E⁻ (slots 0..3 sit where the
    // bicubic layout puts b00, b10, b01).
    let mut grid: [[Expr; 4]; 4] = std::array::from_fn(|_| std::array::from_fn(|_| f32c(0.0)));
    for corner in 0..4 {
        for slot in 0..3 {
            let k = Form::Bicubic.storage_index(corner, slot);
            grid[k / 4][k % 4] = cp_at(cp, g.storage_index(corner, slot));
        }
    }
    // Interior pair weights, as integers: (w⁺, w⁻) per corner (gregory.md §4).
    let pairs: [(Expr, Expr); 4] = [
        (l(iu), l(iv)),
        (l(iv), sub(l(level), l(iu))),
        (sub(l(level), l(iu)), sub(l(level), l(iv))),
        (sub(l(level), l(iv)), l(iu)),
    ];
    // d(w⁺)/du, d(w⁺)/dv, d(w⁻)/du, d(w⁻)/dv in parameter units.
    const DW: [[f32; 4]; 4] = [
        [1.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, -1.0, 0.0],
        [-1.0, 0.0, 0.0, -1.0],
        [0.0, -1.0, 1.0, 0.0],
    ];
    let nf = let_f32(&mut f, "nf", to_f32(l(level)));
    let mut corr_u: Vec<Expr> = Vec::new();
    let mut corr_v: Vec<Expr> = Vec::new();
    for (corner, (wp, wm)) in pairs.into_iter().enumerate() {
        let fp = let_vec(
            &mut f,
            &format!("fp{corner}"),
            cp_at(cp, g.storage_index(corner, 3)),
        );
        let fm = let_vec(
            &mut f,
            &format!("fm{corner}"),
            cp_at(cp, g.storage_index(corner, 4)),
        );
        let wpi = f.local(format!("wp{corner}"), Ty::U32);
        let wmi = f.local(format!("wm{corner}"), Ty::U32);
        f.body.push(Stmt::Let(wpi, wp));
        f.body.push(Stmt::Let(wmi, wm));
        let sum = f.local(format!("ws{corner}"), Ty::U32);
        f.body.push(Stmt::Let(sum, add(l(wpi), l(wmi))));
        // Blend weights (guarded): a = w⁺/s, b = w⁻/s; and the derivative
        // factor 1/s² in parameter units (s/level)².
        let a = f.local(format!("a{corner}"), Ty::F32);
        let b = f.local(format!("b{corner}"), Ty::F32);
        let inv2 = f.local(format!("inv_s2_{corner}"), Ty::F32);
        f.body.push(Stmt::Var(a, f32c(0.5)));
        f.body.push(Stmt::Var(b, f32c(0.5)));
        f.body.push(Stmt::Var(inv2, f32c(0.0)));
        let sf = f.local(format!("sf{corner}"), Ty::F32);
        f.body.push(Stmt::If(
            bin(BinOp::Gt, l(sum), u(0)),
            vec![
                Stmt::Assign(a, div(to_f32(l(wpi)), to_f32(l(sum)))),
                Stmt::Assign(b, div(to_f32(l(wmi)), to_f32(l(sum)))),
                Stmt::Let(sf, div(to_f32(l(sum)), l(nf))),
                Stmt::Assign(inv2, div(f32c(1.0), mul(l(sf), l(sf)))),
            ],
            vec![],
        ));
        let k = Form::Bicubic.storage_index(corner, 3);
        let x = let_vec(
            &mut f,
            &format!("x{corner}"),
            add(mul(l(fp), l(a)), mul(l(fm), l(b))),
        );
        grid[k / 4][k % 4] = l(x);
        // ∂X/∂t = (w⁺'·w⁻ − w⁻'·w⁺)(F⁺ − F⁻)/s², weights in parameter units.
        let wpf = let_f32(&mut f, &format!("wpf{corner}"), div(to_f32(l(wpi)), l(nf)));
        let wmf = let_f32(&mut f, &format!("wmf{corner}"), div(to_f32(l(wmi)), l(nf)));
        let diff = let_vec(&mut f, &format!("dfm{corner}"), sub(l(fp), l(fm)));
        // Bernstein weight of this slot: B_i(u)·B_j(v), i, j ∈ {1, 2}.
        let (i, j) = (k / 4, k % 4);
        let bern = |t_l: LocalId, t_r: LocalId, idx: usize| -> Expr {
            // B_1 = 3·r·l², B_2 = 3·r²·l with l = 1 − t, r = t.
            if idx == 1 {
                mul(mul(f32c(3.0), l(t_r)), mul(l(t_l), l(t_l)))
            } else {
                mul(mul(f32c(3.0), mul(l(t_r), l(t_r))), l(t_l))
            }
        };
        let bw = let_f32(
            &mut f,
            &format!("bw{corner}"),
            mul(bern(lu, ru, i), bern(lv, rv, j)),
        );
        for (dir, out) in [(0usize, &mut corr_u), (1usize, &mut corr_v)] {
            // w⁺'·w⁻ − w⁻'·w⁺ with w' ∈ {−1, 0, 1}: written without the
            // zero and unit factors.
            let terms: Vec<Expr> = [(DW[corner][dir], wmf), (-DW[corner][2 + dir], wpf)]
                .into_iter()
                .filter(|(c, _)| *c != 0.0)
                .map(|(c, w)| {
                    if c > 0.0 {
                        l(w)
                    } else {
                        Expr::Neg(Box::new(l(w)))
                    }
                })
                .collect();
            let num = terms.into_iter().reduce(add).unwrap_or(f32c(0.0));
            out.push(mul(l(diff), mul(mul(num, l(inv2)), l(bw))));
        }
    }
    let (pos, du, dv) = tensor_cubic(&mut f, "", &grid, (lu, ru), (lv, rv), true);
    let sum4 = |v: Vec<Expr>| {
        v.into_iter()
            .reduce(add)
            .expect("four interior corrections")
    };
    let du = let_vec(&mut f, "du", add(du, sum4(corr_u)));
    let dv = let_vec(&mut f, "dv", add(dv, sum4(corr_v)));
    let normal = patch_normal(l(du), l(dv));
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::SAMPLE,
        vec![pos, normal],
    )));
    f
}
