//! glTF node hierarchies kept as entities: each node of the file's scene becomes an entity
//! placed by its own transform under its parent, and the file's first animation becomes
//! keyframed [`Tracks`] on those entities.
//!
//! What is read, and how:
//! - The whole file first goes through `phosphor-mesh`'s glTF reader, as a flattened mesh
//!   would: every check it makes (accessors against their buffers, node cycles, non-finite
//!   transforms, the triangle budget, buffer sizes) is made before anything here, and its
//!   warnings are the asset's. Its world-space positions give the bounds that `normalize`
//!   fits into the unit sphere.
//! - Each glTF mesh a node uses is then read on its own, through the same reader (a copy of
//!   the file whose only node is that mesh, untransformed): its triangles, materials and
//!   texture maps are what the flattened mesh gives them. Nodes that share a mesh share it.
//!   A mesh with no triangles (points or lines only) leaves its node without geometry.
//! - Nodes of the default scene (else the first, else every node that is no one's child) are
//!   kept when they or a descendant have a mesh: a node without one becomes a transform-only
//!   entity when the hierarchy needs it, and is dropped otherwise (cameras, lights, empties).
//! - A node's rest pose is its translation, rotation (kept as a quaternion, [`RestPose`]) and
//!   scale; a `matrix` is decomposed into them, with a warning when it shears (the nearest
//!   scale and rotation are used).
//! - The first animation plays (the others are named in a warning): translation, rotation
//!   and scale channels with `LINEAR` or `STEP` interpolation become [`Tracks`], which hold
//!   their first value before the first key and their last after the last (glTF's rule; they
//!   do not repeat). `CUBICSPLINE` channels keep their value keys (the middle element of each
//!   in-tangent, value, out-tangent triple) and play them linearly, with a warning: the
//!   tangents are not used. Morph-target `weights` channels are ignored with a warning, as
//!   morph targets are not drawn. Key times must increase strictly and every value must be
//!   finite: anything else is an error naming `animations[0].channels[C]`.
//!
//! The cost: the file is read once whole and once per distinct mesh (each read copies the
//! buffers), so loading a file of `M` meshes costs about `M + 1` times a flattened load.
//!
//! [`RestPose`]: crate::hierarchy::RestPose

use std::borrow::Cow;
use std::cell::RefCell;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use glam::{Mat4, Quat, Vec3};
use gltf::json;
use phosphor_mesh::{MeshError, MeshFormat, NormalOptions};

use hecs::Entity;

use crate::Scene;
use crate::animation::{Interpolation, RotationKey, Tracks};
use crate::components::{GltfNode, MeshInfo, MeshRef, MeshSource, Name, SceneMesh, Transform};
use crate::error::SceneError;
use crate::hierarchy::{Parent, Pose, RestPose};

/// Spawns `asset`'s nodes below the entity `root`: each kept node an entity with a [`Name`]
/// (`PREFIX/NODE`), a [`Parent`] (its parent node's entity, else `root`), its [`RestPose`],
/// a [`Pose`], a [`GltfNode`] and its [`Tracks`]; those with a mesh also a [`Transform`] and a
/// [`MeshRef`], then whatever `dress` adds (material, maps). With `normalize`, one more
/// transform-only entity (`PREFIX/normalize`) between `root` and the glTF's roots fits the
/// rest pose into the unit sphere. Returns the mesh entities, in node order.
///
/// # Errors
/// Whatever `dress` returns.
pub(crate) fn spawn_nodes(
    scene: &mut Scene,
    root: Entity,
    prefix: &str,
    asset: &GltfAsset,
    normalize: bool,
    mut dress: impl FnMut(&mut Scene, Entity, &Arc<SceneMesh>) -> Result<(), SceneError>,
) -> Result<Vec<Entity>, SceneError> {
    let mut top = root;
    if normalize {
        let (centre, scale) = asset.fit;
        let fit = Pose {
            translation: -centre * scale,
            rotation: Quat::IDENTITY,
            scale: Vec3::splat(scale),
        };
        top = scene.world.spawn((
            Name(format!("{prefix}/normalize")),
            Parent(root),
            RestPose(fit),
            fit,
            GltfNode { root, node: None },
        ));
    }
    let mut entities: Vec<Entity> = Vec::with_capacity(asset.nodes.len());
    let mut drawn = Vec::new();
    for node in &asset.nodes {
        let parent = node
            .parent
            .and_then(|p| entities.get(p).copied())
            .unwrap_or(top);
        let e = scene.world.spawn((
            Name(format!("{prefix}/{}", node.name)),
            Parent(parent),
            RestPose(node.rest),
            node.rest,
            GltfNode {
                root,
                node: Some(node.index),
            },
        ));
        if let Some(t) = &node.tracks {
            scene.world.insert_one(e, t.clone()).ok();
        }
        if let Some(mesh) = &node.mesh {
            scene
                .world
                .insert(e, (Transform::default(), MeshRef(mesh.clone())))
                .ok();
            dress(scene, e, mesh)?;
            drawn.push(e);
        }
        entities.push(e);
    }
    Ok(drawn)
}

