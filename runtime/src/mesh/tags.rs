//! Scalar tags for the scalar-tagged PN scheme `stpn` (spec/pn.md §3): per
//! vertex a tension θ, sharpness σ, bias β and crease vector Δ, per triangle
//! corner the side sign that picks one of a crease vertex's two normals.
//!
//! OBJ has no place for them, so they come in a small text file beside the
//! mesh (`tessgen tessellate --scheme stpn --tags FILE`):
//!
//! ```text
//! # one `tag` line per tagged vertex; indices are 1-based like OBJ `v` lines,
//! # every key optional (default 0)
//! tag 12 sharpness 1 delta 0 1 0
//! tag 13 tension 0.3 bias 0.2 sharpness 0.8 delta 0 1 0
//! # optional: the side (+1 / -1) of OBJ face 7 (1-based, file order) at vertex 12
//! side 7 12 -1
//! ```
//!
//! Sides are decided per *sector*: the crease edges (both ends carry a Δ)
//! cut a crease vertex's triangle fan into two sectors, and every corner of
//! a sector must use the same side or the edges inside the sector open. The
//! default is the spec's geometric rule `sign(Δ · (centroid(T) − P))`
//! summed over each sector's triangles — per triangle it can flip on thin or
//! tilted triangles, per sector it is stable. A `side` line overrides one
//! corner (quads split into triangles keep their OBJ face's side); sides
//! that disagree inside one sector are an error naming the vertex and faces.
//!
//! The kernels read three flat arrays (OpenSubdiv-`Far` style plain data):
//! [`CreaseTags::tags`] (4 f32 per vertex: θ, σ, β, creased ∈ {0, 1}),
//! [`CreaseTags::crease`] (Δ per vertex) and [`CreaseTags::corner_side`]
//! (±1 at `3·triangle + corner`). `creased` is derived here from Δ ≠ 0 — the
//! spec's rule δ = 1 for an edge whose two ends both carry a crease vector —
//! so no file can make it disagree with Δ.

use glam::Vec3;

/// The arrays of a triangulation that tag resolution reads (see
/// `mesh::trimesh::TriMesh`, which builds one).
#[derive(Clone, Copy, Debug)]
pub struct Triangulation<'a> {
    pub positions: &'a [Vec3],
    pub triangles: &'a [[u32; 3]],
    /// OBJ face (0-based) of each triangle, for errors.
    pub source_face: &'a [u32],
}

/// Scalars per vertex in [`CreaseTags::tags`].
pub const TAGS_PER_VERTEX: usize = 4;

/// Tags of one vertex, as written in a tag file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexTag {
    /// θ: 0 = plain PN, 1 = the edge control points collapse onto the vertex.
    pub tension: f32,
    /// σ in [0, 1]: how far the side normals lean along Δ.
    pub sharpness: f32,
    /// β: tilts the crease curve's normal towards Δ.
    pub bias: f32,
    /// Δ: crease vector, perpendicular to the normal; zero = smooth vertex.
    pub delta: Vec3,
}

impl VertexTag {
    /// All tags neutral: plain PN at this vertex.
    pub const NEUTRAL: VertexTag = VertexTag {
        tension: 0.0,
        sharpness: 0.0,
        bias: 0.0,
        delta: Vec3::ZERO,
    };

    /// The vertex carries a non-null crease vector.
    pub fn is_crease(&self) -> bool {
        self.delta != Vec3::ZERO
    }
}

/// A parsed tag file: vertex tags and explicit sides, not yet tied to a
/// triangulation.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TagFile {
    /// `(0-based vertex, tags)`, in file order.
    pub vertices: Vec<(u32, VertexTag)>,
    /// `(0-based OBJ face, 0-based vertex, side)`, in file order.
    pub sides: Vec<(u32, u32, f32)>,
}

