//! Accessors checked before the `gltf` crate's reader touches them: the reader slices and
//! asserts, so a malformed file must be refused here, naming what is wrong.

use std::borrow::Cow;

use gltf::accessor::{DataType, Dimensions};

use super::invalid;
use crate::error::MeshError;

/// Every vertex attribute of every primitive names an accessor that exists.
pub(super) fn check_attribute_accessors(
    root: &gltf::json::Root,
    file: &str,
) -> Result<(), MeshError> {
    let count = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &primitive.attributes {
                if index.value() >= count {
                    let name = match semantic {
                        gltf::json::validation::Checked::Valid(s) => s.to_string(),
                        gltf::json::validation::Checked::Invalid => "?".to_owned(),
                    };
                    return Err(invalid(
                        file,
                        format!(
                            "invalid glTF: meshes[{m}].primitives[{p}].attributes.{name}: accessor {} does not exist ({count} accessors)",
                            index.value()
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Checks that `accessor` has one of the `types` and lies inside its view and buffer, so the
/// crate's reader (which slices and asserts) cannot panic on it.
pub(super) fn check_accessor(
    accessor: &gltf::Accessor<'_>,
    types: &[(DataType, Dimensions)],
    buffers: &[Cow<'_, [u8]>],
) -> Result<(), String> {
    let what = format!("accessor {}", accessor.index());
    if !types.contains(&(accessor.data_type(), accessor.dimensions())) {
        return Err(format!(
            "{what}: {:?} {:?} is not a type this attribute may have",
            accessor.data_type(),
            accessor.dimensions()
        ));
    }
    if accessor.sparse().is_some() {
        return Err(format!("{what}: sparse accessors are not supported"));
    }
    let view = accessor
        .view()
        .ok_or_else(|| format!("{what}: no buffer view (all zeros)"))?;
    let size = accessor.size();
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "{what}: stride {stride} is below the element size {size}"
        ));
    }
    let count = accessor.count();
    if count == 0 {
        return Err(format!("{what}: count is 0"));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(size))
        .and_then(|x| x.checked_add(accessor.offset()));
    if end.is_none_or(|end| end > view.length()) {
        return Err(format!(
            "{what}: {count} elements do not fit in buffer view {} ({} bytes)",
            view.index(),
            view.length()
        ));
    }
    let buffer_len = buffers.get(view.buffer().index()).map_or(0, |b| b.len());
    if view
        .offset()
        .checked_add(view.length())
        .is_none_or(|end| end > buffer_len)
    {
        return Err(format!(
            "buffer view {} runs past the end of buffer {}",
            view.index(),
            view.buffer().index()
        ));
    }
    Ok(())
}

pub(super) const VEC3_F32: &[(DataType, Dimensions)] = &[(DataType::F32, Dimensions::Vec3)];
pub(super) const UV_TYPES: &[(DataType, Dimensions)] = &[
    (DataType::F32, Dimensions::Vec2),
    (DataType::U8, Dimensions::Vec2),
    (DataType::U16, Dimensions::Vec2),
];
pub(super) const INDEX_TYPES: &[(DataType, Dimensions)] = &[
    (DataType::U8, Dimensions::Scalar),
    (DataType::U16, Dimensions::Scalar),
    (DataType::U32, Dimensions::Scalar),
];
pub(super) const TANGENT_TYPES: &[(DataType, Dimensions)] = &[(DataType::F32, Dimensions::Vec4)];
pub(super) const COLOR_TYPES: &[(DataType, Dimensions)] = &[
    (DataType::F32, Dimensions::Vec3),
    (DataType::F32, Dimensions::Vec4),
    (DataType::U8, Dimensions::Vec3),
    (DataType::U8, Dimensions::Vec4),
    (DataType::U16, Dimensions::Vec3),
    (DataType::U16, Dimensions::Vec4),
];
