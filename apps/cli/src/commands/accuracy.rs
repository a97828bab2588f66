//! `phosphor accuracy`: what accuracy costs in time. Renders the scene in every mode (and `phong`,
//! `gouraud` once more with screen-space interpolation, the lecture notes' scan-line formulas),
//! times each over at least `--frames` frames or [`MIN_TIMED`] after one untimed frame (min,
//! median and max), compares each with `reference` over the pixels it covers (linear values and
//! displayed 8-bit codes) and prints one aligned table row per mode; `--csv` writes the rows
//! to a file. With `--out-dir`: each mode's image (`MODE.png`, encoded as the scene says), its
//! error heat-map (`MODE-error.png`, titled, false colour with a labelled scale bar; none for
//! the reference, whose map would be black), `error-vs-time.png` and `accuracy.csv`.
//!
//! The `as phong` column of the fast-Phong rows is the share of covered pixels drawn exactly
//! as `phong` draws them (bit for bit): the triangles its fit or expansion refused, and those
//! too small to try.
//!
//! The fixed-mode rows force perspective-correct interpolation on or off, the fast-Phong method
//! (`taylor`, Bishop and Weimer 1986; `fit`, six points) and the interpolation (`plane`, or
//! Gouraud 1971's `incremental` scan line) so their labels hold whatever the scene file says; `auto` is the scene as it asks to be drawn (per object, the
//! plan's choice of mode, the scene's own interpolation setting).
//!
//! The last two columns are the Mach-band measure of [`crate::mach`]: the mean jump across the
//! meshes' interior edges of the value (`flat`) or of the one-pixel slope (every other row), in
//! 8-bit codes (codes per pixel for slopes), and its ratio to the same measure on `reference`.
//! With `--out-dir` each row also gets `MODE-mach.png`, the jumps as a heat-map.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use indicatif::ProgressBar;
use phosphor_math::glam::Vec3;
use phosphor_raster::framebuffer::FAR_DEPTH;
use phosphor_raster::{FastPhongMethod, Framebuffer, Interpolation, ShadingMode};
use phosphor_scene::{FrameOptions, Scene, ShadingChoice, render_frame};

use super::{framebuffer, size_field};
use crate::CliError;
use crate::accuracy::{ErrorStats, compare, heat_map, spread, with_scale_labels, with_title};
use crate::args::AccuracyArgs;
use crate::geometric::geometric_reference;
use crate::limits::{FRAMEBUFFER_BYTES_PER_PIXEL, check_memory, sample_bytes_per_pixel};
use crate::mach::{EdgeJumps, JumpKind, TriangleIds, edge_jumps, jump_map, triangle_ids};
use crate::output::{write_image, write_rgb8};
use crate::plot::{PlotPoint, error_vs_time};
use crate::progress::{Progress, QUIET_FOR};

/// Reference frames are timed only while they fit this budget (at least one is always timed):
/// at large sizes one reference frame takes seconds, and the report must stay under a minute.
const REFERENCE_BUDGET: Duration = Duration::from_secs(8);

/// Every row is timed over at least `--frames` frames or this long, whichever comes first
/// (and at least [`MIN_FRAMES`] frames): a stable median and spread on the shared machine.
const MIN_TIMED: Duration = Duration::from_millis(500);

/// The fewest timed frames of a row (the reference's budget aside).
const MIN_FRAMES: u32 = 3;

/// Largest error the heat-maps show in full colour (8 steps of an 8-bit display); larger errors
/// saturate to white. One scale for every mode, so that their maps compare at a glance; fine
/// enough that Gouraud's per-triangle error pattern (its Mach bands) shows beside the highlights.
const HEAT_SCALE: f32 = 8.0 / 255.0;

/// Top of the Mach heat-maps' scale for value jumps (`flat`) and slope jumps (the rest): one
/// scale per kind for every row, so that the maps compare at a glance.
const MACH_VALUE_SCALE: f32 = 16.0 / 255.0;
const MACH_SLOPE_SCALE: f32 = 2.0 / 255.0;

