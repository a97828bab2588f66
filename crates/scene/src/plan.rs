//! The frame plan: which objects to draw, which effects each needs, which lights reach it,
//! and how to shade it ("simulate only the effects a scene calls for").
//!
//! A light is dropped for an object only where its contribution there is exactly zero, so the
//! planned picture equals the full model's pixel for pixel:
//! - disabled or zero-intensity lights;
//! - the wrong side: every normal of the object lies in a cone that faces away from every
//!   direction towards the light over the object's bounding sphere (`N.L <= 0` everywhere, so
//!   the diffuse and specular terms are both 0); never for bump-mapped objects, whose
//!   normals leave the cone;
//! - out of range: a spot light whose outer cone misses the bounding sphere.
//!
//! Attenuation models (`1/d^2`, `1/(K+d)`, ...) never reach exactly zero, so a distant light is
//! kept: dropping it would change the picture.
//!
//! Effects: the intersection of what the material can show and what the kept lights can
//! produce ([`phosphor_lighting::effects_for`]), plus BUMP for a bump-mapped object drawn per
//! pixel. The raster kernel is compiled per effect set, so an absent term costs nothing.
//!
//! Shading `auto` uses the lecture notes' conditions for flat shading, with error estimates against
//! one 8-bit code ([`AUTO_TOLERANCE`]): see [`choose_mode`].

use std::collections::HashMap;
use std::fmt;
use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use hecs::Entity;
use phosphor_lighting::{
    Attenuation, Effects, Light, LightKind, LightSet, Material, SpecularModel,
};
use phosphor_raster::{Antialias, BumpMap, Camera, Projection, ShadingMode, Texture};

use crate::components::{
    Bump, MeshInfo, MeshRef, Name, SceneMesh, Shading, ShadingChoice, Transform,
};
use crate::textures::ColorMap;
use crate::{CullChoice, Scene};

/// `auto` accepts a cheaper mode when its estimated error is at most this (one 8-bit code).
pub const AUTO_TOLERANCE: f32 = 1.0 / 255.0;

/// `auto` picks `fast-phong` over `phong` only where an object's triangles cover at least this
/// many pixels each on average (estimated, [`pixels_per_triangle`]): below it fast Phong fits
/// almost no triangle (it fits only those of `MIN_FIT_AREA_PX`, 128 px, or more, and shades
/// the rest as `phong` does) and its per-triangle checks cost a few percent. Measured on S1's
/// sphere at 1920x1080 with the spheres `auto` sends to this rule (128 to 256 segments), in
/// instructions (callgrind, one thread, two frames; `phosphor bench SCENE --threads 1
/// --frames 1`), fast-phong against phong: 497 against 671 M at 128 segments (est. 83 px per
/// triangle), 675 against 763 M at 192 (37 px), 885 against 872 M at 256 (21 px).
pub const FAST_PHONG_MIN_PIXELS: f32 = 32.0;

/// Estimated screen pixels per front-facing triangle of an object with bounding sphere
/// (`center`, `radius`) and `triangles` triangles, seen from `eye` with vertical field of view
/// `fov_y_deg` in a `width` x `height` viewport: the area of the sphere's projected disc (at
/// most the viewport) over half the triangles (a closed mesh shows about half of them).
#[must_use]
pub fn pixels_per_triangle(
    (center, radius): (Vec3, f32),
    eye: Vec3,
    fov_y_deg: f32,
    (width, height): (u32, u32),
    triangles: usize,
) -> f32 {
    let viewport = width as f32 * height as f32;
    let d = center.distance(eye);
    let tan_half = (fov_y_deg.to_radians() * 0.5).tan();
    let area = if d > radius && tan_half > 0.0 {
        // Angular radius asin(r/d), projected: tan = r / sqrt(d^2 - r^2).
        let r_px = radius / (d * d - radius * radius).sqrt() / tan_half * height as f32 * 0.5;
        (std::f32::consts::PI * r_px * r_px).min(viewport)
    } else {
        viewport
    };
    let px = area / (triangles as f32 * 0.5).max(1.0);
    if px.is_finite() { px } else { 0.0 }
}

