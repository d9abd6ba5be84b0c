//! Sharp features of a subdivision mesh: boundary rule, edge and vertex sharpness, holes
//! (`docs/boundaries.md` §1).
//!
//! [`Features::from_mesh`] interprets a mesh's OpenSubdiv `t` lines; engines that do not read
//! OBJ build the same data with [`Features::new`] and the `with_*` methods and hand it to
//! [`crate::mesh::topology::Topology::build_with`], which checks it against the mesh
//! ([`Features::validate`]).
//!
//! Tag syntax (`shared/meshes/README.md`), with the pairing of `spec/verify/boundary_verify.py`:
//!
//! * `t crease n/1/0 v_0 … v_{n−1} s`: one sharpness for the chain of edges `v_0v_1, v_1v_2, …`
//!   (`n ≥ 2`);
//! * `t crease 2k/k/0 a_0 b_0 … a_{k−1} b_{k−1} s_0 … s_{k−1}` (`k ≥ 2`): one sharpness per pair;
//! * `t corner n/1/0 v… s` or `t corner n/n/0 v… s…`: vertex sharpness;
//! * `t hole n/0/0 f…`: hole faces (0-based);
//! * `t interpolateboundary 1/0/0 k`: 0 none, 1 edge-and-corner (default), 2 edge-only.
//!
//! Sharpness 0 means "not sharp" (it removes an earlier value of the same edge or vertex); a
//! later tag for the same edge or vertex overrides an earlier one. Sharpness in `(0, 10)`
//! (semi-sharp) is kept as given but *applied* as infinitely sharp, with a
//! [`FeatureWarning`]. Any other tag name is reported as [`FeatureWarning::IgnoredTag`].

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt;

use thiserror::Error;

use crate::mesh::{Mesh, Tag};

/// OpenSubdiv's `SHARPNESS_INFINITE`: sharpness at or above it is infinitely sharp.
pub const SHARPNESS_INFINITE: f32 = 10.0;

/// What happens at mesh boundaries (`t interpolateboundary`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum BoundaryRule {
    /// 0: boundary edges are not sharp; every face touching a boundary vertex has no limit
    /// surface and emits nothing.
    None,
    /// 1 (default, the USD default and the ground truth's choice): boundary edges sharp,
    /// one-face boundary vertices are corners.
    #[default]
    EdgeAndCorner,
    /// 2: boundary edges sharp, one-face boundary vertices are creases.
    EdgeOnly,
}

impl BoundaryRule {
    /// The rule of an `interpolateboundary` value (0, 1, 2).
    pub fn from_tag_value(k: i64) -> Option<BoundaryRule> {
        match k {
            0 => Some(BoundaryRule::None),
            1 => Some(BoundaryRule::EdgeAndCorner),
            2 => Some(BoundaryRule::EdgeOnly),
            _ => None,
        }
    }

    /// The `interpolateboundary` value of this rule.
    pub fn tag_value(self) -> u32 {
        match self {
            BoundaryRule::None => 0,
            BoundaryRule::EdgeAndCorner => 1,
            BoundaryRule::EdgeOnly => 2,
        }
    }

    /// Whether boundary edges count as sharp (rules 1 and 2).
    pub fn boundary_sharp(self) -> bool {
        self != BoundaryRule::None
    }
}

impl fmt::Display for BoundaryRule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BoundaryRule::None => "none (0)",
            BoundaryRule::EdgeAndCorner => "edge-and-corner (1)",
            BoundaryRule::EdgeOnly => "edge-only (2)",
        })
    }
}

/// Sharp features of one mesh. Vertex and face numbers are 0-based mesh indices.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Features {
    /// Boundary rule.
    pub boundary: BoundaryRule,
    /// Edge sharpness > 0, keyed by the unordered vertex pair `(min, max)`.
    pub edge_sharpness: BTreeMap<(u32, u32), f32>,
    /// Vertex sharpness > 0.
    pub vertex_sharpness: BTreeMap<u32, f32>,
    /// Hole faces: they emit no patch, their vertices still shape the neighbours.
    pub holes: BTreeSet<u32>,
}