/// One row of the report.
#[derive(Clone, Copy, Debug)]
struct Row {
    /// Name in the table and the plot.
    label: &'static str,
    /// File stem for the images.
    file: &'static str,
    /// What it renders.
    shading: ShadingChoice,
    /// Perspective-correct interpolation: forced on or off, or the scene's.
    perspective_correct: Option<bool>,
    /// Fast Phong's method: forced, or the scene's (or the flag's).
    fast_phong: Option<FastPhongMethod>,
    /// Interpolation of gouraud and phong: forced, or the scene's (or the flag's).
    interpolation: Option<Interpolation>,
    /// Gouraud's vertex clamp: forced, or the scene's.
    gouraud_clamp: Option<bool>,
}

const fn fixed(label: &'static str, mode: ShadingMode, correct: bool) -> Row {
    Row {
        label,
        file: label,
        shading: ShadingChoice::Mode(mode),
        perspective_correct: Some(correct),
        fast_phong: Some(FastPhongMethod::Taylor),
        interpolation: Some(Interpolation::Plane),
        gouraud_clamp: Some(true),
    }
}

/// The reference's row: what every other row is compared with.
const REFERENCE_ROW: Row = fixed(ShadingMode::Reference.name(), ShadingMode::Reference, true);

/// The row of `auto`: the plan's choice per object, the scene's own variants.
const AUTO_ROW: Row = Row {
    label: "auto",
    file: "auto",
    shading: ShadingChoice::Auto,
    perspective_correct: None,
    fast_phong: None,
    interpolation: None,
    gouraud_clamp: None,
};

/// The rows of one mode: the mode itself (fast-phong: each method), then its variants.
fn mode_rows(mode: ShadingMode) -> Vec<Row> {
    let plain = fixed(mode.name(), mode, true);
    match mode {
        ShadingMode::Flat => vec![plain],
        ShadingMode::Reference => vec![REFERENCE_ROW],
        ShadingMode::Gouraud => vec![
            plain,
            Row {
                file: "gouraud-unclamped",
                gouraud_clamp: Some(false),
                ..fixed("gouraud (unclamped)", mode, true)
            },
            Row {
                file: "gouraud-screen-space",
                ..fixed("gouraud (screen-space)", mode, false)
            },
            Row {
                file: "gouraud-incremental",
                interpolation: Some(Interpolation::Incremental),
                ..fixed("gouraud (incremental)", mode, true)
            },
        ],
        ShadingMode::FastPhong => vec![
            Row {
                file: "fast-phong-taylor",
                ..fixed("fast-phong (taylor)", mode, true)
            },
            Row {
                file: "fast-phong-fit",
                fast_phong: Some(FastPhongMethod::Fit),
                ..fixed("fast-phong (fit)", mode, true)
            },
        ],
        ShadingMode::Phong => vec![
            plain,
            Row {
                file: "phong-screen-space",
                ..fixed("phong (screen-space)", mode, false)
            },
            Row {
                file: "phong-incremental",
                interpolation: Some(Interpolation::Incremental),
                ..fixed("phong (incremental)", mode, true)
            },
        ],
    }
}

/// Every row in table order: the modes of [`ShadingMode::ALL`] in its order, `auto`, and the
/// reference last (though it renders first).
fn all_rows() -> Vec<Row> {
    let mut rows: Vec<Row> = ShadingMode::ALL
        .into_iter()
        .filter(|&m| m != ShadingMode::Reference)
        .flat_map(mode_rows)
        .collect();
    rows.push(AUTO_ROW);
    rows.extend(mode_rows(ShadingMode::Reference));
    rows
}

