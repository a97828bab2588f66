//! Scene files (TOML) to a [`Scene`]: every field checked, every error naming its field.

use std::cell::RefCell;
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;
use hecs::Entity;
use phosphor_lighting::{
    Attenuation, Fresnel, FresnelMode, Light, LightKind, Material, SpecularModel,
};
use phosphor_mesh::primitives::{PrimitiveError, gigabytes};
use phosphor_mesh::{MAX_MESH_FILE_BYTES, MeshFormat, NormalOptions, NormalSource, Weighting};
use phosphor_raster::{BumpMap, Camera, Encoding, ProceduralBump, Texture, Wrap};

use super::gltf_nodes::{GltfAsset, load_gltf, spawn_nodes};
use super::motion::{MOTION_KEYS, Motion};
use super::read::{Fields, choose};
use crate::budget::{MAX_DISTRIBUTED_SAMPLES, limit_distributed_samples};
use crate::components::{
    Bump, BumpSource, GltfNode, GltfRoot, MaterialDef, MaterialName, MeshInfo, MeshRef, MeshSource,
    Name, PRIMITIVE_BUDGET_BYTES, Primitive, SceneMesh, Shading, ShadingChoice, Transform,
};
use crate::components::{CastsShadows, ShadowRole};
use crate::error::SceneError;
use crate::hierarchy::{LocalCamera, LocalLight, Parent};
use crate::textures::{ColorMap, MapSource, checkerboard, decode, wrap_of};
use crate::{CullChoice, RenderSettings, Scene};
use phosphor_raster::shadow::{MAX_SHADOW_SIZE, MIN_SHADOW_SIZE};

/// Reads the files a scene names (meshes, MTL, bump images): the disk, or embedded text.
pub trait Files {
    /// The text of `path`, or the I/O error.
    fn read_text(&self, path: &Path) -> std::io::Result<String>;
    /// The bytes of `path` (binary mesh files, bump images), or the I/O error.
    fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        self.read_text(path).map(String::into_bytes)
    }
    /// The bytes of the file `rel` that the mesh file `mesh` names (a glTF buffer), relative
    /// to the mesh's folder.
    fn read_asset(&self, mesh: &Path, rel: &str) -> std::io::Result<Vec<u8>> {
        self.read_bytes(&mesh.parent().unwrap_or(Path::new("")).join(rel))
    }
    /// Whether `path` exists (a bump image is checked when the scene is read, loaded later).
    fn exists(&self, path: &Path) -> bool;
}

/// The file system. Every file is read as a regular file, opened without blocking, of at
/// most [`MAX_MESH_FILE_BYTES`] (`phosphor_mesh::open`: a FIFO or device named by a scene is
/// refused, never waited on); the files a glTF names stay in its folder
/// ([`phosphor_mesh::read_asset`]).
pub struct Disk;

impl Files for Disk {
    fn read_text(&self, path: &Path) -> std::io::Result<String> {
        phosphor_mesh::read_text(path, MAX_MESH_FILE_BYTES)
    }
    fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        phosphor_mesh::read_file(path, MAX_MESH_FILE_BYTES)
    }
    fn read_asset(&self, mesh: &Path, rel: &str) -> std::io::Result<Vec<u8>> {
        phosphor_mesh::read_asset(mesh, rel)
    }
    fn exists(&self, path: &Path) -> bool {
        path.exists()
    }
}

/// Largest scene file read: scene files are a few kilobytes of TOML.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

const TOP: &[&str] = &[
    "render",
    "camera",
    "ambient",
    "lights",
    "materials",
    "objects",
];