/// One kept node of a glTF file.
#[derive(Debug, Clone)]
pub struct AssetNode {
    /// The node's index in the file (`nodes[i]`).
    pub index: usize,
    /// The node's name, else `nodes[i]`; made unique within the file by appending `#i`.
    pub name: String,
    /// The parent: a position in [`GltfAsset::nodes`] (`None`: a root of the glTF scene).
    pub parent: Option<usize>,
    /// Its rest pose relative to its parent.
    pub rest: Pose,
    /// Its mesh, if it has one with triangles.
    pub mesh: Option<Arc<SceneMesh>>,
    /// Its channels of the played animation.
    pub tracks: Option<Tracks>,
}

/// A glTF file read as a node hierarchy.
#[derive(Debug, Clone)]
pub struct GltfAsset {
    /// The kept nodes, parents before children.
    pub nodes: Vec<AssetNode>,
    /// The centre and the scale that fit the rest pose into the unit sphere (what
    /// `normalize` applies, as [`phosphor_mesh::Mesh::normalize_unit`] does to a mesh).
    pub fit: (Vec3, f32),
    /// Warnings, one line each, starting with the file.
    pub warnings: Vec<String>,
}

fn element(file: &str, element: impl Into<String>, what: impl Into<String>) -> MeshError {
    MeshError::Element {
        file: file.to_owned(),
        element: element.into(),
        what: what.into(),
    }
}

fn invalid(file: &str, what: impl Into<String>) -> MeshError {
    MeshError::Invalid {
        file: file.to_owned(),
        what: what.into(),
    }
}

