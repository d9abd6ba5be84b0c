use super::*;

fn mesh_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/meshes")
        .join(format!("{name}.obj"))
}

/// An independent, minimal reading of the `v` and `f` lines (plain `f a b c` syntax only).
fn naive_v_f(text: &str) -> (Vec<[f32; 3]>, Vec<Vec<u32>>) {
    let mut v = Vec::new();
    let mut f = Vec::new();
    for l in text.lines() {
        let w: Vec<&str> = l.split_whitespace().collect();
        match w.first() {
            Some(&"v") => v.push([
                w[1].parse().unwrap(),
                w[2].parse().unwrap(),
                w[3].parse().unwrap(),
            ]),
            Some(&"f") => f.push(
                w[1..]
                    .iter()
                    .map(|s| s.split('/').next().unwrap().parse::<u32>().unwrap() - 1)
                    .collect(),
            ),
            _ => {}
        }
    }
    (v, f)
}

/// Vertices listed in an order no face follows, vertex 5 (0-based 4) unused, and faces whose
/// first-use order differs from file order: exactly what tobj renumbers.
const SCRAMBLED: &str = "\
# file order test
v 0.0 0.0 0.0
v 1.0 0.0 0.0
v 1.0 1.0 0.0
v 0.0 1.0 0.0
v 9.0 9.0 9.0
v 0.5 0.5 1.0
t corner 1/1/0 5 2.5
f 6 3 4
f 4 1 2 3
f 2/7/1 6 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vt 0.5 0.5
vt 0.2 0.2
vt 0.3 0.3
vn 0 0 1
";

#[test]
fn keeps_file_order_and_unused_vertices() {
    let mesh = Mesh::from_obj_str(SCRAMBLED).unwrap();
    let expected_positions = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [9.0, 9.0, 9.0],
        [0.5, 0.5, 1.0],
    ];
    assert_eq!(mesh.positions, expected_positions);
    assert_eq!(mesh.num_vertices(), 6);
    assert_eq!(mesh.num_faces(), 3);
    assert_eq!(mesh.face(0), &[5, 2, 3]);
    assert_eq!(mesh.face(1), &[3, 0, 1, 2]);
    assert_eq!(mesh.face(2), &[1, 5, 0]);
    assert_eq!(mesh.face_offsets, vec![0, 3, 7, 10]);
    assert_eq!(
        mesh.tags,
        vec![Tag {
            name: "corner".into(),
            ints: vec![5],
            floats: vec![2.5],
            strings: vec![],
            line: 8,
        }]
    );
}

/// Pins the finding that made the scanner necessary: tobj drops unused vertices and
/// renumbers positions in order of first use.
#[test]
fn tobj_compacts_positions() {
    let (models, _) = load_with_tobj(SCRAMBLED).unwrap();
    assert_eq!(models.len(), 1);
    let m = &models[0].mesh;
    assert_eq!(m.positions.len(), 5 * 3, "unused vertex dropped");
    assert_eq!(&m.indices[..3], &[0, 1, 2], "first face renumbered 0,1,2");
    assert_eq!(
        &m.positions[..3],
        &[0.5, 0.5, 1.0],
        "tobj 0 is file vertex 5"
    );
}

#[test]
fn groups_restart_tobj_numbering_but_not_ours() {
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ng a\nf 1 2 3\ng b\nusemtl x\nf 3 4 1\n";
    let mesh = Mesh::from_obj_str(text).unwrap();
    assert_eq!(mesh.face(0), &[0, 1, 2]);
    assert_eq!(mesh.face(1), &[2, 3, 0]);
}

#[test]
fn relative_indices_and_w() {
    let text = "v 0 0 0\nv 2 0 0 2\nv 1 1 0\nf -3 -2 -1\n";
    let mesh = Mesh::from_obj_str(text).unwrap();
    assert_eq!(mesh.face(0), &[0, 1, 2]);
    assert_eq!(mesh.positions[1], [1.0, 0.0, 0.0]);
}

