//! Uniform Catmull-Clark refinement of the base mesh, for what the patch
//! schemes cannot take directly: triangles and n-gons (one step makes every
//! face a quad) and semi-sharp creases (after `⌈s⌉` steps of the sharp
//! rules a crease of sharpness `s` has become smooth, so the schemes see
//! only smooth and infinitely sharp features). The Catmull-Clark limit of
//! the refined mesh is the limit of the base mesh, so nothing is
//! approximated by the step itself.
//!
//! What comes out (docs/boundaries.md §8):
//! - [`Refinement::stencils`]: every refined vertex as one flat row over the
//!   base vertices ([`StencilTable`]), so a deforming mesh refines in one
//!   pass, on the CPU or a GPU, with the same bits;
//! - [`Refinement::mesh`] and [`Refinement::features`]: the refined
//!   all-quad mesh with its remaining sharpness, holes and boundary rule —
//!   what [`crate::mesh::topology::Topology::build_with`] takes;
//! - [`Refinement::blocks`] / [`Refinement::leaves`]: which refined faces
//!   tile which output grid — one block per base quad (its `(u, v)` square,
//!   cut into `2ᵏ × 2ᵏ` leaves) and one per sub-face of an n-gon.

mod adaptive;
mod stencil;
mod step;

pub use adaptive::{refine_adaptive, Depths};
pub use stencil::StencilTable;
pub use step::QUAD_CHILD_OFFSET;

use std::collections::BTreeSet;

use crate::mesh::features::{is_semi_sharp, BoundaryRule, Features};
use crate::mesh::topology::{Topology, TopologyError, TopologyOptions};
use crate::mesh::{Mesh, NO_NORMAL};

/// Refinement steps that make the most refined grid still fit `u16` leaf
/// coordinates and keep tables far from `u32` limits.
pub const MAX_REFINE_LEVELS: u32 = 6;

/// Refinement steps the front door may spend on semi-sharp creases when
/// the request does not say: as many as a crease needs (`⌈s⌉`), up to the
/// deepest step. Feature-adaptive refinement only refines the faces around
/// the crease, so this costs a band of faces, not `4ᵏ×` the mesh
/// (docs/boundaries.md §8).
pub const DEFAULT_CREASE_REFINEMENT: u32 = MAX_REFINE_LEVELS;

/// The most crease steps *uniform* refinement takes (16× the patches), for
/// the paths that cannot refine feature-adaptively (the `regular` scheme,
/// whose patches cannot take the irregular rim of a partial mesh).
pub const UNIFORM_CREASE_REFINEMENT: u32 = 2;

/// What a mesh needs refined before a quad scheme can take it exactly.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Need {
    /// Faces that are not quads (one step makes them quads).
    pub non_quads: usize,
    /// Interior edges with a semi-sharp sharpness (0 < s < 10).
    pub semi_sharp_edges: usize,
    /// Vertices with a semi-sharp sharpness.
    pub semi_sharp_vertices: usize,
    /// Largest semi-sharp sharpness (0 if none).
    pub max_semi_sharpness: f32,
}

impl Need {
    /// Steps after which every semi-sharp feature is smooth: `⌈max s⌉`.
    pub fn crease_levels(&self) -> u32 {
        self.max_semi_sharpness.ceil() as u32
    }

    /// Steps needed in all: at least one for non-quads.
    pub fn levels(&self) -> u32 {
        self.crease_levels().max(u32::from(self.non_quads > 0))
    }
}

/// Counts what [`refine`] would be needed for.
pub fn need(mesh: &Mesh, features: &Features) -> Need {
    let mut n = Need {
        non_quads: (0..mesh.num_faces())
            .filter(|&f| mesh.face(f).len() != 4)
            .count(),
        ..Need::default()
    };
    let faces_of_edge = crate::mesh::features::edge_faces(mesh);
    for (e, &s) in &features.edge_sharpness {
        // A boundary edge is sharp anyway: its tag changes nothing.
        if is_semi_sharp(s) && faces_of_edge.get(e).copied().unwrap_or(0) > 1 {
            n.semi_sharp_edges += 1;
            n.max_semi_sharpness = n.max_semi_sharpness.max(s);
        }
    }
    for &s in features.vertex_sharpness.values() {
        if is_semi_sharp(s) {
            n.semi_sharp_vertices += 1;
            n.max_semi_sharpness = n.max_semi_sharpness.max(s);
        }
    }
    n
}

/// One output grid: a base quad (`corner == None`), or sub-face `corner` of
/// a base n-gon; `depth` steps cut it into `2^depth × 2^depth` leaves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Block {
    pub face: u32,
    pub corner: Option<u32>,
    pub depth: u32,
}

/// Where a refined face lies: leaf `(x, y)` of block `block`, `x` along the
/// block's `u`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Leaf {
    pub block: u32,
    pub x: u32,
    pub y: u32,
}

