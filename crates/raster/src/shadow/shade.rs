//! Shading a receiver of shadow maps: the lights with maps are shaded one by one and their
//! diffuse and specular light scaled by the map's visibility at the pixel; ambient, emission
//! and the other lights are untouched.
//!
//! A receiver is drawn per pixel whatever its mode: a shadow's edge crosses triangles, and
//! `flat` or `gouraud` would smear it over them (one visibility per triangle or per vertex).
//! `fast-phong`'s quadratics do not follow a shadow either. `reference` traces an exact shadow
//! ray in `f64` per pixel and light where it is given the casters' triangles
//! ([`ShadowLight::rays`]), and otherwise shades in `f32` here, with the maps. A texture and
//! vertex colours scale the ambient and diffuse light as in the tinted modes. A receiver with
//! a bump map or vertex colours takes the wide form of the shader, whose varyings leave no
//! room for the texture's mip level: it samples the finest level, as tinted `phong` does.

use phosphor_lighting::{Effects, Lanes, LightSet, SeenLights, Vec3s, shade_terms_lanes_seen};

use super::ShadowMap;
use super::cube::CubeShadow;
use super::rays::{Occluders, RayTarget};
use crate::bump::BumpMap;
use crate::shader::{Shader, Varyings, VertexLanes, put_vec3, uv_derivatives, vec3_at};
use crate::shaders::Lit;
use crate::shaders::reference::RayLight;
use crate::shaders::tinted::times;
use crate::texture::Texture;

/// One light with a map, as a receiver sees it.
#[derive(Debug, Clone, Copy)]
pub struct ShadowLight<'a> {
    /// The light alone (ambient zero).
    pub set: &'a LightSet,
    /// Its map, or its cube map's faces.
    pub maps: LightMaps<'a>,
    /// Its casters' triangles, for `reference`'s exact shadow rays. A `reference` draw whose
    /// shadowed lights all have them traces rays; otherwise it looks up the maps like the
    /// other modes.
    pub rays: Option<&'a Occluders>,
    /// The caster of `rays` whose triangles the draw's rays pass by: the receiver itself
    /// where it cannot shadow itself (see [`super::rays`]).
    pub rays_skip: Option<usize>,
}

impl LightMaps<'_> {
    /// Where the light is, for a shadow ray: the position of a perspective view, the direction
    /// towards an orthographic one's light.
    #[must_use]
    pub fn target(&self) -> RayTarget {
        match self {
            LightMaps::One(map) => match map.light().projection {
                super::Projection::Orthographic { .. } => {
                    RayTarget::Direction(map.light().toward.as_dvec3())
                }
                super::Projection::Perspective { .. } => {
                    RayTarget::Position(map.light().toward.as_dvec3())
                }
            },
            LightMaps::Cube(cube) => RayTarget::Position(cube.position.as_dvec3()),
        }
    }
}

/// The maps of one light.
#[derive(Debug, Clone, Copy)]
pub enum LightMaps<'a> {
    /// One map: a directional light's box, a spot's cone, or a point light's single cone.
    One(&'a ShadowMap),
    /// A point light's cube map.
    Cube(CubeShadow<'a>),
}

impl LightMaps<'_> {
    /// How much of the light reaches each lane's point `p` with normal `n` (see
    /// [`ShadowMap::visibility`] and [`CubeShadow::visibility`]).
    #[inline(always)]
    #[must_use]
    pub fn visibility_lanes<L: Lanes>(&self, p: Vec3s<L>, n: Vec3s<L>) -> L {
        match self {
            LightMaps::One(map) => map.visibility_lanes(p, n),
            LightMaps::Cube(cube) => cube.visibility_lanes(p, n),
        }
    }
}

/// Per-pixel shading with shadows for effect set `FX`. Varyings: world position 0..3,
/// normal 3..6, uv 6..8; the `WIDE` form adds the tangent 8..12 and the vertex colour 12..15
/// (and then samples the texture's finest level, as the tinted Phong mode does). One wide form
/// serves bump maps and vertex colours alike, so that receivers add no second copy of the
/// shader per effect set.
#[derive(Debug, Clone, Copy)]
pub struct Shadowed<'a, const FX: u32, const WIDE: bool> {
    /// The lights without maps, the material, the viewer.
    pub lit: Lit<'a>,
    /// The lights with maps.
    pub shadowed: &'a [ShadowLight<'a>],
    /// The colour map, if any.
    pub texture: Option<&'a Texture>,
    /// The height field (used only when `WIDE`).
    pub bump: Option<&'a BumpMap>,
    /// Whether the vertex colours tint the surface (used only when `WIDE`).
    pub colored: bool,
}

