//! The topology builder's error type and the "no element" marker, apart from
//! [`crate::mesh::topology`] so that the fan and sector walk
//! ([`crate::mesh::sectors`]) reports with them without importing the
//! builder that calls it.

use thiserror::Error;

use crate::mesh::features::FeatureError;
use crate::mesh::MeshError;

/// Marker for "no such element" in the flat `u32` arrays (e.g.
/// [`Topology::twin`](crate::Topology::twin) of a boundary half-edge).
pub const NONE: u32 = u32::MAX;

/// Why a mesh is not usable for patch generation. Vertex numbers are 0-based file indices
/// (OBJ index − 1); faces are 0-based in file order.
#[derive(Debug, Error)]
pub enum TopologyError {
    /// The mesh itself is invalid.
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    /// The mesh's tags (or the explicit [`Features`](crate::mesh::features::Features)) are
    /// invalid.
    #[error("invalid tags: {0}")]
    Features(#[from] FeatureError),
    /// A face is not a quad while
    /// [`TopologyOptions::require_quads`](crate::TopologyOptions::require_quads) is set.
    #[error(
        "face {face} has {arity} vertices; this topology takes quads only (the front door, \
         `tessgen_runtime::tessellate`, refines non-quad faces by one Catmull-Clark step first)"
    )]
    NonQuad {
        /// 0-based face index.
        face: usize,
        /// Its number of vertices.
        arity: usize,
    },
    /// An edge is shared by more than two faces. `a → b` is the direction of the first
    /// (lowest half-edge id) face using it.
    #[error("edge {a}-{b} is used by more than two faces")]
    NonManifoldEdge {
        /// First vertex.
        a: u32,
        /// Second vertex.
        b: u32,
    },
    /// Exactly two faces share the edge, but both traverse it as `a → b`: one of them is
    /// flipped. (Kept apart from [`TopologyError::NonManifoldEdge`] because it is fixable by
    /// reorienting faces.)
    #[error("edge {a}->{b} is traversed in the same direction by both of its faces (inconsistent orientation)")]
    InconsistentOrientation {
        /// Origin of both half-edges.
        a: u32,
        /// Destination of both half-edges.
        b: u32,
    },
    /// The faces around a vertex form more than one fan (e.g. two surfaces touching at a point).
    #[error("vertex {vertex} is non-manifold: its faces form more than one fan")]
    NonManifoldVertex {
        /// The vertex.
        vertex: u32,
    },
    /// A vertex has more edges than
    /// [`TopologyOptions::max_valence`](crate::TopologyOptions::max_valence).
    #[error(
        "vertex {vertex} has valence {valence}, more than the maximum {max} of the stencil \
         table (a table generated with `--max-valence {valence}` takes it)"
    )]
    ValenceTooHigh {
        /// The vertex.
        vertex: u32,
        /// Its valence.
        valence: u32,
        /// The configured maximum.
        max: u32,
    },
    /// A crease or corner sector has more faces than the stencil table's sector blocks hold
    /// ([`max_sector_faces`](crate::mesh::sectors::max_sector_faces) of
    /// [`TopologyOptions::max_valence`](crate::TopologyOptions::max_valence)).
    #[error(
        "vertex {vertex} has a sector of {faces} faces between sharp edges, more than \
         max_valence / 2 = {max} (a stencil table generated with `--max-valence {needed}` \
         takes it)"
    )]
    SectorTooLarge {
        /// The vertex.
        vertex: u32,
        /// Faces in the sector.
        faces: u32,
        /// [`max_sector_faces`](crate::mesh::sectors::max_sector_faces) of the configured
        /// maximum valence.
        max: u32,
        /// The smallest `--max-valence` that takes the sector (`2 · faces`).
        needed: u32,
    },
    /// An interior vertex has fewer than 3 edges (the ring formulas need `n ≥ 3`).
    #[error("vertex {vertex} has valence {valence}; interior vertices need at least 3")]
    ValenceTooLow {
        /// The vertex.
        vertex: u32,
        /// Its valence.
        valence: u32,
    },
}
