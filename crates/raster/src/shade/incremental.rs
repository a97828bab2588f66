//! The incremental scan line as a selectable interpolation ([`crate::Interpolation`]): any
//! mode `M` whose per-pixel kernel reads only interpolated attributes (`gouraud`, `phong`),
//! drawn with [`traverse_incremental`] instead of the plane evaluation. Coverage and depth are
//! the same; only the attribute values come from the walk (Gouraud 1971's
//! `I' = I + (I2 - I1)/(y1 - y2)` between scan lines and a constant increment along each span,
//! in `f32`).

use super::{Mode, Passes, TriInput, TriVertices, VertexIn};
use crate::clip::Attrs;
use crate::scanline::{BandTarget, IncrementalTri, Kernel, traverse_incremental};
use crate::setup::RasterTri;

/// Mode `M` with the incremental scan line. The triangle data is the three screen vertices
/// the walk starts from.
#[derive(Debug, Clone, Copy)]
pub struct Incremental<M> {
    /// The mode whose vertex stage and kernel are used.
    pub inner: M,
}

impl<M> Mode for Incremental<M>
where
    M: Mode + Kernel<Tri = ()>,
{
    const ATTRS: usize = <M as Mode>::ATTRS;
    type Tri = Option<IncrementalTri>;
    // Attributes come from the walk, not from planes: no by-pixel pass.
    const PASSES: Passes = match M::PASSES {
        Passes::Single => Passes::Single,
        Passes::DepthFirst | Passes::ByPixel => Passes::DepthFirst,
    };
    const INPUT: TriInput = TriInput::Screen;
    const VERTEX_BATCH: bool = M::VERTEX_BATCH;
    fn vertex(&self, v: &VertexIn) -> Attrs {
        self.inner.vertex(v)
    }
    fn vertex4(&self, v: [&VertexIn; 4]) -> [Attrs; 4] {
        self.inner.vertex4(v)
    }
    fn vertex8(&self, v: [&VertexIn; 8]) -> [Attrs; 8] {
        self.inner.vertex8(v)
    }
    fn triangle(&self, v: TriVertices<'_>, _perspective: bool) -> Option<IncrementalTri> {
        // The renderer hands the screen vertices (INPUT); without them nothing is drawn.
        let TriVertices::Screen(screen) = v else {
            return None;
        };
        Some(IncrementalTri {
            xy: screen.map(|v| (v.x, v.y)),
            inv_w: screen.map(|v| v.inv_w as f32),
            attrs: screen.map(|v| v.attrs),
        })
    }
    fn draw(&self, t: &RasterTri, tri: &Option<IncrementalTri>, target: &mut BandTarget) -> u64 {
        tri.as_ref().map_or(0, |tri| {
            traverse_incremental(t, &self.inner, &(), tri, target)
        })
    }
    fn finish(&self, target: &mut BandTarget) {
        self.inner.finish(target);
    }
}
