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
/// A feature-adaptive refinement is several of these, one per depth with
/// leaves ([`RefinedDomain::for_mesh`]); the first carries the notes.
#[derive(Debug)]
pub struct RefinedDomain {
    pub refinement: Refinement,
    /// What the base mesh needed.
    pub need: Need,
    /// The uniform level this depth's faces run at (`max(1, N / 2ᵈ)`; 0
    /// when adaptive).
    pub leaf_level: u32,
    /// The requested uniform level `N` of the base grids (0 when adaptive).
    pub level: u32,
    /// What the refinement does and approximates, then the tag warnings
    /// that still hold.
    pub notes: Vec<String>,
    /// Base half-edges that stay open (the true boundary; holes'), each
    /// `N` open sample edges in a watertight result.
    pub open_base_halfedges: usize,
    /// The base faces (blocks name them; transitions between depths are
    /// found through their vertices).
    base_face_offsets: Vec<u32>,
    base_face_vertices: Vec<u32>,
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
    /// An internal inconsistency, never a property of the input: a sample
    /// of a base grid that no refined face covers.
    #[error(
        "internal error: sample ({i}, {j}) of base face {face} is covered by no refined face \
         (please report it with the mesh)"
    )]
    Uncovered { face: u32, i: usize, j: usize },
    /// An internal inconsistency: a deeper depth's run did not come back
    /// as one grid per refined face.
    #[error("internal error: a refined depth did not come back as grids (please report it)")]
    NotAGrid,
}

/// `(steps, crease steps)` to apply for `need` at uniform `level`
/// (`None`: adaptive) with uniform refinement: at most
/// [`crate::mesh::refine::UNIFORM_CREASE_REFINEMENT`] crease steps.
pub fn choose_levels(need: &Need, level: Option<u32>, crease_cap: u32) -> (u32, u32) {
    let polygons = u32::from(need.non_quads > 0);
    // A uniform level must stay divisible by the steps' powers of two;
    // adaptive runs tessellate the refined faces, one patch each, so only
    // the uniform refinement's cost bounds their steps.
    let creases = need
        .crease_levels()
        .min(crease_cap)
        .min(crate::mesh::refine::UNIFORM_CREASE_REFINEMENT)
        .min(level.map_or(u32::MAX, u32::trailing_zeros));
    let steps = creases
        .max(polygons)
        .min(crate::mesh::refine::MAX_REFINE_LEVELS);
    (steps, creases)
}

/// The deepest feature-adaptive step a uniform level `N` can read its
/// samples off: a leaf of depth `d` runs at level `N / 2ᵈ`, or — past
/// `log₂ N` when `N` is a power of two — at level 1 with every sample on a
/// leaf corner.
pub fn depth_cap(level: u32) -> u32 {
    if level.is_power_of_two() {
        crate::mesh::refine::MAX_REFINE_LEVELS
    } else {
        level.trailing_zeros()
    }
}

/// What a request asks of the refinement ([`RefinedDomain::for_mesh`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RefineOptions {
    /// The uniform level (`None`: adaptive sampling).
    pub level: Option<u32>,
    /// [`super::Request::crease_refinement`].
    pub crease_cap: u32,
    /// [`super::Request::isolate`]: steps around extraordinary vertices.
    pub isolate: u32,
    pub max_valence: u32,
    /// Whether the scheme can run a partial mesh (it has an extraordinary
    /// class); `regular` cannot.
    pub feature_adaptive: bool,
}

impl RefineOptions {
    /// Whether [`RefineOptions::isolate`] can be applied: uniform sampling
    /// and a scheme that refines feature-adaptively.
    pub fn isolates(&self) -> bool {
        self.isolate > 0 && self.level.is_some() && self.feature_adaptive
    }
}

