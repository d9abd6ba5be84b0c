//! Streaming: [`Session::run_chunked`] hands the result to the caller in
//! chunks of whole patches, so a writer can put each chunk on disk before the
//! next is evaluated and peak memory stays bounded whatever the level and the
//! mesh size (the reliability issue: `--level 200` on `righthanded_L3` used
//! to abort allocating 27 GB before writing a byte).
//!
//! What streams today: uniform tessellation of quad or triangle schemes on
//! the CPU without displacement or refinement, the common case: the patches
//! are constructed once, then [`cpu::evaluate_faces_into`] fills one reused
//! buffer of at most [`CHUNK_SAMPLES`] samples per chunk. Every other request
//! (GPU backends, adaptive, displaced, refined) comes as one chunk, the
//! [`Session::run`] result; their readback is chunked inside, but the whole
//! result is still held once. Each chunk passes the same non-finite check as
//! [`Session::run`]; the samples are [`Session::run`]'s bit for bit.

use super::request::Validated;
use super::{Backend, Error, Output, Sampling, Session};
use crate::cpu::{self, Tessellation};

/// Samples per streamed chunk: 4 Mi samples are 96 MiB of positions and
/// normals, a whole number of patches (at least one) per chunk.
pub const CHUNK_SAMPLES: usize = 1 << 22;

impl Session {
    /// [`Session::run`] in chunks: `sink` receives consecutive parts of the
    /// result (for a grid: whole faces in face order, `face_ids` naming
    /// them), each before the next is evaluated. `max_samples` bounds a
    /// chunk (0: [`CHUNK_SAMPLES`]). Stops at the first error, the sink's
    /// included.
    pub fn run_chunked<E>(
        &mut self,
        v: &Validated<'_>,
        max_samples: usize,
        mut sink: impl FnMut(&Output) -> Result<(), E>,
    ) -> Result<(), ChunkError<E>>
    where
        E: std::fmt::Debug,
    {
        let level = match v.request.sampling {
            Sampling::Uniform(n) => Some(n),
            Sampling::Adaptive(_) => None,
        };
        let streams = v.request.backend == Backend::Cpu
            && v.request.displacement.is_none()
            && v.refined().is_none();
        let (Some(level), true) = (level, streams) else {
            let out = self.run(v).map_err(ChunkError::Tess)?;
            return sink(&out).map_err(ChunkError::Sink);
        };
        let patches = super::backend::cpu_patches(v).map_err(|e| ChunkError::Tess(e.into()))?;
        let per = (v.kernels.grid_len)(level) as usize;
        let limit = if max_samples == 0 {
            CHUNK_SAMPLES
        } else {
            max_samples
        };
        let step = (limit / per.max(1)).max(1);
        let keep: Option<Vec<bool>> = v.no_limit().map(|n| n.iter().map(|&x| !x).collect());
        let faces = patches.face_class.len();
        let mut t = Tessellation::default();
        let mut first = 0;
        while first < faces {
            let end = (first + step).min(faces);
            cpu::evaluate_faces_into(&patches, level, first..end, &mut t)
                .map_err(|e| ChunkError::Tess(e.into()))?;
            if let Some(keep) = &keep {
                t.retain_faces(keep);
            }
            let out = Output::Grid(std::mem::take(&mut t));
            super::finite(v, &out, first * per).map_err(ChunkError::Tess)?;
            sink(&out).map_err(ChunkError::Sink)?;
            // The next chunk reuses the buffers.
            if let Output::Grid(back) = out {
                t = back;
            }
            first = end;
        }
        Ok(())
    }
}

/// Why [`Session::run_chunked`] stopped.
#[derive(Debug, thiserror::Error)]
pub enum ChunkError<E: std::fmt::Debug> {
    #[error(transparent)]
    Tess(Error),
    #[error("the chunk sink failed: {0:?}")]
    Sink(E),
}
