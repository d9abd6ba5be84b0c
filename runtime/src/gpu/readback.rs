//! The one readback scatter: samples the GPU wrote per patch (patches
//! sorted by facet class) back into per-face grids in face order.
//!
//! wgpu's `eval_main` and the Vulkan harness's captured tessellation (and
//! its compute `eval_main`) write the same layout: `SAMPLE_FLOATS` floats
//! per sample (position, normal), `spp` samples per patch, patches in
//! class-sorted order. Gathering them by `patch_faces` lived twice (gpu.rs
//! and vulkan.rs); a layout change now has one place to follow.
//!
//! A readback covers a *window* of consecutive faces (all of them for a
//! whole result, a bounded range for a streamed chunk): [`patch_runs`]
//! names the class-sorted patches of the window, at most two contiguous
//! runs per class, so a chunk in face order costs a few dispatches and
//! never a result-sized buffer.

use crate::cpu::Tessellation;
use crate::gpu::upload::ClassRange;
use glam::Vec3;
use std::ops::Range;

/// Floats per written sample: position then normal.
use crate::abi::SAMPLE_LEN as SAMPLE_FLOATS;

/// The class-sorted patches whose faces lie in `faces`, as ranges of patch
/// indices (into `patch_faces`), each inside one class (named by its index
/// in `classes`). Within a class the
/// emitting patches come first, then the holes, each run in face order
/// ([`crate::gpu::upload::class_layout`]), so a window of faces is at most
/// two contiguous runs per class.
pub(crate) fn patch_runs(
    patch_faces: &[u32],
    classes: &[ClassRange],
    faces: Range<usize>,
) -> Vec<(usize, Range<u64>)> {
    let mut runs = Vec::new();
    for (k, c) in classes.iter().enumerate() {
        let (first, emitting, end) = (
            c.first as usize,
            (c.first + c.emitting) as usize,
            (c.first + c.count) as usize,
        );
        for run in [first..emitting, emitting..end] {
            let Some(sorted) = patch_faces.get(run.clone()) else {
                continue;
            };
            let lo = run.start + sorted.partition_point(|&f| (f as usize) < faces.start);
            let hi = run.start + sorted.partition_point(|&f| (f as usize) < faces.end);
            if lo < hi {
                runs.push((k, lo as u64..hi as u64));
            }
        }
    }
    runs
}

/// Per-face grids of a window of faces being filled from chunks of patch
/// samples.
pub(crate) struct GridReadback {
    level: u32,
    sides: u32,
    faces: Range<usize>,
    spp: usize,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
}

impl GridReadback {
    /// Room for the grids of `faces` of `spp` samples each (unwritten
    /// samples stay zero, as both backends had it), or
    /// [`crate::cpu::TessError::OutOfMemory`].
    pub(crate) fn new(
        level: u32,
        sides: u32,
        faces: Range<usize>,
        spp: u64,
    ) -> Result<Self, crate::cpu::TessError> {
        let spp = spp as usize;
        let total = faces.len() * spp;
        let (mut positions, mut normals) = (Vec::new(), Vec::new());
        crate::cpu::reserve_samples(&mut positions, &mut normals, total)?;
        positions.resize(total, Vec3::ZERO);
        normals.resize(total, Vec3::ZERO);
        Ok(GridReadback {
            level,
            sides,
            faces,
            spp,
            positions,
            normals,
        })
    }

    /// Scatter `floats`, the samples of the consecutive patches starting at
    /// `first_patch` (class-sorted), to their faces' grids: patch `p` is
    /// face `patch_faces[p]`, which must lie in the window.
    pub(crate) fn scatter(&mut self, floats: &[f32], first_patch: u64, patch_faces: &[u32]) {
        let spp = self.spp as u64;
        for (i, s) in floats.chunks_exact(SAMPLE_FLOATS).enumerate() {
            let patch = first_patch + i as u64 / spp;
            let face = patch_faces[patch as usize] as usize - self.faces.start;
            let at = face * self.spp + (i as u64 % spp) as usize;
            self.positions[at] = Vec3::new(s[0], s[1], s[2]);
            self.normals[at] = Vec3::new(s[3], s[4], s[5]);
        }
    }

