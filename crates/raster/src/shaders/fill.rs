//! Coverage and depth only, one constant colour: the fill-only speed bound.

use glam::Vec3;
use phosphor_lighting::{Lanes, Vec3s};

use crate::shader::{Face, Shader, TriangleLanes, Varyings, VertexLanes};

/// Every triangle in `color`.
#[derive(Debug, Clone, Copy)]
pub struct Fill {
    /// The colour written.
    pub color: Vec3,
}

impl Shader for Fill {
    const VARYINGS: usize = 0;
    const FACE: Face = Face::Constant;
    type Stepped = ();
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        [v.position.x.splat(0.0); crate::shader::MAX_VARYINGS]
    }
    #[inline(always)]
    fn constant<L: Lanes>(&self, t: &TriangleLanes<L>) -> Vec3s<L> {
        Vec3s::broadcast(t.corners[0].position.x, self.color)
    }
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        Vec3s::broadcast(v[0], self.color)
    }
}
