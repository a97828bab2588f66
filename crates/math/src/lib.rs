//! `phosphor-math`: glam re-exported, plus the few numeric helpers every Phosphor crate needs and
//! nobody should write twice. Each helper states its numeric contract in its docs; the guards that
//! keep NaN and Inf out of the framebuffer live here, not as scattered epsilons.
//!
//! Conventions: column vectors, right-handed, OpenGL-style clip space (glam's `camera::rh`);
//! angles in radians unless a name says `_deg`.
//!
//! ```
//! use phosphor_math::{clamped_pow, reflect, safe_normalize, glam::Vec3};
//!
//! // Safe normalization returns the fallback instead of NaN for a zero vector.
//! assert_eq!(safe_normalize(Vec3::ZERO, Vec3::Y), Vec3::Y);
//! // The lecture notes' reflection vector R = 2(N.L)N - L.
//! let r = reflect(Vec3::Y, Vec3::new(1.0, 1.0, 0.0).normalize());
//! assert!((r - Vec3::new(-1.0, 1.0, 0.0).normalize()).length() < 1e-6);
//! // Powers of a clamped cosine never leave [0, 1].
//! assert_eq!(clamped_pow(-0.5, 32.0), 0.0);
//! ```

pub mod fixed;

pub use glam;
use glam::{DVec3, Vec2, Vec3};

pub use fixed::{SUBPIXEL_BITS, SUBPIXEL_ONE, to_fixed};

/// Squared lengths below this are treated as zero by [`safe_normalize`]: the reciprocal square
/// root of anything smaller risks overflow to infinity (1/sqrt(1e-38) = 1e19 is fine, but the
/// squared length of a subnormal vector underflows to 0 or a subnormal).
pub const MIN_NORMALIZABLE_LENGTH_SQUARED: f32 = 1e-30;

/// Normalizes `v`, or returns `fallback` where that cannot be done exactly.
///
/// Contract: returns `fallback` (unchanged) when `v` is zero, subnormal, so small that its
/// squared length is below [`MIN_NORMALIZABLE_LENGTH_SQUARED`], contains a NaN or an infinity.
/// Vectors whose squared length overflows `f32` (components near 1e20 and above) are rescaled
/// first, so `1e30 * x` normalizes to `x`. Otherwise the result has unit length within 1e-6.
#[inline]
#[must_use]
pub fn safe_normalize(v: Vec3, fallback: Vec3) -> Vec3 {
    if !v.is_finite() {
        return fallback;
    }
    let len_sq = v.length_squared();
    if len_sq.is_finite() {
        if len_sq < MIN_NORMALIZABLE_LENGTH_SQUARED {
            return fallback;
        }
        return v * len_sq.sqrt().recip();
    }
    // The squared length overflowed: scale by the largest component first (exact, as it is a
    // finite non-zero number here).
    let scaled = v / v.abs().max_element();
    scaled * scaled.length().recip()
}

/// Like [`safe_normalize`] in double precision (used by the `reference` shading mode).
///
/// Contract: returns `fallback` for zero, non-finite or tiny (squared length below 1e-300)
/// input; rescales vectors whose squared length overflows.
#[inline]
#[must_use]
pub fn safe_normalize_f64(v: DVec3, fallback: DVec3) -> DVec3 {
    if !v.is_finite() {
        return fallback;
    }
    let len_sq = v.length_squared();
    if len_sq.is_finite() {
        if len_sq < 1e-300 {
            return fallback;
        }
        return v / len_sq.sqrt();
    }
    let scaled = v / v.abs().max_element();
    scaled / scaled.length()
}

/// The ideal specular reflection of the unit direction `l` (towards the light) about the unit
/// normal `n`: the lecture notes' `R = (2 N.L) N - L`.
///
/// Contract: for unit `n` and `l` the result is a unit vector (within rounding); no
/// normalization is done here, so callers pass unit vectors. Finite input gives finite output.
#[inline]
#[must_use]
pub fn reflect(n: Vec3, l: Vec3) -> Vec3 {
    2.0 * n.dot(l) * n - l
}

/// Double-precision [`reflect`].
#[inline]
#[must_use]
pub fn reflect_f64(n: DVec3, l: DVec3) -> DVec3 {
    2.0 * n.dot(l) * n - l
}

