//! The scan-line rasterizer of Phosphor and its shading modes.
//!
//! The pipeline per draw: vertex stage (model, view, projection with glam's right-handed
//! look-at and OpenGL perspective), homogeneous clipping against the near plane and a guard
//! band (`clip`), perspective divide, viewport and 1/256-pixel snapping (`setup`), optional
//! back-face culling, then traversal by scan line and span over each triangle's bounding box
//! (`scanline`, integer edge functions) in horizontal bands in parallel (`bands`) with a
//! z-buffer (depth in `[0, 1]`, less-than test, the far plane not drawn). Per-pixel modes draw a
//! band in two passes, depth first, so each pixel is shaded once, and shade four pixels at a
//! time, or eight with AVX2 detected at run time ([`simd`]; `phosphor_lighting::shade_lanes`,
//! bit-identical to the scalar model at every width).
//!
//! Conventions (`docs/conventions.md`): row 0 at the top, pixel centres at `(x + 0.5, y + 0.5)`, front faces
//! counter-clockwise. Coverage follows a top-left rule for spans: rows `ceil(y0 - 0.5) ..
//! ceil(y2 - 0.5)`, pixels `[ceil(xl - 0.5), ceil(xr - 0.5))`, evaluated exactly in integers,
//! so a pixel centre on an edge shared by two triangles is drawn exactly once. Attributes are
//! perspective-correct by default (`A/w` and `1/w` stepped, divided per pixel); with
//! [`RenderOptions::perspective_correct`] off they are stepped linearly in screen space, the
//! classic approximation of interpolating in two dimensions (Gouraud 1971, Phong 1975).
//!
//! Shading modes ([`ShadingMode`]): `flat`, `gouraud`, `phong`, `fast-phong` (a quadratic per
//! triangle, Bishop and Weimer 1986's Taylor expansion or a six-point fit,
//! [`RenderOptions::fast_phong`], with a per-triangle fallback to `phong`) and `reference`
//! (f64, exact). The stage modules named above are internal; `docs/architecture.md` describes
//! them. [`bump`] holds bump mapping; [`overlay`] draws wireframes, a grid and axes over a
//! finished frame. Every colour written is checked finite (debug) and clamped to `[0, 1]`.
//!
//! ```
//! use glam::{Mat4, Vec3};
//! use phosphor_lighting::{Effects, Light, LightSet, Material};
//! use phosphor_raster::*;
//!
//! // One triangle facing the S1 camera, lit from the front.
//! let positions = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
//! let normals = [Vec3::Z; 3];
//! let indices = [[0u32, 1, 2]];
//! let lights = LightSet::new(Vec3::splat(0.1), &[Light::directional(-Vec3::Z, Vec3::ONE).unwrap()]);
//! let material = Material::s1();
//! let draw = DrawItem {
//!     mesh: MeshView::new(&positions, &normals, &indices),
//!     model: Mat4::IDENTITY,
//!     material: &material,
//!     lights: &lights,
//!     effects: Effects::ALL,
//!     mode: ShadingMode::Phong,
//!     bump: None,
//!     texture: None,
//!     cull_backfaces: false,
//! };
//! let mut fb = Framebuffer::new(64, 48).unwrap();
//! let stats = render(&mut fb, &Camera::s1(), &[draw], &RenderOptions::default());
//! assert_eq!(stats.triangles_drawn, 1);
//! assert!(fb.pixel(32, 24).x > 0.5); // the centre is covered and lit
//! assert_eq!(fb.pixel(0, 0), Vec3::ZERO); // the corner is background
//! ```

#![cfg_attr(test, allow(clippy::unwrap_used))]
#![allow(
    clippy::needless_range_loop,
    reason = "attribute loops walk a prefix 0..n of several parallel fixed arrays"
)]

use std::fmt;
use std::str::FromStr;

use glam::{Mat4, Vec2, Vec3, Vec4};
use phosphor_lighting::{Effects, LightSet, Material};

