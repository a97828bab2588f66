//! Tangents for tangent-space normal maps, by MikkTSpace.
//!
//! Normal maps baked by Blender, Substance and xNormal, and the ones glTF expects when a file
//! carries no `TANGENT`, are in MikkTSpace: the tangent frame of Mikkelsen's algorithm
//! (the `bevy_mikktspace` crate, a safe Rust port of the reference code), computed per triangle
//! corner from positions, normals and uvs. A map sampled in another frame shows seams and
//! lighting that bends the wrong way, so [`compute`] and [`Mesh::compute_tangents`] use it.
//!
//! Each tangent is `xyz` unit and perpendicular to the vertex normal, `w` the handedness
//! (+1 or -1) with `bitangent = w * normal.cross(tangent)`, as MikkTSpace's shaders rebuild it.
//! Where the corners of one vertex get different frames (uvs mirrored across a seam whose
//! vertices are shared, two fans meeting at one vertex only), [`Mesh::compute_tangents`] splits
//! the vertex so each corner keeps its own; [`compute`], which returns one tangent per vertex
//! of the arrays it is given, keeps the first corner's. A corner MikkTSpace gives no frame
//! (degenerate uvs with no usable neighbour) gets [`fallback_tangent`] of its normal.
//!
//! The analytic primitives use the uv gradient instead (see [`crate::primitives`]): on their
//! smooth parametrisations the two agree to within the tessellation, and its memory is bounded
//! by the primitives' footprint. glTF files that carry `TANGENT` keep their tangents.

mod gradient;

use std::collections::HashMap;

pub(crate) use gradient::compute as gradient_tangents;
pub(crate) use gradient::try_compute as try_gradient_tangents;

use bevy_mikktspace::{Geometry, TangentSpace};
use glam::{Vec2, Vec3, Vec4};

use crate::mesh::Mesh;

/// Tangent for bump mapping where the mesh gives no uv direction: a unit vector perpendicular
/// to `n`, continuous except on one great circle, from Duff et al., "Building an Orthonormal
/// Basis, Revisited" (JCGT 2017). `w` is +1. A non-unit or non-finite `n` is treated as +Z.
#[must_use]
pub fn fallback_tangent(n: Vec3) -> Vec4 {
    let n = phosphor_math::safe_normalize(n, Vec3::Z);
    let sign = 1.0_f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    phosphor_math::safe_normalize(t, Vec3::X).extend(1.0)
}

/// The triangles MikkTSpace reads, and the frame it writes per corner.
struct Corners<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    indices: &'a [[u32; 3]],
    /// Per corner (`triangle * 3 + k`).
    out: Vec<Option<Vec4>>,
}

impl Corners<'_> {
    /// Whether every corner of triangle `face` has a position, normal and uv.
    fn valid(&self, face: usize) -> bool {
        let n = self
            .positions
            .len()
            .min(self.normals.len())
            .min(self.uvs.len());
        self.indices
            .get(face)
            .is_some_and(|t| t.iter().all(|&i| (i as usize) < n))
    }

    /// The vertex at corner `vert` of `face` (only asked for valid faces).
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.indices[face][vert] as usize
    }
}

/// Non-finite components become 0: MikkTSpace is not asked to order NaNs.
fn finite<const N: usize>(v: [f32; N]) -> [f32; N] {
    v.map(|x| if x.is_finite() { x } else { 0.0 })
}

impl Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.indices.len()
    }
    fn num_vertices_of_face(&self, face: usize) -> usize {
        // A face of any other size is skipped by MikkTSpace.
        if self.valid(face) { 3 } else { 0 }
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        finite(self.positions[self.vertex(face, vert)].to_array())
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        finite(self.normals[self.vertex(face, vert)].to_array())
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        finite(self.uvs[self.vertex(face, vert)].to_array())
    }
    fn set_tangent(&mut self, space: Option<TangentSpace>, face: usize, vert: usize) {
        let Some(slot) = self.out.get_mut(face * 3 + vert) else {
            return;
        };
        let normal = self.normals[self.indices[face][vert] as usize];
        *slot = Some(frame(space, normal));
    }
}

/// The tangent of one corner: MikkTSpace's, made exactly perpendicular to `normal` and unit
/// in f32, else [`fallback_tangent`].
fn frame(space: Option<TangentSpace>, normal: Vec3) -> Vec4 {
    let Some(space) = space else {
        return fallback_tangent(normal);
    };
    let n = phosphor_math::safe_normalize(normal, Vec3::Z).as_dvec3();
    let t = Vec3::from_array(space.tangent()).as_dvec3();
    let t = t - n * n.dot(t);
    let len = t.length();
    if !(len > 1e-6 && len.is_finite()) {
        return fallback_tangent(normal);
    }
    let w = if space.is_orientation_preserving() {
        1.0
    } else {
        -1.0
    };
    phosphor_math::safe_normalize((t / len).as_vec3(), Vec3::X).extend(w)
}

