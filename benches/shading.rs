//! Frame time of the rasterizer on the standard scene S1 (docs/conventions.md): per shading mode on
//! the bunny and on a UV sphere of about as many triangles, how the cost grows with triangles,
//! pixels and threads, and what the frame plan gains by simulating only the effects a scene calls
//! for. Throughput is covered pixels (`RenderStats::pixels_shaded` of one frame).
//!
//! Run everything (under 6 minutes on 2 loaded cores): `cargo bench --bench shading`. One group:
//! `cargo bench --bench shading -- s1_bunny`. A short preset for quick local runs (10 samples,
//! short warm-up and measurement): `PHOSPHOR_BENCH_QUICK=1 cargo bench --bench shading`.
//! On a shared, loaded machine `PHOSPHOR_BENCH_CLOCK=cpu` times the process's CPU time (all
//! threads, Linux) instead of the wall clock, which keeps the ratios between modes steady.

#![allow(
    clippy::unwrap_used,
    reason = "a benchmark with missing assets or invalid constants has nothing to measure"
)]

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::measurement::WallTime;
use criterion::{
    BenchmarkGroup, BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group,
    criterion_main,
};
use phosphor::lighting::{Attenuation, Effects, Light, LightKind, LightSet, Material, effects_for};
use phosphor::math::glam::{Mat4, Vec3};
use phosphor::mesh::{Mesh, NormalOptions, load_obj, primitives};
use phosphor::raster::{
    Camera, DrawItem, Framebuffer, MeshView, RenderOptions, RenderStats, ShadingMode, Texture,
    render, render_fill_only,
};

/// The headline size of S1 (docs/conventions.md).
const FULL_HD: (u32, u32) = (1920, 1080);
/// S1's second size.
const HD: (u32, u32) = (1280, 720);
/// Triangles of the S1 bunny (`assets/meshes/bunny.obj`), matched by the sphere.
const BUNNY_TRIANGLES: u32 = 75_000;

/// One object lit and seen as in S1: a mesh, its material, the lights and the effects to draw.
struct Scene {
    mesh: Mesh,
    material: Material,
    lights: LightSet,
    effects: Effects,
    /// A colour map, drawn with the mesh's uvs (the `textured` group).
    texture: Option<Texture>,
}

impl Scene {
    /// `mesh` with S1's material and lights and the plan's minimal effects.
    fn s1(mesh: Mesh) -> Scene {
        Scene::lit(mesh, Material::s1(), LightSet::s1())
    }

    /// `mesh` under `lights` with `material`, drawn with the minimal effects (`effects_for`).
    fn lit(mesh: Mesh, material: Material, lights: LightSet) -> Scene {
        let effects = effects_for(&lights, &material);
        Scene {
            mesh,
            material,
            lights,
            effects,
            texture: None,
        }
    }

    fn draw(&self, mode: ShadingMode) -> DrawItem<'_> {
        let m = &self.mesh;
        DrawItem {
            mesh: MeshView {
                positions: &m.positions,
                normals: &m.normals,
                uvs: self.texture.as_ref().and(m.uvs.as_deref()),
                tangents: None,
                colors: None,
                indices: &m.indices,
            },
            model: Mat4::IDENTITY,
            material: &self.material,
            lights: &self.lights,
            effects: self.effects,
            mode,
            bump: None,
            texture: self.texture.as_ref(),
            cull_backfaces: false,
        }
    }
}

/// The S1 bunny: normals averaged over all faces sharing a position, normalized to the unit ball,
/// stored in render order as the scene loader stores it (`Mesh::sort_spatially`).
fn bunny() -> Mesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/meshes/bunny.obj");
    let mut mesh = load_obj(&path, &NormalOptions::s1()).unwrap();
    mesh.normalize_unit();
    mesh.sort_spatially();
    mesh
}

/// A unit UV sphere with about `triangles` triangles (`2 s (r - 1)` for `s = 2r` segments and
/// `r` rings; the pole fans lose their degenerate half).
fn sphere(triangles: u32) -> Mesh {
    let rings = ((f64::from(triangles) / 4.0).sqrt().round() as u32).max(2);
    primitives::uv_sphere(1.0, 2 * rings, rings)
}

