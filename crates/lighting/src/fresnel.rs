//! The lecture notes' specular-reflection coefficient `W(theta)` (Fresnel's laws), `theta` the
//! angle of incidence, `cos theta = N.L`, and how it enters the specular term ([`FresnelMode`]).
//!
//! The notes write the specular term `I_spec = W(theta) Il cos^ns phi`, with `W` the whole
//! coefficient, and replace `W` by a constant `Ks` for materials whose reflectance does not
//! depend on the angle. The shading code always evaluates `ks W(theta)`: under
//! [`FresnelMode::Scale`] `ks` is the material's, under [`FresnelMode::Replace`] it is held at 1,
//! so the coefficient is `1 W(theta) = W(theta)`, the notes' form. Both are tested against
//! hand-computed values.

use std::fmt;
use std::str::FromStr;

use crate::error::{LightingError, check_scalar};

/// How `W(theta)` enters the specular coefficient.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FresnelMode {
    /// `ks W(theta)`: `W` shapes the change of reflectance with the angle, `ks` sets its colour
    /// and strength (a metal's tinted `ks` under Schlick's curve).
    #[default]
    Scale,
    /// `W(theta)` alone, the lecture notes' `I_spec = W(theta) Il cos^ns phi`: the material's
    /// `ks` must be 1 ([`crate::Material::with_fresnel_mode`] sets it), so `ks W = W`.
    Replace,
}

impl FresnelMode {
    /// The scene-file name: `"scale"` or `"replace"`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            FresnelMode::Scale => "scale",
            FresnelMode::Replace => "replace",
        }
    }
}

impl fmt::Display for FresnelMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Parses the scene-file names `"scale"` and `"replace"` (ASCII case-insensitive).
impl FromStr for FresnelMode {
    type Err = LightingError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "scale" => Ok(FresnelMode::Scale),
            "replace" => Ok(FresnelMode::Replace),
            _ => Err(LightingError::UnknownName {
                field: "fresnel.mode",
                name: s.to_owned(),
                expected: "\"scale\" or \"replace\"",
            }),
        }
    }
}

/// Glass-like reflectance at normal incidence: "at theta = 0 about 4 percent of the incident
/// light on a glass surface is reflected" (the lecture notes).
pub const GLASS_F0: f32 = 0.04;

/// How the specular coefficient varies with the angle of incidence.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Fresnel {
    /// `W = 1`: the material's `ks` is used as is ("for many opaque materials, specular
    /// reflection is nearly constant for all incidence angles", the lecture notes).
    #[default]
    None,
    /// `W = w` for every angle (scales `ks`).
    Constant {
        /// The constant factor.
        w: f32,
    },
    /// Schlick's approximation `W = f0 + (1 - f0)(1 - cos theta)^5`: `f0` at normal incidence,
    /// rising to 1 at 90 degrees, as the lecture notes describe for glass ([`GLASS_F0`]).
    Schlick {
        /// Reflectance at normal incidence, in `[0, 1]`.
        f0: f32,
    },
}

impl Fresnel {
    /// `W(theta)` for `cos_theta = N.L` (clamped to `[0, 1]`, NaN counting as 0).
    #[inline]
    #[must_use]
    #[allow(
        clippy::manual_clamp,
        reason = "max/min map NaN to a bound, clamp() keeps it"
    )]
    pub fn w(self, cos_theta: f32) -> f32 {
        match self {
            Fresnel::None => 1.0,
            Fresnel::Constant { w } => w,
            Fresnel::Schlick { f0 } => {
                let m = 1.0 - cos_theta.max(0.0).min(1.0);
                let m2 = m * m;
                f0 + (1.0 - f0) * (m2 * m2 * m)
            }
        }
    }

    /// Double-precision `W(theta)` (for `shade_reference`).
    #[inline]
    #[must_use]
    #[allow(
        clippy::manual_clamp,
        reason = "max/min map NaN to a bound, clamp() keeps it"
    )]
    pub fn w_f64(self, cos_theta: f64) -> f64 {
        match self {
            Fresnel::None => 1.0,
            Fresnel::Constant { w } => f64::from(w),
            Fresnel::Schlick { f0 } => {
                let f0 = f64::from(f0);
                f0 + (1.0 - f0) * (1.0 - cos_theta.max(0.0).min(1.0)).powi(5)
            }
        }
    }

    /// The largest `W` over all angles (1 for `None` and `Schlick`, `w` for `Constant`).
    #[inline]
    #[must_use]
    pub fn max_w(self) -> f32 {
        match self {
            Fresnel::None => 1.0,
            Fresnel::Constant { w } => w,
            Fresnel::Schlick { f0 } => f0.max(1.0),
        }
    }

    /// True when `W = 1` at every angle (no FRESNEL effect needed).
    #[inline]
    #[must_use]
    pub fn is_identity(self) -> bool {
        match self {
            Fresnel::None => true,
            Fresnel::Constant { w } => w == 1.0,
            Fresnel::Schlick { f0 } => f0 == 1.0,
        }
    }

    /// Checks `w` is finite and non-negative and `f0` is in `[0, 1]`.
    ///
    /// # Errors
    /// [`LightingError`] naming `fresnel.w` or `fresnel.f0`.
    pub fn validate(self) -> Result<(), LightingError> {
        match self {
            Fresnel::None => Ok(()),
            Fresnel::Constant { w } => check_scalar("fresnel.w", w),
            Fresnel::Schlick { f0 } => {
                check_scalar("fresnel.f0", f0)?;
                if f0 > 1.0 {
                    return Err(LightingError::OutOfRange {
                        field: "fresnel.f0",
                        value: f0,
                        range: "[0, 1]",
                    });
                }
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schlick_glass_reflects_four_percent_head_on_and_all_at_grazing() {
        let glass = Fresnel::Schlick { f0: GLASS_F0 };
        assert!((glass.w(1.0) - 0.04).abs() < 1e-7);
        assert!((glass.w(0.0) - 1.0).abs() < 1e-7);
        // W(theta) increases with the angle of incidence (the lecture notes).
        let mut last = glass.w(1.0);
        for i in (0..100).rev() {
            let w = glass.w(i as f32 / 100.0);
            assert!(w >= last);
            last = w;
        }
        assert!((glass.w(0.5) as f64 - glass.w_f64(0.5)).abs() < 1e-6);
    }

    #[test]
    fn none_and_constant_do_not_depend_on_angle() {
        assert_eq!(Fresnel::None.w(0.3), 1.0);
        assert_eq!(Fresnel::Constant { w: 0.7 }.w(0.9), 0.7);
        assert!(Fresnel::None.is_identity());
        assert!(!Fresnel::Schlick { f0: 0.04 }.is_identity());
    }

    #[test]
    fn invalid_fresnel_parameters_are_rejected_by_name() {
        let e = Fresnel::Schlick { f0: 1.5 }.validate().unwrap_err();
        assert!(e.to_string().contains("fresnel.f0"));
        let e = Fresnel::Constant { w: -0.1 }.validate().unwrap_err();
        assert!(e.to_string().contains("fresnel.w"));
    }
}
