//! Triangle-mesh input for the triangle schemes (PN, scalar-tagged PN,
//! Phong): `TriMesh::from_mesh`'s checks and normals on the shared meshes,
//! and the triangle sample pattern's watertightness under exact-bit welding.

mod common;

use std::collections::HashMap;
use std::fmt::Write;

use glam::Vec3;
use tessgen_runtime::grid::{tri_grid_coords, tri_grid_edge, tri_grid_len, tri_grid_triangles};
use tessgen_runtime::mesh::NO_NORMAL;
use tessgen_runtime::stats::MeshStats;
use tessgen_runtime::trimesh::{NormalSource, TriMesh, TriMeshError, TriOptions};
use tessgen_runtime::{obj, weld, Mesh, MeshError};

const LEVELS: &[u32] = &[1, 2, 7, 8, 16];

fn split() -> TriOptions {
    TriOptions {
        split_quads: true,
        ..TriOptions::default()
    }
}

fn split_recompute() -> TriOptions {
    TriOptions {
        split_quads: true,
        recompute_normals: true,
    }
}

fn tri_err(text: &str, opts: &TriOptions) -> TriMeshError {
    let mesh = Mesh::from_obj_str(text).expect("valid OBJ");
    TriMesh::from_mesh(&mesh, opts).expect_err("should be refused")
}

/// Undirected edge → number of triangles using it (independent of the
/// runtime's own count).
fn edge_uses(tris: &[[u32; 3]]) -> HashMap<(u32, u32), usize> {
    let mut uses = HashMap::new();
    for t in tris {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses
}

/// `mesh` as OBJ text with one `vn` line per face corner, `normal(face,
/// vertex)`, and `f v//vn` faces.
fn obj_with_corner_normals(mesh: &Mesh, normal: impl Fn(usize, usize) -> Vec3) -> String {
    let mut s = String::new();
    for p in &mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
    }
    let mut k = 0;
    for f in 0..mesh.num_faces() {
        let mut line = String::from("f");
        for &v in mesh.face(f) {
            let n = normal(f, v as usize);
            let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
            k += 1;
            let _ = write!(line, " {}//{k}", v + 1);
        }
        s.push_str(&line);
        s.push('\n');
    }
    s
}

fn face_centroid(mesh: &Mesh, f: usize) -> Vec3 {
    let face = mesh.face(f);
    face.iter()
        .map(|&v| Vec3::from(mesh.positions[v as usize]))
        .sum::<Vec3>()
        / face.len() as f32
}

fn centroid(t: &TriMesh) -> Vec3 {
    t.positions.iter().sum::<Vec3>() / t.positions.len() as f32
}

// ---------------------------------------------------------------------------
// Splitting the shared closed meshes

#[test]
fn split_closed_meshes_stay_closed_with_same_euler() {
    for name in common::CLOSED_MESHES {
        let mesh = common::mesh(name);
        let euler = MeshStats::of(&mesh).euler_characteristic;
        assert!(
            matches!(
                TriMesh::from_mesh(&mesh, &TriOptions::default()),
                Err(TriMeshError::NotTriangle { face: 0, sides: 4 })
            ),
            "{name}: quads need split_quads"
        );
        let t = TriMesh::from_mesh(&mesh, &split()).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(t.num_triangles(), 2 * mesh.num_faces(), "{name}");
        assert_eq!(t.normal_source, NormalSource::AreaWeighted, "{name}");
        for f in 0..mesh.num_faces() {
            let q = mesh.face(f);
            assert_eq!(t.triangles[2 * f], [q[0], q[1], q[2]], "{name} face {f}");
            assert_eq!(
                t.triangles[2 * f + 1],
                [q[0], q[2], q[3]],
                "{name} face {f}"
            );
            assert_eq!(t.source_face[2 * f..2 * f + 2], [f as u32; 2]);
        }
        let uses = edge_uses(&t.triangles);
        assert!(uses.values().all(|&c| c == 2), "{name}: closed");
        assert!(t.is_closed(), "{name}");
        assert_eq!(t.num_boundary_edges(), 0, "{name}");
        assert_eq!(t.num_edges(), uses.len(), "{name}");
        assert_eq!(t.euler_characteristic(), euler, "{name}");
        for (v, n) in t.normals.iter().enumerate() {
            assert!((n.length() - 1.0).abs() < 1e-6, "{name} vertex {v}: {n}");
        }
    }
}

