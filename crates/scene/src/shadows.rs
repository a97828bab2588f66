//! The shadow part of the frame plan: which lights get a map this frame, over which casters and
//! receivers, at what size, and why the others get none.
//!
//! A light's map is made only when some caster can stand between it and a visible receiver
//! that the light reaches, judged by bounding spheres
//! ([`phosphor_raster::shadow::can_shadow`]). An object counts as its own caster unless it
//! cannot shadow itself: a sphere, a cube or a cylinder primitive (convex, so the lighting's
//! `N.L <= 0` already darkens what faces away) or a flat mesh. So a single convex object over
//! nothing gets no map, and neither does a light behind every receiver. The map's view is
//! fitted to the casters and receivers that passed ([`phosphor_raster::shadow::fit()`]). A
//! point light's cube map makes a face only where one of those pairs both reach into it,
//! judged by sphere and world box ([`phosphor_raster::shadow::fit_cube`]).
//!
//! Size: the scene's `shadow_size`, or by default the next power of two above the largest
//! receiver's diameter on screen (capped by the picture's larger side), within
//! [`MIN_AUTO_SIZE`]..=[`MAX_AUTO_SIZE`]. The maps of a frame together stay within
//! [`MAX_SHADOW_BYTES`]: a map that would pass it is halved until it fits, before anything is
//! allocated.

use std::sync::Arc;

use glam::Mat4;
use phosphor_lighting::{Light, LightKind};
use phosphor_raster::shadow::{
    CubeFace, Extent, LightShape, LightView, NoMap, ShadowMap, Sphere, can_shadow, fit, fit_cube,
};
use phosphor_raster::{Camera, Projection};

use crate::Scene;
use crate::components::{
    CastsShadows, MeshRef, MeshSource, Name, Primitive, SceneMesh, ShadowRole, Transform,
};
use crate::planned::{FrameOptions, PlannedObject};

/// Smallest side the footprint rule picks.
pub const MIN_AUTO_SIZE: u32 = 256;
/// Largest side the footprint rule picks.
pub const MAX_AUTO_SIZE: u32 = 1024;
/// Most bytes the shadow maps of one frame may take while they are made.
pub const MAX_SHADOW_BYTES: u64 = 256 << 20;

/// One object that can cast, visible or not.
#[derive(Debug, Clone)]
pub struct ShadowCaster {
    /// Its name.
    pub name: String,
    /// Object to world.
    pub model: Mat4,
    /// The mesh.
    pub mesh: Arc<SceneMesh>,
    /// World bounding sphere.
    pub bounds: Sphere,
    /// Whether it can shadow itself.
    pub concave: bool,
}

impl ShadowCaster {
    /// Whether this caster is the planned object `o` (the same entity's mesh, placed alike),
    /// and so one that cannot shadow it where it is not concave.
    #[must_use]
    pub fn is_self_of(&self, o: &PlannedObject) -> bool {
        self.name == o.name && self.model == o.model && !self.concave
    }
}

/// A map the frame makes.
#[derive(Debug, Clone)]
pub struct PlannedShadow {
    /// The light (index into the plan's `light_names`).
    pub light: usize,
    /// The light's view, fitted.
    pub view: LightView,
    /// The face of the light's cube map this map is, or `None` for a light's only map.
    pub face: Option<CubeFace>,
    /// Side in texels.
    pub size: u32,
    /// Indices into the plan's `casters` of the casters drawn into it.
    pub casters: Vec<usize>,
    /// Indices into the plan's `objects` of the receivers that look it up.
    pub receivers: Vec<usize>,
    /// How the size was chosen.
    pub size_reason: String,
}

/// The shape of `light` for a map, or why it has none.
fn shape(light: &Light) -> Result<LightShape, &'static str> {
    match light.kind {
        LightKind::Directional { direction } => Ok(LightShape::Directional { direction }),
        LightKind::Spot {
            position,
            direction,
            outer_deg,
            ..
        } => Ok(LightShape::Spot {
            position,
            direction,
            outer_deg,
        }),
        LightKind::Point { position } => Ok(LightShape::Point { position }),
        LightKind::Tube { .. } | LightKind::Rect { .. } => {
            Err("area lights cast no shadow map (not implemented)")
        }
    }
}

