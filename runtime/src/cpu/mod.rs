//! The CPU tessellator: generated kernels over flat topology, rayon over
//! vertices (vertex stage), faces (patch stage) and faces again (evaluation).
//!
//! Each stage writes a disjoint slice per vertex/face, so the parallel result
//! is bit-identical to a sequential run.
//!
//! This folder is the CPU side that every backend shares: the GPU backends
//! and the checks take their scheme lookup, [`Tessellation`] grids,
//! [`adaptive`] host data (edge ids, metrics, factors) and [`displace`]
//! ownership tables from here, and the front door ([`crate::tessellate`])
//! sits above them all. Keeping these out of `tessellate/` keeps the folder
//! graph free of circles (`tessellate → gpu → cpu`, `check → cpu`).

pub mod adaptive;
pub mod construct;
pub mod displace;
mod grid_acc;
mod grid_cpatch;
mod grid_eval;
mod grid_flat;
mod grid_gregory;
mod grid_gregory4;
mod grid_tri;
mod lanes;
mod patch_flat;
mod vertex_flat;

pub use construct::Construction;

use crate::cpu::displace::{DisplaceData, Displacement};
use crate::kernels::{self, common::Inputs, common::Sample, common::SchemeKernels};
use crate::mesh::topology::{FaceClass, Topology, TopologyError, TopologyOptions};
use crate::mesh::Mesh;
use glam::Vec3;
use rayon::prelude::*;

/// Errors of scheme selection and tessellation.
#[derive(Debug, thiserror::Error)]
pub enum TessError {
    #[error(transparent)]
    Topology(#[from] TopologyError),
    #[error("unknown scheme `{name}` (available: {available})")]
    UnknownScheme { name: String, available: String },
    #[error(
        "scheme `{scheme}` has no patch for extraordinary faces; face {face} has a corner of valence ≠ 4 (use `pccm`)"
    )]
    ExtraordinaryFace { scheme: String, face: usize },
    #[error("tessellation level must be in 1..={max}, got {0}", max = MAX_LEVEL)]
    Level(u32),
    #[error("scheme `{scheme}` works on {want}; {hint}")]
    WrongFacet {
        scheme: String,
        want: &'static str,
        hint: &'static str,
    },
    #[error(transparent)]
    TriMesh(#[from] crate::mesh::trimesh::TriMeshError),
    #[error(transparent)]
    Tags(#[from] crate::mesh::tags::TagError),
    #[error(transparent)]
    Displace(#[from] crate::cpu::displace::DisplaceError),
    #[error("output buffers hold {got} samples, the grids need {want}")]
    OutputLength { want: usize, got: usize },
    #[error(
        "the result does not fit in memory: {samples} samples need {bytes} bytes (stream it in \
         chunks: tessellate::Session::run_chunked, or `tessellate` without --check-watertight)"
    )]
    OutOfMemory { samples: usize, bytes: u128 },
    #[error("these patches were not made by this construction (scheme or layout differs, or too few positions)")]
    Layout,
}

/// The error for a scheme given the wrong kind of facet.
pub fn facet_error(scheme: &SchemeKernels) -> TessError {
    if scheme.sides == 3 {
        TessError::WrongFacet {
            scheme: scheme.name.into(),
            want: "triangles",
            hint: "give it a triangle mesh (or split quads: `--split-quads`)",
        }
    } else {
        TessError::WrongFacet {
            scheme: scheme.name.into(),
            want: "quads",
            hint: "triangle meshes need a triangle scheme (pn, stpn, phong)",
        }
    }
}

/// Largest tessellation level accepted (a `(N+1)²` grid per face must stay
/// addressable with u32 indices on every backend).
pub const MAX_LEVEL: u32 = 4096;

/// Look up a scheme's kernels by name.
pub fn scheme(name: &str) -> Result<&'static SchemeKernels, TessError> {
    kernels::scheme(name).ok_or_else(|| TessError::UnknownScheme {
        name: name.into(),
        available: kernels::scheme_names().join(", "),
    })
}

/// Topology options matching the compiled stencil table.
pub fn topology_options() -> TopologyOptions {
    TopologyOptions {
        max_valence: kernels::common::MAX_VALENCE,
        require_quads: true,
    }
}

