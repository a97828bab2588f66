//! The classic illumination models as pure functions over plain data (the lecture notes'
//! vocabulary, docs/conventions.md: `I = Ka`, `I = Ia Ka`, Lambert `Kd Il (N.L)`, Phong 1975's
//! `W(theta) Il (V.R)^ns` with `R = 2(N.L)N - L`, attenuation `1/(K+d)`, distributed light
//! sources).
//!
//! The model, per RGB channel (x = r, y = g, z = b), all intensities linear:
//!
//! `I = emission + ka Ia + sum over lights f(d) Il [kd max(N.L,0) + ks W(theta) max(V.R,0)^n_s]`
//!
//! with the specular term 0 where `N.L <= 0`. [`Material`] holds `ka, kd, ks, n_s`, the
//! [`SpecularModel`] and the [`Fresnel`] `W(theta)` with its [`FresnelMode`] (`W` scales `ks`,
//! or replaces it as the notes' `I_spec = W(theta) Il cos^ns phi` does, `ks` then held at 1);
//! `n_s = inf` is the notes' perfect reflector ([`lobe`]); [`Light`] is a directional, point, spot,
//! tube or rect source with its [`Attenuation`]; [`LightSet`] prepares them once per draw.
//! [`shade()`] is generic over the [`Effects`] bits so an absent term costs nothing;
//! [`shade_split()`] keeps the ambient, diffuse and specular sums apart (fast Phong);
//! [`shade_reference`] is the f64 ground truth; [`PowTable`] is the specular power by table;
//! [`specular_upper_bound`] bounds the specular sum over a whole triangle (fast Phong's guard
//! against a highlight between its samples). [`shade_lanes()`] shades several points per
//! call, generic over a [`Lanes`] type: [`shade_x4()`] four ([`Vec3x4`], SSE2), and on x86-64
//! CPUs with AVX2 eight (`F32x8` inside `Avx2::run`, detected at run time), bit for bit what
//! that many [`shade()`] calls give.
//!
//! Numerics: no public function returns NaN or Inf for finite input. A zero or non-finite
//! normal gives `emission + ka Ia` only; a light at the surface point (`d = 0`) shines along
//! the normal with the attenuation factor capped at `1/MIN_ATTENUATION_DENOMINATOR`; results
//! are clamped to `[0, f32::MAX]` by [`finite_intensity`].
//!
//! Attenuation: pick [`Attenuation::Offset`] (the lecture notes' `1/(K+d)`, S1 uses `K = 1`);
//! the notes found the physical `1/d^2` "produced too much contrast" ([`attenuation`] explains).
//!
//! Effects: `shade::<FX>` evaluates only the terms whose [`Effects`] bit is in `FX`; with the
//! absent terms' coefficients zero (or their lights absent) it equals `shade::<{ALL}>`
//! (tested for all 512 subsets). A planner derives the minimal set with [`effects_for`]
//! (`LightSet::effects_needed() & Material::effects_needed()`) and turns runtime bits into a
//! const instantiation with [`dispatch_effects!`] or [`shade_dyn`] (512 instantiations), or
//! rounds them up with [`Effects::canonical`] and [`dispatch_canonical_effects!`] (16, same
//! results: shading with a superset of the needed effects changes nothing).
//!
//! # One worked example per model
//!
//! ```
//! use glam::Vec3;
//! use phosphor_lighting::*;
//! # fn main() -> Result<(), LightingError> {
//! let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-6;
//! let (p, n, eye) = (Vec3::ZERO, Vec3::Z, Vec3::new(0.0, 0.0, 5.0));
//! let grey = |k: f32| Vec3::splat(k);
//! let mat = |ka, kd, ks, ns| Material::new(grey(ka), grey(kd), grey(ks), ns);
//!
//! // Self-luminous: I = Ka (the emission term, no light at all).
//! let glow = mat(0.0, 0.0, 0.0, 1.0)?.with_emission(grey(0.3))?;
//! let dark = LightSet::new(Vec3::ZERO, &[]);
//! assert!(close(shade::<{ Effects::ALL.bits() }>(&dark, &glow, p, n, eye), grey(0.3)));
//!
//! // Ambient: I = Ia Ka = 0.5 * 0.2.
//! let set = LightSet::new(grey(0.5), &[]);
//! let m = mat(0.2, 0.0, 0.0, 1.0)?;
//! assert!(close(shade::<{ Effects::ALL.bits() }>(&set, &m, p, n, eye), grey(0.1)));
//!
//! // Lambert: I = Kd Il (N.L), light at 60 degrees from the normal: 0.8 * 2 * 0.5.
//! let l = Vec3::new(60f32.to_radians().sin(), 0.0, 60f32.to_radians().cos());
//! let set = LightSet::new(Vec3::ZERO, &[Light::directional(-l, grey(2.0))?]);
//! let m = mat(0.0, 0.8, 0.0, 1.0)?;
//! assert!(close(shade::<{ Effects::ALL.bits() }>(&set, &m, p, n, eye), grey(0.8)));
//!
//! // Ambient + diffuse: I = Ka Ia + Kd Il (N.L) = 0.1 * 1 + 0.8.
//! let set = LightSet::new(grey(1.0), &[Light::directional(-l, grey(2.0))?]);
//! let m = mat(0.1, 0.8, 0.0, 1.0)?;
//! assert!(close(shade::<{ Effects::ALL.bits() }>(&set, &m, p, n, eye), grey(0.9)));
//!
//! // Phong specular: I = Ks Il (V.R)^ns. L at 45 degrees, R = 2(N.L)N - L mirrors it, the
//! // viewer sits 15 degrees off R: 0.5 * 1 * cos(15 deg)^10.
//! let l = Vec3::new(-1.0, 0.0, 1.0).normalize();
//! let r = phosphor_math::reflect(n, l);
//! assert!(close(r, Vec3::new(1.0, 0.0, 1.0).normalize()));
//! let view = Vec3::new(30f32.to_radians().sin(), 0.0, 30f32.to_radians().cos());
//! let set = LightSet::new(Vec3::ZERO, &[Light::directional(-l, grey(1.0))?]);
//! let m = mat(0.0, 0.0, 0.5, 10.0)?;
//! let i = shade::<{ Effects::ALL.bits() }>(&set, &m, p, n, view);
//! assert!(close(i, grey(0.5 * 15f32.to_radians().cos().powi(10))));
//!
//! // Blinn: (N.H)^ns with H = (L + V)/|L + V|; viewer on R again gives 0.5 cos(7.5 deg)^10.
//! let m = m.with_specular(SpecularModel::Blinn);
//! let i = shade::<{ Effects::ALL.bits() }>(&set, &m, p, n, view);
//! assert!(close(i, grey(0.5 * 7.5f32.to_radians().cos().powi(10))));
//!
//! // Fresnel W(theta), Schlick glass: 4 percent head on.
//! let glass = mat(0.0, 0.0, 1.0, 1.0)?.with_fresnel(Fresnel::Schlick { f0: 0.04 })?;
//! let above = LightSet::new(Vec3::ZERO, &[Light::directional(-Vec3::Z, grey(1.0))?]);
//! assert!(close(shade::<{ Effects::ALL.bits() }>(&above, &glass, p, n, eye), grey(0.04)));
//!
//! // Attenuation 1/(K+d): a point light 3 above with K = 1 gives Kd Il / 4.
//! let lamp = Light::point(Vec3::new(0.0, 0.0, 3.0), grey(2.0))?
//!     .with_attenuation(Attenuation::Offset { k: 1.0 })?;
//! let set = LightSet::new(Vec3::ZERO, &[lamp]);
//! let m = mat(0.0, 0.8, 0.0, 1.0)?;
//! assert!(close(shade::<{ Effects::ALL.bits() }>(&set, &m, p, n, eye), grey(0.4)));
//!
//! // Spot: the point is on the axis, inside the inner cone: full intensity.
//! let spot = LightKind::Spot { position: Vec3::new(0.0, 0.0, 2.0), direction: -Vec3::Z,
//!     inner_deg: 10.0, outer_deg: 20.0 };
//! let set = LightSet::new(Vec3::ZERO, &[Light::new(spot, grey(1.0))?]);
//! assert!(close(shade::<{ Effects::ALL.bits() }>(&set, &m, p, n, eye), grey(0.8)));
//!
//! // Distributed: a tube of 4 samples far above acts like one point light of the same Il.
//! let tube = LightKind::Tube { start: Vec3::new(-0.5, 0.0, 1e3), end: Vec3::new(0.5, 0.0, 1e3),
//!     samples: 4 };
//! let set = LightSet::new(Vec3::ZERO, &[Light::new(tube, grey(1.0))?]);
//! assert!(close(shade::<{ Effects::ALL.bits() }>(&set, &m, p, n, eye), grey(0.8)));
//! # Ok(())
//! # }
//! ```
//!
//! # Cost per call
//!
//! Nanoseconds per `shade::<FX>` call, S1's material (with Schlick Fresnel), point lights with
//! `1/(1+d)`, each level adding one effect to the previous one
//! (`cargo bench --bench lighting -- --quick --warm-up-time 0.5 --measurement-time 1`,
//! criterion median, on the 2-core development machine, idle, after the specular power moved to
//! repeated squaring for integer `n_s`; quick runs, so +-10%):
//!
//! | effects                 | 1 light | 3 lights | 8 lights |
//! |-------------------------|--------:|---------:|---------:|
//! | ambient only            |     2.9 |      2.7 |      2.7 |
//! | + diffuse               |    25.7 |     31.2 |     49.9 |
//! | + specular (Phong)      |    39.6 |     61.4 |    114.3 |
//! | + Fresnel (Schlick)     |    40.9 |     60.2 |    115.0 |
//! | + attenuation `1/(K+d)` |    40.4 |     68.0 |    131.3 |
//!
//! Ambient only does not touch the lights (the loops are compiled out). Each call is timed in
//! isolation, so the lit levels pay the latency of one dependent chain (distance square root,
//! reciprocal, dot products) of about 20 ns; further lights overlap and add 2-4 ns (diffuse)
//! to 9-11 ns (with specular) each. Unit normals are used as given (no renormalization).

