//! glTF materials as the mesh's [`MtlMaterial`] list: the base colour factor as `kd`, the base
//! colour texture as `kd_map`, the normal texture and its scale as `normal_map`, each texture's
//! sampler wraps (filters are the renderer's choice). Images come from a file relative to the
//! glTF (the buffer URI rules: no scheme, no absolute path, and the file stays in the glTF's
//! folder unless outside assets are allowed: [`crate::assets::asset_path`]), a base64 `data:`
//! URI, or a buffer view (copied out of the GLB or buffer). Each image is resolved once however
//! many materials use it, and the embedded images copied or decoded stay within
//! [`MAX_MESH_FILE_BYTES`] together. Metallic-roughness, occlusion and emissive textures,
//! textures on another uv set than `TEXCOORD_0`, and extensions (`KHR_texture_transform`, ...)
//! are not used: warnings say so. A texture, image or sampler index out of range is a warning
//! and the reference is dropped ([`drop_bad_references`], before the `gltf` crate validates).

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use gltf::json;
use gltf::json::texture::WrappingMode;
use gltf::json::validation::Checked;

use super::uri::{UriTarget, resolve_uri};
use crate::assets::asset_path;
use crate::mesh::MtlMaterial;
use crate::open::{MAX_MESH_FILE_BYTES, limit_text};
use crate::sanitize::quote;
use crate::texture_ref::{TextureRef, TextureSource, Wrap};

/// Unlinks every texture reference that points nowhere, with a warning each, so validation
/// passes and the rest of the file loads: a sampler out of range becomes the default sampler;
/// a texture whose image is out of range (or is an image with neither a usable buffer view
/// nor a URI) is removed, and so is every material slot naming it or a texture out of range.
pub(super) fn drop_bad_references(root: &mut json::Root, file: &str, warnings: &mut Vec<String>) {
    let (images, views, samplers) = (
        root.images.len(),
        root.buffer_views.len(),
        root.samplers.len(),
    );
    let mut bad_image = vec![false; images];
    for (i, image) in root.images.iter_mut().enumerate() {
        if image
            .buffer_view
            .as_ref()
            .is_some_and(|v| v.value() >= views)
        {
            warnings.push(format!(
                "{file}: images[{i}]: buffer view does not exist ({views} views); image ignored"
            ));
            image.buffer_view = None;
            image.uri = None;
        }
        bad_image[i] = image.buffer_view.is_none() && image.uri.is_none();
    }
    let mut new_index: Vec<Option<u32>> = Vec::with_capacity(root.textures.len());
    let mut kept = Vec::with_capacity(root.textures.len());
    for (t, mut texture) in std::mem::take(&mut root.textures).into_iter().enumerate() {
        if texture
            .sampler
            .as_ref()
            .is_some_and(|s| s.value() >= samplers)
        {
            warnings.push(format!(
                "{file}: textures[{t}]: sampler does not exist ({samplers} samplers); \
                 default sampler (repeat)"
            ));
            texture.sampler = None;
        }
        let source = texture.source.value();
        if source >= images || bad_image[source] {
            warnings.push(format!(
                "{file}: textures[{t}]: image {source} does not exist or has no data \
                 ({images} images); texture ignored"
            ));
            new_index.push(None);
        } else {
            new_index.push(Some(kept.len() as u32));
            kept.push(texture);
        }
    }
    root.textures = kept;
    for (m, material) in root.materials.iter_mut().enumerate() {
        let mut remap = |index: json::Index<json::texture::Texture>, slot: &str| {
            let found = new_index.get(index.value()).copied().flatten();
            if found.is_none() && index.value() >= new_index.len() {
                warnings.push(format!(
                    "{file}: materials[{m}].{slot}: texture {} does not exist; not used",
                    index.value()
                ));
            }
            found.map(json::Index::new)
        };
        let pbr = &mut material.pbr_metallic_roughness;
        for (info, slot) in [
            (&mut pbr.base_color_texture, "baseColorTexture"),
            (
                &mut pbr.metallic_roughness_texture,
                "metallicRoughnessTexture",
            ),
            (&mut material.emissive_texture, "emissiveTexture"),
        ] {
            *info = info.take().and_then(|mut i| {
                i.index = remap(i.index, slot)?;
                Some(i)
            });
        }
        material.normal_texture = material.normal_texture.take().and_then(|mut n| {
            n.index = remap(n.index, "normalTexture")?;
            Some(n)
        });
        material.occlusion_texture = material.occlusion_texture.take().and_then(|mut o| {
            o.index = remap(o.index, "occlusionTexture")?;
            Some(o)
        });
    }
}

