//! Stage 1, VERTEX, in two halves around the bin stage. First every mesh vertex once (a
//! vertex is shared by about six triangles), in parallel: model, view and projection; the
//! normal by the inverse transpose; and, for a vertex inside every clip plane, its snapped
//! screen position ([`vertex_positions`]). Then, after the bin stage has marked the vertices
//! of the triangles it recorded, only those vertices' varyings ([`Shader::vertex`], eight
//! vertices at a time with AVX2, else four), divided by `w` ([`vertex_varyings`]): a vertex
//! that only culled or off-screen triangles share is never shaded. Both are stored compactly
//! because the later stages fetch vertices from all over the mesh and a compact vertex spans
//! fewer cache lines.

use std::sync::atomic::{AtomicBool, Ordering};

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
    /// Per vertex with a screen position, what its varyings are multiplied by (`1/w` when
    /// perspective-correct, else 1: [`crate::setup::attr_scale`]); empty for a shader without
    /// varyings.
    scale: Vec<f32>,
    /// The shader's varyings, `S::VARYINGS` per vertex (divided by `w` when perspective),
    /// after [`vertex_varyings`]: only the vertices it marked hold them.
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

/// Runs the first half of the vertex stage of a draw of `mesh` (`model` to world, `vp`
/// view-projection) on `threads`: every vertex's clip-space and world-space form and its
/// screen position, and, for a shader with `varyings`, what they will be multiplied by. The
/// varyings wait for [`vertex_varyings`], which computes them only for the vertices of
/// triangles the bin stage recorded.
pub(crate) fn vertex_positions(
    mesh: &MeshView,
    model: Mat4,
    vp: Mat4,
    view: &Viewport,
    (threads, wide, varyings): (usize, Wide, bool),
) -> DrawVertices {
    let clip = transform(mesh, model, vp, (threads, wide));
    let mut pos = vec![ScreenPos::NONE; clip.len()];
    let mut scale = vec![0.0; if varyings { clip.len() } else { 0 }];
    for_each_chunk_pair(
        threads,
        &mut pos,
        &mut scale,
        (4096, usize::from(varyings)),
        |first, pos, scale| {
            let src = &clip[first..first + pos.len()];
            let chunk = Positions {
                src,
                view,
                pos,
                scale,
            };
            in_lanes(wide, chunk);
        },
    );
    DrawVertices {
        clip,
        pos,
        scale,
        attrs: Vec::new(),
    }
}

/// Marks of the vertices whose varyings a draw reads: set by the bin stage (from its parallel
/// chunks, hence atomic) for every vertex of a triangle it records unclipped.
pub(crate) struct Used(Vec<AtomicBool>);

impl Used {
    /// No vertex marked, of `len`; none at all to mark when `needed` is false (a shader without
    /// varyings).
    pub fn new(len: usize, needed: bool) -> Used {
        Used(if needed {
            (0..len).map(|_| AtomicBool::new(false)).collect()
        } else {
            Vec::new()
        })
    }

    /// The marks of a draw of `len` vertices: one per vertex, or none for a shader without
    /// varyings.
    #[inline(always)]
    pub fn marks(&self, len: usize) -> &[AtomicBool] {
        self.0.get(..len).unwrap_or(&[])
    }

    /// Marks vertex `i` of `marks` (from [`Used::marks`]; nothing when it has no such mark).
    #[inline(always)]
    pub fn mark(marks: &[AtomicBool], i: usize) {
        if let Some(u) = marks.get(i) {
            u.store(true, Ordering::Relaxed);
        }
    }
}

/// The second half of the vertex stage: `shader`'s varyings ([`Shader::vertex`]), divided by
/// `w` as [`crate::setup::to_screen`] divides them, for the vertices `used` marks (eight
/// marked vertices per call with AVX2, else four). A vertex that only back faces, off-screen
/// or degenerate triangles share is never shaded: with back faces culled that is about half a
/// closed mesh. Each vertex's values are the same bits as when
/// every vertex was shaded (the lanes are independent).
pub(crate) fn vertex_varyings<S: Shader>(
    verts: &mut DrawVertices,
    shader: &S,
    used: &Used,
    (threads, wide): (usize, Wide),
) {
    let n = S::VARYINGS;
    if n == 0 {
        return;
    }
    let mut attrs = vec![0.0; verts.clip.len() * n];
    let chunk = 4096;
    let (clip, scale) = (&verts.clip, &verts.scale);
    for_each_chunk_pair(
        threads,
        &mut attrs,
        &mut [] as &mut [u8],
        (chunk * n, 0),
        |first, attrs, _| {
            let first = first / n;
            let len = attrs.len() / n;
            let chunk = Chunk {
                shader,
                first,
                src: &clip[first..first + len],
                scale: &scale[first..first + len],
                used,
                attrs,
            };
            in_lanes(wide, chunk);
        },
    );
    verts.attrs = attrs;
}