/// Parses scene text. `file` names it in messages; relative paths resolve against `dir`.
pub fn parse_scene(
    text: &str,
    file: &str,
    dir: &Path,
    files: &dyn Files,
) -> Result<Scene, SceneError> {
    let table: toml::Table = toml::from_str(text).map_err(|e| SceneError::Syntax {
        file: file.to_owned(),
        line: e.span().map_or(1, |s| {
            text[..s.start.min(text.len())].matches('\n').count() + 1
        }),
        what: e.message().trim().replace('\n', " "),
    })?;
    let root = Fields::root(file, &table);
    let mut scene = Scene::empty();
    scene.source = Some(dir.join(file.rsplit('/').next().unwrap_or(file)));
    if let Some(r) = root.table("render")? {
        scene.settings = render_settings(&r)?;
    }
    let (camera, camera_motion) = match root.table("camera")? {
        Some(c) => super::camera::camera(&c)?,
        None => (Camera::s1(), Motion::default()),
    };
    let camera_entity = scene.world.spawn((camera,));
    // Children name their parents; each is resolved once every object exists.
    let mut pending: Vec<(Entity, String, String)> = Vec::new();
    if camera_motion.posed() {
        scene
            .world
            .insert_one(camera_entity, LocalCamera(camera))
            .ok();
    }
    if let Some(p) = &camera_motion.parent {
        pending.push((camera_entity, p.clone(), camera_motion.parent_field.clone()));
    }
    camera_motion.attach(&mut scene, camera_entity, Transform::default());
    if let Some(a) = root.table("ambient")? {
        scene.ambient = a.color("intensity")?.unwrap_or(Vec3::ZERO);
        a.finish(&["intensity"])?;
    }
    let mut lights = Vec::new();
    let mut motions = Vec::new();
    for (i, l) in root.tables("lights")?.into_iter().enumerate() {
        let name = l
            .str("name")?
            .map_or_else(|| format!("light {i}"), str::to_owned);
        let shadows = l.bool("shadows")?.unwrap_or(false);
        let (light, motion) = light(&l)?;
        lights.push((name, light, shadows));
        motions.push(motion);
    }
    let mut kinds: Vec<Light> = lights.iter().map(|(_, l, _)| *l).collect();
    let (cuts, asked) = limit_distributed_samples(&mut kinds, MAX_DISTRIBUTED_SAMPLES);
    for cut in &cuts {
        scene.warnings.push(format!(
            "warning: {file}: lights[{}].samples: {} cut to {} (the distributed lights ask for {asked} point samples; the scene budget is {MAX_DISTRIBUTED_SAMPLES})",
            cut.index, cut.before, cut.after
        ));
    }
    for (((name, _, shadows), light), motion) in lights.into_iter().zip(kinds).zip(motions) {
        let e = scene.world.spawn((Name(name), light));
        if shadows {
            scene.world.insert_one(e, CastsShadows).ok();
        }
        if motion.posed() {
            scene.world.insert_one(e, LocalLight(light.kind)).ok();
        }
        if let Some(p) = &motion.parent {
            pending.push((e, p.clone(), motion.parent_field.clone()));
        }
        motion.attach(&mut scene, e, Transform::default());
    }
    for (name, m) in root.named_tables("materials")? {
        let def = material(&m, dir, files)?;
        scene.materials.insert(name.to_owned(), def);
    }
    let mut meshes: HashMap<String, Arc<SceneMesh>> = HashMap::new();
    let mut gltfs: HashMap<String, Arc<GltfAsset>> = HashMap::new();
    let mut bumps: BTreeMap<String, Arc<BumpMap>> = BTreeMap::new();
    let mut maps: BTreeMap<String, Option<Arc<Texture>>> = BTreeMap::new();
    let mut primitive_bytes = 0u64;
    let mut objects = Vec::new();
    nested_objects(root.tables("objects")?, None, 0, &mut objects)?;
    check_primitive_budget(objects.iter().map(|(o, _)| o))?;
    let mut named: Vec<(String, Entity)> = Vec::new();
    let mut spawned: Vec<Entity> = Vec::with_capacity(objects.len());
    for (i, (o, outer)) in objects.into_iter().enumerate() {
        let (entity, mut motion) = object(
            &mut scene,
            &o,
            i,
            dir,
            files,
            &mut meshes,
            &mut gltfs,
            &mut bumps,
            &mut maps,
            &mut primitive_bytes,
        )?;
        spawned.push(entity);
        if let Some(&outer) = outer.and_then(|k| spawned.get(k)) {
            if motion.parent.is_some() {
                return Err(o.error(
                    "parent",
                    "a nested object's parent is the object whose `children` it is in",
                ));
            }
            scene.world.insert_one(entity, Parent(outer)).ok();
            motion.nested = true;
        }
        if let Ok(n) = scene.world.get::<&Name>(entity) {
            named.push((n.0.clone(), entity));
        }
        // The nodes of a glTF it names can be parents too, by their `OBJECT/NODE` names.
        if scene.world.get::<&GltfRoot>(entity).is_ok() {
            let mut nodes = scene.world.query::<(Entity, &GltfNode, &Name)>();
            named.extend(
                nodes
                    .iter()
                    .filter(|(_, g, _)| g.root == entity && g.node.is_some())
                    .map(|(e, _, n)| (n.0.clone(), e)),
            );
        }
        if let Some(p) = &motion.parent {
            pending.push((entity, p.clone(), motion.parent_field.clone()));
        }
        let rest = scene
            .world
            .get::<&Transform>(entity)
            .map(|t| *t)
            .unwrap_or_default();
        motion.attach(&mut scene, entity, rest);
    }
    root.finish(TOP)?;
    super::motion::resolve_parents(&mut scene, file, pending, &named)?;
    // Posed at time 0, so that a loaded scene renders as it stands.
    let placed = crate::animation::update(&mut scene, crate::animation::Time::default());
    scene
        .warnings
        .extend(placed.into_iter().map(|w| format!("{w} ({file})")));
    if scene.light_count() == 0 && scene.world.query::<&MeshRef>().iter().next().is_some() {
        scene.warnings.push(format!(
            "warning: {file}: lights: none, so only the ambient term lights the objects{}",
            if scene.ambient == Vec3::ZERO {
                " and the picture is black (add [[lights]] or [ambient])"
            } else {
                " (add [[lights]] for shading)"
            }
        ));
    }
    Ok(scene)
}

/// Loads a scene file from disk: a regular file of at most [`MAX_SCENE_BYTES`], opened
/// without blocking, as are the files it names ([`Disk`]).
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    read_scene_with(path, &Disk)
}

/// [`load_scene`] reading the files the scene names through `files`.
fn read_scene_with(path: &Path, files: &dyn Files) -> Result<Scene, SceneError> {
    let file = path.display().to_string();
    let text =
        phosphor_mesh::read_text(path, MAX_SCENE_BYTES).map_err(|source| SceneError::Io {
            file: file.clone(),
            source,
        })?;
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let mut scene = parse_scene(&text, &file, &dir, files)?;
    scene.source = Some(path.to_path_buf());
    Ok(scene)
}

/// The disk, noting every path the loader asks for (read, or checked for), so that a
/// viewer knows which files to watch: [`load_scene_noting`].
struct Noting {
    paths: RefCell<BTreeSet<PathBuf>>,
}

impl Noting {
    fn note(&self, path: &Path) {
        self.paths.borrow_mut().insert(path.to_path_buf());
    }
}

impl Files for Noting {
    fn read_text(&self, path: &Path) -> std::io::Result<String> {
        self.note(path);
        Disk.read_text(path)
    }
    fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        self.note(path);
        Disk.read_bytes(path)
    }
    fn read_asset(&self, mesh: &Path, rel: &str) -> std::io::Result<Vec<u8>> {
        self.note(&mesh.parent().unwrap_or(Path::new("")).join(rel));
        Disk.read_asset(mesh, rel)
    }
    fn exists(&self, path: &Path) -> bool {
        self.note(path);
        Disk.exists(path)
    }
}

/// [`load_scene`], returning with the scene (or the error) every file it was made from,
/// whether or not each could be read: the scene file, its meshes, their MTL files and glTF
/// buffers, the images the scene names, and the images the meshes' materials name. A viewer
/// watches them to load the scene again when one changes; after an error they are the
/// files read until it, the scene file always among them.
pub fn load_scene_noting(path: &Path) -> (Result<Scene, SceneError>, BTreeSet<PathBuf>) {
    let noting = Noting {
        paths: RefCell::new(BTreeSet::from([path.to_path_buf()])),
    };
    let scene = read_scene_with(path, &noting);
    let mut files = noting.paths.into_inner();
    if let Ok(scene) = &scene {
        files.extend(image_files(scene));
    }
    (scene, files)
}

/// The image files that the materials of the scene's meshes name (MTL `map_Kd` and `norm`,
/// glTF images stored beside the file), whether or not they could be read.
#[must_use]
pub fn image_files(scene: &Scene) -> BTreeSet<PathBuf> {
    let mut files = BTreeSet::new();
    for m in scene.world.query::<&MeshRef>().iter() {
        for material in &m.0.mesh.materials {
            let normal = material.normal_map.as_ref().map(|(t, _)| t);
            for t in [material.kd_map.as_ref(), normal].into_iter().flatten() {
                if let phosphor_mesh::TextureSource::File(p) = &t.source {
                    files.insert(p.clone());
                }
            }
        }
    }
    files
}

