//! Golden values: the generated CPU kernels reproduce the float64 reference
//! values of `spec/pccm_reference.json` and `spec/schemes_reference.json`
//! (copied to tests/data/spec) within f32 accuracy.

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
            table,
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

fn angle_deg(a: Vec3, b: Vec3) -> f64 {
    (a.normalize().dot(b.normalize()).clamp(-1.0, 1.0) as f64)
        .acos()
        .to_degrees()
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