#[test]
fn real_meshes_match_a_naive_reading() {
    for name in [
        "catmark_cube",
        "catmark_torus",
        "catmark_righthanded",
        "catmark_car",
        "catmark_xord_interior",
    ] {
        let path = mesh_path(name);
        let text = std::fs::read_to_string(&path).unwrap();
        let mesh = Mesh::from_obj_path(&path).unwrap();
        let (v, f) = naive_v_f(&text);
        assert_eq!(mesh.positions, v, "{name}");
        assert_eq!(mesh.num_faces(), f.len(), "{name}");
        for (i, face) in f.iter().enumerate() {
            assert_eq!(mesh.face(i), &face[..], "{name} face {i}");
        }
        let tag_lines = text.lines().filter(|l| l.starts_with("t ")).count();
        assert_eq!(mesh.tags.len(), tag_lines, "{name}");
        mesh.validate().unwrap();
    }
}

#[test]
fn tags_are_parsed() {
    let mesh = Mesh::from_obj_path(mesh_path("catmark_single_crease")).unwrap();
    let t = &mesh.tags[0];
    assert_eq!(t.name, "crease");
    assert_eq!(t.ints, vec![1, 22]);
    assert_eq!(t.floats, vec![10.0]);
    assert!(t.strings.is_empty());
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt name 0/0/2 a b\n";
    let mesh = Mesh::from_obj_str(text).unwrap();
    assert_eq!(mesh.tags[0].strings, vec!["a", "b"]);
    assert_eq!(mesh.tags[0].line, 5);
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

fn err(text: &str) -> MeshError {
    Mesh::from_obj_str(text).unwrap_err()
}

fn obj_line(e: MeshError) -> Option<usize> {
    match e {
        MeshError::Obj { line, .. } => line,
        other => panic!("expected Obj error, got {other:?}"),
    }
}

#[test]
fn malformed_lines_are_located() {
    assert_eq!(
        obj_line(err("v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n")),
        Some(2)
    );
    assert_eq!(obj_line(err("v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")), Some(1));
    assert_eq!(obj_line(err(&format!("{TRI}f 1 2 a\n"))), Some(4));
    assert_eq!(obj_line(err(&format!("{TRI}f 1 2 3/1\n"))), Some(4));
    assert_eq!(obj_line(err(&format!("{TRI}f 1 2 3//1\n"))), Some(4));
    assert_eq!(
        obj_line(err(&format!("{TRI}f 1 2 3\nt crease 2/1/0 0 1\n"))),
        Some(5)
    );
    assert_eq!(
        obj_line(err(&format!("{TRI}f 1 2 3\nt crease 2/1 0 1 1\n"))),
        Some(5)
    );
    assert_eq!(
        obj_line(err(&format!("{TRI}f 1 2 3\nt crease 2/1/0 0 x 1\n"))),
        Some(5)
    );
    assert_eq!(obj_line(err(&format!("{TRI}f 1 2 3\nt\n"))), Some(5));
    assert_eq!(obj_line(err(&format!("{TRI}l 1 2 3\nf 1 2 3\n"))), Some(4));
    assert_eq!(
        obj_line(err("v 1 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")),
        Some(1)
    );
    assert_eq!(
        obj_line(err("v 0 0 0 # c\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")),
        Some(1)
    );
}

#[test]
fn semantic_errors() {
    assert!(matches!(err("# nothing\n"), MeshError::Empty));
    assert!(matches!(err(TRI), MeshError::Empty));
    assert!(matches!(err("f 1 2 3\n"), MeshError::Empty));
    assert!(matches!(
        err("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
        MeshError::NonFinite {
            vertex: 1,
            line: Some(2)
        }
    ));
    assert!(matches!(
        err("v 0 0 0\nv 1 0 0\nv 0 1e50 0\nf 1 2 3\n"),
        MeshError::NonFinite {
            vertex: 2,
            line: Some(3)
        }
    ));
    assert!(matches!(
        err(&format!("{TRI}f 1 2 3\nf 1 2 4\n")),
        MeshError::FaceIndexOutOfRange {
            face: 1,
            line: Some(5),
            index: 3
        }
    ));
    assert!(matches!(
        err(&format!("{TRI}f 0 1 2\n")),
        MeshError::FaceIndexOutOfRange {
            face: 0,
            line: Some(4),
            index: -1
        }
    ));
    assert!(matches!(
        err(&format!("{TRI}f 1 2 -4\n")),
        MeshError::FaceIndexOutOfRange {
            face: 0,
            line: Some(4),
            index: -1
        }
    ));
    // tobj would silently drop these as "lines"/"points".
    assert!(matches!(
        err(&format!("{TRI}f 1 2 3\nf 1 2\n")),
        MeshError::DegenerateFace {
            face: 1,
            line: Some(5),
            arity: 2
        }
    ));
    assert!(matches!(
        err(&format!("{TRI}f 1\n")),
        MeshError::DegenerateFace {
            face: 0,
            line: Some(4),
            arity: 1
        }
    ));
    assert!(matches!(
        err(&format!("{TRI}f 1 2 3 2\n")),
        MeshError::RepeatedVertex {
            face: 0,
            line: Some(4),
            vertex: 1
        }
    ));
}

#[test]
fn from_raw_checks() {
    let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let m = Mesh::from_raw(p.clone(), &[vec![0, 1, 2]]).unwrap();
    assert_eq!(m.face(0), &[0, 1, 2]);
    assert!(m.tags.is_empty());
    assert!(matches!(
        Mesh::from_raw(p.clone(), &[vec![0, 1, 3]]),
        Err(MeshError::FaceIndexOutOfRange {
            face: 0,
            line: None,
            index: 3
        })
    ));
    assert!(matches!(
        Mesh::from_raw(p.clone(), &[vec![0, 1]]),
        Err(MeshError::DegenerateFace {
            face: 0,
            line: None,
            arity: 2
        })
    ));
    assert!(matches!(
        Mesh::from_raw(p.clone(), &[vec![0, 1, 0]]),
        Err(MeshError::RepeatedVertex {
            face: 0,
            line: None,
            vertex: 0
        })
    ));
    assert!(matches!(
        Mesh::from_raw(p.clone(), &[]),
        Err(MeshError::Empty)
    ));
    assert!(matches!(
        Mesh::from_raw(vec![[0.0, f32::INFINITY, 0.0]], &[vec![0, 0, 0]]),
        Err(MeshError::NonFinite {
            vertex: 0,
            line: None
        })
    ));
}

#[test]
fn validate_catches_hand_built_layout() {
    let mut m = Mesh::from_raw(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[vec![0, 1, 2]],
    )
    .unwrap();
    m.face_offsets = vec![0, 4];
    assert!(matches!(m.validate(), Err(MeshError::Layout { .. })));
    m.face_offsets = vec![0, 3];
    m.face_vertices[2] = 7;
    assert!(matches!(
        m.validate(),
        Err(MeshError::FaceIndexOutOfRange {
            face: 0,
            line: None,
            index: 7
        })
    ));
}

#[test]
fn io_error_names_path() {
    let e = Mesh::from_obj_path("/nonexistent/dir/x.obj").unwrap_err();
    assert!(matches!(&e, MeshError::Io { path, .. } if path.ends_with("x.obj")));
    assert!(e.to_string().contains("/nonexistent/dir/x.obj"));
}

#[test]
fn normals_are_kept_per_corner() {
    // Corners with and without normals, a relative normal index, a `v/vt/vn` corner and a
    // normal defined after the face that uses it (allowed, like tobj).
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvn 0 0 2\nvn 0 0 1\n\
                f 1//1 2//-1 3\nf 2/1/3 4//2 3//1\nvn 0.5 0 1 7\n";
    let mesh = Mesh::from_obj_str(text).unwrap();
    assert_eq!(
        mesh.normals,
        vec![[0.0, 0.0, 2.0], [0.0, 0.0, 1.0], [0.5, 0.0, 1.0]]
    );
    assert_eq!(mesh.face_normals, vec![0, 1, NO_NORMAL, 2, 1, 0]);
    assert_eq!(mesh.corner_normal(2), None);
    assert_eq!(mesh.corner_normal(3), Some(2));
    assert!(mesh.has_normals());
    mesh.validate().unwrap();
}

#[test]
fn unreferenced_normals_are_kept_but_no_corner_has_one() {
    let mesh = Mesh::from_obj_str(&format!("{TRI}vn 0 0 1\nf 1 2 3\n")).unwrap();
    assert_eq!(mesh.normals, vec![[0.0, 0.0, 1.0]]);
    assert_eq!(mesh.face_normals, vec![NO_NORMAL; 3]);
    assert!(!mesh.has_normals());
    assert_eq!(mesh.corner_normal(0), None);
    let raw = Mesh::from_raw(mesh.positions.clone(), &[vec![0, 1, 2]]).unwrap();
    assert!(raw.normals.is_empty());
    assert_eq!(raw.face_normals, vec![NO_NORMAL; 3]);
    let mut hand = raw.clone();
    hand.face_normals.clear();
    hand.validate().unwrap();
    assert_eq!(hand.corner_normal(1), None);
}

#[test]
fn normal_errors_are_located() {
    assert!(matches!(
        err(&format!("{TRI}vn 0 0 1\nvn nan 0 1\nf 1//1 2//2 3//1\n")),
        MeshError::NonFiniteNormal {
            normal: 1,
            line: Some(5)
        }
    ));
    // Unused normals are checked too; 1e50 overflows f32 to inf.
    assert!(matches!(
        err(&format!("{TRI}vn 0 1e50 1\nf 1 2 3\n")),
        MeshError::NonFiniteNormal {
            normal: 0,
            line: Some(4)
        }
    ));
    assert!(matches!(
        err(&format!("{TRI}vn 0 inf 1\nf 1 2 3\n")),
        MeshError::NonFiniteNormal { normal: 0, .. }
    ));
    assert_eq!(obj_line(err(&format!("{TRI}vn 0 1\nf 1 2 3\n"))), Some(4));
    assert_eq!(
        obj_line(err(&format!("{TRI}vn 0 0 1\nf 1//1 2//2 3//1\n"))),
        Some(5)
    );
    assert_eq!(
        obj_line(err(&format!("{TRI}vn 0 0 1\nf 1//1 2//-2 3//1\n"))),
        Some(5)
    );
}

#[test]
fn validate_checks_hand_built_normals() {
    let mut m = Mesh::from_raw(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[vec![0, 1, 2]],
    )
    .unwrap();
    m.normals = vec![[0.0, 0.0, 1.0]];
    m.face_normals = vec![0, NO_NORMAL, 0];
    m.validate().unwrap();
    m.face_normals = vec![0, 0];
    assert!(matches!(m.validate(), Err(MeshError::Layout { .. })));
    m.face_normals = vec![0, 0, 1];
    assert!(matches!(
        m.validate(),
        Err(MeshError::NormalIndexOutOfRange {
            face: 0,
            corner: 2,
            index: 1
        })
    ));
    m.face_normals = vec![0, 0, 0];
    m.normals = vec![[0.0, f32::NAN, 1.0]];
    assert!(matches!(
        m.validate(),
        Err(MeshError::NonFiniteNormal {
            normal: 0,
            line: None
        })
    ));
}

#[test]
fn crlf_and_mtllib_are_harmless() {
    let text = "mtllib missing.mtl\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nusemtl red\r\nf 1 2 3\r\n";
    let mesh = Mesh::from_obj_str(text).unwrap();
    assert_eq!(mesh.face(0), &[0, 1, 2]);
}