#[test]
fn split_cube_area_normals_point_outward() {
    let mesh = common::mesh("catmark_cube");
    let t = TriMesh::from_mesh(&mesh, &split()).unwrap();
    let c = centroid(&t);
    for (v, (p, n)) in t.positions.iter().zip(&t.normals).enumerate() {
        let d = (*p - c).normalize();
        assert!(n.dot(d) > 0.5, "vertex {v}: normal {n} vs outward {d}");
    }
}

#[test]
fn consistent_obj_normals_are_used() {
    let cube = common::mesh("catmark_cube");
    // One vn line per corner, all corners of a vertex giving its position
    // (length √3, not unit): consistent after normalisation.
    let text = obj_with_corner_normals(&cube, |_, v| Vec3::from(cube.positions[v]));
    let mesh = Mesh::from_obj_str(&text).unwrap();
    assert_eq!(mesh.normals.len(), 24);
    let t = TriMesh::from_mesh(&mesh, &split()).unwrap();
    assert_eq!(t.normal_source, NormalSource::Obj);
    for (p, n) in t.positions.iter().zip(&t.normals) {
        assert!(
            (*n - p.normalize()).abs().max_element() < 1e-6,
            "{n} vs {p}"
        );
    }
    // recompute_normals ignores them.
    let t = TriMesh::from_mesh(&mesh, &split_recompute()).unwrap();
    assert_eq!(t.normal_source, NormalSource::AreaWeighted);
}

#[test]
fn split_normals_are_refused_unless_recomputed() {
    let cube = common::mesh("catmark_cube");
    // Hard edges: every corner gets its face's normal.
    let text = obj_with_corner_normals(&cube, |f, _| face_centroid(&cube, f));
    let mesh = Mesh::from_obj_str(&text).unwrap();
    // Face 0 is `1 2 4 3`, face 1 `3 4 6 5`: vertex 2 (0-based) is the first
    // vertex met again with another normal.
    match TriMesh::from_mesh(&mesh, &split()) {
        Err(TriMeshError::SplitNormal { vertex, faces }) => {
            assert_eq!((vertex, faces), (2, [0, 1]));
        }
        other => panic!("expected SplitNormal, got {other:?}"),
    }
    let t = TriMesh::from_mesh(&mesh, &split_recompute()).unwrap();
    assert_eq!(t.normal_source, NormalSource::AreaWeighted);
    let c = centroid(&t);
    for (p, n) in t.positions.iter().zip(&t.normals) {
        assert!(n.dot(*p - c) > 0.0);
    }
}

// ---------------------------------------------------------------------------
// Every error variant, with the face / vertex it names

const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nv 0.5 -1 0\n";

#[test]
fn not_triangle_names_the_face() {
    let text = format!("{SQUARE}f 1 2 5\nf 1 2 3 4\n");
    assert!(matches!(
        tri_err(&text, &TriOptions::default()),
        TriMeshError::NotTriangle { face: 1, sides: 4 }
    ));
    let text = format!("{SQUARE}f 1 2 5\nf 2 3 5\nf 1 6 2 3 4\n");
    let e = tri_err(&text, &split());
    assert!(matches!(e, TriMeshError::NotTriangle { face: 2, sides: 5 }));
    assert!(e.to_string().contains("face 2 has 5 sides"), "{e}");
}

#[test]
fn non_manifold_edge_names_edge_and_faces() {
    // Three triangles on edge 1-2 (0-based 0-1).
    let text = format!("{SQUARE}f 3 4 5\nf 1 2 5\nf 2 1 6\nf 1 2 3\n");
    match tri_err(&text, &TriOptions::default()) {
        TriMeshError::NonManifoldEdge { a, b, faces } => {
            assert_eq!((a, b), (0, 1));
            assert_eq!(faces, vec![1, 2, 3]);
        }
        other => panic!("expected NonManifoldEdge, got {other:?}"),
    }
}

#[test]
fn inconsistent_orientation_names_edge_and_faces() {
    // Faces 0 and 2 both run along `2 5`, i.e. 1 -> 4 (0-based).
    let text = format!("{SQUARE}f 1 2 5\nf 3 4 5\nf 2 5 6\n");
    match tri_err(&text, &TriOptions::default()) {
        TriMeshError::InconsistentOrientation { a, b, faces } => {
            assert_eq!((a, b, faces), (1, 4, [0, 2]));
        }
        other => panic!("expected InconsistentOrientation, got {other:?}"),
    }
    // Through a split quad: the quad's second half [0, 2, 3] runs 2 -> 3,
    // and so does the triangle `3 4 5`.
    let text = format!("{SQUARE}f 1 2 3 4\nf 3 4 5\n");
    assert!(matches!(
        tri_err(&text, &split()),
        TriMeshError::InconsistentOrientation {
            a: 2,
            b: 3,
            faces: [0, 1]
        }
    ));
}

