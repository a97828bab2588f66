//! Frame times of the standard scene S1 with the bunny, per shading mode and thread count.
//!
//! `cargo run --release -p phosphor-raster --example s1_frame -- [FRAMES] [WxH] [THREADS...]`
//! prints `MODE threads=N median_ms=X min_ms=Y cpu_ms=Z` per line (`cpu_ms`: on-CPU time of
//! all our threads, the cost without other processes' share of a busy machine), and `fill-only` (coverage, depth,
//! one constant colour) as the speed bound. Loading is excluded; each mode is warmed up once.
//! `S1_CULL=1` skips back faces (the bunny is a closed solid: the same picture); `S1_AA=msaa4`
//! (or another `--aa` name) anti-aliases the modes.

use std::path::Path;
use std::time::Instant;

use glam::Mat4;
use phosphor_lighting::{LightSet, Material, effects_for};
use phosphor_mesh::{NormalOptions, load_obj};
use phosphor_raster::{
    Antialias, Camera, DrawItem, Framebuffer, MeshView, RenderOptions, ShadingMode, render,
    render_fill_only,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let frames: usize = args.first().map_or(Ok(15), |s| s.parse())?;
    let (w, h) = match args.get(1) {
        Some(s) => {
            let (w, h) = s.split_once('x').ok_or("size is WxH")?;
            (w.parse()?, h.parse()?)
        }
        None => (1920, 1080),
    };
    let threads: Vec<usize> = if args.len() > 2 {
        args[2..]
            .iter()
            .map(|s| s.parse())
            .collect::<Result<_, _>>()?
    } else {
        vec![1, 2]
    };
    // The workspace's copy, or `assets/` under the working directory (a binary run elsewhere).
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/meshes/bunny.obj");
    let path = if built.exists() {
        built
    } else {
        Path::new("assets/meshes/bunny.obj").to_path_buf()
    };
    let mut mesh = load_obj(&path, &NormalOptions::s1())?;
    mesh.normalize_unit();
    // Render order, as the scene loader stores a file's mesh; S1_FILE_ORDER=1 keeps the
    // file's order, to measure what the order is worth.
    let file_order = std::env::var_os("S1_FILE_ORDER").is_some();
    if !file_order {
        mesh.sort_spatially();
    }
    // S1_CULL=1 skips back faces, as the scene's plan does for the closed bunny (the same
    // picture); without it both sides are drawn.
    let cull = std::env::var_os("S1_CULL").is_some();
    let (mat, lights, cam) = (Material::s1(), LightSet::s1(), Camera::s1());
    let effects = effects_for(&lights, &mat);
    let item = |mode| DrawItem {
        mesh: MeshView {
            positions: &mesh.positions,
            normals: &mesh.normals,
            uvs: None,
            tangents: None,
            colors: None,
            indices: &mesh.indices,
        },
        model: Mat4::IDENTITY,
        material: &mat,
        lights: &lights,
        effects,
        mode,
        bump: None,
        texture: None,
        cull_backfaces: cull,
    };
    // S1_ONLY=phong (or fill-only, ...) restricts the run to one line, for profilers.
    let only = std::env::var("S1_ONLY").ok();
    let wanted = |name: &str| only.as_deref().is_none_or(|o| o == name);
    let mut fb = Framebuffer::new(w, h)?;
    println!(
        "S1 bunny {w}x{h}: {} triangles ({} order), {frames} frames per line",
        mesh.indices.len(),
        if file_order { "file" } else { "render" }
    );
    for &t in &threads {
        // S1_AA=msaa4 (or any `--aa` name) draws every mode anti-aliased.
        let antialias = match std::env::var("S1_AA") {
            Ok(name) => name.parse()?,
            Err(_) => Antialias::Off,
        };
        let opts = RenderOptions {
            threads: t,
            antialias,
            ..RenderOptions::default()
        };
        let mut time = |name: &str, f: &mut dyn FnMut(&mut Framebuffer) -> u64| {
            let px = f(&mut fb);
            let (mut ms, mut cpu): (Vec<f64>, Vec<f64>) = (0..frames)
                .map(|_| {
                    let (t0, c0) = (Instant::now(), cpu_ns());
                    f(&mut fb);
                    let wall = t0.elapsed().as_secs_f64() * 1e3;
                    (wall, (cpu_ns() - c0) as f64 * 1e-6)
                })
                .unzip();
            ms.sort_by(f64::total_cmp);
            cpu.sort_by(f64::total_cmp);
            println!(
                "{name:<10} threads={t} median_ms={:.2} min_ms={:.2} cpu_ms={:.2} pixels={px}",
                ms[ms.len() / 2],
                ms[0],
                cpu[cpu.len() / 2]
            );
        };
        for mode in [
            ShadingMode::Flat,
            ShadingMode::Gouraud,
            ShadingMode::FastPhong,
            ShadingMode::Phong,
        ] {
            if !wanted(mode.name()) {
                continue;
            }
            let d = [item(mode)];
            time(mode.name(), &mut |fb| {
                render(fb, &cam, &d, &opts).pixels_shaded
            });
        }
        if !wanted("fill-only") {
            continue;
        }
        let d = [item(ShadingMode::Flat)];
        time("fill-only", &mut |fb| {
            render_fill_only(fb, &cam, &d, &opts).pixels_shaded
        });
    }
    Ok(())
}

/// On-CPU time of every thread of this process so far, in ns (`/proc/self/task/*/schedstat`,
/// Linux; 0 elsewhere). On a machine shared with other work the wall clock counts the time
/// other processes hold the cores; this counts only our own work (the median of `cpu_ms`
/// per frame with `threads=1` is the frame's cost on one core).
fn cpu_ns() -> u64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return 0;
    };
    tasks
        .flatten()
        .filter_map(|t| std::fs::read_to_string(t.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum()
}