fn render_settings(r: &Fields<'_>) -> Result<RenderSettings, SceneError> {
    let mut s = RenderSettings::default();
    if let Some(w) = r.u32("width")? {
        s.width = w;
    }
    if let Some(h) = r.u32("height")? {
        s.height = h;
    }
    for (key, v) in [("width", s.width), ("height", s.height)] {
        if v == 0 || v > crate::MAX_SIDE {
            return Err(r.error(
                key,
                format!("must be between 1 and {}, got {v}", crate::MAX_SIDE),
            ));
        }
    }
    if let Some(m) = r.str("shading")? {
        s.shading = m.parse().map_err(|e: String| r.error("shading", e))?;
    }
    if let Some(e) = r.str("encoding")? {
        s.encoding = choose(
            r,
            "encoding",
            e,
            &[("srgb", Encoding::Srgb), ("linear", Encoding::Linear)],
        )?;
    }
    if let Some((b, a)) = r.color_alpha("background")? {
        s.background = b;
        s.background_alpha = a;
    }
    if let Some(p) = r.bool("perspective_correct")? {
        s.perspective_correct = p;
    }
    match r.get("cull_backfaces") {
        None => {}
        Some(toml::Value::Boolean(true)) => s.cull_backfaces = CullChoice::Always,
        Some(toml::Value::Boolean(false)) => s.cull_backfaces = CullChoice::Never,
        Some(toml::Value::String(v)) if v == "auto" => s.cull_backfaces = CullChoice::Auto,
        Some(v) => {
            return Err(r.error(
                "cull_backfaces",
                format!("expected true, false or \"auto\", got {v}"),
            ));
        }
    }
    if let Some(a) = r.str("aa")? {
        s.antialias = a
            .parse()
            .map_err(|e: phosphor_raster::UnknownAntialias| r.error("aa", e.to_string()))?;
        if !s.antialias.fits(s.width, s.height) {
            return Err(r.error(
                "aa",
                format!(
                    "{a} draws {}x{} samples, over the largest side {}",
                    u64::from(s.width) * u64::from(s.antialias.factor()),
                    u64::from(s.height) * u64::from(s.antialias.factor()),
                    crate::MAX_SIDE
                ),
            ));
        }
    }
    if let Some(c) = r.bool("gouraud_clamp")? {
        s.gouraud_vertex_clamp = c;
    }
    if let Some(m) = r.str("fast_phong")? {
        s.fast_phong = m
            .parse()
            .map_err(|e: phosphor_raster::UnknownFastPhongMethod| {
                r.error("fast_phong", e.to_string())
            })?;
    }
    if let Some(m) = r.str("interpolation")? {
        s.interpolation = m
            .parse()
            .map_err(|e: phosphor_raster::UnknownInterpolation| {
                r.error("interpolation", e.to_string())
            })?;
    }
    if let Some(size) = r.u32("shadow_size")? {
        if size != 0 && !(MIN_SHADOW_SIZE..=MAX_SHADOW_SIZE).contains(&size) {
            return Err(r.error(
                "shadow_size",
                format!(
                    "must be 0 (derived from the picture) or {MIN_SHADOW_SIZE} to {MAX_SHADOW_SIZE}, got {size}"
                ),
            ));
        }
        s.shadow_size = size;
    }
    r.finish(&[
        "shadow_size",
        "aa",
        "gouraud_clamp",
        "width",
        "height",
        "shading",
        "encoding",
        "background",
        "perspective_correct",
        "cull_backfaces",
        "fast_phong",
        "interpolation",
    ])?;
    Ok(s)
}

fn attenuation(a: &Fields<'_>) -> Result<Attenuation, SceneError> {
    let model = a.str("model")?.ok_or_else(|| {
        a.error(
            "model",
            "missing (\"none\", \"inverse-square\", \"offset\" or \"quadratic\")",
        )
    })?;
    let att = match model {
        "none" => {
            a.finish(&["model"])?;
            Attenuation::None
        }
        "inverse-square" => {
            a.finish(&["model"])?;
            Attenuation::InverseSquare
        }
        "offset" => {
            let k = a.req_f32("k")?;
            a.finish(&["model", "k"])?;
            Attenuation::Offset { k }
        }
        "quadratic" => {
            let c = a.f32("c")?.unwrap_or(1.0);
            let l = a.f32("l")?.unwrap_or(0.0);
            let q = a.f32("q")?.unwrap_or(0.0);
            a.finish(&["model", "c", "l", "q"])?;
            Attenuation::Quadratic { c, l, q }
        }
        other => {
            return Err(a.error(
                "model",
                format!("unknown value \"{other}\" (expected \"none\", \"inverse-square\", \"offset\" or \"quadratic\")"),
            ));
        }
    };
    att.validate().map_err(|e| a.error_here(e.to_string()))?;
    Ok(att)
}

fn light(l: &Fields<'_>) -> Result<(Light, Motion), SceneError> {
    let motion = super::motion::motion(l)?;
    let kind_name = l.str("type")?.ok_or_else(|| {
        l.error(
            "type",
            "missing (\"point\", \"directional\", \"spot\", \"tube\" or \"rect\")",
        )
    })?;
    let (kind, keys): (LightKind, &[&str]) = match kind_name {
        "point" => (
            LightKind::Point {
                position: l.req_vec3("position")?,
            },
            &["position"],
        ),
        "directional" => (
            LightKind::Directional {
                direction: l.req_vec3("direction")?,
            },
            &["direction"],
        ),
        "spot" => (
            LightKind::Spot {
                position: l.req_vec3("position")?,
                direction: l.req_vec3("direction")?,
                inner_deg: l.f32("inner_deg")?.unwrap_or(20.0),
                outer_deg: l.f32("outer_deg")?.unwrap_or(30.0),
            },
            &["position", "direction", "inner_deg", "outer_deg"],
        ),
        "tube" => (
            LightKind::Tube {
                start: l.req_vec3("start")?,
                end: l.req_vec3("end")?,
                samples: l.u32("samples")?.unwrap_or(8),
            },
            &["start", "end", "samples"],
        ),
        "rect" => (
            LightKind::Rect {
                corner: l.req_vec3("corner")?,
                edge_u: l.req_vec3("edge_u")?,
                edge_v: l.req_vec3("edge_v")?,
                samples: l.u32("samples")?.unwrap_or(4),
            },
            &["corner", "edge_u", "edge_v", "samples"],
        ),
        other => {
            return Err(l.error(
                "type",
                format!("unknown value \"{other}\" (expected \"point\", \"directional\", \"spot\", \"tube\" or \"rect\")"),
            ));
        }
    };
    let intensity = l
        .color("intensity")?
        .ok_or_else(|| l.error("intensity", "missing"))?;
    let mut light = Light::new(kind, intensity).map_err(|e| lighting_error(l, &e))?;
    if let Some(s) = l.color("specular_intensity")? {
        light = light
            .with_specular_intensity(s)
            .map_err(|e| lighting_error(l, &e))?;
    }
    if let Some(a) = l.table("attenuation")? {
        if matches!(kind, LightKind::Directional { .. }) {
            return Err(l.error(
                "attenuation",
                "a directional light is at infinity and cannot be attenuated",
            ));
        }
        light.attenuation = attenuation(&a)?;
    }
    if let Some(e) = l.bool("enabled")? {
        light.enabled = e;
    }
    let mut known = vec![
        "type",
        "name",
        "intensity",
        "specular_intensity",
        "attenuation",
        "enabled",
        "shadows",
    ];
    known.extend_from_slice(keys);
    known.extend_from_slice(MOTION_KEYS);
    l.finish(&known)?;
    Ok((light, motion))
}

