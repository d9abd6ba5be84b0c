//! Construction per deformation: the vertex and patch stages for new
//! positions on a topology that does not change.
//!
//! Everything that depends only on the topology and the scheme — each
//! face's class, the control-point and vertex-output offsets, the flat
//! corner arrays, the parallel work split — is computed once in
//! [`Construction::new`]; [`Construction::update`] then reruns only the
//! vertex and patch stages, writing into the [`Patches`] buffers in place.
//! Smooth vertices run the flat vertex stage (`super::vertex_flat`: the
//! generated sums, per-valence work done once, eight vertices of a valence
//! at once); faces whose kernel only copies vertex outputs run a
//! pre-indexed copy (`super::patch_flat`); crease/corner vertices and
//! every other face run the generated kernels. Every value is summed in the
//! generated order, so the control points are bit-identical to
//! [`super::construct()`]'s (tests/tests/grid_path.rs).
//!
//! A smooth vertex computes only the rows some face reads (`rows_read`):
//! where all its faces are ordinary, PCCM's and ACC's `t` and Gregory's
//! `r` rows (4 of 13 at valence 4) are skipped: 1–6 % of the
//! construction's time on `righthanded_L3` (docs/performance-log.md).

use super::patch_flat::GatherPlan;
use super::vertex_flat::{FlatVertexStage, Scratch};
use super::{corner_arrays, face_classes, facet_error, vertex_out_offsets, Patches, TessError};
use crate::kernels::{self, common::Inputs, common::SchemeKernels};
use crate::mesh::topology::Topology;
use glam::Vec3;
use rayon::prelude::*;

/// Vertices (faces) per parallel task: large enough that rayon's per-task
/// cost vanishes, small enough to balance two to many cores.
const BLOCK: usize = 512;

/// The topology-only part of the construction of one scheme on one mesh.
#[derive(Clone, Debug)]
pub struct Construction<'t> {
    topo: &'t Topology,
    scheme: &'static SchemeKernels,
    face_class: Vec<u32>,
    cp_offsets: Vec<u32>,
    vertex_out_offsets: Vec<u32>,
    corner_vertex: Vec<u32>,
    corner_sector: Vec<u32>,
    /// The smooth vertices' stage with per-valence work done once, per
    /// block of `BLOCK` vertices.
    flat: FlatVertexStage,
    /// The faces whose control points are copies of vertex outputs.
    gather: GatherPlan,
    /// Per vertex: how many of its first vertex-stage rows some face reads
    /// ([`rows_read`]); the rest are not computed.
    read: Vec<u32>,
}

impl<'t> Construction<'t> {
    /// Classes, offsets and corner arrays of `topo` for `scheme` (a quad
    /// scheme).
    pub fn new(topo: &'t Topology, scheme: &'static SchemeKernels) -> Result<Self, TessError> {
        if scheme.sides != 4 {
            return Err(facet_error(scheme));
        }
        let face_class = face_classes(topo, scheme)?;
        let (cp_offsets, _) = super::control_point_offsets(&face_class, scheme);
        let (vertex_out_offsets, _) = vertex_out_offsets(topo, scheme);
        let (corner_vertex, corner_sector) = corner_arrays(topo);
        let vertex_outputs = vertex_out_offsets.last().copied().unwrap_or(0) as usize;
        let zeros = vec![Vec3::ZERO; topo.valence.len()];
        let gather = GatherPlan::new(
            &inputs(
                topo,
                &vertex_out_offsets,
                &corner_vertex,
                &corner_sector,
                &zeros,
                &[],
            ),
            scheme,
            &face_class,
            &cp_offsets,
            vertex_outputs,
        );
        let read = rows_read(&vertex_out_offsets, &corner_vertex, &gather);
        let flat = FlatVertexStage::new(
            topo,
            scheme,
            kernels::table(),
            &vertex_out_offsets,
            BLOCK,
            &read,
        );
        let c = Construction {
            topo,
            scheme,
            face_class,
            cp_offsets,
            vertex_out_offsets,
            corner_vertex,
            corner_sector,
            flat,
            gather,
            read,
        };
        Ok(c)
    }

