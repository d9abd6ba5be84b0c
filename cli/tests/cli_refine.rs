//! End-to-end tests of the refinement path: `tessellate` on meshes with
//! triangles, n-gons and semi-sharp creases, and `tessgen refine`.

mod common;
use common::*;

/// Triangles and n-gons tessellate through one Catmull-Clark step (weld
/// closed but for the true boundary, sub-face groups in the OBJ); an odd
/// level is a usage error of the input (exit 1) that says why, and nothing
/// is written; semi-sharp creases say how many steps were applied.
#[test]
fn tessellate_polygons_and_semi_sharp_creases() {
    let tmp = TempDir::new("polygons");
    let out = tmp.path().join("nq.obj");
    let args = |m: &str, level: &str, extra: &[&str]| {
        let mut a: Vec<std::ffi::OsString> = vec![
            "tessellate".into(),
            mesh(m).into(),
            "--scheme".into(),
            "gregory".into(),
            "--level".into(),
            level.into(),
            "--out".into(),
            out.clone().into(),
            "--check-watertight".into(),
        ];
        a.extend(extra.iter().map(|s| s.into()));
        a
    };
    let o = tessgen(args("catmark_nonquads.obj", "4", &[]));
    assert_ok(&o);
    assert!(
        stdout(&o).contains("all on the mesh boundary"),
        "{}",
        all(&o)
    );
    assert!(stderr(&o).contains("non-quad faces"), "{}", all(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("\ng patch_1_4\n"), "pentagon's last sub-face");
    std::fs::remove_file(&out).unwrap();

    let o = tessgen(args("catmark_nonquads.obj", "5", &[]));
    assert_exit(&o, 1);
    assert!(
        stderr(&o).contains("level must be even (got 5; try 4 or 6)"),
        "{}",
        all(&o)
    );
    assert!(!out.exists());

    let o = tessgen(args("catmark_single_crease.obj", "4", &[]));
    assert_ok(&o);
    assert!(
        stderr(&o).contains("applied exactly by 6 Catmull-Clark steps (feature-adaptive"),
        "{}",
        all(&o)
    );
    let o = tessgen(args(
        "catmark_single_crease.obj",
        "4",
        &["--crease-refinement", "2"],
    ));
    assert_ok(&o);
    assert!(
        stderr(&o).contains("need 6 Catmull-Clark steps; 2 applied (the crease refinement cap"),
        "{}",
        all(&o)
    );
    let o = tessgen(args(
        "catmark_single_crease.obj",
        "4",
        &["--crease-refinement", "0"],
    ));
    assert_ok(&o);
    assert!(
        stderr(&o).contains("approximated as infinitely sharp"),
        "{}",
        all(&o)
    );
}

/// `tessgen refine` writes a refined mesh that tessellates as is, and a
/// stencil table that reproduces its positions from the base mesh bit for
/// bit in the documented order.
#[test]
fn refine_writes_mesh_and_stencils() {
    let tmp = TempDir::new("refine");
    let o = tessgen([
        "refine".as_ref(),
        mesh("catmark_nonquads.obj").as_os_str(),
        "--out".as_ref(),
        tmp.path().as_os_str(),
    ]);
    assert_ok(&o);
    let base = tessgen_runtime::Mesh::from_obj_path(mesh("catmark_nonquads.obj")).unwrap();
    let refined = tessgen_runtime::Mesh::from_obj_path(tmp.path().join("refined.obj")).unwrap();
    let bin = std::fs::read(tmp.path().join("stencils.bin")).unwrap();
    assert_eq!(&bin[..8], b"TGSTEN01");
    let word = |k: usize| u32::from_le_bytes(bin[8 + 4 * k..12 + 4 * k].try_into().unwrap());
    let (rows, terms, nv) = (word(0) as usize, word(1) as usize, word(2) as usize);
    assert_eq!((rows, nv), (refined.num_vertices(), base.num_vertices()));
    let at = |k: usize| word(4 + k);
    for r in 0..rows {
        let mut acc = [0.0f32; 3];
        for k in at(r) as usize..at(r + 1) as usize {
            let i = at(rows + 1 + k) as usize;
            let w = f32::from_bits(at(rows + 1 + terms + k));
            let p = base.positions[i];
            acc = [acc[0] + p[0] * w, acc[1] + p[1] * w, acc[2] + p[2] * w];
        }
        assert_eq!(acc, refined.positions[r], "row {r}");
    }
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.path().join("refinement.json")).unwrap())
            .unwrap();
    assert_eq!(j["levels"], 1);
    assert_eq!(
        j["leaf_list"].as_array().unwrap().len(),
        refined.num_faces()
    );
}