/// MikkTSpace's tangent at every corner (`triangle * 3 + k`); corners of triangles with an
/// index out of range of any input get +X.
fn corner_tangents(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[[u32; 3]],
) -> Vec<Vec4> {
    let mut corners = Corners {
        positions,
        normals,
        uvs,
        indices,
        out: vec![None; indices.len() * 3],
    };
    // The error type has no value: generation cannot fail.
    let _ = bevy_mikktspace::generate_tangents(&mut corners);
    corners
        .out
        .into_iter()
        .map(|t| t.unwrap_or(Vec4::new(1.0, 0.0, 0.0, 1.0)))
        .collect()
}

/// One MikkTSpace tangent per position (see the module docs): where corners of a vertex
/// disagree the first corner's is kept; a vertex no valid triangle uses gets
/// [`fallback_tangent`] of its normal. `normals` and `uvs` should have one entry per position;
/// triangles with an index out of range of any input are skipped.
#[must_use]
pub fn compute(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[[u32; 3]],
) -> Vec<Vec4> {
    let corners = corner_tangents(positions, normals, uvs, indices);
    let mut out: Vec<Option<Vec4>> = vec![None; positions.len()];
    let limit = positions.len().min(normals.len()).min(uvs.len());
    for (tri, frames) in indices.iter().zip(corners.chunks_exact(3)) {
        if tri.iter().any(|&i| i as usize >= limit) {
            continue;
        }
        for (&i, &t) in tri.iter().zip(frames) {
            out[i as usize].get_or_insert(t);
        }
    }
    out.into_iter()
        .enumerate()
        .map(|(i, t)| {
            t.unwrap_or_else(|| fallback_tangent(normals.get(i).copied().unwrap_or(Vec3::Z)))
        })
        .collect()
}

impl Mesh {
    /// Fills `tangents` when there are none (or not one per position): MikkTSpace from the
    /// uvs ([`Mesh::compute_tangents`]), or without uvs [`fallback_tangent`] of each normal (any
    /// unit vector perpendicular to it, `w = +1`). Tangents already there are kept: a glTF
    /// file's authored ones, the ones a loader or primitive computed.
    pub fn ensure_tangents(&mut self) {
        let n = self.positions.len();
        if self.tangents.as_ref().is_none_or(|t| t.len() != n) {
            self.compute_tangents();
        }
    }

    /// Replaces `tangents` with MikkTSpace's from the uvs (see [`crate::tangents`]); a vertex
    /// whose corners get different frames is split, one vertex per frame (its position,
    /// normal, uv and colour copied), so `positions` may grow. Without uvs (or with uvs not one
    /// per position) each vertex gets [`fallback_tangent`] of its normal.
    pub fn compute_tangents(&mut self) {
        let n = self.positions.len();
        let normal = |normals: &[Vec3], i: usize| normals.get(i).copied().unwrap_or(Vec3::Z);
        let Some(uvs) = self.uvs.as_ref().filter(|u| u.len() == n) else {
            let frames = (0..n).map(|i| fallback_tangent(normal(&self.normals, i)));
            self.tangents = Some(frames.collect());
            return;
        };
        let corners = corner_tangents(&self.positions, &self.normals, uvs, &self.indices);
        let mut tangents: Vec<Option<Vec4>> = vec![None; n];
        // Vertices added for a second frame: (original vertex, frame bits) -> new vertex.
        let mut split: HashMap<(u32, [u32; 4]), u32> = HashMap::new();
        let mut indices = std::mem::take(&mut self.indices);
        for (tri, frames) in indices.iter_mut().zip(corners.chunks_exact(3)) {
            if tri.iter().any(|&i| i as usize >= n) {
                continue;
            }
            for (corner, &t) in tri.iter_mut().zip(frames) {
                let v = *corner as usize;
                match tangents[v] {
                    None => tangents[v] = Some(t),
                    Some(first) if first.to_array() == t.to_array() => {}
                    Some(_) => {
                        let key = (*corner, t.to_array().map(f32::to_bits));
                        *corner = *split.entry(key).or_insert_with(|| {
                            tangents.push(Some(t));
                            self.copy_vertex(v)
                        });
                    }
                }
            }
        }
        self.indices = indices;
        let frames = tangents
            .into_iter()
            .enumerate()
            .map(|(i, t)| t.unwrap_or_else(|| fallback_tangent(normal(&self.normals, i))))
            .collect();
        self.tangents = Some(frames);
    }

    /// Appends a copy of vertex `v` (every per-vertex array but `tangents`); returns its index.
    fn copy_vertex(&mut self, v: usize) -> u32 {
        fn push_copy<T: Copy>(values: &mut Vec<T>, v: usize) {
            if let Some(&x) = values.get(v) {
                values.push(x);
            }
        }
        push_copy(&mut self.positions, v);
        push_copy(&mut self.normals, v);
        if let Some(uvs) = &mut self.uvs {
            push_copy(uvs, v);
        }
        if let Some(colors) = &mut self.colors {
            push_copy(colors, v);
        }
        (self.positions.len() - 1) as u32
    }
}
