//! Fixed-point sub-pixel coordinates for exact rasterization.
//!
//! Screen coordinates are snapped to 1/256 of a pixel (8 sub-pixel bits, as Mesa's llvmpipe
//! does), so edge tests are exact integer arithmetic and a pixel centre lying on an edge shared by
//! two triangles is decided identically for both.

/// Sub-pixel bits of the fixed-point screen coordinates.
pub const SUBPIXEL_BITS: u32 = 8;

/// One pixel in fixed point.
pub const SUBPIXEL_ONE: i64 = 1 << SUBPIXEL_BITS;

/// Largest magnitude (in pixels) accepted by [`to_fixed`]: an edge function multiplies two
/// coordinate differences (each below 2^(20+8+1) in fixed point), and sums two such products,
/// so 2^20 pixels keeps it below 2^59, well inside `i64`.
pub const MAX_FIXED_COORD: f32 = (1u32 << 20) as f32;

/// Converts a screen coordinate in pixels to fixed point, rounding to nearest.
///
/// Contract: returns `None` for NaN, infinite, or magnitudes above [`MAX_FIXED_COORD`] pixels
/// (callers clip such triangles to a guard band first); otherwise the nearest multiple of
/// 1/[`SUBPIXEL_ONE`] pixel.
#[inline]
#[must_use]
pub fn to_fixed(x: f32) -> Option<i64> {
    if !x.is_finite() || x.abs() > MAX_FIXED_COORD {
        return None;
    }
    Some(round_half_away(f64::from(x) * SUBPIXEL_ONE as f64))
}

/// `v.round() as i64` for `|v| < 2^52`, from a truncating conversion and the exact remainder
/// `v - trunc(v)`: `f64::round` is a library call on x86-64's baseline (it has no rounding
/// instruction before SSE4.1), and every projected vertex rounds two coordinates.
#[inline]
fn round_half_away(v: f64) -> i64 {
    let t = v as i64;
    let rest = v - t as f64;
    if rest >= 0.5 {
        t + 1
    } else if rest <= -0.5 {
        t - 1
    } else {
        t
    }
}

/// Converts a fixed-point coordinate back to pixels.
#[inline]
#[must_use]
pub fn from_fixed(x: i64) -> f32 {
    (x as f64 / SUBPIXEL_ONE as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn to_fixed_rounds_to_nearest_subpixel() {
        assert_eq!(to_fixed(0.0), Some(0));
        assert_eq!(to_fixed(1.0), Some(256));
        assert_eq!(to_fixed(0.5), Some(128));
        assert_eq!(to_fixed(-0.5), Some(-128));
        assert_eq!(to_fixed(1.0 / 512.0 + 1e-6), Some(1));
        assert_eq!(from_fixed(384), 1.5);
    }

    #[test]
    fn rounding_matches_f64_round_at_ties_and_between() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            0.49999999999999994,
        ];
        for k in -2000..2000 {
            let v = f64::from(k) / 8.0;
            values.extend([v, v + 1e-9, v - 1e-9, v.next_up(), v.next_down()]);
        }
        let big = f64::from(MAX_FIXED_COORD) * SUBPIXEL_ONE as f64;
        values.extend([big, -big, big - 0.5, 1e15 + 0.5, -(1e15 + 0.5)]);
        for v in values {
            assert_eq!(round_half_away(v), v.round() as i64, "{v}");
        }
    }

    #[test]
    fn to_fixed_rejects_non_finite_and_out_of_range() {
        assert_eq!(to_fixed(f32::NAN), None);
        assert_eq!(to_fixed(f32::INFINITY), None);
        assert_eq!(to_fixed(1e30), None);
        assert_eq!(to_fixed(-MAX_FIXED_COORD * 2.0), None);
        assert!(to_fixed(MAX_FIXED_COORD).is_some());
    }

    #[test]
    fn products_of_extreme_coordinates_fit_i64() {
        let m = to_fixed(MAX_FIXED_COORD).expect("in range");
        // An edge function multiplies two coordinate differences (each up to 2*m).
        let prod = (2 * m).checked_mul(2 * m).expect("fits");
        assert!(prod.checked_add(prod).is_some());
    }
}
