//! The scenes that ship inside the binary: the default scene (so the viewer and the CLI run
//! with no arguments) and the standard scene S1 around any mesh.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use phosphor_lighting::{Light, Material};
use phosphor_mesh::{MAX_MESH_FILE_BYTES, MeshError, MeshFormat, NormalOptions};
use phosphor_raster::{Camera, Encoding};

use crate::components::{
    GltfRoot, MaterialDef, MaterialName, MeshInfo, MeshRef, MeshSource, Name, SceneMesh, Transform,
};
use crate::error::SceneError;
use crate::file::gltf_nodes::{load_gltf, spawn_nodes};
use crate::file::load::{Files, parse_scene};
use crate::{RenderSettings, Scene};

/// The default scene's text (`assets/scenes/default.toml`).
pub const DEFAULT_SCENE_TOML: &str = include_str!("../../../assets/scenes/default.toml");
/// The standard scene S1's text (`assets/scenes/s1.toml`).
pub const S1_TOML: &str = include_str!("../../../assets/scenes/s1.toml");

/// The meshes the default scene names, embedded.
const EMBEDDED: &[(&str, &str)] = &[
    (
        "meshes/fandisk.obj",
        include_str!("../../../assets/meshes/fandisk.obj"),
    ),
    (
        "meshes/teapot.obj",
        include_str!("../../../assets/meshes/teapot.obj"),
    ),
];

/// Files served from the binary (by the end of their path), for the default scene.
struct Embedded;

impl Files for Embedded {
    fn read_text(&self, path: &Path) -> std::io::Result<String> {
        let p = path.to_string_lossy().replace('\\', "/");
        EMBEDDED
            .iter()
            .find(|(name, _)| p.ends_with(name))
            .map(|(_, text)| (*text).to_owned())
            .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::NotFound, "not embedded"))
    }
    fn exists(&self, path: &Path) -> bool {
        self.read_text(path).is_ok()
    }
}

impl Scene {
    /// The embedded default scene: several objects and materials (a CAD mesh with creases, a
    /// shiny teapot, a bump-mapped sphere, a Fresnel torus, a matte floor), coloured point,
    /// spot, tube and directional lights, shading `auto`.
    ///
    /// # Errors
    /// Only if the embedded text is broken (a test guards it).
    pub fn default_scene() -> Result<Scene, SceneError> {
        let mut s = parse_scene(
            DEFAULT_SCENE_TOML,
            "default.toml (embedded)",
            Path::new("assets/scenes"),
            &Embedded,
        )?;
        s.source = None;
        Ok(s)
    }

    /// The standard scene S1 (docs/conventions.md) around the mesh file at `path` (OBJ, PLY, STL, glTF or
    /// GLB, by extension): normalized, normals averaged over every face sharing a position
    /// unless the file has authored normals (`vn`) or smoothing groups (`s` lines),
    /// three attenuated point lights, linear encoding.
    ///
    /// # Errors
    /// The mesh's error (file and line).
    pub fn s1_with_mesh(path: &Path) -> Result<Scene, SceneError> {
        Scene::s1_lights_with_mesh(path, NormalOptions::s1())
    }

    /// S1's lights, material and settings around the mesh file at `path` (any format [`Scene::s1_with_mesh`] takes; normalized), with
    /// normals built as `normals` says instead of S1's: what `--mesh` shows, where a cube
    /// should keep its edges. The camera is still S1's; callers frame the mesh themselves
    /// (see [`crate::view::framed_camera`]).
    ///
    /// # Errors
    /// The mesh's error (file and line).
    pub fn s1_lights_with_mesh(path: &Path, normals: NormalOptions) -> Result<Scene, SceneError> {
        if MeshFormat::from_path(path) == MeshFormat::Gltf {
            return Scene::s1_lights_with_gltf(path, normals);
        }
        let (mut mesh, warnings) =
            phosphor_mesh::load_mesh_with_warnings(path, &normals).map_err(|source| {
                SceneError::Mesh {
                    file: "S1".to_owned(),
                    field: "--mesh".to_owned(),
                    source,
                }
            })?;
        mesh.normalize_unit();
        // Render order (see `Mesh::sort_spatially`), as for every file a scene loads.
        mesh.sort_spatially();
        let info = MeshInfo::of(&mesh);
        let mesh = SceneMesh {
            mesh,
            source: MeshSource::File {
                written: path.display().to_string(),
                resolved: PathBuf::from(path),
            },
            normals,
            normalized: true,
            info,
        };
        Ok(Scene::s1_around(mesh, warnings))
    }

    /// S1's lights around a glTF file's node hierarchy (`crate::file::gltf_nodes`): a root
    /// named `mesh`, the nodes below it, the whole fitted into the unit sphere, posed at
    /// time 0.
    fn s1_lights_with_gltf(path: &Path, normals: NormalOptions) -> Result<Scene, SceneError> {
        let fail = |source| SceneError::Mesh {
            file: "S1".to_owned(),
            field: "--mesh".to_owned(),
            source,
        };
        let file = path.display().to_string();
        let bytes = phosphor_mesh::read_file(path, MAX_MESH_FILE_BYTES).map_err(|source| {
            fail(MeshError::Io {
                file: file.clone(),
                source,
            })
        })?;
        let source = MeshSource::File {
            written: file.clone(),
            resolved: PathBuf::from(path),
        };
        let read_relative = |rel: &str| phosphor_mesh::read_asset(path, rel);
        let asset = load_gltf(&bytes, &file, &read_relative, &normals, &source).map_err(fail)?;
        let mut s = Scene::s1_without_mesh(asset.warnings.clone());
        let root = s.world.spawn((
            Name("mesh".to_owned()),
            Transform::default(),
            GltfRoot {
                source,
                normals,
                normalized: true,
            },
            MaterialName("s1".to_owned()),
        ));
        spawn_nodes(&mut s, root, "mesh", &asset, true, |s, e, _| {
            s.world
                .insert(e, (Material::s1(), MaterialName("s1".to_owned())))
                .ok();
            Ok(())
        })?;
        let placed = crate::animation::update(&mut s, crate::animation::Time::default());
        s.warnings.extend(placed);
        Ok(s)
    }

    /// S1 around an already built mesh (used by [`Scene::s1_with_mesh`] and for primitives).
    #[must_use]
    pub fn s1_around(mesh: SceneMesh, warnings: Vec<String>) -> Scene {
        let mut s = Scene::s1_without_mesh(warnings);
        s.world.spawn((
            Name("mesh".to_owned()),
            Transform::default(),
            MeshRef(Arc::new(mesh)),
            Material::s1(),
            MaterialName("s1".to_owned()),
        ));
        s
    }

    /// S1's camera, lights, material and settings, with no object.
    fn s1_without_mesh(warnings: Vec<String>) -> Scene {
        let mut s = Scene::empty();
        s.settings = RenderSettings {
            encoding: Encoding::Linear,
            ..RenderSettings::default()
        };
        s.ambient = glam::Vec3::ONE;
        s.world.spawn((Camera::s1(),));
        for (i, l) in Light::s1_lights().into_iter().enumerate() {
            s.world.spawn((Name(format!("s1 light {}", i + 1)), l));
        }
        s.materials.insert(
            "s1".to_owned(),
            MaterialDef {
                material: Material::s1(),
                bump: None,
                kd_map: None,
            },
        );
        s.warnings = warnings
            .into_iter()
            .map(|w| format!("warning: {w}"))
            .collect();
        s
    }
}
