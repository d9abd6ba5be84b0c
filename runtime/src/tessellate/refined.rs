//! The front door's refinement path (docs/boundaries.md §8): meshes with
//! triangles or n-gons, or with semi-sharp creases, run on their uniformly
//! refined all-quad mesh ([`crate::mesh::refine`]) and come back in the
//! base mesh's layout.
//!
//! How many steps: one for non-quads; `⌈s⌉` for semi-sharp creases, capped
//! by [`super::Request::crease_refinement`], and at a uniform level `N` by
//! the power of two in `N` (a base quad's `(N+1)²` grid is read off its
//! `2ᵏ × 2ᵏ` refined faces at level `N / 2ᵏ`, so `2ᵏ` must divide `N`).
//! Adaptive requests take no crease steps (their output stays per base
//! patch; a mesh with non-quads runs on its one-step refinement, one patch
//! per refined face). Whatever sharpness is left after the last step is
//! applied as infinitely sharp and said so in [`RefinedDomain::notes`].
//!
//! Why the output stays watertight: every refined face is evaluated by the
//! unchanged backends at level `M = N / 2ᵏ`, and shared refined edges come
//! out bit-identical ([`crate::check::weld`]'s contract); assembling a base
//! grid only copies samples, taking each from the leaf it falls in.

use crate::cpu::Tessellation;
use crate::mesh::features::{FeatureWarning, Features};
use crate::mesh::refine::{self, Need, Refinement};
use glam::Vec3;

pub use crate::mesh::refine::DEFAULT_CREASE_REFINEMENT;

/// A refined mesh as a backend runs it, and how to map the result back.
#[derive(Debug)]
pub struct RefinedDomain {
    pub refinement: Refinement,
    /// What the base mesh needed.
    pub need: Need,
    /// The uniform level of the refined faces (`N / 2ᵏ`; 0 when adaptive).
    pub leaf_level: u32,
    /// What the refinement does and approximates, then the tag warnings
    /// that still hold.
    pub notes: Vec<String>,
}

/// Why a request cannot be refined as asked.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RefineError {
    #[error(
        "the mesh has {non_quads} faces that are not quads (first: face {face}, {arity} sides): \
         they are tessellated as their quad sub-faces after one Catmull-Clark step, each sub-face \
         covering half of each base edge, so the level must be even (got {level}; try {} or {})",
        level - 1, level + 1
    )]
    OddLevel {
        level: u32,
        non_quads: usize,
        face: usize,
        arity: usize,
    },
}

/// `(steps, crease steps)` to apply for `need` at uniform `level`
/// (`None`: adaptive).
pub fn choose_levels(need: &Need, level: Option<u32>, crease_cap: u32) -> (u32, u32) {
    let polygons = u32::from(need.non_quads > 0);
    // Adaptive runs keep their per-base-patch output: creases as sharp.
    let creases = match level {
        Some(n) => need.crease_levels().min(crease_cap).min(n.trailing_zeros()),
        None => 0,
    };
    let steps = creases
        .max(polygons)
        .min(crate::mesh::refine::MAX_REFINE_LEVELS);
    (steps, creases)
}

