//! The bad-input matrix of docs/errors.md, run for real: every case is one
//! minimal input given to the `tessgen` binary (in a fresh temp directory,
//! which is the working directory, so messages name files as written), and
//! checks the exact `tessgen:` lines on stderr (clap's `error:` line for
//! usage errors) and the exit code, which is never ≥ 101 (a panic) or a
//! signal (a crash).
//!
//! `docs_errors_md_is_checked` keeps the doc honest: every error variant of
//! the library appears in it, every test it cites exists, and every row that
//! cites a case here shows that case's message and exit code verbatim.
//!
//! In expected lines, `…` stands for any text (device limits, process ids).

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data")
        .join(rel)
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// One row of the matrix.
struct Case {
    id: &'static str,
    args: Vec<String>,
    files: Vec<(String, Vec<u8>)>,
    env: Vec<(&'static str, String)>,
    expect: Vec<String>,
    code: i32,
}

/// `args` split at spaces; `expect` one line per `\n`.
fn case(id: &'static str, args: &str, expect: &str) -> Case {
    Case {
        id,
        args: args.split_whitespace().map(str::to_string).collect(),
        files: Vec::new(),
        env: Vec::new(),
        expect: expect.lines().map(str::to_string).collect(),
        code: 1,
    }
}

impl Case {
    fn file(mut self, name: &str, contents: impl Into<Vec<u8>>) -> Self {
        self.files.push((name.to_string(), contents.into()));
        self
    }
    /// A file of tests/data (e.g. `meshes/catmark_cube.obj`), copied in
    /// under its own name.
    fn data(self, rel: &str) -> Self {
        let bytes = std::fs::read(data(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"));
        let name = Path::new(rel).file_name().unwrap().to_str().unwrap();
        self.file(name, bytes)
    }
    fn env(mut self, key: &'static str, value: &str) -> Self {
        self.env.push((key, value.to_string()));
        self
    }
    fn code(mut self, code: i32) -> Self {
        self.code = code;
        self
    }
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
/// A closed tetrahedron, consistently oriented.
const TET: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
const CUBE: &str = "meshes/catmark_cube.obj";
const CUBE_UV: &str = "meshes/catmark_cube_uv.obj";
const MAP: &str = "displace/atlas_seams.png";
/// An 8193 × 1 grayscale PNG (88 bytes).
const WIDE_PNG: &str = "89504e470d0a1a0a0000000d4948445200002001000000010800000000bce214820000001f4944415478daedc1010900000002a0a637bd1d819a0200000000000000ff0622cb0171b15c4af40000000049454e44ae426082";

fn hex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect()
}

fn quad_with(tag: &str) -> String {
    format!("{QUAD}{tag}\n")
}

/// A disk of `n` quads around vertex 1 (valence `n`).
fn fan(n: usize) -> String {
    let mut s = String::from("v 0 0 0\n");
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        let b = std::f64::consts::TAU * (i as f64 + 0.5) / n as f64;
        s += &format!(
            "v {} {} 0\nv {} {} 0\n",
            a.cos(),
            a.sin(),
            2.0 * b.cos(),
            2.0 * b.sin()
        );
    }
    for i in 0..n {
        let (r, m, r2) = (2 + 2 * i, 3 + 2 * i, 2 + 2 * ((i + 1) % n));
        s += &format!("f 1 {r} {m} {r2}\n");
    }
    s
}

/// A half disk of `n` quads around boundary vertex 1: one sector of `n` faces.
fn half_fan(n: usize) -> String {
    let mut s = String::from("v 0 0 0\n");
    for i in 0..=n {
        let a = std::f64::consts::PI * i as f64 / n as f64;
        s += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    for i in 0..n {
        let b = std::f64::consts::PI * (i as f64 + 0.5) / n as f64;
        s += &format!("v {} {} 0\n", 2.0 * b.cos(), 2.0 * b.sin());
    }
    for i in 0..n {
        s += &format!("f 1 {} {} {}\n", 2 + i, 3 + n + i, 3 + i);
    }
    s
}

/// An `n × n` grid of quads.
fn grid(n: usize) -> String {
    let mut s = String::new();
    for j in 0..=n {
        for i in 0..=n {
            s += &format!("v {i} {j} 0\n");
        }
    }
    let at = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            s += &format!(
                "f {} {} {} {}\n",
                at(i, j),
                at(i + 1, j),
                at(i + 1, j + 1),
                at(i, j + 1)
            );
        }
    }
    s
}

/// A CCLIM001 header (faces, n, floats per sample) and `payload` bytes.
fn limit_file(faces: u32, n: u32, k: u32, payload: usize) -> Vec<u8> {
    let mut b = b"CCLIM001".to_vec();
    for x in [faces, n, k, 0, 0, 0] {
        b.extend_from_slice(&x.to_le_bytes());
    }
    b.resize(b.len() + payload, 0);
    b
}

/// The torus's crease tags with face 3's side at vertex 4 flipped.
fn flipped_side() -> String {
    let tags = std::fs::read_to_string(data("meshes/catmark_torus_crease.tags")).unwrap();
    tags + "side 3 4 -1\n"
}

fn tess(mesh: &str, rest: &str) -> String {
    format!("tessellate {mesh} --out o.obj {rest}")
}

#[rustfmt::skip]
fn cases() -> Vec<Case> {
    let obj = |id, text: &str, expect: &str| case(id, "inspect m.obj", expect).file("m.obj", text);
    let feature = |id, tag: &str, expect: &str| {
        case(id, &tess("m.obj", "--scheme pccm --level 2"), expect).file("m.obj", quad_with(tag))
    };
    let topo = |id, text: &str, expect: &str| {
        case(id, &tess("m.obj", "--scheme pccm --level 2"), expect).file("m.obj", text)
    };
    let tri = |id, text: &str, expect: &str| {
        case(id, &tess("m.obj", "--scheme pn --level 2"), expect).file("m.obj", text)
    };
    let tags = |id, text: &str, expect: &str| {
        case(id, &tess("tet.obj", "--scheme stpn --tags t.tags --level 2"), expect)
            .file("tet.obj", TET)
            .file("t.tags", text)
    };
    let render = |id, rest: &str, expect: &str| {
        case(id, &format!("render catmark_cube.obj --out o.png {rest}"), expect).data(CUBE)
    };
    vec![
        // ---- MeshError ----
        obj("obj_bad_number", &format!("{TRI}v 1 2 x\nf 1 2 3\n"),
            "tessgen: error: m.obj: unreadable OBJ (line 4): cannot parse coordinate `x` as a number"),
        obj("obj_polyline", &format!("{TRI}l 1 2 3\n"),
            "tessgen: error: m.obj: unreadable OBJ (line 4): polyline (`l`) elements are not supported in a surface mesh"),
        obj("obj_bad_face_vertex", &format!("{TRI}f 1 2 a\n"),
            "tessgen: error: m.obj: unreadable OBJ (line 4): bad face vertex `a`"),
        obj("obj_normal_index", &format!("{TRI}f 1//1 2//1 3//1\n"),
            "tessgen: error: m.obj: unreadable OBJ (line 4): normal index out of range"),
        obj("obj_texcoord_not_finite", &format!("{TRI}vt nan 0\nf 1/1 2/1 3/1\n"),
            "tessgen: error: m.obj: unreadable OBJ (line 4): texture coordinate is not finite"),
        obj("obj_malformed_tag", &format!("{TRI}f 1 2 3\nt crease\n"),
            "tessgen: error: m.obj: unreadable OBJ (line 5): malformed `t` tag line: …"),
        case("io_missing_mesh", "inspect none.obj",
            "tessgen: error: cannot read none.obj: No such file or directory (os error 2)"),
        obj("mesh_empty", "# nothing\n",
            "tessgen: error: m.obj: mesh has no faces or no vertices"),
        obj("mesh_non_finite", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
            "tessgen: error: m.obj: vertex 1 (line 2) has a non-finite coordinate"),
        case("mesh_too_large", &tess("m.obj", "--scheme pccm --level 2"),
            "tessgen: error: m.obj: vertex 2 at (1e30, 1e0, 0e0) makes the mesh too large to evaluate in f32: the bounding box's largest side is 1e30, at most 1.6777216e7 is supported (squared derivative lengths would overflow or round to nothing); scale or translate the mesh")
            .file("m.obj", "v 0 0 0\nv 1 0 0\nv 1e30 1 0\nv 0 1 0\nf 1 2 3 4\n"),
        obj("mesh_non_finite_normal", &format!("{TRI}vn 0 inf 1\nf 1 2 3\n"),
            "tessgen: error: m.obj: normal 0 (line 4) has a non-finite component"),
        obj("mesh_face_index", &format!("{TRI}f 1 2 3\nf 1 2 4\n"),
            "tessgen: error: m.obj: face 1 (line 5) refers to vertex 3 (0-based), which does not exist"),
        obj("mesh_face_index_zero", &format!("{TRI}f 0 1 2\n"),
            "tessgen: error: m.obj: face 0 (line 4) refers to vertex -1 (0-based), which does not exist"),
        obj("mesh_degenerate_face", &format!("{TRI}f 1 2\n"),
            "tessgen: error: m.obj: face 0 (line 4) has only 2 vertices"),
        obj("mesh_repeated_vertex", &format!("{TRI}f 1 2 2\n"),
            "tessgen: error: m.obj: face 0 (line 4) uses vertex 1 more than once"),
        // ---- FeatureError (through the topology: "invalid tags") ----
        feature("tag_unknown_vertex", "t crease 2/1/0 0 9 1",
            "tessgen: error: m.obj: invalid tags: line 6: tag `crease` names vertex 9, but the mesh has 4 vertices"),
        feature("tag_not_an_edge", "t crease 2/1/0 0 2 1",
            "tessgen: error: m.obj: invalid tags: line 6: crease 0-2 is not an edge of the mesh"),
        feature("tag_bad_sharpness", "t corner 1/1/0 0 -1",
            "tessgen: error: m.obj: invalid tags: line 6: tag `corner`: sharpness -1 must be finite and ≥ 0"),
        feature("tag_wrong_counts", "t crease 1/1/0 0 1",
            "tessgen: error: m.obj: invalid tags: line 6: tag `crease` has 1 ints, 1 floats and 0 strings; expected n ≥ 2 ints and 1 float (a chain), or 2k ints and k floats (pairs), no strings"),
        feature("tag_hole_out_of_range", "t hole 1/0/0 5",
            "tessgen: error: m.obj: invalid tags: line 6: hole face 5 does not exist (the mesh has 1 faces)"),
        feature("tag_bad_boundary_rule", "t interpolateboundary 1/0/0 7",
            "tessgen: error: m.obj: invalid tags: line 6: interpolateboundary 7 is not 0 (none), 1 (edge-and-corner) or 2 (edge-only)"),
        case("refine_bad_tag", "refine m.obj --out r", 
            "tessgen: error: m.obj: line 6: tag `crease` names vertex 9, but the mesh has 4 vertices")
            .file("m.obj", quad_with("t crease 2/1/0 0 9 1")),
        // ---- TopologyError ----
        case("topo_non_quad", "bench m.obj --levels 2 --runs 1",
            "tessgen: error: m.obj: face 0 has 3 vertices; this topology takes quads only (the front door, `tessgen_runtime::tessellate`, refines non-quad faces by one Catmull-Clark step first)")
            .file("m.obj", format!("{TRI}f 1 2 3\n")),
        topo("topo_non_manifold_edge",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 -1 0\nv 0 -1 0\nv 0 0 1\nv 1 0 1\nf 1 2 3 4\nf 2 1 6 5\nf 1 2 8 7\n",
            "tessgen: error: m.obj: edge 0-1 is used by more than two faces"),
        topo("topo_inconsistent_orientation",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 -1 0\nv 0 -1 0\nf 1 2 3 4\nf 1 2 5 6\n",
            "tessgen: error: m.obj: edge 0->1 is traversed in the same direction by both of its faces (inconsistent orientation)"),
        topo("topo_non_manifold_vertex",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0 0\nv -1 -1 0\nv 0 -1 0\nf 1 2 3 4\nf 1 5 6 7\n",
            "tessgen: error: m.obj: vertex 0 is non-manifold: its faces form more than one fan"),
        topo("topo_valence_too_high", &fan(33),
            "tessgen: error: m.obj: vertex 0 has valence 33, more than the maximum 32 of the stencil table (a table generated with `--max-valence 33` takes it)"),
        topo("topo_sector_too_large", &half_fan(17),
            "tessgen: error: m.obj: vertex 0 has a sector of 17 faces between sharp edges, more than max_valence / 2 = 16 (a stencil table generated with `--max-valence 34` takes it)"),
        topo("topo_valence_too_low", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 4 3 2 1\n",
            "tessgen: error: m.obj: vertex 0 has valence 2; interior vertices need at least 3"),
        case("refine_non_manifold_edge", "refine m.obj --out r",
            "tessgen: error: m.obj: edge 0-1 is used by more than two faces")
            .file("m.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 -1 0\nv 0 -1 0\nv 0 0 1\nv 1 0 1\nf 1 2 3 4\nf 2 1 6 5\nf 1 2 8 7\n"),
        // ---- TriMeshError (triangle schemes) ----
        case("tri_not_triangle_quad", &tess("catmark_cube.obj", "--scheme pn --level 2"),
            "tessgen: error: catmark_cube.obj: face 0 has 4 sides; triangle schemes need triangles (split quads: --split-quads, `Request::split_quads`)")
            .data(CUBE),
        case("tri_not_triangle_ngon", &tess("m.obj", "--scheme pn --split-quads --level 2"),
            "tessgen: error: m.obj: face 0 has 5 sides; triangle schemes need triangles")
            .file("m.obj", "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n"),
        tri("tri_non_manifold_edge", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
            "tessgen: error: m.obj: edge 0-1 is used by more than two triangles (faces [0, 1, 2])"),
        tri("tri_inconsistent_orientation", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nf 1 2 3\nf 1 2 4\n",
            "tessgen: error: m.obj: faces 0 and 1 both run along edge 0->1: inconsistent orientation"),
        tri("tri_missing_normal", &format!("{TRI}vn 0 0 1\nf 1//1 2//1 3\n"),
            "tessgen: error: m.obj: face 0 corner 2 has no normal but other corners do (drop the `vn` normals for area-weighted ones, or set `TriOptions::recompute_normals`)"),
        tri("tri_split_normal", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 0 1 0\nf 1//1 2//1 3//1\nf 2//2 4//2 3//2\n",
            "tessgen: error: m.obj: vertex 1 has different normals in faces 0 and 1 (split normals; drop the `vn` normals for area-weighted ones, or set `TriOptions::recompute_normals`)"),
        tri("tri_degenerate_normal", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n",
            "tessgen: error: m.obj: vertex 0 has no usable normal (zero or non-finite)"),
        // ---- TagError (stpn tag files) ----
        tags("tags_syntax_statement", "bogus 1\n",
            "tessgen: error: t.tags: tags line 1: unknown statement `bogus` (tag, side)"),
        tags("tags_syntax_index", "# comment\ntag 0\n",
            "tessgen: error: t.tags: tags line 2: `0` is not a 1-based vertex index"),
        tags("tags_syntax_number", "tag 1 tension\n",
            "tessgen: error: t.tags: tags line 1: `tension` needs a number"),
        tags("tags_vertex_out_of_range", "tag 9\n",
            "tessgen: error: t.tags: tags line 1: vertex 9 does not exist (the mesh has 4 vertices)"),
        tags("tags_face_out_of_range", "side 9 1 1\n",
            "tessgen: error: t.tags: tags line 1: face 9 does not exist (the mesh has 4 faces)"),
        tags("tags_not_in_face", "side 1 4 1\n",
            "tessgen: error: t.tags: tags line 1: vertex 4 is not a corner of face 1"),
        tags("tags_duplicate", "tag 1\ntag 1\n",
            "tessgen: error: t.tags: tags line 2: vertex 1 is tagged twice (first on line 1)"),
        tags("tags_not_finite", "tag 1 tension nan\n",
            "tessgen: error: t.tags: tags line 1: tension is not a finite number"),
        tags("tags_sharpness_range", "tag 1 sharpness 2\n",
            "tessgen: error: t.tags: tags line 1: sharpness 2 is outside [0, 1]"),
        tags("tags_bad_side", "side 1 1 0\n",
            "tessgen: error: t.tags: tags line 1: side must be +1 or -1, found 0"),
        case("tags_inconsistent_side", &tess("catmark_torus.obj", "--scheme stpn --split-quads --tags t.tags --level 2"),
            "tessgen: error: catmark_torus.obj: vertex 4 (1-based): faces 3 and 31 (1-based) lie in one sector of its crease (no crease edge between them) but were given different sides; the edges between them would open")
            .data("meshes/catmark_torus.obj")
            .file("t.tags", flipped_side()),
        tags("tags_three_crease_corners", "tag 1 delta 0 1 0\ntag 2 delta 0 1 0\ntag 3 delta 0 1 0\n",
            "tessgen: error: tet.obj: face 1 (1-based): all three corners of one of its triangles carry a crease vector; scalar-tagged PN allows at most two crease vertices per triangle (spec/pn.md §3)"),
        case("tags_unreadable", &tess("tet.obj", "--scheme stpn --tags none.tags --level 2"),
            "tessgen: error: none.tags: No such file or directory (os error 2)")
            .file("tet.obj", TET),
        // ---- RefineError, TessError, tessellate::Error ----
        case("refine_odd_level", &tess("m.obj", "--scheme pccm --level 3"),
            "tessgen: error: m.obj: the mesh has 1 faces that are not quads (first: face 0, 3 sides): they are tessellated as their quad sub-faces after one Catmull-Clark step, each sub-face covering half of each base edge, so the level must be even (got 3; try 2 or 4)")
            .file("m.obj", format!("{TRI}f 1 2 3\n")),
        case("tess_extraordinary_face", &tess("catmark_cube.obj", "--scheme regular --level 2"),
            "tessgen: error: catmark_cube.obj: scheme `regular` has no patch for extraordinary faces; face 0 has a corner of valence ≠ 4 (use `pccm`)")
            .data(CUBE),
        case("bench_extraordinary_face", "bench catmark_cube.obj --scheme regular --levels 2 --runs 1",
            "tessgen: error: scheme `regular` has no patch for extraordinary faces; face 0 has a corner of valence ≠ 4 (use `pccm`)")
            .data(CUBE),
        case("front_tags_unused", &tess("tet.obj", "--scheme pn --tags t.tags --level 2"),
            "tessgen: error: tet.obj: scheme `pn` takes no crease tags (only `stpn` reads them)")
            .file("tet.obj", TET).file("t.tags", "tag 1\n"),
        case("front_tags_with_displacement", &tess("catmark_cube_uv.obj", "--scheme stpn --split-quads --tags t.tags --displace atlas_seams.png --level 2"),
            "tessgen: error: catmark_cube_uv.obj: displacement takes no crease tags (--displace does not take --tags)")
            .data(CUBE_UV).data(MAP).file("t.tags", "tag 1\n"),
        case("front_partitioning", &tess("catmark_cube.obj", "--scheme pccm --adaptive random:1 --partitioning fractional-odd"),
            "tessgen: error: catmark_cube.obj: --backend cpu snaps to power-of-two levels: --partitioning integer only (got FractionalOdd; fractional partitioning needs the hardware tessellator, glsl or hlsl)")
            .data(CUBE),
        case("too_many_samples", &tess("m.obj", "--scheme pccm --level 1024"),
            "tessgen: error: m.obj: 4225 faces at level 1024 make 4438890625 samples, more than 2^32 - 1")
            .file("m.obj", grid(65)),
        // ---- DisplaceError ----
        case("displace_missing_texcoord", &tess("catmark_cube.obj", "--scheme pccm --level 2 --displace atlas_seams.png"),
            "tessgen: error: catmark_cube.obj: face 0 corner 0 has no texture coordinate (`f v/vt` needed on every corner to displace)")
            .data(CUBE).data(MAP),
        case("displace_bad_map", &tess("catmark_cube_uv.obj", "--scheme pccm --level 2 --displace wide.png"),
            "tessgen: error: wide.png: displacement map 8193x1: larger than 8192 texels on a side")
            .data(CUBE_UV).file("wide.png", hex(WIDE_PNG)),
        case("displace_scale", &tess("catmark_cube_uv.obj", "--scheme pccm --level 2 --displace atlas_seams.png --displace-scale nan"),
            "tessgen: error: catmark_cube_uv.obj: displacement scale must be finite, got NaN")
            .data(CUBE_UV).data(MAP),
        case("displace_image_format", &tess("catmark_cube_uv.obj", "--scheme pccm --level 2 --displace m.png"),
            "tessgen: error: cannot read displacement map m.png: Format error decoding Png: Invalid PNG signature.")
            .data(CUBE_UV).file("m.png", "not a png\n"),
        case("displace_image_missing", &tess("catmark_cube_uv.obj", "--scheme pccm --level 2 --displace none.png"),
            "tessgen: error: cannot read displacement map none.png: No such file or directory (os error 2)")
            .data(CUBE_UV),
        // ---- BuildError, SchemeError ----
        case("build_scheme", "generate --out g --scheme-file s.tess",
            "tessgen: error: s.tess: line 3, column 3: expected `facet`, `const`, `vertex`, `sector` or `patch`")
            .file("s.tess", "scheme broken {\n  facet quad;\n  oops\n}\n"),
        case("build_duplicate_builtin", "generate --out g --scheme-file s.tess",
            "tessgen: error: s.tess: scheme `pccm` is already declared by codegen/schemes/pccm.tess")
            .file("s.tess", std::fs::read_to_string(root().join("codegen/schemes/regular.tess")).unwrap().replace("scheme regular {", "scheme pccm {")),
        case("build_duplicate_files", "generate --out g --scheme-file a.tess --scheme-file b.tess",
            "tessgen: error: b.tess: scheme `mine` is already declared by a.tess")
            .file("a.tess", std::fs::read_to_string(root().join("codegen/schemes/regular.tess")).unwrap().replace("scheme regular {", "scheme mine {"))
            .file("b.tess", std::fs::read_to_string(root().join("codegen/schemes/regular.tess")).unwrap().replace("scheme regular {", "scheme mine {")),
        case("build_io_scheme_file", "generate --out g --scheme-file none.tess",
            "tessgen: error: none.tess: No such file or directory (os error 2)"),
        case("build_io_out_dir", "table --out f/x", "tessgen: error: f/x: Not a directory (os error 20)")
            .file("f", "a file\n"),
        // ---- LimitError ----
        case("limit_io", "compare catmark_cube.obj --reference none.bin",
            "tessgen: error: none.bin: No such file or directory (os error 2)")
            .data(CUBE),
        case("limit_format_magic", "compare catmark_cube.obj --reference r.bin",
            "tessgen: error: r.bin: not a CCLIM001 file (missing magic)")
            .data(CUBE).file("r.bin", "junk\n"),
        case("limit_format_header", "compare catmark_cube.obj --reference r.bin",
            "tessgen: error: r.bin: not a CCLIM001 file (expected 6 floats per sample and n ≥ 2)")
            .data(CUBE).file("r.bin", limit_file(6, 2, 5, 0)),
        case("limit_format_size", "compare catmark_cube.obj --reference r.bin",
            "tessgen: error: r.bin: not a CCLIM001 file (size does not match the header)")
            .data(CUBE).file("r.bin", limit_file(6, 2, 6, 0)),
        case("limit_format_huge_header", "compare catmark_cube.obj --reference r.bin",
            "tessgen: error: r.bin: not a CCLIM001 file (size does not match the header)")
            .data(CUBE).file("r.bin", limit_file(u32::MAX, u32::MAX, 6, 0)),
        case("limit_face_count", "compare catmark_cube.obj --reference r.bin",
            "tessgen: error: r.bin: limit samples cover 1 faces, the mesh has 6")
            .data(CUBE).file("r.bin", limit_file(1, 2, 6, 2 * 2 * 6 * 4)),
        // ---- the GPU paths (any adapter: lavapipe) ----
        case("gpu_adapter_not_found", &tess("catmark_cube.obj", "--scheme pccm --level 2 --backend wgpu"),
            "tessgen: error: catmark_cube.obj: no adapter matches TESSGEN_ADAPTER=\"no-such-adapter\"")
            .data(CUBE).env("TESSGEN_ADAPTER", "no-such-adapter"),
        render("gpu_adapter_not_found_render", "--size 8x8 --level 1",
            "tessgen: error: no adapter matches TESSGEN_ADAPTER=\"no-such-adapter\"")
            .env("TESSGEN_ADAPTER", "no-such-adapter"),
        case("gpu_no_adapter", &tess("catmark_cube.obj", "--scheme pccm --level 2 --backend wgpu"),
            "tessgen: error: catmark_cube.obj: no GPU adapter found (on CI install Mesa's lavapipe: apt-get install mesa-vulkan-drivers)")
            .data(CUBE).env("VK_ICD_FILENAMES", "/nonexistent/icd.json").env("VK_DRIVER_FILES", "/nonexistent/icd.json"),
        case("gpu_image", "render catmark_cube.obj --size 8x8 --level 1 --out no/such/o.png",
            "tessgen: error: image: no/such/o.png: No such file or directory (os error 2)")
            .data(CUBE),
        case("vk_device_not_found", &tess("catmark_cube.obj", "--scheme pccm --level 2 --backend glsl"),
            "tessgen: error: catmark_cube.obj: no Vulkan device matches TESSGEN_VK_DEVICE=\"no-such-device\"")
            .data(CUBE).env("TESSGEN_VK_DEVICE", "no-such-device"),
        case("vk_call", &tess("catmark_cube.obj", "--scheme pccm --level 2 --backend glsl"),
            "tessgen: error: catmark_cube.obj: Vulkan call vkCreateInstance failed: …")
            .data(CUBE).env("VK_ICD_FILENAMES", "/nonexistent/icd.json").env("VK_DRIVER_FILES", "/nonexistent/icd.json"),
        case("vk_no_glslang", &tess("catmark_cube.obj", "--scheme pccm --level 2 --backend hlsl"),
            "tessgen: error: catmark_cube.obj: glslangValidator could not be run (No such file or directory (os error 2)); install glslang-tools")
            .data(CUBE).env("PATH", "/nonexistent"),
        case("vk_io", &tess("catmark_cube.obj", "--scheme pccm --level 2 --backend glsl"),
            "tessgen: error: catmark_cube.obj: i/o: f/tessgen-vk-…: Not a directory (os error 20)")
            .data(CUBE).file("f", "a file, not a directory\n").env("TMPDIR", "f"),
        case("vk_limit", &tess("catmark_cube.obj", "--scheme pccm --level 65 --backend glsl --check-watertight"),
            "tessgen: error: catmark_cube.obj: scheme `pccm`: tessellation level (maxTessellationGenerationLevel) needs 65, … allows …")
            .data(CUBE),
        // ---- ChunkError (tessellate without --check-watertight streams) ----
        case("chunk_tess", &tess("catmark_cube.obj", "--scheme pccm --level 65 --backend glsl"),
            "tessgen: error: catmark_cube.obj: scheme `pccm`: tessellation level (maxTessellationGenerationLevel) needs 65, … allows …")
            .data(CUBE),
        case("chunk_sink", "tessellate catmark_cube.obj --scheme pccm --level 2 --out /dev/full",
            "tessgen: error: /dev/full: No space left on device (os error 28)")
            .data(CUBE),
        // ---- the CLI's own checks ----
        case("out_unwritable", &tess("catmark_cube.obj", "--scheme pccm --level 2").replace("o.obj", "no/such/o.obj"),
            "tessgen: error: no/such/o.obj.partial: No such file or directory (os error 2)")
            .data(CUBE),
        case("out_unwritable_check", &tess("catmark_cube.obj", "--scheme pccm --level 2 --check-watertight").replace("o.obj", "no/such/o.obj"),
            "tessgen: error: no/such/o.obj: No such file or directory (os error 2)")
            .data(CUBE),
        case("glb_empty", &tess("m.obj", "--scheme pccm --level 2").replace("o.obj", "o.glb"),
            "tessgen: error: o.glb.partial: the result has no triangles (every face a hole?): a .glb cannot hold an empty mesh")
            .file("m.obj", quad_with("t hole 1/0/0 0")),
        case("glb_empty_check", &tess("m.obj", "--scheme pccm --level 2 --check-watertight").replace("o.obj", "o.glb"),
            "tessgen: error: o.glb: the result has no triangles (every face a hole?): a .glb cannot hold an empty mesh")
            .file("m.obj", quad_with("t hole 1/0/0 0")),
        case("usage_heatmap_reference", "compare catmark_cube.obj --heatmap h.png",
            "error: the following required arguments were not provided:")
            .data(CUBE).code(2),
        case("refine_out_unwritable", "refine catmark_cube.obj --out f/x",
            "tessgen: error: f/x: Not a directory (os error 20)")
            .data(CUBE).file("f", "a file\n"),
        render("render_triangle_scheme", "--scheme pn",
            "tessgen: error: catmark_cube.obj: `render` takes quad schemes, not pn"),
        case("view_unknown_key", "view catmark_cube.obj --keys tab,ctrl+z",
            "error: invalid value 'tab,ctrl+z' for '--keys <KEYS>': unknown key `ctrl+z` (known: tab shift+tab + = - a m ] [ w c d . comma left right up down pageup pagedown r p h f1 u escape q)")
            .data(CUBE).code(2),
        case("view_triangle_scheme", "view catmark_cube.obj --scheme pn --frames 1",
            "tessgen: error: catmark_cube.obj: `view` takes quad schemes, not pn")
            .data(CUBE).env("DISPLAY", "").env("WAYLAND_DISPLAY", "").env("WAYLAND_SOCKET", ""),
        case("view_no_display", "view catmark_cube.obj --frames 1",
            "tessgen: error: cannot open a window: neither DISPLAY nor WAYLAND_DISPLAY is set (without a display, run it under Xvfb: xvfb-run tessgen view …)")
            .data(CUBE).env("DISPLAY", "").env("WAYLAND_DISPLAY", "").env("WAYLAND_SOCKET", ""),
        render("render_size_syntax", "--size 800", "tessgen: error: --size \"800\": expected WxH, e.g. 800x600"),
        render("render_size_width", "--size ax600", "tessgen: error: --size \"ax600\": bad width"),
        render("render_size_height", "--size 800xb", "tessgen: error: --size \"800xb\": bad height"),
        render("render_size_range", "--size 0x600", "tessgen: error: --size \"0x600\": width and height must be in 1..=8192"),
        render("render_camera_syntax", "--camera 35", "tessgen: error: --camera \"35\": expected AZ,EL in degrees"),
        render("render_camera_azimuth", "--camera a,25", "tessgen: error: --camera \"a,25\": bad azimuth"),
        render("render_camera_elevation", "--camera 35,b", "tessgen: error: --camera \"35,b\": bad elevation"),
        case("bench_backend", "bench catmark_cube.obj --backend glsl --levels 2 --runs 1",
            "tessgen: error: bench: --backend glsl is not supported (cpu or wgpu)")
            .data(CUBE),
        case("bench_triangle_scheme", "bench catmark_cube.obj --scheme pn --backend wgpu --levels 2 --runs 1",
            "tessgen: error: bench: triangle scheme `pn` is benched on --backend cpu at uniform levels only (on the mesh's quads split into triangles)")
            .data(CUBE),
        case("compare_scheme_fails", "compare catmark_cube.obj --schemes regular --level 2",
            "tessgen: error: regular: scheme `regular` has no patch for extraordinary faces; face 0 has a corner of valence ≠ 4 (use `pccm`)")
            .data(CUBE),
        case("generate_check_out_of_date", "generate --out g --check",
            "tessgen: g/ is out of date (… mismatches); run `tessgen generate --out g`")
            .file("g/README.md", "stale\n"),
        // ---- clap: usage errors, exit 2 ----
        case("usage_unknown_scheme", &tess("m.obj", "--scheme loop --level 2"),
            "error: invalid value 'loop' for '--scheme <SCHEME>': unknown scheme `loop` (available: …)").code(2),
        case("usage_level_range", &tess("m.obj", "--scheme pccm --level 0"),
            "error: invalid value '0' for '--level <N>': 0 is not in 1..=1024").code(2),
        case("usage_level_missing", &tess("m.obj", "--scheme pccm"),
            "error: the following required arguments were not provided:").code(2),
        case("usage_adaptive_metric", &tess("m.obj", "--scheme pccm --adaptive near:2"),
            "error: invalid value 'near:2' for '--adaptive <METRIC>': unknown adaptive metric `near:2` (random:SEED[:LO:HI], distance:K, screen:PX)").code(2),
        case("usage_partitioning", &tess("m.obj", "--scheme pccm --adaptive random:1 --partitioning odd"),
            "error: invalid value 'odd' for '--partitioning <MODE>': unknown partitioning `odd` (integer, fractional-odd, fractional-even)").code(2),
        case("usage_max_factor", &tess("m.obj", "--scheme pccm --adaptive random:1 --max-factor nan"),
            "error: invalid value 'nan' for '--max-factor <F>': `nan` is not a number ≥ 1").code(2),
        case("usage_backend", &tess("m.obj", "--scheme pccm --level 2 --backend metal"),
            "error: invalid value 'metal' for '--backend <BACKEND>'").code(2),
        case("usage_requires", "render m.obj --out o.png --max-factor 8",
            "error: the following required arguments were not provided:").code(2),
        case("usage_subcommand", "frobnicate", "error: unrecognized subcommand 'frobnicate'").code(2),
    ]
}

/// `text` matches `pattern`, where `…` in the pattern is any text.
fn matches(pattern: &str, text: &str) -> bool {
    let parts: Vec<&str> = pattern.split('…').collect();
    if parts.len() == 1 {
        return pattern == text;
    }
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if !text.starts_with(first) || !text[first.len()..].ends_with(last) {
        return false;
    }
    let mut rest = &text[first.len()..text.len() - last.len()];
    for p in &parts[1..parts.len() - 1] {
        match rest.find(p) {
            Some(i) => rest = &rest[i + p.len()..],
            None => return false,
        }
    }
    true
}

/// What the binary said: exit code (None: killed by a signal) and its
/// `tessgen:` / `error:` lines (driver noise left out).
fn run(c: &Case) -> (Option<i32>, Vec<String>) {
    let tmp = common::TempDir::new(c.id);
    for (name, bytes) in &c.files {
        let path = tmp.path().join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, bytes).unwrap();
    }
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_tessgen"));
    cmd.args(&c.args)
        .current_dir(tmp.path())
        .env_remove("TESSGEN_ADAPTER")
        .env_remove("TESSGEN_VK_DEVICE")
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .env("RUST_BACKTRACE", "0");
    for (k, v) in &c.env {
        cmd.env(k, v);
    }
    let out = cmd.output().unwrap();
    let lines = String::from_utf8_lossy(&out.stderr)
        .lines()
        .filter(|l| l.starts_with("tessgen:") || l.starts_with("error:"))
        .filter(|l| !l.contains("XDG_RUNTIME_DIR"))
        .map(str::to_string)
        .collect();
    (out.status.code(), lines)
}

