//! tessgen runtime: meshes in, smooth tessellated surfaces out.
//!
//! * [`mesh`] reads OBJ files (through `tobj`) into a plain polygon mesh.
//! * [`topology`] builds the half-edge structure, every vertex's 1-ring
//!   (stored once, canonical start) and every face's corner records.

pub mod kernels;
pub mod mesh;
pub mod topology;

pub use mesh::{Mesh, MeshError};
pub use topology::{FaceClass, Topology, TopologyError, TopologyOptions};