impl RefinedDomain {
    /// Builds the refinement for `mesh` if it needs one (empty if not):
    /// one domain per depth, shallowest first. Uniform requests refine
    /// feature-adaptively (only around semi-sharp features, as deep as
    /// `⌈s⌉`, `crease_cap` and [`depth_cap`] allow, and around
    /// extraordinary vertices as deep as `isolate` asks); adaptive
    /// requests, and schemes without an extraordinary class (`regular`,
    /// which cannot take the irregular rim of a partial mesh), refine
    /// uniformly.
    pub fn for_mesh(
        mesh: &crate::mesh::Mesh,
        features: &Features,
        warnings: &[FeatureWarning],
        o: &RefineOptions,
    ) -> Result<Vec<RefinedDomain>, super::Error> {
        let RefineOptions {
            level,
            crease_cap,
            max_valence,
            feature_adaptive,
            ..
        } = *o;
        let need = refine::need(mesh, features);
        if need.levels() == 0 && !o.isolates() {
            return Ok(Vec::new());
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
        let polygons = u32::from(need.non_quads > 0);
        let mut isolated = 0;
        let (parts, steps, creases, adaptive_steps) = match (level, feature_adaptive) {
            (Some(n), true) => {
                let creases = need.crease_levels().min(crease_cap).min(depth_cap(n));
                let depths = refine::Depths {
                    features: creases.max(polygons),
                    isolate: o.isolate.min(depth_cap(n)),
                };
                let parts = refine::refine_adaptive(mesh, features, depths, n, max_valence)
                    .map_err(crate::cpu::TessError::from)?;
                // Isolation asked of a mesh without extraordinary faces.
                if parts.len() == 1 && parts[0].levels == 0 && need.levels() == 0 {
                    return Ok(Vec::new());
                }
                isolated = depths.isolate;
                (parts, depths.max(), creases, true)
            }
            _ => {
                let (steps, creases) = choose_levels(&need, level, crease_cap);
                if steps == 0 {
                    return Ok(Vec::new());
                }
                let r = refine::refine(mesh, features, steps, max_valence)
                    .map_err(crate::cpu::TessError::from)?;
                (vec![r], steps, creases, false)
            }
        };
        if parts.is_empty() {
            return Ok(Vec::new());
        }
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
        let by_level = level.is_some_and(|n| {
            let (by_level, by_path) = if adaptive_steps {
                (depth_cap(n), crease_cap)
            } else {
                (
                    n.trailing_zeros(),
                    crease_cap.min(crate::mesh::refine::UNIFORM_CREASE_REFINEMENT),
                )
            };
            by_level < need.crease_levels().min(by_path)
        });
        let faces: usize = parts.iter().map(|r| r.mesh.num_faces()).sum();
        let leaves: usize = parts
            .iter()
            .map(|r| r.mesh.num_faces() - r.features.holes.len())
            .sum();
        let cost = if adaptive_steps {
            format!(
                "feature-adaptive: {leaves} leaf faces in {} depths, {faces} refined faces \
                 evaluated, {:.1}× the {} base faces",
                parts.len(),
                faces as f64 / mesh.num_faces().max(1) as f64,
                mesh.num_faces()
            )
        } else {
            format!("{}× the patches", 1u64 << (2 * steps))
        };
        if isolated > 0 {
            notes.push(format!(
                "extraordinary vertices isolated by {isolated} Catmull-Clark steps (the scheme \
                 approximates only the faces next to them){}",
                if need.max_semi_sharpness > 0.0 {
                    String::new()
                } else {
                    format!(" ({cost})")
                }
            ));
        }
        if need.max_semi_sharpness > 0.0 {
            notes.push(if resolved {
                format!(
                    "semi-sharp creases (sharpness up to {}) applied exactly by {} Catmull-Clark steps \
                     ({cost})",
                    need.max_semi_sharpness, creases,
                )
            } else {
                format!(
                    "semi-sharp creases (sharpness up to {}) need {} Catmull-Clark steps; {} applied \
                     ({}; {cost}), the remaining sharpness is applied as infinitely sharp",
                    need.max_semi_sharpness,
                    need.crease_levels(),
                    creases,
                    if level.is_none() {
                        "adaptive tessellation refines uniformly, at most 2 crease steps"
                    } else if by_level {
                        "a level divisible by a higher power of two allows more"
                    } else if !adaptive_steps
                        && crease_cap > crate::mesh::refine::UNIFORM_CREASE_REFINEMENT
                    {
                        "uniform refinement into one mesh (the `regular` scheme, `render`) \
                         takes at most 2 crease steps"
                    } else {
                        "the crease refinement cap"
                    }
                )
            });
        }
        notes.extend(tag_notes);
        let opts = crate::mesh::topology::TopologyOptions {
            max_valence,
            require_quads: false,
        };
        let base = crate::mesh::topology::Topology::build_with(mesh, &opts, features)
            .map_err(crate::cpu::TessError::from)?;
        let open_base_halfedges = crate::check::weld::open_base_halfedges(&base).len();
        let n = level.unwrap_or(0);
        Ok(parts
            .into_iter()
            .enumerate()
            .map(|(k, refinement)| RefinedDomain {
                leaf_level: level.map_or(0, |n| (n >> refinement.levels).max(1)),
                level: n,
                refinement,
                need,
                notes: if k == 0 { notes.clone() } else { Vec::new() },
                open_base_halfedges,
                base_face_offsets: mesh.face_offsets.clone(),
                base_face_vertices: mesh.face_vertices.clone(),
            })
            .collect())
    }

    /// The base face a refined face comes from.
    pub fn base_face(&self, refined_face: usize) -> usize {
        let r = &self.refinement;
        r.leaves
            .get(refined_face)
            .and_then(|l| r.blocks.get(l.block as usize))
            .map_or(refined_face, |b| b.face as usize)
    }

    /// Whether refined face `f` lies on its block's border (a leaf cell
    /// in the block's first or last row or column): the leaves whose
    /// samples a neighbouring block's transitions can take.
    pub fn on_block_border(&self, f: usize) -> bool {
        let r = &self.refinement;
        let Some(l) = r.leaves.get(f) else {
            return false;
        };
        let Some(b) = r.blocks.get(l.block as usize) else {
            return false;
        };
        let side = 1u32 << r.levels.saturating_sub(u32::from(b.corner.is_some()));
        l.x == 0 || l.y == 0 || l.x + 1 == side || l.y + 1 == side
    }

    /// Whether refined face `f` emits (a leaf: not refined further, not
    /// only a ring, not a hole).
    pub fn emits(&self, f: usize) -> bool {
        !self.refinement.features.holes.contains(&(f as u32))
    }
}

/// One depth of a refined uniform run: its domain and what its backend
/// returned (one grid per refined face at the depth's leaf level), with the
/// faces that have no limit.
pub struct Part<'a> {
    pub domain: &'a RefinedDomain,
    pub t: &'a Tessellation,
    pub no_limit: &'a [bool],
}