/// Reads a glTF or GLB file's bytes as a node hierarchy. `file` names it in messages,
/// `read_relative` reads the files it names (relative to its folder), `source` is what each
/// node's [`SceneMesh`] records as its origin.
///
/// # Errors
/// Whatever the flattened reader refuses, and bad animation data; each message names the
/// file and the element.
pub fn load_gltf(
    bytes: &[u8],
    file: &str,
    read_relative: &dyn Fn(&str) -> std::io::Result<Vec<u8>>,
    normals: &NormalOptions,
    source: &MeshSource,
) -> Result<GltfAsset, MeshError> {
    // Each file the glTF names is read once, however many meshes are read from it.
    let cache: RefCell<HashMap<String, Vec<u8>>> = RefCell::new(HashMap::new());
    let cached = |rel: &str| -> std::io::Result<Vec<u8>> {
        if let Some(b) = cache.borrow().get(rel) {
            return Ok(b.clone());
        }
        let b = read_relative(rel)?;
        cache.borrow_mut().insert(rel.to_owned(), b.clone());
        Ok(b)
    };
    let (flat, mut warnings) =
        phosphor_mesh::parse_mesh_bytes(bytes, file, MeshFormat::Gltf, &cached, normals)?;
    let fit = fit_of(&flat.positions);
    drop(flat);
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| invalid(file, format!("not a readable glTF 2.0 file: {e}")))?;
    let root = document.into_json();
    let order = walk(&root, file)?;

    // The meshes the walked nodes use, each read once.
    let mut meshes: HashMap<usize, Option<Arc<SceneMesh>>> = HashMap::new();
    for &(n, _) in &order {
        let Some(m) = root.nodes.get(n).and_then(|node| node.mesh) else {
            continue;
        };
        if meshes.contains_key(&m.value()) {
            continue;
        }
        let alone = mesh_alone(&root, blob.as_deref(), bytes, m.value(), file)?;
        let read =
            phosphor_mesh::parse_mesh_bytes(&alone, file, MeshFormat::Gltf, &cached, normals);
        let mesh = match read {
            Ok((mut mesh, _)) => {
                // As every mesh file a scene loads: render order, and tangents for maps.
                mesh.sort_spatially();
                if mesh.uvs.is_some() {
                    mesh.ensure_tangents();
                }
                let info = MeshInfo::of(&mesh);
                Some(Arc::new(SceneMesh {
                    mesh,
                    source: source.clone(),
                    normals: *normals,
                    normalized: false,
                    info,
                }))
            }
            // Points or lines only (the flattened read warned of them), or no area at all.
            Err(MeshError::NoFaces { .. }) => None,
            Err(MeshError::Invalid { what, .. }) if what.starts_with("no drawable face") => None,
            Err(e) => return Err(e),
        };
        meshes.insert(m.value(), mesh);
    }

    // Kept: nodes with a mesh, and their ancestors.
    let mut keep = vec![false; root.nodes.len()];
    for &(n, parent) in order.iter().rev() {
        let has_mesh = root
            .nodes
            .get(n)
            .and_then(|node| node.mesh)
            .is_some_and(|m| meshes.get(&m.value()).is_some_and(Option::is_some));
        if has_mesh || keep[n] {
            keep[n] = true;
            if let Some(p) = parent {
                keep[p] = true;
            }
        }
    }
    let mut position: HashMap<usize, usize> = HashMap::new();
    let mut names: HashSet<String> = HashSet::new();
    let mut nodes = Vec::new();
    for &(n, parent) in &order {
        if !keep[n] {
            continue;
        }
        let Some(node) = root.nodes.get(n) else {
            continue;
        };
        let mut name = node.name.clone().unwrap_or_else(|| format!("nodes[{n}]"));
        if !names.insert(name.clone()) {
            name = format!("{name}#{n}");
            names.insert(name.clone());
        }
        let rest = rest_pose(node, n, file, &mut warnings)?;
        let mesh = node
            .mesh
            .and_then(|m| meshes.get(&m.value()).cloned().flatten());
        position.insert(n, nodes.len());
        nodes.push(AssetNode {
            index: n,
            name,
            parent: parent.and_then(|p| position.get(&p).copied()),
            rest,
            mesh,
            tracks: None,
        });
    }
    if !root.skins.is_empty() && !warnings.iter().any(|w| w.contains("skins")) {
        warnings.push(format!(
            "{file}: skins are not applied; meshes are loaded in their bind pose"
        ));
    }
    let buffers = Buffers {
        root: &root,
        blob: blob.as_deref(),
        read: &cached,
        file,
        loaded: HashMap::new(),
    };
    animate(&root, buffers, &position, &mut nodes, &mut warnings)?;
    Ok(GltfAsset {
        nodes,
        fit,
        warnings,
    })
}

/// The centre and scale of [`phosphor_mesh::unit_fit`], in the single precision of poses.
fn fit_of(positions: &[Vec3]) -> (Vec3, f32) {
    let (centre, scale) = phosphor_mesh::unit_fit(positions);
    (centre.as_vec3(), scale as f32)
}

/// The nodes of the scene to show, parents first, each with its parent's node index.
fn walk(root: &json::Root, file: &str) -> Result<Vec<(usize, Option<usize>)>, MeshError> {
    let scene = root
        .scene
        .and_then(|s| root.scenes.get(s.value()))
        .or_else(|| root.scenes.first());
    let roots: Vec<usize> = match scene {
        Some(s) => s.nodes.iter().map(|n| n.value()).collect(),
        None => {
            let mut is_child = vec![false; root.nodes.len()];
            for n in &root.nodes {
                for c in n.children.iter().flatten() {
                    if let Some(slot) = is_child.get_mut(c.value()) {
                        *slot = true;
                    }
                }
            }
            (0..root.nodes.len()).filter(|&i| !is_child[i]).collect()
        }
    };
    let mut visited = vec![false; root.nodes.len()];
    let mut stack: Vec<(usize, Option<usize>)> =
        roots.into_iter().rev().map(|n| (n, None)).collect();
    let mut out = Vec::new();
    while let Some((n, parent)) = stack.pop() {
        let Some(node) = root.nodes.get(n) else {
            return Err(element(
                file,
                format!("nodes[{n}]"),
                format!("out of range ({} nodes)", root.nodes.len()),
            ));
        };
        if std::mem::replace(&mut visited[n], true) {
            return Err(element(
                file,
                format!("nodes[{n}]"),
                "reached twice (a glTF node has at most one parent and no cycle)",
            ));
        }
        for c in node.children.iter().flatten().rev() {
            stack.push((c.value(), Some(n)));
        }
        out.push((n, parent));
    }
    Ok(out)
}