/// [`pixels_per_triangle`] for an orthographic view `view_height` world units tall: the
/// sphere's disc keeps its size at every depth.
#[must_use]
pub fn pixels_per_triangle_orthographic(
    radius: f32,
    view_height: f32,
    (width, height): (u32, u32),
    triangles: usize,
) -> f32 {
    let viewport = width as f32 * height as f32;
    let r_px = radius / view_height * height as f32;
    let area = (std::f32::consts::PI * r_px * r_px).min(viewport);
    let px = area / (triangles as f32 * 0.5).max(1.0);
    if px.is_finite() { px } else { 0.0 }
}

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
    /// Indices (into [`FramePlan::light_names`]) of the lights that reach the object.
    pub lights: Vec<usize>,
    /// Index into [`FramePlan::light_sets`].
    pub light_set: usize,
    /// Whether its back faces are skipped.
    pub cull_backfaces: bool,
    /// Why they are or are not.
    pub cull_reason: &'static str,
}

/// What one frame will draw, and how.
#[derive(Debug, Clone, Default)]
pub struct FramePlan {
    /// The objects to draw, in scene order.
    pub objects: Vec<PlannedObject>,
    /// Objects outside the view frustum.
    pub culled: Vec<String>,
    /// The names of the scene's lights, in scene order.
    pub light_names: Vec<String>,
    /// One prepared light set per distinct set of kept lights.
    pub light_sets: Vec<LightSet>,
}

/// A sphere in world space.
#[derive(Debug, Clone, Copy)]
struct Sphere {
    center: Vec3,
    radius: f32,
}

/// Whether an object's back faces can be skipped (and why): see [`CullChoice`]. Exact under
/// `auto` because from an eye outside a closed, outward-oriented solid every ray meets a
/// front face before any back face; the near plane must not cut the solid either, so the
/// bounds are grown by the distance from the eye to the near plane's corners.
fn cull_decision(
    choice: CullChoice,
    info: &MeshInfo,
    model: Mat4,
    camera: &Camera,
    aspect: f32,
) -> (bool, &'static str) {
    match choice {
        CullChoice::Always => return (true, "culled: the scene culls every object"),
        CullChoice::Never => return (false, "drawn: the scene draws both sides"),
        CullChoice::Auto => {}
    }
    if !info.closed {
        return (
            false,
            "drawn: the mesh is not a closed, outward-oriented solid",
        );
    }
    let det = glam::Mat3::from_mat4(model).determinant();
    if !(det.is_finite() && det > 0.0) {
        return (false, "drawn: the transform mirrors or flattens the mesh");
    }
    let corners = world_corners(info, model);
    let lo = corners.iter().copied().fold(Vec3::INFINITY, Vec3::min);
    let hi = corners.iter().copied().fold(Vec3::NEG_INFINITY, Vec3::max);
    // How far from the eye the near plane's corners lie: the rays start on that rectangle.
    let near_reach = match camera.projection {
        Projection::Perspective => {
            let tan_half = (camera.fov_y_deg.to_radians() * 0.5).tan();
            camera.near * (1.0 + tan_half * tan_half * (1.0 + aspect * aspect)).sqrt()
        }
        Projection::Orthographic { height } => {
            let half = height * 0.5;
            (camera.near * camera.near + half * half * (1.0 + aspect * aspect)).sqrt()
        }
    };
    let margin = Vec3::splat(near_reach.max(0.0) * 1.001 + 1e-6);
    let (lo, hi) = (lo - margin, hi + margin);
    let inside = camera.eye.cmpge(lo).all() && camera.eye.cmple(hi).all();
    if !(lo.is_finite() && hi.is_finite()) || inside {
        return (
            false,
            "drawn: the eye or the near plane is inside its bounds",
        );
    }
    (true, "culled: a closed solid seen from outside")
}

