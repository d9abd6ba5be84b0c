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
//! - refined meshes of one depth (triangles and n-gons; semi-sharp creases
//!   refined uniformly): the refined mesh constructed once, then windows of
//!   whole base blocks (a quad, or an n-gon's sub-face), their refined
//!   faces evaluated and assembled into the base layout;
//! - the Vulkan harness's captured triangles (triangle schemes, adaptive
//!   draws): windows of whole faces, only their patches drawn.
//!
//! What comes as one chunk, the [`Session::run`] result: feature-adaptive
//! refinements (several depths: a transition takes the deepest side's
//! sample across blocks); its readback is chunked inside, but the whole
//! result is held once.
//!
//! Each chunk passes the same non-finite check as [`Session::run`]; the
//! samples are [`Session::run`]'s bit for bit.

use super::backend::{self, GridSource};
use super::refined;
use super::request::{Resolved, Validated};
use super::{Backend, Error, Output, Sampling, Session};
use crate::cpu::adaptive::{AdaptiveRun, AdaptiveTessellation};
use crate::cpu::Tessellation;

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
        let level = match (&v.request.sampling, &v.adaptive, v.request.backend) {
            (Sampling::Uniform(n), _, _) if GridSource::streams(v) => *n,
            (Sampling::Uniform(_), None, _) if v.refined().is_some() && v.deeper.is_empty() => {
                return refined_chunked(self, v, max_samples, &mut sink);
            }
            (Sampling::Adaptive(_), Some(a), Backend::Cpu) => {
                return adaptive_cpu(v, a, max_samples, &mut sink);
            }
            #[cfg(feature = "gpu")]
            (Sampling::Adaptive(_), Some(a), Backend::Wgpu) => {
                return adaptive_wgpu(self, v, a, max_samples, &mut sink);
            }
            #[cfg(feature = "vulkan")]
            (_, _, Backend::VulkanGlsl | Backend::VulkanHlsl) if captured(v) => {
                return captured_chunked(self, v, max_samples, &mut sink);
            }
            _ => {
                let out = self.run(v).map_err(ChunkError::Tess)?;
                return sink(&out).map_err(ChunkError::Sink);
            }
        };
        let source = GridSource::new(v, self).map_err(ChunkError::Tess)?;
        let per = (v.kernels.grid_len)(level) as usize;
        let limit = if max_samples == 0 {
            source.chunk_samples()
        } else {
            max_samples
        };
        let step = (limit / per.max(1)).max(1);
        let keep: Option<Vec<bool>> = v.no_limit().map(super::emitting);
        let faces = source.faces();
        let mut t = Tessellation::default();
        let (mut first, mut written) = (0, 0);
        while first < faces {
            let end = (first + step).min(faces);
            source
                .evaluate(level, first..end, &mut t)
                .map_err(ChunkError::Tess)?;
            if let Some(keep) = &keep {
                t.retain_faces(keep);
            }
            let out = Output::Grid(std::mem::take(&mut t));
            super::finite(v, &out, written).map_err(ChunkError::Tess)?;
            sink(&out).map_err(ChunkError::Sink)?;
            // The next chunk reuses the buffers (the CPU writes in place).
            if let Output::Grid(back) = out {
                written += back.positions.len();
                t = back;
            }
            first = end;
        }
        Ok(())
    }
}

/// An adaptive request on the CPU, streamed: classified once
/// ([`AdaptiveRun::new`]: a few words per face), then evaluated window by
/// window ([`windows`]).
fn adaptive_cpu<E>(
    v: &Validated<'_>,
    a: &Resolved,
    limit: usize,
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
    let limit = if limit == 0 { CHUNK_SAMPLES } else { limit };
    windows(v, run.offsets(), limit, sink, |faces, t| {
        Ok(run.evaluate(faces, t)?)
    })
}

/// An adaptive request on wgpu, streamed: uploaded and classified once
/// (`GpuMesh::classify_adaptive`: the levels read back, 5 words a patch),
/// then each window's buckets dispatched and read back
/// (`GpuMesh::evaluate_classified`), a quarter of the CPU's window (as
/// for grids: [`GridSource::chunk_samples`]).
#[cfg(feature = "gpu")]
fn adaptive_wgpu<E>(
    session: &mut Session,
    v: &Validated<'_>,
    a: &Resolved,
    limit: usize,
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
    let limit = if limit == 0 { CHUNK_SAMPLES / 4 } else { limit };
    windows(v, classified.offsets(), limit, sink, |faces, t| {
        *t = mesh.evaluate_classified(&classified, faces)?;
        Ok(())
    })
}

