//! Distance attenuation `f(d)` of positional lights.
//!
//! Which to pick: the lecture notes report that the physical inverse-square law `1/d^2` "produced
//! too much contrast" (a display cannot show the range between near and far surfaces) and that the
//! empirical `1/(K+d)` "produced a much more acceptable picture". Use [`Attenuation::Offset`] (S1
//! uses `K = 1`) unless you want physics ([`Attenuation::InverseSquare`]) or OpenGL's
//! constant-linear-quadratic form ([`Attenuation::Quadratic`]). Directional lights are never
//! attenuated.
//!
//! Numerics: every model is evaluated as `1 / max(c + l d + q d^2, MIN_ATTENUATION_DENOMINATOR)`
//! with `d` first limited to [`MAX_LIGHT_DISTANCE`], so `d = 0` (a light on the surface) gives
//! the finite factor `1 / MIN_ATTENUATION_DENOMINATOR` at most and `d^2` never overflows.

use crate::error::{LightingError, check_scalar};

/// The smallest denominator of `f(d)`: caps every factor at `1 / MIN_ATTENUATION_DENOMINATOR`
/// (1e4), so a light at the surface point (`d = 0`) under `1/d^2` is bright but finite.
pub const MIN_ATTENUATION_DENOMINATOR: f32 = 1e-4;

/// Distances are limited to this before `f(d)` so `d^2` stays finite (1e36 < f32::MAX).
pub const MAX_LIGHT_DISTANCE: f32 = 1e18;

/// Distance attenuation model `f(d)` of a point, spot or distributed light.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Attenuation {
    /// `f = 1`: no fall-off with distance.
    #[default]
    None,
    /// The physical law `f = 1/d^2` (too much contrast, say the lecture notes).
    InverseSquare,
    /// The lecture notes' empirical `f = 1/(K + d)`.
    Offset {
        /// The lecture notes' `K`, "determined experimentally after the scene is generated".
        k: f32,
    },
    /// OpenGL's `f = 1/(c + l d + q d^2)`.
    Quadratic {
        /// Constant coefficient.
        c: f32,
        /// Linear coefficient.
        l: f32,
        /// Quadratic coefficient.
        q: f32,
    },
}

impl Attenuation {
    /// The model as coefficients `[c, l, q]` of `1/(c + l d + q d^2)`: the branch-free form the
    /// per-pixel loops evaluate.
    #[inline]
    #[must_use]
    pub const fn coefficients(self) -> [f32; 3] {
        match self {
            Attenuation::None => [1.0, 0.0, 0.0],
            Attenuation::InverseSquare => [0.0, 0.0, 1.0],
            Attenuation::Offset { k } => [k, 1.0, 0.0],
            Attenuation::Quadratic { c, l, q } => [c, l, q],
        }
    }

    /// `f(d)` for a distance `d >= 0`; finite and in `(0, 1/MIN_ATTENUATION_DENOMINATOR]` for
    /// valid coefficients (NaN `d` counts as [`MAX_LIGHT_DISTANCE`]).
    #[inline]
    #[must_use]
    pub fn factor(self, d: f32) -> f32 {
        factor_from_coefficients(self.coefficients(), d)
    }

    /// The largest value `f(d)` takes over `d >= 0` (at `d = 0`, as the denominator grows with
    /// `d`): bounds of the model use it.
    #[inline]
    #[must_use]
    pub fn max_factor(self) -> f32 {
        self.factor(0.0)
    }

    /// True when this model is `f = 1` everywhere (no ATTENUATION effect needed).
    #[inline]
    #[must_use]
    pub fn is_none(self) -> bool {
        self.coefficients() == [1.0, 0.0, 0.0]
    }

    /// Checks the coefficients are finite and non-negative.
    ///
    /// # Errors
    /// [`LightingError`] naming `attenuation.k`, `.c`, `.l` or `.q`.
    pub fn validate(self) -> Result<(), LightingError> {
        match self {
            Attenuation::None | Attenuation::InverseSquare => Ok(()),
            Attenuation::Offset { k } => check_scalar("attenuation.k", k),
            Attenuation::Quadratic { c, l, q } => {
                check_scalar("attenuation.c", c)?;
                check_scalar("attenuation.l", l)?;
                check_scalar("attenuation.q", q)
            }
        }
    }
}

