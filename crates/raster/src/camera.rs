//! The camera: glam's right-handed look-at view and an OpenGL perspective (a pinhole, the
//! default) or orthographic (parallel rays) projection.

use glam::{Mat4, Vec3};

/// How a camera projects the scene onto the image.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Projection {
    /// A pinhole at the eye: the view widens with distance by `fov_y_deg` (the default).
    #[default]
    Perspective,
    /// Parallel rays along the view direction: the image spans `height` world units vertically
    /// (and `height * aspect` across) at every depth. The lighting's viewer stays at the eye.
    Orthographic {
        /// World units the image spans vertically (> 0; anything else is taken as 1).
        height: f32,
    },
}

impl Projection {
    /// `perspective` or `orthographic`, as scene files and messages spell it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Projection::Perspective => "perspective",
            Projection::Orthographic { .. } => "orthographic",
        }
    }
}

/// A camera in world space (OpenGL right-handed conventions, see `docs/conventions.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position (also the viewer position `V` of the lighting model).
    pub eye: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// Up direction (need not be orthogonal to the view direction).
    pub up: Vec3,
    /// Vertical field of view in degrees, clamped to `[0.01, 179]`.
    pub fov_y_deg: f32,
    /// Near plane distance (> 0); geometry closer is clipped.
    pub near: f32,
    /// Far plane distance (> near); geometry at or beyond it is not drawn.
    pub far: f32,
    /// Perspective (the default) or orthographic; `fov_y_deg` applies to perspective only.
    pub projection: Projection,
}

impl Camera {
    /// Standard scene S1's camera: eye (0,0,3), target origin, up +Y, fov 45, near 0.1, far 10.
    #[must_use]
    pub const fn s1() -> Camera {
        Camera {
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 0.1,
            far: 10.0,
            projection: Projection::Perspective,
        }
    }

    /// The world-to-view matrix. A degenerate set-up (eye at target, up along the view
    /// direction, non-finite values) falls back to a view along -Z, so no NaN ever appears.
    #[must_use]
    pub fn view(&self) -> Mat4 {
        let dir = self.target - self.eye;
        let ok = self.eye.is_finite()
            && self.target.is_finite()
            && self.up.is_finite()
            && dir.length_squared() > 1e-20
            && dir.normalize().cross(self.up).length_squared() > 1e-12;
        if ok {
            glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up)
        } else {
            let eye = if self.eye.is_finite() {
                self.eye
            } else {
                Vec3::ZERO
            };
            Mat4::from_translation(-eye)
        }
    }

    /// The OpenGL projection for `aspect` = width / height, with parameters sanitized
    /// (fov clamped to `[0.01, 179]` degrees, an orthographic height that is not finite and
    /// positive taken as 1, near >= 1e-6, far > near).
    #[must_use]
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let near = if self.near.is_finite() && self.near > 1e-6 {
            self.near
        } else {
            1e-6
        };
        let far = if self.far.is_finite() && self.far > near * 1.0001 {
            self.far
        } else {
            near * 1e4
        };
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        match self.projection {
            Projection::Perspective => {
                let fov = if self.fov_y_deg.is_finite() {
                    self.fov_y_deg.clamp(0.01, 179.0)
                } else {
                    45.0
                };
                glam::camera::rh::proj::opengl::perspective(fov.to_radians(), aspect, near, far)
            }
            Projection::Orthographic { height } => {
                let half_h = if height.is_finite() && height > 0.0 {
                    height * 0.5
                } else {
                    0.5
                };
                let half_w = half_h * aspect;
                glam::camera::rh::proj::opengl::orthographic(
                    -half_w, half_w, -half_h, half_h, near, far,
                )
            }
        }
    }

    /// World units the image spans vertically at the target's depth: the orthographic
    /// height, or what the field of view spans at the distance to the target.
    #[must_use]
    pub fn view_height_at_target(&self) -> f32 {
        match self.projection {
            Projection::Perspective => {
                2.0 * self.eye.distance(self.target) * (self.fov_y_deg.to_radians() * 0.5).tan()
            }
            Projection::Orthographic { height } => height,
        }
    }

    /// Projection times view: world to clip space.
    #[must_use]
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }
}

impl Default for Camera {
    fn default() -> Self {
        Camera::s1()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn s1_camera_maps_the_target_to_the_screen_centre_in_front() {
        let m = Camera::s1().view_proj(16.0 / 9.0);
        let c = m * glam::Vec4::new(0.0, 0.0, 0.0, 1.0);
        assert!((c.x / c.w).abs() < 1e-6 && (c.y / c.w).abs() < 1e-6);
        let z = c.z / c.w;
        assert!(z > -1.0 && z < 1.0);
        // Up is up: a point above the target has positive NDC y.
        let u = m * glam::Vec4::new(0.0, 0.5, 0.0, 1.0);
        assert!(u.y / u.w > 0.0);
    }

    #[test]
    fn degenerate_camera_gives_finite_matrices() {
        let cam = Camera {
            eye: Vec3::ZERO,
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: f32::NAN,
            near: -1.0,
            far: 0.0,
            projection: Projection::Perspective,
        };
        assert!(cam.view_proj(0.0).is_finite());
        for height in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let ortho = Camera {
                projection: Projection::Orthographic { height },
                ..cam
            };
            assert!(ortho.view_proj(0.0).is_finite(), "{height}");
        }
    }

    #[test]
    fn perspective_is_the_default_and_its_matrix_is_glams_perspective() {
        let cam = Camera::s1();
        assert_eq!(cam.projection, Projection::default());
        let expected =
            glam::camera::rh::proj::opengl::perspective(45f32.to_radians(), 1.5, 0.1, 10.0);
        assert_eq!(cam.projection(1.5), expected);
    }

    #[test]
    fn orthographic_keeps_sizes_at_every_depth() {
        let cam = Camera {
            projection: Projection::Orthographic { height: 4.0 },
            far: 100.0,
            ..Camera::s1()
        };
        let m = cam.view_proj(2.0);
        // A point 1 unit up maps to NDC y = 0.5 (half of the 2-unit half-height), whatever
        // its depth; w stays 1 (no perspective division).
        for z in [1.0f32, 0.0, -20.0, -80.0] {
            let c = m * glam::Vec4::new(0.0, 1.0, z, 1.0);
            assert!((c.w - 1.0).abs() < 1e-6, "w {}", c.w);
            assert!((c.y - 0.5).abs() < 1e-5, "y {} at z {z}", c.y);
            // Across: 1 unit right is 1 / (2 * aspect) of the half-width.
            let r = m * glam::Vec4::new(1.0, 0.0, z, 1.0);
            assert!((r.x - 0.25).abs() < 1e-5, "x {} at z {z}", r.x);
        }
        assert_eq!(cam.view_height_at_target(), 4.0);
        let at_target = Camera::s1().view_height_at_target();
        assert!((at_target - 6.0 * 22.5f32.to_radians().tan()).abs() < 1e-5);
    }
}
