//! The triangle-size study of docs/accuracy.md as a criterion group: S1's sphere held at one
//! screen size (960x540, about 300 px across) and tessellated from 8 to 512 segments, so that
//! the same pixels are shaded by 20 to about 66 000 triangles. Every mode and both fast-Phong
//! methods, one thread, at the baseline SIMD level (four lanes) and the best one this CPU runs.
//! Throughput is the covered pixels of one frame, so criterion's `elem/s` is pixels per second.
//!
//! Before measuring it prints, per tessellation, the triangles drawn, the pixels per triangle
//! and how many triangles each fast-Phong method handed back to `phong` (its fallbacks): where
//! every triangle falls back, that method's row *is* `phong`'s work plus a failed set-up.
//!
//! `cargo bench --bench triangle_size` (`PHOSPHOR_BENCH_QUICK=1` for a short run; one
//! tessellation: `cargo bench --bench triangle_size -- /64`).

#![allow(
    clippy::unwrap_used,
    reason = "a benchmark with missing assets or invalid constants has nothing to measure"
)]

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use phosphor::raster::{FastPhongMethod, Framebuffer, ShadingMode, SimdLevel};
use phosphor::scene::{FrameOptions, Scene, ShadingChoice, render_frame};

/// Segments around the sphere (rings are half as many), from 7000 to 2.5 pixels per triangle.
const SEGMENTS: [u32; 7] = [8, 16, 32, 64, 128, 256, 512];

/// The rows of the study: a name, the mode and the fast-Phong method where it applies.
const ROWS: [(&str, ShadingMode, Option<FastPhongMethod>); 5] = [
    ("flat", ShadingMode::Flat, None),
    ("gouraud", ShadingMode::Gouraud, None),
    (
        "fast-phong:fit",
        ShadingMode::FastPhong,
        Some(FastPhongMethod::Fit),
    ),
    (
        "fast-phong:taylor",
        ShadingMode::FastPhong,
        Some(FastPhongMethod::Taylor),
    ),
    ("phong", ShadingMode::Phong, None),
];

/// S1's sphere scene with the tessellation replaced.
fn sphere(segments: u32) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/s1-sphere.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let needle = "segments = 128, rings = 64";
    assert!(text.contains(needle), "s1-sphere.toml's tessellation moved");
    let text = text.replace(
        needle,
        &format!("segments = {segments}, rings = {}", segments / 2),
    );
    Scene::parse(&text, "s1-sphere.toml").unwrap()
}

fn options(mode: ShadingMode, method: Option<FastPhongMethod>, simd: SimdLevel) -> FrameOptions {
    FrameOptions {
        shading: Some(ShadingChoice::Mode(mode)),
        fast_phong: method,
        threads: 1,
        simd,
        ..FrameOptions::default()
    }
}

fn triangle_size(c: &mut Criterion) {
    let quick = std::env::var_os("PHOSPHOR_BENCH_QUICK").is_some();
    let mut fb = Framebuffer::new(960, 540).unwrap();
    let mut g = c.benchmark_group("triangle_size_960x540");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(if quick { 200 } else { 500 }))
        .measurement_time(Duration::from_millis(if quick { 500 } else { 1500 }));
    for segments in SEGMENTS {
        let scene = sphere(segments);
        let probe = render_frame(
            &scene,
            &mut fb,
            &options(ShadingMode::Phong, None, SimdLevel::Auto),
        );
        let (drawn, pixels) = (probe.stats.triangles_drawn, probe.stats.pixels_shaded);
        let fallbacks: Vec<String> = ROWS
            .iter()
            .filter(|(_, _, method)| method.is_some())
            .map(|&(name, mode, method)| {
                let stats =
                    render_frame(&scene, &mut fb, &options(mode, method, SimdLevel::Auto)).stats;
                format!("{name} {} fallbacks", stats.fallbacks)
            })
            .collect();
        eprintln!(
            "{segments} segments: {drawn} triangles drawn, {pixels} pixels, {:.1} px per triangle; {}",
            pixels as f64 / drawn.max(1) as f64,
            fallbacks.join(", ")
        );
        g.throughput(Throughput::Elements(pixels));
        for simd in [SimdLevel::Baseline, SimdLevel::Auto] {
            for &(name, mode, method) in &ROWS {
                let opts = options(mode, method, simd);
                let id = BenchmarkId::new(format!("{name}/{}", simd.name()), segments);
                g.bench_with_input(id, &opts, |b, opts| {
                    b.iter(|| black_box(render_frame(&scene, &mut fb, opts).stats))
                });
            }
        }
    }
    g.finish();
}

criterion_group!(benches, triangle_size);
criterion_main!(benches);