/// The flat per-vertex and per-corner arrays the `stpn` kernels read.
#[derive(Debug, Clone, PartialEq)]
pub struct CreaseTags {
    /// θ, σ, β, creased per vertex ([`TAGS_PER_VERTEX`] each).
    pub tags: Vec<f32>,
    /// Δ per vertex.
    pub crease: Vec<Vec3>,
    /// Side sign ±1 of corner i of triangle t at `3t + i`.
    pub corner_side: Vec<f32>,
}

/// Why a tag file or its tags were rejected. Lines are 1-based.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TagError {
    #[error("tags line {line}: {message}")]
    Syntax { line: usize, message: String },
    #[error("tags line {line}: vertex {vertex} does not exist (the mesh has {count} vertices)")]
    VertexOutOfRange {
        line: usize,
        vertex: u64,
        count: usize,
    },
    #[error("tags line {line}: face {face} does not exist (the mesh has {count} faces)")]
    FaceOutOfRange {
        line: usize,
        face: u64,
        count: usize,
    },
    #[error("tags line {line}: vertex {vertex} is not a corner of face {face}")]
    NotInFace { line: usize, face: u64, vertex: u64 },
    #[error("tags line {line}: vertex {vertex} is tagged twice (first on line {first})")]
    Duplicate {
        line: usize,
        vertex: u64,
        first: usize,
    },
    #[error("tags line {line}: {what} is not a finite number")]
    NotFinite { line: usize, what: &'static str },
    #[error("tags line {line}: sharpness {value} is outside [0, 1]")]
    SharpnessRange { line: usize, value: f32 },
    #[error("tags line {line}: side must be +1 or -1, found {value}")]
    BadSide { line: usize, value: String },
    #[error(
        "vertex {vertex} (1-based): faces {} and {} (1-based) lie in one sector of its crease (no \
         crease edge between them) but were given different sides; the edges between them would open",
        faces[0], faces[1]
    )]
    InconsistentSide { vertex: u64, faces: [u64; 2] },
    #[error(
        "face {face} (1-based): all three corners of one of its triangles carry a crease vector; \
         scalar-tagged PN allows at most two crease vertices per triangle (spec/pn.md §3)"
    )]
    ThreeCreaseCorners { face: u64 },
}

fn number(line: usize, what: &'static str, tok: Option<&str>) -> Result<f32, TagError> {
    let tok = tok.ok_or_else(|| TagError::Syntax {
        line,
        message: format!("`{what}` needs a number"),
    })?;
    let x: f32 = tok.parse().map_err(|_| TagError::Syntax {
        line,
        message: format!("`{tok}` is not a number ({what})"),
    })?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(TagError::NotFinite { line, what })
    }
}

fn index(line: usize, what: &str, tok: Option<&str>) -> Result<u64, TagError> {
    let tok = tok.ok_or_else(|| TagError::Syntax {
        line,
        message: format!("missing {what} index"),
    })?;
    match tok.parse::<u64>() {
        Ok(i) if i >= 1 => Ok(i),
        _ => Err(TagError::Syntax {
            line,
            message: format!("`{tok}` is not a 1-based {what} index"),
        }),
    }
}

