//! `generated/README.md`: the integration guide for engines that take the
//! generated shaders, printed from the same ABI table and Plan the printers
//! use, so it cannot drift from the code.

use super::abi::{self, Kind, BINDINGS, PARAMS};
use super::{header_lines, hlsl, wgsl};
use crate::plan::{ConstValue, Plan};
use crate::table::StencilTable;
use std::fmt::Write;

fn kind_text(k: Kind) -> (&'static str, &'static str, &'static str) {
    // (WGSL, GLSL, HLSL)
    match k {
        Kind::U32Buffer => ("array<u32>", "uint[] (std430)", "StructuredBuffer<uint>"),
        Kind::Vec3Buffer => (
            "array<f32> (xyz triples)",
            "float[] (std430, xyz triples)",
            "StructuredBuffer<float> (xyz triples)",
        ),
        Kind::F32Buffer => (
            "array<f32>",
            "float[] (std430)",
            "RWStructuredBuffer<float>",
        ),
        Kind::Table => (
            "texture_2d<f32>",
            "sampler2D (texelFetch)",
            "Texture2D<float> (Load)",
        ),
        Kind::Uniform => (
            "var<uniform> Params",
            "uniform Params (std140)",
            "cbuffer Params",
        ),
    }
}

/// The README text.
pub fn readme(plan: &Plan, table: &StencilTable, command: &str) -> String {
    let mut s = String::new();
    for h in header_lines(command) {
        let _ = writeln!(s, "<!-- {h} -->");
    }
    let schemes: Vec<&str> = plan.schemes.iter().map(|(m, _)| m.name.as_str()).collect();
    let _ = writeln!(s, "\n# Generated tessellation code\n");
    let _ = writeln!(
        s,
        "Schemes: {}. Everything here is printed from one Plan per scheme; do not edit, \
         regenerate with `cargo run -p tessgen -- generate --out generated`.\n",
        schemes
            .iter()
            .map(|n| format!("`{n}`"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    s.push_str(
        "| path | what |\n|---|---|\n\
         | `table/stencils.f32`, `table/stencils.json` | the per-valence stencil table (f32 LE, row-major) and its manifest |\n\
         | `rust/tessgen.rs` | CPU kernels (glam `Vec3`), one module per scheme |\n\
         | `wgsl/<scheme>.wgsl` | WebGPU: compute construction, compute evaluation, instanced vertex evaluation |\n\
         | `glsl/<scheme>.{vert,tesc,tese}`, `glsl/<scheme>_{vertex_stage,patch,eval}.comp` | GLSL 450 (Vulkan): tessellation pipeline and compute |\n\
         | `hlsl/<scheme>.hlsl` | HLSL SM 5.0: `vs_main`/`hs_main`/`ds_main` and the compute entry points (listed as `// entry:` lines in each file's header) |\n\n",
    );
    s.push_str("## Pipeline\n\n");
    s.push_str(
        "1. **Vertex stage** (`vertex_stage_main`, compute, one thread per vertex): for each vertex, \
         `ROWS_PER_N·n + ROWS_FIXED` points into `vertex_out` at `vertex_out_offsets[vertex]`, each the \
         sum over ring slots `0..2n` (ring order) of table weight × position.\n\
         2. **Patch stage** (`patch_main` compute, or the hull shader's patch-constant phase): for each \
         patch, its control points from the four corners' vertex-stage outputs.\n\
         3. **Evaluation** (`eval_main` compute into `samples`, `eval_vs` instanced vertex shader, or the \
         domain shader): position and normal at `(u, v) = (iu, iv)/level`.\n\n\
         Patches are sorted by facet class (index into the scheme's patch classes, see below); one \
         dispatch or draw per class, with `params.class`, `params.first` (first patch in `patch_faces`), \
         `params.count` and `params.cp_base` (first control point of the class).\n\n",
    );
    s.push_str("## Bindings (descriptor set / bind group 0)\n\n");
    s.push_str("HLSL: register `tN` for read-only, `uN` for written (`[[vk::binding(N, 0)]]` as well), `b10` for Params.\n\n");
    s.push_str("| binding | name | WGSL | GLSL | HLSL | contents |\n|---|---|---|---|---|---|\n");
    for b in BINDINGS {
        let (w, g, h) = kind_text(b.kind);
        let _ = writeln!(
            s,
            "| {} | `{}` | {w} | {g} | {h} | {}{} |",
            b.binding,
            b.name,
            b.doc,
            if b.written { " (written)" } else { "" }
        );
    }
    s.push_str("\nvec3 buffers are tightly packed f32 triples: element `i` is floats `3i, 3i+1, 3i+2` (12 bytes, no padding).\n\n");
    let _ = writeln!(
        s,
        "### `Params` ({} bytes, std140/WGSL uniform layout)\n",
        abi::PARAMS_SIZE
    );
    s.push_str("| offset | field | meaning |\n|---|---|---|\n");
    for (name, doc) in PARAMS {
        let _ = writeln!(s, "| {} | `{name}` | {doc} |", abi::params_offset(name));
    }
    s.push_str("\nThe field `class` is spelled `class_` in the shaders (a reserved word in WGSL, GLSL and HLSL).\n\n");
    let _ = writeln!(
        s,
        "### `adaptive` ({} f32, binding 19)\n",
        abi::ADAPTIVE_LEN
    );
    s.push_str("Read by `tessgen_edge_factor` in GLSL/HLSL builds with `-DTESSGEN_ADAPTIVE` (the control stage then sets one factor per edge from the edge's end points in canonical order; the evaluation stage reads the coordinate on the 2^-16 fixed-point grid). Metric: screen space by default, `-DTESSGEN_METRIC_DISTANCE`, or `-DTESSGEN_METRIC_BUFFER` (`edge_factors[face_edges[4f + k]]`, triangles `3f + k`, bindings 17 and 18). Partitioning: integer by default, `-DTESSGEN_FRACTIONAL_ODD` or `-DTESSGEN_FRACTIONAL_EVEN`. Quad and triangle schemes (triangles: outer factor k for the edge opposite corner k, the inside factor the largest of the three; the evaluation stage passes the barycentric point to `eval_domain` at level 2^16).\n\n");
    s.push_str("| floats | meaning |\n|---|---|\n");
    for (_, first, count, doc) in abi::ADAPTIVE {
        let _ = writeln!(s, "| {first}..{} | {doc} |", first + count);
    }
    s.push('\n');
    s.push_str("### Displacement in the tessellation stages (`-DTESSGEN_DISPLACE`)\n\n");
    s.push_str("Quad schemes: the GLSL `.tese` and HLSL `ds_main` built with `-DTESSGEN_DISPLACE` call `eval_displaced_tess`: the patch's own sample from its patch-local control points, then the displacement step of `eval_displaced` (bindings 21–24), whose owner normal on the patch boundary comes from `eval_global`, reading the global `control_points` buffer (binding 8). Run the compute patch stage (`patch_main`, class-sorted layout, the `cp_base` the owner records name) before the draw. The stage then also binds `patch_faces` (11), `control_points` (8, read-only) and bindings 21–24. Without the define the stages are unchanged. Works with `-DTESSGEN_ADAPTIVE` too. Triangle schemes displace in the compute/instanced evaluation (`eval_displaced`, 12 texture coordinates and 6 owner records per triangle, bindings 21–24) but not in their tessellation stages.\n\n");
    s.push_str("## Stencil table texture\n\n");
    let _ = writeln!(
        s,
        "`R32Float`, width {} (= 2·MAX_VALENCE + 1 ring slots, MAX_VALENCE = {}), height {} rows. \
         Texel (x = ring slot, y = row); read with `textureLoad`/`texelFetch`/`Load`, never filtered. \
         Rows per scheme and valence: `ROW_BASE[n]` in each scheme's code and `schemes[].valence_row_base` \
         in `table/stencils.json`; per-valence constants at row `CONST_ROW_BASE + n − 3`.\n",
        table.width,
        table.max_valence,
        table.height()
    );
    s.push_str("## Per scheme\n\n");
    for (m, e) in &plan.schemes {
        let get = |n: &str| {
            m.consts
                .iter()
                .find(|c| c.name == n)
                .map(|c| match &c.value {
                    ConstValue::U32(x) => *x,
                    ConstValue::U32Array(_) => 0,
                })
        };
        let _ = writeln!(
            s,
            "### `{}`\n\nVertex-stage points per vertex: {}·n + {}.\n",
            m.name,
            get("ROWS_PER_N").unwrap_or(0),
            get("ROWS_FIXED").unwrap_or(0)
        );
        s.push_str("| class | faces | form | control points | layout |\n|---|---|---|---|---|\n");
        for (k, p) in e.patches.iter().enumerate() {
            let layout = match p.form {
                crate::form::Form::Bicubic => "Bézier net `G[k][l]` at `4k + l` (k along u)",
                crate::form::Form::CPatch => "`6i + {v, t0, t1, b211, b121, b112}` per corner i",
                crate::form::Form::Acc => {
                    "geometry `G[k][l]` at `4k + l`; tangent coefficients at \
                     `16 + 6i + {da00, da01, da10, da11, db00, db10}` in corner i's frame \
                     (a toward v_{i+1}, b toward v_{i-1})"
                }
                crate::form::Form::Gregory => {
                    "`5i + {P, E⁺, E⁻, F⁺, F⁻}` per corner i (OpenSubdiv order)"
                }
                crate::form::Form::TriCubic => {
                    "`5i + {b, bn, bp, n, nm}` per corner i, centre at 15 (cubic triangle + quadratic normal field)"
                }
            };
            let faces = match p.class {
                crate::Class::Ordinary => "all corners valence 4",
                crate::Class::Extraordinary => "some corner valence ≠ 4",
                crate::Class::Triangle => "every triangle",
            };
            let _ = writeln!(
                s,
                "| {k} (`{}`) | {faces} | {} | {} | {layout} |",
                p.class.name(),
                p.form.name(),
                p.control_points
            );
        }
        s.push('\n');
    }
    s.push_str("## Conventions\n\n");
    s.push_str(
        "* **Faces and (u, v)**: corners `v0..v3` counter-clockwise seen from outside; `(u, v) = (0, 0)` at \
         `v0`, `u` along `v0 → v1`, `v` along `v0 → v3`; `∂S/∂u × ∂S/∂v` points outward.\n\
         * **Rings**: `ring[ring_offsets[p]..]` = `[p, p_0 … p_{2n−1}]`, counter-clockwise, even slots edge \
         neighbours, odd slots the diagonal vertex of each sector; stored once per vertex with a canonical \
         start. `corner_sector[4f + i]` = `j` with `p_{2j} = v_{i+1}` in corner i's ring.\n\
         * **Tessellation factors**: every edge factor and both inside factors equal `params.level` \
         (integer partitioning), a per-edge value computed from the edge alone, so both patches of an edge \
         agree. `(level + 1)²` samples per patch.\n\
         * **Domain coordinates**: evaluation works on integers `iu, iv ∈ 0..=level`; the hardware \
         tessellator's `(u, v)` are rounded back to them. Samples with `iu` or `iv` ∈ {0, level} take \
         their position from the one shared edge evaluator (`tessgen_edge`, `precise` in GLSL/HLSL): \
         symmetric de Casteljau with weights `(level − i)/level`, `i/level` formed from integers, so both \
         patches of an edge produce the same bits. GLSL: the `.tese` takes `(u, v)` = \
         `(gl_TessCoord.y, gl_TessCoord.x)` (Vulkan's upper-left domain origin); HLSL: `SV_DomainLocation` as is.\n\
         * **WGSL instanced drawing**: draw an index buffer over the `(level+1)²` grid (vertex id \
         `iv·(level+1) + iu`, counter-clockwise triangles) with one instance per patch of the class.\n\n",
    );
    s.push_str("## Entry points\n\n| target | entry | stage |\n|---|---|---|\n");
    for (n, st) in wgsl::ENTRY_POINTS {
        let _ = writeln!(s, "| WGSL | `{n}` | {st} |");
    }
    for (n, st) in hlsl::ENTRY_POINTS {
        let _ = writeln!(s, "| HLSL | `{n}` | {st} |");
    }
    s.push_str("| GLSL | `main` of each file | by extension: `.vert .tesc .tese .comp` |\n");
    s
}
