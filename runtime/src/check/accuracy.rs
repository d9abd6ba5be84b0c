//! How close a scheme comes to the Catmull-Clark limit surface, and how
//! smooth and watertight its tessellation is — the numbers behind
//! `tessgen compare` and `docs/accuracy.md`.
//!
//! Ground truth is the exact Catmull-Clark limit sampled on a regular grid
//! in every base face (format: `tests/data/cc_limit/UPSTREAM_README.md`).
//! Distances are in % of the local quad size (the mean edge length of the
//! base face), as in the PCCM paper's Figure 11.
//!
//! Two smoothness measures look across every shared edge: the *shading*
//! normal spread ([`boundary_normal_spread`], the normals the scheme
//! evaluates) and the *geometric* normal jump ([`geometric_normal_jump`], a
//! finite-difference estimate of the true surface normal from tessellated
//! positions alone). They differ for schemes that shade with separate tangent
//! patches (ACC): a continuous shading normal over geometry that is only C⁰
//! across edges near extraordinary vertices.

use crate::cpu::{self, Patches, TessError, Tessellation};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use crate::tessellate::{Output, Request, Sampling, Session};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
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
        // Checked: the header's counts come from the file (a header of
        // 2^32 − 1 faces overflowed here, a panic in debug builds).
        let size = [n, n, k, 4]
            .iter()
            .try_fold(faces, |acc, &x| acc.checked_mul(x))
            .and_then(|x| x.checked_add(32));
        if size != Some(b.len()) {
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
    /// Largest angle between the two patches' *shading* normals (the normals
    /// the scheme evaluates) at shared boundary samples, degrees.
    pub max_boundary_normal_spread_deg: f64,
    /// Largest angle between the two patches' *geometric* surface normals at
    /// shared boundary samples, degrees: a finite-difference estimate from the
    /// tessellated positions alone ([`boundary_geometric_normals`]), taken at
    /// level [`GEOMETRIC_JUMP_LEVEL`] whatever `level` is. Shows geometry that
    /// is only C⁰ even where the shading normal is continuous (ACC). For
    /// G¹/C¹ schemes only the estimate's error remains (≤ 0.05° on the shared
    /// meshes).
    pub geometric_normal_jump_deg: f64,
    /// Tessellation level the geometric normal jump was estimated at.
    pub geometric_normal_jump_level: u32,
    /// Open edges after exact-bit welding (0 = watertight for a closed mesh;
    /// an open mesh keeps `N` per base boundary edge).
    pub open_edges: usize,
    /// Open edges beyond the true boundary's (`N` × [`crate::weld::open_base_edges`]):
    /// cracks, 0 = watertight.
    pub cracks: usize,
    /// Largest distance (% of quad size) on *regular* faces (every corner
    /// regular: smooth valence 4, crease sector of 2 faces, corner sector of
    /// 1; none touching a semi-sharp edge), where every quad scheme is the
    /// exact limit: f32 rounding only. `None` without reference or such faces.
    pub max_regular_distance_pct: Option<f64>,
}

fn angle(a: Vec3, b: Vec3) -> f64 {
    angle_f64(a.as_dvec3(), b.as_dvec3())
}

