//! The shader contract: what a shading mode computes per vertex, per triangle and per pixel.
//! The rasterizer owns everything else (clipping, coverage, depth, bands, passes, batching
//! pixels into lanes, SIMD dispatch) and picks, triangle by triangle, the pass that draws it
//! from what the shader declares.
//!
//! A [`Shader`] has three stages:
//!
//! * **per vertex**, [`Shader::vertex`]: up to [`MAX_VARYINGS`] values (the *varyings*) from
//!   the world-space vertex ([`VertexLanes`]), one vertex per lane;
//! * **per triangle**, optional, as [`Shader::FACE`] declares: nothing (the varyings are
//!   interpolated, [`Face::Interpolated`]), one constant colour ([`Face::Constant`],
//!   [`Shader::constant`], several triangles per call in lanes) or per-triangle data with up
//!   to [`MAX_QUADRATICS`] quadratics in screen `x, y` that the rasterizer steps along each
//!   span by forward differences ([`Face::Stepped`], [`Shader::stepped`]);
//! * **per pixel**, [`Shader::pixel`]: a colour from the interpolated varyings, one pixel per
//!   lane ([`Shader::stepped_pixel`] for stepped triangles).
//!
//! Every stage is generic over the lane type `L: Lanes` (one type parameter, no width in any
//! name): the rasterizer calls it with [`F32x1`](phosphor_lighting::F32x1) (one value),
//! [`f32x4`](phosphor_lighting::f32x4) or, on CPUs with AVX2, eight lanes, and because every
//! lane operation is the IEEE one, the picture is the same at every width. Lanes past the
//! pixels of a batch hold copies of its first; their colours are dropped. Mark the stages
//! `#[inline(always)]`: the rasterizer compiles each call for the lane width it runs, and a
//! stage that is not inlined there runs, correctly, at the baseline width's speed.
//!
//! Attributes are interpolated perspective-correctly unless the frame asks for screen-space
//! interpolation; a direction (a normal) arrives not renormalized. Every colour is clamped to
//! `[0, 1]` with NaN mapped to 0 on its way to the framebuffer.
//!
//! A normal visualiser, drawn through [`crate::Frame`]:
//!
//! ```
//! use glam::{Mat4, Vec3};
//! use phosphor_lighting::{Lanes, Vec3s};
//! use phosphor_raster::{Camera, Frame, Framebuffer, MeshView, RenderOptions};
//! use phosphor_raster::shader::{Shader, VertexLanes, Varyings};
//!
//! /// Colours each pixel by its normal, mapped from [-1, 1] to [0, 1].
//! struct Normals;
//!
//! impl Shader for Normals {
//!     const VARYINGS: usize = 3;
//!     type Stepped = ();
//!     #[inline(always)]
//!     fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
//!         let mut out = [v.normal.x.splat(0.0); 16];
//!         (out[0], out[1], out[2]) = (v.normal.x, v.normal.y, v.normal.z);
//!         out
//!     }
//!     #[inline(always)]
//!     fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
//!         let half = v[0].splat(0.5);
//!         Vec3s::new(v[0] * half + half, v[1] * half + half, v[2] * half + half)
//!     }
//! }
//!
//! let positions = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
//! let normals = [Vec3::Z; 3];
//! let mesh = MeshView::new(&positions, &normals, &[[0, 1, 2]]);
//! let mut fb = Framebuffer::new(64, 48)?;
//! let mut frame = Frame::new(&mut fb, &Camera::s1(), &RenderOptions::default());
//! frame.draw(&mesh, Mat4::IDENTITY, &Normals, false);
//! let stats = frame.finish();
//! assert_eq!(stats.triangles_drawn, 1);
//! assert!((fb.pixel(32, 24) - Vec3::new(0.5, 0.5, 1.0)).length() < 1e-6);
//! # Ok::<(), phosphor_raster::RasterError>(())
//! ```

