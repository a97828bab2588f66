//! Which casters can shadow which receivers, judged by bounding spheres, and the light view
//! fitted to them: the map covers only the region where a shadow can fall on a receiver.

use std::fmt;

use glam::{Mat4, Vec3};
use phosphor_math::safe_normalize;

use super::{LightView, MAX_POINT_HALF_ANGLE_DEG, Projection};

/// A bounding sphere in world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (>= 0).
    pub radius: f32,
}

/// The shape of a light that casts shadows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightShape {
    /// Parallel light travelling along `direction`.
    Directional {
        /// Direction of travel.
        direction: Vec3,
    },
    /// A cone of light from `position` along `direction`, `outer_deg` its outer half-angle.
    Spot {
        /// Position.
        position: Vec3,
        /// Axis (direction of travel).
        direction: Vec3,
        /// Outer half-angle in degrees.
        outer_deg: f32,
    },
    /// Light in every direction from `position`.
    Point {
        /// Position.
        position: Vec3,
    },
}

/// Why a light gets no map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoMap {
    /// No caster stands between the light and a receiver.
    NothingBetween,
    /// A point light's casters span more than one map's cone: it takes a cube map
    /// ([`super::fit_cube`]).
    TooWide,
    /// The light's direction or position is degenerate.
    Degenerate,
}

impl fmt::Display for NoMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            NoMap::NothingBetween => "no caster can stand between it and a visible receiver",
            NoMap::TooWide => "its casters surround it wider than one map's cone",
            NoMap::Degenerate => "its direction or position is degenerate",
        })
    }
}

/// The angle in radians a sphere subtends from `from` (its half-angle): `asin(r / d)`, and
/// `pi / 2` when `from` is inside it.
fn half_angle(s: &Sphere, from: Vec3) -> f32 {
    let d = s.center.distance(from);
    if d <= s.radius {
        std::f32::consts::FRAC_PI_2
    } else {
        (s.radius / d).asin()
    }
}

/// Angle in radians between two vectors (0 when either is zero).
fn angle(a: Vec3, b: Vec3) -> f32 {
    let (a, b) = (a.normalize_or_zero(), b.normalize_or_zero());
    a.dot(b).clamp(-1.0, 1.0).acos()
}

/// Whether `caster` can stand between `light` and some point of `receiver`: their shadows'
/// cylinders (directional) or cones (spot, point) meet, and the caster begins nearer the light
/// than the receiver ends.
#[must_use]
pub fn can_shadow(light: &LightShape, caster: &Sphere, receiver: &Sphere) -> bool {
    match *light {
        LightShape::Directional { direction } => {
            let f = safe_normalize(direction, Vec3::ZERO);
            if f == Vec3::ZERO {
                return false;
            }
            let d = receiver.center - caster.center;
            let across = (d - f * d.dot(f)).length();
            let reach = caster.radius + receiver.radius;
            across < reach
                && caster.center.dot(f) - caster.radius < receiver.center.dot(f) + receiver.radius
        }
        LightShape::Spot { position, .. } | LightShape::Point { position } => {
            let (vc, vr) = (caster.center - position, receiver.center - position);
            if vc.length() <= caster.radius {
                return true;
            }
            angle(vc, vr) < half_angle(caster, position) + half_angle(receiver, position)
                && vc.length() - caster.radius < vr.length() + receiver.radius
        }
    }
}

/// The right-handed view from `eye` looking along unit `f`.
fn look_to(eye: Vec3, f: Vec3, up: Vec3) -> Mat4 {
    glam::camera::rh::view::look_at_mat4(eye, eye + f, up)
}

/// A vector not along `f`, for a view's up.
fn up_for(f: Vec3) -> Vec3 {
    if f.y.abs() < 0.9 { Vec3::Y } else { Vec3::X }
}

