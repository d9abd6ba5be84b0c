//! Streaming: [`Session::run_chunked`] hands the result to the caller in
//! chunks of whole patches, so a writer can put each chunk on disk before the
//! next is evaluated and peak memory stays bounded whatever the level and the
//! mesh size (the reliability issue: `--level 200` on `righthanded_L3` used
//! to abort allocating 27 GB before writing a byte).
//!
//! What streams:
//! - every uniform grid request — quad and triangle schemes, with or
//!   without displacement, on the CPU, on wgpu, and for quad schemes
//!   through the Vulkan tessellation harness (GLSL, HLSL). The mesh is
//!   constructed (uploaded) once ([`GridSource`]), then each window of
//!   whole faces is evaluated into a buffer of at most [`CHUNK_SAMPLES`]
//!   samples (on a GPU: only the window's patches are dispatched and read
//!   back) and handed on before the next;
//! - adaptive requests on the CPU and on wgpu: every face classified once
//!   ([`AdaptiveRun`]; on wgpu the classify pass, its levels read back:
//!   each face's edge levels, bucket and sample offset), then windows of
//!   whole faces of at most [`CHUNK_SAMPLES`] samples (a quarter on wgpu),
//!   each an [`Output::Instanced`] naming its faces;
//! - refined meshes (triangles and n-gons; semi-sharp creases; isolated
//!   extraordinary vertices), of one depth or feature-adaptive of several:
//!   each depth's refined mesh constructed once (the depths sharing the
//!   session's one device, as [`Session::run`] runs them), then windows of
//!   whole base blocks (a quad, or an n-gon's sub-face) of at most the
//!   chunk's samples, every depth's refined faces counted, evaluated and
//!   assembled into the base layout. Where depths meet, a transition takes
//!   the deepest side's sample across blocks: a window also evaluates its
//!   halo (the blocks sharing a base vertex with it) below the shallowest
//!   depth — on the CPU only their border leaves — for those samples, and
//!   emits none of it, so the halo adds a few blocks' border leaves to a
//!   window, nothing of the whole result;
//! - the Vulkan harness's captured triangles (triangle schemes, adaptive
//!   draws): windows of whole faces, only their patches drawn.
//!
//! What comes as one chunk, the [`Session::run`] result (its readback is
//! chunked inside, but the whole result is held once): only a refinement
//! whose leaves are not numbered block by block ([`refined::block_faces`]),
//! a fallback — the refinements built here always are.
//!
//! Each chunk passes the same non-finite check as [`Session::run`]; the
//! samples are [`Session::run`]'s bit for bit.

use super::backend::{self, GridSource};
use super::refined;
use super::request::{Resolved, Validated};
use super::{Backend, Error, Output, Sampling, Session};
use crate::cpu::adaptive::{AdaptiveRun, AdaptiveTessellation};
use crate::cpu::Tessellation;
use std::ops::Range;

/// Samples per streamed chunk: 4 Mi samples are 96 MiB of positions and
/// normals, a whole number of patches (at least one) per chunk.
pub const CHUNK_SAMPLES: usize = 1 << 22;

impl Session {
    /// [`Session::run`] in chunks: `sink` receives consecutive parts of the
    /// result (for a grid: whole faces in face order, `face_ids` naming
    /// them), each before the next is evaluated. `max_samples` bounds a
    /// chunk (0: [`CHUNK_SAMPLES`] on the CPU, a quarter of it on a GPU).
    /// Stops at the first error, the sink's included.
    pub fn run_chunked<E>(
        &mut self,
        v: &Validated<'_>,
        max_samples: usize,
        mut sink: impl FnMut(&Output) -> Result<(), E>,
    ) -> Result<(), ChunkError<E>>
    where
        E: std::fmt::Debug,
    {
        let sink = &mut sink;
        match (&v.request.sampling, &v.adaptive, v.request.backend) {
            (Sampling::Uniform(n), _, _) if GridSource::streams(v) => {
                grid_chunked(self, v, *n, max_samples, sink)
            }
            (Sampling::Uniform(_), None, _) if v.refined().is_some() => {
                refined_chunked(self, v, max_samples, sink)
            }
            (Sampling::Adaptive(_), Some(a), Backend::Cpu) => adaptive_cpu(v, a, max_samples, sink),
            #[cfg(feature = "gpu")]
            (Sampling::Adaptive(_), Some(a), Backend::Wgpu) => {
                adaptive_wgpu(self, v, a, max_samples, sink)
            }
            #[cfg(feature = "vulkan")]
            (_, _, Backend::VulkanGlsl | Backend::VulkanHlsl) if captured(v) => {
                captured_chunked(self, v, max_samples, sink)
            }
            _ => {
                let out = self.run(v).map_err(ChunkError::Tess)?;
                sink(&out).map_err(ChunkError::Sink)
            }
        }
    }
}

