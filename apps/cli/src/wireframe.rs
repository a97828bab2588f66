//! A wireframe overlay: every triangle edge drawn as a one-pixel line over a finished frame,
//! depth-tested against it, so that the edges of the surfaces seen show and those hidden
//! behind them do not (f3d's `-e`, and how the triangles behind Gouraud's Mach bands are
//! seen).
//!
//! Each edge shared by two triangles of a draw is drawn once. It is clipped to the view volume
//! in clip space (`-w <= x, y, z <= w`), projected as the triangles are, and drawn by columns
//! or rows, whichever it spans more of: one pixel per step, the one holding the line's exact
//! point at that column's (or row's) centre. Its depth at that point is interpolated along the
//! projected line (normalised depth is affine in screen space along a straight edge) and
//! passes where it is at most the stored depth plus [`DEPTH_BIAS`] times the distance left to
//! the far plane (`1 - stored`): a relative tolerance, since the stored depth is that of the
//! pixel's centre, up to half a pixel from the edge, and normalised depth crowds towards 1
//! with distance. The line's colour is then written into a copy of the frame's colours (the
//! framebuffer, its depth and so its coverage are left as drawn: over a background that is
//! not opaque, a line pixel off the geometry keeps the background's alpha). Nothing here
//! touches the shading: the overlay costs one pass over the edges after the frame.

use phosphor_math::glam::{Mat4, Vec3, Vec4};
use phosphor_raster::framebuffer::{FAR_DEPTH, clamp_color_to};
use phosphor_raster::{Camera, DrawItem, Framebuffer};

/// The depth tolerance of an edge, as a share of the distance from the stored depth to the far
/// plane in normalised depth (about 1% of the distance to the camera with a perspective
/// projection).
pub const DEPTH_BIAS: f32 = 0.01;

/// The colours of `fb` with the edges of every triangle of `draws` drawn over them, as seen
/// by `camera`, in `color` (clamped to `[0, 1]`, or to the framebuffer's wider range), and
/// the count of pixels written. Triangles with an index out of range are skipped, and so are
/// edges with a vertex that is not finite.
#[must_use]
pub fn overlay(
    fb: &Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    color: Vec3,
) -> (Vec<Vec3>, u64) {
    let ceiling = if fb.hdr() {
        phosphor_raster::framebuffer::HDR_MAX
    } else {
        1.0
    };
    let color = clamp_color_to(color, ceiling);
    let vp = camera.view_proj(fb.width() as f32 / fb.height() as f32);
    let mut target = Target {
        width: fb.width() as usize,
        height: fb.height() as usize,
        depth: fb.depth(),
        color: fb.color().to_vec(),
    };
    let mut written = 0;
    for d in draws {
        written += draw_edges(&mut target, vp * d.model, d, color);
    }
    (target.color, written)
}

/// The image the lines go into: the frame's depths, read only, and a copy of its colours.
struct Target<'a> {
    width: usize,
    height: usize,
    depth: &'a [f32],
    color: Vec<Vec3>,
}

