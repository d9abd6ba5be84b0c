//! Streaming (`Session::run_chunked` + `obj::ObjStream`): the result handed
//! out chunk by chunk is the whole result, bit for bit and byte for byte of
//! OBJ, whatever the chunk size: quad and triangle schemes, displaced or
//! not, on the CPU, on wgpu and through the Vulkan harness (GLSL, HLSL), a
//! mesh with holes (faces left out mid-chunk), adaptive requests on the CPU
//! and on wgpu (a triangle soup per face window), refined meshes (windows of
//! base blocks, feature-adaptive refinements of several depths too), and
//! the Vulkan harness's captured triangles.

mod common;

use common::displacement;
use tessgen_runtime::displace::Ownership;
use tessgen_runtime::obj::{to_obj, ObjStream};
use tessgen_runtime::tessellate::{Backend, Output, Request, Session};
use tessgen_runtime::Mesh;

/// The OBJ of `request` on `mesh`, streamed in chunks of `max_samples`,
/// and the number of chunks.
fn streamed(mesh: &Mesh, request: &Request<'_>, max_samples: usize) -> (String, usize) {
    streamed_in(&mut Session::new(), mesh, request, max_samples)
}

/// [`streamed`] with the caller's session (its devices opened once).
fn streamed_in(
    session: &mut Session,
    mesh: &Mesh,
    request: &Request<'_>,
    max_samples: usize,
) -> (String, usize) {
    let v = request.validate(mesh).expect("validate");
    let mut stream = ObjStream::new(Vec::new());
    let mut chunks = 0;
    session
        .run_chunked(&v, max_samples, |out| {
            chunks += 1;
            out.write_obj(&mut stream)
        })
        .expect("run_chunked");
    let bytes = stream.finish().expect("flush");
    (String::from_utf8(bytes).expect("utf-8"), chunks)
}

fn whole(mesh: &Mesh, request: &Request<'_>) -> String {
    whole_in(&mut Session::new(), mesh, request)
}

fn whole_in(session: &mut Session, mesh: &Mesh, request: &Request<'_>) -> String {
    let v = request.validate(mesh).expect("validate");
    session.run(&v).expect("run").to_obj()
}

/// Every backend streams a uniform grid in windows of faces: the GPU ones
/// dispatch and read back only each window's patches (class-sorted runs
/// cut to the window), and the OBJ is the whole run's byte for byte —
/// chunks of one face, of a few faces straddling the class runs, and one
/// chunk. Displaced too (the owners' normals and texture coordinates are
/// read across the window's edge).
#[test]
fn every_backend_streams_grids_in_face_windows() {
    let mut session = Session::new();
    let uv = common::mesh("catmark_cube_uv");
    let d = displacement(Ownership::LowestFace, 0.5);
    let righthanded = common::mesh("catmark_righthanded");
    for backend in [
        Backend::Cpu,
        Backend::Wgpu,
        Backend::VulkanGlsl,
        Backend::VulkanHlsl,
    ] {
        let cases: Vec<(&str, &Mesh, Request<'_>)> = vec![
            (
                "righthanded pccm",
                &righthanded,
                Request::uniform("pccm", 3),
            ),
            (
                "righthanded gregory",
                &righthanded,
                Request::uniform("gregory", 2),
            ),
            (
                "cube displaced",
                &uv,
                Request::uniform("acc", 4).displaced(&d),
            ),
        ];
        for (what, mesh, request) in cases {
            let request = request.on(backend);
            let reference = whole_in(&mut session, mesh, &request);
            // One face a chunk, a few (7 at level 3, 12 at level 2), one chunk.
            for max_samples in [1, 112, 0] {
                let (text, chunks) = streamed_in(&mut session, mesh, &request, max_samples);
                assert!(
                    text == reference,
                    "{what} on {backend:?}, chunks of {max_samples}"
                );
                if max_samples == 1 {
                    assert_eq!(chunks, mesh.num_faces(), "{what} on {backend:?}");
                }
            }
        }
    }
    // Triangle schemes stream on the CPU and on wgpu (the Vulkan harness
    // captures their triangles: one chunk, below).
    let cube = common::mesh("catmark_cube");
    for backend in [Backend::Cpu, Backend::Wgpu] {
        let request = Request::uniform("stpn", 5).split_quads(true).on(backend);
        let reference = whole_in(&mut session, &cube, &request);
        let (text, chunks) = streamed_in(&mut session, &cube, &request, 1);
        assert!(text == reference, "stpn on {backend:?}");
        assert_eq!(
            chunks, 12,
            "stpn on {backend:?}: the cube's 12 split triangles"
        );
    }
}

