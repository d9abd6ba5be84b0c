//! ACC: bicubic geometry plus two tangent patches for the normal (40 control points).

use super::*;

/// ACC (acc.md §5): position from the bicubic geometry patch, normal from
/// the tangent patches, `tessgen_patch_normal(U, V)`.
pub(crate) fn acc_surface(class: Class) -> Function {
    let mut f = Function::new(
        format!("{}_surface", class.name()),
        "ACC patch at (iu, iv)/level (acc.md §5): position from the bicubic geometry patch \
         (points 0..16); normal = tessgen_patch_normal(U, V) from the tangent patches U (quadratic in u, \
         cubic in v) and V (cubic in u, quadratic in v), whose 24 coefficients are stored per \
         corner in the corner's own frame (points 16..40) and mapped back with its signs here.",
    );
    let (cp, iu, iv, level) = surface_params(&mut f);
    let (lu, ru, st) = weights(&mut f, "u", iu, level);
    f.body.extend(st);
    let (lv, rv, st) = weights(&mut f, "v", iv, level);
    f.body.extend(st);
    let (pos, _, _) = tensor_cubic(&mut f, "", &bicubic_grid(cp), (lu, ru), (lv, rv), false);
    let pos = let_vec(&mut f, "position", pos);
    // U[a][b] (3×4) and V[a][b] (4×3) as expressions over stored points.
    let mut uc: [[Option<Expr>; 4]; 4] = Default::default();
    let mut vc: [[Option<Expr>; 4]; 4] = Default::default();
    for corner in 0..4 {
        for slot in 4..10 {
            let t = Form::acc_tangent_slot(corner, slot);
            let mut e = cp_at(cp, Form::Acc.storage_index(corner, slot));
            if t.negate {
                e = Expr::Neg(Box::new(e));
            }
            let dst = if t.in_v { &mut vc } else { &mut uc };
            dst[t.a][t.b] = Some(e);
        }
    }
    let take = |m: &mut [[Option<Expr>; 4]; 4], a: usize, b: usize| {
        m[a][b]
            .take()
            .expect("every ACC tangent coefficient is stored once")
    };
    // U: quadratic along u per v-row, then cubic along v.
    let mut urows = Vec::new();
    for b in 0..4 {
        let q = quadratic(
            &mut f,
            &format!("urow{b}"),
            [
                take(&mut uc, 0, b),
                take(&mut uc, 1, b),
                take(&mut uc, 2, b),
            ],
            lu,
            ru,
        );
        urows.push(let_vec(&mut f, &format!("urow{b}"), q));
    }
    let tu = f.local("tangent_u", Ty::Struct(plan::common::CURVE));
    f.body.push(Stmt::Let(
        tu,
        call(
            FnRef::Common(common_fn::CUBIC),
            vec![
                l(urows[0]),
                l(urows[1]),
                l(urows[2]),
                l(urows[3]),
                l(lv),
                l(rv),
            ],
        ),
    ));
    // V: quadratic along v per u-column, then cubic along u.
    let mut vcols = Vec::new();
    for a in 0..4 {
        let q = quadratic(
            &mut f,
            &format!("vcol{a}"),
            [
                take(&mut vc, a, 0),
                take(&mut vc, a, 1),
                take(&mut vc, a, 2),
            ],
            lv,
            rv,
        );
        vcols.push(let_vec(&mut f, &format!("vcol{a}"), q));
    }
    let tv = f.local("tangent_v", Ty::Struct(plan::common::CURVE));
    f.body.push(Stmt::Let(
        tv,
        call(
            FnRef::Common(common_fn::CUBIC),
            vec![
                l(vcols[0]),
                l(vcols[1]),
                l(vcols[2]),
                l(vcols[3]),
                l(lu),
                l(ru),
            ],
        ),
    ));
    let normal = patch_normal(field(tu, 0), field(tv, 0));
    f.body.push(Stmt::Return(Expr::Make(
        plan::common::SAMPLE,
        vec![l(pos), normal],
    )));
    f
}
