//! Linear `[0, 1]` intensity to 8-bit codes through a 4096-entry table (sRGB or linear), and
//! the tone curves ([`ToneMap`]) that bring intensities above 1 into that range first.

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

    /// The codes of four values, each [`Encoder::encode`]'s: the clamp, scale and
    /// truncation that form a table index run in four lanes (the same IEEE operations in the
    /// same order, so the same index), and each lane's index looks the table up. For whole
    /// images, where the per-value clamp and saturating conversion cost more than the lookup.
    #[inline(always)]
    #[must_use]
    pub fn encode4(self, v: [f32; 4]) -> [u8; 4] {
        use phosphor_lighting::{Lanes, f32x4};
        // `max_c` is the select `x > 0 ? x : 0`: NaN becomes 0 before the index is formed, as
        // in `encode`. The index is in `[0.5, LUT_SIZE - 0.5]`, so truncation needs no
        // saturation.
        let v = f32x4::new(v).max_c(f32x4::ZERO).min_c(f32x4::ONE);
        let at = (v * f32x4::splat((LUT_SIZE - 1) as f32) + f32x4::splat(0.5)).fast_trunc_int();
        at.to_array().map(|i| self.lut[i as usize & (LUT_SIZE - 1)])
    }
}

/// How linear intensities, which may exceed 1 in a high-dynamic-range framebuffer
/// ([`crate::Framebuffer::set_hdr`]), are brought into `[0, 1]` before the 8-bit encoding.
/// Each maps every `f32` (NaN and infinities included) into `[0, 1]`, is non-decreasing on
/// `[0, inf)` and maps 0 to 0; names as used by the CLI.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ToneMap {
    /// `min(x, 1)`: what the encoding tables do, the 8-bit output of every earlier version.
    #[default]
    Clamp,
    /// Reinhard et al. 2002's global operator `x / (1 + x)` per channel: every intensity
    /// keeps a distinct code below 1, and 1 maps to 0.5.
    Reinhard,
    /// Narkowicz 2015's fit of the ACES filmic curve, per channel:
    /// `x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`, clamped to `[0, 1]` (it reaches 1
    /// near `x = 7.24`).
    Aces,
}

impl ToneMap {
    /// Every choice, in the CLI's order.
    pub const ALL: [ToneMap; 3] = [ToneMap::Clamp, ToneMap::Reinhard, ToneMap::Aces];

    /// The name: `clamp`, `reinhard`, `aces`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ToneMap::Clamp => "clamp",
            ToneMap::Reinhard => "reinhard",
            ToneMap::Aces => "aces",
        }
    }

    /// The curve at `x`, in `[0, 1]`; NaN and values below 0 give 0, `+inf` gives 1.
    #[must_use]
    #[allow(
        clippy::manual_clamp,
        reason = "max/min map NaN to a bound, clamp() keeps it"
    )]
    pub fn apply(self, x: f32) -> f32 {
        let x = if x > 0.0 { x } else { 0.0 };
        let y = match self {
            ToneMap::Clamp => x,
            ToneMap::Reinhard if x.is_infinite() => 1.0,
            ToneMap::Reinhard => x / (1.0 + x),
            ToneMap::Aces if x > 1e6 => 1.0,
            ToneMap::Aces => (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14),
        };
        y.max(0.0).min(1.0)
    }
}

impl std::fmt::Display for ToneMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ToneMap {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ToneMap::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| format!("unknown tone map '{s}' (expected clamp, reinhard or aces)"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tone_maps_send_zero_to_zero_rise_and_stay_in_the_unit_range() {
        for t in ToneMap::ALL {
            assert_eq!(t.apply(0.0), 0.0, "{t}");
            assert_eq!(t.name().parse::<ToneMap>(), Ok(t));
            for bad in [f32::NAN, -1.0, f32::NEG_INFINITY] {
                assert_eq!(t.apply(bad), 0.0, "{t} at {bad}");
            }
            assert_eq!(t.apply(f32::INFINITY), 1.0, "{t}");
            let mut last = 0.0;
            for i in 1..=20_000 {
                let x = i as f32 * 1e-3;
                let y = t.apply(x);
                assert!((0.0..=1.0).contains(&y), "{t} at {x}: {y}");
                assert!(y >= last, "{t} falls at {x}: {y} < {last}");
                last = y;
            }
        }
        // The curves themselves, where they differ from the clamp.
        assert_eq!(ToneMap::Clamp.apply(2.0), 1.0);
        assert_eq!(ToneMap::Reinhard.apply(1.0), 0.5);
        assert!((ToneMap::Reinhard.apply(3.0) - 0.75).abs() < 1e-6);
        let aces_1 = 2.54 / 3.16;
        assert!((ToneMap::Aces.apply(1.0) - aces_1).abs() < 1e-6);
        assert_eq!(ToneMap::Aces.apply(7.5), 1.0);
        assert!(ToneMap::Aces.apply(7.0) < 1.0);
        // Reinhard keeps highlights apart that the clamp merges.
        assert!(ToneMap::Reinhard.apply(2.0) < ToneMap::Reinhard.apply(4.0));
        assert!("filmic".parse::<ToneMap>().is_err());
    }

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