/// A lighting error (`field: what`) placed under the table being read.
fn lighting_error(f: &Fields<'_>, e: &phosphor_lighting::LightingError) -> SceneError {
    let text = e.to_string();
    match text.split_once(": ") {
        Some((field, what)) if !field.contains(' ') => f.error(field, what),
        _ => f.error_here(text),
    }
}

fn material(m: &Fields<'_>, dir: &Path, files: &dyn Files) -> Result<MaterialDef, SceneError> {
    let base = Material::default();
    // `ka = "kd"`: the lecture notes' ambient term of a diffuse surface, `I = Ia Kd`.
    let ka_from_kd = matches!(m.get("ka"), Some(toml::Value::String(s)) if s == "kd");
    let kd = m.color("kd")?.unwrap_or(base.kd);
    let mut mat = Material {
        ka: if ka_from_kd {
            kd
        } else {
            m.color("ka")?.unwrap_or(base.ka)
        },
        kd,
        ks: m.color("ks")?.unwrap_or(base.ks),
        // `inf` is the lecture notes' perfect reflector.
        shininess: m.f32_or_inf("shininess")?.unwrap_or(base.shininess),
        emission: m.color("emission")?.unwrap_or(Vec3::ZERO),
        ..base
    };
    if mat.shininess < 0.0 {
        return Err(m.error(
            "shininess",
            format!("must be non-negative, got {}", mat.shininess),
        ));
    }
    if let Some(s) = m.str("specular")? {
        mat.specular = choose(
            m,
            "specular",
            s,
            &[
                ("phong", SpecularModel::Phong),
                ("blinn", SpecularModel::Blinn),
            ],
        )?;
    }
    if let Some(f) = m.table("fresnel")? {
        let model = f.str("model")?.unwrap_or("none");
        mat.fresnel = match model {
            "none" => Fresnel::None,
            "constant" => Fresnel::Constant { w: f.req_f32("w")? },
            "schlick" => Fresnel::Schlick {
                f0: f.f32("f0")?.unwrap_or(phosphor_lighting::GLASS_F0),
            },
            other => {
                return Err(f.error(
                    "model",
                    format!(
                        "unknown value \"{other}\" (expected \"none\", \"constant\" or \"schlick\")"
                    ),
                ));
            }
        };
        if let Some(mode) = f.str("mode")? {
            mat.fresnel_mode = choose(
                &f,
                "mode",
                mode,
                &[
                    ("scale", FresnelMode::Scale),
                    ("replace", FresnelMode::Replace),
                ],
            )?;
        }
        f.finish(&["model", "w", "f0", "mode"])?;
        mat.fresnel.validate().map_err(|e| lighting_error(&f, &e))?;
        // Under "replace" W(theta) is the whole specular coefficient: ks is 1 unless the file
        // says otherwise, and then validate() names the conflict.
        if mat.fresnel_mode == FresnelMode::Replace && m.get("ks").is_none() {
            mat.ks = Vec3::ONE;
        }
    }
    mat.validate().map_err(|e| lighting_error(m, &e))?;
    let bump = match m.table("bump")? {
        Some(b) => Some(bump(&b, dir, files)?),
        None => None,
    };
    // A missing or bad image is a warning when the material is used, not an error: the
    // object renders without its map.
    let kd_map = match m.get("kd_map") {
        Some(toml::Value::Table(_)) => {
            let Some(t) = m.table("kd_map")? else {
                unreachable!("a table")
            };
            if t.str("procedural")? != Some("checker") {
                return Err(t.error("procedural", "expected \"checker\""));
            }
            let squares = t.u32("squares")?.unwrap_or(8);
            if !(1..=256).contains(&squares) {
                return Err(t.error("squares", format!("must be 1 to 256, got {squares}")));
            }
            t.finish(&["procedural", "squares"])?;
            Some(MapSource::Checker { squares })
        }
        _ => m.str("kd_map")?.map(|written| MapSource::File {
            written: written.to_owned(),
            resolved: dir.join(written),
        }),
    };
    m.finish(&[
        "ka",
        "kd",
        "ks",
        "shininess",
        "specular",
        "fresnel",
        "emission",
        "bump",
        "kd_map",
    ])?;
    Ok(MaterialDef {
        material: mat,
        bump,
        kd_map,
    })
}

fn bump(b: &Fields<'_>, dir: &Path, files: &dyn Files) -> Result<(BumpSource, f32), SceneError> {
    let scale = b.f32("scale")?.unwrap_or(1.0);
    let file = |key: &str, m: &str| {
        let resolved = dir.join(m);
        if files.exists(&resolved) {
            Ok((m.to_owned(), resolved))
        } else {
            Err(b.error(key, format!("{}: no such file", resolved.display())))
        }
    };
    let source = match (b.str("procedural")?, b.str("map")?, b.str("normals")?) {
        (Some(p), None, None) => BumpSource::Procedural(choose(
            b,
            "procedural",
            p,
            &[
                ("bumps", ProceduralBump::Bumps),
                ("ripples", ProceduralBump::Ripples),
            ],
        )?),
        (None, Some(m), None) => {
            let (written, resolved) = file("map", m)?;
            BumpSource::Map { written, resolved }
        }
        (None, None, Some(m)) => {
            let (written, resolved) = file("normals", m)?;
            BumpSource::Normals { written, resolved }
        }
        _ => {
            return Err(b.error_here(
                "expected exactly one of `map = \"FILE\"` (heights), `normals = \"FILE\"` (a tangent-space normal map) or `procedural = \"bumps\" | \"ripples\"`",
            ));
        }
    };
    b.finish(&["map", "normals", "procedural", "scale"])?;
    Ok((source, scale))
}

