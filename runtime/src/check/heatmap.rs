//! Heat maps: a tessellated surface coloured by a per-sample value (a
//! scheme's [`super::accuracy::Deviation`] from the Catmull-Clark limit),
//! rasterised on the CPU, with a colour bar — what `tessgen compare
//! --heatmap` writes and `docs/accuracy.md` shows.
//!
//! A small z-buffered triangle rasteriser rather than the wgpu renderer:
//! the values live on the limit samples' grid (level `n − 1`, a few
//! thousand triangles), the picture must be the same on every machine (no
//! GPU, no driver: `scripts/heatmaps.sh` regenerates the docs' images), and
//! the colour is interpolated from the samples' own values, never
//! re-evaluated.
//! Colours: the viridis ramp (perceptually uniform, legible in grey and to
//! colour-blind readers), from 0 at the bottom to the map's maximum at the
//! top, Lambert-shaded by the scheme's own normals so the shape stays
//! readable; samples without a value are grey.

use crate::camera::Camera;
use crate::cpu::Tessellation;
use glam::{Vec3, Vec4};

/// An RGB8 image, row-major from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

/// What the colour bar says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unit {
    /// % of the local quad size.
    Percent,
    /// Degrees.
    Degrees,
}

/// The `q`-quantile (0..1) of the finite values of all `fields`: a
/// colour range shared by several schemes' maps that one outlier sample
/// (a tiny face whose own size makes its percentage large) does not
/// flatten.
pub fn quantile<'a>(fields: impl IntoIterator<Item = &'a [f64]>, q: f64) -> f64 {
    let mut all: Vec<f64> = fields
        .into_iter()
        .flat_map(|f| f.iter().copied().filter(|x| x.is_finite()))
        .collect();
    if all.is_empty() {
        return 0.0;
    }
    all.sort_by(f64::total_cmp);
    let i = ((all.len() - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize;
    all[i]
}

/// How to draw a heat map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatOptions {
    pub width: u32,
    pub height: u32,
    /// The value at the top of the ramp (values above it saturate).
    pub max: f64,
    pub unit: Unit,
    /// Direction from the surface's centre towards the eye.
    pub view: Vec3,
}

/// Width of the colour bar's column at the right of the image.
const BAR_COLUMN: u32 = 112;

/// `grid` coloured by `values` (one per sample of `grid`), seen from
/// `opts.view`, with a colour bar from 0 to `opts.max`.
pub fn render(grid: &Tessellation, values: &[f64], opts: &HeatOptions) -> Image {
    let (w, h) = (opts.width.max(BAR_COLUMN + 16), opts.height.max(64));
    let mut img = Image {
        width: w,
        height: h,
        rgb: vec![255; (w * h * 3) as usize],
    };
    let plot_w = w - BAR_COLUMN;
    let mut depth = vec![f32::INFINITY; (plot_w * h) as usize];
    let (lo, hi) = grid.positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    if lo.x.is_finite() && hi.x.is_finite() {
        let center = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-6);
        let fov_y = 35.0f32;
        let dist = radius / (fov_y.to_radians() * 0.5).sin() * 0.95;
        let eye = center + opts.view.normalize_or(Vec3::Z) * dist;
        let up = if opts.view.normalize_or(Vec3::Z).cross(Vec3::Y).length() < 1e-3 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let camera = Camera {
            eye,
            target: center,
            up,
            fov_y,
        };
        let vp = camera.view_proj(plot_w as f32 / h as f32);
        let light = (eye - center).normalize_or(Vec3::Z);
        let per = grid.grid_len();
        let local = grid.local_triangles();
        let screen = |p: Vec3| {
            let c = vp * Vec4::new(p.x, p.y, p.z, 1.0);
            let n = c.truncate() / c.w;
            Vec3::new(
                (n.x * 0.5 + 0.5) * plot_w as f32,
                (0.5 - n.y * 0.5) * h as f32,
                n.z,
            )
        };
        for g in 0..grid.faces {
            let base = g * per;
            for t in &local {
                let k = t.map(|i| base + i as usize);
                let s = k.map(|i| screen(grid.positions[i]));
                let shade = k.map(|i| 0.35 + 0.65 * grid.normals[i].dot(light).abs());
                let v = k.map(|i| values.get(i).copied().unwrap_or(f64::NAN));
                raster(&mut img, &mut depth, plot_w, s, |b| {
                    let val = b[0] as f64 * v[0] + b[1] as f64 * v[1] + b[2] as f64 * v[2];
                    let light = b[0] * shade[0] + b[1] * shade[1] + b[2] * shade[2];
                    let c = if val.is_nan() {
                        [170.0, 170.0, 170.0]
                    } else {
                        viridis(if opts.max > 0.0 { val / opts.max } else { 0.0 })
                    };
                    c.map(|x| (x * light.clamp(0.0, 1.0)).round() as u8)
                });
            }
        }
    }
    colour_bar(&mut img, plot_w, opts);
    img
}

