//! Scenes in code: typed builders that spawn complete entities.
//!
//! A scene file is one way to fill a [`Scene`]; these builders are the other. Meshes and
//! materials are made once and shared by handle ([`MeshHandle`], [`MaterialHandle`]: an `Arc`
//! each, cloned per entity), and [`Scene::object`] / [`Scene::light`] return a builder that
//! starts from defaults (identity transform, light on) and spawns an entity with every
//! component the renderer needs, so no object can be left out of a frame for want of one.
//! The builder wraps a [`hecs::EntityBuilder`]: [`ObjectBuilder::with`] adds any other
//! component. `parent`, `spin`, `orbit`, `bob` and `tracks` hang an entity off another and
//! set it moving ([`crate::hierarchy`], [`crate::animation`]): it is spawned at its rest
//! place; [`crate::animation::update`] poses the world at an instant.
//!
//! ```
//! use glam::Vec3;
//! use phosphor_lighting::{Light, Material};
//! use phosphor_scene::{Primitive, Scene};
//!
//! let mut scene = Scene::empty();
//! let ball = scene.primitive(Primitive::Sphere { radius: 1.0, segments: 24, rings: 12 })?;
//! let red = scene.add_material("red", Material { kd: Vec3::new(0.8, 0.1, 0.1), ..Material::default() })?;
//! let big = scene.object("big", &ball, &red).spawn();
//! let small = scene.object("small", &ball, &red).translate(Vec3::new(2.0, 0.0, 0.0)).scale(0.5).spawn();
//! scene.light("sun", Light::directional(Vec3::new(0.0, 0.0, -1.0), Vec3::ONE)?).spawn();
//! assert_eq!(scene.objects(), [big, small]);
//! // Both objects draw the one sphere.
//! assert_eq!(scene.triangle_count(), 2 * ball.0.mesh.indices.len());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Vec3};
use hecs::{Entity, EntityBuilder};
use phosphor_lighting::{Light, Material};
use phosphor_mesh::NormalOptions;
use phosphor_raster::{BumpMap, Texture};

use crate::Scene;
use crate::animation::{Bob, Orbit, Spin, Tracks};
use crate::components::{
    Bump, BumpSource, MaterialDef, MaterialName, MeshInfo, MeshRef, MeshSource, Name,
    PRIMITIVE_BUDGET_BYTES, Primitive, SceneMesh, Shading, ShadingChoice, Transform,
};
use crate::error::SceneError;
use crate::hierarchy::{
    GlobalTransform, LocalLight, LocalTransform, Parent, Pose, carry_light, transform_of,
};
use crate::textures::{ColorMap, MapSource, checkerboard};

/// A mesh shared by every object that draws it (cloning it clones an `Arc`).
#[derive(Debug, Clone)]
pub struct MeshHandle(pub Arc<SceneMesh>);

/// A material of the scene's table, shared by every object that uses it: its name, its
/// definition and its bump and colour maps, decoded once.
#[derive(Debug, Clone)]
pub struct MaterialHandle(Arc<MaterialEntry>);

#[derive(Debug)]
struct MaterialEntry {
    name: String,
    def: MaterialDef,
    bump: Option<Arc<BumpMap>>,
    map: Option<Arc<Texture>>,
}

impl MaterialHandle {
    /// The name in the scene's material table.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.0.name
    }

    /// The definition.
    #[must_use]
    pub fn def(&self) -> &MaterialDef {
        &self.0.def
    }
}

impl From<Material> for MaterialDef {
    fn from(material: Material) -> MaterialDef {
        MaterialDef {
            material,
            bump: None,
            kd_map: None,
        }
    }
}

impl SceneMesh {
    /// Wraps a built mesh with the figures the plan needs ([`MeshInfo::of`]).
    #[must_use]
    pub fn new(
        mesh: phosphor_mesh::Mesh,
        source: MeshSource,
        normals: NormalOptions,
        normalized: bool,
    ) -> SceneMesh {
        let info = MeshInfo::of(&mesh);
        SceneMesh {
            mesh,
            source,
            normals,
            normalized,
            info,
        }
    }
}