fn primitive(p: &Fields<'_>) -> Result<Primitive, SceneError> {
    let shape = p.str("shape")?.ok_or_else(|| {
        p.error(
            "shape",
            "missing (\"sphere\", \"cube\", \"cylinder\", \"torus\" or \"plane\")",
        )
    })?;
    let positive = |key: &'static str, default: f32| -> Result<f32, SceneError> {
        let v = p.f32(key)?.unwrap_or(default);
        if v > 0.0 {
            Ok(v)
        } else {
            Err(p.error(key, format!("must be > 0, got {v}")))
        }
    };
    let count = |key: &'static str, default: u32, min: u32| -> Result<u32, SceneError> {
        let v = p.u32(key)?.unwrap_or(default);
        if (min..=4096).contains(&v) {
            Ok(v)
        } else {
            Err(p.error(key, format!("must be between {min} and 4096, got {v}")))
        }
    };
    let (prim, keys): (Primitive, &[&str]) = match shape {
        "sphere" => (
            Primitive::Sphere {
                radius: positive("radius", 1.0)?,
                segments: count("segments", 64, 3)?,
                rings: count("rings", 32, 2)?,
            },
            &["radius", "segments", "rings"],
        ),
        "cube" => (
            Primitive::Cube {
                half_size: positive("half_size", 0.5)?,
            },
            &["half_size"],
        ),
        "cylinder" => (
            Primitive::Cylinder {
                radius: positive("radius", 0.5)?,
                height: positive("height", 1.0)?,
                segments: count("segments", 48, 3)?,
            },
            &["radius", "height", "segments"],
        ),
        "torus" => (
            Primitive::Torus {
                major: positive("major", 0.7)?,
                minor: positive("minor", 0.25)?,
                segments: count("segments", 64, 3)?,
                sides: count("sides", 32, 3)?,
            },
            &["major", "minor", "segments", "sides"],
        ),
        "plane" => (
            Primitive::Plane {
                half_size: positive("half_size", 1.0)?,
                subdivisions: count("subdivisions", 1, 1)?,
            },
            &["half_size", "subdivisions"],
        ),
        other => {
            return Err(p.error(
                "shape",
                format!("unknown value \"{other}\" (expected \"sphere\", \"cube\", \"cylinder\", \"torus\" or \"plane\")"),
            ));
        }
    };
    let mut known = vec!["shape"];
    known.extend_from_slice(keys);
    p.finish(&known)?;
    Ok(prim)
}

fn normal_options(n: Option<Fields<'_>>) -> Result<NormalOptions, SceneError> {
    let mut opts = NormalOptions::default();
    let Some(n) = n else {
        return Ok(opts);
    };
    if let Some(w) = n.str("weighting")? {
        opts.weighting = choose(
            &n,
            "weighting",
            w,
            &[
                ("uniform", Weighting::Uniform),
                ("area", Weighting::Area),
                ("angle", Weighting::Angle),
            ],
        )?;
    }
    if let Some(a) = n.f32("crease_angle_deg")? {
        if !(0.0..=180.0).contains(&a) {
            return Err(n.error(
                "crease_angle_deg",
                format!("must be between 0 and 180, got {a}"),
            ));
        }
        opts.crease_angle_deg = Some(a);
    }
    if let Some(s) = n.bool("smoothing_groups")? {
        opts.use_smoothing_groups = s;
    }
    if let Some(s) = n.bool("split_by_material")? {
        opts.split_by_material = s;
    }
    if let Some(s) = n.str("source")? {
        opts.source = choose(
            &n,
            "source",
            s,
            &[
                ("file", NormalSource::Authored),
                ("computed", NormalSource::Computed),
            ],
        )?;
    }
    n.finish(&[
        "weighting",
        "crease_angle_deg",
        "smoothing_groups",
        "split_by_material",
        "source",
    ])?;
    Ok(opts)
}

fn transform(t: Option<Fields<'_>>) -> Result<Transform, SceneError> {
    let mut tr = Transform::default();
    let Some(t) = t else {
        return Ok(tr);
    };
    if let Some(v) = t.vec3("translate")? {
        tr.translate = v;
    }
    if let Some(v) = t.vec3("rotate_deg")? {
        tr.rotate_deg = v;
    }
    let scale = match t.get("scale").and_then(|v| v.as_array()) {
        Some(_) => t.vec3("scale")?,
        None => t.f32("scale")?.map(Vec3::splat),
    };
    if let Some(s) = scale {
        if s.abs().min_element() < 1e-12 {
            return Err(t.error("scale", "must not be zero (the object would vanish)"));
        }
        tr.scale = s;
    }
    t.finish(&["translate", "rotate_deg", "scale"])?;
    Ok(tr)
}