/// Why a mesh's tags (or a hand-built [`Features`]) cannot be applied. `line` is the 1-based
/// OBJ line of the tag, or 0 for features that did not come from a file.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FeatureError {
    /// A tag names a vertex the mesh does not have.
    #[error("{}tag `{tag}` names vertex {vertex}, but the mesh has {num_vertices} vertices", at(*.line))]
    UnknownVertex {
        /// 1-based OBJ line (0: not from a file).
        line: usize,
        /// Tag name.
        tag: String,
        /// The vertex index as written (0-based).
        vertex: i64,
        /// Number of mesh vertices.
        num_vertices: usize,
    },
    /// A crease pair is not an edge of the mesh.
    #[error("{}crease {a}-{b} is not an edge of the mesh", at(*.line))]
    NotAnEdge {
        /// 1-based OBJ line (0: not from a file).
        line: usize,
        /// First vertex.
        a: u32,
        /// Second vertex.
        b: u32,
    },
    /// A sharpness is negative, NaN or infinite.
    #[error("{}tag `{tag}`: sharpness {value} must be finite and ≥ 0", at(*.line))]
    BadSharpness {
        /// 1-based OBJ line (0: not from a file).
        line: usize,
        /// Tag name.
        tag: String,
        /// The value.
        value: f64,
    },
    /// The numbers of ints, floats or strings do not fit the tag.
    #[error("{}tag `{tag}` has {ints} ints, {floats} floats and {strings} strings; expected {expected}", at(*.line))]
    WrongCounts {
        /// 1-based OBJ line (0: not from a file).
        line: usize,
        /// Tag name.
        tag: String,
        /// Ints given.
        ints: usize,
        /// Floats given.
        floats: usize,
        /// Strings given.
        strings: usize,
        /// What the tag needs, in words.
        expected: &'static str,
    },
    /// A hole names a face the mesh does not have.
    #[error("{}hole face {face} does not exist (the mesh has {num_faces} faces)", at(*.line))]
    HoleOutOfRange {
        /// 1-based OBJ line (0: not from a file).
        line: usize,
        /// The face index as written (0-based).
        face: i64,
        /// Number of faces.
        num_faces: usize,
    },
    /// `interpolateboundary` is not 0, 1 or 2.
    #[error("{}interpolateboundary {value} is not 0 (none), 1 (edge-and-corner) or 2 (edge-only)", at(*.line))]
    BadBoundaryRule {
        /// 1-based OBJ line (0: not from a file).
        line: usize,
        /// The value.
        value: i64,
    },
}

fn at(line: usize) -> String {
    if line == 0 {
        String::new()
    } else {
        format!("line {line}: ")
    }
}

/// Something in the tags that is not applied exactly; never silently dropped.
#[derive(Debug, Clone, PartialEq)]
pub enum FeatureWarning {
    /// A tag tessgen does not apply (unknown name, face-varying options, `smoothtriangles`, …).
    IgnoredTag {
        /// 1-based OBJ line.
        line: usize,
        /// Tag name.
        name: String,
    },
    /// Semi-sharp crease edges (0 < s < 10) on one tag line, applied as infinitely sharp.
    SemiSharpCrease {
        /// 1-based OBJ line.
        line: usize,
        /// Number of semi-sharp interior edges on that line.
        edges: usize,
        /// Their smallest sharpness.
        min: f32,
        /// Their largest sharpness.
        max: f32,
    },
    /// Semi-sharp corner vertices (0 < s < 10) on one tag line, applied as infinitely sharp.
    SemiSharpCorner {
        /// 1-based OBJ line.
        line: usize,
        /// Number of vertices.
        vertices: usize,
        /// Their smallest sharpness.
        min: f32,
        /// Their largest sharpness.
        max: f32,
    },
}

