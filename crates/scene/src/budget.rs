//! The scene's budget of distributed-light samples.
//!
//! A tube light of `n` samples is `n` point lights and a rect light `n x n`, each evaluated
//! at every shaded pixel of every object it reaches. Each light alone is bounded
//! ([`phosphor_lighting::MAX_SAMPLES_PER_EDGE`]), but eight rect lights of 256 samples per
//! edge are half a million point lights per pixel: seconds per frame even at 320x240, a
//! frozen viewer. Above the budget every distributed light is cut in the same proportion, so
//! their balance (and each light's total intensity, which its samples share) is kept.

use phosphor_lighting::{Light, LightKind};

/// Most point samples the distributed (tube, rect) lights of one scene may have together:
/// sixteen times what the shipped default scene uses (one tube of 4 samples), room for a rect
/// of 16 x 16, while the per-pixel light loop stays within a few hundred point lights.
pub const MAX_DISTRIBUTED_SAMPLES: u64 = 256;

/// The point samples a light is evaluated as: `samples` for a tube, `samples^2` for a rect,
/// 0 for the other kinds.
#[must_use]
pub fn point_samples(light: &Light) -> u64 {
    match light.kind {
        LightKind::Tube { samples, .. } => u64::from(samples),
        LightKind::Rect { samples, .. } => u64::from(samples) * u64::from(samples),
        _ => 0,
    }
}

/// One light whose `samples` field was cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SampleCut {
    /// Index of the light in the list given.
    pub index: usize,
    /// Its `samples` as written.
    pub before: u32,
    /// Its `samples` now.
    pub after: u32,
}

/// Cuts the `samples` of every distributed light in `lights` in the same proportion when
/// together they exceed `budget` point samples (a tube by that proportion, a rect's edge count
/// by its square root, never below one sample); returns the cuts made (none within budget)
/// and the total asked for.
pub fn limit_distributed_samples(lights: &mut [Light], budget: u64) -> (Vec<SampleCut>, u64) {
    let total: u64 = lights.iter().map(point_samples).sum();
    if total <= budget {
        return (Vec::new(), total);
    }
    let share = budget as f64 / total as f64;
    let mut cuts = Vec::new();
    for (index, light) in lights.iter_mut().enumerate() {
        let (samples, scale) = match &mut light.kind {
            LightKind::Tube { samples, .. } => (samples, share),
            LightKind::Rect { samples, .. } => (samples, share.sqrt()),
            _ => continue,
        };
        let before = *samples;
        // Floored, so the cut total stays within the budget (unless the lights outnumber it).
        let after = ((f64::from(before) * scale).floor() as u32).clamp(1, before);
        if after != before {
            *samples = after;
            cuts.push(SampleCut {
                index,
                before,
                after,
            });
        }
    }
    (cuts, total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn rect(samples: u32) -> Light {
        let kind = LightKind::Rect {
            corner: Vec3::ZERO,
            edge_u: Vec3::X,
            edge_v: Vec3::Y,
            samples,
        };
        Light::new(kind, Vec3::ONE).unwrap_or_else(|e| panic!("{e}"))
    }

    fn tube(samples: u32) -> Light {
        let kind = LightKind::Tube {
            start: Vec3::ZERO,
            end: Vec3::X,
            samples,
        };
        Light::new(kind, Vec3::ONE).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn lights_within_the_budget_are_kept() {
        let mut lights = vec![rect(4), tube(8), rect(15)];
        let (cuts, total) = limit_distributed_samples(&mut lights, 256);
        assert!(cuts.is_empty());
        assert_eq!(total, 16 + 8 + 225);
        assert_eq!(point_samples(&lights[2]), 225);
    }

    #[test]
    fn over_the_budget_every_distributed_light_is_cut_in_proportion() {
        let mut lights = vec![rect(256); 8];
        lights.push(tube(256));
        lights.push(Light::point(Vec3::ONE, Vec3::ONE).unwrap_or_else(|e| panic!("{e}")));
        let (cuts, total) = limit_distributed_samples(&mut lights, MAX_DISTRIBUTED_SAMPLES);
        assert_eq!(total, 8 * 65_536 + 256);
        assert_eq!(cuts.len(), 9);
        let after: u64 = lights.iter().map(point_samples).sum();
        assert!(after <= MAX_DISTRIBUTED_SAMPLES, "{after}");
        assert!(after >= MAX_DISTRIBUTED_SAMPLES / 2, "{after}");
        // One proportion: every rect alike; the tube's share rounds down to its floor of one.
        assert!(
            cuts[..8]
                .iter()
                .all(|c| c.after == cuts[0].after && c.before == 256)
        );
        assert_eq!(cuts[8].index, 8);
        assert_eq!(cuts[8].after, 1);
    }

    #[test]
    fn a_cut_never_goes_below_one_sample() {
        let mut lights = vec![tube(2); 600];
        let (cuts, _) = limit_distributed_samples(&mut lights, 256);
        assert_eq!(cuts.len(), 600);
        assert!(lights.iter().all(|l| point_samples(l) == 1));
    }
}