use glam::Vec3;
use phosphor_lighting::{Lanes, Vec3s};

/// The most varyings a shader may write per vertex: a world position, a normal, a texture
/// coordinate, a tangent and a colour fit.
pub const MAX_VARYINGS: usize = 16;

/// The most quadratics a stepped triangle carries ([`Stepped`]).
pub const MAX_QUADRATICS: usize = 8;

/// The varyings of one vertex or pixel per lane; a shader uses the first
/// [`Shader::VARYINGS`] and the rest are ignored.
pub type Varyings<L> = [L; MAX_VARYINGS];

/// A vertex as the vertex stage hands it to [`Shader::vertex`], one vertex per lane, in world
/// space.
#[derive(Debug, Clone, Copy)]
pub struct VertexLanes<L> {
    /// World position.
    pub position: Vec3s<L>,
    /// World normal: unit, or zero where the mesh's was degenerate.
    pub normal: Vec3s<L>,
    /// Texture coordinate (zero when the mesh has none).
    pub uv: [L; 2],
    /// World tangent (`x, y, z`, unit) and handedness (`w`, +1 or -1); zero when the mesh
    /// has none.
    pub tangent: [L; 4],
    /// The vertex colour, linear RGB (white when the mesh has none).
    pub color: Vec3s<L>,
}

/// The three corners of one triangle per lane, for [`Shader::constant`].
#[derive(Debug, Clone, Copy)]
pub struct TriangleLanes<L> {
    /// The corners, counter-clockwise seen from the front.
    pub corners: [VertexLanes<L>; 3],
}

/// What a shader computes per triangle ([`Shader::FACE`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Face {
    /// Nothing: every pixel is [`Shader::pixel`] of the interpolated varyings.
    Interpolated,
    /// One colour per triangle, [`Shader::constant`]; the pixel stage is not run and the
    /// varyings are not interpolated (the shader should declare none).
    Constant,
    /// [`Shader::stepped`] per triangle: its data and quadratics, and each pixel
    /// [`Shader::stepped_pixel`]; a triangle for which it returns `None` is drawn as
    /// [`Face::Interpolated`].
    Stepped,
}

/// A quadratic in screen pixels about an origin `(ox, oy)`:
/// `c[0] + c[1] u + c[2] v + c[3] u^2 + c[4] u v + c[5] v^2` with `u = x - ox`, `v = y - oy`
/// (Bishop and Weimer 1986's `T0 + T2 x + T1 y + T5 x^2 + T4 xy + T3 y^2`). The rasterizer
/// evaluates it at each span's first pixel and steps it along the span by forward
/// differences, two additions per pixel, in `f64`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Quadratic(pub [f64; 6]);

impl Quadratic {
    /// The value at offset `(u, v)` from the origin.
    #[inline]
    #[must_use]
    pub fn at(&self, u: f64, v: f64) -> f64 {
        let c = &self.0;
        c[0] + u * (c[1] + c[3] * u + c[4] * v) + v * (c[2] + c[5] * v)
    }

    /// The value at `(u, v)`, its first forward difference `q(u + 1, v) - q(u, v)` and its
    /// (constant) second difference along `u`.
    #[inline]
    #[must_use]
    pub fn differences(&self, u: f64, v: f64) -> [f64; 3] {
        let c = &self.0;
        [
            self.at(u, v),
            c[1] + c[3] * (2.0 * u + 1.0) + c[4] * v,
            2.0 * c[3],
        ]
    }
}

/// A stepped triangle: the shader's data and the quadratics the rasterizer steps for it.
#[derive(Debug, Clone)]
pub struct Stepped<T> {
    /// The quadratics' origin in pixels.
    pub origin: (f64, f64),
    /// The quadratics; the first [`Stepped::count`] are stepped.
    pub quadratics: [Quadratic; MAX_QUADRATICS],
    /// How many quadratics are in use.
    pub count: usize,
    /// The shader's own per-triangle data, handed to [`Shader::stepped_pixel`].
    pub data: T,
}