/// The six frustum planes of an OpenGL view-projection matrix (Gribb & Hartmann), each
/// `(n, d)` with `n.p + d >= 0` inside.
fn frustum_planes(vp: Mat4) -> [Vec4; 6] {
    let r0 = vp.row(0);
    let r1 = vp.row(1);
    let r2 = vp.row(2);
    let r3 = vp.row(3);
    [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 + r2, r3 - r2]
}

fn outside_frustum(planes: &[Vec4; 6], s: Sphere) -> bool {
    planes.iter().any(|p| {
        let n = p.truncate();
        let len = n.length();
        len > 0.0 && n.dot(s.center) + p.w < -s.radius * len
    })
}

/// The angle whose sine is `r / d` (the half-angle a sphere of radius `r` subtends at
/// distance `d`), or `None` when the point is inside the sphere.
fn subtended(r: f32, d: f32) -> Option<f32> {
    (d > r && d > 0.0).then(|| (r / d).clamp(0.0, 1.0).asin())
}

fn angle(a: Vec3, b: Vec3) -> f32 {
    a.cross(b).length().atan2(a.dot(b))
}

/// Where a light sits, for range tests: a point and the radius of the region it spans.
fn light_extent(l: &Light) -> Option<(Vec3, f32)> {
    match l.kind {
        LightKind::Directional { .. } => None,
        LightKind::Point { position } | LightKind::Spot { position, .. } => Some((position, 0.0)),
        LightKind::Tube { start, end, .. } => {
            Some(((start + end) * 0.5, start.distance(end) * 0.5))
        }
        LightKind::Rect {
            corner,
            edge_u,
            edge_v,
            ..
        } => Some((
            corner + (edge_u + edge_v) * 0.5,
            (edge_u + edge_v).length().max((edge_u - edge_v).length()) * 0.5,
        )),
    }
}

/// The corners of the object's bounds in world space: their convex hull holds the object.
fn world_corners(info: &MeshInfo, model: Mat4) -> [Vec3; 8] {
    let (lo, hi) = info.bounds;
    std::array::from_fn(|i| {
        let c = Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        model.transform_point3(c)
    })
}

/// The points whose convex hull holds a light's emitting region (`None`: at infinity).
fn light_points(l: &Light) -> Option<Vec<Vec3>> {
    match l.kind {
        LightKind::Directional { .. } => None,
        LightKind::Point { position } | LightKind::Spot { position, .. } => Some(vec![position]),
        LightKind::Tube { start, end, .. } => Some(vec![start, end]),
        LightKind::Rect {
            corner,
            edge_u,
            edge_v,
            ..
        } => Some(vec![
            corner,
            corner + edge_u,
            corner + edge_v,
            corner + edge_u + edge_v,
        ]),
    }
}

/// Whether every normal in `cone` faces away from the light from every point of the object:
/// `N.L <= 0` for all N with angle(N, axis) <= half and all L = p - x. For one x that holds
/// when angle(axis, p - x) >= 90 deg + half; those directions form a convex cone, and the
/// vectors p - x (p in the light's hull, x in the corners' hull) form a polytope whose
/// vertices are the corner/light-point differences, so checking those vertices is exact.
fn faces_away(light: &Light, corners: &[Vec3; 8], (axis, half): (Vec3, f32)) -> bool {
    // Margin of 1e-3 rad so rounding in the kernels cannot make N.L positive.
    let limit = std::f32::consts::FRAC_PI_2 + half + 1e-3;
    match (light.kind, light_points(light)) {
        (LightKind::Directional { direction }, _) => angle(axis, -direction) >= limit,
        (_, Some(points)) => points.iter().all(|p| {
            corners.iter().all(|x| {
                let v = *p - *x;
                v.length_squared() > 0.0 && angle(axis, v) >= limit
            })
        }),
        (_, None) => false,
    }
}

