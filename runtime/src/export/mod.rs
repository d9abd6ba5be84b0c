//! Binary mesh output: glTF 2.0 binary (`.glb`, [`glb`]) and binary PLY
//! (`.ply`, [`ply`]), chosen by the output's extension ([`Format::of`]),
//! written chunk by chunk like the OBJ ([`crate::tessellate::Session::run_chunked`]).
//!
//! Both are one indexed triangle mesh with a position and a unit normal per
//! vertex, **welded by exact bits**: two patches' samples of a shared edge
//! have the same position bits on every backend (docs/watertight.md), so
//! they become one vertex and the file is one watertight mesh — a closed
//! input gives a closed output, each edge used by exactly two triangles.
//! The welded vertex keeps the normal of the first patch that wrote it (the
//! patches' normals at a shared sample agree to rounding, not to the bit).
//!
//! Memory stays bounded: only samples on a patch's own border can be shared
//! with another patch, so only those go into the weld map (found per patch
//! as the vertices of its open edges, whatever the output's layout: grids,
//! adaptive grids, captured triangles); interior samples get a new index
//! at once. Vertex and index data go to two temporary files beside the
//! output while the chunks arrive, because both containers put their
//! counts (and glTF the position bounds) before the data; [`MeshStream::finish`]
//! writes the header and appends them.

pub mod glb;
pub mod ply;

use glam::Vec3;
use std::collections::HashMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// An output format, by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ text (the default; [`crate::obj::ObjStream`]).
    Obj,
    /// glTF 2.0 binary container.
    Glb,
    /// Binary little-endian PLY.
    Ply,
}

impl Format {
    /// The format `path`'s extension names (`.glb`, `.ply`, case
    /// insensitive); anything else is OBJ.
    pub fn of(path: &Path) -> Format {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("glb") => Format::Glb,
            Some("ply") => Format::Ply,
            _ => Format::Obj,
        }
    }
}

/// Bytes of one vertex in the vertex file: position, normal (6 × f32 LE).
pub const VERTEX_BYTES: u64 = 24;

/// A welded, indexed triangle mesh written patch by patch into two
/// temporary files, then into a `.glb` or `.ply` by [`MeshStream::finish`].
pub struct MeshStream {
    format: Format,
    vertices: Part,
    indices: Part,
    /// Border samples already written: position bits → vertex index.
    weld: HashMap<[u32; 3], u32>,
    vertex_count: u64,
    triangle_count: u64,
    min: Vec3,
    max: Vec3,
    /// Per patch: its sample → vertex index (reused buffers).
    local: Vec<u32>,
    border: Vec<bool>,
    edges: HashMap<(u32, u32), u32>,
}

/// One temporary file, deleted when dropped.
pub(crate) struct Part {
    path: PathBuf,
    out: Option<BufWriter<File>>,
}

impl Part {
    fn create(path: PathBuf) -> std::io::Result<Part> {
        let file = File::create(&path)?;
        Ok(Part {
            path,
            out: Some(BufWriter::with_capacity(1 << 20, file)),
        })
    }

    fn write(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        match &mut self.out {
            Some(w) => w.write_all(bytes),
            None => Err(std::io::Error::other("mesh stream already finished")),
        }
    }

    /// Flush, then copy the whole file into `to`.
    pub(crate) fn append_to(&mut self, to: &mut impl Write) -> std::io::Result<()> {
        if let Some(mut w) = self.out.take() {
            w.flush()?;
        }
        let mut f = File::open(&self.path)?;
        std::io::copy(&mut f, to).map(|_| ())
    }
}

impl Drop for Part {
    fn drop(&mut self) {
        self.out = None;
        let _ = std::fs::remove_file(&self.path);
    }
}

impl MeshStream {
    /// A stream of `format` ([`Format::Glb`] or [`Format::Ply`]) whose
    /// temporary files are `scratch` + `.vertices` / `.indices`.
    pub fn new(format: Format, scratch: &Path) -> std::io::Result<MeshStream> {
        if format == Format::Obj {
            return Err(std::io::Error::other("OBJ is written by ObjStream"));
        }
        let with = |ext: &str| {
            let mut s = scratch.as_os_str().to_owned();
            s.push(ext);
            PathBuf::from(s)
        };
        Ok(MeshStream {
            format,
            vertices: Part::create(with(".vertices"))?,
            indices: Part::create(with(".indices"))?,
            weld: HashMap::new(),
            vertex_count: 0,
            triangle_count: 0,
            min: Vec3::splat(f32::INFINITY),
            max: Vec3::splat(f32::NEG_INFINITY),
            local: Vec::new(),
            border: Vec::new(),
            edges: HashMap::new(),
        })
    }

    /// Vertices written so far (after welding).
    pub fn vertex_count(&self) -> u64 {
        self.vertex_count
    }

    /// Triangles written so far.
    pub fn triangle_count(&self) -> u64 {
        self.triangle_count
    }

