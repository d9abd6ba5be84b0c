//! Plain polygon meshes read from Wavefront OBJ files.
//!
//! A [`Mesh`] is the input of everything else in tessgen: positions, faces, the OBJ's vertex
//! normals (`vn`, with each face corner's normal index) and the OpenSubdiv `t` tag lines,
//! nothing more. The quad schemes ignore the normals (they derive normals from the limit
//! surface); the triangle schemes (PN, Phong; see [`crate::mesh::trimesh`]) interpolate them. Layout is flat (one position array, face vertex lists packed
//! behind an offset array) because the topology layer and the GPU upload both want flat arrays.
//!
//! # Indexing contract
//!
//! Vertex `i` of a mesh loaded from OBJ is the `(i+1)`-th `v` line of the file, faces are in file
//! order, and vertices that no face uses are kept. Ground-truth data (limit positions, tags) is
//! addressed by these file indices, so the loader must not renumber anything.
//!
//! # Why a second line scanner next to `tobj`
//!
//! The OBJ syntax itself is parsed by `tobj` (v4). But `tobj` does **not** keep file order:
//! in `export_faces_multi_index` (used with `single_index: false`) it copies a position into the
//! model the first time a face uses it, so its `positions` are compacted and renumbered in order
//! of first use, per model (every `o`/`g`/`usemtl` starts a new model and a new numbering), and
//! unused vertices are dropped. It also silently drops 1- and 2-vertex faces (`ignore_points`,
//! `ignore_lines`), treats `l` lines with 3+ vertices as faces, and reports errors without a line
//! number. So [`Mesh::from_obj_str`] also runs a small scanner over the `v`/`vt`/`vn`/`f`/`t`
//! lines. The scanner supplies the file-order indices, the normals and each corner's normal
//! index, the tags and line numbers for errors.
//! Only text that the scanner and the mesh checks accept is handed to `tobj` (its bounds checks
//! compute `index * 3 + 2` and can overflow on an OBJ index of 0), and its result is then
//! cross-checked against `tobj`'s per-model index arrays: replaying the first-use renumbering on
//! the file-order faces must reproduce `tobj`'s indices exactly, and the positions must agree.
//! So both parsers have to agree before a mesh is accepted. Normals are read by the scanner
//! alone (with the same `f32` parsing as `tobj`); `tobj`'s normal arrays are renumbered in the
//! same first-use way and would only repeat what the scanner's range checks already prove.

pub mod features;
pub mod refine;
pub mod sectors;
pub mod tags;
pub mod topology;
pub mod topology_error;
pub mod trimesh;

use std::collections::HashMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use thiserror::Error;

/// A polygon mesh in OBJ order.
///
/// Invariants (checked by every constructor and by [`Mesh::validate`]): at least one vertex and
/// one face, all coordinates finite, `face_offsets[0] == 0`, offsets non-decreasing with
/// `face_offsets[num_faces] == face_vertices.len()`, every face has at least 3 vertices, all
/// indices `< num_vertices`, no vertex twice in one face, and all counts fit the `u32` indices
/// used by [`crate::mesh::topology`]. Normals: all finite, `face_normals` as long as `face_vertices`
/// (or empty in a hand-built mesh), every entry [`NO_NORMAL`] or `< normals.len()`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// Vertex positions; index `i` is the `(i+1)`-th `v` line of the OBJ file.
    pub positions: Vec<[f32; 3]>,
    /// Face `f` uses `face_vertices[face_offsets[f]..face_offsets[f + 1]]`
    /// (length `num_faces + 1`). Doubles as the first half-edge id of each face.
    pub face_offsets: Vec<u32>,
    /// 0-based vertex indices of all faces, packed, each face in its file (ccw) order.
    pub face_vertices: Vec<u32>,
    /// OpenSubdiv `t` tag lines, in file order. Kept, not interpreted here.
    pub tags: Vec<Tag>,
    /// Vertex normals as written in the OBJ (not normalised); index `k` is the `(k+1)`-th `vn`
    /// line. Kept raw so that a consumer can tell a zero or non-unit normal from a good one.
    pub normals: Vec<[f32; 3]>,
    /// Parallel to [`Mesh::face_vertices`]: the 0-based index into [`Mesh::normals`] of each face
    /// corner (`f v//vn`), or [`NO_NORMAL`] for a corner written without one. Every constructor
    /// fills it (all [`NO_NORMAL`] from [`Mesh::from_raw`]); [`Mesh::validate`] also accepts it
    /// empty, meaning "no normals", so that meshes assembled by hand with
    /// `..Default::default()` stay valid. [`Mesh::corner_normal`] reads it either way.
    pub face_normals: Vec<u32>,
    /// Texture coordinates `(u, v)` as written in the OBJ (`vt`, first two values); index `k`
    /// is the `(k+1)`-th `vt` line. Read for displacement mapping ([`crate::cpu::displace`]).
    pub texcoords: Vec<[f32; 2]>,
    /// Parallel to [`Mesh::face_vertices`]: the 0-based [`Mesh::texcoords`] index of each face
    /// corner (`f v/vt`), or [`NO_NORMAL`] (the same marker) for a corner without one. May be
    /// empty (no texture coordinates).
    pub face_texcoords: Vec<u32>,
}

