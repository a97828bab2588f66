//! [`LightSet`]: the lights of a draw prepared once (world space) so the per-pixel loops run
//! over plain arrays, one per light kind, with no branching on kind or attenuation model.

use glam::Vec3;
use phosphor_math::safe_normalize;

use crate::attenuation::Attenuation;
use crate::effects::Effects;
use crate::error::LightingError;
use crate::light::{Light, LightKind, MAX_SAMPLES_PER_EDGE};

/// Spot cones whose inner and outer cosines differ by less than this fade over this width
/// instead (a hard edge without dividing by zero).
pub const MIN_SPOT_COS_WIDTH: f32 = 1e-6;

/// A directional light, prepared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreparedDirectional {
    /// Unit vector from the surface towards the light (`-direction`, normalized): the lecture
    /// notes' L.
    pub to_light: Vec3,
    /// Diffuse `Il`.
    pub il: Vec3,
    /// Specular `Il`.
    pub il_specular: Vec3,
}

/// A point light (or one sample of a distributed light), prepared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreparedPoint {
    /// World position.
    pub position: Vec3,
    /// Diffuse `Il` (already divided by the sample count for distributed lights).
    pub il: Vec3,
    /// Specular `Il`.
    pub il_specular: Vec3,
    /// `[c, l, q]` of `f(d) = 1/(c + l d + q d^2)` ([`Attenuation::coefficients`]).
    pub attenuation: [f32; 3],
}

/// A spot light, prepared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreparedSpot {
    /// The light as a point light.
    pub point: PreparedPoint,
    /// Unit cone axis (direction of travel).
    pub axis: Vec3,
    /// Cosine of the outer half-angle: zero light at and beyond it.
    pub cos_outer: f32,
    /// `1 / max(cos_inner - cos_outer, MIN_SPOT_COS_WIDTH)`.
    pub inv_cos_width: f32,
}

/// The smooth cone fall-off of a spot light: smoothstep from `cos_outer` (0) to `cos_inner`
/// (1) of `cos_angle`, the cosine between the axis and the direction from the light to the
/// point. In `[0, 1]` for every input (NaN counts as outside).
#[inline]
#[must_use]
#[allow(
    clippy::manual_clamp,
    reason = "max/min map NaN to 0, clamp() keeps it"
)]
pub fn spot_cone(cos_angle: f32, cos_outer: f32, inv_cos_width: f32) -> f32 {
    let t = ((cos_angle - cos_outer) * inv_cos_width).max(0.0).min(1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Double-precision [`spot_cone`].
#[inline]
#[must_use]
#[allow(
    clippy::manual_clamp,
    reason = "max/min map NaN to 0, clamp() keeps it"
)]
pub fn spot_cone_f64(cos_angle: f64, cos_outer: f64, inv_cos_width: f64) -> f64 {
    let t = ((cos_angle - cos_outer) * inv_cos_width).max(0.0).min(1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Lights prepared once per draw (world space): split by kind, distributed lights expanded
/// to point samples, unit vectors precomputed. Allocation happens here, never per pixel.
///
/// Disabled lights, lights whose diffuse and specular intensities are both zero, and lights
/// that fail [`Light::validate`] are dropped ([`LightSet::try_new`] reports the latter).
/// Negative, NaN or infinite ambient channels count as 0.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LightSet {
    ambient: Vec3,
    directional: Vec<PreparedDirectional>,
    points: Vec<PreparedPoint>,
    spots: Vec<PreparedSpot>,
    samples: Vec<PreparedPoint>,
}

#[allow(
    clippy::manual_clamp,
    reason = "max/min map NaN to 0, clamp() keeps it"
)]
fn sanitize_rgb(v: Vec3) -> Vec3 {
    Vec3::from_array(v.to_array().map(|c| c.max(0.0).min(f32::MAX)))
}

impl LightSet {
    /// Prepares `lights` under the ambient light `ambient` (the lecture notes' `Ia`).
    #[must_use]
    pub fn new(ambient: Vec3, lights: &[Light]) -> LightSet {
        let mut set = LightSet {
            ambient: sanitize_rgb(ambient),
            ..LightSet::default()
        };
        for light in lights {
            if light.validate().is_ok() {
                set.push(light);
            }
        }
        set
    }

    /// The standard scene S1's lights: `Ia = 1` and [`Light::s1_lights`].
    #[must_use]
    pub fn s1() -> LightSet {
        LightSet::new(Vec3::ONE, &Light::s1_lights())
    }

