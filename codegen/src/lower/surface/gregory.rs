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
    let pairs = twist_pairs(iu, iv, level);
    let nf = let_f32(&mut f, "nf", to_f32(l(level)));
    let mut corr_u: Vec<Expr> = Vec::new();
    let mut corr_v: Vec<Expr> = Vec::new();
    for (corner, (wp, wm)) in pairs.into_iter().enumerate() {
        let blend = gregory_blend(
            &mut f,
            corner,
            (
                cp_at(cp, g.storage_index(corner, 3)),
                cp_at(cp, g.storage_index(corner, 4)),
            ),
            (wp, wm),
            nf,
        );
        let k = Form::Bicubic.storage_index(corner, 3);
        grid[k / 4][k % 4] = l(blend.point);
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
        corr_u.push(blend.correction(0, &TWIST_DW[corner], bw));
        corr_v.push(blend.correction(1, &TWIST_DW[corner], bw));
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

/// The integer weights `(w⁺, w⁻)` of each corner's twist pair at
/// `(iu, iv)/level`: the distances to the edge the other point serves
/// (gregory.md §4).
pub(crate) fn twist_pairs(iu: LocalId, iv: LocalId, level: LocalId) -> [(Expr, Expr); 4] {
    [
        (l(iu), l(iv)),
        (l(iv), sub(l(level), l(iu))),
        (sub(l(level), l(iu)), sub(l(level), l(iv))),
        (sub(l(level), l(iv)), l(iu)),
    ]
}

/// d(w⁺)/du, d(w⁺)/dv, d(w⁻)/du, d(w⁻)/dv of [`twist_pairs`], in parameter
/// units.
pub(crate) const TWIST_DW: [[f32; 4]; 4] = [
    [1.0, 0.0, 0.0, 1.0],
    [0.0, 1.0, -1.0, 0.0],
    [-1.0, 0.0, 0.0, -1.0],
    [0.0, -1.0, 1.0, 0.0],
];

/// One rationally blended twist pair of a Gregory-type patch, as locals of
/// the surface function: the blended point and what its derivative terms
/// need.
pub(crate) struct Blend {
    /// `X = a·F⁺ + b·F⁻`.
    pub point: LocalId,
    wpf: LocalId,
    wmf: LocalId,
    diff: LocalId,
    inv2: LocalId,
}

impl Blend {
    /// The blend's own derivative term along `dir` (0 = u, 1 = v):
    /// `∂X/∂t · B`, `∂X/∂t = (w⁺'·w⁻ − w⁻'·w⁺)(F⁺ − F⁻)/s²` with the
    /// weights' derivatives `dw` = (w⁺_u, w⁺_v, w⁻_u, w⁻_v) ∈ {−1, 0, 1},
    /// written without the zero and unit factors; `bw` the slot's
    /// Bernstein weight.
    pub fn correction(&self, dir: usize, dw: &[f32; 4], bw: LocalId) -> Expr {
        let terms: Vec<Expr> = [(dw[dir], self.wmf), (-dw[2 + dir], self.wpf)]
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
        mul(l(self.diff), mul(mul(num, l(self.inv2)), l(bw)))
    }
}

/// Emit the blend of twist pair `(F⁺, F⁻)` of `corner` with the integer
/// weights `(w⁺, w⁻)` (gregory.md §4): `a = w⁺/s`, `b = w⁻/s`, guarded to
/// ½, ½ where `s = 0` (the corner, whose Bernstein weight is 0), and the
/// derivative factor `1/s²` in parameter units. `nf` is the level as f32.
pub(crate) fn gregory_blend(
    f: &mut Function,
    corner: usize,
    (fp, fm): (Expr, Expr),
    (wp, wm): (Expr, Expr),
    nf: LocalId,
) -> Blend {
    let fp = let_vec(f, &format!("fp{corner}"), fp);
    let fm = let_vec(f, &format!("fm{corner}"), fm);
    let wpi = f.local(format!("wp{corner}"), Ty::U32);
    let wmi = f.local(format!("wm{corner}"), Ty::U32);
    f.body.push(Stmt::Let(wpi, wp));
    f.body.push(Stmt::Let(wmi, wm));
    let sum = f.local(format!("ws{corner}"), Ty::U32);
    f.body.push(Stmt::Let(sum, add(l(wpi), l(wmi))));
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
    let point = let_vec(
        f,
        &format!("x{corner}"),
        add(mul(l(fp), l(a)), mul(l(fm), l(b))),
    );
    let wpf = let_f32(f, &format!("wpf{corner}"), div(to_f32(l(wpi)), l(nf)));
    let wmf = let_f32(f, &format!("wmf{corner}"), div(to_f32(l(wmi)), l(nf)));
    let diff = let_vec(f, &format!("dfm{corner}"), sub(l(fp), l(fm)));
    Blend {
        point,
        wpf,
        wmf,
        diff,
        inv2,
    }
}