impl FeatureWarning {
    /// The 1-based OBJ line the warning is about.
    pub fn line(&self) -> usize {
        match self {
            FeatureWarning::IgnoredTag { line, .. }
            | FeatureWarning::SemiSharpCrease { line, .. }
            | FeatureWarning::SemiSharpCorner { line, .. } => *line,
        }
    }
}

fn range(min: f32, max: f32) -> String {
    if min == max {
        format!("{min}")
    } else {
        format!("{min}..{max}")
    }
}

impl fmt::Display for FeatureWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FeatureWarning::IgnoredTag { line, name } => {
                write!(f, "line {line}: tag `{name}` is not applied (ignored)")
            }
            FeatureWarning::SemiSharpCrease {
                line,
                edges,
                min,
                max,
            } => write!(
                f,
                "line {line}: {edges} semi-sharp crease edge{} (sharpness {}) approximated as \
                 infinitely sharp beyond the refinement steps taken (exact after ⌈s⌉ steps)",
                if *edges == 1 { "" } else { "s" },
                range(*min, *max)
            ),
            FeatureWarning::SemiSharpCorner {
                line,
                vertices,
                min,
                max,
            } => write!(
                f,
                "line {line}: {vertices} semi-sharp corner{} (sharpness {}) approximated as \
                 infinitely sharp beyond the refinement steps taken (exact after ⌈s⌉ steps)",
                if *vertices == 1 { "" } else { "s" },
                range(*min, *max)
            ),
        }
    }
}

/// Whether a sharpness is semi-sharp (applied as infinite with a warning).
pub fn is_semi_sharp(s: f32) -> bool {
    s > 0.0 && s < SHARPNESS_INFINITE
}

