//! glTF materials as the mesh's [`MtlMaterial`] list.

use glam::Vec3;

use crate::mesh::MtlMaterial;

/// The MTL-style material of a glTF material: its base colour factor as `kd` (glTF's factors
/// are linear, as MTL's are), other terms at the MTL defaults.
pub(super) fn material(m: &gltf::Material<'_>) -> MtlMaterial {
    let [r, g, b, _alpha] = m.pbr_metallic_roughness().base_color_factor();
    let kd = Vec3::new(r, g, b);
    let d = MtlMaterial::default();
    MtlMaterial {
        name: m.name().map_or_else(
            || format!("material {}", m.index().unwrap_or_default()),
            str::to_owned,
        ),
        kd: if kd.is_finite() && kd.min_element() >= 0.0 {
            kd
        } else {
            d.kd
        },
        ..d
    }
}
