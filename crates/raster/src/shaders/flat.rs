//! `flat`: the model once per triangle, with the face normal, at the centroid (the lecture
//! notes' constant-intensity shading, "calculate the intensity for each facet, say, at the
//! centre"), several triangles per call in lanes.

use glam::Vec3;
use phosphor_lighting::{Lanes, Vec3s, shade_lanes};

use super::Lit;
use crate::shader::{Face, MAX_VARYINGS, Shader, TriangleLanes, Varyings, VertexLanes};

/// The flat mode for effect set `FX`.
#[derive(Debug, Clone, Copy)]
pub struct Flat<'a, const FX: u32> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
}

impl<const FX: u32> Shader for Flat<'_, FX> {
    const VARYINGS: usize = 0;
    const FACE: Face = Face::Constant;
    type Stepped = ();
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        [v.position.x.splat(0.0); MAX_VARYINGS]
    }
    #[inline(always)]
    fn constant<L: Lanes>(&self, t: &TriangleLanes<L>) -> Vec3s<L> {
        let (centroid, n) = super::surface::facet(t);
        // Bit for bit the scalar model in every lane.
        shade_lanes::<FX, L>(self.lit.set, &self.lit.mat, centroid, n, self.lit.eye)
    }
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        Vec3s::broadcast(v[0], Vec3::ZERO)
    }
}

/// Draws `d` flat into `frame`, specialized for its effects.
pub(crate) fn draw(frame: &mut crate::Frame, d: &crate::DrawItem) {
    if super::tinted::is_tinted(d) {
        return super::tinted::draw_flat(frame, d);
    }
    let lit = Lit::new(d.lights, d.material, d.effects, frame.eye());
    crate::with_fx!(d.effects, FX => frame.draw(&d.mesh, d.model, &Flat::<FX> { lit }, d.cull_backfaces));
}
