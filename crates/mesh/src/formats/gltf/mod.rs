//! glTF 2.0, JSON (`.gltf`) or binary (`.glb`), through the `gltf` crate.
//!
//! What is read: the default scene (else the first, else every node that is no one's child),
//! each node's mesh placed by its world transform, primitives of triangle modes (lists, strips
//! and fans; points and lines are skipped with a warning, as OBJ lines are), `POSITION`,
//! `NORMAL`, `TEXCOORD_0`, `COLOR_0` (float, or normalized unsigned byte or short; VEC3 or VEC4,
//! alpha dropped; already linear; white on primitives without it when another has it),
//! `TANGENT` (kept as authored when every primitive has it along with `NORMAL` and
//! `TEXCOORD_0` and the normals are the authored ones), indices, and the materials (see
//! [`material`]: base colour factor and texture, normal texture; metallic-roughness, skins and
//! morph targets are not used).
//! Buffers come from the GLB's binary chunk, `data:` URIs, or files relative to the glTF;
//! nothing is fetched from a network. Before anything is read, a GLB's chunks, the triangles
//! the nodes place and the buffers' declared sizes are checked (`guard`), and each URI is
//! read once; from disk, a buffer stays in the glTF's folder ([`crate::assets`]).
//!
//! Every accessor is checked against its buffer before it is read (type, count, stride,
//! bounds), so a malformed file is an error naming `meshes[M].primitives[P]`, never a panic
//! inside the reader.

use std::borrow::Cow;
use std::collections::HashMap;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::mesh::{Mode, Semantic};

use super::{Welder, element_error, finish, one_line};
use crate::build::TriangleSoup;
use crate::error::MeshError;
use crate::mesh::{Mesh, MtlMaterial};
use crate::normals::NormalOptions;
use crate::sanitize::quote;

mod guard;

mod accessor;
mod attributes;
mod material;
mod nodes;
mod uri;
pub use uri::uri_bytes as gltf_uri_bytes;

use accessor::{
    COLOR_TYPES, INDEX_TYPES, TANGENT_TYPES, UV_TYPES, VEC3_F32, check_accessor,
    check_attribute_accessors,
};
use material::{Textures, drop_bad_references, material};
use nodes::placed_nodes;
use uri::load_buffers;

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
    // Texture references out of range are dropped with a warning rather than failing the
    // validation: the geometry is still good.
    let gltf::Gltf { document, blob } = unchecked;
    let mut root = document.into_json();
    let mut warnings = Vec::new();
    drop_bad_references(&mut root, file, &mut warnings);
    for name in &root.extensions_used {
        warnings.push(format!(
            "{file}: extension {} is not supported; ignored",
            quote(name, 80)
        ));
    }
    let document = gltf::Document::from_json(root).map_err(|e| invalid(file, describe(&e)))?;
    let gltf = gltf::Gltf { document, blob };
    let version = &gltf.as_json().asset.version;
    if !version.starts_with("2.") {
        return Err(invalid(
            file,
            format!(
                "glTF version {} is not supported (2.x only)",
                quote(version, 40)
            ),
        ));
    }
    // Nothing is read before the placed triangles and the buffers' sizes are known to fit.
    let placed = placed_nodes(&gltf, file)?;
    guard::check_placed(&placed, file)?;
    let uri_data = guard::read_uris(&gltf, file, read_relative)?;
    let buffers = load_buffers(&gltf, file, &uri_data)?;
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

    let mut textures = Textures {
        file,
        gltf: &gltf,
        buffers: &buffers,
        images: HashMap::new(),
        embedded_bytes: 0,
    };
    let materials: Vec<MtlMaterial> = gltf
        .materials()
        .map(|m| material(&m, &mut textures, &mut warnings))
        .collect();
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
    if out.any_colors {
        soup.colors = Some((out.colors, out.color_ix));
    }
    if out.all_tangents {
        // Used by the build only with the authored normals (and uvs) they are a frame around.
        soup.tangents = Some((out.tangents, out.tangent_ix));
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

/// The corners of all primitives read so far, welded into one soup.
#[derive(Default)]
struct Assembly {
    soup: TriangleSoup,
    welder: Welder,
    normals: Vec<Vec3>,
    normal_ix: Vec<[u32; 3]>,
    uvs: Vec<Vec2>,
    uv_ix: Vec<[u32; 3]>,
    /// `COLOR_0` (white for a primitive without it: glTF's base colour times 1).
    colors: Vec<Vec3>,
    color_ix: Vec<[u32; 3]>,
    tangents: Vec<Vec4>,
    tangent_ix: Vec<[u32; 3]>,
    /// Per triangle, the glTF material index (`None`: glTF's default material).
    gltf_materials: Vec<Option<usize>>,
    groups: Vec<String>,
    all_normals: bool,
    all_uvs: bool,
    all_tangents: bool,
    /// Whether any primitive has `COLOR_0`.
    any_colors: bool,
    /// Whether any primitive has been added (before that, `all_*` are vacuously true).
    started: bool,
}

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
        let color_accessor = primitive.get(&Semantic::Colors(0));
        if let Some(a) = &color_accessor {
            check_accessor(a, COLOR_TYPES, buffers).map_err(|w| fail(format!("COLOR_0: {w}")))?;
        }
        let tangent_accessor = primitive.get(&Semantic::Tangents);
        if let Some(a) = &tangent_accessor {
            check_accessor(a, TANGENT_TYPES, buffers).map_err(|w| fail(format!("TANGENT: {w}")))?;
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
        for (name, a) in [
            ("NORMAL", &normal_accessor),
            ("TEXCOORD_0", &uv_accessor),
            ("COLOR_0", &color_accessor),
            ("TANGENT", &tangent_accessor),
        ] {
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
        let color_base = self.colors.len() as u32;
        let has_colors = self.read_colors(&reader, &fail)?;
        let tangent_base = self.tangents.len() as u32;
        let has_tangents = self.read_tangents(&reader, linear, &fail)?;
        self.all_normals = has_normals && (self.all_normals || !self.started);
        self.all_uvs = has_uvs && (self.all_uvs || !self.started);
        self.all_tangents = has_tangents && (self.all_tangents || !self.started);
        self.any_colors |= has_colors;
        self.started = true;
        // Without COLOR_0 every corner takes the one white entry pushed for the primitive.
        let color_of = |c: u32| {
            if has_colors {
                color_base + c
            } else {
                color_base
            }
        };

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
            self.color_ix.push(corner.map(color_of));
            self.tangent_ix.push(corner.map(|c| tangent_base + c));
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
