//! `phosphor render`: one frame of a scene to a PNG or EXR file, written whole or not at all.

use std::time::{Duration, Instant};

use phosphor_raster::Encoding;
use phosphor_scene::{FrameOptions, render_frame};

use super::{frame_size, framebuffer, load_source, shading_choice, size_field};
use crate::CliError;
use crate::args::{EncodingArg, RenderArgs};
use crate::limits::{FRAMEBUFFER_BYTES_PER_PIXEL, check_memory, threads};
use crate::output::{check_output, write_image};
use crate::progress::{Progress, time_left};

/// Milliseconds with one decimal, for the closing line.
fn ms(d: Duration) -> String {
    format!("{:.1} ms", d.as_secs_f64() * 1e3)
}

/// Runs `phosphor render`.
pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let started = Instant::now();
    // The output is checked before any work, so that a refusal or a bad extension is immediate.
    if let Some(out) = &args.output {
        check_output(out, args.force)?;
    }
    let progress = Progress::start("loading (stage 1 of 3)");
    let scene = load_source(&args.source)?;
    let load_time = started.elapsed();
    // The render's time counts its framebuffer: allocating and clearing it is part of the work.
    let render_start = Instant::now();
    let (width, height) = frame_size(&scene, args.size);
    // The PNG and EXR encoders stream rows and blocks: the framebuffer is the image's cost.
    check_memory(
        &size_field(&args.source, args.size),
        (width, height),
        FRAMEBUFFER_BYTES_PER_PIXEL,
    )?;
    let opts = FrameOptions {
        shading: args.shading.map(shading_choice),
        threads: threads(args.threads),
        ..FrameOptions::default()
    };
    progress.set(
        &format!("rendering {width}x{height} (stage 2 of 3)"),
        1.0 / 3.0,
        None,
    );
    let mut fb = framebuffer(width, height)?;
    let report = render_frame(&scene, &mut fb, &opts);
    let render_time = render_start.elapsed();
    let mut save_time = Duration::ZERO;
    if let Some(out) = &args.output {
        let encoding = match args.encoding {
            Some(EncodingArg::Srgb) => Encoding::Srgb,
            Some(EncodingArg::Linear) => Encoding::Linear,
            None => scene.settings.encoding,
        };
        let label = format!("saving {} (stage 3 of 3)", out.display());
        let save_start = Instant::now();
        write_image(&fb, out, encoding, args.force, &mut |f| {
            progress.set(&label, (2.0 + f) / 3.0, time_left(save_start.elapsed(), f));
        })?;
        save_time = save_start.elapsed();
    }
    progress.finish();
    if args.plan {
        say!("{}", report.plan.to_string().trim_end());
        say!(
            "plan time: {:.3} ms, raster time: {:.3} ms",
            report.plan_time.as_secs_f64() * 1e3,
            report.raster_time.as_secs_f64() * 1e3
        );
    }
    let Some(out) = &args.output else {
        return Ok(());
    };
    let total = started.elapsed();
    let s = report.stats;
    say!(
        "rendered {} in {} (load {}, render {} = {:.0}%, save {}): {width}x{height}, {} of {} triangles drawn, {} pixels shaded{}",
        out.display(),
        ms(total),
        ms(load_time),
        ms(render_time),
        100.0 * render_time.as_secs_f64() / total.as_secs_f64().max(1e-9),
        ms(save_time),
        s.triangles_drawn,
        s.triangles_in,
        s.pixels_shaded,
        if s.fallbacks > 0 {
            format!(", {} fast-phong fallbacks", s.fallbacks)
        } else {
            String::new()
        }
    );
    if s.bump_ignored > 0 {
        phosphor_output::term::warn(&format!(
            "bump mapping ignored on {} object(s): flat and gouraud shade per triangle or vertex",
            s.bump_ignored
        ));
    }
    Ok(())
}
