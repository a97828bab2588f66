//! Numerical stability of attribute interpolation on hard cases: the default plane evaluation
//! against Gouraud 1971's incremental scan line (`f32` increments per scan line and per pixel),
//! both against the exact linear interpolant (`f64`). Prints the drift table of
//! `docs/numerical-stability.md`:
//!
//! ```text
//! cargo test -p phosphor-raster --lib stability -- --nocapture
//! ```

use crate::clip::{Attrs, MAX_ATTRS};
use crate::coverage::BandTarget;
use crate::framebuffer::clamp_color;
use crate::incremental::{IncrementalTri, traverse_incremental};
use crate::setup::{RasterTri, ScreenVertex};
use crate::traverse::{SpanShade, traverse};
use glam::Vec3;

/// Writes the three interpolated attributes as the colour.
struct Passthrough;

impl SpanShade for Passthrough {
    const ATTRS: usize = 3;
    type Span = ();
    fn span(&self, _: f64, _: f64) {}
    fn pixel(&mut self, _: &(), idx: usize, (a, w): (&Attrs, f32), _: (i64, i64), c: &mut [Vec3]) {
        c[idx] = clamp_color(Vec3::new(a[0] * w, a[1] * w, a[2] * w));
    }
    fn step(_: &mut ()) {}
}

fn vertex(x: f64, y: f64, value: [f32; 3]) -> ScreenVertex {
    let (fx, fy) = ((x * 256.0).round() as i64, (y * 256.0).round() as i64);
    let mut attrs = [0.0; MAX_ATTRS];
    attrs[..3].copy_from_slice(&value);
    ScreenVertex {
        fx,
        fy,
        x: fx as f64 / 256.0,
        y: fy as f64 / 256.0,
        depth: 0.5,
        inv_w: 1.0,
        rhw: 1.0,
        attrs,
    }
}

/// Drift of one case: the largest error of each path against the exact interpolant over the
/// covered pixels, the largest difference between the paths, and the pixels compared.
struct Drift {
    plane: f64,
    incremental: f64,
    between: f64,
    pixels: usize,
}

/// Draws the triangle through `v` into a `w` x `h` image both ways and measures the drift.
fn measure(v: [ScreenVertex; 3], w: u32, h: u32) -> Drift {
    let t = RasterTri::new([&v[0], &v[1], &v[2]], 3, false).unwrap();
    let tri = IncrementalTri {
        xy: v.map(|v| (v.x, v.y)),
        inv_w: [1.0; 3],
        attrs: v.map(|v| v.attrs),
    };
    let n = (w * h) as usize;
    let draw = |incremental: bool| {
        let (mut color, mut depth) = (vec![Vec3::splat(-1.0); n], vec![1.0f32; n]);
        let mut target = BandTarget::new(&mut color, &mut depth, w, 0, false);
        if incremental {
            traverse_incremental(&t, &mut Passthrough, &tri, &mut target);
        } else {
            traverse(&t, &mut Passthrough, &mut target);
        }
        (color, depth)
    };
    let (plane, plane_depth) = draw(false);
    let (inc, inc_depth) = draw(true);
    // The exact interpolant from the snapped vertices, in f64.
    let [a, b, c] = v.map(|v| (v.x, v.y));
    let area = (b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1);
    let mut drift = Drift {
        plane: 0.0,
        incremental: 0.0,
        between: 0.0,
        pixels: 0,
    };
    for (i, (p, q)) in plane.iter().zip(&inc).enumerate() {
        // The same pixels are covered.
        assert_eq!(plane_depth[i] < 1.0, inc_depth[i] < 1.0, "pixel {i}");
        if plane_depth[i] >= 1.0 {
            continue;
        }
        let (x, y) = ((i as u32 % w) as f64 + 0.5, (i as u32 / w) as f64 + 0.5);
        let l1 = ((x - a.0) * (c.1 - a.1) - (y - a.1) * (c.0 - a.0)) / area;
        let l2 = ((b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)) / area;
        let l0 = 1.0 - l1 - l2;
        for k in 0..3 {
            let exact =
                l0 * v[0].attrs[k] as f64 + l1 * v[1].attrs[k] as f64 + l2 * v[2].attrs[k] as f64;
            // The framebuffer holds [0, 1]: a drift past it shows clamped.
            let exact = exact.clamp(0.0, 1.0);
            drift.plane = drift.plane.max((p[k] as f64 - exact).abs());
            drift.incremental = drift.incremental.max((q[k] as f64 - exact).abs());
            drift.between = drift.between.max((p[k] - q[k]).abs() as f64);
        }
        drift.pixels += 1;
    }
    drift
}