pub mod antialias;
pub(crate) mod bands;
pub(crate) mod batch;
pub(crate) mod bin;
pub mod bump;
pub(crate) mod bypixel;
pub mod camera;
pub(crate) mod clip;
pub(crate) mod coverage;
pub mod encode;
pub mod framebuffer;
pub(crate) mod group;
pub(crate) mod incremental;
pub(crate) mod multisample;
pub mod overlay;
pub(crate) mod parallel;
mod pipeline;
pub(crate) mod records;
mod render;
pub(crate) mod setup;
pub mod shader;
pub mod shaders;
pub mod shadow;
pub mod simd;
pub(crate) mod span;
pub(crate) mod stepped;
pub mod texture;
pub(crate) mod traverse;
pub(crate) mod two_pass;
pub(crate) mod vertex;
pub(crate) mod viewport;

#[cfg(test)]
mod tests;

pub use antialias::{Antialias, UnknownAntialias};
pub use bump::{BumpMap, ProceduralBump};
pub use camera::{Camera, Projection};
pub use encode::{Encoding, ToneMap};
pub use framebuffer::{Framebuffer, PixelLayout, RasterError, Shown, WindowBuffer};
pub use render::{Frame, coverage_counts, render, render_fill_only, render_into};
pub use shader::Shader;
pub use shaders::check::FAST_PHONG_TOLERANCE;
pub use shaders::taylor::MAX_TAYLOR_LIGHTS;
pub use shadow::{ShadowLight, ShadowMap};
pub use simd::{SimdLevel, UnknownSimdLevel};
pub use texture::{Filter, Texture, TextureError, Wrap};

/// The shading modes; names as used by the CLI and scene files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShadingMode {
    /// Once per triangle, face normal, at the centroid.
    Flat,
    /// At the vertices, intensities interpolated.
    Gouraud,
    /// Normals and positions interpolated, full model per pixel.
    Phong,
    /// Quadratic polynomials per triangle by forward differences ([`FastPhongMethod`]: Bishop
    /// and Weimer 1986's Taylor expansion, or a six-point fit); falls back to `phong`.
    FastPhong,
    /// f64, exact, per pixel: the ground truth.
    Reference,
}

impl ShadingMode {
    /// Every mode, cheapest first.
    pub const ALL: [ShadingMode; 5] = [
        ShadingMode::Flat,
        ShadingMode::Gouraud,
        ShadingMode::FastPhong,
        ShadingMode::Phong,
        ShadingMode::Reference,
    ];

    /// The mode's name: `flat`, `gouraud`, `phong`, `fast-phong`, `reference`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ShadingMode::Flat => "flat",
            ShadingMode::Gouraud => "gouraud",
            ShadingMode::Phong => "phong",
            ShadingMode::FastPhong => "fast-phong",
            ShadingMode::Reference => "reference",
        }
    }
}

impl fmt::Display for ShadingMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown shading-mode name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown shading mode '{0}' (expected flat, gouraud, phong, fast-phong or reference)")]
pub struct UnknownShadingMode(pub String);

impl FromStr for ShadingMode {
    type Err = UnknownShadingMode;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ShadingMode::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| UnknownShadingMode(s.to_string()))
    }
}

/// How `fast-phong` builds the quadratic it steps across a triangle. Both fall back to exact
/// `phong` per triangle when their check points show more than [`FAST_PHONG_TOLERANCE`]
/// (counted in [`RenderStats::fallbacks`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum FastPhongMethod {
    /// Bishop and Weimer 1986: the diffuse term `(ax + by + c) / (dx^2 + exy + fy^2 + gx +
    /// hy + i)^(1/2)` and each light's specular cosine expanded in a Taylor series to second
    /// degree about the triangle's centroid (`T5 x^2 + T4 xy + T3 y^2 + T2 x + T1 y + T0`),
    /// the specular raised to the shininess per pixel. Light directions, attenuation and the
    /// viewer are taken at the centroid. Its set-up is tried on every triangle, so it is the
    /// slower method on meshes of small triangles.
    Taylor,
    /// A quadratic interpolating the exact terms at the three vertices and the three edge
    /// midpoints (only on triangles of at least `MIN_FIT_AREA_PX` pixels). The default: on
    /// S1 it is as accurate as `phong` and many times faster than `Taylor`.
    #[default]
    Fit,
}

