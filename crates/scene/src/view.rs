//! Where the camera looks from: orbit angles around a centre, a view that fits a bounding
//! sphere, the frames of a turntable, camera changes asked for on a command line, and the
//! `[camera]` block of a scene file.
//!
//! Orbit angles are measured about the camera's `up` direction. The elevation is the angle of
//! the eye above the plane normal to `up`; the azimuth turns within that plane, starting from
//! the side of world +Z (world +X when `up` lies along Z) and growing towards the side of
//! `up x (+Z)`, which is +X for `up = +Y`. Azimuth 0, elevation 0 is therefore S1's view:
//! from +Z, looking along -Z. A turntable turns the same way: frame `k` of `n` is the camera
//! turned by `360 * k / n` degrees about `up`, through the target.
//!
//! ```
//! use phosphor_scene::view::{orbit_eye, turntable_camera};
//! use phosphor_raster::{Camera, Projection};
//! use glam::Vec3;
//!
//! let eye = orbit_eye(Vec3::ZERO, Vec3::Y, 90.0, 0.0, 3.0);
//! assert!((eye - Vec3::new(3.0, 0.0, 0.0)).length() < 1e-5);
//! // A quarter turn of S1's camera looks from +X.
//! let turned = turntable_camera(&Camera::s1(), 1, 4);
//! assert!((turned.eye - Vec3::new(3.0, 0.0, 0.0)).length() < 1e-5);
//! ```

use std::fmt;

use glam::{Quat, Vec3};
use phosphor_raster::{Camera, Projection};
use thiserror::Error;
use toml::Table;

use crate::Scene;
use crate::components::{MeshRef, Transform};

/// The bounding sphere fills this share of the view's narrower half-angle's sine when a view
/// is fitted: a small margin, so that silhouettes never touch the image border.
const FIT_MARGIN: f32 = 1.05;

/// Below this length the horizontal part of world +Z is too short to give a stable azimuth
/// origin (`up` lies along Z), and world +X is used instead.
const AXIS_EPSILON: f32 = 1e-3;

/// Orbit coordinates of an eye around a centre (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitAngles {
    /// Degrees about `up`, from the +Z side.
    pub azimuth_deg: f32,
    /// Degrees above the plane normal to `up`, in [-90, 90].
    pub elevation_deg: f32,
    /// Distance from the centre.
    pub distance: f32,
}

/// The orbit frame of `up`: the azimuth-0 direction, the azimuth-90 direction and unit `up`.
/// `None` when `up` has no direction (zero or not finite).
fn orbit_basis(up: Vec3) -> Option<(Vec3, Vec3, Vec3)> {
    let up = up.try_normalize()?;
    let from_z = Vec3::Z - up * up.z;
    let back = if from_z.length() > AXIS_EPSILON {
        from_z.normalize()
    } else {
        (Vec3::X - up * up.x).try_normalize()?
    };
    Some((back, up.cross(back), up))
}

/// The eye at `azimuth_deg`, `elevation_deg` and `distance` around `centre` (see the module
/// documentation for the angles). A `up` without direction is taken as +Y.
#[must_use]
pub fn orbit_eye(
    centre: Vec3,
    up: Vec3,
    azimuth_deg: f32,
    elevation_deg: f32,
    distance: f32,
) -> Vec3 {
    let (back, right, up) = orbit_basis(up).unwrap_or((Vec3::Z, Vec3::X, Vec3::Y));
    let (sin_az, cos_az) = azimuth_deg.to_radians().sin_cos();
    let (sin_el, cos_el) = elevation_deg.to_radians().sin_cos();
    let direction = (back * cos_az + right * sin_az) * cos_el + up * sin_el;
    centre + direction * distance
}

