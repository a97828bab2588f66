//! `phosphor bench`: frame times per mode, after a warm-up, loading excluded. One line per mode,
//! exactly `MODE median_ms=X min_ms=Y max_ms=Z frames=N` (docs/conventions.md, "Messages"), so
//! scripts can compare runs.

use std::time::Instant;

use phosphor_scene::{FrameOptions, render_frame};

use super::{framebuffer, size_field};
use crate::CliError;
use crate::accuracy::median;
use crate::args::BenchArgs;
use crate::limits::{FRAMEBUFFER_BYTES_PER_PIXEL, check_memory, sample_bytes_per_pixel, threads};

/// Runs `phosphor bench`.
pub fn run(args: &BenchArgs) -> Result<(), CliError> {
    let (scene, width, height) = crate::view::prepare(&args.source, &args.camera, args.size)?;
    check_memory(
        &size_field(&args.source, args.size),
        (width, height),
        FRAMEBUFFER_BYTES_PER_PIXEL + sample_bytes_per_pixel(scene.settings.antialias),
    )?;
    let mut fb = framebuffer(width, height)?;
    let threads = threads(args.threads);
    let simd = args.simd.simd().map_err(CliError::Usage)?;
    for choice in args.shading.choices() {
        let opts = FrameOptions {
            shading: Some(choice),
            threads,
            fast_phong: args.variants.fast_phong(),
            interpolation: args.variants.interpolation(),
            simd,
            shadows: args.shadows.shadows(),
            ..FrameOptions::default()
        };
        render_frame(&scene, &mut fb, &opts); // warm-up: caches, thread pool, tables
        let mut times = Vec::with_capacity(args.frames as usize);
        for _ in 0..args.frames {
            let start = Instant::now();
            render_frame(&scene, &mut fb, &opts);
            times.push(start.elapsed().as_secs_f64() * 1e3);
        }
        let min = times.iter().copied().fold(f64::INFINITY, f64::min);
        let max = times.iter().copied().fold(0.0f64, f64::max);
        say!(
            "{} median_ms={:.3} min_ms={min:.3} max_ms={max:.3} frames={}",
            choice.name(),
            median(&times),
            args.frames
        );
    }
    Ok(())
}