/// A parallel chunk of the vertex stage, written once over [`Lanes`].
trait InLanes: Sized {
    /// The chunk's work, `L::N` vertices per step.
    fn lanes<L: Lanes>(self, like: L);
}

/// Runs `chunk` eight lanes wide inside an AVX2 function when the frame has the token, else
/// four wide (SSE2): the same bits either way.
#[inline(always)]
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_variables))]
fn in_lanes<T: InLanes>(wide: Wide, chunk: T) {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx2) = wide.avx2 {
        avx2.run(Avx2Lanes(chunk));
        return;
    }
    chunk.lanes(phosphor_lighting::f32x4::ZERO);
}

/// [`in_lanes`]' AVX2 task.
#[cfg(target_arch = "x86_64")]
struct Avx2Lanes<T>(T);

#[cfg(target_arch = "x86_64")]
impl<T: InLanes> phosphor_lighting::Avx2Task for Avx2Lanes<T> {
    type Output = ();
    #[inline(always)]
    fn run(self, s: phosphor_lighting::Avx2) {
        self.0.lanes(s.splat(0.0));
    }
}

/// One parallel chunk of [`vertex_positions`].
struct Positions<'a> {
    src: &'a [(Vec4, VertexIn)],
    view: &'a Viewport,
    pos: &'a mut [ScreenPos],
    /// Empty for a shader without varyings.
    scale: &'a mut [f32],
}

impl InLanes for Positions<'_> {
    /// The screen positions need no lane type of their own: an AVX2 build of this loop
    /// vectorizes it.
    #[inline(always)]
    fn lanes<L: Lanes>(self, _: L) {
        self.project();
    }
}

impl Positions<'_> {
    /// The chunk's screen positions, [`LANES`] vertices per call.
    #[inline(always)]
    fn project(self) {
        for (g, group) in self.src.chunks(LANES).enumerate() {
            let base = g * LANES;
            let mut scale = [0.0f32; LANES];
            // A whole group is read without a bound per lane; a short one repeats its last.
            let clip: [Vec4; LANES] = match group.first_chunk::<LANES>() {
                Some(g) => std::array::from_fn(|k| g[k].0),
                None => std::array::from_fn(|k| group[k.min(group.len() - 1)].0),
            };
            let range = base..base + group.len();
            self.view.screen_pos_lanes(
                &clip[..group.len()],
                &mut self.pos[range.clone()],
                &mut scale,
            );
            if let Some(s) = self.scale.get_mut(range) {
                s.copy_from_slice(&scale[..group.len()]);
            }
        }
    }
}

/// One parallel chunk of [`vertex_varyings`]: the vertices `first..` of the draw.
struct Chunk<'a, S> {
    shader: &'a S,
    first: usize,
    src: &'a [(Vec4, VertexIn)],
    scale: &'a [f32],
    used: &'a Used,
    attrs: &'a mut [f32],
}

impl<S: Shader> InLanes for Chunk<'_, S> {
    #[inline(always)]
    fn lanes<L: Lanes>(self, like: L) {
        self.vary(like);
    }
}

impl<S: Shader> Chunk<'_, S> {
    /// Varyings of the chunk's marked vertices, `L::N` of them per call.
    #[inline(always)]
    fn vary<L: Lanes>(mut self, like: L) {
        let mut group = [0usize; 8];
        let mut len = 0;
        let marks = self.used.0.get(self.first..self.first + self.src.len());
        for (j, u) in marks.unwrap_or(&[]).iter().enumerate() {
            if u.load(Ordering::Relaxed) {
                group[len] = j;
                len += 1;
                if len == L::N {
                    self.shade(like, &group[..len]);
                    len = 0;
                }
            }
        }
        if len > 0 {
            self.shade(like, &group[..len]);
        }
    }

    /// Varyings of the chunk's vertices `group` (at least one, at most `L::N`; each has a
    /// screen position, as every marked vertex does).
    #[inline(always)]
    fn shade<L: Lanes>(&mut self, like: L, group: &[usize]) {
        let n = S::VARYINGS;
        let last = group.len() - 1;
        let at = |k: usize| group[k.min(last)];
        let refs: [&VertexIn; 8] = std::array::from_fn(|k| &self.src[at(k)].1);
        let out = self.shader.vertex(&gather(like, &refs[..L::N]));
        // Scaled as `to_screen` scales them (one IEEE product per value).
        let scale = like.with_lanes(std::array::from_fn(|k| self.scale[at(k)]));
        let mut cols = [[0.0f32; 8]; MAX_ATTRS];
        for k in 0..n {
            cols[k] = (out[k] * scale).to_lanes();
        }
        for (j, &v) in group.iter().enumerate() {
            if let Some(row) = self.attrs.get_mut(v * n..(v + 1) * n) {
                for (k, a) in row.iter_mut().enumerate() {
                    *a = cols[k][j];
                }
            }
        }
    }
}

