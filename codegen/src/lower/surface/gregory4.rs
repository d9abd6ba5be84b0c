//! The 29-point biquartic Gregory patch (`docs/g1cc.md` round 6): a 5×5
//! Bézier net whose four twist points are rationally blended pairs.

use super::*;

/// Grid position `(a, b)` (a along u) of point `k` (0..=4) of edge `i` at
/// `depth` rows inside the patch: edge 0 runs along v = 0, edge 1 along
/// u = 1, edge 2 along v = 1 backwards, edge 3 along u = 0 backwards.
pub(crate) fn gregory4_grid_slot(i: usize, k: usize, depth: usize) -> (usize, usize) {
    match i % 4 {
        0 => (k, depth),
        1 => (4 - depth, k),
        2 => (4 - k, 4 - depth),
        _ => (depth, 4 - k),
    }
}

/// `tessgen_quartic(b0..b4, l, r)`: quartic Bézier point and derivative by
/// symmetric de Casteljau (every lerp `x·l + y·r`), the quartic twin of the
/// common `tessgen_cubic`. Emitted in the modules of schemes with a
/// [`Form::Gregory4`] class.
pub(crate) fn quartic_fn() -> Function {
    let mut f = Function::new(
        "tessgen_quartic",
        "Quartic Bézier point and derivative by symmetric de Casteljau: every lerp is `x·l + y·r`.",
    );
    let b: Vec<LocalId> = (0..5).map(|i| f.param(format!("b{i}"), Ty::Vec3)).collect();
    let (wl, wr) = (f.param("l", Ty::F32), f.param("r", Ty::F32));
    f.ret = Some(Ty::Struct(plan::common::CURVE));
    let mut prev = b;
    for (k, letter) in ['c', 'd', 'e'].into_iter().enumerate() {
        let next: Vec<LocalId> = (0..4 - k)
            .map(|j| f.local(format!("{letter}{j}"), Ty::Vec3))
            .collect();
        for (j, id) in next.iter().enumerate() {
            f.body
                .push(Stmt::Let(*id, lerp(l(prev[j]), l(prev[j + 1]), wl, wr)));
        }
        prev = next;
    }
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::CURVE,
        vec![
            lerp(l(prev[0]), l(prev[1]), wl, wr),
            mul(sub(l(prev[1]), l(prev[0])), f32c(4.0)),
        ],
    )));
    f
}

