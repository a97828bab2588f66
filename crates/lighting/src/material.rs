//! Surface optical properties: the lecture notes' `ka`, `kd`, `ks`, `n_s`, `W(theta)` and the
//! self-luminous intensity.

use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use crate::effects::Effects;
use crate::error::{LightingError, check_rgb, check_shininess};
use crate::fresnel::{Fresnel, FresnelMode};

/// Which specular lobe a material uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SpecularModel {
    /// Phong: `(V.R)^n_s` with `R = 2(N.L)N - L` (Phong 1975).
    #[default]
    Phong,
    /// Blinn: `(N.H)^n_s` with the half vector `H = (L + V)/|L + V|`.
    Blinn,
}

impl SpecularModel {
    /// The scene-file name: `"phong"` or `"blinn"`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            SpecularModel::Phong => "phong",
            SpecularModel::Blinn => "blinn",
        }
    }
}

impl fmt::Display for SpecularModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Parses the scene-file names `"phong"` and `"blinn"` (ASCII case-insensitive).
impl FromStr for SpecularModel {
    type Err = LightingError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "phong" => Ok(SpecularModel::Phong),
            "blinn" => Ok(SpecularModel::Blinn),
            _ => Err(LightingError::UnknownName {
                field: "specular",
                name: s.to_owned(),
                expected: "\"phong\" or \"blinn\"",
            }),
        }
    }
}

/// A material: reflection coefficients per RGB channel (x = r, y = g, z = b).
///
/// Fields are public for plain-data use; [`Material::new`] and the `with_*` builders validate
/// (finite, non-negative). Shading stays finite for any field values, but only validated values
/// give the documented bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Ambient-reflection coefficient `Ka` (the lecture notes' `I = Ia Ka`).
    pub ka: Vec3,
    /// Diffuse-reflection coefficient `Kd` (Lambert).
    pub kd: Vec3,
    /// Specular-reflection coefficient `Ks` (the lecture notes' constant in place of `W(theta)`);
    /// 1 under [`FresnelMode::Replace`].
    pub ks: Vec3,
    /// Specular-reflection parameter `n_s` (large: shiny; 1: dull; 0: no fall-off; `+inf`: the
    /// perfect mirror of [`crate::lobe`]).
    pub shininess: f32,
    /// Phong or Blinn lobe.
    pub specular: SpecularModel,
    /// `W(theta)`: multiplies `ks` per angle of incidence.
    pub fresnel: Fresnel,
    /// Whether `W(theta)` scales `ks` or is the whole coefficient (then `ks = 1`).
    pub fresnel_mode: FresnelMode,
    /// Self-luminous intensity added as is (the lecture notes' `I = Ka` for "self-luminous
    /// objects").
    pub emission: Vec3,
}

/// Matte grey: `ka 0.1`, `kd 0.7`, no specular.
impl Default for Material {
    fn default() -> Self {
        Material {
            ka: Vec3::splat(0.1),
            kd: Vec3::splat(0.7),
            ks: Vec3::ZERO,
            shininess: 1.0,
            specular: SpecularModel::Phong,
            fresnel: Fresnel::None,
            fresnel_mode: FresnelMode::Scale,
            emission: Vec3::ZERO,
        }
    }
}

impl Material {
    /// A Phong material without Fresnel variation or emission.
    ///
    /// # Errors
    /// [`LightingError`] naming the first negative or non-finite field (`ka`, `kd`, `ks`,
    /// `shininess`).
    pub fn new(ka: Vec3, kd: Vec3, ks: Vec3, shininess: f32) -> Result<Material, LightingError> {
        let m = Material {
            ka,
            kd,
            ks,
            shininess,
            specular: SpecularModel::Phong,
            fresnel: Fresnel::None,
            fresnel_mode: FresnelMode::Scale,
            emission: Vec3::ZERO,
        };
        m.validate()?;
        Ok(m)
    }

    /// The standard scene S1's material: `ka 0.1` grey, `kd (0.8, 0.6, 0.4)`, `ks 0.5` grey,
    /// `n_s 32`, Phong, no Fresnel.
    #[must_use]
    pub const fn s1() -> Material {
        Material {
            ka: Vec3::splat(0.1),
            kd: Vec3::new(0.8, 0.6, 0.4),
            ks: Vec3::splat(0.5),
            shininess: 32.0,
            specular: SpecularModel::Phong,
            fresnel: Fresnel::None,
            fresnel_mode: FresnelMode::Scale,
            emission: Vec3::ZERO,
        }
    }

    /// This material with another specular lobe.
    #[must_use]
    pub const fn with_specular(mut self, model: SpecularModel) -> Material {
        self.specular = model;
        self
    }

    /// This material with a `W(theta)`.
    ///
    /// # Errors
    /// [`LightingError`] naming `fresnel.w` or `fresnel.f0`.
    pub fn with_fresnel(mut self, fresnel: Fresnel) -> Result<Material, LightingError> {
        fresnel.validate()?;
        self.fresnel = fresnel;
        Ok(self)
    }

    /// This material with `W(theta)` entering the specular coefficient as `mode` says:
    /// [`FresnelMode::Replace`] also sets `ks` to 1, so that the coefficient `ks W(theta)` is
    /// `W(theta)` alone (the lecture notes' form); [`FresnelMode::Scale`] keeps `ks`.
    #[must_use]
    pub fn with_fresnel_mode(mut self, mode: FresnelMode) -> Material {
        self.fresnel_mode = mode;
        if mode == FresnelMode::Replace {
            self.ks = Vec3::ONE;
        }
        self
    }