impl<const FX: u32, const WIDE: bool> Shader for Shadowed<'_, FX, WIDE> {
    const VARYINGS: usize = if WIDE { 15 } else { 8 };
    const GRADIENTS: Option<usize> = if WIDE { None } else { Some(6) };
    type Stepped = ();
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        let mut out = crate::shaders::phong::surface_varyings(v, true);
        if WIDE {
            put_vec3(&mut out, 12, v.color);
        }
        out
    }
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        let (p, geometric) = (vec3_at(v, 0), vec3_at(v, 3));
        let mut n = geometric;
        if let (true, Some(map)) = (WIDE, self.bump) {
            n = crate::shaders::phong::perturbed(map, n, v);
        }
        let lit = &self.lit;
        // One lighting pass: the normal and the view made once for the lights with maps too.
        let at = Receiving {
            lights: self.shadowed,
            p,
            geometric,
        };
        let terms = shade_terms_lanes_seen::<FX, L, _>(lit.set, &at, &lit.mat, (p, n, lit.eye));
        let like = v[0];
        // No closures here: one the compiler leaves out of line is compiled without the
        // caller's AVX2, and every lane operation in it becomes a call.
        let texel = match self.texture {
            Some(texture) => {
                let d = if WIDE {
                    [like.splat(0.0); 4]
                } else {
                    uv_derivatives::<Self, L>(v)
                };
                Some(texture.sample_lanes(v[6], v[7], d))
            }
            None => None,
        };
        let color = if WIDE && self.colored {
            Some(vec3_at(v, 12))
        } else {
            None
        };
        if texel.is_none() && color.is_none() {
            terms.total()
        } else {
            terms.modulated(times(texel, color, like))
        }
    }
}

/// The lights with maps at one group of pixels: their visibility at the surface points `p`
/// with the geometric normal (the map holds the surface, not its bumps).
struct Receiving<'a, L> {
    lights: &'a [ShadowLight<'a>],
    p: Vec3s<L>,
    geometric: Vec3s<L>,
}

impl<L: Lanes> SeenLights<L> for Receiving<'_, L> {
    #[inline(always)]
    fn count(&self) -> usize {
        self.lights.len()
    }
    #[inline(always)]
    fn lights(&self, k: usize) -> &LightSet {
        self.lights[k].set
    }
    #[inline(always)]
    fn seen(&self, k: usize) -> L {
        self.lights[k].maps.visibility_lanes(self.p, self.geometric)
    }
}

/// Draws `d` with its lights `shadowed` (each with a map) shadowed: `rest` holds the draw's
/// other lights and its ambient, `d.lights` all of them (used when no light has a map).
pub(crate) fn draw(
    frame: &mut crate::Frame,
    d: &crate::DrawItem,
    rest: &LightSet,
    shadowed: &[ShadowLight],
) {
    if shadowed.is_empty() {
        return frame.draw_item(d);
    }
    if d.mode == crate::ShadingMode::Reference {
        let rays: Option<Vec<RayLight>> = shadowed
            .iter()
            .map(|s| {
                s.rays.map(|occluders| RayLight {
                    set: s.set,
                    target: s.maps.target(),
                    occluders,
                    skip: s.rays_skip,
                })
            })
            .collect();
        if let Some(rays) = rays {
            return crate::shaders::reference::draw_shadowed(frame, d, rest, &rays);
        }
    }
    let n = d.mesh.positions.len();
    let has_frame =
        d.mesh.uvs.is_some_and(|u| u.len() == n) && d.mesh.tangents.is_some_and(|t| t.len() == n);
    let bump = d
        .bump
        .filter(|_| has_frame && d.effects.contains(Effects::BUMP));
    let lit = Lit::new(rest, d.material, d.effects, frame.eye());
    let texture = d.texture;
    let colored = d.mesh.colors.is_some_and(|c| c.len() == n);
    let (mesh, model, cull) = (&d.mesh, d.model, d.cull_backfaces);
    if bump.is_some() || colored {
        crate::with_fx!(d.effects, FX => frame.draw(mesh, model,
            &Shadowed::<FX, true> { lit, shadowed, texture, bump, colored }, cull))
    } else {
        crate::with_fx!(d.effects, FX => frame.draw(mesh, model,
            &Shadowed::<FX, false> { lit, shadowed, texture, bump: None, colored }, cull))
    }
}