/// A refined request of one depth (a mesh with triangles or n-gons; creases
/// refined uniformly), streamed: the refined mesh constructed (uploaded)
/// once ([`GridSource`]), then windows of whole base blocks — a base quad,
/// or one sub-face of an n-gon — whose refined faces' grids fit the chunk,
/// each evaluated, assembled into the base layout
/// ([`refined::assemble_blocks`]) and handed on. A feature-adaptive
/// refinement (several depths, whose transitions are taken from the
/// deepest side across blocks), or leaves not numbered block by block,
/// come whole.
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
    let (Some(r), Some(block_faces)) = (v.refined(), v.refined().and_then(refined::block_faces))
    else {
        let out = session.run(v).map_err(tess)?;
        return sink(&out).map_err(ChunkError::Sink);
    };
    let source = GridSource::new(v, session).map_err(tess)?;
    let level = r.leaf_level;
    let per = (v.kernels.grid_len)(level) as usize;
    let limit = if max_samples == 0 {
        source.chunk_samples()
    } else {
        max_samples
    };
    let no_limit = v.topology().map_or(&[][..], |t| &t.no_limit[..]);
    let blocks = block_faces.len();
    let mut t = Tessellation::default();
    let (mut first, mut written) = (0, 0);
    while first < blocks {
        // The blocks whose refined faces' grids fit `limit` samples, at
        // least one.
        let start = block_faces[first].start;
        let mut end = first + 1;
        while end < blocks && (block_faces[end].end - start) * per <= limit {
            end += 1;
        }
        let faces = start..block_faces[end - 1].end;
        source.evaluate(level, faces, &mut t).map_err(tess)?;
        let part = refined::Part {
            domain: r,
            t: &t,
            no_limit,
        };
        let mut out = refined::assemble_blocks(&[part], first..end).map_err(tess)?;
        if let Output::Polygons(p) = &mut out {
            p.boundary_open_edges = v.refined_open_edges();
        }
        super::finite(v, &out, written).map_err(tess)?;
        sink(&out).map_err(ChunkError::Sink)?;
        written += out.counts().1;
        first = end;
    }
    Ok(())
}

/// Whether the Vulkan harness captures the request's triangles (triangle
/// schemes, every adaptive draw) rather than reading back grids.
#[cfg(feature = "vulkan")]
fn captured(v: &Validated<'_>) -> bool {
    v.adaptive.is_some() || matches!(v.domain, super::request::Domain::Triangles(_))
}

/// The Vulkan harness's captured triangles, streamed: the mesh uploaded
/// and its pipelines built once, then windows of whole faces, only their
/// patches drawn and their triangles read back
/// (`VkMesh::evaluate_triangles_faces`, `VkMesh::evaluate_adaptive_faces`),
/// each window at most a quarter of [`CHUNK_SAMPLES`] captured vertices
/// by the capture's own bound per patch.
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
    let language = backend::vk_language(v.request.backend);
    let vk = session.vulkan().map_err(tess)?;
    let m = backend::vk_mesh(v, language, vk).map_err(tess)?;
    let level = match v.request.sampling {
        Sampling::Uniform(n) => n,
        Sampling::Adaptive(_) => 1,
    };
    let limit = if max_samples == 0 {
        CHUNK_SAMPLES / 4
    } else {
        max_samples
    };
    let per = m.captured_vertices_per_patch(level).max(1) as usize;
    let step = (limit / per).max(1);
    let faces = m.patch_faces.len();
    let (mut first, mut written) = (0, 0);
    while first < faces {
        let end = (first + step).min(faces);
        let mut c = match v.adaptive {
            Some(_) => m.evaluate_adaptive_faces(first..end),
            None => m.evaluate_triangles_faces(level, first..end),
        }
        .map_err(|e| tess(e.into()))?;
        if let Some(no_limit) = v.no_limit() {
            c.clear_patches(no_limit);
        }
        let out = Output::Captured(c);
        super::finite(v, &out, written).map_err(tess)?;
        sink(&out).map_err(ChunkError::Sink)?;
        written += out.counts().1;
        first = end;
    }
    Ok(())
}

/// The window loop of a classified adaptive run whose face `f`'s grid
/// starts at sample `offsets[f]`: windows of whole faces of at most `limit`
/// samples (at least one face), each evaluated into the reused
/// tessellation, its holes left out, checked for non-finite samples and
/// handed on as an [`Output::Instanced`] naming its faces.
fn windows<E>(
    v: &Validated<'_>,
    offsets: &[usize],
    limit: usize,
    sink: &mut impl FnMut(&Output) -> Result<(), E>,
    mut evaluate: impl FnMut(std::ops::Range<usize>, &mut AdaptiveTessellation) -> Result<(), Error>,
) -> Result<(), ChunkError<E>>
where
    E: std::fmt::Debug,
{
    let faces = offsets.len().saturating_sub(1);
    let keep: Option<Vec<bool>> = v.no_limit().map(super::emitting);
    let mut t = AdaptiveTessellation::default();
    let (mut first, mut written) = (0, 0);
    while first < faces {
        // The faces whose grids end within `limit` samples of `first`'s
        // start, at least one.
        let base = offsets[first];
        let fit = offsets[first..].partition_point(|&o| o - base <= limit);
        let end = (first + fit.saturating_sub(1)).clamp(first + 1, faces);
        evaluate(first..end, &mut t).map_err(ChunkError::Tess)?;
        if let Some(keep) = &keep {
            t.retain_faces(keep);
        }
        let out = Output::Instanced(std::mem::take(&mut t));
        super::finite(v, &out, written).map_err(ChunkError::Tess)?;
        sink(&out).map_err(ChunkError::Sink)?;
        // The next window reuses the buffers (the CPU writes in place).
        if let Output::Instanced(back) = out {
            written += back.positions.len();
            t = back;
        }
        first = end;
    }
    Ok(())
}

/// Why [`Session::run_chunked`] stopped.
#[derive(Debug, thiserror::Error)]
pub enum ChunkError<E: std::fmt::Debug> {
    #[error(transparent)]
    Tess(Error),
    #[error("the chunk sink failed: {0:?}")]
    Sink(E),
}