/// Control-point offset of every face (its class's count, in face order),
/// then the total: the patch stage's output layout.
pub(crate) fn control_point_offsets(face_class: &[u32], scheme: &SchemeKernels) -> (Vec<u32>, u32) {
    let mut offsets = Vec::with_capacity(face_class.len() + 1);
    let mut total = 0u32;
    for &c in face_class {
        offsets.push(total);
        total += scheme.classes[c as usize].control_points;
    }
    offsets.push(total);
    (offsets, total)
}

/// Constructed patches: vertex-stage outputs and per-face control points.
#[derive(Clone, Debug)]
pub struct Patches {
    pub scheme: &'static SchemeKernels,
    /// Index into `scheme.classes` for every face.
    pub face_class: Vec<u32>,
    /// First control point of every face (len faces + 1).
    pub cp_offsets: Vec<u32>,
    pub control_points: Vec<Vec3>,
    pub vertex_out_offsets: Vec<u32>,
    /// The vertex stage's outputs. [`construct()`] computes every entry;
    /// [`Construction`] only those some face reads
    /// ([`Construction::writes_vertex_out`]), the others stay 0.
    pub vertex_out: Vec<Vec3>,
}

/// Flat per-face corner arrays, as the kernels read them.
pub fn corner_arrays(topo: &Topology) -> (Vec<u32>, Vec<u32>) {
    let mut cv = Vec::with_capacity(topo.corners.len() * 4);
    let mut cs = Vec::with_capacity(topo.corners.len() * 4);
    for c in &topo.corners {
        for k in c {
            cv.push(k.vertex);
            cs.push(k.sector);
        }
    }
    (cv, cs)
}

/// Split `data` into consecutive mutable slices at `offsets` (len k + 1).
fn split_by_offsets<'a, T>(mut data: &'a mut [T], offsets: &[u32]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(offsets.len().saturating_sub(1));
    for w in offsets.windows(2) {
        let (head, tail) = data.split_at_mut((w[1] - w[0]) as usize);
        out.push(head);
        data = tail;
    }
    out
}

/// Which patch class of `scheme` every face uses (`ordinary` faces fall back
/// to the extraordinary class if a scheme only declares that one).
pub fn face_classes(topo: &Topology, scheme: &SchemeKernels) -> Result<Vec<u32>, TessError> {
    let find = |name: &str| {
        scheme
            .classes
            .iter()
            .position(|c| c.class == name)
            .map(|i| i as u32)
    };
    let ordinary = find("ordinary");
    let extraordinary = find("extraordinary");
    topo.classes
        .iter()
        .enumerate()
        .map(|(face, c)| match c {
            FaceClass::Ordinary => ordinary
                .or(extraordinary)
                .ok_or(TessError::ExtraordinaryFace {
                    scheme: scheme.name.into(),
                    face,
                }),
            FaceClass::Extraordinary => extraordinary.ok_or(TessError::ExtraordinaryFace {
                scheme: scheme.name.into(),
                face,
            }),
        })
        .collect()
}

/// Run the vertex and patch stages.
pub fn construct(
    topo: &Topology,
    positions: &[Vec3],
    scheme: &'static SchemeKernels,
) -> Result<Patches, TessError> {
    if scheme.sides != 4 {
        return Err(facet_error(scheme));
    }
    let face_class = face_classes(topo, scheme)?;
    // Vertex stage.
    let (vertex_out_offsets, total) = vertex_out_offsets(topo, scheme);
    let (corner_vertex, corner_sector) = corner_arrays(topo);
    let mut vertex_out = vec![Vec3::ZERO; total as usize];
    {
        let inputs = construct::inputs(
            topo,
            &vertex_out_offsets,
            &corner_vertex,
            &corner_sector,
            positions,
            &[],
        );
        split_by_offsets(&mut vertex_out, &vertex_out_offsets)
            .into_par_iter()
            .enumerate()
            .filter(|(_, out)| !out.is_empty())
            .for_each(|(v, out)| (scheme.vertex_stage)(&inputs, out, v as u32, 0));
    }
    // Patch stage.
    let (cp_offsets, total) = control_point_offsets(&face_class, scheme);
    let mut control_points = vec![Vec3::ZERO; total as usize];
    {
        let inputs = construct::inputs(
            topo,
            &vertex_out_offsets,
            &corner_vertex,
            &corner_sector,
            positions,
            &vertex_out,
        );
        split_by_offsets(&mut control_points, &cp_offsets)
            .into_par_iter()
            .enumerate()
            .for_each(|(f, out)| {
                (scheme.classes[face_class[f] as usize].patch)(&inputs, out, f as u32, 0)
            });
    }
    Ok(Patches {
        scheme,
        face_class,
        cp_offsets,
        control_points,
        vertex_out_offsets,
        vertex_out,
    })
}