impl RefinedDomain {
    /// Builds the refinement for `mesh` if it needs one (`Ok(None)` if not).
    pub fn for_mesh(
        mesh: &crate::mesh::Mesh,
        features: &Features,
        warnings: &[FeatureWarning],
        level: Option<u32>,
        crease_cap: u32,
        max_valence: u32,
    ) -> Result<Option<RefinedDomain>, super::Error> {
        let need = refine::need(mesh, features);
        if need.levels() == 0 {
            return Ok(None);
        }
        if let (Some(n), true) = (level, need.non_quads > 0) {
            if n % 2 == 1 {
                let face = (0..mesh.num_faces())
                    .find(|&f| mesh.face(f).len() != 4)
                    .unwrap_or(0);
                return Err(RefineError::OddLevel {
                    level: n,
                    non_quads: need.non_quads,
                    face,
                    arity: mesh.face(face).len(),
                }
                .into());
            }
        }
        let (steps, creases) = choose_levels(&need, level, crease_cap);
        if steps == 0 {
            return Ok(None);
        }
        let refinement = refine::refine(mesh, features, steps, max_valence)
            .map_err(crate::cpu::TessError::from)?;
        let resolved = creases >= need.crease_levels();
        // What the refinement does first, then the tag warnings that still hold.
        let mut notes: Vec<String> = Vec::new();
        let tag_notes: Vec<String> = warnings
            .iter()
            .filter(|w| {
                !(resolved
                    && matches!(
                        w,
                        FeatureWarning::SemiSharpCrease { .. }
                            | FeatureWarning::SemiSharpCorner { .. }
                    ))
            })
            .map(|w| w.to_string())
            .collect();
        if need.non_quads > 0 {
            notes.push(format!(
                "{} non-quad faces: tessellated as their quad sub-faces after one Catmull-Clark step \
                 ({})",
                need.non_quads,
                level.map_or("one adaptive patch per refined face".to_string(), |n| format!(
                    "one grid per sub-face at level {}",
                    n / 2
                ))
            ));
        }
        let by_level =
            level.is_some_and(|n| n.trailing_zeros() < need.crease_levels().min(crease_cap));
        if need.max_semi_sharpness > 0.0 {
            notes.push(if resolved {
                format!(
                    "semi-sharp creases (sharpness up to {}) applied exactly by {} Catmull-Clark steps \
                     ({}× the patches)",
                    need.max_semi_sharpness,
                    steps,
                    1u64 << (2 * steps)
                )
            } else {
                format!(
                    "semi-sharp creases (sharpness up to {}) need {} Catmull-Clark steps; {} applied \
                     ({}), the remaining sharpness is applied as infinitely sharp",
                    need.max_semi_sharpness,
                    need.crease_levels(),
                    creases,
                    if level.is_none() {
                        "adaptive tessellation takes no crease steps"
                    } else if by_level {
                        "a level divisible by a higher power of two allows more"
                    } else {
                        "the crease refinement cap"
                    }
                )
            });
        }
        notes.extend(tag_notes);
        Ok(Some(RefinedDomain {
            leaf_level: level.map_or(0, |n| n >> steps),
            refinement,
            need,
            notes,
        }))
    }

    /// The base face a refined face comes from.
    pub fn base_face(&self, refined_face: usize) -> usize {
        let r = &self.refinement;
        r.leaves
            .get(refined_face)
            .and_then(|l| r.blocks.get(l.block as usize))
            .map_or(refined_face, |b| b.face as usize)
    }

    /// The refined result of a uniform run (`t`: one grid per refined face
    /// at [`RefinedDomain::leaf_level`]) in the base layout: base quads as
    /// one `(N+1)²` grid each, n-gons as their sub-faces at `N/2`; blocks
    /// whose faces have no limit (holes) are left out.
    pub fn assemble(&self, t: &Tessellation, no_limit: &[bool]) -> super::Output {
        let r = &self.refinement;
        let m = self.leaf_level as usize;
        // Leaf faces of every block, row-major.
        let mut leaf_faces: Vec<Vec<u32>> = r
            .blocks
            .iter()
            .map(|b| vec![u32::MAX; 1 << (2 * b.depth)])
            .collect();
        for (f, l) in r.leaves.iter().enumerate() {
            let side = 1usize << r.blocks[l.block as usize].depth;
            leaf_faces[l.block as usize][l.y as usize * side + l.x as usize] = f as u32;
        }
        let mut quads = GridBuilder::default();
        let mut subfaces = GridBuilder::default();
        let mut corners = Vec::new();
        let per_leaf = (m + 1) * (m + 1);
        for (b, block) in r.blocks.iter().enumerate() {
            let faces = &leaf_faces[b];
            if faces
                .iter()
                .all(|&f| no_limit.get(f as usize).copied().unwrap_or(true))
            {
                continue;
            }
            let side = 1usize << block.depth;
            let level = m * side;
            let out = if block.corner.is_some() {
                corners.push(block.corner.unwrap_or(0));
                &mut subfaces
            } else {
                &mut quads
            };
            out.level = level as u32;
            out.ids.push(block.face);
            for j in 0..=level {
                let (y, lj) = leaf_coord(j, m, side);
                for i in 0..=level {
                    let (x, li) = leaf_coord(i, m, side);
                    let leaf = faces[y * side + x] as usize;
                    let s = leaf * per_leaf + lj * (m + 1) + li;
                    out.positions.push(t.positions[s]);
                    out.normals.push(t.normals[s]);
                }
            }
        }
        let quads = quads.finish();
        if corners.is_empty() {
            return super::Output::Grid(quads);
        }
        super::Output::Polygons(PolygonGrids {
            quads,
            subfaces: subfaces.finish(),
            corners,
            boundary_open_edges: 0,
        })
    }
}