    /// This material with a self-luminous intensity.
    ///
    /// # Errors
    /// [`LightingError`] naming `emission`.
    pub fn with_emission(mut self, emission: Vec3) -> Result<Material, LightingError> {
        check_rgb("emission", emission)?;
        self.emission = emission;
        Ok(self)
    }

    /// Checks every field is finite and non-negative, except `shininess`, which may also be
    /// `+inf` (the perfect mirror); `f0` at most 1; `ks` exactly 1 under
    /// [`FresnelMode::Replace`].
    ///
    /// # Errors
    /// [`LightingError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), LightingError> {
        check_rgb("ka", self.ka)?;
        check_rgb("kd", self.kd)?;
        check_rgb("ks", self.ks)?;
        if self.fresnel_mode == FresnelMode::Replace
            && let Some(value) = self.ks.to_array().into_iter().find(|&k| k != 1.0)
        {
            return Err(LightingError::Conflict {
                field: "ks",
                value,
                reason: "must be 1 under fresnel mode \"replace\" (W(theta) is the whole specular coefficient)",
            });
        }
        check_shininess(self.shininess)?;
        self.fresnel.validate()?;
        check_rgb("emission", self.emission)
    }

    /// The effects this material can show: no AMBIENT when `ka = 0`, no DIFFUSE when `kd = 0`,
    /// no SPECULAR when `ks = 0`, no FRESNEL when `W = 1` (or without specular), no EMISSION
    /// when `emission = 0`. The light-dependent bits (ATTENUATION, SPOT, DISTRIBUTED) are all
    /// set: intersect with [`crate::LightSet::effects_needed`] for what a draw uses. BUMP is
    /// never set here (the planner adds it for bump-mapped objects).
    #[must_use]
    pub fn effects_needed(&self) -> Effects {
        let specular = self.ks != Vec3::ZERO;
        Effects::ATTENUATION
            .union(Effects::SPOT)
            .union(Effects::DISTRIBUTED)
            .with(Effects::AMBIENT, self.ka != Vec3::ZERO)
            .with(Effects::DIFFUSE, self.kd != Vec3::ZERO)
            .with(Effects::SPECULAR, specular)
            .with(Effects::FRESNEL, specular && !self.fresnel.is_identity())
            .with(Effects::EMISSION, self.emission != Vec3::ZERO)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constructor_rejects_negative_and_non_finite_fields_by_name() {
        let e = Material::new(Vec3::splat(-0.1), Vec3::ONE, Vec3::ONE, 1.0).unwrap_err();
        assert_eq!(e.to_string(), "ka: must be non-negative, got -0.1");
        let e = Material::new(Vec3::ZERO, Vec3::new(0.0, f32::NAN, 0.0), Vec3::ONE, 1.0);
        assert!(e.unwrap_err().to_string().starts_with("kd: must be finite"));
        let e = Material::new(Vec3::ZERO, Vec3::ONE, Vec3::ONE, f32::NAN).unwrap_err();
        assert_eq!(e.to_string(), "shininess: must be in [0, inf], got NaN");
        let e = Material::new(Vec3::ZERO, Vec3::ONE, Vec3::ONE, f32::NEG_INFINITY).unwrap_err();
        assert_eq!(e.to_string(), "shininess: must be non-negative, got -inf");
        assert!(Material::new(Vec3::ZERO, Vec3::ONE, Vec3::ONE, f32::INFINITY).is_ok());
        let e = Material::s1().with_emission(Vec3::NEG_ONE).unwrap_err();
        assert!(e.to_string().starts_with("emission"));
        assert!(Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, f32::MAX).is_ok());
    }

    #[test]
    fn specular_model_names_round_trip_and_unknown_names_are_rejected() {
        for m in [SpecularModel::Phong, SpecularModel::Blinn] {
            assert_eq!(m.to_string().parse::<SpecularModel>(), Ok(m));
        }
        assert_eq!("Blinn".parse::<SpecularModel>(), Ok(SpecularModel::Blinn));
        let e = "cook-torrance".parse::<SpecularModel>().unwrap_err();
        assert_eq!(
            e.to_string(),
            "specular: unknown name \"cook-torrance\", expected \"phong\" or \"blinn\""
        );
    }

    #[test]
    fn s1_material_has_the_s1_values() {
        let m = Material::s1();
        assert_eq!(m.kd, Vec3::new(0.8, 0.6, 0.4));
        assert_eq!(m.shininess, 32.0);
        assert!(m.validate().is_ok());
        assert!(Material::default().validate().is_ok());
    }

    #[test]
    fn effects_needed_drops_terms_with_zero_coefficients() {
        let m = Material::default();
        let fx = m.effects_needed();
        assert!(fx.contains(Effects::AMBIENT | Effects::DIFFUSE));
        assert!(!fx.contains(Effects::SPECULAR));
        assert!(!fx.contains(Effects::FRESNEL));
        assert!(!fx.contains(Effects::EMISSION));
        let glass = Material::s1().with_fresnel(Fresnel::Schlick { f0: 0.04 });
        assert!(
            glass
                .map(|g| g.effects_needed().contains(Effects::FRESNEL))
                .unwrap_or(false)
        );
    }
}
