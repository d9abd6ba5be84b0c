//! Displacement mapping without cracks (spec/watertight.md Rules 4 and 5):
//! the data the generated `eval_displaced` reads, built once per mesh.
//!
//! * **Ownership**: every mesh edge and vertex is owned by the adjacent face
//!   with the lowest index. The tables hold, per quad, 8 records (triangles 6; edges
//!   0–3, corners 0–3) naming the owner patch's class, first control point,
//!   local edge/corner index and whether it runs the edge the other way; on
//!   the patch boundary `eval_displaced` takes the normal from `eval` of the
//!   owner at the owner's integer coordinates — one call, the same arguments
//!   from every patch of the edge, so the same bits. (We chose this over a
//!   boundary normal "from data identical on both sides": that would need a
//!   second, scheme-specific normal formula along every edge, while the
//!   owner's own formula is already in the Plan and is the surface's true
//!   normal there.)
//! * **Texture coordinates**: 16 `(s, t)` pairs per quad, 12 per triangle
//!   (Rule 5 layout, "3 + 6 + 3" for triangles): per corner k, [own
//!   coordinate, edge k's owner's coordinate of v_k, edge k−1's owner's
//!   coordinate of v_k, vertex v_k's owner's coordinate].
//! * **Triangles** ([`build_tri`]): the same tables over the triangles of a
//!   [`TriMesh`] (6 owner records per triangle: edges 0–2, corners 0–2),
//!   owned by the lowest triangle index; a triangle's coordinates are its
//!   source face's `vt` (split quads inherit their corners').
//! * **Map**: a scalar `R32Float` grid, row 0 at t = 0 (OBJ `vt` v = 0, the
//!   bottom of an image: [`DisplaceMap::from_png`] flips rows), texel centres
//!   at `(i + 0.5)/width`, clamped at the border.
//!
//! [`Ownership::PerPatch`] is the negative control: every patch uses its own
//! normal and its own coordinates on its edges, and the displaced surface
//! cracks along every texture seam.

use crate::mesh::topology::Topology;
use crate::mesh::trimesh::TriMesh;
use crate::mesh::Mesh;
use std::collections::HashMap;

/// Errors building displacement data.
#[derive(Debug, thiserror::Error)]
pub enum DisplaceError {
    #[error("face {face} corner {corner} has no texture coordinate (`f v/vt` needed on every corner to displace)")]
    MissingTexCoord { face: usize, corner: usize },
    #[error("displacement map {width}x{height}: {reason}")]
    BadMap {
        width: u32,
        height: u32,
        reason: &'static str,
    },
    #[error("displacement scale must be finite, got {0}")]
    Scale(f32),
    #[error("cannot read displacement map {path}: {message}")]
    Image { path: String, message: String },
}

/// A scalar displacement map, row-major, row 0 at texture coordinate t = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct DisplaceMap {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<f32>,
}

impl DisplaceMap {
    /// Checked constructor: non-empty, `width·height` finite texels, both
    /// sides within the 2-D texture limit every backend has (8192).
    pub fn new(width: u32, height: u32, texels: Vec<f32>) -> Result<Self, DisplaceError> {
        let bad = |reason| DisplaceError::BadMap {
            width,
            height,
            reason,
        };
        if width == 0 || height == 0 {
            return Err(bad("empty"));
        }
        if width > 8192 || height > 8192 {
            return Err(bad("larger than 8192 texels on a side"));
        }
        if texels.len() != (width as usize) * (height as usize) {
            return Err(bad("texel count is not width·height"));
        }
        if texels.iter().any(|x| !x.is_finite()) {
            return Err(bad("a texel is not finite"));
        }
        Ok(DisplaceMap {
            width,
            height,
            texels,
        })
    }

    /// A 1×1 zero map: what is bound while displacement is off.
    pub fn flat() -> Self {
        DisplaceMap {
            width: 1,
            height: 1,
            texels: vec![0.0],
        }
    }

    /// A procedural test map: `f(s, t)` at the texel centres.
    pub fn from_fn(width: u32, height: u32, f: impl Fn(f32, f32) -> f32) -> Self {
        let mut texels = Vec::with_capacity((width * height) as usize);
        for y in 0..height {
            for x in 0..width {
                texels.push(f(
                    (x as f32 + 0.5) / width as f32,
                    (y as f32 + 0.5) / height as f32,
                ));
            }
        }
        DisplaceMap {
            width,
            height,
            texels,
        }
    }