impl<T> Stepped<T> {
    /// Data with no quadratics (a shader that evaluates its pixels from `data` alone).
    #[must_use]
    pub fn constant(data: T) -> Stepped<T> {
        Stepped {
            origin: (0.0, 0.0),
            quadratics: [Quadratic::default(); MAX_QUADRATICS],
            count: 0,
            data,
        }
    }
}

/// One corner of a screen triangle ([`ScreenTriangle`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenCorner {
    /// Position in pixels (snapped to the grid coverage uses), row 0 at the top.
    pub x: f64,
    /// Position in pixels.
    pub y: f64,
    /// The corner's true `1/w`.
    pub rhw: f64,
    /// The varyings [`Shader::vertex`] gave this corner (of the clipped polygon's corner when
    /// the triangle was clipped), not divided by `w`.
    pub varyings: [f64; MAX_VARYINGS],
}

/// A triangle as [`Shader::stepped`] sees it: three screen corners, in the mesh's order.
#[derive(Debug, Clone, Copy)]
pub struct ScreenTriangle {
    /// The corners.
    pub corners: [ScreenCorner; 3],
    /// Whether the varyings are interpolated perspective-correctly (else linearly in screen
    /// space).
    pub perspective: bool,
}

impl ScreenTriangle {
    /// The area in pixels.
    #[must_use]
    pub fn area(&self) -> f64 {
        let [a, b, c] = &self.corners;
        0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)).abs()
    }

    /// The weights of the corners' varyings at screen barycentrics `l` (which sum to 1):
    /// `l_i rhw_i / sum_j l_j rhw_j` when perspective-correct, else `l` itself.
    #[must_use]
    pub fn weights(&self, l: [f64; 3]) -> [f64; 3] {
        if !self.perspective {
            return l;
        }
        let q: [f64; 3] = std::array::from_fn(|i| l[i] * self.corners[i].rhw);
        let s = q[0] + q[1] + q[2];
        if s.abs() > 1e-300 {
            q.map(|x| x / s)
        } else {
            l
        }
    }

    /// Varying `k` at screen barycentrics `l`, interpolated as the rasterizer does.
    #[must_use]
    pub fn varying(&self, l: [f64; 3], k: usize) -> f64 {
        let w = self.weights(l);
        (0..3).map(|i| w[i] * self.corners[i].varyings[k]).sum()
    }
}

/// The centres of the pixels of a batch, one per lane (`x + 0.5`, `y + 0.5`).
#[derive(Debug, Clone, Copy)]
pub struct Pixels<L> {
    /// Column centres.
    pub x: L,
    /// Row centres.
    pub y: L,
}

/// A shading mode: see the module docs. The built-in modes are in [`crate::shaders`].
pub trait Shader: Sync {
    /// How many varyings [`Shader::vertex`] writes (at most [`MAX_VARYINGS`]).
    const VARYINGS: usize;
    /// The per-triangle stage.
    const FACE: Face = Face::Interpolated;
    /// Whether each pixel is shaded exactly once, after a depth pass has found the nearest
    /// triangle (the default), rather than as each triangle is drawn. A shader whose pixel
    /// stage costs less than finding the nearest triangle first (interpolated colours) says
    /// false; the picture is the same.
    const SHADE_ONCE: bool = true;
    /// The per-triangle data of [`Face::Stepped`] (`()` otherwise).
    type Stepped: Send + Sync;
    /// `Some(k)`: the pixel stage needs the screen-space derivatives of varyings `k` and
    /// `k + 1` (texture coordinates, for a mip level). The rasterizer then fills the
    /// [`GRADIENT_SLOTS`] varyings after the shader's own, read by [`uv_derivatives`]; so
    /// `VARYINGS + GRADIENT_SLOTS` must not exceed [`MAX_VARYINGS`].
    const GRADIENTS: Option<usize> = None;

