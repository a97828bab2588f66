//! glTF 2.0, JSON (`.gltf`) or binary (`.glb`), through the `gltf` crate.
//!
//! What is read: the default scene (else the first, else every node that is no one's child),
//! each node's mesh placed by its world transform, primitives of triangle modes (lists, strips
//! and fans; points and lines are skipped with a warning, as OBJ lines are), `POSITION`,
//! `NORMAL`, `TEXCOORD_0`, indices, and each material's base colour factor as the diffuse
//! reflectance `kd` (textures, metallic-roughness, skins and morph targets are not used).
//! Buffers come from the GLB's binary chunk, `data:` URIs, or files relative to the glTF;
//! nothing is fetched from a network. Before anything is read, a GLB's chunks, the triangles
//! the nodes place and the buffers' declared sizes are checked (`guard`), and each URI is
//! read once; from disk, a buffer stays in the glTF's folder ([`crate::assets`]).
//!
//! Every accessor is checked against its buffer before it is read (type, count, stride,
//! bounds), so a malformed file is an error naming `meshes[M].primitives[P]`, never a panic
//! inside the reader.

use std::borrow::Cow;

use glam::{Mat3, Mat4, Vec2, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::buffer::Source;
use gltf::mesh::{Mode, Semantic};

use super::{Welder, element_error, finish, one_line};
use crate::build::TriangleSoup;
use crate::error::MeshError;
use crate::mesh::{Mesh, MtlMaterial};
use crate::normals::NormalOptions;
use crate::sanitize::quote;

mod guard;

/// Parses a glTF or GLB file's bytes; `file` names it in messages, `read_relative` reads the
/// buffers it names by relative path.
pub(super) fn parse(
    bytes: &[u8],
    file: &str,
    read_relative: &dyn Fn(&str) -> std::io::Result<Vec<u8>>,
    opts: &NormalOptions,
) -> Result<(Mesh, Vec<String>), MeshError> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(MeshError::NoFaces {
            file: file.to_owned(),
        });
    }
    guard::check_glb(bytes, file)?;
    // gltf-json 1.4's validation indexes the accessor list with a primitive's POSITION index
    // unchecked, so a file naming an accessor that does not exist would panic there: parse
    // without validation first and refuse such indices, then parse with validation.
    let unchecked = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| invalid(file, describe(&e)))?;
    check_attribute_accessors(unchecked.as_json(), file)?;
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| invalid(file, describe(&e)))?;
    let version = &gltf.as_json().asset.version;
    if !version.starts_with("2.") {
        return Err(invalid(
            file,
            format!("glTF version {version} is not supported (2.x only)"),
        ));
    }
    // Nothing is read before the placed triangles and the buffers' sizes are known to fit.
    let placed = placed_nodes(&gltf, file)?;
    guard::check_placed(&placed, file)?;
    let uri_data = guard::read_uris(&gltf, file, read_relative)?;
    let buffers = load_buffers(&gltf, file, &uri_data)?;
    let mut warnings = Vec::new();
    if gltf.skins().next().is_some() {
        warnings.push(format!(
            "{file}: skins are not applied; meshes are loaded in their bind pose"
        ));
    }

    let mut out = Assembly::default();
    for (node, world) in placed {
        let Some(mesh) = node.mesh() else { continue };
        let name = mesh
            .name()
            .map_or_else(|| format!("mesh {}", mesh.index()), str::to_owned);
        if !out.groups.contains(&name) {
            out.groups.push(name);
        }
        for primitive in mesh.primitives() {
            let element = format!("meshes[{}].primitives[{}]", mesh.index(), primitive.index());
            out.add(&primitive, world, &buffers, file, &element, &mut warnings)?;
        }
    }

    let materials: Vec<MtlMaterial> = gltf.materials().map(|m| material(&m)).collect();
    let mut soup = out.soup;
    if !materials.is_empty() {
        // Primitives without a material use glTF's default one (base colour 1, 1, 1).
        let default_id = materials.len() as u32;
        for (id, gltf_id) in soup.material_ids.iter_mut().zip(&out.gltf_materials) {
            *id = gltf_id.map_or(default_id, |i| i as u32);
        }
    }
    if out.all_normals {
        soup.normals = Some((out.normals, out.normal_ix));
    }
    if out.all_uvs {
        soup.uvs = Some((out.uvs, out.uv_ix));
    }
    let mut mesh = finish(soup, file, opts)?;
    mesh.materials = materials;
    if out.gltf_materials.iter().any(Option::is_none) && !mesh.materials.is_empty() {
        mesh.materials.push(MtlMaterial {
            name: "default".to_owned(),
            kd: Vec3::ONE,
            ..MtlMaterial::default()
        });
    }
    mesh.groups = out.groups;
    Ok((mesh, warnings))
}

