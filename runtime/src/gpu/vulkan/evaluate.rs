//! Evaluation: the vertex and patch stages ([`VkMesh::construct`]), uniform
//! evaluation through the tessellation pipeline ([`VkMesh::evaluate`]) or the
//! compute `eval_main` ([`VkMesh::evaluate_compute`]), chunked draws, and the
//! samples buffer read back into per-face grids.

use crate::abi::{self, binding};
use crate::cpu::{self, Tessellation};
use crate::gpu::readback::{patch_runs, GridReadback};
use crate::gpu::upload::ClassRange;
use ash::vk;
use std::ops::Range;

use super::device::VkError;
use super::{Buf, VkMesh};

/// Patches per draw of the grid readback. lavapipe (Mesa 22.3) loses
/// patches of large tessellation draws: a 5 000-patch draw of
/// `catmark_righthanded_L3`'s faces at level 2 came back with 6 704
/// degenerate triangles and 112 cracks, the whole 27 776-patch mesh with
/// most patches garbage at every level, while 4 097 patches and any draw
/// split into 1 024-patch pieces are exact. Splitting costs one submit per
/// piece (28 for that mesh) and changes no sample.
const GRID_PATCHES_PER_DRAW: u64 = 1024;

impl<'v> VkMesh<'v> {
    /// Run the vertex stage (quad schemes); the control stage builds each
    /// patch's control points inside every draw. Displacing builds also run
    /// the compute patch stage, class by class, into the global
    /// control-point buffer (binding 8) at the class-sorted layout the
    /// owner records name: the evaluation stage evaluates owner patches
    /// from it.
    pub fn construct(&self) -> Result<(), VkError> {
        let run = || {
            self.vertex_stage()?;
            if !self.displaced() {
                return Ok(());
            }
            self.patch_stage()
        };
        run().map_err(|e| e.on_device(&self.vk.name))
    }

    /// The compute patch stage, class by class, into the global
    /// control-point buffer (binding 8).
    fn patch_stage(&self) -> Result<(), VkError> {
        let per = abi::WORKGROUP_SIZE * self.vk.limits.max_compute_work_group_count_x.max(1);
        for c in &self.classes {
            let mut done = 0;
            while done < c.count {
                let count = per.min(c.count - done);
                self.set_params([
                    c.first + done,
                    count,
                    c.class,
                    c.cp_base + done * c.points,
                    1,
                    0,
                ]);
                let (pipe, layout, set) = (self.patch_pipeline, self.layout, self.set);
                self.vk.submit(|d, cb| unsafe {
                    d.cmd_bind_pipeline(cb, vk::PipelineBindPoint::COMPUTE, pipe);
                    d.cmd_bind_descriptor_sets(
                        cb,
                        vk::PipelineBindPoint::COMPUTE,
                        layout,
                        0,
                        &[set],
                        &[],
                    );
                    d.cmd_dispatch(cb, count.div_ceil(abi::WORKGROUP_SIZE), 1, 1);
                })?;
                done += count;
            }
        }
        Ok(())
    }

    /// The vertex stage as a compute dispatch (quad schemes), after the
    /// refinement stage of a mesh refined on the GPU (its output is the
    /// vertex stage's `positions`; every submit is ordered after the last).
    fn vertex_stage(&self) -> Result<(), VkError> {
        if let Some(r) = self.refine {
            self.dispatch_items(self.refine_pipeline, r.rows)?;
        }
        self.dispatch_items(self.vertex_pipeline, self.num_vertices)
    }

    /// `pipeline` over items `0 .. items` (vertices, refined vertices), one
    /// invocation each, in dispatches of at most the device's workgroup
    /// count (`params.first`, `params.count` per dispatch).
    fn dispatch_items(&self, pipeline: vk::Pipeline, items: u32) -> Result<(), VkError> {
        let per = abi::WORKGROUP_SIZE * self.vk.limits.max_compute_work_group_count_x.max(1);
        let mut first = 0;
        while first < items {
            let count = per.min(items - first);
            self.set_params([first, count, 0, 0, 1, 0]);
            let (layout, set) = (self.layout, self.set);
            self.vk.submit(|d, cb| unsafe {
                d.cmd_bind_pipeline(cb, vk::PipelineBindPoint::COMPUTE, pipeline);
                d.cmd_bind_descriptor_sets(
                    cb,
                    vk::PipelineBindPoint::COMPUTE,
                    layout,
                    0,
                    &[set],
                    &[],
                );
                d.cmd_dispatch(cb, count.div_ceil(abi::WORKGROUP_SIZE), 1, 1);
            })?;
            first += count;
        }
        Ok(())
    }

    /// Tessellate every patch at `level` through the hardware tessellator and
    /// read the captured samples back in face order: the same layout as
    /// [`cpu::evaluate`].
    pub fn evaluate(&self, level: u32) -> Result<Tessellation, VkError> {
        self.evaluate_window(level, 0..self.patch_faces.len(), true)
    }