/// One grid of samples per face, in face order. Quads (`sides` 4): a
/// `(level+1)²` grid, sample `j·(level+1) + i` at `(u, v) = (i, j)/level`.
/// Triangles (`sides` 3): `(level+1)(level+2)/2` samples row by row, sample
/// `(i, j)` at barycentrics `(level − i − j, i, j)/level` of corners 0, 1, 2
/// ([`crate::grid::tri_grid_coords`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tessellation {
    pub level: u32,
    pub faces: usize,
    pub sides: u32,
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// Base face of each grid when some faces emit nothing (holes, faces
    /// without a limit surface: docs/boundaries.md §5); empty means grid `f`
    /// is face `f`.
    pub face_ids: Vec<u32>,
}

impl Tessellation {
    /// Base face of grid `g` (docs/boundaries.md §5).
    pub fn face_of(&self, g: usize) -> usize {
        self.face_ids.get(g).map_or(g, |&f| f as usize)
    }

    /// Keeps only the grids of faces with `keep[face]`, recording their
    /// base faces in [`Tessellation::face_ids`].
    pub fn retain_faces(&mut self, keep: &[bool]) {
        let per = self.grid_len();
        let (mut ids, mut pos, mut nrm) = (Vec::new(), Vec::new(), Vec::new());
        for g in 0..self.faces {
            let f = self.face_of(g);
            if keep.get(f).copied().unwrap_or(true) {
                ids.push(f as u32);
                pos.extend_from_slice(&self.positions[g * per..(g + 1) * per]);
                nrm.extend_from_slice(&self.normals[g * per..(g + 1) * per]);
            }
        }
        self.faces = ids.len();
        self.face_ids = ids;
        self.positions = pos;
        self.normals = nrm;
    }

    /// Samples per face.
    pub fn grid_len(&self) -> usize {
        if self.sides == 3 {
            crate::grid::tri_grid_len(self.level)
        } else {
            ((self.level + 1) * (self.level + 1)) as usize
        }
    }

    /// The triangles of one face's sample grid (local indices): what welding
    /// and OBJ output connect.
    pub fn local_triangles(&self) -> Vec<[u32; 3]> {
        if self.sides == 3 {
            crate::grid::tri_grid_triangles(self.level)
        } else {
            crate::grid::grid_triangles(self.level)
        }
    }
}

/// Face `face`'s patch at a hardware tessellator's barycentric domain point
/// `(x, y, z)` of corners 0, 1, 2, through the generated `eval_domain` (what
/// the GLSL/HLSL evaluation stages of triangle schemes run): the integer
/// grid path on the patch boundary, the surface at the raw point inside.
/// `None` for quad schemes or a face out of range.
pub fn eval_domain(patches: &Patches, face: usize, domain: [f32; 3], level: u32) -> Option<Sample> {
    let f = patches.scheme.eval_domain?;
    let class = *patches.face_class.get(face)?;
    let cp = &patches.control_points
        [*patches.cp_offsets.get(face)? as usize..*patches.cp_offsets.get(face + 1)? as usize];
    Some(f(cp, class, 0, domain[0], domain[1], domain[2], level))
}

/// [`eval_domain`] with the displacement step, through the generated
/// `eval_domain_displaced` (what the displacing GLSL/HLSL evaluation stages
/// of triangle schemes run): on the patch boundary `eval_displaced` at the
/// integer grid point (the owner's normal and texture coordinate), inside
/// the raw point along its own normal. `data` must be built for this
/// [`Patches`]' layout ([`displacement_data_tri`]). `None` for quad
/// schemes or a face out of range.
pub fn eval_domain_displaced(
    patches: &Patches,
    data: &DisplaceData,
    face: usize,
    domain: [f32; 3],
    level: u32,
) -> Option<Sample> {
    let f = patches.scheme.eval_domain_displaced?;
    let (class, cp_base) = face_patch(patches, face)?;
    let inputs = displace_inputs(data);
    Some(f(
        &inputs,
        &patches.control_points,
        face as u32,
        class,
        cp_base,
        domain[0],
        domain[1],
        domain[2],
        level,
    ))
}