/// Marker in [`Mesh::face_normals`] for a face corner without a normal index.
pub const NO_NORMAL: u32 = u32::MAX;

/// One OpenSubdiv tag line: `t <name> <nint>/<nfloat>/<nstring> <ints> <floats> <strings>`.
///
/// Vertex indices inside tags are 0-based (OpenSubdiv's convention), i.e. they already match
/// [`Mesh`] vertex indices.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Tag {
    /// Tag name, e.g. `crease`, `corner`, `interpolateboundary`.
    pub name: String,
    /// The integer arguments.
    pub ints: Vec<i64>,
    /// The float arguments.
    pub floats: Vec<f64>,
    /// The string arguments.
    pub strings: Vec<String>,
    /// 1-based line number of the tag in the OBJ file (0 if the tag was not read from a file).
    pub line: usize,
}

/// Why a mesh could not be read or is not a valid polygon mesh.
///
/// Face and vertex numbers are 0-based (file order); `line` numbers are 1-based.
#[derive(Debug, Error)]
pub enum MeshError {
    /// The OBJ text is malformed (bad `v`/`f`/`t` syntax, unsupported element, or `tobj`
    /// rejected it).
    #[error("unreadable OBJ{}: {message}", at_line(*.line))]
    Obj {
        /// 1-based line of the offending element, when it could be located.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The file could not be read.
    #[error("cannot read {}: {source}", .path.display())]
    Io {
        /// The file that was asked for.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The mesh has no faces or no vertices.
    #[error("mesh has no faces or no vertices")]
    Empty,
    /// A vertex has a NaN or infinite coordinate.
    #[error("vertex {vertex}{} has a non-finite coordinate", at_line(*.line))]
    NonFinite {
        /// 0-based vertex index.
        vertex: usize,
        /// 1-based line of its `v` line, when read from OBJ.
        line: Option<usize>,
    },
    /// The mesh is too large for f32 evaluation (checked by the front door,
    /// [`crate::tessellate::Request::validate`]): unit normals are formed
    /// from squared lengths of cross products of derivatives, which are
    /// about the fourth power of the mesh's extent, and the stencil sums
    /// round at the scale of the largest coordinate. Past these bounds a
    /// normal silently becomes zero or NaN, so the mesh is refused instead.
    #[error(
        "vertex {vertex} at ({:e}, {:e}, {:e}) makes the mesh too large to evaluate in f32: {what} \
         is {value:e}, at most {max:e} is supported (squared derivative lengths would overflow \
         or round to nothing); scale or translate the mesh",
        position[0], position[1], position[2]
    )]
    TooLarge {
        /// 0-based vertex index: the one farthest out.
        vertex: usize,
        position: [f32; 3],
        /// Which bound: "the bounding box's largest side" or "its largest |coordinate|".
        what: &'static str,
        value: f32,
        max: f32,
    },
    /// A `vn` normal has a NaN or infinite component (unused normals included, for the same
    /// reason as positions: it is a sign of a broken file).
    #[error("normal {normal}{} has a non-finite component", at_line(*.line))]
    NonFiniteNormal {
        /// 0-based normal index.
        normal: usize,
        /// 1-based line of its `vn` line, when read from OBJ.
        line: Option<usize>,
    },
    /// A face corner refers to a normal that does not exist (hand-built meshes only: the OBJ
    /// reader reports such a file as [`MeshError::Obj`] with its line).
    #[error("face {face} corner {corner} refers to normal {index}, which does not exist")]
    NormalIndexOutOfRange {
        /// 0-based face index.
        face: usize,
        /// 0-based corner within the face.
        corner: usize,
        /// The 0-based normal index asked for.
        index: u32,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face}{} refers to vertex {index} (0-based), which does not exist", at_line(*.line))]
    FaceIndexOutOfRange {
        /// 0-based face index.
        face: usize,
        /// 1-based line of its `f` line, when read from OBJ.
        line: Option<usize>,
        /// The 0-based vertex index asked for (OBJ index − 1, relative indices resolved);
        /// negative when an OBJ index was 0 or a relative index points before the first vertex.
        index: i64,
    },
    /// A face has fewer than 3 vertices.
    #[error("face {face}{} has only {arity} vertices", at_line(*.line))]
    DegenerateFace {
        /// 0-based face index.
        face: usize,
        /// 1-based line of its `f` line, when read from OBJ.
        line: Option<usize>,
        /// Its number of vertices.
        arity: usize,
    },
    /// A face uses the same vertex more than once.
    #[error("face {face}{} uses vertex {vertex} more than once", at_line(*.line))]
    RepeatedVertex {
        /// 0-based face index.
        face: usize,
        /// 1-based line of its `f` line, when read from OBJ.
        line: Option<usize>,
        /// The repeated 0-based vertex index.
        vertex: u32,
    },
    /// The public arrays of a hand-built [`Mesh`] are inconsistent (offsets) or too large for
    /// `u32` indexing.
    #[error("inconsistent mesh layout: {message}")]
    Layout {
        /// What is inconsistent.
        message: String,
    },
}

