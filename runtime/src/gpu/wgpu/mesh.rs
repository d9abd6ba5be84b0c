//! A control mesh onto the device: [`GpuMesh`]'s constructors (quad and
//! triangle schemes, with or without displacement) upload an [`Upload`]
//! into buffers and `R32Float` textures (stencil table, displacement map)
//! checked against the [`Limits`], build the pipelines, and run the vertex
//! and patch stages ([`GpuMesh::construct`]); new positions go in with
//! [`GpuMesh::update_positions`], the control points come back with
//! [`GpuMesh::control_points`].

use crate::abi::{self, binding};
use crate::gpu::upload::{params_bytes, vec3_bytes, Upload};
use crate::kernels;
use crate::mesh::topology::Topology;
use glam::{Mat4, Vec3};
use std::collections::HashMap;

use super::device::{check, entry_bindings};
use super::{Gpu, GpuError, GpuMesh, Limits};

/// An `R32Float` texture holding `texels` (row-major, `width` columns).
pub(super) fn r32_texture(
    gpu: &Gpu,
    label: &'static str,
    width: u32,
    height: u32,
    texels: &[f32],
) -> wgpu::TextureView {
    let size = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    };
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let bytes: Vec<u8> = texels.iter().flat_map(|w| w.to_le_bytes()).collect();
    gpu.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        &bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * width),
            rows_per_image: Some(height),
        },
        size,
    );
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

impl<'g> GpuMesh<'g> {
    /// Upload a mesh and build the scheme's pipelines, with the device's limits.
    pub fn new(
        gpu: &'g Gpu,
        topo: &Topology,
        positions: &[Vec3],
        scheme: &str,
    ) -> Result<Self, GpuError> {
        Self::with_limits(gpu, topo, positions, scheme, gpu.limits)
    }

    /// Like [`GpuMesh::new`] with explicit (smaller) limits.
    pub fn with_limits(
        gpu: &'g Gpu,
        topo: &Topology,
        positions: &[Vec3],
        scheme_name: &str,
        limits: Limits,
    ) -> Result<Self, GpuError> {
        let upload = Upload::quad(topo, positions, scheme_name)?;
        Self::build(gpu, limits, upload)
    }

    /// Upload a refined quad mesh whose positions the GPU computes
    /// (docs/boundaries.md §8): `topo` is the refined topology, `base` the
    /// base mesh's positions and `stencils` one row per refined vertex. Every
    /// [`GpuMesh::construct`] runs `refine_main` before the vertex stage,
    /// so [`GpuMesh::update_positions`] takes *base* positions: an animated
    /// mesh refines on the GPU, to the CPU's bits (`StencilTable::apply`
    /// sums in the same order). `displaced` adds displacement as
    /// [`GpuMesh::new_displaced`] does, with `mesh` the refined mesh.
    pub fn new_refined(
        gpu: &'g Gpu,
        topo: &Topology,
        base: &[Vec3],
        stencils: &crate::mesh::refine::StencilTable,
        scheme_name: &str,
        displaced: Option<(&crate::Mesh, &crate::cpu::displace::Displacement)>,
    ) -> Result<Self, GpuError> {
        let zeros = vec![Vec3::ZERO; topo.valence.len()];
        let upload = Upload::quad(topo, &zeros, scheme_name)?.with_refinement(base, stencils)?;
        let upload = match displaced {
            None => upload,
            Some((mesh, d)) => upload.displaced_quads(mesh, topo, d)?,
        };
        Self::build(gpu, gpu.limits, upload)
    }

    /// Upload a quad mesh with displacement ([`crate::cpu::displace`]): the
    /// texture coordinates come from `mesh` (the OBJ's `vt`), owners are
    /// recorded in this upload's class-sorted control-point layout.
    pub fn new_displaced(
        gpu: &'g Gpu,
        mesh: &crate::Mesh,
        topo: &Topology,
        positions: &[Vec3],
        scheme_name: &str,
        d: &crate::cpu::displace::Displacement,
    ) -> Result<Self, GpuError> {
        let upload = Upload::quad(topo, positions, scheme_name)?.displaced_quads(mesh, topo, d)?;
        Self::build(gpu, gpu.limits, upload)
    }

    /// Upload a triangle mesh for a triangle scheme (`pn`, `stpn`, `phong`):
    /// corner vertices, positions, unit normals and the crease tags (read
    /// only by `stpn`); no vertex stage runs.
    pub fn new_tri(
        gpu: &'g Gpu,
        mesh: &crate::mesh::trimesh::TriMesh,
        scheme_name: &str,
    ) -> Result<Self, GpuError> {
        Self::with_limits_tri(gpu, mesh, scheme_name, gpu.limits)
    }