    /// [`Self::evaluate`] of the faces `faces` only (`face_ids` = the
    /// range), each face's samples bit for bit the same: what a streaming
    /// caller reads chunk by chunk (`tessellate::Session::run_chunked`).
    /// The samples buffer holds at most the window's patches.
    pub fn evaluate_faces(&self, level: u32, faces: Range<usize>) -> Result<Tessellation, VkError> {
        self.evaluate_window(level, faces, false)
    }

    fn evaluate_window(
        &self,
        level: u32,
        faces: Range<usize>,
        whole: bool,
    ) -> Result<Tessellation, VkError> {
        if self.options.adaptive.is_some() {
            return Err(VkError::AdaptiveNotGrid);
        }
        if self.scheme.sides == 3 {
            return Err(VkError::TriangleDomain {
                scheme: self.scheme.name.into(),
            });
        }
        self.check_level(level)?;
        self.with_samples(level, faces, whole, |p0, n| {
            self.draw_chunk(level, p0, n, GRID_PATCHES_PER_DRAW)
        })
        .map_err(|e| e.on_device(&self.vk.name))
    }

    /// Evaluate every patch at `level` with the emitted *compute* entries
    /// instead of the tessellation pipeline (GLSL `<scheme>_patch.comp` and
    /// `<scheme>_eval.comp`, HLSL `patch_main` and `eval_main`): the vertex
    /// stage, the patch stage into the global control-point buffer, then
    /// `eval_main` over each class range of the patches into the samples,
    /// read back in face order — [`cpu::evaluate`]'s layout, quad and
    /// triangle schemes alike. A displacing mesh ([`Self::new_displaced`],
    /// [`Self::new_tri_displaced`]) displaces (`eval_displaced_global`).
    /// Builds the two compute pipelines on first use.
    pub fn evaluate_compute(&mut self, level: u32) -> Result<Tessellation, VkError> {
        let name = self.vk.name.clone();
        self.evaluate_compute_on(level)
            .map_err(|e| e.on_device(&name))
    }

    fn evaluate_compute_on(&mut self, level: u32) -> Result<Tessellation, VkError> {
        cpu::check_level(level)?;
        if self.patch_pipeline == vk::Pipeline::null() {
            self.patch_pipeline = self.compute_pipeline("patch")?;
        }
        if self.eval_pipeline == vk::Pipeline::null() {
            self.eval_pipeline = self.compute_pipeline("eval")?;
        }
        self.vertex_stage()?;
        self.patch_stage()?;
        let spp = (self.scheme.grid_len)(level) as u64;
        // Invocations of one dispatch: WORKGROUP_SIZE per workgroup (a
        // level-64 quad patch has 4,225 samples, far below).
        let per_dispatch =
            abi::WORKGROUP * self.vk.limits.max_compute_work_group_count_x.max(1) as u64;
        self.with_samples(level, 0..self.patch_faces.len(), true, |p0, n| {
            for c in &self.classes {
                let mut lo = (c.first as u64).max(p0);
                let hi = ((c.first + c.count) as u64).min(p0 + n);
                while lo < hi {
                    let count = (hi - lo).min((per_dispatch / spp).max(1));
                    self.set_params([
                        lo as u32,
                        count as u32,
                        c.class,
                        c.cp_base + (lo as u32 - c.first) * c.points,
                        level,
                        (lo - p0) as u32,
                    ]);
                    let (pipe, layout, set) = (self.eval_pipeline, self.layout, self.set);
                    let groups = (count * spp).div_ceil(abi::WORKGROUP) as u32;
                    self.vk.submit(|d, cb| unsafe {
                        d.cmd_bind_pipeline(cb, vk::PipelineBindPoint::COMPUTE, pipe);
                        d.cmd_bind_descriptor_sets(
                            cb,
                            vk::PipelineBindPoint::COMPUTE,
                            layout,
                            0,
                            &[set],
                            &[],
                        );
                        d.cmd_dispatch(cb, groups, 1, 1);
                    })?;
                    lo += count;
                }
            }
            Ok(())
        })
    }

    pub(super) fn check_level(&self, level: u32) -> Result<(), VkError> {
        cpu::check_level(level)?;
        let max_level = self.vk.limits.max_tessellation_generation_level;
        if level > max_level {
            return Err(VkError::Limit {
                scheme: self.scheme.name.into(),
                what: "tessellation level (maxTessellationGenerationLevel)",
                needed: level as u64,
                max: max_level as u64,
                device: self.vk.name.clone(),
            });
        }
        Ok(())
    }

