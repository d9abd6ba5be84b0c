//! tessgen runtime: meshes in, smooth tessellated surfaces out.
//!
//! * [`mesh`] reads OBJ files (through `tobj`) into a plain polygon mesh.
//! * [`topology`] builds the half-edge structure, every vertex's 1-ring
//!   (stored once, canonical start) and every face's corner records.
//! * [`kernels`] is the Rust code tessgen generated for the built-in schemes
//!   (at build time, by this crate's `build.rs`) and its stencil table.
//! * [`tessellate`] is the front door: a [`tessellate::Request`] (scheme,
//!   level or adaptive metric, backend, displacement, tags) validated once
//!   against the mesh, then run on the CPU, wgpu or the Vulkan harness.
//! * [`cpu`] runs those kernels over a mesh, in parallel.
//! * [`weld`] checks watertightness by exact-bit welding; [`obj`] writes grids.
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
pub mod check;
pub mod cpu;
pub mod gpu;
pub mod grid;
pub mod kernels;
pub mod mesh;
pub mod tessellate;

/// The mesh, check, cpu and gpu modules at their long-standing public paths
/// (`tessgen_runtime::topology`, `::weld`, `::adaptive`, `::vulkan`, …).
pub use check::{accuracy, obj, stats, weld};
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
