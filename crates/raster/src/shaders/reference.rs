//! `reference`: the ground truth. Per pixel, in f64, the perspective-correct barycentric
//! weights are solved exactly at the pixel centre, the surface point and normal built from
//! them, and `shade_reference` (all effects, no shortcuts) evaluated. Coverage is the same
//! fill rule as every other mode; the draw's effect set does not apply (the model is exact).

use glam::{DVec2, DVec3, Vec2, Vec3, Vec4};
use phosphor_lighting::{LightSet, Material, shade_reference};

use super::{Mode, Passes, TriInput, TriVertices, VertexIn, surface_attrs};
use crate::bump::BumpMap;
use crate::clip::{Attrs, MAX_ATTRS};
use crate::scanline::{BandTarget, Kernel, traverse};
use crate::setup::RasterTri;

/// The reference mode.
#[derive(Debug, Clone, Copy)]
pub struct Reference<'a> {
    /// Lights of the draw.
    pub set: &'a LightSet,
    /// The material (all terms).
    pub mat: Material,
    /// Viewer position.
    pub eye: DVec3,
    /// Height field, when the draw is bumped (and has uvs and tangents).
    pub bump: Option<&'a BumpMap>,
}

/// Per-triangle data: screen positions, true `1/w`, and the undivided attributes.
#[derive(Debug, Clone, Copy)]
pub struct RefTri {
    screen: [DVec2; 3],
    rhw: [f64; 3],
    attrs: [[f64; MAX_ATTRS]; 3],
    inv_area: f64,
}

impl Kernel for Reference<'_> {
    const ATTRS: usize = 0;
    type Tri = RefTri;
    type Span = ();
    #[inline]
    fn span(&self, _: &RefTri, _: f32, _: f32) {}
    fn shade(&self, t: &RefTri, _: &(), _: &Attrs, px: u32, py: u32) -> Vec3 {
        let p = DVec2::new(px as f64 + 0.5, py as f64 + 0.5);
        let [a, b, c] = t.screen;
        let cross = |u: DVec2, v: DVec2| u.x * v.y - u.y * v.x;
        // Screen-space barycentrics, then perspective-correct ones: b_i/w_i normalized.
        let l0 = cross(b - p, c - p) * t.inv_area;
        let l1 = cross(c - p, a - p) * t.inv_area;
        let l2 = 1.0 - l0 - l1;
        let q = [l0 * t.rhw[0], l1 * t.rhw[1], l2 * t.rhw[2]];
        let s = q[0] + q[1] + q[2];
        let wts = if s.abs() > 1e-300 {
            q.map(|x| x / s)
        } else {
            [l0, l1, l2]
        };
        let mut v = [0.0f64; MAX_ATTRS];
        for (k, slot) in v.iter_mut().enumerate() {
            *slot = wts[0] * t.attrs[0][k] + wts[1] * t.attrs[1][k] + wts[2] * t.attrs[2][k];
        }
        let point = DVec3::new(v[0], v[1], v[2]);
        let mut normal = DVec3::new(v[3], v[4], v[5]);
        if let Some(map) = self.bump {
            let t4 = Vec4::new(v[8] as f32, v[9] as f32, v[10] as f32, v[11] as f32);
            let uv = Vec2::new(v[6] as f32, v[7] as f32);
            normal = map.perturb(normal.as_vec3(), t4, uv).as_dvec3();
        }
        shade_reference(self.set, &self.mat, point, normal, self.eye).as_vec3()
    }
    #[inline]
    fn step(_: &mut ()) {}
}

impl Mode for Reference<'_> {
    const ATTRS: usize = 12;
    type Tri = Option<RefTri>;
    const PASSES: Passes = Passes::DepthFirst;
    const INPUT: TriInput = TriInput::Screen;
    fn vertex(&self, v: &VertexIn) -> Attrs {
        surface_attrs(v)
    }
    fn triangle(&self, v: TriVertices<'_>, perspective: bool) -> Option<RefTri> {
        // The renderer hands the screen vertices (INPUT); without them nothing is drawn.
        let TriVertices::Screen(v) = v else {
            return None;
        };
        let screen = v.map(|s| DVec2::new(s.x, s.y));
        let rhw = v.map(|s| s.rhw);
        let attrs = v.map(|s| {
            // Undo the traversal's division by w (when perspective-correct).
            let scale = if perspective { 1.0 / s.rhw } else { 1.0 };
            s.attrs.map(|a| a as f64 * scale)
        });
        let [a, b, c] = screen;
        let area = (b - a).perp_dot(c - a);
        Some(RefTri {
            screen,
            rhw,
            attrs,
            inv_area: if area != 0.0 { 1.0 / area } else { 0.0 },
        })
    }
    fn draw(&self, t: &RasterTri, tri: &Option<RefTri>, target: &mut BandTarget) -> u64 {
        tri.as_ref().map_or(0, |tri| traverse(t, self, tri, target))
    }
}
