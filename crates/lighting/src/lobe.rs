//! The specular lobe `cos^n_s phi` (Phong 1975's `(V.R)^n_s`, Blinn 1977's `(N.H)^n_s`),
//! including the lecture notes' perfect reflector, `n_s` infinite.
//!
//! A finite `n_s` is [`clamped_pow_fast`]: the cosine clamped to `[0, 1]`, then raised to
//! `n_s`. An infinite `n_s` is a perfect mirror: "incident light is reflected only in the
//! specular reflection direction", so the lobe is 1 where `phi = 0` and 0 everywhere else. In
//! floating point `phi = 0` cannot be tested exactly: the cosine of two vectors that are the same
//! direction comes out a little below 1, so the mirror accepts a cosine within
//! [`MIRROR_COS_TOLERANCE`] of 1. Every shading path (scalar [`crate::shade()`], four-wide
//! [`crate::shade_x4()`], the f64 [`crate::shade_reference`] and the bound of
//! [`crate::specular_upper_bound`]) goes through these functions, so they agree on which points
//! see the mirror's highlight.

use phosphor_math::{clamped_pow_f64, clamped_pow_fast};

/// How far below 1 a cosine may be and still count as the exact mirror direction (`phi = 0`)
/// under `n_s = inf`. It covers the rounding of `V.R` itself: the shading code uses a normal
/// whose squared length is within [`crate::shade::UNIT_NORMAL_TOLERANCE`] (1e-6) of 1 without
/// renormalizing it, which moves `R`, and so `V.R`, by up to about 1e-6; each f32 dot product
/// and the reflection `R = 2(N.L)N - L` add a few units of f32 rounding (1.2e-7 each). A cosine
/// of `1 - 2e-6` is an angle of 0.002 radians (0.11 degrees).
pub const MIRROR_COS_TOLERANCE: f32 = 2e-6;

/// The perfect mirror's lobe: 1 where `cos_phi >= 1 - MIRROR_COS_TOLERANCE`, else 0 (NaN
/// gives 0).
#[inline]
#[must_use]
pub fn mirror_lobe(cos_phi: f32) -> f32 {
    if cos_phi >= 1.0 - MIRROR_COS_TOLERANCE {
        1.0
    } else {
        0.0
    }
}

/// Double-precision [`mirror_lobe`], with the f32 threshold itself (so that a cosine that is
/// an f32 gets the same answer in both, and the reference and the f32 modes light the same
/// points up to the rounding of the cosine).
#[inline]
#[must_use]
pub fn mirror_lobe_f64(cos_phi: f64) -> f64 {
    if cos_phi >= f64::from(1.0f32 - MIRROR_COS_TOLERANCE) {
        1.0
    } else {
        0.0
    }
}

/// `cos_phi^shininess` for the specular term: [`mirror_lobe`] for `shininess = +inf`,
/// [`clamped_pow_fast`] otherwise. Always in `[0, 1]`, never NaN.
#[inline]
#[must_use]
pub fn specular_lobe(cos_phi: f32, shininess: f32) -> f32 {
    if shininess == f32::INFINITY {
        mirror_lobe(cos_phi)
    } else {
        clamped_pow_fast(cos_phi, shininess)
    }
}

/// Double-precision [`specular_lobe`] (through [`clamped_pow_f64`] and [`mirror_lobe_f64`]).
#[inline]
#[must_use]
pub fn specular_lobe_f64(cos_phi: f64, shininess: f64) -> f64 {
    if shininess == f64::INFINITY {
        mirror_lobe_f64(cos_phi)
    } else {
        clamped_pow_f64(cos_phi, shininess)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// R.V exactly 1, 1e-6 below (inside the tolerance), 1e-5 below (outside), 0, negative,
    /// and the non-numbers: the mirror is 1 only on the first two.
    #[test]
    fn infinite_shininess_lights_only_the_mirror_direction() {
        let cases: [(f32, f32); 9] = [
            (1.0, 1.0),
            (0.999_999, 1.0),
            (1.0 - MIRROR_COS_TOLERANCE, 1.0),
            (0.999_99, 0.0),
            (0.5, 0.0),
            (0.0, 0.0),
            (-0.3, 0.0),
            (-1.0, 0.0),
            (f32::NAN, 0.0),
        ];
        for (cos_phi, want) in cases {
            assert_eq!(specular_lobe(cos_phi, f32::INFINITY), want, "cos {cos_phi}");
            assert_eq!(
                specular_lobe_f64(f64::from(cos_phi), f64::INFINITY),
                f64::from(want),
                "f64 cos {cos_phi}"
            );
        }
        // A cosine slightly above 1 (rounding of nearly parallel unit vectors) is the mirror.
        assert_eq!(specular_lobe(1.000_000_1, f32::INFINITY), 1.0);
        assert_eq!(specular_lobe(f32::INFINITY, f32::INFINITY), 1.0);
        assert_eq!(specular_lobe(f32::NEG_INFINITY, f32::INFINITY), 0.0);
    }

    #[test]
    fn finite_shininess_is_the_clamped_power() {
        for n in [0.0, 1.0, 32.0, 255.5, 1e4] {
            for c in [-0.5, 0.0, 0.3, 0.999_999, 1.0] {
                assert_eq!(specular_lobe(c, n), clamped_pow_fast(c, n), "{c}^{n}");
                assert_eq!(
                    specular_lobe_f64(f64::from(c), f64::from(n)),
                    clamped_pow_f64(f64::from(c), f64::from(n))
                );
            }
        }
        // 0.999999^1e6 = e^-1 (to 1e-6): a huge finite n_s is not yet the mirror.
        let lobe = specular_lobe_f64(0.999_999, 1e6);
        assert!((lobe - (-1.0f64).exp()).abs() < 1e-6, "{lobe}");
    }

    #[test]
    fn the_lobe_never_leaves_the_unit_interval_or_is_nan() {
        let cosines = [f32::NAN, -2.0, -0.0, 0.0, 0.25, 1.0, 3.0, f32::INFINITY];
        let exponents = [
            f32::NAN,
            -1.0,
            0.0,
            0.5,
            7.0,
            300.0,
            f32::MAX,
            f32::INFINITY,
        ];
        for c in cosines {
            for n in exponents {
                let l = specular_lobe(c, n);
                assert!((0.0..=1.0).contains(&l), "{c}^{n} = {l}");
                let l = specular_lobe_f64(f64::from(c), f64::from(n));
                assert!((0.0..=1.0).contains(&l), "f64 {c}^{n} = {l}");
            }
        }
    }
}