/// S1's thread count for the benchmarks: 2, or all cores if fewer.
fn two_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get().min(2))
}

/// What one frame runs: a shading mode, or coverage and depth only.
#[derive(Clone, Copy)]
enum Pass {
    Shade(ShadingMode),
    FillOnly,
}

impl Pass {
    fn name(self) -> &'static str {
        match self {
            Pass::Shade(mode) => mode.name(),
            Pass::FillOnly => "fill-only",
        }
    }
}

/// The passes of the S1 groups: every mode of [`ShadingMode::ALL`] (cheapest first), then
/// the fill-only bound.
fn s1_passes() -> impl Iterator<Item = Pass> {
    ShadingMode::ALL
        .into_iter()
        .map(Pass::Shade)
        .chain([Pass::FillOnly])
}

/// The two modes the growth and plan groups compare.
const GROWTH_MODES: [ShadingMode; 2] = [ShadingMode::Phong, ShadingMode::Gouraud];

/// How one benchmark renders: scene, pass, size and threads.
#[derive(Clone, Copy)]
struct Frame<'a> {
    scene: &'a Scene,
    pass: Pass,
    size: (u32, u32),
    threads: usize,
}

impl Frame<'_> {
    fn render(&self, fb: &mut Framebuffer) -> RenderStats {
        let opts = RenderOptions {
            threads: self.threads,
            ..RenderOptions::default()
        };
        let camera = Camera::s1();
        match self.pass {
            Pass::Shade(mode) => render(fb, &camera, &[self.scene.draw(mode)], &opts),
            Pass::FillOnly => {
                let draw = self.scene.draw(ShadingMode::Flat);
                render_fill_only(fb, &camera, &[draw], &opts)
            }
        }
    }
}

/// Benchmarks `frame` as `id` in `g`, with the covered pixels of one frame as throughput.
fn bench_frame(g: &mut BenchmarkGroup<'_, WallTime>, id: BenchmarkId, frame: Frame<'_>) {
    let mut fb = Framebuffer::new(frame.size.0, frame.size.1).unwrap();
    let pixels = frame.render(&mut fb).pixels_shaded;
    g.throughput(Throughput::Elements(pixels));
    let cpu_clock = cpu_clock();
    g.bench_function(id, |b| {
        if cpu_clock {
            b.iter_custom(|iters| {
                let start = process_cpu_time();
                for _ in 0..iters {
                    black_box(frame.render(&mut fb));
                }
                process_cpu_time().saturating_sub(start)
            });
        } else {
            b.iter(|| black_box(frame.render(&mut fb)));
        }
    });
}

/// `PHOSPHOR_BENCH_CLOCK=cpu`: time the CPU time of the whole process (all threads) instead of
/// the wall clock, so that other processes on a shared machine slow a frame down less. Not for
/// the `threads` group, where it measures the total work, not the speed-up.
/// Falls back to the wall clock where `/proc/self/task` is missing (not Linux).
fn cpu_clock() -> bool {
    std::env::var("PHOSPHOR_BENCH_CLOCK").is_ok_and(|v| v == "cpu")
        && Path::new("/proc/self/task").is_dir()
}

/// The CPU time this process's live threads have run: the first field (nanoseconds) of
/// Linux's `/proc/self/task/*/schedstat`. The rayon pools are
/// built once and kept, so no thread that worked on a frame exits before it is counted.
fn process_cpu_time() -> Duration {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return Duration::ZERO; // cpu_clock() checked it exists
    };
    let nanos = tasks
        .filter_map(|task| std::fs::read_to_string(task.ok()?.path().join("schedstat")).ok())
        .filter_map(|stat| stat.split_whitespace().next()?.parse::<u64>().ok())
        .sum();
    Duration::from_nanos(nanos)
}

/// Sampling settings: the default keeps a full run to a few minutes on 2 cores;
/// `PHOSPHOR_BENCH_QUICK=1` is a short preset for local checks.
struct Settings {
    sample_size: usize,
    /// Samples for the slowest frames (a million triangles, 4K, `reference`).
    heavy_sample_size: usize,
    warm_up: Duration,
    measurement: Duration,
}