/// Biquartic Gregory patch: each twist point is the rational blend of its
/// pair (the point serving the corner's edge toward the next corner, `fp`,
/// and the one serving the edge toward the previous corner, `fm`) with
/// integer-formed weights, guarded to ½, ½ at the corner where their
/// Bernstein weight is 0 — the pairs and weights of [`gregory_surface`] on a
/// 5×5 net. Normals use the exact derivatives (the frozen-net Bézier
/// derivative plus `Σ B_i B_j ∂b_ij`), so golden values and the G¹ argument
/// of docs/g1cc.md both apply. `quartic` is the module's `tessgen_quartic`.
pub(crate) fn gregory4_surface(class: Class, quartic: usize) -> Function {
    let mut f = Function::new(
        format!("{}_surface", class.name()),
        "Biquartic Gregory patch at (iu, iv)/level (docs/g1cc.md round 6): blend the four twist \
         pairs with integer-formed weights (guarded at the corners), evaluate the 25-point \
         Bézier net by symmetric de Casteljau, add the blend's own derivative terms, normal = \
         tessgen_patch_normal(∂u, ∂v).",
    );
    let (cp, iu, iv, level) = surface_params(&mut f);
    let (lu, ru, st) = weights(&mut f, "u", iu, level);
    f.body.extend(st);
    let (lv, rv, st) = weights(&mut f, "v", iv, level);
    f.body.extend(st);
    let g = Form::Gregory4;
    let mut grid: [[Expr; 5]; 5] = std::array::from_fn(|_| std::array::from_fn(|_| f32c(0.0)));
    // Per corner i: p, ep (edge i, k = 1), em (edge i − 1, k = 3), m (edge
    // i, k = 2) on the boundary; g (edge i, k = 2) one row inside.
    for corner in 0..4 {
        let prev = (corner + 3) % 4;
        for (slot, (edge, k, depth)) in [
            (0, (corner, 0, 0)),
            (1, (corner, 1, 0)),
            (2, (prev, 3, 0)),
            (3, (corner, 2, 0)),
            (6, (corner, 2, 1)),
        ] {
            let (a, b) = gregory4_grid_slot(edge, k, depth);
            grid[a][b] = cp_at(cp, g.storage_index(corner, slot));
        }
    }
    grid[2][2] = cp_at(cp, g.single_index(0));
    // Twist pair weights, as integers: (w⁺, w⁻) per corner, as gregory.rs.
    let pairs = twist_pairs(iu, iv, level);
    let nf = let_f32(&mut f, "nf", to_f32(l(level)));
    let mut corr_u: Vec<Expr> = Vec::new();
    let mut corr_v: Vec<Expr> = Vec::new();
    for (corner, (wp, wm)) in pairs.into_iter().enumerate() {
        let (a, b) = gregory4_grid_slot(corner, 1, 1);
        let blend = gregory_blend(
            &mut f,
            corner,
            (
                cp_at(cp, g.storage_index(corner, 4)),
                cp_at(cp, g.storage_index(corner, 5)),
            ),
            (wp, wm),
            nf,
        );
        grid[a][b] = l(blend.point);
        // Bernstein weight of the twist slot: B_a(u)·B_b(v), a, b ∈ {1, 3},
        // B_1 = 4·r·l³, B_3 = 4·r³·l.
        let bern = |t_l: LocalId, t_r: LocalId, idx: usize| -> Expr {
            let (rp, lp) = if idx == 1 { (1, 3) } else { (3, 1) };
            let pow = |x: LocalId, k: usize| (1..k).fold(l(x), |acc, _| mul(acc, l(x)));
            mul(mul(f32c(4.0), pow(t_r, rp)), pow(t_l, lp))
        };
        let bw = let_f32(
            &mut f,
            &format!("bw{corner}"),
            mul(bern(lu, ru, a), bern(lv, rv, b)),
        );
        corr_u.push(blend.correction(0, &TWIST_DW[corner], bw));
        corr_v.push(blend.correction(1, &TWIST_DW[corner], bw));
    }
    let (pos, du, dv) = tensor_quartic(&mut f, &grid, quartic, (lu, ru), (lv, rv));
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

/// Tensor-product quartic Bézier over `grid[a][b]` (a along u): symmetric
/// de Casteljau along u on each of the five rows, then along v on the row
/// points (position, ∂/∂v) and on the row derivatives (∂/∂u).
fn tensor_quartic(
    f: &mut Function,
    grid: &[[Expr; 5]; 5],
    quartic: usize,
    (lu, ru): (LocalId, LocalId),
    (lv, rv): (LocalId, LocalId),
) -> (Expr, Expr, Expr) {
    let mut rows = Vec::new();
    for row in 0..5 {
        let id = f.local(format!("row{row}"), Ty::Struct(plan::common::CURVE));
        f.body.push(Stmt::Let(
            id,
            call(
                FnRef::Local(quartic),
                grid.iter()
                    .map(|column| column[row].clone())
                    .chain([l(lu), l(ru)])
                    .collect(),
            ),
        ));
        rows.push(id);
    }
    let mut out = Vec::new();
    for (name, k) in [("along_v", 0), ("along_u", 1)] {
        let id = f.local(name, Ty::Struct(plan::common::CURVE));
        f.body.push(Stmt::Let(
            id,
            call(
                FnRef::Local(quartic),
                rows.iter()
                    .map(|r| field(*r, k))
                    .chain([l(lv), l(rv)])
                    .collect(),
            ),
        ));
        out.push(id);
    }
    (field(out[0], 0), field(out[1], 0), field(out[0], 1))
}