/// The rows `--fast-phong` and `--interpolation` keep: a row forcing another variant of a mode
/// the flag names is left out; `auto` takes the flags as overrides.
fn rows(args: &AccuracyArgs) -> Vec<Row> {
    let (fast, interp) = (args.variants.fast_phong(), args.variants.interpolation());
    all_rows()
        .into_iter()
        .filter(|r| {
            let uses_fast = r.mode() == Some(ShadingMode::FastPhong);
            let uses_interp = matches!(r.mode(), Some(ShadingMode::Gouraud | ShadingMode::Phong));
            let other_fast = uses_fast && fast.is_some() && r.fast_phong != fast;
            let other_interp = uses_interp && interp.is_some() && r.interpolation != interp;
            !other_fast && !other_interp
        })
        .map(|r| Row {
            fast_phong: r.fast_phong.or(fast),
            interpolation: r.interpolation.or(interp),
            ..r
        })
        .collect()
}

/// A row once measured.
struct Measured {
    row: Row,
    /// Milliseconds per frame: median.
    ms: f64,
    /// Milliseconds per frame: fastest and slowest.
    ms_range: (f64, f64),
    /// Frames timed.
    frames: usize,
    /// Fast-Phong rows: the share of covered pixels drawn exactly as `phong` draws them.
    as_phong: Option<f64>,
    /// Error against the geometric reference, where the scene has primitives to show it.
    geometric: Option<ErrorStats>,
    /// Error against the reference.
    stats: ErrorStats,
    /// The Mach-band measure: mean jump across interior edges, and its ratio to the reference's.
    mach: (f64, f64),
    /// Pixels shaded per frame (every pixel written, in the one-pass modes).
    pixels: u64,
}

impl Row {
    /// The shading mode every object gets, if one is forced.
    fn mode(self) -> Option<ShadingMode> {
        match self.shading {
            ShadingChoice::Mode(m) => Some(m),
            ShadingChoice::Auto => None,
        }
    }
}

/// Renders one untimed frame of `row` into `fb` and returns a copy of its colours, the time
/// it took and the pixels it shaded.
fn render_image(scene: &Scene, fb: &mut Framebuffer, row: Row) -> (Vec<Vec3>, Duration, u64) {
    let start = Instant::now();
    let report = render_frame(scene, fb, &options(row));
    (
        fb.color().to_vec(),
        start.elapsed(),
        report.stats.pixels_shaded,
    )
}

fn options(row: Row) -> FrameOptions {
    FrameOptions {
        shading: Some(row.shading),
        perspective_correct: row.perspective_correct,
        threads: 0,
        fast_phong: row.fast_phong,
        interpolation: row.interpolation,
        gouraud_vertex_clamp: row.gouraud_clamp,
        // The rows measure shading: a shadowed receiver is drawn per pixel in every mode, so
        // shadows would only blur them. The maps' error is measured apart, against
        // `reference`'s exact shadow rays (`shadow_error`).
        shadows: Some(false),
        ..FrameOptions::default()
    }
}

/// How many of the `requested` reference frames fit [`REFERENCE_BUDGET`], given that the first
/// took `first`: at least one, at most `requested`.
fn reference_frames(requested: u32, first: Duration) -> u32 {
    let fit = REFERENCE_BUDGET.as_secs_f64() / first.as_secs_f64().max(1e-9);
    requested.min((fit.floor() as u32).max(1))
}

/// Milliseconds of each timed frame of `row`: frames until `frames` are drawn or
/// `min_time` has passed, whichever comes first, at least `min(frames, MIN_FRAMES)`; `tick`
/// after each.
fn time_frames(
    scene: &Scene,
    fb: &mut Framebuffer,
    row: Row,
    (frames, min_time): (u32, Duration),
    tick: &mut dyn FnMut(),
) -> Vec<f64> {
    let opts = options(row);
    let begin = Instant::now();
    let mut times = Vec::new();
    while times.len() < frames as usize
        && (times.len() < MIN_FRAMES.min(frames) as usize || begin.elapsed() < min_time)
    {
        let start = Instant::now();
        render_frame(scene, fb, &opts);
        times.push(start.elapsed().as_secs_f64() * 1e3);
        tick();
    }
    times
}

