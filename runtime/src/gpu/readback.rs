//! The one readback scatter: samples the GPU wrote per patch (patches
//! sorted by facet class) back into per-face grids in face order.
//!
//! wgpu's `eval_main` and the Vulkan harness's captured tessellation (and
//! its compute `eval_main`) write the same layout: `SAMPLE_FLOATS` floats
//! per sample (position, normal), `spp` samples per patch, patches in
//! class-sorted order. Gathering them by `patch_faces` lived twice (gpu.rs
//! and vulkan.rs); a layout change now has one place to follow.

use crate::cpu::Tessellation;
use glam::Vec3;

/// Floats per written sample: position then normal.
use crate::abi::SAMPLE_LEN as SAMPLE_FLOATS;

/// Per-face grids being filled from chunks of patch samples.
pub(crate) struct GridReadback {
    level: u32,
    sides: u32,
    faces: usize,
    spp: usize,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
}

impl GridReadback {
    /// Room for `faces` grids of `spp` samples (unwritten samples stay zero,
    /// as both backends had it).
    pub(crate) fn new(level: u32, sides: u32, faces: usize, spp: u64) -> Self {
        let spp = spp as usize;
        GridReadback {
            level,
            sides,
            faces,
            spp,
            positions: vec![Vec3::ZERO; faces * spp],
            normals: vec![Vec3::ZERO; faces * spp],
        }
    }

    /// Scatter `floats`, the samples of the consecutive patches starting at
    /// `first_patch` (class-sorted), to their faces' grids: patch `p` is
    /// face `patch_faces[p]`.
    pub(crate) fn scatter(&mut self, floats: &[f32], first_patch: u64, patch_faces: &[u32]) {
        let spp = self.spp as u64;
        for (i, s) in floats.chunks_exact(SAMPLE_FLOATS).enumerate() {
            let patch = first_patch + i as u64 / spp;
            let face = patch_faces[patch as usize] as usize;
            let at = face * self.spp + (i as u64 % spp) as usize;
            self.positions[at] = Vec3::new(s[0], s[1], s[2]);
            self.normals[at] = Vec3::new(s[3], s[4], s[5]);
        }
    }

    /// The grids, [`crate::cpu::evaluate`]'s layout.
    pub(crate) fn finish(self) -> Tessellation {
        Tessellation {
            level: self.level,
            faces: self.faces,
            sides: self.sides,
            positions: self.positions,
            normals: self.normals,
            face_ids: Vec::new(),
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
        let mut r = GridReadback::new(1, 4, 2, 2);
        // Patches [face 1, face 0], two samples each, read in two chunks.
        let floats: Vec<f32> = (0..24).map(|x| x as f32).collect();
        r.scatter(&floats[..12], 0, &[1, 0]);
        r.scatter(&floats[12..], 1, &[1, 0]);
        let t = r.finish();
        assert_eq!(t.faces, 2);
        assert_eq!(t.positions[2], Vec3::new(0.0, 1.0, 2.0));
        assert_eq!(t.normals[3], Vec3::new(9.0, 10.0, 11.0));
        assert_eq!(t.positions[0], Vec3::new(12.0, 13.0, 14.0));
        assert_eq!(t.normals[1], Vec3::new(21.0, 22.0, 23.0));
    }
}