/// Whether a mesh can shadow itself.
fn concave(mesh: &SceneMesh) -> bool {
    let convex = matches!(
        mesh.source,
        MeshSource::Primitive(
            Primitive::Sphere { .. } | Primitive::Cube { .. } | Primitive::Cylinder { .. }
        )
    );
    let flat = mesh.info.normal_cone.is_some_and(|(_, half)| half < 1e-4);
    !(convex || flat)
}

/// Every object that casts (in scene order), visible or not.
#[must_use]
pub fn casters(scene: &Scene) -> Vec<ShadowCaster> {
    let mut out: Vec<(u32, ShadowCaster)> = scene
        .world
        .query::<(
            hecs::Entity,
            &Name,
            &Transform,
            &MeshRef,
            Option<&ShadowRole>,
        )>()
        .iter()
        .filter(|(_, _, _, _, role)| role.is_none_or(|r| r.cast))
        .filter_map(|(e, n, t, m, _)| {
            let model = t.matrix();
            let bounds = Sphere {
                center: model.transform_point3(m.0.info.center),
                radius: m.0.info.radius * t.max_scale(),
            };
            (bounds.center.is_finite() && bounds.radius.is_finite()).then(|| {
                (
                    e.id(),
                    ShadowCaster {
                        name: n.0.clone(),
                        model,
                        mesh: m.0.clone(),
                        bounds,
                        concave: concave(&m.0),
                    },
                )
            })
        })
        .collect();
    out.sort_by_key(|(id, _)| *id);
    out.into_iter().map(|(_, c)| c).collect()
}

/// The diameter in pixels of `s` on screen (an estimate from its distance).
fn screen_diameter(s: &Sphere, camera: &Camera, height: u32) -> f32 {
    let world_height = match camera.projection {
        Projection::Perspective => {
            let d = (s.center - camera.eye).length().max(s.radius).max(1e-6);
            2.0 * d * (camera.fov_y_deg.to_radians() * 0.5).tan()
        }
        Projection::Orthographic { height } => height,
    };
    2.0 * s.radius / world_height * height as f32
}

/// Screen pixels per map texel that the footprint rule aims at. The lookup's tent filter
/// spreads every shadow edge over three texels, so a penumbra is soft whatever the map's
/// size; one texel per two pixels keeps it about six pixels wide, and costs a quarter of the
/// texels (and of the map's memory traffic) that one texel per pixel would.
pub const PIXELS_PER_TEXEL: f32 = 2.0;

/// The side the footprint rule picks for receivers `receivers`: the largest receiver's
/// diameter on screen (at most the picture's larger side) over [`PIXELS_PER_TEXEL`], rounded
/// to the nearest power of two, from [`MIN_AUTO_SIZE`] to [`MAX_AUTO_SIZE`].
#[must_use]
pub fn auto_size(receivers: &[Sphere], camera: &Camera, viewport: (u32, u32)) -> u32 {
    let largest = receivers
        .iter()
        .map(|s| screen_diameter(s, camera, viewport.1))
        .fold(0.0f32, f32::max)
        .min(viewport.0.max(viewport.1) as f32);
    let texels = largest / PIXELS_PER_TEXEL;
    let side = if texels.is_finite() && texels > 1.0 {
        // The nearer of the powers of two either side, in ratio (the geometric mean between).
        let up = (texels.ceil() as u32).next_power_of_two();
        if texels * texels * 2.0 < (up as f32) * (up as f32) {
            up / 2
        } else {
            up
        }
    } else {
        MIN_AUTO_SIZE
    };
    side.clamp(MIN_AUTO_SIZE, MAX_AUTO_SIZE)
}

