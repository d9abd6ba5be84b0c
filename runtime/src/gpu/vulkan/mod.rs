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
//!
//! The structs ([`Vulkan`], [`VkMesh`], and the buffer and image handles)
//! are here, their methods split by concern: `device` (instance, device,
//! errors, limits), `memory` (buffers, images), `shaders`
//! (glslangValidator, the capture geometry shader), `mesh` (`VkMesh`
//! creation, descriptors, pipelines), `evaluate` (the stages, uniform
//! evaluation) and `triangles` (captured draws, adaptive).

mod device;
mod evaluate;
mod memory;
mod mesh;
mod shaders;
mod triangles;

pub use device::{check_limits, per_patch_locations, DeviceLimits, VkError};
pub use triangles::{triangles_per_patch, vertices_per_patch};

use crate::abi::binding;
use crate::cpu::adaptive::Adaptive;
use crate::gpu::upload::ClassRange;
use crate::kernels::common::SchemeKernels;
use ash::vk;

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
/// included, then the sector records of crease and corner vertices and the
/// per-corner constant valences (the WGSL-only bucket bindings 25–30 are
/// left out of the set).
const LAYOUT_BINDINGS: &[u32] = &{
    const LOW: usize = binding::DISPLACE_MAP as usize + 1;
    const HIGH: [u32; 8] = [
        binding::VERTEX_SECTORS,
        binding::SECTORS,
        binding::CORNER_VALENCE,
        binding::REFINE_BASE,
        binding::REFINE_OFFSETS,
        binding::REFINE_INDICES,
        binding::REFINE_WEIGHTS,
        binding::REFINED_POSITIONS,
    ];
    let mut all = [0u32; LOW + HIGH.len()];
    let mut b = 0;
    while b < LOW {
        all[b] = b as u32;
        b += 1;
    }
    let mut k = 0;
    while k < HIGH.len() {
        all[LOW + k] = HIGH[k];
        k += 1;
    }
    all
};

/// A 2-D `R32_SFLOAT` image with its memory and view (the stencil table,
/// the displacement map).
#[derive(Clone, Copy)]
struct Img {
    image: vk::Image,
    memory: vk::DeviceMemory,
    view: vk::ImageView,
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

/// A buffer with its memory, mapped.
struct Buf {
    buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    size: u64,
    ptr: *mut u8,
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
    /// The refinement stage (`refine_main`) of a mesh refined on the GPU
    /// ([`VkMesh::new_refined`]), run before the vertex stage.
    refine_pipeline: vk::Pipeline,
    refine: Option<crate::gpu::upload::RefineLayout>,
    /// The compute patch stage (displacing builds, and
    /// [`VkMesh::evaluate_compute`]): fills the global control-point buffer
    /// the evaluation stage reads owners from.
    patch_pipeline: vk::Pipeline,
    /// The compute evaluation `eval_main` ([`VkMesh::evaluate_compute`];
    /// built on first use).
    eval_pipeline: vk::Pipeline,
    draw_pipeline: vk::Pipeline,
    /// The displacement map to upload (taken from the [`crate::gpu::upload::Upload`]).
    displace_map: crate::cpu::displace::DisplaceMap,
}

/// `options` with [`DISPLACE`] among its defines.
fn displacing(options: &Options) -> Options {
    let mut options = options.clone();
    if !options.defines.iter().any(|x| x == DISPLACE) {
        options.defines.push(DISPLACE.into());
    }
    options
}
