//! `phong`: normals and world positions interpolated, the normal renormalized, the full model
//! per pixel (Phong 1975: normal-vector interpolation shading), eight pixels at a time with
//! AVX2 (else four). With `BUMP`, the normal is perturbed by the height field in the tangent
//! frame first (Blinn 1978).

use phosphor_lighting::{Lanes, Vec3s, shade_lanes};

use super::Lit;
pub use super::surface::{perturbed, surface_varyings};
use crate::bump::BumpMap;
use crate::shader::{Shader, Varyings, VertexLanes, vec3_at};

/// The Phong mode for effect set `FX`, with or without bump mapping.
#[derive(Debug, Clone, Copy)]
pub struct Phong<'a, const FX: u32, const BUMP: bool> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
    /// The height field (used only when `BUMP`).
    pub bump: Option<&'a BumpMap>,
}

impl<const FX: u32, const BUMP: bool> Shader for Phong<'_, FX, BUMP> {
    const VARYINGS: usize = if BUMP { 12 } else { 6 };
    type Stepped = ();
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        surface_varyings(v, BUMP)
    }
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        let (p, mut n) = (vec3_at(v, 0), vec3_at(v, 3));
        if let (true, Some(map)) = (BUMP, self.bump) {
            n = perturbed(map, n, v);
        }
        // `shade` renormalizes n (a zero or non-finite n gives ambient + emission); bit for
        // bit the scalar model in every lane.
        let lit = &self.lit;
        shade_lanes::<FX, L>(lit.set, &lit.mat, p, n, lit.eye)
    }
}

/// Draws `d` with Phong shading into `frame`, specialized for its effects and bump map.
pub(crate) fn draw(frame: &mut crate::Frame, d: &crate::DrawItem) {
    if super::tinted::is_tinted(d) {
        return super::tinted::draw_phong(frame, d);
    }
    let lit = Lit::new(d.lights, d.material, d.effects, frame.eye());
    let (mesh, model, cull) = (&d.mesh, d.model, d.cull_backfaces);
    match d.bump {
        Some(map) => {
            crate::with_fx!(d.effects, FX => frame.draw(mesh, model, &Phong::<FX, true> { lit, bump: Some(map) }, cull))
        }
        None => {
            crate::with_fx!(d.effects, FX => frame.draw(mesh, model, &Phong::<FX, false> { lit, bump: None }, cull))
        }
    }
}
