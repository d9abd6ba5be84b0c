//! The Vulkan tessellation harness: runs the emitted **GLSL** and **HLSL**
//! tessellation shaders in a real Vulkan tessellation pipeline (Mesa's
//! lavapipe on CI) and captures every evaluated sample, so their output can
//! be welded and compared with the CPU exactly like the CPU and wgpu paths.
//!
//! * Shaders: the GLSL (`<scheme>.vert/.tesc/.tese`, `<scheme>_vertex_stage.comp`)
//!   and HLSL (`<scheme>.hlsl`, entry points `vs_main`, `hs_main`, `ds_main`,
//!   `vertex_stage_main`) that this crate's `build.rs` generates, compiled to
//!   SPIR-V by `glslangValidator` (HLSL with `-D`) with `-DTESSGEN_CAPTURE`:
//!   for quad schemes the evaluation stage then also writes its sample into
//!   the `samples` buffer at `eval_main`'s layout; for triangle schemes (whose
//!   hardware inner vertices are not grid points) it exports its domain point
//!   and patch, and a harness geometry shader records every emitted triangle
//!   ([`VkMesh::evaluate_triangles`], [`crate::gpu::capture`]).
//! * Quad schemes run the vertex stage as a compute dispatch first; then, per
//!   facet class, one draw of `count` patches (patch size 1, rasterizer
//!   discard, a render pass without attachments) with
//!   `Params { first, count, class, cp_base, level, out_base }`.
//! * The data uploaded is [`crate::gpu::upload::Upload`], the same as the wgpu
//!   path's.
//!
//! The Vulkan loader is opened at run time (`ash::Entry::load`), so a build
//! with this feature needs no Vulkan SDK; running needs `libvulkan1` and a
//! driver (`mesa-vulkan-drivers` for lavapipe) and `glslangValidator`
//! (`glslang-tools`).

use crate::abi::{self, binding, PARAMS_SIZE};
use crate::cpu::adaptive::{self, Adaptive, Metric};
use crate::cpu::{self, Tessellation};
use crate::gpu::capture::{CaptureError, TriangleCapture, ADAPTIVE_LEVEL, VERTEX_FLOATS};
use crate::gpu::readback::GridReadback;
use crate::gpu::upload::{
    f32_bytes, params_bytes, u32_bytes, ClassRange, Upload, UploadBuffer, UploadError,
};
use crate::kernels::{self, common::SchemeKernels};
use crate::mesh::topology::Topology;
use ash::vk;
use glam::{Mat4, Vec3};
use std::ffi::CStr;
use std::path::PathBuf;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Which emitted shader language to run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Language {
    #[default]
    Glsl,
    Hlsl,
}

impl Language {
    pub const ALL: [Language; 2] = [Language::Glsl, Language::Hlsl];
    pub fn name(self) -> &'static str {
        match self {
            Language::Glsl => "glsl",
            Language::Hlsl => "hlsl",
        }
    }
}

/// Define that compiles the shared boundary path out of `eval` (a negative
/// control: the watertightness check must then find cracks).
pub const NO_BOUNDARY_PATH: &str = crate::abi::define::NO_BOUNDARY_PATH;
/// Define that makes the shared edge evaluator form `l = 1 − r` in float
/// (watertight.md Rule 2's forbidden form): a negative control that must
/// open the weld at levels whose `i/level` is inexact.
pub const ASYMMETRIC_EDGE_WEIGHTS: &str = crate::abi::define::ASYMMETRIC_EDGE_WEIGHTS;
/// Define that makes the evaluation stage write its samples (always set by
/// this harness).
pub const CAPTURE: &str = crate::abi::define::CAPTURE;
/// Define of the displacing evaluation stage (quad schemes; set by
/// [`VkMesh::new_displaced`]): the harness then also runs the compute patch
/// stage into the global control-point buffer before the draws, which the
/// evaluation stage reads for the owner patch's normal.
pub const DISPLACE: &str = crate::abi::define::DISPLACE;

/// Descriptor bindings the harness lays out: every ABI binding up to the
/// displacement map, the harness's triangle capture (`binding::TRIANGLES`)
/// included.
const LAYOUT_BINDINGS: u32 = binding::DISPLACE_MAP + 1;

/// A 2-D `R32_SFLOAT` image with its memory and view (the stencil table,
/// the displacement map).
#[derive(Clone, Copy)]
struct Img {
    image: vk::Image,
    memory: vk::DeviceMemory,
    view: vk::ImageView,
}

impl Default for Img {
    fn default() -> Self {
        Img {
            image: vk::Image::null(),
            memory: vk::DeviceMemory::null(),
            view: vk::ImageView::null(),
        }
    }
}

impl Img {
    fn destroy(&self, d: &ash::Device) {
        unsafe {
            d.destroy_image_view(self.view, None);
            d.destroy_image(self.image, None);
            d.free_memory(self.memory, None);
        }
    }
}

/// How to build the shaders.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Options {
    pub language: Language,
    /// Extra preprocessor defines (e.g. [`NO_BOUNDARY_PATH`]).
    pub defines: Vec<String>,
    /// Adaptive tessellation (quad schemes): per-edge factors, captured as
    /// triangles by [`VkMesh::evaluate_adaptive`].
    pub adaptive: Option<Adaptive>,
}

impl Options {
    pub fn new(language: Language) -> Self {
        Options {
            language,
            defines: Vec::new(),
            adaptive: None,
        }
    }

    /// Every define the shaders are compiled with, besides [`CAPTURE`].
    fn all_defines(&self) -> Vec<String> {
        let mut d = self.defines.clone();
        if let Some(a) = &self.adaptive {
            d.extend(a.defines());
        }
        d
    }
}

