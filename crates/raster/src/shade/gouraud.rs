//! `gouraud`: the model at the vertices (their averaged normals), intensities interpolated
//! (Gouraud 1971: `I4 = (y4 - y2)/(y1 - y2) I1 + (y1 - y4)/(y1 - y2) I2`, then `Ip` along the span).
//! By default the intensity plane is evaluated at each span start; with
//! [`crate::Interpolation::Incremental`] the values are stepped per scan line and per pixel as
//! Gouraud 1971 does ([`crate::shade::incremental`]).

use glam::Vec3;
use phosphor_lighting::{Vec3x4, shade, shade_x4};

use super::{Lit, Mode, TriVertices, VertexIn, get3, halves, join, lit8, put3};
use crate::clip::{Attrs, MAX_ATTRS};
use crate::scanline::{BandTarget, Kernel, traverse};
use crate::setup::RasterTri;

/// The Gouraud mode for effect set `FX`.
#[derive(Debug, Clone, Copy)]
pub struct Gouraud<'a, const FX: u32> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
    /// Clamp each vertex intensity to at most 1 before interpolating
    /// ([`crate::RenderOptions::gouraud_vertex_clamp`]).
    pub vertex_clamp: bool,
}

impl<const FX: u32> Gouraud<'_, FX> {
    /// The intensity a vertex contributes: clamped to the display range, or as computed.
    #[inline]
    fn at_vertex(&self, i: Vec3) -> Vec3 {
        if self.vertex_clamp {
            i.min(Vec3::ONE)
        } else {
            i
        }
    }
}

impl<const FX: u32> Kernel for Gouraud<'_, FX> {
    const ATTRS: usize = 3;
    type Tri = ();
    type Span = ();
    #[inline]
    fn span(&self, _: &(), _: f32, _: f32) {}
    #[inline]
    fn shade(&self, _: &(), _: &(), attrs: &Attrs, _: u32, _: u32) -> Vec3 {
        get3(attrs, 0)
    }
    #[inline]
    fn step(_: &mut ()) {}
}

impl<const FX: u32> Mode for Gouraud<'_, FX> {
    const ATTRS: usize = 3;
    type Tri = ();
    const VERTEX_BATCH: bool = true;
    fn vertex(&self, v: &VertexIn) -> Attrs {
        let mut a = [0.0; MAX_ATTRS];
        let i = shade::<FX>(self.lit.set, &self.lit.mat, v.world, v.normal, self.lit.eye);
        put3(&mut a, 0, self.at_vertex(i));
        a
    }
    fn vertex4(&self, v: [&VertexIn; 4]) -> [Attrs; 4] {
        // Bit for bit `vertex` in every lane.
        let i = shade_x4::<FX>(
            self.lit.set,
            &self.lit.mat,
            Vec3x4::from_array(v.map(|v| v.world)),
            Vec3x4::from_array(v.map(|v| v.normal)),
            self.lit.eye,
        )
        .to_array();
        i.map(|i| {
            let mut a = [0.0; MAX_ATTRS];
            put3(&mut a, 0, self.at_vertex(i));
            a
        })
    }
    fn vertex8(&self, v: [&VertexIn; 8]) -> [Attrs; 8] {
        // Eight lanes where the frame runs them, bit for bit `vertex` in every lane.
        let Some(i) = lit8::<FX>(&self.lit, v.map(|v| v.world), v.map(|v| v.normal)) else {
            let (lo, hi) = halves(&v);
            return join(self.vertex4(lo), self.vertex4(hi));
        };
        i.map(|i| {
            let mut a = [0.0; MAX_ATTRS];
            put3(&mut a, 0, self.at_vertex(i));
            a
        })
    }
    fn triangle(&self, _: TriVertices<'_>, _: bool) {}
    fn draw(&self, t: &RasterTri, tri: &(), target: &mut BandTarget) -> u64 {
        traverse(t, self, tri, target)
    }
}
