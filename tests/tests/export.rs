//! Binary mesh output (`export::MeshStream`, `Output::write_mesh`): glTF 2.0
//! binary and binary PLY.
//!
//! For each case — uniform grids, a mesh with a boundary, a holed mesh,
//! refined n-gons (polygon grids), adaptive grids on the CPU, captured
//! triangles from the Vulkan harness — the file written chunk by chunk
//! (`Session::run_chunked`, chunks of one face and of everything) is the
//! whole result's byte for byte (a feature-adaptive refinement of several
//! depths too); the `.glb` is re-read and validated by the
//! `gltf` crate, the `.ply` by `ply-rs-bw`; both hold the same vertices and
//! triangles; the positions' bounds in the glTF accessor are the data's;
//! and the welded mesh is watertight: on a closed input every edge is used
//! by exactly two triangles and the Euler characteristic is the input's,
//! on an open one the open edges are exactly the request's expected count.

mod common;

use glam::Vec3;
use std::collections::HashMap;
use tessgen_runtime::export::{Format, MeshStream};
use tessgen_runtime::tessellate::{Backend, Request, Session};
use tessgen_runtime::Mesh;

fn scratch(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("tessgen-export-{}-{tag}", std::process::id()))
}

/// The file of `format` for `request`, streamed in chunks of `max_samples`
/// (0: the default chunk), and the number of chunks.
fn streamed(
    session: &mut Session,
    mesh: &Mesh,
    request: &Request<'_>,
    format: Format,
    max_samples: usize,
) -> (Vec<u8>, usize) {
    let v = request.validate(mesh).expect("validate");
    let mut m = MeshStream::new(format, &scratch(&format!("{format:?}-{max_samples}")))
        .expect("mesh stream");
    let mut chunks = 0;
    session
        .run_chunked(&v, max_samples, |out| {
            chunks += 1;
            out.write_mesh(&mut m)
        })
        .expect("run_chunked");
    let mut bytes = Vec::new();
    m.finish(&mut bytes).expect("finish");
    (bytes, chunks)
}

/// Positions and triangles read back from a `.glb` through the `gltf`
/// crate (which validates the document), and the accessor's bounds.
fn read_glb(bytes: &[u8]) -> (Vec<Vec3>, Vec<[u32; 3]>, [f32; 3], [f32; 3]) {
    let g = gltf::Gltf::from_slice(bytes).expect("a valid glTF");
    let blob = g.blob.as_deref().expect("a BIN chunk");
    assert_eq!(g.meshes().count(), 1);
    let mesh = g.meshes().next().expect("mesh");
    let prim = mesh.primitives().next().expect("primitive");
    assert_eq!(prim.mode(), gltf::mesh::Mode::Triangles);
    let reader = prim.reader(|_| Some(blob));
    let positions: Vec<Vec3> = reader
        .read_positions()
        .expect("positions")
        .map(Vec3::from)
        .collect();
    let normals: Vec<Vec3> = reader
        .read_normals()
        .expect("normals")
        .map(Vec3::from)
        .collect();
    assert_eq!(normals.len(), positions.len());
    for n in &normals {
        assert!((n.length() - 1.0).abs() < 1e-5, "normal {n} is not unit");
    }
    let idx: Vec<u32> = reader.read_indices().expect("indices").into_u32().collect();
    let tris: Vec<[u32; 3]> = idx.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    let acc = prim.get(&gltf::Semantic::Positions).expect("POSITION");
    let as3 = |v: Option<gltf::json::Value>| -> [f32; 3] {
        let v = v.expect("bounds");
        let a = v.as_array().expect("array");
        [0, 1, 2].map(|k| a[k].as_f64().expect("number") as f32)
    };
    (positions, tris, as3(acc.min()), as3(acc.max()))
}

/// Positions and triangles read back from a binary `.ply` by `ply-rs-bw`.
fn read_ply(bytes: &[u8]) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::{DefaultElement, Property};
    let mut r = std::io::Cursor::new(bytes);
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut r)
        .expect("a valid PLY");
    let f = |e: &DefaultElement, k: &str| match e.get(k) {
        Some(Property::Float(x)) => *x,
        other => panic!("{k}: {other:?}"),
    };
    let positions = ply.payload["vertex"]
        .iter()
        .map(|e| Vec3::new(f(e, "x"), f(e, "y"), f(e, "z")))
        .collect();
    let tris = ply.payload["face"]
        .iter()
        .map(|e| match e.get("vertex_indices") {
            Some(Property::ListUInt(v)) if v.len() == 3 => [v[0], v[1], v[2]],
            other => panic!("face: {other:?}"),
        })
        .collect();
    (positions, tris)
}

