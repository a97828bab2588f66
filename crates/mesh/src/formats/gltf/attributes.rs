//! Vertex attributes beyond position, normal and uv: `COLOR_0` and `TANGENT`.

use glam::{Mat3, Vec3, Vec4};

use super::Assembly;
use crate::build::unit_color;
use crate::error::MeshError;

impl Assembly {
    /// Appends the primitive's `COLOR_0` as linear RGB in `[0, 1]` (normalized integers
    /// divided by their maximum, alpha dropped), or one white entry when it has none; returns
    /// whether it has colours.
    pub(super) fn read_colors<'a, 's, F>(
        &mut self,
        reader: &gltf::mesh::Reader<'a, 's, F>,
        fail: &dyn Fn(String) -> MeshError,
    ) -> Result<bool, MeshError>
    where
        F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
    {
        let Some(colors) = reader.read_colors(0) else {
            self.colors.push(Vec3::ONE);
            return Ok(false);
        };
        for (k, c) in colors.into_rgb_f32().enumerate() {
            let c = Vec3::from_array(c);
            if !c.is_finite() {
                return Err(fail(format!("COLOR_0[{k}]: NaN or infinite value")));
            }
            self.colors.push(unit_color(c));
        }
        Ok(true)
    }

    /// Appends the primitive's `TANGENT`s turned by the node's `linear` transform (handedness
    /// flipped by a mirroring one); returns whether it has them.
    pub(super) fn read_tangents<'a, 's, F>(
        &mut self,
        reader: &gltf::mesh::Reader<'a, 's, F>,
        linear: Mat3,
        fail: &dyn Fn(String) -> MeshError,
    ) -> Result<bool, MeshError>
    where
        F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
    {
        let Some(tangents) = reader.read_tangents() else {
            return Ok(false);
        };
        let flip = if linear.determinant() < 0.0 {
            -1.0
        } else {
            1.0
        };
        for (k, t) in tangents.enumerate() {
            let t = Vec4::from_array(t);
            if !t.is_finite() {
                return Err(fail(format!("TANGENT[{k}]: NaN or infinite value")));
            }
            let xyz = linear * t.truncate();
            let xyz = if xyz.is_finite() { xyz } else { t.truncate() };
            self.tangents.push(xyz.extend(t.w * flip));
        }
        Ok(true)
    }
}
