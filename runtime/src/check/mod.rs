//! Checking and writing what a tessellation produced: exact-bit welding
//! (watertightness), mesh statistics, accuracy against the Catmull-Clark
//! limit, and the OBJ output every backend writes the same way. Nothing here
//! tessellates; everything reads a [`crate::Tessellation`] or its samples.

pub mod accuracy;
pub mod heatmap;
pub mod obj;
pub mod stats;
pub mod weld;