    /// This construction with the baseline copies of the vertex stage's
    /// lane loops and of the patch copy even where AVX2 is available, so
    /// the tests check both copies give the same bits.
    #[doc(hidden)]
    pub fn with_baseline_lanes(mut self) -> Self {
        self.flat.force_baseline();
        self.gather.force_baseline();
        self
    }

    /// Whether [`Construction::update`] writes entry `entry` of
    /// `vertex_out`. It skips the rows no face reads (see `rows_read`):
    /// they hold 0 after [`Construction::construct`] and are never
    /// updated, where [`super::construct()`] computes them. Every control
    /// point is written.
    pub fn writes_vertex_out(&self, entry: usize) -> bool {
        let offsets = &self.vertex_out_offsets;
        if entry >= offsets.last().copied().unwrap_or(0) as usize {
            return false;
        }
        let v = offsets.partition_point(|&o| o as usize <= entry) - 1;
        !self.flat.covers(self.topo, v) || entry - (offsets[v] as usize) < self.read[v] as usize
    }

    /// Fresh [`Patches`] for `positions` (allocates the buffers once).
    pub fn construct(&self, positions: &[Vec3]) -> Patches {
        let vertices = self.vertex_out_offsets.last().copied().unwrap_or(0) as usize;
        let points = self.cp_offsets.last().copied().unwrap_or(0) as usize;
        let mut patches = Patches {
            scheme: self.scheme,
            face_class: self.face_class.clone(),
            cp_offsets: self.cp_offsets.clone(),
            control_points: vec![Vec3::ZERO; points],
            vertex_out_offsets: self.vertex_out_offsets.clone(),
            vertex_out: vec![Vec3::ZERO; vertices],
        };
        self.update_buffers(
            positions,
            &mut patches.vertex_out,
            &mut patches.control_points,
        );
        patches
    }

    /// Reruns the vertex and patch stages for new `positions` (one per mesh
    /// vertex) into `patches`, which must come from [`Construction::construct`]
    /// of this construction (same scheme and layout; checked).
    pub fn update(&self, positions: &[Vec3], patches: &mut Patches) -> Result<(), TessError> {
        let total = |o: &[u32]| o.last().copied().unwrap_or(0) as usize;
        let same = std::ptr::eq(patches.scheme, self.scheme)
            && patches.cp_offsets == self.cp_offsets
            && patches.vertex_out_offsets == self.vertex_out_offsets
            && patches.vertex_out.len() == total(&self.vertex_out_offsets)
            && patches.control_points.len() == total(&self.cp_offsets);
        if !same || positions.len() < self.topo.valence.len() {
            return Err(TessError::Layout);
        }
        self.update_buffers(
            positions,
            &mut patches.vertex_out,
            &mut patches.control_points,
        );
        Ok(())
    }

    fn inputs<'a>(&'a self, positions: &'a [Vec3], vertex_out: &'a [Vec3]) -> Inputs<'a> {
        inputs(
            self.topo,
            &self.vertex_out_offsets,
            &self.corner_vertex,
            &self.corner_sector,
            positions,
            vertex_out,
        )
    }

    fn update_buffers(
        &self,
        positions: &[Vec3],
        vertex_out: &mut [Vec3],
        control_points: &mut [Vec3],
    ) {
        let scheme = self.scheme;
        {
            let inputs = self.inputs(positions, &[]);
            let offsets = &self.vertex_out_offsets;
            blocks(vertex_out, offsets).for_each_init(Scratch::new, |scratch, (first, out)| {
                let b = first / BLOCK;
                self.flat.block(b, positions, out, scratch);
                let base = offsets[first];
                for &v in self.flat.kernel_vertices(b) {
                    (scheme.vertex_stage)(&inputs, out, v, offsets[v as usize] - base);
                }
            });
        }
        let inputs = self.inputs(positions, vertex_out);
        let offsets = &self.cp_offsets;
        let classes = &self.face_class;
        let flat = &self.gather.flat;
        blocks(control_points, offsets).for_each(|(first, out)| {
            let base = offsets[first];
            let last = (first + BLOCK).min(offsets.len() - 1);
            let mut f = first;
            while f < last {
                if flat[f] {
                    // A run of copied faces: one tight loop over its
                    // control points.
                    let g = (f..last).find(|&g| !flat[g]).unwrap_or(last);
                    let (a, b) = (offsets[f] as usize, offsets[g] as usize);
                    let dst = &mut out[a - base as usize..b - base as usize];
                    self.gather.copy(a, b, vertex_out, dst);
                    f = g;
                } else {
                    let patch = scheme.classes[classes[f] as usize].patch;
                    patch(&inputs, out, f as u32, offsets[f] - base);
                    f += 1;
                }
            }
        });
    }
}

