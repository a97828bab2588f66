//! One line of an overlay: clipped, projected and drawn (the module's docs say how).

use glam::{Vec3, Vec4};

use super::{DEPTH_BIAS, LineStyle};
use crate::Framebuffer;
use crate::framebuffer::{FAR_DEPTH, clamp_color_to};

/// Whether a line hides behind what the frame drew.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Depth {
    /// Drawn where it is in front of the stored depth (within [`DEPTH_BIAS`]).
    Tested,
    /// Drawn over everything.
    OnTop,
}

/// Draws the clip-space segment `p q`: the part inside the view volume, if any. Returns the
/// pixels written.
pub(super) fn draw_clipped(
    fb: &mut Framebuffer,
    p: Vec4,
    q: Vec4,
    style: LineStyle,
    depth: Depth,
) -> u64 {
    match clip_segment(p, q) {
        Some((p, q)) => draw_line(fb, screen(fb, p), screen(fb, q), style, depth),
        None => 0,
    }
}

/// The part of segment `p q` inside the view volume `-w <= x, y, z <= w`, or `None` (Liang
/// and Barsky 1984, in homogeneous coordinates). A vertex that is not finite drops the segment.
pub(super) fn clip_segment(p: Vec4, q: Vec4) -> Option<(Vec4, Vec4)> {
    if !(p.is_finite() && q.is_finite()) {
        return None;
    }
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    let d = q - p;
    // Each plane as `w + s * c >= 0` for coordinate `c` (x, y, z) and sign `s`.
    for axis in 0..3 {
        for s in [1.0f32, -1.0] {
            let f0 = p.w + s * p[axis];
            let df = d.w + s * d[axis];
            if df == 0.0 {
                if f0 < 0.0 {
                    return None;
                }
            } else {
                let t = -f0 / df;
                if df > 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    Some((p + d * t0, p + d * t1))
}

/// A clip-space point inside the view volume on screen: pixels (y down) and normalised depth.
fn screen(fb: &Framebuffer, c: Vec4) -> Vec3 {
    let w = if c.w > 0.0 { c.w } else { f32::MIN_POSITIVE };
    Vec3::new(
        (c.x / w + 1.0) * 0.5 * fb.width() as f32,
        (1.0 - c.y / w) * 0.5 * fb.height() as f32,
        (c.z / w) * 0.5 + 0.5,
    )
}

/// Draws the line from `a` to `b` (screen pixels and normalised depth) one step per pixel
/// centre along the axis it spans more of; returns the pixels written. Points off the image
/// are skipped, so any finite input is safe.
pub(super) fn draw_line(
    fb: &mut Framebuffer,
    a: Vec3,
    b: Vec3,
    style: LineStyle,
    depth: Depth,
) -> u64 {
    if !(a.is_finite() && b.is_finite()) {
        return 0;
    }
    let color = clamp_color_to(
        style.color,
        if fb.hdr() {
            crate::framebuffer::HDR_MAX
        } else {
            1.0
        },
    );
    let (width, height) = (fb.width() as usize, fb.height() as usize);
    let d = b - a;
    // Step along the axis the line spans more of; `major` picks x (0) or y (1).
    let major = if d.x.abs() >= d.y.abs() { 0 } else { 1 };
    let (a, b) = if d[major] < 0.0 { (b, a) } else { (a, b) };
    let d = b - a;
    let span = d[major];
    let (major_limit, minor_limit) = if major == 0 {
        (width, height)
    } else {
        (height, width)
    };
    // Pixel centres `k + 0.5` within `[a, b]` along the major axis, inside the image.
    let first = (a[major] - 0.5).ceil().max(0.0);
    let last = (b[major] - 0.5).floor().min(major_limit as f32 - 1.0);
    let mut written = 0;
    let mut put = |k: f32, j: f32, z: f32, w: f32| {
        if w <= 0.0 || j < 0.0 || j >= minor_limit as f32 {
            return;
        }
        let (x, y) = if major == 0 {
            (k as usize, j as usize)
        } else {
            (j as usize, k as usize)
        };
        if depth == Depth::Tested {
            let stored = fb.depth_at(x as u32, y as u32);
            if !(z >= 0.0 && z <= stored + DEPTH_BIAS * (FAR_DEPTH - stored).max(0.0)) {
                return;
            }
        }
        fb.blend(x, y, color, w.min(1.0));
        written += 1;
    };
    let mut k = first;
    while k <= last {
        let t = if span > 0.0 {
            ((k + 0.5 - a[major]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let p = a + d * t;
        let minor = p[1 - major];
        if style.smooth {
            // The two pixel centres `j + 0.5` either side of the exact point.
            let s = minor - 0.5;
            let j0 = s.floor();
            let far = s - j0;
            put(k, j0, p.z, 1.0 - far);
            put(k, j0 + 1.0, p.z, far);
        } else {
            put(k, minor.floor(), p.z, 1.0);
        }
        k += 1.0;
    }
    written
}