/// The closed-form bound of the incremental scan line's drift for vertex values in `[0, 1]`,
/// with `u = 2^-24` the f32 unit roundoff. Over `R` walked rows (from the triangle's top),
/// spans of at most `C` pixels, `|x| <= X`, horizontal extent `W` and x-gradient `G`:
/// - an edge walker's value is off by `E_v <= (R + 1) u + 5u` (one rounding per step on a
///   value in `[0, 1]`, and `3u` relative in the increment `(I2 - I1)/(y1 - y2)` over at most
///   the edge's whole change of 1), its `x` by `E_x <= (R + 1) u X + 5u W`;
/// - a span's increment `(I5 - I4)/(x5 - x4)` then misses `G` by at most `(2 E_v + u +
///   G (2 E_x + u W)) / width + u G`, at most `C` times, and each of its at most `C + 1` steps
///   rounds once more, and the edge's x error moves its start by `G E_x`.
///
/// In all, `u (3 (R + 1) + 15 + 3 G ((R + 1) X + 5 W) + (C + 2) + 2 + 2 G W)`; the test allows
/// twice that for the conversions of the row offsets it leaves out.
fn incremental_bound(v: &[ScreenVertex; 3]) -> f64 {
    let u = f64::from(f32::EPSILON) / 2.0;
    let ys = v.map(|v| v.y);
    let xs = v.map(|v| v.x);
    let (y_lo, y_hi) = (
        ys.iter().copied().fold(f64::INFINITY, f64::min),
        ys.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    let (x_lo, x_hi) = (
        xs.iter().copied().fold(f64::INFINITY, f64::min),
        xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    let rows = (y_hi - y_lo).ceil() + 1.0;
    let width = x_hi - x_lo;
    let cols = width.ceil() + 1.0;
    let x_max = x_lo.abs().max(x_hi.abs()) + 1.0;
    // The plane's x-gradient of each attribute, largest over the three.
    let [a, b, c] = v.map(|v| (v.x, v.y));
    let area = (b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1);
    let g = (0..3)
        .map(|k| {
            let [fa, fb, fc] = v.map(|v| f64::from(v.attrs[k]));
            (((fb - fa) * (c.1 - a.1) - (fc - fa) * (b.1 - a.1)) / area).abs()
        })
        .fold(0.0, f64::max);
    let bound = u
        * (3.0 * (rows + 1.0)
            + 15.0
            + 3.0 * g * ((rows + 1.0) * x_max + 5.0 * width)
            + (cols + 2.0)
            + 2.0
            + 2.0 * g * width);
    2.0 * bound
}

/// Largest error of the plane evaluation against the exact interpolant on every case: a few
/// f32 roundings of the value (the plane is evaluated in f64 at each span start, then stepped
/// at most one image row in f32), far below one 8-bit code (0.0039).
const PLANE_BOUND: f64 = 1e-4;

#[test]
fn plane_evaluation_does_not_drift_where_the_incremental_scan_line_does() {
    let values = [[0.1, 0.9, 0.5], [0.9, 0.2, 0.3], [0.4, 0.6, 0.95]];
    let vx = |x: f64, y: f64, k: usize| vertex(x, y, values[k]);
    let cases: Vec<(&str, [ScreenVertex; 3], u32, u32)> = vec![
        (
            "long thin (4000 x 3 px)",
            [vx(0.3, 1.2, 0), vx(3999.7, 2.1, 1), vx(0.6, 4.4, 2)],
            4000,
            8,
        ),
        (
            "sliver under 0.02 px wide, 4000 rows",
            [vx(2.49, 0.2, 0), vx(2.52, 3999.8, 1), vx(2.51, 0.3, 2)],
            8,
            4000,
        ),
        (
            "8192 rows",
            [vx(0.4, 0.3, 0), vx(63.7, 4100.2, 1), vx(5.1, 8191.6, 2)],
            64,
            8192,
        ),
        (
            "16384 rows",
            [vx(0.4, 0.3, 0), vx(63.7, 8200.2, 1), vx(5.1, 16383.6, 2)],
            64,
            16384,
        ),
        (
            "huge coordinates (vertices 500 000 px away)",
            [
                vx(-500_000.3, -400_000.7, 0),
                vx(500_000.1, -390_000.2, 1),
                vx(100.9, 600_000.4, 2),
            ],
            256,
            256,
        ),
        (
            "tiny triangle (1.5 px)",
            [vx(10.1, 10.2, 0), vx(11.8, 10.4, 1), vx(10.3, 11.9, 2)],
            32,
            32,
        ),
    ];
    println!(
        "| case | pixels | plane vs exact | incremental vs exact | closed-form bound | incremental vs plane |"
    );
    println!("|---|---:|---:|---:|---:|---:|");
    for (name, v, w, h) in cases {
        let d = measure(v, w, h);
        let bound = incremental_bound(&v);
        println!(
            "| {name} | {} | {:.2e} | {:.2e} | {:.2e} | {:.2e} |",
            d.pixels, d.plane, d.incremental, bound, d.between
        );
        assert!(d.pixels > 0, "{name}: nothing drawn");
        assert!(d.plane <= PLANE_BOUND, "{name}: plane drift {}", d.plane);
        assert!(
            d.incremental <= bound,
            "{name}: incremental drift {} over the closed-form bound {bound}",
            d.incremental
        );
    }
}