    /// Like [`LightSet::new`] but reports the first invalid light (by index) instead of
    /// dropping it.
    ///
    /// # Errors
    /// `(index, error)` of the first light failing [`Light::validate`].
    pub fn try_new(ambient: Vec3, lights: &[Light]) -> Result<LightSet, (usize, LightingError)> {
        for (i, light) in lights.iter().enumerate() {
            light.validate().map_err(|e| (i, e))?;
        }
        Ok(LightSet::new(ambient, lights))
    }

    fn push(&mut self, light: &Light) {
        let il = light.intensity;
        let il_specular = light.specular_il();
        if !light.enabled || (il == Vec3::ZERO && il_specular == Vec3::ZERO) {
            return;
        }
        let attenuation = light.attenuation.coefficients();
        let point = |position: Vec3, share: f32| PreparedPoint {
            position,
            il: il * share,
            il_specular: il_specular * share,
            attenuation,
        };
        match light.kind {
            LightKind::Directional { direction } => {
                // safe_normalize rescales directions whose squared length overflows.
                self.directional.push(PreparedDirectional {
                    to_light: -safe_normalize(direction, Vec3::ZERO),
                    il,
                    il_specular,
                });
            }
            LightKind::Point { position } => self.points.push(point(position, 1.0)),
            LightKind::Spot {
                position,
                direction,
                inner_deg,
                outer_deg,
            } => {
                let cos_inner = inner_deg.to_radians().cos();
                let cos_outer = outer_deg.to_radians().cos();
                self.spots.push(PreparedSpot {
                    point: point(position, 1.0),
                    axis: safe_normalize(direction, Vec3::ZERO),
                    cos_outer,
                    inv_cos_width: (cos_inner - cos_outer).max(MIN_SPOT_COS_WIDTH).recip(),
                });
            }
            LightKind::Tube {
                start,
                end,
                samples,
            } => {
                // Midpoints of `samples` equal sub-segments, each carrying intensity/samples.
                let n = samples.clamp(1, MAX_SAMPLES_PER_EDGE);
                let share = 1.0 / n as f32;
                for i in 0..n {
                    let s = (i as f32 + 0.5) * share;
                    self.samples.push(point(start + (end - start) * s, share));
                }
            }
            LightKind::Rect {
                corner,
                edge_u,
                edge_v,
                samples,
            } => {
                // Centres of the `samples x samples` equal cells, each intensity/samples^2.
                let n = samples.clamp(1, MAX_SAMPLES_PER_EDGE);
                let step = 1.0 / n as f32;
                let share = step * step;
                for i in 0..n {
                    for j in 0..n {
                        let s = (i as f32 + 0.5) * step;
                        let t = (j as f32 + 0.5) * step;
                        self.samples
                            .push(point(corner + edge_u * s + edge_v * t, share));
                    }
                }
            }
        }
    }

    /// The ambient light `Ia`.
    #[inline]
    #[must_use]
    pub fn ambient(&self) -> Vec3 {
        self.ambient
    }

    /// Directional lights.
    #[inline]
    #[must_use]
    pub fn directional(&self) -> &[PreparedDirectional] {
        &self.directional
    }

    /// Point lights.
    #[inline]
    #[must_use]
    pub fn points(&self) -> &[PreparedPoint] {
        &self.points
    }

    /// Spot lights.
    #[inline]
    #[must_use]
    pub fn spots(&self) -> &[PreparedSpot] {
        &self.spots
    }

    /// Point samples of the distributed (tube, rect) lights.
    #[inline]
    #[must_use]
    pub fn distributed_samples(&self) -> &[PreparedPoint] {
        &self.samples
    }

    /// Number of prepared lights (distributed lights count once per sample).
    #[must_use]
    pub fn len(&self) -> usize {
        self.directional.len() + self.points.len() + self.spots.len() + self.samples.len()
    }

    /// True when no light is left (ambient only).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The effects these lights can produce: AMBIENT when `Ia != 0`; DIFFUSE, SPECULAR and
    /// FRESNEL when any light is left; ATTENUATION when a positional light has a model other
    /// than `f = 1`; SPOT when a spot light is left; DISTRIBUTED when a tube or rect is left;
    /// EMISSION always (it is the material's). BUMP is never set here. Intersect with
    /// [`crate::Material::effects_needed`] for what a draw uses.
    #[must_use]
    pub fn effects_needed(&self) -> Effects {
        let none = Attenuation::None.coefficients();
        let attenuated = self
            .points
            .iter()
            .chain(self.spots.iter().map(|s| &s.point))
            .chain(&self.samples)
            .any(|p| p.attenuation != none);
        Effects::EMISSION
            .with(Effects::AMBIENT, self.ambient != Vec3::ZERO)
            .with(
                Effects::DIFFUSE | Effects::SPECULAR | Effects::FRESNEL,
                !self.is_empty(),
            )
            .with(Effects::ATTENUATION, attenuated)
            .with(Effects::SPOT, !self.spots.is_empty())
            .with(Effects::DISTRIBUTED, !self.samples.is_empty())
    }
}