fn at_line(line: Option<usize>) -> String {
    line.map(|l| format!(" (line {l})")).unwrap_or_default()
}

fn obj_err(line: usize, message: impl Into<String>) -> MeshError {
    MeshError::Obj {
        line: Some(line),
        message: message.into(),
    }
}

impl Mesh {
    /// Number of vertices, including vertices no face uses.
    pub fn num_vertices(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.face_offsets.len().saturating_sub(1)
    }

    /// The vertex indices of face `f` in file (ccw) order. Panics if `f >= num_faces()`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.face_vertices[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// The 0-based [`Mesh::normals`] index of half-edge / face corner `corner` (an index into
    /// [`Mesh::face_vertices`]), or `None` when it has none (also when `face_normals` is empty
    /// or shorter, so hand-built meshes without normals need not fill it).
    pub fn corner_normal(&self, corner: usize) -> Option<u32> {
        self.face_normals
            .get(corner)
            .copied()
            .filter(|&n| n != NO_NORMAL)
    }

    /// The texture coordinate of face corner `corner` (an index into [`Mesh::face_vertices`]),
    /// or `None` when it has none.
    pub fn corner_texcoord(&self, corner: usize) -> Option<[f32; 2]> {
        self.face_texcoords
            .get(corner)
            .copied()
            .filter(|&n| n != NO_NORMAL)
            .and_then(|n| self.texcoords.get(n as usize).copied())
    }

    /// Whether any face corner has a normal index. `vn` lines that no face uses do not count:
    /// they carry no per-vertex information.
    pub fn has_normals(&self) -> bool {
        self.face_normals.iter().any(|&n| n != NO_NORMAL)
    }