/// The error of a builder call, named as a scene file's would be (`code: FIELD: what`).
fn code_error(field: impl Into<String>, what: impl Into<String>) -> SceneError {
    SceneError::field("code", field.into(), what.into())
}

impl Scene {
    /// A primitive's mesh (built with its exact normals), to share between objects.
    ///
    /// # Errors
    /// A size that is not positive and finite, or a mesh over [`PRIMITIVE_BUDGET_BYTES`].
    pub fn primitive(&mut self, primitive: Primitive) -> Result<MeshHandle, SceneError> {
        let sizes: Vec<f32> = match primitive {
            Primitive::Sphere { radius, .. } => vec![radius],
            Primitive::Cube { half_size } | Primitive::Plane { half_size, .. } => vec![half_size],
            Primitive::Cylinder { radius, height, .. } => vec![radius, height],
            Primitive::Torus { major, minor, .. } => vec![major, minor],
        };
        if let Some(bad) = sizes.iter().find(|s| !(s.is_finite() && **s > 0.0)) {
            return Err(code_error(
                "primitive",
                format!("{primitive:?}: sizes must be > 0 and finite, got {bad}"),
            ));
        }
        // The counts scene files accept (file/load.rs `primitive`).
        let counts: Vec<(&str, u32, u32)> = match primitive {
            Primitive::Sphere {
                segments, rings, ..
            } => {
                vec![("segments", segments, 3), ("rings", rings, 2)]
            }
            Primitive::Cube { .. } => vec![],
            Primitive::Cylinder { segments, .. } => vec![("segments", segments, 3)],
            Primitive::Torus {
                segments, sides, ..
            } => {
                vec![("segments", segments, 3), ("sides", sides, 3)]
            }
            Primitive::Plane { subdivisions, .. } => vec![("subdivisions", subdivisions, 1)],
        };
        for (field, n, min) in counts {
            if !(min..=4096).contains(&n) {
                return Err(code_error(
                    format!("primitive.{field}"),
                    format!("must be between {min} and 4096, got {n}"),
                ));
            }
        }
        let mut mesh = primitive
            .try_build(PRIMITIVE_BUDGET_BYTES)
            .map_err(|e| code_error(format!("primitive.{}", e.field()), e.what()))?;
        if mesh.uvs.is_some() {
            mesh.ensure_tangents();
        }
        Ok(MeshHandle(Arc::new(SceneMesh::new(
            mesh,
            MeshSource::Primitive(primitive),
            NormalOptions::default(),
            false,
        ))))
    }

    /// A mesh file (OBJ, PLY, STL, glTF or GLB, by extension) with normals built as
    /// `normals` says; its warnings join [`Scene::warnings`]. Saved as `mesh = "PATH"`, the
    /// path as given.
    ///
    /// # Errors
    /// The mesh's error (file and line).
    pub fn mesh_file(
        &mut self,
        path: &Path,
        normals: NormalOptions,
    ) -> Result<MeshHandle, SceneError> {
        let (mut mesh, warnings) =
            phosphor_mesh::load_mesh_with_warnings(path, &normals).map_err(|source| {
                SceneError::Mesh {
                    file: "code".to_owned(),
                    field: "mesh".to_owned(),
                    source,
                }
            })?;
        mesh.sort_spatially();
        if mesh.uvs.is_some() {
            mesh.ensure_tangents();
        }
        self.warnings
            .extend(warnings.into_iter().map(|w| format!("warning: {w}")));
        let source = MeshSource::File {
            written: path.display().to_string(),
            resolved: path.to_path_buf(),
        };
        Ok(MeshHandle(Arc::new(SceneMesh::new(
            mesh, source, normals, false,
        ))))
    }