/// Bytes per pixel the report holds at once: the framebuffer, the reference's and a mode's
/// colours (linear f32 RGB), and a heat-map with its labelled copy (8-bit RGB).
const BYTES_PER_PIXEL: u64 = FRAMEBUFFER_BYTES_PER_PIXEL + 12 + 12 + 3 + 3;

/// Frames drawn so far against the frames the report will draw, on the progress bar.
struct Frames {
    bar: ProgressBar,
}

impl Frames {
    fn tick(&mut self) {
        self.bar.inc(1);
    }
}

/// Writes `MODE-mach.png`: the row's edge jumps as a labelled heat-map on its kind's scale.
fn write_mach_map(
    dir: &Path,
    row: Row,
    jumps: &EdgeJumps,
    ids: &TriangleIds,
    kind: JumpKind,
    force: bool,
) -> Result<(), CliError> {
    let scale = match kind {
        JumpKind::Value => MACH_VALUE_SCALE,
        JumpKind::Slope => MACH_SLOPE_SCALE,
    };
    let map = jump_map(jumps, ids, scale)
        .ok_or_else(|| CliError::Input("frames of different sizes".to_owned()))?;
    write_rgb8(
        &dir.join(format!("{}-mach.png", row.file)),
        &with_scale_labels(&map, scale),
        force,
    )
}

/// What the table's header line calls the scene.
fn scene_name(args: &AccuracyArgs) -> String {
    match (&args.source.scene, &args.source.mesh) {
        (Some(path), _) => path.display().to_string(),
        (None, Some(mesh)) => format!("{} under S1's lights", mesh.display()),
        (None, None) => "the default scene".to_owned(),
    }
}

/// The worker threads `threads: 0` gives (all cores).
fn thread_count() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
}

/// An error in the table: three significant digits in scientific notation, or `0`.
fn error_cell(value: f64) -> String {
    if value == 0.0 {
        "0".to_owned()
    } else {
        format!("{value:.3e}")
    }
}

/// A Mach measure in the table: codes with three decimals, `-` when nothing was measured.
fn mach_cell(jump: f64) -> String {
    if jump.is_finite() {
        format!("{:.3}", jump * 255.0)
    } else {
        "-".to_owned()
    }
}

/// A ratio in the table: two decimals and `x`, `-` when undefined.
fn ratio_cell(ratio: f64) -> String {
    if ratio.is_finite() {
        format!("{ratio:.2}x")
    } else {
        "-".to_owned()
    }
}

/// A share in the table: percent with two decimals, `-` when not measured.
fn share_cell(share: Option<f64>) -> String {
    share.map_or_else(|| "-".to_owned(), |v| format!("{:.2}%", v * 100.0))
}

fn print_table(rows: &[Measured], gouraud_ms: f64) {
    say!(
        "{:<22}  {:>8}  {:>8}  {:>8}  {:>6}  {:>10}  {:>9}  {:>9}  {:>9}  {:>9}  {:>8}  {:>8}  {:>7}  {:>8}",
        "mode",
        "ms med",
        "ms min",
        "ms max",
        "frames",
        "vs gouraud",
        "RMSE",
        "PSNR dB",
        "max abs",
        "max codes",
        ">1 code",
        "as phong",
        "mach",
        "mach/ref"
    );
    for m in rows {
        let relative = if gouraud_ms > 0.0 {
            format!("{:.2}x", m.ms / gouraud_ms)
        } else {
            "-".to_owned()
        };
        say!(
            "{:<22}  {:>8.2}  {:>8.2}  {:>8.2}  {:>6}  {:>10}  {:>9}  {:>9.2}  {:>9}  {:>9.2}  {:>8}  {:>8}  {:>7}  {:>8}",
            m.row.label,
            m.ms,
            m.ms_range.0,
            m.ms_range.1,
            m.frames,
            relative,
            error_cell(m.stats.rmse),
            m.stats.psnr_db,
            error_cell(m.stats.max_abs),
            m.stats.max_codes,
            share_cell(Some(m.stats.share_over_code)),
            share_cell(m.as_phong),
            mach_cell(m.mach.0),
            ratio_cell(m.mach.1)
        );
    }
}