impl Settings {
    fn from_env() -> Settings {
        if std::env::var("PHOSPHOR_BENCH_QUICK").is_ok_and(|v| v == "1") {
            Settings {
                sample_size: 10,
                heavy_sample_size: 10,
                warm_up: Duration::from_millis(300),
                measurement: Duration::from_secs(1),
            }
        } else {
            Settings {
                sample_size: 20,
                heavy_sample_size: 10,
                warm_up: Duration::from_secs(1),
                measurement: Duration::from_secs(4),
            }
        }
    }

    /// A group with these settings; flat sampling, since a frame takes milliseconds.
    fn group<'a>(&self, c: &'a mut Criterion, name: &str) -> BenchmarkGroup<'a, WallTime> {
        let mut g = c.benchmark_group(name);
        g.sampling_mode(SamplingMode::Flat)
            .sample_size(self.sample_size)
            .warm_up_time(self.warm_up)
            .measurement_time(self.measurement);
        g
    }

    /// Sets the sample size for the next benchmark in `g`: fewer samples when it is `heavy`.
    fn samples(&self, g: &mut BenchmarkGroup<'_, WallTime>, heavy: bool) {
        g.sample_size(if heavy {
            self.heavy_sample_size
        } else {
            self.sample_size
        });
    }
}

/// One group per S1 scene: every mode and fill-only at 1920x1080 on two threads.
fn s1_modes(c: &mut Criterion) {
    let settings = Settings::from_env();
    for (name, mesh) in [
        ("s1_sphere", sphere(BUNNY_TRIANGLES)),
        ("s1_bunny", bunny()),
    ] {
        let scene = Scene::s1(mesh);
        let mut g = settings.group(c, name);
        for pass in s1_passes() {
            let heavy = matches!(pass, Pass::Shade(ShadingMode::Reference));
            settings.samples(&mut g, heavy);
            let frame = Frame {
                scene: &scene,
                pass,
                size: FULL_HD,
                threads: two_threads(),
            };
            bench_frame(&mut g, BenchmarkId::from_parameter(pass.name()), frame);
        }
        g.finish();
    }
}

/// What a colour map costs: the S1 sphere at 1920x1080 on two threads in each mode, plain and
/// with a 512x512 checkerboard (16 repeats around, trilinear), the texture sampled per pixel.
fn textured(c: &mut Criterion) {
    let settings = Settings::from_env();
    let n = 512u32;
    let texels = (0..n * n)
        .map(|k| {
            if ((k % n) / 32 + (k / n) / 32).is_multiple_of(2) {
                Vec3::ONE
            } else {
                Vec3::splat(0.2)
            }
        })
        .collect();
    let checker = Texture::new(n, n, texels).unwrap();
    let plain = Scene::s1(sphere(BUNNY_TRIANGLES));
    let mapped = Scene {
        texture: Some(checker),
        ..Scene::s1(sphere(BUNNY_TRIANGLES))
    };
    let mut g = settings.group(c, "textured");
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        for (tag, scene) in [("plain", &plain), ("textured", &mapped)] {
            settings.samples(&mut g, false);
            let frame = Frame {
                scene,
                pass: Pass::Shade(mode),
                size: FULL_HD,
                threads: two_threads(),
            };
            bench_frame(&mut g, BenchmarkId::new(mode.name(), tag), frame);
        }
    }
    g.finish();
}

/// The sphere at about 1k, 10k, 100k and 1M triangles, 1280x720.
fn growth_triangles(c: &mut Criterion) {
    let settings = Settings::from_env();
    let mut g = settings.group(c, "growth_triangles");
    for target in [1_000, 10_000, 100_000, 1_000_000] {
        let scene = Scene::s1(sphere(target));
        let triangles = scene.mesh.indices.len();
        for mode in GROWTH_MODES {
            settings.samples(&mut g, target >= 1_000_000);
            let frame = Frame {
                scene: &scene,
                pass: Pass::Shade(mode),
                size: HD,
                threads: two_threads(),
            };
            bench_frame(&mut g, BenchmarkId::new(mode.name(), triangles), frame);
        }
    }
    g.finish();
}

