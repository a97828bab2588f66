//! The vector width of per-pixel lighting, chosen at run time.
//!
//! `phong` shades the pixels of a band four at a time on every CPU (SSE2, the x86-64
//! baseline) and eight at a time where the CPU has AVX2, detected once per process. Both run
//! the same operations in the same order per lane (`phosphor_lighting::shade_lanes`), so the
//! picture has the same bits at every level; [`SimdLevel`] exists to compare their speed and
//! to test that claim, not to trade accuracy.

use std::fmt;
use std::str::FromStr;

/// Which vector width the per-pixel lighting uses. Every level gives the same picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SimdLevel {
    /// The widest level this CPU runs (the default).
    #[default]
    Auto,
    /// Four lanes: SSE2 on x86-64, what every CPU of the target runs.
    Baseline,
    /// Eight lanes with AVX2 (x86-64 only; a CPU without it runs the baseline).
    Avx2,
}

impl SimdLevel {
    /// The levels, as the CLI names them.
    pub const ALL: [SimdLevel; 3] = [SimdLevel::Auto, SimdLevel::Baseline, SimdLevel::Avx2];

    /// The CLI name.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            SimdLevel::Auto => "auto",
            SimdLevel::Baseline => "baseline",
            SimdLevel::Avx2 => "avx2",
        }
    }

    /// Whether this CPU runs the level (`Auto` and `Baseline` always).
    #[must_use]
    pub fn available(self) -> bool {
        match self {
            SimdLevel::Auto | SimdLevel::Baseline => true,
            SimdLevel::Avx2 => avx2().is_some(),
        }
    }

    /// The level a frame runs at: `Auto` becomes the widest available, and a level this CPU
    /// lacks becomes `Baseline`.
    #[must_use]
    pub fn resolve(self) -> SimdLevel {
        match self {
            SimdLevel::Baseline => SimdLevel::Baseline,
            SimdLevel::Auto | SimdLevel::Avx2 if avx2().is_some() => SimdLevel::Avx2,
            SimdLevel::Auto | SimdLevel::Avx2 => SimdLevel::Baseline,
        }
    }

    /// The AVX2 token when the frame runs eight lanes.
    pub(crate) fn token(self) -> Option<Avx2> {
        match self.resolve() {
            SimdLevel::Avx2 => avx2(),
            _ => None,
        }
    }
}

impl fmt::Display for SimdLevel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A SIMD level name that is not one of [`SimdLevel::ALL`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown SIMD level `{0}` (expected auto, baseline or avx2)")]
pub struct UnknownSimdLevel(pub String);

impl FromStr for SimdLevel {
    type Err = UnknownSimdLevel;
    fn from_str(s: &str) -> Result<SimdLevel, UnknownSimdLevel> {
        SimdLevel::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| UnknownSimdLevel(s.to_owned()))
    }
}

/// The eight-lane token of this platform.
#[cfg(target_arch = "x86_64")]
pub(crate) type Avx2 = phosphor_lighting::Avx2;

/// No eight-lane level off x86-64: a type with no values.
#[cfg(not(target_arch = "x86_64"))]
#[derive(Debug, Clone, Copy)]
pub(crate) enum Avx2 {}

#[cfg(target_arch = "x86_64")]
fn avx2() -> Option<Avx2> {
    Avx2::detect()
}

#[cfg(not(target_arch = "x86_64"))]
fn avx2() -> Option<Avx2> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_resolve_to_a_level_the_cpu_runs() {
        for level in SimdLevel::ALL {
            assert_eq!(level.name().parse::<SimdLevel>(), Ok(level));
            let r = level.resolve();
            assert_ne!(r, SimdLevel::Auto);
            assert!(r.available(), "{level} resolved to {r}");
            assert_eq!(level.token().is_some(), r == SimdLevel::Avx2);
        }
        assert_eq!(SimdLevel::Baseline.resolve(), SimdLevel::Baseline);
        assert!("sse9".parse::<SimdLevel>().is_err());
    }
}
