//! tessgen's fuzz targets.
//!
//! Each target takes arbitrary bytes and drives one input path of the
//! library the way the command line does; the only thing it may do is
//! return: `true` when the input went all the way through (it loaded,
//! compiled or tessellated), `false` for a typed error on the way. A
//! panic, an abort or a hang is a finding. The same functions run
//!
//! * under AFL++ (`src/bin/fuzz_*.rs`, built with `cargo afl build -p
//!   tessgen-fuzz --features afl --release`; README, "Fuzzing"), and
//! * in `cargo test` (`tests/corpus.rs`), over every input checked in under
//!   `fuzz/corpus/<target>/` (seeds and the minimised corpus) and
//!   `fuzz/regressions/<target>/` (each crash found, kept as a test).
//!
//! Targets:
//!
//! * [`obj`]: OBJ text with OpenSubdiv `t` tags → mesh, magnitude check,
//!   topology (boundaries, creases, non-manifold input), request
//!   validation (refinement of non-quads and semi-sharp creases).
//! * [`mesh`]: structure-aware: the bytes choose a scheme, level, options,
//!   a small mesh (positions, faces of 3–5 sides, tags) that is written as
//!   OBJ and tessellated end to end on the CPU; every sample of an `Ok`
//!   result must be finite, and the result streamed in chunks of one face
//!   and of a few must give the same OBJ bytes, and in chunks of a few the
//!   same welded PLY bytes (`export::MeshStream`).
//! * [`tags`]: a stpn tag file for the cube, then the tagged tessellation.
//! * [`scheme`]: `.tess` source → scheme, stencil table, Plan and all four
//!   printers.

use std::fmt::Write as _;

use tessgen_codegen::{Builder, SchemeSource};
use tessgen_runtime::adaptive::Partitioning;
use tessgen_runtime::export::{Format, MeshStream};
use tessgen_runtime::obj::ObjStream;
use tessgen_runtime::tags::TagFile;
use tessgen_runtime::tessellate::{AdaptiveRequest, EdgeMetric, Output, Request, Session};
use tessgen_runtime::{cpu, Mesh, Topology};

/// Inputs above this are cut: the targets look for wrong handling, not for
/// slow inputs (AFL's own limit is set lower, README).
const MAX_INPUT: usize = 64 * 1024;

/// The built-in schemes, in the order [`mesh`] picks them.
pub const SCHEMES: [&str; 9] = [
    "regular",
    "pccm",
    "acc",
    "gregory",
    "gregory-osd",
    "pn",
    "stpn",
    "phong",
    "g1cc",
];

/// OBJ text (and its `t` tags) through the loader, the topology and a
/// request's validation.
pub fn obj(data: &[u8]) -> bool {
    let Some(text) = text(data) else { return false };
    let Ok(mesh) = Mesh::from_obj_str(text) else {
        return false;
    };
    let _ = mesh.check_magnitude();
    let _ = Topology::build(&mesh, &cpu::topology_options());
    // Validation refines non-quads and semi-sharp creases: the boundary and
    // crease paths, without evaluating. One crease step: a sharpness-10
    // crease at the default steps made one input of `single_crease.obj`
    // take 100 ms, and the steps repeat the same code.
    let mut valid = false;
    for scheme in ["pccm", "pn"] {
        let request = Request::uniform(scheme, 1).crease_refinement(1);
        valid |= request.validate(&mesh).is_ok();
    }
    valid
}

/// A stpn tag file (the bytes) for the cube, then the tagged stpn
/// tessellation of the cube's split quads at level 2.
pub fn tags(data: &[u8]) -> bool {
    let Some(text) = text(data) else { return false };
    let Ok(mesh) = Mesh::from_obj_str(CUBE) else {
        panic!("the built-in cube must load")
    };
    let Ok(tags) = TagFile::parse(text, mesh.num_vertices(), mesh.num_faces(), |f| {
        mesh.face(f)
    }) else {
        return false;
    };
    let request = Request::uniform("stpn", 2).split_quads(true).tagged(&tags);
    finished(tessgen_runtime::tessellate::tessellate(&mesh, &request)).is_some()
}

/// `.tess` source through parsing, checking, the stencil table (valences
/// up to 6), lowering and every printer.
pub fn scheme(data: &[u8]) -> bool {
    let Some(text) = text(data) else { return false };
    let builder = Builder::new()
        .scheme(SchemeSource::new("fuzz.tess", text))
        .max_valence(6)
        .all_targets()
        .command("fuzz");
    builder.compile().is_ok()
}

