//! Captured draws: triangle schemes ([`VkMesh::evaluate_triangles`]) and
//! every adaptive draw ([`VkMesh::evaluate_adaptive`]) record the triangles
//! the hardware tessellator emitted through the capture geometry shader,
//! sized by the bounds here.

use crate::abi::binding;
use crate::gpu::capture::{TriangleCapture, ADAPTIVE_LEVEL, VERTEX_FLOATS};
use crate::gpu::upload::u32_bytes;
use ash::vk;

use super::device::VkError;
use super::VkMesh;
use crate::gpu::readback::patch_runs;
use std::ops::Range;

/// Bytes before the captured vertices in the capture buffer (counter,
/// capacity, padding).
pub(super) const CAPTURE_HEADER: u64 = 16;

/// An upper bound on the triangles the tessellator emits for one triangle
/// patch at `level` with equal factors: ring by ring `6a − 6` for a ring
/// of `a` segments per side (`a = level, level − 2, …`), plus 1 for an odd
/// level's centre triangle: `1.5·level²` (even), `1.5·level² − 0.5` (odd).
pub fn triangles_per_patch(level: u32) -> u64 {
    let n = level as u64;
    (3 * n * n).div_ceil(2)
}

/// Distinct vertices the tessellator emits for one triangle patch at
/// `level` with equal factors: `3a` per ring of `a` segments per side
/// (`a = level, level − 2, … > 0`), plus the centre point of an even level.
pub fn vertices_per_patch(level: u32) -> u64 {
    let rings: u64 = (0..=level / 2)
        .map(|k| level.saturating_sub(2 * k) as u64)
        .filter(|&a| a > 0)
        .map(|a| 3 * a)
        .sum();
    rings + u64::from(level.is_multiple_of(2))
}

/// Triangle patches per draw of the capture: lavapipe (Mesa's draw module)
/// numbers the tessellated vertices of one draw that feed a geometry shader
/// with 16-bit indices, so past 65 536 vertices a triangle picks up vertices
/// of an earlier patch (seen at level 64 from patch 20 on: 3169 vertices per
/// patch). Draws stay below that; a triangle whose vertices name different
/// patches is still reported ([`crate::gpu::capture::CaptureError::MixedPatches`]).
pub(super) fn patches_per_draw(level: u32) -> u64 {
    (u16::MAX as u64 / vertices_per_patch(level).max(1)).max(1)
}

impl<'v> VkMesh<'v> {
    /// Triangle schemes: tessellate every patch at `level` through the
    /// hardware tessellator and capture the triangles it emitted (position,
    /// normal, raw domain point, patch of every vertex) with the harness's
    /// geometry shader, grouped per face of the triangle mesh. The
    /// tessellator's inner vertices are not the barycentric lattice, so this
    /// is not a grid like [`Self::evaluate`]'s.
    pub fn evaluate_triangles(&self, level: u32) -> Result<TriangleCapture, VkError> {
        self.evaluate_triangles_faces(level, 0..self.patch_faces.len())
    }

    /// [`Self::evaluate_triangles`] of the faces `faces` only (clamped to
    /// the mesh's; `first_face` = its start), each patch's capture the
    /// same: only the window's patches are drawn, so a streaming caller
    /// (`tessellate::Session::run_chunked`) holds one window's triangles.
    pub fn evaluate_triangles_faces(
        &self,
        level: u32,
        faces: Range<usize>,
    ) -> Result<TriangleCapture, VkError> {
        if self.options.adaptive.is_some() {
            return Err(VkError::AdaptiveNotGrid);
        }
        if self.scheme.sides != 3 {
            return Err(VkError::QuadDomain {
                scheme: self.scheme.name.into(),
            });
        }
        self.check_level(level)?;
        self.capture(
            level,
            level,
            triangles_per_patch(level),
            patches_per_draw(level),
            faces,
        )
    }

    /// Run an adaptive draw ([`Options::adaptive`](super::Options::adaptive), quad or triangle
    /// scheme) and capture every tessellated triangle with the same
    /// geometry shader as [`Self::evaluate_triangles`]: per vertex the
    /// position, normal, domain point (quads `(u, v, 0)`, triangles
    /// barycentric) and patch. The capture's `level` is the fixed-point
    /// denominator `2^16` the evaluation stage used, so
    /// [`TriangleCapture::max_deviation`] can evaluate the CPU at the same
    /// points. Weld with [`TriangleCapture::weld`].
    pub fn evaluate_adaptive(&self) -> Result<TriangleCapture, VkError> {
        self.evaluate_adaptive_faces(0..self.patch_faces.len())
    }