/// The loop every stream runs: windows `first..end` of `count` units (faces,
/// or a refined mesh's base blocks), `end = next(first)` (at least one unit),
/// each made by `chunk(window, recycled)` — `recycled` is the previous
/// chunk, whose buffers a backend that writes in place reuses —, checked
/// for non-finite samples (named by their place in the whole result) and
/// handed to `sink` before the next window is evaluated.
fn stream<E>(
    v: &Validated<'_>,
    count: usize,
    mut next: impl FnMut(usize) -> usize,
    mut chunk: impl FnMut(Range<usize>, Output) -> Result<Output, Error>,
    sink: &mut impl FnMut(&Output) -> Result<(), E>,
) -> Result<(), ChunkError<E>>
where
    E: std::fmt::Debug,
{
    let (mut first, mut written) = (0, 0);
    let mut recycled = Output::Grid(Tessellation::default());
    while first < count {
        let end = next(first).clamp(first + 1, count);
        let out = chunk(first..end, recycled).map_err(ChunkError::Tess)?;
        super::finite(v, &out, written).map_err(ChunkError::Tess)?;
        sink(&out).map_err(ChunkError::Sink)?;
        written += out.samples();
        recycled = out;
        first = end;
    }
    Ok(())
}

/// `next` for [`stream`] when unit `u`'s samples start at `offsets[u]`
/// (`units + 1` entries): the units whose samples end within `limit` of
/// the window's start.
fn fitting(offsets: &[usize], limit: usize) -> impl Fn(usize) -> usize + '_ {
    move |first| {
        let base = offsets[first];
        first
            + offsets[first..]
                .partition_point(|&o| o - base <= limit)
                .saturating_sub(1)
    }
}

/// `max_samples`, or `default` when it is 0.
fn or_default(max_samples: usize, default: usize) -> usize {
    if max_samples == 0 {
        default
    } else {
        max_samples
    }
}

/// A uniform grid request: constructed (uploaded) once ([`GridSource`]),
/// then windows of whole faces of at most the chunk's samples, their holes
/// left out, into the recycled tessellation (the CPU writes in place).
fn grid_chunked<E>(
    session: &mut Session,
    v: &Validated<'_>,
    level: u32,
    max_samples: usize,
    sink: &mut impl FnMut(&Output) -> Result<(), E>,
) -> Result<(), ChunkError<E>>
where
    E: std::fmt::Debug,
{
    let source = GridSource::new(v, session).map_err(ChunkError::Tess)?;
    let per = (v.kernels.grid_len)(level) as usize;
    let step = (or_default(max_samples, source.chunk_samples()) / per.max(1)).max(1);
    let keep: Option<Vec<bool>> = v.no_limit().map(super::emitting);
    let chunk = |faces, recycled: Output| {
        let mut t = recycled.into_grid().unwrap_or_default();
        source.evaluate(level, faces, &mut t)?;
        if let Some(keep) = &keep {
            t.retain_faces(keep);
        }
        Ok(Output::Grid(t))
    };
    stream(v, source.faces(), |first| first + step, chunk, sink)
}