/// A small mesh and request from the bytes, tessellated on the CPU.
///
/// Layout (missing bytes read as 0): byte 0 picks the scheme, byte 1 the
/// level (1–3), byte 2 the options (isolation 0–2, adaptive, one mesh,
/// split quads, crease steps 0–2), byte 3 the base mesh (its low two bits:
/// faces from the bytes, the cube, an open 3 × 3 grid, a pyramid of four
/// triangles on a quad) and, for faces from the bytes, the vertex count
/// (4–19). Then three signed bytes per vertex (added to the base
/// positions, `/16`); for faces from the bytes, faces (a side count 3–5
/// and that many vertex bytes) until a byte `0xFF`; then tags of three
/// bytes each (kind, a, b): creases along a face's edge or between any two
/// vertices, corners, holes, the boundary rule.
pub fn mesh(data: &[u8]) -> bool {
    let data = &data[..data.len().min(MAX_INPUT)];
    let mut r = Reader { data, at: 0 };
    let scheme = SCHEMES[r.byte() as usize % SCHEMES.len()];
    let level = 1 + u32::from(r.byte()) % 3;
    let flags = r.byte();
    let base = r.byte();
    let (mut positions, mut faces) = match base % 4 {
        1 => base_mesh(CUBE),
        2 => base_mesh(GRID),
        3 => base_mesh(PYRAMID),
        _ => (
            vec![[0.0f32; 3]; 4 + usize::from(base >> 2) % 16],
            Vec::new(),
        ),
    };
    let nv = positions.len();
    for p in &mut positions {
        for c in p.iter_mut() {
            *c += f32::from(r.byte() as i8) / 16.0;
        }
    }
    if base.is_multiple_of(4) {
        while !r.done() && faces.len() < 24 {
            let sides = r.byte();
            if sides == 0xFF {
                break;
            }
            let face = (0..3 + usize::from(sides) % 3)
                .map(|_| usize::from(r.byte()) % nv)
                .collect();
            faces.push(face);
        }
    }
    let mut text = String::new();
    for [x, y, z] in &positions {
        let _ = writeln!(text, "v {x} {y} {z}");
    }
    for f in &faces {
        text.push('f');
        for v in f {
            let _ = write!(text, " {}", v + 1);
        }
        text.push('\n');
    }
    while !r.done() {
        let (kind, a, b) = (r.byte(), r.byte(), r.byte());
        let (va, vb) = (usize::from(a) % nv, usize::from(b) % nv);
        let sharp = f32::from(b % 16) / 2.0;
        let _ = match kind % 6 {
            0 if !faces.is_empty() => {
                let f = &faces[usize::from(a) % faces.len()];
                let k = usize::from(b) % f.len();
                let s = f32::from(kind >> 3) / 4.0;
                writeln!(text, "t crease 2/1/0 {} {} {s}", f[k], f[(k + 1) % f.len()])
            }
            1 => writeln!(text, "t corner 1/1/0 {va} {sharp}"),
            2 => writeln!(text, "t hole 1/0/0 {}", usize::from(a) % faces.len().max(1)),
            3 => writeln!(text, "t interpolateboundary 1/0/0 {}", a % 3),
            _ => writeln!(text, "t crease 2/1/0 {va} {vb} {sharp}"),
        };
    }
    let Ok(mesh) = Mesh::from_obj_str(&text) else {
        return false;
    };
    let request = if flags & 0x08 != 0 {
        Request::adaptive(
            scheme,
            AdaptiveRequest {
                metric: EdgeMetric::Random {
                    seed: u64::from(flags),
                    lo: 1.0,
                    hi: 4.0,
                },
                partitioning: Partitioning::Integer,
                max_factor: 4.0,
            },
        )
    } else {
        Request::uniform(scheme, level)
    };
    let request = request
        .isolate(u32::from(flags & 0x03) % 3)
        .one_mesh(flags & 0x10 != 0)
        .split_quads(flags & 0x20 != 0)
        .crease_refinement(u32::from(flags >> 6).min(2));
    let Ok(v) = request.validate(&mesh) else {
        return false;
    };
    let mut session = Session::new();
    let whole = session.run(&v);
    let text = whole.as_ref().map(Output::to_obj).ok();
    let Some(out) = finished(whole) else {
        return false;
    };
    // Streaming changes no byte: the chunks of one face (block) and of a
    // few, written one after the other, are the whole result's OBJ.
    for max_samples in [1, 97] {
        let mut stream = ObjStream::new(Vec::new());
        let streamed = session.run_chunked(&v, max_samples, |out| out.write_obj(&mut stream));
        if let Err(e) = streamed {
            panic!("the whole run succeeded but streaming in chunks of {max_samples} failed: {e}");
        }
        let bytes = stream.finish().unwrap_or_default();
        if Some(bytes.as_slice()) != text.as_deref().map(str::as_bytes) {
            panic!("streaming in chunks of {max_samples} changed the OBJ");
        }
    }
    // The welded binary mesh (`.ply`, `.glb` share the weld) streams to the
    // same bytes too.
    {
        let ply = |write: &mut dyn FnMut(&mut MeshStream) -> Result<(), String>| {
            let mut m = match MeshStream::new(Format::Ply, &scratch()) {
                Ok(m) => m,
                // The temporary directory is not the tessellator's to fuzz.
                Err(_) => return None,
            };
            if let Err(e) = write(&mut m) {
                panic!("writing the welded mesh failed: {e}");
            }
            let mut bytes = Vec::new();
            m.finish(&mut bytes).ok().map(|()| bytes)
        };
        let whole_ply = ply(&mut |m| out.write_mesh(m).map_err(|e| e.to_string()));
        let chunked = ply(&mut |m| {
            session
                .run_chunked(&v, 97, |o| o.write_mesh(m))
                .map_err(|e| format!("{e:?}"))
        });
        if whole_ply.is_some() && chunked.is_some() && whole_ply != chunked {
            panic!("streaming in chunks of 97 changed the welded PLY");
        }
    }
    true
}

