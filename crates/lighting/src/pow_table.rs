//! [`PowTable`]: `x^n` for `x` in `[0, 1]` through a lookup table, as Bishop and Weimer (1986)
//! evaluate the specular power in fast Phong shading.
//!
//! The table covers `[x0, 1]` only, where `x0^n = POW_TABLE_CUTOFF`: below `x0` the power is
//! smaller than the cutoff and the lookup returns 0. Between entries it interpolates linearly,
//! so the error is at most `h^2/8 max|f''|` with `h = (1 - x0)/(size - 1)` (plus the cutoff and
//! rounding), see [`PowTable::max_error`]. As `n (1 - x0)` is about `ln(1/cutoff) = 9.2` for
//! every large `n`, the error is almost independent of the shininess: about `12/(size-1)^2`
//! for `n >= 2` (1.2e-5 at 1024 entries, well under the cutoff 1e-4 and half a level of 8-bit
//! output, 2e-3).

/// Powers below this are returned as 0 (the table starts where `x^n` reaches it).
pub const POW_TABLE_CUTOFF: f32 = 1e-4;

/// The most entries a table may have (larger requests are capped).
pub const MAX_POW_TABLE_SIZE: usize = 1 << 20;

/// Allowance for f32 rounding in the table and the interpolation, added to the error bound.
const ROUNDING_ALLOWANCE: f32 = 1e-6;

/// `x^n` on `[0, 1]` by table lookup with linear interpolation.
#[derive(Debug, Clone, PartialEq)]
pub struct PowTable {
    exponent: f32,
    x0: f32,
    scale: f32,
    values: Vec<f32>,
    max_error: f32,
}

impl PowTable {
    /// A table of `x^n` with `size` entries (`2..=MAX_POW_TABLE_SIZE`, clamped). A negative or
    /// NaN `n` counts as 0 (`x^0 = 1`), like [`phosphor_math::clamped_pow`]; an infinite one as `f32::MAX`.
    #[must_use]
    pub fn new(n: f32, size: usize) -> PowTable {
        let exponent = if n.is_nan() {
            0.0
        } else {
            n.clamp(0.0, f32::MAX)
        };
        let size = size.clamp(2, MAX_POW_TABLE_SIZE);
        let x0 = if exponent == 0.0 {
            0.0
        } else {
            POW_TABLE_CUTOFF.powf(exponent.recip()).min(1.0)
        };
        // The grid is x0 + i h, evaluated in f64: near 1 a steep power (n = 1e4) changes by
        // 1e-3 between neighbouring f32 values, so grid points rounded to f32 would not be
        // where the interpolation assumes them.
        let width = 1.0 - f64::from(x0);
        let segments = (size - 1) as f64;
        let h = width / segments;
        let n64 = f64::from(exponent);
        let values = (0..size)
            .map(|i| {
                let x = if i == size - 1 {
                    1.0
                } else {
                    f64::from(x0) + h * i as f64
                };
                phosphor_math::clamped_pow_f64(x, n64) as f32
            })
            .collect();
        let scale = if width > 0.0 {
            (segments / width) as f32
        } else {
            0.0
        };
        // max |f''| on [x0, 1]: n |n - 1| x^(n-2), largest at x = 1 for n >= 2, at x0 below.
        let curvature = if exponent >= 2.0 {
            n64 * (n64 - 1.0)
        } else if x0 > 0.0 {
            n64 * (n64 - 1.0).abs() * f64::from(x0).powf(n64 - 2.0)
        } else {
            0.0
        };
        let interpolation = h.powi(2) / 8.0 * curvature;
        let max_error =
            (interpolation.max(f64::from(POW_TABLE_CUTOFF)) as f32 + ROUNDING_ALLOWANCE).min(1.0);
        PowTable {
            exponent,
            x0,
            scale,
            values,
            max_error,
        }
    }

    /// `x^n` for `x` clamped to `[0, 1]` (NaN counts as 0), within [`PowTable::max_error`] of
    /// `clamped_pow(x, n)`. Always in `[0, 1]`.
    #[inline]
    #[must_use]
    #[allow(
        clippy::manual_clamp,
        reason = "max/min map NaN to 0, clamp() keeps it"
    )]
    pub fn lookup(&self, x: f32) -> f32 {
        let x = x.max(0.0).min(1.0);
        if x < self.x0 {
            return 0.0;
        }
        let last = self.values.len() - 2;
        let t = (x - self.x0) * self.scale;
        let i = (t as usize).min(last);
        let frac = (t - i as f32).min(1.0);
        let (a, b) = (self.values[i], self.values[i + 1]);
        a + (b - a) * frac
    }

    /// The bound on `|lookup(x) - x^n|` over `[0, 1]`: interpolation `h^2/8 max|f''|` or the
    /// cutoff, whichever is larger, plus a rounding allowance; at most 1.
    #[inline]
    #[must_use]
    pub fn max_error(&self) -> f32 {
        self.max_error
    }

    /// The exponent `n` the table was built for.
    #[inline]
    #[must_use]
    pub fn exponent(&self) -> f32 {
        self.exponent
    }

    /// Number of entries.
    #[inline]
    #[must_use]
    pub fn size(&self) -> usize {
        self.values.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn measured_error(table: &PowTable) -> f32 {
        let samples = 200_000;
        (0..=samples)
            .map(|i| {
                let x = i as f32 / samples as f32;
                let exact = f64::from(x).powf(f64::from(table.exponent()));
                (f64::from(table.lookup(x)) - exact).abs() as f32
            })
            .fold(0.0, f32::max)
    }

    #[test]
    fn lookup_stays_within_the_documented_error_of_powf() {
        for n in [1.0, 1.5, 2.0, 5.0, 32.0, 100.0, 10_000.0] {
            let table = PowTable::new(n, 1024);
            let err = measured_error(&table);
            assert!(
                err <= table.max_error(),
                "n {n}: {err} > {}",
                table.max_error()
            );
            if n >= 2.0 {
                assert!(
                    table.max_error() < 2e-4,
                    "n {n}: bound {}",
                    table.max_error()
                );
            }
        }
    }

    #[test]
    fn edge_exponents_and_inputs_stay_in_unit_range() {
        let zero = PowTable::new(0.0, 16);
        assert_eq!(zero.lookup(0.0), 1.0);
        assert_eq!(zero.lookup(0.5), 1.0);
        let huge = PowTable::new(f32::MAX, 16);
        assert_eq!(huge.lookup(1.0), 1.0);
        assert_eq!(huge.lookup(0.999), 0.0);
        let t = PowTable::new(32.0, 0);
        assert_eq!(t.size(), 2);
        for x in [f32::NAN, -1.0, 2.0, f32::INFINITY, 0.5] {
            let y = t.lookup(x);
            assert!((0.0..=1.0).contains(&y));
        }
        assert_eq!(PowTable::new(f32::NAN, 8).exponent(), 0.0);
    }
}