#[test]
fn streamed_obj_is_the_whole_obj() {
    let cases: &[(&str, &str, u32)] = &[
        ("catmark_cube", "pccm", 3),
        ("catmark_righthanded", "gregory", 5),
        ("catmark_tent", "acc", 4),
        ("catmark_cube", "pn", 4),
    ];
    for &(name, scheme, level) in cases {
        let mesh = common::mesh(name);
        // The triangle scheme on the cube's split quads.
        let request = Request::uniform(scheme, level).split_quads(scheme == "pn");
        let reference = whole(&mesh, &request);
        for max_samples in [1, 50, 1000, 0] {
            let (text, chunks) = streamed(&mesh, &request, max_samples);
            assert!(text == reference, "{name} {scheme} chunks of {max_samples}");
            if max_samples == 1 {
                assert!(chunks > 1, "{name}: {chunks} chunk(s)");
            }
        }
    }
}

/// An adaptive request with random factors in `[1, max]` per edge.
fn adaptive(scheme: &str, max: f32) -> Request<'static> {
    common::random_adaptive(scheme, 7, 1.0, max, max)
}

/// Adaptive requests stream on the CPU and on wgpu: every face classified
/// once, then windows of whole faces (on wgpu only the window's buckets
/// dispatched and read back). The chunks' grids are the whole run's bit for
/// bit (levels, faces, samples) and their triangle soup is its OBJ byte for
/// byte — quad and triangle schemes, displaced, holes left out mid-chunk,
/// semi-sharp crease steps (the refined mesh's faces), an open boundary;
/// one face a chunk, about a quarter of the samples, one chunk. The Vulkan
/// harness's adaptive draws come whole (captured triangles, one chunk).
#[test]
fn adaptive_streams_in_face_windows() {
    let mut session = Session::new();
    let uv = common::mesh("catmark_cube_uv");
    let d = displacement(Ownership::LowestFace, 0.5);
    let righthanded = common::mesh("catmark_righthanded");
    let cube = common::mesh("catmark_cube");
    let holed = common::holed("catmark_cube", &[1, 4]);
    let creased = common::mesh("catmark_single_crease");
    let tent = common::mesh("catmark_tent");
    let cases: Vec<(&str, &Mesh, Request<'_>)> = vec![
        ("righthanded pccm", &righthanded, adaptive("pccm", 16.0)),
        (
            "righthanded gregory",
            &righthanded,
            adaptive("gregory", 8.0),
        ),
        ("holed cube pccm", &holed, adaptive("pccm", 8.0)),
        ("single crease acc", &creased, adaptive("acc", 4.0)),
        ("tent pccm (boundary)", &tent, adaptive("pccm", 8.0)),
        (
            "cube acc displaced",
            &uv,
            adaptive("acc", 8.0).displaced(&d),
        ),
        ("cube pn", &cube, adaptive("pn", 8.0).split_quads(true)),
        (
            "cube phong displaced",
            &uv,
            adaptive("phong", 4.0).split_quads(true).displaced(&d),
        ),
    ];
    for (backend, (what, mesh, request)) in [Backend::Cpu, Backend::Wgpu]
        .into_iter()
        .flat_map(|b| cases.iter().map(move |c| (b, c)))
    {
        let request = request.clone().on(backend);
        let what = format!("{what} on {backend:?}");
        let v = request.validate(mesh).expect("validate");
        let whole = session.run(&v).expect("run");
        let Output::Instanced(a) = &whole else {
            panic!("{what}: not instanced");
        };
        let reference = whole.to_obj();
        let faces = a.levels.len();
        // One face a chunk, about a quarter of the samples, one chunk.
        for max_samples in [1, a.positions.len() / 4, 0] {
            let mut stream = ObjStream::new(Vec::new());
            let (mut levels, mut ids, mut positions, mut normals) =
                (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            let mut chunks = 0;
            session
                .run_chunked(&v, max_samples, |out| {
                    chunks += 1;
                    let Output::Instanced(c) = out else {
                        panic!("{what}: a chunk that is not instanced");
                    };
                    assert_eq!(c.edge_levels, a.edge_levels, "{what}");
                    levels.extend_from_slice(&c.levels);
                    ids.extend((0..c.levels.len()).map(|g| c.face_of(g)));
                    positions.extend_from_slice(&c.positions);
                    normals.extend_from_slice(&c.normals);
                    out.write_obj(&mut stream)
                })
                .expect("run_chunked");
            let text = String::from_utf8(stream.finish().expect("flush")).expect("utf-8");
            assert!(text == reference, "{what}: chunks of {max_samples}");
            assert_eq!(levels, a.levels, "{what}: chunks of {max_samples}");
            let want: Vec<usize> = (0..faces).map(|g| a.face_of(g)).collect();
            assert_eq!(ids, want, "{what}: chunks of {max_samples}");
            assert!(positions == a.positions && normals == a.normals, "{what}");
            // Faces of the mesh run, holes included.
            let run = a.edge_levels.len() / a.sides as usize;
            match max_samples {
                // One face a chunk (a hole's chunk is empty).
                1 => assert_eq!(chunks, run, "{what}"),
                0 => assert_eq!(chunks, 1, "{what}"),
                _ => assert!(chunks > 1 && chunks <= run, "{what}: {chunks} chunks"),
            }
        }
    }
}

/// The Vulkan harness's captured triangles stream in windows of faces, only
/// their patches drawn: adaptive draws (quad and triangle schemes, a hole)
/// and triangle schemes at a uniform level, GLSL and HLSL; the OBJ is the
/// whole capture's byte for byte, and so is the adaptive soup.
#[test]
fn captured_triangles_stream_in_face_windows() {
    let mut session = Session::new();
    let righthanded = common::mesh("catmark_righthanded");
    let cube = common::mesh("catmark_cube");
    let holed = common::holed("catmark_cube", &[2]);
    let cases: Vec<(&str, &Mesh, Request<'_>, Backend, usize)> = vec![
        (
            "righthanded pccm adaptive",
            &righthanded,
            adaptive("pccm", 8.0),
            Backend::VulkanGlsl,
            300,
        ),
        (
            "holed cube gregory adaptive",
            &holed,
            adaptive("gregory", 6.0),
            Backend::VulkanHlsl,
            300,
        ),
        (
            "cube pn adaptive",
            &cube,
            adaptive("pn", 5.0).split_quads(true),
            Backend::VulkanGlsl,
            300,
        ),
        (
            "cube stpn level 4",
            &cube,
            Request::uniform("stpn", 4).split_quads(true),
            Backend::VulkanHlsl,
            60,
        ),
    ];
    // Chunks of one face, of a few (by the capture's bound per patch), all.
    for (what, mesh, request, backend, few) in cases {
        let request = request.on(backend);
        let v = request.validate(mesh).expect("validate");
        let whole = session.run(&v).expect("run");
        let Output::Captured(c) = &whole else {
            panic!("{what}: not captured");
        };
        let faces = c.patches.len();
        let (reference, soup) = (whole.to_obj(), soup_of(&whole));
        for max_samples in [1, few, 0] {
            let (text, chunks) = streamed_in(&mut session, mesh, &request, max_samples);
            assert!(text == reference, "{what}: chunks of {max_samples}");
            let mut stream = ObjStream::new(Vec::new());
            session
                .run_chunked(&v, max_samples, |out| {
                    out.write_soup(&mut stream).map(|_| ())
                })
                .expect("run_chunked");
            assert!(stream.finish().expect("flush") == soup, "{what}: soup");
            match max_samples {
                1 => assert_eq!(chunks, faces, "{what}"),
                0 => assert_eq!(chunks, 1, "{what}"),
                _ => assert!(chunks > 1 && chunks < faces, "{what}: {chunks} chunks"),
            }
        }
    }
}

/// The triangle soup of a whole result.
fn soup_of(out: &Output) -> Vec<u8> {
    let mut stream = ObjStream::new(Vec::new());
    out.write_soup(&mut stream).expect("soup");
    stream.finish().expect("flush")
}

/// Hole faces are left out inside a chunk; the OBJ names every grid after
/// its base face, streamed or not.
#[test]
fn holes_are_left_out_per_chunk() {
    let mut mesh = common::mesh("catmark_cube");
    mesh.tags.push(tessgen_runtime::mesh::Tag {
        name: "hole".into(),
        ints: vec![1, 4],
        floats: vec![],
        strings: vec![],
        line: 0,
    });
    let request = Request::uniform("pccm", 3);
    let reference = whole(&mesh, &request);
    assert!(!reference.contains("g patch_1\n") && reference.contains("g patch_5\n"));
    for max_samples in [1, 40, 0] {
        assert!(streamed(&mesh, &request, max_samples).0 == reference);
    }
}

/// Refined meshes of one depth stream in windows of base blocks (a base
/// quad, or one sub-face of an n-gon) on every backend: the refined mesh
/// constructed once, each window's refined faces evaluated and assembled
/// into the base layout; the OBJ is the whole run's byte for byte — n-gons,
/// triangles, semi-sharp creases refined uniformly (the regular scheme),
/// holes.
#[test]
fn refined_meshes_stream_in_block_windows() {
    let mut session = Session::new();
    let nonquads = common::mesh("catmark_nonquads");
    let tris = common::mesh("catmark_smoothtris0");
    let crease = common::mesh("catmark_single_crease");
    let holed = common::holed("catmark_nonquads", &[0, 3]);
    let cases: Vec<(&str, &Mesh, Request<'_>, Vec<Backend>)> = vec![
        (
            "nonquads pccm",
            &nonquads,
            Request::uniform("pccm", 4),
            vec![Backend::Cpu, Backend::Wgpu, Backend::VulkanHlsl],
        ),
        (
            "smoothtris acc",
            &tris,
            Request::uniform("acc", 6),
            vec![Backend::Cpu, Backend::Wgpu],
        ),
        (
            "single crease regular",
            &crease,
            Request::uniform("regular", 4),
            vec![Backend::Cpu, Backend::VulkanGlsl],
        ),
        (
            "holed nonquads gregory",
            &holed,
            Request::uniform("gregory", 2),
            vec![Backend::Cpu, Backend::Wgpu],
        ),
    ];
    for (what, mesh, request, backends) in cases {
        for backend in backends {
            let request = request.clone().on(backend);
            let v = request.validate(mesh).expect("validate");
            let blocks = v.refined().expect("refined").refinement.blocks.len();
            let reference = whole_in(&mut session, mesh, &request);
            for max_samples in [1, 200, 0] {
                let (text, chunks) = streamed_in(&mut session, mesh, &request, max_samples);
                assert!(
                    text == reference,
                    "{what} on {backend:?}, chunks of {max_samples}"
                );
                match max_samples {
                    1 => assert_eq!(chunks, blocks, "{what} on {backend:?}"),
                    0 => assert_eq!(chunks, 1, "{what} on {backend:?}"),
                    _ => assert!(chunks > 1 && chunks < blocks, "{what}: {chunks}"),
                }
            }
        }
    }
}

/// The samples of a grid or polygon-grid result, as bits, with the base
/// face (and corner) of each grid: the quads', then the sub-faces'.
type GridBits = (Vec<u32>, Vec<[u32; 6]>, Vec<(u32, u32)>, Vec<[u32; 6]>);

fn grid_bits(out: &Output, into: &mut GridBits) {
    let bits = |t: &tessgen_runtime::Tessellation| {
        t.positions
            .iter()
            .zip(&t.normals)
            .map(|(p, n)| {
                let (p, n) = (p.to_array(), n.to_array());
                [p[0], p[1], p[2], n[0], n[1], n[2]].map(f32::to_bits)
            })
            .collect::<Vec<_>>()
    };
    let ids = |t: &tessgen_runtime::Tessellation| {
        (0..t.faces)
            .map(|g| t.face_of(g) as u32)
            .collect::<Vec<_>>()
    };
    match out {
        Output::Grid(t) => {
            into.0.extend(ids(t));
            into.1.extend(bits(t));
        }
        Output::Polygons(p) => {
            into.0.extend(ids(&p.quads));
            into.1.extend(bits(&p.quads));
            into.2
                .extend(ids(&p.subfaces).into_iter().zip(p.corners.iter().copied()));
            into.3.extend(bits(&p.subfaces));
        }
        other => panic!("not grids: {other:?}"),
    }
}

/// Whether two blocks of different depths share a base vertex (so the
/// refinement has transitions, whose samples a window takes from its
/// neighbours).
fn has_transitions(mesh: &Mesh, v: &tessgen_runtime::tessellate::Validated<'_>) -> bool {
    let blocks = &v.refined().expect("refined").refinement.blocks;
    let mut depths: std::collections::HashMap<u32, std::collections::BTreeSet<u32>> =
        Default::default();
    for b in blocks {
        for &vertex in mesh.face(b.face as usize) {
            depths.entry(vertex).or_default().insert(b.depth);
        }
    }
    depths.values().any(|d| d.len() > 1)
}

/// Feature-adaptive refinements (several depths: around semi-sharp
/// creases, isolated extraordinary vertices, n-gons' sub-faces) stream in
/// windows of base blocks on every backend, each depth's refined mesh
/// constructed once on the session's one device: chunks of one block, of a
/// few, and one chunk give the whole run's samples bit for bit and its OBJ
/// byte for byte. The meshes have transitions between depths, where a
/// window takes the deepest side's sample from the blocks around it (its
/// halo): without them a one-block window's border would be its own.
#[test]
fn feature_adaptive_refinements_stream_in_block_windows() {
    let mut session = Session::new();
    let crease = common::mesh("catmark_single_crease");
    let xord = common::mesh("catmark_xord_interior");
    let pawn = common::mesh("catmark_pawn");
    let nonquads = common::mesh("catmark_nonquads");
    let holed = common::holed("catmark_nonquads", &[0, 3]);
    let every = vec![
        Backend::Cpu,
        Backend::Wgpu,
        Backend::VulkanGlsl,
        Backend::VulkanHlsl,
    ];
    // (what, mesh, request, backends, blocks of different depths meet)
    let cases: Vec<(&str, &Mesh, Request<'_>, Vec<Backend>, bool)> = vec![
        (
            "single crease pccm",
            &crease,
            Request::uniform("pccm", 4),
            every.clone(),
            true,
        ),
        (
            "pawn pccm",
            &pawn,
            Request::uniform("pccm", 2),
            vec![Backend::Cpu, Backend::Wgpu],
            true,
        ),
        (
            "xord interior pccm isolated",
            &xord,
            Request::uniform("pccm", 8).isolate(2),
            every.clone(),
            false,
        ),
        (
            "nonquads gregory isolated",
            &nonquads,
            Request::uniform("gregory", 4).isolate(2),
            vec![Backend::Cpu, Backend::Wgpu, Backend::VulkanGlsl],
            false,
        ),
        (
            "holed nonquads pccm isolated",
            &holed,
            Request::uniform("pccm", 4).isolate(2),
            vec![Backend::Cpu, Backend::Wgpu],
            false,
        ),
    ];
    for (what, mesh, request, backends, transitions) in cases {
        for backend in backends {
            let request = request.clone().on(backend);
            let v = request.validate(mesh).expect("validate");
            assert!(v.parts().count() > 1, "{what}: one depth");
            if transitions {
                assert!(has_transitions(mesh, &v), "{what}: no transitions");
            }
            let blocks = v.refined().expect("refined").refinement.blocks.len();
            let whole = session.run(&v).expect("run");
            let (reference, mut samples) = (whole.to_obj(), GridBits::default());
            grid_bits(&whole, &mut samples);
            // A few blocks a chunk: a quarter of the result (every depth's
            // evaluated samples count).
            let few = whole.samples() / 4;
            for max_samples in [1, few, 0] {
                let mut stream = ObjStream::new(Vec::new());
                let (mut chunks, mut streamed) = (0, GridBits::default());
                session
                    .run_chunked(&v, max_samples, |out| {
                        chunks += 1;
                        grid_bits(out, &mut streamed);
                        out.write_obj(&mut stream)
                    })
                    .expect("run_chunked");
                let text = String::from_utf8(stream.finish().expect("flush")).expect("utf-8");
                let at = format!("{what} on {backend:?}, chunks of {max_samples}");
                assert!(streamed == samples, "{at}: samples");
                assert!(text == reference, "{at}: OBJ");
                match max_samples {
                    1 => assert_eq!(chunks, blocks, "{at}"),
                    0 => assert_eq!(chunks, 1, "{at}"),
                    _ => assert!(chunks > 1 && chunks < blocks, "{at}: {chunks} chunks"),
                }
            }
        }
    }
}

/// The grid writer of a whole result is `to_obj`'s.
#[test]
fn the_grid_writer_is_to_obj() {
    let cube = common::mesh("catmark_cube");
    let request = Request::uniform("pccm", 3).on(Backend::Wgpu);
    let v = request.validate(&cube).expect("validate");
    let out = Session::new().run(&v).expect("run");
    assert!(to_obj(out.grid().expect("grid")) == out.to_obj());
}

/// The convenient (whole-result) API refuses a result that cannot be
/// allocated with a typed error instead of aborting the process: 434 faces
/// at level 4096 are 7.28 G samples, 175 GB. Linux refuses such a request
/// outright unless overcommit is unconditional (mode 1), where the test
/// cannot tell and is skipped.
#[test]
fn a_result_that_does_not_fit_is_an_error() {
    let mode = std::fs::read_to_string("/proc/sys/vm/overcommit_memory").unwrap_or_default();
    if mode.trim() == "1" {
        eprintln!("skipped: vm.overcommit_memory = 1 grants any allocation");
        return;
    }
    let mesh = common::mesh("catmark_righthanded");
    let request = Request::uniform("pccm", 4096);
    let v = request.validate(&mesh).expect("validate");
    match Session::new().run(&v) {
        Err(tessgen_runtime::tessellate::Error::Tess(
            e @ tessgen_runtime::TessError::OutOfMemory { .. },
        )) => {
            let text = e.to_string();
            assert!(text.contains("7284867506 samples"), "{text}");
            assert!(text.contains("run_chunked"), "{text}");
        }
        other => panic!("{:?}", other.map(|o| o.counts())),
    }
}