/// An adaptive request on the CPU: classified once ([`AdaptiveRun::new`]:
/// a few words per face), then evaluated window by window
/// ([`adaptive_windows`]).
fn adaptive_cpu<E>(
    v: &Validated<'_>,
    a: &Resolved,
    max_samples: usize,
    sink: &mut impl FnMut(&Output) -> Result<(), E>,
) -> Result<(), ChunkError<E>>
where
    E: std::fmt::Debug,
{
    let tess = |e: Error| ChunkError::Tess(e);
    let patches = backend::cpu_patches(v).map_err(|e| tess(e.into()))?;
    let displace = backend::cpu_displacement(v, &patches).map_err(tess)?;
    let run = AdaptiveRun::new(
        &patches,
        v.domain.edges(),
        &a.adaptive,
        a.max_level,
        displace.as_ref(),
    )
    .map_err(|e| tess(e.into()))?;
    let limit = or_default(max_samples, CHUNK_SAMPLES);
    adaptive_windows(v, run.offsets(), limit, sink, |faces, t| {
        Ok(run.evaluate(faces, t)?)
    })
}

/// An adaptive request on wgpu: uploaded and classified once
/// (`GpuMesh::classify_adaptive`: the levels read back, 5 words a patch),
/// then each window's buckets dispatched and read back
/// (`GpuMesh::evaluate_classified`), a quarter of the CPU's window (as
/// for grids: [`GridSource::chunk_samples`]).
#[cfg(feature = "gpu")]
fn adaptive_wgpu<E>(
    session: &mut Session,
    v: &Validated<'_>,
    a: &Resolved,
    max_samples: usize,
    sink: &mut impl FnMut(&Output) -> Result<(), E>,
) -> Result<(), ChunkError<E>>
where
    E: std::fmt::Debug,
{
    let tess = |e: Error| ChunkError::Tess(e);
    let gpu = session.gpu().map_err(tess)?;
    let mesh = backend::wgpu_mesh(v, gpu).map_err(tess)?;
    let classified = mesh
        .classify_adaptive(v.domain.edges(), &a.adaptive, a.max_level)
        .map_err(|e| tess(e.into()))?;
    let limit = or_default(max_samples, CHUNK_SAMPLES / 4);
    adaptive_windows(v, classified.offsets(), limit, sink, |faces, t| {
        *t = mesh.evaluate_classified(&classified, faces)?;
        Ok(())
    })
}

/// The windows of a classified adaptive run whose face `f`'s grid starts at
/// sample `offsets[f]`: whole faces of at most `limit` samples, each
/// evaluated into the recycled tessellation, its holes left out, handed on
/// as an [`Output::Instanced`] naming its faces.
fn adaptive_windows<E>(
    v: &Validated<'_>,
    offsets: &[usize],
    limit: usize,
    sink: &mut impl FnMut(&Output) -> Result<(), E>,
    mut evaluate: impl FnMut(Range<usize>, &mut AdaptiveTessellation) -> Result<(), Error>,
) -> Result<(), ChunkError<E>>
where
    E: std::fmt::Debug,
{
    let keep: Option<Vec<bool>> = v.no_limit().map(super::emitting);
    let chunk = |faces, recycled: Output| {
        let mut t = match recycled {
            Output::Instanced(t) => t,
            _ => AdaptiveTessellation::default(),
        };
        evaluate(faces, &mut t)?;
        if let Some(keep) = &keep {
            t.retain_faces(keep);
        }
        Ok(Output::Instanced(t))
    };
    let faces = offsets.len().saturating_sub(1);
    stream(v, faces, fitting(offsets, limit), chunk, sink)
}