/// Errors of the Vulkan harness.
#[derive(Debug, thiserror::Error)]
pub enum VkError {
    #[error("cannot load the Vulkan loader (install libvulkan1, and mesa-vulkan-drivers for lavapipe): {0}")]
    Loader(String),
    #[error("Vulkan call {call} failed: {result}")]
    Call {
        call: &'static str,
        result: vk::Result,
    },
    #[error("no Vulkan device supports tessellationShader and vertexPipelineStoresAndAtomics with a graphics+compute queue (install mesa-vulkan-drivers for lavapipe)")]
    NoDevice,
    #[error("no Vulkan device matches TESSGEN_VK_DEVICE={0:?}")]
    DeviceNotFound(String),
    #[error("glslangValidator could not be run ({0}); install glslang-tools")]
    NoGlslang(String),
    #[error("glslangValidator failed on {file} (stage {stage}):\n{log}")]
    Compile {
        file: String,
        stage: &'static str,
        log: String,
    },
    #[error("no {language} shader {file} for scheme `{scheme}` in this build")]
    NoShader {
        language: &'static str,
        scheme: String,
        file: String,
    },
    #[error("scheme `{scheme}`: {what} needs {needed}, the device allows {max}")]
    Limit {
        scheme: String,
        what: &'static str,
        needed: u64,
        max: u64,
    },
    #[error("no Vulkan memory type for {0}")]
    NoMemoryType(&'static str),
    #[error("i/o: {0}")]
    Io(String),
    #[error(transparent)]
    Tess(#[from] cpu::TessError),
    #[error("positions: expected {expected}, got {got}")]
    PositionCount { expected: usize, got: usize },
    #[error("scheme `{scheme}` has a triangle domain: the hardware's inner vertices are not grid points, so capture its triangles with evaluate_triangles")]
    TriangleDomain { scheme: String },
    #[error("scheme `{scheme}` has a quad domain: evaluate_triangles is for triangle schemes")]
    QuadDomain { scheme: String },
    #[error(
        "the Vulkan device has no geometryShader, which the triangle and adaptive captures need"
    )]
    NoGeometryShader,
    #[error("level {level}: the tessellator emitted {emitted} triangles for {patches} patches, more than the {capacity} the capture holds")]
    CaptureOverflow {
        level: u32,
        patches: u64,
        emitted: u64,
        capacity: u64,
    },
    #[error(transparent)]
    Capture(#[from] CaptureError),
    #[error("explicit edge factors: the mesh has {expected} edges, {got} factors were given")]
    EdgeFactorCount { expected: usize, got: usize },
    #[error("adaptive draws need VkMesh::evaluate_adaptive (the samples are not a grid)")]
    AdaptiveNotGrid,
}

impl From<UploadError> for VkError {
    fn from(e: UploadError) -> Self {
        match e {
            UploadError::Tess(e) => VkError::Tess(e),
            UploadError::PositionCount { expected, got } => {
                VkError::PositionCount { expected, got }
            }
        }
    }
}

fn call(call: &'static str) -> impl FnOnce(vk::Result) -> VkError {
    move |result| VkError::Call { call, result }
}

/// The device limits the harness checks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeviceLimits {
    pub max_tessellation_patch_size: u32,
    pub max_tessellation_generation_level: u32,
    pub max_tessellation_control_per_patch_output_components: u32,
    pub max_tessellation_evaluation_input_components: u32,
    pub max_storage_buffer_range: u32,
    pub max_image_dimension_2d: u32,
    pub max_compute_work_group_count_x: u32,
}

/// A Vulkan instance, device and queue.
pub struct Vulkan {
    _entry: ash::Entry,
    instance: ash::Instance,
    device: ash::Device,
    queue: vk::Queue,
    memory: vk::PhysicalDeviceMemoryProperties,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    /// Device name and driver (e.g. `llvmpipe (LLVM 15.0.7, 256 bits)`).
    pub name: String,
    pub limits: DeviceLimits,
    /// Whether `geometryShader` is enabled (the triangle capture needs it).
    pub geometry_shader: bool,
}

impl Vulkan {
    /// The first device with tessellation shaders and vertex-pipeline stores
    /// (or the one whose name contains `TESSGEN_VK_DEVICE`).
    pub fn new() -> Result<Vulkan, VkError> {
        // SAFETY: loading the system Vulkan loader; every handle created
        // below is destroyed in Drop, in reverse order.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| VkError::Loader(e.to_string()))?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"tessgen")
            .api_version(vk::API_VERSION_1_1);
        let ci = vk::InstanceCreateInfo::default().application_info(&app);
        let instance =
            unsafe { entry.create_instance(&ci, None) }.map_err(call("vkCreateInstance"))?;
        match Self::with_instance(entry, instance.clone()) {
            Ok(v) => Ok(v),
            Err(e) => {
                unsafe { instance.destroy_instance(None) };
                Err(e)
            }
        }
    }