    /// Draws of the patches `p0 .. p0 + n`: per facet class, at most
    /// `per_draw` patches each.
    pub(super) fn draw_chunk(
        &self,
        level: u32,
        p0: u64,
        n: u64,
        per_draw: u64,
    ) -> Result<(), VkError> {
        for c in &self.classes {
            let lo = (c.first as u64).max(p0);
            let hi = ((c.first + c.count) as u64).min(p0 + n);
            let mut at = lo;
            while at < hi {
                let next = hi.min(at.saturating_add(per_draw.max(1)));
                self.draw(level, c, p0, at, next)?;
                at = next;
            }
        }
        Ok(())
    }

    /// One draw of the patches `lo .. hi` of class range `c`, the readback
    /// chunk starting at patch `p0`.
    fn draw(&self, level: u32, c: &ClassRange, p0: u64, lo: u64, hi: u64) -> Result<(), VkError> {
        let (first, count) = (lo as u32, (hi - lo) as u32);
        self.set_params([
            first,
            count,
            c.class,
            c.cp_base + (first - c.first) * c.points,
            level,
            (lo - p0) as u32,
        ]);
        let (pipe, layout, set) = (self.draw_pipeline, self.layout, self.set);
        let (rp, fb) = (self.render_pass, self.framebuffer);
        self.vk.submit(|d, cb| unsafe {
            d.cmd_begin_render_pass(
                cb,
                &vk::RenderPassBeginInfo::default()
                    .render_pass(rp)
                    .framebuffer(fb)
                    .render_area(vk::Rect2D {
                        offset: vk::Offset2D { x: 0, y: 0 },
                        extent: vk::Extent2D {
                            width: 1,
                            height: 1,
                        },
                    }),
                vk::SubpassContents::INLINE,
            );
            d.cmd_bind_pipeline(cb, vk::PipelineBindPoint::GRAPHICS, pipe);
            d.cmd_bind_descriptor_sets(cb, vk::PipelineBindPoint::GRAPHICS, layout, 0, &[set], &[]);
            // Patch size 1: one vertex per patch.
            d.cmd_draw(cb, count, 1, 0, 0);
            d.cmd_end_render_pass(cb);
        })?;
        Ok(())
    }

    /// A samples buffer of as many patches' grids at `level` as fit one
    /// storage binding (and 256 MiB, and the window), bound at
    /// [`binding::SAMPLES`]; then [`Self::read_samples`] with it over the
    /// patches of the faces `faces` (`whole`: every face of the mesh).
    fn with_samples(
        &self,
        level: u32,
        faces: Range<usize>,
        whole: bool,
        run: impl Fn(u64, u64) -> Result<(), VkError>,
    ) -> Result<Tessellation, VkError> {
        let spp = (self.scheme.grid_len)(level) as u64;
        let per_patch = spp * abi::SAMPLE_BYTES;
        // Patches per readback chunk: within one storage binding and 256 MiB.
        let cap = (self.vk.limits.max_storage_buffer_range as u64).min(256 << 20);
        if per_patch > cap {
            return Err(VkError::Limit {
                scheme: self.scheme.name.into(),
                what: "bytes of samples of one patch (maxStorageBufferRange)",
                needed: per_patch,
                max: cap,
                device: self.vk.name.clone(),
            });
        }
        let all = self.patch_faces.len();
        let faces = cpu::clamp_window(faces, all);
        let chunk = (cap / per_patch).min(faces.len().max(1) as u64);
        let samples = self.vk.buffer(
            "samples",
            chunk * per_patch,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let result = self.read_samples(level, spp, chunk, &samples, faces, run);
        samples.destroy(&self.vk.device);
        Ok(result?.finish(whole))
    }

    /// Bind `samples`, let `run(p0, n)` write patches `p0 .. p0 + n` (one
    /// class's, of the window's [`patch_runs`]) at `(patch − p0)·spp`
    /// samples of SAMPLE_FLOATS floats, chunk by chunk, and gather them in
    /// face order.
    fn read_samples(
        &self,
        level: u32,
        spp: u64,
        chunk: u64,
        samples: &Buf,
        faces: Range<usize>,
        run: impl Fn(u64, u64) -> Result<(), VkError>,
    ) -> Result<GridReadback, VkError> {
        self.write_buffer(binding::SAMPLES, samples);
        let mut grids = GridReadback::new(level, self.scheme.sides, faces.clone(), spp)?;
        let nan: Vec<u8> = std::iter::repeat_n(
            f32::NAN.to_le_bytes(),
            (chunk * spp) as usize * abi::SAMPLE_LEN,
        )
        .flatten()
        .collect();
        for (_, patches) in patch_runs(&self.patch_faces, &self.classes, faces) {
            let mut p0 = patches.start;
            while p0 < patches.end {
                let n = chunk.min(patches.end - p0);
                // Unwritten samples stay NaN, so a missed write fails parity.
                samples.write(&nan);
                run(p0, n)?;
                let floats = samples.read_f32((n * spp) as usize * abi::SAMPLE_LEN);
                grids.scatter(&floats, p0, &self.patch_faces);
                p0 += n;
            }
        }
        Ok(grids)
    }
}