#[allow(
    clippy::too_many_arguments,
    reason = "one object reads the scene, its folder, its files, three caches and the memory taken"
)]
fn object(
    scene: &mut Scene,
    o: &Fields<'_>,
    index: usize,
    dir: &Path,
    files: &dyn Files,
    meshes: &mut HashMap<String, Arc<SceneMesh>>,
    gltfs: &mut HashMap<String, Arc<GltfAsset>>,
    bumps: &mut BTreeMap<String, Arc<BumpMap>>,
    maps: &mut BTreeMap<String, Option<Arc<Texture>>>,
    primitive_bytes: &mut u64,
) -> Result<(Entity, Motion), SceneError> {
    let name = o
        .str("name")?
        .map_or_else(|| format!("object {index}"), str::to_owned);
    let normals = normal_options(o.table("normals")?)?;
    let normalize = o.bool("normalize")?.unwrap_or(false);
    let source = match (o.str("mesh")?, o.table("primitive")?) {
        (Some(m), None) => MeshSource::File {
            written: m.to_owned(),
            resolved: dir.join(m),
        },
        (None, Some(p)) => MeshSource::Primitive(primitive(&p)?),
        _ => {
            return Err(o.error_here(
                "expected exactly one of `mesh = \"FILE.obj\"` or `primitive = { shape = ... }`",
            ));
        }
    };
    let is_gltf = matches!(&source, MeshSource::File { resolved, .. }
        if MeshFormat::from_path(resolved) == MeshFormat::Gltf);
    let loaded = if is_gltf {
        let key = format!("{source:?}|{normals:?}");
        let asset = match gltfs.get(&key) {
            Some(a) => a.clone(),
            None => {
                let a = Arc::new(gltf_asset(scene, o, &source, &normals, files)?);
                gltfs.insert(key, a.clone());
                a
            }
        };
        Loaded::Gltf(asset, source)
    } else {
        let key = format!("{source:?}|{normals:?}|{normalize}");
        Loaded::Mesh(match meshes.get(&key) {
            Some(m) => m.clone(),
            None => {
                let m = Arc::new(build_mesh(
                    scene,
                    o,
                    source,
                    normals,
                    normalize,
                    files,
                    primitive_bytes,
                )?);
                meshes.insert(key, m.clone());
                m
            }
        })
    };
    let material_name = o.str("material")?.unwrap_or("default");
    let def = match scene.materials.get(material_name) {
        Some(d) => d.clone(),
        None if material_name == "default" => MaterialDef {
            material: Material::default(),
            bump: None,
            kd_map: None,
        },
        None => {
            let known: Vec<&str> = scene.materials.keys().map(String::as_str).collect();
            return Err(o.error(
                "material",
                format!(
                    "unknown material \"{material_name}\" (defined: {})",
                    if known.is_empty() {
                        "none".to_owned()
                    } else {
                        known.join(", ")
                    }
                ),
            ));
        }
    };
    let shading = match o.str("shading")? {
        Some(s) => Some(Shading(
            s.parse::<ShadingChoice>()
                .map_err(|e| o.error("shading", e))?,
        )),
        None => None,
    };
    let role = ShadowRole {
        cast: o.bool("cast_shadows")?.unwrap_or(true),
        receive: o.bool("receive_shadows")?.unwrap_or(true),
    };
    let transform = transform(o.table("transform")?)?;
    let motion = super::motion::motion(o)?;
    o.finish(&[
        "cast_shadows",
        "receive_shadows",
        "name",
        "mesh",
        "primitive",
        "material",
        "normalize",
        "shading",
        "normals",
        "transform",
        "parent",
        "spin",
        "orbit",
        "bob",
        "animation",
        "children",
    ])?;
    let mesh = match loaded {
        Loaded::Mesh(mesh) => mesh,
        Loaded::Gltf(asset, source) => {
            let entity = scene.world.spawn((
                Name(name.clone()),
                transform,
                GltfRoot {
                    source,
                    normals,
                    normalized: normalize,
                },
                MaterialName(material_name.to_owned()),
            ));
            if let Some(s) = shading {
                scene.world.insert_one(entity, s).ok();
            }
            if role != ShadowRole::default() {
                scene.world.insert_one(entity, role).ok();
            }
            let before = scene.warnings.len();
            spawn_nodes(scene, entity, &name, &asset, normalize, |scene, e, mesh| {
                scene
                    .world
                    .insert(e, (def.material, MaterialName(material_name.to_owned())))
                    .ok();
                dress(
                    scene,
                    o,
                    e,
                    mesh,
                    (&def, material_name),
                    (shading, role),
                    files,
                    bumps,
                    maps,
                )
            })?;
            // One line per distinct warning, however many nodes share a material or map.
            let mut seen = HashSet::new();
            let mut k = before;
            while k < scene.warnings.len() {
                if seen.insert(scene.warnings[k].clone()) {
                    k += 1;
                } else {
                    scene.warnings.remove(k);
                }
            }
            return Ok((entity, motion));
        }
    };
    let entity = scene.world.spawn((
        Name(name),
        transform,
        MeshRef(mesh.clone()),
        def.material,
        MaterialName(material_name.to_owned()),
    ));
    dress(
        scene,
        o,
        entity,
        &mesh,
        (&def, material_name),
        (shading, role),
        files,
        bumps,
        maps,
    )?;
    Ok((entity, motion))
}

/// What an object's `mesh` or `primitive` loaded: one mesh, or a glTF node hierarchy (and
/// its source).
enum Loaded {
    Mesh(Arc<SceneMesh>),
    Gltf(Arc<GltfAsset>, MeshSource),
}

/// Reads the glTF file an object names as a node hierarchy; its warnings go to the scene.
fn gltf_asset(
    scene: &mut Scene,
    o: &Fields<'_>,
    source: &MeshSource,
    normals: &NormalOptions,
    files: &dyn Files,
) -> Result<GltfAsset, SceneError> {
    let MeshSource::File { resolved, .. } = source else {
        return Err(o.error("mesh", "a glTF node hierarchy is read from a file"));
    };
    let shown = resolved.display().to_string();
    let bytes = files
        .read_bytes(resolved)
        .map_err(|e| o.error("mesh", format!("{shown}: cannot read: {e}")))?;
    let read_relative = |rel: &str| files.read_asset(resolved, rel);
    let asset = load_gltf(&bytes, &shown, &read_relative, normals, source).map_err(|source| {
        SceneError::Mesh {
            file: o.file().to_owned(),
            field: o.path_of("mesh"),
            source,
        }
    })?;
    scene
        .warnings
        .extend(asset.warnings.iter().map(|w| format!("warning: {w}")));
    Ok(asset)
}

/// Gives an object's entity (or one glTF node's) its shading override, shadow role, bump
/// map and colour map: what its material `def` (named `material_name`) and its mesh say.
#[allow(
    clippy::too_many_arguments,
    reason = "the entity, its material, its overrides, the files and the two map caches"
)]
fn dress(
    scene: &mut Scene,
    o: &Fields<'_>,
    entity: Entity,
    mesh: &Arc<SceneMesh>,
    (def, material_name): (&MaterialDef, &str),
    (shading, role): (Option<Shading>, ShadowRole),
    files: &dyn Files,
    bumps: &mut BTreeMap<String, Arc<BumpMap>>,
    maps: &mut BTreeMap<String, Option<Arc<Texture>>>,
) -> Result<(), SceneError> {
    if let Some(s) = shading {
        scene.world.insert_one(entity, s).ok();
    }
    if role != ShadowRole::default() {
        scene.world.insert_one(entity, role).ok();
    }
    if let Some((src, scale)) = &def.bump {
        let key = material_name.to_owned();
        let map = match bumps.get(&key) {
            Some(m) => m.clone(),
            None => {
                let map = Arc::new(match src {
                    BumpSource::Procedural(kind) => BumpMap::Procedural {
                        kind: *kind,
                        scale: *scale,
                    },
                    BumpSource::Map { resolved, .. } | BumpSource::Normals { resolved, .. } => {
                        let normals = matches!(src, BumpSource::Normals { .. });
                        let field = || {
                            let key = if normals { "normals" } else { "map" };
                            format!("materials.{material_name}.bump.{key}")
                        };
                        let bytes = files.read_bytes(resolved).map_err(|e| {
                            SceneError::field(
                                o.file(),
                                field(),
                                format!("{}: cannot read: {e}", resolved.display()),
                            )
                        })?;
                        let decode = if normals {
                            super::bump_image::decode_normals
                        } else {
                            super::bump_image::decode
                        };
                        decode(&bytes, resolved, *scale)
                            .map_err(|e| SceneError::field(o.file(), field(), e))?
                    }
                });
                bumps.insert(key, map.clone());
                map
            }
        };
        if mesh.mesh.uvs.is_none() {
            scene.warnings.push(format!(
                "warning: {}: {}: material \"{material_name}\" has a bump map but the mesh has no texture coordinates; bump mapping is ignored",
                o.file(),
                o.path_of("material")
            ));
        }
        scene.world.insert_one(entity, Bump(map)).ok();
    } else if let Some(map) = mesh_normal_map(scene, o, mesh, bumps) {
        scene.world.insert_one(entity, Bump(map)).ok();
    }
    if let Some(map) = color_map(scene, o, material_name, def, mesh, files, maps) {
        scene.world.insert_one(entity, ColorMap(map)).ok();
    }
    Ok(())
}