    /// A PNG (any bit depth/colour type the `image` crate reads) as heights
    /// in [0, 1] from its luminance; image rows are flipped so that the
    /// bottom row is t = 0, as OBJ texture coordinates expect.
    #[cfg(feature = "gpu")]
    pub fn from_png(path: &std::path::Path) -> Result<Self, DisplaceError> {
        let err = |message: String| DisplaceError::Image {
            path: path.display().to_string(),
            message,
        };
        let img = image::open(path)
            .map_err(|e| err(e.to_string()))?
            .into_luma16();
        let (w, h) = img.dimensions();
        let mut texels = Vec::with_capacity((w * h) as usize);
        for y in (0..h).rev() {
            for x in 0..w {
                texels.push(img.get_pixel(x, y).0[0] as f32 / 65535.0);
            }
        }
        DisplaceMap::new(w, h, texels)
    }
}

/// Who decides the normal and texture coordinate on shared edges/corners.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ownership {
    /// The lowest adjacent face index owns (Rules 4–5): watertight.
    LowestFace,
    /// Negative control: every patch its own normal and coordinates.
    PerPatch,
}

/// A displacement request: `p + scale · h(tc) · n`.
#[derive(Clone, Debug)]
pub struct Displacement {
    pub map: DisplaceMap,
    pub scale: f32,
    pub ownership: Ownership,
}

/// The per-mesh arrays `eval_displaced` reads (bindings 21–24).
#[derive(Clone, Debug, PartialEq)]
pub struct DisplaceData {
    /// 32 f32 per quad (16 `(s, t)` pairs), 24 per triangle.
    pub texcoords: Vec<f32>,
    /// 32 u32 per quad (8 records of 4), 24 per triangle.
    pub owners: Vec<u32>,
    /// `[scale, width, height, 0]`.
    pub info: [f32; 4],
    pub map: DisplaceMap,
}

impl DisplaceData {
    /// Displacement off: scale 0, so `eval_displaced` returns `eval`'s
    /// sample bit for bit and never reads the other arrays.
    pub fn off() -> Self {
        DisplaceData {
            texcoords: Vec::new(),
            owners: Vec::new(),
            info: [0.0, 1.0, 1.0, 0.0],
            map: DisplaceMap::flat(),
        }
    }
}

/// Per face and corner k: the faces and local indices that own edge k,
/// edge k−1 seen from v_k, and vertex v_k.
struct Owner {
    face: usize,
    /// Owner's local edge (edge slots) or corner (corner slots) index.
    k: usize,
    reversed: bool,
}

/// Edge and vertex owners of every face of `sides` corners (`vert(f, k)`,
/// k taken mod `sides`): `[edge 0..sides, corner 0..sides]`.
fn owner_table(
    nf: usize,
    sides: usize,
    vert: impl Fn(usize, usize) -> u32,
    ownership: Ownership,
) -> Vec<Vec<Owner>> {
    let vert = |f: usize, k: usize| vert(f, k % sides);
    // Undirected edge → (face, local edge) of every face using it.
    let mut edges: HashMap<(u32, u32), Vec<(usize, usize)>> = HashMap::new();
    // Vertex → lowest (face, corner).
    let mut vowner: HashMap<u32, (usize, usize)> = HashMap::new();
    for f in 0..nf {
        for k in 0..sides {
            let (a, b) = (vert(f, k), vert(f, k + 1));
            edges.entry((a.min(b), a.max(b))).or_default().push((f, k));
            vowner.entry(vert(f, k)).or_insert((f, k));
        }
    }
    (0..nf)
        .map(|f| {
            (0..2 * sides)
                .map(|slot| {
                    if ownership == Ownership::PerPatch {
                        return Owner {
                            face: f,
                            k: slot % sides,
                            reversed: false,
                        };
                    }
                    if slot < sides {
                        let (a, b) = (vert(f, slot), vert(f, slot + 1));
                        let (g, kg) = edges[&(a.min(b), a.max(b))]
                            .iter()
                            .copied()
                            .min()
                            .unwrap_or((f, slot));
                        Owner {
                            face: g,
                            k: kg,
                            reversed: g != f,
                        }
                    } else {
                        let (g, kg) = vowner[&vert(f, slot - sides)];
                        Owner {
                            face: g,
                            k: kg,
                            reversed: false,
                        }
                    }
                })
                .collect()
        })
        .collect()
}