/// `(open edges, edges used more than twice, Euler characteristic)`.
fn topology(vertices: usize, tris: &[[u32; 3]]) -> (usize, usize, i64) {
    let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
    for t in tris {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let open = edges.values().filter(|&&n| n == 1).count();
    let over = edges.values().filter(|&&n| n > 2).count();
    let euler = vertices as i64 - edges.len() as i64 + tris.len() as i64;
    (open, over, euler)
}

#[test]
fn glb_and_ply_are_welded_watertight_and_stream_byte_for_byte() {
    let mut session = Session::new();
    let cube = common::mesh("catmark_cube");
    let torus = common::mesh("catmark_torus");
    let tent = common::mesh("catmark_tent");
    let nonquads = common::mesh("catmark_nonquads");
    let crease = common::mesh("catmark_single_crease");
    let holed = common::holed("catmark_cube", &[1, 4]);
    // (what, mesh, request, Euler characteristic of a closed input)
    let cases: Vec<(&str, &Mesh, Request<'_>, Option<i64>)> = vec![
        ("cube pccm", &cube, Request::uniform("pccm", 5), Some(2)),
        (
            "torus gregory",
            &torus,
            Request::uniform("gregory", 4),
            Some(0),
        ),
        (
            "cube pn",
            &cube,
            Request::uniform("pn", 3).split_quads(true),
            Some(2),
        ),
        (
            "tent acc (boundary)",
            &tent,
            Request::uniform("acc", 4),
            None,
        ),
        ("holed cube pccm", &holed, Request::uniform("pccm", 3), None),
        (
            "nonquads pccm (refined)",
            &nonquads,
            Request::uniform("pccm", 4),
            None,
        ),
        (
            "single crease pccm (feature-adaptive depths)",
            &crease,
            Request::uniform("pccm", 4),
            None,
        ),
        (
            "cube pccm adaptive",
            &cube,
            common::random_adaptive("pccm", 7, 1.0, 8.0, 8.0),
            Some(2),
        ),
        (
            "cube pccm wgpu",
            &cube,
            Request::uniform("pccm", 4).on(Backend::Wgpu),
            Some(2),
        ),
        (
            "cube pn glsl (captured)",
            &cube,
            Request::uniform("pn", 3)
                .split_quads(true)
                .on(Backend::VulkanGlsl),
            Some(2),
        ),
    ];
    for (what, mesh, request, closed_euler) in &cases {
        let v = request.validate(mesh).expect("validate");
        let whole_out = session.run(&v).expect("run");
        let expected_open = v.expected_open_edges(&whole_out);
        let mut files = Vec::new();
        for format in [Format::Glb, Format::Ply] {
            let (whole, one) = streamed(&mut session, mesh, request, format, usize::MAX);
            let (per_face, many) = streamed(&mut session, mesh, request, format, 1);
            assert_eq!(one, 1, "{what}: one chunk");
            assert!(
                whole == per_face,
                "{what} {format:?}: streamed ({many} chunks) differs"
            );
            let mut direct = MeshStream::new(format, &scratch("direct")).expect("stream");
            whole_out.write_mesh(&mut direct).expect("write_mesh");
            let mut bytes = Vec::new();
            direct.finish(&mut bytes).expect("finish");
            assert!(
                bytes == whole,
                "{what} {format:?}: run_chunked and run differ"
            );
            files.push(whole);
        }
        let (gp, gt, lo, hi) = read_glb(&files[0]);
        let (pp, pt) = read_ply(&files[1]);
        assert_eq!(gp, pp, "{what}: glb and ply vertices");
        assert_eq!(gt, pt, "{what}: glb and ply triangles");
        let min = gp.iter().fold(Vec3::INFINITY, |a, &p| a.min(p));
        let max = gp.iter().fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
        assert_eq!((lo, hi), (min.to_array(), max.to_array()), "{what}: bounds");
        // Welded: no two vertices share position bits.
        let mut seen = std::collections::HashSet::new();
        let dup = gp
            .iter()
            .filter(|p| !seen.insert([p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]))
            .count();
        assert_eq!(dup, 0, "{what}: {dup} vertices left unwelded");
        let (open, over, euler) = topology(gp.len(), &gt);
        assert_eq!(over, 0, "{what}: edges used more than twice");
        assert_eq!(open, expected_open, "{what}: open edges");
        if let Some(e) = closed_euler {
            assert_eq!(open, 0, "{what}: a closed input gives a closed mesh");
            assert_eq!(euler, *e, "{what}: Euler characteristic");
        }
    }
}

#[test]
fn an_empty_result_is_an_error_in_glb_not_a_broken_file() {
    let m = MeshStream::new(Format::Glb, &scratch("empty")).expect("stream");
    let mut bytes = Vec::new();
    let e = m.finish(&mut bytes).expect_err("empty glb");
    assert!(e.to_string().contains("no triangles"), "{e}");
    // An empty PLY is a valid file with zero elements.
    let m = MeshStream::new(Format::Ply, &scratch("empty-ply")).expect("stream");
    let mut bytes = Vec::new();
    m.finish(&mut bytes).expect("empty ply");
    let (p, t) = read_ply(&bytes);
    assert!(p.is_empty() && t.is_empty());
}

#[test]
fn formats_follow_the_extension() {
    use std::path::Path;
    assert_eq!(Format::of(Path::new("a.glb")), Format::Glb);
    assert_eq!(Format::of(Path::new("a.GLB")), Format::Glb);
    assert_eq!(Format::of(Path::new("a.ply")), Format::Ply);
    assert_eq!(Format::of(Path::new("a.obj")), Format::Obj);
    assert_eq!(Format::of(Path::new("a")), Format::Obj);
    assert!(MeshStream::new(Format::Obj, &scratch("obj")).is_err());
}
