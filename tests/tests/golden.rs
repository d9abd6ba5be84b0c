//! Golden values: the generated CPU kernels reproduce the float64 reference
//! values of `spec/pccm_reference.json` and `spec/schemes_reference.json`
//! (copied to tests/data/spec), and `spec/g1cc_reference.json`
//! (docs/verify/g1cc_quartic_verify.py --golden), within f32 accuracy.

mod common;

use glam::Vec3;
use serde_json::Value;
use tessgen_runtime::kernels::{self, common::Inputs, common::SchemeKernels};

fn v3(v: &Value) -> Vec3 {
    let a: Vec<f32> = v
        .as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("num") as f32)
        .collect();
    Vec3::new(a[0], a[1], a[2])
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("num"))
        .collect()
}

/// regular.md §3: quad-ring index of corner k's ring `[p, p_0 .. p_{2n-1}]`
/// with `p_0 = v_{k+1}`.
fn ring_slots(valences: [u32; 4]) -> [Vec<u32>; 4] {
    let mut start = [0u32; 4];
    start[0] = 4;
    for k in 1..4 {
        start[k] = start[k - 1] + 2 * valences[k - 1] - 5;
    }
    std::array::from_fn(|k| {
        let n = valences[k];
        let prev = (k + 3) % 4;
        let mut r = vec![
            k as u32,
            ((k + 1) % 4) as u32,
            ((k + 2) % 4) as u32,
            ((k + 3) % 4) as u32,
        ];
        r.push(start[prev] + 2 * valences[prev] - 6);
        for i in 0..(2 * n - 5) {
            r.push(start[k] + i);
        }
        r.push(if k == 3 { 4 } else { start[k + 1] });
        r
    })
}

/// Runs the generated kernels on one quad given by its 1-ring.
struct Quad {
    positions: Vec<Vec3>,
    valence: Vec<u32>,
    ring_offsets: Vec<u32>,
    ring: Vec<u32>,
    out_offsets: Vec<u32>,
    vertex_out: Vec<Vec3>,
    cp: Vec<Vec3>,
    class: u32,
    /// No crease or corner vertices: every sector range empty.
    vertex_sectors: Vec<u32>,
    /// Per-valence constants at each corner's own valence.
    corner_valence: Vec<u32>,
}

impl Quad {
    fn new(scheme: &SchemeKernels, valences: [u32; 4], positions: Vec<Vec3>) -> Quad {
        let slots = ring_slots(valences);
        let m = positions.len();
        let mut valence = vec![0u32; m];
        let mut ring_offsets = vec![0u32; m];
        let mut ring = Vec::new();
        let mut out_offsets = vec![0u32; m];
        let mut total = 0;
        for k in 0..4 {
            valence[k] = valences[k];
            ring_offsets[k] = ring.len() as u32;
            ring.extend_from_slice(&slots[k]);
            out_offsets[k] = total;
            total += scheme.rows_per_n * valences[k] + scheme.rows_fixed;
        }
        let mut q = Quad {
            positions,
            valence,
            ring_offsets,
            ring,
            out_offsets,
            vertex_out: vec![Vec3::ZERO; total as usize],
            cp: Vec::new(),
            class: 0,
            vertex_sectors: vec![0; m + 1],
            corner_valence: valences.to_vec(),
        };
        let table = kernels::table();
        let corner_vertex = [0u32, 1, 2, 3];
        let corner_sector = [0u32; 4];
        let mut vout = vec![Vec3::ZERO; total as usize];
        {
            let inputs = q.inputs(&[], &corner_vertex, &corner_sector, table);
            for k in 0..4u32 {
                (scheme.vertex_stage)(&inputs, &mut vout, k, q.out_offsets[k as usize]);
            }
        }
        q.vertex_out = vout;
        let ordinary = valences == [4, 4, 4, 4];
        let want = if ordinary {
            "ordinary"
        } else {
            "extraordinary"
        };
        q.class = scheme
            .classes
            .iter()
            .position(|c| c.class == want)
            .expect("class") as u32;
        let ck = &scheme.classes[q.class as usize];
        let mut cp = vec![Vec3::ZERO; ck.control_points as usize];
        {
            let inputs = q.inputs(&q.vertex_out, &corner_vertex, &corner_sector, table);
            (ck.patch)(&inputs, &mut cp, 0, 0);
        }
        q.cp = cp;
        q
    }