/// `base^exponent` for a cosine-like base: the base is clamped to `[0, 1]` first, as the lecture
/// notes do for `(V.R)^n` ("cos phi varies from 0 to 1").
///
/// Contract: the result is always in `[0, 1]` and finite. A NaN base counts as 0. A negative
/// or NaN exponent counts as 0, and `x^0 = 1` for every base including 0 (`n_s = 0`
/// means "no falloff"). An infinite exponent gives 1 for base 1 and 0 otherwise (the lecture
/// notes' perfect reflector, `n_s` infinite; the lighting crate adds a rounding tolerance).
#[inline]
#[must_use]
#[allow(
    clippy::manual_clamp,
    reason = "clamp() propagates NaN; max/min map it to 0"
)]
pub fn clamped_pow(base: f32, exponent: f32) -> f32 {
    // `f32::clamp` propagates NaN; `max`/`min` replace it, which is what we want here.
    let b = base.max(0.0).min(1.0);
    let e = exponent.max(0.0);
    if e == 0.0 {
        return 1.0;
    }
    if b == 0.0 {
        return 0.0;
    }
    // powf of a value in (0, 1] with a positive exponent is in [0, 1]; it cannot overflow.
    b.powf(e)
}

/// Integer exponents up to this take [`clamped_pow_fast`]'s repeated-squaring path.
pub const MAX_SQUARING_EXPONENT: f32 = 256.0;

/// [`clamped_pow`] with the same contract, faster for the common integer shininess: an
/// integer exponent up to [`MAX_SQUARING_EXPONENT`] is evaluated by repeated squaring (at most
/// 8 squarings and 8 products, relative error below `n` f32 ulps, under 2e-5 for `n = 256`),
/// any other exponent by `powf`. The per-pixel specular term uses it: `powf` was a tenth of
/// Phong shading's instructions.
#[inline]
#[must_use]
#[allow(
    clippy::manual_clamp,
    reason = "clamp() propagates NaN; max/min map it to 0"
)]
pub fn clamped_pow_fast(base: f32, exponent: f32) -> f32 {
    let e = exponent.max(0.0);
    if e > MAX_SQUARING_EXPONENT || e.fract() != 0.0 {
        return clamped_pow(base, exponent);
    }
    let mut b = base.max(0.0).min(1.0);
    let mut n = e as u32;
    let mut acc = 1.0;
    while n > 0 {
        if n & 1 == 1 {
            acc *= b;
        }
        n >>= 1;
        if n > 0 {
            b *= b;
        }
    }
    acc
}

/// Double-precision [`clamped_pow`], same contract.
#[inline]
#[must_use]
#[allow(
    clippy::manual_clamp,
    reason = "clamp() propagates NaN; max/min map it to 0"
)]
pub fn clamped_pow_f64(base: f64, exponent: f64) -> f64 {
    let b = base.max(0.0).min(1.0);
    let e = exponent.max(0.0);
    if e == 0.0 {
        return 1.0;
    }
    if b == 0.0 {
        return 0.0;
    }
    b.powf(e)
}

/// Twice the signed area of the 2D triangle `(a, b, c)`: positive when counter-clockwise in a
/// y-up frame. The edge function of Pineda-style rasterizers.
#[inline]
#[must_use]
pub fn orient2d(a: Vec2, b: Vec2, c: Vec2) -> f32 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

/// Barycentric coordinates `(w0, w1, w2)` of `p` in the 2D triangle `(a, b, c)`, so that
/// `p = w0 a + w1 b + w2 c` and `w0 + w1 + w2 = 1`.
///
/// Contract: returns `None` for a degenerate triangle (zero, subnormal or non-finite area) and
/// never divides by it; otherwise the three weights are finite.
#[inline]
#[must_use]
pub fn barycentric(p: Vec2, a: Vec2, b: Vec2, c: Vec2) -> Option<Vec3> {
    let area = orient2d(a, b, c);
    if !area.is_normal() {
        return None;
    }
    let w0 = orient2d(b, c, p) / area;
    let w1 = orient2d(c, a, p) / area;
    let w = Vec3::new(w0, w1, 1.0 - w0 - w1);
    w.is_finite().then_some(w)
}

