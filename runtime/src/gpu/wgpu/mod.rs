//! The wgpu GPU path: the generated WGSL runs the vertex and patch stages in
//! compute passes and evaluates patches either into a storage buffer (for
//! readback) or in an instanced vertex shader (for drawing).
//!
//! Layout follows OpenSubdiv's `Far` idea: topology, rings and the stencil
//! table are uploaded once as flat buffers / an `R32Float` texture; the GPU
//! only indexes them. Patches are sorted by facet class so each class is one
//! dispatch (or one instanced draw). Device limits are respected by splitting
//! dispatches and readbacks into chunks, never by truncating.
//!
//! The struct is here; its methods are split by concern: `device` (the
//! device, limits, errors), `mesh` (upload and construction), `pass` (what
//! every pass shares), `evaluate` (uniform grids), `adaptive` (host
//! lists and the choice of path) and `buckets` (the GPU-driven buckets).

mod adaptive;
mod buckets;
mod device;
mod evaluate;
mod mesh;
mod pass;

pub use adaptive::Classified;
pub(crate) use buckets::{Buckets, Run, CHUNK, SLOTS};
pub use device::{Gpu, GpuError, Limits};

pub use crate::gpu::upload::ClassRange;
use crate::kernels::common::SchemeKernels;
use std::collections::HashMap;

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
    /// The refinement stage, when the GPU refines the positions
    /// ([`GpuMesh::new_refined`]).
    refine: Option<crate::gpu::upload::RefineLayout>,
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