/// The objects' world bounding spheres, as the plan measured them.
fn bounds_of(o: &PlannedObject) -> Sphere {
    let scale = o
        .model
        .to_scale_rotation_translation()
        .0
        .abs()
        .max_element();
    Sphere {
        center: o.model.transform_point3(o.mesh.info.center),
        radius: o.mesh.info.radius * scale,
    }
}

/// The world box of a mesh with object-space bounds `bounds` placed by `model`: the box of
/// its eight corners, or `None` where that is not finite.
fn world_box((lo, hi): (glam::Vec3, glam::Vec3), model: &Mat4) -> Option<(glam::Vec3, glam::Vec3)> {
    let corners = (0..8).map(|i| {
        let pick = |bit: usize, a: f32, b: f32| if i & bit == 0 { a } else { b };
        model.transform_point3(glam::Vec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        ))
    });
    let (min, max) = corners.fold(
        (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN)),
        |(a, b), p| (a.min(p), b.max(p)),
    );
    (min.is_finite() && max.is_finite()).then_some((min, max))
}

/// A map to make: the cube face it is (if any), its view, its casters and its receivers.
type View = (Option<CubeFace>, LightView, Vec<usize>, Vec<usize>);

/// The maps of a frame: those made, and one line per shadowing light that gets none.
#[derive(Debug, Clone, Default)]
pub struct ShadowPlan {
    /// The maps made.
    pub maps: Vec<PlannedShadow>,
    /// `(light, why not)` for the lights with shadows on that get no map.
    pub skipped: Vec<(usize, String)>,
    /// `(light, faces)`: the faces of a light's cube map not made, since no caster can shadow
    /// a visible receiver through them.
    pub faces_skipped: Vec<(usize, Vec<CubeFace>)>,
}