    /// Upload a triangle mesh with displacement: 12 texture coordinates per
    /// triangle from `mesh` (the mesh `tri` was made from), owners recorded
    /// in this upload's class-sorted control-point layout
    /// ([`crate::cpu::displace::build_tri`]).
    pub fn new_tri_displaced(
        gpu: &'g Gpu,
        mesh: &crate::Mesh,
        tri: &crate::mesh::trimesh::TriMesh,
        scheme_name: &str,
        d: &crate::cpu::displace::Displacement,
    ) -> Result<Self, GpuError> {
        let upload = Upload::tri(tri, scheme_name)?.displaced_tris(mesh, tri, d)?;
        Self::build(gpu, gpu.limits, upload)
    }

    /// Like [`GpuMesh::new_tri`] with explicit (smaller) limits.
    pub fn with_limits_tri(
        gpu: &'g Gpu,
        mesh: &crate::mesh::trimesh::TriMesh,
        scheme_name: &str,
        limits: Limits,
    ) -> Result<Self, GpuError> {
        let upload = Upload::tri(mesh, scheme_name)?;
        Self::build(gpu, limits, upload)
    }

    /// The parts every mesh shares: buffers, the stencil table, pipelines,
    /// then the first construction.
    fn build(gpu: &'g Gpu, limits: Limits, upload: Upload) -> Result<Self, GpuError> {
        gpu.healthy()?;
        let scheme = upload.scheme;
        for b in &upload.buffers {
            check(&gpu.info.name, &limits, b.label, b.bytes.len() as u64)?;
        }
        let source =
            kernels::wgsl(scheme.name).ok_or_else(|| GpuError::NoShader(scheme.name.into()))?;
        let bindings = entry_bindings(scheme.name)?;
        let dev = &gpu.device;
        let mut buffers = HashMap::new();
        for b in upload.buffers {
            let (label, contents) = (b.label, b.bytes);
            let extra = if b.read_back {
                wgpu::BufferUsages::COPY_SRC
            } else {
                wgpu::BufferUsages::empty()
            };
            let buf = dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                // wgpu rejects zero-sized storage bindings.
                size: (contents.len() as u64).max(16),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | extra,
                mapped_at_creation: false,
            });
            gpu.queue.write_buffer(&buf, 0, &contents);
            buffers.insert(b.binding, buf);
        }

        // The stencil table as an R32Float texture, its rows wrapped into
        // column blocks (`kernels::table_texture`).
        let table = kernels::table_texture();
        let width = kernels::common::TABLE_TEXTURE_WIDTH;
        let height = kernels::common::TABLE_TEXTURE_HEIGHT;
        if width > limits.max_texture_dimension_2d || height > limits.max_texture_dimension_2d {
            return Err(GpuError::TableTooLarge {
                width,
                height,
                max: limits.max_texture_dimension_2d,
                adapter: gpu.info.name.clone(),
            });
        }
        let table_view = r32_texture(gpu, "stencil_table", width, height, table);
        let map = &upload.displace_map;
        if map.width > limits.max_texture_dimension_2d
            || map.height > limits.max_texture_dimension_2d
        {
            return Err(GpuError::MapTooLarge {
                width: map.width,
                height: map.height,
                max: limits.max_texture_dimension_2d,
                adapter: gpu.info.name.clone(),
            });
        }
        let displace_view = r32_texture(gpu, "displace_map", map.width, map.height, &map.texels);

        let (module, vertex_pipeline, patch_pipeline, eval_pipeline) = gpu.scoped(|| {
            let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(scheme.name),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            let pipe = |entry: &str| {
                gpu.count_pipeline();
                dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: None,
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            };
            let v = pipe(abi::entry::VERTEX_STAGE);
            let p = pipe(abi::entry::PATCH_STAGE);
            let e = pipe(abi::entry::EVAL);
            (module, v, p, e)
        })?;
        let mesh = GpuMesh {
            gpu,
            scheme,
            limits,
            classes: upload.classes,
            patch_faces: upload.patch_faces,
            num_vertices: upload.num_vertices,
            num_positions: upload.num_positions,
            refine: upload.refine,
            buffers,
            table_view,
            displace_view,
            module,
            bindings,
            vertex_pipeline,
            patch_pipeline,
            eval_pipeline,
            pipelines: Default::default(),
            driven_samples: Default::default(),
        };
        mesh.construct()?;
        Ok(mesh)
    }

    /// Run the refinement stage (a refined mesh), then the vertex and patch
    /// stages (again), e.g. after moving positions.
    pub fn construct(&self) -> Result<(), GpuError> {
        let dev = &self.gpu.device;
        // Built (and cached) outside the error scope below.
        let refine = match self.refine {
            Some(r) => Some((r, self.compute_pipeline(abi::entry::REFINE)?)),
            None => None,
        };
        self.gpu.scoped(|| {
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("construct"),
            });
            // (pipeline, bind group, workgroups) in dispatch order.
            let mut groups: Vec<(&wgpu::ComputePipeline, wgpu::BindGroup, u32)> = Vec::new();
            if let Some((r, pipeline)) = &refine {
                let layout = pipeline.get_bind_group_layout(0);
                let chunk = self.chunk(1) as u32;
                let mut first = 0;
                while first < r.rows {
                    let count = chunk.min(r.rows - first);
                    let p =
                        self.params_buffer(&params_bytes(Mat4::IDENTITY, first, count, 0, 0, 1, 0));
                    groups.push((
                        pipeline,
                        self.bind_group(abi::entry::REFINE, &layout, &p, None),
                        count.div_ceil(abi::WORKGROUP_SIZE),
                    ));
                    first += count;
                }
            }
            let vchunk = self.chunk(1) as u32;
            let mut first = 0;
            while first < self.num_vertices {
                let count = vchunk.min(self.num_vertices - first);
                let p = self.params_buffer(&params_bytes(Mat4::IDENTITY, first, count, 0, 0, 1, 0));
                let layout = self.vertex_pipeline.get_bind_group_layout(0);
                groups.push((
                    &self.vertex_pipeline,
                    self.bind_group(abi::entry::VERTEX_STAGE, &layout, &p, None),
                    count.div_ceil(abi::WORKGROUP_SIZE),
                ));
                first += count;
            }
            let pchunk = self.chunk(1) as u32;
            for c in &self.classes {
                let mut k = 0;
                while k < c.count {
                    let count = pchunk.min(c.count - k);
                    let p = self.params_buffer(&params_bytes(
                        Mat4::IDENTITY,
                        c.first + k,
                        count,
                        c.class,
                        c.cp_base + k * c.points,
                        1,
                        0,
                    ));
                    let layout = self.patch_pipeline.get_bind_group_layout(0);
                    groups.push((
                        &self.patch_pipeline,
                        self.bind_group(abi::entry::PATCH_STAGE, &layout, &p, None),
                        count.div_ceil(abi::WORKGROUP_SIZE),
                    ));
                    k += count;
                }
            }
            {
                // Dispatches of one pass are ordered: each sees the storage
                // writes of the ones before it.
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("construct"),
                    timestamp_writes: None,
                });
                for (pipeline, group, wgs) in &groups {
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(0, group, &[]);
                    pass.dispatch_workgroups(*wgs, 1, 1);
                }
            }
            self.gpu.queue.submit([enc.finish()]);
        })
    }

    /// Block until all submitted GPU work is done (for timing).
    pub fn wait(&self) -> Result<(), GpuError> {
        self.gpu
            .device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map(|_| ())
            .map_err(|e| GpuError::Readback(e.to_string()))
    }

    /// Upload moved control-mesh positions and rebuild the patches; the
    /// topology, rings and table stay on the GPU. For a refined mesh
    /// ([`GpuMesh::new_refined`]) these are the *base* mesh's positions,
    /// refined on the GPU.
    pub fn update_positions(&self, positions: &[Vec3]) -> Result<(), GpuError> {
        let (expected, target) = match self.refine {
            Some(r) => (r.base, binding::REFINE_BASE),
            None => (self.num_positions, binding::POSITIONS),
        };
        if positions.len() as u32 != expected {
            return Err(GpuError::PositionCount {
                expected: expected as usize,
                got: positions.len(),
            });
        }
        if let Some(buf) = self.buffers.get(&target) {
            self.gpu.queue.write_buffer(buf, 0, &vec3_bytes(positions));
        }
        self.construct()
    }

    /// Read back the control points (class-sorted layout, see [`ClassRange`](super::ClassRange)).
    pub fn control_points(&self) -> Result<Vec<Vec3>, GpuError> {
        let Some(src) = self.buffers.get(&binding::CONTROL_POINTS) else {
            return Ok(Vec::new());
        };
        let staging = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("control points readback"),
            size: src.size(),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("cp readback"),
            });
        enc.copy_buffer_to_buffer(src, 0, &staging, 0, src.size());
        self.gpu.queue.submit([enc.finish()]);
        let f = self.read(&staging)?;
        Ok(f.chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect())
    }
}