#![cfg_attr(test, allow(clippy::unwrap_used))]

pub mod attenuation;
pub mod bound;
pub mod effects;
mod error;
pub mod fresnel;
pub mod lanes;
pub mod light;
pub mod lightset;
pub mod lobe;
pub mod material;
pub mod pow_table;
pub mod reference;
pub mod shade;
pub mod shade_wide;

pub use attenuation::{Attenuation, MAX_LIGHT_DISTANCE, MIN_ATTENUATION_DENOMINATOR};
pub use bound::{lobe_sharpness, specular_upper_bound};
pub use effects::Effects;
pub use error::LightingError;
pub use fresnel::{Fresnel, FresnelMode, GLASS_F0};
#[cfg(target_arch = "x86_64")]
pub use lanes::{Avx2, Avx2Task, F32x8};
pub use lanes::{F32x1, Lanes, f32x4};
pub use light::{Light, LightKind, MAX_SAMPLES_PER_EDGE};
pub use lightset::{LightSet, PreparedDirectional, PreparedPoint, PreparedSpot, effects_for};
pub use lobe::{MIRROR_COS_TOLERANCE, specular_lobe, specular_lobe_f64};
pub use material::{Material, SpecularModel};
pub use pow_table::PowTable;
pub use reference::{shade_reference, shade_reference_tinted};
pub use shade::{ShadeTerms, finite_intensity, shade, shade_canonical, shade_dyn, shade_split};
#[cfg(target_arch = "x86_64")]
pub use shade_wide::Vec3x8;
pub use shade_wide::{
    NoneSeen, SeenLights, TermsLanes, Vec3s, Vec3x4, shade_lanes, shade_terms_lanes,
    shade_terms_lanes_seen, shade_x4,
};

#[cfg(test)]
mod tests;
