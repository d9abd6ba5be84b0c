//! Plain polygon meshes read from Wavefront OBJ files.
//!
//! A [`Mesh`] is the input of everything else in tessgen: positions, faces, the OBJ's vertex
//! normals (`vn`, with each face corner's normal index) and the OpenSubdiv `t` tag lines,
//! nothing more. The quad schemes ignore the normals (they derive normals from the limit
//! surface); the triangle schemes (PN, Phong; see [`crate::trimesh`]) interpolate them. Layout is flat (one position array, face vertex lists packed
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
/// used by [`crate::topology`]. Normals: all finite, `face_normals` as long as `face_vertices`
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
    /// is the `(k+1)`-th `vt` line. Read for displacement mapping ([`crate::displace`]).
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
    #[error("face {face} refers to vertex {index} (0-based), which does not exist")]
    FaceIndexOutOfRange {
        /// 0-based face index.
        face: usize,
        /// The 0-based vertex index asked for (OBJ index − 1, relative indices resolved);
        /// negative when an OBJ index was 0 or a relative index points before the first vertex.
        index: i64,
    },
    /// A face has fewer than 3 vertices.
    #[error("face {face} has only {arity} vertices")]
    DegenerateFace {
        /// 0-based face index.
        face: usize,
        /// Its number of vertices.
        arity: usize,
    },
    /// A face uses the same vertex more than once.
    #[error("face {face} uses vertex {vertex} more than once")]
    RepeatedVertex {
        /// 0-based face index.
        face: usize,
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
            Some(&scanned.position_lines),
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
    /// assembled by hand; [`crate::topology::Topology::build`] calls this first so that a broken
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
            check_face(f, self.face(f), self.positions.len(), &mut scratch)?;
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
    fn from_parts(
        positions: Vec<[f32; 3]>,
        position_lines: Option<&[usize]>,
        faces: &[Vec<i64>],
        tags: Vec<Tag>,
    ) -> Result<Mesh, MeshError> {
        if positions.is_empty() || faces.is_empty() {
            return Err(MeshError::Empty);
        }
        check_finite(&positions, position_lines)?;
        let total: usize = faces.iter().map(Vec::len).sum();
        check_sizes(positions.len(), total)?;
        let mut scratch = Vec::new();
        let mut face_offsets = Vec::with_capacity(faces.len() + 1);
        let mut face_vertices = Vec::with_capacity(total);
        face_offsets.push(0u32);
        for (f, face) in faces.iter().enumerate() {
            check_face(f, face, positions.len(), &mut scratch)?;
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
    indices: &[I],
    num_vertices: usize,
    scratch: &mut Vec<i64>,
) -> Result<(), MeshError> {
    if indices.len() < 3 {
        return Err(MeshError::DegenerateFace {
            face,
            arity: indices.len(),
        });
    }
    let nv = num_vertices as i64;
    if let Some(bad) = indices
        .iter()
        .map(|&i| i.into())
        .find(|&i| i < 0 || i >= nv)
    {
        return Err(MeshError::FaceIndexOutOfRange { face, index: bad });
    }
    scratch.clear();
    scratch.extend(indices.iter().map(|&i| i.into()));
    scratch.sort_unstable();
    if let Some(w) = scratch.windows(2).find(|w| w[0] == w[1]) {
        return Err(MeshError::RepeatedVertex {
            face,
            vertex: w[0] as u32,
        });
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// tobj

/// Runs `tobj` on the text. Materials are never loaded: a mesh has no use for them, and
/// `from_obj_str` must not open files named inside the string.
fn load_with_tobj(text: &str) -> tobj::LoadResult {
    // `..Default::default()` is redundant with tobj's default features, but tobj has
    // feature-gated fields (`merge_identical_points`, `reordering`) that another crate in the
    // build could switch on; this keeps the literal compiling in that case.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let mut reader = Cursor::new(text.as_bytes());
    tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
}

/// Proves that the scanner's file-order faces are what `tobj` read.
///
/// `tobj` numbers positions per model in order of first use; replaying that renumbering on the
/// file-order faces must give `tobj`'s index arrays exactly, and the positions behind each index
/// must agree. Faces are consumed model by model in file order.
fn cross_check(mesh: &Mesh, models: &[tobj::Model], face_lines: &[usize]) -> Result<(), MeshError> {
    let mut f = 0usize;
    let disagree = |f: usize, what: &str| MeshError::Obj {
        line: face_lines.get(f).copied(),
        message: format!("tobj and the line scanner disagree on face {f}: {what}"),
    };
    for model in models {
        let m = &model.mesh;
        // tobj leaves face_arities empty when every face of the model is a triangle.
        let arities: Vec<usize> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3]
        } else {
            m.face_arities.iter().map(|&a| a as usize).collect()
        };
        let mut first_use: HashMap<u32, u32> = HashMap::new();
        let mut cursor = 0usize;
        for arity in arities {
            if f >= mesh.num_faces() {
                return Err(disagree(f, "tobj has more faces"));
            }
            let face = mesh.face(f);
            if face.len() != arity {
                return Err(disagree(f, "number of vertices"));
            }
            for (c, &vertex) in face.iter().enumerate() {
                let next = first_use.len() as u32;
                let expected = *first_use.entry(vertex).or_insert(next);
                let got = m.indices.get(cursor + c).copied();
                if got != Some(expected) {
                    return Err(disagree(f, "vertex numbering"));
                }
                let t = expected as usize * 3;
                let ours = mesh.positions[vertex as usize];
                let same = m.positions.get(t..t + 3).is_some_and(|p| {
                    p.iter().zip(ours).all(|(&a, b)| {
                        let (a, b) = (f64::from(a), f64::from(b));
                        (a - b).abs() <= 1e-6 * a.abs().max(1.0)
                    })
                });
                if !same {
                    return Err(disagree(f, "vertex position"));
                }
            }
            cursor += arity;
            f += 1;
        }
        if cursor != m.indices.len() {
            return Err(disagree(f, "tobj has extra indices"));
        }
    }
    if f != mesh.num_faces() {
        return Err(disagree(f, "tobj has fewer faces"));
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// line scanner

struct Scanned {
    positions: Vec<[f32; 3]>,
    position_lines: Vec<usize>,
    /// 0-based resolved position indices, not yet range-checked.
    faces: Vec<Vec<i64>>,
    /// Parallel to `faces`: 1-based resolved normal index per corner, 0 = none. Range-checked
    /// by `scan_obj` before it returns.
    face_normals: Vec<Vec<i64>>,
    /// Parallel to `faces`: 1-based resolved `vt` index per corner, 0 = none (range-checked).
    face_texcoords: Vec<Vec<i64>>,
    texcoords: Vec<[f32; 2]>,
    texcoord_lines: Vec<usize>,
    normals: Vec<[f32; 3]>,
    normal_lines: Vec<usize>,
    face_lines: Vec<usize>,
    tags: Vec<Tag>,
}

/// Reads the `v`/`vt`/`vn`/`f`/`t` lines in the same way `tobj` does (same tokenising, same
/// `f32` parsing, `w` division, 1-based and relative indices resolved against the positions read
/// so far), keeping file order and line numbers.
fn scan_obj(text: &str) -> Result<Scanned, MeshError> {
    let mut s = Scanned {
        positions: Vec::new(),
        position_lines: Vec::new(),
        faces: Vec::new(),
        face_normals: Vec::new(),
        face_texcoords: Vec::new(),
        texcoords: Vec::new(),
        texcoord_lines: Vec::new(),
        normals: Vec::new(),
        normal_lines: Vec::new(),
        face_lines: Vec::new(),
        tags: Vec::new(),
    };
    let mut num_vt = 0usize;
    // (line, vt index, vn index) of every face corner that names them; checked at the end
    // because, like tobj, we allow references to elements defined later in the file.
    let mut attr_refs: Vec<(usize, i64, i64)> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let mut words = raw.split_whitespace();
        match words.next() {
            None | Some("#") => {}
            Some("v") => {
                let p = scan_vertex(line, words)?;
                s.positions.push(p);
                s.position_lines.push(line);
            }
            Some("vt") => {
                let t = scan_floats(line, words, 2, "texture coordinate")?;
                s.texcoords.push([t[0], t[1]]);
                s.texcoord_lines.push(line);
                num_vt += 1;
            }
            Some("vn") => {
                let n = scan_floats(line, words, 3, "normal")?;
                s.normals.push([n[0], n[1], n[2]]);
                s.normal_lines.push(line);
            }
            Some("f") => {
                let mut face = Vec::new();
                let mut normals = Vec::new();
                let mut tcs = Vec::new();
                for word in words {
                    let (v, vt, vn) =
                        scan_corner(line, word, s.positions.len(), num_vt, s.normals.len())?;
                    face.push(v);
                    normals.push(vn.unwrap_or(0));
                    tcs.push(vt.unwrap_or(0));
                    if vt.is_some() || vn.is_some() {
                        attr_refs.push((line, vt.unwrap_or(0), vn.unwrap_or(0)));
                    }
                }
                s.faces.push(face);
                s.face_normals.push(normals);
                s.face_texcoords.push(tcs);
                s.face_lines.push(line);
            }
            Some("l") => {
                return Err(obj_err(
                    line,
                    "polyline (`l`) elements are not supported in a surface mesh",
                ))
            }
            Some("t") => s.tags.push(scan_tag(line, words)?),
            Some("usemtl") if words.next().is_none() => {
                return Err(obj_err(line, "`usemtl` without a material name"))
            }
            Some(_) => {}
        }
    }
    let num_vn = s.normals.len();
    for (line, vt, vn) in attr_refs {
        if vt < 0 || vt as usize > num_vt {
            return Err(obj_err(line, "texture coordinate index out of range"));
        }
        if vn < 0 || vn as usize > num_vn {
            return Err(obj_err(line, "normal index out of range"));
        }
    }
    Ok(s)
}

fn parse_f32(line: usize, word: &str, what: &str) -> Result<f32, MeshError> {
    word.parse::<f32>()
        .map_err(|_| obj_err(line, format!("cannot parse {what} `{word}` as a number")))
}

/// `v x y z [w]` or `v x y z r g b` (colour ignored), as tobj accepts them.
fn scan_vertex<'a>(
    line: usize,
    mut words: impl Iterator<Item = &'a str>,
) -> Result<[f32; 3], MeshError> {
    let mut p = [0.0f32; 3];
    for c in &mut p {
        let w = words
            .next()
            .ok_or_else(|| obj_err(line, "a `v` line needs 3 coordinates"))?;
        *c = parse_f32(line, w, "coordinate")?;
    }
    let rest: Vec<&str> = words.collect();
    match rest.len() {
        0 | 3 => {}
        1 => {
            let w = parse_f32(line, rest[0], "homogeneous w")?;
            if w == 0.0 {
                return Err(obj_err(line, "homogeneous w is 0"));
            }
            for c in &mut p {
                *c /= w;
            }
        }
        n => {
            return Err(obj_err(
                line,
                format!("a `v` line has 3, 4 or 6 values, not {}", n + 3),
            ))
        }
    }
    Ok(p)
}

/// Parses the first `n` values of a `vt`/`vn` line (like tobj, further values are ignored).
fn scan_floats<'a>(
    line: usize,
    words: impl Iterator<Item = &'a str>,
    n: usize,
    what: &str,
) -> Result<Vec<f32>, MeshError> {
    let values = words
        .take(n)
        .map(|w| parse_f32(line, w, what))
        .collect::<Result<Vec<f32>, MeshError>>()?;
    if values.len() < n {
        return Err(obj_err(line, format!("a {what} needs {n} values")));
    }
    Ok(values)
}

/// One `f` token `v`, `v/vt`, `v//vn` or `v/vt/vn`. Returns the 0-based position index
/// (resolved, unchecked) and the 1-based vt/vn indices when present (relative ones resolved).
fn scan_corner(
    line: usize,
    word: &str,
    num_v: usize,
    num_vt: usize,
    num_vn: usize,
) -> Result<(i64, Option<i64>, Option<i64>), MeshError> {
    let parts: Vec<&str> = word.split('/').collect();
    if parts.len() > 3 {
        return Err(obj_err(line, format!("bad face vertex `{word}`")));
    }
    let number = |s: &str| -> Result<i64, MeshError> {
        s.parse::<i64>()
            .map_err(|_| obj_err(line, format!("bad face vertex `{word}`")))
    };
    // OBJ indices are 1-based; negative ones count back from the last element read so far.
    let resolve = |x: i64, count: usize| if x < 0 { count as i64 + x } else { x - 1 };
    if parts[0].is_empty() {
        return Err(obj_err(
            line,
            format!("face vertex `{word}` has no position index"),
        ));
    }
    let v = resolve(number(parts[0])?, num_v);
    let attr = |k: usize, count: usize| -> Result<Option<i64>, MeshError> {
        match parts.get(k) {
            Some(s) if !s.is_empty() => Ok(Some(resolve(number(s)?, count) + 1)),
            _ => Ok(None),
        }
    };
    let vt = attr(1, num_vt)?;
    let vn = attr(2, num_vn)?;
    if vt == Some(0) || vn == Some(0) {
        return Err(obj_err(line, format!("bad face vertex `{word}`")));
    }
    Ok((v, vt, vn))
}

/// `t <name> <nint>/<nfloat>/<nstring> <ints...> <floats...> <strings...>`.
fn scan_tag<'a>(line: usize, mut words: impl Iterator<Item = &'a str>) -> Result<Tag, MeshError> {
    let bad = |what: &str| obj_err(line, format!("malformed `t` tag line: {what}"));
    let name = words.next().ok_or_else(|| bad("no tag name"))?;
    let counts = words
        .next()
        .ok_or_else(|| bad("no <nint>/<nfloat>/<nstring> counts"))?;
    let counts: Vec<usize> = counts
        .split('/')
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|_| bad("counts must be <nint>/<nfloat>/<nstring>"))?;
    let [ni, nf, ns] = counts[..] else {
        return Err(bad("counts must be <nint>/<nfloat>/<nstring>"));
    };
    let args: Vec<&str> = words.collect();
    if args.len() != ni + nf + ns {
        return Err(bad(&format!(
            "{} arguments given, counts say {}",
            args.len(),
            ni + nf + ns
        )));
    }
    let ints = args[..ni]
        .iter()
        .map(|w| {
            w.parse::<i64>()
                .map_err(|_| bad(&format!("`{w}` is not an integer")))
        })
        .collect::<Result<_, _>>()?;
    let floats = args[ni..ni + nf]
        .iter()
        .map(|w| {
            w.parse::<f64>()
                .map_err(|_| bad(&format!("`{w}` is not a number")))
        })
        .collect::<Result<_, _>>()?;
    let strings = args[ni + nf..].iter().map(|w| w.to_string()).collect();
    Ok(Tag {
        name: name.to_string(),
        ints,
        floats,
        strings,
        line,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh_path(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../tests/data/meshes")
            .join(format!("{name}.obj"))
    }

    /// An independent, minimal reading of the `v` and `f` lines (plain `f a b c` syntax only).
    fn naive_v_f(text: &str) -> (Vec<[f32; 3]>, Vec<Vec<u32>>) {
        let mut v = Vec::new();
        let mut f = Vec::new();
        for l in text.lines() {
            let w: Vec<&str> = l.split_whitespace().collect();
            match w.first() {
                Some(&"v") => v.push([
                    w[1].parse().unwrap(),
                    w[2].parse().unwrap(),
                    w[3].parse().unwrap(),
                ]),
                Some(&"f") => f.push(
                    w[1..]
                        .iter()
                        .map(|s| s.split('/').next().unwrap().parse::<u32>().unwrap() - 1)
                        .collect(),
                ),
                _ => {}
            }
        }
        (v, f)
    }

    /// Vertices listed in an order no face follows, vertex 5 (0-based 4) unused, and faces whose
    /// first-use order differs from file order: exactly what tobj renumbers.
    const SCRAMBLED: &str = "\
# file order test
v 0.0 0.0 0.0
v 1.0 0.0 0.0
v 1.0 1.0 0.0
v 0.0 1.0 0.0
v 9.0 9.0 9.0
v 0.5 0.5 1.0
t corner 1/1/0 5 2.5
f 6 3 4
f 4 1 2 3
f 2/7/1 6 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vt 0.5 0.5
vt 0.2 0.2
vt 0.3 0.3
vn 0 0 1
";

    #[test]
    fn keeps_file_order_and_unused_vertices() {
        let mesh = Mesh::from_obj_str(SCRAMBLED).unwrap();
        let expected_positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [9.0, 9.0, 9.0],
            [0.5, 0.5, 1.0],
        ];
        assert_eq!(mesh.positions, expected_positions);
        assert_eq!(mesh.num_vertices(), 6);
        assert_eq!(mesh.num_faces(), 3);
        assert_eq!(mesh.face(0), &[5, 2, 3]);
        assert_eq!(mesh.face(1), &[3, 0, 1, 2]);
        assert_eq!(mesh.face(2), &[1, 5, 0]);
        assert_eq!(mesh.face_offsets, vec![0, 3, 7, 10]);
        assert_eq!(
            mesh.tags,
            vec![Tag {
                name: "corner".into(),
                ints: vec![5],
                floats: vec![2.5],
                strings: vec![],
                line: 8,
            }]
        );
    }

    /// Pins the finding that made the scanner necessary: tobj drops unused vertices and
    /// renumbers positions in order of first use.
    #[test]
    fn tobj_compacts_positions() {
        let (models, _) = load_with_tobj(SCRAMBLED).unwrap();
        assert_eq!(models.len(), 1);
        let m = &models[0].mesh;
        assert_eq!(m.positions.len(), 5 * 3, "unused vertex dropped");
        assert_eq!(&m.indices[..3], &[0, 1, 2], "first face renumbered 0,1,2");
        assert_eq!(
            &m.positions[..3],
            &[0.5, 0.5, 1.0],
            "tobj 0 is file vertex 5"
        );
    }

    #[test]
    fn groups_restart_tobj_numbering_but_not_ours() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ng a\nf 1 2 3\ng b\nusemtl x\nf 3 4 1\n";
        let mesh = Mesh::from_obj_str(text).unwrap();
        assert_eq!(mesh.face(0), &[0, 1, 2]);
        assert_eq!(mesh.face(1), &[2, 3, 0]);
    }

    #[test]
    fn relative_indices_and_w() {
        let text = "v 0 0 0\nv 2 0 0 2\nv 1 1 0\nf -3 -2 -1\n";
        let mesh = Mesh::from_obj_str(text).unwrap();
        assert_eq!(mesh.face(0), &[0, 1, 2]);
        assert_eq!(mesh.positions[1], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn real_meshes_match_a_naive_reading() {
        for name in [
            "catmark_cube",
            "catmark_torus",
            "catmark_righthanded",
            "catmark_car",
            "catmark_xord_interior",
        ] {
            let path = mesh_path(name);
            let text = std::fs::read_to_string(&path).unwrap();
            let mesh = Mesh::from_obj_path(&path).unwrap();
            let (v, f) = naive_v_f(&text);
            assert_eq!(mesh.positions, v, "{name}");
            assert_eq!(mesh.num_faces(), f.len(), "{name}");
            for (i, face) in f.iter().enumerate() {
                assert_eq!(mesh.face(i), &face[..], "{name} face {i}");
            }
            let tag_lines = text.lines().filter(|l| l.starts_with("t ")).count();
            assert_eq!(mesh.tags.len(), tag_lines, "{name}");
            mesh.validate().unwrap();
        }
    }

    #[test]
    fn tags_are_parsed() {
        let mesh = Mesh::from_obj_path(mesh_path("catmark_single_crease")).unwrap();
        let t = &mesh.tags[0];
        assert_eq!(t.name, "crease");
        assert_eq!(t.ints, vec![1, 22]);
        assert_eq!(t.floats, vec![10.0]);
        assert!(t.strings.is_empty());
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt name 0/0/2 a b\n";
        let mesh = Mesh::from_obj_str(text).unwrap();
        assert_eq!(mesh.tags[0].strings, vec!["a", "b"]);
        assert_eq!(mesh.tags[0].line, 5);
    }

    const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

    fn err(text: &str) -> MeshError {
        Mesh::from_obj_str(text).unwrap_err()
    }

    fn obj_line(e: MeshError) -> Option<usize> {
        match e {
            MeshError::Obj { line, .. } => line,
            other => panic!("expected Obj error, got {other:?}"),
        }
    }

    #[test]
    fn malformed_lines_are_located() {
        assert_eq!(
            obj_line(err("v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n")),
            Some(2)
        );
        assert_eq!(obj_line(err("v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")), Some(1));
        assert_eq!(obj_line(err(&format!("{TRI}f 1 2 a\n"))), Some(4));
        assert_eq!(obj_line(err(&format!("{TRI}f 1 2 3/1\n"))), Some(4));
        assert_eq!(obj_line(err(&format!("{TRI}f 1 2 3//1\n"))), Some(4));
        assert_eq!(
            obj_line(err(&format!("{TRI}f 1 2 3\nt crease 2/1/0 0 1\n"))),
            Some(5)
        );
        assert_eq!(
            obj_line(err(&format!("{TRI}f 1 2 3\nt crease 2/1 0 1 1\n"))),
            Some(5)
        );
        assert_eq!(
            obj_line(err(&format!("{TRI}f 1 2 3\nt crease 2/1/0 0 x 1\n"))),
            Some(5)
        );
        assert_eq!(obj_line(err(&format!("{TRI}f 1 2 3\nt\n"))), Some(5));
        assert_eq!(obj_line(err(&format!("{TRI}l 1 2 3\nf 1 2 3\n"))), Some(4));
        assert_eq!(
            obj_line(err("v 1 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")),
            Some(1)
        );
        assert_eq!(
            obj_line(err("v 0 0 0 # c\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")),
            Some(1)
        );
    }

    #[test]
    fn semantic_errors() {
        assert!(matches!(err("# nothing\n"), MeshError::Empty));
        assert!(matches!(err(TRI), MeshError::Empty));
        assert!(matches!(err("f 1 2 3\n"), MeshError::Empty));
        assert!(matches!(
            err("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
            MeshError::NonFinite {
                vertex: 1,
                line: Some(2)
            }
        ));
        assert!(matches!(
            err("v 0 0 0\nv 1 0 0\nv 0 1e50 0\nf 1 2 3\n"),
            MeshError::NonFinite {
                vertex: 2,
                line: Some(3)
            }
        ));
        assert!(matches!(
            err(&format!("{TRI}f 1 2 3\nf 1 2 4\n")),
            MeshError::FaceIndexOutOfRange { face: 1, index: 3 }
        ));
        assert!(matches!(
            err(&format!("{TRI}f 0 1 2\n")),
            MeshError::FaceIndexOutOfRange { face: 0, index: -1 }
        ));
        assert!(matches!(
            err(&format!("{TRI}f 1 2 -4\n")),
            MeshError::FaceIndexOutOfRange { face: 0, index: -1 }
        ));
        // tobj would silently drop these as "lines"/"points".
        assert!(matches!(
            err(&format!("{TRI}f 1 2 3\nf 1 2\n")),
            MeshError::DegenerateFace { face: 1, arity: 2 }
        ));
        assert!(matches!(
            err(&format!("{TRI}f 1\n")),
            MeshError::DegenerateFace { face: 0, arity: 1 }
        ));
        assert!(matches!(
            err(&format!("{TRI}f 1 2 3 2\n")),
            MeshError::RepeatedVertex { face: 0, vertex: 1 }
        ));
    }

    #[test]
    fn from_raw_checks() {
        let p = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let m = Mesh::from_raw(p.clone(), &[vec![0, 1, 2]]).unwrap();
        assert_eq!(m.face(0), &[0, 1, 2]);
        assert!(m.tags.is_empty());
        assert!(matches!(
            Mesh::from_raw(p.clone(), &[vec![0, 1, 3]]),
            Err(MeshError::FaceIndexOutOfRange { face: 0, index: 3 })
        ));
        assert!(matches!(
            Mesh::from_raw(p.clone(), &[vec![0, 1]]),
            Err(MeshError::DegenerateFace { face: 0, arity: 2 })
        ));
        assert!(matches!(
            Mesh::from_raw(p.clone(), &[vec![0, 1, 0]]),
            Err(MeshError::RepeatedVertex { face: 0, vertex: 0 })
        ));
        assert!(matches!(
            Mesh::from_raw(p.clone(), &[]),
            Err(MeshError::Empty)
        ));
        assert!(matches!(
            Mesh::from_raw(vec![[0.0, f32::INFINITY, 0.0]], &[vec![0, 0, 0]]),
            Err(MeshError::NonFinite {
                vertex: 0,
                line: None
            })
        ));
    }

    #[test]
    fn validate_catches_hand_built_layout() {
        let mut m = Mesh::from_raw(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[vec![0, 1, 2]],
        )
        .unwrap();
        m.face_offsets = vec![0, 4];
        assert!(matches!(m.validate(), Err(MeshError::Layout { .. })));
        m.face_offsets = vec![0, 3];
        m.face_vertices[2] = 7;
        assert!(matches!(
            m.validate(),
            Err(MeshError::FaceIndexOutOfRange { face: 0, index: 7 })
        ));
    }

    #[test]
    fn io_error_names_path() {
        let e = Mesh::from_obj_path("/nonexistent/dir/x.obj").unwrap_err();
        assert!(matches!(&e, MeshError::Io { path, .. } if path.ends_with("x.obj")));
        assert!(e.to_string().contains("/nonexistent/dir/x.obj"));
    }

    #[test]
    fn normals_are_kept_per_corner() {
        // Corners with and without normals, a relative normal index, a `v/vt/vn` corner and a
        // normal defined after the face that uses it (allowed, like tobj).
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvn 0 0 2\nvn 0 0 1\n\
                    f 1//1 2//-1 3\nf 2/1/3 4//2 3//1\nvn 0.5 0 1 7\n";
        let mesh = Mesh::from_obj_str(text).unwrap();
        assert_eq!(
            mesh.normals,
            vec![[0.0, 0.0, 2.0], [0.0, 0.0, 1.0], [0.5, 0.0, 1.0]]
        );
        assert_eq!(mesh.face_normals, vec![0, 1, NO_NORMAL, 2, 1, 0]);
        assert_eq!(mesh.corner_normal(2), None);
        assert_eq!(mesh.corner_normal(3), Some(2));
        assert!(mesh.has_normals());
        mesh.validate().unwrap();
    }

    #[test]
    fn unreferenced_normals_are_kept_but_no_corner_has_one() {
        let mesh = Mesh::from_obj_str(&format!("{TRI}vn 0 0 1\nf 1 2 3\n")).unwrap();
        assert_eq!(mesh.normals, vec![[0.0, 0.0, 1.0]]);
        assert_eq!(mesh.face_normals, vec![NO_NORMAL; 3]);
        assert!(!mesh.has_normals());
        assert_eq!(mesh.corner_normal(0), None);
        let raw = Mesh::from_raw(mesh.positions.clone(), &[vec![0, 1, 2]]).unwrap();
        assert!(raw.normals.is_empty());
        assert_eq!(raw.face_normals, vec![NO_NORMAL; 3]);
        let mut hand = raw.clone();
        hand.face_normals.clear();
        hand.validate().unwrap();
        assert_eq!(hand.corner_normal(1), None);
    }

    #[test]
    fn normal_errors_are_located() {
        assert!(matches!(
            err(&format!("{TRI}vn 0 0 1\nvn nan 0 1\nf 1//1 2//2 3//1\n")),
            MeshError::NonFiniteNormal {
                normal: 1,
                line: Some(5)
            }
        ));
        // Unused normals are checked too; 1e50 overflows f32 to inf.
        assert!(matches!(
            err(&format!("{TRI}vn 0 1e50 1\nf 1 2 3\n")),
            MeshError::NonFiniteNormal {
                normal: 0,
                line: Some(4)
            }
        ));
        assert!(matches!(
            err(&format!("{TRI}vn 0 inf 1\nf 1 2 3\n")),
            MeshError::NonFiniteNormal { normal: 0, .. }
        ));
        assert_eq!(obj_line(err(&format!("{TRI}vn 0 1\nf 1 2 3\n"))), Some(4));
        assert_eq!(
            obj_line(err(&format!("{TRI}vn 0 0 1\nf 1//1 2//2 3//1\n"))),
            Some(5)
        );
        assert_eq!(
            obj_line(err(&format!("{TRI}vn 0 0 1\nf 1//1 2//-2 3//1\n"))),
            Some(5)
        );
    }

    #[test]
    fn validate_checks_hand_built_normals() {
        let mut m = Mesh::from_raw(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[vec![0, 1, 2]],
        )
        .unwrap();
        m.normals = vec![[0.0, 0.0, 1.0]];
        m.face_normals = vec![0, NO_NORMAL, 0];
        m.validate().unwrap();
        m.face_normals = vec![0, 0];
        assert!(matches!(m.validate(), Err(MeshError::Layout { .. })));
        m.face_normals = vec![0, 0, 1];
        assert!(matches!(
            m.validate(),
            Err(MeshError::NormalIndexOutOfRange {
                face: 0,
                corner: 2,
                index: 1
            })
        ));
        m.face_normals = vec![0, 0, 0];
        m.normals = vec![[0.0, f32::NAN, 1.0]];
        assert!(matches!(
            m.validate(),
            Err(MeshError::NonFiniteNormal {
                normal: 0,
                line: None
            })
        ));
    }

    #[test]
    fn crlf_and_mtllib_are_harmless() {
        let text =
            "mtllib missing.mtl\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nusemtl red\r\nf 1 2 3\r\n";
        let mesh = Mesh::from_obj_str(text).unwrap();
        assert_eq!(mesh.face(0), &[0, 1, 2]);
    }
}
