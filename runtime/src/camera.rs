//! A look-at perspective camera: the clip-from-world matrix every view of
//! a surface uses — the wgpu renderer's ([`crate::render`]), the CPU heat
//! maps' ([`crate::heatmap`]) and an engine example's.

use glam::{Mat4, Vec3};

/// A look-at perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y: f32,
}

impl Camera {
    /// A camera that frames the bounding box `lo..hi` from direction `dir`.
    pub fn framing(lo: Vec3, hi: Vec3, dir: Vec3) -> Camera {
        let center = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-6);
        let fov_y: f32 = 35.0;
        let dist = radius / (fov_y.to_radians() * 0.5).sin() * 0.8;
        Camera {
            eye: center + dir.normalize_or(Vec3::Z) * dist,
            target: center,
            up: Vec3::Y,
            fov_y,
        }
    }

    /// Column-major clip-from-world matrix (WebGPU depth range 0..1).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let dist = (self.eye - self.target).length().max(1e-6);
        let (near, far) = (dist * 0.01, dist * 10.0);
        // Right-handed view, perspective with depth 0..1 (WebGPU/Vulkan/D3D).
        let f = (self.target - self.eye).normalize_or(Vec3::NEG_Z);
        let s = f.cross(self.up).normalize_or(Vec3::X);
        let u = s.cross(f);
        let view = Mat4::from_cols(
            glam::Vec4::new(s.x, u.x, -f.x, 0.0),
            glam::Vec4::new(s.y, u.y, -f.y, 0.0),
            glam::Vec4::new(s.z, u.z, -f.z, 0.0),
            glam::Vec4::new(-s.dot(self.eye), -u.dot(self.eye), f.dot(self.eye), 1.0),
        );
        let h = 1.0 / (self.fov_y.to_radians() * 0.5).tan();
        let r = far / (near - far);
        let proj = Mat4::from_cols(
            glam::Vec4::new(h / aspect, 0.0, 0.0, 0.0),
            glam::Vec4::new(0.0, h, 0.0, 0.0),
            glam::Vec4::new(0.0, 0.0, r, -1.0),
            glam::Vec4::new(0.0, 0.0, r * near, 0.0),
        );
        proj * view
    }
}