    /// Append one patch: its samples and its triangles over them (local
    /// indices). Samples on the patch's open edges are welded with the
    /// other patches' (and with each other) by their position bits;
    /// samples no triangle uses are left out, and so are triangles the weld
    /// collapses to a segment or a point (two corners the same vertex: an
    /// adaptive grid's border samples snapped onto a coarser edge).
    pub fn patch(
        &mut self,
        positions: &[Vec3],
        normals: &[Vec3],
        triangles: &[[u32; 3]],
    ) -> std::io::Result<()> {
        let n = positions.len();
        if normals.len() != n || triangles.iter().flatten().any(|&k| k as usize >= n) {
            return Err(std::io::Error::other(
                "a patch's triangles index past its samples",
            ));
        }
        // The patch's open edges (used by one of its triangles): their
        // vertices are the samples another patch can share.
        self.edges.clear();
        for t in triangles {
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                *self.edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        self.border.clear();
        self.border.resize(n, false);
        for (&(a, b), &uses) in &self.edges {
            if uses == 1 {
                self.border[a as usize] = true;
                self.border[b as usize] = true;
            }
        }
        self.local.clear();
        self.local.resize(n, u32::MAX);
        let mut tri_bytes = Vec::with_capacity(triangles.len() * 13);
        let mut kept = 0u64;
        for t in triangles {
            let mut ids = [0u32; 3];
            for (id, &k) in ids.iter_mut().zip(t) {
                *id = self.vertex(k as usize, positions, normals)?;
            }
            // A triangle the weld collapses (an adaptive grid's border
            // samples snapped onto a coarser edge coincide) has no area.
            if ids[0] == ids[1] || ids[1] == ids[2] || ids[2] == ids[0] {
                continue;
            }
            kept += 1;
            match self.format {
                Format::Ply => ply::face_bytes(ids, &mut tri_bytes),
                _ => ids
                    .iter()
                    .for_each(|i| tri_bytes.extend_from_slice(&i.to_le_bytes())),
            }
        }
        self.indices.write(&tri_bytes)?;
        self.triangle_count += kept;
        Ok(())
    }

    /// The vertex index of sample `k` of the current patch, writing the
    /// vertex if it is new.
    fn vertex(&mut self, k: usize, positions: &[Vec3], normals: &[Vec3]) -> std::io::Result<u32> {
        if self.local[k] != u32::MAX {
            return Ok(self.local[k]);
        }
        let p = positions[k];
        let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        if self.border[k] {
            if let Some(&id) = self.weld.get(&key) {
                self.local[k] = id;
                return Ok(id);
            }
        }
        let id = vertex_index(self.vertex_count)?;
        let nrm = normals[k];
        let mut bytes = [0u8; VERTEX_BYTES as usize];
        for (c, v) in [p.x, p.y, p.z, nrm.x, nrm.y, nrm.z].iter().enumerate() {
            bytes[4 * c..4 * c + 4].copy_from_slice(&v.to_le_bytes());
        }
        self.vertices.write(&bytes)?;
        self.min = self.min.min(p);
        self.max = self.max.max(p);
        self.vertex_count += 1;
        if self.border[k] {
            self.weld.insert(key, id);
        }
        self.local[k] = id;
        Ok(id)
    }

    /// Write the container into `out`: header (counts, glTF's bounds),
    /// then the vertex and index data. The temporary files are removed.
    pub fn finish(mut self, out: &mut impl Write) -> std::io::Result<()> {
        let counts = Counts {
            vertices: self.vertex_count,
            triangles: self.triangle_count,
            min: self.min,
            max: self.max,
        };
        match self.format {
            Format::Glb => glb::write(out, &counts, &mut self.vertices, &mut self.indices),
            Format::Ply => ply::write(out, &counts, &mut self.vertices, &mut self.indices),
            Format::Obj => Err(std::io::Error::other("OBJ is written by ObjStream")),
        }?;
        out.flush()
    }
}

/// The `u32` index of the vertex after `count` written ones: both formats
/// index with `u32`, and `u32::MAX` is left unused (the "none yet" mark of
/// a patch's local map).
fn vertex_index(count: u64) -> std::io::Result<u32> {
    u32::try_from(count)
        .ok()
        .filter(|&i| i != u32::MAX)
        .ok_or_else(|| std::io::Error::other("more than 2^32 - 1 vertices in one mesh"))
}

/// What the headers need.
pub(crate) struct Counts {
    pub vertices: u64,
    pub triangles: u64,
    pub min: Vec3,
    pub max: Vec3,
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_vertex_index_limit_is_an_error() {
        assert_eq!(
            super::vertex_index(u32::MAX as u64 - 1).ok(),
            Some(u32::MAX - 1)
        );
        let e = super::vertex_index(u32::MAX as u64).expect_err("past the limit");
        assert_eq!(e.to_string(), "more than 2^32 - 1 vertices in one mesh");
        assert!(super::vertex_index(u64::MAX).is_err());
    }
}
