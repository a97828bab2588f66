//! Stage 1, VERTEX: every mesh vertex once (a vertex is shared by about six triangles), in
//! parallel: model, view and projection; the normal by the inverse transpose; then, eight
//! vertices at a time with AVX2 (else four), the shader's varyings ([`Shader::vertex`]) and,
//! for a vertex inside every clip plane, its snapped screen position and varyings divided by
//! `w`, stored compactly because the later stages fetch vertices from all over the mesh and a
//! compact vertex spans fewer cache lines.

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use phosphor_lighting::{F32x1, Lanes, Vec3s};

use crate::MeshView;
use crate::batch::Wide;
use crate::clip::{Attrs, ClipVertex, MAX_ATTRS};
use crate::parallel::{for_each_chunk_pair, map_indices};
use crate::setup::ScreenPos;
use crate::shader::{Shader, VertexLanes};
use crate::viewport::{LANES, Viewport};

/// One mesh vertex in world space, as the vertex stage hands it on. Laid out in order (the
/// first eight floats are position, normal and uv, the next seven tangent and colour), so that
/// eight vertices become lanes by two transposes ([`gather`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
pub struct VertexIn {
    /// World position.
    pub world: Vec3,
    /// World normal (unit, or zero when the input was degenerate).
    pub normal: Vec3,
    /// Texture coordinate (zero without uvs).
    pub uv: Vec2,
    /// World tangent with handedness in `w` (zero without tangents).
    pub tangent: Vec4,
    /// Vertex colour (white without colours).
    pub color: Vec3,
}

/// One draw's vertices after the vertex stage.
pub(crate) struct DrawVertices {
    /// Clip-space position and world-space vertex, per mesh vertex.
    pub clip: Vec<(Vec4, VertexIn)>,
    /// Snapped screen position per vertex ([`ScreenPos::NONE`] outside the clip volume).
    pub pos: Vec<ScreenPos>,
    /// The shader's varyings, `S::VARYINGS` per vertex (divided by `w` when perspective).
    pub attrs: Vec<f32>,
}

impl DrawVertices {
    /// Vertex `i` in clip space with `shader`'s varyings (not divided by `w`): what clipping
    /// and stepped triangles start from.
    #[inline]
    pub fn clip_vertex<S: Shader>(&self, shader: &S, i: usize) -> ClipVertex {
        ClipVertex {
            pos: self.clip[i].0,
            attrs: varyings_one(shader, &self.clip[i].1),
        }
    }
}

/// The varyings of one vertex (one lane: the bits every width gives).
#[inline]
pub(crate) fn varyings_one<S: Shader>(shader: &S, v: &VertexIn) -> Attrs {
    let out = shader.vertex(&gather(F32x1(0.0), &[v]));
    let mut a = [0.0; MAX_ATTRS];
    for k in 0..S::VARYINGS.min(MAX_ATTRS) {
        a[k] = out[k].0;
    }
    a
}

/// The vertices `v` (at most `L::N`, at least one; the last repeated) as lanes of the kind
/// of `like`: two transposes of eight floats per vertex (a half no shader reads is never
/// built).
#[inline(always)]
pub(crate) fn gather<L: Lanes>(like: L, v: &[&VertexIn]) -> VertexLanes<L> {
    let last = v.len().saturating_sub(1);
    let lo: [[f32; 8]; 8] = std::array::from_fn(|k| {
        let v = v[k.min(last)];
        let (p, n, uv) = (v.world, v.normal, v.uv);
        [p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y]
    });
    let hi: [[f32; 8]; 8] = std::array::from_fn(|k| {
        let v = v[k.min(last)];
        let (t, c) = (v.tangent, v.color);
        [t.x, t.y, t.z, t.w, c.x, c.y, c.z, 0.0]
    });
    let (a, b) = (like.columns(&lo), like.columns(&hi));
    VertexLanes {
        position: Vec3s::new(a[0], a[1], a[2]),
        normal: Vec3s::new(a[3], a[4], a[5]),
        uv: [a[6], a[7]],
        tangent: [b[0], b[1], b[2], b[3]],
        color: Vec3s::new(b[4], b[5], b[6]),
    }
}