/// The rows against the geometric reference: `reference`'s row is the mesh's own error
/// (tessellation, normal averaging), every other row the mode's total.
fn print_geometric(rows: &[Measured], pixels: usize) {
    say!(
        "against the geometric reference (the exact surfaces of the scene's spheres, cylinder sides and tori, f64; {pixels} pixels): reference's row is the mesh's own error"
    );
    say!(
        "  {:<22}  {:>9}  {:>9}  {:>9}  {:>8}",
        "mode",
        "RMSE",
        "max abs",
        "max codes",
        ">1 code"
    );
    for m in rows {
        if let Some(g) = &m.geometric {
            say!(
                "  {:<22}  {:>9}  {:>9}  {:>9.2}  {:>8}",
                m.row.label,
                error_cell(g.rmse),
                error_cell(g.max_abs),
                g.max_codes,
                share_cell(Some(g.share_over_code))
            );
        }
    }
}

/// The rows as CSV (a header line, then one line per row; the label quoted).
fn csv(rows: &[Measured]) -> String {
    let mut out = String::from(
        "mode,frames,ms_min,ms_median,ms_max,rmse,psnr_db,max_abs,max_codes,share_over_one_code,covered_pixels,as_phong,mach,mach_ratio,geometric_rmse,geometric_max_abs,geometric_max_codes\n",
    );
    let num = |v: f64| {
        if v.is_finite() {
            format!("{v}")
        } else {
            String::new()
        }
    };
    for m in rows {
        out += &format!(
            "\"{}\",{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            m.row.label,
            m.frames,
            num(m.ms_range.0),
            num(m.ms),
            num(m.ms_range.1),
            num(m.stats.rmse),
            num(m.stats.psnr_db),
            num(m.stats.max_abs),
            num(m.stats.max_codes),
            num(m.stats.share_over_code),
            m.stats.covered,
            m.as_phong.map_or(String::new(), num),
            num(m.mach.0 * 255.0),
            num(m.mach.1),
            m.geometric.map_or(String::new(), |g| num(g.rmse)),
            m.geometric.map_or(String::new(), |g| num(g.max_abs)),
            m.geometric.map_or(String::new(), |g| num(g.max_codes)),
        );
    }
    out
}

/// The share of `covered` pixels of `image` equal to `phong` bit for bit.
fn share_as(image: &[Vec3], phong: &[Vec3], covered: &[bool]) -> Option<f64> {
    let mut same = 0usize;
    let mut count = 0usize;
    for ((a, b), c) in image.iter().zip(phong).zip(covered) {
        if *c {
            count += 1;
            if a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits) {
                same += 1;
            }
        }
    }
    (count > 0).then(|| same as f64 / count as f64)
}

/// The lecture notes' timing claims, each beside the measured ratio to `gouraud` per frame
/// and per shaded pixel.
const CLAIMS: [(ShadingMode, &str); 2] = [
    (ShadingMode::FastPhong, "2x (twice as long as Gouraud)"),
    (ShadingMode::Phong, "6-7x (six to seven times Gouraud)"),
];

/// Prints [`CLAIMS`] beside every row of their modes: milliseconds per frame, and per shaded
/// pixel (the frame's time over its pixels shaded), each as a multiple of `gouraud`'s.
fn print_claims(rows: &[Measured]) {
    let Some(g) = rows.iter().find(|m| m.row.label == "gouraud") else {
        return;
    };
    let per_pixel = |m: &Measured| m.ms / m.pixels.max(1) as f64;
    say!(
        "timing claims of the lecture notes against this run, as multiples of gouraud ({:.1} ms, {} pixels shaded):",
        g.ms,
        g.pixels
    );
    for (mode, claim) in CLAIMS {
        for m in rows.iter().filter(|m| m.row.mode() == Some(mode)) {
            say!(
                "  {:<22}  claimed {:<34}  measured {:>7} per frame, {:>7} per shaded pixel",
                m.row.label,
                claim,
                ratio_cell(m.ms / g.ms),
                ratio_cell(per_pixel(m) / per_pixel(g))
            );
        }
    }
}

