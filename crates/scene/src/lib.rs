//! `phosphor-scene`: the ECS of Phosphor. A [hecs] `World` holds the objects (mesh, material,
//! transform, optional bump map and shading override), the lights and the camera; scene files
//! (TOML) load into it and save from it; the frame plan decides per object which effects to
//! simulate, which lights reach it and how to shade it, and which lights get a shadow map
//! ([`shadows`]); the render system hands plain draw data to `phosphor-raster`.
//!
//! Systems are free functions over the scene ([`plan::plan_frame`], [`render::render_frame`]);
//! there is no global state.
//!
//! A scene is built in code with typed builders ([`builder`]): meshes and materials are made
//! once and shared by handle, and each object or light is spawned complete, with defaults.
//!
//! ```
//! use glam::Vec3;
//! use phosphor_lighting::{Light, Material};
//! use phosphor_raster::Framebuffer;
//! use phosphor_scene::{FrameOptions, Primitive, Scene, render_frame, scene_to_toml};
//!
//! let mut scene = Scene::empty();
//! scene.ambient = Vec3::splat(0.1);
//! let ball = scene.primitive(Primitive::Sphere { radius: 1.0, segments: 32, rings: 16 })?;
//! let matte = scene.add_material(
//!     "matte",
//!     Material { kd: Vec3::new(0.8, 0.6, 0.4), ..Material::default() },
//! )?;
//! scene.object("ball", &ball, &matte).spawn();
//! scene
//!     .light("sun", Light::directional(Vec3::new(0.0, 0.0, -1.0), Vec3::new(1.0, 0.9, 0.8))?)
//!     .spawn();
//!
//! let mut fb = Framebuffer::new(64, 48)?;
//! let report = render_frame(&scene, &mut fb, &FrameOptions::default());
//! assert_eq!(report.plan.objects.len(), 1);
//! assert!(report.warnings.is_empty());
//! // A matte sphere under a distant light: `auto` needs no specular term.
//! assert!(!report.plan.objects[0].effects.contains(phosphor_lighting::Effects::SPECULAR));
//! assert!(fb.pixel(32, 24).x > 0.5);
//!
//! // Saved, it is a scene file that loads back to the same objects.
//! let text = scene_to_toml(&scene);
//! assert!(text.contains("[materials.matte]"), "{text}");
//! assert!(text.contains("kd = [0.8, 0.6, 0.4]"), "{text}");
//! let again = Scene::parse(&text, "saved.toml")?;
//! assert_eq!(again.objects().len(), 1);
//!
//! // Errors name the file and the field.
//! let err = Scene::parse("[camera]\nnear = -1\n", "bad.toml").unwrap_err();
//! assert_eq!(err.to_string(), "bad.toml: camera.near: must be > 0, got -1");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Scene files follow the format of docs/conventions.md ("Scene files"); see
//! `assets/scenes/default.toml` for every field.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::Vec3;
use hecs::{Entity, World};
use phosphor_lighting::Light;
use phosphor_raster::{Antialias, Camera, Encoding, FastPhongMethod, Interpolation};

pub mod animation;
pub mod budget;
pub mod builder;
pub mod builtin;
pub mod components;
pub mod error;
pub mod error_bound;
pub mod file;
pub mod hierarchy;
pub mod plan;
mod planned;
pub mod preset;
pub mod render;
pub mod shadows;
pub mod textures;
pub mod view;

