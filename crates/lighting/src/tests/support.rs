//! Shared helpers: a tiny deterministic generator of random scenes.

use glam::Vec3;

use crate::{Attenuation, Fresnel, FresnelMode, Light, LightKind, Material, SpecularModel};

/// xorshift64*: deterministic, dependency-free randomness for exhaustive loops.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let u = (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * u
    }
    pub fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

pub fn random_material(rng: &mut Rng) -> Material {
    let mode = if rng.below(4) == 0 {
        FresnelMode::Replace
    } else {
        FresnelMode::Scale
    };
    Material {
        ka: rng.vec(0.0, 1.0),
        kd: rng.vec(0.0, 1.0),
        ks: rng.vec(0.0, 1.0),
        shininess: [0.0, 1.0, 8.0, 32.0, 200.0, f32::INFINITY][rng.below(6) as usize],
        specular: if rng.below(2) == 0 {
            SpecularModel::Phong
        } else {
            SpecularModel::Blinn
        },
        fresnel: match rng.below(3) {
            0 => Fresnel::None,
            1 => Fresnel::Constant {
                w: rng.range(0.0, 1.0),
            },
            _ => Fresnel::Schlick {
                f0: rng.range(0.0, 1.0),
            },
        },
        fresnel_mode: FresnelMode::Scale,
        emission: rng.vec(0.0, 0.5),
    }
    .with_fresnel_mode(mode)
}

pub fn random_attenuation(rng: &mut Rng) -> Attenuation {
    match rng.below(4) {
        0 => Attenuation::None,
        1 => Attenuation::InverseSquare,
        2 => Attenuation::Offset {
            k: rng.range(0.0, 2.0),
        },
        _ => Attenuation::Quadratic {
            c: rng.range(0.0, 1.0),
            l: rng.range(0.0, 1.0),
            q: rng.range(0.0, 1.0),
        },
    }
}

pub fn random_light(rng: &mut Rng) -> Light {
    let kind = match rng.below(5) {
        0 => LightKind::Directional {
            direction: rng.vec(-1.0, 1.0) + Vec3::splat(1e-3),
        },
        1 => LightKind::Point {
            position: rng.vec(-5.0, 5.0),
        },
        2 => {
            let inner_deg = rng.range(0.0, 60.0);
            LightKind::Spot {
                position: rng.vec(-5.0, 5.0),
                direction: rng.vec(-1.0, 1.0) + Vec3::splat(1e-3),
                inner_deg,
                outer_deg: inner_deg + rng.range(0.0, 60.0),
            }
        }
        3 => LightKind::Tube {
            start: rng.vec(-5.0, 5.0),
            end: rng.vec(-5.0, 5.0),
            samples: 1 + rng.below(4) as u32,
        },
        _ => LightKind::Rect {
            corner: rng.vec(-5.0, 5.0),
            edge_u: rng.vec(-1.0, 1.0),
            edge_v: rng.vec(-1.0, 1.0),
            samples: 1 + rng.below(3) as u32,
        },
    };
    Light {
        kind,
        intensity: rng.vec(0.0, 3.0),
        specular_intensity: if rng.below(3) == 0 {
            Some(rng.vec(0.0, 3.0))
        } else {
            None
        },
        attenuation: random_attenuation(rng),
        enabled: true,
    }
}

pub fn random_lights(rng: &mut Rng) -> Vec<Light> {
    let count = rng.below(6) as usize;
    (0..count).map(|_| random_light(rng)).collect()
}

pub fn assert_close(a: Vec3, b: Vec3, tol: f32, what: &str) {
    let scale = 1.0 + a.abs().max(b.abs()).max_element();
    assert!(
        (a - b).abs().max_element() <= tol * scale,
        "{what}: {a} vs {b}"
    );
}