/// The minimal effects for drawing `material` under `lights`: the intersection of both needs.
#[must_use]
pub fn effects_for(lights: &LightSet, material: &crate::Material) -> Effects {
    lights.effects_needed() & material.effects_needed()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lights_are_split_by_kind_and_dead_ones_dropped() {
        let lights = [
            Light::point(Vec3::X, Vec3::ONE).unwrap(),
            Light::point(Vec3::X, Vec3::ZERO).unwrap(),
            Light::point(Vec3::Y, Vec3::ONE)
                .unwrap()
                .with_enabled(false),
            Light::directional(Vec3::new(0.0, -2.0, 0.0), Vec3::ONE).unwrap(),
            Light {
                intensity: Vec3::splat(-1.0),
                ..Light::point(Vec3::X, Vec3::ONE).unwrap()
            },
        ];
        let set = LightSet::new(Vec3::splat(0.2), &lights);
        assert_eq!(set.points().len(), 1);
        assert_eq!(set.directional().len(), 1);
        assert_eq!(set.directional()[0].to_light, Vec3::Y);
        assert_eq!(set.len(), 2);
        let err = LightSet::try_new(Vec3::ZERO, &lights).unwrap_err();
        assert_eq!(err.0, 4);
    }

    #[test]
    fn distributed_lights_become_equal_share_samples_at_cell_centres() {
        let tube = LightKind::Tube {
            start: Vec3::ZERO,
            end: Vec3::new(4.0, 0.0, 0.0),
            samples: 4,
        };
        let rect = LightKind::Rect {
            corner: Vec3::ZERO,
            edge_u: Vec3::X,
            edge_v: Vec3::Z,
            samples: 2,
        };
        let set = LightSet::new(
            Vec3::ZERO,
            &[
                Light::new(tube, Vec3::splat(2.0)).unwrap(),
                Light::new(rect, Vec3::ONE).unwrap(),
            ],
        );
        let s = set.distributed_samples();
        assert_eq!(s.len(), 4 + 4);
        let xs: Vec<f32> = s[..4].iter().map(|p| p.position.x).collect();
        assert_eq!(xs, [0.5, 1.5, 2.5, 3.5]);
        assert!(s[..4].iter().all(|p| p.il == Vec3::splat(0.5)));
        assert_eq!(s[4].position, Vec3::new(0.25, 0.0, 0.25));
        assert!(s[4..].iter().all(|p| p.il == Vec3::splat(0.25)));
        let total: Vec3 = s.iter().map(|p| p.il).sum();
        assert!((total - Vec3::splat(3.0)).length() < 1e-6);
    }

    #[test]
    fn effects_needed_reflects_the_lights_present() {
        let set = LightSet::new(Vec3::ZERO, &[]);
        assert_eq!(set.effects_needed(), Effects::EMISSION);
        let plain = Light::point(Vec3::X, Vec3::ONE).unwrap();
        let set = LightSet::new(Vec3::ONE, &[plain]);
        let fx = set.effects_needed();
        assert!(fx.contains(Effects::AMBIENT | Effects::DIFFUSE | Effects::SPECULAR));
        assert!(!fx.contains(Effects::ATTENUATION));
        assert!(!fx.contains(Effects::SPOT));
        let set = LightSet::new(Vec3::ONE, &Light::s1_lights());
        assert!(set.effects_needed().contains(Effects::ATTENUATION));
        let s1 = effects_for(&set, &crate::Material::s1());
        assert!(!s1.contains(Effects::FRESNEL) && !s1.contains(Effects::SPOT));
    }

    #[test]
    fn spot_cone_fades_smoothly_and_handles_equal_angles() {
        let (co, ci) = (0.5f32, 0.9f32);
        let inv = (ci - co).recip();
        assert_eq!(spot_cone(0.4, co, inv), 0.0);
        assert_eq!(spot_cone(0.95, co, inv), 1.0);
        assert!((spot_cone(0.7, co, inv) - 0.5).abs() < 1e-6);
        let hard = MIN_SPOT_COS_WIDTH.recip();
        assert_eq!(spot_cone(0.6, 0.5, hard), 1.0);
        assert_eq!(spot_cone(f32::NAN, 0.5, hard), 0.0);
    }
}