impl FastPhongMethod {
    /// Both methods, the default first.
    pub const ALL: [FastPhongMethod; 2] = [FastPhongMethod::Fit, FastPhongMethod::Taylor];

    /// The method's name: `taylor` or `fit`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            FastPhongMethod::Taylor => "taylor",
            FastPhongMethod::Fit => "fit",
        }
    }
}

impl fmt::Display for FastPhongMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown fast-Phong method name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown fast-phong method '{0}' (expected taylor or fit)")]
pub struct UnknownFastPhongMethod(pub String);

impl FromStr for FastPhongMethod {
    type Err = UnknownFastPhongMethod;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        FastPhongMethod::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| UnknownFastPhongMethod(s.to_string()))
    }
}

/// How `gouraud` and `phong` carry their attributes across a triangle. Coverage and depth are
/// the same under both; `flat`, `fast-phong` and `reference` ignore it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Interpolation {
    /// Every attribute plane evaluated afresh (in `f64`) at each span start, then stepped
    /// along the span: no error accumulates down a tall triangle.
    #[default]
    Plane,
    /// The classic incremental scan line (Gouraud 1971): edge values stepped from one scan
    /// line to the next by constant increments, spans stepped per pixel, all in `f32`. Its
    /// rounding error accumulates (see `docs/numerical-stability.md`).
    Incremental,
}

impl Interpolation {
    /// Both, the default first.
    pub const ALL: [Interpolation; 2] = [Interpolation::Plane, Interpolation::Incremental];

    /// The name: `plane` or `incremental`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Interpolation::Plane => "plane",
            Interpolation::Incremental => "incremental",
        }
    }
}

impl fmt::Display for Interpolation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown interpolation name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown interpolation '{0}' (expected plane or incremental)")]
pub struct UnknownInterpolation(pub String);

impl FromStr for Interpolation {
    type Err = UnknownInterpolation;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Interpolation::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| UnknownInterpolation(s.to_string()))
    }
}

/// Borrowed mesh data for one draw (all per-vertex slices as long as `positions`).
#[derive(Debug, Clone, Copy)]
pub struct MeshView<'a> {
    /// Object-space positions.
    pub positions: &'a [Vec3],
    /// Unit normals, one per position.
    pub normals: &'a [Vec3],
    /// Texture coordinates (needed for bump mapping).
    pub uvs: Option<&'a [Vec2]>,
    /// Tangents with handedness in `w` (needed for bump mapping).
    pub tangents: Option<&'a [Vec4]>,
    /// Vertex colours, linear RGB (white without).
    pub colors: Option<&'a [Vec3]>,
    /// Triangles, counter-clockwise = front; out-of-range indices are skipped.
    pub indices: &'a [[u32; 3]],
}

impl<'a> MeshView<'a> {
    /// Positions, normals and triangles, with no uvs, tangents or colours.
    #[must_use]
    pub const fn new(
        positions: &'a [Vec3],
        normals: &'a [Vec3],
        indices: &'a [[u32; 3]],
    ) -> MeshView<'a> {
        MeshView {
            positions,
            normals,
            uvs: None,
            tangents: None,
            colors: None,
            indices,
        }
    }
}

