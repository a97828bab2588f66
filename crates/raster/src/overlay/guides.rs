//! Guides: a ground grid under the scene and the world's axes in a corner.

use glam::{Vec2, Vec3};

use super::LineStyle;
use super::line::{Depth, draw_clipped, draw_line};
use crate::{Camera, DrawItem, Framebuffer};

/// The most lines a grid has on each side of its centre, whatever the scene's proportions.
const MAX_HALF_LINES: i32 = 100;

/// A square grid of lines on a horizontal plane (world `y` is up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// The plane's height.
    pub y: f32,
    /// The centre, on a line crossing (world `x` and `z`).
    pub center: Vec2,
    /// Distance between neighbouring lines.
    pub spacing: f32,
    /// Lines on each side of the centre, in both directions.
    pub half_lines: i32,
}

impl Grid {
    /// A grid under everything `draws` holds: on the plane of its lowest point, centred
    /// under it, with lines a round distance apart (1, 2 or 5 times a power of ten) giving
    /// about eight cells across its wider horizontal side, and a cell to spare at each
    /// border. `None` when no draw has a finite vertex.
    #[must_use]
    pub fn under(draws: &[DrawItem]) -> Option<Grid> {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for d in draws {
            for p in d.mesh.positions {
                let w = d.model.transform_point3(*p);
                if w.is_finite() {
                    lo = lo.min(w);
                    hi = hi.max(w);
                }
            }
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        let size = hi - lo;
        let across = size.x.max(size.z).max(size.y).max(1e-6);
        let spacing = round_step(across / 8.0);
        let middle = (lo + hi) * 0.5;
        let center = (Vec2::new(middle.x, middle.z) / spacing).round() * spacing;
        let reach = (Vec2::new(size.x, size.z) * 0.5
            + (Vec2::new(middle.x, middle.z) - center).abs())
        .max_element();
        let half_lines = ((reach / spacing).ceil() as i32 + 1).clamp(1, MAX_HALF_LINES);
        Some(Grid {
            y: lo.y,
            center,
            spacing,
            half_lines,
        })
    }

    /// Draws the grid's lines over `fb` as seen by `camera`, depth-tested (objects hide the
    /// grid behind them; a floor at the grid's height shows it). Returns the pixels written;
    /// nothing for a grid whose values are not finite and positive.
    pub fn draw(&self, fb: &mut Framebuffer, camera: &Camera, style: LineStyle) -> u64 {
        if !(self.y.is_finite()
            && self.center.is_finite()
            && self.spacing.is_finite()
            && self.spacing > 0.0)
        {
            return 0;
        }
        let vp = camera.view_proj(fb.width() as f32 / fb.height() as f32);
        let n = self.half_lines.clamp(0, MAX_HALF_LINES);
        let reach = n as f32 * self.spacing;
        let at = |x: f32, z: f32| vp * Vec3::new(x, self.y, z).extend(1.0);
        let (cx, cz) = (self.center.x, self.center.y);
        let mut written = 0;
        for i in -n..=n {
            let offset = i as f32 * self.spacing;
            // A line along z at this x, and one along x at this z.
            written += draw_clipped(
                fb,
                at(cx + offset, cz - reach),
                at(cx + offset, cz + reach),
                style,
                Depth::Tested,
            );
            written += draw_clipped(
                fb,
                at(cx - reach, cz + offset),
                at(cx + reach, cz + offset),
                style,
                Depth::Tested,
            );
        }
        written
    }
}

/// The smallest of 1, 2 or 5 times a power of ten that is at least `v` (positive, finite).
fn round_step(v: f32) -> f32 {
    let power = 10f32.powf(v.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * power)
        .find(|&s| s >= v * (1.0 - 1e-6))
        .unwrap_or(10.0 * power)
}

/// The colours of the axes' lines: x red, y green, z blue (linear RGB).
pub const AXIS_COLORS: [Vec3; 3] = [
    Vec3::new(0.9, 0.1, 0.1),
    Vec3::new(0.1, 0.75, 0.1),
    Vec3::new(0.15, 0.3, 1.0),
];

/// Draws the world's `x`, `y` and `z` axes (red, green, blue) as a triad in the lower-left
/// corner of `fb`, turned as `camera` sees them (its rotation only, so the triad keeps its
/// size and place as the view moves), over everything, the axis pointing most towards the
/// viewer last. Returns the pixels written.
pub fn axes(fb: &mut Framebuffer, camera: &Camera, smooth: bool) -> u64 {
    let view = camera.view();
    let side = fb.width().min(fb.height()) as f32;
    let length = (side * 0.06).max(6.0);
    let origin = Vec3::new(length * 1.5, fb.height() as f32 - length * 1.5, 0.0);
    let mut dirs: Vec<(Vec3, Vec3)> = (0..3)
        .map(|i| (view.transform_vector3(Vec3::AXES[i]), AXIS_COLORS[i]))
        .collect();
    // The view's z points at the viewer: draw the farthest first.
    dirs.sort_by(|a, b| a.0.z.total_cmp(&b.0.z));
    let mut written = 0;
    for (d, color) in dirs {
        let d = if d.is_finite() { d } else { Vec3::ZERO };
        let tip = origin + Vec3::new(d.x, -d.y, 0.0) * length;
        written += draw_line(fb, origin, tip, LineStyle { color, smooth }, Depth::OnTop);
    }
    written
}