/// The orbit coordinates of `eye` around `centre` for `up`: the inverse of [`orbit_eye`].
/// An eye on the centre has distance 0 and angles 0.
#[must_use]
pub fn orbit_angles(eye: Vec3, centre: Vec3, up: Vec3) -> OrbitAngles {
    let offset = eye - centre;
    let distance = offset.length();
    let (back, right, up) = orbit_basis(up).unwrap_or((Vec3::Z, Vec3::X, Vec3::Y));
    let Some(direction) = offset.try_normalize() else {
        return OrbitAngles {
            azimuth_deg: 0.0,
            elevation_deg: 0.0,
            distance: 0.0,
        };
    };
    let elevation = direction.dot(up).clamp(-1.0, 1.0).asin();
    let azimuth = direction.dot(right).atan2(direction.dot(back));
    OrbitAngles {
        azimuth_deg: azimuth.to_degrees(),
        elevation_deg: elevation.to_degrees(),
        distance,
    }
}

/// Frame `frame` of a turntable of `frames` frames: `camera` turned by `360 * frame / frames`
/// degrees about its `up` direction, through its target. Frame 0 is `camera` itself; the
/// angle is computed from the frame number alone, so any subset of the frames rendered
/// anywhere gives the same cameras.
#[must_use]
pub fn turntable_camera(camera: &Camera, frame: u32, frames: u32) -> Camera {
    let turns = f64::from(frame) / f64::from(frames.max(1));
    let angle = (turns * std::f64::consts::TAU) as f32;
    let axis = camera.up.try_normalize().unwrap_or(Vec3::Y);
    let eye = camera.target + Quat::from_axis_angle(axis, angle) * (camera.eye - camera.target);
    Camera { eye, ..*camera }
}

/// The distance from which a sphere of `radius` fits a view of `fov_y_deg` degrees vertically
/// at `aspect` = width / height (the narrower of the two half-angles decides), with a 5% margin.
#[must_use]
pub fn fit_distance(radius: f32, fov_y_deg: f32, aspect: f32) -> f32 {
    let half_y = fov_y_deg.to_radians() * 0.5;
    let half_x = (half_y.tan() * aspect).atan();
    let half = half_y.min(half_x);
    radius * FIT_MARGIN / half.sin()
}

/// Near and far planes that keep a sphere of `radius` at `distance` from the eye between them,
/// with room to spare; the near plane stays positive when the eye is inside the sphere.
pub(crate) fn planes_around(distance: f32, radius: f32) -> (f32, f32) {
    let far = (distance + radius) * 1.5;
    let near = ((distance - radius) * 0.5).max(far * 1e-4);
    (near, far)
}

/// A camera at `azimuth_deg`, `elevation_deg` around the sphere (`centre`, `radius`), far
/// enough that the sphere fits a view of `fov_y_deg` at `aspect`, with near and far planes
/// around it.
#[must_use]
pub fn framed_camera(
    centre: Vec3,
    radius: f32,
    up: Vec3,
    azimuth_deg: f32,
    elevation_deg: f32,
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
    Camera {
        eye: orbit_eye(centre, up, azimuth_deg, elevation_deg, distance),
        target: centre,
        up,
        fov_y_deg,
        near,
        far,
        projection: Projection::Perspective,
    }
}

impl Scene {
    /// A world-space sphere holding every object (each mesh's bounding sphere carried by its
    /// transform); `None` without objects.
    #[must_use]
    pub fn bounding_sphere(&self) -> Option<(Vec3, f32)> {
        let spheres: Vec<(Vec3, f32)> = self
            .world
            .query::<(&Transform, &MeshRef)>()
            .iter()
            .map(|(t, m)| {
                let info = &m.0.info;
                (
                    t.matrix().transform_point3(info.center),
                    info.radius * t.max_scale(),
                )
            })
            .filter(|(c, r)| c.is_finite() && r.is_finite())
            .collect();
        let (first, _) = *spheres.first()?;
        let (lo, hi) = spheres.iter().fold((first, first), |(lo, hi), &(c, r)| {
            (lo.min(c - Vec3::splat(r)), hi.max(c + Vec3::splat(r)))
        });
        let centre = (lo + hi) * 0.5;
        let radius = spheres
            .iter()
            .map(|&(c, r)| c.distance(centre) + r)
            .fold(0.0f32, f32::max);
        Some((centre, radius))
    }
}

