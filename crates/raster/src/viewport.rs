//! The image a draw is projected onto and how it is split into bands: what every stage
//! needs to know of the target, in one place.

use glam::Vec4;

use crate::clip::{ClipVertex, guard_band, inside_clip_volume};
use crate::setup::{ScreenPos, ScreenVertex, attr_scale, project, to_screen};

/// Pixel rows per band. A multisampled image's bands hold this many rows of pixels, `block`
/// sample rows each ([`band_rows`]): bands of the same pixel rows keep the same split of the
/// work over threads, and a triangle is set up in no more bands than without multisampling.
pub const BAND_ROWS: u32 = 16;

/// Scan lines per band of an image with `block x block` samples per pixel (1: none).
#[must_use]
pub const fn band_rows(block: u32) -> u32 {
    BAND_ROWS * block
}

/// The image a draw is projected onto.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Viewport {
    /// Image width in pixels (or samples).
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The guard band's extent in clip space ([`guard_band`]).
    pub guard: (f32, f32),
    /// Whether attributes are divided by `w` (perspective-correct interpolation).
    pub perspective: bool,
    /// Scan lines per band ([`band_rows`]).
    pub band_rows: u32,
}

impl Viewport {
    /// A `width` x `height` image with `block x block` samples per pixel (1: one).
    pub fn new(width: u32, height: u32, perspective: bool, block: u32) -> Viewport {
        Viewport {
            width,
            height,
            guard: guard_band(width, height),
            perspective,
            band_rows: band_rows(block),
        }
    }

    /// Whether `pos` is finite and inside every clip plane (a triangle of three such
    /// vertices is not changed by clipping).
    #[inline]
    fn inside(&self, pos: Vec4) -> bool {
        pos.is_finite() && inside_clip_volume(pos, self.guard)
    }

    /// Divide and viewport of `cv` with `n` attributes, with no clip-volume test (for the
    /// corners clipping made, which lie on its planes).
    #[inline]
    pub fn project(&self, cv: &ClipVertex, n: usize) -> Option<ScreenVertex> {
        to_screen(cv, self.width, self.height, n, self.perspective)
    }

    /// The screen position of a vertex inside the clip volume and the scale of its
    /// attributes (`1/w` when perspective-correct, else 1): the bits of [`to_screen`].
    #[inline]
    pub(crate) fn screen_pos(&self, pos: Vec4) -> Option<(ScreenPos, f32)> {
        if !self.inside(pos) {
            return None;
        }
        let (p, rhw) = project(pos, self.width, self.height, self.perspective)?;
        Some((p, attr_scale(rhw, self.perspective)))
    }
}