pub use budget::{MAX_DISTRIBUTED_SAMPLES, SampleCut, limit_distributed_samples, point_samples};
pub use builder::{LightBuilder, MaterialHandle, MeshHandle, ObjectBuilder};
pub use components::{
    Bump, BumpSource, CastsShadows, GltfNode, GltfRoot, MaterialDef, MaterialName, MeshInfo,
    MeshRef, MeshSource, Name, Primitive, SceneMesh, Shading, ShadingChoice, ShadowRole, Transform,
};
pub use error::SceneError;
pub use error_bound::{ErrorBounds, shading_error_bounds};
pub use file::load::{
    Disk, Files, MAX_SCENE_BYTES, image_files, load_scene, load_scene_noting, parse_scene,
};
pub use file::save::{save_scene, scene_to_toml};
pub use plan::{
    AUTO_TOLERANCE, AutoInput, FrameOptions, FramePlan, PlannedObject, linear_tolerance,
    pixels_per_triangle, plan_frame,
};
pub use render::{
    FrameReport, draw_items, raster_options, render_frame, render_frame_into, render_plan,
    unrenderable,
};
pub use textures::ColorMap;

/// Largest accepted image side, in pixels.
pub const MAX_SIDE: u32 = 16_384;

/// The `[render]` table: output size and frame-wide choices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Width in pixels (default 1280).
    pub width: u32,
    /// Height in pixels (default 720).
    pub height: u32,
    /// Default shading of every object (`auto` unless set).
    pub shading: ShadingChoice,
    /// PNG encoding (sRGB unless set).
    pub encoding: Encoding,
    /// Clear colour (black unless set), linear, not multiplied by its opacity.
    pub background: Vec3,
    /// Opacity of the background in `[0, 1]` (1 unless set: `background = [r, g, b, a]`, or
    /// `"transparent"` for black at 0). A frame is cleared to `background` times it, so that
    /// the image holds colours premultiplied by its opacity
    /// ([`phosphor_raster::Framebuffer::alpha`]).
    pub background_alpha: f32,
    /// Perspective-correct interpolation (on unless set).
    pub perspective_correct: bool,
    /// Which back faces to skip (`auto` unless set: only where that cannot change a pixel).
    pub cull_backfaces: CullChoice,
    /// Anti-aliasing (`off` unless set): `msaa4`, `ssaa4`, `msaa16` and `ssaa16` draw 4 or 16
    /// samples per pixel, multisampled or supersampled ([`phosphor_raster::antialias`]).
    pub antialias: Antialias,
    /// `gouraud` clamps vertex intensities to 1 before interpolating (`gouraud_clamp`, on
    /// unless set; see [`phosphor_raster::RenderOptions::gouraud_vertex_clamp`]).
    pub gouraud_vertex_clamp: bool,
    /// How `fast-phong` makes its quadratics (`fast_phong = "fit" | "taylor"`, fit unless
    /// set).
    pub fast_phong: FastPhongMethod,
    /// How `gouraud` and `phong` interpolate (`interpolation = "plane" | "incremental"`, plane
    /// unless set).
    pub interpolation: Interpolation,
    /// Side of every shadow map in texels (`shadow_size`; 0, the default, derives it from the
    /// receivers' footprint on screen).
    pub shadow_size: u32,
}

/// Back-face culling of a scene (`[render] cull_backfaces`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CullChoice {
    /// Per object, where skipping back faces cannot change a pixel: a closed, outward
    /// oriented mesh ([`phosphor_mesh::is_closed_solid`]) under a transform that keeps its
    /// orientation, with the eye (and the near plane) outside its bounds.
    #[default]
    Auto,
    /// Every object's back faces (`true`): open meshes show holes where their back is seen.
    Always,
    /// None (`false`): both sides of every triangle are drawn.
    Never,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 1280,
            height: 720,
            shading: ShadingChoice::Auto,
            encoding: Encoding::Srgb,
            background: Vec3::ZERO,
            background_alpha: 1.0,
            perspective_correct: true,
            cull_backfaces: CullChoice::Auto,
            antialias: Antialias::Off,
            gouraud_vertex_clamp: true,
            fast_phong: FastPhongMethod::Fit,
            interpolation: Interpolation::Plane,
            shadow_size: 0,
        }
    }
}

