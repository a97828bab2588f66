//! `phosphor render`: frames of a scene to PNG or EXR files, each written whole or not at all,
//! or one PNG to standard output.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use phosphor_raster::{Antialias, Encoding};
use phosphor_scene::animation::{Time, is_animated, update};
use phosphor_scene::view::turntable_camera;
use phosphor_scene::{FrameOptions, render_frame};

use super::{framebuffer, size_field};
use crate::CliError;
use crate::args::{EncodingArg, RenderArgs, ToneMapArg};
use crate::folders::{make_missing, missing_folders, remove_empty};
use crate::frames::{Output, animation_frames, frames_to_render, output_for};
use crate::limits::{FRAMEBUFFER_BYTES_PER_PIXEL, check_memory, sample_bytes_per_pixel, threads};
use crate::output::{
    Format, Look, check_output, format_of, is_stdout, write_image, write_png_to_stdout,
};
use crate::progress::{Progress, QUIET_FOR, set_fraction};
use crate::view::prepare;

/// Milliseconds with one decimal, for the closing line.
fn ms(d: Duration) -> String {
    format!("{:.1} ms", d.as_secs_f64() * 1e3)
}

/// Runs `phosphor render`: one frame, or the frames of a turntable (see `crate::frames`).
pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let started = Instant::now();
    // The frames and the output are checked before any work, so that a usage error, a refusal
    // or a bad extension is immediate.
    let frames = match args.fps {
        Some(fps) => animation_frames(fps, args.frames)?,
        None => frames_to_render(args.turntable, args.frames)?,
    };
    let stdout_is_terminal = std::io::stdout().is_terminal();
    let output = output_for(
        args.output.as_deref(),
        frames.len(),
        args.plan,
        stdout_is_terminal,
    )?;
    if let Output::Files(pattern) = &output {
        // A missing folder is made only when the frame is written (crate::folders).
        let first = pattern.path(frames.start);
        let missing = missing_folders(&first)?;
        if pattern.is_numbered() || !missing.is_empty() {
            format_of(pattern.given())?;
        }
        // The first file stands for its folder, refused now (unwritable, not a real one) and
        // not after the first frame is drawn. A missing folder is made then, so the nearest
        // folder that exists above it must take a file.
        match (missing.first(), first.file_name()) {
            (Some(top), Some(name)) => {
                let existing = top.parent().unwrap_or(top);
                if check_output(&existing.join(name), args.force).is_err() {
                    return Err(CliError::Input(format!(
                        "{}: cannot make folder {}: {} takes no new entry",
                        first.display(),
                        top.display(),
                        existing.display()
                    )));
                }
            }
            _ => {
                check_output(&first, args.force)?;
            }
        }
        if args.plan && is_stdout(&pattern.path(frames.start)) {
            return Err(CliError::Usage(format!(
                "-o {}: is standard output, which cannot also take --plan",
                pattern.given().display()
            )));
        }
    }
    let format = match &output {
        Output::Files(pattern) => format_of(&pattern.path(frames.start))?,
        Output::Stdout | Output::None => Format::Png,
    };
    if format == Format::Exr && args.tone_map != ToneMapArg::Clamp {
        return Err(CliError::Usage(format!(
            "--tone-map {}: applies to PNG only; EXR keeps intensities above 1 as they are",
            args.tone_map.tone_map()
        )));
    }
    let mut progress = Progress::new();
    let sequence = (frames.len() > 1).then(|| progress.counter("frames", frames.len() as u64));
    let stage = progress.fraction("loading (stage 1 of 3)");
    progress.show_after(QUIET_FOR);
    let (mut scene, width, height) = prepare(&args.source, &args.camera, args.size)?;
    if let Some(background) = args.background {
        background.apply(&mut scene);
    }
    let load_time = started.elapsed();
    // The PNG and EXR encoders stream rows and blocks: the framebuffer is the image's cost.
    check_memory(
        &size_field(&args.source, args.size),
        (width, height),
        FRAMEBUFFER_BYTES_PER_PIXEL + sample_bytes_per_pixel(scene.settings.antialias),
    )?;
    let simd = args.simd.simd().map_err(CliError::Usage)?;
    let opts = FrameOptions {
        shading: args.shading,
        threads: threads(args.threads),
        fast_phong: args.variants.fast_phong(),
        interpolation: args.variants.interpolation(),
        simd,
        shadows: args.shadows.shadows(),
        ..FrameOptions::default()
    };
    let encoding = match args.encoding {
        Some(EncodingArg::Srgb) => Encoding::Srgb,
        Some(EncodingArg::Linear) => Encoding::Linear,
        None => scene.settings.encoding,
    };
    // The render's time counts its framebuffer: allocating and clearing it is part of the work.
    let alloc_start = Instant::now();
    let mut fb = framebuffer(width, height)?;
    let look = Look {
        encoding,
        scale: args.exposure.exp2(),
        tone_map: args.tone_map.tone_map(),
        background_alpha: scene.settings.background_alpha,
    };
    fb.set_hdr(look.needs_hdr(format));
    let alloc_time = alloc_start.elapsed();
    let overlays = phosphor_raster::overlay::Overlays {
        wireframe: args.wireframe.map(|color| {
            (
                args.wire_edges
                    .unwrap_or(phosphor_raster::overlay::Edges::All),
                color,
            )
        }),
        grid: args.grid,
        axes: args.axes,
    };
    let home = scene.camera();
    let start_time = args.time.unwrap_or(0.0);
    // The world is posed for each frame's instant before its plan is made: the plan (modes,
    // lights kept, culling) is per frame, as objects move.
    let posed = is_animated(&scene.world) || args.time.is_some() || args.fps.is_some();
    let mut told: Vec<String> = Vec::new();
    for (index, frame) in frames.enumerate() {
        let frame_start = Instant::now();
        let time = match args.fps {
            Some(fps) => Time::of_frame(start_time, frame, fps),
            None => Time::at(start_time),
        };
        if posed {
            for w in update(&mut scene, time) {
                if !told.contains(&w) {
                    phosphor_output::term::warn(w.trim_start_matches("warning: "));
                    told.push(w);
                }
            }
        }
        let what = match (args.turntable, args.fps) {
            (Some(n), _) => {
                scene.set_camera(turntable_camera(&home, frame, n));
                format!("frame {frame} of {n}, ")
            }
            (None, Some(_)) => format!("frame {frame} at {:.3} s, ", time.seconds),
            (None, None) => String::new(),
        };
        // Each stage is a third of the frame's bar: loading (or nothing), rendering, saving.
        stage.reset();
        set_fraction(
            &stage,
            &format!("rendering {what}{width}x{height} (stage 2 of 3)"),
            1.0 / 3.0,
        );
        let render_start = Instant::now();
        let report = render_frame(&scene, &mut fb, &opts);
        // Overlays change the colours only: depths, and so the alpha, stay as drawn.
        if !overlays.is_empty() {
            let items = phosphor_scene::draw_items(&report.plan);
            let smooth = report.stats.antialias != Antialias::Off;
            overlays.draw(&mut fb, &scene.camera(), &items, smooth);
        }
        let colour = fb.color();
        let mut render_time = render_start.elapsed();
        if index == 0 {
            render_time += alloc_time;
        }
        if args.plan {
            progress.suspend(|| {
                say!("{}", report.plan.to_string().trim_end());
                say!(
                    "plan time: {:.3} ms, raster time: {:.3} ms",
                    report.plan_time.as_secs_f64() * 1e3,
                    report.raster_time.as_secs_f64() * 1e3
                );
                for (m, t) in report.plan.shadows.maps.iter().zip(&report.shadow_times) {
                    say!(
                        "shadow map of {}{}: {:.3} ms (in the raster time)",
                        report.plan.light_names[m.light],
                        m.face
                            .map_or_else(String::new, |f| format!(", cube face {f}")),
                        t.as_secs_f64() * 1e3
                    );
                }
                let aa = report.stats.antialias;
                say!(
                    "anti-aliasing: {aa}, {} sample{} per pixel",
                    aa.samples(),
                    if aa.samples() == 1 { "" } else { "s" }
                );
            });
        }
        let save_start = Instant::now();
        let out = match &output {
            Output::None => None,
            Output::Stdout => {
                // Standard output holds the image and nothing else.
                write_png_to_stdout(&fb, colour, &look)?;
                None
            }
            Output::Files(pattern) => {
                let out = pattern.path(frame);
                let made = make_missing(&out)?;
                let label = format!("saving {} (stage 3 of 3)", out.display());
                let checked = if pattern.is_numbered() || !made.is_empty() {
                    check_output(&out, args.force).map(|_| ())
                } else {
                    Ok(())
                };
                let written = checked.and_then(|()| {
                    write_image((&fb, colour), &out, &look, args.force, &mut |f| {
                        set_fraction(&stage, &label, (2.0 + f) / 3.0);
                    })
                });
                if let Err(e) = written {
                    remove_empty(&made);
                    return Err(e);
                }
                Some(out)
            }
        };
        if let Some(bar) = &sequence {
            bar.inc(1);
        }
        let save_time = save_start.elapsed();
        let s = report.stats;
        if let Some(out) = out {
            let total = if index == 0 {
                started.elapsed()
            } else {
                frame_start.elapsed()
            };
            let load = if index == 0 {
                load_time
            } else {
                Duration::ZERO
            };
            let line = format!(
                "rendered {} in {} (load {}, render {} = {:.0}%, save {}): {width}x{height}, {} of {} triangles drawn, {} {} shaded{}",
                out.display(),
                ms(total),
                ms(load),
                ms(render_time),
                100.0 * render_time.as_secs_f64() / total.as_secs_f64().max(1e-9),
                ms(save_time),
                s.triangles_drawn,
                s.triangles_in,
                s.pixels_shaded,
                // Supersampled, the counts are of samples; multisampled, of shadings (one per
                // pixel and triangle in the per-pixel modes).
                if s.antialias == Antialias::Off {
                    "pixels"
                } else if s.antialias.multisample() {
                    "pixel-triangle pairs"
                } else {
                    "samples"
                },
                if s.fallbacks > 0 {
                    format!(", {} fast-phong fallbacks", s.fallbacks)
                } else {
                    String::new()
                }
            );
            // An image written to standard output (`-o /dev/stdout`) is all that goes there.
            if is_stdout(&out) {
                phosphor_output::term::tell(&line);
            } else {
                progress.suspend(|| say!("{line}"));
            }
        }
        for w in &report.warnings {
            if !told.contains(w) {
                phosphor_output::term::warn(w.trim_start_matches("warning: "));
                told.push(w.clone());
            }
        }
        if s.bump_ignored > 0 && index == 0 {
            phosphor_output::term::warn(&format!(
                "bump mapping ignored on {} object(s): flat and gouraud shade per triangle or vertex",
                s.bump_ignored
            ));
        }
    }
    progress.finish();
    Ok(())
}