/// A refined mesh and how it maps back to the base (module docs).
#[derive(Debug, Clone)]
pub struct Refinement {
    /// Steps applied.
    pub levels: u32,
    /// Refined vertex `r` = row `r` over the base vertices.
    pub stencils: StencilTable,
    /// The refined all-quad mesh (positions from [`Refinement::stencils`],
    /// texture coordinates refined linearly per face corner).
    pub mesh: Mesh,
    /// Remaining sharpness (`s − levels`, infinite stays infinite), holes
    /// (children of holes and of faces without a limit), the boundary rule.
    pub features: Features,
    /// Output grids in base face order (n-gon sub-faces by corner).
    pub blocks: Vec<Block>,
    /// Per refined face.
    pub leaves: Vec<Leaf>,
}

impl Refinement {
    /// Refined positions for new base positions (same topology): the
    /// deformation path, in the table's reference order.
    pub fn positions(&self, base: &[[f32; 3]]) -> Vec<[f32; 3]> {
        self.stencils.apply(base)
    }
}

/// Refines `mesh` by `levels` uniform Catmull-Clark steps with `features`
/// applied. The base mesh is checked first, as
/// [`Topology::build_with`] checks a quad mesh (non-manifold edges and
/// vertices, orientation, valence above `max_valence`), so a refinement
/// never starts on a mesh the schemes would refuse for another reason.
pub fn refine(
    mesh: &Mesh,
    features: &Features,
    levels: u32,
    max_valence: u32,
) -> Result<Refinement, TopologyError> {
    let levels = levels.min(MAX_REFINE_LEVELS);
    let mut blocks = Vec::new();
    let mut state = State::start(mesh, features, max_valence, &mut blocks)?;
    for _ in 0..levels {
        let s = step::step(&state.level);
        let all = vec![true; state.level.num_faces()];
        let mut next = state.children(&all, &mut blocks, levels);
        next.rows = stencil::compose(&s.rows, &state.rows, mesh.num_vertices());
        next.level = s.child;
        state = next;
    }
    let order = sort_blocks(&mut blocks);
    for b in &mut blocks {
        b.depth = if b.corner.is_some() {
            levels - 1
        } else {
            levels
        };
    }
    for l in &mut state.leaves {
        l.block = order[l.block as usize];
    }
    Ok(state.into_refinement(mesh, features, levels, blocks))
}

/// One level of a refinement in progress: the mesh, its vertices as rows
/// over the base, and per face where it lies and whether it emits nothing;
/// texture coordinates per face corner.
#[derive(Debug, Clone)]
pub(super) struct State {
    level: step::Level,
    rows: Vec<Vec<(u32, f64)>>,
    leaves: Vec<Leaf>,
    empty: Vec<bool>,
    /// Per face corner (empty without texture coordinates).
    uv: Vec<[f32; 2]>,
}

impl State {
    /// The base mesh, checked as [`refine`] says; its quads start blocks.
    fn start(
        mesh: &Mesh,
        features: &Features,
        max_valence: u32,
        blocks: &mut Vec<Block>,
    ) -> Result<State, TopologyError> {
        let opts = TopologyOptions {
            max_valence,
            require_quads: false,
        };
        let base = Topology::build_with(mesh, &opts, features)?;
        let level = step::Level {
            num_vertices: mesh.num_vertices(),
            face_offsets: mesh.face_offsets.clone(),
            face_vertices: mesh.face_vertices.clone(),
            edge_sharpness: features
                .edge_sharpness
                .iter()
                .map(|(&k, &s)| (k, s))
                .collect(),
            vertex_sharpness: features
                .vertex_sharpness
                .iter()
                .map(|(&k, &s)| (k, s))
                .collect(),
            boundary_corners: features.boundary == BoundaryRule::EdgeAndCorner,
        };
        let mut leaves = Vec::with_capacity(mesh.num_faces());
        for f in 0..mesh.num_faces() {
            if mesh.face(f).len() == 4 {
                leaves.push(Leaf {
                    block: blocks.len() as u32,
                    x: 0,
                    y: 0,
                });
                blocks.push(Block {
                    face: f as u32,
                    corner: None,
                    depth: 0,
                });
            } else {
                // Placeholder: an n-gon is no leaf; its children start blocks.
                leaves.push(Leaf {
                    block: u32::MAX,
                    x: 0,
                    y: 0,
                });
            }
        }
        let empty = (0..mesh.num_faces())
            .map(|f| base.no_limit[f] || features.holes.contains(&(f as u32)))
            .collect();
        let uv = if !mesh.face_texcoords.is_empty() && !mesh.texcoords.is_empty() {
            (0..mesh.face_vertices.len())
                .map(|c| mesh.corner_texcoord(c).unwrap_or([0.0; 2]))
                .collect()
        } else {
            Vec::new()
        };
        let rows = (0..mesh.num_vertices() as u32)
            .map(|v| vec![(v, 1.0)])
            .collect();
        Ok(State {
            level,
            rows,
            leaves,
            empty,
            uv,
        })
    }

