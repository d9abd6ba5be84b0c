//! The bicubic B-spline / Bézier tensor patch (16 control points).

use super::*;

pub(crate) fn bicubic_surface(class: Class) -> Function {
    let mut f = Function::new(
        format!("{}_surface", class.name()),
        "Bicubic Bézier patch at (iu, iv)/level: symmetric de Casteljau along u on each of the \
         four rows, then along v on the row points (position, ∂/∂v) and on the row \
         derivatives (∂/∂u); normal = tessgen_patch_normal(∂u, ∂v).",
    );
    let (cp, iu, iv, level) = surface_params(&mut f);
    let (lu, ru, st) = weights(&mut f, "u", iu, level);
    f.body.extend(st);
    let (lv, rv, st) = weights(&mut f, "v", iv, level);
    f.body.extend(st);
    let (pos, du, dv) = tensor_cubic(&mut f, "", &bicubic_grid(cp), (lu, ru), (lv, rv), true);
    let normal = patch_normal(du, dv);
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::SAMPLE,
        vec![pos, normal],
    )));
    f
}