/// What resolving a material's textures needs from the file.
pub(super) struct Textures<'a> {
    /// The glTF, for messages; its folder resolves image files.
    pub file: &'a str,
    pub gltf: &'a gltf::Gltf,
    pub buffers: &'a [Cow<'a, [u8]>],
    /// Images already resolved, by image index, so materials share them (an embedded image is
    /// copied once) and a bad one is refused for the same reason each time: the source and
    /// how the file wrote it, or why it is not used.
    pub images: HashMap<usize, Result<(TextureSource, String), String>>,
    /// Bytes of the embedded images copied or decoded so far, at most
    /// [`MAX_MESH_FILE_BYTES`].
    pub embedded_bytes: u64,
}

/// The MTL-style material of glTF material `m` (see the module docs); problems with its
/// textures are pushed onto `warnings`.
pub(super) fn material(
    m: &gltf::Material<'_>,
    textures: &mut Textures<'_>,
    warnings: &mut Vec<String>,
) -> MtlMaterial {
    let [r, g, b, _alpha] = m.pbr_metallic_roughness().base_color_factor();
    let kd = Vec3::new(r, g, b);
    let d = MtlMaterial::default();
    let index = m.index().unwrap_or_default();
    let element = format!("materials[{index}]");
    let json = m
        .index()
        .and_then(|i| textures.gltf.as_json().materials.get(i));
    let pbr = json.map(|j| &j.pbr_metallic_roughness);
    let kd_map = pbr
        .and_then(|p| p.base_color_texture.as_ref())
        .and_then(|info| {
            let slot = format!("{element}.pbrMetallicRoughness.baseColorTexture");
            textures.reference(info.index.value(), info.tex_coord, &slot, warnings)
        });
    let normal_map = json.and_then(|j| j.normal_texture.as_ref()).and_then(|n| {
        let slot = format!("{element}.normalTexture");
        let scale = if n.scale.is_finite() { n.scale } else { 1.0 };
        let texture = textures.reference(n.index.value(), n.tex_coord, &slot, warnings)?;
        Some((texture, scale))
    });
    let mut unused = Vec::new();
    if let Some(j) = json {
        for (present, name) in [
            (
                j.pbr_metallic_roughness
                    .metallic_roughness_texture
                    .is_some(),
                "metallicRoughnessTexture",
            ),
            (j.occlusion_texture.is_some(), "occlusionTexture"),
            (j.emissive_texture.is_some(), "emissiveTexture"),
        ] {
            if present {
                unused.push(name.to_owned());
            }
        }
    }
    MtlMaterial {
        name: m
            .name()
            .map_or_else(|| format!("material {index}"), str::to_owned),
        kd: if kd.is_finite() && kd.min_element() >= 0.0 {
            kd
        } else {
            d.kd
        },
        kd_map,
        normal_map,
        unused,
        ..d
    }
}