/// Whether `light` can add anything to an object in `s` (corners `corners`) whose normals
/// lie in `cone`.
fn reaches(light: &Light, s: Sphere, corners: &[Vec3; 8], cone: Option<(Vec3, f32)>) -> bool {
    if !light.enabled
        || light.intensity.max_element() <= 0.0 && light.specular_il().max_element() <= 0.0
    {
        return false;
    }
    if let Some(cone) = cone
        && faces_away(light, corners, cone)
    {
        return false;
    }
    if let LightKind::Spot {
        position,
        direction,
        outer_deg,
        ..
    } = light.kind
    {
        let to_object = s.center - position;
        if let (Some(dir), Some(half)) = (
            direction.try_normalize(),
            subtended(s.radius, to_object.length()),
        ) && let Some(to) = to_object.try_normalize()
            && angle(dir, to) - half > outer_deg.to_radians() + 1e-3
        {
            return false;
        }
    }
    true
}

/// The largest attenuation factor over distances `>= d`, and the relative change of the
/// factor over a step of `e` at `d`.
fn attenuation_at(att: Attenuation, d: f32, e: f32) -> (f32, f32) {
    let [c, l, q] = att.coefficients();
    let f = att.factor(d);
    let denom = c + l * d + q * d * d;
    let slope = if denom > 0.0 {
        (l + 2.0 * q * d) / denom
    } else {
        1.0
    };
    (f, (slope * e).min(1.0))
}

/// How far N.L (and V.R) can vary over one face because the light or the eye is near.
struct Figures {
    flat_error: f32,
    gouraud_error: f32,
}

fn error_figures(
    m: &Material,
    effects: Effects,
    lights: &[&Light],
    info: &MeshInfo,
    s: Sphere,
    eye: Vec3,
    scale: f32,
) -> Figures {
    let e = info.max_edge * scale;
    let spread = info.max_normal_spread;
    let kd = if effects.contains(Effects::DIFFUSE) {
        m.kd.max_element()
    } else {
        0.0
    };
    let ks = if effects.contains(Effects::SPECULAR) {
        m.ks.max_element() * m.fresnel.max_w()
    } else {
        0.0
    };
    let slope_spec = m.shininess.max(1.0).sqrt();
    let d_eye = (eye.distance(s.center) - s.radius).max(0.0);
    let dv = if d_eye > 0.0 {
        e / d_eye
    } else {
        f32::INFINITY
    };
    let mut flat = 0.0f32;
    let mut gouraud = 0.0f32;
    for l in lights {
        let il = l.intensity.max_element().max(l.specular_il().max_element());
        let (dl, (f, da)) = match light_extent(l) {
            None => (0.0, (1.0, 0.0)),
            Some((p, extent)) => {
                let d = (p.distance(s.center) - s.radius - extent).max(0.0);
                let dl = if d > 0.0 {
                    (e + extent) / d
                } else {
                    f32::INFINITY
                };
                let att = if effects.contains(Effects::ATTENUATION) {
                    l.attenuation
                } else {
                    Attenuation::None
                };
                (dl, attenuation_at(att, d, e))
            }
        };
        let i = il * f;
        // Flat: the face's single value against the exact one, first order in the variation
        // of N.L (light direction), V.R (light and eye) and f(d) across a face.
        flat += i * (kd * (dl + da) + ks * (slope_spec * (dl + dv) + da));
        // Gouraud (diffuse only): linear interpolation of a cosine over an angle theta is off
        // by about theta^2 / 8; the attenuation's curvature likewise.
        let theta = spread + dl;
        gouraud += i * kd * (theta * theta / 8.0 + da * da / 8.0);
    }
    Figures {
        flat_error: if flat.is_finite() {
            flat
        } else {
            f32::INFINITY
        },
        gouraud_error: if gouraud.is_finite() {
            gouraud
        } else {
            f32::INFINITY
        },
    }
}

