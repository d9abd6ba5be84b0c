//! The OBJ line scanner and the cross-check against `tobj` (see the module
//! doc of [`crate::mesh`] for why both parsers read every file).

use super::*;

/// Runs `tobj` on the text. Materials are never loaded: a mesh has no use for them, and
/// `from_obj_str` must not open files named inside the string.
pub(super) fn load_with_tobj(text: &str) -> tobj::LoadResult {
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
pub(super) fn cross_check(
    mesh: &Mesh,
    models: &[tobj::Model],
    face_lines: &[usize],
) -> Result<(), MeshError> {
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

pub(super) struct Scanned {
    pub(super) positions: Vec<[f32; 3]>,
    pub(super) position_lines: Vec<usize>,
    /// 0-based resolved position indices, not yet range-checked.
    pub(super) faces: Vec<Vec<i64>>,
    /// Parallel to `faces`: 1-based resolved normal index per corner, 0 = none. Range-checked
    /// by `scan_obj` before it returns.
    pub(super) face_normals: Vec<Vec<i64>>,
    /// Parallel to `faces`: 1-based resolved `vt` index per corner, 0 = none (range-checked).
    pub(super) face_texcoords: Vec<Vec<i64>>,
    pub(super) texcoords: Vec<[f32; 2]>,
    pub(super) texcoord_lines: Vec<usize>,
    pub(super) normals: Vec<[f32; 3]>,
    pub(super) normal_lines: Vec<usize>,
    pub(super) face_lines: Vec<usize>,
    pub(super) tags: Vec<Tag>,
}

/// Reads the `v`/`vt`/`vn`/`f`/`t` lines in the same way `tobj` does (same tokenising, same
/// `f32` parsing, `w` division, 1-based and relative indices resolved against the positions read
/// so far), keeping file order and line numbers.
pub(super) fn scan_obj(text: &str) -> Result<Scanned, MeshError> {
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