/// The S1 sphere from 320x240 to 3840x2160.
fn growth_pixels(c: &mut Criterion) {
    let settings = Settings::from_env();
    let scene = Scene::s1(sphere(BUNNY_TRIANGLES));
    let mut g = settings.group(c, "growth_pixels");
    for size in [(320, 240), (640, 480), HD, FULL_HD, (3840, 2160)] {
        for mode in GROWTH_MODES {
            settings.samples(&mut g, size.0 >= 3840);
            let frame = Frame {
                scene: &scene,
                pass: Pass::Shade(mode),
                size,
                threads: two_threads(),
            };
            let id = BenchmarkId::new(mode.name(), format!("{}x{}", size.0, size.1));
            bench_frame(&mut g, id, frame);
        }
    }
    g.finish();
}

/// The S1 bunny in `phong` at 1920x1080 on 1, 2 and all cores (each count once).
fn threads(c: &mut Criterion) {
    let settings = Settings::from_env();
    let scene = Scene::s1(bunny());
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut counts = vec![1, 2, all];
    counts.sort_unstable();
    counts.dedup();
    let mut g = settings.group(c, "threads");
    for threads in counts {
        let frame = Frame {
            scene: &scene,
            pass: Pass::Shade(ShadingMode::Phong),
            size: FULL_HD,
            threads,
        };
        bench_frame(&mut g, BenchmarkId::new("phong", threads), frame);
    }
    g.finish();
}

/// S1's lights as the `plan_gain` group varies them.
#[derive(Clone, Copy)]
enum S1Lights {
    /// Moved to infinity: directional, along the same directions towards the origin, same
    /// intensities.
    Directional,
    /// Point lights without attenuation.
    Point,
    /// S1 as it is: point lights with `1/(1 + d)`.
    PointAttenuated,
}

impl S1Lights {
    const ALL: [S1Lights; 3] = [
        S1Lights::Directional,
        S1Lights::Point,
        S1Lights::PointAttenuated,
    ];

    fn name(self) -> &'static str {
        match self {
            S1Lights::Directional => "directional",
            S1Lights::Point => "point",
            S1Lights::PointAttenuated => "point-attenuated",
        }
    }

    fn set(self) -> LightSet {
        let lights = Light::s1_lights().map(|l| {
            let LightKind::Point { position } = l.kind else {
                unreachable!("S1's lights are point lights")
            };
            match self {
                S1Lights::Directional => Light::directional(-position, l.intensity).unwrap(),
                S1Lights::Point => l.with_attenuation(Attenuation::None).unwrap(),
                S1Lights::PointAttenuated => l,
            }
        });
        LightSet::new(Vec3::ONE, &lights)
    }
}

/// The frame plan's gain on the S1 bunny at 1920x1080: a material without specular (`ks = 0`)
/// drawn with its minimal effects against the full kernel (`Effects::ALL`), and directional
/// against point lights of the same directions.
fn plan_gain(c: &mut Criterion) {
    let settings = Settings::from_env();
    let mesh = bunny();
    let s1 = Material::s1();
    let matte = Material::new(s1.ka, s1.kd, Vec3::ZERO, s1.shininess).unwrap();
    let minimal = Scene::lit(mesh.clone(), matte, LightSet::s1());
    let full = Scene {
        effects: Effects::ALL,
        ..Scene::lit(mesh.clone(), matte, LightSet::s1())
    };
    let mut variants = vec![("ks0-minimal", minimal), ("ks0-all-effects", full)];
    for lights in S1Lights::ALL {
        variants.push((lights.name(), Scene::lit(mesh.clone(), s1, lights.set())));
    }
    let mut g = settings.group(c, "plan_gain");
    for (name, scene) in &variants {
        for mode in GROWTH_MODES {
            let frame = Frame {
                scene,
                pass: Pass::Shade(mode),
                size: FULL_HD,
                threads: two_threads(),
            };
            bench_frame(&mut g, BenchmarkId::new(mode.name(), name), frame);
        }
    }
    g.finish();
}

criterion_group!(
    benches,
    s1_modes,
    growth_triangles,
    growth_pixels,
    threads,
    plan_gain,
    textured
);
criterion_main!(benches);