/// Leaf and local index of grid line `i` of a block `side` leaves wide.
fn leaf_coord(i: usize, m: usize, side: usize) -> (usize, usize) {
    let x = (i / m.max(1)).min(side - 1);
    (x, i - x * m)
}

#[derive(Default)]
struct GridBuilder {
    level: u32,
    ids: Vec<u32>,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
}

impl GridBuilder {
    fn finish(self) -> Tessellation {
        Tessellation {
            level: self.level,
            faces: self.ids.len(),
            sides: 4,
            positions: self.positions,
            normals: self.normals,
            face_ids: self.ids,
        }
    }
}

/// A mesh with non-quad faces, uniformly tessellated (docs/boundaries.md
/// §8): its base quads as one `(N+1)²` grid each, and every other face as
/// its quad sub-faces, one `(N/2+1)²` grid each (sub-face `corner` of face
/// `subfaces.face_ids[k]`: `u` from that corner along the next edge, `v`
/// along the previous edge, the far corner at the face's centroid point).
#[derive(Clone, Debug, PartialEq)]
pub struct PolygonGrids {
    /// Base quads at level `N`; `face_ids` are base faces.
    pub quads: Tessellation,
    /// Non-quad sub-faces at level `N/2`; `face_ids` are base faces.
    pub subfaces: Tessellation,
    /// Corner of each sub-face grid.
    pub corners: Vec<u32>,
    /// Open sample edges on the true boundary (set by the front door).
    pub boundary_open_edges: usize,
}

impl PolygonGrids {
    /// Every triangle, base face order: quads, then sub-faces.
    pub fn triangles(&self) -> Vec<[Vec3; 3]> {
        let mut out = super::grid_triangles(&self.quads);
        out.extend(super::grid_triangles(&self.subfaces));
        out
    }

    /// OBJ text: `g patch_<face>` per base quad (level `N`) and
    /// `g patch_<face>_<corner>` per sub-face (level `N/2`), in base face
    /// order, each with its `v`/`vn` lines and triangles
    /// ([`crate::check::obj`]'s layout).
    pub fn to_obj(&self) -> String {
        let mut s = format!(
            "# tessgen {} level {} (n-gon sub-faces at level {})\n",
            env!("CARGO_PKG_VERSION"),
            self.quads.level.max(2 * self.subfaces.level),
            self.subfaces.level
        );
        let mut order: Vec<(u32, u32, bool, usize)> = (0..self.quads.faces)
            .map(|g| (self.quads.face_of(g) as u32, 0, false, g))
            .chain(
                (0..self.subfaces.faces)
                    .map(|g| (self.subfaces.face_of(g) as u32, self.corners[g], true, g)),
            )
            .collect();
        order.sort_unstable();
        let mut base = 1u32;
        for (face, corner, sub, g) in order {
            let t = if sub { &self.subfaces } else { &self.quads };
            let per = t.grid_len();
            let name = if sub {
                format!("patch_{face}_{corner}")
            } else {
                format!("patch_{face}")
            };
            crate::check::obj::write_patch(
                &mut s,
                &name,
                &t.positions[g * per..(g + 1) * per],
                &t.normals[g * per..(g + 1) * per],
                &t.local_triangles(),
                base,
            );
            base += per as u32;
        }
        s
    }
}