fn angle_f64(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// Grid index of parameter `t` along local edge `k` of a `level` grid (edge 0: v = 0, t = u;
/// 1: u = 1, t = v; 2: v = 1, t = 1 − u; 3: u = 0, t = 1 − v): the layout every backend's
/// grid output shares.
pub fn edge_sample(k: u32, t: u32, level: u32) -> u32 {
    inner_sample(k, t, 0, level)
}

/// Grid index of the sample `depth` grid steps into the face from parameter
/// `t` on local edge `k` (edge 0: v=0, t=u; 1: u=1, t=v; 2: v=1, t=1−u;
/// 3: u=0, t=1−v).
fn inner_sample(k: u32, t: u32, depth: u32, level: u32) -> u32 {
    let (i, j) = match k {
        0 => (t, depth),
        1 => (level - depth, t),
        2 => (level - t, level - depth),
        _ => (depth, level - t),
    };
    j * (level + 1) + i
}

/// The tessellation level [`compare`] estimates the geometric normal jump at,
/// whatever its own `level` (the jump is a property of the surface).
///
/// Coarser grids leave more finite-difference error: on
/// `catmark_toroidal_tet`, where G¹ Gregory patches should show 0°, the
/// estimate is 4.2° at 16, 1.2° at 32, 0.26° at 64 and 0.04° at 128. With
/// the face-local frame of [`patches_geometric_normal_jump`] f32 rounding
/// stays below ~0.05° at this level (regular torus 0.004°, the 27,776-quad
/// `catmark_righthanded_L3` 0.04°). Only the strips along the edges are
/// evaluated, not whole grids, so the cost is O(edges · level).
pub const GEOMETRIC_JUMP_LEVEL: u32 = 128;

/// One-sided first-derivative weights (times 6h) into the face: exact for
/// cubics, error O(h³).
const ACROSS: [f64; 4] = [-11.0, 18.0, -9.0, 2.0];

/// Edge parameters `t` (grid steps) where the geometric normal is estimated
/// at `level`: all but the first and last eighth of the edge; `None` below
/// level 4.
fn jump_range(level: u32) -> Option<std::ops::RangeInclusive<u32>> {
    if level < ACROSS.len() as u32 {
        return None;
    }
    let skip = level.div_ceil(8).max(1);
    Some(skip..=level - skip)
}

/// Geometric normals of the two patches at one shared boundary sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryNormals {
    /// The two faces sharing the edge (`face[0]` owns the lower half-edge).
    pub face: [u32; 2],
    /// The sample's grid index in each face (`j·(level+1) + i`).
    pub sample: [u32; 2],
    /// Unit normal estimated from each face's positions, oriented like the
    /// scheme's `∂u × ∂v` (outward for counter-clockwise faces).
    pub normal: [DVec3; 2],
}

/// The geometric (true) surface normal of each patch at the shared-edge
/// samples of a tessellation, estimated from its positions alone — scheme
/// agnostic, and the surface's normal rather than the shading normal.
///
/// At parameter `t` of a face's local edge `k` (running corner `k` → `k+1`),
/// with `p_d` the sample `d` grid steps into the face:
///
/// * along the edge: central difference of the boundary samples,
///   `p(t+1) − p(t−1)`;
/// * across the edge, into the face: the cubic-exact one-sided difference
///   `(−11·p_0 + 18·p_1 − 9·p_2 + 2·p_3)/(6h)` — the second-order
///   `(−3·p_0 + 4·p_1 − p_2)/(2h)` left 0.3° on the regular torus and 8° on
///   Gregory patches of `catmark_toroidal_tet` at level 16, 1.8° still at 64;
/// * normal = normalize(along × across). With `along` in the face's own edge
///   direction and `across` pointing inwards this is the direction of
///   `∂u × ∂v` on every edge (edge 1: `∂v × −∂u`, …); the second face walks
///   the edge the other way round in its own frame, so both normals come
///   out outward with no explicit flip.
///
/// The first and last eighth of every edge are skipped (at least the
/// corners): the corners are mesh vertices, where every scheme here
/// interpolates the limit tangent plane (no jump) but where rational
/// (Gregory) patches have cross derivatives whose higher derivatives grow
/// like 1/u, so the estimate there converges only as O(h); ACC's geometric
/// jump vanishes at the corners and peaks inside the edge. Elsewhere the
/// error is O(h³) across plus O(h²) along the edge (the latter shared by
/// both faces, so it mostly cancels in the jump). Needs `level ≥ 4` (empty
/// below) and quads.
pub fn boundary_geometric_normals(topo: &Topology, t: &Tessellation) -> Vec<BoundaryNormals> {
    if t.sides != 4 {
        return Vec::new();
    }
    let per = t.grid_len() as u32;
    boundary_normals_by(topo, t.level, |f, s| {
        t.positions[(f * per + s) as usize].as_dvec3()
    })
}

/// Largest angle (degrees) between the two patches' geometric normals over
/// the shared-edge samples of a tessellation: see
/// [`boundary_geometric_normals`].
pub fn geometric_normal_jump(topo: &Topology, t: &Tessellation) -> f64 {
    max_jump(&boundary_geometric_normals(topo, t))
}

