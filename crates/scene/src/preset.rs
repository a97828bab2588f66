//! The standard views of a scene: front, back, left, right, top, bottom and iso, each looking
//! at the centre of the scene's bounding sphere from the distance where the sphere fits the
//! view (as `--mesh` frames a mesh).
//!
//! World +Y is up and the front is the +Z side, as in S1: `front` looks from +Z along -Z,
//! `right` from +X, `top` down from +Y with the front at the bottom of the image (up is -Z),
//! `bottom` up from -Y with the front at the top, and `iso` from the (+X, +Y, +Z) diagonal
//! (azimuth 45, elevation 35.26 degrees), the isometric view.
//!
//! ```
//! use glam::Vec3;
//! use phosphor_scene::preset::{ViewPreset, preset_camera};
//!
//! let top: ViewPreset = "top".parse().unwrap();
//! let cam = preset_camera(top, Vec3::ZERO, 1.0, 45.0, 16.0 / 9.0);
//! assert!(cam.eye.y > 0.0 && cam.eye.x.abs() < 1e-6 && cam.eye.z.abs() < 1e-6);
//! assert_eq!(cam.up, -Vec3::Z);
//! ```

use std::fmt;
use std::str::FromStr;

use glam::Vec3;
use phosphor_raster::{Camera, Projection};

use crate::view::{fit_distance, planes_around};

/// A standard view (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViewPreset {
    /// From +Z, looking along -Z.
    Front,
    /// From -Z.
    Back,
    /// From -X.
    Left,
    /// From +X.
    Right,
    /// Down from +Y, the front at the bottom of the image.
    Top,
    /// Up from -Y, the front at the top of the image.
    Bottom,
    /// From the (+X, +Y, +Z) diagonal.
    Iso,
}

impl ViewPreset {
    /// Every preset, in the order the viewer's key steps through them.
    pub const ALL: [ViewPreset; 7] = [
        ViewPreset::Front,
        ViewPreset::Right,
        ViewPreset::Back,
        ViewPreset::Left,
        ViewPreset::Top,
        ViewPreset::Bottom,
        ViewPreset::Iso,
    ];

    /// The name on a command line: `front`, `back`, `left`, `right`, `top`, `bottom`, `iso`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ViewPreset::Front => "front",
            ViewPreset::Back => "back",
            ViewPreset::Left => "left",
            ViewPreset::Right => "right",
            ViewPreset::Top => "top",
            ViewPreset::Bottom => "bottom",
            ViewPreset::Iso => "iso",
        }
    }

    /// The preset after this one in [`ViewPreset::ALL`], the first after the last.
    #[must_use]
    pub fn next(self) -> ViewPreset {
        let at = ViewPreset::ALL
            .iter()
            .position(|p| *p == self)
            .unwrap_or_default();
        ViewPreset::ALL[(at + 1) % ViewPreset::ALL.len()]
    }

    /// The unit direction from the centre to the eye, and the camera's up direction.
    #[must_use]
    pub fn direction_and_up(self) -> (Vec3, Vec3) {
        match self {
            ViewPreset::Front => (Vec3::Z, Vec3::Y),
            ViewPreset::Back => (-Vec3::Z, Vec3::Y),
            ViewPreset::Left => (-Vec3::X, Vec3::Y),
            ViewPreset::Right => (Vec3::X, Vec3::Y),
            ViewPreset::Top => (Vec3::Y, -Vec3::Z),
            ViewPreset::Bottom => (-Vec3::Y, Vec3::Z),
            ViewPreset::Iso => (Vec3::ONE.normalize(), Vec3::Y),
        }
    }
}

impl fmt::Display for ViewPreset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ViewPreset {
    type Err = String;

    fn from_str(text: &str) -> Result<ViewPreset, String> {
        ViewPreset::ALL
            .into_iter()
            .find(|p| p.name() == text)
            .ok_or_else(|| {
                format!(
                    "unknown view `{text}` (expected front, back, left, right, top, bottom or iso)"
                )
            })
    }
}

/// The perspective camera of `preset` looking at `centre`, at the distance where a sphere of
/// `radius` around it fits a view of `fov_y_deg` at `aspect` (width / height) with a 5%
/// margin, with near and far planes around the sphere. A radius that is not finite and
/// positive is taken as 1.
#[must_use]
pub fn preset_camera(
    preset: ViewPreset,
    centre: Vec3,
    radius: f32,
    fov_y_deg: f32,
    aspect: f32,
) -> Camera {
    let radius = if radius.is_finite() && radius > 0.0 {
        radius
    } else {
        1.0
    };
    let distance = fit_distance(radius, fov_y_deg, aspect);
    let (near, far) = planes_around(distance, radius);
    let (direction, up) = preset.direction_and_up();
    Camera {
        eye: centre + direction * distance,
        target: centre,
        up,
        fov_y_deg,
        near,
        far,
        projection: Projection::Perspective,
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn every_preset_looks_at_the_centre_from_its_side_and_fits_the_sphere() {
        let centre = Vec3::new(1.0, -2.0, 0.5);
        for preset in ViewPreset::ALL {
            let cam = preset_camera(preset, centre, 2.0, 45.0, 16.0 / 9.0);
            let (dir, up) = preset.direction_and_up();
            assert_eq!(cam.target, centre);
            assert!(
                (cam.eye - centre).normalize().distance(dir) < 1e-5,
                "{preset}"
            );
            assert!(dir.cross(up).length() > 0.8, "{preset}: up along the view");
            let d = cam.eye.distance(centre);
            assert!(cam.near < d - 2.0 && cam.far > d + 2.0, "{preset}");
            // The sphere fits the vertical half-angle (the narrower one at 16:9).
            assert!((2.0 / d).asin() < 22.5f32.to_radians(), "{preset}");
            assert!(cam.view().is_finite() && cam.view_proj(1.5).is_finite());
            assert_eq!(preset.name().parse::<ViewPreset>(), Ok(preset));
        }
        // Up +Y: the right view shows +Z (the front) on the left of the image.
        let right = preset_camera(ViewPreset::Right, Vec3::ZERO, 1.0, 45.0, 1.0);
        let front_point = right.view_proj(1.0) * Vec3::Z.extend(1.0);
        assert!(front_point.x < 0.0);
        // Top: the front (+Z) is at the bottom of the image.
        let top = preset_camera(ViewPreset::Top, Vec3::ZERO, 1.0, 45.0, 1.0);
        let front_point = top.view_proj(1.0) * Vec3::Z.extend(1.0);
        assert!(front_point.y < 0.0);
        assert!(
            "side"
                .parse::<ViewPreset>()
                .unwrap_err()
                .contains("front, back")
        );
    }

    #[test]
    fn next_steps_through_every_preset_once() {
        let mut seen = vec![ViewPreset::Front];
        let mut p = ViewPreset::Front.next();
        while p != ViewPreset::Front {
            seen.push(p);
            p = p.next();
        }
        assert_eq!(seen, ViewPreset::ALL.to_vec());
    }
}