/// Face `face`'s displaced sample at integer grid point `(iu, iv)` of
/// `level`, through the generated `eval_displaced` (the owner's normal and
/// texture coordinate on the boundary). `None` for a face out of range.
pub fn eval_displaced_at(
    patches: &Patches,
    data: &DisplaceData,
    face: usize,
    iu: u32,
    iv: u32,
    level: u32,
) -> Option<Sample> {
    let f = patches.scheme.eval_displaced?;
    let (class, cp_base) = face_patch(patches, face)?;
    let inputs = displace_inputs(data);
    Some(f(
        &inputs,
        &patches.control_points,
        face as u32,
        class,
        cp_base,
        iu,
        iv,
        level,
    ))
}

/// Face `face`'s class and first control point in `patches`' global array.
fn face_patch(patches: &Patches, face: usize) -> Option<(u32, u32)> {
    Some((
        *patches.face_class.get(face)?,
        *patches.cp_offsets.get(face)?,
    ))
}

/// The generated kernels' view of the displacement arrays.
pub(crate) fn displace_inputs(data: &DisplaceData) -> Inputs<'_> {
    Inputs {
        texcoords: &data.texcoords,
        owners: &data.owners,
        displace_info: &data.info,
        displace_map: &data.map.texels,
        displace_width: data.map.width,
        ..Default::default()
    }
}

/// Evaluate every patch on a `level × level` grid (the convenience API:
/// fresh buffers; [`evaluate_into`] reuses them).
pub fn evaluate(patches: &Patches, level: u32) -> Result<Tessellation, TessError> {
    let mut t = Tessellation {
        level,
        faces: 0,
        sides: patches.scheme.sides,
        positions: Vec::new(),
        normals: Vec::new(),
        face_ids: Vec::new(),
    };
    evaluate_into(patches, level, &mut t)?;
    Ok(t)
}

/// [`evaluate`] into an existing [`Tessellation`], whose buffers are
/// resized only when the grid size changed: an engine (or the bench)
/// re-evaluating at the same level allocates and first-touches nothing.
/// The result is [`evaluate`]'s, bit for bit.
pub fn evaluate_into(patches: &Patches, level: u32, t: &mut Tessellation) -> Result<(), TessError> {
    check_level(level)?;
    let total = (patches.scheme.grid_len)(level) as usize * patches.face_class.len();
    reserve_samples(&mut t.positions, &mut t.normals, total)?;
    t.level = level;
    t.faces = patches.face_class.len();
    t.sides = patches.scheme.sides;
    t.face_ids.clear();
    t.positions.resize(total, Vec3::ZERO);
    t.normals.resize(total, Vec3::ZERO);
    evaluate_slices(patches, level, &mut t.positions, &mut t.normals)
}

/// Every patch's grid into the caller's `positions` and `normals` (each
/// `grid_len(level) × faces` long, [`Tessellation`]'s layout), by the fast
/// grid path: per-patch and per-column invariants hoisted, SIMD over the
/// samples, border samples from the shared edge evaluator in their own
/// loop — the same operations in the same order per sample as the
/// generated per-sample `eval` ([`evaluate_per_sample_into`]), so the same
/// bits.
pub fn evaluate_slices(
    patches: &Patches,
    level: u32,
    positions: &mut [Vec3],
    normals: &mut [Vec3],
) -> Result<(), TessError> {
    grid_path(patches, level, positions, normals, grid_eval::Isa::detect())
}

/// The copies of the lane loops this machine runs, best last:
/// `baseline`, then `avx2` and `avx512` where detected.
#[doc(hidden)]
pub fn lane_copies() -> Vec<&'static str> {
    ["baseline", "avx2", "avx512"]
        .into_iter()
        .filter(|n| grid_eval::Isa::named(n).is_some())
        .collect()
}

/// [`evaluate_slices`] with the copy `name` of [`lane_copies`] (the tests
/// check every copy gives the same bits; the bench times each).
/// [`TessError::Level`]-style errors as `evaluate_slices`; a copy this
/// machine does not run falls back to the detected one.
#[doc(hidden)]
pub fn evaluate_slices_copy(
    name: &str,
    patches: &Patches,
    level: u32,
    positions: &mut [Vec3],
    normals: &mut [Vec3],
) -> Result<(), TessError> {
    let isa = grid_eval::Isa::named(name).unwrap_or_else(grid_eval::Isa::detect);
    grid_path(patches, level, positions, normals, isa)
}