    fn with_instance(entry: ash::Entry, instance: ash::Instance) -> Result<Vulkan, VkError> {
        let devices = unsafe { instance.enumerate_physical_devices() }
            .map_err(call("vkEnumeratePhysicalDevices"))?;
        let want = std::env::var("TESSGEN_VK_DEVICE").ok();
        let mut chosen = None;
        for pd in devices {
            let props = unsafe { instance.get_physical_device_properties(pd) };
            let name = props
                .device_name_as_c_str()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            if let Some(w) = &want {
                if !name.to_lowercase().contains(&w.to_lowercase()) {
                    continue;
                }
            }
            let f = unsafe { instance.get_physical_device_features(pd) };
            if f.tessellation_shader == vk::FALSE
                || f.vertex_pipeline_stores_and_atomics == vk::FALSE
            {
                continue;
            }
            let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
            let Some(family) = families.iter().position(|q| {
                q.queue_flags
                    .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
            }) else {
                continue;
            };
            chosen = Some((pd, props, name, family as u32, f.geometry_shader));
            break;
        }
        let Some((pd, props, name, family, geometry_shader)) = chosen else {
            return Err(match want {
                Some(w) => VkError::DeviceNotFound(w),
                None => VkError::NoDevice,
            });
        };
        let features = vk::PhysicalDeviceFeatures {
            tessellation_shader: vk::TRUE,
            vertex_pipeline_stores_and_atomics: vk::TRUE,
            geometry_shader,
            ..Default::default()
        };
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        let dci = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_features(&features);
        let device =
            unsafe { instance.create_device(pd, &dci, None) }.map_err(call("vkCreateDevice"))?;
        let queue = unsafe { device.get_device_queue(family, 0) };
        let memory = unsafe { instance.get_physical_device_memory_properties(pd) };
        let setup = || -> Result<(vk::CommandPool, vk::CommandBuffer, vk::Fence), VkError> {
            let pool = unsafe {
                device.create_command_pool(
                    &vk::CommandPoolCreateInfo::default()
                        .queue_family_index(family)
                        .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER),
                    None,
                )
            }
            .map_err(call("vkCreateCommandPool"))?;
            let cmd = unsafe {
                device.allocate_command_buffers(
                    &vk::CommandBufferAllocateInfo::default()
                        .command_pool(pool)
                        .level(vk::CommandBufferLevel::PRIMARY)
                        .command_buffer_count(1),
                )
            }
            .map_err(call("vkAllocateCommandBuffers"))?[0];
            let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
                .map_err(call("vkCreateFence"))?;
            Ok((pool, cmd, fence))
        };
        let (pool, cmd, fence) = match setup() {
            Ok(x) => x,
            Err(e) => {
                unsafe { device.destroy_device(None) };
                return Err(e);
            }
        };
        let l = &props.limits;
        let driver = format!(
            "{name} (Vulkan {}.{}.{})",
            vk::api_version_major(props.api_version),
            vk::api_version_minor(props.api_version),
            vk::api_version_patch(props.api_version)
        );
        Ok(Vulkan {
            _entry: entry,
            instance,
            device,
            queue,
            memory,
            pool,
            cmd,
            fence,
            name: driver,
            geometry_shader: geometry_shader == vk::TRUE,
            limits: DeviceLimits {
                max_tessellation_patch_size: l.max_tessellation_patch_size,
                max_tessellation_generation_level: l.max_tessellation_generation_level,
                max_tessellation_control_per_patch_output_components: l
                    .max_tessellation_control_per_patch_output_components,
                max_tessellation_evaluation_input_components: l
                    .max_tessellation_evaluation_input_components,
                max_storage_buffer_range: l.max_storage_buffer_range,
                max_image_dimension_2d: l.max_image_dimension2_d,
                max_compute_work_group_count_x: l.max_compute_work_group_count[0],
            },
        })
    }

    fn memory_type(
        &self,
        bits: u32,
        want: vk::MemoryPropertyFlags,
        what: &'static str,
    ) -> Result<u32, VkError> {
        (0..self.memory.memory_type_count)
            .find(|&i| {
                bits & (1 << i) != 0
                    && self.memory.memory_types[i as usize]
                        .property_flags
                        .contains(want)
            })
            .ok_or(VkError::NoMemoryType(what))
    }

    /// A host-visible, coherent, persistently mapped buffer.
    fn buffer(
        &self,
        what: &'static str,
        size: u64,
        usage: vk::BufferUsageFlags,
    ) -> Result<Buf, VkError> {
        let size = size.max(16);
        let d = &self.device;
        let buffer = unsafe {
            d.create_buffer(
                &vk::BufferCreateInfo::default()
                    .size(size)
                    .usage(usage)
                    .sharing_mode(vk::SharingMode::EXCLUSIVE),
                None,
            )
        }
        .map_err(call("vkCreateBuffer"))?;
        let req = unsafe { d.get_buffer_memory_requirements(buffer) };
        let ty = match self.memory_type(
            req.memory_type_bits,
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
            what,
        ) {
            Ok(t) => t,
            Err(e) => {
                unsafe { d.destroy_buffer(buffer, None) };
                return Err(e);
            }
        };
        let memory = match unsafe {
            d.allocate_memory(
                &vk::MemoryAllocateInfo::default()
                    .allocation_size(req.size)
                    .memory_type_index(ty),
                None,
            )
        } {
            Ok(m) => m,
            Err(e) => {
                unsafe { d.destroy_buffer(buffer, None) };
                return Err(call("vkAllocateMemory")(e));
            }
        };
        let buf = Buf {
            buffer,
            memory,
            size,
            ptr: std::ptr::null_mut(),
        };
        let bound = unsafe { d.bind_buffer_memory(buffer, memory, 0) }
            .map_err(call("vkBindBufferMemory"))
            .and_then(|_| {
                unsafe { d.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()) }
                    .map_err(call("vkMapMemory"))
            });
        match bound {
            Ok(ptr) => Ok(Buf {
                ptr: ptr as *mut u8,
                ..buf
            }),
            Err(e) => {
                buf.destroy(d);
                Err(e)
            }
        }
    }

    /// Record `f` into the command buffer, submit it and wait.
    fn submit(&self, f: impl FnOnce(&ash::Device, vk::CommandBuffer)) -> Result<(), VkError> {
        let d = &self.device;
        unsafe {
            d.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty())
                .map_err(call("vkResetCommandBuffer"))?;
            d.begin_command_buffer(
                self.cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .map_err(call("vkBeginCommandBuffer"))?;
            // Earlier submissions' shader writes (vertex stage, uploads) are
            // visible to everything recorded here.
            let all = vk::MemoryBarrier::default()
                .src_access_mask(
                    vk::AccessFlags::SHADER_WRITE
                        | vk::AccessFlags::TRANSFER_WRITE
                        | vk::AccessFlags::HOST_WRITE,
                )
                .dst_access_mask(
                    vk::AccessFlags::SHADER_READ
                        | vk::AccessFlags::SHADER_WRITE
                        | vk::AccessFlags::UNIFORM_READ
                        | vk::AccessFlags::TRANSFER_READ
                        | vk::AccessFlags::TRANSFER_WRITE,
                );
            d.cmd_pipeline_barrier(
                self.cmd,
                vk::PipelineStageFlags::ALL_COMMANDS | vk::PipelineStageFlags::HOST,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::DependencyFlags::empty(),
                &[all],
                &[],
                &[],
            );
            f(d, self.cmd);
            let to_host = vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::HOST_READ);
            d.cmd_pipeline_barrier(
                self.cmd,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::PipelineStageFlags::HOST,
                vk::DependencyFlags::empty(),
                &[to_host],
                &[],
                &[],
            );
            d.end_command_buffer(self.cmd)
                .map_err(call("vkEndCommandBuffer"))?;
            let cmds = [self.cmd];
            d.queue_submit(
                self.queue,
                &[vk::SubmitInfo::default().command_buffers(&cmds)],
                self.fence,
            )
            .map_err(call("vkQueueSubmit"))?;
            let waited = d
                .wait_for_fences(&[self.fence], true, u64::MAX)
                .map_err(call("vkWaitForFences"));
            d.reset_fences(&[self.fence])
                .map_err(call("vkResetFences"))?;
            waited
        }
    }
}