/// A camera value that can be changed from a command line, for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CameraOption {
    /// `--eye`.
    Eye,
    /// `--target`.
    Target,
    /// `--up`.
    Up,
    /// `--fov`.
    Fov,
    /// `--azimuth`.
    Azimuth,
    /// `--elevation`.
    Elevation,
    /// `--distance`.
    Distance,
}

impl CameraOption {
    /// The command-line flag.
    #[must_use]
    pub fn flag(self) -> &'static str {
        match self {
            CameraOption::Eye => "--eye",
            CameraOption::Target => "--target",
            CameraOption::Up => "--up",
            CameraOption::Fov => "--fov",
            CameraOption::Azimuth => "--azimuth",
            CameraOption::Elevation => "--elevation",
            CameraOption::Distance => "--distance",
        }
    }
}

impl fmt::Display for CameraOption {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.flag())
    }
}

/// A camera change that cannot be made: `FLAG: what`.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{option}: {what}")]
pub struct CameraOverrideError {
    /// The value at fault.
    pub option: CameraOption,
    /// What is wrong with it.
    pub what: String,
}

fn fault(option: CameraOption, what: impl Into<String>) -> CameraOverrideError {
    CameraOverrideError {
        option,
        what: what.into(),
    }
}

/// Changes to a scene's camera, as a command line asks for them: either an explicit eye
/// (`eye`, `target`), or orbit coordinates around the scene's centre (`azimuth_deg`,
/// `elevation_deg`, `distance`; the centre is `target` when given); `up` and `fov_y_deg` in
/// both forms. Orbit values left out keep the scene camera's own, measured around the centre.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CameraOverride {
    /// Eye position.
    pub eye: Option<Vec3>,
    /// The point looked at (and orbited around).
    pub target: Option<Vec3>,
    /// Up direction.
    pub up: Option<Vec3>,
    /// Vertical field of view, degrees, in (0, 180).
    pub fov_y_deg: Option<f32>,
    /// Orbit azimuth, degrees.
    pub azimuth_deg: Option<f32>,
    /// Orbit elevation, degrees, in (-90, 90).
    pub elevation_deg: Option<f32>,
    /// Orbit distance, > 0.
    pub distance: Option<f32>,
}

/// A number as a message shows it: its shortest form (`1e20`, not `100000000000000000000`).
fn short(x: f32) -> String {
    let (plain, exponent) = (format!("{x}"), format!("{x:e}"));
    if exponent.len() < plain.len() {
        exponent
    } else {
        plain
    }
}

/// `x,y,z` as a message shows it, each number in its shortest form.
fn show(v: Vec3) -> String {
    let [x, y, z] = v.to_array().map(short);
    format!("{x},{y},{z}")
}

