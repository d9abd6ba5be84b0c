//! Headless rendering: the generated `eval_vs` evaluates an instanced
//! refinement pattern (one cache-ordered index buffer over the patch grid,
//! one instance per patch) and `shade_fs` lights it from the evaluated
//! normals — ordinary patches orange, extraordinary ones blue, as in the
//! PCCM paper's figures. Renders offscreen and reads the image back.

use crate::gpu::renderer::{AdaptiveSurfaceRenderer, SurfaceOptions, SurfaceRenderer};
use crate::gpu::wgpu::{GpuError, GpuMesh};

pub use crate::camera::Camera;

/// What to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    pub level: u32,
    pub width: u32,
    pub height: u32,
    pub camera: Camera,
    /// Background colour, linear RGBA.
    pub background: [f64; 4],
    /// Darken patch boundaries (a wireframe of the base faces).
    pub wireframe: bool,
}

/// An RGBA8 image, row-major, top row first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl Image {
    /// Encode as PNG.
    pub fn save_png(&self, path: impl AsRef<std::path::Path>) -> Result<(), GpuError> {
        let path = path.as_ref();
        image::save_buffer(
            path,
            &self.rgba,
            self.width,
            self.height,
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|e| GpuError::Image(format!("{}: {e}", path.display())))
    }

    /// Decode a PNG (for reference-image tests).
    pub fn load_png(path: impl AsRef<std::path::Path>) -> Result<Image, GpuError> {
        let path = path.as_ref();
        let img = image::open(path)
            .map_err(|e| GpuError::Image(format!("{}: {e}", path.display())))?
            .to_rgba8();
        Ok(Image {
            width: img.width(),
            height: img.height(),
            rgba: img.into_raw(),
        })
    }

    /// Number of pixels whose colour differs from `other`'s (same size) by
    /// more than `tol` in some channel: the reference-image tests' measure.
    pub fn count_differing(&self, other: &Image, tol: u8) -> usize {
        self.rgba
            .chunks_exact(4)
            .zip(other.rgba.chunks_exact(4))
            .filter(|(p, q)| (0..4).any(|c| p[c].abs_diff(q[c]) > tol))
            .count()
    }

    /// Number of pixels close to an RGB colour (each channel within `tol`).
    pub fn count_color(&self, rgb: [u8; 3], tol: u8) -> usize {
        self.rgba
            .chunks_exact(4)
            .filter(|p| (0..3).all(|c| p[c].abs_diff(rgb[c]) <= tol))
            .count()
    }
}

/// Colour format of `render`'s target ([`Target`]).
pub const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Depth format of `render`'s target.
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

