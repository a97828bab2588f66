//! The shading modes. Each is a type implementing [`Mode`] (per vertex, per triangle) and a
//! [`Kernel`](crate::scanline::Kernel) (per pixel), monomorphized per effect set.
//!
//! # Effect specialization
//!
//! A draw's runtime [`Effects`] are mapped to one of six `const FX: u32` instantiations:
//! the base `AMBIENT | DIFFUSE | EMISSION | SPOT | DISTRIBUTED` plus every combination of
//! `SPECULAR`, `ATTENUATION` and (with specular) `FRESNEL`, the bits that change the
//! per-pixel cost. The cheap terms are always compiled in and switched off, where the draw
//! leaves them out, by zeroing their coefficient in a copy of the material (`ka`, `kd`,
//! `emission`; `ks` needs no copy since SPECULAR is specialized). Spot and distributed lights
//! cost nothing when the light set has none; a draw that leaves out SPOT or DISTRIBUTED while
//! its light set holds such lights still sees them (drop them from the `LightSet` instead).

use glam::{Vec2, Vec3, Vec4};
use phosphor_lighting::{Effects, Material};

use crate::clip::Attrs;
use crate::scanline::{BandTarget, ByPixel};
use crate::setup::{RasterTri, ScreenPos, ScreenVertex};

pub mod fast_phong;
pub mod flat;
pub mod gouraud;
pub mod incremental;
pub mod phong;
pub mod reference;
pub mod taylor;

/// One mesh vertex in world space, as the vertex stage hands it to a mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexIn {
    /// World position.
    pub world: Vec3,
    /// World normal (unit, or zero when the input was degenerate).
    pub normal: Vec3,
    /// Texture coordinate (zero without uvs).
    pub uv: Vec2,
    /// World tangent with handedness in `w` (zero without tangents).
    pub tangent: Vec4,
}

/// How a band draws a mode's triangles (see the bands stage).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Passes {
    /// One pass: each triangle depth-tested, shaded and written in turn (modes whose
    /// per-pixel shading costs less than a second traversal).
    Single,
    /// A depth pass recording the nearest triangle per pixel, then the triangles that own a
    /// pixel traversed again, each shading only its own pixels: every pixel shaded once.
    DepthFirst,
    /// A depth pass, then every visible pixel shaded from the id buffer alone
    /// ([`Mode::shade4`] of its interpolated attributes), with no second traversal; triangles
    /// for which [`Mode::by_pixel`] is false are traversed again as in
    /// [`Passes::DepthFirst`]. For modes whose pixels depend on nothing but the attributes.
    ByPixel,
}

/// What a mode's triangle set-up ([`Mode::triangle`]) reads besides the snapped positions.
/// The renderer fetches or builds exactly that: a dense mesh's vertices are scattered in
/// memory, and fetching them is most of the cost of accepting a triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TriInput {
    /// Nothing ([`TriVertices::Positions`]).
    Positions,
    /// The three world vertices ([`TriVertices::World`]), four triangles at a time
    /// ([`Mode::triangle4`]): for modes whose triangle data costs a lighting evaluation.
    World,
    /// The three screen vertices ([`TriVertices::Screen`]), built once per mesh vertex.
    Screen,
    /// The three screen vertices, built when the triangle is handed over (the same bits): for
    /// modes that settle nearly every triangle by [`Mode::triangle_from_positions`].
    ScreenPerTriangle,
}

