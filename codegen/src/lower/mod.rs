//! Lowering: Scheme IR → Plan.
//!
//! All operation order is decided here, once, for every backend:
//! * the vertex stage sums ring slots 0, 1, …, 2n in ring order with the f32
//!   table weights, skipping exact zeros (DESIGN.md Rule 1);
//! * the patch stage unrolls the scheme's per-corner definitions in source
//!   order, folding number arithmetic in f64 before it becomes an f32 literal;
//! * evaluation forms every weight pair from integer tessellation
//!   coordinates and evaluates shared boundaries through one edge evaluator
//!   (symmetric de Casteljau; `spec/watertight.md` Rule 2).

use crate::front::scheme::{self, Class, Scheme, CORNER_VAR};
use crate::front::sym::{self, Sym};
use crate::plan::build::*;
use crate::plan::form::Form;
use crate::plan::{self, *};
use crate::table::{SchemeRows, StencilTable};
use std::collections::BTreeMap;

pub mod adaptive;
mod common;
pub mod displace;
pub mod entries;
mod eval;
mod grid;
mod patch;
pub mod refine;
mod surface;
pub mod tess;
mod vertex;
pub use common::common_module;
use eval::*;
use grid::*;
use patch::*;
use surface::*;
use vertex::*;

fn f32c(x: f64) -> Expr {
    Expr::F32(x as f32)
}