/// Where a sample on a block's border lies on the base mesh, the same from
/// every block that has it: a base vertex, sample `k` of `N` along a base
/// edge from its lower vertex, sample `k` of `N/2` along an n-gon's inner
/// line from the midpoint of its edge `e` to its centre, or the centre.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Border {
    Vertex(u32),
    Edge(u32, u32, usize),
    Inner(u32, u32, usize),
    Centre(u32),
}

fn edge_sample(a: u32, b: u32, k: usize, n: usize) -> Border {
    match k {
        0 => Border::Vertex(a),
        k if k == n => Border::Vertex(b),
        k if a < b => Border::Edge(a, b, k),
        k => Border::Edge(b, a, n - k),
    }
}

/// The refined result of a uniform run in the base layout: base quads as
/// one `(N+1)²` grid each, n-gons as their sub-faces at `N/2`; blocks that
/// emit nothing (holes) are left out. Each sample comes from the leaf that
/// covers it (the shallowest depth whose face at the sample's quadtree cell
/// is a leaf). Where blocks of different depths meet, their shared border
/// samples are evaluated by different meshes and are equal only up to
/// rounding (exactly, where both sides' patches are the limit): the deepest
/// side's sample is taken on both, so the result stays watertight bit for
/// bit. Borders between leaves of one depth are left as evaluated — the
/// backends' shared-edge contract makes them equal, and the weld checks it.
pub fn assemble(parts: &[Part<'_>]) -> Result<super::Output, super::Error> {
    assemble_window(parts, None)
}

/// [`assemble`] of the blocks `blocks` only, for a refinement streamed
/// block window by block window (`Session::run_chunked`): each part's `t`
/// need hold only the grids of the leaves of those blocks and of `halo`
/// (through its `face_ids`). `halo` (sorted, outside the window: see
/// [`Neighbours::halo`]; empty for one depth) are the blocks that share a
/// border sample with the window: their samples there take part in the
/// transitions between depths as in the whole (the deepest side's sample,
/// the first block's in block order), but they are not emitted. Each
/// block's samples are then [`assemble`]'s bit for bit; the result is
/// [`super::Output::Polygons`] whenever the whole would be (the mesh has a
/// non-quad block), its levels those of the whole (`N`, `N/2`), so the
/// chunks' OBJ written one after the other is the whole's.
pub fn assemble_blocks(
    parts: &[Part<'_>],
    blocks: std::ops::Range<usize>,
    halo: &[usize],
) -> Result<super::Output, super::Error> {
    assemble_window(parts, Some((blocks, halo)))
}

/// The refined face range of every block (`None` unless each block's
/// leaves are consecutive refined faces, in block order, as the
/// refinement numbers them): how a streaming caller maps a block window
/// to the refined faces it evaluates.
pub fn block_faces(domain: &RefinedDomain) -> Option<Vec<std::ops::Range<usize>>> {
    let r = &domain.refinement;
    let mut ranges = vec![0..0; r.blocks.len()];
    let mut next = 0usize;
    for (f, l) in r.leaves.iter().enumerate() {
        let b = l.block as usize;
        let range = ranges.get_mut(b)?;
        if range.start == range.end {
            // A block's first leaf: blocks in order, none seen before.
            if b < next {
                return None;
            }
            *range = f..f + 1;
            next = b + 1;
        } else if range.end == f {
            range.end = f + 1;
        } else {
            return None;
        }
    }
    // Blocks without leaves start where the next block does.
    let mut at = r.leaves.len();
    for range in ranges.iter_mut().rev() {
        if range.start == range.end {
            *range = at..at;
        }
        at = range.start;
    }
    Some(ranges)
}

/// The blocks around each base vertex: which blocks a window's border
/// samples can be shared with (every `Border` key of a block lies on its
/// base face — a vertex, an edge, the face's inner lines — so the blocks
/// that have it are those of the base faces sharing a vertex with it).
pub struct Neighbours<'a> {
    domain: &'a RefinedDomain,
    /// The blocks of base vertex `v`: `blocks[offsets[v]..offsets[v + 1]]`,
    /// ascending.
    offsets: Vec<usize>,
    blocks: Vec<u32>,
}

impl<'a> Neighbours<'a> {
    /// The blocks of `domain`'s base mesh by base vertex (a few words per
    /// block corner).
    pub fn new(domain: &'a RefinedDomain) -> Self {
        let vertices = domain
            .base_face_vertices
            .iter()
            .map(|&v| v as usize + 1)
            .max()
            .unwrap_or(0);
        let mut offsets = vec![0usize; vertices + 1];
        let faces = |b: &refine::Block| domain.base_vertices(b.face);
        for b in &domain.refinement.blocks {
            for &v in faces(b) {
                offsets[v as usize + 1] += 1;
            }
        }
        for k in 1..offsets.len() {
            offsets[k] += offsets[k - 1];
        }
        let mut fill = offsets.clone();
        let mut blocks = vec![0u32; offsets[vertices]];
        for (k, b) in domain.refinement.blocks.iter().enumerate() {
            for &v in faces(b) {
                blocks[fill[v as usize]] = k as u32;
                fill[v as usize] += 1;
            }
        }
        Neighbours {
            domain,
            offsets,
            blocks,
        }
    }

    /// The blocks sharing a base vertex with block `b` (`b` among them;
    /// some more than once).
    pub fn around(&self, b: usize) -> impl Iterator<Item = usize> + '_ {
        let face = self.domain.refinement.blocks[b].face;
        self.domain.base_vertices(face).iter().flat_map(move |&v| {
            self.blocks[self.offsets[v as usize]..self.offsets[v as usize + 1]]
                .iter()
                .map(|&k| k as usize)
        })
    }

    /// The blocks outside `window` that share a base vertex with a block
    /// in it, ascending: the halo [`assemble_blocks`] takes.
    pub fn halo(&self, window: std::ops::Range<usize>) -> Vec<usize> {
        let mut halo: Vec<usize> = window
            .clone()
            .flat_map(|b| self.around(b))
            .filter(|k| !window.contains(k))
            .collect();
        halo.sort_unstable();
        halo.dedup();
        halo
    }
}