/// The grids of faces `faces` (a range of `patches`' faces) into a
/// [`Tessellation`] holding just them (`face_ids` = the range), its buffers
/// reused when large enough: what a streaming caller evaluates chunk by
/// chunk (`tessellate::Session::run_chunked`). Each face's samples are
/// [`evaluate`]'s bit for bit.
pub fn evaluate_faces_into(
    patches: &Patches,
    level: u32,
    faces: std::ops::Range<usize>,
    t: &mut Tessellation,
) -> Result<(), TessError> {
    check_level(level)?;
    let faces = clamp_window(faces, patches.face_class.len());
    let per = (patches.scheme.grid_len)(level) as usize;
    let total = per * faces.len();
    reserve_samples(&mut t.positions, &mut t.normals, total)?;
    t.level = level;
    t.faces = faces.len();
    t.sides = patches.scheme.sides;
    t.face_ids.clear();
    t.face_ids.extend(faces.clone().map(|f| f as u32));
    t.positions.resize(total, Vec3::ZERO);
    t.normals.resize(total, Vec3::ZERO);
    grid_path_from(
        patches,
        level,
        faces.start,
        &mut t.positions,
        &mut t.normals,
        grid_eval::Isa::detect(),
    )
}

/// A grid level every evaluator takes: `1..=MAX_LEVEL`, else
/// [`TessError::Level`] (one check for the CPU, the GPU backends and the
/// accuracy check).
pub(crate) fn check_level(level: u32) -> Result<(), TessError> {
    if level == 0 || level > MAX_LEVEL {
        return Err(TessError::Level(level));
    }
    Ok(())
}

/// A window of faces cut to the `all` faces there are: what every
/// windowed evaluator (CPU, adaptive, wgpu, the Vulkan harness) evaluates
/// of the window it is given.
pub(crate) fn clamp_window(faces: std::ops::Range<usize>, all: usize) -> std::ops::Range<usize> {
    faces.start.min(all)..faces.end.min(all)
}

/// Room for `total` samples in both buffers, or [`TessError::OutOfMemory`]
/// (never an allocation that aborts the process).
pub(crate) fn reserve_samples(
    positions: &mut Vec<Vec3>,
    normals: &mut Vec<Vec3>,
    total: usize,
) -> Result<(), TessError> {
    let oom = |_| TessError::OutOfMemory {
        samples: total,
        bytes: 2 * total as u128 * std::mem::size_of::<Vec3>() as u128,
    };
    positions
        .try_reserve_exact(total.saturating_sub(positions.len()))
        .map_err(oom)?;
    normals
        .try_reserve_exact(total.saturating_sub(normals.len()))
        .map_err(oom)
}

fn grid_path(
    patches: &Patches,
    level: u32,
    positions: &mut [Vec3],
    normals: &mut [Vec3],
    isa: grid_eval::Isa,
) -> Result<(), TessError> {
    check_outputs(patches, level, positions, normals)?;
    grid_path_from(patches, level, 0, positions, normals, isa)
}

/// The grids of the faces with `emits[face]` only, in face order, into a
/// [`Tessellation`] whose [`Tessellation::face_ids`] name them: what
/// [`evaluate`] followed by [`Tessellation::retain_faces`] gives, bit for
/// bit, without evaluating the faces that emit nothing (holes, and the
/// ring-only faces of a feature-adaptive depth: 70 % of the faces of
/// `catmark_car`'s depths).
pub fn evaluate_emitting(
    patches: &Patches,
    level: u32,
    emits: &[bool],
) -> Result<Tessellation, TessError> {
    check_level(level)?;
    let faces: Vec<u32> = (0..patches.face_class.len())
        .filter(|&f| emits.get(f).copied().unwrap_or(true))
        .map(|f| f as u32)
        .collect();
    let per = (patches.scheme.grid_len)(level) as usize;
    let total = per * faces.len();
    let mut t = Tessellation {
        level,
        faces: faces.len(),
        sides: patches.scheme.sides,
        ..Default::default()
    };
    reserve_samples(&mut t.positions, &mut t.normals, total)?;
    t.positions.resize(total, Vec3::ZERO);
    t.normals.resize(total, Vec3::ZERO);
    let isa = grid_eval::Isa::detect();
    grid_path_of(
        patches,
        level,
        |k| faces[k] as usize,
        &mut t.positions,
        &mut t.normals,
        isa,
    );
    t.face_ids = faces;
    Ok(t)
}