    /// Adds (or replaces) the material `name` in the scene's table, decoding its bump and
    /// colour maps once, and returns the handle objects share it by.
    ///
    /// # Errors
    /// A coefficient out of range ([`Material::validate`]), or a bump image that cannot be
    /// read. A colour map that cannot be read is a warning, as in scene files.
    pub fn add_material(
        &mut self,
        name: &str,
        def: impl Into<MaterialDef>,
    ) -> Result<MaterialHandle, SceneError> {
        let def = def.into();
        let field = |f: &str| format!("materials.{name}.{f}");
        def.material
            .validate()
            .map_err(|e| code_error(format!("materials.{name}"), e.to_string()))?;
        let bump = match &def.bump {
            None => None,
            Some((BumpSource::Procedural(kind), scale)) => Some(Arc::new(BumpMap::Procedural {
                kind: *kind,
                scale: *scale,
            })),
            Some((
                src @ (BumpSource::Map { resolved, .. } | BumpSource::Normals { resolved, .. }),
                scale,
            )) => {
                type Decode = fn(&[u8], &std::path::Path, f32) -> Result<BumpMap, String>;
                let (key, decode) = match src {
                    BumpSource::Normals { .. } => (
                        "bump.normals",
                        crate::file::bump_image::decode_normals as Decode,
                    ),
                    _ => ("bump.map", crate::file::bump_image::decode as Decode),
                };
                let bytes = std::fs::read(resolved).map_err(|e| {
                    code_error(
                        field(key),
                        format!("{}: cannot read: {e}", resolved.display()),
                    )
                })?;
                Some(Arc::new(
                    decode(&bytes, resolved, *scale).map_err(|e| code_error(field(key), e))?,
                ))
            }
        };
        let map = match &def.kd_map {
            None => None,
            Some(MapSource::Checker { squares }) => Some(Arc::new(checkerboard(
                *squares,
                (2048 / (*squares).max(1)).clamp(8, 64),
                Vec3::ONE,
                Vec3::splat(0.25),
            ))),
            Some(MapSource::File { resolved, written }) => {
                let decoded = std::fs::read(resolved)
                    .map_err(|e| format!("cannot read: {e}"))
                    .and_then(|bytes| {
                        crate::textures::decode(
                            &bytes,
                            (phosphor_raster::Wrap::Repeat, phosphor_raster::Wrap::Repeat),
                        )
                    });
                match decoded {
                    Ok(t) => Some(Arc::new(t)),
                    Err(e) => {
                        self.warnings.push(format!(
                            "warning: code: {}: \"{written}\": {e}; drawn without it",
                            field("kd_map")
                        ));
                        None
                    }
                }
            }
        };
        self.materials.insert(name.to_owned(), def.clone());
        Ok(MaterialHandle(Arc::new(MaterialEntry {
            name: name.to_owned(),
            def,
            bump,
            map,
        })))
    }

    /// Starts an object named `name` drawing `mesh` in `material`, at the origin, unscaled.
    pub fn object(
        &mut self,
        name: &str,
        mesh: &MeshHandle,
        material: &MaterialHandle,
    ) -> ObjectBuilder<'_> {
        ObjectBuilder {
            scene: self,
            name: name.to_owned(),
            mesh: mesh.clone(),
            material: material.clone(),
            transform: Transform::default(),
            motion: Motion::default(),
            extra: EntityBuilder::new(),
        }
    }

    /// Starts a light named `name`.
    pub fn light(&mut self, name: &str, light: Light) -> LightBuilder<'_> {
        LightBuilder {
            scene: self,
            name: name.to_owned(),
            light,
            motion: Motion::default(),
            extra: EntityBuilder::new(),
        }
    }
}

/// An object being built ([`Scene::object`]); [`ObjectBuilder::spawn`] makes the entity.
#[must_use = "nothing is spawned until `spawn` is called"]
pub struct ObjectBuilder<'a> {
    scene: &'a mut Scene,
    name: String,
    mesh: MeshHandle,
    material: MaterialHandle,
    transform: Transform,
    motion: Motion,
    extra: EntityBuilder,
}

/// The parent and motion components a builder was given.
#[derive(Default)]
struct Motion {
    parent: Option<Entity>,
    moves: bool,
}