/// Reads a map's encoded bytes when it is first needed.
type ReadBytes<'a> = Box<dyn Fn() -> std::io::Result<Arc<[u8]>> + 'a>;

/// The colour map of an object: its scene material's `kd_map`, else the one map every
/// material of its mesh names (MTL `map_Kd`, glTF `baseColorTexture`), decoded once per
/// image. A map that cannot be used is one warning naming the material, the map and the
/// file, and the object is drawn without it.
fn color_map(
    scene: &mut Scene,
    o: &Fields<'_>,
    material_name: &str,
    def: &MaterialDef,
    mesh: &SceneMesh,
    files: &dyn Files,
    maps: &mut BTreeMap<String, Option<Arc<Texture>>>,
) -> Option<Arc<Texture>> {
    let (what, key, wrap, factor, read): (String, String, _, Vec3, ReadBytes<'_>) = if let Some(
        src,
    ) =
        &def.kd_map
    {
        match src {
            MapSource::File { written, resolved } => {
                let resolved = resolved.clone();
                (
                    format!("material \"{material_name}\" kd_map \"{written}\""),
                    format!("file:{}", resolved.display()),
                    (Wrap::Repeat, Wrap::Repeat),
                    Vec3::ONE,
                    Box::new(move || files.read_bytes(&resolved).map(Arc::from)),
                )
            }
            MapSource::Checker { squares } => {
                mesh.mesh.uvs.as_ref()?;
                let key = format!("checker:{squares}");
                let map = maps.entry(key).or_insert_with(|| {
                    Some(Arc::new(checkerboard(
                        *squares,
                        (2048 / *squares).clamp(8, 64),
                        Vec3::ONE,
                        Vec3::splat(0.25),
                    )))
                });
                return map.clone();
            }
        }
    } else {
        let used: BTreeSet<u32> = mesh.mesh.material_ids.iter().copied().collect();
        // The map with its material's colour factor (glTF baseColorFactor, MTL Kd), which
        // multiplies it in both formats.
        let refs: Vec<Option<(&phosphor_mesh::TextureRef, Vec3)>> = used
            .iter()
            .map(|&i| {
                let m = mesh.mesh.materials.get(i as usize)?;
                Some((m.kd_map.as_ref()?, m.kd))
            })
            .collect();
        let (first, factor) = refs.iter().flatten().next().copied()?;
        if refs.iter().any(|r| *r != Some((first, factor))) {
            scene.warnings.push(format!(
                    "warning: {}: {}: the mesh's materials name different colour maps or colour factors (or some no map); one map per object is drawn, so none is",
                    o.file(),
                    o.path_of("mesh")
                ));
            return None;
        }
        let source = first.source.clone();
        (
            format!(
                "mesh material map \"{}\"",
                phosphor_mesh::sanitize::quote(&first.written, 80)
            ),
            format!("mesh:{:?}|{factor}", first.source),
            (wrap_of(first.wrap_u), wrap_of(first.wrap_v)),
            factor,
            Box::new(move || source.bytes()),
        )
    };
    if mesh.mesh.uvs.is_none() {
        scene.warnings.push(format!(
            "warning: {}: {}: {what}: the mesh has no texture coordinates; the map is not drawn",
            o.file(),
            o.path_of("material")
        ));
        return None;
    }
    let key = format!("{key}|{wrap:?}");
    if let Some(done) = maps.get(&key) {
        return done.clone();
    }
    let texture = read()
        .map_err(|e| format!("cannot read: {e}"))
        .and_then(|bytes| decode(&bytes, wrap))
        .map(|t| {
            if factor == Vec3::ONE {
                t
            } else {
                t.tinted(factor)
            }
        });
    let texture = match texture {
        Ok(t) => Some(Arc::new(t)),
        Err(e) => {
            scene.warnings.push(format!(
                "warning: {}: {}: {what}: {e}; drawn without it",
                o.file(),
                o.path_of("material")
            ));
            None
        }
    };
    maps.insert(key, texture.clone());
    texture
}

/// The normal map every material of the object's mesh names (MTL `norm`, glTF
/// `normalTexture` with its scale), when its scene material has no bump map, decoded once per
/// image and scale. As with colour maps, a map that cannot be used is one warning and the
/// object is drawn without it.
fn mesh_normal_map(
    scene: &mut Scene,
    o: &Fields<'_>,
    mesh: &SceneMesh,
    bumps: &mut BTreeMap<String, Arc<BumpMap>>,
) -> Option<Arc<BumpMap>> {
    let used: BTreeSet<u32> = mesh.mesh.material_ids.iter().copied().collect();
    let maps: Vec<_> = used
        .iter()
        .map(|&i| {
            mesh.mesh
                .materials
                .get(i as usize)
                .and_then(|m| m.normal_map.as_ref())
        })
        .collect();
    let (first, scale) = maps.iter().flatten().next().copied()?;
    let what = format!(
        "mesh material normal map \"{}\"",
        phosphor_mesh::sanitize::quote(&first.written, 80)
    );
    let warn = |scene: &mut Scene, why: &str| {
        scene.warnings.push(format!(
            "warning: {}: {}: {what}: {why}",
            o.file(),
            o.path_of("mesh")
        ));
    };
    if maps
        .iter()
        .any(|m| m.map(|(t, s)| (t, *s)) != Some((first, *scale)))
    {
        warn(
            scene,
            "the mesh's materials name different normal maps (or some none); one map per object is drawn, so none is",
        );
        return None;
    }
    if mesh.mesh.uvs.is_none() || mesh.mesh.tangents.is_none() {
        warn(
            scene,
            "the mesh has no texture coordinates (and so no tangents); the map is not drawn",
        );
        return None;
    }
    let key = format!("mesh-normals:{:?}|{scale}", first.source);
    if let Some(done) = bumps.get(&key) {
        return Some(done.clone());
    }
    let path = Path::new(&first.written);
    let map = first
        .source
        .bytes()
        .map_err(|e| format!("cannot read: {e}"))
        .and_then(|bytes| super::bump_image::decode_normals(&bytes, path, *scale));
    match map {
        Ok(map) => {
            let map = Arc::new(map);
            bumps.insert(key, map.clone());
            Some(map)
        }
        Err(e) => {
            warn(scene, &format!("{e}; drawn without it"));
            None
        }
    }
}

