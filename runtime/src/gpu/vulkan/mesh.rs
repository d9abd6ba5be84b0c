//! [`VkMesh`] creation: the constructors (quad and triangle schemes, with or
//! without displacement) turn an [`Upload`] (plus the adaptive buffers) into
//! storage buffers, descriptors and the compute and tessellation pipelines;
//! and its teardown.

use crate::abi::{binding, PARAMS_SIZE};
use crate::cpu::adaptive::{self, Adaptive, Metric};
use crate::gpu::upload::{f32_bytes, params_bytes, u32_bytes, Upload, UploadBuffer};
use crate::mesh::topology::Topology;
use ash::vk;
use glam::{Mat4, Vec3};

use super::device::{call, check_limits, VkError};
use super::{displacing, Img, Language, Options, VkMesh, Vulkan, DISPLACE, LAYOUT_BINDINGS};

impl<'v> VkMesh<'v> {
    /// A quad mesh for a quad scheme.
    pub fn new(
        vk: &'v Vulkan,
        topo: &Topology,
        positions: &[Vec3],
        scheme: &str,
        options: &Options,
    ) -> Result<Self, VkError> {
        let upload = Self::quad_upload(vk, topo, positions, scheme, options)?;
        Self::build(vk, upload, options)
    }

    /// A refined quad mesh whose positions the GPU computes
    /// (docs/boundaries.md §8): `topo` is the refined topology, `base` the
    /// base mesh's positions, `stencils` one row per refined vertex; the
    /// emitted `refine_main` runs before the vertex stage. `displaced` adds
    /// displacement as [`Self::new_displaced`] does (`mesh`: the refined
    /// mesh).
    pub fn new_refined(
        vk: &'v Vulkan,
        topo: &Topology,
        base: &[Vec3],
        stencils: &crate::mesh::refine::StencilTable,
        scheme: &str,
        displaced: Option<(&crate::Mesh, &crate::cpu::displace::Displacement)>,
        options: &Options,
    ) -> Result<Self, VkError> {
        let zeros = vec![Vec3::ZERO; topo.valence.len()];
        let upload = Self::quad_upload(vk, topo, &zeros, scheme, options)?
            .with_refinement(base, stencils)?;
        match displaced {
            None => Self::build(vk, upload, options),
            Some((mesh, d)) => Self::build(
                vk,
                upload.displaced_quads(mesh, topo, d)?,
                &displacing(options),
            ),
        }
    }

    /// A quad mesh with displacement ([`crate::cpu::displace`]): the texture
    /// coordinates come from `mesh` (the OBJ's `vt`), the owners are
    /// recorded in this upload's class-sorted control-point layout, and the
    /// shaders are built with [`DISPLACE`]: the harness runs the compute
    /// patch stage into the global control-point buffer, then the draws,
    /// whose evaluation stage displaces each captured sample.
    pub fn new_displaced(
        vk: &'v Vulkan,
        mesh: &crate::Mesh,
        topo: &Topology,
        positions: &[Vec3],
        scheme: &str,
        d: &crate::cpu::displace::Displacement,
        options: &Options,
    ) -> Result<Self, VkError> {
        let upload = Self::quad_upload(vk, topo, positions, scheme, options)?
            .displaced_quads(mesh, topo, d)?;
        Self::build(vk, upload, &displacing(options))
    }

    /// A triangle mesh for a triangle scheme with displacement: 12 texture
    /// coordinates per triangle from `source` (the mesh `tri` was made
    /// from, [`crate::cpu::displace::build_tri`]), owners in this upload's
    /// layout, shaders built with [`DISPLACE`]. The harness runs the
    /// compute patch stage into the global control-point buffer before the
    /// draws; the evaluation stage's `eval_domain_displaced_tess` displaces
    /// boundary points with the owner's normal and texture coordinate and
    /// interior points with their own. Capture with
    /// [`Self::evaluate_triangles`] (or [`Self::evaluate_adaptive`]).
    pub fn new_tri_displaced(
        vk: &'v Vulkan,
        source: &crate::Mesh,
        tri: &crate::mesh::trimesh::TriMesh,
        scheme: &str,
        d: &crate::cpu::displace::Displacement,
        options: &Options,
    ) -> Result<Self, VkError> {
        let upload = Self::tri_upload(vk, tri, scheme, options)?.displaced_tris(source, tri, d)?;
        Self::build(vk, upload, &displacing(options))
    }

    /// Whether the shaders are built with [`DISPLACE`].
    pub(super) fn displaced(&self) -> bool {
        self.options.defines.iter().any(|x| x == DISPLACE)
    }

