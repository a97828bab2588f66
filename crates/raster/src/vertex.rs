//! Stage 1, VERTEX: every mesh vertex once (a vertex is shared by about six triangles), in
//! parallel: model, view and projection; the normal by the inverse transpose; the mode's
//! attributes; and, for a vertex inside every clip plane, its snapped screen position and
//! attributes (divided by `w`), stored compactly because the later stages fetch vertices from
//! all over the mesh and a compact vertex spans fewer cache lines.

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

use crate::DrawItem;
use crate::clip::{Attrs, ClipVertex, guard_band, inside_clip_volume};
use crate::parallel::{for_each_chunk_pair, map_indices};
use crate::setup::{ScreenPos, ScreenVertex, attr_scale, project, to_screen};
use crate::shade::{Mode, TriInput, VertexIn};

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
    /// Scan lines per band ([`crate::bin::band_rows`]).
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
            band_rows: crate::bin::band_rows(block),
        }
    }

    /// The screen vertex of `cv` with `n` attributes, when it is inside every clip plane
    /// (a triangle of three such vertices is not changed by clipping).
    #[inline]
    pub fn screen(&self, cv: &ClipVertex, n: usize) -> Option<ScreenVertex> {
        self.inside(cv.pos).then(|| self.project(cv, n)).flatten()
    }

    /// Whether `pos` is finite and inside every clip plane (see [`Viewport::screen`]).
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

    /// [`Viewport::screen`]'s position and the scale of its attributes (`1/w` when
    /// perspective-correct, else 1), with the same bits.
    #[inline]
    fn screen_pos(&self, pos: Vec4) -> Option<(ScreenPos, f32)> {
        if !self.inside(pos) {
            return None;
        }
        let (p, rhw) = project(pos, self.width, self.height, self.perspective)?;
        Some((p, attr_scale(rhw, self.perspective)))
    }
}

/// One draw's vertices after the vertex stage.
pub(crate) struct DrawVertices {
    /// Clip-space position and world-space vertex, per mesh vertex.
    pub clip: Vec<(Vec4, VertexIn)>,
    /// Snapped screen position per vertex ([`ScreenPos::NONE`] outside the clip volume).
    pub pos: Vec<ScreenPos>,
    /// The mode's attributes, `M::ATTRS` per vertex (divided by `w` when perspective).
    pub attrs: Vec<f32>,
    /// Whole screen vertices, for modes whose [`Mode::INPUT`] is [`TriInput::Screen`]
    /// (empty otherwise: a whole one is over 100 bytes).
    pub screen: Vec<Option<ScreenVertex>>,
}

impl DrawVertices {
    /// Vertex `i` in clip space with `mode`'s attributes (not divided by `w`): what clipping
    /// starts from. Its screen vertex has the bits of the one the stage stored.
    #[inline]
    pub fn clip_vertex<M: Mode>(&self, mode: &M, i: usize) -> ClipVertex {
        ClipVertex {
            pos: self.clip[i].0,
            attrs: mode.vertex(&self.clip[i].1),
        }
    }
}

/// Runs the vertex stage of draw `d` for `mode` (`vp`: view-projection) on `threads`.
pub(crate) fn vertex_stage<M: Mode>(
    d: &DrawItem,
    vp: Mat4,
    mode: &M,
    view: &Viewport,
    threads: usize,
) -> DrawVertices {
    let clip = transform(d, vp, threads);
    let mut pos = vec![ScreenPos::NONE; clip.len()];
    let mut attrs = vec![0.0; clip.len() * M::ATTRS];
    for_each_chunk_pair(
        threads,
        &mut pos,
        &mut attrs,
        (4096, M::ATTRS),
        |first, pos, attrs| {
            let src = &clip[first..first + pos.len()];
            // Position and the mode's attributes of vertex `i` (of this chunk), scaled as
            // `to_screen` scales them.
            let mut put = |i: usize, v: &Vec4, a: &Attrs| {
                if let Some((p, scale)) = view.screen_pos(*v) {
                    pos[i] = p;
                    let out = attrs.get_mut(i * M::ATTRS..(i + 1) * M::ATTRS);
                    for (o, a) in out.unwrap_or(&mut []).iter_mut().zip(a) {
                        *o = a * scale;
                    }
                }
            };
            if !M::VERTEX_BATCH {
                for (i, v) in src.iter().enumerate() {
                    put(i, &v.0, &mode.vertex(&v.1));
                }
                return;
            }
            for (g, group) in src.chunks(8).enumerate() {
                let a8 = mode.vertex8(std::array::from_fn(|k| &group[k.min(group.len() - 1)].1));
                for (j, (v, a)) in group.iter().zip(&a8).enumerate() {
                    put(8 * g + j, &v.0, a);
                }
            }
        },
    );
    let mut out = DrawVertices {
        clip,
        pos,
        attrs,
        screen: Vec::new(),
    };
    if matches!(M::INPUT, TriInput::Screen) {
        out.screen = map_indices(threads, out.clip.len(), 4096, |i| {
            view.screen(&out.clip_vertex(mode, i), M::ATTRS)
        });
    }
    out
}

/// World position, normal (inverse transpose), uv and tangent per vertex, with the
/// clip-space position.
fn transform(d: &DrawItem, vp: Mat4, threads: usize) -> Vec<(Vec4, VertexIn)> {
    let m3 = Mat3::from_mat4(d.model);
    let normal_matrix = {
        let nm = m3.inverse().transpose();
        if nm.is_finite() { nm } else { m3 }
    };
    let flip = if m3.determinant() < 0.0 { -1.0 } else { 1.0 };
    let mesh = &d.mesh;
    map_indices(threads, mesh.positions.len(), 4096, |i| {
        let world = d.model.transform_point3(mesh.positions[i]);
        let normal = mesh
            .normals
            .get(i)
            .map_or(Vec3::ZERO, |n| (normal_matrix * *n).normalize_or_zero());
        let uv = mesh
            .uvs
            .and_then(|u| u.get(i).copied())
            .unwrap_or(Vec2::ZERO);
        let tangent = mesh
            .tangents
            .and_then(|t| t.get(i).copied())
            .map_or(Vec4::ZERO, |t| {
                (m3 * t.truncate()).normalize_or_zero().extend(t.w * flip)
            });
        (
            vp * world.extend(1.0),
            VertexIn {
                world,
                normal,
                uv,
                tangent,
            },
        )
    })
}