#[test]
fn every_bad_input_gets_its_message_and_exit_code() {
    let cases = cases();
    let ids: BTreeSet<&str> = cases.iter().map(|c| c.id).collect();
    assert_eq!(ids.len(), cases.len(), "case ids must be unique");
    let mut failures = Vec::new();
    for c in &cases {
        let (code, lines) = run(c);
        let ok_lines = lines.len() == c.expect.len()
            && c.expect.iter().zip(&lines).all(|(p, l)| matches(p, l));
        match code {
            None => failures.push(format!("{}: killed by a signal", c.id)),
            Some(n) if n >= 101 => failures.push(format!("{}: exit {n} (a panic or abort)", c.id)),
            Some(n) if n != c.code || !ok_lines => failures.push(format!(
                "{}: exit {n} (want {}), stderr lines:\n    {}\n  want:\n    {}",
                c.id,
                c.code,
                lines.join("\n    "),
                c.expect.join("\n    ")
            )),
            Some(_) => {}
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

// ---- docs/errors.md ----

/// The error types of the matrix: the name the doc writes, the file that
/// defines it, the name in that file.
const TYPES: &[(&str, &str, &str)] = &[
    ("MeshError", "runtime/src/mesh/mod.rs", "MeshError"),
    (
        "FeatureError",
        "runtime/src/mesh/features.rs",
        "FeatureError",
    ),
    ("TagError", "runtime/src/mesh/tags.rs", "TagError"),
    (
        "TopologyError",
        "runtime/src/mesh/topology_error.rs",
        "TopologyError",
    ),
    (
        "TriMeshError",
        "runtime/src/mesh/trimesh.rs",
        "TriMeshError",
    ),
    (
        "RefineError",
        "runtime/src/tessellate/refined.rs",
        "RefineError",
    ),
    ("TessError", "runtime/src/cpu/mod.rs", "TessError"),
    (
        "tessellate::Error",
        "runtime/src/tessellate/request.rs",
        "Error",
    ),
    (
        "ChunkError",
        "runtime/src/tessellate/stream.rs",
        "ChunkError",
    ),
    (
        "AdaptiveError",
        "runtime/src/cpu/adaptive.rs",
        "AdaptiveError",
    ),
    (
        "DisplaceError",
        "runtime/src/cpu/displace.rs",
        "DisplaceError",
    ),
    ("BuildError", "codegen/src/error.rs", "BuildError"),
    ("LimitError", "runtime/src/check/accuracy.rs", "LimitError"),
    ("GpuError", "runtime/src/gpu/wgpu/device.rs", "GpuError"),
    ("UploadError", "runtime/src/gpu/upload.rs", "UploadError"),
    ("VkError", "runtime/src/gpu/vulkan/device.rs", "VkError"),
    ("CaptureError", "runtime/src/gpu/capture.rs", "CaptureError"),
];

/// The variants of `pub enum name` in `source` (rustfmt layout: one variant
/// per line at four spaces, attributes and docs start with `#` or `/`).
fn variants(source: &str, name: &str) -> Vec<String> {
    let is_start = |l: &str| {
        l.strip_prefix("pub enum ")
            .and_then(|rest| rest.strip_prefix(name))
            .is_some_and(|after| !after.starts_with(|c: char| c.is_alphanumeric() || c == '_'))
    };
    let mut lines = source.lines().skip_while(|l| !is_start(l));
    assert!(lines.next().is_some(), "no `pub enum {name}`");
    lines
        .take_while(|l| !l.starts_with('}'))
        .filter_map(|l| l.strip_prefix("    "))
        .filter(|l| l.starts_with(|c: char| c.is_ascii_uppercase()))
        .map(|l| {
            l.chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect()
        })
        .collect()
}

/// `pub enum …Error` / `pub struct …Error` of every product source file.
fn error_types() -> BTreeSet<String> {
    fn walk(dir: &Path, out: &mut BTreeSet<String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|x| x == "rs") {
                for l in std::fs::read_to_string(&path).unwrap().lines() {
                    for kw in ["pub enum ", "pub struct "] {
                        if let Some(rest) = l.strip_prefix(kw) {
                            let name: String = rest
                                .chars()
                                .take_while(|c| c.is_alphanumeric() || *c == '_')
                                .collect();
                            if name.ends_with("Error") {
                                out.insert(name);
                            }
                        }
                    }
                }
            }
        }
    }
    let mut out = BTreeSet::new();
    for d in ["runtime/src", "codegen/src", "cli/src", "macros/src"] {
        walk(&root().join(d), &mut out);
    }
    out
}

/// The code spans of a table cell (`` `a` `` and ``` `` a`b `` ```).
fn code_spans(cell: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = cell;
    while let Some(i) = rest.find('`') {
        let ticks = rest[i..].chars().take_while(|&c| c == '`').count();
        let fence = &rest[i..i + ticks];
        let body = &rest[i + ticks..];
        let Some(j) = body.find(fence) else { break };
        let s = &body[..j];
        let s = if ticks > 1 {
            s.strip_prefix(' ')
                .unwrap_or(s)
                .strip_suffix(' ')
                .unwrap_or(s)
        } else {
            s
        };
        out.push(s.replace("\\|", "|"));
        rest = &body[j + ticks..];
    }
    out
}

/// The cells of a table row, split at unescaped `|`.
fn cells(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|').trim_end_matches('|');
    let mut out = vec![String::new()];
    let mut prev = ' ';
    for c in inner.chars() {
        if c == '|' && prev != '\\' {
            out.push(String::new());
        } else {
            out.last_mut().unwrap().push(c);
        }
        prev = c;
    }
    out.iter().map(|c| c.trim().to_string()).collect()
}

#[test]
fn docs_errors_md_is_checked() {
    let doc = std::fs::read_to_string(root().join("docs/errors.md")).expect("docs/errors.md");
    let cases = cases();
    let by_id: BTreeMap<&str, &Case> = cases.iter().map(|c| (c.id, c)).collect();
    let mut problems = Vec::new();
    let mut cited_cases = BTreeSet::new();
    let mut named = BTreeSet::new();
    let mut rows = 0;
    for line in doc.lines().filter(|l| l.starts_with("| `")) {
        let c = cells(line);
        if c.len() != 5 {
            problems.push(format!("not 5 cells: {line}"));
            continue;
        }
        rows += 1;
        named.extend(code_spans(&c[0]));
        let tests = code_spans(&c[4]);
        if tests.is_empty() && !(c[4].contains("not provokable") || c[4].contains("unreachable")) {
            problems.push(format!(
                "no test, and not marked not provokable / unreachable: {line}"
            ));
        }
        for t in tests {
            let Some((file, name)) = t.rsplit_once("::") else {
                problems.push(format!("test `{t}` is not file::name: {line}"));
                continue;
            };
            if file == "cli/tests/errors.rs" {
                cited_cases.insert(name.to_string());
                let Some(case) = by_id.get(name) else {
                    problems.push(format!("no case `{name}` in cli/tests/errors.rs"));
                    continue;
                };
                if code_spans(&c[2]) != case.expect {
                    problems.push(format!(
                        "{name}: the doc's message {:?} is not the case's {:?}",
                        code_spans(&c[2]),
                        case.expect
                    ));
                }
                if c[3] != case.code.to_string() {
                    problems.push(format!(
                        "{name}: the doc's exit code {} is not the case's {}",
                        c[3], case.code
                    ));
                }
                continue;
            }
            // `file::function` or `file::module::function`.
            let file = file.split("::").next().unwrap_or(file);
            match std::fs::read_to_string(root().join(file)) {
                Err(e) => problems.push(format!("`{t}`: {file}: {e}")),
                Ok(src) if !src.contains(&format!("fn {name}(")) => {
                    problems.push(format!("`{t}`: no `fn {name}(` in {file}"))
                }
                Ok(_) => {}
            }
        }
    }
    for id in by_id.keys() {
        if !cited_cases.contains(*id) {
            problems.push(format!("case `{id}` is not cited in docs/errors.md"));
        }
    }
    let listed: BTreeSet<&str> = TYPES.iter().map(|t| t.2).collect();
    for ty in error_types() {
        if !listed.contains(ty.as_str()) && ty != "SchemeError" {
            problems.push(format!("`pub … {ty}` is not in this test's TYPES (and so not checked against docs/errors.md)"));
        }
    }
    if !doc.contains("`SchemeError`") {
        problems.push("SchemeError is not described".into());
    }
    for (doc_name, file, name) in TYPES {
        let src = std::fs::read_to_string(root().join(file)).unwrap();
        let vs = variants(&src, name);
        assert!(!vs.is_empty(), "{name} in {file}: no variants found");
        for v in vs {
            let full = format!("{doc_name}::{v}");
            if !named.contains(&full) {
                problems.push(format!("`{full}` ({file}) has no row in docs/errors.md"));
            }
        }
    }
    assert!(rows > 100, "only {rows} rows found");
    assert!(
        problems.is_empty(),
        "docs/errors.md:\n{}",
        problems.join("\n")
    );
}
