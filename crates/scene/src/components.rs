//! The components of the scene world and the plain data they carry.
//!
//! An object is an entity with [`Name`], [`Transform`], [`MeshRef`], a
//! [`phosphor_lighting::Material`], a [`MaterialName`], and optionally a [`Bump`] and a
//! [`Shading`] override. A light is an entity with [`Name`] and a [`phosphor_lighting::Light`].
//! The camera is an entity with a [`phosphor_raster::Camera`].

use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;
use std::sync::Arc;

use glam::{EulerRot, Mat4, Quat, Vec3};
use phosphor_mesh::{Mesh, NormalOptions};
use phosphor_raster::{BumpMap, ProceduralBump, ShadingMode};

/// A display name (objects and lights), used by `--plan` and the viewer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Name(pub String);

/// Object to world: scale, then rotation (degrees about X, then Y, then Z), then translation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// Translation.
    pub translate: Vec3,
    /// Rotation in degrees, applied about X first, then Y, then Z.
    pub rotate_deg: Vec3,
    /// Scale per axis.
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Transform {
            translate: Vec3::ZERO,
            rotate_deg: Vec3::ZERO,
            scale: Vec3::ONE,
        }
    }
}

impl Transform {
    /// The object-to-world matrix `T * Rz * Ry * Rx * S`.
    #[must_use]
    pub fn matrix(&self) -> Mat4 {
        let r = self.rotate_deg * (std::f32::consts::PI / 180.0);
        let rotation = Quat::from_euler(EulerRot::ZYX, r.z, r.y, r.x);
        Mat4::from_scale_rotation_translation(self.scale, rotation, self.translate)
    }

    /// The largest absolute scale factor: bounds a length's growth from object to world.
    #[must_use]
    pub fn max_scale(&self) -> f32 {
        self.scale.abs().max_element()
    }
}

/// A primitive shape with exact normals (phosphor-mesh's primitives).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Primitive {
    /// UV sphere.
    Sphere {
        /// Radius.
        radius: f32,
        /// Segments around the axis.
        segments: u32,
        /// Rings from pole to pole.
        rings: u32,
    },
    /// Axis-aligned cube.
    Cube {
        /// Half the edge length.
        half_size: f32,
    },
    /// Capped cylinder along Y.
    Cylinder {
        /// Radius.
        radius: f32,
        /// Height.
        height: f32,
        /// Segments around the axis.
        segments: u32,
    },
    /// Torus around Y.
    Torus {
        /// Radius of the centre circle.
        major: f32,
        /// Radius of the tube.
        minor: f32,
        /// Segments around the main axis.
        segments: u32,
        /// Segments around the tube.
        sides: u32,
    },
    /// Square in the XZ plane facing +Y.
    Plane {
        /// Half the edge length.
        half_size: f32,
        /// Cells per edge.
        subdivisions: u32,
    },
}

/// Memory all the primitive meshes of one scene may take while built, in bytes (each
/// distinct primitive counted once, by [`Primitive::footprint`]): room for one primitive at
/// the largest counts a scene file allows (4096 x 4096, about 2.7 GB), with the renderer's
/// own per-frame buffers still to fit beside it. The budget every mesh a file sizes is
/// checked against ([`phosphor_mesh::primitives::MEMORY_BUDGET_BYTES`]; a glTF file's placed
/// copies of its meshes share it too).
pub const PRIMITIVE_BUDGET_BYTES: u64 = phosphor_mesh::primitives::MEMORY_BUDGET_BYTES;

impl Primitive {
    /// The size of the mesh [`Primitive::build`] makes, known before building it.
    #[must_use]
    pub fn footprint(&self) -> phosphor_mesh::primitives::Footprint {
        use phosphor_mesh::primitives as p;
        match *self {
            Primitive::Sphere {
                segments, rings, ..
            } => p::uv_sphere_footprint(segments, rings),
            Primitive::Cube { .. } => p::cube_footprint(),
            Primitive::Cylinder { segments, .. } => p::cylinder_footprint(segments),
            Primitive::Torus {
                segments, sides, ..
            } => p::torus_footprint(segments, sides),
            Primitive::Plane { subdivisions, .. } => p::plane_footprint(subdivisions),
        }
    }

    /// Builds the mesh when its footprint is within `limit_bytes`, without aborting when the
    /// system refuses the memory; the error names the count that sized it.
    pub fn try_build(
        &self,
        limit_bytes: u64,
    ) -> Result<Mesh, phosphor_mesh::primitives::PrimitiveError> {
        use phosphor_mesh::primitives as p;
        match *self {
            Primitive::Sphere {
                radius,
                segments,
                rings,
            } => p::try_uv_sphere(radius, segments, rings, limit_bytes),
            Primitive::Cube { half_size } => Ok(p::cube(half_size)),
            Primitive::Cylinder {
                radius,
                height,
                segments,
            } => p::try_cylinder(radius, height, segments, limit_bytes),
            Primitive::Torus {
                major,
                minor,
                segments,
                sides,
            } => p::try_torus(major, minor, segments, sides, limit_bytes),
            Primitive::Plane {
                half_size,
                subdivisions,
            } => p::try_plane(half_size, subdivisions, limit_bytes),
        }
    }