/// Fill triangle `s` (screen x, y, depth) where it is nearest, colouring
/// each covered pixel centre by `colour(barycentric weights)`.
fn raster(
    img: &mut Image,
    depth: &mut [f32],
    plot_w: u32,
    s: [Vec3; 3],
    colour: impl Fn([f32; 3]) -> [u8; 3],
) {
    let area = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y);
    if area.abs() < 1e-12 || !area.is_finite() {
        return;
    }
    let x0 = s
        .iter()
        .map(|p| p.x)
        .fold(f32::INFINITY, f32::min)
        .floor()
        .max(0.0) as u32;
    let x1 = (s
        .iter()
        .map(|p| p.x)
        .fold(f32::NEG_INFINITY, f32::max)
        .ceil() as i64)
        .clamp(0, plot_w as i64 - 1) as u32;
    let y0 = s
        .iter()
        .map(|p| p.y)
        .fold(f32::INFINITY, f32::min)
        .floor()
        .max(0.0) as u32;
    let y1 = (s
        .iter()
        .map(|p| p.y)
        .fold(f32::NEG_INFINITY, f32::max)
        .ceil() as i64)
        .clamp(0, img.height as i64 - 1) as u32;
    let edge = |a: Vec3, b: Vec3, x: f32, y: f32| (b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y);
    for y in y0..=y1 {
        for x in x0..=x1 {
            let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
            let b = [
                edge(s[1], s[2], px, py) / area,
                edge(s[2], s[0], px, py) / area,
                edge(s[0], s[1], px, py) / area,
            ];
            if b.iter().any(|&w| w < -1e-6) {
                continue;
            }
            let z = b[0] * s[0].z + b[1] * s[1].z + b[2] * s[2].z;
            let di = (y * plot_w + x) as usize;
            if z.is_nan() || z >= depth[di] || !(0.0..=1.0).contains(&z) {
                continue;
            }
            depth[di] = z;
            let o = ((y * img.width + x) * 3) as usize;
            img.rgb[o..o + 3].copy_from_slice(&colour(b));
        }
    }
}

/// The viridis ramp at `t` (clamped to 0..1), as 0..255 floats.
pub fn viridis(t: f64) -> [f32; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [68.0, 1.0, 84.0],
        [59.0, 82.0, 139.0],
        [33.0, 145.0, 140.0],
        [94.0, 201.0, 98.0],
        [253.0, 231.0, 37.0],
    ];
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) } as f32 * 4.0;
    let i = (t.floor() as usize).min(3);
    let f = t - i as f32;
    std::array::from_fn(|c| STOPS[i][c] * (1.0 - f) + STOPS[i + 1][c] * f)
}

/// The colour bar and its three labels (0, half, max) in the right column.
fn colour_bar(img: &mut Image, plot_w: u32, opts: &HeatOptions) {
    let (top, bottom) = (24u32, img.height.saturating_sub(24));
    let (x0, x1) = (plot_w + 8, plot_w + 24);
    for y in top..bottom {
        let t = 1.0 - (y - top) as f64 / (bottom - top).max(1) as f64;
        let c = viridis(t).map(|x| x.round() as u8);
        for x in x0..x1 {
            let o = ((y * img.width + x) * 3) as usize;
            img.rgb[o..o + 3].copy_from_slice(&c);
        }
    }
    let unit = match opts.unit {
        Unit::Percent => '%',
        Unit::Degrees => '°',
    };
    for (frac, y) in [(0.0, bottom), (0.5, (top + bottom) / 2), (1.0, top)] {
        let v = opts.max * frac;
        let text = format!("{v:.2}{unit}");
        text_at(img, x1 + 6, y.saturating_sub(7), &text);
    }
}