    fn inputs<'a>(
        &'a self,
        vout: &'a [Vec3],
        cv: &'a [u32],
        cs: &'a [u32],
        table: &'a [f32],
    ) -> Inputs<'a> {
        Inputs {
            positions: &self.positions,
            valence: &self.valence,
            ring_offsets: &self.ring_offsets,
            ring: &self.ring,
            vertex_out_offsets: &self.out_offsets,
            vertex_out: vout,
            corner_vertex: cv,
            corner_sector: cs,
            vertex_sectors: &self.vertex_sectors,
            corner_valence: &self.corner_valence,
            normals: &[],
            tags: &[],
            crease: &[],
            corner_side: &[],
            face_edges: &[],
            edge_factors: &[],
            adaptive: &[],
            table,
            ..Default::default()
        }
    }
}

/// Worst relative position error and normal angle (degrees) seen.
#[derive(Default, Debug)]
struct Worst {
    pos: f64,
    cp: f64,
    angle: f64,
}

fn rel(a: Vec3, b: Vec3, scale: f32) -> f64 {
    ((a - b).length() / scale.max(1.0)) as f64
}

/// Angle in degrees, in f64 via atan2 (acos of an f32 dot product cannot
/// resolve angles below ~0.02°).
fn angle_deg(a: Vec3, b: Vec3) -> f64 {
    let (a, b) = (a.as_dvec3(), b.as_dvec3());
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// (u, v) in the golden files are multiples of 1/20.
const LEVEL: u32 = 20;

fn grid(uv: &Value) -> (u32, u32) {
    let a = f64s(uv);
    let iu = (a[0] * LEVEL as f64).round() as u32;
    let iv = (a[1] * LEVEL as f64).round() as u32;
    assert!(
        ((iu as f64 / LEVEL as f64) - a[0]).abs() < 1e-12,
        "uv {a:?} not on the 1/20 grid"
    );
    (iu, iv)
}

fn scale_of(positions: &[Vec3]) -> f32 {
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for p in positions {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (hi - lo).length()
}

#[test]
fn ring_slot_formula_matches_the_golden_file() {
    let g = common::json("spec/pccm_reference.json");
    for case in g["cases"].as_array().expect("cases") {
        let val: Vec<u32> = f64s(&case["valences"]).iter().map(|x| *x as u32).collect();
        let slots = ring_slots([val[0], val[1], val[2], val[3]]);
        for k in 0..4 {
            let want: Vec<u32> = f64s(&case["corners"][k]["ring_slots"])
                .iter()
                .map(|x| *x as u32)
                .collect();
            assert_eq!(slots[k], want, "{} corner {k}", case["name"]);
        }
    }
}

#[test]
fn pccm_matches_pccm_reference() {
    let g = common::json("spec/pccm_reference.json");
    let scheme = kernels::scheme("pccm").expect("pccm");
    let mut worst = Worst::default();
    for case in g["cases"].as_array().expect("cases") {
        let val: Vec<u32> = f64s(&case["valences"]).iter().map(|x| *x as u32).collect();
        let val = [val[0], val[1], val[2], val[3]];
        let pos: Vec<Vec3> = case["quad_ring_positions"]
            .as_array()
            .expect("ring")
            .iter()
            .map(v3)
            .collect();
        let scale = scale_of(&pos);
        let q = Quad::new(scheme, val, pos);
        let name = case["name"].as_str().unwrap_or("?");
        if case["patch_type"] == "bicubic" {
            let gk = case["bicubic_g"].as_array().expect("g");
            for (k, row) in gk.iter().enumerate() {
                for (l, g) in row.as_array().expect("row").iter().enumerate() {
                    let e = rel(q.cp[4 * k + l], v3(g), scale);
                    worst.cp = worst.cp.max(e);
                    assert!(e < 1e-5, "{name}: G[{k}][{l}] off by {e}");
                }
            }
        } else {
            for (i, c) in case["coeffs24"]
                .as_array()
                .expect("coeffs")
                .iter()
                .enumerate()
            {
                let e = rel(q.cp[i], v3(c), scale);
                worst.cp = worst.cp.max(e);
                assert!(e < 1e-5, "{name}: {} off by {e}", case["coeffs24_names"][i]);
            }
        }
        for s in case["samples"].as_array().expect("samples") {
            let (iu, iv) = grid(&s["uv"]);
            let out = (scheme.eval)(&q.cp, q.class, 0, iu, iv, LEVEL);
            let e = rel(out.position, v3(&s["position"]), scale);
            let a = angle_deg(out.normal, v3(&s["normal"]));
            worst.pos = worst.pos.max(e);
            worst.angle = worst.angle.max(a);
            assert!(e < 1e-5, "{name} at {}: position off by {e}", s["uv"]);
            assert!(a < 1e-3, "{name} at {}: normal off by {a}°", s["uv"]);
        }
    }
    println!("pccm golden: worst {worst:?}");
}

#[test]
fn regular_matches_schemes_reference() {
    let g = common::json("spec/schemes_reference.json");
    let case = &g["quad_cases"][0];
    assert_eq!(f64s(&case["valences"]), vec![4.0; 4]);
    let pos: Vec<Vec3> = case["ring_positions"]
        .as_array()
        .expect("ring")
        .iter()
        .map(v3)
        .collect();
    let scale = scale_of(&pos);
    for name in ["regular", "pccm"] {
        let scheme = kernels::scheme(name).expect("scheme");
        let q = Quad::new(scheme, [4; 4], pos.clone());
        for (i, b) in case["regular"]["bezier_16"]
            .as_array()
            .expect("bezier")
            .iter()
            .enumerate()
        {
            let e = rel(q.cp[i], v3(b), scale);
            assert!(e < 1e-5, "{name}: b[{}][{}] off by {e}", i / 4, i % 4);
        }
        for s in case["regular"]["eval"].as_array().expect("eval") {
            let (iu, iv) = grid(&s["uv"]);
            let out = (scheme.eval)(&q.cp, q.class, 0, iu, iv, LEVEL);
            let e = rel(out.position, v3(&s["position"]), scale);
            let a = angle_deg(out.normal, v3(&s["normal"]));
            assert!(e < 1e-5, "{name} at {}: position off by {e}", s["uv"]);
            assert!(a < 1e-3, "{name} at {}: normal off by {a}°", s["uv"]);
        }
    }
}

#[test]
fn vertex_stage_rows_match_reference_stencils() {
    let g = common::json("spec/pccm_reference.json");
    let out = tessgen_codegen::Builder::new()
        .builtin_schemes()
        .compile()
        .expect("compile");
    let table = &out.table;
    let pccm = table
        .schemes
        .iter()
        .find(|s| s.scheme == "pccm")
        .expect("pccm rows");
    for (n, rows) in g["vertex_stage_stencils"]["valences"]
        .as_object()
        .expect("valences")
    {
        let n: u32 = n.parse().expect("valence");
        for (key, output) in [("f0", "f"), ("e0", "e"), ("v", "v"), ("t0", "t")] {
            let info = table
                .rows
                .iter()
                .find(|r| {
                    r.scheme == "pccm"
                        && r.valence == n
                        && r.output == output
                        && r.sector.unwrap_or(0) == 0
                })
                .expect("row");
            assert!(info.row >= pccm.valence_row_base[n as usize]);
            let want = f64s(&rows[key]);
            assert_eq!(want.len() as u32, 2 * n + 1);
            for (c, w) in want.iter().enumerate() {
                let got = table.weight(info.row, c as u32);
                assert_eq!(got, *w as f32, "valence {n} {key} slot {c}");
            }
        }
    }
}

fn ring_of(case: &Value) -> ([u32; 4], Vec<Vec3>) {
    let n = f64s(&case["valences"]);
    let valences = [n[0] as u32, n[1] as u32, n[2] as u32, n[3] as u32];
    let pos = case["ring_positions"]
        .as_array()
        .expect("ring")
        .iter()
        .map(v3)
        .collect();
    (valences, pos)
}

/// Positions and normals of `scheme` at the golden (u, v) samples of `key`.
fn check_eval(name: &str, case: &Value, key: &str, worst: &mut Worst) {
    let scheme = kernels::scheme(name).expect("scheme");
    let (valences, pos) = ring_of(case);
    let scale = scale_of(&pos);
    let q = Quad::new(scheme, valences, pos);
    for s in case[key]["eval"].as_array().expect("eval") {
        let (iu, iv) = grid(&s["uv"]);
        let out = (scheme.eval)(&q.cp, q.class, 0, iu, iv, LEVEL);
        let e = rel(out.position, v3(&s["position"]), scale);
        let a = angle_deg(out.normal, v3(&s["normal"]));
        assert!(
            e < 1e-5,
            "{name} {valences:?} at {}: position off by {e}",
            s["uv"]
        );
        assert!(
            a < 1e-3,
            "{name} {valences:?} at {}: normal off by {a}°",
            s["uv"]
        );
        assert!(out.position.is_finite() && out.normal.is_finite());
        worst.pos = worst.pos.max(e);
        worst.angle = worst.angle.max(a);
    }
}

/// ACC (acc.md §7.5): geometry points, both tangent patches (through the
/// corner-frame storage map of the `acc` form) and evaluation, on all four
/// golden quads (valences 4444, 5444, 3546, 8374).
#[test]
fn acc_matches_schemes_reference() {
    use tessgen_codegen::plan::form::Form;
    let g = common::json("spec/schemes_reference.json");
    let scheme = kernels::scheme("acc").expect("acc");
    let mut worst = Worst::default();
    for case in g["quad_cases"].as_array().expect("cases") {
        let (valences, pos) = ring_of(case);
        let scale = scale_of(&pos);
        let q = Quad::new(scheme, valences, pos);
        let acc = &case["acc"];
        for (i, b) in acc["geometry_bezier_16"]
            .as_array()
            .expect("geometry")
            .iter()
            .enumerate()
        {
            let e = rel(q.cp[i], v3(b), scale);
            assert!(e < 1e-5, "{valences:?}: b[{}][{}] off by {e}", i / 4, i % 4);
            worst.cp = worst.cp.max(e);
        }
        if valences != [4; 4] {
            let u = acc["tangent_u_3x4"].as_array().expect("U");
            let v = acc["tangent_v_4x3"].as_array().expect("V");
            for corner in 0..4 {
                for slot in 4..10 {
                    let t = Form::acc_tangent_slot(corner, slot);
                    let want = if t.in_v {
                        v3(&v[3 * t.a + t.b])
                    } else {
                        v3(&u[4 * t.a + t.b])
                    };
                    let want = if t.negate { -want } else { want };
                    let got = q.cp[Form::Acc.storage_index(corner, slot)];
                    let e = rel(got, want, scale);
                    assert!(
                        e < 1e-5,
                        "{valences:?}: corner {corner} slot {} ({t:?}) off by {e}",
                        Form::Acc.slots()[slot]
                    );
                    worst.cp = worst.cp.max(e);
                }
            }
        }
        check_eval("acc", case, "acc", &mut worst);
    }
    println!("acc golden: worst {worst:?}");
}

/// Gregory, both variants (gregory.md §6): the 20 control points on the
/// extraordinary golden quads, and position and (exact-derivative) normal
/// at the golden samples on all four, the corner samples included (the
/// guarded blend must stay finite).
#[test]
fn gregory_matches_schemes_reference() {
    let g = common::json("spec/schemes_reference.json");
    for (name, key) in [("gregory", "gregory_paper"), ("gregory_osd", "gregory_osd")] {
        let scheme = kernels::scheme(name).expect("scheme");
        let mut worst = Worst::default();
        for case in g["quad_cases"].as_array().expect("cases") {
            let (valences, pos) = ring_of(case);
            let scale = scale_of(&pos);
            let q = Quad::new(scheme, valences, pos);
            if valences != [4; 4] {
                for (i, b) in case[key]["control_20"]
                    .as_array()
                    .expect("control_20")
                    .iter()
                    .enumerate()
                {
                    let e = rel(q.cp[i], v3(b), scale);
                    assert!(
                        e < 1e-5,
                        "{name} {valences:?}: point {i} (corner {}, {}) off by {e}",
                        i / 5,
                        ["P", "E+", "E-", "F+", "F-"][i % 5]
                    );
                    worst.cp = worst.cp.max(e);
                }
            }
            check_eval(name, case, key, &mut worst);
        }
        println!("{name} golden: worst {worst:?}");
    }
}

/// One golden triangle's inputs: corners 0, 1, 2 with positions, normals
/// and (for `st_pn`) the scalar tags and side signs; neutral tags otherwise.
struct TriCase {
    p: Vec<Vec3>,
    n: Vec<Vec3>,
    tags: Vec<f32>,
    crease: Vec<Vec3>,
    side: Vec<f32>,
}

impl TriCase {
    fn load(case: &serde_json::Value) -> TriCase {
        let p: Vec<Vec3> = case["P"].as_array().expect("P").iter().map(v3).collect();
        let n: Vec<Vec3> = case["N"].as_array().expect("N").iter().map(v3).collect();
        let mut tags = vec![0.0; 12];
        let mut crease = vec![Vec3::ZERO; 3];
        let mut side = vec![1.0; 3];
        if let Some(ts) = case["tags"].as_array() {
            for (i, t) in ts.iter().enumerate() {
                let delta = v3(&t["Delta"]);
                let creased = if delta != Vec3::ZERO { 1.0 } else { 0.0 };
                tags[4 * i..4 * i + 4].copy_from_slice(&[
                    t["theta"].as_f64().expect("theta") as f32,
                    t["sigma"].as_f64().expect("sigma") as f32,
                    t["beta"].as_f64().expect("beta") as f32,
                    creased,
                ]);
                crease[i] = delta;
            }
            side = f64s(&case["side"]).iter().map(|&x| x as f32).collect();
        }
        TriCase {
            p,
            n,
            tags,
            crease,
            side,
        }
    }

    /// Runs a triangle scheme's patch stage on this triangle.
    fn control_points(&self, scheme: &SchemeKernels) -> Vec<Vec3> {
        let class = &scheme.classes[0];
        let mut cp = vec![Vec3::ZERO; class.control_points as usize];
        let inputs = Inputs {
            positions: &self.p,
            valence: &[],
            ring_offsets: &[],
            ring: &[],
            vertex_out_offsets: &[],
            vertex_out: &[],
            corner_vertex: &[0, 1, 2],
            corner_sector: &[],
            normals: &self.n,
            tags: &self.tags,
            crease: &self.crease,
            corner_side: &self.side,
            face_edges: &[],
            edge_factors: &[],
            adaptive: &[],
            table: kernels::table(),
            ..Default::default()
        };
        (class.patch)(&inputs, &mut cp, 0, 0);
        cp
    }
}

/// One triangle through a triangle scheme's patch stage and evaluator, at
/// the golden barycentric samples (multiples of 1/60).
fn check_triangle(name: &str, key: &str) -> Worst {
    const TRI_LEVEL: u32 = 60;
    let g = common::json("spec/schemes_reference.json");
    let case = &g[key];
    let scheme = kernels::scheme(name).expect("scheme");
    assert_eq!(scheme.sides, 3);
    let tc = TriCase::load(case);
    let scale = scale_of(&tc.p);
    let cp = tc.control_points(scheme);
    let mut worst = Worst::default();
    for s in case["eval"].as_array().expect("eval") {
        let w = f64s(&s["bary"]);
        let iu = (w[1] * TRI_LEVEL as f64).round() as u32;
        let iv = (w[2] * TRI_LEVEL as f64).round() as u32;
        assert!((w[1] * TRI_LEVEL as f64 - iu as f64).abs() < 1e-9);
        assert!((w[2] * TRI_LEVEL as f64 - iv as f64).abs() < 1e-9);
        let out = (scheme.eval)(&cp, 0, 0, iu, iv, TRI_LEVEL);
        let e = rel(out.position, v3(&s["position"]), scale);
        let a = angle_deg(out.normal, v3(&s["normal"]));
        assert!(e < 1e-5, "{name} at {w:?}: position off by {e}");
        assert!(a < 1e-3, "{name} at {w:?}: normal off by {a}°");
        worst.pos = worst.pos.max(e);
        worst.angle = worst.angle.max(a);
    }
    worst
}

/// The cubic-triangle control points as the reference names them:
/// `b_ijk` exponents of (w1, w2, w3) = corners (0, 1, 2).
fn tri_control_names() -> [(&'static str, usize); 10] {
    use tessgen_codegen::plan::form::Form;
    let f = Form::TriCubic;
    [
        ("b300", f.storage_index(0, 0)),
        ("b030", f.storage_index(1, 0)),
        ("b003", f.storage_index(2, 0)),
        ("b210", f.storage_index(0, 1)),
        ("b201", f.storage_index(0, 2)),
        ("b021", f.storage_index(1, 1)),
        ("b120", f.storage_index(1, 2)),
        ("b102", f.storage_index(2, 1)),
        ("b012", f.storage_index(2, 2)),
        ("b111", f.single_index(0)),
    ]
}

/// PN triangles (pn.md §5): the 10 geometry and 6 normal control points,
/// and positions/normals at the golden barycentric samples.
#[test]
fn pn_matches_schemes_reference() {
    use tessgen_codegen::plan::form::Form;
    let g = common::json("spec/schemes_reference.json");
    let pn = &g["pn"];
    let scheme = kernels::scheme("pn").expect("pn");
    let tc = TriCase::load(pn);
    let scale = scale_of(&tc.p);
    let cp = tc.control_points(scheme);
    let f = Form::TriCubic;
    for (key, idx) in tri_control_names() {
        let e = rel(cp[idx], v3(&pn["control"][key]), scale);
        assert!(e < 1e-5, "pn {key} off by {e}");
    }
    let normals = [
        ("n200", f.storage_index(0, 3)),
        ("n020", f.storage_index(1, 3)),
        ("n002", f.storage_index(2, 3)),
        ("n110", f.storage_index(0, 4)),
        ("n011", f.storage_index(1, 4)),
        ("n101", f.storage_index(2, 4)),
    ];
    for (key, idx) in normals {
        let e = rel(cp[idx], v3(&pn["normal_control"][key]), 1.0);
        assert!(e < 1e-5, "pn {key} off by {e}");
    }
    let w = check_triangle("pn", "pn");
    println!("pn golden: worst {w:?}");
}

/// Scalar-tagged PN (pn.md §3): a tension, two sharpness values, a bias
/// and crease vectors on two corners (their shared edge is a crease edge,
/// δ = 1). Checks the ten control points, the side normals N' (the normal
/// field's corner coefficients) and positions/normals at the samples.
#[test]
fn stpn_matches_schemes_reference() {
    use tessgen_codegen::plan::form::Form;
    let g = common::json("spec/schemes_reference.json");
    let st = &g["st_pn"];
    let scheme = kernels::scheme("stpn").expect("stpn");
    let tc = TriCase::load(st);
    let scale = scale_of(&tc.p);
    let cp = tc.control_points(scheme);
    let mut worst = 0.0f64;
    for (key, idx) in tri_control_names() {
        let e = rel(cp[idx], v3(&st["control"][key]), scale);
        assert!(e < 1e-5, "stpn {key} off by {e}");
        worst = worst.max(e);
    }
    let f = Form::TriCubic;
    for (i, want) in st["sharp_normals"]
        .as_array()
        .expect("sharp")
        .iter()
        .enumerate()
    {
        let a = angle_deg(cp[f.storage_index(i, 3)], v3(want));
        assert!(a < 1e-3, "stpn sharp normal {i} off by {a}°");
    }
    let w = check_triangle("stpn", "st_pn");
    println!("stpn golden: control points worst {worst:.2e}, eval {w:?}");
}

/// With neutral tags scalar-tagged PN is plain PN (pn.md §3): the same
/// control points up to f32 rounding on the pn golden triangle.
#[test]
fn stpn_with_neutral_tags_is_pn() {
    let g = common::json("spec/schemes_reference.json");
    let tc = TriCase::load(&g["pn"]);
    let scale = scale_of(&tc.p);
    let a = tc.control_points(kernels::scheme("pn").expect("pn"));
    let b = tc.control_points(kernels::scheme("stpn").expect("stpn"));
    assert_eq!(a.len(), b.len());
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| rel(*x, *y, scale))
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "stpn (neutral) vs pn: {worst}");
}

/// Phong tessellation with α = 3/4 (pn.md §4), degree-raised to the cubic
/// triangle form: positions and Phong-interpolated normals.
#[test]
fn phong_matches_schemes_reference() {
    let g = common::json("spec/schemes_reference.json");
    assert_eq!(g["phong"]["alpha"].as_f64(), Some(0.75));
    let w = check_triangle("phong", "phong");
    println!("phong golden: worst {w:?}");
}

/// Every sector row (crease and corner sectors of 1..4 faces, every quad
/// scheme) equals the float64 rows of `spec/sectors_reference.json`, which
/// `docs/verify/sectors_verify.py` computes independently from the phantom
/// rule and the overrides of docs/boundaries.md §3 (rounded once to f32):
/// its `schemes` section (the adopted blocks) and, for crease sectors of
/// m ≥ 3, `schemes_exact_crease_tangent` (the prototype of the exact crease
/// tangents, boundary.md §3.2–§3.3, which the blocks adopt there).
#[test]
fn sector_rows_match_sectors_reference() {
    let g = common::json("spec/sectors_reference.json");
    let out = tessgen_codegen::Builder::new()
        .builtin_schemes()
        .compile()
        .expect("compile");
    let table = &out.table;
    let mut checked = 0;
    let mut sections: Vec<(&String, serde_json::Value)> = Vec::new();
    for (scheme, kinds) in g["schemes"].as_object().expect("schemes") {
        sections.push((scheme, kinds.clone()));
    }
    let mut exact_checked = 0;
    for (scheme, by_m) in g["schemes_exact_crease_tangent"]
        .as_object()
        .expect("schemes_exact_crease_tangent")
    {
        let crease: serde_json::Map<String, serde_json::Value> = by_m
            .as_object()
            .expect("m")
            .iter()
            .filter(|(m, _)| m.parse::<u32>().expect("m") >= 3)
            .map(|(m, b)| (m.clone(), b.clone()))
            .collect();
        exact_checked += crease.len();
        sections.push((
            scheme,
            serde_json::json!({ "crease": crease, "corner": {} }),
        ));
    }
    assert!(
        exact_checked >= 10,
        "exact crease rows: {exact_checked} blocks"
    );
    for (scheme, kinds) in &sections {
        let scheme = *scheme;
        let rows = table
            .schemes
            .iter()
            .find(|s| &s.scheme == scheme)
            .expect("scheme rows");
        for (ki, kind) in ["crease", "corner"].iter().enumerate() {
            for (m, block) in kinds[*kind].as_object().expect("kind") {
                let m: u32 = m.parse().expect("m");
                let base =
                    rows.sector_row_base[ki * table.max_sector_faces as usize + m as usize - 1];
                let mut r = base;
                for o in block["outputs"].as_array().expect("outputs") {
                    for want in o["rows"].as_array().expect("rows") {
                        let info = &table.sector_rows[r as usize];
                        assert_eq!(info.output, o["name"].as_str().unwrap_or(""));
                        assert_eq!(info.kind, Some(*kind));
                        assert_eq!(info.faces, Some(m));
                        let want = f64s(want);
                        assert_eq!(want.len() as u32, 2 * m + 2);
                        for (c, w) in want.iter().enumerate() {
                            let got = table.sector_weight(r, c as u32);
                            assert!(
                                (got as f64 - w).abs() <= 1e-7 * (1.0 + w.abs()),
                                "{scheme} {kind} m={m} {} row {r} slot {c}: {got} vs {w}",
                                info.output
                            );
                            checked += 1;
                        }
                        r += 1;
                    }
                }
                // The block holds exactly the rows the reference lists.
                let next = table.sector_rows.get(r as usize);
                assert!(
                    next.is_none_or(|n| n.faces != Some(m) || n.kind != Some(*kind)),
                    "{scheme} {kind} m={m}: more rows than the reference"
                );
            }
        }
    }
    assert!(checked > 1000, "only {checked} weights checked");
}

/// Storage index in the `gregory4` form of a point of g1cc's golden net,
/// keyed as the verification script writes it: `(a, b)` (a along u) or
/// `('h' | 'v', (a, b))`, the twist point serving the horizontal or the
/// vertical edge at that grid position. Worked out here from the form's
/// definition (plan/form.rs), independently of the lowering's own map: per
/// corner i `7i + {p, ep, em, m, fp, fm, g}`, the centre at 28.
fn g1cc_storage(key: &str) -> usize {
    let d: Vec<usize> = key
        .chars()
        .filter_map(|c| c.to_digit(10))
        .map(|x| x as usize)
        .collect();
    let (a, b) = (d[0], d[1]);
    // Point k of edge i at `depth` rows inside: edge 0 along v = 0, 1
    // along u = 1, 2 along v = 1 backwards, 3 along u = 0 backwards.
    let at = |i: usize, k: usize, depth: usize| match i % 4 {
        0 => (k, depth),
        1 => (4 - depth, k),
        2 => (4 - k, 4 - depth),
        _ => (depth, 4 - k),
    };
    if key.contains('h') || key.contains('v') {
        let corner = (0..4)
            .find(|&i| at(i, 1, 1) == (a, b))
            .expect("twist position");
        // Corner i's fp serves edge i (horizontal for even i), fm edge i − 1.
        let horizontal = key.contains('h');
        let fp = (corner % 2 == 0) == horizontal;
        return 7 * corner + if fp { 4 } else { 5 };
    }
    if (a, b) == (2, 2) {
        return 28;
    }
    for i in 0..4 {
        for (slot, (edge, k, depth)) in [
            (0, (i, 0, 0)),
            (1, (i, 1, 0)),
            (2, ((i + 3) % 4, 3, 0)),
            (3, (i, 2, 0)),
            (6, (i, 2, 1)),
        ] {
            if at(edge, k, depth) == (a, b) {
                return 7 * i + slot;
            }
        }
    }
    panic!("no g1cc slot at {key}")
}

/// g1cc (docs/g1cc.md round 6): on one face per extraordinary valence of
/// the closed shared meshes (3 on catmark_cube, 5 on catmark_righthanded, 6
/// on catmark_toroidal_tet), the 29 control points through the whole CPU
/// pipeline (vertex stage, patch stage), and position and exact-derivative
/// normal at six (u, v) samples, corners and edges included, against the
/// float64 values of the verification script.
#[test]
fn g1cc_matches_g1cc_reference() {
    use tessgen_runtime::{cpu, Topology};
    let g = common::json("spec/g1cc_reference.json");
    let scheme = kernels::scheme("g1cc").expect("scheme");
    let keys: Vec<&str> = g["keys"]
        .as_array()
        .expect("keys")
        .iter()
        .map(|k| k.as_str().expect("key"))
        .collect();
    assert_eq!(keys.len(), 29);
    let mut slots: Vec<usize> = keys.iter().map(|k| g1cc_storage(k)).collect();
    slots.sort_unstable();
    assert_eq!(
        slots,
        (0..29).collect::<Vec<_>>(),
        "the key map is a permutation"
    );
    let mut worst = Worst::default();
    let cases = g["cases"].as_array().expect("cases");
    assert_eq!(cases.len(), 3);
    for case in cases {
        let name = case["mesh"].as_str().expect("mesh");
        let face = case["face"].as_u64().expect("face") as usize;
        let mesh = common::mesh(name);
        let scale = common::bbox_diagonal(&mesh);
        let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
        let positions: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|p| Vec3::from_array(*p))
            .collect();
        let patches = cpu::construct(&topo, &positions, scheme).expect("construct");
        let base = patches.cp_offsets[face] as usize;
        let class = patches.face_class[face];
        let cp = &patches.control_points[base..base + 29];
        for (k, want) in case["control_points"]
            .as_array()
            .expect("control points")
            .iter()
            .enumerate()
        {
            let e = rel(cp[g1cc_storage(keys[k])], v3(want), scale);
            assert!(e < 1e-5, "{name} face {face}: point {} off by {e}", keys[k]);
            worst.cp = worst.cp.max(e);
        }
        for s in case["eval"].as_array().expect("eval") {
            let uv = Value::Array(vec![s["u"].clone(), s["v"].clone()]);
            let (iu, iv) = grid(&uv);
            let out = (scheme.eval)(&patches.control_points, class, base as u32, iu, iv, LEVEL);
            let e = rel(out.position, v3(&s["position"]), scale);
            let a = angle_deg(out.normal, v3(&s["normal"]));
            assert!(e < 1e-5, "{name} face {face} at {uv}: position off by {e}");
            assert!(a < 1e-3, "{name} face {face} at {uv}: normal off by {a}°");
            worst.pos = worst.pos.max(e);
            worst.angle = worst.angle.max(a);
        }
    }
    println!("g1cc golden: worst {worst:?}");
}