/// The grids of the faces `faces` (ascending) into `t`, whose
/// [`Tessellation::face_ids`] name them, its buffers reused when large
/// enough: [`evaluate_emitting`] of a streamed window (a feature-adaptive
/// depth's leaves around a block window, its ring-only faces left out).
/// Each face's samples are [`evaluate`]'s bit for bit.
pub fn evaluate_listed_into(
    patches: &Patches,
    level: u32,
    faces: &[u32],
    t: &mut Tessellation,
) -> Result<(), TessError> {
    check_level(level)?;
    let all = patches.face_class.len();
    let faces: Vec<u32> = faces
        .iter()
        .copied()
        .filter(|&f| (f as usize) < all)
        .collect();
    let per = (patches.scheme.grid_len)(level) as usize;
    let total = per * faces.len();
    reserve_samples(&mut t.positions, &mut t.normals, total)?;
    t.level = level;
    t.faces = faces.len();
    t.sides = patches.scheme.sides;
    t.positions.resize(total, Vec3::ZERO);
    t.normals.resize(total, Vec3::ZERO);
    let isa = grid_eval::Isa::detect();
    grid_path_of(
        patches,
        level,
        |k| faces[k] as usize,
        &mut t.positions,
        &mut t.normals,
        isa,
    );
    t.face_ids = faces;
    Ok(())
}

/// The grids of faces `first ..` (as many as `positions` holds whole grids).
fn grid_path_from(
    patches: &Patches,
    level: u32,
    first: usize,
    positions: &mut [Vec3],
    normals: &mut [Vec3],
    isa: grid_eval::Isa,
) -> Result<(), TessError> {
    grid_path_of(patches, level, |k| first + k, positions, normals, isa);
    Ok(())
}

/// Grid `k` of `positions` / `normals` is face `face(k)`'s.
fn grid_path_of(
    patches: &Patches,
    level: u32,
    face: impl Fn(usize) -> usize + Sync,
    positions: &mut [Vec3],
    normals: &mut [Vec3],
    isa: grid_eval::Isa,
) {
    let kernels = patches.scheme;
    let per = (kernels.grid_len)(level) as usize;
    let paths = grid_eval::class_paths(kernels);
    let weights = lanes::LevelWeights::new(level);
    positions
        .par_chunks_mut(per)
        .zip(normals.par_chunks_mut(per))
        .enumerate()
        .with_min_len(8)
        .for_each(|(k, (pos, nrm))| {
            let f = face(k);
            let class = patches.face_class[f];
            let cp = &patches.control_points
                [patches.cp_offsets[f] as usize..patches.cp_offsets[f + 1] as usize];
            grid_eval::patch_grid(
                kernels,
                paths[class as usize],
                isa,
                &weights,
                cp,
                class,
                level,
                pos,
                nrm,
            );
        });
}

/// The per-sample path: the generated `eval` at every sample `s`, at the
/// grid point `(grid_iu(s), grid_iv(s))` — what [`evaluate`] ran before the
/// grid path, kept as its reference (tests/tests/grid_path.rs) and as the
/// bench's same-run baseline.
pub fn evaluate_per_sample_into(
    patches: &Patches,
    level: u32,
    positions: &mut [Vec3],
    normals: &mut [Vec3],
) -> Result<(), TessError> {
    let kernels = patches.scheme;
    let per = check_outputs(patches, level, positions, normals)?;
    positions
        .par_chunks_mut(per)
        .zip(normals.par_chunks_mut(per))
        .enumerate()
        .for_each(|(f, (pos, nrm))| {
            let class = patches.face_class[f];
            let cp = &patches.control_points
                [patches.cp_offsets[f] as usize..patches.cp_offsets[f + 1] as usize];
            for (s, (p, n)) in pos.iter_mut().zip(nrm.iter_mut()).enumerate() {
                let s = s as u32;
                let (iu, iv) = ((kernels.grid_iu)(s, level), (kernels.grid_iv)(s, level));
                let out = (kernels.eval)(cp, class, 0, iu, iv, level);
                *p = out.position;
                *n = out.normal;
            }
        });
    Ok(())
}

