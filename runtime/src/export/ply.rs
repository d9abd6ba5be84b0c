//! Binary little-endian PLY: `element vertex` with `x y z nx ny nz` as
//! floats, `element face` with `vertex_indices` as a `uchar` count (3) and
//! `uint` indices — the layout Blender, MeshLab and most PLY readers take.
//! The header is written by hand: the PLY crates build the whole mesh in
//! memory before writing, and here the counts are all it needs
//! (`tests/tests/export.rs` re-reads the file with the `ply-rs-bw` crate).

use super::{Counts, Part};
use std::io::Write;

/// One face record: count 3, then the three indices.
pub(crate) fn face_bytes(ids: [u32; 3], out: &mut Vec<u8>) {
    out.push(3);
    for i in ids {
        out.extend_from_slice(&i.to_le_bytes());
    }
}

pub(crate) fn write(
    out: &mut impl Write,
    counts: &Counts,
    vertices: &mut Part,
    faces: &mut Part,
) -> std::io::Result<()> {
    write!(
        out,
        "ply\nformat binary_little_endian 1.0\ncomment tessgen {}\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        env!("CARGO_PKG_VERSION"),
        counts.vertices,
        counts.triangles
    )?;
    vertices.append_to(out)?;
    faces.append_to(out)
}
