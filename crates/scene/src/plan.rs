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
//! Shading `auto` takes `flat` or `gouraud` only where a proven bound of their error against
//! `reference` is within one displayed 8-bit code ([`AUTO_TOLERANCE`]) on every triangle, and
//! `phong` elsewhere: see [`choose_mode`].

use std::collections::HashMap;
use std::fmt;

use glam::{Mat4, Vec3, Vec4};
use hecs::Entity;
use phosphor_lighting::{Effects, Light, LightKind, LightSet, Material};
use phosphor_raster::encode::srgb_encode;
use phosphor_raster::{Camera, Encoding, Projection, ShadingMode};

use crate::components::{Bump, MeshInfo, MeshRef, Name, Shading, ShadingChoice, Transform};
use crate::error_bound::{ErrorBounds, shading_error_bounds};
use crate::textures::ColorMap;
use crate::{CullChoice, Scene};

/// `auto` accepts a cheaper mode when its estimated error is at most this (one 8-bit code).
pub const AUTO_TOLERANCE: f32 = 1.0 / 255.0;

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

pub use crate::planned::{FrameOptions, PlannedObject};

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
    /// Every object that casts shadows, visible or not (filled only when a light has shadows
    /// on).
    pub casters: Vec<crate::shadows::ShadowCaster>,
    /// The shadow maps this frame makes, and why the other shadowing lights get none.
    pub shadows: crate::shadows::ShadowPlan,
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

/// The largest linear error whose displayed error is at most one code for every true value
/// of at least `lowest`: linear encoding 1/255; sRGB, being concave, shows a linear error
/// largest at the lowest value, so the step from `lowest` to the value one code above it.
#[must_use]
pub fn linear_tolerance(lowest: f32, encoding: Encoding) -> f32 {
    match encoding {
        Encoding::Linear => AUTO_TOLERANCE,
        Encoding::Srgb => {
            let lo = if lowest.is_finite() {
                lowest.clamp(0.0, 1.0)
            } else {
                0.0
            };
            let up = srgb_encode(lo) + AUTO_TOLERANCE;
            if up >= 1.0 {
                return 1.0 - lo;
            }
            // Inverse sRGB, rounded down a little so the round trip stays under one code.
            let lin = if up <= 0.040_45 {
                up / 12.92
            } else {
                ((up + 0.055) / 1.055).powf(2.4)
            };
            ((lin - lo) * 0.999).max(0.0)
        }
    }
}

/// A linear error as displayed codes above `lowest` (for the plan's reasons; finite).
fn codes(err: f32, lowest: f32, encoding: Encoding) -> f32 {
    let lo = if lowest.is_finite() {
        lowest.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let err = if err.is_finite() { err.min(1.0) } else { 1.0 };
    match encoding {
        Encoding::Linear => err * 255.0,
        Encoding::Srgb => (srgb_encode(lo + err) - srgb_encode(lo)) * 255.0,
    }
}

/// The largest flat and gouraud error bounds ([`shading_error_bounds`]) over the triangles of
/// `mesh` drawn with `model`, stopping early once every mode still asked about (`flat` only
/// when `want_flat`) is over `tolerance`: the triangles are visited in strides across the
/// whole mesh so that a failing region is met early. Returns the bounds and whether the scan
/// stopped early (then they are lower bounds of the object's bounds, still over `tolerance`).
/// With `skip_back_faces` (back faces culled, perspective view: a face is back-facing on
/// screen exactly when the eye lies behind its plane) faces the eye sees from behind are
/// left out.
fn object_error_bounds(
    set: &LightSet,
    material: &Material,
    mesh: &phosphor_mesh::Mesh,
    model: Mat4,
    eye: Vec3,
    (vertex_clamp, want_flat, tolerance): (bool, bool, f32),
    skip_back_faces: bool,
) -> (ErrorBounds, bool) {
    let m3 = glam::Mat3::from_mat4(model);
    let normal_matrix = {
        let nm = m3.inverse().transpose();
        if nm.is_finite() { nm } else { m3 }
    };
    let corner = |i: u32| {
        let i = i as usize;
        let p = mesh
            .positions
            .get(i)
            .map_or(Vec3::NAN, |p| model.transform_point3(*p));
        let n = mesh
            .normals
            .get(i)
            .map_or(Vec3::ZERO, |n| (normal_matrix * *n).normalize_or_zero());
        (p, n)
    };
    let count = mesh.indices.len();
    const STRIDE: usize = 97;
    let mut worst = ErrorBounds::ZERO;
    for start in 0..STRIDE.min(count) {
        for t in (start..count).step_by(STRIDE) {
            let [a, b, c] = mesh.indices[t].map(corner);
            // A face the eye sees from behind is culled: none of its pixels are drawn. The
            // margin (the view ray at least 0.6 degrees behind the plane) keeps faces seen
            // edge-on, which snapping to 1/256 pixel may turn front-facing, in the bound.
            let normal = (b.0 - a.0).cross(c.0 - a.0);
            let to_eye = eye - a.0;
            let facing = normal.dot(to_eye);
            if skip_back_faces && facing < -0.01 * normal.length() * to_eye.length() {
                continue;
            }
            let bound = shading_error_bounds(
                set,
                material,
                [a.0, b.0, c.0],
                [a.1, b.1, c.1],
                eye,
                vertex_clamp,
            );
            worst.flat = worst.flat.max(bound.flat);
            worst.gouraud = worst.gouraud.max(bound.gouraud);
            if (!want_flat || worst.flat > tolerance) && worst.gouraud > tolerance {
                return (worst, true);
            }
        }
    }
    (worst, false)
}

/// What `auto` looks at for one object.
#[derive(Debug, Clone, Copy)]
pub struct AutoInput<'a> {
    /// The material.
    pub material: &'a Material,
    /// The planned effects.
    pub effects: Effects,
    /// The lights that reach the object, prepared.
    pub set: &'a LightSet,
    /// The mesh.
    pub mesh: &'a phosphor_mesh::Mesh,
    /// The mesh figures.
    pub info: &'a MeshInfo,
    /// Object to world.
    pub model: Mat4,
    /// The viewer.
    pub eye: Vec3,
    /// Whether a bump map applies.
    pub bumped: bool,
    /// Whether a texture or vertex colours tint the shading.
    pub tinted: bool,
    /// `gouraud` clamps each vertex to 1 ([`FrameOptions::gouraud_vertex_clamp`]).
    pub vertex_clamp: bool,
    /// How the picture is displayed: one code is measured in this encoding.
    pub encoding: Encoding,
    /// Back faces are culled and the view is a perspective one from `eye`: faces seen from
    /// behind draw no pixel and need no bound.
    pub skip_back_faces: bool,
}