impl RefinedDomain {
    /// The vertices of base face `f`.
    fn base_vertices(&self, f: u32) -> &[u32] {
        let (a, b) = (
            self.base_face_offsets[f as usize] as usize,
            self.base_face_offsets[f as usize + 1] as usize,
        );
        &self.base_face_vertices[a..b]
    }
}

/// Where an assembled sample is kept: the output's quad or sub-face grids,
/// or (a halo block's border sample) only for the transitions; a halo
/// sample of the shallowest depth is not evaluated (it never wins a
/// transition: the deepest side's does) and takes part with its depth only.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Dst {
    Quads,
    Subfaces,
    Halo,
    Unevaluated,
}

fn assemble_window(
    parts: &[Part<'_>],
    window: Option<(std::ops::Range<usize>, &[usize])>,
) -> Result<super::Output, super::Error> {
    let Some(first) = parts.first() else {
        return Ok(super::Output::Grid(Tessellation::default()));
    };
    let blocks = &first.domain.refinement.blocks;
    let n = first.domain.level as usize;
    // Emitted: the window's blocks; assembled: those and the halo's.
    let emitted = |b: usize| window.as_ref().is_none_or(|(w, _)| w.contains(&b));
    let in_window = |b: usize| {
        window
            .as_ref()
            .is_none_or(|(w, halo)| w.contains(&b) || halo.binary_search(&b).is_ok())
    };
    // Per part and block: the emitting leaf face of every cell, row-major.
    let cells: Vec<Vec<Option<Vec<u32>>>> = parts
        .iter()
        .map(|p| {
            let r = &p.domain.refinement;
            let mut c: Vec<Option<Vec<u32>>> = vec![None; blocks.len()];
            for (f, l) in r.leaves.iter().enumerate() {
                if !in_window(l.block as usize)
                    || !p.domain.emits(f)
                    || p.no_limit.get(f).copied().unwrap_or(true)
                {
                    continue;
                }
                let b = &blocks[l.block as usize];
                let side = 1usize << r.levels.saturating_sub(u32::from(b.corner.is_some()));
                let cell = c[l.block as usize].get_or_insert_with(|| vec![u32::MAX; side * side]);
                cell[l.y as usize * side + l.x as usize] = f as u32;
            }
            c
        })
        .collect();
    // Grid of each face in a part's result: face f, or (when the backend
    // left out the faces that emit nothing) its place in `face_ids`.
    let grid_of: Vec<Option<Vec<u32>>> = parts
        .iter()
        .map(|p| {
            // (A part with no grids here: none.)
            (!p.t.face_ids.is_empty() || p.t.faces == 0).then(|| {
                let mut g = vec![u32::MAX; p.domain.refinement.leaves.len().max(p.t.faces)];
                for (k, &f) in p.t.face_ids.iter().enumerate() {
                    if let Some(x) = g.get_mut(f as usize) {
                        *x = k as u32;
                    }
                }
                g
            })
        })
        .collect();
    let mut quads = GridBuilder::default();
    let mut subfaces = GridBuilder::default();
    let mut halo: Vec<(Vec3, Vec3)> = Vec::new();
    let mut corners = Vec::new();
    // Border samples: where they are kept, and the depth that gave them,
    // in block order (the whole's order, halo blocks in their place).
    let mut borders: std::collections::HashMap<Border, Vec<(Dst, usize, u32)>> =
        std::collections::HashMap::new();
    let base = |f: u32| first.domain.base_vertices(f);
    // The grids' levels and the output's kind are the mesh's, whatever a
    // window (or the set of faces that emit) holds: a streamed result
    // writes the whole one's header, and a mesh whose n-gons are all holes
    // is still polygon grids.
    (quads.level, subfaces.level) = (n as u32, (n / 2) as u32);
    // The blocks that emit (in the window or its halo), then room for the
    // window's grids, or TessError::OutOfMemory (never an allocation that
    // aborts).
    let assembled: Vec<usize> = (0..blocks.len())
        .filter(|&b| in_window(b) && cells.iter().any(|c| c[b].is_some()))
        .collect();
    let sub_blocks = assembled
        .iter()
        .filter(|&&b| emitted(b) && blocks[b].corner.is_some())
        .count();
    let quad_blocks = assembled.iter().filter(|&&b| emitted(b)).count() - sub_blocks;
    let samples = |l: usize, count: usize| count.saturating_mul((l + 1) * (l + 1));
    crate::cpu::reserve_samples(
        &mut quads.positions,
        &mut quads.normals,
        samples(n, quad_blocks),
    )?;
    crate::cpu::reserve_samples(
        &mut subfaces.positions,
        &mut subfaces.normals,
        samples(n / 2, sub_blocks),
    )?;
    for &b in &assembled {
        let block = &blocks[b];
        let sub = block.corner.is_some();
        let l = if sub { n / 2 } else { n };
        let emit = emitted(b);
        let dst = match (emit, sub) {
            (false, _) => Dst::Halo,
            (true, true) => Dst::Subfaces,
            (true, false) => Dst::Quads,
        };
        if emit {
            let out = if sub {
                corners.push(block.corner.unwrap_or(0));
                &mut subfaces
            } else {
                &mut quads
            };
            out.ids.push(block.face);
        }
        let w = base(block.face);
        for j in 0..=l {
            // A halo block takes part with its border samples only.
            let step = if emit || j == 0 || j == l {
                1
            } else {
                l.max(1)
            };
            for i in (0..=l).step_by(step) {
                let mut found = None;
                // A halo leaf left unevaluated (the shallowest depth's,
                // whose sample never wins a transition): its depth only.
                let mut unevaluated = None;
                for ((p, c), grid) in parts.iter().zip(&cells).zip(&grid_of) {
                    let Some(cell) = &c[b] else { continue };
                    let r = p.domain.refinement.levels - u32::from(sub);
                    let side = 1usize << r;
                    let m = p.domain.leaf_level as usize;
                    let (x, li) = leaf_coord(i, l, m, side);
                    let (y, lj) = leaf_coord(j, l, m, side);
                    let f = cell[y * side + x];
                    let g = match grid {
                        Some(g) => g.get(f as usize).copied().unwrap_or(u32::MAX),
                        None => f,
                    };
                    if f != u32::MAX && g != u32::MAX {
                        found = Some((p, g as usize * (m + 1) * (m + 1) + lj * (m + 1) + li));
                        break;
                    }
                    if f != u32::MAX && !emit {
                        unevaluated = Some(p.domain.refinement.levels);
                        break;
                    }
                }
                let (depth, at) = match (found, unevaluated) {
                    (Some((p, s)), _) => {
                        let sample = (p.t.positions[s], p.t.normals[s]);
                        let at = match dst {
                            Dst::Quads => quads.push(sample),
                            Dst::Subfaces => subfaces.push(sample),
                            Dst::Halo | Dst::Unevaluated => {
                                halo.push(sample);
                                halo.len() - 1
                            }
                        };
                        (p.domain.refinement.levels, at)
                    }
                    (None, Some(depth)) => (depth, usize::MAX),
                    (None, None) => {
                        return Err(RefineError::Uncovered {
                            face: block.face,
                            i,
                            j,
                        }
                        .into())
                    }
                };
                let dst = if at == usize::MAX {
                    Dst::Unevaluated
                } else {
                    dst
                };
                // Transitions are between depths: one depth has none.
                if parts.len() > 1 && (i == 0 || j == 0 || i == l || j == l) {
                    let mut keys: Vec<Border> = Vec::with_capacity(2);
                    match block.corner {
                        None => {
                            if j == 0 {
                                keys.push(edge_sample(w[0], w[1], i, n));
                            }
                            if i == n {
                                keys.push(edge_sample(w[1], w[2], j, n));
                            }
                            if j == n {
                                keys.push(edge_sample(w[3], w[2], i, n));
                            }
                            if i == 0 {
                                keys.push(edge_sample(w[0], w[3], j, n));
                            }
                        }
                        Some(c) => {
                            let k = w.len() as u32;
                            let (c0, c1, cm) = (c, (c + 1) % k, (c + k - 1) % k);
                            let (wc, wn, wp) = (w[c0 as usize], w[c1 as usize], w[cm as usize]);
                            let inner = |e: u32, t: usize| match t {
                                0 => edge_sample(w[e as usize], w[((e + 1) % k) as usize], l, n),
                                t if t == l => Border::Centre(block.face),
                                t => Border::Inner(block.face, e, t),
                            };
                            if j == 0 {
                                keys.push(edge_sample(wc, wn, i, n));
                            }
                            if i == 0 {
                                keys.push(edge_sample(wc, wp, j, n));
                            }
                            if i == l {
                                keys.push(inner(c0, j));
                            }
                            if j == l {
                                keys.push(inner(cm, i));
                            }
                        }
                    }
                    keys.dedup();
                    for key in keys {
                        borders.entry(key).or_default().push((dst, at, depth));
                    }
                }
            }
        }
    }
    // Transitions: the deepest side's sample (the first such block's) on
    // every side; a halo block only gives it.
    for uses in borders.values() {
        let deepest = uses.iter().map(|u| u.2).max().unwrap_or(0);
        if uses.iter().all(|u| u.2 == deepest) {
            continue;
        }
        let Some(&(src, at, _)) = uses.iter().find(|u| u.2 == deepest) else {
            continue;
        };
        let sample = match src {
            Dst::Quads => quads.get(at),
            Dst::Subfaces => subfaces.get(at),
            Dst::Halo => halo[at],
            // Never: an unevaluated sample is of the shallowest depth,
            // the deepest only where every use is (no transition).
            Dst::Unevaluated => continue,
        };
        for &(d, a, _) in uses {
            match d {
                Dst::Quads => quads.set(a, sample),
                Dst::Subfaces => subfaces.set(a, sample),
                Dst::Halo | Dst::Unevaluated => {}
            }
        }
    }
    let quads = quads.finish();
    if !blocks.iter().any(|b| b.corner.is_some()) {
        return Ok(super::Output::Grid(quads));
    }
    Ok(super::Output::Polygons(PolygonGrids {
        quads,
        subfaces: subfaces.finish(),
        corners,
        boundary_open_edges: 0,
    }))
}

/// Cell and local index of grid line `i` of a block grid at level `l`
/// whose depth cuts it into `side` cells, each run at level `m`
/// ([`depth_cap`]: `m·side = l`, or `m = 1` and `l` divides `side`).
fn leaf_coord(i: usize, l: usize, m: usize, side: usize) -> (usize, usize) {
    let t = i * side;
    let x = (t / l.max(1)).min(side - 1);
    (x, (t - x * l) * m / l.max(1))
}

#[derive(Default)]
struct GridBuilder {
    level: u32,
    ids: Vec<u32>,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
}

impl GridBuilder {
    /// Appends a sample; returns its index.
    fn push(&mut self, (p, n): (Vec3, Vec3)) -> usize {
        self.positions.push(p);
        self.normals.push(n);
        self.positions.len() - 1
    }

    fn get(&self, at: usize) -> (Vec3, Vec3) {
        (self.positions[at], self.normals[at])
    }

    fn set(&mut self, at: usize, (p, n): (Vec3, Vec3)) {
        self.positions[at] = p;
        self.normals[at] = n;
    }

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
        crate::check::obj::obj_text(|stream| self.write_obj(stream))
    }

    /// Every grid in base face order, `(face, corner, is a sub-face, grid)`:
    /// base quads (corner 0) and sub-faces by base face, then corner — the
    /// order of every writer, so chunks in base-block windows concatenate
    /// to the whole.
    pub(crate) fn base_order(&self) -> Vec<(u32, u32, bool, usize)> {
        let mut order: Vec<(u32, u32, bool, usize)> = (0..self.quads.faces)
            .map(|g| (self.quads.face_of(g) as u32, 0, false, g))
            .chain(
                (0..self.subfaces.faces)
                    .map(|g| (self.subfaces.face_of(g) as u32, self.corners[g], true, g)),
            )
            .collect();
        order.sort_unstable();
        order
    }

    /// [`PolygonGrids::to_obj`] appended to an OBJ stream (the header with
    /// the stream's first chunk, vertex indices continuing across chunks),
    /// so a streamed refined result is byte for byte the whole one.
    pub fn write_obj<W: std::io::Write>(
        &self,
        stream: &mut crate::check::obj::ObjStream<W>,
    ) -> std::io::Result<()> {
        let header = format!(
            "# tessgen {} level {} (n-gon sub-faces at level {})",
            env!("CARGO_PKG_VERSION"),
            self.quads.level.max(2 * self.subfaces.level),
            self.subfaces.level
        );
        let order = self.base_order();
        let (quad_tris, sub_tris) = (
            self.quads.local_triangles(),
            self.subfaces.local_triangles(),
        );
        stream.write_patches(
            &header,
            order.into_iter().map(|(face, corner, sub, g)| {
                let t = if sub { &self.subfaces } else { &self.quads };
                let per = t.grid_len();
                let name = if sub {
                    format!("patch_{face}_{corner}")
                } else {
                    format!("patch_{face}")
                };
                let tris = if sub { &sub_tris[..] } else { &quad_tris[..] };
                (
                    name,
                    &t.positions[g * per..(g + 1) * per],
                    &t.normals[g * per..(g + 1) * per],
                    tris,
                )
            }),
        )
    }
}
