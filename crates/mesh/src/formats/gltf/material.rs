//! glTF materials as the mesh's [`MtlMaterial`] list: the base colour factor as `kd`, the base
//! colour texture as `kd_map`, the normal texture and its scale as `normal_map`, each texture's
//! sampler wraps (filters are the renderer's choice). Images come from a file relative to the
//! glTF (the buffer URI rules: no scheme, no absolute path), a base64 `data:` URI, or a buffer
//! view (copied out of the GLB or buffer). Metallic-roughness, occlusion and emissive textures,
//! textures on another uv set than `TEXCOORD_0`, and extensions (`KHR_texture_transform`, ...)
//! are not used: warnings say so. A texture, image or sampler index out of range is a warning
//! and the reference is dropped ([`drop_bad_references`], before the `gltf` crate validates).

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;
use gltf::json;
use gltf::json::texture::WrappingMode;
use gltf::json::validation::Checked;

use super::uri::{UriTarget, resolve_uri};
use crate::mesh::MtlMaterial;
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
    /// Embedded images already copied, by image index, so materials share them.
    pub embedded: HashMap<usize, Arc<[u8]>>,
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
        let image = root.images.get(image_index)?;
        let name = image
            .name
            .clone()
            .unwrap_or_else(|| format!("images[{image_index}]"));
        let mime = image.mime_type.as_ref().map(|m| m.0.clone());
        let (source, written) = if let Some(view) = image.buffer_view {
            let bytes = match self.embedded.get(&image_index) {
                Some(bytes) => bytes.clone(),
                None => {
                    let Some(bytes) = self.view_bytes(view.value()) else {
                        warnings.push(format!(
                            "{file}: {slot}: images[{image_index}]: buffer view {} runs past \
                             its buffer; texture not used",
                            view.value()
                        ));
                        return None;
                    };
                    self.embedded.insert(image_index, bytes.clone());
                    bytes
                }
            };
            let written = format!("images[{image_index}] (buffer view {})", view.value());
            (TextureSource::Embedded { name, mime, bytes }, written)
        } else {
            let uri = image.uri.as_deref()?;
            match resolve_uri(uri) {
                Ok(UriTarget::Relative(path)) => {
                    let dir = Path::new(file).parent().unwrap_or(Path::new(""));
                    (TextureSource::File(dir.join(PathBuf::from(&path))), path)
                }
                Ok(UriTarget::Data {
                    mime: data_mime,
                    bytes,
                }) => {
                    let bytes: Arc<[u8]> = bytes.into();
                    let written = format!("images[{image_index}] (data: URI)");
                    let mime = data_mime.or(mime);
                    (TextureSource::Embedded { name, mime, bytes }, written)
                }
                Err(why) => {
                    warnings.push(format!(
                        "{file}: {slot}: images[{image_index}]: {why}; texture not used"
                    ));
                    return None;
                }
            }
        };
        Some(TextureRef {
            source,
            wrap_u,
            wrap_v,
            written,
        })
    }

    /// A copy of buffer view `view`'s bytes; `None` when it runs past its buffer.
    fn view_bytes(&self, view: usize) -> Option<Arc<[u8]>> {
        let view = self.gltf.views().nth(view)?;
        let buffer = self.buffers.get(view.buffer().index())?;
        let end = view.offset().checked_add(view.length())?;
        buffer.get(view.offset()..end).map(Arc::from)
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
