//! The wgpu GPU path: the generated WGSL runs the vertex and patch stages in
//! compute passes and evaluates patches either into a storage buffer (for
//! readback) or in an instanced vertex shader (for drawing).
//!
//! Layout follows OpenSubdiv's `Far` idea: topology, rings and the stencil
//! table are uploaded once as flat buffers / an `R32Float` texture; the GPU
//! only indexes them. Patches are sorted by facet class so each class is one
//! dispatch (or one instanced draw). Device limits are respected by splitting
//! dispatches and readbacks into chunks, never by truncating.

use crate::cpu::{self, Tessellation};
use crate::gpu::readback::GridReadback;
use crate::kernels::{self, common::SchemeKernels};
use crate::mesh::topology::Topology;
use glam::{Mat4, Vec3};
use std::collections::HashMap;

use crate::abi::{self, binding, PARAMS_SIZE};
pub use crate::gpu::upload::ClassRange;
use crate::gpu::upload::{params_bytes, vec3_bytes, Upload, UploadError};
use wgpu::naga;

/// Bucket slots per class range of the GPU-driven adaptive buffers (slot
/// `BUCKET_SLOTS·r + j`: class range r, bucket `2^j`; from the ABI).
pub(crate) const SLOTS: u32 = abi::BUCKET_SLOTS;
/// Patches per chunk of the GPU-driven bucket compaction (one workgroup
/// each in `adaptive_count_main` / `adaptive_scatter_main`; from the ABI).
pub(crate) const CHUNK: u32 = abi::BUCKET_CHUNK;

/// How one compute run of a phase is dispatched: direct with x workgroups,
/// or indirect from the byte offset of its slot's arguments.
pub(crate) enum Run {
    Direct(u32),
    Indirect(u64),
}

/// The buffers of one GPU-driven adaptive run (see
/// [`GpuMesh::evaluate_adaptive_gpu_driven`]).
pub(crate) struct Buckets {
    face_edges: wgpu::Buffer,
    edge_factors: wgpu::Buffer,
    params: wgpu::Buffer,
    levels: wgpu::Buffer,
    list: wgpu::Buffer,
    dispatch: wgpu::Buffer,
    pub(crate) draw: wgpu::Buffer,
    chunks: wgpu::Buffer,
    pub(crate) slots: u32,
    list_words: u64,
}

impl Buckets {
    /// The per-call bindings: the edge inputs, the levels, the lists
    /// (also as `bucket_patches`, what the evaluation and the draws read)
    /// and the indirect arguments.
    pub(crate) fn bindings(&self) -> [(u32, &wgpu::Buffer); 9] {
        [
            (binding::FACE_EDGES, &self.face_edges),
            (binding::EDGE_FACTORS, &self.edge_factors),
            (binding::ADAPTIVE, &self.params),
            (binding::PATCH_LEVELS, &self.levels),
            (binding::BUCKET_LIST, &self.list),
            (binding::BUCKET_DISPATCH, &self.dispatch),
            (binding::BUCKET_DRAW, &self.draw),
            (binding::BUCKET_PATCHES, &self.list),
            (binding::BUCKET_CHUNKS, &self.chunks),
        ]
    }
}

/// Errors of the GPU path.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found (on CI install Mesa's lavapipe: apt-get install mesa-vulkan-drivers)"
    )]
    NoAdapter,
    #[error("no adapter matches TESSGEN_ADAPTER={0:?}")]
    AdapterNotFound(String),
    #[error("requesting the device failed: {0}")]
    Device(String),
    #[error("no WGSL for scheme `{0}` in this build")]
    NoShader(String),
    #[error("generated WGSL does not parse/validate: {0}")]
    Shader(String),
    #[error("the displacement map ({width}x{height}) exceeds max_texture_dimension_2d = {max}")]
    MapTooLarge { width: u32, height: u32, max: u32 },
    #[error("the stencil table ({width}x{height}) exceeds max_texture_dimension_2d = {max}")]
    TableTooLarge { width: u32, height: u32, max: u32 },
    #[error("{what} needs {needed} bytes in one binding, more than max_storage_buffer_binding_size = {max}")]
    BufferTooLarge {
        what: &'static str,
        needed: u64,
        max: u64,
    },
    #[error("{patches} patches need {chunks} workgroups of {CHUNK} in one dispatch of the GPU-driven buckets, more than max_workgroups_per_dimension = {max}")]
    TooManyChunks { patches: u64, chunks: u64, max: u32 },
    #[error("wgpu reported an error: {0}")]
    Wgpu(String),
    #[error("image: {0}")]
    Image(String),
    #[error("readback failed: {0}")]
    Readback(String),
    #[error(transparent)]
    Tess(#[from] cpu::TessError),
    #[error("positions: expected {expected}, got {got}")]
    PositionCount { expected: usize, got: usize },
    #[error(transparent)]
    Adaptive(#[from] crate::cpu::adaptive::AdaptiveError),
}

impl From<UploadError> for GpuError {
    fn from(e: UploadError) -> Self {
        match e {
            UploadError::Tess(e) => GpuError::Tess(e),
            UploadError::PositionCount { expected, got } => {
                GpuError::PositionCount { expected, got }
            }
        }
    }
}

/// The limits this crate plans its dispatches with. Defaults come from the
/// device; tests force them small to exercise splitting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    pub max_workgroups_per_dimension: u32,
    pub max_texture_dimension_2d: u32,
    pub max_storage_buffer_binding_size: u64,
}

/// A device and queue.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: Limits,
}

