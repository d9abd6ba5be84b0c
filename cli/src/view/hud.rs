//! The viewer's on-screen text and the pass that puts the frame on the
//! window: the surface is drawn into an offscreen RGBA8 target exactly as
//! `render` draws it, then one full-screen triangle copies that target to
//! the window's (or a screenshot's) target texel for texel, blending the
//! HUD's text box over its top-left corner. With the HUD off the window
//! shows the very bytes `render` writes to its PNG.

/// Pixels of one glyph cell (font8x8: 8×8, drawn at `scale`).
const CELL: u32 = 8;

/// Text lines rasterised into an RGBA8 box: white glyphs (font8x8's
/// public-domain 8×8 bitmaps) on a translucent dark background.
pub(crate) struct TextBox {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl TextBox {
    /// `lines` at `scale` pixels per font pixel, with a 4-pixel margin (so
    /// never empty); characters outside ASCII are drawn as `?`.
    pub fn new(lines: &[String], scale: u32) -> TextBox {
        let scale = scale.max(1);
        let margin = 4;
        let cols = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0) as u32;
        let width = cols * CELL * scale + 2 * margin;
        let height = lines.len() as u32 * (CELL + 2) * scale + 2 * margin;
        let mut rgba = [0u8, 0, 0, 150].repeat((width * height) as usize);
        for (row, line) in lines.iter().enumerate() {
            for (col, ch) in line.chars().enumerate() {
                let glyph = font8x8::legacy::BASIC_LEGACY[if ch.is_ascii() {
                    ch as usize
                } else {
                    b'?' as usize
                }];
                for (gy, bits) in glyph.iter().enumerate() {
                    for gx in 0..CELL {
                        if bits & (1 << gx) == 0 {
                            continue;
                        }
                        for sy in 0..scale {
                            for sx in 0..scale {
                                let x = margin + (col as u32 * CELL + gx) * scale + sx;
                                let y = margin + (row as u32 * (CELL + 2) + gy as u32) * scale + sy;
                                let at = 4 * (y * width + x) as usize;
                                rgba[at..at + 4].copy_from_slice(&[255, 255, 255, 255]);
                            }
                        }
                    }
                }
            }
        }
        TextBox {
            width,
            height,
            rgba,
        }
    }

    /// Nothing to show: one transparent texel.
    pub fn empty() -> TextBox {
        TextBox {
            width: 1,
            height: 1,
            rgba: vec![0; 4],
        }
    }
}

/// The composite pass: the frame texel for texel, the HUD blended over it.
const COMPOSITE_WGSL: &str = r#"
@group(0) @binding(0) var frame: texture_2d<f32>;
@group(0) @binding(1) var hud: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32((i << 1u) & 2u);
    let y = f32(i & 2u);
    return vec4<f32>(2.0 * x - 1.0, 1.0 - 2.0 * y, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(at.xy);
    var c = textureLoad(frame, p, 0);
    let box = vec2<i32>(textureDimensions(hud));
    if (p.x < box.x && p.y < box.y) {
        let h = textureLoad(hud, p, 0);
        c = vec4<f32>(mix(c.rgb, h.rgb, h.a), 1.0);
    }
    return c;
}
"#;

/// The composite pipeline for one target format, and the HUD texture.
pub(crate) struct Composite {
    pipeline: wgpu::RenderPipeline,
    hud: wgpu::Texture,
}

impl Composite {
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Composite {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("view composite"),
            source: wgpu::ShaderSource::Wgsl(COMPOSITE_WGSL.into()),
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("view composite"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Composite {
            pipeline,
            hud: hud_texture(device, 1, 1),
        }
    }

    /// Show `text` from the next pass on (a new texture only when its size
    /// changes).
    pub fn set_text(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, text: &TextBox) {
        if (self.hud.width(), self.hud.height()) != (text.width, text.height) {
            self.hud = hud_texture(device, text.width, text.height);
        }
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &self.hud,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &text.rgba,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * text.width),
                rows_per_image: Some(text.height),
            },
            wgpu::Extent3d {
                width: text.width,
                height: text.height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Record the pass from `frame` (a view of the offscreen target) into
    /// `target`.
    pub fn encode(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        frame: &wgpu::TextureView,
        target: &wgpu::TextureView,
    ) {
        let hud = self.hud.create_view(&Default::default());
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("view composite"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(frame),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&hud),
                },
            ],
        });
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("view composite"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}

fn hud_texture(device: &wgpu::Device, width: u32, height: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("view hud"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_box_draws_glyph_pixels_on_a_translucent_background() {
        let b = TextBox::new(&["A".to_string(), "".to_string()], 1);
        assert_eq!((b.width, b.height), (8 + 8, 2 * 10 + 8));
        let white = b
            .rgba
            .chunks_exact(4)
            .filter(|p| p == &[255, 255, 255, 255])
            .count();
        let glyph: u32 = font8x8::legacy::BASIC_LEGACY[b'A' as usize]
            .iter()
            .map(|r| r.count_ones())
            .sum();
        assert_eq!(white as u32, glyph);
        assert!(b
            .rgba
            .chunks_exact(4)
            .all(|p| p[3] == 255 || p == [0, 0, 0, 150]));
        let big = TextBox::new(&["A".to_string()], 2);
        let white2 = big.rgba.chunks_exact(4).filter(|p| p[0] == 255).count();
        assert_eq!(white2 as u32, 4 * glyph);
        assert_eq!(TextBox::new(&[], 2).rgba.len(), 4 * (8 * 8) as usize);
    }
}