/// `auto`: the cheapest mode whose error against `reference` is proven at most one displayed
/// code on every pixel, with the reason.
///
/// - `flat` where nothing lit varies (no light reaches a diffuse or specular term), or where
///   the object is a polyhedron (the lecture notes' condition c) and the bound of
///   [`shading_error_bounds`] over every triangle is within one code (conditions a and b, lights
///   and viewer far enough, made exact);
/// - `gouraud` where that bound for `gouraud` is within one code on every triangle (terminators,
///   spot-cone edges, attenuation, highlights between vertices and the vertex clamp are all
///   inside the bound);
/// - `phong` otherwise (the model per pixel in f32: within 1e-5 of `reference` untextured),
///   and for bump maps, textures and vertex colours, which the bounds do not cover.
///   `fast-phong` is never chosen: its fit is checked at ten points, not bounded between them.
///
/// One code is [`AUTO_TOLERANCE`] in the scene's encoding: for sRGB, the linear step
/// ([`linear_tolerance`]) above the object's lowest intensity, its ambient and emission term.
#[must_use]
pub fn choose_mode(o: &AutoInput<'_>) -> (ShadingMode, String) {
    let AutoInput {
        material,
        effects,
        set,
        info,
        ..
    } = *o;
    if o.bumped {
        return (
            ShadingMode::Phong,
            "bump-mapped: normals vary per pixel".to_owned(),
        );
    }
    if o.tinted {
        return (
            ShadingMode::Phong,
            "textured or vertex-coloured: the error bounds cover untinted shading".to_owned(),
        );
    }
    let lit = !effects
        .intersection(Effects::DIFFUSE | Effects::SPECULAR)
        .is_empty()
        && !set.is_empty();
    if !lit {
        return (
            ShadingMode::Flat,
            "unlit: ambient and emission are constant".to_owned(),
        );
    }
    let ambient = material.emission + material.ka * set.ambient();
    let lowest = ambient.min_element();
    let tolerance = linear_tolerance(lowest, o.encoding);
    let (bounds, partial) = object_error_bounds(
        set,
        material,
        o.mesh,
        o.model,
        o.eye,
        (o.vertex_clamp, info.polyhedron, tolerance),
        o.skip_back_faces,
    );
    let show = |err: f32| {
        let c = codes(err, lowest, o.encoding);
        if partial && err > tolerance {
            format!("over one code ({c:.1} on a triangle)")
        } else {
            format!("{c:.2} codes")
        }
    };
    if info.polyhedron && bounds.flat <= tolerance {
        return (
            ShadingMode::Flat,
            format!(
                "polyhedron; flat proven within {} of reference",
                show(bounds.flat)
            ),
        );
    }
    if bounds.gouraud <= tolerance {
        return (
            ShadingMode::Gouraud,
            format!(
                "gouraud proven within {} of reference",
                show(bounds.gouraud)
            ),
        );
    }
    (
        ShadingMode::Phong,
        format!(
            "gouraud bound {}: phong, the model per pixel",
            show(bounds.gouraud)
        ),
    )
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
            Option<&crate::components::ShadowRole>,
        )>()
        .iter()
        .map(|(e, n, t, m, mat, b, s, c, role)| {
            (
                e,
                n.0.clone(),
                *t,
                m.0.clone(),
                *mat,
                b.map(|b| b.0.clone()),
                s.map(|s| s.0),
                (c.map(|c| c.0.clone()), role.is_none_or(|r| r.receive)),
            )
        })
        .collect();
    objects.sort_by_key(|o| o.0.id());
    for (entity, name, tr, mesh, material, bump, shading, (texture, receives_shadows)) in objects {
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
        let (cull_backfaces, cull_reason) = cull_decision(
            scene.settings.cull_backfaces,
            &mesh.info,
            model,
            camera,
            aspect,
        );
        let choice = opts.shading.or(shading).unwrap_or(scene.settings.shading);
        let (mode, reason) = match (choice, opts.shading.is_some(), shading.is_some()) {
            (ShadingChoice::Mode(m), true, _) => (m, "forced for every object".to_owned()),
            (ShadingChoice::Mode(m), false, true) => (m, "the object's shading".to_owned()),
            (ShadingChoice::Mode(m), false, false) => (m, "the scene's shading".to_owned()),
            (ShadingChoice::Auto, _, _) => choose_mode(&AutoInput {
                material: &material,
                effects,
                set,
                mesh: &mesh.mesh,
                info: &mesh.info,
                model,
                eye: camera.eye,
                bumped,
                tinted: texture.is_some() || mesh.mesh.colors.is_some(),
                vertex_clamp: opts
                    .gouraud_vertex_clamp
                    .unwrap_or(scene.settings.gouraud_vertex_clamp),
                encoding: scene.settings.encoding,
                skip_back_faces: cull_backfaces
                    && matches!(camera.projection, Projection::Perspective),
            }),
        };
        let per_pixel = matches!(
            mode,
            ShadingMode::Phong | ShadingMode::FastPhong | ShadingMode::Reference
        );
        let bump = if bumped && per_pixel { bump } else { None };
        effects = effects.with(Effects::BUMP, bump.is_some());
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
            receives_shadows,
        });
    }
    let shadowing = opts.shadows == Some(true)
        || (opts.shadows.is_none()
            && scene
                .world
                .query::<&crate::components::CastsShadows>()
                .iter()
                .next()
                .is_some());
    if shadowing {
        plan.casters = crate::shadows::casters(scene);
        plan.shadows = crate::shadows::plan_shadows(
            scene,
            &plan.objects,
            &plan.casters,
            (camera, viewport),
            opts,
        );
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
        for m in &self.shadows.maps {
            let names = |list: &[String]| list.join(", ");
            let casters: Vec<String> = m
                .casters
                .iter()
                .map(|&c| self.casters[c].name.clone())
                .collect();
            let receivers: Vec<String> = m
                .receivers
                .iter()
                .map(|&r| self.objects[r].name.clone())
                .collect();
            writeln!(
                f,
                "  shadow map of {}: {}x{} ({}), {} view; casters: {}; receivers: {}",
                self.light_names[m.light],
                m.size,
                m.size,
                m.size_reason,
                match (m.face, m.view.projection) {
                    (Some(face), _) => format!("cube face {face}"),
                    (None, phosphor_raster::shadow::Projection::Orthographic { .. }) => {
                        "orthographic".to_owned()
                    }
                    (None, phosphor_raster::shadow::Projection::Perspective { .. }) => {
                        "perspective".to_owned()
                    }
                },
                names(&casters),
                names(&receivers)
            )?;
        }
        for (light, why) in &self.shadows.skipped {
            writeln!(f, "  no shadow map for {}: {why}", self.light_names[*light])?;
        }
        for (light, faces) in &self.shadows.faces_skipped {
            let faces: Vec<String> = faces.iter().map(ToString::to_string).collect();
            writeln!(
                f,
                "  cube faces of {} not made ({}): no caster can shadow a visible receiver through them",
                self.light_names[*light],
                faces.join(", ")
            )?;
        }
        Ok(())
    }
}