impl Gpu {
    /// Pick an adapter: `TESSGEN_ADAPTER` (substring of the adapter name) if
    /// set, else the first high-performance adapter, software ones included
    /// (Mesa's lavapipe in CI).
    pub fn new() -> Result<Gpu, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Gpu, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if std::env::var_os("WGPU_BACKEND").is_none() {
            desc.backends = wgpu::Backends::PRIMARY;
        }
        let instance = wgpu::Instance::new(desc);
        let adapter = match std::env::var("TESSGEN_ADAPTER") {
            Ok(want) => {
                let all = instance.enumerate_adapters(wgpu::Backends::all()).await;
                all.into_iter()
                    .find(|a| {
                        a.get_info()
                            .name
                            .to_lowercase()
                            .contains(&want.to_lowercase())
                    })
                    .ok_or(GpuError::AdapterNotFound(want))?
            }
            Err(_) => instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::HighPerformance,
                    force_fallback_adapter: false,
                    compatible_surface: None,
                    ..Default::default()
                })
                .await
                .map_err(|_| GpuError::NoAdapter)?,
        };
        let info = adapter.get_info();
        let alimits = adapter.limits();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("tessgen"),
                required_features: wgpu::Features::empty(),
                required_limits: alimits.clone(),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::Device(e.to_string()))?;
        let limits = Limits {
            max_workgroups_per_dimension: alimits.max_compute_workgroups_per_dimension,
            max_texture_dimension_2d: alimits.max_texture_dimension_2d,
            max_storage_buffer_binding_size: alimits.max_storage_buffer_binding_size as u64,
        };
        Ok(Gpu {
            device,
            queue,
            info,
            limits,
        })
    }

    /// Run `f` and turn any wgpu validation error it caused into a `GpuError`.
    pub(crate) fn scoped<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(GpuError::Wgpu(e.to_string())),
            None => Ok(out),
        }
    }
}

/// Which bindings each entry point of a WGSL module uses (naga reflection),
/// so bind groups match the pipelines' automatic layouts exactly.
fn entry_bindings(source: &str) -> Result<HashMap<String, Vec<u32>>, GpuError> {
    let module = naga::front::wgsl::parse_str(source)
        .map_err(|e| GpuError::Shader(e.emit_to_string(source)))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| GpuError::Shader(e.emit_to_string(source)))?;
    let mut out = HashMap::new();
    for (i, ep) in module.entry_points.iter().enumerate() {
        let fi = info.get_entry_point(i);
        let mut used = Vec::new();
        for (h, var) in module.global_variables.iter() {
            if !fi[h].is_empty() {
                if let Some(b) = &var.binding {
                    used.push(b.binding);
                }
            }
        }
        used.sort_unstable();
        out.insert(ep.name.clone(), used);
    }
    Ok(out)
}

/// A control mesh on the GPU with one scheme's pipelines.
pub struct GpuMesh<'g> {
    gpu: &'g Gpu,
    pub scheme: &'static SchemeKernels,
    pub limits: Limits,
    pub classes: Vec<ClassRange>,
    /// Face of each patch (patches sorted by class).
    pub patch_faces: Vec<u32>,
    /// Vertices the vertex stage runs over (0 for triangle schemes).
    num_vertices: u32,
    /// Control-mesh positions uploaded.
    num_positions: u32,
    buffers: HashMap<u32, wgpu::Buffer>,
    table_view: wgpu::TextureView,
    /// The displacement map (binding 20; 1×1 zero while displacement is off).
    displace_view: wgpu::TextureView,
    module: wgpu::ShaderModule,
    bindings: HashMap<String, Vec<u32>>,
    vertex_pipeline: wgpu::ComputePipeline,
    patch_pipeline: wgpu::ComputePipeline,
    eval_pipeline: wgpu::ComputePipeline,
    /// The other compute entries' pipelines (adaptive classify, bucket
    /// passes, adaptive evaluation), built on first use and kept: building
    /// one compiles the entry for the device, which on llvmpipe cost more
    /// than the work of a level-4 adaptive run when it was done per call.
    pipelines: std::sync::Mutex<HashMap<String, wgpu::ComputePipeline>>,
    /// The GPU-driven adaptive path's samples buffer (sized for every patch
    /// at the call's `max_level`), kept for the next call that fits:
    /// allocating and zero-initialising it per call was most of that
    /// path's cost over the host lists on llvmpipe. Locked for the whole
    /// call, so concurrent calls on one mesh do not share it.
    driven_samples: std::sync::Mutex<Option<wgpu::Buffer>>,
}