#[test]
fn missing_normal_names_face_and_corner() {
    let text = format!("{SQUARE}vn 0 0 1\nf 1//1 2//1 5//1\nf 2//1 3 5//1\n");
    assert!(matches!(
        tri_err(&text, &TriOptions::default()),
        TriMeshError::MissingNormal { face: 1, corner: 1 }
    ));
    let mesh = Mesh::from_obj_str(&text).unwrap();
    let opts = TriOptions {
        recompute_normals: true,
        ..TriOptions::default()
    };
    let t = TriMesh::from_mesh(&mesh, &opts).unwrap();
    assert_eq!(t.normal_source, NormalSource::AreaWeighted);
}

#[test]
fn degenerate_normals_name_the_vertex() {
    // A zero OBJ normal on vertex 4 (0-based).
    let text = format!("{SQUARE}vn 0 0 1\nvn 0 0 0\nf 1//1 2//1 5//2\n");
    assert!(matches!(
        tri_err(&text, &TriOptions::default()),
        TriMeshError::DegenerateNormal { vertex: 4 }
    ));
    // Area weighting: two triangles glued back to back cancel exactly.
    let text = format!("{SQUARE}f 2 3 5\nf 2 5 3\n");
    assert!(matches!(
        tri_err(&text, &TriOptions::default()),
        TriMeshError::DegenerateNormal { vertex: 1 }
    ));
    // A zero-area (collinear) triangle has no direction either.
    let text = "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";
    assert!(matches!(
        tri_err(text, &TriOptions::default()),
        TriMeshError::DegenerateNormal { vertex: 0 }
    ));
}

#[test]
fn invalid_mesh_is_a_mesh_error() {
    let mut mesh = Mesh::from_obj_str(&format!("{SQUARE}vn 0 0 1\nf 1//1 2//1 5//1\n")).unwrap();
    mesh.face_normals[2] = 7;
    assert!(matches!(
        TriMesh::from_mesh(&mesh, &TriOptions::default()),
        Err(TriMeshError::Mesh(MeshError::NormalIndexOutOfRange {
            face: 0,
            corner: 2,
            index: 7
        }))
    ));
    mesh.face_normals[2] = NO_NORMAL;
    mesh.face_vertices[0] = 99;
    assert!(matches!(
        TriMesh::from_mesh(&mesh, &TriOptions::default()),
        Err(TriMeshError::Mesh(MeshError::FaceIndexOutOfRange { .. }))
    ));
}

#[test]
fn unused_vertices_keep_zero_normals() {
    let text = format!("{SQUARE}f 1 2 5\n");
    let t =
        TriMesh::from_mesh(&Mesh::from_obj_str(&text).unwrap(), &TriOptions::default()).unwrap();
    assert_eq!(t.num_vertices(), 6);
    for v in [2, 3, 5] {
        assert_eq!(t.normals[v], Vec3::ZERO);
    }
    assert_eq!(t.euler_characteristic(), 1);
    assert_eq!(t.num_boundary_edges(), 3);
}

// ---------------------------------------------------------------------------
// Flat tessellation: the triangle sample pattern welds watertight

/// Linear interpolation of every triangle at `level`, with weights formed
/// from the integer barycentrics and only the non-zero terms summed, so an
/// edge sample is `wa·A + wb·B` on one side and `wb·B + wa·A` on the other
/// (bit-identical: IEEE + and × are commutative) and a corner is `1·P = P`.
fn flat_tessellation(t: &TriMesh, level: u32) -> Vec<Vec3> {
    let coords = tri_grid_coords(level);
    let mut out = Vec::with_capacity(t.num_triangles() * coords.len());
    for k in 0..t.num_triangles() {
        let corners = t.triangle_positions(k);
        for c in &coords {
            let mut p: Option<Vec3> = None;
            for i in 0..3 {
                if c[i] != 0 {
                    let term = corners[i] * (c[i] as f32 / level as f32);
                    p = Some(p.map_or(term, |s| s + term));
                }
            }
            out.push(p.expect("a sample has a non-zero weight"));
        }
    }
    out
}

