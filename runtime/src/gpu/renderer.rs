//! A surface an engine draws every frame: the render pipeline, the index
//! buffer of the refinement pattern and one bind group per facet class are
//! built once ([`SurfaceRenderer::new`]); per frame the caller moves the
//! control mesh if it animates ([`GpuMesh::update_positions`]: the vertex
//! and patch stages run again on the GPU), hands over its camera
//! ([`SurfaceRenderer::prepare`]: one small uniform write per class) and
//! records the draws into its own render pass ([`SurfaceRenderer::draw`]),
//! next to its other geometry. [`GpuMesh::render`] (the CLI's `render`) is
//! this renderer drawing into an offscreen target.
//!
//! The draws are the generated `eval_vs` (instanced: one instance per
//! patch of a class, the pattern's indices over the patch's grid) and
//! `shade_fs`; the pass needs a depth attachment when the renderer was
//! made with a depth format.

use super::pattern;
use super::wgpu::{GpuError, GpuMesh};
use crate::abi;
use glam::Mat4;

/// The attachments the renderer draws into and what it draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceOptions {
    /// Format of the pass's colour attachment.
    pub color: wgpu::TextureFormat,
    /// Format of its depth attachment (`None`: no depth test).
    pub depth: Option<wgpu::TextureFormat>,
    /// Multisample count of the attachments.
    pub samples: u32,
    /// Uniform level: `(N + 1)²` samples per quad patch.
    pub level: u32,
    /// Darken patch boundaries (a wireframe of the base faces).
    pub wireframe: bool,
}

impl SurfaceOptions {
    /// RGBA8 colour, 32-bit float depth, no multisampling, at `level`.
    pub fn new(level: u32) -> SurfaceOptions {
        SurfaceOptions {
            color: wgpu::TextureFormat::Rgba8Unorm,
            depth: Some(wgpu::TextureFormat::Depth32Float),
            samples: 1,
            level,
            wireframe: false,
        }
    }
}

/// One class's instanced draw: its uniforms (rewritten per frame) and the
/// bind group that holds them and the mesh's buffers.
struct ClassDraw {
    params: wgpu::Buffer,
    group: wgpu::BindGroup,
    first: u32,
    instances: u32,
    class: u32,
    cp_base: u32,
}

/// A mesh's surface, drawn into the caller's render passes.
pub struct SurfaceRenderer {
    pipeline: wgpu::RenderPipeline,
    indices: wgpu::Buffer,
    index_count: u32,
    draws: Vec<ClassDraw>,
    opts: SurfaceOptions,
}

impl SurfaceRenderer {
    /// Build the pipeline, the pattern and the per-class bind groups for
    /// `mesh` (its emitting patches: holes are left out).
    pub fn new(mesh: &GpuMesh<'_>, opts: &SurfaceOptions) -> Result<SurfaceRenderer, GpuError> {
        let opts = SurfaceOptions {
            level: opts.level.clamp(1, crate::cpu::MAX_LEVEL),
            samples: opts.samples.max(1),
            ..*opts
        };
        let gpu = mesh.gpu();
        gpu.scoped(|| {
            let pipeline = mesh.surface_pipeline("eval_vs", &opts);
            let (indices, index_count) = pattern_buffer(mesh, opts.level);
            let layout = pipeline.get_bind_group_layout(0);
            let draws = mesh
                .classes
                .iter()
                .filter(|c| c.emitting > 0)
                .map(|c| {
                    let params = mesh.params(
                        Mat4::IDENTITY,
                        c.first,
                        c.emitting,
                        c.class,
                        c.cp_base,
                        opts.level,
                        0,
                        u32::from(opts.wireframe),
                    );
                    ClassDraw {
                        group: mesh.bind_group("eval_vs", &layout, &params, None),
                        params,
                        first: c.first,
                        instances: c.emitting,
                        class: c.class,
                        cp_base: c.cp_base,
                    }
                })
                .collect();
            SurfaceRenderer {
                pipeline,
                indices,
                index_count,
                draws,
                opts,
            }
        })
    }

    /// The options it was built with (the level clamped to the runtime's
    /// range).
    pub fn options(&self) -> &SurfaceOptions {
        &self.opts
    }

    /// Change the uniform level: a new index buffer; the bind groups stay.
    pub fn set_level(&mut self, mesh: &GpuMesh<'_>, level: u32) {
        let level = level.clamp(1, crate::cpu::MAX_LEVEL);
        if level != self.opts.level {
            (self.indices, self.index_count) = pattern_buffer(mesh, level);
            self.opts.level = level;
        }
    }

    /// Darken patch boundaries or not (takes effect at the next
    /// [`SurfaceRenderer::prepare`]).
    pub fn set_wireframe(&mut self, on: bool) {
        self.opts.wireframe = on;
    }

    /// This frame's camera: `view_proj` (column-major, clip from world,
    /// depth 0..1) into every class's uniforms, through the mesh's queue.
    pub fn prepare(&self, mesh: &GpuMesh<'_>, view_proj: Mat4) {
        for d in &self.draws {
            let mut bytes = crate::gpu::upload::params_bytes(
                view_proj,
                d.first,
                d.instances,
                d.class,
                d.cp_base,
                self.opts.level,
                0,
            );
            let at = abi::params::FLAGS;
            bytes[at..at + 4].copy_from_slice(&u32::from(self.opts.wireframe).to_le_bytes());
            mesh.gpu().queue.write_buffer(&d.params, 0, &bytes);
        }
    }

    /// Record the draws (one instanced draw per class) into `pass`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        for d in &self.draws {
            pass.set_bind_group(0, &d.group, &[]);
            pass.draw_indexed(0..self.index_count, 0, 0..d.instances);
        }
    }

    /// Samples drawn per frame (every class's patches × the grid).
    pub fn samples_per_frame(&self, mesh: &GpuMesh<'_>) -> u64 {
        let g = (mesh.scheme.grid_len)(self.opts.level) as u64;
        self.draws.iter().map(|d| d.instances as u64 * g).sum()
    }
}

/// The refinement pattern of `level` as an index buffer, and its length.
fn pattern_buffer(mesh: &GpuMesh<'_>, level: u32) -> (wgpu::Buffer, u32) {
    let indices = if mesh.scheme.sides == 3 {
        crate::grid::tri_grid_triangles(level).concat()
    } else {
        pattern::cache_friendly_indices(level, 20)
    };
    (mesh.index_buffer(&indices), indices.len() as u32)
}