/// World position, normal (inverse transpose), uv, tangent and colour per vertex, with the
/// clip-space position.
fn transform(
    mesh: &MeshView,
    model: Mat4,
    vp: Mat4,
    (threads, wide): (usize, Wide),
) -> Vec<(Vec4, VertexIn)> {
    let m3 = Mat3::from_mat4(model);
    let normal_matrix = {
        let nm = m3.inverse().transpose();
        if nm.is_finite() { nm } else { m3 }
    };
    let flip = if m3.determinant() < 0.0 { -1.0 } else { 1.0 };
    let placement = Placement {
        model,
        normal: normal_matrix,
        vp,
    };
    let plain = mesh.uvs.is_none() && mesh.tangents.is_none() && mesh.colors.is_none();
    if plain && (mesh.normals.is_empty() || mesh.normals.len() >= mesh.positions.len()) {
        // Most meshes: positions and normals only, in lanes.
        return surfaces(mesh, &placement, (threads, wide));
    }
    map_indices(threads, mesh.positions.len(), 4096, |i| {
        let (clip, mut v) = placement.surface(mesh, i);
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

/// Where a draw's vertices go: model to world, the normals' matrix (the inverse transpose),
/// and the view-projection.
struct Placement {
    model: Mat4,
    normal: Mat3,
    vp: Mat4,
}

impl Placement {
    /// Vertex `i`'s clip-space position, world position and normal (zero where the mesh has
    /// none, as in a positions-only draw), the other inputs at their defaults: the reference
    /// [`Surfaces`] computes in lanes, and the vertex of meshes with more inputs.
    #[inline(always)]
    fn surface(&self, mesh: &MeshView, i: usize) -> (Vec4, VertexIn) {
        let world = self.model.transform_point3(mesh.positions[i]);
        let normal = mesh
            .normals
            .get(i)
            .map_or(Vec3::ZERO, |n| (self.normal * *n).normalize_or_zero());
        (
            self.vp * world.extend(1.0),
            VertexIn {
                world,
                normal,
                ..VertexIn::PLAIN
            },
        )
    }
}

impl VertexIn {
    /// The inputs a mesh without uvs, tangents or colours gives every vertex besides its
    /// position and normal.
    const PLAIN: VertexIn = VertexIn {
        world: Vec3::ZERO,
        normal: Vec3::ZERO,
        uv: Vec2::ZERO,
        tangent: Vec4::ZERO,
        color: Vec3::ONE,
    };
}

/// [`Placement::surface`] of every vertex of a mesh with positions and normals only (`normals`
/// empty or as long as `positions`), in parallel chunks, eight vertices at a time with AVX2,
/// else four: the same bits, each lane computed with the operations of glam's
/// `transform_point3`, `Mat3 * Vec3`, `normalize_or_zero` and `Mat4 * Vec4`, in their order.
fn surfaces(
    mesh: &MeshView,
    placement: &Placement,
    (threads, wide): (usize, Wide),
) -> Vec<(Vec4, VertexIn)> {
    // The output's first pass is parallel too: a large mesh's vertices are tens of megabytes.
    let mut out = map_indices(threads, mesh.positions.len(), 4096, |_| {
        (Vec4::ZERO, VertexIn::PLAIN)
    });
    for_each_chunk_pair(
        threads,
        &mut out,
        &mut [] as &mut [u8],
        (4096, 0),
        |first, out, _| {
            let range = first..first + out.len();
            let (Some(positions), normals) =
                (mesh.positions.get(range.clone()), mesh.normals.get(range))
            else {
                return;
            };
            let chunk = Surfaces {
                placement,
                positions,
                normals,
                out,
            };
            in_lanes(wide, chunk);
        },
    );
    out
}

/// One parallel chunk of [`surfaces`].
struct Surfaces<'a> {
    placement: &'a Placement,
    positions: &'a [Vec3],
    /// `None` for a mesh without normals.
    normals: Option<&'a [Vec3]>,
    out: &'a mut [(Vec4, VertexIn)],
}

impl InLanes for Surfaces<'_> {
    /// The chunk's vertices, `L::N` per step.
    #[inline(always)]
    fn lanes<L: Lanes>(self, like: L) {
        let s = |x: f32| like.splat(x);
        // Rows of the matrices: component `c` of a product is row `c` dotted with the vector.
        let (m, nm, vp) = (
            self.placement.model,
            self.placement.normal,
            self.placement.vp,
        );
        let (m0, m1, m2) = (m.row(0), m.row(1), m.row(2));
        let (n0, n1, n2) = (nm.row(0), nm.row(1), nm.row(2));
        let (v0, v1, v2, v3) = (vp.row(0), vp.row(1), vp.row(2), vp.row(3));
        let zero = s(0.0);
        for (g, out) in self.out.chunks_mut(L::N).enumerate() {
            let range = g * L::N..g * L::N + out.len();
            let Some(p) = self.positions.get(range.clone()) else {
                return;
            };
            let p = columns3(like, p);
            // transform_point3: ((x X + y Y) + z Z) + W per component.
            let w = [
                sum3(like, m0.truncate(), p) + s(m0.w),
                sum3(like, m1.truncate(), p) + s(m1.w),
                sum3(like, m2.truncate(), p) + s(m2.w),
            ];
            // Mat4 * (world, 1): the same sums, W times 1 being W.
            let clip = [
                sum3(like, v0.truncate(), w) + s(v0.w),
                sum3(like, v1.truncate(), w) + s(v1.w),
                sum3(like, v2.truncate(), w) + s(v2.w),
                sum3(like, v3.truncate(), w) + s(v3.w),
            ];
            let normal = match self.normals.and_then(|n| n.get(range)) {
                Some(n) => {
                    let n = columns3(like, n);
                    // Mat3 * Vec3, then normalize_or_zero: the reciprocal of the length (the
                    // dot product summed x, y, z), used when finite and above zero (not NaN).
                    let t = [sum3(like, n0, n), sum3(like, n1, n), sum3(like, n2, n)];
                    let rcp = s(1.0) / (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
                    let ok = rcp.cmp_ge(s(f32::from_bits(1))) & rcp.cmp_le(s(f32::MAX));
                    [
                        ok.blend(t[0] * rcp, zero),
                        ok.blend(t[1] * rcp, zero),
                        ok.blend(t[2] * rcp, zero),
                    ]
                }
                None => [zero; 3],
            };
            if let (8, Some(out)) = (L::N, out.first_chunk_mut::<8>()) {
                // Eight whole vertices: the first eight floats of each (clip, world and the
                // normal's x, in the tuple's order) are the columns of eight rows, one
                // transpose rather than a move per float.
                let rows = [
                    clip[0].to_lanes(),
                    clip[1].to_lanes(),
                    clip[2].to_lanes(),
                    clip[3].to_lanes(),
                    w[0].to_lanes(),
                    w[1].to_lanes(),
                    w[2].to_lanes(),
                    normal[0].to_lanes(),
                ];
                let cols = like.columns(&rows);
                let (ny, nz) = (normal[1].to_lanes(), normal[2].to_lanes());
                for j in 0..8 {
                    let a = cols[j].to_lanes();
                    out[j] = (
                        Vec4::new(a[0], a[1], a[2], a[3]),
                        VertexIn {
                            world: Vec3::new(a[4], a[5], a[6]),
                            normal: Vec3::new(a[7], ny[j], nz[j]),
                            ..VertexIn::PLAIN
                        },
                    );
                }
                continue;
            }
            let [wx, wy, wz] = [w[0].to_lanes(), w[1].to_lanes(), w[2].to_lanes()];
            let [nx, ny, nz] = [
                normal[0].to_lanes(),
                normal[1].to_lanes(),
                normal[2].to_lanes(),
            ];
            let [cx, cy, cz, cw] = [
                clip[0].to_lanes(),
                clip[1].to_lanes(),
                clip[2].to_lanes(),
                clip[3].to_lanes(),
            ];
            let k = out.len().min(8);
            for j in 0..k {
                out[j] = (
                    Vec4::new(cx[j], cy[j], cz[j], cw[j]),
                    VertexIn {
                        world: Vec3::new(wx[j], wy[j], wz[j]),
                        normal: Vec3::new(nx[j], ny[j], nz[j]),
                        ..VertexIn::PLAIN
                    },
                );
            }
        }
    }
}

/// The `x`, `y` and `z` of `v` (one to `L::N` vectors, the last repeated) as lanes.
#[inline(always)]
fn columns3<L: Lanes>(like: L, v: &[Vec3]) -> [L; 3] {
    let lanes = |a: &[Vec3; 8]| {
        [
            like.with_lanes(std::array::from_fn(|j| a[j].x)),
            like.with_lanes(std::array::from_fn(|j| a[j].y)),
            like.with_lanes(std::array::from_fn(|j| a[j].z)),
        ]
    };
    // A whole group of eight, read in place without a bound per lane.
    if let Some(a) = v.first_chunk::<8>() {
        return lanes(a);
    }
    let last = v.len().saturating_sub(1);
    lanes(&std::array::from_fn(|j| {
        v.get(j.min(last)).copied().unwrap_or(Vec3::ZERO)
    }))
}

/// `(k.x x + k.y y) + k.z z`, summed in glam's order.
#[inline(always)]
fn sum3<L: Lanes>(like: L, k: Vec3, [x, y, z]: [L; 3]) -> L {
    like.splat(k.x) * x + like.splat(k.y) * y + like.splat(k.z) * z
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicUsize, Ordering};

    use glam::{Mat4, Vec3};
    use phosphor_lighting::{Lanes, Vec3s};

    use super::*;
    use crate::shader::Varyings;
    use crate::tests::support::uv_sphere;
    use crate::{Camera, Frame, Framebuffer, RenderOptions, SimdLevel};

    /// Position and normal as varyings; counts the vertices [`Shader::vertex`] was called for.
    struct Counting(AtomicUsize);

    impl Shader for Counting {
        const VARYINGS: usize = 6;
        type Stepped = ();
        fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
            self.0.fetch_add(L::N, Ordering::Relaxed);
            let mut out = [v.normal.x.splat(0.0); 16];
            let (p, n) = (v.position, v.normal);
            [out[0], out[1], out[2]] = [p.x, p.y, p.z];
            [out[3], out[4], out[5]] = [n.x, n.y, n.z];
            out
        }
        fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
            let half = v[0].splat(0.5);
            Vec3s::new(v[3] * half + half, v[4] * half + half, v[5] * half + half)
        }
    }

    /// The marked vertices' varyings are the same bits whichever other vertices are marked,
    /// at both lane widths, and an unmarked vertex is never shaded (left at zero).
    #[test]
    fn varyings_of_marked_vertices_do_not_depend_on_the_others() {
        let mesh = uv_sphere(1.0, 40, 20);
        let view = Viewport::new(320, 240, true, 1);
        let vp = Camera::s1().view_proj(320.0 / 240.0);
        let shader = Counting(AtomicUsize::new(0));
        for simd in [SimdLevel::Baseline, SimdLevel::Auto] {
            let wide = Wide { avx2: simd.token() };
            let vary = |marked: &dyn Fn(usize) -> bool| {
                let mut verts =
                    vertex_positions(&mesh.view(), Mat4::IDENTITY, vp, &view, (1, wide, true));
                let used = Used::new(verts.clip.len(), true);
                for i in (0..verts.clip.len()).filter(|&i| marked(i)) {
                    Used::mark(used.marks(verts.clip.len()), i);
                }
                vertex_varyings(&mut verts, &shader, &used, (1, wide));
                verts.attrs
            };
            let marked = |i: usize| i.is_multiple_of(23) || (100..140).contains(&i);
            let all = vary(&|_| true);
            let some = vary(&marked);
            let n = Counting::VARYINGS;
            let (mut compared, mut skipped) = (0, 0);
            for i in 0..all.len() / n {
                let (a, s) = (&all[i * n..(i + 1) * n], &some[i * n..(i + 1) * n]);
                if marked(i) {
                    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(a), bits(s), "vertex {i} ({simd:?})");
                    compared += usize::from(a.iter().any(|&x| x != 0.0));
                } else {
                    assert!(s.iter().all(|&x| x == 0.0), "vertex {i} ({simd:?})");
                    skipped += usize::from(a.iter().any(|&x| x != 0.0));
                }
            }
            assert!(compared > 40, "only {compared} marked vertices on screen");
            assert!(skipped > 200, "only {skipped} vertices on screen skipped");
        }
    }

    /// The vertices [`surfaces`] computes in lanes are the bits of [`Placement::surface`], at
    /// both widths and in a partial last group: ordinary normals; zero, underflowing,
    /// overflowing and non-finite ones (all zero); a tiny one that still normalizes; and a
    /// mesh without normals.
    #[test]
    fn surfaces_in_lanes_are_the_bits_of_the_scalar_vertex() {
        let positions: Vec<Vec3> = (0..37)
            .map(|i| {
                let t = i as f32 * 0.37;
                Vec3::new(t.sin() * 3.1, t.cos() * 1.7 - 0.2, (t * 1.3).sin() + 0.5)
            })
            .collect();
        let mut normals: Vec<Vec3> = positions
            .iter()
            .map(|p| *p * 0.9 + Vec3::new(0.1, -0.3, 0.2))
            .collect();
        normals[3] = Vec3::ZERO;
        normals[4] = Vec3::splat(1e-30);
        normals[5] = Vec3::splat(1e30);
        normals[6] = Vec3::new(f32::NAN, 0.0, 1.0);
        normals[7] = Vec3::new(f32::INFINITY, 0.0, 0.0);
        normals[8] = Vec3::new(1e-20, 0.0, 0.0);
        let model = Mat4::from_scale_rotation_translation(
            Vec3::new(1.5, 0.5, 2.0),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(0.3, -1.0, 2.0),
        );
        let placement = Placement {
            model,
            normal: Mat3::from_mat4(model).inverse().transpose(),
            vp: Camera::s1().view_proj(16.0 / 9.0),
        };
        let bits = |(c, v): (Vec4, VertexIn)| {
            let f = [c.to_array(), v.world.extend(0.0).to_array()];
            let g = [v.normal.extend(0.0).to_array(), v.tangent.to_array()];
            let h = [
                v.uv.extend(0.0).extend(0.0).to_array(),
                v.color.extend(0.0).to_array(),
            ];
            let all: Vec<f32> = [f, g, h].concat().concat();
            all.into_iter().map(f32::to_bits).collect::<Vec<u32>>()
        };
        let mut normalized = 0;
        for normals in [&normals[..], &[]] {
            let mesh = MeshView::new(&positions, normals, &[]);
            let scalar: Vec<_> = (0..positions.len())
                .map(|i| bits(placement.surface(&mesh, i)))
                .collect();
            for simd in [SimdLevel::Baseline, SimdLevel::Auto] {
                let wide = Wide { avx2: simd.token() };
                let lanes: Vec<_> = surfaces(&mesh, &placement, (2, wide))
                    .into_iter()
                    .map(bits)
                    .collect();
                assert_eq!(lanes, scalar, "{simd:?}, {} normals", normals.len());
            }
            normalized += (0..positions.len())
                .filter(|&i| placement.surface(&mesh, i).1.normal != Vec3::ZERO)
                .count();
        }
        // Every normal but the five degenerate ones normalizes.
        assert_eq!(normalized, positions.len() - 5);
    }

    /// With back faces culled, a closed sphere seen from outside shades the varyings of little
    /// more than its front half, and draws the same picture as with both sides drawn.
    #[test]
    fn culled_back_faces_leave_their_vertices_unshaded() {
        let mesh = uv_sphere(1.0, 64, 32);
        let draw = |cull: bool| {
            let shader = Counting(AtomicUsize::new(0));
            let mut fb = Framebuffer::new(200, 150).expect("framebuffer");
            let opts = RenderOptions {
                threads: 2,
                ..RenderOptions::default()
            };
            let mut frame = Frame::new(&mut fb, &Camera::s1(), &opts);
            frame.draw(&mesh.view(), Mat4::IDENTITY, &shader, cull);
            frame.finish();
            let px: Vec<Vec3> = (0..150)
                .flat_map(|y| (0..200).map(move |x| (x, y)))
                .map(|(x, y)| fb.pixel(x, y))
                .collect();
            (shader.0.into_inner(), px)
        };
        let (both, both_px) = draw(false);
        let (culled, culled_px) = draw(true);
        let total = mesh.positions.len();
        assert!(
            both * 20 >= total * 19,
            "both sides: {both} of {total} vertices shaded"
        );
        assert!(
            culled * 10 < total * 7,
            "culled: {culled} of {total} vertices shaded"
        );
        assert!(both_px == culled_px, "the pictures differ");
    }
}
