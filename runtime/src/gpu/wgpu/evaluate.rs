//! Uniform evaluation: `eval_main` over every patch at one level, one
//! dispatch per facet class split at the device limits, read back through
//! the one readback scatter into per-face grids ([`Tessellation`]). A
//! window of faces ([`GpuMesh::evaluate_faces`]) dispatches only its own
//! patches, so a streamed chunk costs a chunk's memory on both sides.

use crate::abi;
use crate::cpu::{self, Tessellation};
use crate::gpu::readback::{patch_runs, GridReadback};
use crate::gpu::upload::params_bytes;
use glam::Mat4;
use std::ops::Range;

use super::{GpuError, GpuMesh};

impl<'g> GpuMesh<'g> {
    /// Evaluate every patch on its `level` grid (the scheme's `grid_len`
    /// samples) with `eval_main` and read it back, in face order (the same
    /// layout as the CPU path).
    pub fn evaluate(&self, level: u32) -> Result<Tessellation, GpuError> {
        self.evaluate_window(level, 0..self.patch_faces.len(), true)
    }

    /// The grids of the faces `faces` only (`face_ids` = the range), each
    /// [`Self::evaluate`]'s bit for bit: what a streaming caller reads chunk
    /// by chunk (`tessellate::Session::run_chunked`). The samples buffer of
    /// a dispatch holds at most the window's patches.
    pub fn evaluate_faces(
        &self,
        level: u32,
        faces: Range<usize>,
    ) -> Result<Tessellation, GpuError> {
        let all = self.patch_faces.len();
        let faces = cpu::clamp_window(faces, all);
        self.evaluate_window(level, faces, false)
    }

    fn evaluate_window(
        &self,
        level: u32,
        faces: Range<usize>,
        whole: bool,
    ) -> Result<Tessellation, GpuError> {
        cpu::check_level(level)?;
        let spp = (self.scheme.grid_len)(level) as u64;
        if spp * abi::SAMPLE_BYTES > self.limits.max_storage_buffer_binding_size {
            return Err(GpuError::BufferTooLarge {
                what: "samples of one patch",
                needed: spp * abi::SAMPLE_BYTES,
                max: self.limits.max_storage_buffer_binding_size,
                adapter: self.gpu.info.name.clone(),
            });
        }
        let mut grids = GridReadback::new(level, self.scheme.sides, faces.clone(), spp)?;
        // Patches per readback chunk: within the dispatch and binding limits.
        let by_dispatch = self.chunk(spp);
        let by_binding =
            (self.limits.max_storage_buffer_binding_size / (spp * abi::SAMPLE_BYTES)).max(1);
        let chunk = by_dispatch.min(by_binding);
        let dev = &self.gpu.device;
        for (k, run) in patch_runs(&self.patch_faces, &self.classes, faces) {
            let c = &self.classes[k];
            let mut at = run.start;
            while at < run.end {
                let count = chunk.min(run.end - at) as u32;
                let first = at as u32;
                let bytes = count as u64 * spp * abi::SAMPLE_BYTES;
                let (samples, staging) = self.sample_buffers(bytes);
                self.gpu.scoped(|| {
                    let p = self.params_buffer(&params_bytes(
                        Mat4::IDENTITY,
                        first,
                        count,
                        c.class,
                        c.cp_base + (first - c.first) * c.points,
                        level,
                        0,
                    ));
                    let layout = self.eval_pipeline.get_bind_group_layout(0);
                    let group = self.bind_group("eval_main", &layout, &p, Some(&samples));
                    let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("eval"),
                    });
                    {
                        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                            label: Some("eval"),
                            timestamp_writes: None,
                        });
                        pass.set_pipeline(&self.eval_pipeline);
                        pass.set_bind_group(0, &group, &[]);
                        pass.dispatch_workgroups(
                            ((count as u64 * spp).div_ceil(abi::WORKGROUP)) as u32,
                            1,
                            1,
                        );
                    }
                    enc.copy_buffer_to_buffer(&samples, 0, &staging, 0, bytes);
                    self.gpu.queue.submit([enc.finish()]);
                })?;
                let floats = self.read(&staging)?;
                grids.scatter(&floats, at, &self.patch_faces);
                at += count as u64;
            }
        }
        Ok(grids.finish(whole))
    }
}