/// A refined request (a mesh with triangles or n-gons, semi-sharp creases;
/// a feature-adaptive refinement of several depths too): each depth's
/// refined mesh constructed (uploaded) once ([`GridSource`], the depths
/// sharing the session's device as [`Session::run`] does), then windows of
/// whole base blocks — a base quad, or one sub-face of an n-gon — whose
/// refined faces' grids (every depth's) fit the chunk, each evaluated,
/// assembled into the base layout ([`refined::assemble_blocks`]) and
/// handed on. With several depths, a window's transitions take the deepest
/// side's sample across blocks: the window's halo (the blocks sharing a
/// base vertex with it, [`refined::Neighbours::halo`]) is evaluated too,
/// for its border samples only, and not emitted. Leaves not numbered block
/// by block come whole.
fn refined_chunked<E>(
    session: &mut Session,
    v: &Validated<'_>,
    max_samples: usize,
    sink: &mut impl FnMut(&Output) -> Result<(), E>,
) -> Result<(), ChunkError<E>>
where
    E: std::fmt::Debug,
{
    let tess = |e: Error| ChunkError::Tess(e);
    let depths: Option<Vec<_>> = v
        .parts()
        .map(|p| {
            let r = p.refined()?;
            Some((p, r, refined::block_faces(r)?))
        })
        .collect();
    let Some(depths) = depths.filter(|d| !d.is_empty()) else {
        let out = session.run(v).map_err(tess)?;
        return sink(&out).map_err(ChunkError::Sink);
    };
    let device = backend::device(session, v.request.backend).map_err(tess)?;
    let sources = depths
        .iter()
        .map(|(p, _, _)| GridSource::on(p, device))
        .collect::<Result<Vec<_>, _>>()
        .map_err(tess)?;
    let blocks = depths[0].2.len();
    let limit = or_default(max_samples, sources[0].chunk_samples());
    // Block b's refined faces' samples, every depth's, start at
    // offsets[b]: each depth's faces are numbered block by block.
    let per: Vec<usize> = depths
        .iter()
        .map(|(_, r, _)| (v.kernels.grid_len)(r.leaf_level) as usize)
        .collect();
    let mut offsets = vec![0usize; blocks + 1];
    for b in 0..blocks {
        let faces: usize = depths
            .iter()
            .zip(&per)
            .map(|((_, _, f), per)| f[b].len() * per)
            .sum();
        offsets[b + 1] = offsets[b] + faces;
    }
    let neighbours = (depths.len() > 1).then(|| refined::Neighbours::new(depths[0].1));
    let mut grids: Vec<Tessellation> = depths.iter().map(|_| Tessellation::default()).collect();
    // Per depth, the faces that emit (the CPU evaluates only those).
    let emits: Vec<Option<Vec<bool>>> = depths
        .iter()
        .map(|(p, _, _)| p.no_limit().map(super::emitting))
        .collect();
    let mut scratch = Tessellation::default();
    let chunk = |window: Range<usize>, previous: Output| {
        // The previous chunk is handed on: nothing of it is reused here.
        drop(previous);
        let halo = neighbours
            .as_ref()
            .map_or_else(Vec::new, |n| n.halo(window.clone()));
        for (k, (((_, r, faces), source), (t, emits))) in depths
            .iter()
            .zip(&sources)
            .zip(grids.iter_mut().zip(&emits))
            .enumerate()
        {
            // The window's refined faces of this depth, and (below the
            // shallowest depth, whose samples never win a transition) the
            // halo's, into one tessellation; the CPU evaluates only those
            // that emit, of the halo only its blocks' border leaves.
            let own = faces[window.start].start..faces[window.end - 1].end;
            let mut runs = vec![own.clone()];
            if k > 0 {
                runs.extend(halo.iter().map(|&b| faces[b].clone()));
            }
            let keep = |f: usize| {
                emits
                    .as_ref()
                    .is_none_or(|e| e.get(f).copied().unwrap_or(true))
                    && (own.contains(&f) || r.on_block_border(f))
            };
            source.evaluate_runs(r.leaf_level, &runs, &keep, t, &mut scratch)?;
        }
        let parts: Vec<refined::Part<'_>> = depths
            .iter()
            .zip(&grids)
            .map(|((p, r, _), t)| refined::Part {
                domain: r,
                t,
                no_limit: p.topology().map_or(&[][..], |t| &t.no_limit[..]),
            })
            .collect();
        let mut out = refined::assemble_blocks(&parts, window, &halo)?;
        if let Output::Polygons(p) = &mut out {
            p.boundary_open_edges = v.refined_open_edges();
        }
        Ok(out)
    };
    match &neighbours {
        None => stream(v, blocks, fitting(&offsets, limit), chunk, sink),
        Some(n) => {
            // A halo block costs its grids below the shallowest depth.
            let halo_cost: Vec<usize> = (0..blocks)
                .map(|b| {
                    depths[1..]
                        .iter()
                        .zip(&per[1..])
                        .map(|((_, _, f), per)| f[b].len() * per)
                        .sum()
                })
                .collect();
            let next = with_halo(n, &offsets, &halo_cost, limit);
            stream(v, blocks, next, chunk, sink)
        }
    }
}