    /// Reads an OBJ file. See [`Mesh::from_obj_str`].
    pub fn from_obj_path(path: impl AsRef<Path>) -> Result<Mesh, MeshError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| MeshError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Mesh::from_obj_str(&text)
    }

    /// Parses OBJ text: `v`, `vn`, `f` (the position and normal indices of `v/vt/vn` are kept)
    /// and `t` lines; `vt` is checked but dropped; `o`, `g`, `s`, `usemtl`, `mtllib`, comments and
    /// unknown lines are ignored (material files are never opened); `l` lines are rejected.
    /// Vertex and face order is the file's (see the module docs for why `tobj` alone is not
    /// enough).
    pub fn from_obj_str(text: &str) -> Result<Mesh, MeshError> {
        // The scanner and the mesh checks run first, so that tobj only ever sees text whose
        // indices are known to be in range (tobj's own bounds checks compute `index * 3 + 2`
        // and can overflow on an index of 0).
        let scanned = scan_obj(text)?;
        let mesh = Mesh::from_parts(
            scanned.positions,
            Some((&scanned.position_lines, &scanned.face_lines)),
            &scanned.faces,
            scanned.tags,
        )?;
        check_finite_normals(&scanned.normals, Some(&scanned.normal_lines))?;
        // The scanner range-checked every normal index (1-based, 0 = none) against the `vn`
        // count, which `check_normal_count` bounds below u32::MAX.
        check_normal_count(scanned.normals.len())?;
        let face_normals = scanned
            .face_normals
            .iter()
            .flatten()
            .map(|&n| if n == 0 { NO_NORMAL } else { (n - 1) as u32 })
            .collect();
        if let Some(i) = scanned
            .texcoords
            .iter()
            .position(|t| !t.iter().all(|x| x.is_finite()))
        {
            return Err(obj_err(
                scanned.texcoord_lines[i],
                "texture coordinate is not finite",
            ));
        }
        // Range-checked by the scanner (1-based, 0 = none).
        let face_texcoords = scanned
            .face_texcoords
            .iter()
            .flatten()
            .map(|&n| if n == 0 { NO_NORMAL } else { (n - 1) as u32 })
            .collect();
        let mesh = Mesh {
            normals: scanned.normals,
            face_normals,
            texcoords: scanned.texcoords,
            face_texcoords,
            ..mesh
        };
        match load_with_tobj(text) {
            Err(e) => Err(MeshError::Obj {
                line: None,
                message: format!("tobj rejected the file: {e}"),
            }),
            Ok((models, _materials)) => {
                cross_check(&mesh, &models, &scanned.face_lines)?;
                Ok(mesh)
            }
        }
    }

    /// Builds a mesh from positions and per-face 0-based vertex lists (kept in the given order,
    /// no tags, no normals). Checks indices, arities, repeated vertices and finiteness.
    pub fn from_raw(positions: Vec<[f32; 3]>, faces: &[Vec<u32>]) -> Result<Mesh, MeshError> {
        let faces: Vec<Vec<i64>> = faces
            .iter()
            .map(|f| f.iter().map(|&i| i64::from(i)).collect())
            .collect();
        Mesh::from_parts(positions, None, &faces, Vec::new())
    }

    /// Re-checks all invariants listed on [`Mesh`]. The fields are public, so a mesh can be
    /// assembled by hand; [`crate::mesh::topology::Topology::build`] calls this first so that a broken
    /// mesh gives an error instead of an out-of-bounds panic.
    pub fn validate(&self) -> Result<(), MeshError> {
        let layout = |message: String| MeshError::Layout { message };
        if self.face_offsets.first() != Some(&0) {
            return Err(layout("face_offsets must start with 0".into()));
        }
        if let Some(f) = self.face_offsets.windows(2).position(|w| w[0] > w[1]) {
            return Err(layout(format!("face_offsets decrease at face {f}")));
        }
        let end = self.face_offsets.last().copied().unwrap_or(0) as usize;
        if end != self.face_vertices.len() {
            return Err(layout(format!(
                "face_offsets ends at {end} but face_vertices has {} entries",
                self.face_vertices.len()
            )));
        }
        check_sizes(self.positions.len(), self.face_vertices.len())?;
        if self.positions.is_empty() || self.num_faces() == 0 {
            return Err(MeshError::Empty);
        }
        check_finite(&self.positions, None)?;
        let mut scratch = Vec::new();
        for f in 0..self.num_faces() {
            check_face(f, None, self.face(f), self.positions.len(), &mut scratch)?;
        }
        self.validate_normals()
    }

    /// The normal part of [`Mesh::validate`].
    fn validate_normals(&self) -> Result<(), MeshError> {
        check_normal_count(self.normals.len())?;
        check_finite_normals(&self.normals, None)?;
        if self.face_normals.is_empty() {
            return Ok(());
        }
        if self.face_normals.len() != self.face_vertices.len() {
            return Err(MeshError::Layout {
                message: format!(
                    "face_normals has {} entries but face_vertices has {} (it must be empty or \
                     parallel)",
                    self.face_normals.len(),
                    self.face_vertices.len()
                ),
            });
        }
        for f in 0..self.num_faces() {
            let start = self.face_offsets[f] as usize;
            let end = self.face_offsets[f + 1] as usize;
            for (corner, &n) in self.face_normals[start..end].iter().enumerate() {
                if n != NO_NORMAL && n as usize >= self.normals.len() {
                    return Err(MeshError::NormalIndexOutOfRange {
                        face: f,
                        corner,
                        index: n,
                    });
                }
            }
        }
        Ok(())
    }

    /// Common constructor: checks everything, then packs the faces.
    /// `lines`: the 1-based OBJ lines of the `v` and the `f` lines, for errors.
    fn from_parts(
        positions: Vec<[f32; 3]>,
        lines: Option<(&[usize], &[usize])>,
        faces: &[Vec<i64>],
        tags: Vec<Tag>,
    ) -> Result<Mesh, MeshError> {
        if positions.is_empty() || faces.is_empty() {
            return Err(MeshError::Empty);
        }
        let (position_lines, face_lines) = lines.unzip();
        check_finite(&positions, position_lines)?;
        let total: usize = faces.iter().map(Vec::len).sum();
        check_sizes(positions.len(), total)?;
        let mut scratch = Vec::new();
        let mut face_offsets = Vec::with_capacity(faces.len() + 1);
        let mut face_vertices = Vec::with_capacity(total);
        face_offsets.push(0u32);
        for (f, face) in faces.iter().enumerate() {
            let line = face_lines.and_then(|l| l.get(f).copied());
            check_face(f, line, face, positions.len(), &mut scratch)?;
            // check_face proved 0 <= i < positions.len() <= u32::MAX.
            face_vertices.extend(face.iter().map(|&i| i as u32));
            // check_sizes proved the total fits in u32.
            face_offsets.push(face_vertices.len() as u32);
        }
        Ok(Mesh {
            positions,
            face_offsets,
            face_vertices,
            tags,
            normals: Vec::new(),
            face_normals: vec![NO_NORMAL; total],
            texcoords: Vec::new(),
            face_texcoords: Vec::new(),
        })
    }
}