    /// Builds the mesh.
    #[must_use]
    pub fn build(&self) -> Mesh {
        use phosphor_mesh::primitives as p;
        match *self {
            Primitive::Sphere {
                radius,
                segments,
                rings,
            } => p::uv_sphere(radius, segments, rings),
            Primitive::Cube { half_size } => p::cube(half_size),
            Primitive::Cylinder {
                radius,
                height,
                segments,
            } => p::cylinder(radius, height, segments),
            Primitive::Torus {
                major,
                minor,
                segments,
                sides,
            } => p::torus(major, minor, segments, sides),
            Primitive::Plane {
                half_size,
                subdivisions,
            } => p::plane(half_size, subdivisions),
        }
    }
}

/// Where an object's mesh came from (kept so a scene can be saved as it was written).
#[derive(Debug, Clone, PartialEq)]
pub enum MeshSource {
    /// A mesh file (OBJ, PLY, STL, glTF, GLB): the path as written in the scene file, and as
    /// resolved.
    File {
        /// As written (relative to the scene file).
        written: String,
        /// Resolved against the scene file's folder.
        resolved: PathBuf,
    },
    /// A primitive.
    Primitive(Primitive),
}

/// A mesh shared between entities, with what the planner needs to know about it.
#[derive(Debug)]
pub struct SceneMesh {
    /// The triangles.
    pub mesh: Mesh,
    /// Where it came from.
    pub source: MeshSource,
    /// The normal options it was built with.
    pub normals: NormalOptions,
    /// Whether it was normalized (bounding-box centre to origin, farthest vertex at 1).
    pub normalized: bool,
    /// Bounds and shape figures for the frame plan.
    pub info: MeshInfo,
}

/// On the entity a scene file's object names a glTF file with: the root of the file's node
/// hierarchy, whose entities ([`GltfNode`]) hang below it. It has no mesh of its own; its
/// transform and motion move the whole tree. Kept so the scene saves as it was written.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfRoot {
    /// The file (the path as written, and as resolved).
    pub source: MeshSource,
    /// The normal options its meshes were built with.
    pub normals: NormalOptions,
    /// Whether the whole hierarchy was fitted into the unit sphere (`normalize`).
    pub normalized: bool,
}

/// On each entity made from a glTF node: the [`GltfRoot`] entity it belongs to and the
/// node's index in the file. These entities come from the file, so a saved scene does not
/// write them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GltfNode {
    /// The root entity.
    pub root: hecs::Entity,
    /// The node's index (`nodes[i]`); `None` for the entity that applies `normalize`.
    pub node: Option<usize>,
}

/// An object's mesh: an `Arc` shared by every entity that draws it.
#[derive(Debug, Clone)]
pub struct MeshRef(pub Arc<SceneMesh>);

/// The name of an object's material in the scene's material table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MaterialName(pub String);

/// A bump map in a material: where its height field comes from, and its slope scale.
#[derive(Debug, Clone, PartialEq)]
pub enum BumpSource {
    /// A built-in height field.
    Procedural(ProceduralBump),
    /// A height-field image, as written in the scene file and as resolved.
    Map {
        /// As written.
        written: String,
        /// Resolved against the scene file's folder.
        resolved: PathBuf,
    },
    /// A tangent-space normal-map image (`2 c - 1` per channel, `+y` towards `+v`), as
    /// written in the scene file and as resolved.
    Normals {
        /// As written.
        written: String,
        /// Resolved against the scene file's folder.
        resolved: PathBuf,
    },
}

/// An object's bump map (present only on objects whose material has one).
#[derive(Debug, Clone)]
pub struct Bump(pub Arc<BumpMap>);

/// How an object is shaded: `auto` or a fixed mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ShadingChoice {
    /// The cheapest mode that is good enough (the plan decides per object).
    #[default]
    Auto,
    /// A fixed mode.
    Mode(ShadingMode),
}

impl ShadingChoice {
    /// The name used in scene files and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ShadingChoice::Auto => "auto",
            ShadingChoice::Mode(m) => m.name(),
        }
    }
}

impl fmt::Display for ShadingChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ShadingChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s == "auto" {
            return Ok(ShadingChoice::Auto);
        }
        s.parse::<ShadingMode>()
            .map(ShadingChoice::Mode)
            .map_err(|_| {
                let modes: Vec<String> = ShadingMode::ALL
                    .iter()
                    .map(|m| format!("\"{m}\""))
                    .collect();
                let (last, rest) = modes
                    .split_last()
                    .map_or(("", &[][..]), |(l, r)| (l.as_str(), r));
                format!(
                    "unknown shading \"{s}\" (expected \"auto\", {} or {last})",
                    rest.join(", ")
                )
            })
    }
}

/// An object's own shading choice, overriding the scene's `[render] shading`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shading(pub ShadingChoice);

/// On a light: it casts shadows (`shadows = true` in a scene file; off without this
/// component). Its shadow map is made only when the frame plan finds a caster that can stand
/// between it and a visible receiver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CastsShadows;

