//! `phosphor accuracy`: what accuracy costs in time. Renders the scene in every mode (and
//! `phong`, `gouraud` once more with screen-space interpolation, the seeds' approximation),
//! times each as the median of `--frames` frames after one untimed frame, compares each with
//! `reference` and prints one aligned table row per mode. With `--out-dir`: each mode's image
//! (`MODE.png`, encoded as the scene says), its error heat-map (`MODE-error.png`, false colour
//! with a labelled scale bar; none for the reference, whose map would be black) and
//! `error-vs-time.png`.
//!
//! The fixed-mode rows force perspective-correct interpolation on or off so their labels hold
//! whatever the scene file says; `auto` is the scene as it asks to be drawn (per object, the
//! plan's choice of mode, the scene's own interpolation setting).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use phosphor_math::glam::Vec3;
use phosphor_raster::{Framebuffer, ShadingMode};
use phosphor_scene::{FrameOptions, Scene, ShadingChoice, render_frame};

use super::{frame_size, framebuffer, load_source, size_field};
use crate::CliError;
use crate::accuracy::{ErrorStats, compare, heat_map, median, with_scale_labels};
use crate::args::AccuracyArgs;
use crate::limits::{FRAMEBUFFER_BYTES_PER_PIXEL, check_memory};
use crate::output::{write_image, write_rgb8};
use crate::plot::{PlotPoint, error_vs_time};
use crate::progress::{Progress, time_left};

/// Reference frames are timed only while they fit this budget (at least one is always timed):
/// at large sizes one reference frame takes seconds, and the report must stay under a minute.
const REFERENCE_BUDGET: Duration = Duration::from_secs(8);

/// Largest error the heat-maps show in full colour (8 steps of an 8-bit display); larger errors
/// saturate to white. One scale for every mode, so that their maps compare at a glance; fine
/// enough that Gouraud's per-triangle error pattern (its Mach bands) shows beside the highlights.
const HEAT_SCALE: f32 = 8.0 / 255.0;

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
}

const fn fixed(label: &'static str, mode: ShadingMode, correct: bool) -> Row {
    Row {
        label,
        file: label,
        shading: ShadingChoice::Mode(mode),
        perspective_correct: Some(correct),
    }
}

/// The rows in table order (the reference last, though it renders first).
const ROWS: [Row; 8] = [
    fixed("flat", ShadingMode::Flat, true),
    fixed("gouraud", ShadingMode::Gouraud, true),
    Row {
        file: "gouraud-screen-space",
        ..fixed("gouraud (screen-space)", ShadingMode::Gouraud, false)
    },
    fixed("fast-phong", ShadingMode::FastPhong, true),
    fixed("phong", ShadingMode::Phong, true),
    Row {
        file: "phong-screen-space",
        ..fixed("phong (screen-space)", ShadingMode::Phong, false)
    },
    Row {
        label: "auto",
        file: "auto",
        shading: ShadingChoice::Auto,
        perspective_correct: None,
    },
    fixed("reference", ShadingMode::Reference, true),
];

/// A row once measured.
struct Measured {
    row: Row,
    /// Median milliseconds per frame.
    ms: f64,
    /// Error against the reference.
    stats: ErrorStats,
}

/// Renders one untimed frame of `row` into `fb` and returns a copy of its colours.
fn render_image(scene: &Scene, fb: &mut Framebuffer, row: Row) -> (Vec<Vec3>, Duration) {
    let start = Instant::now();
    render_frame(scene, fb, &options(row));
    (fb.color().to_vec(), start.elapsed())
}

fn options(row: Row) -> FrameOptions {
    FrameOptions {
        shading: Some(row.shading),
        perspective_correct: row.perspective_correct,
        threads: 0,
        ..FrameOptions::default()
    }
}

/// How many of the `requested` reference frames fit [`REFERENCE_BUDGET`], given that the first
/// took `first`: at least one, at most `requested`.
fn reference_frames(requested: u32, first: Duration) -> u32 {
    let fit = REFERENCE_BUDGET.as_secs_f64() / first.as_secs_f64().max(1e-9);
    requested.min((fit.floor() as u32).max(1))
}

/// Median milliseconds of `frames` timed frames of `row`; `tick` after each.
fn time_frames(
    scene: &Scene,
    fb: &mut Framebuffer,
    row: Row,
    frames: u32,
    tick: &mut dyn FnMut(),
) -> f64 {
    let opts = options(row);
    let times: Vec<f64> = (0..frames)
        .map(|_| {
            let start = Instant::now();
            render_frame(scene, fb, &opts);
            let ms = start.elapsed().as_secs_f64() * 1e3;
            tick();
            ms
        })
        .collect();
    median(&times)
}

/// Bytes per pixel the report holds at once: the framebuffer, the reference's and a mode's
/// colours (linear f32 RGB), and a heat-map with its labelled copy (8-bit RGB).
const BYTES_PER_PIXEL: u64 = FRAMEBUFFER_BYTES_PER_PIXEL + 12 + 12 + 3 + 3;

/// Frames drawn so far against the frames the report will draw, on the progress line.
struct Frames<'a> {
    progress: &'a Progress,
    done: u32,
    total: u32,
}

impl Frames<'_> {
    fn tick(&mut self) {
        self.done += 1;
        let f = f64::from(self.done) / f64::from(self.total.max(self.done));
        self.progress.set(
            &format!("measuring: frame {} of {}", self.done, self.total),
            f,
            time_left(self.progress.elapsed(), f),
        );
    }
}