/// What `auto` looks at for one object.
#[derive(Debug, Clone, Copy)]
pub struct AutoInput<'a> {
    /// The material.
    pub material: &'a Material,
    /// The planned effects.
    pub effects: Effects,
    /// The lights that reach the object.
    pub lights: &'a [&'a Light],
    /// The mesh figures.
    pub info: &'a MeshInfo,
    /// World bounding-sphere centre.
    pub center: Vec3,
    /// World bounding-sphere radius.
    pub radius: f32,
    /// Largest scale factor of the object's transform.
    pub scale: f32,
    /// The viewer.
    pub eye: Vec3,
    /// Whether a bump map applies.
    pub bumped: bool,
    /// Estimated screen pixels per front-facing triangle ([`pixels_per_triangle`]).
    pub pixels_per_triangle: f32,
}

/// `auto`: the cheapest mode that is good enough, with the reason.
///
/// - `flat` where the object is a polyhedron (the lecture notes' condition c) and lights and viewer
///   are far enough that N.L and V.R barely vary over a face (conditions a and b): estimated
///   error at most [`AUTO_TOLERANCE`].
/// - `gouraud` where there is no specular term and the mesh is fine relative to the light's
///   variation (estimated interpolation error at most the tolerance).
/// - `phong` where highlights are smaller than the triangles (the highlight's half-width in
///   normal angle is less than the normals' spread within a typical triangle, the 90th
///   percentile), and for bump maps.
/// - `fast-phong` otherwise: the highlights span several triangles, where a quadratic
///   fit holds (and its per-triangle fallback guards the rest), provided the triangles
///   are large enough on screen for its fit to pay ([`FAST_PHONG_MIN_PIXELS`]); `phong`
///   where they are not.
#[must_use]
pub fn choose_mode(o: &AutoInput<'_>) -> (ShadingMode, String) {
    let AutoInput {
        material,
        effects,
        lights,
        info,
        ..
    } = *o;
    if o.bumped {
        return (
            ShadingMode::Phong,
            "bump-mapped: normals vary per pixel".to_owned(),
        );
    }
    let s = Sphere {
        center: o.center,
        radius: o.radius,
    };
    let fig = error_figures(material, effects, lights, info, s, o.eye, o.scale);
    let lit = !effects
        .intersection(Effects::DIFFUSE | Effects::SPECULAR)
        .is_empty()
        && !lights.is_empty();
    if !lit {
        return (
            ShadingMode::Flat,
            "unlit: ambient and emission are constant".to_owned(),
        );
    }
    if info.polyhedron && fig.flat_error <= AUTO_TOLERANCE {
        return (
            ShadingMode::Flat,
            format!(
                "polyhedron, lights and viewer far (est. error {:.4} <= 1/255)",
                fig.flat_error
            ),
        );
    }
    if !effects.contains(Effects::SPECULAR) && fig.gouraud_error <= AUTO_TOLERANCE {
        return (
            ShadingMode::Gouraud,
            format!(
                "no specular term, normals within {:.1} deg per triangle (est. error {:.4} <= 1/255)",
                info.max_normal_spread.to_degrees(),
                fig.gouraud_error
            ),
        );
    }
    // Fast Phong only pays on triangles large on screen; elsewhere Phong is both exact and
    // faster.
    let px = o.pixels_per_triangle;
    let per_pixel = |why: String| {
        if px >= FAST_PHONG_MIN_PIXELS {
            (
                ShadingMode::FastPhong,
                format!("{why}; triangles large on screen (est. {px:.0} px each)"),
            )
        } else {
            (
                ShadingMode::Phong,
                format!(
                    "{why}; triangles too small on screen for fast Phong to pay (est. {px:.0} < {FAST_PHONG_MIN_PIXELS:.0} px each)"
                ),
            )
        }
    };
    if !effects.contains(Effects::SPECULAR) {
        return per_pixel(format!(
            "no specular term but coarse for its lights (est. gouraud error {:.4} > 1/255)",
            fig.gouraud_error
        ));
    }
    // Half-width of the highlight at half intensity, in the angle of the normal: (R.V)^n
    // turns twice as fast as N; (N.H)^n as fast as N.
    let lobe = 0.5f32.powf(1.0 / material.shininess.max(1e-3)).acos();
    let half_width = match material.specular {
        SpecularModel::Phong => lobe * 0.5,
        SpecularModel::Blinn => lobe,
    };
    if half_width < info.typical_normal_spread {
        (
            ShadingMode::Phong,
            format!(
                "highlight (half-width {:.1} deg) smaller than triangles (normal spread {:.1} deg)",
                half_width.to_degrees(),
                info.typical_normal_spread.to_degrees()
            ),
        )
    } else {
        per_pixel(format!(
            "highlight (half-width {:.1} deg) spans triangles (normal spread {:.1} deg)",
            half_width.to_degrees(),
            info.typical_normal_spread.to_degrees()
        ))
    }
}