/// Samples per grid, after checking the level and both buffer lengths.
fn check_outputs(
    patches: &Patches,
    level: u32,
    positions: &[Vec3],
    normals: &[Vec3],
) -> Result<usize, TessError> {
    check_level(level)?;
    let per = (patches.scheme.grid_len)(level) as usize;
    let want = per * patches.face_class.len();
    for got in [positions.len(), normals.len()] {
        if got != want {
            return Err(TessError::OutputLength { want, got });
        }
    }
    Ok(per)
}

/// The `grid_len(level)` samples of the faces `faces` in face order,
/// sample `s` at the grid point `(grid_iu(s), grid_iv(s))`, from
/// `sample(face, class, iu, iv)`: the grid walk behind
/// [`evaluate_displaced`] (`whole`: every face, `face_ids` left empty).
fn evaluate_grid(
    patches: &Patches,
    level: u32,
    faces: std::ops::Range<usize>,
    whole: bool,
    sample: impl Fn(usize, u32, u32, u32) -> Sample + Sync,
) -> Result<Tessellation, TessError> {
    check_level(level)?;
    let kernels = patches.scheme;
    let per = (kernels.grid_len)(level) as usize;
    let all = patches.face_class.len();
    let faces = clamp_window(faces, all);
    let total = per * faces.len();
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    reserve_samples(&mut positions, &mut normals, total)?;
    let mut samples: Vec<Sample> = Vec::new();
    samples
        .try_reserve_exact(total)
        .map_err(|_| TessError::OutOfMemory {
            samples: total,
            bytes: 4 * total as u128 * std::mem::size_of::<Vec3>() as u128,
        })?;
    samples.resize(
        total,
        Sample {
            position: Vec3::ZERO,
            normal: Vec3::ZERO,
        },
    );
    samples
        .par_chunks_mut(per.max(1))
        .enumerate()
        .for_each(|(g, grid)| {
            let f = faces.start + g;
            let class = patches.face_class[f];
            for (s, out) in grid.iter_mut().enumerate() {
                let s = s as u32;
                let (iu, iv) = ((kernels.grid_iu)(s, level), (kernels.grid_iv)(s, level));
                *out = sample(f, class, iu, iv);
            }
        });
    Ok(Tessellation {
        level,
        faces: faces.len(),
        sides: kernels.sides,
        positions: {
            positions.extend(samples.iter().map(|s| s.position));
            positions
        },
        normals: {
            normals.extend(samples.iter().map(|s| s.normal));
            normals
        },
        face_ids: if whole {
            Vec::new()
        } else {
            faces.map(|f| f as u32).collect()
        },
    })
}

/// [`evaluate`] through the displacement step: `p + scale · h(tc) · n` with
/// the owner's normal and texture coordinate on shared edges and corners
/// ([`crate::cpu::displace`]). `data` must be built with this [`Patches`]'
/// layout ([`displacement_data`]). With [`DisplaceData::off`] the result is
/// [`evaluate`]'s, bit for bit.
pub fn evaluate_displaced(
    patches: &Patches,
    level: u32,
    data: &DisplaceData,
) -> Result<Tessellation, TessError> {
    displaced_window(patches, level, data, 0..patches.face_class.len(), true)
}

/// [`evaluate_displaced`] of the faces `faces` only (`face_ids` = the
/// range), each face's samples bit for bit the same: a streamed chunk
/// (`tessellate::Session::run_chunked`).
pub fn evaluate_displaced_faces(
    patches: &Patches,
    level: u32,
    data: &DisplaceData,
    faces: std::ops::Range<usize>,
) -> Result<Tessellation, TessError> {
    displaced_window(patches, level, data, faces, false)
}

fn displaced_window(
    patches: &Patches,
    level: u32,
    data: &DisplaceData,
    faces: std::ops::Range<usize>,
    whole: bool,
) -> Result<Tessellation, TessError> {
    let kernels = patches.scheme;
    let Some(eval) = kernels.eval_displaced else {
        return Err(facet_error(kernels));
    };
    let inputs = displace_inputs(data);
    evaluate_grid(patches, level, faces, whole, |f, class, iu, iv| {
        let cp_base = patches.cp_offsets[f];
        eval(
            &inputs,
            &patches.control_points,
            f as u32,
            class,
            cp_base,
            iu,
            iv,
            level,
        )
    })
}

