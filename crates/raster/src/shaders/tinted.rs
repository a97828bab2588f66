//! Tinted draws: a mesh's vertex colours and a colour map ([`Texture`]) scale the ambient and
//! diffuse light, and the specular highlight is added untinted, as fixed-function OpenGL's
//! "modulate with separate specular" does: `(ambient + diffuse) * colour * texel + specular`.
//! A draw with neither takes the untinted modes, unchanged.
//!
//! What each mode does with the tint:
//! * `flat` lights the facet once, as always; vertex colours are averaged over the triangle
//!   and a texture is sampled per pixel (a stepped triangle with no quadratics, see
//!   [`FlatTextured`]);
//! * `gouraud` lights the vertices, folds the vertex colour into their ambient and diffuse
//!   light, interpolates that and the specular light apart, and samples a texture per pixel;
//! * `phong` (and `fast-phong`, whose quadratics do not follow a texture or a colour, so it
//!   draws a tinted object as `phong`) lights and tints every pixel;
//! * `reference` does the same in `f64`, sampling with the same filter.
//!
//! A texture's mip level comes from the exact screen derivatives of the pixel's texture
//! coordinates ([`crate::shader::uv_derivatives`]). Phong with vertex colours or a bump map
//! as well as a texture has no varyings left for them and samples the finest level (bilinear).

use glam::Vec3;
use phosphor_lighting::{Lanes, Vec3s, shade_split, shade_terms_lanes};

use super::Lit;
use crate::bump::BumpMap;
use crate::shader::{
    Face, MAX_QUADRATICS, MAX_VARYINGS, Pixels, ScreenTriangle, Shader, Stepped, TriangleLanes,
    Varyings, VertexLanes, put_vec3, uv_derivatives, vec3_at,
};
use crate::texture::Texture;

/// Whether draw `d` is tinted: it has vertex colours or a texture.
#[must_use]
pub fn is_tinted(d: &crate::DrawItem) -> bool {
    d.texture.is_some() || d.mesh.colors.is_some()
}

/// `texture` at `(u, v)` with derivatives `d` per lane, or `None` without one.
#[inline(always)]
fn texel<L: Lanes>(texture: Option<&Texture>, u: L, v: L, d: [L; 4]) -> Option<Vec3s<L>> {
    texture.map(|t| t.sample_lanes(u, v, d))
}

/// `a * b`, either missing counting as white; white when both are.
#[inline(always)]
pub(crate) fn times<L: Lanes>(a: Option<Vec3s<L>>, b: Option<Vec3s<L>>, like: L) -> Vec3s<L> {
    match (a, b) {
        (Some(a), Some(b)) => a * b,
        (Some(a), None) | (None, Some(a)) => a,
        (None, None) => Vec3s::broadcast(like, Vec3::ONE),
    }
}

/// Flat shading with vertex colours and no texture: the facet lit once, its light scaled by
/// the mean of the three corner colours.
#[derive(Debug, Clone, Copy)]
pub struct FlatColored<'a, const FX: u32> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
}

impl<const FX: u32> Shader for FlatColored<'_, FX> {
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
        let third = centroid.x.splat(1.0 / 3.0);
        let scale = |v: Vec3s<L>| Vec3s::new(v.x * third, v.y * third, v.z * third);
        let [ca, cb, cc] = t.corners.map(|c| c.color);
        let lit = &self.lit;
        shade_terms_lanes::<FX, L>(lit.set, &lit.mat, centroid, n, lit.eye)
            .modulated(scale(ca + cb + cc))
    }
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        Vec3s::broadcast(v[0], Vec3::ZERO)
    }
}

/// A flat-shaded textured triangle's light: ambient plus diffuse, and specular.
#[derive(Debug, Clone, Copy)]
pub struct FlatLight {
    /// Ambient and diffuse light of the facet, times the mean vertex colour.
    pub lit: Vec3,
    /// Specular light of the facet.
    pub specular: Vec3,
}

/// Flat shading with a texture: the facet lit once per triangle (at the centroid of the drawn,
/// possibly clipped, triangle, with its face normal), the texture sampled per pixel. Varyings:
/// world position 0..3, uv 3..5, colour 5..8.
#[derive(Debug, Clone, Copy)]
pub struct FlatTextured<'a, const FX: u32> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
    /// The colour map.
    pub texture: &'a Texture,
}