/// [`geometric_normal_jump`] of `patches` at `level`, evaluating only the
/// strips of samples next to the edges, so fine levels stay cheap on large
/// meshes.
///
/// Each face is evaluated in a local frame: its control points less the
/// patch's corner-0 position (the patches are affine in their control
/// points, so this moves the surface and nothing else; vector slots such as
/// ACC's tangent coefficients shift too, which only alters the shading
/// normal, unused here). Differences of f32
/// positions then lose no precision to the absolute coordinates, which on
/// small faces far from the origin (`catmark_righthanded` refined three
/// times) would otherwise swamp the finite differences at fine levels. The
/// normals therefore match those of [`cpu::evaluate`]'s grid at `level` up
/// to its rounding, not bit for bit.
pub fn patches_geometric_normal_jump(
    topo: &Topology,
    patches: &Patches,
    level: u32,
) -> Result<f64, TessError> {
    cpu::check_level(level)?;
    let k = patches.scheme;
    if k.sides != 4 {
        return Err(cpu::facet_error(k));
    }
    let faces = patches.face_class.len();
    let cps = |f: usize| {
        &patches.control_points[patches.cp_offsets[f] as usize..patches.cp_offsets[f + 1] as usize]
    };
    let local: Vec<Vec3> = (0..faces)
        .into_par_iter()
        .flat_map_iter(|f| {
            let origin = (k.eval)(cps(f), patches.face_class[f], 0, 0, 0, level).position;
            cps(f).iter().map(move |c| *c - origin)
        })
        .collect();
    let normals = boundary_normals_by(topo, level, |f, s| {
        let f = f as usize;
        let cp = &local[patches.cp_offsets[f] as usize..patches.cp_offsets[f + 1] as usize];
        let (iu, iv) = ((k.grid_iu)(s, level), (k.grid_iv)(s, level));
        (k.eval)(cp, patches.face_class[f], 0, iu, iv, level)
            .position
            .as_dvec3()
    });
    Ok(max_jump(&normals))
}

fn max_jump(normals: &[BoundaryNormals]) -> f64 {
    normals
        .iter()
        .map(|b| angle_f64(b.normal[0], b.normal[1]))
        .fold(0.0, f64::max)
}

/// [`boundary_geometric_normals`] over positions `pos(face, grid index)` of a
/// `level` grid.
fn boundary_normals_by(
    topo: &Topology,
    level: u32,
    pos: impl Fn(u32, u32) -> DVec3 + Sync,
) -> Vec<BoundaryNormals> {
    let Some(range) = jump_range(level) else {
        return Vec::new();
    };
    let normal = |f: u32, k: u32, t: u32| -> DVec3 {
        let along = pos(f, edge_sample(k, t + 1, level)) - pos(f, edge_sample(k, t - 1, level));
        let across = ACROSS.iter().enumerate().fold(DVec3::ZERO, |a, (d, w)| {
            a + *w * pos(f, inner_sample(k, t, d as u32, level))
        });
        along.cross(across).normalize_or_zero()
    };
    (0..topo.twin.len() as u32)
        .into_par_iter()
        .filter(|&h| {
            let g = topo.twin[h as usize];
            g != crate::mesh::topology::NONE && g > h
        })
        .flat_map_iter(|h| {
            let g = topo.twin[h as usize];
            let (fa, fb) = (topo.face[h as usize], topo.face[g as usize]);
            let (ka, kb) = (
                h - topo.face_offsets[fa as usize],
                g - topo.face_offsets[fb as usize],
            );
            range.clone().map(move |t| BoundaryNormals {
                face: [fa, fb],
                sample: [edge_sample(ka, t, level), edge_sample(kb, level - t, level)],
                normal: [normal(fa, ka, t), normal(fb, kb, level - t)],
            })
        })
        .collect()
}

