//! The pinhole camera: glam's right-handed look-at view and OpenGL perspective projection.

use glam::{Mat4, Vec3};

/// A perspective camera in world space (OpenGL right-handed conventions, see `docs/conventions.md`).
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
    /// (fov clamped to `[0.01, 179]` degrees, near >= 1e-6, far > near).
    #[must_use]
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let fov = if self.fov_y_deg.is_finite() {
            self.fov_y_deg.clamp(0.01, 179.0)
        } else {
            45.0
        };
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
        glam::camera::rh::proj::opengl::perspective(fov.to_radians(), aspect, near, far)
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
        };
        assert!(cam.view_proj(0.0).is_finite());
    }
}
