//! The render system: plan the frame from the world, then hand plain draw data to
//! phosphor-raster (which never sees hecs).

use std::time::{Duration, Instant};

use phosphor_raster::{DrawItem, Framebuffer, MeshView, RenderOptions, RenderStats};

use phosphor_lighting::Material;

use crate::Scene;
use crate::components::{MeshRef, Name, Transform};
use crate::plan::{FrameOptions, FramePlan, plan_frame};

/// What one frame did.
#[derive(Debug, Clone)]
pub struct FrameReport {
    /// The plan it followed.
    pub plan: FramePlan,
    /// The rasterizer's counts.
    pub stats: RenderStats,
    /// Time spent planning.
    pub plan_time: Duration,
    /// Time spent rasterizing and shading.
    pub raster_time: Duration,
    /// Entities with a mesh that were not drawn for want of a component
    /// ([`unrenderable`]), one `warning: ...` line each.
    pub warnings: Vec<String>,
}

/// The entities that have a mesh ([`MeshRef`]) but lack a component the frame plan needs to
/// draw them ([`Name`], [`Transform`], a [`Material`]): one `warning: ...` line each, naming
/// the entity and what it lacks. The plan draws only complete objects; this says which were
/// left out and why, instead of dropping them silently. [`Scene::object`] spawns complete
/// ones.
#[must_use]
pub fn unrenderable(world: &hecs::World) -> Vec<String> {
    let mut out: Vec<(u32, String)> = world
        .query::<(
            hecs::Entity,
            &MeshRef,
            Option<&Name>,
            Option<&Transform>,
            Option<&Material>,
        )>()
        .iter()
        .filter_map(|(e, _, n, t, m)| {
            let missing: Vec<&str> = [
                ("Name", n.is_none()),
                ("Transform", t.is_none()),
                ("Material", m.is_none()),
            ]
            .iter()
            .filter(|(_, gone)| *gone)
            .map(|(c, _)| *c)
            .collect();
            (!missing.is_empty()).then(|| {
                let who = n.map_or_else(|| format!("entity {}", e.id()), |n| format!("object \"{}\"", n.0));
                (
                    e.id(),
                    format!(
                        "warning: {who} has a mesh but no {}; it is not drawn (Scene::object spawns every component)",
                        missing.join(", ")
                    ),
                )
            })
        })
        .collect();
    out.sort();
    out.into_iter().map(|(_, w)| w).collect()
}

/// The raster draw list of a plan (borrows the plan).
#[must_use]
pub fn draw_items(plan: &FramePlan) -> Vec<DrawItem<'_>> {
    plan.objects
        .iter()
        .map(|o| {
            let m = &o.mesh.mesh;
            DrawItem {
                mesh: MeshView {
                    positions: &m.positions,
                    normals: &m.normals,
                    uvs: m.uvs.as_deref(),
                    tangents: m.tangents.as_deref(),
                    colors: m.colors.as_deref(),
                    indices: &m.indices,
                },
                model: o.model,
                material: &o.material,
                lights: &plan.light_sets[o.light_set],
                effects: o.effects,
                mode: o.mode,
                bump: o.bump.as_deref(),
                texture: o.texture.as_deref(),
                cull_backfaces: o.cull_backfaces,
            }
        })
        .collect()
}

/// The raster options of a scene under `opts`.
#[must_use]
pub fn raster_options(scene: &Scene, opts: &FrameOptions) -> RenderOptions {
    RenderOptions {
        threads: opts.threads,
        perspective_correct: opts
            .perspective_correct
            .unwrap_or(scene.settings.perspective_correct),
        // Decided per object by the plan (`PlannedObject::cull_backfaces`).
        cull_backfaces: false,
        background: scene.settings.background,
        antialias: opts.antialias.unwrap_or(scene.settings.antialias),
        gouraud_vertex_clamp: opts
            .gouraud_vertex_clamp
            .unwrap_or(scene.settings.gouraud_vertex_clamp),
        fast_phong: opts.fast_phong.unwrap_or(scene.settings.fast_phong),
        interpolation: opts.interpolation.unwrap_or(scene.settings.interpolation),
        simd: opts.simd,
    }
}

/// Plans and renders one frame of `scene` into `fb` (cleared first).
pub fn render_frame(scene: &Scene, fb: &mut Framebuffer, opts: &FrameOptions) -> FrameReport {
    let start = Instant::now();
    let camera = scene.camera();
    let plan = plan_frame(scene, &camera, (fb.width(), fb.height()), opts);
    let plan_time = start.elapsed();
    let start = Instant::now();
    let stats = phosphor_raster::render(
        fb,
        &camera,
        &draw_items(&plan),
        &raster_options(scene, opts),
    );
    FrameReport {
        plan,
        stats,
        plan_time,
        raster_time: start.elapsed(),
        warnings: unrenderable(&scene.world),
    }
}