/// On an object: whether it casts and receives shadows (`cast_shadows`, `receive_shadows`;
/// both on without this component).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShadowRole {
    /// It can darken other objects (and itself).
    pub cast: bool,
    /// Shadows fall on it.
    pub receive: bool,
}

impl Default for ShadowRole {
    fn default() -> Self {
        ShadowRole {
            cast: true,
            receive: true,
        }
    }
}

/// Figures about a mesh that the frame plan uses, computed once per mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshInfo {
    /// Axis-aligned bounds (object space): lowest and highest corner.
    pub bounds: (Vec3, Vec3),
    /// Centre of the bounding sphere (object space).
    pub center: Vec3,
    /// Radius of the bounding sphere (object space).
    pub radius: f32,
    /// The longest triangle edge (object space).
    pub max_edge: f32,
    /// The largest angle between two vertex normals of one triangle, radians.
    pub max_normal_spread: f32,
    /// The 90th percentile of that angle over the triangles: the spread of a typical
    /// triangle, not of the worst one (a crease-split sliver should not decide for a mesh).
    pub typical_normal_spread: f32,
    /// Every triangle's vertex normals equal its face normal (within 1e-3 rad): a polyhedron,
    /// the lecture notes' condition (c) for flat shading.
    pub polyhedron: bool,
    /// Axis of a cone holding every vertex normal, when one narrower than 90 degrees exists.
    pub normal_cone: Option<(Vec3, f32)>,
    /// The mesh bounds a solid: closed, consistently and outwardly oriented
    /// ([`phosphor_mesh::is_closed_solid`]), so its back faces are hidden from outside.
    pub closed: bool,
}

/// Angle between two unit vectors, robust near 0 and pi.
fn angle_between(a: Vec3, b: Vec3) -> f32 {
    let cross = a.cross(b).length();
    cross.atan2(a.dot(b))
}

impl MeshInfo {
    /// Measures `mesh`. Degenerate and out-of-range triangles are ignored.
    #[must_use]
    pub fn of(mesh: &Mesh) -> MeshInfo {
        let (lo, hi) = mesh.bounds();
        let center = if lo.is_finite() && hi.is_finite() {
            (lo + hi) * 0.5
        } else {
            Vec3::ZERO
        };
        let radius = mesh
            .positions
            .iter()
            .filter(|p| p.is_finite())
            .map(|p| p.distance(center))
            .fold(0.0f32, f32::max);
        let mut max_edge = 0.0f32;
        let mut spreads = Vec::with_capacity(mesh.indices.len());
        let mut polyhedron = true;
        for (t, tri) in mesh.indices.iter().enumerate() {
            let Some([a, b, c]) = mesh.triangle_positions(t) else {
                continue;
            };
            max_edge = max_edge
                .max(a.distance(b))
                .max(b.distance(c))
                .max(c.distance(a));
            let n = tri.map(|i| mesh.normals.get(i as usize).copied().unwrap_or(Vec3::ZERO));
            spreads.push(
                angle_between(n[0], n[1])
                    .max(angle_between(n[1], n[2]))
                    .max(angle_between(n[2], n[0])),
            );
            if polyhedron && let Some(face) = mesh.face_normal(t) {
                polyhedron = n.iter().all(|v| angle_between(*v, face) < 1e-3);
            }
        }
        let spread = spreads.iter().copied().fold(0.0f32, f32::max);
        let typical = if spreads.is_empty() {
            0.0
        } else {
            let k = (spreads.len() * 9 / 10).min(spreads.len() - 1);
            *spreads.select_nth_unstable_by(k, f32::total_cmp).1
        };
        MeshInfo {
            bounds: if lo.is_finite() && hi.is_finite() {
                (lo, hi)
            } else {
                (Vec3::ZERO, Vec3::ZERO)
            },
            center,
            radius,
            max_edge,
            max_normal_spread: spread,
            typical_normal_spread: typical,
            polyhedron,
            normal_cone: normal_cone(&mesh.normals),
            closed: phosphor_mesh::is_closed_solid(&mesh.positions, &mesh.indices),
        }
    }
}

/// A cone (axis, half-angle) holding every normal, when the normals' mean direction gives
/// one narrower than 90 degrees; `None` otherwise (a closed object faces every way).
fn normal_cone(normals: &[Vec3]) -> Option<(Vec3, f32)> {
    let sum: Vec3 = normals.iter().copied().filter(|n| n.is_finite()).sum();
    let axis = sum.try_normalize()?;
    let half = normals
        .iter()
        .filter(|n| n.is_finite())
        .map(|n| angle_between(axis, n.normalize_or_zero()))
        .fold(0.0f32, f32::max);
    (half < std::f32::consts::FRAC_PI_2 - 1e-3).then_some((axis, half))
}

/// A material as the scene file defines it: the lighting coefficients and an optional bump.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialDef {
    /// The coefficients.
    pub material: phosphor_lighting::Material,
    /// The bump map, if any: source and slope scale.
    pub bump: Option<(BumpSource, f32)>,
    /// The colour map (`kd_map`), if any: it scales the ambient and diffuse light.
    pub kd_map: Option<crate::textures::MapSource>,
}
