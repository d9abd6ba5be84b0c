//! Feature-adaptive refinement: refine only where a semi-sharp crease or
//! corner still needs it, so a crease of sharpness `s` costs `⌈s⌉` levels
//! around its line instead of `4^⌈s⌉` times the patches of the whole mesh
//! (docs/boundaries.md §8).
//!
//! The result is one [`Refinement`] per depth `d` that has leaves: the mesh
//! `M_d` of that depth, whose faces are either *leaves* (they emit their
//! part of a base grid at level `N / 2ᵈ`) or *holes* (refined further, or
//! only there as the 1-ring of a leaf). Every depth runs through the
//! unchanged backends; assembling the base grids takes each sample from the
//! leaf that covers it (`crate::tessellate::refined`).
//!
//! Which faces are refined at depth `d` (`R_d`): the leaves-to-be of depth
//! `d` (all base faces at `d = 0`, else the children of `R_{d−1}`) with a
//! corner that has a semi-sharp vertex sharpness or a semi-sharp incident
//! edge — the faces whose limit the sharp rules still change — and every
//! face at `d = 0` when the mesh has non-quads (one step makes them quads).
//!
//! With [`Depths::isolate`] `k > 0`, the leaves-to-be of depth `d < k` that
//! are not one bicubic patch (a corner of valence ≠ 4, an irregular sector:
//! [`FaceClass::Extraordinary`] of the depth's topology) are refined too, as
//! OpenSubdiv's isolation level does: after `k` steps an extraordinary
//! vertex's patches are `2⁻ᵏ` of the face around it, and the faces between
//! are regular, so exact. The schemes' approximation is left only there.
//!
//! Why the kept vertices are exact: `M_{d+1}` is the children of `S_d`, the
//! faces of `M_d` that share a vertex with `R_d` (plus whatever keeps the
//! mesh manifold). A child vertex is exact when the faces around its
//! parent vertex, edge or face are in `M_d` with exact vertices. The 2-ring
//! of `R_{d+1}` in `M_{d+1}` lies in the children of the 1-ring of `R_d`
//! (the children are half the size), so by induction from the complete base
//! mesh every vertex a leaf's patch reads (its 1-ring) is exact. Vertices on
//! the rim of a partial mesh are not, and no leaf reads them.

use super::stencil;
use super::step::{self, Level};
use super::{Block, Refinement, State};
use crate::mesh::features::{is_semi_sharp, Features};
use crate::mesh::topology::{FaceClass, Topology, TopologyError, TopologyOptions};
use crate::mesh::Mesh;

/// How deep [`refine_adaptive`] refines, per reason.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Depths {
    /// Steps around semi-sharp creases and corners (`⌈s⌉` resolves a
    /// crease of sharpness `s`); at least 1 when the mesh has non-quads.
    pub features: u32,
    /// Steps around faces that are not one bicubic patch (extraordinary
    /// vertices, irregular sectors): OpenSubdiv's isolation level. 0: none.
    pub isolate: u32,
}

impl Depths {
    /// The deepest step either reason takes, capped at
    /// [`super::MAX_REFINE_LEVELS`].
    pub fn max(self) -> u32 {
        self.features
            .max(self.isolate)
            .min(super::MAX_REFINE_LEVELS)
    }
}

/// Per face of `level`: whether it is not one bicubic patch, by the
/// topology a scheme would build on that depth's mesh. Only asked of
/// faces whose corners have their whole ring in `level` (children of
/// refined faces), so the rim of a partial mesh does not count.
fn irregular(
    level: &Level,
    features: &Features,
    max_valence: u32,
) -> Result<Vec<bool>, TopologyError> {
    let mesh = level
        .clone()
        .into_mesh(vec![[0.0; 3]; level.num_vertices], Vec::new());
    let features = level.features(features.boundary, Default::default());
    let opts = TopologyOptions {
        max_valence,
        require_quads: false,
    };
    let topo = Topology::build_with(&mesh, &opts, &features)?;
    Ok(topo
        .classes
        .iter()
        .map(|&c| c == FaceClass::Extraordinary)
        .collect())
}