impl Drop for Vulkan {
    fn drop(&mut self) {
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_fence(self.fence, None);
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}

/// A buffer with its memory, mapped.
struct Buf {
    buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    size: u64,
    ptr: *mut u8,
}

impl Buf {
    fn write(&self, bytes: &[u8]) {
        let n = bytes.len().min(self.size as usize);
        // SAFETY: `ptr` maps the whole (host-coherent) allocation of at
        // least `size` bytes; no submission is in flight while we write.
        unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), self.ptr, n) };
    }
    fn read_f32(&self, floats: usize) -> Vec<f32> {
        let n = floats.min(self.size as usize / 4);
        // SAFETY: as in `write`; the fence wait made the device writes
        // available and the barrier made them visible to the host.
        let bytes = unsafe { std::slice::from_raw_parts(self.ptr, n * 4) };
        bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    }
    fn destroy(&self, d: &ash::Device) {
        unsafe {
            d.destroy_buffer(self.buffer, None);
            d.free_memory(self.memory, None);
        }
    }
}

/// The harness's one geometry shader (not a generated file), for every
/// draw whose tessellated vertices are not a grid: triangle schemes (their
/// inner rings are not the lattice) and adaptive draws of any scheme. It
/// receives every triangle the tessellator emitted, with the evaluation
/// stage's outputs at the locations both emitted languages write (GLSL
/// `te_normal` 0, `te_position` 1, and with `-DTESSGEN_CAPTURE` `te_domain`
/// 2, `te_patch` 3; HLSL `DsOut` in declaration order), and appends it to
/// the capture buffer (binding 20, `binding::TRIANGLES`): a `u32` triangle
/// counter bumped atomically, the capacity, then `VERTEX_FLOATS` floats per
/// vertex. A triangle past the capacity is counted but not written, so the
/// host can tell an overflow from a full buffer. The domain point is
/// barycentric `(x, y, z)` for triangles and `(u, v, 0)` for quads, so the
/// host can evaluate the CPU surface at every captured vertex (parity).
///
/// The binding and the vertex stride are filled in from
/// [`binding::TRIANGLES`] and [`VERTEX_FLOATS`] (`capture_geometry_shader`),
/// so the GLSL and the host's reading of the buffer cannot disagree.
const CAPTURE_GEOMETRY_TEMPLATE: &str = r#"#version 450
layout(triangles) in;
layout(points, max_vertices = 1) out;

layout(location = 0) in vec3 te_normal[];
layout(location = 1) in vec3 te_position[];
layout(location = 2) in vec3 te_domain[];
layout(location = 3) flat in uint te_patch[];

layout(std430, set = 0, binding = @TRIANGLES@) buffer Capture {
    uint triangles;
    uint capacity;
    uint pad0;
    uint pad1;
    float data[];
};

void main() {
    uint t = atomicAdd(triangles, 1u);
    if (t >= capacity) {
        return;
    }
    for (uint k = 0u; k < 3u; k += 1u) {
        uint o = (3u * t + k) * @VERTEX_FLOATS@u;
        data[o + 0u] = te_position[k].x;
        data[o + 1u] = te_position[k].y;
        data[o + 2u] = te_position[k].z;
        data[o + 3u] = te_normal[k].x;
        data[o + 4u] = te_normal[k].y;
        data[o + 5u] = te_normal[k].z;
        data[o + 6u] = te_domain[k].x;
        data[o + 7u] = te_domain[k].y;
        data[o + 8u] = te_domain[k].z;
        data[o + 9u] = uintBitsToFloat(te_patch[k]);
    }
}
"#;

/// [`CAPTURE_GEOMETRY_TEMPLATE`] with the capture binding and stride.
fn capture_geometry_shader() -> &'static str {
    static SOURCE: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    SOURCE.get_or_init(|| {
        CAPTURE_GEOMETRY_TEMPLATE
            .replace("@TRIANGLES@", &binding::TRIANGLES.to_string())
            .replace("@VERTEX_FLOATS@", &VERTEX_FLOATS.to_string())
    })
}

/// The adaptive buffers (bindings 17–19) for `face_edges` ids at
/// `sides·f + k` over `edges` edges: the ids, the explicit factors, the
/// metric parameters. [`Metric::PerFaceEdge`] (the negative control) gives
/// every face edge its own id instead.
fn adaptive_buffers(
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

/// Bytes before the captured vertices in the capture buffer (counter,
/// capacity, padding).
const CAPTURE_HEADER: u64 = 16;

/// An upper bound on the triangles the tessellator emits for one triangle
/// patch at `level` with equal factors: ring by ring `6a − 6` for a ring
/// of `a` segments per side (`a = level, level − 2, …`), plus 1 for an odd
/// level's centre triangle: `1.5·level²` (even), `1.5·level² − 0.5` (odd).
pub fn triangles_per_patch(level: u32) -> u64 {
    let n = level as u64;
    (3 * n * n).div_ceil(2)
}

/// Distinct vertices the tessellator emits for one triangle patch at
/// `level` with equal factors: `3a` per ring of `a` segments per side
/// (`a = level, level − 2, … > 0`), plus the centre point of an even level.
pub fn vertices_per_patch(level: u32) -> u64 {
    let rings: u64 = (0..=level / 2)
        .map(|k| level.saturating_sub(2 * k) as u64)
        .filter(|&a| a > 0)
        .map(|a| 3 * a)
        .sum();
    rings + u64::from(level.is_multiple_of(2))
}

/// Triangle patches per draw of the capture: lavapipe (Mesa's draw module)
/// numbers the tessellated vertices of one draw that feed a geometry shader
/// with 16-bit indices, so past 65 536 vertices a triangle picks up vertices
/// of an earlier patch (seen at level 64 from patch 20 on: 3169 vertices per
/// patch). Draws stay below that; a triangle whose vertices name different
/// patches is still reported ([`CaptureError::MixedPatches`]).
fn patches_per_draw(level: u32) -> u64 {
    (u16::MAX as u64 / vertices_per_patch(level).max(1)).max(1)
}

/// glslangValidator on one emitted shader, to SPIR-V words.
fn compile(
    source: &str,
    file: &str,
    stage: &'static str,
    entry: Option<&str>,
    defines: &[String],
) -> Result<Vec<u32>, VkError> {
    static SEQ: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "tessgen-vk-{}-{}",
        std::process::id(),
        SEQ.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).map_err(|e| VkError::Io(format!("{}: {e}", dir.display())))?;
    let name = file.replace('/', "_");
    let src: PathBuf = dir.join(&name);
    let spv = dir.join(format!("{name}.{stage}.spv"));
    let result = (|| {
        std::fs::write(&src, source).map_err(|e| VkError::Io(format!("{}: {e}", src.display())))?;
        let mut cmd = Command::new("glslangValidator");
        cmd.args(["-V", "--target-env", "vulkan1.1", "-S", stage]);
        if let Some(e) = entry {
            // HLSL source, this entry point.
            cmd.args(["-D", "-e", e]);
        }
        cmd.arg(format!("-D{CAPTURE}"));
        for d in defines {
            cmd.arg(format!("-D{d}"));
        }
        cmd.arg(&src).arg("-o").arg(&spv);
        let out = cmd
            .output()
            .map_err(|e| VkError::NoGlslang(e.to_string()))?;
        if !out.status.success() {
            return Err(VkError::Compile {
                file: file.to_string(),
                stage,
                log: format!(
                    "{}{}",
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                ),
            });
        }
        let bytes =
            std::fs::read(&spv).map_err(|e| VkError::Io(format!("{}: {e}", spv.display())))?;
        ash::util::read_spv(&mut std::io::Cursor::new(bytes))
            .map_err(|e| VkError::Io(format!("{}: {e}", spv.display())))
    })();
    let _ = std::fs::remove_dir_all(&dir);
    result
}

