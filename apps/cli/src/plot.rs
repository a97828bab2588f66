//! The accuracy report's plot: error (RMSE against `reference`, log scale) against time per
//! frame, one marker per mode, with axes, ticks, numbers, axis titles, a title and a legend.
//!
//! Drawn directly into an 8-bit RGB image with the built-in bitmap font ([`crate::font`]):
//! no plotting crate, no system fonts (CI installs nothing but Xvfb), nothing to load at run
//! time. A mode with zero error (the reference itself) cannot sit on a log axis; its marker is
//! drawn on the bottom axis line and its legend entry says `rmse 0`.

use crate::font::{draw_text, put, text_height, text_width};
use crate::rgb8::Rgb8Image;

/// Width of the plot image in pixels.
pub const WIDTH: u32 = 1040;
/// Height of the plot image in pixels.
pub const HEIGHT: u32 = 600;
/// The plot area: left, top, right, bottom edges in pixels (the axes lie on left and bottom).
pub const AREA: (i64, i64, i64, i64) = (110, 60, 700, 520);
/// Text scale: each font pixel is this many image pixels.
const TEXT: u32 = 2;
/// Radius of a marker in pixels.
const MARKER: i64 = 7;
/// Left edge of the legend.
const LEGEND_X: i64 = 730;

const BLACK: [u8; 3] = [0, 0, 0];
const GRID: [u8; 3] = [225, 225, 225];
const MINOR_GRID: [u8; 3] = [243, 243, 243];
const GREY: [u8; 3] = [90, 90, 90];

/// Marker colours, one per mode in order (Okabe-Ito, distinguishable with colour blindness).
pub const PALETTE: [[u8; 3]; 8] = [
    [0, 114, 178],
    [230, 159, 0],
    [0, 158, 115],
    [204, 121, 167],
    [213, 94, 0],
    [86, 180, 233],
    [120, 120, 0],
    [0, 0, 0],
];

/// One mode on the plot.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotPoint {
    /// The mode's name, as in the table.
    pub label: String,
    /// Median milliseconds per frame.
    pub ms: f64,
    /// Fastest and slowest frame, milliseconds (drawn as an error bar).
    pub ms_range: (f64, f64),
    /// RMSE against the reference (0 for the reference itself).
    pub rmse: f64,
}

/// Marker shapes, cycled with the palette so that markers on the same spot stay apart.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shape {
    Circle,
    Square,
    Diamond,
    Triangle,
}

const SHAPES: [Shape; 4] = [
    Shape::Circle,
    Shape::Square,
    Shape::Diamond,
    Shape::Triangle,
];

/// The colour and shape of the `i`-th mode: colours cycle through [`PALETTE`], shapes step
/// once more every time the colours wrap, so no two of the first 32 modes share both.
fn style(i: usize) -> ([u8; 3], Shape) {
    (
        PALETTE[i % PALETTE.len()],
        SHAPES[(i + i / PALETTE.len()) % SHAPES.len()],
    )
}

/// Height of a legend entry (name line and numbers line), pixels.
fn legend_step() -> i64 {
    2 * (i64::from(text_height(TEXT)) + 9)
}

/// The image height for `n` modes: [`HEIGHT`], or taller so that every legend entry fits.
#[must_use]
pub fn height_for(n: usize) -> u32 {
    let (_, top, _, _) = AREA;
    let needed = top + 30 + n as i64 * legend_step() + 10;
    HEIGHT.max(u32::try_from(needed).unwrap_or(u32::MAX))
}

/// A step of 1, 2 or 5 times a power of ten giving about `ticks` intervals over `range`.
fn nice_step(range: f64, ticks: f64) -> f64 {
    let raw = range / ticks;
    let magnitude = 10f64.powf(raw.log10().floor());
    let norm = raw / magnitude;
    let unit = if norm <= 1.0 {
        1.0
    } else if norm <= 2.0 {
        2.0
    } else if norm <= 5.0 {
        5.0
    } else {
        10.0
    };
    unit * magnitude
}

/// The axes' ranges: time linear from 0, error in whole decades.
#[derive(Clone, Copy, Debug)]
struct Axes {
    x_max: f64,
    x_step: f64,
    decade_lo: i32,
    decade_hi: i32,
}

