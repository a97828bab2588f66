//! `reference`: the ground truth. Per pixel, in f64, the perspective-correct barycentric
//! weights are solved exactly at the pixel centre, the surface point and normal built from
//! them, and `shade_reference` (all effects, no shortcuts) evaluated. Coverage is the same
//! fill rule as every other mode; the draw's effect set does not apply (the model is exact).

use glam::{DVec2, DVec3, Vec2, Vec3, Vec4};
use phosphor_lighting::{Lanes, LightSet, Material, Vec3s, shade_reference_tinted};

use super::phong::surface_varyings;
use crate::bump::BumpMap;
use crate::shader::{
    Face, MAX_QUADRATICS, MAX_VARYINGS, Pixels, ScreenTriangle, Shader, Stepped, Varyings,
    VertexLanes, put_vec3,
};
use crate::shadow::rays::{Occluders, RayTarget};
use crate::texture::Texture;

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
    /// Colour map, sampled in `f64` with its filter at the exact screen derivatives of the
    /// perspective-correct texture coordinates.
    pub texture: Option<&'a Texture>,
    /// Whether the mesh has vertex colours (varyings 12..15).
    pub colors: bool,
    /// Lights with shadows, each added where its exact shadow ray is clear (`set` holds the
    /// others and the ambient).
    pub shadowed: &'a [RayLight<'a>],
    /// The material for the lights of `shadowed`: ambient and emission zeroed (counted once,
    /// with `set`).
    pub direct: Material,
}

/// A light with shadows as `reference` draws it: its light alone, where it is, and what can
/// block it.
#[derive(Debug, Clone, Copy)]
pub struct RayLight<'a> {
    /// The light alone (ambient zero).
    pub set: &'a LightSet,
    /// Its position or direction.
    pub target: RayTarget,
    /// Its casters' triangles.
    pub occluders: &'a Occluders,
    /// The caster among them whose triangles never block (the receiver itself, where it
    /// cannot shadow itself).
    pub skip: Option<usize>,
}

/// Per-triangle data: screen positions, true `1/w`, and the varyings (not divided by `w`).
#[derive(Debug, Clone, Copy)]
pub struct RefTri {
    screen: [DVec2; 3],
    rhw: [f64; 3],
    attrs: [[f64; MAX_VARYINGS]; 3],
    inv_area: f64,
}

impl Reference<'_> {
    /// The exact colour at pixel centre `p` of triangle `t`.
    fn at(&self, t: &RefTri, p: DVec2) -> Vec3 {
        let [a, b, c] = t.screen;
        let cross = |u: DVec2, v: DVec2| u.x * v.y - u.y * v.x;
        // Screen-space barycentrics, then perspective-correct ones: b_i/w_i normalized.
        // The perspective-correct weights at `p`, and the sums `sum_i l_i rhw_i` and
        // `sum_i l_i rhw_i u_i, ... v_i` (affine in `p`) that the derivatives need.
        let at = |p: DVec2| {
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
            let uv = |k: usize| q[0] * t.attrs[0][k] + q[1] * t.attrs[1][k] + q[2] * t.attrs[2][k];
            (wts, [s, uv(6), uv(7)])
        };
        let (wts, sums) = at(p);
        let v: [f64; 15] = std::array::from_fn(|k| {
            wts[0] * t.attrs[0][k] + wts[1] * t.attrs[1][k] + wts[2] * t.attrs[2][k]
        });
        let point = DVec3::new(v[0], v[1], v[2]);
        let mut normal = DVec3::new(v[3], v[4], v[5]);
        if let Some(map) = self.bump {
            let t4 = Vec4::new(v[8] as f32, v[9] as f32, v[10] as f32, v[11] as f32);
            let uv = Vec2::new(v[6] as f32, v[7] as f32);
            normal = map.perturb(normal.as_vec3(), t4, uv).as_dvec3();
        }
        let mut tint = DVec3::ONE;
        if self.colors {
            tint = DVec3::new(v[12], v[13], v[14]);
        }
        if let Some(texture) = self.texture {
            // u = N / D with N and D affine: du/dx = (N_x - u D_x) / D.
            let (sx, sy) = (at(p + DVec2::X).1, at(p + DVec2::Y).1);
            let d = |s2: [f64; 3], k: usize, uv: f64| {
                let den = sums[0];
                if den.abs() > 1e-300 {
                    ((s2[k] - sums[k]) - uv * (s2[0] - sums[0])) / den
                } else {
                    0.0
                }
            };
            let (u, w) = (v[6], v[7]);
            let derivs = [d(sx, 1, u), d(sx, 2, w), d(sy, 1, u), d(sy, 2, w)];
            tint *= texture.sample_f64(u, w, derivs);
        }
        let mut colour = shade_reference_tinted(self.set, &self.mat, point, normal, self.eye, tint);
        for light in self.shadowed {
            if light.occluders.visibility(point, light.target, light.skip) > 0.0 {
                colour +=
                    shade_reference_tinted(light.set, &self.direct, point, normal, self.eye, tint);
            }
        }
        colour.as_vec3()
    }
}