/// Lower one scheme to its module.
pub fn scheme_module(
    s: &Scheme,
    rows: &SchemeRows,
    sector_column: u32,
    max_sector_faces: u32,
) -> (Module, Entries) {
    let mut m = Module {
        name: s.name.clone(),
        doc: s.doc.clone(),
        ..Default::default()
    };
    let row_base = m.add_const(
        "ROW_BASE",
        "First stencil-table row of each valence's vertex-stage block (index = valence).",
        ConstValue::U32Array(rows.valence_row_base.clone()),
    );
    let const_row = m.add_const(
        "CONST_ROW_BASE",
        "Stencil-table row of valence 3's per-valence constants; valence n is row CONST_ROW_BASE + n - 3.",
        ConstValue::U32(rows.const_row_base),
    );
    let (ra, rb) = s.rows_linear();
    m.add_const(
        "ROWS_PER_N",
        "Vertex-stage outputs per vertex: ROWS_PER_N·n + ROWS_FIXED.",
        ConstValue::U32(ra),
    );
    m.add_const("ROWS_FIXED", "See ROWS_PER_N.", ConstValue::U32(rb));

    let sector = SectorConsts {
        row_base: m.add_const(
            "SECTOR_ROW_BASE",
            "First sector-region row of each sector block, index kind · SECTOR_MAX_FACES + m − 1 (kind 0 crease, 1 corner; m faces).",
            ConstValue::U32Array(rows.sector_row_base.clone()),
        ),
        column: m.add_const(
            "SECTOR_COLUMN",
            "First stencil-table column of the sector region: partial-ring slot k of a sector row is column SECTOR_COLUMN + k.",
            ConstValue::U32(sector_column),
        ),
        max_faces: m.add_const(
            "SECTOR_MAX_FACES",
            "Largest sector (faces) the table holds: MAX_VALENCE / 2.",
            ConstValue::U32(max_sector_faces),
        ),
    };
    let vertex_stage = m.functions.len();
    m.functions
        .push(vertex_stage_fn(s, row_base, &sector, ra, rb));

    let mut patches = Vec::new();
    for pc in &s.patches {
        let idx = m.functions.len();
        m.functions.push(patch_fn(s, pc, const_row));
        patches.push(PatchEntry {
            class: pc.class,
            form: pc.form,
            control_points: pc.form.num_points() as u32,
            function: idx,
        });
    }
    // Boundary curves of every class, flattened: [class][edge][points].
    let mut curves = Vec::new();
    for pe in &patches {
        for e in 0..pe.form.sides() {
            curves.extend(pe.form.edge_curve(e).iter().map(|&x| x as u32));
        }
    }
    let points = patches.first().map_or(4, |p| p.form.curve_points());
    let curve_const = m.add_const(
        "EDGE_CURVE",
        &if points == 4 {
            "Control-point indices of each class's cubic boundary curves: [class][edge][4], edge k runs v_k → v_{k+1}.".to_string()
        } else {
            format!("Control-point indices of each class's boundary curves of degree {}: [class][edge][{points}], edge k runs v_k → v_{{k+1}}.", points - 1)
        },
        ConstValue::U32Array(curves),
    );
    // Quartic boundaries: the module's own shared edge evaluator and the
    // quartic de Casteljau step of its surfaces (cubic schemes call the
    // common ones and emit neither).
    let (edge_fn, quartic) = if points == 4 {
        (FnRef::Common(common_fn::EDGE), None)
    } else {
        m.functions.push(crate::lower::common::edge_fn(points));
        m.functions.push(quartic_fn());
        let n = m.functions.len();
        (FnRef::Local(n - 2), Some(n - 1))
    };
    let mut surfaces = Vec::new();
    // Triangle forms: the surface at float barycentric weights, per class.
    let mut surfaces_at = Vec::new();
    for pe in &patches {
        let f = match pe.form {
            Form::Bicubic => bicubic_surface(pe.class),
            Form::CPatch => cpatch_surface(pe.class),
            Form::Acc => acc_surface(pe.class),
            Form::Gregory => gregory_surface(pe.class),
            Form::Gregory4 => gregory4_surface(pe.class, quartic.unwrap_or_default()),
            Form::TriCubic => {
                let at = m.functions.len();
                m.functions.push(tri_cubic_surface_at(pe.class));
                surfaces_at.push(at);
                tri_cubic_surface(pe.class, at)
            }
        };
        surfaces.push(m.functions.len());
        m.functions.push(f);
    }
    let sides = s.facet.sides() as u32;
    let eval = m.functions.len();
    m.functions
        .push(eval_fn(&patches, &surfaces, curve_const, sides, edge_fn));
    let eval_domain = if sides == 3 && surfaces_at.len() == patches.len() {
        m.functions.push(eval_domain_fn(eval, &surfaces_at));
        Some(m.functions.len() - 1)
    } else {
        None
    };
    let grid = [
        m.functions.len(),
        m.functions.len() + 1,
        m.functions.len() + 2,
    ];
    m.functions.extend(grid_fns(sides));
    let grid_index = m.functions.len();
    m.functions.push(grid_index_fn(sides));
    // The displacement step (16 texture coordinates per quad patch, 12 per
    // triangle).
    let eval_displaced = {
        let height = m.functions.len();
        m.functions.push(crate::lower::displace::height_fn());
        let texcoord = m.functions.len();
        m.functions
            .push(crate::lower::displace::texcoord_fn(height, sides));
        let displace = m.functions.len();
        m.functions
            .push(crate::lower::displace::displace_point_fn());
        let idx = m.functions.len();
        m.functions.push(crate::lower::displace::eval_displaced_fn(
            &crate::lower::displace::Callees {
                eval,
                owner_eval: eval,
                texcoord,
                displace,
            },
            sides,
        ));
        (idx, texcoord, displace, height)
    };
    // Adaptive tessellation on the instanced path (quad and triangle
    // schemes: the same signatures, the domain's snap inside).
    let adaptive = {
        let (_, texcoord, displace, _) = eval_displaced;
        let edge_level = m.functions.len();
        m.functions
            .push(crate::lower::adaptive::patch_edge_level_fn(
                curve_const,
                sides,
                points as u32,
            ));
        let eval_a = m.functions.len();
        m.functions
            .push(crate::lower::adaptive::eval_adaptive_fn(eval, sides));
        let eval_ad = m.functions.len();
        m.functions
            .push(crate::lower::adaptive::eval_adaptive_displaced_fn(
                crate::lower::displace::Callees {
                    eval,
                    owner_eval: eval,
                    texcoord,
                    displace,
                },
                sides,
            ));
        AdaptiveEntries {
            edge_level,
            eval: eval_a,
            eval_displaced: eval_ad,
        }
    };
    // Triangles: the displacement step at the tessellator's float domain
    // point (integer path on the boundary, raw point inside); the CPU's
    // copy calls `eval_displaced` (the parity reference of the captures).
    let domain_displaced = eval_domain.map(|ed| {
        let (idx, _, displace, height_fn) = eval_displaced;
        let height = m.functions.len();
        m.functions
            .push(crate::lower::displace::height_at_domain_fn(height_fn));
        let f = m.functions.len();
        m.functions
            .push(crate::lower::displace::eval_domain_displaced_fn(
            &crate::lower::displace::DomainCallees {
                boundary: idx,
                eval_domain: ed,
                height,
                displace,
            },
            "eval_domain_displaced",
            "eval_domain with the displacement step (watertight.md Rules 4 and 5): on the patch \
             boundary (a coordinate exactly 0) eval_displaced at the integer grid point \
             (round(y·level), round(z·level)), the owner's normal and texture coordinate like \
             every other patch of the edge; inside, the raw point displaced along its own normal \
             by the height at its interior texture coordinate (tessgen_height_at_domain).",
        ));
        (f, ed, height, displace)
    });
    // The tessellation stages' variant: own sample from the patch-local
    // control points, the owner's from the global buffer.
    let tess_displaced = {
        let (own_displaced, texcoord, displace, _) = eval_displaced;
        let start = m.functions.len();
        // `eval_displaced` on the global buffer, with `eval_global` and the
        // surface copies under it.
        let globals = crate::lower::displace::global_variants(&mut m, own_displaced);
        let owner_eval = crate::lower::displace::global_of(&globals, eval);
        let compute_eval = crate::lower::displace::global_of(&globals, own_displaced);
        let idx = m.functions.len();
        m.functions
            .push(crate::lower::displace::eval_displaced_tess_fn(
                &crate::lower::displace::Callees {
                    eval,
                    owner_eval,
                    texcoord,
                    displace,
                },
                sides,
            ));
        let domain = domain_displaced.map(|(_, ed, height, displace)| {
            m.functions.push(crate::lower::displace::eval_domain_displaced_fn(
                &crate::lower::displace::DomainCallees {
                    boundary: idx,
                    eval_domain: ed,
                    height,
                    displace,
                },
                "eval_domain_displaced_tess",
                "eval_domain_displaced for the tessellation evaluation stage: the boundary through \
                 eval_displaced_tess (own sample from the patch-local control points, the owner's \
                 normal from the global control-point buffer), the interior displaced along its \
                 own normal.",
            ));
            m.functions.len() - 1
        });
        Some(TessDisplaced {
            eval_displaced: idx,
            eval_domain: domain,
            eval_displaced_global: compute_eval,
            functions: start..m.functions.len(),
        })
    };
    let eval_domain_displaced = domain_displaced.map(|d| d.0);
    let eval_displaced = Some(eval_displaced.0);
    let mut entries = Entries {
        vertex_stage,
        patches,
        eval,
        eval_domain,
        eval_displaced,
        eval_domain_displaced,
        tess_displaced,
        sides,
        grid,
        grid_index,
        adaptive,
        tess: TessStages {
            control: Function::new("", ""),
            evaluation: Function::new("", ""),
            hull: Function::new("", ""),
            unpack: Function::new("", ""),
            store_cp: Function::new("", ""),
            load_cp: Function::new("", ""),
            points: 0,
            slots: 0,
        },
        compute_vertex: Function::new("", ""),
        compute_eval: Function::new("", ""),
        compute_patch: Function::new("", ""),
        compute_patch_local: Function::new("", ""),
        compute_refine: crate::lower::refine::refine_main(),
        instanced: Vec::new(),
    };
    // The hardware tessellation stages' bodies call the functions above.
    entries.tess = crate::lower::tess::stages(&entries, curve_const);
    entries.compute_vertex = crate::lower::tess::compute_vertex(&entries);
    entries.compute_eval = crate::lower::tess::compute_eval(&entries);
    entries.compute_patch = crate::lower::entries::patch_main(&entries);
    entries.compute_patch_local = crate::lower::tess::compute_patch_local(&entries);
    entries.instanced = crate::lower::entries::instanced(&entries);
    (m, entries)
}

/// Lower every scheme against one stencil table.
pub fn plan(schemes: &[Scheme], table: &StencilTable) -> Plan {
    let common = common_module(table);
    let schemes = schemes
        .iter()
        .zip(&table.schemes)
        .map(|(s, rows)| scheme_module(s, rows, table.sector_column, table.max_sector_faces))
        .collect();
    Plan { common, schemes }
}