/// What the table's header line calls the scene.
fn scene_name(args: &AccuracyArgs) -> String {
    match (&args.source.scene, &args.source.mesh) {
        (Some(path), _) => path.display().to_string(),
        (None, Some(mesh)) => format!("{} in S1", mesh.display()),
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

fn print_table(rows: &[Measured], gouraud_ms: f64) {
    say!(
        "{:<22}  {:>9}  {:>10}  {:>9}  {:>9}  {:>9}  {:>7}",
        "mode",
        "ms/frame",
        "vs gouraud",
        "RMSE",
        "PSNR dB",
        "max abs",
        ">1/255"
    );
    for m in rows {
        let relative = if gouraud_ms > 0.0 {
            format!("{:.2}x", m.ms / gouraud_ms)
        } else {
            "-".to_owned()
        };
        say!(
            "{:<22}  {:>9.1}  {:>10}  {:>9}  {:>9.2}  {:>9}  {:>6.2}%",
            m.row.label,
            m.ms,
            relative,
            error_cell(m.stats.rmse),
            m.stats.psnr_db,
            error_cell(m.stats.max_abs),
            m.stats.share_over_lsb * 100.0
        );
    }
}

/// Runs `phosphor accuracy`.
pub fn run(args: &AccuracyArgs) -> Result<(), CliError> {
    let scene = load_source(&args.source)?;
    let (width, height) = frame_size(&scene, args.size);
    check_memory(
        &size_field(&args.source, args.size),
        (width, height),
        BYTES_PER_PIXEL,
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
                fb,
                &dir.join(format!("{}.png", row.file)),
                encoding,
                args.force,
                &mut |_| {},
            ),
            None => Ok(()),
        }
    };
    let progress = Progress::start("measuring");
    // One untimed and `frames` timed frames per row (fewer for a slow reference).
    let rows = ROWS.len() as u32;
    let mut frames = Frames {
        progress: &progress,
        done: 0,
        total: rows * (1 + args.frames),
    };

    // The reference first: its untimed frame is what every mode is compared with.
    let reference_row = ROWS[ROWS.len() - 1];
    let (reference, first_time) = render_image(&scene, &mut fb, reference_row);
    frames.tick();
    save(&fb, reference_row)?;
    let reference_frames = reference_frames(args.frames, first_time);
    frames.total -= args.frames - reference_frames;
    let reference_ms = time_frames(
        &scene,
        &mut fb,
        reference_row,
        reference_frames,
        &mut || {
            frames.tick();
        },
    );

    let mut measured = Vec::with_capacity(ROWS.len());
    for row in ROWS {
        if row.label == reference_row.label {
            let stats = compare(&reference, &reference)
                .ok_or_else(|| CliError::Input("the reference frame is empty".to_owned()))?;
            measured.push(Measured {
                row,
                ms: reference_ms,
                stats,
            });
            continue;
        }
        let (image, _) = render_image(&scene, &mut fb, row);
        frames.tick();
        save(&fb, row)?;
        let stats = compare(&image, &reference)
            .ok_or_else(|| CliError::Input("frames of different sizes".to_owned()))?;
        if let Some(dir) = &out_dir {
            let map = heat_map(&image, &reference, width, height, HEAT_SCALE)
                .ok_or_else(|| CliError::Input("frames of different sizes".to_owned()))?;
            let path = dir.join(format!("{}-error.png", row.file));
            write_rgb8(&path, &with_scale_labels(&map, HEAT_SCALE), args.force)?;
        }
        let ms = time_frames(&scene, &mut fb, row, args.frames, &mut || frames.tick());
        measured.push(Measured { row, ms, stats });
    }
    progress.finish();

    let threads = thread_count();
    say!(
        "scene: {}, {width}x{height}, {threads} thread{}, median of {} frame{} per mode after one untimed",
        scene_name(args),
        if threads == 1 { "" } else { "s" },
        args.frames,
        if args.frames == 1 { "" } else { "s" },
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

    if let Some(dir) = &out_dir {
        let points: Vec<PlotPoint> = measured
            .iter()
            .map(|m| PlotPoint {
                label: m.row.label.to_owned(),
                ms: m.ms,
                rmse: m.stats.rmse,
            })
            .collect();
        let title = format!("error against time: {}, {width}x{height}", scene_name(args));
        write_rgb8(
            &dir.join("error-vs-time.png"),
            &error_vs_time(&title, &points),
            args.force,
        )?;
        say!(
            "wrote {}: MODE.png, MODE-error.png (heat-map, white at {:.3} = 8/255 or more), error-vs-time.png",
            dir.display(),
            HEAT_SCALE
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
        for mode in ShadingMode::ALL {
            assert!(
                ROWS.iter()
                    .any(|r| r.shading == ShadingChoice::Mode(mode) && r.label == mode.name()),
                "{mode:?}"
            );
        }
        let mut files: Vec<&str> = ROWS.iter().map(|r| r.file).collect();
        files.sort_unstable();
        files.dedup();
        assert_eq!(files.len(), ROWS.len());
        assert_eq!(ROWS[ROWS.len() - 1].label, "reference");
        assert!(ROWS.iter().any(|r| r.shading == ShadingChoice::Auto));
    }
}
