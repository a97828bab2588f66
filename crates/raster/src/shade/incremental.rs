//! The incremental scan line as a selectable interpolation ([`crate::Interpolation`]): any
//! mode `M` whose per-pixel kernel reads only interpolated attributes (`gouraud`, `phong`),
//! drawn with [`traverse_incremental`] instead of the plane evaluation. Coverage and depth are
//! the same; only the attribute values come from the walk (Gouraud 1971's
//! `I' = I + (I2 - I1)/(y1 - y2)` between scan lines and a constant increment along each span,
//! in `f32`).

use super::{Mode, VertexIn};
use crate::clip::Attrs;
use crate::scanline::{BandTarget, IncrementalTri, Kernel, traverse_incremental};
use crate::setup::{RasterTri, ScreenVertex};

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
    type Tri = IncrementalTri;
    const EARLY_Z: bool = M::EARLY_Z;
    fn vertex(&self, v: &VertexIn) -> Attrs {
        self.inner.vertex(v)
    }
    fn vertex4(&self, v: [&VertexIn; 4]) -> [Attrs; 4] {
        self.inner.vertex4(v)
    }
    const READS_VERTICES: bool = false;
    fn triangle(
        &self,
        _: [&VertexIn; 3],
        screen: [&ScreenVertex; 3],
        _perspective: bool,
    ) -> IncrementalTri {
        IncrementalTri {
            xy: screen.map(|v| (v.x, v.y)),
            inv_w: screen.map(|v| v.inv_w as f32),
            attrs: screen.map(|v| v.attrs),
        }
    }
    fn draw(&self, t: &RasterTri, tri: &IncrementalTri, target: &mut BandTarget) -> u64 {
        traverse_incremental(t, &self.inner, &(), tri, target)
    }
    fn finish(&self, target: &mut BandTarget) {
        self.inner.finish(target);
    }
}