    /// The upload of a quad mesh, with the adaptive buffers if asked for.
    fn quad_upload(
        vk: &'v Vulkan,
        topo: &Topology,
        positions: &[Vec3],
        scheme: &str,
        options: &Options,
    ) -> Result<Upload, VkError> {
        let mut upload = Upload::quad(topo, positions, scheme)?;
        if let Some(a) = &options.adaptive {
            let (ids, edges) = adaptive::edge_ids(topo);
            upload.buffers.extend(adaptive_buffers(vk, a, ids, edges)?);
        }
        Ok(upload)
    }

    /// A triangle mesh for a triangle scheme.
    pub fn new_tri(
        vk: &'v Vulkan,
        mesh: &crate::mesh::trimesh::TriMesh,
        scheme: &str,
        options: &Options,
    ) -> Result<Self, VkError> {
        let upload = Self::tri_upload(vk, mesh, scheme, options)?;
        Self::build(vk, upload, options)
    }

    /// The upload of a triangle mesh, with the adaptive buffers if asked for.
    fn tri_upload(
        vk: &'v Vulkan,
        mesh: &crate::mesh::trimesh::TriMesh,
        scheme: &str,
        options: &Options,
    ) -> Result<Upload, VkError> {
        let mut upload = Upload::tri(mesh, scheme)?;
        if let Some(a) = &options.adaptive {
            let (ids, edges) = mesh.edge_ids();
            upload.buffers.extend(adaptive_buffers(vk, a, ids, edges)?);
        }
        Ok(upload)
    }

    fn empty(vk: &'v Vulkan, upload: &Upload, options: &Options) -> Self {
        VkMesh {
            vk,
            scheme: upload.scheme,
            options: options.clone(),
            classes: upload.classes.clone(),
            patch_faces: upload.patch_faces.clone(),
            num_vertices: upload.num_vertices,
            buffers: Vec::new(),
            dummy: None,
            params: None,
            table_img: Img::default(),
            map_img: Img::default(),
            sampler: vk::Sampler::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
            layout: vk::PipelineLayout::null(),
            render_pass: vk::RenderPass::null(),
            framebuffer: vk::Framebuffer::null(),
            modules: Vec::new(),
            vertex_pipeline: vk::Pipeline::null(),
            refine_pipeline: vk::Pipeline::null(),
            refine: upload.refine,
            patch_pipeline: vk::Pipeline::null(),
            eval_pipeline: vk::Pipeline::null(),
            draw_pipeline: vk::Pipeline::null(),
            displace_map: upload.displace_map.clone(),
        }
    }

    fn build(vk: &'v Vulkan, upload: Upload, options: &Options) -> Result<Self, VkError> {
        Self::build_on(vk, upload, options).map_err(|e| e.on_device(&vk.name))
    }

    fn build_on(vk: &'v Vulkan, upload: Upload, options: &Options) -> Result<Self, VkError> {
        check_limits(upload.scheme, &vk.limits, &vk.name)?;
        let max = vk.limits.max_storage_buffer_range as u64;
        for b in &upload.buffers {
            if b.bytes.len() as u64 > max {
                return Err(VkError::Limit {
                    scheme: upload.scheme.name.into(),
                    what: "bytes in one storage buffer (maxStorageBufferRange)",
                    needed: b.bytes.len() as u64,
                    max,
                    device: vk.name.clone(),
                });
            }
        }
        // Every handle goes into `mesh` as soon as it exists, so an error
        // part-way drops (and destroys) what was made.
        let mut mesh = Self::empty(vk, &upload, options);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        for b in &upload.buffers {
            let buf = vk.buffer(b.label, b.bytes.len() as u64, storage)?;
            buf.write(&b.bytes);
            mesh.buffers.push((b.binding, buf));
        }
        mesh.dummy = Some(vk.buffer("unused bindings", 16, storage)?);
        mesh.params =
            Some(vk.buffer("params", PARAMS_SIZE, vk::BufferUsageFlags::UNIFORM_BUFFER)?);
        mesh.table()?;
        mesh.map()?;
        mesh.descriptors()?;
        mesh.pipelines()?;
        mesh.construct()?;
        Ok(mesh)
    }

    /// Descriptor type of a binding as the emitted language declares it:
    /// GLSL's table and displacement map are `sampler2D`s, HLSL's
    /// `Texture2D`s (`.Load`).
    pub(super) fn descriptor_type(&self, b: u32) -> vk::DescriptorType {
        match (b, self.options.language) {
            (binding::STENCIL_TABLE | binding::DISPLACE_MAP, Language::Glsl) => {
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER
            }
            (binding::STENCIL_TABLE | binding::DISPLACE_MAP, Language::Hlsl) => {
                vk::DescriptorType::SAMPLED_IMAGE
            }
            (binding::PARAMS, _) => vk::DescriptorType::UNIFORM_BUFFER,
            _ => vk::DescriptorType::STORAGE_BUFFER,
        }
    }