    /// The grids, [`crate::cpu::evaluate`]'s layout; a window that is not
    /// the whole mesh names its faces in `face_ids`, as
    /// [`crate::cpu::evaluate_faces_into`] does.
    pub(crate) fn finish(self, whole: bool) -> Tessellation {
        Tessellation {
            level: self.level,
            faces: self.faces.len(),
            sides: self.sides,
            positions: self.positions,
            normals: self.normals,
            face_ids: if whole {
                Vec::new()
            } else {
                self.faces.map(|f| f as u32).collect()
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Patch order is not face order: each patch's samples land in its
    /// face's grid, in sample order, whichever chunk brought them.
    #[test]
    fn scatters_class_sorted_patches_to_faces() {
        let mut r = GridReadback::new(1, 4, 0..2, 2).unwrap();
        // Patches [face 1, face 0], two samples each, read in two chunks.
        let floats: Vec<f32> = (0..24).map(|x| x as f32).collect();
        r.scatter(&floats[..12], 0, &[1, 0]);
        r.scatter(&floats[12..], 1, &[1, 0]);
        let t = r.finish(true);
        assert_eq!(t.faces, 2);
        assert_eq!(t.positions[2], Vec3::new(0.0, 1.0, 2.0));
        assert_eq!(t.normals[3], Vec3::new(9.0, 10.0, 11.0));
        assert_eq!(t.positions[0], Vec3::new(12.0, 13.0, 14.0));
        assert_eq!(t.normals[1], Vec3::new(21.0, 22.0, 23.0));
    }

    fn range(class: u32, first: u32, count: u32, emitting: u32) -> ClassRange {
        ClassRange {
            class,
            first,
            count,
            emitting,
            cp_base: 0,
            points: 16,
        }
    }

    /// A window of faces is each class's emitting run and hole run cut to
    /// the window; every patch of a face in the window is in exactly one
    /// run, and no other patch is.
    #[test]
    fn patch_runs_cover_exactly_the_window() {
        // Faces 0..8; class 0: faces 1 3 4 6 (6 a hole), class 1: 0 2 7 5
        // (5 a hole).
        let patch_faces = [1, 3, 4, 6, 0, 2, 7, 5];
        let classes = [range(0, 0, 4, 3), range(1, 4, 4, 3)];
        for lo in 0..=8 {
            for hi in lo..=8 {
                let runs = patch_runs(&patch_faces, &classes, lo..hi);
                let mut got: Vec<u64> = runs.iter().flat_map(|(_, r)| r.clone()).collect();
                got.sort_unstable();
                let want: Vec<u64> = (0..8u64)
                    .filter(|&p| (lo..hi).contains(&(patch_faces[p as usize] as usize)))
                    .collect();
                assert_eq!(got, want, "window {lo}..{hi}");
                for (k, r) in &runs {
                    let c = &classes[*k];
                    let inside = r.start >= c.first as u64 && r.end <= (c.first + c.count) as u64;
                    assert!(inside, "run {r:?} is not inside class {k}");
                }
            }
        }
        assert_eq!(
            patch_runs(&patch_faces, &classes, 3..7),
            vec![(0, 1..3), (0, 3..4), (1, 7..8)]
        );
    }

    /// A window's grids sit at `face − start` and name their faces.
    #[test]
    fn a_window_is_indexed_from_its_first_face() {
        let mut r = GridReadback::new(1, 4, 5..7, 1).unwrap();
        let floats: Vec<f32> = (0..12).map(|x| x as f32).collect();
        // Patches 2 and 3 are faces 6 and 5.
        r.scatter(&floats, 2, &[0, 1, 6, 5]);
        let t = r.finish(false);
        assert_eq!(t.face_ids, vec![5, 6]);
        assert_eq!(t.positions[1], Vec3::new(0.0, 1.0, 2.0));
        assert_eq!(t.positions[0], Vec3::new(6.0, 7.0, 8.0));
    }
}