impl CameraOverride {
    /// Whether anything is to change.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        *self == CameraOverride::default()
    }

    fn orbits(&self) -> bool {
        self.azimuth_deg.is_some() || self.elevation_deg.is_some() || self.distance.is_some()
    }

    /// Checks each value on its own (finite, in range, and no explicit eye together with orbit
    /// values), so that a command line can reject it before reading any file.
    ///
    /// # Errors
    /// The first value at fault, named.
    pub fn check(&self) -> Result<(), CameraOverrideError> {
        for (option, v) in [
            (CameraOption::Eye, self.eye),
            (CameraOption::Target, self.target),
            (CameraOption::Up, self.up),
        ] {
            if let Some(v) = v
                && !v.is_finite()
            {
                return Err(fault(option, format!("must be finite, got {}", show(v))));
            }
        }
        if let Some(up) = self.up
            && up.length_squared() < 1e-12
        {
            return Err(fault(CameraOption::Up, "must not be zero"));
        }
        for (option, v) in [
            (CameraOption::Fov, self.fov_y_deg),
            (CameraOption::Azimuth, self.azimuth_deg),
            (CameraOption::Elevation, self.elevation_deg),
            (CameraOption::Distance, self.distance),
        ] {
            if let Some(v) = v
                && !v.is_finite()
            {
                return Err(fault(option, format!("must be a finite number, got {v}")));
            }
        }
        if let Some(fov) = self.fov_y_deg
            && !(fov > 0.0 && fov < 180.0)
        {
            return Err(fault(
                CameraOption::Fov,
                format!("must be between 0 and 180 (exclusive), got {fov}"),
            ));
        }
        if let Some(e) = self.elevation_deg
            && !(e > -90.0 && e < 90.0)
        {
            return Err(fault(
                CameraOption::Elevation,
                format!("must be between -90 and 90 (exclusive), got {e}"),
            ));
        }
        if let Some(d) = self.distance
            && d <= 0.0
        {
            return Err(fault(
                CameraOption::Distance,
                format!("must be > 0, got {d}"),
            ));
        }
        if self.eye.is_some() && self.orbits() {
            return Err(fault(
                CameraOption::Eye,
                "cannot be combined with --azimuth, --elevation or --distance",
            ));
        }
        Ok(())
    }

    /// The option blamed when the view direction comes out parallel to `up`: `up` itself if it
    /// was given, else whatever moved the view.
    fn blamed_for_up(&self) -> CameraOption {
        [
            (self.up.is_some(), CameraOption::Up),
            (self.eye.is_some(), CameraOption::Eye),
            (self.elevation_deg.is_some(), CameraOption::Elevation),
            (self.target.is_some(), CameraOption::Target),
            (self.azimuth_deg.is_some(), CameraOption::Azimuth),
        ]
        .into_iter()
        .find_map(|(given, option)| given.then_some(option))
        .unwrap_or(CameraOption::Distance)
    }

    /// `camera` with these changes. `bounds` is the scene's bounding sphere
    /// ([`Scene::bounding_sphere`]): its centre is the orbit centre when no `target` is given,
    /// and when the eye or target moves the near and far planes widen so that it stays
    /// between them. Nothing given: `camera` unchanged.
    ///
    /// # Errors
    /// A value that is not finite or out of range, an eye on the target, or a view direction
    /// parallel to `up`: the error names the option at fault.
    pub fn apply(
        &self,
        camera: Camera,
        bounds: Option<(Vec3, f32)>,
    ) -> Result<Camera, CameraOverrideError> {
        self.check()?;
        if self.is_empty() {
            return Ok(camera);
        }
        let mut cam = camera;
        if let Some(up) = self.up {
            cam.up = up;
        }
        if let Some(fov) = self.fov_y_deg {
            cam.fov_y_deg = fov;
        }
        if self.orbits() {
            let centre = self
                .target
                .or(bounds.map(|(c, _)| c))
                .unwrap_or(camera.target);
            let current = orbit_angles(camera.eye, centre, cam.up);
            cam.target = centre;
            cam.eye = orbit_eye(
                centre,
                cam.up,
                self.azimuth_deg.unwrap_or(current.azimuth_deg),
                self.elevation_deg.unwrap_or(current.elevation_deg),
                self.distance.unwrap_or(current.distance),
            );
        } else {
            cam.eye = self.eye.unwrap_or(cam.eye);
            cam.target = self.target.unwrap_or(cam.target);
        }
        let dir = cam.target - cam.eye;
        if !dir.length_squared().is_finite() {
            // Past 1.8e19 the squared distance overflows single precision: the view direction
            // would come out as (0,0,0), which no later message could explain.
            let option = if self.eye.is_some() {
                CameraOption::Eye
            } else if self.target.is_some() {
                CameraOption::Target
            } else {
                CameraOption::Distance
            };
            let apart = (cam.target.as_dvec3() - cam.eye.as_dvec3()).length() as f32;
            return Err(fault(
                option,
                format!(
                    "puts the eye at {}, {} from the target ({}): too far for single precision \
                     (at most 1.8e19)",
                    show(cam.eye),
                    short(apart),
                    show(cam.target)
                ),
            ));
        }
        if dir.length_squared() < 1e-12 {
            return Err(if self.target.is_some() {
                fault(
                    CameraOption::Target,
                    format!("must differ from the eye ({})", show(cam.eye)),
                )
            } else {
                let option = if self.eye.is_some() {
                    CameraOption::Eye
                } else {
                    CameraOption::Distance
                };
                fault(
                    option,
                    format!("puts the eye on the target ({})", show(cam.target)),
                )
            });
        }
        if dir.normalize().cross(cam.up.normalize()).length_squared() < 1e-10 {
            return Err(fault(
                self.blamed_for_up(),
                format!(
                    "the view direction ({}) is parallel to up ({})",
                    show(dir.normalize()),
                    show(cam.up)
                ),
            ));
        }
        let moved = self.eye.is_some() || self.target.is_some() || self.orbits();
        if moved && let Some((centre, radius)) = bounds {
            let (near, far) = planes_around(cam.eye.distance(centre), radius);
            cam.far = cam.far.max(far);
            cam.near = cam.near.min(near);
        }
        Ok(cam)
    }
}