/// An `R32Float` texture holding `texels` (row-major, `width` columns).
fn r32_texture(
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

/// A buffer larger than one storage binding is a typed error, never a
/// truncation.
fn check(limits: &Limits, what: &'static str, bytes: u64) -> Result<(), GpuError> {
    if bytes > limits.max_storage_buffer_binding_size {
        Err(GpuError::BufferTooLarge {
            what,
            needed: bytes,
            max: limits.max_storage_buffer_binding_size,
        })
    } else {
        Ok(())
    }
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
        let upload = Upload::quad(topo, positions, scheme_name)?;
        let (class, cp_base) = upload.face_layout();
        let data = crate::cpu::displace::build(mesh, topo, &class, &cp_base, d)
            .map_err(cpu::TessError::from)?;
        Self::build(gpu, gpu.limits, upload.with_displacement(&data))
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
        let upload = Upload::tri(tri, scheme_name)?;
        let (class, cp_base) = upload.face_layout();
        let data = crate::cpu::displace::build_tri(mesh, tri, &class, &cp_base, d)
            .map_err(cpu::TessError::from)?;
        Self::build(gpu, gpu.limits, upload.with_displacement(&data))
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
        let scheme = upload.scheme;
        for b in &upload.buffers {
            check(&limits, b.label, b.bytes.len() as u64)?;
        }
        let source =
            kernels::wgsl(scheme.name).ok_or_else(|| GpuError::NoShader(scheme.name.into()))?;
        let bindings = entry_bindings(source)?;
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

        // The stencil table as an R32Float texture (x = ring slot, y = row).
        let table = kernels::table();
        let width = kernels::common::TABLE_WIDTH;
        let height = (table.len() as u32) / width;
        if width > limits.max_texture_dimension_2d || height > limits.max_texture_dimension_2d {
            return Err(GpuError::TableTooLarge {
                width,
                height,
                max: limits.max_texture_dimension_2d,
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
            });
        }
        let displace_view = r32_texture(gpu, "displace_map", map.width, map.height, &map.texels);

        let (module, vertex_pipeline, patch_pipeline, eval_pipeline) = gpu.scoped(|| {
            let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(scheme.name),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            let pipe = |entry: &str| {
                dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: None,
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            };
            let v = pipe("vertex_stage_main");
            let p = pipe("patch_main");
            let e = pipe("eval_main");
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

    pub(crate) fn gpu(&self) -> &Gpu {
        self.gpu
    }

    /// A Params uniform buffer.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn params(
        &self,
        view_proj: Mat4,
        first: u32,
        count: u32,
        class: u32,
        cp_base: u32,
        level: u32,
        out_base: u32,
        flags: u32,
    ) -> wgpu::Buffer {
        let mut bytes = params_bytes(view_proj, first, count, class, cp_base, level, out_base);
        let at = abi::params::FLAGS;
        bytes[at..at + 4].copy_from_slice(&flags.to_le_bytes());
        self.params_buffer(&bytes)
    }

    /// A storage buffer holding `bytes` (at least 16 bytes), with `extra`
    /// usages on top of STORAGE | COPY_DST.
    fn storage_init(
        &self,
        label: &'static str,
        bytes: &[u8],
        extra: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let buf = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: (bytes.len() as u64).max(16),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | extra,
            mapped_at_creation: false,
        });
        self.gpu.queue.write_buffer(&buf, 0, bytes);
        buf
    }

    /// The compute pipeline of one entry point of the scheme's module
    /// (layout derived from the shader), built once per mesh.
    fn compute_pipeline(&self, entry: &str) -> Result<wgpu::ComputePipeline, GpuError> {
        let cached = |m: &HashMap<String, wgpu::ComputePipeline>| m.get(entry).cloned();
        if let Some(p) = self.pipelines.lock().ok().as_deref().and_then(cached) {
            return Ok(p);
        }
        let p = self.gpu.scoped(|| {
            self.gpu
                .device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: None,
                    module: &self.module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
        })?;
        if let Ok(mut m) = self.pipelines.lock() {
            m.insert(entry.to_string(), p.clone());
        }
        Ok(p)
    }

    /// The checks both adaptive paths make before any GPU work — the mesh
    /// is of the scheme's domain (`Domain`) and the uploaded one
    /// (`MeshMismatch`) — and the edge inputs (factors, face edges, params).
    pub(crate) fn adaptive_inputs(
        &self,
        mesh: crate::cpu::adaptive::AdaptiveMesh<'_>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
    ) -> Result<crate::cpu::adaptive::EdgeInputs, GpuError> {
        crate::cpu::adaptive::check_mesh(self.scheme, &mesh, self.patch_faces.len())?;
        Ok(crate::cpu::adaptive::edge_inputs(mesh, a, max_level)?)
    }

    /// Per-face bucket levels, edge levels and sample offsets from the
    /// classify output (`patch_levels`: PATCH_LEVELS_WORDS per class-sorted patch, the
    /// edge levels then the bucket).
    fn face_levels(&self, words: &[u32]) -> (Vec<u32>, Vec<u32>, Vec<usize>) {
        let (faces, sides) = (self.patch_faces.len(), self.scheme.sides as usize);
        let mut levels = vec![0u32; faces];
        let mut edge_levels = vec![0u32; sides * faces];
        for (p, &face) in self.patch_faces.iter().enumerate() {
            let (w, face) = (
                &words[abi::LEVELS_LEN * p..][..abi::LEVELS_LEN],
                face as usize,
            );
            levels[face] = w[abi::LEVELS_BUCKET];
            edge_levels[sides * face..sides * face + sides].copy_from_slice(&w[..sides]);
        }
        let mut offsets = Vec::with_capacity(faces + 1);
        let mut total = 0usize;
        for &l in &levels {
            offsets.push(total);
            total += (self.scheme.grid_len)(l) as usize;
        }
        offsets.push(total);
        (levels, edge_levels, offsets)
    }

    /// Little-endian u32 words of a MAP_READ buffer.
    fn read_words(&self, staging: &wgpu::Buffer) -> Result<Vec<u32>, GpuError> {
        Ok(self
            .read_bytes(staging)?
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect())
    }

    fn params_buffer(&self, bytes: &[u8]) -> wgpu::Buffer {
        let buf = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: PARAMS_SIZE,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.gpu.queue.write_buffer(&buf, 0, bytes);
        buf
    }

    /// Bind group for `entry` with exactly the bindings it uses.
    pub(crate) fn bind_group(
        &self,
        entry: &str,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        samples: Option<&wgpu::Buffer>,
    ) -> wgpu::BindGroup {
        self.bind_group_with(entry, layout, params, samples, &[])
    }

    /// [`GpuMesh::bind_group`] with per-call buffers (`extra`, by binding)
    /// taking precedence over the mesh's own.
    pub(crate) fn bind_group_with(
        &self,
        entry: &str,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        samples: Option<&wgpu::Buffer>,
        extra: &[(u32, &wgpu::Buffer)],
    ) -> wgpu::BindGroup {
        let used = self.bindings.get(entry).cloned().unwrap_or_default();
        let mut entries = Vec::new();
        for b in used {
            if let Some((_, buf)) = extra.iter().find(|(k, _)| *k == b) {
                entries.push(wgpu::BindGroupEntry {
                    binding: b,
                    resource: buf.as_entire_binding(),
                });
                continue;
            }
            let resource = match b {
                binding::STENCIL_TABLE => wgpu::BindingResource::TextureView(&self.table_view),
                binding::DISPLACE_MAP => wgpu::BindingResource::TextureView(&self.displace_view),
                binding::PARAMS => params.as_entire_binding(),
                binding::SAMPLES => match samples {
                    Some(s) => s.as_entire_binding(),
                    None => continue,
                },
                other => match self.buffers.get(&other) {
                    Some(buf) => buf.as_entire_binding(),
                    None => continue,
                },
            };
            entries.push(wgpu::BindGroupEntry {
                binding: b,
                resource,
            });
        }
        self.gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(entry),
                layout,
                entries: &entries,
            })
    }

    /// Items per dispatch so that `items · per_item / WORKGROUP_SIZE` workgroups fit the limit.
    fn chunk(&self, per_item: u64) -> u64 {
        let max_threads = self.limits.max_workgroups_per_dimension as u64 * abi::WORKGROUP;
        (max_threads / per_item.max(1)).max(1)
    }

    /// Run the vertex and patch stages (again), e.g. after moving positions.
    pub fn construct(&self) -> Result<(), GpuError> {
        let dev = &self.gpu.device;
        self.gpu.scoped(|| {
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("construct"),
            });
            let mut groups = Vec::new();
            let vchunk = self.chunk(1) as u32;
            let mut first = 0;
            while first < self.num_vertices {
                let count = vchunk.min(self.num_vertices - first);
                let p = self.params_buffer(&params_bytes(Mat4::IDENTITY, first, count, 0, 0, 1, 0));
                let layout = self.vertex_pipeline.get_bind_group_layout(0);
                groups.push((
                    0,
                    self.bind_group("vertex_stage_main", &layout, &p, None),
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
                        1,
                        self.bind_group("patch_main", &layout, &p, None),
                        count.div_ceil(abi::WORKGROUP_SIZE),
                    ));
                    k += count;
                }
            }
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("construct"),
                    timestamp_writes: None,
                });
                for (stage, group, wgs) in &groups {
                    pass.set_pipeline(if *stage == 0 {
                        &self.vertex_pipeline
                    } else {
                        &self.patch_pipeline
                    });
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
    /// topology, rings and table stay on the GPU.
    pub fn update_positions(&self, positions: &[Vec3]) -> Result<(), GpuError> {
        if positions.len() as u32 != self.num_positions {
            return Err(GpuError::PositionCount {
                expected: self.num_positions as usize,
                got: positions.len(),
            });
        }
        if let Some(buf) = self.buffers.get(&binding::POSITIONS) {
            self.gpu.queue.write_buffer(buf, 0, &vec3_bytes(positions));
        }
        self.construct()
    }

    /// Evaluate every patch on its `level` grid (the scheme's `grid_len`
    /// samples) with `eval_main` and read it back, in face order (the same
    /// layout as the CPU path).
    pub fn evaluate(&self, level: u32) -> Result<Tessellation, GpuError> {
        if level == 0 || level > cpu::MAX_LEVEL {
            return Err(cpu::TessError::Level(level).into());
        }
        let spp = (self.scheme.grid_len)(level) as u64;
        let faces = self.patch_faces.len();
        let mut grids = GridReadback::new(level, self.scheme.sides, faces, spp);
        // Patches per readback chunk: within the dispatch and binding limits.
        let by_dispatch = self.chunk(spp);
        let by_binding =
            (self.limits.max_storage_buffer_binding_size / (spp * abi::SAMPLE_BYTES)).max(1);
        if spp * abi::SAMPLE_BYTES > self.limits.max_storage_buffer_binding_size {
            return Err(GpuError::BufferTooLarge {
                what: "samples of one patch",
                needed: spp * abi::SAMPLE_BYTES,
                max: self.limits.max_storage_buffer_binding_size,
            });
        }
        let chunk = by_dispatch.min(by_binding) as u32;
        let dev = &self.gpu.device;
        for c in &self.classes {
            let mut k = 0;
            while k < c.count {
                let count = chunk.min(c.count - k);
                let bytes = count as u64 * spp * abi::SAMPLE_BYTES;
                let samples = dev.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("samples"),
                    size: bytes,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                let staging = dev.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("samples readback"),
                    size: bytes,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                self.gpu.scoped(|| {
                    let p = self.params_buffer(&params_bytes(
                        Mat4::IDENTITY,
                        c.first + k,
                        count,
                        c.class,
                        c.cp_base + k * c.points,
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
                grids.scatter(&floats, (c.first + k) as u64, &self.patch_faces);
                k += count;
            }
        }
        Ok(grids.finish())
    }

    /// Adaptive tessellation on the instanced path (quad schemes on a
    /// [`Topology`], triangle schemes on the [`crate::mesh::trimesh::TriMesh`]
    /// uploaded with [`GpuMesh::new_tri`]), the same result as
    /// [`crate::cpu::adaptive::evaluate_cpu_adaptive`] bit for bit:
    ///
    /// 1. `adaptive_classify_main`, one dispatch per class: every patch's
    ///    four power-of-two edge levels (triangles: three, slot 3 is 1) (the metric of `a`, computed on the
    ///    GPU from the edge's end points or read from the explicit factors;
    ///    largest level `max_level`) and its bucket (the largest of the four)
    ///    into `patch_levels`;
    /// 2. a small readback of `patch_levels` (5 u32 per patch) from which the
    ///    host builds one entry list per (class, bucket) in `bucket_patches`
    ///    — not GPU-driven: no atomic bucket counters or indirect arguments;
    /// 3. `eval_adaptive_main`, one dispatch per (class, bucket) at the
    ///    bucket's level (split at the device limits), boundary samples
    ///    snapped onto the edges' own levels; read back in face order.
    ///
    /// A renderer draws step 3 with `eval_adaptive_vs` instead: one
    /// instanced draw of the level's grid per (class, bucket).
    ///
    /// Both entries evaluate through `eval_adaptive_displaced`: on a mesh
    /// uploaded with displacement ([`GpuMesh::new_displaced`],
    /// [`GpuMesh::new_tri_displaced`]) the result is displaced with
    /// ownership (measured: the same bits as
    /// [`crate::cpu::adaptive::evaluate_cpu_adaptive_displaced`] for pccm, pn
    /// and phong; gregory within 2.4e-8 × diagonal, its interior normal);
    /// otherwise (scale 0) it is the undisplaced tessellation bit for bit.
    ///
    /// This is the host-list path; [`GpuMesh::evaluate_adaptive`] runs
    /// [`GpuMesh::evaluate_adaptive_gpu_driven`] instead whenever its
    /// samples buffer (every patch at `max_level`) fits the binding limit.
    pub fn evaluate_adaptive_host_lists<'m>(
        &self,
        mesh: impl Into<crate::cpu::adaptive::AdaptiveMesh<'m>>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
    ) -> Result<crate::cpu::adaptive::AdaptiveTessellation, GpuError> {
        let inp = self.adaptive_inputs(mesh.into(), a, max_level)?;
        let faces = self.patch_faces.len();
        let dev = &self.gpu.device;
        let storage = |label, bytes: &[u8], extra| self.storage_init(label, bytes, extra);
        use crate::gpu::upload::{f32_bytes, u32_bytes};
        let patches = self.patch_faces.len() as u64;
        check(&self.limits, "patch_levels", patches * abi::LEVELS_BYTES)?;
        let face_edges = storage(
            "face_edges",
            &u32_bytes(&inp.face_edges),
            wgpu::BufferUsages::empty(),
        );
        let edge_factors = storage(
            "edge_factors",
            &f32_bytes(&inp.edge_factors),
            wgpu::BufferUsages::empty(),
        );
        let params_buf = storage(
            "adaptive",
            &f32_bytes(&inp.params),
            wgpu::BufferUsages::empty(),
        );
        let levels_buf = storage(
            "patch_levels",
            &vec![0u8; patches as usize * 20],
            wgpu::BufferUsages::COPY_SRC,
        );
        let extra = [
            (binding::FACE_EDGES, &face_edges),
            (binding::EDGE_FACTORS, &edge_factors),
            (binding::ADAPTIVE, &params_buf),
            (binding::PATCH_LEVELS, &levels_buf),
        ];
        let pipe = |entry: &str| self.compute_pipeline(entry);
        let classify = pipe("adaptive_classify_main")?;
        let eval = pipe("eval_adaptive_main")?;

        // 1. classify, then read the levels back.
        let staging = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("patch_levels readback"),
            size: (patches * abi::LEVELS_BYTES).max(16),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.gpu.scoped(|| {
            let chunk = self.chunk(1) as u32;
            let mut groups = Vec::new();
            for c in &self.classes {
                let mut k = 0;
                while k < c.count {
                    let count = chunk.min(c.count - k);
                    let p = self.params_buffer(&params_bytes(
                        Mat4::IDENTITY,
                        c.first + k,
                        count,
                        c.class,
                        c.cp_base + k * c.points,
                        max_level,
                        0,
                    ));
                    let layout = classify.get_bind_group_layout(0);
                    groups.push((
                        self.bind_group_with("adaptive_classify_main", &layout, &p, None, &extra),
                        count.div_ceil(abi::WORKGROUP_SIZE),
                    ));
                    k += count;
                }
            }
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("adaptive classify"),
            });
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("adaptive classify"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&classify);
                for (group, wgs) in &groups {
                    pass.set_bind_group(0, group, &[]);
                    pass.dispatch_workgroups(*wgs, 1, 1);
                }
            }
            enc.copy_buffer_to_buffer(&levels_buf, 0, &staging, 0, patches * abi::LEVELS_BYTES);
            self.gpu.queue.submit([enc.finish()]);
        })?;
        let words = self.read_words(&staging)?;

        // 2. per face levels, and one entry list per (class, bucket).
        let (levels, edge_levels, offsets) = self.face_levels(&words);
        let total = offsets[faces];
        let mut lists: std::collections::BTreeMap<(u32, u32), Vec<u32>> = Default::default();
        for c in &self.classes {
            for k in 0..c.count {
                let p = (c.first + k) as usize;
                let w = &words[abi::LEVELS_LEN * p..][..abi::LEVELS_LEN];
                lists
                    .entry((c.class, w[abi::LEVELS_BUCKET]))
                    .or_default()
                    .extend([p as u32, c.cp_base + k * c.points, w[0], w[1], w[2], w[3]]);
            }
        }
        let all: Vec<u32> = lists.values().flatten().copied().collect();
        check(
            &self.limits,
            "bucket_patches",
            all.len() as u64 * abi::WORD_BYTES,
        )?;
        let bucket_buf = storage(
            "bucket_patches",
            &u32_bytes(&all),
            wgpu::BufferUsages::empty(),
        );

        // 3. one dispatch per (class, bucket), split at the limits.
        let mut positions = vec![Vec3::ZERO; total];
        let mut normals = vec![Vec3::ZERO; total];
        let mut start = 0u32;
        for (&(class, level), list) in &lists {
            let n = (list.len() / abi::ENTRY_LEN) as u32;
            let spp = (self.scheme.grid_len)(level) as u64;
            if spp * abi::SAMPLE_BYTES > self.limits.max_storage_buffer_binding_size {
                return Err(GpuError::BufferTooLarge {
                    what: "samples of one patch",
                    needed: spp * abi::SAMPLE_BYTES,
                    max: self.limits.max_storage_buffer_binding_size,
                });
            }
            let by_binding =
                (self.limits.max_storage_buffer_binding_size / (spp * abi::SAMPLE_BYTES)).max(1);
            let chunk = self.chunk(spp).min(by_binding) as u32;
            let mut k = 0;
            while k < n {
                let count = chunk.min(n - k);
                let bytes = count as u64 * spp * abi::SAMPLE_BYTES;
                let samples = dev.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("samples"),
                    size: bytes,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                let staging = dev.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("samples readback"),
                    size: bytes,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                self.gpu.scoped(|| {
                    let p = self.params_buffer(&params_bytes(
                        Mat4::IDENTITY,
                        start + k,
                        count,
                        class,
                        0,
                        level,
                        0,
                    ));
                    let layout = eval.get_bind_group_layout(0);
                    let group = self.bind_group_with(
                        "eval_adaptive_main",
                        &layout,
                        &p,
                        Some(&samples),
                        &[(binding::BUCKET_PATCHES, &bucket_buf)],
                    );
                    let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("eval adaptive"),
                    });
                    {
                        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                            label: Some("eval adaptive"),
                            timestamp_writes: None,
                        });
                        pass.set_pipeline(&eval);
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
                for (i, s) in floats.chunks_exact(abi::SAMPLE_LEN).enumerate() {
                    let entry = (k as u64 + i as u64 / spp) as usize;
                    let face = self.patch_faces[list[abi::ENTRY_LEN * entry] as usize] as usize;
                    let at = offsets[face] + (i as u64 % spp) as usize;
                    positions[at] = Vec3::new(s[0], s[1], s[2]);
                    normals[at] = Vec3::new(s[3], s[4], s[5]);
                }
                k += count;
            }
            start += n;
        }
        Ok(crate::cpu::adaptive::AdaptiveTessellation {
            sides: self.scheme.sides,
            levels,
            edge_levels,
            offsets,
            positions,
            normals,
        })
    }

    /// Adaptive tessellation on the instanced path (quad schemes on a
    /// [`Topology`], triangle schemes on the [`crate::mesh::trimesh::TriMesh`]
    /// uploaded with [`GpuMesh::new_tri`]), the same result as
    /// [`crate::cpu::adaptive::evaluate_cpu_adaptive`] (or `_displaced`, on a
    /// mesh uploaded with displacement): GPU-driven buckets
    /// ([`GpuMesh::evaluate_adaptive_gpu_driven`], no readback before the
    /// evaluation) when every patch's samples at `max_level` fit one
    /// storage binding, otherwise the host-list path
    /// ([`GpuMesh::evaluate_adaptive_host_lists`], which splits its
    /// dispatches at the limits). Both give the same bits.
    pub fn evaluate_adaptive<'m>(
        &self,
        mesh: impl Into<crate::cpu::adaptive::AdaptiveMesh<'m>>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
    ) -> Result<crate::cpu::adaptive::AdaptiveTessellation, GpuError> {
        let bytes = self.patch_faces.len() as u64
            * (self.scheme.grid_len)(max_level) as u64
            * abi::SAMPLE_BYTES;
        if max_level.is_power_of_two()
            && max_level <= cpu::MAX_LEVEL
            && bytes <= self.limits.max_storage_buffer_binding_size
            && self.chunk_rows() <= self.limits.max_workgroups_per_dimension as u64
        {
            self.evaluate_adaptive_gpu_driven(mesh, a, max_level)
        } else {
            self.evaluate_adaptive_host_lists(mesh, a, max_level)
        }
    }

    /// [`GpuMesh::evaluate_adaptive_host_lists`] with the buckets built on the GPU:
    /// nothing is read back before the evaluation.
    ///
    /// 1. `adaptive_classify_main` as there;
    /// 2. per class range r, `adaptive_count_main`: a workgroup per chunk
    ///    of [`CHUNK`] patches counts the chunk's patches of each bucket
    ///    slot `16r + j` (bucket `2^j`) into `bucket_chunks`;
    /// 3. `adaptive_plan_main` (one workgroup): each chunk's offset within
    ///    each slot (a scan over the chunks per slot), each slot's count,
    ///    first entry and first sample (prefix sums) and its
    ///    `dispatch_workgroups_indirect` arguments (y = ⌈workgroups / 32768⌉
    ///    rows of x = ⌈workgroups / y⌉, so fewer than y are idle);
    /// 4. per class range, `adaptive_scatter_main`: a workgroup per chunk
    ///    writes every patch at its slot's first entry plus its chunk's
    ///    offset plus its rank in the chunk — patch order, no atomics, so the lists
    ///    are the host-built ones;
    /// 5. one `dispatch_workgroups_indirect` of `eval_adaptive_indirect_main`
    ///    per slot up to `max_level` (empty slots dispatch nothing).
    ///
    /// Then one readback of `patch_levels`, the lists and the samples,
    /// reassembled per face: the same [`crate::cpu::adaptive::AdaptiveTessellation`]
    /// as [`GpuMesh::evaluate_adaptive_host_lists`], bit for bit. The samples buffer
    /// is sized for every patch at `max_level` (the host does not know the
    /// buckets before the evaluation): `BufferTooLarge` beyond the binding
    /// limit, `TooManyChunks` beyond 256 × max_workgroups_per_dimension
    /// patches.
    pub fn evaluate_adaptive_gpu_driven<'m>(
        &self,
        mesh: impl Into<crate::cpu::adaptive::AdaptiveMesh<'m>>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
    ) -> Result<crate::cpu::adaptive::AdaptiveTessellation, GpuError> {
        let inp = self.adaptive_inputs(mesh.into(), a, max_level)?;
        let faces = self.patch_faces.len();
        let dev = &self.gpu.device;
        let b = self.bucket_buffers(&inp)?;
        let slots = b.slots;
        let patches = faces as u64;
        let max_spp = (self.scheme.grid_len)(max_level) as u64;
        let sample_bytes = (patches * max_spp * abi::SAMPLE_BYTES).max(abi::SAMPLE_BYTES);
        check(
            &self.limits,
            "samples (every patch at the largest level)",
            sample_bytes,
        )?;
        let mut kept = self
            .driven_samples
            .lock()
            .map_err(|_| GpuError::Readback("samples buffer lock poisoned".into()))?;
        if kept.as_ref().is_some_and(|b| b.size() < sample_bytes) {
            *kept = None;
        }
        let samples: &wgpu::Buffer = kept.get_or_insert_with(|| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("samples (GPU-driven adaptive)"),
                size: sample_bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        });
        let staging = |label: &'static str, size: u64| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let levels_read = staging("patch_levels readback", patches * abi::LEVELS_BYTES);
        let list_read = staging("bucket_list readback", b.list_words * abi::WORD_BYTES);
        let mut phases = self.bucket_phases(max_level, slots);
        let mut evals = Vec::new();
        for (slot, class, level) in self.bucket_slots(max_level) {
            evals.push((
                self.slot_params(Mat4::IDENTITY, slots, class, level, slot, 0),
                Run::Indirect(12 * slot as u64),
            ));
        }
        phases.push(("eval_adaptive_indirect_main", evals));
        self.gpu.scoped(|| -> Result<(), GpuError> {
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("adaptive, GPU-driven"),
            });
            self.encode_phases(&mut enc, &phases, &b, Some(samples))?;
            enc.copy_buffer_to_buffer(&b.levels, 0, &levels_read, 0, patches * abi::LEVELS_BYTES);
            enc.copy_buffer_to_buffer(&b.list, 0, &list_read, 0, b.list_words * abi::WORD_BYTES);
            self.gpu.queue.submit([enc.finish()]);
            Ok(())
        })??;
        let lv = self.read_words(&levels_read)?;
        let list = self.read_words(&list_read)?;
        // After the evaluation, the headers say how many samples were
        // written (the end of the furthest slot: first sample + count ·
        // samples per patch): read back only those, not the buffer sized
        // for every patch at `max_level`.
        let written: u64 = (0..slots as usize)
            .map(|b| {
                let spp = (self.scheme.grid_len)(1 << (b as u32 % SLOTS)) as u64;
                list[abi::HEADER_LEN * b + 2] as u64 + list[abi::HEADER_LEN * b] as u64 * spp
            })
            .max()
            .unwrap_or(0)
            .min(patches * max_spp);
        let samples_read = staging("samples readback", written * abi::SAMPLE_BYTES);
        self.gpu.scoped(|| {
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("adaptive samples readback"),
            });
            enc.copy_buffer_to_buffer(samples, 0, &samples_read, 0, written * abi::SAMPLE_BYTES);
            self.gpu.queue.submit([enc.finish()]);
        })?;
        let floats = self.read(&samples_read)?;
        let (levels, edge_levels, offsets) = self.face_levels(&lv);
        let total = offsets[faces];
        let mut positions = vec![Vec3::ZERO; total];
        let mut normals = vec![Vec3::ZERO; total];
        for b in 0..slots as usize {
            let (n, first, sample) = (
                list[abi::HEADER_LEN * b] as usize,
                list[abi::HEADER_LEN * b + 1] as usize,
                list[abi::HEADER_LEN * b + 2] as usize,
            );
            let spp = (self.scheme.grid_len)(1 << (b as u32 % SLOTS)) as usize;
            for m in 0..n {
                let e = abi::HEADER_LEN * slots as usize + abi::ENTRY_LEN * (first + m);
                let face = self.patch_faces[list[e] as usize] as usize;
                for s in 0..spp {
                    let f = &floats[abi::SAMPLE_LEN * (sample + m * spp + s)..][..abi::SAMPLE_LEN];
                    positions[offsets[face] + s] = Vec3::new(f[0], f[1], f[2]);
                    normals[offsets[face] + s] = Vec3::new(f[3], f[4], f[5]);
                }
            }
        }
        Ok(crate::cpu::adaptive::AdaptiveTessellation {
            sides: self.scheme.sides,
            levels,
            edge_levels,
            offsets,
            positions,
            normals,
        })
    }

    /// The buffers of the GPU-driven buckets for the edge inputs `inp`
    /// (`patch_levels`, `bucket_list` with its header of 4 u32 per slot,
    /// the indirect dispatch and draw arguments), checked against the
    /// binding limit.
    pub(crate) fn bucket_buffers(
        &self,
        inp: &crate::cpu::adaptive::EdgeInputs,
    ) -> Result<Buckets, GpuError> {
        use crate::gpu::upload::{f32_bytes, u32_bytes};
        let storage = |label, bytes: &[u8], extra| self.storage_init(label, bytes, extra);
        let patches = self.patch_faces.len() as u64;
        let slots = SLOTS * self.classes.len() as u32;
        let list_words = abi::BUCKET_HEADER_WORDS as u64 * slots as u64
            + abi::BUCKET_ENTRY_WORDS as u64 * patches;
        check(&self.limits, "patch_levels", patches * abi::LEVELS_BYTES)?;
        check(&self.limits, "bucket_list", list_words * abi::WORD_BYTES)?;
        let chunk_rows = self.chunk_rows();
        if chunk_rows > self.limits.max_workgroups_per_dimension as u64 {
            return Err(GpuError::TooManyChunks {
                patches,
                chunks: chunk_rows,
                max: self.limits.max_workgroups_per_dimension,
            });
        }
        let chunk_words = 2 * chunk_rows * slots as u64;
        check(&self.limits, "bucket_chunks", chunk_words * abi::WORD_BYTES)?;
        let zeros = |words: u64| vec![0u8; (words * abi::WORD_BYTES) as usize];
        Ok(Buckets {
            face_edges: storage(
                "face_edges",
                &u32_bytes(&inp.face_edges),
                wgpu::BufferUsages::empty(),
            ),
            edge_factors: storage(
                "edge_factors",
                &f32_bytes(&inp.edge_factors),
                wgpu::BufferUsages::empty(),
            ),
            params: storage(
                "adaptive",
                &f32_bytes(&inp.params),
                wgpu::BufferUsages::empty(),
            ),
            levels: storage(
                "patch_levels",
                &zeros(abi::PATCH_LEVELS_WORDS as u64 * patches),
                wgpu::BufferUsages::COPY_SRC,
            ),
            list: storage(
                "bucket_list",
                &zeros(list_words),
                wgpu::BufferUsages::COPY_SRC,
            ),
            dispatch: storage(
                "bucket_dispatch",
                &zeros(abi::BUCKET_DISPATCH_WORDS as u64 * slots as u64),
                wgpu::BufferUsages::INDIRECT,
            ),
            draw: storage(
                "bucket_draw",
                &zeros(abi::BUCKET_DRAW_WORDS as u64 * slots as u64),
                wgpu::BufferUsages::INDIRECT,
            ),
            chunks: storage(
                "bucket_chunks",
                &zeros(chunk_words),
                wgpu::BufferUsages::empty(),
            ),
            slots,
            list_words,
        })
    }

    /// Chunks of [`CHUNK`] patches the bucket compaction runs over (one
    /// row of `bucket_chunks` each; at most max_workgroups_per_dimension,
    /// as `bucket_buffers` checks).
    fn chunk_rows(&self) -> u64 {
        (self.patch_faces.len() as u64).div_ceil(CHUNK as u64)
    }

    /// Every bucket slot up to `max_level`: `(slot 16r + j, class of range
    /// r, level 2^j)`.
    pub(crate) fn bucket_slots(&self, max_level: u32) -> Vec<(u32, u32, u32)> {
        let mut out = Vec::new();
        for (r, c) in self.classes.iter().enumerate() {
            let mut j = 0;
            while (1u32 << j) <= max_level && j < SLOTS {
                out.push((SLOTS * r as u32 + j, c.class, 1 << j));
                j += 1;
            }
        }
        out
    }

    /// The Params of slot `slot`'s evaluation or draw: entries after the
    /// header of `slots` slots (`first`), the slot in `out_base`.
    pub(crate) fn slot_params(
        &self,
        view_proj: Mat4,
        slots: u32,
        class: u32,
        level: u32,
        slot: u32,
        flags: u32,
    ) -> wgpu::Buffer {
        self.params(view_proj, slots, 0, class, 0, level, slot, flags)
    }

    /// Steps 1–4 of the GPU-driven buckets (classify, count, plan, scatter)
    /// as `(entry, [(params, run)])`.
    pub(crate) fn bucket_phases(
        &self,
        max_level: u32,
        slots: u32,
    ) -> Vec<(&'static str, Vec<(wgpu::Buffer, Run)>)> {
        let prm = |first, count, class, cp_base, level, out_base| {
            self.params_buffer(&params_bytes(
                Mat4::IDENTITY,
                first,
                count,
                class,
                cp_base,
                level,
                out_base,
            ))
        };
        let mut phases = Vec::new();
        let chunk = self.chunk(1) as u32;
        let mut classify = Vec::new();
        for c in &self.classes {
            let mut k = 0;
            while k < c.count {
                let count = chunk.min(c.count - k);
                let p = prm(
                    c.first + k,
                    count,
                    c.class,
                    c.cp_base + k * c.points,
                    max_level,
                    0,
                );
                classify.push((p, Run::Direct(count.div_ceil(abi::WORKGROUP_SIZE))));
                k += count;
            }
        }
        phases.push(("adaptive_classify_main", classify));
        // The count and scatter passes: per class range, a workgroup per
        // chunk of CHUNK patches that holds one of the range's patches.
        let per_range = || {
            self.classes
                .iter()
                .enumerate()
                .filter(|(_, c)| c.count > 0)
                .map(|(r, c)| {
                    let p = prm(
                        c.first,
                        c.count,
                        c.class,
                        c.cp_base,
                        slots,
                        SLOTS * r as u32,
                    );
                    let chunks = (c.first + c.count - 1) / CHUNK - c.first / CHUNK + 1;
                    (p, Run::Direct(chunks))
                })
                .collect::<Vec<_>>()
        };
        phases.push(("adaptive_count_main", per_range()));
        phases.push((
            "adaptive_plan_main",
            vec![(
                prm(self.chunk_rows() as u32, slots, 0, 0, 0, 0),
                Run::Direct(1),
            )],
        ));
        phases.push(("adaptive_scatter_main", per_range()));
        phases
    }

    /// Record compute `phases` into `enc`, each run with the bucket
    /// buffers `b` bound (and `samples`).
    pub(crate) fn encode_phases(
        &self,
        enc: &mut wgpu::CommandEncoder,
        phases: &[(&'static str, Vec<(wgpu::Buffer, Run)>)],
        b: &Buckets,
        samples: Option<&wgpu::Buffer>,
    ) -> Result<(), GpuError> {
        let extra = b.bindings();
        for (entry, runs) in phases {
            let pipeline = self.compute_pipeline(entry)?;
            let layout = pipeline.get_bind_group_layout(0);
            let groups: Vec<wgpu::BindGroup> = runs
                .iter()
                .map(|(p, _)| self.bind_group_with(entry, &layout, p, samples, &extra))
                .collect();
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(entry),
                timestamp_writes: None,
            });
            pass.set_pipeline(&pipeline);
            for ((_, run), group) in runs.iter().zip(&groups) {
                pass.set_bind_group(0, group, &[]);
                match run {
                    Run::Direct(x) => pass.dispatch_workgroups(*x, 1, 1),
                    Run::Indirect(at) => pass.dispatch_workgroups_indirect(&b.dispatch, *at),
                }
            }
        }
        Ok(())
    }

    /// Read back the control points (class-sorted layout, see [`ClassRange`]).
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

    fn read(&self, staging: &wgpu::Buffer) -> Result<Vec<f32>, GpuError> {
        let bytes = self.read_bytes(staging)?;
        Ok(bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect())
    }

    /// Map a MAP_READ buffer and copy its bytes out.
    pub(crate) fn read_bytes(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.gpu
            .device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let data = staging
            .get_mapped_range(..)
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let out = data.to_vec();
        drop(data);
        staging.unmap();
        Ok(out)
    }

    /// The shader module (for render pipelines).
    pub fn module(&self) -> &wgpu::ShaderModule {
        &self.module
    }
}