/// The builder methods for a parent and motion, shared by objects and lights.
macro_rules! motion_methods {
    () => {
        /// Places it relative to `parent` (an entity that exists): its transform, or a
        /// light's position and direction, are then in the parent's space.
        pub fn parent(mut self, parent: Entity) -> Self {
            self.motion.parent = Some(parent);
            self
        }

        /// Turns it on the clock ([`Spin`]).
        pub fn spin(mut self, spin: Spin) -> Self {
            self.motion.moves = true;
            self.extra.add(spin);
            self
        }

        /// Moves it around a circle on the clock ([`Orbit`]).
        pub fn orbit(mut self, orbit: Orbit) -> Self {
            self.motion.moves = true;
            self.extra.add(orbit);
            self
        }

        /// Moves it up and down on the clock ([`Bob`]).
        pub fn bob(mut self, bob: Bob) -> Self {
            self.motion.moves = true;
            self.extra.add(bob);
            self
        }

        /// Moves it by keyframes ([`Tracks`]).
        pub fn tracks(mut self, tracks: Tracks) -> Self {
            self.motion.moves = true;
            self.extra.add(tracks);
            self
        }
    };
}

/// The world matrix of `parent` as it stands (its [`GlobalTransform`], else its
/// [`Transform`], else identity).
fn world_of(scene: &Scene, parent: Option<Entity>) -> Mat4 {
    let Some(p) = parent else {
        return Mat4::IDENTITY;
    };
    if let Ok(g) = scene.world.get::<&GlobalTransform>(p) {
        return g.0;
    }
    scene
        .world
        .get::<&Transform>(p)
        .map_or(Mat4::IDENTITY, |t| t.matrix())
}

/// Adds the hierarchy components of a posed entity (one with a parent or a motion) resting at
/// `rest`, and returns its world matrix at rest.
fn pose_components(
    scene: &Scene,
    motion: &Motion,
    rest: Transform,
    extra: &mut EntityBuilder,
) -> Option<Mat4> {
    if motion.parent.is_none() && !motion.moves {
        return None;
    }
    let world = world_of(scene, motion.parent) * rest.matrix();
    extra.add_bundle((
        LocalTransform(rest),
        Pose::from(rest),
        GlobalTransform(world),
    ));
    if let Some(p) = motion.parent {
        extra.add(Parent(p));
    }
    Some(world)
}

impl ObjectBuilder<'_> {
    motion_methods!();

    /// Places it at `t` (in its parent's space when it has one).
    pub fn translate(mut self, t: Vec3) -> Self {
        self.transform.translate = t;
        self
    }

    /// Rotates it by `deg` degrees about X, then Y, then Z (as scene files do).
    pub fn rotate_deg(mut self, deg: Vec3) -> Self {
        self.transform.rotate_deg = deg;
        self
    }

    /// Scales it uniformly.
    pub fn scale(mut self, s: f32) -> Self {
        self.transform.scale = Vec3::splat(s);
        self
    }

    /// Sets the whole transform.
    pub fn transform(mut self, t: Transform) -> Self {
        self.transform = t;
        self
    }

    /// Shades it with `choice` instead of the scene's `[render] shading`.
    pub fn shading(mut self, choice: ShadingChoice) -> Self {
        self.extra.add(Shading(choice));
        self
    }

    /// Whether it casts and receives shadows (`cast_shadows`, `receive_shadows`; both on
    /// unless set).
    pub fn shadows(mut self, cast: bool, receive: bool) -> Self {
        self.extra
            .add(crate::components::ShadowRole { cast, receive });
        self
    }

    /// Adds any other component.
    pub fn with<T: hecs::Component>(mut self, component: T) -> Self {
        self.extra.add(component);
        self
    }

    /// Spawns the object: [`Name`], [`Transform`], [`MeshRef`], the material (its
    /// coefficients and [`MaterialName`]) and, where the material has them and the mesh has
    /// texture coordinates, its [`Bump`] and [`ColorMap`]. A map the mesh cannot show is a
    /// warning in [`Scene::warnings`], as in scene files.
    pub fn spawn(self) -> Entity {
        let ObjectBuilder {
            scene,
            name,
            mesh,
            material,
            transform,
            motion,
            mut extra,
        } = self;
        let entry = &material.0;
        let placed = pose_components(scene, &motion, transform, &mut extra)
            .map_or(transform, |m| transform_of(m).0);
        extra.add_bundle((
            Name(name.clone()),
            placed,
            MeshRef(mesh.0.clone()),
            entry.def.material,
            MaterialName(entry.name.clone()),
        ));
        let has_uvs = mesh.0.mesh.uvs.is_some();
        for (what, present) in [
            ("a bump map", entry.bump.is_some()),
            ("a colour map", entry.map.is_some()),
        ] {
            if present && !has_uvs {
                scene.warnings.push(format!(
                    "warning: code: object \"{name}\": material \"{}\" has {what} but the mesh has no texture coordinates; it is not drawn",
                    entry.name
                ));
            }
        }
        if let Some(b) = &entry.bump {
            extra.add(Bump(b.clone()));
        }
        if let Some(m) = entry.map.as_ref().filter(|_| has_uvs) {
            extra.add(ColorMap(m.clone()));
        }
        scene.world.spawn(extra.build())
    }
}

