//! One frame, draw by draw in submission order: each draw's mode is chosen (and specialized
//! for its effects), then run through the three stages, [`crate::vertex`], [`crate::bin`]
//! and [`crate::bands`]; with anti-aliasing, into a sample image resolved at the end.

use glam::{Mat4, Vec3};
use phosphor_lighting::Effects;

use crate::antialias::{Antialias, resolve};
use crate::bands::{BandInput, draw_bands};
use crate::bin::bin_draw;
use crate::framebuffer::{Framebuffer, RasterError};
use crate::shade::fast_phong::FastPhong;
use crate::shade::flat::{FillOnly, Flat};
use crate::shade::gouraud::Gouraud;
use crate::shade::incremental::Incremental;
use crate::shade::phong::Phong;
use crate::shade::reference::Reference;
use crate::shade::{Lit, Mode, effective_material};
use crate::vertex::{Viewport, vertex_stage};
use crate::{Camera, DrawItem, Interpolation, RenderOptions, RenderStats, ShadingMode};

/// Renders `draws` seen by `camera` into `fb` (cleared to `opts.background` first).
///
/// With [`RenderOptions::antialias`] on, the frame is drawn into a sample image `k` times
/// larger on each side (kept in `fb` for the next frame) and box-filtered into `fb`; an image
/// whose sample image would exceed the largest side is drawn with one sample per pixel, and
/// [`RenderStats::antialias`] says which was used.
///
/// Every draw is shaded with its own mode and effect set; bad input (indices out of range,
/// non-finite positions, zero-area triangles) is skipped, never a panic.
pub fn render(
    fb: &mut Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
) -> RenderStats {
    let aa = opts.antialias;
    if aa != Antialias::Off && aa.fits(fb.width(), fb.height()) {
        let k = aa.factor();
        let (width, height) = (fb.width() * k, fb.height() * k);
        let reusable = fb
            .samples
            .take()
            .filter(|s| s.width() == width && s.height() == height);
        // `fits` checked the sides, so only the allocation itself can fail: draw one sample
        // per pixel then, and say so in the stats.
        if let Some(mut samples) =
            reusable.or_else(|| Framebuffer::new(width, height).ok().map(Box::new))
        {
            let block = if aa.multisample() { k } else { 1 };
            let mut stats = render_samples(&mut samples, camera, draws, opts, block);
            resolve(&samples, fb, k, opts.threads);
            fb.samples = Some(samples);
            stats.antialias = aa;
            stats.simd = opts.simd.resolve();
            return stats;
        }
    }
    fb.samples = None;
    let mut stats = render_samples(fb, camera, draws, opts, 1);
    stats.simd = opts.simd.resolve();
    stats
}

/// Draws `draws` into `fb` as it is, a sample per pixel (`opts.antialias` is not looked at):
/// with `block > 1`, `fb` is a multisampled sample image whose per-pixel modes shade once per
/// `block x block` samples and triangle.
fn render_samples(
    fb: &mut Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
    block: u32,
) -> RenderStats {
    fb.defer_clear(opts.background);
    let mut stats = RenderStats::default();
    let vp = camera.view_proj(fb.width() as f32 / fb.height() as f32);
    let out = Output::Shade { block };
    for d in draws {
        shade_draw(fb, vp, camera.eye, d, opts, out, &mut stats);
    }
    fb.finish_clear();
    stats
}

/// What [`run`] writes.
#[derive(Debug, Clone, Copy)]
enum Output {
    /// Colours and depths; `block` as in [`draw_bands`] (1: every pixel shaded).
    Shade { block: u32 },
    /// The coverage-count test hook (no depth test): each pixel's red channel counts.
    Count,
}

/// Coverage and depth only, every draw in one constant colour (white): the fill-only speed
/// bound. Modes, lights and effects are ignored.
pub fn render_fill_only(
    fb: &mut Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
) -> RenderStats {
    fb.defer_clear(opts.background);
    let mut stats = RenderStats::default();
    let vp = camera.view_proj(fb.width() as f32 / fb.height() as f32);
    let mode = FillOnly { color: Vec3::ONE };
    for d in draws {
        run(
            fb,
            vp,
            d,
            &mode,
            opts,
            &mut stats,
            Output::Shade { block: 1 },
        );
    }
    fb.finish_clear();
    stats
}