/// The vertices of one triangle handed to [`Mode::triangle`], as its [`Mode::INPUT`] asks.
#[derive(Debug, Clone, Copy)]
pub enum TriVertices<'a> {
    /// For [`TriInput::Positions`].
    Positions,
    /// For [`TriInput::World`]: the mesh triangle's world vertices (of the whole triangle
    /// when it was clipped: the same plane).
    World([&'a VertexIn; 3]),
    /// For [`TriInput::Screen`] and [`TriInput::ScreenPerTriangle`]: the screen triangle's
    /// vertices (attributes divided by `w` when perspective-correct).
    Screen([&'a ScreenVertex; 3]),
}

/// Per-draw stages of a shading mode: the vertex attributes, the triangle set-up, and the
/// drawing of one set-up triangle into a band.
pub trait Mode: Sync {
    /// Attributes written by [`Mode::vertex`] and interpolated by the traversal.
    const ATTRS: usize;
    /// Per-triangle data.
    type Tri: Send + Sync;
    /// How a band draws this mode's triangles.
    const PASSES: Passes = Passes::Single;
    /// What [`Mode::triangle`] reads.
    const INPUT: TriInput = TriInput::Positions;
    /// Whether the vertex stage hands vertices over eight at a time ([`Mode::vertex8`]), for
    /// modes whose per-vertex work runs in lanes (Gouraud's lighting); otherwise one at a
    /// time ([`Mode::vertex`]), which copies no array of eight attribute sets.
    const VERTEX_BATCH: bool = false;
    /// The attributes of one vertex.
    fn vertex(&self, v: &VertexIn) -> Attrs;
    /// [`Mode::vertex`] of four vertices (modes that shade per vertex do it four at a time).
    fn vertex4(&self, v: [&VertexIn; 4]) -> [Attrs; 4] {
        v.map(|v| self.vertex(v))
    }
    /// [`Mode::vertex`] of eight vertices: by default two calls of [`Mode::vertex4`].
    fn vertex8(&self, v: [&VertexIn; 8]) -> [Attrs; 8] {
        let (lo, hi) = halves(&v);
        join(self.vertex4(lo), self.vertex4(hi))
    }
    /// Set-up for one screen triangle from the vertices its [`Mode::INPUT`] names.
    fn triangle(&self, v: TriVertices<'_>, perspective: bool) -> Self::Tri;
    /// The triangle's data from its snapped screen positions alone, when they decide it
    /// (`None`: call [`Mode::triangle`]). Checked first for a triangle inside the clip volume,
    /// so that one the positions settle costs no fetch of its vertices.
    #[inline]
    fn triangle_from_positions(&self, p: &[ScreenPos; 3]) -> Option<Self::Tri> {
        let _ = p;
        None
    }
    /// [`Mode::triangle`] of four triangles' world vertices ([`TriInput::World`]).
    fn triangle4(&self, src: [[&VertexIn; 3]; 4], perspective: bool) -> [Self::Tri; 4] {
        src.map(|v| self.triangle(TriVertices::World(v), perspective))
    }
    /// Draws the triangle's pixels inside `target`; returns the pixels shaded.
    fn draw(&self, t: &RasterTri, tri: &Self::Tri, target: &mut BandTarget) -> u64;
    /// The colours of the first `count` of four pixels with attributes `attrs` (lanes past
    /// `count` repeat lane 0); called only with [`Passes::ByPixel`].
    fn shade4(&self, attrs: &[Attrs; 4], count: usize) -> [Vec3; 4] {
        let _ = (attrs, count);
        [Vec3::ZERO; 4]
    }
    /// With [`Passes::ByPixel`]: shades the band's pixels from the id buffer
    /// ([`ByPixel::shade`]), four per call of [`Mode::shade4`] by default. A mode that shades
    /// more pixels per call overrides it, so that only that mode compiles the wider pass.
    fn shade_pixels(&self, pass: &ByPixel, color: &mut [Vec3]) -> u64 {
        pass.shade::<4>(color, |a, count| self.shade4(a, count))
    }
    /// With [`Passes::ByPixel`]: whether this triangle's pixels come from the by-pixel pass
    /// ([`Mode::shade4`] of its interpolated attributes). A triangle for which it is false is
    /// drawn by [`Mode::draw`] in a visible pass after it, over the pixels it owns (fast
    /// Phong's fitted polynomials).
    fn by_pixel(tri: &Self::Tri) -> bool {
        let _ = tri;
        true
    }
    /// Called after a band's last triangle: shades pixels still waiting in
    /// `target.pending` (kernels shading four pixels across triangles).
    fn finish(&self, target: &mut BandTarget) {
        let _ = target;
    }
    /// True when the set-up fell back to a costlier kernel (fast Phong to Phong).
    fn is_fallback(_tri: &Self::Tri) -> bool {
        false
    }
}

/// The two halves of eight items: how an eight-wide call falls back to four-wide ones.
pub(crate) fn halves<T: Copy>(v: &[T; 8]) -> ([T; 4], [T; 4]) {
    (
        std::array::from_fn(|k| v[k]),
        std::array::from_fn(|k| v[4 + k]),
    )
}

/// Two halves joined back into eight items ([`halves`]'s inverse).
pub(crate) fn join<T: Copy>(lo: [T; 4], hi: [T; 4]) -> [T; 8] {
    std::array::from_fn(|k| if k < 4 { lo[k] } else { hi[k - 4] })
}

/// The model at eight surface points at once, compiled for AVX2, when the frame runs eight
/// lanes (`lit.avx2`); `None` otherwise. Bit for bit `shade` in every lane.
#[cfg(target_arch = "x86_64")]
pub(crate) fn lit8<const FX: u32>(lit: &Lit, p: [Vec3; 8], n: [Vec3; 8]) -> Option<[Vec3; 8]> {
    Some(lit.avx2?.run(Lit8::<FX> { lit, p, n }))
}

/// No eight-lane level off x86-64.
#[cfg(not(target_arch = "x86_64"))]
pub(crate) fn lit8<const FX: u32>(_: &Lit, _: [Vec3; 8], _: [Vec3; 8]) -> Option<[Vec3; 8]> {
    None
}

/// [`lit8`] as one AVX2 task.
#[cfg(target_arch = "x86_64")]
struct Lit8<'a, const FX: u32> {
    lit: &'a Lit<'a>,
    p: [Vec3; 8],
    n: [Vec3; 8],
}

#[cfg(target_arch = "x86_64")]
impl<const FX: u32> phosphor_lighting::Avx2Task for Lit8<'_, FX> {
    type Output = [Vec3; 8];
    #[inline(always)]
    fn run(self, s: phosphor_lighting::Avx2) -> [Vec3; 8] {
        use phosphor_lighting::{Vec3s, shade_lanes};
        let w = s.splat(0.0);
        let (p, n) = (Vec3s::from_vecs(w, self.p), Vec3s::from_vecs(w, self.n));
        let lit = self.lit;
        shade_lanes::<FX, _>(lit.set, &lit.mat, p, n, lit.eye).to_vecs()
    }
}

/// Bits always compiled into a kernel (cheap, or free when the light set lacks them).
pub const BASE_FX: u32 = Effects::AMBIENT.bits()
    | Effects::DIFFUSE.bits()
    | Effects::EMISSION.bits()
    | Effects::SPOT.bits()
    | Effects::DISTRIBUTED.bits();

/// Runs `$body` with `const $fx: u32` set to the instantiation for runtime effects `$effects`
/// (see the module docs for the six instantiations).
#[macro_export]
#[doc(hidden)]
macro_rules! with_fx {
    ($effects:expr, $fx:ident => $body:expr) => {{
        use phosphor_lighting::Effects as E;
        use $crate::shade::BASE_FX;
        let e: E = $effects;
        let s = e.contains(E::SPECULAR);
        let a = e.contains(E::ATTENUATION);
        let f = s && e.contains(E::FRESNEL);
        match (s, a, f) {
            (false, false, _) => {
                const $fx: u32 = BASE_FX;
                $body
            }
            (false, true, _) => {
                const $fx: u32 = BASE_FX | E::ATTENUATION.bits();
                $body
            }
            (true, false, false) => {
                const $fx: u32 = BASE_FX | E::SPECULAR.bits();
                $body
            }
            (true, true, false) => {
                const $fx: u32 = BASE_FX | E::SPECULAR.bits() | E::ATTENUATION.bits();
                $body
            }
            (true, false, true) => {
                const $fx: u32 = BASE_FX | E::SPECULAR.bits() | E::FRESNEL.bits();
                $body
            }
            (true, true, true) => {
                const $fx: u32 =
                    BASE_FX | E::SPECULAR.bits() | E::ATTENUATION.bits() | E::FRESNEL.bits();
                $body
            }
        }
    }};
}

/// The material as the draw's effects see it: coefficients of left-out cheap terms zeroed.
#[must_use]
pub fn effective_material(mat: &Material, effects: Effects) -> Material {
    let mut m = *mat;
    if !effects.contains(Effects::AMBIENT) {
        m.ka = Vec3::ZERO;
    }
    if !effects.contains(Effects::DIFFUSE) {
        m.kd = Vec3::ZERO;
    }
    if !effects.contains(Effects::EMISSION) {
        m.emission = Vec3::ZERO;
    }
    m
}

/// Writes `v` into `attrs[at..at + 3]`.
#[inline]
pub(crate) fn put3(attrs: &mut Attrs, at: usize, v: Vec3) {
    attrs[at] = v.x;
    attrs[at + 1] = v.y;
    attrs[at + 2] = v.z;
}

/// Reads `attrs[at..at + 3]`.
#[inline]
#[must_use]
pub(crate) fn get3(attrs: &Attrs, at: usize) -> Vec3 {
    Vec3::new(attrs[at], attrs[at + 1], attrs[at + 2])
}

/// The standard attribute layout of the per-pixel modes: world position 0..3, normal 3..6,
/// uv 6..8, tangent 8..12.
#[must_use]
pub(crate) fn surface_attrs(v: &VertexIn) -> Attrs {
    let mut a = [0.0; crate::clip::MAX_ATTRS];
    put3(&mut a, 0, v.world);
    put3(&mut a, 3, v.normal);
    a[6] = v.uv.x;
    a[7] = v.uv.y;
    a[8] = v.tangent.x;
    a[9] = v.tangent.y;
    a[10] = v.tangent.z;
    a[11] = v.tangent.w;
    a
}

/// What every lit mode shades with: the draw's lights, material and viewer.
#[derive(Debug, Clone, Copy)]
pub struct Lit<'a> {
    /// Lights prepared for the draw.
    pub set: &'a phosphor_lighting::LightSet,
    /// The material, with left-out terms zeroed ([`effective_material`]).
    pub mat: Material,
    /// Viewer position (the camera eye).
    pub eye: Vec3,
    /// The AVX2 token when per-pixel lighting runs eight lanes ([`crate::SimdLevel`]).
    pub avx2: Option<crate::simd::Avx2>,
}
