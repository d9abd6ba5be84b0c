//! How close a scheme comes to the Catmull-Clark limit surface, and how
//! smooth and watertight its tessellation is — the numbers behind
//! `tessgen compare` and `docs/accuracy.md`.
//!
//! Ground truth is the exact Catmull-Clark limit sampled on a regular grid
//! in every base face (format: `tests/data/cc_limit/UPSTREAM_README.md`).
//! Distances are in % of the local quad size (the mean edge length of the
//! base face), as in the PCCM paper's Figure 11.

use crate::cpu::{self, TessError, Tessellation};
use crate::mesh::Mesh;
use crate::topology::Topology;
use crate::weld;
use glam::{DVec3, Vec3};
use std::path::Path;

/// Errors reading limit samples.
#[derive(Debug, thiserror::Error)]
pub enum LimitError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}: not a CCLIM001 file ({reason})")]
    Format { path: String, reason: String },
    #[error("{path}: limit samples cover {file} faces, the mesh has {mesh}")]
    FaceCount {
        path: String,
        file: usize,
        mesh: usize,
    },
}

/// Exact limit samples: `samples[(face·n + j)·n + i] = (position, normal)` at
/// `u = i/(n−1)`, `v = j/(n−1)`.
#[derive(Clone, Debug, PartialEq)]
pub struct LimitSamples {
    pub n: usize,
    pub faces: usize,
    pub samples: Vec<[Vec3; 2]>,
}

impl LimitSamples {
    /// Read a `CCLIM001` file.
    pub fn load(path: impl AsRef<Path>) -> Result<LimitSamples, LimitError> {
        let p = path.as_ref().display().to_string();
        let b = std::fs::read(path.as_ref()).map_err(|source| LimitError::Io {
            path: p.clone(),
            source,
        })?;
        let bad = |reason: &str| LimitError::Format {
            path: p.clone(),
            reason: reason.into(),
        };
        if b.len() < 32 || &b[..8] != b"CCLIM001" {
            return Err(bad("missing magic"));
        }
        let word = |k: usize| {
            u32::from_le_bytes([b[8 + 4 * k], b[9 + 4 * k], b[10 + 4 * k], b[11 + 4 * k]]) as usize
        };
        let (faces, n, k) = (word(0), word(1), word(2));
        if k != 6 || n < 2 {
            return Err(bad("expected 6 floats per sample and n ≥ 2"));
        }
        if b.len() != 32 + faces * n * n * k * 4 {
            return Err(bad("size does not match the header"));
        }
        let f: Vec<f32> = b[32..]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        let samples = f
            .chunks_exact(6)
            .map(|c| [Vec3::new(c[0], c[1], c[2]), Vec3::new(c[3], c[4], c[5])])
            .collect();
        Ok(LimitSamples { n, faces, samples })
    }
}

/// One scheme on one mesh.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Accuracy {
    pub scheme: String,
    pub level: u32,
    /// Distance to the limit, % of local quad size (None without reference).
    pub max_distance_pct: Option<f64>,
    pub rms_distance_pct: Option<f64>,
    /// Normal deviation from the limit normal, degrees.
    pub max_normal_deg: Option<f64>,
    pub rms_normal_deg: Option<f64>,
    /// Largest angle between the two patches' normals at shared boundary samples.
    pub max_boundary_normal_spread_deg: f64,
    /// Open edges after exact-bit welding (0 = watertight).
    pub open_edges: usize,
}

