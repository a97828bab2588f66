//! Light sources: the lecture notes' point sources, plus directional, spot and distributed (tube,
//! rect) lights. The ambient light `Ia` is not a `Light`: [`crate::LightSet`] holds it.

use glam::Vec3;

use crate::attenuation::Attenuation;
use crate::error::{LightingError, check_direction, check_finite_vec, check_rgb, check_scalar};

/// The most point samples one tube may be split into, and the most per edge of a rect
/// (so a rect has at most `MAX_SAMPLES_PER_EDGE^2` samples).
pub const MAX_SAMPLES_PER_EDGE: u32 = 256;

/// Where a light is and how it spreads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightKind {
    /// A light at infinity (the sun): `direction` is where the light TRAVELS (towards the
    /// scene). Never attenuated.
    Directional {
        /// Travel direction (need not be unit).
        direction: Vec3,
    },
    /// The lecture notes' point source, radiating uniformly in all directions.
    Point {
        /// World position.
        position: Vec3,
    },
    /// A point source restricted to a cone around `direction`, fading smoothly (smoothstep of
    /// the cosine) from full inside `inner_deg` to zero outside `outer_deg` (half-angles).
    Spot {
        /// World position.
        position: Vec3,
        /// Cone axis, the direction the light travels.
        direction: Vec3,
        /// Half-angle of full intensity, degrees, `0 <= inner <= outer`.
        inner_deg: f32,
        /// Half-angle where the light reaches zero, degrees, `<= 180`.
        outer_deg: f32,
    },
    /// The lecture notes' distributed source (a fluorescent tube): the segment `start..end`,
    /// integrated as `samples` point lights at the midpoints of equal sub-segments, each with
    /// `intensity / samples`.
    Tube {
        /// One end.
        start: Vec3,
        /// The other end.
        end: Vec3,
        /// Number of point samples, `1..=MAX_SAMPLES_PER_EDGE`.
        samples: u32,
    },
    /// A distributed parallelogram `corner + s edge_u + t edge_v` (`s, t` in `[0, 1]`),
    /// integrated as `samples x samples` point lights at the cell centres, each with
    /// `intensity / samples^2`.
    Rect {
        /// One corner.
        corner: Vec3,
        /// First edge from the corner.
        edge_u: Vec3,
        /// Second edge from the corner.
        edge_v: Vec3,
        /// Samples per edge, `1..=MAX_SAMPLES_PER_EDGE`.
        samples: u32,
    },
}

/// A light: kind, RGB intensity `Il`, an optional separate intensity for the specular term (as
/// the lecture notes say OpenGL allows), attenuation and an on/off switch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Position, direction and spread.
    pub kind: LightKind,
    /// `Il` (linear RGB, non-negative) used by the diffuse term, and by the specular term
    /// unless `specular_intensity` is set.
    pub intensity: Vec3,
    /// `Il` of the specular term, when it differs from `intensity`.
    pub specular_intensity: Option<Vec3>,
    /// `f(d)`; ignored for directional lights.
    pub attenuation: Attenuation,
    /// Disabled lights are dropped by [`crate::LightSet::new`].
    pub enabled: bool,
}

impl Light {
    /// A light with no attenuation, enabled.
    ///
    /// # Errors
    /// [`LightingError`] naming the bad field: negative or non-finite `intensity`, non-finite
    /// positions, zero or non-finite directions or edges, angles outside `0 <= inner <= outer
    /// <= 180`, `samples` outside `1..=MAX_SAMPLES_PER_EDGE`.
    pub fn new(kind: LightKind, intensity: Vec3) -> Result<Light, LightingError> {
        let light = Light {
            kind,
            intensity,
            specular_intensity: None,
            attenuation: Attenuation::None,
            enabled: true,
        };
        light.validate()?;
        Ok(light)
    }

    /// A point light.
    ///
    /// # Errors
    /// As [`Light::new`].
    pub fn point(position: Vec3, intensity: Vec3) -> Result<Light, LightingError> {
        Light::new(LightKind::Point { position }, intensity)
    }

    /// A directional light travelling along `direction`.
    ///
    /// # Errors
    /// As [`Light::new`].
    pub fn directional(direction: Vec3, intensity: Vec3) -> Result<Light, LightingError> {
        Light::new(LightKind::Directional { direction }, intensity)
    }

    /// The standard scene S1's point lights, all with the lecture notes' `f(d) = 1/(K + d)` at
    /// `K = 1`: `(2,2,2)` Il 3.0; `(-2,1,1)` Il (2.0, 2.0, 2.4); `(0,-2,2)` Il 1.2.
    #[must_use]
    pub const fn s1_lights() -> [Light; 3] {
        const fn s1_point(position: Vec3, intensity: Vec3) -> Light {
            Light {
                kind: LightKind::Point { position },
                intensity,
                specular_intensity: None,
                attenuation: Attenuation::Offset { k: 1.0 },
                enabled: true,
            }
        }
        [
            s1_point(Vec3::new(2.0, 2.0, 2.0), Vec3::splat(3.0)),
            s1_point(Vec3::new(-2.0, 1.0, 1.0), Vec3::new(2.0, 2.0, 2.4)),
            s1_point(Vec3::new(0.0, -2.0, 2.0), Vec3::splat(1.2)),
        ]
    }

    /// This light with an attenuation model.
    ///
    /// # Errors
    /// [`LightingError`] naming `attenuation.k`, `.c`, `.l` or `.q`.
    pub fn with_attenuation(mut self, attenuation: Attenuation) -> Result<Light, LightingError> {
        attenuation.validate()?;
        self.attenuation = attenuation;
        Ok(self)
    }