/// Test hook: how many times each pixel of a `width` x `height` image is covered by `draws`,
/// with no depth test (row-major). With a correct fill rule a closed, non-overlapping
/// triangulation covers every pixel inside its silhouette exactly once per layer.
pub fn coverage_counts(
    width: u32,
    height: u32,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
) -> Result<Vec<u32>, RasterError> {
    let mut fb = Framebuffer::new(width, height)?;
    let vp = camera.view_proj(width as f32 / height as f32);
    let mode = FillOnly { color: Vec3::ONE };
    let mut stats = RenderStats::default();
    for d in draws {
        run(&mut fb, vp, d, &mode, opts, &mut stats, Output::Count);
    }
    Ok(fb.color.iter().map(|c| c.x as u32).collect())
}

fn shade_draw(
    fb: &mut Framebuffer,
    vp: Mat4,
    eye: Vec3,
    d: &DrawItem,
    opts: &RenderOptions,
    out: Output,
    stats: &mut RenderStats,
) {
    let n = d.mesh.positions.len();
    let has_frame =
        d.mesh.uvs.is_some_and(|u| u.len() == n) && d.mesh.tangents.is_some_and(|t| t.len() == n);
    let wants_bump = d.bump.is_some() && d.effects.contains(Effects::BUMP);
    let per_pixel = matches!(
        d.mode,
        ShadingMode::Phong | ShadingMode::FastPhong | ShadingMode::Reference
    );
    let bump = if wants_bump && has_frame && per_pixel {
        d.bump
    } else {
        None
    };
    if wants_bump && bump.is_none() {
        stats.bump_ignored += 1;
    }
    let incremental = opts.interpolation == Interpolation::Incremental;
    let lit = Lit {
        set: d.lights,
        mat: effective_material(d.material, d.effects),
        eye,
        avx2: opts.simd.token(),
    };
    match (d.mode, bump) {
        (ShadingMode::Flat, _) => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Flat::<FX> { lit }, opts, stats, out))
        }
        (ShadingMode::Gouraud, _) if incremental => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Incremental { inner: Gouraud::<FX> { lit, vertex_clamp: opts.gouraud_vertex_clamp } }, opts, stats, out))
        }
        (ShadingMode::Gouraud, _) => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Gouraud::<FX> { lit, vertex_clamp: opts.gouraud_vertex_clamp }, opts, stats, out))
        }
        (ShadingMode::Phong, Some(map)) if incremental => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Incremental { inner: Phong::<FX, true> { lit, bump: Some(map) } }, opts, stats, out))
        }
        (ShadingMode::Phong | ShadingMode::FastPhong, Some(map)) => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Phong::<FX, true> { lit, bump: Some(map) }, opts, stats, out))
        }
        (ShadingMode::Phong, None) if incremental => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Incremental { inner: Phong::<FX, false> { lit, bump: None } }, opts, stats, out))
        }
        (ShadingMode::Phong, None) => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Phong::<FX, false> { lit, bump: None }, opts, stats, out))
        }
        (ShadingMode::FastPhong, None) => {
            let method = opts.fast_phong;
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &FastPhong::<FX> { lit, method }, opts, stats, out))
        }
        (ShadingMode::Reference, _) => {
            let mut mat = lit.mat;
            if !d.effects.contains(Effects::SPECULAR) {
                mat.ks = Vec3::ZERO;
            }
            if !d.effects.contains(Effects::FRESNEL) {
                mat.fresnel = phosphor_lighting::Fresnel::None;
            }
            let mode = Reference {
                set: d.lights,
                mat,
                eye: eye.as_dvec3(),
                bump,
            };
            run(fb, vp, d, &mode, opts, stats, out);
        }
    }
}

/// Runs mode `M` over one draw through the three stages: vertex, bin (both in parallel over
/// the mesh, in order) and bands.
fn run<M: Mode>(
    fb: &mut Framebuffer,
    vp: Mat4,
    d: &DrawItem,
    mode: &M,
    opts: &RenderOptions,
    stats: &mut RenderStats,
    out: Output,
) {
    let (count, block) = match out {
        Output::Shade { block } => (false, block),
        Output::Count => (true, 1),
    };
    let view = Viewport::new(fb.width(), fb.height(), opts.perspective_correct, block);
    let cull = opts.cull_backfaces || d.cull_backfaces;
    let verts = vertex_stage(d, vp, mode, &view, opts.threads);
    let binned = bin_draw(d, mode, &verts, &view, cull, opts.threads);
    stats.triangles_in += d.mesh.indices.len() as u64;
    stats.triangles_drawn += binned.drawn;
    stats.fallbacks += binned.fallbacks;
    let input = BandInput {
        mode,
        pos: &verts.pos,
        attrs: &verts.attrs,
        chunks: &binned.chunks,
        perspective: view.perspective,
    };
    stats.pixels_shaded += draw_bands(fb, &input, opts.threads, count, block);
}