    /// The varyings of one vertex per lane. Called only for the vertices of triangles the
    /// draw records (not culled, not degenerate, on screen), grouped into lanes in any way:
    /// each lane's result must depend on its own vertex alone.
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L>;

    /// The colour of one triangle per lane ([`Face::Constant`]).
    #[inline(always)]
    fn constant<L: Lanes>(&self, t: &TriangleLanes<L>) -> Vec3s<L> {
        Vec3s::broadcast(t.corners[0].position.x, Vec3::ZERO)
    }

    /// [`Face::Stepped`]: triangles covering fewer pixels than this are drawn as
    /// [`Face::Interpolated`] without calling [`Shader::stepped`] (the area is known before
    /// any corner is fetched).
    #[inline]
    fn min_stepped_area(&self) -> f64 {
        0.0
    }

    /// [`Face::Stepped`]: the triangle's data and quadratics, or `None` to draw it as
    /// [`Face::Interpolated`] (counted as a fallback in [`crate::RenderStats::fallbacks`]).
    #[inline]
    fn stepped(&self, t: &ScreenTriangle) -> Option<Stepped<Self::Stepped>> {
        let _ = t;
        None
    }

    /// The colour of one pixel per lane from its interpolated varyings.
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L>;

    /// The colour of one pixel per lane of a stepped triangle: its data, its quadratics'
    /// values at the pixel (the first [`Stepped::count`]), its varyings and its centre.
    #[inline(always)]
    fn stepped_pixel<L: Lanes>(
        &self,
        data: &Self::Stepped,
        quadratics: &[L; MAX_QUADRATICS],
        v: &Varyings<L>,
        at: &Pixels<L>,
    ) -> Vec3s<L> {
        let _ = (data, quadratics, at);
        self.pixel(v)
    }
}

/// Varyings the rasterizer adds for [`Shader::GRADIENTS`].
pub const GRADIENT_SLOTS: usize = 6;

/// The varyings the rasterizer interpolates for `S`: its own and the gradient slots.
#[must_use]
pub const fn interpolated<S: Shader>() -> usize {
    match S::GRADIENTS {
        Some(_) => S::VARYINGS + GRADIENT_SLOTS,
        None => S::VARYINGS,
    }
}

/// `[du/dx, dv/dx, du/dy, dv/dy]` per lane for a shader whose [`Shader::GRADIENTS`] is
/// `Some(k)`, with `u = v[k]`, `v = v[k + 1]`: exact for the perspective-correct (or, in
/// screen-space interpolation, affine) interpolation of the pixel's own triangle.
///
/// With `u = U / R` (`U` and `R = 1/w` affine in screen space),
/// `du/dx = (U_x - u R_x) / R`; the gradient slots hold `U_x, V_x, U_y, V_y, R_x, R_y`
/// times `w`.
#[inline(always)]
#[must_use]
pub fn uv_derivatives<S: Shader, L: Lanes>(v: &Varyings<L>) -> [L; 4] {
    let k: usize = S::GRADIENTS.unwrap_or_default();
    let g = S::VARYINGS;
    let (u, vv) = (v[k], v[k + 1]);
    [
        v[g] - u * v[g + 4],
        v[g + 1] - vv * v[g + 4],
        v[g + 2] - u * v[g + 5],
        v[g + 3] - vv * v[g + 5],
    ]
}

/// `v[at..at + 3]` as a vector of lanes.
#[inline(always)]
#[must_use]
pub fn vec3_at<L: Lanes>(v: &Varyings<L>, at: usize) -> Vec3s<L> {
    Vec3s::new(v[at], v[at + 1], v[at + 2])
}

/// Writes `x` to `v[at..at + 3]`.
#[inline(always)]
pub fn put_vec3<L: Lanes>(v: &mut Varyings<L>, at: usize, x: Vec3s<L>) {
    v[at] = x.x;
    v[at + 1] = x.y;
    v[at + 2] = x.z;
}