impl Axes {
    fn fit(points: &[PlotPoint]) -> Axes {
        let ms_max = points
            .iter()
            .flat_map(|p| [p.ms, p.ms_range.1])
            .filter(|v| v.is_finite())
            .fold(0.0f64, f64::max);
        let ms_max = if ms_max > 0.0 { ms_max } else { 1.0 };
        let x_step = nice_step(ms_max, 5.0);
        let x_max = (ms_max / x_step - 1e-9).ceil().max(1.0) * x_step;
        let positive = points
            .iter()
            .map(|p| p.rmse)
            .filter(|v| v.is_finite() && *v > 0.0);
        let lo = positive.clone().fold(f64::INFINITY, f64::min);
        let hi = positive.fold(0.0f64, f64::max);
        // The small offsets keep exact powers of ten (0.1 is 10^-0.99999...) on their decade.
        let (decade_lo, mut decade_hi) = if hi > 0.0 {
            (
                (lo.log10() + 1e-9).floor() as i32,
                (hi.log10() - 1e-9).ceil() as i32,
            )
        } else {
            (-4, 0)
        };
        if decade_hi <= decade_lo {
            decade_hi = decade_lo + 1;
        }
        Axes {
            x_max,
            x_step,
            decade_lo,
            decade_hi,
        }
    }

    fn x(&self, ms: f64) -> i64 {
        let (left, _, right, _) = AREA;
        left + ((ms / self.x_max).clamp(0.0, 1.0) * (right - left) as f64).round() as i64
    }

    /// The pixel row of an error; zero (or anything below the axis) sits on the bottom axis.
    fn y(&self, rmse: f64) -> i64 {
        let (_, top, _, bottom) = AREA;
        if rmse.is_nan() || rmse <= 0.0 {
            return bottom;
        }
        let t =
            (rmse.log10() - f64::from(self.decade_lo)) / f64::from(self.decade_hi - self.decade_lo);
        bottom - (t.clamp(0.0, 1.0) * (bottom - top) as f64).round() as i64
    }
}

fn hline(img: &mut Rgb8Image, x0: i64, x1: i64, y: i64, colour: [u8; 3]) {
    for x in x0..=x1 {
        put(img, x, y, colour);
    }
}

fn vline(img: &mut Rgb8Image, x: i64, y0: i64, y1: i64, colour: [u8; 3]) {
    for y in y0..=y1 {
        put(img, x, y, colour);
    }
}

/// A filled marker centred on (`cx`, `cy`) with a dark outline.
fn marker(img: &mut Rgb8Image, cx: i64, cy: i64, shape: Shape, colour: [u8; 3]) {
    let r = MARKER;
    let inside = |dx: i64, dy: i64, r: i64| match shape {
        Shape::Circle => dx * dx + dy * dy <= r * r,
        Shape::Square => dx.abs() <= r * 4 / 5 && dy.abs() <= r * 4 / 5,
        Shape::Diamond => dx.abs() + dy.abs() <= r,
        // Apex up: the half-width grows from 0 at the top to r at the bottom.
        Shape::Triangle => dy >= -r && dy <= r * 3 / 4 && 2 * dx.abs() <= dy + r,
    };
    for dy in -r - 1..=r + 1 {
        for dx in -r - 1..=r + 1 {
            if inside(dx, dy, r - 1) {
                put(img, cx + dx, cy + dy, colour);
            } else if inside(dx, dy, r + 1) {
                put(img, cx + dx, cy + dy, BLACK);
            }
        }
    }
}

/// Formats a tick value with as many decimals as the step needs.
fn tick_label(value: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    format!("{value:.decimals$}")
}

/// Formats an error for the legend: `0`, or three significant digits in scientific notation.
fn error_label(rmse: f64) -> String {
    if rmse > 0.0 {
        format!("{rmse:.2e}")
    } else {
        "0".to_owned()
    }
}