/// The kernels' inputs over a topology and its construction arrays (the
/// table is the built-in one; every other input empty).
pub(super) fn inputs<'a>(
    topo: &'a Topology,
    vertex_out_offsets: &'a [u32],
    corner_vertex: &'a [u32],
    corner_sector: &'a [u32],
    positions: &'a [Vec3],
    vertex_out: &'a [Vec3],
) -> Inputs<'a> {
    Inputs {
        positions,
        valence: &topo.valence,
        ring_offsets: &topo.ring_offsets,
        ring: &topo.ring,
        vertex_out_offsets,
        vertex_out,
        corner_vertex,
        corner_sector,
        vertex_sectors: &topo.vertex_sectors,
        sectors: &topo.sectors,
        corner_valence: &topo.corner_valence,
        table: kernels::table(),
        ..Default::default()
    }
}

/// Per vertex: how many of its first rows (its `vertex_out` entries, in
/// order) some face reads. A face that runs its generated kernel may read
/// any row of its corners (a patch kernel reads the outputs of its own
/// corners only: the scheme language's `v(i)`, `e(i, k)`, …), so its
/// corners get every row; a flat face reads exactly the entries it copies.
/// On an all-ordinary neighbourhood that is PCCM's and Gregory's `f`, `e`
/// and `v` (the first `2n + 1` rows), not PCCM's `t` or Gregory's `r`.
fn rows_read(vertex_out_offsets: &[u32], corner_vertex: &[u32], gather: &GatherPlan) -> Vec<u32> {
    let vertices = vertex_out_offsets.len().saturating_sub(1);
    let rows = |v: usize| vertex_out_offsets[v + 1] - vertex_out_offsets[v];
    let mut read = vec![0u32; vertices];
    let faces = gather.flat.len();
    let corners = corner_vertex.len().checked_div(faces).unwrap_or(0);
    for (f, &flat) in gather.flat.iter().enumerate() {
        if !flat {
            for &v in &corner_vertex[f * corners..(f + 1) * corners] {
                if let Some(r) = read.get_mut(v as usize) {
                    *r = rows(v as usize);
                }
            }
        }
    }
    for j in gather.sources() {
        // The vertex whose entries hold `j`.
        let v = vertex_out_offsets.partition_point(|&o| o <= j) - 1;
        if let Some(r) = read.get_mut(v) {
            *r = (*r).max(j - vertex_out_offsets[v] + 1);
        }
    }
    read
}

/// `data` split at every `BLOCK`-th entry of `offsets` (len items + 1), as
/// a parallel iterator of (first item, its block's slice).
fn blocks<'a>(
    data: &'a mut [Vec3],
    offsets: &'a [u32],
) -> impl ParallelIterator<Item = (usize, &'a mut [Vec3])> + 'a {
    let items = offsets.len().saturating_sub(1);
    let mut slices = Vec::with_capacity(items.div_ceil(BLOCK));
    let mut rest = data;
    let mut first = 0;
    while first < items {
        let last = (first + BLOCK).min(items);
        let (head, tail) = rest.split_at_mut((offsets[last] - offsets[first]) as usize);
        slices.push((first, head));
        rest = tail;
        first = last;
    }
    slices.into_par_iter()
}
