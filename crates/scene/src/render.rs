//! The render system: plan the frame from the world, then hand plain draw data to
//! phosphor-raster (which never sees hecs).

use std::time::{Duration, Instant};

use glam::Vec3;
use phosphor_lighting::{Light, LightSet, Material};
use phosphor_raster::shadow::{Caster, CubeShadow, LightMaps, Occluders, ShadowLight, ShadowMap};
use phosphor_raster::{
    Camera, DrawItem, Frame, Framebuffer, MeshView, RenderOptions, RenderStats, ShadingMode,
    WindowBuffer,
};

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
    /// Time spent rasterizing and shading (the shadow maps included).
    pub raster_time: Duration,
    /// Time spent rendering each shadow map, in the order of the plan's maps.
    pub shadow_times: Vec<Duration>,
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
        .map(|o| DrawItem {
            mesh: mesh_view(&o.mesh.mesh),
            model: o.model,
            material: &o.material,
            lights: &plan.light_sets[o.light_set],
            effects: o.effects,
            mode: o.mode,
            bump: o.bump.as_deref(),
            texture: o.texture.as_deref(),
            cull_backfaces: o.cull_backfaces,
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
        // Premultiplied: a pixel's colour and its opacity are averaged alike.
        background: scene.settings.background * scene.settings.background_alpha,
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
    frame_into(scene, fb, opts, None)
}

/// [`render_frame`], and the finished image read out into a window's buffer as
/// [`Framebuffer::write_0rgb_over`] reads it, by the last object's bands while their rows
/// are still in cache ([`phosphor_raster::Frame::show_in`]): a window's frame without a
/// second pass over the image.
pub fn render_frame_into(
    scene: &Scene,
    fb: &mut Framebuffer,
    opts: &FrameOptions,
    window: WindowBuffer<'_>,
) -> FrameReport {
    frame_into(scene, fb, opts, Some(window))
}

/// [`render_frame`] with an optional window buffer.
fn frame_into(
    scene: &Scene,
    fb: &mut Framebuffer,
    opts: &FrameOptions,
    window: Option<WindowBuffer<'_>>,
) -> FrameReport {
    let start = Instant::now();
    let camera = scene.camera();
    let plan = plan_frame(scene, &camera, (fb.width(), fb.height()), opts);
    let plan_time = start.elapsed();
    let start = Instant::now();
    let (stats, shadow_times) = draw_plan(
        scene,
        fb,
        (&camera, &plan),
        &raster_options(scene, opts),
        window,
    );
    FrameReport {
        plan,
        stats,
        plan_time,
        raster_time: start.elapsed(),
        shadow_times,
        warnings: unrenderable(&scene.world),
    }
}

/// A mesh as the rasterizer borrows it.
fn mesh_view(m: &phosphor_mesh::Mesh) -> MeshView<'_> {
    MeshView {
        positions: &m.positions,
        normals: &m.normals,
        uvs: m.uvs.as_deref(),
        tangents: m.tangents.as_deref(),
        colors: m.colors.as_deref(),
        indices: &m.indices,
    }
}

/// Draws `plan` into `fb`: its shadow maps first, then every object, the receivers of a map
/// with their shadowing lights apart ([`phosphor_raster::Frame::draw_shadowed`]). Without maps
/// this is [`phosphor_raster::render`] of [`draw_items`], the same bytes. Returns the
/// rasterizer's counts and each map's rendering time.
pub fn render_plan(
    scene: &Scene,
    fb: &mut Framebuffer,
    camera: &Camera,
    plan: &FramePlan,
    opts: &RenderOptions,
) -> (RenderStats, Vec<Duration>) {
    draw_plan(scene, fb, (camera, plan), opts, None)
}