/// Every flat array of the topology (half-edges, rings of `2n+1` entries per vertex) is indexed
/// by `u32`, with `u32::MAX` as the "none" marker; refuse meshes whose arrays could overflow that.
fn check_sizes(num_vertices: usize, num_face_vertices: usize) -> Result<(), MeshError> {
    let ring_entries = (num_face_vertices as u128) * 2 + num_vertices as u128;
    if ring_entries >= u128::from(u32::MAX) {
        return Err(MeshError::Layout {
            message: format!(
                "{num_vertices} vertices and {num_face_vertices} face corners are too many for u32 indices"
            ),
        });
    }
    Ok(())
}

/// Largest side of a mesh's bounding box that f32 evaluation supports
/// ([`MeshError::TooLarge`]): 2²⁴, about 1000× below where
/// `catmark_toroidal_tet` scaled up first gave zero normals (extent ≈ 2·10¹¹),
/// and where f32 has no fractional digits left anyway.
pub const MAX_EXTENT: f32 = 16_777_216.0;
/// Largest |coordinate| f32 evaluation supports: 2⁴⁰, where an ulp is 2¹⁷, so
/// the stencil sums' rounding noise stays far below [`MAX_EXTENT`].
pub const MAX_COORDINATE: f32 = 1_099_511_627_776.0;