fn invalid(file: &str, what: impl Into<String>) -> MeshError {
    MeshError::Invalid {
        file: file.to_owned(),
        what: what.into(),
    }
}

/// The crate's error on one line; validation errors name their JSON paths (the first few).
/// Every vertex attribute of every primitive names an accessor that exists.
fn check_attribute_accessors(root: &gltf::json::Root, file: &str) -> Result<(), MeshError> {
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

fn describe(e: &gltf::Error) -> String {
    match e {
        gltf::Error::Validation(list) => {
            let shown: Vec<String> = list
                .iter()
                .take(3)
                .map(|(path, err)| format!("{path}: {err}"))
                .collect();
            let more = list.len().saturating_sub(3);
            let tail = if more > 0 {
                format!(" (and {more} more)")
            } else {
                String::new()
            };
            format!("invalid glTF: {}{tail}", shown.join("; "))
        }
        other => format!(
            "not a readable glTF 2.0 file: {}",
            one_line(&other.to_string())
        ),
    }
}

/// The MTL-style material of a glTF material: its base colour factor as `kd` (glTF's factors
/// are linear, as MTL's are), other terms at the MTL defaults.
fn material(m: &gltf::Material<'_>) -> MtlMaterial {
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

/// The bytes of every buffer, each at least as long as the file declares; `uri_data` holds
/// the bytes of the URIs they name ([`guard::read_uris`]).
fn load_buffers<'a>(
    gltf: &'a gltf::Gltf,
    file: &str,
    uri_data: &'a std::collections::HashMap<String, Vec<u8>>,
) -> Result<Vec<Cow<'a, [u8]>>, MeshError> {
    let mut out = Vec::new();
    for buffer in gltf.buffers() {
        let element = format!("buffers[{}]", buffer.index());
        let data: Cow<'a, [u8]> = match buffer.source() {
            Source::Bin => Cow::Borrowed(gltf.blob.as_deref().ok_or_else(|| {
                element_error(
                    file,
                    &element,
                    "refers to a GLB binary chunk the file lacks",
                )
            })?),
            Source::Uri(uri) => Cow::Borrowed(
                uri_data
                    .get(uri)
                    .ok_or_else(|| element_error(file, &element, "its uri was not read"))?,
            ),
        };
        if data.len() < buffer.length() {
            return Err(element_error(
                file,
                &element,
                format!(
                    "truncated: {} bytes, the file declares {}",
                    data.len(),
                    buffer.length()
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// A buffer's bytes from its URI: a base64 `data:` URI, or a file relative to the glTF.
fn uri_bytes(
    uri: &str,
    read_relative: &dyn Fn(&str) -> std::io::Result<Vec<u8>>,
) -> Result<Vec<u8>, String> {
    if let Some(data) = uri.strip_prefix("data:") {
        let (meta, payload) = data
            .split_once(',')
            .ok_or_else(|| "data URI without a comma".to_owned())?;
        if !meta.ends_with(";base64") {
            return Err("data URI is not base64".to_owned());
        }
        return base64_decode(payload).ok_or_else(|| "data URI: malformed base64".to_owned());
    }
    // A scheme (`http:`, `file:`) or an absolute path is not a relative reference: refused
    // rather than fetched.
    let scheme = uri.split_once(':').is_some_and(|(s, _)| {
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
    });
    if scheme || uri.starts_with('/') || uri.starts_with('\\') {
        return Err(format!(
            "uri '{}' is not a relative file; only relative files, data: URIs and the \
             GLB binary chunk are read",
            quote(uri, 80)
        ));
    }
    let path = percent_decode(uri)
        .ok_or_else(|| format!("uri '{}': malformed %-escape", quote(uri, 80)))?;
    read_relative(&path).map_err(|e| format!("cannot read '{}': {e}", quote(&path, 80)))
}

/// Standard base64 (RFC 4648), padding optional; `None` on any other character.
fn base64_decode(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let digits = text.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(digits.len() * 3 / 4);
    for chunk in digits.chunks(4) {
        if chunk.len() == 1 {
            return None;
        }
        let mut bits = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            bits |= value(c)? << (18 - 6 * k);
        }
        let bytes = bits.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    Some(out)
}

/// `%XX` escapes of a URI path decoded (glTF writers escape spaces in file names).
fn percent_decode(uri: &str) -> Option<String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Every node of the scene to show, with its world transform (parents first).
fn placed_nodes<'a>(
    gltf: &'a gltf::Gltf,
    file: &str,
) -> Result<Vec<(gltf::Node<'a>, Mat4)>, MeshError> {
    let roots: Vec<gltf::Node<'a>> = match gltf.default_scene().or_else(|| gltf.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; gltf.nodes().len()];
            for n in gltf.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            gltf.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let mut visited = vec![false; gltf.nodes().len()];
    let mut stack: Vec<(gltf::Node<'a>, Mat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Mat4::IDENTITY))
        .collect();
    let mut out = Vec::new();
    while let Some((node, parent)) = stack.pop() {
        let element = format!("nodes[{}]", node.index());
        if std::mem::replace(&mut visited[node.index()], true) {
            return Err(element_error(
                file,
                element,
                "reached twice (a glTF node has at most one parent and no cycle)",
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !world.is_finite() {
            return Err(element_error(
                file,
                element,
                "transform is not finite (NaN or overflow)",
            ));
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, world));
        }
        out.push((node, world));
    }
    Ok(out)
}

/// The corners of all primitives read so far, welded into one soup.
#[derive(Default)]
struct Assembly {
    soup: TriangleSoup,
    welder: Welder,
    normals: Vec<Vec3>,
    normal_ix: Vec<[u32; 3]>,
    uvs: Vec<Vec2>,
    uv_ix: Vec<[u32; 3]>,
    /// Per triangle, the glTF material index (`None`: glTF's default material).
    gltf_materials: Vec<Option<usize>>,
    groups: Vec<String>,
    all_normals: bool,
    all_uvs: bool,
    /// Whether any primitive has been added (before that, `all_*` are vacuously true).
    started: bool,
}

/// Checks that `accessor` has one of the `types` and lies inside its view and buffer, so the
/// crate's reader (which slices and asserts) cannot panic on it.
fn check_accessor(
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

const VEC3_F32: &[(DataType, Dimensions)] = &[(DataType::F32, Dimensions::Vec3)];
const UV_TYPES: &[(DataType, Dimensions)] = &[
    (DataType::F32, Dimensions::Vec2),
    (DataType::U8, Dimensions::Vec2),
    (DataType::U16, Dimensions::Vec2),
];
const INDEX_TYPES: &[(DataType, Dimensions)] = &[
    (DataType::U8, Dimensions::Scalar),
    (DataType::U16, Dimensions::Scalar),
    (DataType::U32, Dimensions::Scalar),
];

impl Assembly {
    /// Adds one primitive placed by `world`; `element` names it in messages.
    fn add(
        &mut self,
        primitive: &gltf::Primitive<'_>,
        world: Mat4,
        buffers: &[Cow<'_, [u8]>],
        file: &str,
        element: &str,
        warnings: &mut Vec<String>,
    ) -> Result<(), MeshError> {
        let fail = |what: String| element_error(file, element, what);
        let mode = primitive.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            warnings.push(format!(
                "{file}: {element}: mode {mode:?} skipped (not triangles)"
            ));
            return Ok(());
        }
        let position_accessor = primitive
            .get(&Semantic::Positions)
            .ok_or_else(|| fail("no POSITION attribute".to_owned()))?;
        check_accessor(&position_accessor, VEC3_F32, buffers)
            .map_err(|w| fail(format!("POSITION: {w}")))?;
        let normal_accessor = primitive.get(&Semantic::Normals);
        if let Some(a) = &normal_accessor {
            check_accessor(a, VEC3_F32, buffers).map_err(|w| fail(format!("NORMAL: {w}")))?;
        }
        let uv_accessor = primitive.get(&Semantic::TexCoords(0));
        if let Some(a) = &uv_accessor {
            check_accessor(a, UV_TYPES, buffers).map_err(|w| fail(format!("TEXCOORD_0: {w}")))?;
        }
        if let Some(a) = primitive.indices() {
            check_accessor(&a, INDEX_TYPES, buffers).map_err(|w| fail(format!("indices: {w}")))?;
        }

        let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
        let local: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| fail("POSITION: cannot be read".to_owned()))?
            .map(Vec3::from_array)
            .collect();
        let count = local.len();
        for (name, a) in [("NORMAL", &normal_accessor), ("TEXCOORD_0", &uv_accessor)] {
            match a {
                Some(a) if a.count() != count => {
                    return Err(fail(format!(
                        "{name} has {} elements, POSITION {count}",
                        a.count()
                    )));
                }
                _ => {}
            }
        }
        let indices: Vec<u32> = match reader.read_indices() {
            Some(ix) => ix.into_u32().collect(),
            None => (0..count as u32).collect(),
        };
        if let Some((k, &i)) = indices
            .iter()
            .enumerate()
            .find(|&(_, &i)| i as usize >= count)
        {
            return Err(fail(format!(
                "indices[{k}]: vertex {i} out of range ({count} vertices)"
            )));
        }

        // Positions to world space; welded by the world position so primitives and nodes
        // that touch can be smoothed together, as OBJ groups are.
        let mut ids = Vec::with_capacity(count);
        for (k, p) in local.iter().enumerate() {
            let w = world.transform_point3(*p);
            if !p.is_finite() || !w.is_finite() {
                return Err(fail(format!("POSITION[{k}]: NaN or infinite coordinate")));
            }
            ids.push(self.welder.id(&mut self.soup, w));
        }
        // Normals by the inverse transpose; a mirroring transform (negative determinant)
        // turns the winding around, so triangles are flipped to keep counter-clockwise front.
        let linear = Mat3::from_mat4(world);
        let mirrored = linear.determinant() < 0.0;
        let normal_matrix = linear.inverse().transpose();
        let normal_base = self.normals.len() as u32;
        let has_normals = match reader.read_normals() {
            Some(ns) => {
                for (k, n) in ns.enumerate() {
                    let n = Vec3::from_array(n);
                    if !n.is_finite() {
                        return Err(fail(format!("NORMAL[{k}]: NaN or infinite value")));
                    }
                    let m = normal_matrix * n;
                    self.normals.push(if m.is_finite() { m } else { n });
                }
                true
            }
            None => false,
        };
        let uv_base = self.uvs.len() as u32;
        let has_uvs = match reader.read_tex_coords(0) {
            Some(uvs) => {
                // glTF puts the uv origin at the top left of the image, OBJ at the bottom left.
                self.uvs
                    .extend(uvs.into_f32().map(|[u, v]| Vec2::new(u, 1.0 - v)));
                true
            }
            None => false,
        };
        if has_uvs
            && self.uvs[uv_base as usize..]
                .iter()
                .any(|uv| !uv.is_finite())
        {
            return Err(fail("TEXCOORD_0: NaN or infinite value".to_owned()));
        }
        self.all_normals = has_normals && (self.all_normals || !self.started);
        self.all_uvs = has_uvs && (self.all_uvs || !self.started);
        self.started = true;

        let material = primitive.material().index();
        for corner in triangles(mode, &indices) {
            let corner = if mirrored {
                [corner[0], corner[2], corner[1]]
            } else {
                corner
            };
            self.soup.triangles.push(corner.map(|c| ids[c as usize]));
            self.normal_ix.push(corner.map(|c| normal_base + c));
            self.uv_ix.push(corner.map(|c| uv_base + c));
            self.soup.material_ids.push(0);
            self.gltf_materials.push(material);
        }
        Ok(())
    }
}

/// The triangles of a triangle-mode primitive's index list (glTF 2.0, 3.7.2.1 "Topology").
fn triangles(mode: Mode, ix: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (0..ix.len().saturating_sub(2))
            .map(|i| {
                if i % 2 == 0 {
                    [ix[i], ix[i + 1], ix[i + 2]]
                } else {
                    [ix[i + 1], ix[i], ix[i + 2]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..ix.len().saturating_sub(1))
            .map(|i| [ix[i], ix[i + 1], ix[0]])
            .collect(),
        _ => ix.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_with_and_without_padding() {
        assert_eq!(
            base64_decode("aGVsbG8=").as_deref(),
            Some(b"hello".as_slice())
        );
        assert_eq!(
            base64_decode("aGVsbG8").as_deref(),
            Some(b"hello".as_slice())
        );
        assert_eq!(
            base64_decode("AAECAw==").as_deref(),
            Some([0u8, 1, 2, 3].as_slice())
        );
        assert_eq!(base64_decode("").as_deref(), Some([].as_slice()));
        assert!(base64_decode("a").is_none());
        assert!(base64_decode("a$==").is_none());
    }

    #[test]
    fn network_and_absolute_uris_are_refused() {
        let never = |_: &str| -> std::io::Result<Vec<u8>> { panic!("must not read") };
        for uri in [
            "http://example.invalid/a.bin",
            "file:///etc/passwd",
            "/abs/a.bin",
            "C:\\a.bin",
        ] {
            let e = uri_bytes(uri, &never).expect_err(uri);
            assert!(e.contains("not a relative file"), "{e}");
        }
        let read = |p: &str| Ok(p.as_bytes().to_vec());
        assert_eq!(
            uri_bytes("my%20mesh.bin", &read).as_deref(),
            Ok(b"my mesh.bin".as_slice())
        );
    }

    #[test]
    fn strips_and_fans_follow_the_specification() {
        assert_eq!(
            triangles(Mode::TriangleStrip, &[0, 1, 2, 3]),
            vec![[0, 1, 2], [2, 1, 3]]
        );
        assert_eq!(
            triangles(Mode::TriangleFan, &[0, 1, 2, 3]),
            vec![[1, 2, 0], [2, 3, 0]]
        );
        assert_eq!(triangles(Mode::Triangles, &[0, 1, 2, 3]), vec![[0, 1, 2]]);
    }
}