/// Builds the plan of one frame seen by `camera` in a `viewport` of width x height pixels.
#[must_use]
pub fn plan_frame(
    scene: &Scene,
    camera: &Camera,
    viewport: (u32, u32),
    opts: &FrameOptions,
) -> FramePlan {
    let aspect = viewport.0.max(1) as f32 / viewport.1.max(1) as f32;
    let lights = scene.lights();
    let planes = frustum_planes(camera.view_proj(aspect));
    let mut plan = FramePlan {
        light_names: lights.iter().map(|(n, _)| n.clone()).collect(),
        ..FramePlan::default()
    };
    let mut sets: HashMap<Vec<usize>, usize> = HashMap::new();
    let mut objects: Vec<_> = scene
        .world
        .query::<(
            Entity,
            &Name,
            &Transform,
            &MeshRef,
            &Material,
            Option<&Bump>,
            Option<&Shading>,
            Option<&ColorMap>,
        )>()
        .iter()
        .map(|(e, n, t, m, mat, b, s, c)| {
            (
                e,
                n.0.clone(),
                *t,
                m.0.clone(),
                *mat,
                b.map(|b| b.0.clone()),
                s.map(|s| s.0),
                c.map(|c| c.0.clone()),
            )
        })
        .collect();
    objects.sort_by_key(|o| o.0.id());
    for (entity, name, tr, mesh, material, bump, shading, texture) in objects {
        // Sampling is compiled into the draw only where a map is drawn.
        let texture = texture.filter(|_| opts.textures && mesh.mesh.uvs.is_some());
        let model = tr.matrix();
        let scale = tr.max_scale();
        let sphere = Sphere {
            center: model.transform_point3(mesh.info.center),
            radius: mesh.info.radius * scale,
        };
        if !sphere.center.is_finite()
            || !sphere.radius.is_finite()
            || outside_frustum(&planes, sphere)
        {
            plan.culled.push(name);
            continue;
        }
        let bumped = opts.bump && bump.is_some() && mesh.mesh.uvs.is_some();
        // World-space normal cone (rotation only keeps it; non-uniform scale may widen it: then
        // the cone is not used).
        let uniform = (tr.scale.abs() - Vec3::splat(scale)).abs().max_element() <= 1e-6 * scale;
        let cone = if bumped || !uniform || tr.scale.min_element() < 0.0 {
            None
        } else {
            mesh.info
                .normal_cone
                .map(|(axis, half)| (model.transform_vector3(axis).normalize_or_zero(), half))
        };
        let corners = world_corners(&mesh.info, model);
        let kept: Vec<usize> = lights
            .iter()
            .enumerate()
            .filter(|(_, (_, l))| reaches(l, sphere, &corners, cone))
            .map(|(i, _)| i)
            .collect();
        let set_index = match sets.get(&kept) {
            Some(&i) => i,
            None => {
                let chosen: Vec<Light> = kept.iter().map(|&i| lights[i].1).collect();
                plan.light_sets.push(LightSet::new(scene.ambient, &chosen));
                sets.insert(kept.clone(), plan.light_sets.len() - 1);
                plan.light_sets.len() - 1
            }
        };
        let set = &plan.light_sets[set_index];
        let mut effects = phosphor_lighting::effects_for(set, &material);
        let kept_lights: Vec<&Light> = kept.iter().map(|&i| &lights[i].1).collect();
        let choice = opts.shading.or(shading).unwrap_or(scene.settings.shading);
        let (mode, reason) = match (choice, opts.shading.is_some(), shading.is_some()) {
            (ShadingChoice::Mode(m), true, _) => (m, "forced for every object".to_owned()),
            (ShadingChoice::Mode(m), false, true) => (m, "the object's shading".to_owned()),
            (ShadingChoice::Mode(m), false, false) => (m, "the scene's shading".to_owned()),
            (ShadingChoice::Auto, _, _) => choose_mode(&AutoInput {
                material: &material,
                effects,
                lights: &kept_lights,
                info: &mesh.info,
                center: sphere.center,
                radius: sphere.radius,
                scale,
                eye: camera.eye,
                bumped,
                pixels_per_triangle: match camera.projection {
                    Projection::Perspective => pixels_per_triangle(
                        (sphere.center, sphere.radius),
                        camera.eye,
                        camera.fov_y_deg,
                        viewport,
                        mesh.mesh.indices.len(),
                    ),
                    Projection::Orthographic { height } => pixels_per_triangle_orthographic(
                        sphere.radius,
                        height,
                        viewport,
                        mesh.mesh.indices.len(),
                    ),
                },
            }),
        };
        let per_pixel = matches!(
            mode,
            ShadingMode::Phong | ShadingMode::FastPhong | ShadingMode::Reference
        );
        let bump = if bumped && per_pixel { bump } else { None };
        effects = effects.with(Effects::BUMP, bump.is_some());
        let (cull_backfaces, cull_reason) = cull_decision(
            scene.settings.cull_backfaces,
            &mesh.info,
            model,
            camera,
            aspect,
        );
        plan.objects.push(PlannedObject {
            entity,
            name,
            model,
            mesh,
            material,
            bump,
            texture,
            mode,
            reason,
            effects,
            lights: kept,
            light_set: set_index,
            cull_backfaces,
            cull_reason,
        });
    }
    plan
}

impl fmt::Display for FramePlan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "frame plan: {} objects drawn, {} culled, {} lights, {} light sets",
            self.objects.len(),
            self.culled.len(),
            self.light_names.len(),
            self.light_sets.len()
        )?;
        for o in &self.objects {
            let effects: Vec<&str> = Effects::NAMED
                .iter()
                .filter(|(e, _)| o.effects.contains(*e))
                .map(|(_, n)| *n)
                .collect();
            let lights: Vec<&str> = o
                .lights
                .iter()
                .map(|&i| self.light_names[i].as_str())
                .collect();
            writeln!(f, "  {}: {} ({})", o.name, o.mode, o.reason)?;
            writeln!(
                f,
                "    effects: {}",
                if effects.is_empty() {
                    "none".to_owned()
                } else {
                    effects.join(", ")
                }
            )?;
            writeln!(f, "    back faces: {}", o.cull_reason)?;
            writeln!(
                f,
                "    lights: {} of {}{}",
                lights.len(),
                self.light_names.len(),
                if lights.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", lights.join(", "))
                }
            )?;
        }
        for c in &self.culled {
            writeln!(f, "  {c}: culled (outside the view frustum)")?;
        }
        Ok(())
    }
}