/// Undirected edges of a mesh → number of faces using them.
pub(crate) fn edge_faces(mesh: &Mesh) -> HashMap<(u32, u32), u32> {
    let mut edges = HashMap::with_capacity(mesh.face_vertices.len());
    for f in 0..mesh.num_faces() {
        let face = mesh.face(f);
        for (i, &a) in face.iter().enumerate() {
            let b = face[(i + 1) % face.len()];
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    edges
}

fn check_sharpness(line: usize, tag: &str, value: f64) -> Result<f32, FeatureError> {
    if !value.is_finite() || value < 0.0 || !(value as f32).is_finite() {
        return Err(FeatureError::BadSharpness {
            line,
            tag: tag.into(),
            value,
        });
    }
    Ok(value as f32)
}

fn check_vertex(line: usize, tag: &str, v: i64, nv: usize) -> Result<u32, FeatureError> {
    if v < 0 || v as u64 >= nv as u64 {
        return Err(FeatureError::UnknownVertex {
            line,
            tag: tag.into(),
            vertex: v,
            num_vertices: nv,
        });
    }
    Ok(v as u32)
}

fn wrong_counts(t: &Tag, expected: &'static str) -> FeatureError {
    FeatureError::WrongCounts {
        line: t.line,
        tag: t.name.clone(),
        ints: t.ints.len(),
        floats: t.floats.len(),
        strings: t.strings.len(),
        expected,
    }
}

/// Min and max of a non-empty list of sharpness values.
fn min_max(values: &[f32]) -> (f32, f32) {
    values
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &s| {
            (lo.min(s), hi.max(s))
        })
}

impl Features {
    /// No features: edge-and-corner boundaries, nothing sharp, no holes.
    pub fn new() -> Features {
        Features::default()
    }

    /// Sets the sharpness of edge `a`–`b` (either order); 0 removes it.
    pub fn with_crease(mut self, a: u32, b: u32, sharpness: f32) -> Features {
        self.set_crease(a, b, sharpness);
        self
    }

    /// Sets the sharpness of vertex `v`; 0 removes it.
    pub fn with_corner(mut self, v: u32, sharpness: f32) -> Features {
        self.set_corner(v, sharpness);
        self
    }

    /// Marks face `f` as a hole.
    pub fn with_hole(mut self, f: u32) -> Features {
        self.holes.insert(f);
        self
    }

    /// Sets the boundary rule.
    pub fn with_boundary(mut self, rule: BoundaryRule) -> Features {
        self.boundary = rule;
        self
    }

    /// In-place form of [`Features::with_crease`].
    pub fn set_crease(&mut self, a: u32, b: u32, sharpness: f32) {
        let key = (a.min(b), a.max(b));
        if sharpness == 0.0 {
            self.edge_sharpness.remove(&key);
        } else {
            self.edge_sharpness.insert(key, sharpness);
        }
    }

    /// In-place form of [`Features::with_corner`].
    pub fn set_corner(&mut self, v: u32, sharpness: f32) {
        if sharpness == 0.0 {
            self.vertex_sharpness.remove(&v);
        } else {
            self.vertex_sharpness.insert(v, sharpness);
        }
    }

    /// Sharpness of edge `a`–`b` (0 if none).
    pub fn edge(&self, a: u32, b: u32) -> f32 {
        self.edge_sharpness
            .get(&(a.min(b), a.max(b)))
            .copied()
            .unwrap_or(0.0)
    }

    /// Sharpness of vertex `v` (0 if none).
    pub fn vertex(&self, v: u32) -> f32 {
        self.vertex_sharpness.get(&v).copied().unwrap_or(0.0)
    }

    /// Checks hand-built features against a mesh: every vertex exists, every crease is a mesh
    /// edge, every sharpness finite and ≥ 0, every hole a face. Errors carry line 0.
    pub fn validate(&self, mesh: &Mesh) -> Result<(), FeatureError> {
        let nv = mesh.num_vertices();
        let edges = edge_faces(mesh);
        for (&(a, b), &s) in &self.edge_sharpness {
            check_vertex(0, "crease", i64::from(a), nv)?;
            check_vertex(0, "crease", i64::from(b), nv)?;
            if a == b || !edges.contains_key(&(a, b)) {
                return Err(FeatureError::NotAnEdge { line: 0, a, b });
            }
            check_sharpness(0, "crease", f64::from(s))?;
        }
        for (&v, &s) in &self.vertex_sharpness {
            check_vertex(0, "corner", i64::from(v), nv)?;
            check_sharpness(0, "corner", f64::from(s))?;
        }
        if let Some(&f) = self.holes.iter().find(|&&f| f as usize >= mesh.num_faces()) {
            return Err(FeatureError::HoleOutOfRange {
                line: 0,
                face: i64::from(f),
                num_faces: mesh.num_faces(),
            });
        }
        Ok(())
    }

    /// Interprets `mesh.tags` (see the module docs). The first bad tag is an error; tags that
    /// are not applied exactly give warnings, in file order.
    pub fn from_mesh(mesh: &Mesh) -> Result<(Features, Vec<FeatureWarning>), FeatureError> {
        let mut out = Features::new();
        let mut warnings = Vec::new();
        let nv = mesh.num_vertices();
        let nf = mesh.num_faces();
        let mut edges: Option<HashMap<(u32, u32), u32>> = None;
        for t in &mesh.tags {
            let line = t.line;
            let name = t.name.as_str();
            match name {
                "crease" => {
                    let (ni, nfl) = (t.ints.len(), t.floats.len());
                    const EXPECTED: &str = "n ≥ 2 ints and 1 float (a chain), or 2k ints and k \
                                            floats (pairs), no strings";
                    let pairs: Vec<(i64, i64, f64)> = if !t.strings.is_empty() || nfl == 0 {
                        return Err(wrong_counts(t, EXPECTED));
                    } else if nfl == 1 {
                        if ni < 2 {
                            return Err(wrong_counts(t, EXPECTED));
                        }
                        t.ints
                            .windows(2)
                            .map(|w| (w[0], w[1], t.floats[0]))
                            .collect()
                    } else {
                        if ni != 2 * nfl {
                            return Err(wrong_counts(t, EXPECTED));
                        }
                        t.ints
                            .chunks_exact(2)
                            .zip(&t.floats)
                            .map(|(c, &s)| (c[0], c[1], s))
                            .collect()
                    };
                    let edges = edges.get_or_insert_with(|| edge_faces(mesh));
                    let mut semi = Vec::new();
                    for (a, b, s) in pairs {
                        let a = check_vertex(line, name, a, nv)?;
                        let b = check_vertex(line, name, b, nv)?;
                        let key = (a.min(b), a.max(b));
                        let Some(&faces) = edges.get(&key).filter(|_| a != b) else {
                            return Err(FeatureError::NotAnEdge { line, a, b });
                        };
                        let s = check_sharpness(line, name, s)?;
                        // A boundary edge is sharp anyway (rules 1, 2): nothing is approximated.
                        if is_semi_sharp(s) && faces > 1 {
                            semi.push(s);
                        }
                        out.set_crease(a, b, s);
                    }
                    if !semi.is_empty() {
                        let (min, max) = min_max(&semi);
                        warnings.push(FeatureWarning::SemiSharpCrease {
                            line,
                            edges: semi.len(),
                            min,
                            max,
                        });
                    }
                }
                "corner" => {
                    let (ni, nfl) = (t.ints.len(), t.floats.len());
                    if ni == 0 || !t.strings.is_empty() || !(nfl == 1 || nfl == ni) {
                        return Err(wrong_counts(t, "n ≥ 1 ints and 1 or n floats, no strings"));
                    }
                    let mut semi = Vec::new();
                    for (i, &v) in t.ints.iter().enumerate() {
                        let v = check_vertex(line, name, v, nv)?;
                        let s =
                            check_sharpness(line, name, t.floats[if nfl == 1 { 0 } else { i }])?;
                        if is_semi_sharp(s) {
                            semi.push(s);
                        }
                        out.set_corner(v, s);
                    }
                    if !semi.is_empty() {
                        let (min, max) = min_max(&semi);
                        warnings.push(FeatureWarning::SemiSharpCorner {
                            line,
                            vertices: semi.len(),
                            min,
                            max,
                        });
                    }
                }
                "hole" => {
                    if t.ints.is_empty() || !t.floats.is_empty() || !t.strings.is_empty() {
                        return Err(wrong_counts(t, "n ≥ 1 ints (faces), no floats or strings"));
                    }
                    for &f in &t.ints {
                        if f < 0 || f as u64 >= nf as u64 {
                            return Err(FeatureError::HoleOutOfRange {
                                line,
                                face: f,
                                num_faces: nf,
                            });
                        }
                        out.holes.insert(f as u32);
                    }
                }
                "interpolateboundary" => {
                    if t.ints.len() != 1 || !t.floats.is_empty() || !t.strings.is_empty() {
                        return Err(wrong_counts(t, "1 int (0, 1 or 2), no floats or strings"));
                    }
                    let value = t.ints[0];
                    out.boundary = BoundaryRule::from_tag_value(value)
                        .ok_or(FeatureError::BadBoundaryRule { line, value })?;
                }
                _ => warnings.push(FeatureWarning::IgnoredTag {
                    line,
                    name: name.to_string(),
                }),
            }
        }
        Ok((out, warnings))
    }

    /// Number of edges with sharpness ≥ 10 and with `0 < s < 10`.
    pub fn crease_counts(&self) -> (usize, usize) {
        let semi = self
            .edge_sharpness
            .values()
            .filter(|&&s| is_semi_sharp(s))
            .count();
        (self.edge_sharpness.len() - semi, semi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2×2 grid of quads (9 vertices, 4 faces) followed by `tags`.
    fn grid(tags: &str) -> Mesh {
        let mut s = String::new();
        for j in 0..3 {
            for i in 0..3 {
                s += &format!("v {i} {j} 0\n");
            }
        }
        for j in 0..2 {
            for i in 0..2 {
                let v = |di: u32, dj: u32| (j + dj) * 3 + i + di + 1;
                s += &format!("f {} {} {} {}\n", v(0, 0), v(1, 0), v(1, 1), v(0, 1));
            }
        }
        // tag lines start at line 14
        s += tags;
        Mesh::from_obj_str(&s).unwrap()
    }

    fn err(tags: &str) -> FeatureError {
        Features::from_mesh(&grid(tags)).unwrap_err()
    }

    #[test]
    fn applies_tags() {
        let (f, w) = Features::from_mesh(&grid(
            "t crease 3/1/0 1 4 7 10\nt crease 4/2/0 3 4 4 5 10 0\nt corner 2/1/0 0 8 10\n\
             t hole 1/0/0 3\nt interpolateboundary 1/0/0 2\n",
        ))
        .unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(f.edge(4, 1), 10.0);
        assert_eq!(f.edge(7, 4), 10.0);
        assert_eq!(f.edge(3, 4), 10.0);
        assert_eq!(f.edge(4, 5), 0.0);
        assert_eq!(f.edge_sharpness.len(), 3);
        assert_eq!(f.vertex(8), 10.0);
        assert_eq!(f.vertex_sharpness.len(), 2);
        assert_eq!(f.holes, BTreeSet::from([3]));
        assert_eq!(f.boundary, BoundaryRule::EdgeOnly);
        assert_eq!(f.crease_counts(), (3, 0));
        // the builder gives the same
        let b = Features::new()
            .with_crease(1, 4, 10.0)
            .with_crease(4, 7, 10.0)
            .with_crease(4, 3, 10.0)
            .with_corner(0, 10.0)
            .with_corner(8, 10.0)
            .with_hole(3)
            .with_boundary(BoundaryRule::EdgeOnly);
        assert_eq!(b, f);
        assert_eq!(b.validate(&grid("")), Ok(()));
    }

    #[test]
    fn zero_removes_and_later_wins() {
        let (f, _) =
            Features::from_mesh(&grid("t crease 2/1/0 1 4 10\nt crease 2/1/0 4 1 0\n")).unwrap();
        assert!(f.edge_sharpness.is_empty());
        assert_eq!(Features::from_mesh(&grid("")).unwrap().0, Features::new());
    }

    #[test]
    fn warnings() {
        let (f, w) = Features::from_mesh(&grid(
            "t smoothtriangles 0/0/1 catmark\nt crease 4/2/0 1 4 4 7 2 10\nt crease 2/1/0 0 1 3\n\
             t corner 2/2/0 4 5 0.5 12\nt facevaryinginterpolateboundary 1/0/0 1\n",
        ))
        .unwrap();
        assert_eq!(
            w,
            vec![
                FeatureWarning::IgnoredTag {
                    line: 14,
                    name: "smoothtriangles".into()
                },
                FeatureWarning::SemiSharpCrease {
                    line: 15,
                    edges: 1,
                    min: 2.0,
                    max: 2.0
                },
                FeatureWarning::SemiSharpCorner {
                    line: 17,
                    vertices: 1,
                    min: 0.5,
                    max: 0.5
                },
                FeatureWarning::IgnoredTag {
                    line: 18,
                    name: "facevaryinginterpolateboundary".into()
                },
            ]
        );
        // 0-1 is a boundary edge: sharp anyway, no warning, but the value is kept
        assert_eq!(f.edge(0, 1), 3.0);
        assert_eq!(f.crease_counts(), (1, 2));
        let text: Vec<String> = w.iter().map(ToString::to_string).collect();
        assert!(text[0].contains("line 14") && text[0].contains("smoothtriangles"));
        assert!(
            text[1].contains("line 15") && text[1].contains("approximated as infinitely sharp")
        );
        assert!(
            text[2].contains("line 17") && text[2].contains("approximated as infinitely sharp")
        );
        assert_eq!(w[3].line(), 18);
    }

    #[test]
    fn errors() {
        assert_eq!(
            err("t crease 2/1/0 1 9 10\n"),
            FeatureError::UnknownVertex {
                line: 14,
                tag: "crease".into(),
                vertex: 9,
                num_vertices: 9
            }
        );
        assert!(matches!(
            err("\nt corner 1/1/0 -1 10\n"),
            FeatureError::UnknownVertex {
                line: 15,
                vertex: -1,
                ..
            }
        ));
        assert_eq!(
            err("t crease 2/1/0 0 4 10\n"),
            FeatureError::NotAnEdge {
                line: 14,
                a: 0,
                b: 4
            }
        );
        assert_eq!(
            err("t crease 2/1/0 4 4 10\n"),
            FeatureError::NotAnEdge {
                line: 14,
                a: 4,
                b: 4
            }
        );
        assert!(matches!(
            err("t crease 2/1/0 1 4 -1\n"),
            FeatureError::BadSharpness { line: 14, .. }
        ));
        assert!(matches!(
            err("t crease 2/1/0 1 4 nan\n"),
            FeatureError::BadSharpness { line: 14, .. }
        ));
        assert!(matches!(
            err("t corner 1/1/0 4 inf\n"),
            FeatureError::BadSharpness { line: 14, .. }
        ));
        for bad in [
            "t crease 1/1/0 1 10\n",
            "t crease 2/0/0 1 4\n",
            "t crease 3/2/0 1 4 7 10 10\n",
            "t corner 0/1/0 10\n",
            "t corner 3/2/0 0 1 2 10 10\n",
            "t hole 0/0/0\n",
            "t hole 1/1/0 0 1\n",
            "t interpolateboundary 2/0/0 1 1\n",
            "t interpolateboundary 0/1/0 1\n",
        ] {
            assert!(
                matches!(err(bad), FeatureError::WrongCounts { line: 14, .. }),
                "{bad}: {:?}",
                err(bad)
            );
        }
        assert_eq!(
            err("t hole 2/0/0 1 4\n"),
            FeatureError::HoleOutOfRange {
                line: 14,
                face: 4,
                num_faces: 4
            }
        );
        assert_eq!(
            err("t interpolateboundary 1/0/0 3\n"),
            FeatureError::BadBoundaryRule { line: 14, value: 3 }
        );
        let e = err("t interpolateboundary 1/0/0 3\n").to_string();
        assert!(e.starts_with("line 14:"), "{e}");
    }

    #[test]
    fn validate_hand_built() {
        let m = grid("");
        assert!(matches!(
            Features::new().with_crease(0, 4, 10.0).validate(&m),
            Err(FeatureError::NotAnEdge { line: 0, .. })
        ));
        assert!(matches!(
            Features::new().with_crease(0, 40, 10.0).validate(&m),
            Err(FeatureError::UnknownVertex { line: 0, .. })
        ));
        assert!(matches!(
            Features::new().with_crease(0, 1, f32::NAN).validate(&m),
            Err(FeatureError::BadSharpness { line: 0, .. })
        ));
        assert!(matches!(
            Features::new().with_corner(3, -2.0).validate(&m),
            Err(FeatureError::BadSharpness { line: 0, .. })
        ));
        assert!(matches!(
            Features::new().with_corner(30, 2.0).validate(&m),
            Err(FeatureError::UnknownVertex { line: 0, .. })
        ));
        assert!(matches!(
            Features::new().with_hole(4).validate(&m),
            Err(FeatureError::HoleOutOfRange { line: 0, .. })
        ));
        let e = Features::new().with_hole(4).validate(&m).unwrap_err();
        assert!(!e.to_string().contains("line"), "{e}");
    }
}
