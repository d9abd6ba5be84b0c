//! The GLSL [`Dialect`]: what this target spells its own way (types,
//! literals, names, memory, stage inputs and outputs); everything else is
//! the shared spelling layer's ([`crate::backend::dialect`]).

use super::*;

/// The GLSL dialect, for one function of one file.
pub(super) struct Cx<'c, 'a> {
    pub(super) w: &'c Writer<'a>,
    pub(super) m: &'c Module,
    pub(super) f: &'c Function,
}

impl Dialect for Cx<'_, '_> {
    fn plan(&self) -> &Plan {
        self.w.plan
    }
    fn module(&self) -> &Module {
        self.m
    }
    fn function(&self) -> &Function {
        self.f
    }
    fn ident(&self, name: &str) -> String {
        ident(name)
    }
    fn local(&self, id: LocalId) -> String {
        self.w.locals[id.0].clone()
    }
    fn f32_lit(&self, x: f32) -> String {
        f32_lit(x)
    }
    fn f32_ty(&self) -> &'static str {
        "float"
    }
    fn u32_ty(&self) -> &'static str {
        "uint"
    }
    fn vec2_ty(&self) -> &'static str {
        "vec2"
    }
    fn vec3_ty(&self) -> &'static str {
        "vec3"
    }
    fn builtin_override(&self, b: Builtin, a: &[String]) -> Option<String> {
        // findLSB(0) is -1: clamp to WGSL's 32.
        match b {
            Builtin::CountTrailingZeros => Some(format!("min(uint(findLSB({})), 32u)", a[0])),
            Builtin::Project => Some(format!("({} * vec4({}, 1.0))", param("view_proj"), a[0])),
            _ => None,
        }
    }
    fn decl(&self, id: LocalId, _mutable: bool) -> String {
        self.w.decl(self.f, id)
    }
    /// Parentheses around a condition that is not already a binary.
    fn if_head(&self, c: &Expr) -> String {
        let s = dialect::expr(self, c);
        if matches!(c, Expr::Binary(..)) {
            format!("if {s} {{")
        } else {
            format!("if ({s}) {{")
        }
    }
    fn preprocessor(&self) -> bool {
        true
    }
    fn special_stmt(&self, s: &Stmt, out: &mut Lines) {
        let x = |e: &Expr| dialect::expr(self, e);
        match s {
            Stmt::Store(r, i, v) => {
                let (i, v) = (x(i), x(v));
                let s = if self.w.stage.tess() && *r == Resource::ControlPoints {
                    format!("{}({i}, {v});", ident(&self.w.entries.tess.store_cp.name))
                } else if r.ty() == Ty::Vec3 {
                    format!("store_{}({i}, {v});", r.name())
                } else {
                    format!("{}[{i}] = {v};", r.name())
                };
                out.line(&s);
            }
            Stmt::StoreFloat(r, i, v) => out.line(&format!("{}[{}] = {};", r.name(), x(i), x(v))),
            Stmt::Barrier(Barrier::Workgroup) => out.line("barrier();"),
            Stmt::Barrier(Barrier::Storage) => {
                out.line("memoryBarrierBuffer();");
                out.line("barrier();");
            }
            Stmt::StorePatchSlot(a, b, v) => {
                out.line(&format!("tcs_cp[{}][{}] = {};", x(a), x(b), x(v)))
            }
            Stmt::Output(o, e) => {
                let v = dialect::expr(self, e);
                // GLSL's quad domain is (u, v) = (y, x): its slots are
                // `hw_factor_edges(sides, false)`.
                let slot = crate::plan::abi::factor_slot(self.w.entries.sides, *o, false);
                let slot = slot.unwrap_or_default();
                match o {
                    StageOut::EdgeFactor(_) => {
                        out.line(&format!("gl_TessLevelOuter[{slot}] = {v};"));
                    }
                    StageOut::InsideFactor(_) => {
                        out.line(&format!("gl_TessLevelInner[{slot}] = {v};"));
                    }
                    StageOut::Position => out.line(&format!("te_position = {v};")),
                    StageOut::Clip => out.line(&format!("gl_Position = {v};")),
                    StageOut::Normal => out.line(&format!("te_normal = {v};")),
                    StageOut::Domain => out.line(&format!("te_domain = {v};")),
                    StageOut::Patch => out.line(&format!("te_patch = {v};")),
                    StageOut::PatchClass | StageOut::Uv | StageOut::Color => {
                        unreachable!("an output of the instanced entries in a tessellation stage")
                    }
                }
            }
            _ => unreachable!("spelled by dialect::stmts"),
        }
    }
    fn special(&self, e: &Expr) -> String {
        let x = |e: &Expr| dialect::expr(self, e);
        let w = self.w;
        match e {
            Expr::Fetch(r, i) => {
                let idx = x(i);
                if w.stage.tess() && *r == Resource::ControlPoints {
                    format!("{}({idx})", ident(&w.entries.tess.load_cp.name))
                } else if r.ty() == Ty::Vec3 {
                    format!("load_{}({idx})", r.name())
                } else {
                    format!("{}[{idx}]", r.name())
                }
            }
            Expr::TableWeight(row, col) => {
                let (tx, ty) = crate::plan::flat::table_texel(row, col);
                format!(
                    "texelFetch(stencil_table, ivec2(int({}), int({})), 0).x",
                    x(&tx),
                    x(&ty)
                )
            }
            Expr::Stage(StageIn::TessCoord(k)) => {
                // Quads: the patch's (u, v) is (gl_TessCoord.y, gl_TessCoord.x),
                // see the layout declaration; triangles: barycentric as is.
                let axes = if w.entries.sides == 4 {
                    ["y", "x", "z"]
                } else {
                    ["x", "y", "z"]
                };
                format!("gl_TessCoord.{}", axes[*k as usize])
            }
            Expr::Stage(StageIn::PatchInDraw) => "uint(gl_PrimitiveID)".into(),
            Expr::Float(r, i) => format!("{}[{}]", r.name(), x(i)),
            Expr::Stage(StageIn::GlobalId) => "gl_GlobalInvocationID.x".into(),
            Expr::Stage(StageIn::GlobalIdY) => "gl_GlobalInvocationID.y".into(),
            Expr::Stage(StageIn::WorkgroupId) => "gl_WorkGroupID.x".into(),
            Expr::Stage(StageIn::LocalIndex) => "gl_LocalInvocationIndex".into(),
            Expr::Stage(StageIn::VertexIndex) => "uint(gl_VertexIndex)".into(),
            Expr::Stage(StageIn::InstanceIndex) => "uint(gl_InstanceIndex)".into(),
            Expr::Stage(StageIn::Varying(_)) => {
                unreachable!("fragment input outside Entries::instanced")
            }
            Expr::PatchSlot(a, b) => format!("tcs_cp[{}][{}]", x(a), x(b)),
            Expr::Stage(StageIn::Param(n)) => param(n),
            Expr::Texel(r, a, b) => format!(
                "texelFetch({}, ivec2(int({}), int({})), 0).x",
                r.name(),
                x(a),
                x(b)
            ),
            _ => unreachable!("spelled by dialect::expr"),
        }
    }
}