/// The arrays for faces of `sides` corners: `uv(f, k)` is face f's own
/// texture coordinate at corner k (k < sides).
fn build_facets(
    nf: usize,
    sides: usize,
    vert: impl Fn(usize, usize) -> u32,
    uv: impl Fn(usize, usize) -> Result<[f32; 2], DisplaceError>,
    face_class: &[u32],
    face_cp_base: &[u32],
    d: &Displacement,
) -> Result<DisplaceData, DisplaceError> {
    if !d.scale.is_finite() {
        return Err(DisplaceError::Scale(d.scale));
    }
    let uv = |f: usize, k: usize| uv(f, k % sides);
    let table = owner_table(nf, sides, vert, d.ownership);
    let mut texcoords = Vec::with_capacity(nf * 8 * sides);
    let mut owners = Vec::with_capacity(nf * 8 * sides);
    for (f, own) in table.iter().enumerate() {
        for k in 0..sides {
            // [interior, edge k's owner at v_k, edge k−1's owner at v_k, vertex owner].
            let e = &own[k];
            let ep = &own[(k + sides - 1) % sides];
            let c = &own[sides + k];
            // The edge owner's corner at our v_k: its edge runs the other
            // way (our v_k is its v_{kg+1}) unless it is us.
            let at_vk_edge = if e.reversed { e.k + 1 } else { e.k };
            let at_vk_prev = if ep.reversed { ep.k } else { ep.k + 1 };
            for p in [
                uv(f, k)?,
                uv(e.face, at_vk_edge)?,
                uv(ep.face, at_vk_prev)?,
                uv(c.face, c.k)?,
            ] {
                texcoords.extend_from_slice(&p);
            }
        }
        for o in own {
            owners.extend_from_slice(&[
                face_class[o.face],
                face_cp_base[o.face],
                o.k as u32,
                o.reversed as u32,
            ]);
        }
    }
    Ok(DisplaceData {
        texcoords,
        owners,
        info: [d.scale, d.map.width as f32, d.map.height as f32, 0.0],
        map: d.map.clone(),
    })
}

/// Build the arrays for `mesh` (whose faces `topo` was built from), with the
/// patches' classes and first control points in the layout of the backend
/// that will evaluate them (CPU: face order; GPU: sorted by class).
pub fn build(
    mesh: &Mesh,
    topo: &Topology,
    face_class: &[u32],
    face_cp_base: &[u32],
    d: &Displacement,
) -> Result<DisplaceData, DisplaceError> {
    build_facets(
        topo.corners.len(),
        4,
        |f, k| topo.corners[f][k].vertex,
        |f, k| {
            let c = mesh.face_offsets[f] as usize + k;
            mesh.corner_texcoord(c)
                .ok_or(DisplaceError::MissingTexCoord { face: f, corner: k })
        },
        face_class,
        face_cp_base,
        d,
    )
}

/// [`build`] for a triangle scheme: 12 texture coordinates and 6 owner
/// records per triangle of `tri`, owners by the lowest *triangle* index.
/// A triangle's coordinates are its source face's `vt` at the same vertex
/// (a split quad's two triangles inherit their corners' coordinates), so
/// `mesh` must be the mesh `tri` was made from. A missing `vt` is reported
/// at the source face and its corner in file order.
pub fn build_tri(
    mesh: &Mesh,
    tri: &TriMesh,
    face_class: &[u32],
    face_cp_base: &[u32],
    d: &Displacement,
) -> Result<DisplaceData, DisplaceError> {
    build_facets(
        tri.triangles.len(),
        3,
        |f, k| tri.triangles[f][k],
        |f, k| {
            let src = tri.source_face[f] as usize;
            let v = tri.triangles[f][k];
            let corner = mesh.face(src).iter().position(|&x| x == v).unwrap_or(k);
            let c = mesh.face_offsets[src] as usize + corner;
            mesh.corner_texcoord(c)
                .ok_or(DisplaceError::MissingTexCoord { face: src, corner })
        },
        face_class,
        face_cp_base,
        d,
    )
}
