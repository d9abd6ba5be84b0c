//! The GPU side: what every GPU backend uploads and reads back, and the two
//! backends that run the emitted shaders.
//!
//! * [`upload`]: the backend-neutral buffers of a mesh (one per ABI binding,
//!   patches sorted by facet class).
//! * `readback`: the one scatter of per-patch GPU samples back into
//!   per-face grids (crate-internal).
//! * [`capture`]: a hardware tessellator's output as triangles (always
//!   built: the front door's `Output::Captured` holds one).
//! * [`wgpu`] (feature `gpu`): the generated WGSL in compute
//!   passes and instanced draws; [`renderer`] (a surface drawn every frame
//!   into an engine's render pass), [`render`] (offscreen images through
//!   it) and the instanced [`pattern`] draw with it.
//! * `vulkan` (feature `vulkan`): the emitted GLSL/HLSL tessellation shaders
//!   in a real Vulkan tessellation pipeline.
//!
//! Everything here depends on [`crate::cpu`] (scheme lookup, the grid
//! type, adaptive and displacement host data) and nothing here depends on
//! [`crate::tessellate`], the front door above it. The wgpu types are
//! re-exported here at their long-standing paths (`gpu::Gpu`,
//! `gpu::GpuMesh`, …). Inside this file the child module `wgpu` shadows the
//! `wgpu` crate, so the crate would be `::wgpu` here (it is not used here).

pub mod capture;
pub mod pattern;
#[cfg(any(feature = "gpu", feature = "vulkan"))]
pub(crate) mod readback;
#[cfg(feature = "gpu")]
pub mod render;
#[cfg(feature = "gpu")]
pub mod renderer;
pub mod upload;
#[cfg(feature = "vulkan")]
pub mod vulkan;
#[cfg(feature = "gpu")]
pub mod wgpu;

#[cfg(feature = "gpu")]
pub use self::wgpu::{ClassRange, Gpu, GpuError, GpuMesh, Limits};