/// Plans the maps of a frame: `objects` are the visible objects planned, `casters` every
/// caster ([`casters`]), `lights` the scene's lights.
#[must_use]
pub fn plan_shadows(
    scene: &Scene,
    objects: &[PlannedObject],
    casters: &[ShadowCaster],
    (camera, viewport): (&Camera, (u32, u32)),
    opts: &FrameOptions,
) -> ShadowPlan {
    let mut plan = ShadowPlan::default();
    if opts.shadows == Some(false) {
        return plan;
    }
    let mut bytes = 0u64;
    for (li, e) in scene.light_entities().into_iter().enumerate() {
        let Ok(light) = scene.world.get::<&Light>(e).map(|l| *l) else {
            continue;
        };
        let wanted = opts.shadows == Some(true) || scene.world.get::<&CastsShadows>(e).is_ok();
        if !wanted {
            continue;
        }
        let mut skip = |why: &str| plan.skipped.push((li, why.to_owned()));
        if !light.enabled {
            skip("the light is off");
            continue;
        }
        let shape = match shape(&light) {
            Ok(s) => s,
            Err(why) => {
                skip(why);
                continue;
            }
        };
        let receivers: Vec<usize> = objects
            .iter()
            .enumerate()
            .filter(|(_, o)| o.receives_shadows && o.lights.contains(&li))
            .map(|(i, _)| i)
            .collect();
        if receivers.is_empty() {
            skip("it reaches no visible receiver");
            continue;
        }
        let mut used_casters = Vec::new();
        let mut used_receivers = Vec::new();
        let mut pairs = Vec::new();
        for (ci, c) in casters.iter().enumerate() {
            for &ri in &receivers {
                let r = &objects[ri];
                if c.is_self_of(r) {
                    continue;
                }
                if can_shadow(&shape, &c.bounds, &bounds_of(r)) {
                    if !used_casters.contains(&ci) {
                        used_casters.push(ci);
                    }
                    if !used_receivers.contains(&ri) {
                        used_receivers.push(ri);
                    }
                    pairs.push((ci, ri));
                }
            }
        }
        used_receivers.sort_unstable();
        // The pairs as positions in the used lists, for the cube's faces.
        let at = |list: &[usize], i: usize| list.iter().position(|&x| x == i).unwrap_or(0);
        let pairs: Vec<(usize, usize)> = pairs
            .iter()
            .map(|&(c, r)| (at(&used_casters, c), at(&used_receivers, r)))
            .collect();
        let caster_spheres: Vec<Sphere> = used_casters.iter().map(|&c| casters[c].bounds).collect();
        let receiver_spheres: Vec<Sphere> = used_receivers
            .iter()
            .map(|&r| bounds_of(&objects[r]))
            .collect();
        let (mut size, mut size_reason) = if scene.settings.shadow_size != 0 {
            (
                scene.settings.shadow_size,
                "the scene's shadow_size".to_owned(),
            )
        } else {
            (
                auto_size(&receiver_spheres, camera, viewport),
                "from the receivers' footprint on screen".to_owned(),
            )
        };
        // One view, or (a point light surrounded by its casters) the faces of a cube, each
        // with the casters drawn into it and the receivers that look it up.
        let cube = |size: u32| -> Result<Vec<View>, NoMap> {
            let LightShape::Point { position } = shape else {
                return Err(NoMap::TooWide);
            };
            let extent = |sphere: Sphere, bounds, model: &Mat4| Extent {
                sphere,
                aabb: world_box(bounds, model),
            };
            let caster_extents: Vec<Extent> = used_casters
                .iter()
                .map(|&c| {
                    extent(
                        casters[c].bounds,
                        casters[c].mesh.info.bounds,
                        &casters[c].model,
                    )
                })
                .collect();
            let receiver_extents: Vec<Extent> = used_receivers
                .iter()
                .map(|&r| {
                    let o = &objects[r];
                    extent(bounds_of(o), o.mesh.info.bounds, &o.model)
                })
                .collect();
            let faces = fit_cube(
                position,
                &caster_extents,
                &receiver_extents,
                Some(&pairs),
                size,
            )?;
            Ok(faces
                .into_iter()
                .map(|f| {
                    let cs = f.casters.iter().map(|&i| used_casters[i]).collect();
                    let rs = f.receivers.iter().map(|&i| used_receivers[i]).collect();
                    (Some(f.face), f.view, cs, rs)
                })
                .collect())
        };
        let mut views = match fit(&shape, &caster_spheres, &receiver_spheres) {
            Ok(v) => vec![(None, v, used_casters.clone(), used_receivers.clone())],
            Err(NoMap::TooWide) => match cube(size) {
                Ok(faces) => faces,
                Err(why) => {
                    skip(&why.to_string());
                    continue;
                }
            },
            Err(why) => {
                skip(&why.to_string());
                continue;
            }
        };
        let count = views.len() as u64;
        while bytes + count * ShadowMap::bytes_for(size) > MAX_SHADOW_BYTES
            && size > MIN_AUTO_SIZE / 4
        {
            size /= 2;
            size_reason = format!(
                "halved to fit the frame's {} MB of maps",
                MAX_SHADOW_BYTES >> 20
            );
        }
        if bytes + count * ShadowMap::bytes_for(size) > MAX_SHADOW_BYTES {
            skip("the frame's maps already take their memory budget");
            continue;
        }
        // A cube's faces are a little wider than 90 degrees by a number of texels: fitted
        // again at the size that was kept (the faces can only be fewer).
        if views[0].0.is_some() {
            let Ok(faces) = cube(size) else {
                skip("its cube map's faces no longer fit at the size kept");
                continue;
            };
            views = faces;
            let made: Vec<CubeFace> = views.iter().filter_map(|v| v.0).collect();
            let left: Vec<CubeFace> = CubeFace::ALL
                .into_iter()
                .filter(|f| !made.contains(f))
                .collect();
            if !left.is_empty() {
                plan.faces_skipped.push((li, left));
            }
        }
        bytes += views.len() as u64 * ShadowMap::bytes_for(size);
        for (face, view, casters, receivers) in views {
            plan.maps.push(PlannedShadow {
                light: li,
                view,
                face,
                size,
                casters,
                receivers,
                size_reason: size_reason.clone(),
            });
        }
    }
    plan
}