/// The edges of one draw, each once (as its two vertex indices, smaller first).
fn edges(d: &DrawItem) -> Vec<(u32, u32)> {
    let n = d.mesh.positions.len() as u32;
    let mut edges: Vec<(u32, u32)> = d
        .mesh
        .indices
        .iter()
        .filter(|t| t.iter().all(|&i| i < n))
        .flat_map(|&[a, b, c]| [(a, b), (b, c), (c, a)])
        .filter(|(a, b)| a != b)
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

fn draw_edges(fb: &mut Target, mvp: Mat4, d: &DrawItem, color: Vec3) -> u64 {
    let clip: Vec<Vec4> = d
        .mesh
        .positions
        .iter()
        .map(|p| mvp * p.extend(1.0))
        .collect();
    let mut written = 0;
    for (a, b) in edges(d) {
        let (p, q) = (clip[a as usize], clip[b as usize]);
        if let Some((p, q)) = clip_segment(p, q) {
            written += draw_line(fb, screen(fb, p), screen(fb, q), color);
        }
    }
    written
}

/// The part of segment `p q` inside the view volume `-w <= x, y, z <= w`, or `None` (Liang
/// and Barsky 1984, in homogeneous coordinates). A vertex that is not finite drops the edge.
fn clip_segment(p: Vec4, q: Vec4) -> Option<(Vec4, Vec4)> {
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
fn screen(fb: &Target, c: Vec4) -> Vec3 {
    let w = if c.w > 0.0 { c.w } else { f32::MIN_POSITIVE };
    Vec3::new(
        (c.x / w + 1.0) * 0.5 * fb.width as f32,
        (1.0 - c.y / w) * 0.5 * fb.height as f32,
        (c.z / w) * 0.5 + 0.5,
    )
}

/// Draws the line from `a` to `b` (screen pixels and depth) one pixel per column or row,
/// depth-tested; returns the pixels written.
fn draw_line(fb: &mut Target, a: Vec3, b: Vec3, color: Vec3) -> u64 {
    let (width, height) = (fb.width, fb.height);
    let d = b - a;
    // Step along the axis the line spans more of; `major` picks x (0) or y (1).
    let major = if d.x.abs() >= d.y.abs() { 0 } else { 1 };
    let (a, b) = if d[major] < 0.0 { (b, a) } else { (a, b) };
    let d = b - a;
    let span = d[major];
    // Pixel centres `k + 0.5` within `[a, b]` along the major axis, inside the image.
    let limit = if major == 0 { width } else { height } as f32;
    let first = (a[major] - 0.5).ceil().max(0.0);
    let last = (b[major] - 0.5).floor().min(limit - 1.0);
    let mut written = 0;
    let mut k = first;
    while k <= last {
        let centre = k + 0.5;
        let t = if span > 0.0 {
            ((centre - a[major]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let p = a + d * t;
        let (x, y) = if major == 0 {
            (k, p.y.floor())
        } else {
            (p.x.floor(), k)
        };
        if x >= 0.0 && y >= 0.0 && (x as usize) < width && (y as usize) < height {
            let at = y as usize * width + x as usize;
            let stored = fb.depth[at];
            if p.z <= stored + DEPTH_BIAS * (FAR_DEPTH - stored).max(0.0) && p.z >= 0.0 {
                fb.color[at] = color;
                written += 1;
            }
        }
        k += 1.0;
    }
    written
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use phosphor_lighting::{Effects, Light, LightSet, Material};
    use phosphor_math::glam::{Mat4, Vec3};
    use phosphor_raster::{Camera, DrawItem, Framebuffer, MeshView, RenderOptions, ShadingMode};

    use super::overlay;

    /// A quad of two triangles (diagonal from `(x0, y1)` to `(x1, y0)`) at NDC depth `z`:
    /// positions, normals and triangles.
    fn quad(
        cam: &Camera,
        (w, h): (u32, u32),
        (x0, y0, x1, y1): (f64, f64, f64, f64),
        z: f64,
    ) -> (Vec<Vec3>, Vec<Vec3>, Vec<[u32; 3]>) {
        let inv = cam.view_proj(w as f32 / h as f32).as_dmat4().inverse();
        let p = |x: f64, y: f64| {
            let ndc = phosphor_math::glam::DVec4::new(
                x / f64::from(w) * 2.0 - 1.0,
                1.0 - y / f64::from(h) * 2.0,
                z,
                1.0,
            );
            let p = inv * ndc;
            (p.truncate() / p.w).as_vec3()
        };
        (
            vec![p(x0, y1), p(x1, y1), p(x1, y0), p(x0, y0)],
            vec![Vec3::Z; 4],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    fn item<'a>(
        m: &'a (Vec<Vec3>, Vec<Vec3>, Vec<[u32; 3]>),
        material: &'a Material,
        lights: &'a LightSet,
    ) -> DrawItem<'a> {
        DrawItem {
            mesh: MeshView::new(&m.0, &m.1, &m.2),
            model: Mat4::IDENTITY,
            material,
            lights,
            effects: Effects::DIFFUSE,
            mode: ShadingMode::Flat,
            bump: None,
            texture: None,
            cull_backfaces: false,
        }
    }

    #[test]
    fn edges_are_drawn_once_per_column_where_seen_and_hidden_behind_nearer_surfaces() {
        let cam = Camera::s1();
        let size = (64u32, 48u32);
        let lights = LightSet::new(
            Vec3::ZERO,
            &[Light::directional(-Vec3::Z, Vec3::splat(0.5)).unwrap()],
        );
        let material = Material::s1();
        // The back quad spans columns 8.5..56.5; the front one, nearer, covers its right half.
        let back = quad(&cam, size, (8.5, 8.5, 56.5, 40.5), 0.9);
        let front = quad(&cam, size, (36.2, 4.3, 60.7, 44.6), 0.5);
        let draws = [
            item(&back, &material, &lights),
            item(&front, &material, &lights),
        ];
        let opts = RenderOptions {
            threads: 1,
            ..RenderOptions::default()
        };
        let mut shaded = Framebuffer::new(size.0, size.1).unwrap();
        phosphor_raster::render(&mut shaded, &cam, &draws, &opts);
        let red = Vec3::new(1.0, 0.0, 0.0);
        let (wired, written) = overlay(&shaded, &cam, &draws, red);
        let at = |x: u32, y: u32| (y * size.0 + x) as usize;
        let is_red = |x: u32, y: u32| wired[at(x, y)] == red;
        // The back quad's top edge, row 8 (y = 8.5 lies on the border of rows 8 and 9: the
        // pixel holding it is row 8), from column 8 to where the front quad begins.
        for x in 9..35 {
            assert!(is_red(x, 8), "top edge at column {x}");
            assert!(
                !is_red(x, 7) && !is_red(x, 10),
                "one pixel thick at column {x}"
            );
        }
        // Its diagonal, from (8.5, 40.5) to (56.5, 8.5): one pixel per column (it spans more
        // columns than rows), in the row holding the exact point at the column's centre.
        for x in 9..35 {
            let t = (x as f64 + 0.5 - 8.5) / 48.0;
            let y = (40.5 - t * 32.0).floor() as u32;
            assert!(is_red(x, y), "diagonal at ({x}, {y})");
            let in_column = (0..size.1).filter(|&y| is_red(x, y)).count();
            assert_eq!(in_column, 3, "column {x}: top, diagonal and bottom edges");
        }
        // Behind the front quad the back quad's edges are hidden: in columns 38..56 its top and
        // bottom rows and its diagonal show only where the front quad's own diagonal crosses.
        let (mut top, mut bottom, mut diagonal) = (0, 0, 0);
        for x in 38..56 {
            top += usize::from(is_red(x, 8));
            bottom += usize::from(is_red(x, 40));
            let t = (x as f64 + 0.5 - 8.5) / 48.0;
            diagonal += usize::from(is_red(x, (40.5 - t * 32.0).floor() as u32));
            assert!(
                is_red(x, 4) && is_red(x, 44),
                "front quad's edges at column {x}"
            );
        }
        assert!(
            top <= 2 && bottom <= 2 && diagonal <= 2,
            "{top} {bottom} {diagonal}"
        );
        // Nothing but line pixels changed (a pixel two edges cross is written twice).
        let mut changed = 0;
        for y in 0..size.1 {
            for x in 0..size.0 {
                if wired[at(x, y)] != shaded.pixel(x, y) {
                    assert!(is_red(x, y), "({x}, {y})");
                    changed += 1;
                }
            }
        }
        assert!(
            changed > 100 && changed <= written,
            "{changed} of {written}"
        );
        // A mesh with an index out of range, or a vertex at infinity, is skipped, not a panic.
        let mut broken = quad(&cam, size, (8.5, 8.5, 56.5, 40.5), 0.9);
        broken.2.push([0, 1, 99]);
        broken.0[2] = Vec3::INFINITY;
        let (c, _) = overlay(&shaded, &cam, &[item(&broken, &material, &lights)], red);
        assert!(c.iter().all(|c| c.is_finite()));
        // Colours are clamped to the framebuffer's range.
        let (c, _) = overlay(&shaded, &cam, &draws, Vec3::new(f32::NAN, 9.0, -1.0));
        assert!(
            c.iter()
                .all(|c| c.is_finite() && c.max_element() <= 1.0 && c.min_element() >= 0.0)
        );
    }
}
