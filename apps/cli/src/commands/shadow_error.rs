//! The shadow maps' error in `phosphor accuracy`: where the scene's plan makes shadow maps,
//! `phong` drawn with them against `reference` drawn with an exact `f64` shadow ray per pixel
//! and light, both with the scene's shadows, over the pixels the reference covers. Phong's own
//! shading error is under 1e-5, so what the row shows is the maps' (their texels, bias and
//! filtered penumbra against the hard shadow of the exact rays).

use std::path::Path;
use std::time::Instant;

use phosphor_math::glam::Vec3;

use phosphor_raster::framebuffer::FAR_DEPTH;
use phosphor_raster::{Encoding, Framebuffer, ShadingMode};
use phosphor_scene::{FrameOptions, Scene, ShadingChoice, render_frame};

use crate::CliError;
use crate::accuracy::{compare, heat_map, with_scale_labels, with_title};
use crate::output::write_rgb8;

/// The measured error and what it was measured on.
#[derive(Debug, Clone)]
pub struct ShadowError {
    /// `LIGHT SIZExSIZE` (with the cube face) per map made.
    pub maps: Vec<String>,
    /// Error of `phong` with the maps against `reference` with rays.
    pub stats: crate::accuracy::ErrorStats,
    /// Covered pixels the rays put in some light's shadow (darker than without shadows).
    pub shadowed_pixels: usize,
    /// Milliseconds of one frame: phong with maps, reference with rays.
    pub ms: (f64, f64),
}

fn options(mode: ShadingMode) -> FrameOptions {
    FrameOptions {
        shading: Some(ShadingChoice::Mode(mode)),
        // As the scene says.
        shadows: None,
        threads: 0,
        ..FrameOptions::default()
    }
}

/// Measures the shadow maps' error on `scene`, or `None` when its plan makes no map;
/// `unshadowed` is the report's own `reference` frame, drawn with shadows off. With
/// `out_dir`, writes `shadow-maps-error.png` there (white at `scale`).
///
/// # Errors
/// Writing the heat-map fails.
pub fn measure(
    scene: &Scene,
    fb: &mut Framebuffer,
    (encoding, unshadowed): (Encoding, &[Vec3]),
    out_dir: Option<&Path>,
    (scale, force): (f32, bool),
) -> Result<Option<ShadowError>, CliError> {
    let start = Instant::now();
    let report = render_frame(scene, fb, &options(ShadingMode::Reference));
    let rays_ms = start.elapsed().as_secs_f64() * 1e3;
    if report.plan.shadows.maps.is_empty() {
        return Ok(None);
    }
    let maps = report
        .plan
        .shadows
        .maps
        .iter()
        .map(|m| {
            let face = m.face.map_or_else(String::new, |f| format!(" face {f}"));
            format!(
                "{}{face} {}x{}",
                report.plan.light_names[m.light], m.size, m.size
            )
        })
        .collect();
    let rays = fb.color().to_vec();
    let covered: Vec<bool> = fb.depth().iter().map(|&z| z < FAR_DEPTH).collect();
    let shadowed_pixels = rays
        .iter()
        .zip(unshadowed)
        .zip(&covered)
        .filter(|((a, b), c)| **c && (a.x < b.x || a.y < b.y || a.z < b.z))
        .count();
    let start = Instant::now();
    render_frame(scene, fb, &options(ShadingMode::Phong));
    let maps_ms = start.elapsed().as_secs_f64() * 1e3;
    let image = fb.color().to_vec();
    let stats = compare(&image, &rays, Some(&covered), encoding)
        .ok_or_else(|| CliError::Input("the reference frame covers no pixel".to_owned()))?;
    if let Some(dir) = out_dir {
        let map = heat_map(&image, &rays, fb.width(), fb.height(), scale)
            .ok_or_else(|| CliError::Input("frames of different sizes".to_owned()))?;
        let title = format!(
            "phong with shadow maps: |error| vs reference with exact shadow rays, linear, largest channel (white: {scale:.4} = 8/255 or more)"
        );
        write_rgb8(
            &dir.join("shadow-maps-error.png"),
            &with_title(&with_scale_labels(&map, scale), &title),
            force,
        )?;
    }
    Ok(Some(ShadowError {
        maps,
        stats,
        shadowed_pixels,
        ms: (maps_ms, rays_ms),
    }))
}
