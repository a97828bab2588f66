//! The built-in shading modes, each a [`Shader`](crate::shader::Shader) written against the
//! public contract alone: [`flat`], [`gouraud`], [`phong`], [`fast_phong`] (with
//! [`taylor`]), [`reference`](mod@reference), and [`fill`] (coverage and depth in one colour);
//! [`tinted`] holds their forms for a draw with vertex colours or a texture.
//!
//! # Effect specialization
//!
//! A draw's runtime [`Effects`] are mapped to one of six `const FX: u32` instantiations:
//! the base `AMBIENT | DIFFUSE | EMISSION | SPOT | DISTRIBUTED` plus every combination of
//! `SPECULAR`, `ATTENUATION` and (with specular) `FRESNEL`, the bits that change the
//! per-pixel cost. The cheap terms are always compiled in and switched off, where the draw
//! leaves them out, by zeroing their coefficient in a copy of the material (`ka`, `kd`,
//! `emission`; `ks` needs no copy since SPECULAR is specialized). Spot and distributed lights
//! cost nothing when the light set has none; a draw that leaves out SPOT or DISTRIBUTED while
//! its light set holds such lights still sees them (drop them from the `LightSet` instead).

use glam::Vec3;
use phosphor_lighting::{Effects, LightSet, Material};

pub mod check;
pub mod fast_phong;
pub mod fill;
pub mod flat;
pub mod gouraud;
pub mod phong;
pub mod reference;
mod surface;
pub mod taylor;
pub mod tinted;

/// What every lit mode shades with: the draw's lights, material and viewer.
#[derive(Debug, Clone, Copy)]
pub struct Lit<'a> {
    /// Lights prepared for the draw.
    pub set: &'a LightSet,
    /// The material, with left-out terms zeroed ([`effective_material`]).
    pub mat: Material,
    /// Viewer position (the camera eye).
    pub eye: Vec3,
}

impl<'a> Lit<'a> {
    /// The lights and material of a draw with effects `effects`, seen from `eye`.
    #[must_use]
    pub fn new(set: &'a LightSet, mat: &Material, effects: Effects, eye: Vec3) -> Lit<'a> {
        Lit {
            set,
            mat: effective_material(mat, effects),
            eye,
        }
    }
}

/// Bits always compiled into a shader (cheap, or free when the light set lacks them).
pub const BASE_FX: u32 = Effects::AMBIENT.bits()
    | Effects::DIFFUSE.bits()
    | Effects::EMISSION.bits()
    | Effects::SPOT.bits()
    | Effects::DISTRIBUTED.bits();

/// Runs `$body` with `const $fx: u32` set to the instantiation for runtime effects `$effects`
/// (see the module docs for the six instantiations).
#[macro_export]
#[doc(hidden)]
macro_rules! with_fx {
    ($effects:expr, $fx:ident => $body:expr) => {{
        use phosphor_lighting::Effects as E;
        use $crate::shaders::BASE_FX;
        let e: E = $effects;
        let s = e.contains(E::SPECULAR);
        let a = e.contains(E::ATTENUATION);
        let f = s && e.contains(E::FRESNEL);
        match (s, a, f) {
            (false, false, _) => {
                const $fx: u32 = BASE_FX;
                $body
            }
            (false, true, _) => {
                const $fx: u32 = BASE_FX | E::ATTENUATION.bits();
                $body
            }
            (true, false, false) => {
                const $fx: u32 = BASE_FX | E::SPECULAR.bits();
                $body
            }
            (true, true, false) => {
                const $fx: u32 = BASE_FX | E::SPECULAR.bits() | E::ATTENUATION.bits();
                $body
            }
            (true, false, true) => {
                const $fx: u32 = BASE_FX | E::SPECULAR.bits() | E::FRESNEL.bits();
                $body
            }
            (true, true, true) => {
                const $fx: u32 =
                    BASE_FX | E::SPECULAR.bits() | E::ATTENUATION.bits() | E::FRESNEL.bits();
                $body
            }
        }
    }};
}

/// The material as the draw's effects see it: coefficients of left-out cheap terms zeroed.
#[must_use]
pub fn effective_material(mat: &Material, effects: Effects) -> Material {
    let mut m = *mat;
    if !effects.contains(Effects::AMBIENT) {
        m.ka = Vec3::ZERO;
    }
    if !effects.contains(Effects::DIFFUSE) {
        m.kd = Vec3::ZERO;
    }
    if !effects.contains(Effects::EMISSION) {
        m.emission = Vec3::ZERO;
    }
    m
}