/// Runs `phosphor accuracy`.
pub fn run(args: &AccuracyArgs) -> Result<(), CliError> {
    let (scene, width, height) = crate::view::prepare(&args.source, &args.camera, args.size)?;
    check_memory(
        &size_field(&args.source, args.size),
        (width, height),
        BYTES_PER_PIXEL + sample_bytes_per_pixel(scene.settings.antialias),
    )?;
    let out_dir: Option<PathBuf> = args.out_dir.clone();
    if let Some(dir) = &out_dir {
        std::fs::create_dir_all(dir)
            .map_err(|e| CliError::Input(format!("{}: cannot create: {e}", dir.display())))?;
    }
    let mut fb = framebuffer(width, height)?;
    let encoding = scene.settings.encoding;
    let save = |fb: &Framebuffer, row: Row| -> Result<(), CliError> {
        match &out_dir {
            Some(dir) => write_image(
                (fb, fb.color()),
                &dir.join(format!("{}.png", row.file)),
                &crate::output::Look::plain(encoding),
                args.force,
                &mut |_| {},
            ),
            None => Ok(()),
        }
    };
    // One untimed and `frames` timed frames per row (fewer for a slow reference).
    let table = rows(args);
    let rows = table.len() as u64;
    let mut progress = Progress::new();
    let mut frames = Frames {
        bar: progress.counter("measuring: frames", rows * (1 + u64::from(args.frames))),
    };
    progress.show_after(QUIET_FOR);

    // The reference first: its untimed frame is what every mode is compared with.
    let reference_row = REFERENCE_ROW;
    let (reference, first_time, reference_pixels) = render_image(&scene, &mut fb, reference_row);
    frames.tick();
    save(&fb, reference_row)?;
    let reference_frames = reference_frames(args.frames, first_time);
    let untimed = u64::from(args.frames - reference_frames);
    frames
        .bar
        .set_length(frames.bar.length().unwrap_or(0).saturating_sub(untimed));
    let covered: Vec<bool> = fb.depth().iter().map(|&z| z < FAR_DEPTH).collect();
    let reference_times = time_frames(
        &scene,
        &mut fb,
        reference_row,
        (reference_frames, Duration::ZERO),
        &mut || {
            frames.tick();
        },
    );
    // Phong's picture, for the share of fast Phong's pixels drawn exactly as phong.
    let (phong_image, _, _) = render_image(
        &scene,
        &mut fb,
        fixed(ShadingMode::Phong.name(), ShadingMode::Phong, true),
    );

    // The Mach measure's triangle ids, and the reference's own jumps of both kinds.
    let ids = triangle_ids(&scene, width, height, &options(reference_row));
    let reference_jumps = |kind| edge_jumps(&reference, &ids, kind);
    let reference_mach =
        [JumpKind::Value, JumpKind::Slope].map(|kind| (kind, reference_jumps(kind)));
    let geometric = geometric_reference(&scene, &options(reference_row), &ids, &reference);
    let geometric_pixels = geometric.count();
    let against_geometric = |image: &[Vec3]| {
        (geometric_pixels > 0)
            .then(|| compare(image, &geometric.image, Some(&geometric.exact), encoding))
            .flatten()
    };
    let mach_of = |row: Row, image: &[Vec3]| -> Result<(f64, f64), CliError> {
        let kind = JumpKind::for_mode(row.mode());
        let jumps = edge_jumps(image, &ids, kind);
        let base = reference_mach
            .iter()
            .find(|(k, _)| *k == kind)
            .map_or(f64::NAN, |(_, j)| j.mean);
        if let Some(dir) = &out_dir {
            write_mach_map(dir, row, &jumps, &ids, kind, args.force)?;
        }
        Ok((jumps.mean, jumps.mean / base))
    };

    let mut measured = Vec::with_capacity(table.len());
    for row in table {
        if row.label == reference_row.label {
            let stats = compare(&reference, &reference, Some(&covered), encoding)
                .ok_or_else(|| CliError::Input("the reference frame covers no pixel".to_owned()))?;
            let mach = mach_of(row, &reference)?;
            let (lo, ms, hi) = spread(&reference_times);
            measured.push(Measured {
                row,
                ms,
                ms_range: (lo, hi),
                frames: reference_times.len(),
                as_phong: None,
                geometric: against_geometric(&reference),
                stats,
                mach,
                pixels: reference_pixels,
            });
            continue;
        }
        let (image, _, pixels) = render_image(&scene, &mut fb, row);
        frames.tick();
        save(&fb, row)?;
        let stats = compare(&image, &reference, Some(&covered), encoding)
            .ok_or_else(|| CliError::Input("frames of different sizes".to_owned()))?;
        if let Some(dir) = &out_dir {
            let map = heat_map(&image, &reference, width, height, HEAT_SCALE)
                .ok_or_else(|| CliError::Input("frames of different sizes".to_owned()))?;
            let path = dir.join(format!("{}-error.png", row.file));
            let title = format!(
                "{}: |error| vs reference, linear, largest channel (white: {:.4} = 8/255 or more)",
                row.label, HEAT_SCALE
            );
            write_rgb8(
                &path,
                &with_title(&with_scale_labels(&map, HEAT_SCALE), &title),
                args.force,
            )?;
        }
        let mach = mach_of(row, &image)?;
        let as_phong = (row.mode() == Some(ShadingMode::FastPhong))
            .then(|| share_as(&image, &phong_image, &covered))
            .flatten();
        let times = time_frames(&scene, &mut fb, row, (args.frames, MIN_TIMED), &mut || {
            frames.tick()
        });
        let (lo, ms, hi) = spread(&times);
        measured.push(Measured {
            row,
            ms,
            ms_range: (lo, hi),
            frames: times.len(),
            as_phong,
            geometric: against_geometric(&image),
            stats,
            mach,
            pixels,
        });
    }
    progress.finish();

    let threads = thread_count();
    say!(
        "scene: {}, {width}x{height}, {threads} thread{}, each mode timed over {} frame{} or {} ms (whichever first, at least {}) after one untimed; errors over the {} pixels the reference covers, in linear values and {} codes",
        scene_name(args),
        if threads == 1 { "" } else { "s" },
        args.frames,
        if args.frames == 1 { "" } else { "s" },
        MIN_TIMED.as_millis(),
        MIN_FRAMES.min(args.frames),
        covered.iter().filter(|c| **c).count(),
        match encoding {
            phosphor_raster::Encoding::Srgb => "displayed sRGB",
            phosphor_raster::Encoding::Linear => "displayed linear",
        }
    );
    if reference_frames < args.frames {
        say!(
            "note: reference timed over {reference_frames} frame{} (its first took {:.1} s; budget {} s)",
            if reference_frames == 1 { "" } else { "s" },
            first_time.as_secs_f64(),
            REFERENCE_BUDGET.as_secs()
        );
    }
    let gouraud_ms = measured
        .iter()
        .find(|m| m.row.label == "gouraud")
        .map_or(0.0, |m| m.ms);
    print_table(&measured, gouraud_ms);
    print_claims(&measured);
    if geometric_pixels > 0 {
        print_geometric(&measured, geometric_pixels);
    }
    let table_csv = csv(&measured);
    if let Some(path) = &args.csv {
        crate::output::write_bytes(path, table_csv.as_bytes(), args.force)?;
        say!("wrote {}", path.display());
    }
    let [(_, value), (_, slope)] = &reference_mach;
    say!(
        "mach: mean jump across {} interior edges ({} pixel pairs) of the value (flat, codes) or the one-pixel slope (others, codes/px); mach/ref: against reference's {} (value) and {} (slope){}",
        value.edges,
        value.pairs,
        mach_cell(value.mean),
        mach_cell(slope.mean),
        if ids.undecoded > 0 {
            format!("; {} pixels without a triangle id", ids.undecoded)
        } else {
            String::new()
        }
    );

    // The rows above are drawn without shadows; the maps' own error is measured apart.
    let shadows = super::shadow_error::measure(
        &scene,
        &mut fb,
        (encoding, &reference),
        out_dir.as_deref(),
        (HEAT_SCALE, args.force),
    )?;
    if let Some(s) = &shadows {
        say!(
            "shadow maps against exact shadow rays: phong with the scene's maps ({}) against reference with one f64 ray per pixel and light; {} covered pixels in shadow by the rays",
            s.maps.join(", "),
            s.shadowed_pixels
        );
        say!(
            "  RMSE {}, PSNR {:.2} dB, max abs {}, max codes {:.2}, >1 code {}; one frame: phong with maps {:.1} ms, reference with rays {:.1} ms",
            error_cell(s.stats.rmse),
            s.stats.psnr_db,
            error_cell(s.stats.max_abs),
            s.stats.max_codes,
            share_cell(Some(s.stats.share_over_code)),
            s.ms.0,
            s.ms.1
        );
    }

    if let Some(dir) = &out_dir {
        let points: Vec<PlotPoint> = measured
            .iter()
            .map(|m| PlotPoint {
                label: m.row.label.to_owned(),
                ms: m.ms,
                ms_range: m.ms_range,
                rmse: m.stats.rmse,
            })
            .collect();
        let title = format!("error against time: {}, {width}x{height}", scene_name(args));
        write_rgb8(
            &dir.join("error-vs-time.png"),
            &error_vs_time(&title, &points),
            args.force,
        )?;
        crate::output::write_bytes(&dir.join("accuracy.csv"), table_csv.as_bytes(), args.force)?;
        say!(
            "wrote {}: MODE.png, MODE-error.png (heat-map, white at {:.3} = 8/255 or more), MODE-mach.png (edge jumps, white at {:.0}/255 for values, {:.0}/255 per pixel for slopes), error-vs-time.png, accuracy.csv{}",
            dir.display(),
            HEAT_SCALE,
            MACH_VALUE_SCALE * 255.0,
            MACH_SLOPE_SCALE * 255.0,
            if shadows.is_some() {
                ", shadow-maps-error.png"
            } else {
                ""
            }
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slow_reference_frames_are_timed_within_the_budget_but_at_least_once() {
        let ms = Duration::from_millis;
        assert_eq!(reference_frames(3, ms(400)), 3);
        assert_eq!(reference_frames(3, ms(3_000)), 2);
        assert_eq!(reference_frames(3, ms(60_000)), 1);
        assert_eq!(reference_frames(1, Duration::ZERO), 1);
    }

    #[test]
    fn rows_cover_every_mode_once_with_distinct_files_and_reference_last() {
        let rows = all_rows();
        for mode in ShadingMode::ALL {
            assert!(
                rows.iter().any(|r| r.shading == ShadingChoice::Mode(mode)
                    && (r.label == mode.name() || r.label.starts_with(mode.name()))),
                "{mode:?}"
            );
        }
        let mut files: Vec<&str> = rows.iter().map(|r| r.file).collect();
        files.sort_unstable();
        files.dedup();
        assert_eq!(files.len(), rows.len());
        assert_eq!(rows[rows.len() - 1].label, "reference");
        assert!(rows.iter().any(|r| r.shading == ShadingChoice::Auto));
        // Every variant of fast-phong and of the interpolation has a row.
        for method in FastPhongMethod::ALL {
            assert!(
                rows.iter()
                    .any(|r| r.fast_phong == Some(method)
                        && r.mode() == Some(ShadingMode::FastPhong))
            );
        }
        for mode in [ShadingMode::Gouraud, ShadingMode::Phong] {
            for interpolation in Interpolation::ALL {
                assert!(
                    rows.iter()
                        .any(|r| r.mode() == Some(mode) && r.interpolation == Some(interpolation))
                );
            }
        }
    }
}