    /// This light with its own specular intensity.
    ///
    /// # Errors
    /// [`LightingError`] naming `specular_intensity`.
    pub fn with_specular_intensity(mut self, il: Vec3) -> Result<Light, LightingError> {
        check_rgb("specular_intensity", il)?;
        self.specular_intensity = Some(il);
        Ok(self)
    }

    /// This light switched on or off.
    #[must_use]
    pub const fn with_enabled(mut self, enabled: bool) -> Light {
        self.enabled = enabled;
        self
    }

    /// The intensity of the specular term (`specular_intensity` or `intensity`).
    #[inline]
    #[must_use]
    pub fn specular_il(&self) -> Vec3 {
        self.specular_intensity.unwrap_or(self.intensity)
    }

    /// Checks every field (see [`Light::new`]).
    ///
    /// # Errors
    /// [`LightingError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), LightingError> {
        check_rgb("intensity", self.intensity)?;
        if let Some(il) = self.specular_intensity {
            check_rgb("specular_intensity", il)?;
        }
        self.attenuation.validate()?;
        match self.kind {
            LightKind::Directional { direction } => check_direction("direction", direction),
            LightKind::Point { position } => check_finite_vec("position", position),
            LightKind::Spot {
                position,
                direction,
                inner_deg,
                outer_deg,
            } => {
                check_finite_vec("position", position)?;
                check_direction("direction", direction)?;
                check_scalar("inner_deg", inner_deg)?;
                check_scalar("outer_deg", outer_deg)?;
                if outer_deg > 180.0 {
                    return Err(LightingError::OutOfRange {
                        field: "outer_deg",
                        value: outer_deg,
                        range: "[0, 180]",
                    });
                }
                if inner_deg > outer_deg {
                    return Err(LightingError::OutOfRange {
                        field: "inner_deg",
                        value: inner_deg,
                        range: "[0, outer_deg]",
                    });
                }
                Ok(())
            }
            LightKind::Tube {
                start,
                end,
                samples,
            } => {
                check_finite_vec("start", start)?;
                check_finite_vec("end", end)?;
                check_samples(samples)
            }
            LightKind::Rect {
                corner,
                edge_u,
                edge_v,
                samples,
            } => {
                check_finite_vec("corner", corner)?;
                check_finite_vec("edge_u", edge_u)?;
                check_finite_vec("edge_v", edge_v)?;
                check_samples(samples)
            }
        }
    }
}

fn check_samples(samples: u32) -> Result<(), LightingError> {
    if samples == 0 || samples > MAX_SAMPLES_PER_EDGE {
        return Err(LightingError::CountOutOfRange {
            field: "samples",
            value: samples,
            range: "[1, 256]",
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negative_or_non_finite_intensity_is_rejected_by_name() {
        let e = Light::point(Vec3::ZERO, Vec3::new(1.0, -1.0, 1.0)).unwrap_err();
        assert_eq!(e.to_string(), "intensity: must be non-negative, got -1");
        let e = Light::point(Vec3::ZERO, Vec3::splat(f32::INFINITY)).unwrap_err();
        assert!(e.to_string().starts_with("intensity: must be finite"));
        let e = Light::point(Vec3::splat(f32::NAN), Vec3::ONE).unwrap_err();
        assert!(e.to_string().starts_with("position"));
        let ok = Light::point(Vec3::ZERO, Vec3::ONE).unwrap();
        let e = ok.with_specular_intensity(Vec3::splat(-2.0)).unwrap_err();
        assert!(e.to_string().starts_with("specular_intensity"));
        // Zero intensity is allowed (LightSet drops it).
        assert!(Light::point(Vec3::ZERO, Vec3::ZERO).is_ok());
    }

    #[test]
    fn degenerate_geometry_is_rejected_by_name() {
        let e = Light::directional(Vec3::ZERO, Vec3::ONE).unwrap_err();
        assert_eq!(e.to_string(), "direction: must be a non-zero vector");
        let spot = |inner_deg, outer_deg| LightKind::Spot {
            position: Vec3::ZERO,
            direction: Vec3::NEG_Y,
            inner_deg,
            outer_deg,
        };
        let e = Light::new(spot(30.0, 20.0), Vec3::ONE).unwrap_err();
        assert!(e.to_string().starts_with("inner_deg"));
        let e = Light::new(spot(30.0, 200.0), Vec3::ONE).unwrap_err();
        assert!(e.to_string().starts_with("outer_deg"));
        let tube = LightKind::Tube {
            start: Vec3::ZERO,
            end: Vec3::X,
            samples: 0,
        };
        assert!(
            Light::new(tube, Vec3::ONE)
                .unwrap_err()
                .to_string()
                .starts_with("samples")
        );
    }

    #[test]
    fn sample_counts_are_echoed_as_given() {
        // Through f32 the largest u32 would read 4294967300.
        let rect = LightKind::Rect {
            corner: Vec3::ZERO,
            edge_u: Vec3::X,
            edge_v: Vec3::Y,
            samples: u32::MAX,
        };
        assert_eq!(
            Light::new(rect, Vec3::ONE).unwrap_err().to_string(),
            "samples: must be in [1, 256], got 4294967295"
        );
    }

    #[test]
    fn s1_lights_match_the_s1_definition() {
        let [a, b, c] = Light::s1_lights();
        assert_eq!(
            a.kind,
            LightKind::Point {
                position: Vec3::new(2.0, 2.0, 2.0)
            }
        );
        assert_eq!(b.intensity, Vec3::new(2.0, 2.0, 2.4));
        assert_eq!(c.intensity, Vec3::splat(1.2));
        assert!([a, b, c].iter().all(|l| l.validate().is_ok()));
        assert_eq!(a.attenuation, Attenuation::Offset { k: 1.0 });
    }
}