impl<const FX: u32> Shader for FlatTextured<'_, FX> {
    const VARYINGS: usize = 8;
    const FACE: Face = Face::Stepped;
    const GRADIENTS: Option<usize> = Some(3);
    type Stepped = FlatLight;
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        let mut out = [v.position.x.splat(0.0); MAX_VARYINGS];
        put_vec3(&mut out, 0, v.position);
        (out[3], out[4]) = (v.uv[0], v.uv[1]);
        put_vec3(&mut out, 5, v.color);
        out
    }
    fn stepped(&self, t: &ScreenTriangle) -> Option<Stepped<FlatLight>> {
        let p = t.corners.map(|c| {
            Vec3::new(
                c.varyings[0] as f32,
                c.varyings[1] as f32,
                c.varyings[2] as f32,
            )
        });
        let color = t.corners.map(|c| {
            Vec3::new(
                c.varyings[5] as f32,
                c.varyings[6] as f32,
                c.varyings[7] as f32,
            )
        });
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let n = phosphor_math::safe_normalize((p[1] - p[0]).cross(p[2] - p[0]), Vec3::ZERO);
        let lit = &self.lit;
        let terms = shade_split::<FX>(lit.set, &lit.mat, centroid, n, lit.eye);
        let mean = (color[0] + color[1] + color[2]) / 3.0;
        Some(Stepped::constant(FlatLight {
            lit: (terms.ambient + terms.diffuse) * mean,
            specular: terms.specular,
        }))
    }
    /// Never called: every triangle is stepped. The texture alone.
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        self.texture
            .sample_lanes(v[3], v[4], uv_derivatives::<Self, L>(v))
    }
    #[inline(always)]
    fn stepped_pixel<L: Lanes>(
        &self,
        light: &FlatLight,
        _: &[L; MAX_QUADRATICS],
        v: &Varyings<L>,
        _: &Pixels<L>,
    ) -> Vec3s<L> {
        let tex = self
            .texture
            .sample_lanes(v[3], v[4], uv_derivatives::<Self, L>(v));
        let like = v[0];
        tex * Vec3s::broadcast(like, light.lit) + Vec3s::broadcast(like, light.specular)
    }
}

/// Gouraud shading with vertex colours and no texture: each vertex's ambient and diffuse
/// light scaled by its colour, plus its specular light, interpolated.
#[derive(Debug, Clone, Copy)]
pub struct GouraudColored<'a, const FX: u32> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
    /// Clamp each vertex intensity to at most 1 before interpolating.
    pub vertex_clamp: bool,
}

/// `c` with each channel at most 1 when `clamp`.
#[inline(always)]
fn clamped<L: Lanes>(c: Vec3s<L>, clamp: bool) -> Vec3s<L> {
    if clamp {
        let one = c.x.splat(1.0);
        Vec3s::new(c.x.min_c(one), c.y.min_c(one), c.z.min_c(one))
    } else {
        c
    }
}

impl<const FX: u32> Shader for GouraudColored<'_, FX> {
    const VARYINGS: usize = 3;
    const SHADE_ONCE: bool = false;
    type Stepped = ();
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        let lit = &self.lit;
        let terms = shade_terms_lanes::<FX, L>(lit.set, &lit.mat, v.position, v.normal, lit.eye);
        let mut out = [v.position.x.splat(0.0); MAX_VARYINGS];
        put_vec3(
            &mut out,
            0,
            clamped(terms.modulated(v.color), self.vertex_clamp),
        );
        out
    }
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        vec3_at(v, 0)
    }
}

/// Gouraud shading with a texture: per vertex, ambient plus diffuse light times the vertex
/// colour (varyings 0..3) and specular light (3..6), interpolated apart; uv 6..8; the texture
/// sampled per pixel scales the first.
#[derive(Debug, Clone, Copy)]
pub struct GouraudTextured<'a, const FX: u32> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
    /// Clamp each vertex's two intensities to at most 1 before interpolating.
    pub vertex_clamp: bool,
    /// The colour map.
    pub texture: &'a Texture,
}

impl<const FX: u32> Shader for GouraudTextured<'_, FX> {
    const VARYINGS: usize = 8;
    const GRADIENTS: Option<usize> = Some(6);
    type Stepped = ();
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        let lit = &self.lit;
        let terms = shade_terms_lanes::<FX, L>(lit.set, &lit.mat, v.position, v.normal, lit.eye);
        let mut out = [v.position.x.splat(0.0); MAX_VARYINGS];
        let light = (terms.ambient + terms.diffuse) * v.color;
        put_vec3(&mut out, 0, clamped(light, self.vertex_clamp));
        put_vec3(&mut out, 3, clamped(terms.specular, self.vertex_clamp));
        (out[6], out[7]) = (v.uv[0], v.uv[1]);
        out
    }
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        let tex = self
            .texture
            .sample_lanes(v[6], v[7], uv_derivatives::<Self, L>(v));
        vec3_at(v, 0) * tex + vec3_at(v, 3)
    }
}

