//! The illumination model, generic over the [`Effects`] bits:
//!
//! `I = emission + ka Ia + sum over lights f(d) Il [kd max(N.L, 0) + ks W(theta) max(V.R, 0)^n_s]`
//!
//! with the specular term 0 where `N.L <= 0`: the lecture notes' ambient `I = Ia Ka`, Lambert's
//! `I = Kd Il (N.L)`, Phong 1975's `Ks Il (V.R)^ns` and the attenuation `1/(K+d)`. `ks` is 1
//! under [`crate::FresnelMode::Replace`], and the lobe goes through
//! [`crate::lobe::specular_lobe`], so `n_s = inf` is a perfect mirror.
//! A term whose bit is absent from `FX` is not evaluated (the `if` on a const folds away), and
//! the result equals the all-effects path with that term zeroed.

use glam::Vec3;
use phosphor_math::{MIN_NORMALIZABLE_LENGTH_SQUARED, reflect, safe_normalize};

use crate::attenuation::factor_from_coefficients;
use crate::effects::Effects;
use crate::lightset::{LightSet, PreparedPoint, spot_cone};
use crate::lobe::specular_lobe;
use crate::material::{Material, SpecularModel};

/// The three sums of the model, kept apart for fast Phong's separate polynomials.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ShadeTerms {
    /// `emission + ka Ia` (no light direction involved).
    pub ambient: Vec3,
    /// `sum f(d) Il kd max(N.L, 0)`.
    pub diffuse: Vec3,
    /// `sum f(d) Il_spec ks W(theta) max(V.R, 0)^n_s` (0 where `N.L <= 0`).
    pub specular: Vec3,
}

impl ShadeTerms {
    /// `ambient + diffuse + specular`, kept finite by [`finite_intensity`].
    #[inline]
    #[must_use]
    pub fn total(self) -> Vec3 {
        finite_intensity(self.ambient + self.diffuse + self.specular)
    }
}

/// The output guard of every shading function: each channel is clamped to `[0, f32::MAX]`
/// and NaN becomes 0. Valid inputs give finite, non-negative sums anyway; this keeps absurd
/// ones (intensities near `f32::MAX` overflowing, negative coefficients written straight into
/// the public fields) from putting NaN or Inf into a framebuffer.
#[inline]
#[must_use]
#[allow(
    clippy::manual_clamp,
    reason = "max/min map NaN to 0, clamp() keeps it"
)]
pub fn finite_intensity(v: Vec3) -> Vec3 {
    Vec3::new(
        v.x.max(0.0).min(f32::MAX),
        v.y.max(0.0).min(f32::MAX),
        v.z.max(0.0).min(f32::MAX),
    )
}

#[inline(always)]
const fn has(fx: u32, effect: Effects) -> bool {
    fx & effect.bits() != 0
}

/// The model at surface point `p` with normal `n` seen from `eye`; see the module docs.
///
/// `n` need not be unit (it is normalized); a zero, tiny or non-finite `n` gives
/// `emission + ka Ia` only. An `eye` at `p` views along `n`. A light at `p` (`d = 0`) shines
/// along `n` with the capped factor of [`crate::attenuation`]. Returns the unclamped
/// (but finite, non-negative) intensity.
///
/// ```
/// use phosphor_lighting::{shade, Effects, Light, LightSet, Material};
/// use glam::Vec3;
/// let set = LightSet::new(Vec3::ONE, &[Light::point(Vec3::new(0.0, 0.0, 2.0), Vec3::ONE)?]);
/// const FX: u32 = Effects::AMBIENT.bits() | Effects::DIFFUSE.bits();
/// let i = shade::<FX>(&set, &Material::s1(), Vec3::ZERO, Vec3::Z, Vec3::new(0.0, 0.0, 3.0));
/// // Ia Ka + Kd Il (N.L) = 0.1 + (0.8, 0.6, 0.4) * 1
/// assert!((i - Vec3::new(0.9, 0.7, 0.5)).length() < 1e-6);
/// # Ok::<(), phosphor_lighting::LightingError>(())
/// ```
#[inline]
#[must_use]
pub fn shade<const FX: u32>(set: &LightSet, mat: &Material, p: Vec3, n: Vec3, eye: Vec3) -> Vec3 {
    shade_split::<FX>(set, mat, p, n, eye).total()
}