/// Deepest nesting of `children` tables.
const MAX_NESTING: usize = 64;

/// Appends `list` and, after each object, the objects of its `children` array (depth first),
/// each with the position in `out` of the object it is nested in.
fn nested_objects<'a>(
    list: Vec<Fields<'a>>,
    outer: Option<usize>,
    depth: usize,
    out: &mut Vec<(Fields<'a>, Option<usize>)>,
) -> Result<(), SceneError> {
    for o in list {
        let children = o.tables("children")?;
        if depth >= MAX_NESTING && !children.is_empty() {
            return Err(o.error(
                "children",
                format!("objects nest at most {MAX_NESTING} deep"),
            ));
        }
        out.push((o, outer));
        let me = out.len() - 1;
        nested_objects(children, Some(me), depth + 1, out)?;
    }
    Ok(())
}

/// Adds up the footprints of the scene's distinct primitives in file order and refuses the
/// first object that takes the total over [`PRIMITIVE_BUDGET_BYTES`], before any mesh is
/// built (building the earlier ones could take seconds and gigabytes first). A primitive
/// that does not parse is left for [`object`] to report in its turn.
fn check_primitive_budget<'a, 'b: 'a>(
    objects: impl Iterator<Item = &'a Fields<'b>>,
) -> Result<(), SceneError> {
    let mut seen = HashSet::new();
    let mut used = 0u64;
    for o in objects {
        let Ok(Some(p)) = o.table("primitive") else {
            continue;
        };
        let Ok(prim) = primitive(&p) else {
            continue;
        };
        if !seen.insert(format!("{prim:?}")) {
            continue;
        }
        let f = prim.footprint();
        f.check(PRIMITIVE_BUDGET_BYTES.saturating_sub(used))
            .map_err(|e| over_budget(o, &e, used))?;
        used = used.saturating_add(f.bytes());
    }
    Ok(())
}

/// The error for a primitive refused by the budget, or whose memory the system refused:
/// `objects[i].primitive.COUNT: the mesh needs N GB ...`, with what earlier objects hold.
fn over_budget(o: &Fields<'_>, e: &PrimitiveError, used: u64) -> SceneError {
    let mut what = e.what();
    if used > 0 {
        what.push_str(&format!(
            " (all primitives of a scene share {} GB; earlier objects take {} GB)",
            gigabytes(PRIMITIVE_BUDGET_BYTES),
            gigabytes(used)
        ));
    }
    o.error(&format!("primitive.{}", e.field()), what)
}

/// Builds an object's mesh. A primitive is checked against what is left of
/// [`PRIMITIVE_BUDGET_BYTES`] after the scene's earlier primitives (`primitive_bytes`, which
/// grows by its footprint) before anything is allocated.
fn build_mesh(
    scene: &mut Scene,
    o: &Fields<'_>,
    source: MeshSource,
    normals: NormalOptions,
    normalize: bool,
    files: &dyn Files,
    primitive_bytes: &mut u64,
) -> Result<SceneMesh, SceneError> {
    let mut mesh = match &source {
        MeshSource::Primitive(p) => {
            let left = PRIMITIVE_BUDGET_BYTES.saturating_sub(*primitive_bytes);
            let mesh = p
                .try_build(left)
                .map_err(|e| over_budget(o, &e, *primitive_bytes))?;
            *primitive_bytes = primitive_bytes.saturating_add(p.footprint().bytes());
            mesh
        }
        MeshSource::File { resolved, .. } if MeshFormat::from_path(resolved) != MeshFormat::Obj => {
            let shown = resolved.display().to_string();
            let bytes = files
                .read_bytes(resolved)
                .map_err(|e| o.error("mesh", format!("{shown}: cannot read: {e}")))?;
            let read_relative = |rel: &str| files.read_asset(resolved, rel);
            let format = MeshFormat::from_path(resolved);
            let (mesh, warnings) =
                phosphor_mesh::parse_mesh_bytes(&bytes, &shown, format, &read_relative, &normals)
                    .map_err(|source| SceneError::Mesh {
                    file: o.file().to_owned(),
                    field: o.path_of("mesh"),
                    source,
                })?;
            scene
                .warnings
                .extend(warnings.into_iter().map(|w| format!("warning: {w}")));
            mesh
        }
        MeshSource::File { written, resolved } => {
            let shown = resolved.display().to_string();
            let text = files
                .read_text(resolved)
                .map_err(|e| o.error("mesh", format!("{shown}: cannot read: {e}")))?;
            let mtl = mtl_text(&text, resolved, files);
            let (mesh, warnings) =
                phosphor_mesh::parse_obj_with_warnings(&text, &shown, mtl.as_deref(), &normals)
                    .map_err(|source| SceneError::Mesh {
                        file: o.file().to_owned(),
                        field: o.path_of("mesh"),
                        source,
                    })?;
            let _ = written;
            scene
                .warnings
                .extend(warnings.into_iter().map(|w| format!("warning: {w}")));
            mesh
        }
    };
    if normalize {
        mesh.normalize_unit();
    }
    if matches!(source, MeshSource::File { .. }) {
        // A file's triangles come in the order they were written, often all over the surface;
        // stored along a space-filling curve, a screen band's vertices sit together in memory.
        mesh.sort_spatially();
    }
    if mesh.uvs.is_some() {
        mesh.ensure_tangents();
    }
    let info = MeshInfo::of(&mesh);
    Ok(SceneMesh {
        mesh,
        source,
        normals,
        normalized: normalize,
        info,
    })
}

/// The text of the first MTL file an OBJ's `mtllib` line names, if it can be read.
fn mtl_text(obj: &str, obj_path: &Path, files: &dyn Files) -> Option<String> {
    let line = obj
        .lines()
        .map(str::trim_start)
        .find(|l| l.starts_with("mtllib "))?;
    let name = line["mtllib ".len()..].trim();
    let dir: PathBuf = obj_path.parent().unwrap_or(Path::new("")).to_path_buf();
    files.read_text(&dir.join(name)).ok()
}