/// Runs the vertex stage of a draw of `mesh` (`model` to world, `vp` view-projection) for
/// `shader` on `threads`.
pub(crate) fn vertex_stage<S: Shader>(
    mesh: &MeshView,
    model: Mat4,
    vp: Mat4,
    shader: &S,
    view: &Viewport,
    (threads, wide): (usize, Wide),
) -> DrawVertices {
    let clip = transform(mesh, model, vp, threads);
    let mut pos = vec![ScreenPos::NONE; clip.len()];
    let n = S::VARYINGS;
    let mut attrs = vec![0.0; clip.len() * n];
    for_each_chunk_pair(
        threads,
        &mut pos,
        &mut attrs,
        (4096, n),
        |first, pos, attrs| {
            let src = &clip[first..first + pos.len()];
            let chunk = Chunk {
                shader,
                src,
                view,
                pos,
                attrs,
            };
            #[cfg(target_arch = "x86_64")]
            if let Some(avx2) = wide.avx2 {
                avx2.run(chunk);
                return;
            }
            chunk.vary(phosphor_lighting::f32x4::ZERO);
        },
    );
    DrawVertices { clip, pos, attrs }
}

/// One parallel chunk of the vertex stage.
struct Chunk<'a, S> {
    shader: &'a S,
    src: &'a [(Vec4, VertexIn)],
    view: &'a Viewport,
    pos: &'a mut [ScreenPos],
    attrs: &'a mut [f32],
}

impl<S: Shader> Chunk<'_, S> {
    /// Positions and varyings of the chunk's vertices, `L::N` at a time.
    #[inline(always)]
    fn vary<L: Lanes>(self, like: L) {
        let n = S::VARYINGS;
        for (g, group) in self.src.chunks(L::N).enumerate() {
            let base = g * L::N;
            let mut scale = [0.0f32; LANES];
            let clip: [Vec4; LANES] = std::array::from_fn(|k| group[k.min(group.len() - 1)].0);
            let on_screen = self.view.screen_pos_lanes(
                &clip[..group.len()],
                &mut self.pos[base..base + group.len()],
                &mut scale,
            );
            if n == 0 || !on_screen {
                continue;
            }
            let refs: [&VertexIn; 8] = std::array::from_fn(|k| &group[k.min(group.len() - 1)].1);
            let out = self.shader.vertex(&gather(like, &refs[..L::N]));
            // Scaled as `to_screen` scales them (one IEEE product per value).
            let scale = like.with_lanes(scale);
            let mut cols = [[0.0f32; 8]; MAX_ATTRS];
            for k in 0..n {
                cols[k] = (out[k] * scale).to_lanes();
            }
            for (j, pos) in self.pos[base..base + group.len()].iter().enumerate() {
                if pos.is_none() {
                    continue;
                }
                let at = (base + j) * n;
                if let Some(row) = self.attrs.get_mut(at..at + n) {
                    for (k, a) in row.iter_mut().enumerate() {
                        *a = cols[k][j];
                    }
                }
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
impl<S: Shader> phosphor_lighting::Avx2Task for Chunk<'_, S> {
    type Output = ();
    #[inline(always)]
    fn run(self, s: phosphor_lighting::Avx2) {
        self.vary(s.splat(0.0));
    }
}

/// World position, normal (inverse transpose), uv, tangent and colour per vertex, with the
/// clip-space position.
fn transform(mesh: &MeshView, model: Mat4, vp: Mat4, threads: usize) -> Vec<(Vec4, VertexIn)> {
    let m3 = Mat3::from_mat4(model);
    let normal_matrix = {
        let nm = m3.inverse().transpose();
        if nm.is_finite() { nm } else { m3 }
    };
    let flip = if m3.determinant() < 0.0 { -1.0 } else { 1.0 };
    // Position and normal (zero where the mesh has none, as in a positions-only draw), with
    // the other inputs at their defaults.
    let surface = |i: usize| {
        let world = model.transform_point3(mesh.positions[i]);
        let normal = mesh
            .normals
            .get(i)
            .map_or(Vec3::ZERO, |n| (normal_matrix * *n).normalize_or_zero());
        (
            vp * world.extend(1.0),
            VertexIn {
                world,
                normal,
                uv: Vec2::ZERO,
                tangent: Vec4::ZERO,
                color: Vec3::ONE,
            },
        )
    };
    if mesh.uvs.is_none() && mesh.tangents.is_none() && mesh.colors.is_none() {
        // Most meshes: no per-vertex tests for the arrays that are absent.
        return map_indices(threads, mesh.positions.len(), 4096, surface);
    }
    map_indices(threads, mesh.positions.len(), 4096, |i| {
        let (clip, mut v) = surface(i);
        if let Some(uv) = mesh.uvs.and_then(|u| u.get(i).copied()) {
            v.uv = uv;
        }
        if let Some(t) = mesh.tangents.and_then(|t| t.get(i).copied()) {
            v.tangent = (m3 * t.truncate()).normalize_or_zero().extend(t.w * flip);
        }
        if let Some(c) = mesh.colors.and_then(|c| c.get(i).copied()) {
            v.color = c;
        }
        (clip, v)
    })
}