/// The per-patch output locations a scheme's control stage writes: the
/// control points packed into `ceil(3·KMAX / 4)` `vec4`s, plus one for the
/// patch index the HLSL hull passes on; against the device's
/// `maxTessellationControlPerPatchOutputComponents / 4` locations (Vulkan's
/// "Shader Input and Output Locations" table).
pub fn per_patch_locations(scheme: &SchemeKernels) -> u32 {
    let kmax = scheme
        .classes
        .iter()
        .map(|c| c.control_points)
        .max()
        .unwrap_or(1);
    (3 * kmax).div_ceil(4) + 1
}

/// Check that a scheme's tessellation pipeline fits the device.
pub fn check_limits(scheme: &SchemeKernels, l: &DeviceLimits) -> Result<(), VkError> {
    let locations = per_patch_locations(scheme) as u64;
    let limit = |what, needed: u64, max: u64| {
        if needed > max {
            Err(VkError::Limit {
                scheme: scheme.name.to_string(),
                what,
                needed,
                max,
            })
        } else {
            Ok(())
        }
    };
    limit(
        "patch size (control points per input patch)",
        1,
        l.max_tessellation_patch_size as u64,
    )?;
    limit(
        "per-patch output locations of the control stage (maxTessellationControlPerPatchOutputComponents / 4)",
        locations,
        l.max_tessellation_control_per_patch_output_components as u64 / 4,
    )?;
    limit(
        "input locations of the evaluation stage (maxTessellationEvaluationInputComponents / 4)",
        locations,
        l.max_tessellation_evaluation_input_components as u64 / 4,
    )
}

