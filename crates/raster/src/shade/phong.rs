//! `phong`: normals and world positions interpolated, the normal renormalized, the full model
//! per pixel (Phong 1975: normal-vector interpolation shading). With `BUMP`, the normal is
//! perturbed by the height field in the tangent frame first.

use glam::{Vec2, Vec3, Vec4};
use phosphor_lighting::{Vec3x4, f32x4, shade, shade_x4};

use super::{Lit, Mode, Passes, TriVertices, VertexIn, get3, surface_attrs};
use crate::bump::BumpMap;
use crate::clip::Attrs;
use crate::scanline::{BandTarget, Kernel, traverse};
use crate::setup::RasterTri;

/// The Phong mode for effect set `FX`, with or without bump mapping.
#[derive(Debug, Clone, Copy)]
pub struct Phong<'a, const FX: u32, const BUMP: bool> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
    /// The height field (used only when `BUMP`).
    pub bump: Option<&'a BumpMap>,
}

impl<const FX: u32, const BUMP: bool> Kernel for Phong<'_, FX, BUMP> {
    const ATTRS: usize = if BUMP { 12 } else { 6 };
    type Tri = ();
    type Span = ();
    #[inline]
    fn span(&self, _: &(), _: f32, _: f32) {}
    #[inline]
    fn shade(&self, _: &(), _: &(), attrs: &Attrs, _: u32, _: u32) -> Vec3 {
        let p = get3(attrs, 0);
        let mut n = get3(attrs, 3);
        if BUMP {
            if let Some(map) = self.bump {
                let uv = Vec2::new(attrs[6], attrs[7]);
                let t = Vec4::new(attrs[8], attrs[9], attrs[10], attrs[11]);
                n = map.perturb(n, t, uv);
            }
        }
        // `shade` renormalizes n (a zero or non-finite n gives ambient + emission).
        shade::<FX>(self.lit.set, &self.lit.mat, p, n, self.lit.eye)
    }
    #[inline]
    fn step(_: &mut ()) {}
    const LANES: usize = 4;
    const ACROSS_TRIANGLES: bool = true;
    #[inline]
    fn shade_lanes(&self, _: &(), attrs: &[Attrs; 4], _: usize) -> [Vec3; 4] {
        let (p, n) = if BUMP {
            // By reference: `attrs.map` would copy each 48-byte attribute set first.
            let p: [Vec3; 4] = std::array::from_fn(|k| get3(&attrs[k], 0));
            let mut n: [Vec3; 4] = std::array::from_fn(|k| get3(&attrs[k], 3));
            if let Some(map) = self.bump {
                for (n, a) in n.iter_mut().zip(attrs) {
                    let uv = Vec2::new(a[6], a[7]);
                    let t = Vec4::new(a[8], a[9], a[10], a[11]);
                    *n = map.perturb(*n, t, uv);
                }
            }
            (Vec3x4::from_array(p), Vec3x4::from_array(n))
        } else {
            // Position and normal are lanes 0..6 of each pixel's set: two 4x4 transposes
            // (eight shuffles each) turn the four sets into the lanes of `shade_x4`, where
            // gathering them one float at a time took 48 scalar moves.
            let row = |k: usize, at: usize| {
                let a = &attrs[k];
                f32x4::new([a[at], a[at + 1], a[at + 2], a[at + 3]])
            };
            let [px, py, pz, nx] = f32x4::transpose([row(0, 0), row(1, 0), row(2, 0), row(3, 0)]);
            let [ny, nz, _, _] = f32x4::transpose([row(0, 4), row(1, 4), row(2, 4), row(3, 4)]);
            (Vec3x4::new(px, py, pz), Vec3x4::new(nx, ny, nz))
        };
        // Bit for bit `shade` in every lane.
        shade_x4::<FX>(self.lit.set, &self.lit.mat, p, n, self.lit.eye).to_array()
    }
}

impl<const FX: u32, const BUMP: bool> Mode for Phong<'_, FX, BUMP> {
    const ATTRS: usize = if BUMP { 12 } else { 6 };
    type Tri = ();
    const PASSES: Passes = Passes::ByPixel;
    fn vertex(&self, v: &VertexIn) -> Attrs {
        surface_attrs(v)
    }
    fn triangle(&self, _: TriVertices<'_>, _: bool) {}
    fn draw(&self, t: &RasterTri, tri: &(), target: &mut BandTarget) -> u64 {
        traverse(t, self, tri, target)
    }
    fn finish(&self, target: &mut BandTarget) {
        target.pending.flush(self, &(), target.color);
    }
    #[inline]
    fn shade4(&self, attrs: &[Attrs; 4], count: usize) -> [Vec3; 4] {
        self.shade_lanes(&(), attrs, count)
    }
}