/// The displacement arrays for the CPU layout of `patches` (control points
/// in face order).
pub fn displacement_data(
    mesh: &Mesh,
    topo: &Topology,
    patches: &Patches,
    d: &Displacement,
) -> Result<DisplaceData, TessError> {
    Ok(crate::cpu::displace::build(
        mesh,
        topo,
        &patches.face_class,
        &patches.cp_offsets[..patches.face_class.len()],
        d,
    )?)
}

/// The displacement arrays of a triangle scheme for the CPU layout of
/// `patches` (built by [`construct_tri`] from `tri`, which was made from
/// `mesh`).
pub fn displacement_data_tri(
    mesh: &Mesh,
    tri: &crate::mesh::trimesh::TriMesh,
    patches: &Patches,
    d: &Displacement,
) -> Result<DisplaceData, TessError> {
    Ok(crate::cpu::displace::build_tri(
        mesh,
        tri,
        &patches.face_class,
        &patches.cp_offsets[..patches.face_class.len()],
        d,
    )?)
}

/// Start of each vertex's vertex-stage outputs (`rows_per_n·n + rows_fixed`
/// points each, none for an unused vertex), with the total as the last
/// entry and returned on its own: the layout of `vertex_out` on every backend.
pub fn vertex_out_offsets(topo: &Topology, scheme: &SchemeKernels) -> (Vec<u32>, u32) {
    let mut offsets = Vec::with_capacity(topo.valence.len() + 1);
    let mut total = 0u32;
    for &n in &topo.valence {
        offsets.push(total);
        if n > 0 {
            total += scheme.rows_per_n * n + scheme.rows_fixed;
        }
    }
    offsets.push(total);
    (offsets, total)
}

/// Patch stage of a triangle scheme (`pn`, `phong`): per triangle, from its
/// corners' positions and unit normals. There is no vertex stage.
pub fn construct_tri(
    mesh: &crate::mesh::trimesh::TriMesh,
    scheme: &'static SchemeKernels,
) -> Result<Patches, TessError> {
    if scheme.sides != 3 {
        return Err(facet_error(scheme));
    }
    let class = &scheme.classes[0];
    let faces = mesh.triangles.len();
    let corner_vertex: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let cp_offsets: Vec<u32> = (0..=faces as u32)
        .map(|f| f * class.control_points)
        .collect();
    let mut control_points = vec![Vec3::ZERO; faces * class.control_points as usize];
    let inputs = Inputs {
        positions: &mesh.positions,
        valence: &[],
        ring_offsets: &[],
        ring: &[],
        vertex_out_offsets: &[],
        vertex_out: &[],
        corner_vertex: &corner_vertex,
        corner_sector: &[],
        normals: &mesh.normals,
        tags: &mesh.crease_tags.tags,
        crease: &mesh.crease_tags.crease,
        corner_side: &mesh.crease_tags.corner_side,
        face_edges: &[],
        edge_factors: &[],
        adaptive: &[],
        table: kernels::table(),
        ..Default::default()
    };
    control_points
        .par_chunks_mut(class.control_points as usize)
        .enumerate()
        .for_each(|(f, out)| (class.patch)(&inputs, out, f as u32, 0));
    Ok(Patches {
        scheme,
        face_class: vec![0; faces],
        cp_offsets,
        control_points,
        vertex_out_offsets: Vec::new(),
        vertex_out: Vec::new(),
    })
}

/// The triangle mesh a triangle scheme runs on: quads split when asked,
/// normals from the OBJ or area-weighted, crease tags from `tags`.
pub fn tri_mesh(
    mesh: &Mesh,
    split_quads: bool,
    tags: Option<&crate::mesh::tags::TagFile>,
) -> Result<crate::mesh::trimesh::TriMesh, TessError> {
    let tri = crate::mesh::trimesh::TriMesh::from_mesh(
        mesh,
        &crate::mesh::trimesh::TriOptions {
            split_quads,
            ..Default::default()
        },
    )?;
    Ok(match tags {
        Some(t) => tri.with_tags(t)?,
        None => tri,
    })
}