/// Worst normal spread across shared edges of a tessellation.
pub fn boundary_normal_spread(topo: &Topology, t: &Tessellation) -> f64 {
    let per = t.grid_len() as u32;
    let mut worst = 0.0f64;
    for h in 0..topo.twin.len() as u32 {
        let g = topo.twin[h as usize];
        if g == crate::mesh::topology::NONE || g < h {
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
/// measure smoothness and watertightness at `level`. Runs through the front
/// door on the CPU, so a mesh with non-quads or semi-sharp creases is
/// measured as it tessellates: on its refinement (only base quads have
/// limit samples; smoothness is measured on the refined patches).
pub fn compare(
    mesh: &Mesh,
    scheme: &str,
    level: u32,
    limit: Option<&LimitSamples>,
) -> Result<Accuracy, crate::tessellate::Error> {
    compare_with(mesh, &Request::uniform(scheme, level), limit)
}

/// [`compare`] with the request's options (its scheme and level; e.g.
/// [`Request::crease_refinement`]).
pub fn compare_with(
    mesh: &Mesh,
    request: &Request<'_>,
    limit: Option<&LimitSamples>,
) -> Result<Accuracy, crate::tessellate::Error> {
    let level = match request.sampling {
        Sampling::Uniform(n) => n,
        Sampling::Adaptive(_) => 0,
    };
    let scheme = request.scheme.as_str();
    let v = request.validate(mesh)?;
    let topo = v.topology().ok_or_else(|| cpu::facet_error(v.kernels()))?;
    let positions: Vec<Vec3> = v
        .run_mesh()
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    let kernels = v.kernels();
    let patches = cpu::construct(topo, &positions, kernels)?;
    let geometric_normal_jump_deg =
        patches_geometric_normal_jump(topo, &patches, GEOMETRIC_JUMP_LEVEL)?;
    let t = cpu::evaluate(&patches, level)?;
    let mut acc = Accuracy {
        scheme: scheme.into(),
        level,
        max_distance_pct: None,
        rms_distance_pct: None,
        max_normal_deg: None,
        rms_normal_deg: None,
        max_boundary_normal_spread_deg: boundary_normal_spread(topo, &t),
        geometric_normal_jump_deg,
        geometric_normal_jump_level: GEOMETRIC_JUMP_LEVEL,
        open_edges: 0,
        cracks: 0,
        max_regular_distance_pct: None,
    };
    let mut session = Session::new();
    let out = session.run(&v)?;
    let w = out.weld();
    acc.open_edges = w.open_edges;
    acc.cracks = w.cracks(v.expected_open_edges(&out));
    // Faces whose limit is one bicubic patch: regular corners, no
    // semi-sharp edge at any corner (docs/boundaries.md §2) — on a refined
    // mesh, every refined face of the base face.
    // A feature-adaptive refinement: the leaves of every depth.
    let mut regular = vec![true; mesh.num_faces()];
    for part in v.parts() {
        let Some(topo) = part.topology() else {
            continue;
        };
        let mut semi = vec![false; topo.num_vertices()];
        for (&(a, b), &s) in &topo.features.edge_sharpness {
            if s > 0.0 && s < crate::mesh::features::SHARPNESS_INFINITE {
                for v in [a, b] {
                    if let Some(x) = semi.get_mut(v as usize) {
                        *x = true;
                    }
                }
            }
        }
        let run_mesh = part.run_mesh();
        let leaf_regular = |f: usize| {
            topo.classes[f] == crate::mesh::topology::FaceClass::Ordinary
                && run_mesh.face(f).iter().all(|&v| !semi[v as usize])
        };
        match part.refined() {
            Some(r) => {
                for (f, leaf) in r.refinement.leaves.iter().enumerate() {
                    if r.emits(f) {
                        let base = r.refinement.blocks[leaf.block as usize].face as usize;
                        regular[base] &= leaf_regular(f);
                    }
                }
            }
            None => {
                for (f, x) in regular.iter_mut().enumerate() {
                    *x = leaf_regular(f);
                }
            }
        }
    }
    if let Some(lim) = limit {
        let dev = deviation_with(&mut session, mesh, request, lim)?;
        let per = lim.n * lim.n;
        let (mut dmax, mut dsum, mut amax, mut asum, mut count) =
            (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0usize);
        let mut rmax: Option<f64> = None;
        for (s, (&d, &a)) in dev.distance_pct.iter().zip(&dev.normal_deg).enumerate() {
            if d.is_nan() {
                continue;
            }
            if regular[dev.grid.face_of(s / per)] {
                rmax = Some(rmax.unwrap_or(0.0).max(d));
            }
            dmax = dmax.max(d);
            amax = amax.max(a);
            dsum += d * d;
            asum += a * a;
            count += 1;
        }
        let c = count.max(1) as f64;
        acc.max_distance_pct = Some(dmax);
        acc.rms_distance_pct = Some((dsum / c).sqrt());
        acc.max_normal_deg = Some(amax);
        acc.rms_normal_deg = Some((asum / c).sqrt());
        acc.max_regular_distance_pct = rmax;
    }
    Ok(acc)
}

/// A scheme's deviation from the Catmull-Clark limit at every limit sample:
/// its grid at the limit samples' `(u, v)` (level `n − 1`, one grid per
/// base quad; a refined mesh's n-gon sub-faces have no limit samples) and,
/// per grid sample, the distance in % of the base face's size and the
/// normal's angle in degrees (NaN where the limit file has no sample).
#[derive(Clone, Debug)]
pub struct Deviation {
    pub grid: Tessellation,
    pub distance_pct: Vec<f64>,
    pub normal_deg: Vec<f64>,
}

/// [`Deviation`] of `request`'s scheme on `mesh` (its level is replaced
/// by the limit samples' grid).
pub fn deviation(
    mesh: &Mesh,
    request: &Request<'_>,
    limit: &LimitSamples,
) -> Result<Deviation, crate::tessellate::Error> {
    deviation_with(&mut Session::new(), mesh, request, limit)
}

fn deviation_with(
    session: &mut Session,
    mesh: &Mesh,
    request: &Request<'_>,
    lim: &LimitSamples,
) -> Result<Deviation, crate::tessellate::Error> {
    let sampled = Request {
        sampling: Sampling::Uniform((lim.n - 1) as u32),
        ..request.clone()
    };
    let vs = sampled.validate(mesh)?;
    let g = match session.run(&vs)? {
        Output::Grid(g) => g,
        Output::Polygons(p) => p.quads,
        _ => return Err(cpu::facet_error(vs.kernels()).into()),
    };
    let per = lim.n * lim.n;
    let mut distance_pct = vec![f64::NAN; g.positions.len()];
    let mut normal_deg = vec![f64::NAN; g.positions.len()];
    for k in 0..g.faces {
        let f = g.face_of(k);
        if f >= lim.faces || g.grid_len() != per {
            continue;
        }
        let face = mesh.face(f);
        let mut size = 0.0f64;
        for i in 0..face.len() {
            let a = Vec3::from_array(mesh.positions[face[i] as usize]);
            let b = Vec3::from_array(mesh.positions[face[(i + 1) % face.len()] as usize]);
            size += (b - a).length() as f64;
        }
        let size = (size / face.len() as f64).max(f64::MIN_POSITIVE);
        for s in 0..per {
            let [p, n] = lim.samples[f * per + s];
            if !p.is_finite() {
                continue;
            }
            distance_pct[k * per + s] =
                (g.positions[k * per + s] - p).as_dvec3().length() / size * 100.0;
            normal_deg[k * per + s] = angle(g.normals[k * per + s], n);
        }
    }
    Ok(Deviation {
        grid: g,
        distance_pct,
        normal_deg,
    })
}

/// Markdown table of results. "max geometric normal jump °" is the
/// finite-difference estimate of [`Accuracy::geometric_normal_jump_deg`]
/// (level [`GEOMETRIC_JUMP_LEVEL`], not N).
pub fn markdown(mesh: &str, rows: &[Accuracy]) -> String {
    let opt = |x: Option<f64>| x.map(|v| format!("{v:.3e}")).unwrap_or_else(|| "–".into());
    let mut s = String::from(
        "| mesh | scheme | N | max dist % | rms dist % | max normal ° | rms normal ° | regular faces max dist % | max boundary normal spread ° | max geometric normal jump ° | open edges | cracks |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {mesh} | {} | {} | {} | {} | {} | {} | {} | {:.3e} | {:.3e} | {} | {} |\n",
            r.scheme,
            r.level,
            opt(r.max_distance_pct),
            opt(r.rms_distance_pct),
            opt(r.max_normal_deg),
            opt(r.rms_normal_deg),
            opt(r.max_regular_distance_pct),
            r.max_boundary_normal_spread_deg,
            r.geometric_normal_jump_deg,
            r.open_edges,
            r.cracks
        ));
    }
    s
}