/// Parses `X,Y,Z`: three finite numbers separated by commas (spaces allowed).
///
/// # Errors
/// A message saying what was expected.
pub fn parse_vec3(text: &str) -> Result<Vec3, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let expected = || format!("expected X,Y,Z (three numbers), got `{text}`");
    if parts.len() != 3 {
        return Err(expected());
    }
    let mut v = [0.0f32; 3];
    for (o, p) in v.iter_mut().zip(&parts) {
        *o = p.parse::<f32>().map_err(|_| expected())?;
        if !o.is_finite() {
            return Err(format!("must be finite, got `{text}`"));
        }
    }
    Ok(Vec3::from_array(v))
}

/// `x` as a TOML number that reads back as exactly `x`: its shortest decimal form (`0.1`, not
/// `0.10000000149011612`) where that survives the loader's f64-then-f32 reading, else the
/// exact f64 value.
fn exact_number(x: f32) -> toml::Value {
    let short: Option<f64> = format!("{x}").parse().ok();
    toml::Value::Float(match short {
        Some(v) if v as f32 == x => v,
        _ => f64::from(x),
    })
}

/// `camera` as the `[camera]` table of a scene file, every field written so that loading it
/// gives back exactly `camera` (what the viewer prints for pasting into a scene).
#[must_use]
pub fn camera_toml(camera: &Camera) -> String {
    let v3 = |v: Vec3| toml::Value::Array(v.to_array().map(exact_number).to_vec());
    let mut t = Table::new();
    t.insert("eye".to_owned(), v3(camera.eye));
    t.insert("target".to_owned(), v3(camera.target));
    t.insert("up".to_owned(), v3(camera.up));
    t.insert("fov_y_deg".to_owned(), exact_number(camera.fov_y_deg));
    t.insert("near".to_owned(), exact_number(camera.near));
    t.insert("far".to_owned(), exact_number(camera.far));
    if let Projection::Orthographic { height } = camera.projection {
        t.insert(
            "projection".to_owned(),
            toml::Value::String(camera.projection.name().to_owned()),
        );
        t.insert("ortho_height".to_owned(), exact_number(height));
    }
    let mut root = Table::new();
    root.insert("camera".to_owned(), toml::Value::Table(t));
    toml::to_string(&root).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-4
    }

    #[test]
    fn orbit_zero_is_s1s_view_and_azimuth_turns_towards_plus_x() {
        assert!(close(
            orbit_eye(Vec3::ZERO, Vec3::Y, 0.0, 0.0, 3.0),
            Camera::s1().eye
        ));
        assert!(close(
            orbit_eye(Vec3::ZERO, Vec3::Y, 90.0, 0.0, 2.0),
            Vec3::new(2.0, 0.0, 0.0)
        ));
        assert!(close(
            orbit_eye(Vec3::ONE, Vec3::Y, 0.0, 90.0, 2.0),
            Vec3::new(1.0, 3.0, 1.0)
        ));
        // Up along Z: the azimuth origin is +X, and the result stays finite.
        let e = orbit_eye(Vec3::ZERO, Vec3::Z, 0.0, 0.0, 1.0);
        assert!(close(e, Vec3::X), "{e:?}");
    }

    #[test]
    fn orbit_angles_invert_orbit_eye() {
        for (az, el, d) in [(0.0, 0.0, 3.0), (30.0, 20.0, 2.5), (-120.0, -45.0, 7.0)] {
            for up in [Vec3::Y, Vec3::new(0.3, 1.0, -0.2), Vec3::Z] {
                let centre = Vec3::new(0.5, -1.0, 2.0);
                let a = orbit_angles(orbit_eye(centre, up, az, el, d), centre, up);
                assert!((a.azimuth_deg - az).abs() < 1e-3, "{a:?} vs {az}");
                assert!((a.elevation_deg - el).abs() < 1e-3, "{a:?} vs {el}");
                assert!((a.distance - d).abs() < 1e-4, "{a:?} vs {d}");
            }
        }
    }

    #[test]
    fn turntable_turns_about_up_through_the_target_keeping_the_distance() {
        let cam = Camera {
            eye: Vec3::new(1.0, 2.0, 5.0),
            target: Vec3::new(1.0, 0.0, 1.0),
            ..Camera::s1()
        };
        assert_eq!(turntable_camera(&cam, 0, 12), cam);
        let a0 = orbit_angles(cam.eye, cam.target, cam.up);
        for k in 1..12 {
            let t = turntable_camera(&cam, k, 12);
            assert_eq!(
                (t.target, t.up, t.fov_y_deg),
                (cam.target, cam.up, cam.fov_y_deg)
            );
            let a = orbit_angles(t.eye, t.target, t.up);
            assert!((a.distance - a0.distance).abs() < 1e-4);
            assert!((a.elevation_deg - a0.elevation_deg).abs() < 1e-3);
            let turned = (a.azimuth_deg - a0.azimuth_deg).rem_euclid(360.0);
            assert!(
                (turned - 30.0 * k as f32).abs() < 1e-2,
                "frame {k}: {turned}"
            );
        }
        assert!(close(turntable_camera(&cam, 12, 12).eye, cam.eye));
    }

    #[test]
    fn a_fitted_sphere_stays_inside_both_half_angles() {
        for aspect in [0.5f32, 1.0, 16.0 / 9.0] {
            let cam = framed_camera(Vec3::ONE, 2.0, Vec3::Y, 30.0, 20.0, 45.0, aspect);
            let d = cam.eye.distance(cam.target);
            let seen = (2.0 / d).asin();
            let half_y = 22.5f32.to_radians();
            let half_x = (half_y.tan() * aspect).atan();
            assert!(seen < half_y.min(half_x), "aspect {aspect}");
            assert!(seen > 0.9 * half_y.min(half_x), "tight, aspect {aspect}");
            assert!(cam.near > 0.0 && cam.near < d - 2.0 && cam.far > d + 2.0);
        }
    }

    #[test]
    fn bounding_sphere_holds_every_object_in_world_space() {
        let scene = Scene::parse(
            "[[objects]]\nprimitive = { shape = \"sphere\", radius = 1.0 }\ntransform = { translate = [4, 0, 0] }\n\
             [[objects]]\nprimitive = { shape = \"cube\", half_size = 1.0 }\ntransform = { scale = 2 }\n",
            "t.toml",
        )
        .unwrap();
        let (c, r) = scene.bounding_sphere().unwrap();
        assert!(c.distance(Vec3::new(4.0, 0.0, 0.0)) + 1.0 <= r + 1e-4);
        // The cube's corners at distance 2 * sqrt(3) from the origin.
        assert!(c.distance(Vec3::splat(2.0)) <= r + 1e-4);
        assert!(c.distance(Vec3::splat(-2.0)) <= r + 1e-4);
        assert!(Scene::empty().bounding_sphere().is_none());
    }

    #[test]
    fn nothing_to_override_leaves_the_camera_as_it_is() {
        let cam = Camera::s1();
        let got = CameraOverride::default().apply(cam, Some((Vec3::ZERO, 5.0)));
        assert_eq!(got, Ok(cam));
    }

    #[test]
    fn orbit_overrides_keep_what_is_not_given() {
        let cam = Camera::s1();
        let o = CameraOverride {
            azimuth_deg: Some(90.0),
            ..CameraOverride::default()
        };
        let got = o.apply(cam, Some((Vec3::ZERO, 1.0))).unwrap();
        assert!(close(got.eye, Vec3::new(3.0, 0.0, 0.0)), "{:?}", got.eye);
        let o = CameraOverride {
            distance: Some(20.0),
            ..CameraOverride::default()
        };
        let got = o.apply(cam, Some((Vec3::ZERO, 1.0))).unwrap();
        assert!(close(got.eye, Vec3::new(0.0, 0.0, 20.0)));
        assert!(got.far > 21.0, "the far plane follows the eye: {}", got.far);
        assert!(got.near <= cam.near);
    }

    #[test]
    fn explicit_eye_target_up_and_fov_are_taken_as_given() {
        let o = CameraOverride {
            eye: Some(Vec3::new(1.0, 2.0, 3.0)),
            target: Some(Vec3::new(0.0, 1.0, 0.0)),
            up: Some(Vec3::Z),
            fov_y_deg: Some(30.0),
            ..CameraOverride::default()
        };
        let got = o.apply(Camera::s1(), None).unwrap();
        assert_eq!(
            (got.eye, got.target, got.up, got.fov_y_deg),
            (
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::Z,
                30.0
            )
        );
        assert_eq!((got.near, got.far), (0.1, 10.0));
    }

    #[test]
    fn an_eye_too_far_for_single_precision_is_named_as_given() {
        let o = CameraOverride {
            eye: Some(Vec3::new(1e20, 0.0, 0.0)),
            ..CameraOverride::default()
        };
        let e = o.apply(Camera::s1(), None).unwrap_err();
        assert_eq!(
            e.to_string(),
            "--eye: puts the eye at 1e20,0,0, 1e20 from the target (0,0,0): too far for single \
             precision (at most 1.8e19)"
        );
        let o = CameraOverride {
            distance: Some(3e19),
            ..CameraOverride::default()
        };
        let e = o.apply(Camera::s1(), None).unwrap_err();
        assert_eq!(e.option, CameraOption::Distance, "{e}");
    }

    #[test]
    fn bad_overrides_name_the_option_at_fault() {
        let bad = |o: CameraOverride| o.apply(Camera::s1(), Some((Vec3::ZERO, 1.0))).unwrap_err();
        let none = CameraOverride::default();
        let e = bad(CameraOverride {
            fov_y_deg: Some(180.0),
            ..none
        });
        assert_eq!(
            e.to_string(),
            "--fov: must be between 0 and 180 (exclusive), got 180"
        );
        let e = bad(CameraOverride {
            fov_y_deg: Some(f32::NAN),
            ..none
        });
        assert_eq!(e.to_string(), "--fov: must be a finite number, got NaN");
        let e = bad(CameraOverride {
            eye: Some(Vec3::ZERO),
            ..none
        });
        assert_eq!(e.option, CameraOption::Eye);
        let e = bad(CameraOverride {
            target: Some(Vec3::new(0.0, 0.0, 3.0)),
            ..none
        });
        assert_eq!(e.to_string(), "--target: must differ from the eye (0,0,3)");
        let e = bad(CameraOverride {
            up: Some(Vec3::new(0.0, 0.0, -2.0)),
            ..none
        });
        assert_eq!(e.option, CameraOption::Up);
        assert!(e.what.contains("parallel"), "{e}");
        let e = bad(CameraOverride {
            eye: Some(Vec3::new(0.0, 4.0, 0.0)),
            ..none
        });
        assert_eq!(e.option, CameraOption::Eye);
        assert!(e.what.contains("parallel"), "{e}");
        for (o, option) in [
            (
                CameraOverride {
                    elevation_deg: Some(90.0),
                    ..none
                },
                CameraOption::Elevation,
            ),
            (
                CameraOverride {
                    distance: Some(0.0),
                    ..none
                },
                CameraOption::Distance,
            ),
            (
                CameraOverride {
                    up: Some(Vec3::ZERO),
                    ..none
                },
                CameraOption::Up,
            ),
            (
                CameraOverride {
                    eye: Some(Vec3::new(f32::INFINITY, 0.0, 0.0)),
                    ..none
                },
                CameraOption::Eye,
            ),
            (
                CameraOverride {
                    eye: Some(Vec3::ONE),
                    azimuth_deg: Some(10.0),
                    ..none
                },
                CameraOption::Eye,
            ),
        ] {
            assert_eq!(bad(o).option, option, "{o:?}");
        }
    }

    #[test]
    fn vectors_parse_as_three_finite_numbers() {
        assert_eq!(parse_vec3("1,-2.5, 3e1"), Ok(Vec3::new(1.0, -2.5, 30.0)));
        for bad in ["", "1,2", "1,2,3,4", "a,b,c", "1;2;3"] {
            assert!(parse_vec3(bad).unwrap_err().contains("X,Y,Z"), "{bad}");
        }
        assert!(parse_vec3("nan,0,0").unwrap_err().contains("finite"));
    }

    #[test]
    fn camera_block_loads_back_to_the_same_camera() {
        let cameras = [
            Camera::s1(),
            Camera {
                eye: Vec3::new(0.123_456_79, -7.5e-3, 1.0e4 / 3.0),
                target: Vec3::new(-1.0 / 3.0, 2.0, 0.1),
                up: Vec3::new(0.2, 0.9, -0.1),
                fov_y_deg: 33.333_33,
                near: 0.017,
                far: 123.456,
                projection: Projection::Perspective,
            },
            Camera {
                projection: Projection::Orthographic { height: 2.75 },
                ..Camera::s1()
            },
        ];
        for cam in cameras {
            let text = camera_toml(&cam);
            assert!(text.starts_with("[camera]\n"), "{text}");
            assert!(!text.contains("0000000"), "shortest decimals: {text}");
            let scene = Scene::parse(&text, "camera.toml").unwrap();
            assert_eq!(scene.camera(), cam, "{text}");
        }
    }

    proptest::proptest! {
        #[test]
        fn any_valid_camera_block_loads_back_exactly(
            eye in proptest::array::uniform3(-1e4f32..1e4),
            target in proptest::array::uniform3(-1e4f32..1e4),
            up in proptest::array::uniform3(-1f32..1.0),
            fov in 0.01f32..179.99,
            near in 1e-4f32..10.0,
            depth in 1.001f32..1e5,
            ortho in proptest::prop_oneof![proptest::strategy::Just(0.0f32), 1e-3f32..1e4],
        ) {
            let cam = Camera {
                eye: Vec3::from_array(eye),
                target: Vec3::from_array(target),
                up: Vec3::from_array(up),
                fov_y_deg: fov,
                near,
                far: near * depth,
                projection: if ortho > 0.0 {
                    Projection::Orthographic { height: ortho }
                } else {
                    Projection::Perspective
                },
            };
            let dir = cam.target - cam.eye;
            proptest::prop_assume!(dir.length() > 1e-3 && cam.far > cam.near);
            proptest::prop_assume!(dir.normalize().cross(cam.up).length_squared() > 1e-6);
            let text = camera_toml(&cam);
            let scene = Scene::parse(&text, "camera.toml").unwrap();
            proptest::prop_assert_eq!(scene.camera(), cam, "{}", text);
        }
    }
}