fn angle(a: Vec3, b: Vec3) -> f64 {
    let (a, b): (DVec3, DVec3) = (a.as_dvec3(), b.as_dvec3());
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// Grid index of parameter `t` along local edge `k` of a `level` grid.
fn edge_sample(k: u32, t: u32, level: u32) -> u32 {
    let (i, j) = match k {
        0 => (t, 0),
        1 => (level, t),
        2 => (level - t, level),
        _ => (0, level - t),
    };
    j * (level + 1) + i
}

/// Worst normal spread across shared edges of a tessellation.
pub fn boundary_normal_spread(topo: &Topology, t: &Tessellation) -> f64 {
    let per = t.grid_len() as u32;
    let mut worst = 0.0f64;
    for h in 0..topo.twin.len() as u32 {
        let g = topo.twin[h as usize];
        if g == crate::topology::NONE || g < h {
            continue;
        }
        let (fa, fb) = (topo.face[h as usize], topo.face[g as usize]);
        let (ka, kb) = (
            h - topo.face_offsets[fa as usize],
            g - topo.face_offsets[fb as usize],
        );
        for s in 0..=t.level {
            let a = t.normals[(fa * per + edge_sample(ka, s, t.level)) as usize];
            let b = t.normals[(fb * per + edge_sample(kb, t.level - s, t.level)) as usize];
            worst = worst.max(angle(a, b));
        }
    }
    worst
}

/// Compare `scheme` on `mesh` with the limit samples (if given), and
/// measure smoothness and watertightness at `level`.
pub fn compare(
    mesh: &Mesh,
    scheme: &str,
    level: u32,
    limit: Option<&LimitSamples>,
) -> Result<Accuracy, TessError> {
    let topo = Topology::build(mesh, &cpu::topology_options())?;
    let positions: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    let kernels = cpu::scheme(scheme)?;
    let patches = cpu::construct(&topo, &positions, kernels)?;
    let t = cpu::evaluate(&patches, level)?;
    let mut acc = Accuracy {
        scheme: scheme.into(),
        level,
        max_distance_pct: None,
        rms_distance_pct: None,
        max_normal_deg: None,
        rms_normal_deg: None,
        max_boundary_normal_spread_deg: boundary_normal_spread(&topo, &t),
        open_edges: weld::weld(&t).open_edges,
    };
    if let Some(lim) = limit {
        let g = cpu::evaluate(&patches, (lim.n - 1) as u32)?;
        let per = lim.n * lim.n;
        let (mut dmax, mut dsum, mut amax, mut asum, mut count) =
            (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0usize);
        for f in 0..lim.faces.min(g.faces) {
            let face = mesh.face(f);
            let mut size = 0.0f64;
            for k in 0..face.len() {
                let a = Vec3::from_array(mesh.positions[face[k] as usize]);
                let b = Vec3::from_array(mesh.positions[face[(k + 1) % face.len()] as usize]);
                size += (b - a).length() as f64;
            }
            let size = (size / face.len() as f64).max(f64::MIN_POSITIVE);
            for s in 0..per {
                let [p, n] = lim.samples[f * per + s];
                let d = (g.positions[f * per + s] - p).as_dvec3().length() / size * 100.0;
                let a = angle(g.normals[f * per + s], n);
                dmax = dmax.max(d);
                amax = amax.max(a);
                dsum += d * d;
                asum += a * a;
                count += 1;
            }
        }
        let c = count.max(1) as f64;
        acc.max_distance_pct = Some(dmax);
        acc.rms_distance_pct = Some((dsum / c).sqrt());
        acc.max_normal_deg = Some(amax);
        acc.rms_normal_deg = Some((asum / c).sqrt());
    }
    Ok(acc)
}

/// Markdown table of results.
pub fn markdown(mesh: &str, rows: &[Accuracy]) -> String {
    let opt = |x: Option<f64>| x.map(|v| format!("{v:.3e}")).unwrap_or_else(|| "–".into());
    let mut s = String::from(
        "| mesh | scheme | N | max dist % | rms dist % | max normal ° | rms normal ° | max boundary normal spread ° | open edges |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {mesh} | {} | {} | {} | {} | {} | {} | {:.3e} | {} |\n",
            r.scheme,
            r.level,
            opt(r.max_distance_pct),
            opt(r.rms_distance_pct),
            opt(r.max_normal_deg),
            opt(r.rms_normal_deg),
            r.max_boundary_normal_spread_deg,
            r.open_edges
        ));
    }
    s
}