    /// Leaves, emptiness and texture coordinates of the children of the
    /// faces in `keep`, in child face order (the caller sets the child
    /// level and rows). Children of an n-gon start blocks of `depth`.
    fn children(&self, keep: &[bool], blocks: &mut Vec<Block>, depth: u32) -> State {
        let has_uv = !self.uv.is_empty();
        let mut next = State {
            level: step::Level::default(),
            rows: Vec::new(),
            leaves: Vec::new(),
            empty: Vec::new(),
            uv: Vec::new(),
        };
        for f in (0..self.level.num_faces()).filter(|&f| keep[f]) {
            let n = self.level.face(f).len();
            let first = self.level.face_offsets[f] as usize;
            let parent = self.leaves[f];
            #[allow(clippy::needless_range_loop)] // `i` is also the sub-face corner
            for i in 0..n {
                next.empty.push(self.empty[f]);
                next.leaves.push(if n == 4 {
                    let (ox, oy) = QUAD_CHILD_OFFSET[i];
                    Leaf {
                        block: parent.block,
                        x: 2 * parent.x + ox,
                        y: 2 * parent.y + oy,
                    }
                } else {
                    blocks.push(Block {
                        face: f as u32,
                        corner: Some(i as u32),
                        depth: depth.saturating_sub(1),
                    });
                    Leaf {
                        block: (blocks.len() - 1) as u32,
                        x: 0,
                        y: 0,
                    }
                });
                if has_uv {
                    let corner = |k: usize| self.uv[first + k % n];
                    let mid = |a: [f32; 2], b: [f32; 2]| [(a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5];
                    let mut c = [0.0f32; 2];
                    for k in 0..n {
                        c = [c[0] + corner(k)[0], c[1] + corner(k)[1]];
                    }
                    let c = [c[0] / n as f32, c[1] / n as f32];
                    let next_mid = mid(corner(i), corner(i + 1));
                    let prev = mid(corner(i + n - 1), corner(i));
                    next.uv.extend_from_slice(&step::child_face(
                        n,
                        i,
                        corner(i),
                        next_mid,
                        c,
                        prev,
                    ));
                }
            }
        }
        next
    }

    /// The finished level as a [`Refinement`] of `levels` steps.
    fn into_refinement(
        self,
        mesh: &Mesh,
        features: &Features,
        levels: u32,
        blocks: Vec<Block>,
    ) -> Refinement {
        let stencils = StencilTable::from_rows(&self.rows);
        let positions = stencils.apply(&mesh.positions);
        let holes: BTreeSet<u32> = self
            .empty
            .iter()
            .enumerate()
            .filter(|(_, &e)| e)
            .map(|(f, _)| f as u32)
            .collect();
        let features = self.level.features(features.boundary, holes);
        let refined = self.level.into_mesh(positions, self.uv);
        Refinement {
            levels,
            stencils,
            mesh: refined,
            features,
            blocks,
            leaves: self.leaves,
        }
    }
}

impl step::Level {
    /// The level's faces as a [`Mesh`] with `positions` and, when `uv` is
    /// not empty, one texture coordinate per face corner (no normals).
    fn into_mesh(self, positions: Vec<[f32; 3]>, uv: Vec<[f32; 2]>) -> Mesh {
        let nc = self.face_vertices.len();
        let face_texcoords = if uv.is_empty() {
            Vec::new()
        } else {
            (0..nc as u32).collect()
        };
        Mesh {
            positions,
            face_offsets: self.face_offsets,
            face_vertices: self.face_vertices,
            tags: Vec::new(),
            normals: Vec::new(),
            face_normals: vec![NO_NORMAL; nc],
            texcoords: uv,
            face_texcoords,
        }
    }

    /// The level's remaining sharpness as [`Features`], with `boundary`
    /// and `holes`.
    fn features(&self, boundary: BoundaryRule, holes: BTreeSet<u32>) -> Features {
        Features {
            boundary,
            edge_sharpness: self.edge_sharpness.iter().map(|(&e, &s)| (e, s)).collect(),
            vertex_sharpness: self
                .vertex_sharpness
                .iter()
                .map(|(&v, &s)| (v, s))
                .collect(),
            holes,
        }
    }
}

/// Sorts `blocks` into base face order (n-gon sub-face blocks are appended
/// at the first step) and returns each old block's new index.
fn sort_blocks(blocks: &mut Vec<Block>) -> Vec<u32> {
    let mut order: Vec<u32> = (0..blocks.len() as u32).collect();
    order.sort_by_key(|&b| (blocks[b as usize].face, blocks[b as usize].corner));
    let mut new_index = vec![0u32; blocks.len()];
    for (k, &b) in order.iter().enumerate() {
        new_index[b as usize] = k as u32;
    }
    *blocks = order.iter().map(|&b| blocks[b as usize]).collect();
    new_index
}

#[cfg(test)]
mod tests;
