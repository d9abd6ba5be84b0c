//! An engine's frame loop on plain wgpu with a tessgen surface in it.
//!
//! The engine owns the device, the targets and the render pass; tessgen
//! gets the device once (`Gpu::from_parts`), uploads the mesh once
//! (`GpuMesh::new`) and builds its pipeline and bind groups once
//! (`SurfaceRenderer::new`, for the engine's attachment formats). Each
//! frame the engine animates the control mesh (`GpuMesh::update_positions`:
//! the vertex and patch stages run again on the GPU), passes its camera
//! (`SurfaceRenderer::prepare`) and lets the surface record its draws into
//! the engine's pass (`SurfaceRenderer::draw`). Headless here (an offscreen
//! target instead of a window's surface), so it runs in CI on lavapipe.

use glam::Vec3;
use std::time::Instant;
use tessgen_runtime::gpu::renderer::{SurfaceOptions, SurfaceRenderer};
use tessgen_runtime::gpu::{Gpu, GpuMesh, Limits};
use tessgen_runtime::render::Camera;
use tessgen_runtime::{cpu, Mesh, Topology};

/// The engine's own attachment formats (a window would use its surface's).
pub const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;

/// What a run measured.
pub struct Report {
    pub adapter: String,
    /// Wall time of each frame (animate, prepare, draw, submit, wait).
    pub frame_ms: Vec<f64>,
    pub samples_per_frame: u64,
    /// Pipelines tessgen had created after the first frame, and at the end.
    pub pipelines: (usize, usize),
    /// The last frame, RGBA8.
    pub pixels: Vec<u8>,
}

/// Open a device the way an engine would: any adapter, default limits.
fn open_device() -> Result<Gpu, String> {
    pollster::block_on(async {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions::default())
            .await
            .map_err(|e| format!("no adapter: {e}"))?;
        let info = adapter.get_info();
        let al = adapter.limits();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("engine"),
                required_limits: al.clone(),
                ..Default::default()
            })
            .await
            .map_err(|e| e.to_string())?;
        let limits = Limits {
            max_workgroups_per_dimension: al.max_compute_workgroups_per_dimension,
            max_texture_dimension_2d: al.max_texture_dimension_2d,
            max_storage_buffer_binding_size: al.max_storage_buffer_binding_size as u64,
        };
        Ok(Gpu::from_parts(device, queue, info, limits))
    })
}

/// `frames` frames of `obj` (a quad mesh) with `scheme` at `level`, the
/// control mesh breathing, into a `size` target.
pub fn run(
    obj: &str,
    scheme: &str,
    level: u32,
    frames: usize,
    size: (u32, u32),
) -> Result<Report, String> {
    let gpu = open_device()?;
    let mesh = Mesh::from_obj_str(obj).map_err(|e| e.to_string())?;
    let topo = Topology::build(&mesh, &cpu::topology_options()).map_err(|e| e.to_string())?;
    let rest: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    let surface_mesh = GpuMesh::new(&gpu, &topo, &rest, scheme).map_err(|e| e.to_string())?;
    let mut opts = SurfaceOptions::new(level);
    (opts.color, opts.depth) = (COLOR, Some(DEPTH));
    let surface = SurfaceRenderer::new(&surface_mesh, &opts).map_err(|e| e.to_string())?;

    // The engine's targets, made once.
    let (w, h) = size;
    let extent = wgpu::Extent3d {
        width: w,
        height: h,
        depth_or_array_layers: 1,
    };
    let target = |format, usage| {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("engine target"),
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
    let (color_view, depth_view) = (
        color.create_view(&Default::default()),
        depth.create_view(&Default::default()),
    );
    let row =
        (4 * w).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("engine readback"),
        size: (row * h) as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });

    let center = rest.iter().copied().sum::<Vec3>() / rest.len().max(1) as f32;
    let radius = rest
        .iter()
        .map(|p| (*p - center).length())
        .fold(0.0, f32::max)
        .max(1e-3);
    let mut frame_ms = Vec::with_capacity(frames);
    let mut first_pipelines = 0;
    for frame in 0..frames {
        let start = Instant::now();
        // Animation: the control mesh breathes; tessgen rebuilds the patches on the GPU.
        let s = 1.0 + 0.1 * (frame as f32 * 0.7).sin();
        let moved: Vec<Vec3> = rest.iter().map(|p| center + (*p - center) * s).collect();
        surface_mesh
            .update_positions(&moved)
            .map_err(|e| e.to_string())?;
        // The engine's camera, orbiting.
        let a = frame as f32 * 0.3;
        let eye = center + Vec3::new(a.sin(), 0.5, a.cos()) * radius * 3.0;
        // (Any clip-from-world matrix with depth 0..1 will do; this one is tessgen's.)
        let camera = Camera {
            eye,
            target: center,
            up: Vec3::Y,
            fov_y: 35.0,
        };
        let view_proj = camera.view_proj(w as f32 / h as f32);
        surface.prepare(&surface_mesh, view_proj);
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("engine frame"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
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
            // ... the engine's own draws would go here too ...
            surface.draw(&mut pass);
        }
        if frame + 1 == frames {
            enc.copy_texture_to_buffer(
                color.as_image_copy(),
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
        }
        gpu.queue.submit([enc.finish()]);
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| e.to_string())?;
        frame_ms.push(start.elapsed().as_secs_f64() * 1e3);
        if frame == 0 {
            first_pipelines = gpu.pipelines_created();
        }
    }
    let slice = readback.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| e.to_string())?;
    let data = slice.get_mapped_range().map_err(|e| e.to_string())?;
    let pixels = (0..h as usize)
        .flat_map(|y| data[y * row as usize..][..4 * w as usize].to_vec())
        .collect();
    Ok(Report {
        adapter: gpu.info.name.clone(),
        frame_ms,
        samples_per_frame: surface.samples_per_frame(&surface_mesh),
        pipelines: (first_pipelines, gpu.pipelines_created()),
        pixels,
    })
}
