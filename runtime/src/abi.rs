//! The GPU ABI, declared once in `tessgen-codegen` (`backend::abi`) and
//! printed as Rust by this crate's `build.rs`: binding numbers by name
//! ([`binding`]), the Params layout ([`params`], [`PARAMS_SIZE`]), strides,
//! workgroup sizes, the bucket constants, the `adaptive` buffer's slots
//! ([`adaptive`]), the define names ([`define`]) and every WGSL entry's
//! binding list. The runtime names these instead of typing numbers, so an
//! ABI change it does not follow fails to compile here rather than at run
//! time on a GPU.
#![allow(dead_code)]

include!(concat!(env!("OUT_DIR"), "/abi.rs"));

/// The `u32` constants as `u64`/`usize`, for buffer-size arithmetic.
pub const WORKGROUP: u64 = WORKGROUP_SIZE as u64;
pub const SAMPLE_LEN: usize = SAMPLE_FLOATS as usize;
/// `u32` per `patch_levels` record, as a slice length.
pub const LEVELS_LEN: usize = PATCH_LEVELS_WORDS as usize;
/// `u32` per bucket-list entry, as a slice length.
pub const ENTRY_LEN: usize = BUCKET_ENTRY_WORDS as usize;
/// `u32` per bucket-slot header, as a slice length.
pub const HEADER_LEN: usize = BUCKET_HEADER_WORDS as usize;
/// Bytes of one `patch_levels` record.
pub const LEVELS_BYTES: u64 = (PATCH_LEVELS_WORDS * ELEMENT_BYTES) as u64;
/// Index of the bucket word in a `patch_levels` record.
pub const LEVELS_BUCKET: usize = PATCH_LEVELS_BUCKET as usize;
/// Bytes per `u32`/`f32` buffer element, as `u64` for buffer sizes.
pub const WORD_BYTES: u64 = ELEMENT_BYTES as u64;

// Records the runtime spells as Rust values follow the ABI or fail to
// compile: a sample is read as two `Vec3` (position, normal) in gpu/wgpu and
// gpu/vulkan, a `bucket_patches` entry is built as six `u32` (patch, first
// control point, four edge levels) in `GpuMesh::evaluate_adaptive`, and a
// `patch_levels` record is read as four edge levels then the bucket.
const _: () = assert!(SAMPLE_FLOATS == 6);
const _: () = assert!(BUCKET_ENTRY_WORDS == 6);
const _: () = assert!(PATCH_LEVELS_WORDS == 5 && PATCH_LEVELS_BUCKET == 4);