/// The file's bytes with `mesh` as its only node and no animation or skin: what the
/// flattened reader turns into that mesh alone, untransformed.
fn mesh_alone(
    root: &json::Root,
    blob: Option<&[u8]>,
    bytes: &[u8],
    mesh: usize,
    file: &str,
) -> Result<Vec<u8>, MeshError> {
    let mut r = root.clone();
    let Some(user) = root
        .nodes
        .iter()
        .find(|n| n.mesh.is_some_and(|m| m.value() == mesh))
    else {
        return Err(invalid(file, format!("meshes[{mesh}]: no node uses it")));
    };
    let mut only = user.clone();
    only.children = None;
    only.matrix = None;
    only.rotation = None;
    only.scale = None;
    only.translation = None;
    only.skin = None;
    only.camera = None;
    only.extensions = None;
    r.nodes = vec![only];
    r.scene = None;
    r.scenes.clear();
    r.animations.clear();
    r.skins.clear();
    let text = r
        .to_vec()
        .map_err(|e| invalid(file, format!("meshes[{mesh}]: cannot be copied: {e}")))?;
    if !bytes.starts_with(b"glTF") {
        return Ok(text);
    }
    let glb = gltf::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: 0,
        },
        json: Cow::Owned(text),
        bin: blob.map(Cow::Borrowed),
    };
    glb.to_vec()
        .map_err(|e| invalid(file, format!("meshes[{mesh}]: cannot be copied: {e}")))
}

/// A node's rest pose: its TRS, or its matrix decomposed (a warning when that shears).
fn rest_pose(
    node: &json::Node,
    n: usize,
    file: &str,
    warnings: &mut Vec<String>,
) -> Result<Pose, MeshError> {
    let pose = match node.matrix {
        Some(m) => {
            let m = Mat4::from_cols_array(&m);
            let (scale, rotation, translation) = m.to_scale_rotation_translation();
            let back = Mat4::from_scale_rotation_translation(scale, rotation, translation);
            if m.is_finite()
                && !m.abs_diff_eq(
                    back,
                    1e-4 * m
                        .abs()
                        .to_cols_array()
                        .iter()
                        .fold(1.0f32, |a, &b| a.max(b)),
                )
            {
                warnings.push(format!(
                    "{file}: nodes[{n}]: its matrix shears; drawn with the nearest scale and rotation"
                ));
            }
            Pose {
                translation,
                rotation,
                scale,
            }
        }
        None => Pose {
            translation: node.translation.map_or(Vec3::ZERO, Vec3::from_array),
            rotation: node
                .rotation
                .map_or(Quat::IDENTITY, |q| Quat::from_array(q.0).normalize()),
            scale: node.scale.map_or(Vec3::ONE, Vec3::from_array),
        },
    };
    if !(pose.translation.is_finite() && pose.rotation.is_finite() && pose.scale.is_finite()) {
        return Err(element(
            file,
            format!("nodes[{n}]"),
            "transform is not finite (NaN or overflow)",
        ));
    }
    Ok(pose)
}

/// The buffers animation data is read from, each loaded when first needed.
struct Buffers<'a> {
    root: &'a json::Root,
    blob: Option<&'a [u8]>,
    read: &'a dyn Fn(&str) -> std::io::Result<Vec<u8>>,
    file: &'a str,
    loaded: HashMap<usize, Vec<u8>>,
}