/// One object to draw.
#[derive(Debug, Clone, Copy)]
pub struct DrawItem<'a> {
    /// The mesh.
    pub mesh: MeshView<'a>,
    /// Object to world.
    pub model: Mat4,
    /// Surface material.
    pub material: &'a Material,
    /// Lights, prepared once.
    pub lights: &'a LightSet,
    /// The terms to simulate (BUMP enables the bump map).
    pub effects: Effects,
    /// How to shade.
    pub mode: ShadingMode,
    /// Optional height field (with BUMP in `effects`, uvs and tangents in the mesh).
    pub bump: Option<&'a BumpMap>,
    /// Optional colour map (with uvs in the mesh): it scales the ambient and diffuse light,
    /// the specular highlight is added untinted ([`shaders`] says how each mode samples).
    pub texture: Option<&'a Texture>,
    /// Skip this draw's triangles facing away (clockwise on screen), as
    /// [`RenderOptions::cull_backfaces`] does for every draw. Exact only for a closed solid seen
    /// from outside; the scene's frame plan decides when that holds.
    pub cull_backfaces: bool,
}

/// Frame-wide options. The variants of the approximate modes ([`RenderOptions::fast_phong`],
/// [`RenderOptions::interpolation`]) live here rather than in [`ShadingMode`]: they change how
/// a mode computes, not what it computes, and every draw of a frame uses the same.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderOptions {
    /// Worker threads; 0 = all cores. The picture does not depend on it.
    pub threads: usize,
    /// Perspective-correct attributes (default); false = screen-space linear
    /// (Gouraud 1971, Phong 1975).
    pub perspective_correct: bool,
    /// Skip triangles facing away (clockwise on screen).
    pub cull_backfaces: bool,
    /// Clear colour.
    pub background: Vec3,
    /// Anti-aliasing (off by default): samples per pixel, see [`antialias`].
    pub antialias: Antialias,
    /// `gouraud` clamps each vertex intensity to at most 1 before interpolating (default:
    /// what is interpolated is what each vertex shows, see `docs/conventions.md`); false
    /// interpolates the model's values as Gouraud 1971 writes them and clamps only the pixel.
    /// A framebuffer that keeps intensities above 1 ([`Framebuffer::set_hdr`]) shows them at
    /// the vertices too, so there it does not apply.
    pub gouraud_vertex_clamp: bool,
    /// How `fast-phong` makes its per-triangle polynomials (default: the six-point fit; or
    /// Bishop and Weimer 1986's Taylor expansion).
    pub fast_phong: FastPhongMethod,
    /// How `gouraud` and `phong` interpolate their attributes across a triangle (default:
    /// planes evaluated at each span start).
    pub interpolation: Interpolation,
    /// The vector width of per-pixel lighting (default: the widest this CPU runs); the
    /// picture is the same at every level ([`simd`]).
    pub simd: SimdLevel,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            threads: 0,
            perspective_correct: true,
            cull_backfaces: false,
            background: Vec3::ZERO,
            antialias: Antialias::Off,
            gouraud_vertex_clamp: true,
            fast_phong: FastPhongMethod::Fit,
            interpolation: Interpolation::Plane,
            simd: SimdLevel::Auto,
        }
    }
}

/// What a frame did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RenderStats {
    /// Triangles submitted.
    pub triangles_in: u64,
    /// Triangles with at least one piece set up (not clipped away, culled or degenerate).
    pub triangles_drawn: u64,
    /// Shadings of pixels that passed the depth test: one per pixel without anti-aliasing,
    /// one per sample with supersampling, and with multisampling one per pixel and triangle in
    /// the per-pixel modes (one per sample in the others).
    pub pixels_shaded: u64,
    /// Fast-Phong triangle pieces drawn with `phong` because the fit was not good enough.
    pub fallbacks: u64,
    /// Draws whose bump map was ignored (flat/gouraud, or no uvs/tangents in the mesh).
    pub bump_ignored: u64,
    /// The anti-aliasing the frame was drawn with (see [`RenderStats::pixels_shaded`]).
    pub antialias: Antialias,
    /// The SIMD level the frame ran at ([`SimdLevel::resolve`] of the option).
    pub simd: SimdLevel,
}
