//! The [`Mesh`] type: an indexed triangle list whose vertices are already split where surfaces
//! meet, so a renderer can interpolate `normals` without knowing about creases.

use glam::{Vec2, Vec3, Vec4};

use crate::normals::triangle_normal_f64;
use crate::texture_ref::TextureRef;

/// A material from an MTL file or a glTF material (the subset the illumination model uses),
/// with the texture maps it names.
#[derive(Clone, Debug, PartialEq)]
pub struct MtlMaterial {
    /// `newmtl` name.
    pub name: String,
    /// Ambient reflectance `Ka` (default 0).
    pub ka: Vec3,
    /// Diffuse reflectance `Kd` (default 0.8 grey).
    pub kd: Vec3,
    /// Specular reflectance `Ks` (default 0).
    pub ks: Vec3,
    /// Specular exponent `Ns` (default 1).
    pub ns: f32,
    /// Diffuse (base colour) map: MTL `map_Kd`, glTF `baseColorTexture`; it multiplies `kd`.
    pub kd_map: Option<TextureRef>,
    /// Specular colour map: MTL `map_Ks`; it multiplies `ks`.
    pub ks_map: Option<TextureRef>,
    /// Tangent-space normal map (MikkTSpace, +Y up) and its scale (MTL `norm` with `-bm`,
    /// glTF `normalTexture` with `scale`; 1 when not given).
    pub normal_map: Option<(TextureRef, f32)>,
    /// Statements and maps the file gives that Phosphor does not use (`d`, `map_d`, `bump`,
    /// `refl`, ...), each once in order of appearance, for the caller to warn about once.
    pub unused: Vec<String>,
}

impl Default for MtlMaterial {
    fn default() -> Self {
        MtlMaterial {
            name: String::from("default"),
            ka: Vec3::ZERO,
            kd: Vec3::splat(0.8),
            ks: Vec3::ZERO,
            ns: 1.0,
            kd_map: None,
            ks_map: None,
            normal_map: None,
            unused: Vec::new(),
        }
    }
}

/// An indexed triangle mesh.
///
/// Invariants kept by every constructor in this crate: `normals` has one unit, finite entry per
/// position; `uvs`, `colors` and `tangents`, when present, have one entry per position; every
/// index is in range; `surface_ids`, `material_ids` and `smoothing_groups` have one entry per triangle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// One per vertex (vertices are split where surfaces meet).
    pub positions: Vec<Vec3>,
    /// Unit, finite, same length as `positions`.
    pub normals: Vec<Vec3>,
    /// Texture coordinates, same length as `positions` when present.
    pub uvs: Option<Vec<Vec2>>,
    /// Vertex colours, linear RGB in `[0, 1]`, same length as `positions` when present (PLY
    /// `red green blue`, glTF `COLOR_0`, OBJ `v x y z r g b`; docs/mesh-formats.md).
    pub colors: Option<Vec<Vec3>>,
    /// `xyz` unit tangent (perpendicular to the normal), `w` = handedness (+1/-1) so that
    /// `bitangent = w * normal.cross(tangent)`; same length as `positions` when present.
    pub tangents: Option<Vec<Vec4>>,
    /// Triangles, counter-clockwise = front.
    pub indices: Vec<[u32; 3]>,
    /// Per triangle: the surface (connected set of triangles smoothed together) it belongs to.
    pub surface_ids: Vec<u32>,
    /// Per triangle: index into `materials` (0 when there are none).
    pub material_ids: Vec<u32>,
    /// Per triangle: the OBJ smoothing group (`s N`), 0 for `s off` or a file without `s` lines.
    pub smoothing_groups: Vec<u32>,
    /// Materials from the MTL file; may be empty.
    pub materials: Vec<MtlMaterial>,
    /// `o`/`g` names in order of first appearance, informational.
    pub groups: Vec<String>,
}

/// The centre of the bounding box of `positions` and the uniform scale that brings the
/// farthest of them to distance 1 from it, in `f64`: what [`Mesh::normalize_unit`] applies,
/// and what a scene fits several meshes' world positions with. The scale is 1 when every
/// position coincides (or a distance is not finite), and the centre the origin when there
/// is none.
///
/// ```
/// use glam::{DVec3, Vec3};
/// let (centre, scale) = phosphor_mesh::unit_fit(&[Vec3::new(-1.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0)]);
/// assert_eq!((centre, scale), (DVec3::new(1.0, 0.0, 0.0), 0.5));
/// ```
#[must_use]
pub fn unit_fit(positions: &[Vec3]) -> (glam::DVec3, f64) {
    let Some(&first) = positions.first() else {
        return (glam::DVec3::ZERO, 1.0);
    };
    let (lo, hi) = positions
        .iter()
        .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let centre = (lo.as_dvec3() + hi.as_dvec3()) * 0.5;
    let farthest = positions
        .iter()
        .map(|p| (p.as_dvec3() - centre).length())
        .fold(0.0_f64, f64::max);
    let scale = if farthest > 0.0 && farthest.is_finite() {
        1.0 / farthest
    } else {
        1.0
    };
    (centre, scale)
}

