//! Overlays: lines drawn over a finished frame, for seeing what the shading hides.
//!
//! - [`wireframe`]: every triangle edge, or only the crease edges ([`Edges`]). It is how the
//!   triangles behind Gouraud's Mach bands are seen.
//! - [`Grid`]: a ground grid on the plane under the scene, in round steps.
//! - [`axes`]: the world's axes as a small triad in the lower-left corner, turning with the
//!   view.
//!
//! An overlay changes only the colours of the pixels its lines cross: depths, and so
//! [`Framebuffer::coverage`](crate::Framebuffer::coverage) and the alpha of a transparent
//! background, stay as drawn. It costs one pass over its lines after the frame and nothing
//! while shading.
//!
//! A line is clipped to the view volume in clip space (`-w <= x, y, z <= w`, Liang and
//! Barsky 1984), projected as the triangles are, and drawn by columns or rows, whichever it
//! spans more of, one step per pixel centre along that axis. [`LineStyle::smooth`] off: the
//! one pixel holding the line's exact point at that centre is written. On: the two pixels
//! whose centres straddle the exact point share it, weighted by their distance to it (the
//! weights sum to 1), and the line's colour is blended in by that weight (Wu 1991's
//! anti-aliased lines). Lines in the scene ([`wireframe`], [`Grid`]) are depth-tested: a
//! pixel takes the line where the line's depth (normalised depth is affine in screen space
//! along a straight segment) is at most the stored depth plus [`DEPTH_BIAS`] times the
//! distance left to the far plane. The tolerance is relative because the stored depth is the
//! pixel centre's, up to a pixel from the line, and normalised depth crowds towards 1 with
//! distance. The triad of [`axes`] is drawn on top.
//!
//! ```
//! use glam::{Mat4, Vec3};
//! use phosphor_lighting::{Effects, Light, LightSet, Material};
//! use phosphor_raster::overlay::{self, Edges, LineStyle};
//! use phosphor_raster::*;
//!
//! let positions = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
//! let (normals, indices) = ([Vec3::Z; 3], [[0u32, 1, 2]]);
//! let lights = LightSet::new(Vec3::splat(0.1), &[Light::directional(-Vec3::Z, Vec3::ONE).unwrap()]);
//! let material = Material::s1();
//! let draw = DrawItem {
//!     mesh: MeshView::new(&positions, &normals, &indices),
//!     model: Mat4::IDENTITY,
//!     material: &material,
//!     lights: &lights,
//!     effects: Effects::ALL,
//!     mode: ShadingMode::Gouraud,
//!     bump: None,
//!     texture: None,
//!     cull_backfaces: false,
//! };
//! let mut fb = Framebuffer::new(64, 48).unwrap();
//! let camera = Camera::s1();
//! render(&mut fb, &camera, &[draw], &RenderOptions::default());
//! let red = LineStyle { color: Vec3::X, smooth: false };
//! let written = overlay::wireframe(&mut fb, &camera, &[draw], Edges::All, red);
//! assert!(written > 40); // three edges, one pixel per column or row
//! overlay::axes(&mut fb, &camera, true);
//! ```

mod edges;
mod guides;
mod line;

pub use edges::{Edges, edge_list, wireframe};
pub use guides::{AXIS_COLORS, Grid, axes};

use glam::Vec3;

/// The depth tolerance of a line in the scene, as a share of the distance from the stored
/// depth to the far plane in normalised depth (about 1% of the distance to the camera with a
/// perspective projection).
pub const DEPTH_BIAS: f32 = 0.01;

/// How an overlay's lines look.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineStyle {
    /// Linear RGB, clamped to the framebuffer's range (NaN as 0).
    pub color: Vec3,
    /// Anti-aliased: two pixels share each step by their distance to the exact line, instead
    /// of one taking it whole. A frame drawn with anti-aliasing wants smooth lines.
    pub smooth: bool,
}

/// The overlays of a frame, drawn in one call by [`Overlays::draw`]. The default draws none.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Overlays {
    /// The wireframe's edges and colour.
    pub wireframe: Option<(Edges, Vec3)>,
    /// The colour of a [`Grid::under`] the draws.
    pub grid: Option<Vec3>,
    /// The triad of [`axes`].
    pub axes: bool,
}

impl Overlays {
    /// No overlay asked for.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        *self == Overlays::default()
    }

    /// Draws the grid, then the wireframe, then the axes (each over the ones before) over
    /// `fb`, a frame of `draws` seen by `camera`; `smooth` lines for a frame drawn with
    /// anti-aliasing. Returns the pixels written.
    pub fn draw(
        &self,
        fb: &mut crate::Framebuffer,
        camera: &crate::Camera,
        draws: &[crate::DrawItem],
        smooth: bool,
    ) -> u64 {
        let mut written = 0;
        if let Some(color) = self.grid {
            if let Some(grid) = Grid::under(draws) {
                written += grid.draw(fb, camera, LineStyle { color, smooth });
            }
        }
        if let Some((edges, color)) = self.wireframe {
            written += wireframe(fb, camera, draws, edges, LineStyle { color, smooth });
        }
        if self.axes {
            written += axes(fb, camera, smooth);
        }
        written
    }
}
