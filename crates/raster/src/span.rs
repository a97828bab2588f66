//! What a traversal does at each covered pixel ([`SpanShade`]): the one contract between the
//! walkers ([`crate::traverse`], [`crate::incremental`]) and what they shade with, kept apart
//! so that the shades ([`crate::stepped`] among them) and the walkers import it one way.

use glam::Vec3;

use crate::clip::Attrs;

/// What a traversal does at each covered pixel that passes its test.
pub(crate) trait SpanShade {
    /// Attributes read (a prefix of [`Attrs`]).
    const ATTRS: usize;
    /// Per-span state.
    type Span;
    /// State at the first pixel of a span whose centre is `(x, y)` in pixels.
    fn span(&self, x: f64, y: f64) -> Self::Span;
    /// Shades pixel `idx` of the band, at column `x` of row `y`, whose attributes are
    /// `attrs` times `w` (the perspective divide), into `color`.
    fn pixel(
        &mut self,
        span: &Self::Span,
        idx: usize,
        attrs: (&Attrs, f32),
        at: (i64, i64),
        color: &mut [Vec3],
    );
    /// Moves the span state one pixel to the right.
    fn step(span: &mut Self::Span);
    /// Shades what is still waiting (batched kernels), after the triangle or the band.
    #[inline(always)]
    fn flush(&mut self, color: &mut [Vec3]) {
        let _ = color;
    }
}