/// A light being built ([`Scene::light`]); [`LightBuilder::spawn`] makes the entity.
#[must_use = "nothing is spawned until `spawn` is called"]
pub struct LightBuilder<'a> {
    scene: &'a mut Scene,
    name: String,
    light: Light,
    motion: Motion,
    extra: EntityBuilder,
}

impl LightBuilder<'_> {
    motion_methods!();

    /// Gives it shadows (`shadows = true`): a shadow map wherever the frame plan finds a
    /// caster between it and a visible receiver.
    pub fn shadows(mut self) -> Self {
        self.extra.add(crate::components::CastsShadows);
        self
    }

    /// Adds any other component.
    pub fn with<T: hecs::Component>(mut self, component: T) -> Self {
        self.extra.add(component);
        self
    }

    /// Spawns the light with its [`Name`] (with a parent: placed in the world, its own
    /// geometry kept as [`LocalLight`]).
    pub fn spawn(self) -> Entity {
        let LightBuilder {
            scene,
            name,
            mut light,
            motion,
            mut extra,
        } = self;
        if let Some(m) = pose_components(scene, &motion, Transform::default(), &mut extra) {
            extra.add(LocalLight(light.kind));
            light.kind = carry_light(light.kind, m);
        }
        extra.add_bundle((Name(name), light));
        scene.world.spawn(extra.build())
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use phosphor_lighting::LightKind;
    use phosphor_raster::Framebuffer;

    use super::*;
    use crate::animation::{Time, update};
    use crate::{FrameOptions, render_frame};

    fn ball_and_clay(scene: &mut Scene) -> (MeshHandle, MaterialHandle) {
        let ball = scene
            .primitive(Primitive::Sphere {
                radius: 1.0,
                segments: 12,
                rings: 6,
            })
            .unwrap();
        let clay = scene.add_material("clay", Material::s1()).unwrap();
        (ball, clay)
    }

    #[test]
    fn objects_built_in_code_share_their_mesh_and_are_complete() {
        let mut scene = Scene::empty();
        let (ball, clay) = ball_and_clay(&mut scene);
        let a = scene.object("a", &ball, &clay).spawn();
        let b = scene
            .object("b", &ball, &clay)
            .translate(Vec3::X)
            .shading(ShadingChoice::Mode(phosphor_raster::ShadingMode::Flat))
            .spawn();
        let (ma, mb) = (
            scene.world.get::<&MeshRef>(a).unwrap().0.clone(),
            scene.world.get::<&MeshRef>(b).unwrap().0.clone(),
        );
        assert!(Arc::ptr_eq(&ma, &mb), "one mesh, two objects");
        assert_eq!(scene.world.get::<&MaterialName>(b).unwrap().0, "clay");
        assert_eq!(scene.materials["clay"].material, Material::s1());
        assert_eq!(scene.world.get::<&Transform>(b).unwrap().translate, Vec3::X);
        assert!(crate::unrenderable(&scene.world).is_empty());
        let mut fb = Framebuffer::new(32, 24).unwrap();
        let report = render_frame(&scene, &mut fb, &FrameOptions::default());
        assert_eq!(report.plan.objects.len(), 2);
        assert_eq!(
            report.plan.objects[1].mode,
            phosphor_raster::ShadingMode::Flat
        );
    }

    #[test]
    fn bad_values_in_code_are_errors_naming_the_field() {
        let mut scene = Scene::empty();
        for r in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let e = scene
                .primitive(Primitive::Sphere {
                    radius: r,
                    segments: 8,
                    rings: 4,
                })
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("code: primitive: "), "{e}");
        }
        let e = scene
            .primitive(Primitive::Sphere {
                radius: 1.0,
                segments: u32::MAX,
                rings: u32::MAX,
            })
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "code: primitive.segments: must be between 3 and 4096, got 4294967295"
        );
        let bad = Material {
            kd: Vec3::new(f32::NAN, 0.0, 0.0),
            ..Material::default()
        };
        let e = scene.add_material("odd", bad).unwrap_err().to_string();
        assert!(e.starts_with("code: materials.odd: "), "{e}");
        assert!(
            scene.materials.is_empty(),
            "a refused material is not entered"
        );
    }

    #[test]
    fn an_object_missing_a_component_is_named_not_skipped_silently() {
        let mut scene = Scene::empty();
        let (ball, _) = ball_and_clay(&mut scene);
        let loose = scene.world.spawn((
            Transform::default(),
            MeshRef(ball.0.clone()),
            Material::s1(),
        ));
        let bare = scene.world.spawn((Name("bare".into()), MeshRef(ball.0)));
        let mut fb = Framebuffer::new(32, 24).unwrap();
        let report = render_frame(&scene, &mut fb, &FrameOptions::default());
        assert!(report.plan.objects.is_empty());
        assert_eq!(
            report.warnings,
            [
                format!(
                    "warning: entity {} has a mesh but no Name; it is not drawn (Scene::object spawns every component)",
                    loose.id()
                ),
                "warning: object \"bare\" has a mesh but no Transform, Material; it is not drawn (Scene::object spawns every component)".to_owned(),
            ]
        );
        let _ = bare;
        // A light without a name still shines, named by its entity.
        let sun = scene
            .world
            .spawn((Light::directional(-Vec3::Z, Vec3::ONE).unwrap(),));
        assert_eq!(scene.lights()[0].0, format!("entity {}", sun.id()));
    }

    #[test]
    fn children_are_spawned_in_place_and_follow_their_parent_on_the_clock() {
        let mut scene = Scene::empty();
        let (ball, clay) = ball_and_clay(&mut scene);
        let table = scene
            .object("table", &ball, &clay)
            .translate(Vec3::new(0.0, 0.0, -5.0))
            .spin(Spin {
                axis: Vec3::Y,
                deg_per_s: 90.0,
            })
            .spawn();
        let cup = scene
            .object("cup", &ball, &clay)
            .translate(Vec3::new(2.0, 0.0, 0.0))
            .scale(0.25)
            .parent(table)
            .spawn();
        let lamp = scene
            .light(
                "lamp",
                Light::point(Vec3::new(0.0, 1.0, 0.0), Vec3::ONE).unwrap(),
            )
            .parent(cup)
            .spawn();
        let cup_at = |s: &Scene| s.world.get::<&Transform>(cup).unwrap().translate;
        let lamp_at = |s: &Scene| match s.world.get::<&Light>(lamp).unwrap().kind {
            LightKind::Point { position } => position,
            k => panic!("{k:?}"),
        };
        assert!((cup_at(&scene) - Vec3::new(2.0, 0.0, -5.0)).length() < 1e-5);
        assert!((lamp_at(&scene) - Vec3::new(2.0, 0.25, -5.0)).length() < 1e-5);
        // A quarter turn of the table later, the cup and its lamp are on its -Z side.
        assert!(update(&mut scene, Time::at(1.0)).is_empty());
        assert!(
            (cup_at(&scene) - Vec3::new(0.0, 0.0, -7.0)).length() < 1e-4,
            "{}",
            cup_at(&scene)
        );
        assert!((lamp_at(&scene) - Vec3::new(0.0, 0.25, -7.0)).length() < 1e-4);
        let scale = scene.world.get::<&Transform>(cup).unwrap().scale;
        assert!(
            (scale - Vec3::splat(0.25)).abs().max_element() < 1e-6,
            "{scale}"
        );
    }
}
