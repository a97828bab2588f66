//! What the frame plan takes and gives per object: the frame-wide choices that override the
//! scene ([`FrameOptions`]) and one object as it will be drawn ([`PlannedObject`]). Kept apart
//! from the planning so that the shadow planning reads them without importing it.

use std::sync::Arc;

use glam::Mat4;
use hecs::Entity;
use phosphor_lighting::{Effects, Material};
use phosphor_raster::{Antialias, BumpMap, ShadingMode, Texture};

use crate::components::{SceneMesh, ShadingChoice};

/// Frame-wide choices that override the scene (command-line flags, viewer keys).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameOptions {
    /// Overrides every object's shading (`--shading`, viewer keys 1-5).
    pub shading: Option<ShadingChoice>,
    /// Bump mapping on (default) or off for every object.
    pub bump: bool,
    /// Colour maps on (default) or off for every object.
    pub textures: bool,
    /// Overrides the scene's `perspective_correct`.
    pub perspective_correct: Option<bool>,
    /// Worker threads, 0 = all cores.
    pub threads: usize,
    /// Overrides the scene's anti-aliasing (`--aa`, the viewer's `A` key).
    pub antialias: Option<Antialias>,
    /// Overrides the scene's `gouraud_clamp`.
    pub gouraud_vertex_clamp: Option<bool>,
    /// Overrides the scene's `fast_phong` (`--fast-phong`).
    pub fast_phong: Option<phosphor_raster::FastPhongMethod>,
    /// Overrides the scene's `interpolation` (`--interpolation`).
    pub interpolation: Option<phosphor_raster::Interpolation>,
    /// The vector width of per-pixel lighting (`--simd`; the same picture at every level).
    pub simd: phosphor_raster::SimdLevel,
    /// Overrides every light's `shadows` (`--shadows on|off`, the viewer's `H` key): `Some(false)`
    /// turns every shadow off, `Some(true)` turns them on for every directional, spot and
    /// point light.
    pub shadows: Option<bool>,
}

impl Default for FrameOptions {
    fn default() -> Self {
        FrameOptions {
            shading: None,
            bump: true,
            textures: true,
            perspective_correct: None,
            threads: 0,
            antialias: None,
            gouraud_vertex_clamp: None,
            fast_phong: None,
            interpolation: None,
            simd: phosphor_raster::SimdLevel::Auto,
            shadows: None,
        }
    }
}

/// One object as the plan will draw it.
#[derive(Debug, Clone)]
pub struct PlannedObject {
    /// The entity.
    pub entity: Entity,
    /// Its name.
    pub name: String,
    /// Object to world.
    pub model: Mat4,
    /// The mesh.
    pub mesh: Arc<SceneMesh>,
    /// The material.
    pub material: Material,
    /// The bump map, when bump mapping applies to this draw.
    pub bump: Option<Arc<BumpMap>>,
    /// The colour map, when the object has one, its mesh has uvs and maps are on.
    pub texture: Option<Arc<Texture>>,
    /// The mode chosen.
    pub mode: ShadingMode,
    /// Why that mode.
    pub reason: String,
    /// The terms simulated.
    pub effects: Effects,
    /// Indices (into the plan's `light_names`) of the lights that reach the object.
    pub lights: Vec<usize>,
    /// Index into the plan's `light_sets`.
    pub light_set: usize,
    /// Whether its back faces are skipped.
    pub cull_backfaces: bool,
    /// Why they are or are not.
    pub cull_reason: &'static str,
    /// Whether shadows fall on it (`receive_shadows`, on by default).
    pub receives_shadows: bool,
}
