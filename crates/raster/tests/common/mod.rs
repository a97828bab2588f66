//! Helpers the shadow tests share.

use glam::Vec3;
use phosphor_lighting::{Vec3s, f32x4};
use phosphor_mesh::Mesh;
use phosphor_raster::MeshView;

/// The mesh as the rasterizer takes it (no uvs, tangents or colours).
pub fn view(m: &Mesh) -> MeshView<'_> {
    MeshView {
        positions: &m.positions,
        normals: &m.normals,
        uvs: None,
        tangents: None,
        colors: None,
        indices: &m.indices,
    }
}

/// Four vectors side by side: lane `i` holds `v[i]`.
pub fn lanes4(v: &[Vec3; 4]) -> Vec3s<f32x4> {
    let lane = |f: fn(Vec3) -> f32| f32x4::from(v.map(f));
    Vec3s::new(lane(|v| v.x), lane(|v| v.y), lane(|v| v.z))
}

/// Bounding spheres as cube-map extents, with no boxes.
pub fn extents(
    spheres: &[phosphor_raster::shadow::Sphere],
) -> Vec<phosphor_raster::shadow::Extent> {
    spheres.iter().map(|&s| s.into()).collect()
}