    /// One set with every ABI binding, visible to every stage.
    fn descriptors(&mut self) -> Result<(), VkError> {
        let d = &self.vk.device;
        let bindings: Vec<vk::DescriptorSetLayoutBinding> = LAYOUT_BINDINGS
            .iter()
            .map(|&b| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b)
                    .descriptor_type(self.descriptor_type(b))
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::ALL)
            })
            .collect();
        self.set_layout = unsafe {
            d.create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                None,
            )
        }
        .map_err(call("vkCreateDescriptorSetLayout"))?;
        let sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: LAYOUT_BINDINGS.len() as u32,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::UNIFORM_BUFFER,
                descriptor_count: 1,
            },
            vk::DescriptorPoolSize {
                ty: self.descriptor_type(binding::STENCIL_TABLE),
                // The stencil table and the displacement map.
                descriptor_count: 2,
            },
        ];
        self.pool = unsafe {
            d.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(1)
                    .pool_sizes(&sizes),
                None,
            )
        }
        .map_err(call("vkCreateDescriptorPool"))?;
        let layouts = [self.set_layout];
        self.set = unsafe {
            d.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(self.pool)
                    .set_layouts(&layouts),
            )
        }
        .map_err(call("vkAllocateDescriptorSets"))?[0];
        self.layout = unsafe {
            d.create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default().set_layouts(&layouts),
                None,
            )
        }
        .map_err(call("vkCreatePipelineLayout"))?;
        for &b in LAYOUT_BINDINGS {
            if b == binding::SAMPLES {
                continue;
            }
            if b == binding::STENCIL_TABLE || b == binding::DISPLACE_MAP {
                let view = if b == binding::STENCIL_TABLE {
                    self.table_img.view
                } else {
                    self.map_img.view
                };
                let info = [vk::DescriptorImageInfo::default()
                    .sampler(self.sampler)
                    .image_view(view)
                    .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)];
                let w = vk::WriteDescriptorSet::default()
                    .dst_set(self.set)
                    .dst_binding(b)
                    .descriptor_type(self.descriptor_type(b))
                    .image_info(&info);
                unsafe { d.update_descriptor_sets(&[w], &[]) };
                continue;
            }
            // The refinement stage writes the buffer the vertex stage reads
            // as `positions`.
            let b_buf = if b == binding::REFINED_POSITIONS && self.refine.is_some() {
                binding::POSITIONS
            } else {
                b
            };
            let buf = if b == binding::PARAMS {
                self.params.as_ref()
            } else {
                self.buffers
                    .iter()
                    .find(|(k, _)| *k == b_buf)
                    .map(|(_, buf)| buf)
                    .or(self.dummy.as_ref())
            };
            if let Some(buf) = buf {
                self.write_buffer(b, buf);
            }
        }
        Ok(())
    }

    /// A compute pipeline of the emitted `stage` ("comp": the vertex stage,
    /// "patch", "eval").
    pub(super) fn compute_pipeline(
        &mut self,
        stage: &'static str,
    ) -> Result<vk::Pipeline, VkError> {
        let (m, name) = self.module(stage)?;
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(m)
            .name(name);
        let ci = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(self.layout);
        Ok(unsafe {
            self.vk
                .device
                .create_compute_pipelines(vk::PipelineCache::null(), &[ci], None)
        }
        .map_err(|(_, e)| call("vkCreateComputePipelines")(e))?[0])
    }

    fn pipelines(&mut self) -> Result<(), VkError> {
        if self.num_vertices > 0 {
            self.vertex_pipeline = self.compute_pipeline("comp")?;
        }
        if self.refine.is_some() {
            self.refine_pipeline = self.compute_pipeline("refine")?;
        }
        if self.displaced() {
            self.patch_pipeline = self.compute_pipeline("patch")?;
        }
        let (vert, vn) = self.module("vert")?;
        let (tesc, cn) = self.module("tesc")?;
        let (tese, en) = self.module("tese")?;
        // Triangle schemes and adaptive draws: the harness's geometry
        // shader records the tessellator's output triangles (see
        // CAPTURE_GEOMETRY_TEMPLATE).
        let geom = if self.scheme.sides == 3 || self.options.adaptive.is_some() {
            if !self.vk.geometry_shader {
                return Err(VkError::NoGeometryShader);
            }
            Some(self.module("geom")?)
        } else {
            None
        };
        let d = &self.vk.device;
        let sub =
            [vk::SubpassDescription::default()
                .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)];
        self.render_pass = unsafe {
            d.create_render_pass(&vk::RenderPassCreateInfo::default().subpasses(&sub), None)
        }
        .map_err(call("vkCreateRenderPass"))?;
        self.framebuffer = unsafe {
            d.create_framebuffer(
                &vk::FramebufferCreateInfo::default()
                    .render_pass(self.render_pass)
                    .width(1)
                    .height(1)
                    .layers(1),
                None,
            )
        }
        .map_err(call("vkCreateFramebuffer"))?;
        let mut stages = vec![
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vert)
                .name(vn),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::TESSELLATION_CONTROL)
                .module(tesc)
                .name(cn),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::TESSELLATION_EVALUATION)
                .module(tese)
                .name(en),
        ];
        if let Some((gm, gn)) = geom {
            stages.push(
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(vk::ShaderStageFlags::GEOMETRY)
                    .module(gm)
                    .name(gn),
            );
        }
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::PATCH_LIST);
        let tess = vk::PipelineTessellationStateCreateInfo::default().patch_control_points(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .rasterizer_discard_enable(true)
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let ci = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .tessellation_state(&tess)
            .rasterization_state(&raster)
            .layout(self.layout)
            .render_pass(self.render_pass)
            .subpass(0);
        self.draw_pipeline =
            unsafe { d.create_graphics_pipelines(vk::PipelineCache::null(), &[ci], None) }
                .map_err(|(_, e)| call("vkCreateGraphicsPipelines")(e))?[0];
        Ok(())
    }

    pub(super) fn set_params(&self, p: [u32; 6]) {
        if let Some(b) = &self.params {
            b.write(&params_bytes(
                Mat4::IDENTITY,
                p[0],
                p[1],
                p[2],
                p[3],
                p[4],
                p[5],
            ));
        }
    }
}