impl Shader for Reference<'_> {
    const VARYINGS: usize = 15;
    const FACE: Face = Face::Stepped;
    type Stepped = RefTri;
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        let mut out = surface_varyings(v, true);
        put_vec3(&mut out, 12, v.color);
        out
    }
    fn stepped(&self, t: &ScreenTriangle) -> Option<Stepped<RefTri>> {
        let screen = t.corners.map(|c| DVec2::new(c.x, c.y));
        let [a, b, c] = screen;
        let area = (b - a).perp_dot(c - a);
        Some(Stepped::constant(RefTri {
            screen,
            // Always perspective-correct: the true surface point, whatever the frame
            // interpolates.
            rhw: t.corners.map(|c| c.rhw),
            attrs: t.corners.map(|c| c.varyings),
            inv_area: if area != 0.0 { 1.0 / area } else { 0.0 },
        }))
    }
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        // Every triangle is stepped.
        Vec3s::broadcast(v[0], Vec3::ZERO)
    }
    #[inline(always)]
    fn stepped_pixel<L: Lanes>(
        &self,
        t: &RefTri,
        _: &[L; MAX_QUADRATICS],
        _: &Varyings<L>,
        at: &Pixels<L>,
    ) -> Vec3s<L> {
        let (x, y) = (at.x.to_lanes(), at.y.to_lanes());
        let c: [Vec3; 8] = std::array::from_fn(|i| {
            if i < L::N {
                self.at(t, DVec2::new(f64::from(x[i]), f64::from(y[i])))
            } else {
                Vec3::ZERO
            }
        });
        Vec3s::from_vecs(at.x, c)
    }
}

/// Draws `d` exactly into `frame`: every term the draw's effects keep, in f64.
pub(crate) fn draw(frame: &mut crate::Frame, d: &crate::DrawItem) {
    draw_shadowed(frame, d, d.lights, &[]);
}

/// Draws `d` exactly, its lights `shadowed` each added only where its shadow ray is clear and
/// the lights of `rest` (with the ambient) everywhere.
pub(crate) fn draw_shadowed(
    frame: &mut crate::Frame,
    d: &crate::DrawItem,
    rest: &LightSet,
    shadowed: &[RayLight],
) {
    use phosphor_lighting::Effects;
    let mut mat = super::effective_material(d.material, d.effects);
    if !d.effects.contains(Effects::SPECULAR) {
        mat.ks = Vec3::ZERO;
    }
    if !d.effects.contains(Effects::FRESNEL) {
        mat.fresnel = phosphor_lighting::Fresnel::None;
    }
    let mut direct = mat;
    direct.ka = Vec3::ZERO;
    direct.emission = Vec3::ZERO;
    let shader = Reference {
        set: rest,
        mat,
        eye: frame.eye().as_dvec3(),
        bump: d.bump,
        texture: d.texture,
        colors: d.mesh.colors.is_some(),
        shadowed,
        direct,
    };
    frame.draw(&d.mesh, d.model, &shader, d.cull_backfaces);
}