impl TagFile {
    /// Parse a tag file for a mesh with `num_vertices` vertices and
    /// `num_faces` OBJ faces; `face_vertices(f)` lists face `f`'s vertices
    /// (0-based) so a `side` line naming a vertex outside its face is caught
    /// here, with its line.
    pub fn parse<'m>(
        text: &str,
        num_vertices: usize,
        num_faces: usize,
        face_vertices: impl Fn(usize) -> &'m [u32],
    ) -> Result<TagFile, TagError> {
        let mut file = TagFile::default();
        let mut seen = std::collections::HashMap::new();
        for (k, raw) in text.lines().enumerate() {
            let line = k + 1;
            let content = raw.split('#').next().unwrap_or("");
            let mut toks = content.split_whitespace();
            let Some(head) = toks.next() else { continue };
            match head {
                "tag" => {
                    let v = index(line, "vertex", toks.next())?;
                    if v as usize > num_vertices {
                        return Err(TagError::VertexOutOfRange {
                            line,
                            vertex: v,
                            count: num_vertices,
                        });
                    }
                    if let Some(first) = seen.insert(v, line) {
                        return Err(TagError::Duplicate {
                            line,
                            vertex: v,
                            first,
                        });
                    }
                    let mut tag = VertexTag::NEUTRAL;
                    while let Some(key) = toks.next() {
                        match key {
                            "tension" => tag.tension = number(line, "tension", toks.next())?,
                            "sharpness" => {
                                tag.sharpness = number(line, "sharpness", toks.next())?;
                                if !(0.0..=1.0).contains(&tag.sharpness) {
                                    return Err(TagError::SharpnessRange {
                                        line,
                                        value: tag.sharpness,
                                    });
                                }
                            }
                            "bias" => tag.bias = number(line, "bias", toks.next())?,
                            "delta" => {
                                let x = number(line, "delta", toks.next())?;
                                let y = number(line, "delta", toks.next())?;
                                let z = number(line, "delta", toks.next())?;
                                tag.delta = Vec3::new(x, y, z);
                            }
                            other => {
                                return Err(TagError::Syntax {
                                    line,
                                    message: format!(
                                        "unknown key `{other}` (tension, sharpness, bias, delta)"
                                    ),
                                })
                            }
                        }
                    }
                    file.vertices.push(((v - 1) as u32, tag));
                }
                "side" => {
                    let f = index(line, "face", toks.next())?;
                    let v = index(line, "vertex", toks.next())?;
                    let s = toks.next().unwrap_or("");
                    let side = match s {
                        "1" | "+1" => 1.0,
                        "-1" => -1.0,
                        _ => {
                            return Err(TagError::BadSide {
                                line,
                                value: s.to_string(),
                            })
                        }
                    };
                    if let Some(extra) = toks.next() {
                        return Err(TagError::Syntax {
                            line,
                            message: format!("unexpected `{extra}` after the side"),
                        });
                    }
                    if f as usize > num_faces {
                        return Err(TagError::FaceOutOfRange {
                            line,
                            face: f,
                            count: num_faces,
                        });
                    }
                    if !face_vertices((f - 1) as usize).contains(&((v - 1) as u32)) {
                        return Err(TagError::NotInFace {
                            line,
                            face: f,
                            vertex: v,
                        });
                    }
                    file.sides.push(((f - 1) as u32, (v - 1) as u32, side));
                }
                other => {
                    return Err(TagError::Syntax {
                        line,
                        message: format!("unknown statement `{other}` (tag, side)"),
                    })
                }
            }
        }
        Ok(file)
    }
}

impl CreaseTags {
    /// Neutral tags for every vertex and side +1 everywhere: `stpn` is then
    /// plain PN.
    pub fn neutral(num_vertices: usize, num_triangles: usize) -> CreaseTags {
        CreaseTags {
            tags: vec![0.0; num_vertices * TAGS_PER_VERTEX],
            crease: vec![Vec3::ZERO; num_vertices],
            corner_side: vec![1.0; num_triangles * 3],
        }
    }

