//! `tessgen compare`'s measurements: distance and normal deviation from the
//! exact Catmull-Clark limit, boundary smoothness, watertightness.

mod common;

use tessgen_runtime::accuracy::{compare, LimitError, LimitSamples};

#[test]
fn torus_schemes_are_the_limit_and_cube_is_close() {
    let torus = common::mesh("catmark_torus");
    let lim = LimitSamples::load(common::data("cc_limit/catmark_torus.bin")).expect("limit");
    for scheme in ["regular", "pccm"] {
        let a = compare(&torus, scheme, 8, Some(&lim)).expect("compare");
        let d = a.max_distance_pct.unwrap_or(f64::MAX);
        assert!(
            d < 1e-4,
            "{scheme}: {d} % of the quad size on the regular torus"
        );
        assert_eq!(a.open_edges, 0);
    }
    let cube = common::mesh("catmark_cube");
    let lim = LimitSamples::load(common::data("cc_limit/catmark_cube.bin")).expect("limit");
    let a = compare(&cube, "pccm", 8, Some(&lim)).expect("compare");
    let d = a.max_distance_pct.unwrap_or(f64::MAX);
    // c-patches approximate CC near valence-3 vertices: a few percent, not zero.
    assert!(d > 0.1 && d < 10.0, "cube distance {d} %");
    assert!(a.max_boundary_normal_spread_deg < 0.01);
    assert_eq!(a.open_edges, 0);
    // Without a reference only smoothness and watertightness are measured.
    let a = compare(&cube, "pccm", 4, None).expect("compare");
    assert!(a.max_distance_pct.is_none());
}

#[test]
fn bad_limit_files_are_typed_errors() {
    let dir = std::env::temp_dir().join(format!("tessgen-accuracy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let bad = dir.join("bad.bin");
    std::fs::write(&bad, b"NOTCCLIM and some more bytes to be long enough....").expect("write");
    assert!(matches!(
        LimitSamples::load(&bad),
        Err(LimitError::Format { .. })
    ));
    let mut short = std::fs::read(common::data("cc_limit/catmark_cube.bin")).expect("read");
    short.truncate(100);
    std::fs::write(&bad, &short).expect("write");
    assert!(matches!(
        LimitSamples::load(&bad),
        Err(LimitError::Format { .. })
    ));
    assert!(matches!(
        LimitSamples::load(dir.join("missing.bin")),
        Err(LimitError::Io { .. })
    ));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn zz_diag() {
    use tessgen_runtime::accuracy::boundary_geometric_normals;
    use tessgen_runtime::{cpu, Topology};
    for m in common::CLOSED_MESHES {
        let mesh = common::mesh(m);
        let topo = Topology::build(&mesh, &cpu::topology_options()).unwrap();
        let pos: Vec<glam::Vec3> = mesh.positions.iter().map(|p| glam::Vec3::from_array(*p)).collect();
        for sch in ["pccm", "acc", "gregory", "gregory_osd"] {
            let patches = cpu::construct(&topo, &pos, cpu::scheme(sch).unwrap()).unwrap();
            for lv in [8u32, 16, 32, 64] {
                let t = cpu::evaluate(&patches, lv).unwrap();
                let per = t.grid_len() as u32;
                let b = boundary_geometric_normals(&topo, &t);
                let (mut jm, mut jloc, mut dev, mut devloc) = (0.0f64, 0.0, 0.0f64, 0.0);
                let mut jmid = 0.0f64;
                for x in &b {
                    let s = x.sample[0];
                    let (i, j) = (s % (lv + 1), s / (lv + 1));
                    let tpar = if j == 0 || j == lv { i } else { j } as f64 / lv as f64;
                    let a = x.normal[0].angle_between(x.normal[1]).to_degrees();
                    if a > jm { jm = a; jloc = tpar; }
                    if (0.2..=0.8).contains(&tpar) { jmid = jmid.max(a); }
                    for k in 0..2 {
                        let sn = t.normals[(x.face[k] * per + x.sample[k]) as usize].as_dvec3();
                        let d = sn.angle_between(x.normal[k]).to_degrees();
                        if d > dev { dev = d; devloc = tpar; }
                    }
                }
                println!("{m:22} {sch:12} L{lv:3} jump {jm:9.4} at t={jloc:.3}  jump(t in .2-.8) {jmid:9.4}  max|geo-shading| {dev:9.4} at t={devloc:.3}");
            }
        }
    }
}
