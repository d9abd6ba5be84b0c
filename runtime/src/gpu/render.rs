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

    /// Number of pixels close to an RGB colour (each channel within `tol`).
    pub fn count_color(&self, rgb: [u8; 3], tol: u8) -> usize {
        self.rgba
            .chunks_exact(4)
            .filter(|p| (0..3).all(|c| p[c].abs_diff(rgb[c]) <= tol))
            .count()
    }
}

const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

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
        let dev = &gpu.device;
        let (w, h) = (opts.width.max(1), opts.height.max(1));
        gpu.scoped(|| -> Result<(wgpu::Buffer, u32), GpuError> {
            let extent = wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            };
            let target = |format, usage| {
                dev.create_texture(&wgpu::TextureDescriptor {
                    label: Some("render target"),
                    size: extent,
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
            };
            let color = target(
                COLOR,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            );
            let depth = target(DEPTH, wgpu::TextureUsages::RENDER_ATTACHMENT);
            let color_view = color.create_view(&Default::default());
            let depth_view = depth.create_view(&Default::default());
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("render"),
            });
            pre(&mut enc)?;
            {
                let [r, g, b, a] = opts.background;
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("render"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &color_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &depth_view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                record(&mut pass);
            }
            let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
            let row = (4 * w).div_ceil(align) * align;
            let readback = dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("image readback"),
                size: (row * h) as u64,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            enc.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture: &color,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &readback,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(h),
                    },
                },
                extent,
            );
            gpu.queue.submit([enc.finish()]);
            Ok((readback, row))
        })?
        .and_then(|(readback, row)| {
            let bytes = self.read_bytes(&readback)?;
            let mut rgba = Vec::with_capacity((4 * w * h) as usize);
            for y in 0..h {
                let start = (y * row) as usize;
                rgba.extend_from_slice(&bytes[start..start + (4 * w) as usize]);
            }
            Ok(Image {
                width: w,
                height: h,
                rgba,
            })
        })
    }
}