/// The plot of error against time for `points` (in table order), titled `title`.
/// [`WIDTH`] x [`HEIGHT`] pixels.
#[must_use]
pub fn error_vs_time(title: &str, points: &[PlotPoint]) -> Rgb8Image {
    let height = height_for(points.len());
    let mut img = Rgb8Image {
        width: WIDTH,
        height,
        data: vec![255; WIDTH as usize * height as usize * 3],
    };
    let axes = Axes::fit(points);
    let (left, top, right, bottom) = AREA;
    let th = i64::from(text_height(TEXT));
    let width_of = |s: &str| i64::from(text_width(s, TEXT));

    // Grid and ticks of the time axis.
    let mut k = 0u32;
    loop {
        let ms = f64::from(k) * axes.x_step;
        if ms > axes.x_max * (1.0 + 1e-9) {
            break;
        }
        let x = axes.x(ms);
        if k > 0 {
            vline(&mut img, x, top, bottom - 1, GRID);
        }
        vline(&mut img, x, bottom, bottom + 6, BLACK);
        let label = tick_label(ms, axes.x_step);
        draw_text(
            &mut img,
            x - width_of(&label) / 2,
            bottom + 12,
            &label,
            TEXT,
            BLACK,
        );
        k += 1;
    }
    // Grid and ticks of the error axis: decades labelled, 2..9 as minor ticks.
    for decade in axes.decade_lo..=axes.decade_hi {
        let y = axes.y(10f64.powi(decade));
        if decade > axes.decade_lo {
            hline(&mut img, left + 1, right, y, GRID);
        }
        hline(&mut img, left - 6, left, y, BLACK);
        let label = format!("1e{decade}");
        draw_text(
            &mut img,
            left - 12 - width_of(&label),
            y - th / 2,
            &label,
            TEXT,
            BLACK,
        );
        if decade < axes.decade_hi {
            for m in 2..10 {
                let y = axes.y(f64::from(m) * 10f64.powi(decade));
                hline(&mut img, left + 1, right, y, MINOR_GRID);
                hline(&mut img, left - 3, left, y, BLACK);
            }
        }
    }
    // The axes themselves, two pixels wide, and a frame.
    for d in 0..2 {
        vline(&mut img, left - d, top, bottom + d, BLACK);
        hline(&mut img, left - d, right, bottom + d, BLACK);
    }
    vline(&mut img, right, top, bottom, GREY);
    hline(&mut img, left, right, top, GREY);

    // Titles.
    draw_text(&mut img, left, 16, title, TEXT, BLACK);
    let x_title = "time per frame (ms): median, bar from min to max";
    draw_text(
        &mut img,
        (left + right) / 2 - width_of(x_title) / 2,
        bottom + 44,
        x_title,
        TEXT,
        BLACK,
    );
    draw_text(
        &mut img,
        8,
        top - th - 10,
        "RMSE vs reference (log)",
        TEXT,
        BLACK,
    );

    // Time bars (min to max, with end caps), markers over them, then the legend: marker,
    // name, and its numbers on a second line.
    for (i, p) in points.iter().enumerate() {
        let (lo, hi) = p.ms_range;
        if lo.is_finite() && hi.is_finite() && hi >= lo {
            let (colour, _) = style(i);
            let y = axes.y(p.rmse);
            let (x0, x1) = (axes.x(lo), axes.x(hi));
            for d in -1..=1 {
                hline(&mut img, x0, x1, y + d, colour);
            }
            vline(&mut img, x0, y - 5, y + 5, colour);
            vline(&mut img, x1, y - 5, y + 5, colour);
        }
    }
    for (i, p) in points.iter().enumerate() {
        let (colour, shape) = style(i);
        marker(&mut img, axes.x(p.ms), axes.y(p.rmse), shape, colour);
    }
    draw_text(&mut img, LEGEND_X, top, "mode", TEXT, BLACK);
    for (i, p) in points.iter().enumerate() {
        let y = top + 30 + i as i64 * legend_step();
        let (colour, shape) = style(i);
        marker(&mut img, LEGEND_X + MARKER, y + th / 2, shape, colour);
        draw_text(&mut img, LEGEND_X + 3 * MARKER, y, &p.label, TEXT, BLACK);
        let numbers = format!(
            "{:.1} ms ({:.1}-{:.1}), rmse {}",
            p.ms,
            p.ms_range.0,
            p.ms_range.1,
            error_label(p.rmse)
        );
        draw_text(
            &mut img,
            LEGEND_X + 3 * MARKER,
            y + th + 6,
            &numbers,
            TEXT,
            GREY,
        );
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(img: &Rgb8Image, x: i64, y: i64) -> [u8; 3] {
        let o = (y as usize * img.width as usize + x as usize) * 3;
        [img.data[o], img.data[o + 1], img.data[o + 2]]
    }

    fn points() -> Vec<PlotPoint> {
        // Chosen so the axes are known: time 0..100 ms, error 1e-3..1e-1.
        vec![
            PlotPoint {
                label: "gouraud".into(),
                ms: 50.0,
                ms_range: (50.0, 50.0),
                rmse: 1e-2,
            },
            PlotPoint {
                label: "phong".into(),
                ms: 100.0,
                ms_range: (100.0, 100.0),
                rmse: 1e-3,
            },
            PlotPoint {
                label: "flat".into(),
                ms: 20.0,
                ms_range: (20.0, 20.0),
                rmse: 1e-1,
            },
            PlotPoint {
                label: "reference".into(),
                ms: 80.0,
                ms_range: (80.0, 80.0),
                rmse: 0.0,
            },
        ]
    }

    #[test]
    fn axes_fit_nice_ranges_and_whole_decades() {
        let a = Axes::fit(&points());
        assert!((a.x_max - 100.0).abs() < 1e-9, "{}", a.x_max);
        assert!((a.x_step - 20.0).abs() < 1e-9);
        assert_eq!((a.decade_lo, a.decade_hi), (-3, -1));
        assert!((nice_step(7.3, 5.0) - 2.0).abs() < 1e-12);
        assert!((nice_step(0.9, 5.0) - 0.2).abs() < 1e-12);
    }

    #[test]
    fn plot_has_its_size_axes_and_a_marker_per_mode_where_it_belongs() {
        let img = error_vs_time("test", &points());
        assert_eq!((img.width, img.height), (WIDTH, HEIGHT));
        assert_eq!(img.data.len(), (WIDTH * HEIGHT * 3) as usize);
        let (left, top, right, bottom) = AREA;
        // Axis lines: the left one over the plot's height, the bottom one over its width
        // (sampled away from ticks and markers).
        for y in [top + 3, (top + bottom) / 2 + 13, bottom - 3] {
            assert_eq!(at(&img, left, y), BLACK, "left axis at y {y}");
        }
        for x in [left + 30, (left + right) / 2 + 17, right - 12] {
            assert_eq!(at(&img, x, bottom), BLACK, "bottom axis at x {x}");
        }
        // Markers: centre of each at (time, log error) in the plot area.
        let w = (right - left) as f64;
        let h = (bottom - top) as f64;
        let expected = [
            (
                left + (0.5 * w).round() as i64,
                bottom - (0.5 * h).round() as i64,
            ),
            (right, bottom),
            (left + (0.2 * w).round() as i64, top),
        ];
        for (i, (x, y)) in expected.into_iter().enumerate() {
            assert_eq!(at(&img, x, y), PALETTE[i], "marker {i} at ({x}, {y})");
        }
        // The reference (error 0) sits on the bottom axis at 80 ms.
        let x = left + (0.8 * w).round() as i64;
        assert_eq!(at(&img, x, bottom - 3), PALETTE[3]);
        // Legend: one marker per mode in its colour.
        for i in 0..4 {
            let y = top
                + 30
                + i * 2 * (i64::from(text_height(TEXT)) + 9)
                + i64::from(text_height(TEXT)) / 2;
            assert_eq!(at(&img, LEGEND_X + MARKER, y), PALETTE[i as usize]);
        }
        // Tick numbers and titles put dark pixels left of the axis and below it.
        let dark = |x0: i64, x1: i64, y0: i64, y1: i64| {
            (y0..y1).any(|y| (x0..x1).any(|x| at(&img, x, y) == BLACK))
        };
        assert!(dark(0, left - 8, top, bottom), "no y tick labels");
        assert!(
            dark(left, right, bottom + 10, bottom + 30),
            "no x tick labels"
        );
        assert!(
            dark(left, right, bottom + 40, HEIGHT as i64),
            "no x axis title"
        );
        assert!(dark(left, right, 0, top - 2), "no title");
    }

    #[test]
    fn twelve_modes_get_distinct_markers_a_whole_legend_and_time_bars() {
        let styles: Vec<_> = (0..12).map(style).collect();
        for i in 0..12 {
            for j in 0..i {
                assert_ne!(styles[i], styles[j], "modes {j} and {i} share a marker");
            }
        }
        let pts: Vec<PlotPoint> = (0..12)
            .map(|i| PlotPoint {
                label: format!("mode {i}"),
                ms: 10.0 + f64::from(i),
                ms_range: (5.0 + f64::from(i), 40.0),
                rmse: 1e-3,
            })
            .collect();
        let img = error_vs_time("t", &pts);
        assert_eq!(img.height, height_for(12));
        // The last legend entry's marker is inside the image, in its colour.
        let y = AREA.1 + 30 + 11 * legend_step() + i64::from(text_height(TEXT)) / 2;
        assert!(y < i64::from(img.height));
        assert_eq!(at(&img, LEGEND_X + MARKER, y), style(11).0);
        // The last mode's bar reaches its slowest frame, right of the marker.
        let axes = Axes::fit(&pts);
        assert_eq!(at(&img, axes.x(38.0), axes.y(1e-3)), style(11).0);
    }

    #[test]
    fn plot_survives_empty_and_degenerate_input() {
        let img = error_vs_time("", &[]);
        assert_eq!(img.data.len(), (WIDTH * HEIGHT * 3) as usize);
        let img = error_vs_time(
            "x",
            &[PlotPoint {
                label: "nan".into(),
                ms: f64::NAN,
                ms_range: (f64::NAN, f64::INFINITY),
                rmse: f64::INFINITY,
            }],
        );
        assert_eq!((img.width, img.height), (WIDTH, HEIGHT));
    }
}