/// [`shade`] split into `(ambient + emission, diffuse sum, specular sum)`; each term finite
/// and non-negative, and `shade` is their sum.
#[inline]
#[must_use]
pub fn shade_split<const FX: u32>(
    set: &LightSet,
    mat: &Material,
    p: Vec3,
    n: Vec3,
    eye: Vec3,
) -> ShadeTerms {
    let mut ambient = Vec3::ZERO;
    if has(FX, Effects::EMISSION) {
        // The lecture notes' I = Ka for self-luminous objects, added as is.
        ambient += mat.emission;
    }
    if has(FX, Effects::AMBIENT) {
        // The lecture notes' I = Ia Ka.
        ambient += mat.ka * set.ambient();
    }
    let mut terms = ShadeTerms {
        ambient: finite_intensity(ambient),
        ..ShadeTerms::default()
    };
    if !has(FX, Effects::DIFFUSE) && !has(FX, Effects::SPECULAR) {
        return terms;
    }
    let n = unit_normal(n);
    if n == Vec3::ZERO {
        return terms;
    }
    let v = safe_normalize(eye - p, n);
    let mut acc = Sums::default();
    for light in set.directional() {
        acc.add::<FX>(mat, n, v, light.to_light, light.il, light.il_specular);
    }
    for light in set.points() {
        let (l, f) = towards::<FX>(light, p, n);
        acc.add::<FX>(mat, n, v, l, light.il * f, light.il_specular * f);
    }
    if has(FX, Effects::SPOT) {
        for spot in set.spots() {
            let (l, f) = towards::<FX>(&spot.point, p, n);
            let f = f * spot_cone(-l.dot(spot.axis), spot.cos_outer, spot.inv_cos_width);
            acc.add::<FX>(mat, n, v, l, spot.point.il * f, spot.point.il_specular * f);
        }
    }
    if has(FX, Effects::DISTRIBUTED) {
        for light in set.distributed_samples() {
            let (l, f) = towards::<FX>(light, p, n);
            acc.add::<FX>(mat, n, v, l, light.il * f, light.il_specular * f);
        }
    }
    terms.diffuse = finite_intensity(acc.diffuse);
    terms.specular = finite_intensity(acc.specular);
    terms
}

/// Normals whose squared length is within this of 1 are used as given (the rasterizer passes
/// unit normals; renormalizing them would cost a square root and a division per pixel).
pub const UNIT_NORMAL_TOLERANCE: f32 = 1e-6;

/// `n` when it is already unit (within [`UNIT_NORMAL_TOLERANCE`] in squared length), else
/// `safe_normalize(n, 0)`: zero for a zero, tiny or non-finite normal.
#[inline(always)]
fn unit_normal(n: Vec3) -> Vec3 {
    // NaN or infinite lengths fail the comparison and take the guarded path.
    if (n.length_squared() - 1.0).abs() <= UNIT_NORMAL_TOLERANCE {
        n
    } else {
        safe_normalize(n, Vec3::ZERO)
    }
}

/// Unit vector from `p` towards a positional light (falling back to `n` when the light is at
/// `p`) and the attenuation factor (1 without ATTENUATION).
#[inline(always)]
fn towards<const FX: u32>(light: &PreparedPoint, p: Vec3, n: Vec3) -> (Vec3, f32) {
    let delta = light.position - p;
    let d2 = delta.length_squared();
    let (l, d) = if d2.is_finite() && d2 >= MIN_NORMALIZABLE_LENGTH_SQUARED {
        let d = d2.sqrt();
        (delta * d.recip(), d)
    } else {
        (safe_normalize(delta, n), delta.length())
    };
    let f = if has(FX, Effects::ATTENUATION) {
        factor_from_coefficients(light.attenuation, d)
    } else {
        1.0
    };
    (l, f)
}

#[derive(Default)]
struct Sums {
    diffuse: Vec3,
    specular: Vec3,
}

impl Sums {
    /// One light's `kd Il (N.L) + ks W Il_spec (V.R)^n`, `il` already attenuated.
    #[inline(always)]
    fn add<const FX: u32>(
        &mut self,
        mat: &Material,
        n: Vec3,
        v: Vec3,
        l: Vec3,
        il: Vec3,
        il_s: Vec3,
    ) {
        let n_dot_l = n.dot(l);
        if n_dot_l <= 0.0 {
            // The light is behind the surface: no diffuse, and no specular (the lecture notes'
            // figure of N, L, R).
            return;
        }
        if has(FX, Effects::DIFFUSE) {
            // The lecture notes' I = Kd Il (N.L) (Lambert).
            self.diffuse += (mat.kd * n_dot_l) * il;
        }
        if has(FX, Effects::SPECULAR) {
            let lobe = match mat.specular {
                // Phong 1975: (V.R)^ns with R = 2(N.L)N - L.
                SpecularModel::Phong => specular_lobe(reflect(n, l).dot(v), mat.shininess),
                SpecularModel::Blinn => {
                    specular_lobe(n.dot(safe_normalize(l + v, n)), mat.shininess)
                }
            };
            let w = if has(FX, Effects::FRESNEL) {
                mat.fresnel.w(n_dot_l)
            } else {
                1.0
            };
            self.specular += (mat.ks * (w * lobe)) * il_s;
        }
    }
}

/// [`shade`] with the effects chosen at run time: dispatches to the `shade::<FX>`
/// instantiation for `effects` (see [`crate::dispatch_effects`]). Inlined, so the 512
/// instantiations are only compiled where this is called.
#[inline]
#[must_use]
pub fn shade_dyn(
    effects: Effects,
    set: &LightSet,
    mat: &Material,
    p: Vec3,
    n: Vec3,
    eye: Vec3,
) -> Vec3 {
    crate::dispatch_effects!(effects, FX => shade::<FX>(set, mat, p, n, eye))
}

/// [`shade`] through [`crate::dispatch_canonical_effects`]: the runtime `effects` rounded up
/// to their canonical superset (16 instantiations), same result as [`shade_dyn`].
#[inline]
#[must_use]
pub fn shade_canonical(
    effects: Effects,
    set: &LightSet,
    mat: &Material,
    p: Vec3,
    n: Vec3,
    eye: Vec3,
) -> Vec3 {
    crate::dispatch_canonical_effects!(effects, FX => shade::<FX>(set, mat, p, n, eye))
}