/// True when every component is finite (not NaN, not infinite).
#[inline]
#[must_use]
pub fn all_finite(values: &[f32]) -> bool {
    values.iter().all(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPS: f32 = 1e-6;

    fn approx(a: Vec3, b: Vec3, tol: f32) -> bool {
        (a - b).abs().max_element() <= tol
    }

    #[test]
    fn safe_normalize_returns_fallback_for_zero_subnormal_nan_and_inf() {
        let fb = Vec3::new(0.0, 0.0, 1.0);
        let sub = f32::MIN_POSITIVE / 4.0;
        assert!(sub > 0.0 && !sub.is_normal());
        for v in [
            Vec3::ZERO,
            Vec3::splat(-0.0),
            Vec3::new(sub, 0.0, 0.0),
            Vec3::new(sub, sub, sub),
            Vec3::new(1e-20, 0.0, 0.0),
            Vec3::new(f32::NAN, 1.0, 0.0),
            Vec3::new(f32::INFINITY, 0.0, 0.0),
            Vec3::new(f32::NEG_INFINITY, 1.0, 1.0),
        ] {
            assert_eq!(safe_normalize(v, fb), fb, "input {v:?}");
        }
    }

    #[test]
    fn safe_normalize_handles_huge_vectors_without_overflow() {
        let v = Vec3::new(1e30, 1e30, 0.0);
        let n = safe_normalize(v, Vec3::Z);
        assert!(
            approx(n, Vec3::new(1.0, 1.0, 0.0).normalize(), EPS),
            "{n:?}"
        );
        let m = safe_normalize(Vec3::splat(f32::MAX), Vec3::Z);
        assert!(approx(m, Vec3::splat(1.0 / 3f32.sqrt()), EPS), "{m:?}");
    }

    #[test]
    fn safe_normalize_gives_unit_length_for_ordinary_vectors() {
        for v in [
            Vec3::X * 3.0,
            Vec3::new(1e-10, 2e-10, 0.0),
            Vec3::new(-4.0, 3.0, 12.0),
        ] {
            let n = safe_normalize(v, Vec3::Z);
            assert!((n.length() - 1.0).abs() < EPS, "{v:?} -> {n:?}");
            assert!(n.dot(v) > 0.0);
        }
    }

    #[test]
    fn safe_normalize_f64_matches_f32_contract() {
        assert_eq!(safe_normalize_f64(DVec3::ZERO, DVec3::Y), DVec3::Y);
        assert_eq!(
            safe_normalize_f64(DVec3::new(f64::NAN, 0.0, 0.0), DVec3::Y),
            DVec3::Y
        );
        let n = safe_normalize_f64(DVec3::new(1e200, 1e200, 0.0), DVec3::Y);
        assert!((n.length() - 1.0).abs() < 1e-12);
        let m = safe_normalize_f64(DVec3::new(0.0, 3.0, 4.0), DVec3::Y);
        assert!((m - DVec3::new(0.0, 0.6, 0.8)).length() < 1e-15);
    }

    #[test]
    fn reflect_mirrors_about_the_normal() {
        let n = Vec3::Y;
        let l = Vec3::new(1.0, 1.0, 0.0).normalize();
        assert!(approx(
            reflect(n, l),
            Vec3::new(-1.0, 1.0, 0.0).normalize(),
            EPS
        ));
        // Light straight along the normal reflects onto itself.
        assert!(approx(reflect(n, n), n, EPS));
        // Exactly opposite vectors: L = -N reflects to -N (R = -2N + N); finite.
        assert!(approx(reflect(n, -n), -n, EPS));
        // Grazing light (N.L = 0) reflects to -L.
        assert!(approx(reflect(n, Vec3::X), -Vec3::X, EPS));
        assert!((reflect_f64(DVec3::Y, DVec3::X) + DVec3::X).length() < 1e-15);
    }

    #[test]
    fn fast_pow_matches_powf_on_integer_and_fractional_exponents() {
        for n in [
            0.0f32,
            1.0,
            2.0,
            5.0,
            32.0,
            100.0,
            256.0,
            257.0,
            32.5,
            -3.0,
            f32::NAN,
        ] {
            for i in 0..=200 {
                let x = i as f32 / 200.0;
                let (fast, exact) = (clamped_pow_fast(x, n), clamped_pow(x, n));
                assert!((0.0..=1.0).contains(&fast), "{x}^{n} = {fast}");
                assert!(
                    (fast - exact).abs() <= 2e-5 * exact.max(1e-30) + 1e-37,
                    "{x}^{n}: {fast} vs {exact}"
                );
            }
        }
        assert_eq!(clamped_pow_fast(f32::NAN, 32.0), 0.0);
        assert_eq!(clamped_pow_fast(0.0, 0.0), 1.0);
        assert_eq!(clamped_pow_fast(2.0, 8.0), 1.0);
    }

    #[test]
    fn clamped_pow_stays_in_unit_interval_at_the_edges() {
        assert_eq!(clamped_pow(0.5, 0.0), 1.0);
        assert_eq!(clamped_pow(0.0, 0.0), 1.0);
        assert_eq!(clamped_pow(0.0, 1.0), 0.0);
        assert_eq!(clamped_pow(-1.0, 3.0), 0.0);
        assert_eq!(clamped_pow(f32::NAN, 3.0), 0.0);
        assert_eq!(clamped_pow(2.0, 3.0), 1.0);
        assert_eq!(clamped_pow(1.0, f32::MAX), 1.0);
        assert_eq!(clamped_pow(0.999, f32::INFINITY), 0.0);
        assert_eq!(clamped_pow(1.0, f32::INFINITY), 1.0);
        assert_eq!(clamped_pow(0.5, f32::NAN), 1.0);
        assert!((clamped_pow(0.5, 2.0) - 0.25).abs() < EPS);
        assert!(clamped_pow(0.99, 10000.0) >= 0.0);
        let sub = f32::MIN_POSITIVE / 8.0;
        assert!(clamped_pow(sub, 2.0).is_finite());
        assert_eq!(clamped_pow_f64(-0.1, 2.0), 0.0);
        assert_eq!(clamped_pow_f64(0.3, 0.0), 1.0);
        assert!((clamped_pow_f64(0.5, 3.0) - 0.125).abs() < 1e-15);
    }

    #[test]
    fn barycentric_reconstructs_the_point_and_rejects_degenerate_triangles() {
        let (a, b, c) = (
            Vec2::new(0.0, 0.0),
            Vec2::new(4.0, 0.0),
            Vec2::new(0.0, 4.0),
        );
        let p = Vec2::new(1.0, 2.0);
        let w = barycentric(p, a, b, c).expect("non-degenerate");
        let q = w.x * a + w.y * b + w.z * c;
        assert!((q - p).length() < EPS);
        assert!((w.element_sum() - 1.0).abs() < EPS);
        // Collinear, repeated vertex, tiny-area and non-finite triangles give None.
        assert!(barycentric(p, a, b, Vec2::new(8.0, 0.0)).is_none());
        assert!(barycentric(p, a, a, c).is_none());
        let t = 1e-23;
        assert!(barycentric(p, a, Vec2::new(t, 0.0), Vec2::new(0.0, t)).is_none());
        assert!(barycentric(p, a, b, Vec2::new(f32::NAN, 1.0)).is_none());
        assert!(barycentric(p, a, Vec2::new(1e30, 0.0), Vec2::new(0.0, 1e30)).is_none());
    }

    #[test]
    fn orient2d_sign_follows_winding() {
        let (a, b, c) = (Vec2::ZERO, Vec2::X, Vec2::Y);
        assert!(orient2d(a, b, c) > 0.0);
        assert!(orient2d(a, c, b) < 0.0);
        assert_eq!(orient2d(a, b, b * 2.0), 0.0);
    }

    #[test]
    fn all_finite_detects_nan_and_inf() {
        assert!(all_finite(&[0.0, -1.0, 1e30]));
        assert!(!all_finite(&[0.0, f32::NAN]));
        assert!(!all_finite(&[f32::INFINITY]));
    }

    mod props {
        use super::super::*;
        use proptest::prelude::*;

        fn any_f32() -> impl Strategy<Value = f32> {
            prop_oneof![
                proptest::num::f32::ANY,
                -1e6f32..1e6f32,
                Just(0.0f32),
                Just(f32::MIN_POSITIVE / 2.0)
            ]
        }

        proptest! {
            #[test]
            fn safe_normalize_is_unit_or_fallback(x in any_f32(), y in any_f32(), z in any_f32()) {
                let n = safe_normalize(Vec3::new(x, y, z), Vec3::Z);
                prop_assert!(n.is_finite());
                prop_assert!(n == Vec3::Z || (n.length() - 1.0).abs() < 1e-5);
            }

            #[test]
            fn clamped_pow_is_in_unit_interval(b in any_f32(), e in any_f32()) {
                let p = clamped_pow(b, e);
                prop_assert!((0.0..=1.0).contains(&p));
            }
        }
    }
}