impl Buffers<'_> {
    /// The bytes of buffer `b`: the GLB's binary chunk, a `data:` URI, or a file.
    fn get(&mut self, b: usize) -> Result<&[u8], String> {
        if !self.loaded.contains_key(&b) {
            let buffer = self
                .root
                .buffers
                .get(b)
                .ok_or_else(|| format!("buffer {b} out of range"))?;
            let data = match &buffer.uri {
                None => self
                    .blob
                    .map(<[u8]>::to_vec)
                    .ok_or_else(|| format!("buffers[{b}]: no uri and no GLB binary chunk"))?,
                Some(uri) => phosphor_mesh::gltf_uri_bytes(uri, self.read)
                    .map_err(|e| format!("buffers[{b}]: {e}"))?,
            };
            if (data.len() as u64) < buffer.byte_length.0 {
                return Err(format!(
                    "buffers[{b}]: {} bytes, but byteLength says {}",
                    data.len(),
                    buffer.byte_length.0
                ));
            }
            self.loaded.insert(b, data);
        }
        Ok(self.loaded.get(&b).map_or(&[][..], Vec::as_slice))
    }

    /// Accessor `a` as `width` floats per element (`rotation`: unit-normalized integer
    /// components are allowed, as glTF allows them for rotations).
    fn floats(&mut self, a: usize, width: usize, rotation: bool) -> Result<Vec<f32>, String> {
        use json::accessor::{ComponentType, Type};
        use json::validation::Checked;
        let root = self.root;
        let acc = root.accessors.get(a).ok_or_else(|| {
            format!(
                "accessor {a} out of range ({} accessors)",
                root.accessors.len()
            )
        })?;
        let want = match width {
            1 => Type::Scalar,
            3 => Type::Vec3,
            _ => Type::Vec4,
        };
        if acc.type_ != Checked::Valid(want) {
            return Err(format!("accessors[{a}]: expected type {want:?}"));
        }
        if acc.sparse.is_some() {
            return Err(format!(
                "accessors[{a}]: sparse accessors are not read in animations"
            ));
        }
        let Checked::Valid(ct) = acc.component_type else {
            return Err(format!("accessors[{a}]: unknown component type"));
        };
        let ct = ct.0;
        let size = match ct {
            ComponentType::F32 => 4,
            ComponentType::I8 | ComponentType::U8 if rotation && acc.normalized => 1,
            ComponentType::I16 | ComponentType::U16 if rotation && acc.normalized => 2,
            other => {
                return Err(format!(
                    "accessors[{a}]: component type {other:?} is not allowed here"
                ));
            }
        };
        let count =
            usize::try_from(acc.count.0).map_err(|_| format!("accessors[{a}]: count too large"))?;
        let Some(view) = acc.buffer_view else {
            // No buffer view: all zeros (glTF 2.0, 3.6.2.3).
            return Ok(vec![0.0; count.saturating_mul(width).min(1 << 24)]);
        };
        let v = root
            .buffer_views
            .get(view.value())
            .ok_or_else(|| format!("accessors[{a}]: bufferView {} out of range", view.value()))?;
        let elem = size * width;
        let stride = v.byte_stride.map_or(elem, |s| s.0).max(elem);
        let view_len = usize::try_from(v.byte_length.0).unwrap_or(usize::MAX);
        let view_off = usize::try_from(v.byte_offset.map_or(0, |o| o.0)).unwrap_or(usize::MAX);
        let acc_off = usize::try_from(acc.byte_offset.map_or(0, |o| o.0)).unwrap_or(usize::MAX);
        let need = count
            .checked_sub(1)
            .map_or(Some(0), |last| {
                last.checked_mul(stride)
                    .and_then(|x| x.checked_add(elem))
                    .and_then(|x| x.checked_add(acc_off))
            })
            .ok_or_else(|| format!("accessors[{a}]: too large"))?;
        if need > view_len {
            return Err(format!(
                "accessors[{a}]: needs {need} bytes of bufferViews[{}], which has {view_len}",
                view.value()
            ));
        }
        let data = self.get(v.buffer.value())?;
        let end = view_off.saturating_add(view_len);
        let bytes = data.get(view_off..end).ok_or_else(|| {
            format!(
                "bufferViews[{}]: bytes {view_off}..{end} lie outside buffers[{}] ({} bytes)",
                view.value(),
                v.buffer.value(),
                data.len()
            )
        })?;
        let mut out = Vec::with_capacity(count * width);
        for i in 0..count {
            let at = acc_off + i * stride;
            for k in 0..width {
                let p = at + k * size;
                let b = &bytes[p..p + size];
                out.push(match ct {
                    ComponentType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                    ComponentType::I8 => (f32::from(b[0] as i8) / 127.0).max(-1.0),
                    ComponentType::U8 => f32::from(b[0]) / 255.0,
                    ComponentType::I16 => {
                        (f32::from(i16::from_le_bytes([b[0], b[1]])) / 32767.0).max(-1.0)
                    }
                    _ => f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0,
                });
            }
        }
        Ok(out)
    }
}