/// How many of the faces `counted` use each edge `(min, max)` of `level`.
fn edge_uses(
    level: &Level,
    counted: impl Fn(usize) -> bool,
) -> std::collections::HashMap<(u32, u32), u32> {
    let mut uses = std::collections::HashMap::with_capacity(level.face_vertices.len());
    for f in (0..level.num_faces()).filter(|&f| counted(f)) {
        let face = level.face(f);
        for (i, &a) in face.iter().enumerate() {
            let b = face[(i + 1) % face.len()];
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses
}

/// Per face of `level`: whether a corner vertex has a semi-sharp vertex
/// sharpness or a semi-sharp interior incident edge.
fn touches_semi_sharp(level: &Level) -> Vec<bool> {
    let faces_of_edge = edge_uses(level, |_| true);
    let mut semi = vec![false; level.num_vertices];
    for (&(a, b), &s) in &level.edge_sharpness {
        // A boundary edge is sharp anyway: its tag changes nothing.
        if is_semi_sharp(s) && faces_of_edge.get(&(a, b)).copied().unwrap_or(0) > 1 {
            semi[a as usize] = true;
            semi[b as usize] = true;
        }
    }
    for (&v, &s) in &level.vertex_sharpness {
        if is_semi_sharp(s) {
            if let Some(x) = semi.get_mut(v as usize) {
                *x = true;
            }
        }
    }
    (0..level.num_faces())
        .map(|f| level.face(f).iter().any(|&v| semi[v as usize]))
        .collect()
}

/// Whether a face at `depth` (its leaf `l` in block `b`) holds a sample of
/// its block's grid at uniform level `level`: every face does while a face
/// is larger than a sample spacing; deeper, a face runs at level 1 and
/// only a corner on a sample counts, so a face with none is never refined
/// (it emits nothing anyway).
fn has_sample(b: &Block, l: &super::Leaf, depth: u32, level: u32) -> bool {
    let sub = b.corner.is_some();
    let grid = if sub { level / 2 } else { level }.max(1) as u64;
    let side = 1u64 << depth.saturating_sub(u32::from(sub));
    if side < grid || !side.is_multiple_of(grid) {
        return true;
    }
    let k = side / grid;
    let on = |c: u32| u64::from(c) % k == 0 || (u64::from(c) + 1) % k == 0;
    on(l.x) && on(l.y)
}

/// Faces per vertex of `level`.
fn vertex_faces(level: &Level) -> Vec<Vec<u32>> {
    let mut out = vec![Vec::new(); level.num_vertices];
    for f in 0..level.num_faces() {
        for &v in level.face(f) {
            out[v as usize].push(f as u32);
        }
    }
    out
}

/// `S_d`: the faces sharing a vertex with a face of `refine`, grown until
/// every vertex's kept faces form one fan (a vertex with more than two
/// boundary edges among the kept faces gets all its faces), so the child
/// mesh is manifold.
fn support(level: &Level, refine: &[bool]) -> Vec<bool> {
    let vf = vertex_faces(level);
    let mut keep = vec![false; level.num_faces()];
    for f in (0..level.num_faces()).filter(|&f| refine[f]) {
        for &v in level.face(f) {
            for &g in &vf[v as usize] {
                keep[g as usize] = true;
            }
        }
    }
    loop {
        // Kept faces per edge, then boundary edges per vertex.
        let uses = edge_uses(level, |f| keep[f]);
        let mut open = vec![0u32; level.num_vertices];
        for (&(a, b), &n) in &uses {
            if n == 1 {
                open[a as usize] += 1;
                open[b as usize] += 1;
            }
        }
        let mut grew = false;
        for (v, &n) in open.iter().enumerate() {
            if n > 2 {
                for &g in &vf[v] {
                    grew |= !keep[g as usize];
                    keep[g as usize] = true;
                }
            }
        }
        if !grew {
            return keep;
        }
    }
}

/// Keeps the child faces of the parent faces in `keep` (child face ids are
/// parent corner ids) and the vertices they use, renumbered in order.
/// Returns the child level and, per kept vertex, its old index.
fn restrict(child: &Level, parent_offsets: &[u32], keep: &[bool]) -> (Level, Vec<u32>) {
    let mut face_keep = vec![false; child.num_faces()];
    for (f, &k) in keep.iter().enumerate() {
        if k {
            for c in parent_offsets[f]..parent_offsets[f + 1] {
                face_keep[c as usize] = true;
            }
        }
    }
    let mut new_index = vec![u32::MAX; child.num_vertices];
    for f in (0..child.num_faces()).filter(|&f| face_keep[f]) {
        for &v in child.face(f) {
            new_index[v as usize] = 0;
        }
    }
    let mut old: Vec<u32> = Vec::new();
    for (v, n) in new_index.iter_mut().enumerate() {
        if *n == 0 {
            *n = old.len() as u32;
            old.push(v as u32);
        }
    }
    let mut out = Level {
        num_vertices: old.len(),
        face_offsets: vec![0],
        face_vertices: Vec::new(),
        boundary_corners: child.boundary_corners,
        ..Level::default()
    };
    for f in (0..child.num_faces()).filter(|&f| face_keep[f]) {
        out.face_vertices
            .extend(child.face(f).iter().map(|&v| new_index[v as usize]));
        out.face_offsets.push(out.face_vertices.len() as u32);
    }
    let map = |v: u32| {
        new_index
            .get(v as usize)
            .copied()
            .filter(|&n| n != u32::MAX)
    };
    for (&(a, b), &s) in &child.edge_sharpness {
        if let (Some(a), Some(b)) = (map(a), map(b)) {
            out.edge_sharpness.insert((a.min(b), a.max(b)), s);
        }
    }
    for (&v, &s) in &child.vertex_sharpness {
        if let Some(v) = map(v) {
            out.vertex_sharpness.insert(v, s);
        }
    }
    (out, old)
}

/// Refines `mesh` adaptively around its semi-sharp features (and, with
/// [`Depths::isolate`], its extraordinary vertices), as deep as `depths`
/// says (module docs): one [`Refinement`] per depth with leaves, shallowest
/// first, all with the same [`Refinement::blocks`]. The base mesh is
/// checked as [`super::refine`] checks it.
pub fn refine_adaptive(
    mesh: &Mesh,
    features: &Features,
    depths: Depths,
    level: u32,
    max_valence: u32,
) -> Result<Vec<Refinement>, TopologyError> {
    let max_depth = depths.max();
    let mut blocks: Vec<Block> = Vec::new();
    let mut state = State::start(mesh, features, max_valence, &mut blocks)?;
    let non_quads = (0..mesh.num_faces()).any(|f| mesh.face(f).len() != 4);
    // Leaves-to-be of this depth.
    let mut active = vec![true; mesh.num_faces()];
    let mut out: Vec<(u32, State, Vec<bool>)> = Vec::new();
    for d in 0..=max_depth {
        let refine: Vec<bool> = if d == max_depth {
            vec![false; state.level.num_faces()]
        } else if d == 0 && non_quads {
            vec![true; state.level.num_faces()]
        } else {
            let n = state.level.num_faces();
            let semi = if d < depths.features {
                touches_semi_sharp(&state.level)
            } else {
                vec![false; n]
            };
            let odd = if d < depths.isolate {
                irregular(&state.level, features, max_valence)?
            } else {
                vec![false; n]
            };
            (0..n)
                .map(|f| {
                    let l = &state.leaves[f];
                    (semi[f] || odd[f])
                        && active[f]
                        && !state.empty[f]
                        && has_sample(&blocks[l.block as usize], l, d, level)
                })
                .collect()
        };
        let emits: Vec<bool> = active.iter().zip(&refine).map(|(&a, &r)| a && !r).collect();
        if emits.iter().zip(&state.empty).any(|(&e, &h)| e && !h) {
            out.push((d, state.clone(), emits));
        }
        if !refine.iter().any(|&r| r) {
            break;
        }
        let keep = support(&state.level, &refine);
        let s = step::step(&state.level);
        let (child, old) = restrict(&s.child, &state.level.face_offsets, &keep);
        let rows: Vec<Vec<(u32, f64)>> = old.iter().map(|&v| s.rows[v as usize].clone()).collect();
        let rows = stencil::compose(&rows, &state.rows, mesh.num_vertices());
        let mut next = state.children(&keep, &mut blocks, d + 1);
        next.level = child;
        next.rows = rows;
        active = (0..state.level.num_faces())
            .filter(|&f| keep[f])
            .flat_map(|f| std::iter::repeat_n(refine[f], state.level.face(f).len()))
            .collect();
        state = next;
    }
    let order = super::sort_blocks(&mut blocks);
    // A block's depth: its deepest leaves, relative to the block's own root
    // (an n-gon's sub-face is one face at depth 1).
    for b in &mut blocks {
        b.depth = 0;
    }
    for (d, st, emits) in &out {
        for (l, _) in st.leaves.iter().zip(emits).filter(|(_, &e)| e) {
            let b = &mut blocks[order[l.block as usize] as usize];
            let root = u32::from(b.corner.is_some());
            b.depth = b.depth.max(d.saturating_sub(root));
        }
    }
    Ok(out
        .into_iter()
        .map(|(d, mut st, emits)| {
            for l in &mut st.leaves {
                l.block = order[l.block as usize];
            }
            // Faces refined further or only there as a ring emit nothing.
            for (e, &x) in st.empty.iter_mut().zip(&emits) {
                *e |= !x;
            }
            st.into_refinement(mesh, features, d, blocks.clone())
        })
        .collect())
}