/// The light view covering `casters` (those that can shadow a receiver) and `receivers` (those
/// they can shadow): an orthographic box along a directional light, fitted across to where
/// both meet and in depth from the nearest caster to the farthest receiver; a perspective cone
/// from a spot (at most its outer cone) or point light (at most
/// [`MAX_POINT_HALF_ANGLE_DEG`]).
///
/// # Errors
/// [`NoMap`]: nothing to cast, too wide, or a degenerate light.
pub fn fit(
    light: &LightShape,
    casters: &[Sphere],
    receivers: &[Sphere],
) -> Result<LightView, NoMap> {
    if casters.is_empty() || receivers.is_empty() {
        return Err(NoMap::NothingBetween);
    }
    let all = || casters.iter().chain(receivers);
    if all().any(|s| !s.center.is_finite() || !s.radius.is_finite() || s.radius < 0.0) {
        return Err(NoMap::Degenerate);
    }
    match *light {
        LightShape::Directional { direction } => fit_directional(direction, casters, receivers),
        LightShape::Spot {
            position,
            direction,
            outer_deg,
        } => {
            let axis = safe_normalize(direction, Vec3::ZERO);
            let cap = outer_deg.clamp(0.1, 85.0).to_radians();
            fit_cone(position, axis, cap, casters, receivers, cap)
        }
        LightShape::Point { position } => {
            let sum: Vec3 = casters
                .iter()
                .map(|c| (c.center - position).normalize_or_zero())
                .sum();
            // Casters on every side cancel out: no single cone holds them.
            if sum.length() < 1e-3 * casters.len() as f32 {
                return Err(NoMap::TooWide);
            }
            let axis = safe_normalize(sum, Vec3::ZERO);
            let cap = MAX_POINT_HALF_ANGLE_DEG.to_radians();
            fit_cone(position, axis, cap, casters, receivers, f32::INFINITY)
        }
    }
}

fn fit_directional(
    direction: Vec3,
    casters: &[Sphere],
    receivers: &[Sphere],
) -> Result<LightView, NoMap> {
    let f = safe_normalize(direction, Vec3::ZERO);
    if f == Vec3::ZERO {
        return Err(NoMap::Degenerate);
    }
    let up = up_for(f);
    let view0 = look_to(Vec3::ZERO, f, up);
    // Boxes across the light ([min x, min y, max x, max y]) and the depth ranges.
    let bounds = |set: &[Sphere]| {
        let mut b = [f32::MAX, f32::MAX, f32::MIN, f32::MIN];
        let (mut near, mut far) = (f32::MAX, f32::MIN);
        for s in set {
            let c = view0.transform_point3(s.center);
            b[0] = b[0].min(c.x - s.radius);
            b[1] = b[1].min(c.y - s.radius);
            b[2] = b[2].max(c.x + s.radius);
            b[3] = b[3].max(c.y + s.radius);
            near = near.min(-c.z - s.radius);
            far = far.max(-c.z + s.radius);
        }
        (b, near, far)
    };
    let (bc, near, _) = bounds(casters);
    let (br, _, far) = bounds(receivers);
    let b = [
        bc[0].max(br[0]),
        bc[1].max(br[1]),
        bc[2].min(br[2]),
        bc[3].min(br[3]),
    ];
    if b[0] >= b[2] || b[1] >= b[3] || near >= far {
        return Err(NoMap::NothingBetween);
    }
    let margin = 1e-3 * (far - near) + 1e-4;
    let half = 0.5 * (b[2] - b[0]).max(b[3] - b[1]) * 1.01;
    let (cx, cy) = (0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3]));
    let eye = view0
        .inverse()
        .transform_point3(Vec3::new(cx, cy, -(near - margin)));
    let view = LightView {
        view: look_to(eye, f, up),
        projection: Projection::Orthographic { half_width: half },
        near: margin,
        far: far - near + 2.0 * margin,
        toward: -f,
    };
    if view.is_valid() {
        Ok(view)
    } else {
        Err(NoMap::Degenerate)
    }
}

fn fit_cone(
    position: Vec3,
    axis: Vec3,
    cap: f32,
    casters: &[Sphere],
    receivers: &[Sphere],
    spot_cap: f32,
) -> Result<LightView, NoMap> {
    if axis == Vec3::ZERO || !position.is_finite() {
        return Err(NoMap::Degenerate);
    }
    let widest = |set: &[Sphere]| {
        set.iter()
            .map(|s| angle(axis, s.center - position) + half_angle(s, position))
            .fold(0.0f32, f32::max)
    };
    let wanted = widest(casters).min(widest(receivers));
    let half = if wanted > cap {
        if spot_cap.is_finite() {
            spot_cap
        } else {
            return Err(NoMap::TooWide);
        }
    } else {
        wanted.max(1e-3)
    };
    let near = casters
        .iter()
        .map(|s| s.center.distance(position) - s.radius)
        .fold(f32::MAX, f32::min);
    let far = receivers
        .iter()
        .map(|s| s.center.distance(position) + s.radius)
        .fold(f32::MIN, f32::max);
    let near = near.max(far * 1e-3).max(1e-4);
    if near >= far {
        return Err(NoMap::NothingBetween);
    }
    // Slightly wider and deeper than the bounds, so no caster touches the map's edges.
    let view = LightView {
        view: look_to(position, axis, up_for(axis)),
        projection: Projection::Perspective {
            tan_half: (half * 1.01).min(1.5).tan(),
        },
        near: near * 0.99,
        far: far * 1.01,
        toward: position,
    };
    if view.is_valid() {
        Ok(view)
    } else {
        Err(NoMap::Degenerate)
    }
}
