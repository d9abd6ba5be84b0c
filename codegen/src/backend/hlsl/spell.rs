//! The HLSL [`Dialect`]: what this target spells its own way (types,
//! literals, names, memory, stage inputs and outputs); everything else is
//! the shared spelling layer's ([`crate::backend::dialect`]).

use super::*;

/// The HLSL dialect, for one function (`cx`: its local names, how it
/// reaches the control points).
pub(super) struct Hx<'c, 'a> {
    pub(super) w: &'c Writer<'a>,
    pub(super) cx: &'c Ctx<'c>,
}

impl Dialect for Hx<'_, '_> {
    fn plan(&self) -> &Plan {
        self.w.plan
    }
    fn module(&self) -> &Module {
        self.cx.m
    }
    fn function(&self) -> &Function {
        self.cx.f
    }
    fn ident(&self, name: &str) -> String {
        ident(name)
    }
    fn local(&self, id: LocalId) -> String {
        self.cx.names[id.0].clone()
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
        "float2"
    }
    fn vec3_ty(&self) -> &'static str {
        "float3"
    }
    fn builtin_override(&self, b: Builtin, a: &[String]) -> Option<String> {
        // firstbitlow(0) is 0xffffffff: clamp to WGSL's 32.
        match b {
            Builtin::CountTrailingZeros => Some(format!("min(firstbitlow({}), 32u)", a[0])),
            Builtin::Project => Some(format!("mul(params.view_proj, float4({}, 1.0f))", a[0])),
            _ => None,
        }
    }
    /// Functions that reach the control points take the caller's array.
    fn call(&self, r: FnRef, callee: &Function, args: Vec<String>) -> String {
        let (module, _) = self.w.callee(self.cx.m, r);
        let mut a = Vec::new();
        if self.w.cp_of(module, callee) != Cp::None {
            a.push(self.cx.cp.name().to_string());
        }
        a.extend(args);
        format!("{}({})", ident(&callee.name), a.join(", "))
    }
    fn make(&self, s: usize, args: Vec<String>) -> String {
        let name = &self.w.plan.common.structs[s].name;
        format!("make_{name}({})", args.join(", "))
    }
    fn decl(&self, id: LocalId, _mutable: bool) -> String {
        self.w.decl(self.cx, &id)
    }
    fn if_head(&self, c: &Expr) -> String {
        format!("if ({}) {{", dialect::expr(self, c))
    }
    fn for_head(&self, id: LocalId, start: String, end: String, step: Option<String>) -> String {
        let v = self.local(id);
        let step = step.unwrap_or_else(|| "1u".into());
        format!(
            "for ({} = {start}; {v} < {end}; {v} += {step}) {{",
            self.w.decl(self.cx, &id)
        )
    }
    fn preprocessor(&self) -> bool {
        true
    }
    fn special_stmt(&self, s: &Stmt, out: &mut Lines) {
        let x = |e: &Expr| dialect::expr(self, e);
        let cx = self.cx;
        match s {
            Stmt::Store(r, i, v) => {
                let (i, v) = (x(i), x(v));
                let s = match (r, r.ty()) {
                    (Resource::ControlPoints, _) => format!("{}[{i}] = {v};", cx.cp.name()),
                    (_, Ty::Vec3) => format!("store_{}({i}, {v});", r.name()),
                    _ => format!(
                        "{}[{i}] = {v};",
                        write_view(abi::binding_of(*r)).unwrap_or_else(|| r.name().to_string())
                    ),
                };
                out.line(&s);
            }
            Stmt::StoreFloat(r, i, v) => {
                let b = abi::binding_of(*r);
                out.line(&format!(
                    "{}[{}] = {};",
                    write_view(b).unwrap_or_else(|| r.name().to_string()),
                    x(i),
                    x(v)
                ));
            }
            Stmt::Barrier(Barrier::Workgroup) => out.line("GroupMemoryBarrierWithGroupSync();"),
            Stmt::Barrier(Barrier::Storage) => out.line("DeviceMemoryBarrierWithGroupSync();"),
            Stmt::StorePatchSlot(a, b, v) => {
                out.line(&format!("c.cp[{}][{}] = {};", x(a), x(b), x(v)))
            }
            Stmt::StorePatchCp(j, v) => out.line(&format!(
                "{}(c, {}, {});",
                ident(&self.w.entries.tess.store_cp.name),
                x(j),
                x(v)
            )),
            Stmt::ClearPatchSlot(a) => {
                out.line(&format!("c.cp[{}] = float4(0.0f, 0.0f, 0.0f, 0.0f);", x(a)))
            }
            Stmt::PatchLocal => {
                out.line(&format!("float3 {}[{}];", cx.cp.name(), Named::Kmax.name()))
            }
            Stmt::Output(o, e) => {
                let v = dialect::expr(self, e);
                let sides = self.w.entries.sides;
                // HLSL's quad domain is (u, v) = (x, y): its slots are
                // `hw_factor_edges(sides, true)`.
                let slot = crate::plan::abi::factor_slot(sides, *o, true).unwrap_or_default();
                match o {
                    StageOut::EdgeFactor(_) => {
                        out.line(&format!("c.edges[{slot}] = {v};"));
                    }
                    StageOut::InsideFactor(_) => {
                        if sides == 3 {
                            out.line(&format!("c.inside = {v};"));
                        } else {
                            out.line(&format!("c.inside[{slot}] = {v};"));
                        }
                    }
                    StageOut::Clip => out.line(&format!("o.position = {v};")),
                    StageOut::Position => out.line(&format!("o.world = {v};")),
                    StageOut::Normal => out.line(&format!("o.normal = {v};")),
                    StageOut::Domain => out.line(&format!("o.domain = {v};")),
                    StageOut::Patch => out.line(&format!("o.patch_index = {v};")),
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
        let cx = self.cx;
        match e {
            Expr::Fetch(r, i) => {
                let idx = x(i);
                match (r, r.ty()) {
                    (Resource::ControlPoints, _) => format!("{}[{idx}]", cx.cp.name()),
                    (_, Ty::Vec3) => format!("fetch_{}({idx})", r.name()),
                    _ => format!(
                        "{}[{idx}]",
                        read_view(abi::binding_of(*r)).unwrap_or_else(|| r.name().to_string())
                    ),
                }
            }
            Expr::TableWeight(row, col) => {
                let (tx, ty) = crate::plan::flat::table_texel(row, col);
                format!(
                    "stencil_table.Load(int3(int({}), int({}), 0))",
                    x(&tx),
                    x(&ty)
                )
            }
            // SV_DomainLocation: quads (u, v) = (x, y), triangles barycentric.
            Expr::Stage(StageIn::TessCoord(k)) => format!("uv.{}", ["x", "y", "z"][*k as usize]),
            Expr::Stage(StageIn::PatchInDraw) => cx.patch.to_string(),
            Expr::Float(r, i) => format!(
                "{}[{}]",
                read_view(abi::binding_of(*r)).unwrap_or_else(|| r.name().to_string()),
                x(i)
            ),
            Expr::Stage(StageIn::GlobalId) => "global_id.x".into(),
            Expr::Stage(StageIn::GlobalIdY) => "global_id.y".into(),
            // The HLSL entries declare only SV_DispatchThreadID.
            Expr::Stage(
                StageIn::WorkgroupId
                | StageIn::LocalIndex
                | StageIn::VertexIndex
                | StageIn::InstanceIndex
                | StageIn::Varying(_),
            ) => unreachable!("entry input outside Entries::instanced"),
            Expr::PatchSlot(a, b) => format!("c.cp[{}][{}]", x(a), x(b)),
            Expr::PatchCp(j) => {
                format!("{}(c, {})", ident(&self.w.entries.tess.load_cp.name), x(j))
            }
            Expr::Stage(StageIn::Param(n)) => format!("params.{}", ident(n)),
            Expr::Texel(r, a, b) => {
                format!("{}.Load(int3(int({}), int({}), 0))", r.name(), x(a), x(b))
            }
            _ => unreachable!("spelled by dialect::expr"),
        }
    }
}