/// A fresh temporary path for a [`MeshStream`]'s vertex and index files.
fn scratch() -> std::path::PathBuf {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    std::env::temp_dir().join(format!("tessgen-fuzz-{}-{n}", std::process::id()))
}

/// Positions and 0-based faces of one of the built-in OBJ texts.
fn base_mesh(obj: &str) -> (Vec<[f32; 3]>, Vec<Vec<usize>>) {
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for line in obj.lines() {
        let mut toks = line.split_whitespace();
        match toks.next() {
            Some("v") => {
                let mut p = [0.0f32; 3];
                for (c, t) in p.iter_mut().zip(toks) {
                    *c = t.parse().unwrap_or(0.0);
                }
                positions.push(p);
            }
            Some("f") => faces.push(
                toks.filter_map(|t| t.parse::<usize>().ok())
                    .map(|i| i - 1)
                    .collect(),
            ),
            _ => {}
        }
    }
    (positions, faces)
}

/// Whether the tessellation succeeded; an `Ok` result must be finite
/// everywhere (the library turns a non-finite sample into
/// `Error::NonFiniteSample`, issue 18), else this panics: a finding.
fn finished(result: Result<Output, tessgen_runtime::tessellate::Error>) -> Option<Output> {
    let out = result.ok()?;
    if let Some((face, sample)) = out.first_non_finite() {
        panic!("non-finite sample {sample} of face {face} in an Ok result");
    }
    Some(out)
}

/// The bytes as text, if they are UTF-8 (the loaders take `&str`; a file
/// that is not UTF-8 is refused before them), cut to [`MAX_INPUT`].
fn text(data: &[u8]) -> Option<&str> {
    std::str::from_utf8(&data[..data.len().min(MAX_INPUT)]).ok()
}

/// Bytes in order, zeros past the end.
struct Reader<'a> {
    data: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn byte(&mut self) -> u8 {
        let b = self.data.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        b
    }

    fn done(&self) -> bool {
        self.at >= self.data.len()
    }
}

/// An open 3 × 3 grid of quads (a boundary all round, four corners).
const GRID: &str = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 3 1 0\n\
v 0 2 0\nv 1 2 0\nv 2 2 0\nv 3 2 0\nv 0 3 0\nv 1 3 0\nv 2 3 0\nv 3 3 0\n\
f 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 5 6 10 9\nf 6 7 11 10\nf 7 8 12 11\n\
f 9 10 14 13\nf 10 11 15 14\nf 11 12 16 15\n";

/// A closed pyramid: a quad base and four triangles (non-quads).
const PYRAMID: &str = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 1\n\
f 4 3 2 1\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n";

/// The unit cube, all quads (the [`tags`] target's mesh, a [`mesh`] base).
pub const CUBE: &str =
    "v -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 -1\nv 1 -1 -1\n\
f 1 2 4 3\nf 3 4 6 5\nf 5 6 8 7\nf 7 8 2 1\nf 2 8 6 4\nf 7 1 3 5\n";