/// A scene: the world and the few plain resources beside it.
pub struct Scene {
    /// Entities: objects, lights, the camera.
    pub world: World,
    /// The `[render]` table.
    pub settings: RenderSettings,
    /// Ambient intensity `Ia`.
    pub ambient: Vec3,
    /// The material table, by name (objects hold copies; kept for saving and the viewer).
    pub materials: BTreeMap<String, MaterialDef>,
    /// The file it was loaded from, if any.
    pub source: Option<PathBuf>,
    /// Warnings from loading (missing MTL, ignored bump maps), each a `warning: ...` line.
    pub warnings: Vec<String>,
    /// The clock the world was last posed at ([`animation::update`]).
    pub time: animation::Time,
}

impl std::fmt::Debug for Scene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Scene")
            .field("entities", &self.world.len())
            .field("settings", &self.settings)
            .field("ambient", &self.ambient)
            .field("source", &self.source)
            .finish_non_exhaustive()
    }
}

impl Scene {
    /// An empty scene: no camera (S1's is used), no lights, no objects.
    #[must_use]
    pub fn empty() -> Scene {
        Scene {
            world: World::new(),
            settings: RenderSettings::default(),
            ambient: Vec3::ZERO,
            materials: BTreeMap::new(),
            source: None,
            warnings: Vec::new(),
            time: animation::Time::default(),
        }
    }

    /// Parses scene text; `file` names it in messages and relative paths resolve against the
    /// current folder.
    ///
    /// # Errors
    /// [`SceneError`] naming the file and field.
    pub fn parse(text: &str, file: &str) -> Result<Scene, SceneError> {
        parse_scene(text, file, Path::new(""), &Disk)
    }

    /// Loads a scene file (paths inside relative to it).
    ///
    /// # Errors
    /// [`SceneError`] naming the file and field (and the OBJ line for meshes).
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        load_scene(path)
    }

    /// The entities that have a `T`, in scene order (spawn order).
    fn entities_with<T: hecs::Component>(&self) -> Vec<Entity> {
        let mut v: Vec<Entity> = self
            .world
            .query::<(Entity, &T)>()
            .iter()
            .map(|(e, _)| e)
            .collect();
        v.sort_by_key(|e| e.id());
        v
    }

    /// The camera: the first camera entity, or S1's.
    #[must_use]
    pub fn camera(&self) -> Camera {
        self.entities_with::<Camera>()
            .first()
            .and_then(|&e| self.world.get::<&Camera>(e).ok().map(|c| *c))
            .unwrap_or(Camera::s1())
    }

    /// Replaces the camera (creating the entity if there is none).
    pub fn set_camera(&mut self, camera: Camera) {
        let q = self.world.query_mut::<&mut Camera>();
        if let Some(c) = q.into_iter().next() {
            *c = camera;
            return;
        }
        self.world.spawn((camera,));
    }

    /// The lights with their names, in scene order.
    #[must_use]
    pub fn lights(&self) -> Vec<(String, Light)> {
        self.light_entities()
            .into_iter()
            .filter_map(|e| {
                // A light spawned without a name still shines; it is listed by its entity.
                let name = self
                    .world
                    .get::<&Name>(e)
                    .map_or_else(|_| format!("entity {}", e.id()), |n| n.0.clone());
                let light = *self.world.get::<&Light>(e).ok()?;
                Some((name, light))
            })
            .collect()
    }

    /// The light entities, in scene order.
    #[must_use]
    pub fn light_entities(&self) -> Vec<Entity> {
        self.entities_with::<Light>()
    }

    /// Number of lights.
    #[must_use]
    pub fn light_count(&self) -> usize {
        self.world.query::<&Light>().iter().count()
    }

    /// The object entities (those with a mesh), in scene order.
    #[must_use]
    pub fn objects(&self) -> Vec<Entity> {
        self.entities_with::<MeshRef>()
    }

    /// Triangles over all objects.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.world
            .query::<&MeshRef>()
            .iter()
            .map(|m| m.0.mesh.indices.len())
            .sum()
    }
}

#[cfg(test)]
mod tests;