/// Turns the first animation's channels into [`Tracks`] on the kept nodes.
fn animate(
    root: &json::Root,
    mut buffers: Buffers<'_>,
    position: &HashMap<usize, usize>,
    nodes: &mut [AssetNode],
    warnings: &mut Vec<String>,
) -> Result<(), MeshError> {
    use json::animation::{Interpolation as GltfInterpolation, Property};
    use json::validation::Checked;
    let file = buffers.file;
    let Some(anim) = root.animations.first() else {
        return Ok(());
    };
    if root.animations.len() > 1 {
        warnings.push(format!(
            "{file}: animations[1..{}] are not played (the first animation plays)",
            root.animations.len()
        ));
    }
    let mut weights_warned = false;
    let mut cubic_warned = false;
    for (c, channel) in anim.channels.iter().enumerate() {
        let at = format!("animations[0].channels[{c}]");
        let fail = |what: String| element(file, at.clone(), what);
        let Checked::Valid(property) = channel.target.path else {
            return Err(fail("unknown target path".to_owned()));
        };
        if property == Property::MorphTargetWeights {
            if !weights_warned {
                warnings.push(format!(
                    "{file}: {at}: morph target weights are not animated (morph targets are not drawn)"
                ));
                weights_warned = true;
            }
            continue;
        }
        let node = channel.target.node.value();
        if node >= root.nodes.len() {
            return Err(fail(format!(
                "target node {node} out of range ({} nodes)",
                root.nodes.len()
            )));
        }
        let sampler = anim.samplers.get(channel.sampler.value()).ok_or_else(|| {
            fail(format!(
                "sampler {} out of range ({} samplers)",
                channel.sampler.value(),
                anim.samplers.len()
            ))
        })?;
        // A node that is not kept (no mesh below it) moves nothing that is drawn.
        let Some(&slot) = position.get(&node) else {
            continue;
        };
        let Checked::Valid(interp) = sampler.interpolation else {
            return Err(fail("unknown interpolation".to_owned()));
        };
        let times = buffers
            .floats(sampler.input.value(), 1, false)
            .map_err(|e| fail(format!("input: {e}")))?;
        let rotation = property == Property::Rotation;
        let width = if rotation { 4 } else { 3 };
        let mut values = buffers
            .floats(sampler.output.value(), width, rotation)
            .map_err(|e| fail(format!("output: {e}")))?;
        let interpolation = match interp {
            GltfInterpolation::Linear => Interpolation::Linear,
            GltfInterpolation::Step => Interpolation::Step,
            GltfInterpolation::CubicSpline => {
                if !cubic_warned {
                    warnings.push(format!(
                        "{file}: {at}: CUBICSPLINE keys are played linearly between their values (tangents are not used)"
                    ));
                    cubic_warned = true;
                }
                // Per key: in-tangent, value, out-tangent; the value is the middle one.
                if values.len() != times.len() * 3 * width {
                    return Err(fail(format!(
                        "CUBICSPLINE output has {} elements for {} keys (3 per key)",
                        values.len() / width,
                        times.len()
                    )));
                }
                values = values
                    .chunks_exact(3 * width)
                    .flat_map(|k| k[width..2 * width].to_vec())
                    .collect();
                Interpolation::Linear
            }
        };
        let tracks = nodes[slot].tracks.get_or_insert_with(Tracks::default);
        let taken = match property {
            Property::Translation => tracks.translation.is_some(),
            Property::Rotation => tracks.rotation.is_some(),
            _ => tracks.scale.is_some(),
        };
        if taken {
            warnings.push(format!(
                "{file}: {at}: a second channel for the same node and path; the first one plays"
            ));
            continue;
        }
        let bad = |e: crate::animation::TrackError| fail(e.to_string());
        match property {
            Property::Rotation => {
                let keys = values
                    .chunks_exact(4)
                    .map(|q| {
                        let q = Quat::from_xyzw(q[0], q[1], q[2], q[3]);
                        RotationKey::Quat(if q.length() > 1e-6 { q.normalize() } else { q })
                    })
                    .collect();
                tracks.rotation =
                    Some(Tracks::rotation(times, keys, interpolation, false).map_err(bad)?);
            }
            _ => {
                let keys = values
                    .chunks_exact(3)
                    .map(|v| Vec3::new(v[0], v[1], v[2]))
                    .collect();
                let track = Tracks::vec3(times, keys, interpolation, false).map_err(bad)?;
                if property == Property::Translation {
                    tracks.translation = Some(track);
                } else {
                    tracks.scale = Some(track);
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_matches_the_meshes_normalization() {
        let (c, s) = fit_of(&[Vec3::new(-1.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0)]);
        assert_eq!(c, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(s, 0.5);
    }
}