impl Mesh {
    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// The unit normal of triangle `tri` from its positions (counter-clockwise = front),
    /// computed in f64 so slivers and huge or tiny coordinates keep their direction.
    /// `None` for a zero-area (degenerate) triangle or an index out of range.
    #[must_use]
    pub fn face_normal(&self, tri: usize) -> Option<Vec3> {
        let [a, b, c] = self.triangle_positions(tri)?;
        triangle_normal_f64(a, b, c).map(|(n, _)| n.as_vec3())
    }

    /// The three corner positions of triangle `tri`, `None` when out of range.
    #[must_use]
    pub fn triangle_positions(&self, tri: usize) -> Option<[Vec3; 3]> {
        let idx = self.indices.get(tri)?;
        Some([
            *self.positions.get(idx[0] as usize)?,
            *self.positions.get(idx[1] as usize)?,
            *self.positions.get(idx[2] as usize)?,
        ])
    }

    /// Axis-aligned bounds `(min, max)` of the positions; `(0, 0)` for an empty mesh.
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut it = self.positions.iter();
        let Some(&first) = it.next() else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        it.fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)))
    }

    /// Moves the bounding-box centre to the origin and scales uniformly so that the farthest
    /// vertex is at distance 1 (S1, docs/conventions.md). Normals and tangents are unchanged (a
    /// uniform scale keeps directions). A mesh whose vertices all coincide is only translated.
    pub fn normalize_unit(&mut self) {
        let (centre, scale) = unit_fit(&self.positions);
        for p in &mut self.positions {
            *p = ((p.as_dvec3() - centre) * scale).as_vec3();
        }
    }

    /// Number of triangles whose area is zero (see [`Mesh::face_normal`]).
    #[must_use]
    pub fn degenerate_count(&self) -> usize {
        (0..self.indices.len())
            .filter(|&t| self.face_normal(t).is_none())
            .count()
    }

    /// Twice the area of triangle `tri` in f64 (0 when degenerate or out of range).
    #[must_use]
    pub fn double_area(&self, tri: usize) -> f64 {
        self.triangle_positions(tri)
            .and_then(|[a, b, c]| triangle_normal_f64(a, b, c))
            .map_or(0.0, |(_, a2)| a2)
    }

    /// True when every invariant in the type docs holds (lengths, index ranges, unit finite
    /// normals and tangents, colours in `[0, 1]`). Used by the tests; cheap enough for debug assertions.
    #[must_use]
    pub fn is_consistent(&self) -> bool {
        let n = self.positions.len();
        let t = self.indices.len();
        let unit = |v: Vec3| v.is_finite() && (v.length() - 1.0).abs() < 1e-4;
        self.normals.len() == n
            && self
                .uvs
                .as_ref()
                .is_none_or(|u| u.len() == n && u.iter().all(|x| x.is_finite()))
            && self.colors.as_ref().is_none_or(|c| {
                c.len() == n
                    && c.iter()
                        .all(|x| x.cmpge(Vec3::ZERO).all() && x.cmple(Vec3::ONE).all())
            })
            && self.tangents.as_ref().is_none_or(|ts| {
                ts.len() == n && ts.iter().all(|x| unit(x.truncate()) && x.w.abs() == 1.0)
            })
            && self.surface_ids.len() == t
            && self.material_ids.len() == t
            && self.smoothing_groups.len() == t
            && self.positions.iter().all(|p| p.is_finite())
            && self.normals.iter().all(|&v| unit(v))
            && self
                .indices
                .iter()
                .all(|tri| tri.iter().all(|&i| (i as usize) < n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalize_unit_leaves_a_single_point_finite() {
        let mut m = Mesh {
            positions: vec![Vec3::splat(5.0); 3],
            normals: vec![Vec3::Z; 3],
            indices: vec![[0, 1, 2]],
            ..Mesh::default()
        };
        m.normalize_unit();
        assert!(m.positions.iter().all(|p| *p == Vec3::ZERO));
    }
}