/// `text` (digits, `.`, `%`, `°`) in a 5 × 7 pixel font at twice its size,
/// its top left at `(x, y)`.
fn text_at(img: &mut Image, x: u32, y: u32, text: &str) {
    let mut cx = x;
    for ch in text.chars() {
        let rows = glyph(ch);
        for (r, bits) in rows.iter().enumerate() {
            for c in 0..5u32 {
                if bits & (0b10000 >> c) == 0 {
                    continue;
                }
                for (dy, dx) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    let (px, py) = (cx + 2 * c + dx, y + 2 * r as u32 + dy);
                    if px < img.width && py < img.height {
                        let o = ((py * img.width + px) * 3) as usize;
                        img.rgb[o..o + 3].copy_from_slice(&[0, 0, 0]);
                    }
                }
            }
        }
        cx += 12;
    }
}

/// Rows of a 5 × 7 glyph (bit 4 the leftmost column).
fn glyph(ch: char) -> [u8; 7] {
    match ch {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        '.' => [0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C],
        '%' => [0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03],
        '°' => [0x0C, 0x12, 0x12, 0x0C, 0x00, 0x00, 0x00],
        _ => [0; 7],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat_grid() -> Tessellation {
        // One quad patch at level 2 in the z = 0 plane, normals +z.
        let positions: Vec<Vec3> = (0..9)
            .map(|s| Vec3::new((s % 3) as f32, (s / 3) as f32, 0.0))
            .collect();
        Tessellation {
            level: 2,
            faces: 1,
            sides: 4,
            normals: vec![Vec3::Z; 9],
            positions,
            face_ids: Vec::new(),
        }
    }

    fn opts(max: f64) -> HeatOptions {
        HeatOptions {
            width: 320,
            height: 200,
            max,
            unit: Unit::Percent,
            view: Vec3::Z,
        }
    }

    /// The ramp's ends, and values mapped through it: a zero field is the
    /// ramp's bottom colour where the surface is, a field at the maximum its
    /// top colour; the colour bar is drawn either way.
    #[test]
    fn values_map_through_the_ramp() {
        assert_eq!(viridis(0.0), [68.0, 1.0, 84.0]);
        assert_eq!(viridis(1.0), [253.0, 231.0, 37.0]);
        assert_eq!(viridis(7.0), viridis(1.0));
        let g = flat_grid();
        let count = |img: &Image, c: [u8; 3]| img.rgb.chunks_exact(3).filter(|p| *p == c).count();
        // Seen head on, |n·l| = 1: the colour is the ramp's own.
        let zero = render(&g, &[0.0; 9], &opts(1.0));
        let full = render(&g, &[1.0; 9], &opts(1.0));
        assert!(
            count(&zero, [68, 1, 84]) > 1000,
            "the surface in the bottom colour"
        );
        assert!(
            count(&full, [253, 231, 37]) > 1000,
            "the surface in the top colour"
        );
        assert_ne!(zero.rgb, full.rgb);
        // No value: grey.
        let none = render(&g, &[f64::NAN; 9], &opts(1.0));
        assert!(count(&none, [170, 170, 170]) > 1000);
        assert_eq!(none.rgb.len(), (320 * 200 * 3) as usize);
    }

    #[test]
    fn quantiles_skip_non_finite_values() {
        let a = [0.0, 1.0, 2.0, f64::NAN];
        let b = [3.0, 4.0];
        assert_eq!(quantile([&a[..], &b[..]], 1.0), 4.0);
        assert_eq!(quantile([&a[..], &b[..]], 0.0), 0.0);
        assert_eq!(quantile([&a[..], &b[..]], 0.5), 2.0);
        assert_eq!(quantile([&[f64::NAN][..]], 0.5), 0.0);
    }
}
