//! Linear `[0, 1]` intensity to 8-bit codes through a 4096-entry table (sRGB or linear).

use std::sync::OnceLock;

/// Entries in the encoding tables: 12 bits of input resolution, finer than the 8-bit output
/// so every code is reachable and the table error stays below half a code.
pub const LUT_SIZE: usize = 4096;

/// How the linear framebuffer intensity becomes an 8-bit code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Encoding {
    /// The sRGB transfer curve (IEC 61966-2-1), for display.
    #[default]
    Srgb,
    /// The linear value times 255, rounded (the intensity as is, the classic display range; S1 uses it).
    Linear,
}

/// The sRGB encoding of a linear value in `[0, 1]`.
#[must_use]
pub fn srgb_encode(linear: f32) -> f32 {
    let v = linear.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

fn build(encode: fn(f32) -> f32) -> Box<[u8; LUT_SIZE]> {
    let mut lut = Box::new([0u8; LUT_SIZE]);
    for (i, slot) in lut.iter_mut().enumerate() {
        let v = encode(i as f32 / (LUT_SIZE - 1) as f32);
        *slot = (v * 255.0 + 0.5).clamp(0.0, 255.0) as u8;
    }
    lut
}

fn table(encoding: Encoding) -> &'static [u8; LUT_SIZE] {
    static SRGB: OnceLock<Box<[u8; LUT_SIZE]>> = OnceLock::new();
    static LINEAR: OnceLock<Box<[u8; LUT_SIZE]>> = OnceLock::new();
    match encoding {
        Encoding::Srgb => SRGB.get_or_init(|| build(srgb_encode)),
        Encoding::Linear => LINEAR.get_or_init(|| build(|v| v)),
    }
}

/// The 8-bit code of a linear value (NaN counts as 0, values are clamped to `[0, 1]`).
#[inline]
#[must_use]
pub fn encode(value: f32, encoding: Encoding) -> u8 {
    Encoder::new(encoding).encode(value)
}

/// [`encode`] with its table looked up once (for whole images).
#[derive(Debug, Clone, Copy)]
pub struct Encoder {
    lut: &'static [u8; LUT_SIZE],
}

impl Encoder {
    /// The encoder for `encoding`.
    #[must_use]
    pub fn new(encoding: Encoding) -> Encoder {
        Encoder {
            lut: table(encoding),
        }
    }

    /// Same as [`encode`].
    #[inline]
    #[must_use]
    pub fn encode(self, value: f32) -> u8 {
        // NaN maps to 0 before the index is formed (clamp would keep it).
        let v = if value.is_nan() {
            0.0
        } else {
            value.clamp(0.0, 1.0)
        };
        self.lut[(v * (LUT_SIZE - 1) as f32 + 0.5) as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_encoding_matches_the_curve_within_one_code() {
        for i in 0..=1000 {
            let v = i as f32 / 1000.0;
            let exact = srgb_encode(v) * 255.0;
            assert!(
                (encode(v, Encoding::Srgb) as f32 - exact).abs() <= 1.0,
                "{v}"
            );
            assert!((encode(v, Encoding::Linear) as f32 - v * 255.0).abs() <= 1.0);
        }
        assert_eq!(encode(f32::NAN, Encoding::Srgb), 0);
        assert_eq!(encode(2.0, Encoding::Linear), 255);
        assert_eq!(encode(1.0, Encoding::Srgb), 255);
    }
}