impl Textures<'_> {
    /// The reference to texture `index` used with uv set `tex_coord` by `slot` (for
    /// messages); `None`, with a warning, when it cannot be used.
    fn reference(
        &mut self,
        index: usize,
        tex_coord: u32,
        slot: &str,
        warnings: &mut Vec<String>,
    ) -> Option<TextureRef> {
        let file = self.file;
        if tex_coord != 0 {
            warnings.push(format!(
                "{file}: {slot}: texCoord {tex_coord} is not supported (only TEXCOORD_0); \
                 texture not used"
            ));
            return None;
        }
        let root = self.gltf.as_json();
        let texture = root.textures.get(index)?;
        let (wrap_u, wrap_v) = texture
            .sampler
            .and_then(|s| root.samplers.get(s.value()))
            .map_or((Wrap::Repeat, Wrap::Repeat), |s| {
                (wrap(&s.wrap_s), wrap(&s.wrap_t))
            });
        let image_index = texture.source.value();
        let resolved = match self.images.get(&image_index) {
            Some(resolved) => resolved.clone(),
            None => {
                let resolved = self.image(image_index)?;
                self.images.insert(image_index, resolved.clone());
                resolved
            }
        };
        let (source, written) = match resolved {
            Ok(found) => found,
            Err(why) => {
                warnings.push(format!(
                    "{file}: {slot}: images[{image_index}]: {why}; texture not used"
                ));
                return None;
            }
        };
        Some(TextureRef {
            source,
            wrap_u,
            wrap_v,
            written,
        })
    }

    /// Image `index`: its source and how the file wrote it, or why it cannot be used;
    /// `None` when it does not exist (dropped by [`drop_bad_references`]).
    fn image(&mut self, index: usize) -> Option<Result<(TextureSource, String), String>> {
        let image = self.gltf.as_json().images.get(index)?;
        let name = image
            .name
            .clone()
            .unwrap_or_else(|| format!("images[{index}]"));
        let mime = image.mime_type.as_ref().map(|m| m.0.clone());
        let (bytes, mime, written) = if let Some(view) = image.buffer_view {
            let Some(bytes) = self.view_bytes(view.value()) else {
                return Some(Err(format!(
                    "buffer view {} runs past its buffer",
                    view.value()
                )));
            };
            let written = format!("images[{index}] (buffer view {})", view.value());
            (bytes, mime, written)
        } else {
            match resolve_uri(image.uri.as_deref()?) {
                Ok(UriTarget::Relative(path)) => {
                    // Confined as a buffer's file is; read later, by whoever decodes it.
                    return Some(match asset_path(Path::new(self.file), &path) {
                        Ok(found) => Ok((TextureSource::File(found), path)),
                        Err(why) => Err(format!("uri '{}' {why}", quote(&path, 80))),
                    });
                }
                Ok(UriTarget::Data {
                    mime: data_mime,
                    bytes,
                }) => (
                    bytes,
                    data_mime.or(mime),
                    format!("images[{index}] (data: URI)"),
                ),
                Err(why) => return Some(Err(why)),
            }
        };
        let total = self.embedded_bytes.saturating_add(bytes.len() as u64);
        if total > MAX_MESH_FILE_BYTES {
            return Some(Err(format!(
                "{} bytes, over the {} the embedded images may take together",
                bytes.len(),
                limit_text(MAX_MESH_FILE_BYTES)
            )));
        }
        self.embedded_bytes = total;
        let bytes: Arc<[u8]> = bytes.into();
        Some(Ok((TextureSource::Embedded { name, mime, bytes }, written)))
    }

    /// A copy of buffer view `view`'s bytes; `None` when it runs past its buffer.
    fn view_bytes(&self, view: usize) -> Option<Vec<u8>> {
        let view = self.gltf.views().nth(view)?;
        let buffer = self.buffers.get(view.buffer().index())?;
        let end = view.offset().checked_add(view.length())?;
        buffer.get(view.offset()..end).map(<[u8]>::to_vec)
    }
}

/// The wrap of a sampler axis.
fn wrap(mode: &Checked<WrappingMode>) -> Wrap {
    match mode {
        Checked::Valid(WrappingMode::ClampToEdge) => Wrap::ClampToEdge,
        Checked::Valid(WrappingMode::MirroredRepeat) => Wrap::MirroredRepeat,
        _ => Wrap::Repeat,
    }
}
