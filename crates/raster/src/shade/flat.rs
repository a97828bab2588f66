//! `flat`: the model once per triangle, with the face normal, at the centroid (the lecture
//! notes' constant-intensity shading, "calculate the intensity for each facet, say, at the centre").

use glam::Vec3;
use phosphor_lighting::{Vec3x4, shade, shade_x4};
use phosphor_math::safe_normalize;

use super::{Lit, Mode, TriInput, TriVertices, VertexIn};
use crate::clip::{Attrs, MAX_ATTRS};
use crate::scanline::{BandTarget, Kernel, traverse};
use crate::setup::RasterTri;

/// The flat mode for effect set `FX`.
#[derive(Debug, Clone, Copy)]
pub struct Flat<'a, const FX: u32> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
}

impl<const FX: u32> Kernel for Flat<'_, FX> {
    const ATTRS: usize = 0;
    type Tri = Vec3;
    type Span = ();
    #[inline]
    fn span(&self, _: &Vec3, _: f32, _: f32) {}
    #[inline]
    fn shade(&self, tri: &Vec3, _: &(), _: &Attrs, _: u32, _: u32) -> Vec3 {
        *tri
    }
    #[inline]
    fn step(_: &mut ()) {}
}

impl<const FX: u32> Mode for Flat<'_, FX> {
    const ATTRS: usize = 0;
    type Tri = Vec3;
    fn vertex(&self, _: &VertexIn) -> Attrs {
        [0.0; MAX_ATTRS]
    }
    const INPUT: TriInput = TriInput::World;
    fn triangle(&self, v: TriVertices<'_>, _: bool) -> Vec3 {
        // The renderer hands the world vertices (INPUT); without them there is no facet.
        let TriVertices::World(src) = v else {
            return Vec3::ZERO;
        };
        let (centroid, n) = facet(src.map(|v| v.world));
        shade::<FX>(self.lit.set, &self.lit.mat, centroid, n, self.lit.eye)
    }
    fn triangle4(&self, src: [[&VertexIn; 3]; 4], _: bool) -> [Vec3; 4] {
        let f = src.map(|v| facet(v.map(|v| v.world)));
        // Bit for bit `triangle` in every lane.
        shade_x4::<FX>(
            self.lit.set,
            &self.lit.mat,
            Vec3x4::from_array(f.map(|f| f.0)),
            Vec3x4::from_array(f.map(|f| f.1)),
            self.lit.eye,
        )
        .to_array()
    }
    fn draw(&self, t: &RasterTri, tri: &Vec3, target: &mut BandTarget) -> u64 {
        traverse(t, self, tri, target)
    }
}

/// The centroid and the unit face normal (zero when degenerate) of a triangle.
fn facet([a, b, c]: [Vec3; 3]) -> (Vec3, Vec3) {
    // Counter-clockwise is front, so the cross product points outwards.
    let n = safe_normalize((b - a).cross(c - a), Vec3::ZERO);
    ((a + b + c) / 3.0, n)
}

/// Coverage and depth only, one constant colour (the fill-only speed bound).
#[derive(Debug, Clone, Copy)]
pub struct FillOnly {
    /// The colour written.
    pub color: Vec3,
}

impl Mode for FillOnly {
    const ATTRS: usize = 0;
    type Tri = Vec3;
    fn vertex(&self, _: &VertexIn) -> Attrs {
        [0.0; MAX_ATTRS]
    }
    fn triangle(&self, _: TriVertices<'_>, _: bool) -> Vec3 {
        self.color
    }
    fn draw(&self, t: &RasterTri, tri: &Vec3, target: &mut BandTarget) -> u64 {
        traverse(t, &ConstKernel, tri, target)
    }
}

/// The kernel writing the per-triangle colour as is.
#[derive(Debug, Clone, Copy)]
pub struct ConstKernel;

impl Kernel for ConstKernel {
    const ATTRS: usize = 0;
    type Tri = Vec3;
    type Span = ();
    #[inline]
    fn span(&self, _: &Vec3, _: f32, _: f32) {}
    #[inline]
    fn shade(&self, tri: &Vec3, _: &(), _: &Attrs, _: u32, _: u32) -> Vec3 {
        *tri
    }
    #[inline]
    fn step(_: &mut ()) {}
}
