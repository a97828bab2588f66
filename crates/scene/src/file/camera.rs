//! A scene file's `[camera]` table: where the eye is, what it looks at, and how it projects.
//!
//! ```toml
//! [camera]
//! eye = [0, 0, 3]
//! target = [0, 0, 0]
//! fov_y_deg = 45                  # perspective only
//! projection = "orthographic"     # or "perspective" (the default)
//! ortho_height = 2.5              # orthographic: world units the image spans vertically
//! ```
//!
//! An orthographic camera without `ortho_height` spans what the perspective view spans at the
//! target's depth, so that switching the projection keeps the framing of the target.

use phosphor_raster::{Camera, Projection};

use super::read::{Fields, choose};
use crate::error::SceneError;

/// The `[camera]` table.
pub(crate) fn camera(c: &Fields<'_>) -> Result<(Camera, super::motion::Motion), SceneError> {
    let motion = super::motion::motion(c)?;
    let s1 = Camera::s1();
    let mut cam = Camera {
        eye: c.vec3("eye")?.unwrap_or(s1.eye),
        target: c.vec3("target")?.unwrap_or(s1.target),
        up: c.vec3("up")?.unwrap_or(s1.up),
        fov_y_deg: c.f32("fov_y_deg")?.unwrap_or(s1.fov_y_deg),
        near: c.f32("near")?.unwrap_or(s1.near),
        far: c.f32("far")?.unwrap_or(s1.far),
        projection: Projection::Perspective,
    };
    let orthographic = match c.str("projection")? {
        Some(name) => choose(
            c,
            "projection",
            name,
            &[("perspective", false), ("orthographic", true)],
        )?,
        None => false,
    };
    let height = c.f32("ortho_height")?;
    c.finish(&[
        "eye",
        "target",
        "up",
        "fov_y_deg",
        "near",
        "far",
        "projection",
        "ortho_height",
        "parent",
        "spin",
        "orbit",
        "bob",
        "animation",
    ])?;
    if !(cam.fov_y_deg > 0.0 && cam.fov_y_deg < 180.0) {
        return Err(c.error(
            "fov_y_deg",
            format!(
                "must be between 0 and 180 (exclusive), got {}",
                cam.fov_y_deg
            ),
        ));
    }
    if cam.near <= 0.0 {
        return Err(c.error("near", format!("must be > 0, got {}", cam.near)));
    }
    if cam.far <= cam.near {
        return Err(c.error(
            "far",
            format!("must be greater than near ({}), got {}", cam.near, cam.far),
        ));
    }
    let dir = cam.target - cam.eye;
    if dir.length_squared() < 1e-12 {
        return Err(c.error("target", "must differ from eye"));
    }
    if dir.normalize().cross(cam.up).length_squared() < 1e-10 {
        return Err(c.error("up", "must not be parallel to the view direction"));
    }
    match (orthographic, height) {
        (false, Some(_)) => {
            return Err(c.error(
                "ortho_height",
                "applies to projection = \"orthographic\" only",
            ));
        }
        (true, Some(h)) if !(h.is_finite() && h > 0.0) => {
            return Err(c.error("ortho_height", format!("must be > 0, got {h}")));
        }
        (true, h) => {
            let height = h.unwrap_or_else(|| cam.view_height_at_target());
            cam.projection = Projection::Orthographic { height };
        }
        (false, None) => {}
    }
    Ok((cam, motion))
}
