//! `phong`: normals and world positions interpolated, the normal renormalized, the full model
//! per pixel (Phong 1975: normal-vector interpolation shading), eight pixels at a time with
//! AVX2 (else four). With `BUMP`, the normal is perturbed by the height field in the tangent
//! frame first (Blinn 1978).

use glam::{Vec2, Vec3, Vec4};
use phosphor_lighting::{Lanes, Vec3s, shade_lanes};

use super::Lit;
use crate::bump::BumpMap;
use crate::shader::{MAX_VARYINGS, Shader, Varyings, VertexLanes, put_vec3, vec3_at};

/// The Phong mode for effect set `FX`, with or without bump mapping.
#[derive(Debug, Clone, Copy)]
pub struct Phong<'a, const FX: u32, const BUMP: bool> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
    /// The height field (used only when `BUMP`).
    pub bump: Option<&'a BumpMap>,
}

/// The varyings of the per-pixel modes: world position 0..3, normal 3..6, and with a tangent
/// frame uv 6..8 and tangent 8..12.
#[inline(always)]
pub fn surface_varyings<L: Lanes>(v: &VertexLanes<L>, frame: bool) -> Varyings<L> {
    let mut out = [v.position.x.splat(0.0); MAX_VARYINGS];
    put_vec3(&mut out, 0, v.position);
    put_vec3(&mut out, 3, v.normal);
    if frame {
        out[6] = v.uv[0];
        out[7] = v.uv[1];
        out[8..12].copy_from_slice(&v.tangent);
    }
    out
}

/// The normals `n` perturbed by `map` at the lanes' uvs and tangents (varyings 6..12).
#[inline(always)]
pub fn perturbed<L: Lanes>(map: &BumpMap, n: Vec3s<L>, v: &Varyings<L>) -> Vec3s<L> {
    let (u, w) = (v[6].to_lanes(), v[7].to_lanes());
    let t = [v[8], v[9], v[10], v[11]].map(Lanes::to_lanes);
    let n0 = n.to_vecs();
    let out: [Vec3; 8] = std::array::from_fn(|i| {
        if i < L::N {
            let tangent = Vec4::new(t[0][i], t[1][i], t[2][i], t[3][i]);
            map.perturb(n0[i], tangent, Vec2::new(u[i], w[i]))
        } else {
            Vec3::ZERO
        }
    });
    Vec3s::from_vecs(n.x, out)
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