impl Mesh {
    /// Refuses a mesh whose size would overflow f32 evaluation
    /// ([`MeshError::TooLarge`], naming the vertex farthest out): a bounding
    /// box side above [`MAX_EXTENT`] or a coordinate above
    /// [`MAX_COORDINATE`]. Every vertex counts, as for `check_finite`.
    pub fn check_magnitude(&self) -> Result<(), MeshError> {
        let p = &self.positions;
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for v in p {
            for c in 0..3 {
                lo[c] = lo[c].min(v[c]);
                hi[c] = hi[c].max(v[c]);
            }
        }
        let extent = (0..3).map(|c| hi[c] - lo[c]).fold(0.0f32, f32::max);
        let largest = p.iter().flatten().map(|c| c.abs()).fold(0.0f32, f32::max);
        let (what, value, max, far) = if extent > MAX_EXTENT {
            // Farthest from the per-axis median (an outlier does not move it).
            let mid: Vec<f64> = (0..3)
                .map(|c| {
                    let mut axis: Vec<f32> = p.iter().map(|v| v[c]).collect();
                    axis.sort_unstable_by(f32::total_cmp);
                    f64::from(axis.get(axis.len() / 2).copied().unwrap_or(0.0))
                })
                .collect();
            let dist = |v: &[f32; 3]| {
                (0..3)
                    .map(|c| (f64::from(v[c]) - mid[c]).abs())
                    .fold(0.0f64, f64::max)
            };
            let far = (0..p.len())
                .max_by(|&a, &b| dist(&p[a]).total_cmp(&dist(&p[b])))
                .unwrap_or(0);
            ("the bounding box's largest side", extent, MAX_EXTENT, far)
        } else if largest > MAX_COORDINATE {
            let far = (0..p.len())
                .max_by(|&a, &b| {
                    let m = |v: &[f32; 3]| v.iter().map(|c| c.abs()).fold(0.0f32, f32::max);
                    m(&p[a]).total_cmp(&m(&p[b]))
                })
                .unwrap_or(0);
            ("its largest |coordinate|", largest, MAX_COORDINATE, far)
        } else {
            return Ok(());
        };
        Err(MeshError::TooLarge {
            vertex: far,
            position: p.get(far).copied().unwrap_or_default(),
            what,
            value,
            max,
        })
    }
}

/// Rejects NaN/inf anywhere, unused vertices included: a non-finite value is a sign of a broken
/// file, and generated shaders would spread it over whole patches.
fn check_finite(positions: &[[f32; 3]], lines: Option<&[usize]>) -> Result<(), MeshError> {
    match positions
        .iter()
        .position(|p| p.iter().any(|c| !c.is_finite()))
    {
        Some(vertex) => Err(MeshError::NonFinite {
            vertex,
            line: lines.and_then(|l| l.get(vertex).copied()),
        }),
        None => Ok(()),
    }
}

/// Normal indices are stored as `u32` with [`NO_NORMAL`] (`u32::MAX`) as the "none" marker.
fn check_normal_count(num_normals: usize) -> Result<(), MeshError> {
    if num_normals as u128 >= u128::from(NO_NORMAL) {
        return Err(MeshError::Layout {
            message: format!("{num_normals} normals are too many for u32 indices"),
        });
    }
    Ok(())
}

/// Rejects NaN/inf in any normal, used or not (same reasoning as [`check_finite`]).
fn check_finite_normals(normals: &[[f32; 3]], lines: Option<&[usize]>) -> Result<(), MeshError> {
    match normals
        .iter()
        .position(|n| n.iter().any(|c| !c.is_finite()))
    {
        Some(normal) => Err(MeshError::NonFiniteNormal {
            normal,
            line: lines.and_then(|l| l.get(normal).copied()),
        }),
        None => Ok(()),
    }
}

/// Checks one face: arity, index range, repeated vertices (in that order).
fn check_face<I: Copy + Into<i64>>(
    face: usize,
    line: Option<usize>,
    indices: &[I],
    num_vertices: usize,
    scratch: &mut Vec<i64>,
) -> Result<(), MeshError> {
    if indices.len() < 3 {
        return Err(MeshError::DegenerateFace {
            face,
            line,
            arity: indices.len(),
        });
    }
    let nv = num_vertices as i64;
    if let Some(bad) = indices
        .iter()
        .map(|&i| i.into())
        .find(|&i| i < 0 || i >= nv)
    {
        return Err(MeshError::FaceIndexOutOfRange {
            face,
            line,
            index: bad,
        });
    }
    scratch.clear();
    scratch.extend(indices.iter().map(|&i| i.into()));
    scratch.sort_unstable();
    if let Some(w) = scratch.windows(2).find(|w| w[0] == w[1]) {
        return Err(MeshError::RepeatedVertex {
            face,
            line,
            vertex: w[0] as u32,
        });
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// tobj

mod obj;
use obj::*;

#[cfg(test)]
mod tests;