/// `1 / max(c + l d + q d^2, MIN_ATTENUATION_DENOMINATOR)` with `d` limited to
/// [`MAX_LIGHT_DISTANCE`] (the guard described in the module docs).
#[inline]
#[must_use]
#[allow(
    clippy::manual_clamp,
    reason = "min/max map a NaN distance to a bound, clamp() keeps it"
)]
pub fn factor_from_coefficients([c, l, q]: [f32; 3], d: f32) -> f32 {
    let d = d.min(MAX_LIGHT_DISTANCE).max(0.0);
    let denominator = c + l * d + q * (d * d);
    // `max` maps a NaN (only from invalid negative/NaN coefficients) to the guard as well.
    denominator.max(MIN_ATTENUATION_DENOMINATOR).recip()
}

/// Double-precision `f(d)` with the same guard (for `shade_reference`).
#[inline]
#[must_use]
#[allow(
    clippy::manual_clamp,
    reason = "min/max map a NaN distance to a bound, clamp() keeps it"
)]
pub fn factor_from_coefficients_f64([c, l, q]: [f32; 3], d: f64) -> f64 {
    let d = d.min(f64::from(MAX_LIGHT_DISTANCE)).max(0.0);
    let denominator = f64::from(c) + f64::from(l) * d + f64::from(q) * (d * d);
    1.0 / denominator.max(f64::from(MIN_ATTENUATION_DENOMINATOR))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_matches_the_notes_one_over_k_plus_d() {
        // The lecture notes' f = 1/(K+d): K = 1, d = 3 -> 0.25; K = 0.5, d = 1.5 -> 0.5.
        assert!((Attenuation::Offset { k: 1.0 }.factor(3.0) - 0.25).abs() < 1e-6);
        assert!((Attenuation::Offset { k: 0.5 }.factor(1.5) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn inverse_square_and_quadratic_match_their_formulas() {
        assert!((Attenuation::InverseSquare.factor(2.0) - 0.25).abs() < 1e-6);
        let q = Attenuation::Quadratic {
            c: 1.0,
            l: 0.5,
            q: 0.25,
        };
        assert!((q.factor(2.0) - 1.0 / 3.0).abs() < 1e-6);
        assert_eq!(Attenuation::None.factor(123.0), 1.0);
    }

    #[test]
    fn zero_distance_is_capped_not_infinite() {
        let cap = 1.0 / MIN_ATTENUATION_DENOMINATOR;
        assert_eq!(Attenuation::InverseSquare.factor(0.0), cap);
        assert_eq!(Attenuation::Offset { k: 0.0 }.factor(0.0), cap);
        let zero = Attenuation::Quadratic {
            c: 0.0,
            l: 0.0,
            q: 0.0,
        };
        assert_eq!(zero.factor(5.0), cap);
        assert!(Attenuation::InverseSquare.factor(f32::MAX).is_finite());
        assert!(Attenuation::InverseSquare.factor(f32::NAN).is_finite());
    }

    #[test]
    fn max_factor_bounds_every_distance() {
        let models = [
            Attenuation::None,
            Attenuation::InverseSquare,
            Attenuation::Offset { k: 0.3 },
            Attenuation::Quadratic {
                c: 0.2,
                l: 1.0,
                q: 3.0,
            },
        ];
        for m in models {
            for d in [0.0, 1e-6, 0.1, 1.0, 10.0, 1e20] {
                assert!(m.factor(d) <= m.max_factor());
            }
        }
    }

    #[test]
    fn negative_or_non_finite_coefficients_are_rejected_by_name() {
        let e = Attenuation::Offset { k: -1.0 }.validate().unwrap_err();
        assert!(e.to_string().starts_with("attenuation.k"));
        let e = Attenuation::Quadratic {
            c: 1.0,
            l: f32::NAN,
            q: 0.0,
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().starts_with("attenuation.l"));
    }
}