/// [`render_plan`], reading the finished image out into `window` when given.
fn draw_plan(
    scene: &Scene,
    fb: &mut Framebuffer,
    (camera, plan): (&Camera, &FramePlan),
    opts: &RenderOptions,
    window: Option<WindowBuffer<'_>>,
) -> (RenderStats, Vec<Duration>) {
    let items = draw_items(plan);
    if plan.shadows.maps.is_empty() {
        return (
            phosphor_raster::render_into(fb, camera, &items, opts, window),
            Vec::new(),
        );
    }
    let lights = scene.lights();
    let mut times = Vec::new();
    let maps: Vec<Option<ShadowMap>> = plan
        .shadows
        .maps
        .iter()
        .map(|m| {
            let start = Instant::now();
            let casters: Vec<Caster> = m
                .casters
                .iter()
                .map(|&c| Caster {
                    mesh: mesh_view(&plan.casters[c].mesh.mesh),
                    model: plan.casters[c].model,
                })
                .collect();
            // The plan checked the size and the view; a map that still fails is left out.
            let map = ShadowMap::render(&m.view, m.size, &casters, opts).ok();
            times.push(start.elapsed());
            map
        })
        .collect();
    let occluders = exact_occluders(plan);
    let alone: Vec<LightSet> = plan
        .shadows
        .maps
        .iter()
        .map(|m| LightSet::new(Vec3::ZERO, &[lights[m.light].1]))
        .collect();
    let mut frame = Frame::new(fb, camera, opts);
    if let Some(w) = window {
        frame.show_in(w);
    }
    for (i, (o, d)) in plan.objects.iter().zip(&items).enumerate() {
        if i + 1 == plan.objects.len() {
            // The last object's bands resolve the anti-aliased image while in cache.
            frame.resolve_as_drawn();
        }
        let mine: Vec<usize> = (0..maps.len())
            .filter(|&k| maps[k].is_some() && plan.shadows.maps[k].receivers.contains(&i))
            .collect();
        if mine.is_empty() {
            frame.draw_item(d);
            continue;
        }
        // A receiver that cannot shadow itself lets its exact shadow rays pass its own
        // triangles.
        let own = plan.casters.iter().position(|c| c.is_self_of(o));
        // One entry per light: its map, or the faces of its cube map this object receives.
        let mut shadowed: Vec<ShadowLight> = Vec::new();
        let mut done: Vec<usize> = Vec::new();
        for &k in &mine {
            let (m, Some(map)) = (&plan.shadows.maps[k], maps[k].as_ref()) else {
                continue;
            };
            if done.contains(&m.light) {
                continue;
            }
            done.push(m.light);
            let light_maps = if m.face.is_some() {
                let mut faces = [None; 6];
                for &j in &mine {
                    let mj = &plan.shadows.maps[j];
                    if let (true, Some(face), Some(map)) = (mj.light == m.light, mj.face, &maps[j])
                    {
                        faces[face.index()] = Some(map);
                    }
                }
                LightMaps::Cube(CubeShadow {
                    position: m.view.toward,
                    faces,
                })
            } else {
                LightMaps::One(map)
            };
            // The light's occluders sit with its first map.
            let rays = plan
                .shadows
                .maps
                .iter()
                .position(|n| n.light == m.light)
                .and_then(|first| occluders[first].as_ref());
            shadowed.push(ShadowLight {
                set: &alone[k],
                maps: light_maps,
                rays: rays.map(|r| &r.0),
                rays_skip: rays
                    .zip(own)
                    .and_then(|(r, own)| r.1.iter().position(|&c| c == own)),
            });
        }
        let rest: Vec<Light> = o
            .lights
            .iter()
            .filter(|l| !done.contains(l))
            .map(|&l| lights[l].1)
            .collect();
        let rest = LightSet::new(scene.ambient, &rest);
        frame.draw_shadowed(d, &rest, &shadowed);
    }
    (frame.finish(), times)
}

/// The triangles that can block each light with shadows, for `reference`'s exact shadow rays,
/// with the plan's caster indices they came from (in the order [`Occluders`] numbers them):
/// at the index of the light's first map, those of all its maps. Built only when some object
/// is drawn in `reference`; `None` elsewhere.
fn exact_occluders(plan: &FramePlan) -> Vec<Option<(Occluders, Vec<usize>)>> {
    let exact = plan
        .objects
        .iter()
        .any(|o| o.mode == ShadingMode::Reference);
    let maps = &plan.shadows.maps;
    maps.iter()
        .enumerate()
        .map(|(k, m)| {
            let first = maps.iter().position(|n| n.light == m.light);
            if !exact || first != Some(k) {
                return None;
            }
            let mut ids: Vec<usize> = maps
                .iter()
                .filter(|n| n.light == m.light)
                .flat_map(|n| n.casters.iter().copied())
                .collect();
            ids.sort_unstable();
            ids.dedup();
            let casters: Vec<Caster> = ids
                .iter()
                .map(|&c| Caster {
                    mesh: mesh_view(&plan.casters[c].mesh.mesh),
                    model: plan.casters[c].model,
                })
                .collect();
            Some((Occluders::new(&casters), ids))
        })
        .collect()
}
