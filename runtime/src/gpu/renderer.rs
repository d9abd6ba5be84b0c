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
    /// One grey for every patch class instead of the class colours
    /// (ordinary orange, extraordinary blue).
    pub plain: bool,
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
            plain: false,
        }
    }

    /// `shade_fs`'s `Params.flags` for these options (bits from the ABI).
    pub fn flags(&self) -> u32 {
        let bit = |on: bool, b: u32| if on { b } else { 0 };
        bit(self.wireframe, abi::FLAG_WIREFRAME) | bit(self.plain, abi::FLAG_PLAIN)
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
                        opts.flags(),
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

    /// Colour every class alike or not (takes effect at the next
    /// [`SurfaceRenderer::prepare`]).
    pub fn set_plain(&mut self, on: bool) {
        self.opts.plain = on;
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
            crate::gpu::upload::set_params_flags(&mut bytes, self.opts.flags());
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

/// One bucket slot's indirect draw: its uniforms (rewritten per frame),
/// the bind group with the bucket buffers, the index buffer of its level
/// and where its `draw_indexed_indirect` arguments are.
struct SlotDraw {
    params: wgpu::Buffer,
    group: wgpu::BindGroup,
    pattern: usize,
    offset: u64,
    slot: u32,
    class: u32,
    level: u32,
}

/// Adaptive tessellation drawn every frame, with the buckets built on the
/// GPU (the passes of [`GpuMesh::evaluate_adaptive_gpu_driven`]: classify,
/// count, plan, scatter) and drawn by indirect draws of
/// `eval_adaptive_indirect_vs`, one per bucket slot: nothing is read back.
/// The bucket buffers, the pipelines, one index buffer per level `2^j` and
/// the per-slot bind groups are made once ([`AdaptiveSurfaceRenderer::new`]);
/// per frame the caller may change the metric ([`set_adaptive`]: a screen
/// metric follows the camera), hands over the camera ([`prepare`]),
/// records the bucket passes into its encoder before its render pass
/// ([`encode`]) and the draws into the pass ([`draw`]).
///
/// [`set_adaptive`]: AdaptiveSurfaceRenderer::set_adaptive
/// [`prepare`]: AdaptiveSurfaceRenderer::prepare
/// [`encode`]: AdaptiveSurfaceRenderer::encode
/// [`draw`]: AdaptiveSurfaceRenderer::draw
pub struct AdaptiveSurfaceRenderer {
    buckets: super::wgpu::Buckets,
    phases: Vec<(&'static str, Vec<(wgpu::Buffer, super::wgpu::Run)>)>,
    pipeline: wgpu::RenderPipeline,
    patterns: Vec<wgpu::Buffer>,
    draws: Vec<SlotDraw>,
    /// Explicit factors the buckets hold room for (one per edge id).
    edges: usize,
    max_level: u32,
    opts: SurfaceOptions,
}

impl AdaptiveSurfaceRenderer {
    /// Build the buckets of `topo` (the mesh `mesh` was uploaded from) for
    /// `a` and levels up to `max_level` (a power of two), and the pipeline
    /// of `opts`' formats (`opts.level` is not used: each patch's level is
    /// its bucket).
    pub fn new<'m>(
        mesh: &GpuMesh<'_>,
        topo: impl Into<crate::cpu::adaptive::AdaptiveMesh<'m>>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
        opts: &SurfaceOptions,
    ) -> Result<AdaptiveSurfaceRenderer, GpuError> {
        let mut inp = mesh.adaptive_inputs(topo.into(), a, max_level)?;
        // Room for explicit factors whatever metric `set_adaptive` brings.
        let edges = inp.face_edges.iter().max().map_or(0, |&e| e as usize + 1);
        inp.edge_factors.resize(edges.max(1), 0.0);
        let buckets = mesh.bucket_buffers(&inp)?;
        let phases = mesh.bucket_phases(max_level, buckets.slots, true);
        let opts = SurfaceOptions {
            samples: opts.samples.max(1),
            ..*opts
        };
        mesh.gpu().scoped(|| {
            let pipeline = mesh.surface_pipeline("eval_adaptive_indirect_vs", &opts);
            // One index buffer per level 2^j: exactly the cells of the grid
            // (the plan pass writes 6·L² (quads) or 3·L² (triangles) indices).
            let patterns = (0..super::wgpu::SLOTS)
                .map(|j| 1u32 << j)
                .take_while(|&l| l <= max_level)
                .map(|l| {
                    let indices = if mesh.scheme.sides == 3 {
                        crate::grid::tri_grid_triangles(l).concat()
                    } else {
                        pattern::scanline_indices(l)
                    };
                    mesh.index_buffer(&indices)
                })
                .collect();
            let layout = pipeline.get_bind_group_layout(0);
            let extra = buckets.bindings();
            let draws = mesh
                .bucket_slots(max_level)
                .into_iter()
                .map(|(slot, class, level)| {
                    let params = mesh.slot_params(
                        Mat4::IDENTITY,
                        buckets.slots,
                        class,
                        level,
                        slot,
                        opts.flags(),
                    );
                    SlotDraw {
                        group: mesh.bind_group_with(
                            "eval_adaptive_indirect_vs",
                            &layout,
                            &params,
                            None,
                            &extra,
                        ),
                        params,
                        pattern: level.trailing_zeros() as usize,
                        offset: (abi::BUCKET_DRAW_WORDS * abi::ELEMENT_BYTES) as u64 * slot as u64,
                        slot,
                        class,
                        level,
                    }
                })
                .collect();
            AdaptiveSurfaceRenderer {
                buckets,
                phases,
                pipeline,
                patterns,
                draws,
                edges,
                max_level,
                opts,
            }
        })
    }

    /// The largest level a patch can take.
    pub fn max_level(&self) -> u32 {
        self.max_level
    }

    /// Another metric or clamp range for the next frames (checked as
    /// [`crate::cpu::adaptive::edge_inputs`] checks them; explicit factors
    /// one per edge id of the mesh the renderer was made for; a per-face-edge
    /// metric only if it was made with one).
    pub fn set_adaptive(
        &self,
        mesh: &GpuMesh<'_>,
        a: &crate::cpu::adaptive::Adaptive,
    ) -> Result<(), GpuError> {
        crate::cpu::adaptive::check_settings(a, self.edges)?;
        self.buckets
            .write_inputs(&mesh.gpu().queue, &a.params(), a.edge_factors());
        Ok(())
    }

    /// The options it was built with (wireframe and plain as last set).
    pub fn options(&self) -> &SurfaceOptions {
        &self.opts
    }

    /// Darken patch boundaries or not (takes effect at the next
    /// [`AdaptiveSurfaceRenderer::prepare`]).
    pub fn set_wireframe(&mut self, on: bool) {
        self.opts.wireframe = on;
    }

    /// Colour every class alike or not (takes effect at the next
    /// [`AdaptiveSurfaceRenderer::prepare`]).
    pub fn set_plain(&mut self, on: bool) {
        self.opts.plain = on;
    }

    /// This frame's camera into every slot's uniforms.
    pub fn prepare(&self, mesh: &GpuMesh<'_>, view_proj: Mat4) {
        for d in &self.draws {
            let mut bytes = crate::gpu::upload::params_bytes(
                view_proj,
                self.buckets.slots,
                0,
                d.class,
                0,
                d.level,
                d.slot,
            );
            crate::gpu::upload::set_params_flags(&mut bytes, self.opts.flags());
            mesh.gpu().queue.write_buffer(&d.params, 0, &bytes);
        }
    }

    /// Record the bucket passes (compute) into `enc`, before the render
    /// pass that [`AdaptiveSurfaceRenderer::draw`] records into.
    pub fn encode(
        &self,
        mesh: &GpuMesh<'_>,
        enc: &mut wgpu::CommandEncoder,
    ) -> Result<(), GpuError> {
        mesh.encode_phases(enc, &self.phases, &self.buckets, None)
    }

    /// Record the indirect draws (one per bucket slot) into `pass`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        for d in &self.draws {
            pass.set_index_buffer(
                self.patterns[d.pattern].slice(..),
                wgpu::IndexFormat::Uint32,
            );
            pass.set_bind_group(0, &d.group, &[]);
            pass.draw_indexed_indirect(&self.buckets.draw, d.offset);
        }
    }
}
