//! tessgen runtime: meshes in, smooth tessellated surfaces out.
//!
//! The folders follow the pipeline, each using only the ones before it
//! (no import circles between modules or folders):
//!
//! * [`mesh`] reads OBJ files (through `tobj`) and their tags into a plain
//!   polygon mesh; [`topology`] builds the half-edge structure, every
//!   vertex's 1-ring (stored once, canonical start) and every face's corner
//!   records; [`trimesh`] the triangle meshes of triangle schemes.
//! * [`abi`] (the GPU interface) and [`kernels`] (the Rust code tessgen
//!   generated for the built-in schemes, and its stencil table) are written
//!   at build time by this crate's `build.rs`; [`grid`] is the per-patch
//!   sample layout they share.
//! * [`cpu`] runs those kernels over a mesh, in parallel, and holds what
//!   every backend takes from the host: [`adaptive`] (edge ids, metrics,
//!   factors) and [`displace`] (ownership tables, maps). It is its own
//!   folder, below `gpu` and `check`, because both use its types while the
//!   front door dispatches to the GPU backends.
//! * [`check`]: [`weld`] checks watertightness by exact-bit welding;
//!   [`stats`], [`accuracy`]; [`obj`] writes grids.
//! * [`gpu`]: the backend-neutral [`upload`], the hardware [`capture`], the
//!   wgpu path (`gpu::wgpu`, feature `gpu`, with `render` and its
//!   instanced [`pattern`]) and the Vulkan tessellation harness
//!   (`gpu::vulkan`, feature `vulkan`).
//! * [`tessellate`] is the front door: a [`tessellate::Request`] (scheme,
//!   level or adaptive metric, backend, displacement, tags) validated once
//!   against the mesh, then run on the CPU, wgpu or the Vulkan harness.
//!
//! ```no_run
//! use tessgen_runtime::tessellate::{tessellate, Request};
//! use tessgen_runtime::Mesh;
//! let mesh = Mesh::from_obj_path("cube.obj")?;
//! let out = tessellate(&mesh, &Request::uniform("pccm", 8))?;
//! assert!(out.weld().is_closed_manifold());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod abi;
pub mod camera;
pub mod check;
pub mod cpu;
pub mod export;
pub mod gpu;
pub mod grid;
pub mod kernels;
pub mod mesh;
pub mod tessellate;

/// Modules of mesh/, check/, cpu/ and gpu/ at their long-standing public
/// paths (`tessgen_runtime::topology`, `::weld`, `::adaptive`, `::upload`,
/// `::render`, `::vulkan`, …); the wgpu types stay at `gpu::{Gpu, GpuMesh,
/// …}` (re-exported by `gpu/mod.rs`).
pub use check::{accuracy, heatmap, obj, stats, weld};
pub use cpu::{adaptive, displace};
#[cfg(feature = "gpu")]
pub use gpu::render;
#[cfg(feature = "vulkan")]
pub use gpu::vulkan;
pub use gpu::{capture, pattern, upload};
pub use mesh::{tags, topology, trimesh};

pub use cpu::{TessError, Tessellation};
pub use mesh::{Mesh, MeshError};
pub use topology::{FaceClass, Topology, TopologyError, TopologyOptions};