    /// [`Self::evaluate_adaptive`] of the faces `faces` only (clamped to
    /// the mesh's; `first_face` = its start): only the window's patches
    /// are drawn. The factors are functions of the edge alone, so each
    /// patch's capture is the whole draw's.
    pub fn evaluate_adaptive_faces(&self, faces: Range<usize>) -> Result<TriangleCapture, VkError> {
        if self.options.adaptive.is_none() {
            return Err(VkError::AdaptiveNotGrid);
        }
        // At most 2·(ceil(max) + 2)² triangles per patch (the inside factor
        // is at most the largest edge factor, a fractional pattern adds one
        // transition ring; a triangle patch emits fewer than a quad), and
        // at most (m + 1)² vertices: draws stay under lavapipe's 16-bit
        // vertex numbering with a geometry shader (see patches_per_draw).
        let m = self.adaptive_bound();
        let per_draw = (u16::MAX as u64 / ((m + 1) * (m + 1))).max(1);
        self.capture(1, ADAPTIVE_LEVEL, 2 * m * m, per_draw, faces)
    }

    /// An upper bound on the vertices one patch's capture holds at `level`
    /// (adaptive draws: at their largest factor): how a streaming caller
    /// sizes its windows of faces.
    pub fn captured_vertices_per_patch(&self, level: u32) -> u64 {
        match &self.options.adaptive {
            Some(_) => {
                let m = self.adaptive_bound();
                (m + 1) * (m + 1)
            }
            None => vertices_per_patch(level),
        }
    }

    /// `ceil(max) + 2` for an adaptive draw's largest factor `max`, which
    /// the tessellator clamps to the device's maxTessellationGenerationLevel
    /// (so `--max-factor 1000` is sized as 64 on lavapipe, not refused).
    fn adaptive_bound(&self) -> u64 {
        let max = self.options.adaptive.as_ref().map_or(1.0, |a| a.max);
        let device = self.vk.limits.max_tessellation_generation_level as f32;
        max.min(device).max(1.0).ceil() as u64 + 2
    }

    /// Draw the patches of the faces `faces` (`Params.level = level`;
    /// adaptive builds ignore it) with the capture geometry shader bound to
    /// `binding::TRIANGLES`, in readback chunks of at most `tris_per_patch`
    /// triangles per patch (within one class-sorted run of the window,
    /// [`patch_runs`]) and draws of at most `per_draw` patches; the capture
    /// records `record_level`.
    fn capture(
        &self,
        level: u32,
        record_level: u32,
        tris_per_patch: u64,
        per_draw: u64,
        faces: Range<usize>,
    ) -> Result<TriangleCapture, VkError> {
        let per_patch = tris_per_patch * 3 * VERTEX_FLOATS as u64 * 4;
        let cap = (self.vk.limits.max_storage_buffer_range as u64).min(256 << 20) - CAPTURE_HEADER;
        if per_patch > cap {
            return Err(VkError::Limit {
                scheme: self.scheme.name.into(),
                what: "bytes of captured triangles of one patch (maxStorageBufferRange)",
                needed: per_patch,
                max: cap,
                device: self.vk.name.clone(),
            });
        }
        let faces = crate::cpu::clamp_window(faces, self.patch_faces.len());
        let chunk = (cap / per_patch).min(faces.len().max(1) as u64);
        let buf = self.vk.buffer(
            "captured triangles",
            CAPTURE_HEADER + chunk * per_patch,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let result = (|| {
            self.write_buffer(binding::TRIANGLES, &buf);
            if let Some(d) = &self.dummy {
                // The evaluation stage writes no grid samples here.
                self.write_buffer(binding::SAMPLES, d);
            }
            let mut raw = Vec::new();
            for (_, patches) in patch_runs(&self.patch_faces, &self.classes, faces.clone()) {
                let mut p0 = patches.start;
                while p0 < patches.end {
                    let n = chunk.min(patches.end - p0);
                    let capacity = n * tris_per_patch;
                    buf.write(&u32_bytes(&[0, capacity as u32, 0, 0]));
                    self.draw_chunk(level, p0, n, per_draw)?;
                    let head = buf.read_f32(4);
                    let emitted = head[0].to_bits() as u64;
                    if emitted > capacity {
                        return Err(VkError::CaptureOverflow {
                            level: record_level,
                            patches: n,
                            emitted,
                            capacity,
                        });
                    }
                    let floats = buf.read_f32(4 + emitted as usize * 3 * VERTEX_FLOATS);
                    raw.extend_from_slice(&floats[4..]);
                    p0 += n;
                }
            }
            Ok(TriangleCapture::from_raw_window(
                record_level,
                &raw,
                &self.patch_faces,
                faces,
            )?)
        })();
        buf.destroy(&self.vk.device);
        result.map_err(|e| e.on_device(&self.vk.name))
    }
}