/// The adaptive buffers (bindings 17–19) for `face_edges` ids at
/// `sides·f + k` over `edges` edges: the ids, the explicit factors, the
/// metric parameters. [`Metric::PerFaceEdge`] (the negative control) gives
/// every face edge its own id instead.
pub(super) fn adaptive_buffers(
    vk: &Vulkan,
    a: &Adaptive,
    mut ids: Vec<u32>,
    mut edges: u32,
) -> Result<Vec<UploadBuffer>, VkError> {
    if !vk.geometry_shader {
        return Err(VkError::NoGeometryShader);
    }
    if let Metric::PerFaceEdge(_) = &a.metric {
        edges = ids.len() as u32;
        ids = (0..edges).collect();
    }
    if let Metric::Buffer(f) | Metric::PerFaceEdge(f) = &a.metric {
        if f.len() != edges as usize {
            return Err(VkError::EdgeFactorCount {
                expected: edges as usize,
                got: f.len(),
            });
        }
    }
    let buf = |binding, label, bytes| UploadBuffer {
        binding,
        label,
        bytes,
        read_back: false,
    };
    Ok(vec![
        buf(binding::FACE_EDGES, "face_edges", u32_bytes(&ids)),
        buf(
            binding::EDGE_FACTORS,
            "edge_factors",
            f32_bytes(a.edge_factors()),
        ),
        buf(binding::ADAPTIVE, "adaptive", f32_bytes(&a.params())),
    ])
}

impl Drop for VkMesh<'_> {
    fn drop(&mut self) {
        let d = &self.vk.device;
        unsafe {
            let _ = d.device_wait_idle();
            d.destroy_pipeline(self.draw_pipeline, None);
            d.destroy_pipeline(self.vertex_pipeline, None);
            d.destroy_pipeline(self.refine_pipeline, None);
            for m in &self.modules {
                d.destroy_shader_module(*m, None);
            }
            d.destroy_framebuffer(self.framebuffer, None);
            d.destroy_render_pass(self.render_pass, None);
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_pool(self.pool, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
            d.destroy_sampler(self.sampler, None);
        }
        self.table_img.destroy(d);
        self.map_img.destroy(d);
        unsafe {
            d.destroy_pipeline(self.patch_pipeline, None);
            d.destroy_pipeline(self.eval_pipeline, None);
        }
        for (_, b) in &self.buffers {
            b.destroy(d);
        }
        for b in [&self.dummy, &self.params].into_iter().flatten() {
            b.destroy(d);
        }
    }
}
