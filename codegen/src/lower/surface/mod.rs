//! Surface evaluation of each patch form, at integer domain coordinates (weights formed from
//! integers, watertight.md Rule 2), and the helpers the forms share.

use super::*;

mod acc;
mod bicubic;
mod cpatch;
mod gregory;
mod gregory4;
mod tri;
pub(crate) use acc::*;
pub(crate) use bicubic::*;
pub(crate) use cpatch::*;
pub(crate) use gregory::*;
pub(crate) use gregory4::*;
pub(crate) use tri::*;

/// Integer-formed weight pair `((level - i)/level, i/level)`.
pub(crate) fn weights(
    f: &mut Function,
    name: &str,
    i: LocalId,
    level: LocalId,
) -> (LocalId, LocalId, Vec<Stmt>) {
    let wl = f.local(format!("l{name}"), Ty::F32);
    let wr = f.local(format!("r{name}"), Ty::F32);
    let st = vec![
        Stmt::Let(wl, div(to_f32(sub(l(level), l(i))), to_f32(l(level)))),
        Stmt::Let(wr, div(to_f32(l(i)), to_f32(l(level)))),
    ];
    (wl, wr, st)
}

pub(crate) fn surface_params(f: &mut Function) -> (LocalId, LocalId, LocalId, LocalId) {
    let cp = f.param("cp_base", Ty::U32);
    let iu = f.param("iu", Ty::U32);
    let iv = f.param("iv", Ty::U32);
    let level = f.param("level", Ty::U32);
    f.ret = Some(Ty::Struct(plan::common::SAMPLE));
    (cp, iu, iv, level)
}

/// A `Curve` field: 0 = point, 1 = derivative.
pub(crate) fn field(id: LocalId, k: usize) -> Expr {
    Expr::Field(Box::new(l(id)), k)
}

/// Bind `e` to a new `vec3` local.
pub(crate) fn let_vec(f: &mut Function, name: &str, e: Expr) -> LocalId {
    let id = f.local(name, Ty::Vec3);
    f.body.push(Stmt::Let(id, e));
    id
}

/// Bind `e` to a new `f32` local.
pub(crate) fn let_f32(f: &mut Function, name: &str, e: Expr) -> LocalId {
    let id = f.local(name, Ty::F32);
    f.body.push(Stmt::Let(id, e));
    id
}

/// Tensor-product cubic Bézier over `grid[k][l]` (k along u): symmetric de
/// Casteljau along u on each of the four rows, then along v on the row
/// points (position, ∂/∂v) and, if `with_du`, on the row derivatives
/// (∂/∂u). Returns `(position, du, dv)`; `du` is the zero vector without
/// `with_du` (nothing is emitted for it).
pub(crate) fn tensor_cubic(
    f: &mut Function,
    prefix: &str,
    grid: &[[Expr; 4]; 4],
    (lu, ru): (LocalId, LocalId),
    (lv, rv): (LocalId, LocalId),
    with_du: bool,
) -> (Expr, Expr, Expr) {
    let mut rows = Vec::new();
    for row in 0..4 {
        let id = f.local(format!("{prefix}row{row}"), Ty::Struct(plan::common::CURVE));
        f.body.push(Stmt::Let(
            id,
            call(
                FnRef::Common(common_fn::CUBIC),
                grid.iter()
                    .map(|column| column[row].clone())
                    .chain([l(lu), l(ru)])
                    .collect(),
            ),
        ));
        rows.push(id);
    }
    let along_v = f.local(format!("{prefix}along_v"), Ty::Struct(plan::common::CURVE));
    let mut passes = vec![(along_v, 0)];
    let along_u = with_du.then(|| {
        let id = f.local(format!("{prefix}along_u"), Ty::Struct(plan::common::CURVE));
        passes.push((id, 1));
        id
    });
    for (id, k) in passes {
        f.body.push(Stmt::Let(
            id,
            call(
                FnRef::Common(common_fn::CUBIC),
                vec![
                    field(rows[0], k),
                    field(rows[1], k),
                    field(rows[2], k),
                    field(rows[3], k),
                    l(lv),
                    l(rv),
                ],
            ),
        ));
    }
    let du = match along_u {
        Some(id) => field(id, 0),
        None => Expr::Call(Builtin::Vec3, vec![f32c(0.0), f32c(0.0), f32c(0.0)]),
    };
    (field(along_v, 0), du, field(along_v, 1))
}

/// Quadratic Bézier by symmetric de Casteljau (`x·l + y·r` at every step).
pub(crate) fn quadratic(
    f: &mut Function,
    name: &str,
    b: [Expr; 3],
    wl: LocalId,
    wr: LocalId,
) -> Expr {
    let [b0, b1, b2] = b;
    let q0 = let_vec(f, &format!("{name}_0"), lerp(b0, b1.clone(), wl, wr));
    let q1 = let_vec(f, &format!("{name}_1"), lerp(b1, b2, wl, wr));
    lerp(l(q0), l(q1), wl, wr)
}

/// A quad patch's unit normal from its tangents (`tessgen_patch_normal`:
/// zero where they are parallel, and `eval` looks just inside).
pub(crate) fn patch_normal(a: Expr, b: Expr) -> Expr {
    call(FnRef::Common(common_fn::PATCH_NORMAL), vec![a, b])
}

/// Stored control point `k` of the patch at `cp`.
pub(crate) fn cp_at(cp: LocalId, k: usize) -> Expr {
    fetch(Resource::ControlPoints, add(l(cp), u(k as u32)))
}

/// The 16 stored points of a [`Form::Bicubic`] layout as a grid `[k][l]`.
pub(crate) fn bicubic_grid(cp: LocalId) -> [[Expr; 4]; 4] {
    std::array::from_fn(|k| std::array::from_fn(|row| cp_at(cp, 4 * k + row)))
}
