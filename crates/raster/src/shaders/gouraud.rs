//! `gouraud`: the model at the vertices (their averaged normals), intensities interpolated
//! (Gouraud 1971: `I4 = (y4 - y2)/(y1 - y2) I1 + (y1 - y4)/(y1 - y2) I2`, then `Ip` along the
//! span). The vertices are lit eight at a time with AVX2 (else four); interpolated colours
//! cost less per pixel than finding the nearest triangle first, so each triangle is shaded as
//! it is drawn ([`Shader::SHADE_ONCE`] false).

use phosphor_lighting::{Lanes, Vec3s, shade_lanes};

use super::Lit;
use crate::shader::{MAX_VARYINGS, Shader, Varyings, VertexLanes, put_vec3, vec3_at};

/// The Gouraud mode for effect set `FX`.
#[derive(Debug, Clone, Copy)]
pub struct Gouraud<'a, const FX: u32> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
    /// Clamp each vertex intensity to at most 1 before interpolating
    /// ([`crate::RenderOptions::gouraud_vertex_clamp`]).
    pub vertex_clamp: bool,
}

impl<const FX: u32> Shader for Gouraud<'_, FX> {
    const VARYINGS: usize = 3;
    const SHADE_ONCE: bool = false;
    type Stepped = ();
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        let lit = &self.lit;
        let mut i = shade_lanes::<FX, L>(lit.set, &lit.mat, v.position, v.normal, lit.eye);
        if self.vertex_clamp {
            // What is interpolated is what each vertex shows.
            let one = v.position.x.splat(1.0);
            i = Vec3s::new(i.x.min_c(one), i.y.min_c(one), i.z.min_c(one));
        }
        let mut out = [v.position.x.splat(0.0); MAX_VARYINGS];
        put_vec3(&mut out, 0, i);
        out
    }
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        vec3_at(v, 0)
    }
}

/// Draws `d` with Gouraud shading into `frame`, specialized for its effects.
pub(crate) fn draw(frame: &mut crate::Frame, d: &crate::DrawItem) {
    if super::tinted::is_tinted(d) {
        return super::tinted::draw_gouraud(frame, d);
    }
    let lit = Lit::new(d.lights, d.material, d.effects, frame.eye());
    let vertex_clamp = frame.options().gouraud_vertex_clamp && !frame.hdr();
    crate::with_fx!(d.effects, FX => frame.draw(&d.mesh, d.model, &Gouraud::<FX> { lit, vertex_clamp }, d.cull_backfaces));
}
