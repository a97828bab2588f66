//! What shadows cost: the default scene at 1280x720 with its key light's shadow map (the
//! scene's own choice) against the same frame with shadows off, on the machine's threads.
//! Before measuring it prints each map's size and the time its rendering took in one frame.
//!
//! `cargo bench --bench shadows` (set `PHOSPHOR_BENCH_QUICK=1` for a short run).

#![allow(clippy::unwrap_used, reason = "benchmark set-up on known-good data")]

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use phosphor::raster::Framebuffer;
use phosphor::scene::{FrameOptions, Scene, render_frame};

fn shadow_cost(c: &mut Criterion) {
    let quick = std::env::var_os("PHOSPHOR_BENCH_QUICK").is_some();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/default.toml");
    let scene = Scene::load(&path).unwrap();
    let mut fb = Framebuffer::new(1280, 720).unwrap();
    let with = FrameOptions::default();
    let without = FrameOptions {
        shadows: Some(false),
        ..FrameOptions::default()
    };
    let report = render_frame(&scene, &mut fb, &with);
    for (map, time) in report.plan.shadows.maps.iter().zip(&report.shadow_times) {
        let light = scene
            .lights()
            .get(map.light)
            .map_or_else(|| format!("light {}", map.light), |(n, _)| n.clone());
        eprintln!(
            "shadow map of {light}: {0}x{0}, rendered in {1:.2} ms",
            map.size,
            time.as_secs_f64() * 1e3
        );
    }
    assert!(
        !report.plan.shadows.maps.is_empty(),
        "the default scene's key light makes a map"
    );
    let mut g = c.benchmark_group("shadows_default_scene_1280x720");
    g.sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(if quick { 2 } else { 6 }));
    g.bench_function("key_light_map", |b| {
        b.iter(|| black_box(render_frame(&scene, &mut fb, &with).stats))
    });
    g.bench_function("shadows_off", |b| {
        b.iter(|| black_box(render_frame(&scene, &mut fb, &without).stats))
    });
    g.finish();
}

criterion_group!(benches, shadow_cost);
criterion_main!(benches);