impl GpuMesh<'_> {
    /// Render the surface offscreen: one instanced draw of `eval_vs` per
    /// facet class at the uniform `opts.level`, of the class's emitting
    /// patches (holes are left out).
    pub fn render(&self, opts: &RenderOptions) -> Result<Image, GpuError> {
        let surface = SurfaceRenderer::new(
            self,
            &SurfaceOptions {
                color: COLOR,
                depth: Some(DEPTH),
                samples: 1,
                level: opts.level,
                wireframe: opts.wireframe,
                plain: false,
            },
        )?;
        let (w, h) = (opts.width.max(1), opts.height.max(1));
        surface.prepare(self, opts.camera.view_proj(w as f32 / h as f32));
        self.render_with(opts, |_| Ok(()), |pass| surface.draw(pass))
    }

    /// Render adaptive tessellation with GPU-driven buckets: the classify,
    /// count, plan and scatter passes of
    /// [`GpuMesh::evaluate_adaptive_gpu_driven`] build the bucket lists and,
    /// per bucket slot (class range, level `2^j`), `draw_indexed_indirect`
    /// arguments (`bucket_draw`: the level's grid, one instance per
    /// patch); then one indirect draw of `eval_adaptive_indirect_vs` per
    /// slot up to `max_level`, with that level's index buffer. Nothing is
    /// read back before the image: the host never learns the buckets.
    /// Boundary samples are snapped onto each edge's own level, so the
    /// rasterized surface has no T-junction cracks (`opts.level` is
    /// unused; displaced on a mesh uploaded with displacement).
    pub fn render_adaptive<'m>(
        &self,
        opts: &RenderOptions,
        mesh: impl Into<crate::cpu::adaptive::AdaptiveMesh<'m>>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
    ) -> Result<Image, GpuError> {
        let surface = AdaptiveSurfaceRenderer::new(
            self,
            mesh,
            a,
            max_level,
            &SurfaceOptions {
                color: COLOR,
                depth: Some(DEPTH),
                samples: 1,
                level: 1,
                wireframe: opts.wireframe,
                plain: false,
            },
        )?;
        let (w, h) = (opts.width.max(1), opts.height.max(1));
        surface.prepare(self, opts.camera.view_proj(w as f32 / h as f32));
        self.render_with(
            opts,
            |enc| surface.encode(self, enc),
            |pass| surface.draw(pass),
        )
    }

    /// The render pipeline of vertex entry `vs` (`eval_vs`,
    /// `eval_adaptive_indirect_vs`) with `shade_fs`, for attachments of
    /// `opts`' formats: triangle lists, no culling (the surface is seen from
    /// both sides), depth test `Less` with depth writes.
    pub(crate) fn surface_pipeline(&self, vs: &str, opts: &SurfaceOptions) -> wgpu::RenderPipeline {
        self.gpu().count_pipeline();
        self.gpu()
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("tessgen surface"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: self.module(),
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: opts.depth.map(|format| wgpu::DepthStencilState {
                    format,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: opts.samples,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: self.module(),
                    entry_point: Some("shade_fs"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: opts.color,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
    }

    /// An index buffer holding `indices`.
    pub(crate) fn index_buffer(&self, indices: &[u32]) -> wgpu::Buffer {
        let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let buf = self.gpu().device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("refinement pattern"),
            size: (bytes.len() as u64).max(4),
            usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.gpu().queue.write_buffer(&buf, 0, &bytes);
        buf
    }

    /// Draw offscreen: `pre` recorded before the render pass (compute
    /// passes), then `record` into a pass over a cleared colour and depth
    /// target of `opts`' size; the image read back.
    fn render_with(
        &self,
        opts: &RenderOptions,
        pre: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<(), GpuError>,
        record: impl FnOnce(&mut wgpu::RenderPass<'_>),
    ) -> Result<Image, GpuError> {
        let gpu = self.gpu();
        let [r, g, b, a] = opts.background;
        let readback = gpu.scoped(|| -> Result<Readback, GpuError> {
            let target = Target::new(gpu, opts.width, opts.height, wgpu::TextureUsages::COPY_SRC);
            let mut enc = gpu
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("render"),
                });
            pre(&mut enc)?;
            record(&mut target.pass(&mut enc, wgpu::Color { r, g, b, a }));
            let readback = Readback::copy(gpu, &mut enc, &target.color);
            gpu.queue.submit([enc.finish()]);
            Ok(readback)
        })??;
        readback.image(self)
    }
}

/// An offscreen colour and depth target of one size in `render`'s formats
/// (RGBA8, 32-bit float depth): what `render` draws into, and what a viewer
/// draws into before it puts the frame on its window.
pub struct Target {
    pub color: wgpu::Texture,
    pub depth: wgpu::Texture,
}

impl Target {
    /// A `width × height` target (at least 1×1); the colour texture also
    /// has `usage` (`COPY_SRC` to read it back, `TEXTURE_BINDING` to sample
    /// it).
    pub fn new(
        gpu: &crate::gpu::Gpu,
        width: u32,
        height: u32,
        usage: wgpu::TextureUsages,
    ) -> Target {
        let make = |format, usage| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("render target"),
                size: wgpu::Extent3d {
                    width: width.max(1),
                    height: height.max(1),
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        Target {
            color: make(COLOR, wgpu::TextureUsages::RENDER_ATTACHMENT | usage),
            depth: make(DEPTH, wgpu::TextureUsages::RENDER_ATTACHMENT),
        }
    }

    /// A render pass over the target, colour cleared to `background` and
    /// depth to 1, for the surface renderers' `draw`.
    pub fn pass<'e>(
        &self,
        enc: &'e mut wgpu::CommandEncoder,
        background: wgpu::Color,
    ) -> wgpu::RenderPass<'e> {
        enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("render"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.color.create_view(&Default::default()),
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(background),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth.create_view(&Default::default()),
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}

/// An RGBA8 texture's copy on its way to the host: recorded into an
/// encoder ([`Readback::copy`]), read once the encoder is submitted
/// ([`Readback::image`]).
pub struct Readback {
    buffer: wgpu::Buffer,
    row: u32,
    width: u32,
    height: u32,
}

impl Readback {
    /// Record the copy of `texture` (RGBA8, `COPY_SRC`) into `enc`.
    pub fn copy(
        gpu: &crate::gpu::Gpu,
        enc: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
    ) -> Readback {
        let (width, height) = (texture.width(), texture.height());
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let row = (4 * width).div_ceil(align) * align;
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("image readback"),
            size: (row * height) as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        enc.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(height),
                },
            },
            texture.size(),
        );
        Readback {
            buffer,
            row,
            width,
            height,
        }
    }

    /// The image, once the copy's encoder is submitted (waits for it).
    pub fn image(&self, mesh: &GpuMesh<'_>) -> Result<Image, GpuError> {
        let bytes = mesh.read_bytes(&self.buffer)?;
        let (w, row) = (self.width as usize, self.row as usize);
        let rgba = (0..self.height as usize)
            .flat_map(|y| &bytes[y * row..y * row + 4 * w])
            .copied()
            .collect();
        Ok(Image {
            width: self.width,
            height: self.height,
            rgba,
        })
    }
}