/// `next` for [`stream`] over a feature-adaptive refinement's blocks: the
/// blocks from the window's start whose samples (`offsets`, as for
/// [`fitting`]) and their halo's (`halo_cost` each, the halo as
/// [`refined::Neighbours::halo`]) fit within `limit`, at least one.
fn with_halo<'a>(
    n: &'a refined::Neighbours<'_>,
    offsets: &'a [usize],
    halo_cost: &'a [usize],
    limit: usize,
) -> impl FnMut(usize) -> usize + 'a {
    // The window (stamp) in which a block was counted in the halo.
    let mut in_halo = vec![usize::MAX; halo_cost.len()];
    let mut around: Vec<usize> = Vec::new();
    move |first| {
        let (mut end, mut total) = (first, 0usize);
        while end < halo_cost.len() {
            let mut add = offsets[end + 1] - offsets[end];
            if in_halo[end] == first {
                add -= halo_cost[end].min(add);
            }
            around.clear();
            around.extend(
                n.around(end)
                    .filter(|&b| !(first..=end).contains(&b) && in_halo[b] != first),
            );
            around.sort_unstable();
            around.dedup();
            add += around.iter().map(|&b| halo_cost[b]).sum::<usize>();
            if end > first && total + add > limit {
                break;
            }
            for &b in &around {
                in_halo[b] = first;
            }
            total += add;
            end += 1;
        }
        end
    }
}

/// Whether the Vulkan harness captures the request's triangles (triangle
/// schemes, every adaptive draw) rather than reading back grids.
#[cfg(feature = "vulkan")]
fn captured(v: &Validated<'_>) -> bool {
    v.adaptive.is_some() || matches!(v.domain, super::request::Domain::Triangles(_))
}

/// The Vulkan harness's captured triangles: the mesh uploaded and its
/// pipelines built once, then windows of whole faces, only their patches
/// drawn and their triangles read back (`VkMesh::evaluate_triangles_faces`,
/// `VkMesh::evaluate_adaptive_faces`), each window at most a quarter of
/// [`CHUNK_SAMPLES`] captured vertices by the capture's own bound per
/// patch.
#[cfg(feature = "vulkan")]
fn captured_chunked<E>(
    session: &mut Session,
    v: &Validated<'_>,
    max_samples: usize,
    sink: &mut impl FnMut(&Output) -> Result<(), E>,
) -> Result<(), ChunkError<E>>
where
    E: std::fmt::Debug,
{
    let tess = |e: Error| ChunkError::Tess(e);
    let vk = session.vulkan().map_err(tess)?;
    let m = backend::vk_mesh(v, vk).map_err(tess)?;
    let level = match v.request.sampling {
        Sampling::Uniform(n) => n,
        Sampling::Adaptive(_) => 1,
    };
    let per = m.captured_vertices_per_patch(level).max(1) as usize;
    let step = (or_default(max_samples, CHUNK_SAMPLES / 4) / per).max(1);
    let chunk = |faces: Range<usize>, _| {
        let mut c = match v.adaptive {
            Some(_) => m.evaluate_adaptive_faces(faces),
            None => m.evaluate_triangles_faces(level, faces),
        }?;
        if let Some(no_limit) = v.no_limit() {
            c.clear_patches(no_limit);
        }
        Ok(Output::Captured(c))
    };
    stream(v, m.patch_faces.len(), |first| first + step, chunk, sink)
}

/// Why [`Session::run_chunked`] stopped.
#[derive(Debug, thiserror::Error)]
pub enum ChunkError<E: std::fmt::Debug> {
    #[error(transparent)]
    Tess(Error),
    #[error("the chunk sink failed: {0:?}")]
    Sink(E),
}
