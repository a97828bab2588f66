//! `phosphor render`: frames of a scene to PNG or EXR files, each written atomically, or one
//! PNG to standard output.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use phosphor_raster::{Encoding, Framebuffer};
use phosphor_scene::view::turntable_camera;
use phosphor_scene::{FrameOptions, render_frame};

use super::{framebuffer, shading_choice};
use crate::CliError;
use crate::args::{EncodingArg, RenderArgs};
use crate::frames::{Output, frames_to_render, output_for, write_png_to_stdout};
use crate::view::prepare;

/// The output format, from the extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Png,
    Exr,
}

fn format_of(path: &Path) -> Result<Format, CliError> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("png") => Ok(Format::Png),
        Some("exr") => Ok(Format::Exr),
        _ => Err(CliError::Usage(format!(
            "{}: output must end in .png or .exr",
            path.display()
        ))),
    }
}

/// Writes `fb` to `out` through a temporary file beside it and a rename, so a failure never
/// leaves a half-written file, nor touches an existing one.
pub fn write_image(fb: &Framebuffer, out: &Path, encoding: Encoding) -> Result<(), CliError> {
    let format = format_of(out)?;
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = if format == Format::Png { "png" } else { "exr" };
    let tmp: PathBuf = out.with_file_name(format!(".{name}.{}.tmp.{ext}", std::process::id()));
    let written = match format {
        Format::Png => fb.save_png(&tmp, encoding),
        Format::Exr => fb.save_exr(&tmp),
    };
    let result = written.map_err(|e| e.to_string()).and_then(|()| {
        std::fs::rename(&tmp, out).map_err(|e| format!("{}: cannot write: {e}", out.display()))
    });
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        // The library names the temporary file; name the one the user asked for.
        let tmp_name = tmp.display().to_string();
        return Err(CliError::Input(
            e.replace(&tmp_name, &out.display().to_string()),
        ));
    }
    Ok(())
}

/// A spinner-style progress line on stderr for renders longer than a second (terminal only).
struct Progress {
    done: Arc<AtomicBool>,
    handle: Option<std::thread::JoinHandle<()>>,
}

impl Progress {
    fn start(label: String) -> Progress {
        let done = Arc::new(AtomicBool::new(false));
        let handle = std::io::stderr().is_terminal().then(|| {
            let done = done.clone();
            std::thread::spawn(move || {
                let start = Instant::now();
                let mut shown = false;
                while !done.load(Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(100));
                    let t = start.elapsed();
                    if t >= Duration::from_secs(1) {
                        let bar = "#".repeat(((t.as_millis() / 250) % 20) as usize + 1);
                        eprint!("\r{label} [{bar:<20}] {:.1} s", t.as_secs_f64());
                        shown = true;
                    }
                }
                if shown {
                    eprint!("\r{}\r", " ".repeat(label.len() + 32));
                }
            })
        });
        Progress { done, handle }
    }

    fn finish(mut self) {
        self.done.store(true, Ordering::Relaxed);
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

/// Runs `phosphor render`: one frame, or the frames of a turntable (see `crate::frames`).
pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    // Check the frames and the output before any work, so a usage error is immediate.
    let frames = frames_to_render(args.turntable, args.frames)?;
    let output = output_for(args.output.as_deref(), frames.len(), args.plan)?;
    if let Output::Files(pattern) = &output {
        format_of(pattern.given())?;
    }
    let (mut scene, width, height) = prepare(&args.source, &args.camera, args.size)?;
    let opts = FrameOptions {
        shading: args.shading.map(shading_choice),
        threads: args.threads.unwrap_or(0),
        ..FrameOptions::default()
    };
    let encoding = match args.encoding {
        Some(EncodingArg::Srgb) => Encoding::Srgb,
        Some(EncodingArg::Linear) => Encoding::Linear,
        None => scene.settings.encoding,
    };
    let mut fb = framebuffer(width, height)?;
    let home = scene.camera();
    for &frame in &frames {
        let label = match args.turntable {
            Some(n) => {
                scene.set_camera(turntable_camera(&home, frame, n));
                format!("rendering frame {frame} of {n}, {width}x{height}")
            }
            None => format!("rendering {width}x{height}"),
        };
        let progress = Progress::start(label);
        let start = Instant::now();
        let report = render_frame(&scene, &mut fb, &opts);
        let elapsed = start.elapsed();
        progress.finish();
        if args.plan {
            say!("{}", report.plan.to_string().trim_end());
            say!(
                "plan time: {:.3} ms, raster time: {:.3} ms",
                report.plan_time.as_secs_f64() * 1e3,
                report.raster_time.as_secs_f64() * 1e3
            );
        }
        let out = match &output {
            Output::None => continue,
            Output::Stdout => {
                // Standard output holds the image and nothing else.
                write_png_to_stdout(&fb, encoding)?;
                None
            }
            Output::Files(pattern) => {
                let out = pattern.path(frame);
                write_image(&fb, &out, encoding)?;
                Some(out)
            }
        };
        let s = report.stats;
        if let Some(out) = out {
            say!(
                "rendered {} in {:.1} ms: {width}x{height}, {} of {} triangles drawn, {} pixels shaded{}",
                out.display(),
                elapsed.as_secs_f64() * 1e3,
                s.triangles_drawn,
                s.triangles_in,
                s.pixels_shaded,
                if s.fallbacks > 0 {
                    format!(", {} fast-phong fallbacks", s.fallbacks)
                } else {
                    String::new()
                }
            );
        }
        if s.bump_ignored > 0 {
            eprintln!(
                "warning: bump mapping ignored on {} object(s): flat and gouraud shade per triangle or vertex",
                s.bump_ignored
            );
        }
    }
    Ok(())
}
