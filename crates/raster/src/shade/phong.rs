//! `phong`: normals and world positions interpolated, the normal renormalized, the full model
//! per pixel (Phong 1975: normal-vector interpolation shading). With `BUMP`, the normal is
//! perturbed by the height field in the tangent frame first.

use glam::{Vec2, Vec3, Vec4};
#[cfg(target_arch = "x86_64")]
use phosphor_lighting::{Vec3s, shade_lanes};
use phosphor_lighting::{Vec3x4, f32x4, shade, shade_x4};

use super::{Lit, Mode, Passes, TriVertices, VertexIn, get3, halves, join, surface_attrs};
use crate::bump::BumpMap;
use crate::clip::Attrs;
use crate::scanline::{BandTarget, ByPixel, Kernel, traverse};
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
    fn shade_pixels(&self, pass: &ByPixel, color: &mut [Vec3]) -> u64 {
        if !BUMP && self.lit.avx2.is_some() {
            pass.shade::<8>(color, |a, count| self.shade8(a, count))
        } else {
            pass.shade::<4>(color, |a, count| self.shade4(a, count))
        }
    }
}

impl<const FX: u32, const BUMP: bool> Phong<'_, FX, BUMP> {
    /// The colours of eight pixels (lanes past `count` repeat lane 0): one AVX2 task where
    /// the frame runs eight lanes, else two calls of [`Mode::shade4`].
    #[inline]
    fn shade8(&self, attrs: &[Attrs; 8], count: usize) -> [Vec3; 8] {
        #[cfg(target_arch = "x86_64")]
        if let (false, Some(avx2)) = (BUMP, self.lit.avx2) {
            return avx2.run(Shade8::<FX> {
                lit: &self.lit,
                attrs,
            });
        }
        let (lo, hi) = halves(attrs);
        join(
            self.shade4(&lo, count.min(4)),
            self.shade4(&hi, count.saturating_sub(4)),
        )
    }
}

/// Eight pixels of `Phong` without bump mapping, as one AVX2 task.
#[cfg(target_arch = "x86_64")]
struct Shade8<'a, const FX: u32> {
    lit: &'a Lit<'a>,
    attrs: &'a [Attrs; 8],
}

#[cfg(target_arch = "x86_64")]
impl<const FX: u32> phosphor_lighting::Avx2Task for Shade8<'_, FX> {
    type Output = [Vec3; 8];
    #[inline(always)]
    fn run(self, s: phosphor_lighting::Avx2) -> [Vec3; 8] {
        // Position and normal are attributes 0..6 of each pixel: one 8 x 8 transpose of the
        // pixels' first eight attributes gives them as lanes.
        let rows: [[f32; 8]; 8] = std::array::from_fn(|k| {
            let mut row = [0.0; 8];
            row.copy_from_slice(&self.attrs[k][..8]);
            row
        });
        let c = s.transpose(rows);
        let (p, n) = (Vec3s::new(c[0], c[1], c[2]), Vec3s::new(c[3], c[4], c[5]));
        // Bit for bit `shade` in every lane.
        let lit = self.lit;
        shade_lanes::<FX, _>(lit.set, &lit.mat, p, n, lit.eye).to_vecs()
    }
}