/// Phong shading tinted: world position 0..3, normal 3..6, uv 6..8, with `BUMP` the tangent
/// 8..12, with `COLOR` the vertex colour after. The texture's mip level needs six more
/// varyings, which only the plain textured form has room for.
#[derive(Debug, Clone, Copy)]
pub struct PhongTinted<'a, const FX: u32, const COLOR: bool, const BUMP: bool> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
    /// The colour map, if any.
    pub texture: Option<&'a Texture>,
    /// The height field (used only when `BUMP`).
    pub bump: Option<&'a BumpMap>,
}

impl<const FX: u32, const COLOR: bool, const BUMP: bool> PhongTinted<'_, FX, COLOR, BUMP> {
    /// First varying of the colour.
    const COLOR_AT: usize = if BUMP { 12 } else { 8 };
}

impl<const FX: u32, const COLOR: bool, const BUMP: bool> Shader
    for PhongTinted<'_, FX, COLOR, BUMP>
{
    const VARYINGS: usize = Self::COLOR_AT + if COLOR { 3 } else { 0 };
    const GRADIENTS: Option<usize> = if COLOR || BUMP { None } else { Some(6) };
    type Stepped = ();
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        let mut out = super::surface::surface_varyings(v, true);
        if COLOR {
            put_vec3(&mut out, Self::COLOR_AT, v.color);
        }
        out
    }
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        let (p, mut n) = (vec3_at(v, 0), vec3_at(v, 3));
        if let (true, Some(map)) = (BUMP, self.bump) {
            n = super::surface::perturbed(map, n, v);
        }
        let like = v[0];
        let d = if Self::GRADIENTS.is_some() {
            uv_derivatives::<Self, L>(v)
        } else {
            [like.splat(0.0); 4]
        };
        let tex = texel(self.texture, v[6], v[7], d);
        let color = COLOR.then(|| vec3_at(v, Self::COLOR_AT));
        let lit = &self.lit;
        shade_terms_lanes::<FX, L>(lit.set, &lit.mat, p, n, lit.eye)
            .modulated(times(tex, color, like))
    }
}

/// Draws tinted `d` flat.
pub(crate) fn draw_flat(frame: &mut crate::Frame, d: &crate::DrawItem) {
    let lit = Lit::new(d.lights, d.material, d.effects, frame.eye());
    let (mesh, model, cull) = (&d.mesh, d.model, d.cull_backfaces);
    match d.texture {
        Some(texture) => {
            crate::with_fx!(d.effects, FX => frame.draw(mesh, model, &FlatTextured::<FX> { lit, texture }, cull))
        }
        None => {
            crate::with_fx!(d.effects, FX => frame.draw(mesh, model, &FlatColored::<FX> { lit }, cull))
        }
    }
}

/// Draws tinted `d` with Gouraud shading.
pub(crate) fn draw_gouraud(frame: &mut crate::Frame, d: &crate::DrawItem) {
    let lit = Lit::new(d.lights, d.material, d.effects, frame.eye());
    let vertex_clamp = frame.options().gouraud_vertex_clamp && !frame.hdr();
    let (mesh, model, cull) = (&d.mesh, d.model, d.cull_backfaces);
    match d.texture {
        Some(texture) => crate::with_fx!(d.effects, FX => frame.draw(
            mesh,
            model,
            &GouraudTextured::<FX> { lit, vertex_clamp, texture },
            cull
        )),
        None => crate::with_fx!(d.effects, FX => frame.draw(
            mesh,
            model,
            &GouraudColored::<FX> { lit, vertex_clamp },
            cull
        )),
    }
}

/// Draws tinted `d` with Phong shading.
pub(crate) fn draw_phong(frame: &mut crate::Frame, d: &crate::DrawItem) {
    let lit = Lit::new(d.lights, d.material, d.effects, frame.eye());
    let (mesh, model, cull) = (&d.mesh, d.model, d.cull_backfaces);
    let (texture, bump) = (d.texture, d.bump);
    match (mesh.colors.is_some(), bump.is_some()) {
        (false, false) => crate::with_fx!(d.effects, FX => frame.draw(
            mesh, model, &PhongTinted::<FX, false, false> { lit, texture, bump }, cull)),
        (true, false) => crate::with_fx!(d.effects, FX => frame.draw(
            mesh, model, &PhongTinted::<FX, true, false> { lit, texture, bump }, cull)),
        (false, true) => crate::with_fx!(d.effects, FX => frame.draw(
            mesh, model, &PhongTinted::<FX, false, true> { lit, texture, bump }, cull)),
        (true, true) => crate::with_fx!(d.effects, FX => frame.draw(
            mesh, model, &PhongTinted::<FX, true, true> { lit, texture, bump }, cull)),
    }
}