/// Weld independently of `weld::weld_triangles` and rebuild a mesh from the
/// result, so that `TriMesh::from_mesh` checks manifoldness *and*
/// orientation of the welded surface.
fn welded_mesh(positions: &[Vec3], level: u32) -> Mesh {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut welded_positions = Vec::new();
    let welded: Vec<u32> = positions
        .iter()
        .map(|p| {
            let key = p.to_array().map(f32::to_bits);
            *ids.entry(key).or_insert_with(|| {
                welded_positions.push(p.to_array());
                welded_positions.len() as u32 - 1
            })
        })
        .collect();
    let per = tri_grid_len(level);
    let local = tri_grid_triangles(level);
    let faces: Vec<Vec<u32>> = (0..positions.len() / per)
        .flat_map(|f| {
            local
                .iter()
                .map(|t| t.iter().map(|&k| welded[f * per + k as usize]).collect())
                .collect::<Vec<_>>()
        })
        .collect();
    Mesh::from_raw(welded_positions, &faces).unwrap()
}

#[test]
fn flat_tessellation_welds_closed() {
    for name in common::CLOSED_MESHES {
        let mesh = common::mesh(name);
        let t = TriMesh::from_mesh(&mesh, &split()).unwrap();
        let euler = t.euler_characteristic();
        for &level in LEVELS {
            let positions = flat_tessellation(&t, level);
            let r =
                weld::weld_triangles(&positions, tri_grid_len(level), &tri_grid_triangles(level));
            assert!(
                r.is_closed_manifold(),
                "{name} level {level}: {} open, {} overused, {} degenerate",
                r.open_edges,
                r.overused_edges,
                r.degenerate_triangles
            );
            assert_eq!(r.euler, euler, "{name} level {level}");
            assert_eq!(
                r.triangles,
                t.num_triangles() * (level * level) as usize,
                "{name} level {level}"
            );
            let n = level as usize;
            let v_expected = mesh.num_vertices()
                + t.num_edges() * (n - 1)
                + t.num_triangles() * (n.saturating_sub(1) * n.saturating_sub(2) / 2);
            assert_eq!(r.vertices, v_expected, "{name} level {level}: vertices");
            let welded =
                TriMesh::from_mesh(&welded_mesh(&positions, level), &TriOptions::default())
                    .unwrap_or_else(|e| panic!("{name} level {level}: {e}"));
            assert!(welded.is_closed(), "{name} level {level}");
            assert_eq!(welded.euler_characteristic(), euler, "{name} level {level}");
        }
    }
}

/// Negative control: one sample on a shared edge moved by one ulp opens the
/// two edge segments it touches, on both sides.
#[test]
fn one_ulp_opens_the_flat_weld() {
    let t = TriMesh::from_mesh(&common::mesh("catmark_torus"), &split()).unwrap();
    for &level in LEVELS {
        let mut positions = flat_tessellation(&t, level);
        let local = tri_grid_triangles(level);
        let per = tri_grid_len(level);
        assert!(weld::weld_triangles(&positions, per, &local).is_closed_manifold());
        // Level 1 has no edge-interior sample: move corner 0 instead.
        let s = tri_grid_edge(level, 0)[level as usize / 2] as usize;
        let p = &mut positions[s];
        p.x = f32::from_bits(p.x.to_bits() + 1);
        let r = weld::weld_triangles(&positions, per, &local);
        assert!(!r.is_closed_manifold(), "level {level}");
        assert_eq!(r.open_edges, 4, "level {level}");
    }
}

#[test]
fn triangle_obj_output_reads_back() {
    let t = TriMesh::from_mesh(&common::mesh("catmark_cube"), &split()).unwrap();
    let level = 2;
    let positions = flat_tessellation(&t, level);
    let normals: Vec<Vec3> = (0..t.num_triangles())
        .flat_map(|k| {
            let n = t.triangle_normals(k);
            tri_grid_coords(level)
                .into_iter()
                .map(move |c| (0..3).map(|i| n[i] * c[i] as f32).sum::<Vec3>().normalize())
        })
        .collect();
    let text = obj::tri_to_obj(&positions, &normals, level);
    let back = Mesh::from_obj_str(&text).unwrap();
    assert_eq!(back.num_faces(), t.num_triangles() * 4);
    assert_eq!(back.num_vertices(), positions.len());
    assert_eq!(back.normals.len(), normals.len());
    for (a, b) in back.positions.iter().zip(&positions) {
        assert_eq!(Vec3::from(*a), *b, "shortest round-trip printing");
    }
}