/// A control mesh uploaded for one scheme, with its tessellation pipeline.
pub struct VkMesh<'v> {
    vk: &'v Vulkan,
    pub scheme: &'static SchemeKernels,
    pub options: Options,
    pub classes: Vec<ClassRange>,
    /// Face of each patch (patches sorted by class).
    pub patch_faces: Vec<u32>,
    num_vertices: u32,
    /// Storage buffers by binding (the samples buffer is made per evaluation).
    buffers: Vec<(u32, Buf)>,
    dummy: Option<Buf>,
    params: Option<Buf>,
    /// The stencil table (binding 9).
    table_img: Img,
    /// The displacement map (`binding::DISPLACE_MAP`; 1×1 zero unless displacing).
    map_img: Img,
    sampler: vk::Sampler,
    set_layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
    layout: vk::PipelineLayout,
    render_pass: vk::RenderPass,
    framebuffer: vk::Framebuffer,
    modules: Vec<vk::ShaderModule>,
    vertex_pipeline: vk::Pipeline,
    /// The compute patch stage (displacing builds, and
    /// [`VkMesh::evaluate_compute`]): fills the global control-point buffer
    /// the evaluation stage reads owners from.
    patch_pipeline: vk::Pipeline,
    /// The compute evaluation `eval_main` ([`VkMesh::evaluate_compute`];
    /// built on first use).
    eval_pipeline: vk::Pipeline,
    draw_pipeline: vk::Pipeline,
    /// The displacement map to upload (taken from the [`Upload`]).
    displace_map: crate::cpu::displace::DisplaceMap,
}

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
        let upload = Self::quad_upload(vk, topo, positions, scheme, options)?;
        let (class, cp_base) = upload.face_layout();
        let data = crate::cpu::displace::build(mesh, topo, &class, &cp_base, d)
            .map_err(cpu::TessError::from)?;
        Self::build(vk, upload.with_displacement(&data), &displacing(options))
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
        let upload = Self::tri_upload(vk, tri, scheme, options)?;
        let (class, cp_base) = upload.face_layout();
        let data = crate::cpu::displace::build_tri(source, tri, &class, &cp_base, d)
            .map_err(cpu::TessError::from)?;
        Self::build(vk, upload.with_displacement(&data), &displacing(options))
    }

    /// Whether the shaders are built with [`DISPLACE`].
    fn displaced(&self) -> bool {
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
            patch_pipeline: vk::Pipeline::null(),
            eval_pipeline: vk::Pipeline::null(),
            draw_pipeline: vk::Pipeline::null(),
            displace_map: upload.displace_map.clone(),
        }
    }

    fn build(vk: &'v Vulkan, upload: Upload, options: &Options) -> Result<Self, VkError> {
        check_limits(upload.scheme, &vk.limits)?;
        let max = vk.limits.max_storage_buffer_range as u64;
        for b in &upload.buffers {
            if b.bytes.len() as u64 > max {
                return Err(VkError::Limit {
                    scheme: upload.scheme.name.into(),
                    what: "bytes in one storage buffer (maxStorageBufferRange)",
                    needed: b.bytes.len() as u64,
                    max,
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

    /// An `R32_SFLOAT` image of `width × height` texels (row-major), in
    /// shader-read layout; handles go into `img` as soon as they exist, so
    /// an error part-way leaves them for the caller to destroy.
    fn r32_image(
        &self,
        img: &mut Img,
        what: &'static str,
        width: u32,
        height: u32,
        texels: &[f32],
    ) -> Result<(), VkError> {
        let vk = self.vk;
        let d = &vk.device;
        let max = vk.limits.max_image_dimension_2d;
        if width.max(height) > max {
            return Err(VkError::Limit {
                scheme: self.scheme.name.into(),
                what: "image texels along one side (maxImageDimension2D)",
                needed: width.max(height) as u64,
                max: max as u64,
            });
        }
        let extent = vk::Extent3D {
            width,
            height,
            depth: 1,
        };
        img.image = unsafe {
            d.create_image(
                &vk::ImageCreateInfo::default()
                    .image_type(vk::ImageType::TYPE_2D)
                    .format(vk::Format::R32_SFLOAT)
                    .extent(extent)
                    .mip_levels(1)
                    .array_layers(1)
                    .samples(vk::SampleCountFlags::TYPE_1)
                    .tiling(vk::ImageTiling::OPTIMAL)
                    .usage(vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST)
                    .initial_layout(vk::ImageLayout::UNDEFINED),
                None,
            )
        }
        .map_err(call("vkCreateImage"))?;
        let req = unsafe { d.get_image_memory_requirements(img.image) };
        let ty = vk
            .memory_type(
                req.memory_type_bits,
                vk::MemoryPropertyFlags::DEVICE_LOCAL,
                what,
            )
            .or_else(|_| {
                vk.memory_type(req.memory_type_bits, vk::MemoryPropertyFlags::empty(), what)
            })?;
        img.memory = unsafe {
            d.allocate_memory(
                &vk::MemoryAllocateInfo::default()
                    .allocation_size(req.size)
                    .memory_type_index(ty),
                None,
            )
        }
        .map_err(call("vkAllocateMemory"))?;
        unsafe { d.bind_image_memory(img.image, img.memory, 0) }
            .map_err(call("vkBindImageMemory"))?;
        let bytes: Vec<u8> = texels.iter().flat_map(|w| w.to_le_bytes()).collect();
        let staging = vk.buffer(
            "image staging",
            bytes.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
        )?;
        staging.write(&bytes);
        let range = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        };
        let image = img.image;
        let copied = vk.submit(|d, cb| unsafe {
            let to_dst = vk::ImageMemoryBarrier::default()
                .old_layout(vk::ImageLayout::UNDEFINED)
                .new_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
                .dst_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .image(image)
                .subresource_range(range);
            d.cmd_pipeline_barrier(
                cb,
                vk::PipelineStageFlags::TOP_OF_PIPE,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[to_dst],
            );
            let region = vk::BufferImageCopy::default()
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: 1,
                })
                .image_extent(extent);
            d.cmd_copy_buffer_to_image(
                cb,
                staging.buffer,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            );
            let to_read = vk::ImageMemoryBarrier::default()
                .old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
                .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
                .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::SHADER_READ)
                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .image(image)
                .subresource_range(range);
            d.cmd_pipeline_barrier(
                cb,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[to_read],
            );
        });
        staging.destroy(d);
        copied?;
        img.view = unsafe {
            d.create_image_view(
                &vk::ImageViewCreateInfo::default()
                    .image(img.image)
                    .view_type(vk::ImageViewType::TYPE_2D)
                    .format(vk::Format::R32_SFLOAT)
                    .subresource_range(range),
                None,
            )
        }
        .map_err(call("vkCreateImageView"))?;
        Ok(())
    }

    /// The stencil table as an `R32_SFLOAT` image (x = ring slot, y = row).
    fn table(&mut self) -> Result<(), VkError> {
        let table = kernels::table();
        let width = kernels::common::TABLE_WIDTH;
        let height = (table.len() as u32 / width).max(1);
        let mut img = Img::default();
        let made = self.r32_image(&mut img, "the stencil table", width, height, table);
        self.table_img = img;
        made?;
        let vk = self.vk;
        let d = &vk.device;
        self.sampler = unsafe {
            d.create_sampler(
                &vk::SamplerCreateInfo::default()
                    .mag_filter(vk::Filter::NEAREST)
                    .min_filter(vk::Filter::NEAREST)
                    .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                    .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE),
                None,
            )
        }
        .map_err(call("vkCreateSampler"))?;
        Ok(())
    }

    /// The displacement map (`binding::DISPLACE_MAP`) as an `R32_SFLOAT` image; a 1×1
    /// zero map while displacement is off. Read with exact texel fetches.
    fn map(&mut self) -> Result<(), VkError> {
        let m = self.displace_map.clone();
        let mut img = Img::default();
        let made = self.r32_image(
            &mut img,
            "the displacement map",
            m.width.max(1),
            m.height.max(1),
            &m.texels,
        );
        self.map_img = img;
        made
    }

    /// Descriptor type of a binding as the emitted language declares it:
    /// GLSL's table and displacement map are `sampler2D`s, HLSL's
    /// `Texture2D`s (`.Load`).
    fn descriptor_type(&self, b: u32) -> vk::DescriptorType {
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
        let bindings: Vec<vk::DescriptorSetLayoutBinding> = (0..LAYOUT_BINDINGS)
            .map(|b| {
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
                descriptor_count: LAYOUT_BINDINGS,
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
        for b in 0..LAYOUT_BINDINGS {
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
            let buf = if b == binding::PARAMS {
                self.params.as_ref()
            } else {
                self.buffers
                    .iter()
                    .find(|(k, _)| *k == b)
                    .map(|(_, buf)| buf)
                    .or(self.dummy.as_ref())
            };
            if let Some(buf) = buf {
                self.write_buffer(b, buf);
            }
        }
        Ok(())
    }

    fn write_buffer(&self, b: u32, buf: &Buf) {
        let info = [vk::DescriptorBufferInfo::default()
            .buffer(buf.buffer)
            .offset(0)
            .range(vk::WHOLE_SIZE)];
        let w = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(b)
            .descriptor_type(self.descriptor_type(b))
            .buffer_info(&info);
        unsafe { self.vk.device.update_descriptor_sets(&[w], &[]) };
    }

    /// Source, file name and entry point of a stage of the emitted shaders.
    fn shader(
        &self,
        stage: &'static str,
    ) -> Result<(String, &'static str, Option<&'static str>), VkError> {
        let s = self.scheme.name;
        let (file, entry) = match self.options.language {
            Language::Glsl => (
                match stage {
                    "comp" => format!("glsl/{s}_vertex_stage.comp"),
                    "patch" => format!("glsl/{s}_patch.comp"),
                    "eval" => format!("glsl/{s}_eval.comp"),
                    other => format!("glsl/{s}.{other}"),
                },
                None,
            ),
            Language::Hlsl => (
                format!("hlsl/{s}.hlsl"),
                Some(match stage {
                    "vert" => "vs_main",
                    "tesc" => "hs_main",
                    "tese" => "ds_main",
                    "patch" => "patch_main",
                    "eval" => "eval_main",
                    _ => "vertex_stage_main",
                }),
            ),
        };
        let source = kernels::shader(&file).ok_or_else(|| VkError::NoShader {
            language: self.options.language.name(),
            scheme: s.into(),
            file: file.clone(),
        })?;
        Ok((file, source, entry))
    }

    fn module(
        &mut self,
        stage: &'static str,
    ) -> Result<(vk::ShaderModule, &'static CStr), VkError> {
        let (file, source, entry) = if stage == "geom" {
            (
                "harness/capture_triangles.geom".to_string(),
                capture_geometry_shader(),
                None,
            )
        } else {
            self.shader(stage)?
        };
        // The compute patch and evaluation stages are compute shaders like
        // the vertex stage.
        let glslang_stage = if matches!(stage, "patch" | "eval") {
            "comp"
        } else {
            stage
        };
        let words = compile(
            source,
            &file,
            glslang_stage,
            entry,
            &self.options.all_defines(),
        )?;
        let m = unsafe {
            self.vk
                .device
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&words), None)
        }
        .map_err(call("vkCreateShaderModule"))?;
        self.modules.push(m);
        let name: &'static CStr = match entry {
            None => c"main",
            Some("vs_main") => c"vs_main",
            Some("hs_main") => c"hs_main",
            Some("ds_main") => c"ds_main",
            Some("patch_main") => c"patch_main",
            Some("eval_main") => c"eval_main",
            Some(_) => c"vertex_stage_main",
        };
        Ok((m, name))
    }

    /// A compute pipeline of the emitted `stage` ("comp": the vertex stage,
    /// "patch", "eval").
    fn compute_pipeline(&mut self, stage: &'static str) -> Result<vk::Pipeline, VkError> {
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

    fn set_params(&self, p: [u32; 6]) {
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

    /// Run the vertex stage (quad schemes); the control stage builds each
    /// patch's control points inside every draw. Displacing builds also run
    /// the compute patch stage, class by class, into the global
    /// control-point buffer (binding 8) at the class-sorted layout the
    /// owner records name: the evaluation stage evaluates owner patches
    /// from it.
    pub fn construct(&self) -> Result<(), VkError> {
        self.vertex_stage()?;
        if !self.displaced() {
            return Ok(());
        }
        self.patch_stage()
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

    /// The vertex stage as a compute dispatch (quad schemes).
    fn vertex_stage(&self) -> Result<(), VkError> {
        let per = abi::WORKGROUP_SIZE * self.vk.limits.max_compute_work_group_count_x.max(1);
        let mut first = 0;
        while first < self.num_vertices {
            let count = per.min(self.num_vertices - first);
            self.set_params([first, count, 0, 0, 1, 0]);
            let (pipe, layout, set) = (self.vertex_pipeline, self.layout, self.set);
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
            first += count;
        }
        Ok(())
    }

    /// Tessellate every patch at `level` through the hardware tessellator and
    /// read the captured samples back in face order: the same layout as
    /// [`cpu::evaluate`].
    pub fn evaluate(&self, level: u32) -> Result<Tessellation, VkError> {
        if self.options.adaptive.is_some() {
            return Err(VkError::AdaptiveNotGrid);
        }
        if self.scheme.sides == 3 {
            return Err(VkError::TriangleDomain {
                scheme: self.scheme.name.into(),
            });
        }
        self.check_level(level)?;
        self.with_samples(level, |p0, n| self.draw_chunk(level, p0, n, u64::MAX))
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
        if level == 0 || level > cpu::MAX_LEVEL {
            return Err(cpu::TessError::Level(level).into());
        }
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
        self.with_samples(level, |p0, n| {
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

    fn check_level(&self, level: u32) -> Result<(), VkError> {
        if level == 0 || level > cpu::MAX_LEVEL {
            return Err(cpu::TessError::Level(level).into());
        }
        let max_level = self.vk.limits.max_tessellation_generation_level;
        if level > max_level {
            return Err(VkError::Limit {
                scheme: self.scheme.name.into(),
                what: "tessellation level (maxTessellationGenerationLevel)",
                needed: level as u64,
                max: max_level as u64,
            });
        }
        Ok(())
    }

    /// Draws of the patches `p0 .. p0 + n`: per facet class, at most
    /// `per_draw` patches each.
    fn draw_chunk(&self, level: u32, p0: u64, n: u64, per_draw: u64) -> Result<(), VkError> {
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

    /// Triangle schemes: tessellate every patch at `level` through the
    /// hardware tessellator and capture the triangles it emitted (position,
    /// normal, raw domain point, patch of every vertex) with the harness's
    /// geometry shader, grouped per face of the triangle mesh. The
    /// tessellator's inner vertices are not the barycentric lattice, so this
    /// is not a grid like [`Self::evaluate`]'s.
    pub fn evaluate_triangles(&self, level: u32) -> Result<TriangleCapture, VkError> {
        if self.options.adaptive.is_some() {
            return Err(VkError::AdaptiveNotGrid);
        }
        if self.scheme.sides != 3 {
            return Err(VkError::QuadDomain {
                scheme: self.scheme.name.into(),
            });
        }
        self.check_level(level)?;
        self.capture(
            level,
            level,
            triangles_per_patch(level),
            patches_per_draw(level),
        )
    }

    /// Run an adaptive draw ([`Options::adaptive`], quad or triangle
    /// scheme) and capture every tessellated triangle with the same
    /// geometry shader as [`Self::evaluate_triangles`]: per vertex the
    /// position, normal, domain point (quads `(u, v, 0)`, triangles
    /// barycentric) and patch. The capture's `level` is the fixed-point
    /// denominator `2^16` the evaluation stage used, so
    /// [`TriangleCapture::max_deviation`] can evaluate the CPU at the same
    /// points. Weld with [`TriangleCapture::weld`].
    pub fn evaluate_adaptive(&self) -> Result<TriangleCapture, VkError> {
        let Some(a) = &self.options.adaptive else {
            return Err(VkError::AdaptiveNotGrid);
        };
        // At most 2·(ceil(max) + 2)² triangles per patch (the inside factor
        // is at most the largest edge factor, a fractional pattern adds one
        // transition ring; a triangle patch emits fewer than a quad), and
        // at most (m + 1)² vertices: draws stay under lavapipe's 16-bit
        // vertex numbering with a geometry shader (see patches_per_draw).
        let m = a.max.max(1.0).ceil() as u64 + 2;
        let per_draw = (u16::MAX as u64 / ((m + 1) * (m + 1))).max(1);
        self.capture(1, ADAPTIVE_LEVEL, 2 * m * m, per_draw)
    }

    /// Draw every patch (`Params.level = level`; adaptive builds ignore it)
    /// with the capture geometry shader bound to `binding::TRIANGLES`, in
    /// readback chunks of at most `tris_per_patch` triangles per patch and
    /// draws of at most `per_draw` patches; the capture records `record_level`.
    fn capture(
        &self,
        level: u32,
        record_level: u32,
        tris_per_patch: u64,
        per_draw: u64,
    ) -> Result<TriangleCapture, VkError> {
        let per_patch = tris_per_patch * 3 * VERTEX_FLOATS as u64 * 4;
        let cap = (self.vk.limits.max_storage_buffer_range as u64).min(256 << 20) - CAPTURE_HEADER;
        if per_patch > cap {
            return Err(VkError::Limit {
                scheme: self.scheme.name.into(),
                what: "bytes of captured triangles of one patch (maxStorageBufferRange)",
                needed: per_patch,
                max: cap,
            });
        }
        let total = self.patch_faces.len() as u64;
        let chunk = (cap / per_patch).min(total.max(1));
        let buf = self.vk.buffer(
            "captured triangles",
            CAPTURE_HEADER + chunk * per_patch,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let result = (|| {
            self.write_buffer(binding::TRIANGLES, &buf);
            if let Some(d) = &self.dummy {
                // The evaluation stage writes no grid samples here.
                self.write_buffer(binding::SAMPLES, d);
            }
            let mut raw = Vec::new();
            let mut p0 = 0u64;
            while p0 < total {
                let n = chunk.min(total - p0);
                let capacity = n * tris_per_patch;
                buf.write(&u32_bytes(&[0, capacity as u32, 0, 0]));
                self.draw_chunk(level, p0, n, per_draw)?;
                let head = buf.read_f32(4);
                let emitted = head[0].to_bits() as u64;
                if emitted > capacity {
                    return Err(VkError::CaptureOverflow {
                        level: record_level,
                        patches: n,
                        emitted,
                        capacity,
                    });
                }
                let floats = buf.read_f32(4 + emitted as usize * 3 * VERTEX_FLOATS);
                raw.extend_from_slice(&floats[4..]);
                p0 += n;
            }
            Ok(TriangleCapture::from_raw(
                record_level,
                &raw,
                &self.patch_faces,
                self.patch_faces.len(),
            )?)
        })();
        buf.destroy(&self.vk.device);
        result
    }

    /// A samples buffer of as many patches' grids at `level` as fit one
    /// storage binding (and 256 MiB), bound at [`binding::SAMPLES`]; then
    /// [`Self::read_samples`] with it.
    fn with_samples(
        &self,
        level: u32,
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
            });
        }
        let total = self.patch_faces.len() as u64;
        let chunk = (cap / per_patch).min(total.max(1));
        let samples = self.vk.buffer(
            "samples",
            chunk * per_patch,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let result = self.read_samples(level, spp, chunk, &samples, run);
        samples.destroy(&self.vk.device);
        result
    }

    /// Bind `samples`, let `run(p0, n)` write patches `p0 .. p0 + n` at
    /// `(patch − p0)·spp` samples of SAMPLE_FLOATS floats, chunk by chunk, and gather
    /// them in face order.
    fn read_samples(
        &self,
        level: u32,
        spp: u64,
        chunk: u64,
        samples: &Buf,
        run: impl Fn(u64, u64) -> Result<(), VkError>,
    ) -> Result<Tessellation, VkError> {
        self.write_buffer(binding::SAMPLES, samples);
        let faces = self.patch_faces.len();
        let mut grids = GridReadback::new(level, self.scheme.sides, faces, spp);
        let nan: Vec<u8> = std::iter::repeat_n(
            f32::NAN.to_le_bytes(),
            (chunk * spp) as usize * abi::SAMPLE_LEN,
        )
        .flatten()
        .collect();
        let mut p0 = 0u64;
        while p0 < faces as u64 {
            let n = chunk.min(faces as u64 - p0);
            // Unwritten samples stay NaN, so a missed write fails parity.
            samples.write(&nan);
            run(p0, n)?;
            let floats = samples.read_f32((n * spp) as usize * abi::SAMPLE_LEN);
            grids.scatter(&floats, p0, &self.patch_faces);
            p0 += n;
        }
        Ok(grids.finish())
    }
}

impl Drop for VkMesh<'_> {
    fn drop(&mut self) {
        let d = &self.vk.device;
        unsafe {
            let _ = d.device_wait_idle();
            d.destroy_pipeline(self.draw_pipeline, None);
            d.destroy_pipeline(self.vertex_pipeline, None);
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

/// `options` with [`DISPLACE`] among its defines.
fn displacing(options: &Options) -> Options {
    let mut options = options.clone();
    if !options.defines.iter().any(|x| x == DISPLACE) {
        options.defines.push(DISPLACE.into());
    }
    options
}