    /// Tags of a triangulation from a parsed file: explicit sides where the
    /// file names them, the geometric default elsewhere. Takes the
    /// triangulation's arrays (a `TriMesh`'s `positions`, `triangles`,
    /// `source_face`) rather than the type, so the tag format does not depend
    /// on the mesh module that applies it.
    pub fn resolve(mesh: Triangulation<'_>, file: &TagFile) -> Result<CreaseTags, TagError> {
        let mut per_vertex = vec![VertexTag::NEUTRAL; mesh.positions.len()];
        for (v, t) in &file.vertices {
            per_vertex[*v as usize] = *t;
        }
        let explicit: std::collections::HashMap<(u32, u32), f32> =
            file.sides.iter().map(|(f, v, s)| ((*f, *v), *s)).collect();
        let mut out = CreaseTags::neutral(mesh.positions.len(), mesh.triangles.len());
        for (v, t) in per_vertex.iter().enumerate() {
            let flag = if t.is_crease() { 1.0 } else { 0.0 };
            out.tags[v * TAGS_PER_VERTEX..(v + 1) * TAGS_PER_VERTEX].copy_from_slice(&[
                t.tension,
                t.sharpness,
                t.bias,
                flag,
            ]);
            out.crease[v] = t.delta;
        }
        for (t, tri) in mesh.triangles.iter().enumerate() {
            if tri.iter().all(|&v| per_vertex[v as usize].is_crease()) {
                return Err(TagError::ThreeCreaseCorners {
                    face: mesh.source_face[t] as u64 + 1,
                });
            }
        }
        // Sectors: around a crease vertex, triangles joined by a non-crease
        // edge belong to one sector (the crease edges cut the fan). Every
        // corner of a sector must get the same side, or the sector's inner
        // edges would open; the sides are decided per sector, not per
        // triangle.
        let is_crease = |v: u32| per_vertex[v as usize].is_crease();
        let mut edge_triangle = std::collections::HashMap::new();
        let mut corners_of: Vec<Vec<(usize, usize)>> = vec![Vec::new(); mesh.positions.len()];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for i in 0..3 {
                edge_triangle.insert((tri[i], tri[(i + 1) % 3]), t);
                if is_crease(tri[i]) {
                    corners_of[tri[i] as usize].push((t, i));
                }
            }
        }
        for (v, corners) in corners_of.iter().enumerate() {
            if corners.is_empty() {
                continue;
            }
            let v = v as u32;
            let delta = per_vertex[v as usize].delta;
            let p = mesh.positions[v as usize];
            // Union-find over this vertex's corners.
            let slot: std::collections::HashMap<usize, usize> = corners
                .iter()
                .enumerate()
                .map(|(k, &(t, _))| (t, k))
                .collect();
            let mut parent: Vec<usize> = (0..corners.len()).collect();
            fn root(parent: &mut [usize], mut k: usize) -> usize {
                while parent[k] != k {
                    parent[k] = parent[parent[k]];
                    k = parent[k];
                }
                k
            }
            for (k, &(t, i)) in corners.iter().enumerate() {
                let w = mesh.triangles[t][(i + 1) % 3];
                if is_crease(w) {
                    continue;
                }
                // The triangle across edge v → w runs w → v.
                if let Some(other) = edge_triangle.get(&(w, v)).and_then(|o| slot.get(o)) {
                    let (a, b) = (root(&mut parent, k), root(&mut parent, *other));
                    parent[a] = b;
                }
            }
            let roots: Vec<usize> = (0..corners.len()).map(|k| root(&mut parent, k)).collect();
            let mut sectors: Vec<usize> = roots.clone();
            sectors.sort_unstable();
            sectors.dedup();
            // Score each sector by how far it lies along Δ (the spec's
            // geometric rule, summed over the sector's triangles).
            let score: Vec<f32> = sectors
                .iter()
                .map(|&r| {
                    corners
                        .iter()
                        .zip(&roots)
                        .filter(|(_, &rk)| rk == r)
                        .map(|(&(t, _), _)| {
                            let c = mesh.triangles[t]
                                .iter()
                                .map(|&u| mesh.positions[u as usize])
                                .sum::<Vec3>()
                                / 3.0;
                            delta.dot(c - p)
                        })
                        .sum()
                })
                .collect();
            let best = (0..sectors.len())
                .max_by(|&a, &b| score[a].total_cmp(&score[b]))
                .unwrap_or(0);
            let default_side = |k: usize| -> f32 {
                match sectors.len() {
                    // A crease through the vertex: the sector Δ points into is +.
                    2 => {
                        if sectors[best] == roots[k] {
                            1.0
                        } else {
                            -1.0
                        }
                    }
                    // A crease end (or an isolated crease vertex): one sector.
                    _ => {
                        let r = sectors.iter().position(|&s| s == roots[k]).unwrap_or(0);
                        if score[r] > 0.0 {
                            1.0
                        } else {
                            -1.0
                        }
                    }
                }
            };
            let mut sector_side: std::collections::HashMap<usize, (f32, u32)> =
                std::collections::HashMap::new();
            for (k, &(t, i)) in corners.iter().enumerate() {
                let face = mesh.source_face[t];
                let side = explicit
                    .get(&(face, v))
                    .copied()
                    .unwrap_or_else(|| default_side(k));
                if let Some(&(s0, f0)) = sector_side.get(&roots[k]) {
                    if s0 != side {
                        return Err(TagError::InconsistentSide {
                            vertex: v as u64 + 1,
                            faces: [f0 as u64 + 1, face as u64 + 1],
                        });
                    }
                } else {
                    sector_side.insert(roots[k], (side, face));
                }
                out.corner_side[3 * t + i] = side;
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<TagFile, TagError> {
        let faces: Vec<Vec<u32>> = vec![vec![0, 1, 2], vec![0, 2, 3]];
        TagFile::parse(text, 4, faces.len(), |f| &faces[f])
    }

    #[test]
    fn parses_tags_and_sides() {
        let f = parse(
            "# comment\n\ntag 1 sharpness 1 delta 0 1 0 # trailing\ntag 3 tension 0.3 bias 0.2\nside 2 1 -1\n",
        )
        .expect("valid");
        assert_eq!(f.vertices.len(), 2);
        assert_eq!(f.vertices[0].0, 0);
        assert_eq!(f.vertices[0].1.sharpness, 1.0);
        assert_eq!(f.vertices[0].1.delta, Vec3::Y);
        assert_eq!(f.vertices[1].1.tension, 0.3);
        assert_eq!(f.sides, vec![(1, 0, -1.0)]);
    }

    #[test]
    fn errors_name_the_line() {
        let cases: [(&str, TagError); 9] = [
            (
                "tag 9\n",
                TagError::VertexOutOfRange {
                    line: 1,
                    vertex: 9,
                    count: 4,
                },
            ),
            (
                "\ntag 0\n",
                TagError::Syntax {
                    line: 2,
                    message: "`0` is not a 1-based vertex index".into(),
                },
            ),
            (
                "tag 1 tension nan\n",
                TagError::NotFinite {
                    line: 1,
                    what: "tension",
                },
            ),
            (
                "tag 1 sharpness 2\n",
                TagError::SharpnessRange {
                    line: 1,
                    value: 2.0,
                },
            ),
            (
                "tag 1\ntag 1\n",
                TagError::Duplicate {
                    line: 2,
                    vertex: 1,
                    first: 1,
                },
            ),
            (
                "side 3 1 1\n",
                TagError::FaceOutOfRange {
                    line: 1,
                    face: 3,
                    count: 2,
                },
            ),
            (
                "side 1 4 1\n",
                TagError::NotInFace {
                    line: 1,
                    face: 1,
                    vertex: 4,
                },
            ),
            (
                "side 1 1 0\n",
                TagError::BadSide {
                    line: 1,
                    value: "0".into(),
                },
            ),
            (
                "tag 1 delta 0 1\n",
                TagError::Syntax {
                    line: 1,
                    message: "`delta` needs a number".into(),
                },
            ),
        ];
        for (text, want) in cases {
            assert_eq!(parse(text), Err(want), "{text:?}");
        }
        assert!(matches!(
            parse("crease 1 2\n"),
            Err(TagError::Syntax { line: 1, .. })
        ));
        assert!(matches!(
            parse("tag 1 weight 2\n"),
            Err(TagError::Syntax { line: 1, .. })
        ));
    }
}
