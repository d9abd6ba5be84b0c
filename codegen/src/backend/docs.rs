//! `generated/README.md`: the integration guide for engines that take the
//! generated shaders, printed from the same ABI table and Plan the printers
//! use, so it cannot drift from the code.

use super::abi::{self, Access, Kind, BINDINGS, PARAMS};
use super::{header_lines, hlsl};
use crate::markdown::table_cell;
use crate::plan::{ConstValue, Plan};
use crate::table::StencilTable;
use std::fmt::Write;

/// The WGSL, GLSL and HLSL declarations of binding `b`, one per view
/// (bindings 5 and 8 have a `read_write` and a `read` view in WGSL and
/// HLSL; GLSL files declare the one view they use).
fn decl_text(b: &abi::Binding) -> (String, String, String) {
    let views = abi::wgsl_views(b);
    let wgsl = views
        .iter()
        .map(|(name, access)| match b.kind {
            Kind::Table => format!("`{name}: texture_2d<f32>`"),
            Kind::Uniform => format!("`{name}: var<uniform> Params`"),
            Kind::U32Buffer | Kind::F32Buffer | Kind::Vec3Buffer => {
                let elem = if b.kind == Kind::U32Buffer {
                    "u32"
                } else {
                    "f32"
                };
                let acc = match access {
                    Access::Read => "read",
                    Access::ReadWrite => "read_write",
                };
                format!("`{name}: var<storage, {acc}> array<{elem}>`")
            }
        })
        .collect::<Vec<_>>()
        .join("<br>");
    let (g_elem, h_elem) = match b.kind {
        Kind::U32Buffer => ("uint", "uint"),
        _ => ("float", "float"),
    };
    let (glsl, hlsl) = match b.kind {
        Kind::Table => (
            "sampler2D (texelFetch)".to_string(),
            "`Texture2D<float>` (Load)".to_string(),
        ),
        Kind::Uniform => (
            "uniform Params (std140)".to_string(),
            "cbuffer Params".to_string(),
        ),
        _ if b.written && b.resource.is_some() => (
            format!("{g_elem}[] (std430; readonly where only read)"),
            format!(
                "`StructuredBuffer<{h_elem}> {0}`<br>`RWStructuredBuffer<{h_elem}> {0}_rw`",
                b.name
            ),
        ),
        _ if b.written => (
            format!("{g_elem}[] (std430)"),
            format!("`RWStructuredBuffer<{h_elem}>`"),
        ),
        _ => (
            format!("readonly {g_elem}[] (std430)"),
            format!("`StructuredBuffer<{h_elem}>`"),
        ),
    };
    (wgsl, glsl, hlsl)
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
    s.push_str(INPUTS);
    s.push_str("## Bindings (descriptor set / bind group 0)\n\n");
    s.push_str("HLSL: register `tN` for read-only, `uN` for written (`[[vk::binding(N, 0)]]` as well), `b10` for Params.\n\n");
    s.push_str("| binding | name | WGSL | GLSL | HLSL | contents |\n|---|---|---|---|---|---|\n");
    for b in BINDINGS {
        let (w, g, h) = decl_text(b);
        let _ = writeln!(
            s,
            "| {} | `{}` | {w} | {g} | {h} | {}{} |",
            b.binding,
            b.name,
            table_cell(b.doc),
            if b.written { " (written)" } else { "" }
        );
    }
    let _ = writeln!(
        s,
        "\nBinding {} is never declared by the emitted shaders: the runtime's Vulkan harness uses it for its own \
         geometry-shader capture.",
        abi::HARNESS_TRIANGLES
    );
    s.push_str("\nvec3 buffers are tightly packed f32 triples: element `i` is floats `3i, 3i+1, 3i+2` (12 bytes, no padding).\n\n");
    let _ = writeln!(
        s,
        "### `Params` ({} bytes, std140/WGSL uniform layout)\n",
        abi::PARAMS_SIZE
    );
    s.push_str("| offset | field | meaning |\n|---|---|---|\n");
    for (name, doc) in PARAMS {
        let _ = writeln!(
            s,
            "| {} | `{name}` | {} |",
            abi::params_offset(name),
            table_cell(doc)
        );
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
        let _ = writeln!(s, "| {first}..{} | {} |", first + count, table_cell(doc));
    }
    s.push('\n');
    s.push_str("### Displacement in the tessellation stages (`-DTESSGEN_DISPLACE`)\n\n");
    s.push_str("Quad schemes: the GLSL `.tese` and HLSL `ds_main` built with `-DTESSGEN_DISPLACE` call `eval_displaced_tess`: the patch's own sample from its patch-local control points, then the displacement step of `eval_displaced` (bindings 21–24), whose owner normal on the patch boundary comes from `eval_global`, reading the global `control_points` buffer (binding 8). Run the compute patch stage (`patch_main`, class-sorted layout, the `cp_base` the owner records name) before the draw. The stage then also binds `patch_faces` (11), `control_points` (8, read-only) and bindings 21–24. Without the define the stages are unchanged. Works with `-DTESSGEN_ADAPTIVE` too. Triangle schemes displace in the compute/instanced evaluation (`eval_displaced`, 12 texture coordinates and 6 owner records per triangle, bindings 21–24) but not in their tessellation stages.\n\n");
    s.push_str("## Stencil table texture\n\n");
    let _ = writeln!(
        s,
        "`R32Float`, {} × {} texels. The logical table has {} rows of `TABLE_WIDTH` = {} columns \
         (2·MAX_VALENCE + 1 = {} ring slots, MAX_VALENCE = {}, then from column {} the sector region); \
         its rows wrap into column blocks of `TABLE_BLOCK_ROWS` = {} rows, so logical row r, column c is \
         texel (x, y) = (c + TABLE_WIDTH·⌊r / TABLE_BLOCK_ROWS⌋, r mod TABLE_BLOCK_ROWS) — 4096 is the \
         texture side Vulkan guarantees, and the table outgrew WebGPU's default 8192. Every shader reads \
         with `textureLoad`/`texelFetch`/`Load` at that texel, never filtered. \
         Rows per scheme and valence: `ROW_BASE[n]` in each scheme's code and `schemes[].valence_row_base` \
         in `table/stencils.json`; per-valence constants at row `CONST_ROW_BASE + n − 3`. \
         Upload `table/stencils.f32` as it is: it is the texture, row-major (`writeTexture` with \
         `bytesPerRow` = 4·{}; `texture_width`, `texture_height` and `block_rows` are also in \
         `table/stencils.json`, and `TABLE_TEXTURE_WIDTH`/`TABLE_TEXTURE_HEIGHT` in the code), and bind it \
         at `stencil_table` (binding 9).\n",
        table.texture_width(),
        table.texture_height(),
        table.height(),
        table.width,
        table.sector_column,
        table.max_valence,
        table.sector_column,
        crate::table::TABLE_BLOCK_ROWS,
        table.texture_width()
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
                crate::plan::form::Form::Bicubic => "Bézier net `G[k][l]` at `4k + l` (k along u)",
                crate::plan::form::Form::CPatch => "`6i + {v, t0, t1, b211, b121, b112}` per corner i",
                crate::plan::form::Form::Acc => {
                    "geometry `G[k][l]` at `4k + l`; tangent coefficients at \
                     `16 + 6i + {da00, da01, da10, da11, db00, db10}` in corner i's frame \
                     (a toward v_{i+1}, b toward v_{i-1})"
                }
                crate::plan::form::Form::Gregory => {
                    "`5i + {P, E⁺, E⁻, F⁺, F⁻}` per corner i (OpenSubdiv order)"
                }
                crate::plan::form::Form::Gregory4 => {
                    "`7i + {P, E⁺, E⁻, M, F⁺, F⁻, G}` per corner i, centre at 28 (biquartic Gregory net, quartic boundaries)"
                }
                crate::plan::form::Form::TriCubic => {
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
        let _ = writeln!(
            s,
            "\n`patch_main` of `{}` uses bindings {}.\n",
            m.name,
            binding_list(&abi::patch_main_bindings(plan, m, e))
        );
    }
    s.push_str("## Conventions\n\n");
    s.push_str(
        "* **Faces and (u, v)**: corners `v0..v3` counter-clockwise seen from outside; `(u, v) = (0, 0)` at \
         `v0`, `u` along `v0 → v1`, `v` along `v0 → v3`; `∂S/∂u × ∂S/∂v` points outward.\n\
         * **Rings, sectors and corners**: see *Building the inputs* above (`ring`, `corner_sector` are defined \
         there by half-edges, never by searching vertex ids).\n\
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
    s.push_str(&entry_sections());
    s.push_str("\n### Other targets\n\n| target | entry | stage |\n|---|---|---|\n");
    for (n, st) in hlsl::ENTRY_POINTS {
        let _ = writeln!(s, "| HLSL | `{n}` | {st} |");
    }
    s.push_str("| GLSL | `main` of each file | by extension: `.vert .tesc .tese .comp` |\n");
    s
}

/// `5 (rw)`-style list of `(binding, access)`.
fn binding_list(b: &[(u32, Access)]) -> String {
    b.iter()
        .map(|(n, a)| match a {
            Access::Read => format!("{n}"),
            Access::ReadWrite => format!("**{n} (read_write)**"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// How a foreign host builds every input buffer from an OBJ quad mesh: the
/// topology rules the runtime's `topology` module implements, written out
/// so a host can reproduce its bits (tests/tests/foreign_host.rs does,
/// from this text alone).
const INPUTS: &str = "## Building the inputs (quad schemes)\n\n\
The control mesh must be manifold and consistently oriented (every edge shared by at most two \
faces, which run it in opposite directions), every face a quad, every used interior vertex of valence \
3..=MAX_VALENCE. The rules below are for a closed mesh without tags; open meshes and tags follow after them. \
Vertices are numbered in file order from 0; a vertex no face uses has valence 0 (it keeps its number).\n\n\
* **Half-edges.** Faces are numbered in file order; corner `i` of face `f` (corners `v0..v3` in file order, \
counter-clockwise seen from outside) is half-edge `h = 4f + i`, running `v_i → v_{i+1 mod 4}`. \
`next(h)` is corner `i+1 mod 4` of the same face, `prev(h)` corner `i−1 mod 4`; `twin(h)` is the half-edge of the \
other face that runs the same edge the other way.\n\
* **Valence** `n` of vertex `p`: its number of outgoing half-edges (= faces around it). `valence[p]` (binding 1).\n\
* **Sectors and the canonical start.** Sector 0 of `p` is its outgoing half-edge with the **smallest id** `h`; \
sector `j + 1` is `twin(prev(s_j))` (counter-clockwise around `p`); this visits all `n` outgoing half-edges.\n\
* **Ring.** For sector `j` with half-edge `s_j` in face `(p, a, b, c)` (from `s_j` on, in the face's own order): \
`p_{2j} = a` (the edge neighbour, `dest(s_j)`) and `p_{2j+1} = b` (the diagonal vertex). The ring of `p` is \
`[p, p_0, p_1, …, p_{2n−1}]` (2n + 1 entries), stored once in `ring` (binding 3), vertex after vertex in vertex \
order; `ring_offsets` (binding 2) has one entry per vertex plus a final one: `ring_offsets[p]` is where `p`'s \
ring starts, `ring_offsets[p + 1]` where it ends (an unused vertex has an empty ring).\n\
* **Vertex-stage outputs.** `vertex_out_offsets[p]` (binding 4, one per vertex plus a final total) are the \
running sums of `ROWS_PER_N·n + ROWS_FIXED` points (0 for an unused vertex; the numbers per scheme below); \
`vertex_out` (binding 5) holds 3 f32 per point, any contents before the vertex stage.\n\
* **Corners.** `corner_vertex[4f + i] = v_i` (binding 6) and `corner_sector[4f + i] = j` (binding 7), the sector \
of `v_i` whose half-edge `s_j` **is** half-edge `4f + i` (by half-edge identity: on small meshes a vertex can \
occur twice in one ring, so searching the ring for `v_{i+1}` can pick the wrong sector).\n\
* **Classes and patch order.** A face is `ordinary` (class 0) when its four corners all have valence 4, \
`extraordinary` (class 1) otherwise (a scheme with one class, like `regular`, refuses other faces). `patch_faces` \
(binding 11) lists the faces of class 0 in face order, then those of class 1; class `c` starts at \
`first = ` the number of patches of the classes before it, and its control points at `cp_base = Σ` over \
those classes of `count · CONTROL_POINTS[class]` (points; 3 f32 each in `control_points`, binding 8).\n\
* **Positions** (binding 0): 3 f32 per vertex, in vertex order.\n\
* **Smooth meshes: no sectors.** For a closed mesh without tags, bind `vertex_sectors` (binding 31) = one 0 per \
vertex plus a final 0 (every range empty), any 4-byte buffer at `sectors` (32), and `corner_valence` (33) = \
`valence[v_i]` at `4f + i`.\n\
* **Displacement off**: `eval_main` and `eval_vs` still use bindings 21–24. Bind `displace_info` = \
`[0, 1, 1, 0]` (scale 0: the sample is `eval`'s, bit for bit), any 4-byte buffers at 21 and 22, and a 1×1 \
`R32Float` texture at 24.\n\n\
Triangle schemes (`facet tri`): `corner_vertex[3f + i]`, positions, unit normals (binding 13), \
one class; no vertex stage, no rings.\n\n\
### Open meshes, creases and corners\n\n\
Boundaries and OpenSubdiv `t crease|corner|hole|interpolateboundary` tags (docs/boundaries.md in the \
tessgen repository has the full contract; the runtime's `mesh::topology` implements it):\n\n\
* An edge is **sharp** if it is a boundary edge (one face) or has crease sharpness > 0. A vertex is a \
**corner** (vertex sharpness > 0, three or more sharp edges, or a one-face boundary vertex under \
`interpolateboundary 1`, the default), a **crease** (two sharp edges), a **dart** (one) or **smooth** (none). \
Smooth vertices and darts are built exactly as above.\n\
* **Ring positions.** Every vertex has one position per incident edge: `valence[p]` = faces for an interior \
vertex, faces + 1 for a boundary vertex (its trailing boundary edge has no outgoing half-edge). \
`corner_sector[4f + i]` is the position of the face's edge `v_i → v_{i+1}`.\n\
* **Canonical start of a crease or corner vertex**: a boundary vertex starts at its leading boundary edge (the \
one whose half-edge `p → q_0` exists); an interior one at the sharp edge whose outgoing half-edge has the \
smallest id. Positions then run counter-clockwise.\n\
* **Sectors.** Sharp edges cut the fan into sectors; a sector of `m` faces covers positions `j0 … j0 + m` and \
its **partial ring** `[p, q_0, d_0, q_1, …, d_{m−1}, q_m]` (2m + 2 vertex indices, `q_i` the edge neighbour at \
position `j0 + i`, `d_i` the diagonal of face `j0 + i`) is stored in `ring`, the vertex's sectors one after the \
other (a corner with no sharp edge has one sector, the whole fan, with `q_m = q_0`). `vertex_sectors[p]` \
(binding 31, one per vertex plus a final total) is its first sector; `sectors` (binding 32) holds \
`SECTOR_WORDS` u32 per sector: kind (0 crease, 1 corner), `m`, positions written (`m`, or `m + 1` for the last \
sector of a boundary vertex), `j0`, and the index in `ring` of its partial ring. A sector may have at most \
`SECTOR_MAX_FACES` = MAX_VALENCE / 2 faces.\n\
* **Vertex-stage outputs** of a crease or corner vertex: `ROWS_PER_N · valence[p] + ROWS_FIXED` points, as for \
any vertex.\n\
* **`corner_valence[4f + i]`** (binding 33): the vertex valence at smooth and dart corners, the sector's \
virtual valence (4 if `m = 1`, else `2m`) at crease and corner corners.\n\
* **Classes.** A face is `ordinary` when each corner is regular: smooth of valence 4 with no sharp edge, a \
crease corner in a sector of 2 faces, or a corner in a sector of 1 face.\n\
* **Holes** (and, with `interpolateboundary 0`, faces touching the boundary) have no limit surface: build \
their patches like any other (their vertices take part in every ring) and do not draw or emit them.\n\n";

/// The WGSL entry points: bindings per entry, workgroup sizes, invocation
/// mapping, explicit layouts and split dispatches.
fn entry_sections() -> String {
    let mut s = String::new();
    s.push_str("## WGSL entry points\n\n");
    s.push_str(
        "Each entry uses exactly the bindings listed (`read_write` in bold; every other binding read-only \
         storage, the uniform block or a texture). With `layout: \"auto\"` a bind group must hold exactly \
         these bindings; with an explicit layout (below) declare these and bind them. `patch_main`'s list \
         depends on the scheme (given per scheme above); the two bindings listed are common to all.\n\n",
    );
    s.push_str(
        "| entry | stage | workgroup size | bindings | invocations |\n|---|---|---|---|---|\n",
    );
    for e in abi::WGSL_ENTRIES {
        let wg = if e.workgroup_size == 0 {
            "—".to_string()
        } else {
            e.workgroup_size.to_string()
        };
        let _ = writeln!(
            s,
            "| `{}` | {} | {wg} | {} | {} |",
            e.name,
            e.stage.name(),
            binding_list(e.bindings),
            e.invocation
        );
    }
    let _ = writeln!(
        s,
        "\nWORKGROUP_SIZE = {}, SAMPLE_FLOATS = {}, `grid_len(level)` = `(level + 1)²` for quad schemes \
         (sample `s` = `iv·(level + 1) + iu`; the WGSL's `grid_len`, `grid_iu`, `grid_iv` define it for every scheme).\n",
        abi::WORKGROUP_SIZE,
        abi::SAMPLE_FLOATS
    );
    s.push_str("### Explicit bind group layouts\n\n");
    s.push_str(
        "Group 0, one entry per binding of the entry's list: read-only storage → `buffer: { type: \"read-only-storage\" }`, \
         `read_write` → `buffer: { type: \"storage\" }`, `params` (10) → `buffer: { type: \"uniform\" }` \
         (at least `Params`' size), textures (9, 24) → `texture: { sampleType: \"unfilterable-float\", \
         viewDimension: \"2d\" }` (`R32Float` is not filterable; the shaders only `textureLoad`). Visibility: \
         `COMPUTE` for compute entries, `VERTEX` for `eval_vs` (`shade_fs`: `FRAGMENT`). Buffers are runtime-sized \
         arrays: bind at least 4 bytes (an empty array as one element).\n\n",
    );
    s.push_str("### Dispatching, and the per-dimension limit\n\n");
    let _ = writeln!(
        s,
        "A compute entry needs x = ⌈items / workgroup size⌉ workgroups (items: vertices, patches, or patches × \
         `grid_len(level)` samples for `eval_main`), y = z = 1. WebGPU guarantees only \
         `maxComputeWorkgroupsPerDimension` = {} workgroups per dimension (and 128 MiB per storage binding), so \
         a larger run is split into several dispatches, each with its own `Params` (a uniform buffer per \
         dispatch, or one with dynamic offsets), each covering `count` items so that ⌈count · per item / \
         WORKGROUP_SIZE⌉ stays within the limit:\n",
        abi::WEBGPU_MAX_WORKGROUPS_PER_DIMENSION
    );
    s.push_str(
        "* `vertex_stage_main`: `first` = the first vertex of the split, `count` its vertices.\n\
         * `patch_main`, per class: the split's patches are `k .. k + count` of the class: `first = class first + k`, \
         `cp_base = class cp_base + k · CONTROL_POINTS[class]`, `class` and `count` as named.\n\
         * `eval_main`, per class, likewise `first`, `cp_base`, `count`, plus `level` and `out_base`: sample `s` of \
         the split's patch `q` (0-based within the split) is written at sample index `out_base + q·grid_len(level) + s` \
         (floats `SAMPLE_FLOATS·` that index). Into one `samples` buffer in `patch_faces` order: \
         `out_base = (class first + k) · grid_len(level)`; into a buffer per split: `out_base = 0`.\n\
         * `eval_vs` draws `count` instances with `first`/`cp_base` as `patch_main`; the index buffer covers the \
         `(level + 1)²` grid (vertex id = sample `s`).\n\n",
    );
    s.push_str("### Core WebGPU and compatibility mode\n\n");
    s.push_str(
        "Every entry point compiles and builds its pipeline under WebGPU's default limits on wgpu (naga) and on \
         Dawn (Chrome's WebGPU, Tint), with no error and no warning: the tests `validate_wgsl` and `dawn` check \
         each file. In WebGPU's **compatibility mode** (`featureLevel: \"compatibility\"`) five entries per \
         file need core WebGPU:\n\n\
         * `eval_vs`, `eval_adaptive_vs`, `eval_adaptive_indirect_vs`: they read the control points and the \
         patch lists from storage buffers in the vertex stage, and compatibility mode's default \
         `maxStorageBuffersInVertexStage` is 0 (an adapter that allows more can be asked for it in \
         `requiredLimits`);\n\
         * `adaptive_count_main`, `adaptive_scatter_main`: their workgroups have 256 invocations, above \
         compatibility mode's default 128.\n\n\
         Every other entry builds in compatibility mode, `shade_fs` included: its flat `patch_class` input uses \
         `either` sampling (every vertex of a draw has the same class; compatibility mode has no `first`).\n",
    );
    s
}
