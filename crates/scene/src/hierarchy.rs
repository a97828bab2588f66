//! Parents and children: an entity placed relative to another, and the system that gives every
//! entity of a hierarchy its world transform.
//!
//! The renderer reads world-space components: an object's [`Transform`], a light's
//! [`Light`], the [`Camera`]. A root that never moves needs nothing more (its `Transform` is
//! its place in the world). An entity with a [`Parent`], or one that moves on the clock
//! ([`crate::animation`]), also carries what was authored relative to its parent:
//! - [`LocalTransform`], its rest transform in the parent's space (what a scene file's
//!   `transform` says, and what is saved);
//! - [`Pose`], that transform this frame, once the animation systems have moved it;
//! - for a light, [`LocalLight`] (its position and direction in the parent's space); for the
//!   camera, [`LocalCamera`].
//!
//! [`propagate_transforms`] composes each entity's pose with its ancestors' into a
//! [`GlobalTransform`] and writes the world-space `Transform`; [`place_lights`] and
//! [`place_cameras`] move lights and cameras with theirs. Each is a free function over the
//! world, run once per frame in that order ([`crate::animation::update`]).
//!
//! ```
//! use glam::{Mat4, Vec3};
//! use phosphor_scene::hierarchy::{GlobalTransform, LocalTransform, Parent, Pose, propagate_transforms};
//! use phosphor_scene::Transform;
//!
//! let mut world = hecs::World::new();
//! let arm = Transform { translate: Vec3::X, ..Transform::default() };
//! let root = world.spawn((arm, LocalTransform(arm), Pose::from(arm)));
//! let hand = world.spawn((Parent(root), arm, LocalTransform(arm), Pose::from(arm)));
//! assert!(propagate_transforms(&mut world).is_empty());
//! let at = world.get::<&GlobalTransform>(hand).unwrap().0.transform_point3(Vec3::ZERO);
//! assert!((at - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-6);
//! ```

use std::collections::HashMap;

use glam::{EulerRot, Mat4, Quat, Vec3};
use hecs::{Entity, World};
use phosphor_lighting::{Light, LightKind};
use phosphor_raster::Camera;

use crate::components::Transform;

/// The entity this one is placed relative to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Parent(pub Entity);

/// The rest transform relative to the parent (to the world for a root that moves): what was
/// authored, never changed by the systems.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalTransform(pub Transform);

/// This frame's transform relative to the parent: [`LocalTransform`] as the animation systems
/// left it (scale, then rotation, then translation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Translation.
    pub translation: Vec3,
    /// Rotation.
    pub rotation: Quat,
    /// Scale per axis.
    pub scale: Vec3,
}

impl From<Transform> for Pose {
    fn from(t: Transform) -> Pose {
        let r = t.rotate_deg * (std::f32::consts::PI / 180.0);
        Pose {
            translation: t.translate,
            rotation: Quat::from_euler(EulerRot::ZYX, r.z, r.y, r.x),
            scale: t.scale,
        }
    }
}

impl Pose {
    /// The matrix `T * R * S`.
    #[must_use]
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// The rest pose relative to the parent, given as a [`Pose`] (its rotation a quaternion)
/// rather than a [`LocalTransform`]: a glTF node's, whose rotation would lose precision
/// through Euler angles. Never changed by the systems; an entity has this or a
/// `LocalTransform`, not both.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestPose(pub Pose);

/// Object to world this frame, as [`propagate_transforms`] composed it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlobalTransform(pub Mat4);

/// A light's geometry in its parent's space: the [`Light`]'s kind is this, carried into the
/// world by [`place_lights`]. Only the position and direction move; intensity and the on/off
/// switch stay the `Light`'s own (the viewer toggles them there).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalLight(pub LightKind);

/// A camera in its parent's space (eye, target and up), carried into the world by
/// [`place_cameras`]: a camera on a rig.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalCamera(pub Camera);

/// Copies every [`LocalTransform`] (or [`RestPose`]) into its [`Pose`]: the start of a
/// frame, before the animation systems move the poses.
pub fn reset_poses(world: &mut World) {
    for (local, pose) in world.query_mut::<(&LocalTransform, &mut Pose)>() {
        *pose = Pose::from(local.0);
    }
    for (rest, pose) in world
        .query_mut::<(&RestPose, &mut Pose)>()
        .without::<&LocalTransform>()
    {
        *pose = rest.0;
    }
}

/// The world matrix of every entity that has a [`Pose`] or a [`Parent`]: its parent's world
/// matrix (identity without one) times its pose (identity without one). A parent that has
/// neither is a root placed by its [`Transform`] (identity without one).
///
/// Writes [`GlobalTransform`] on those entities (adding it where missing) and, on the ones
/// with a `Transform`, that matrix as a `Transform` (what the frame plan reads). Returns one
/// `warning: ...` line per entity whose world matrix is not a scale, rotation and translation
/// (a non-uniform scale above a rotated child shears it; the `Transform` then holds the
/// nearest one and the object is drawn with it), and per parent chain that loops (its
/// members are placed as roots).
pub fn propagate_transforms(world: &mut World) -> Vec<String> {
    let nodes: Vec<(Entity, Option<Entity>, Option<Mat4>)> = world
        .query::<(Entity, Option<&Parent>, Option<&Pose>)>()
        .iter()
        .filter(|(_, parent, pose)| parent.is_some() || pose.is_some())
        .map(|(e, parent, pose)| (e, parent.map(|p| p.0), pose.map(Pose::matrix)))
        .collect();
    let local: HashMap<Entity, (Option<Entity>, Option<Mat4>)> =
        nodes.iter().map(|&(e, p, m)| (e, (p, m))).collect();
    let mut done: HashMap<Entity, Mat4> = HashMap::new();
    let mut warnings = Vec::new();
    for &(start, _, _) in &nodes {
        // Walk up to the first ancestor already placed (or a root), then back down.
        let mut chain = vec![start];
        let mut looped = false;
        let mut base = Mat4::IDENTITY;
        while let Some(&e) = chain.last() {
            if let Some(m) = done.get(&e) {
                base = *m;
                chain.pop();
                break;
            }
            let parent = local.get(&e).and_then(|(p, _)| *p);
            match parent {
                Some(p) if chain.contains(&p) => {
                    looped = true;
                    break;
                }
                Some(p) if local.contains_key(&p) => chain.push(p),
                Some(p) => {
                    base = world
                        .get::<&Transform>(p)
                        .map_or(Mat4::IDENTITY, |t| t.matrix());
                    break;
                }
                None => break,
            }
        }
        let own = |e: &Entity| local.get(e).and_then(|(_, m)| *m).unwrap_or(Mat4::IDENTITY);
        if looped {
            warnings.push(format!(
                "warning: entity {}: its parents form a loop; it and its ancestors are placed as roots",
                start.id()
            ));
            for e in &chain {
                done.insert(*e, own(e));
            }
            continue;
        }
        for e in chain.iter().rev() {
            base *= own(e);
            done.insert(*e, base);
        }
    }
    let mut placed: Vec<(Entity, Mat4)> = done.into_iter().collect();
    placed.sort_by_key(|(e, _)| e.id());
    for (e, m) in placed {
        if let Ok(mut t) = world.get::<&mut Transform>(e) {
            let (nearest, sheared) = transform_of(m);
            *t = nearest;
            if sheared {
                warnings.push(format!(
                    "warning: entity {}: its world transform is sheared (a non-uniform scale above a rotated child); drawn with the nearest scale and rotation",
                    e.id()
                ));
            }
        }
        if world.insert_one(e, GlobalTransform(m)).is_err() {
            // Despawned between the query and here: nothing to place.
        }
    }
    warnings
}

/// The [`Transform`] of a world matrix, and whether it is sheared (the transform then is
/// the nearest one: the scale and rotation glam's decomposition finds).
#[must_use]
pub fn transform_of(m: Mat4) -> (Transform, bool) {
    let (scale, rotation, translate) = m.to_scale_rotation_translation();
    let (z, y, x) = rotation.to_euler(EulerRot::ZYX);
    let t = Transform {
        translate,
        rotate_deg: Vec3::new(x, y, z) * (180.0 / std::f32::consts::PI),
        scale,
    };
    let back = Mat4::from_scale_rotation_translation(scale, rotation, translate);
    let size = m
        .x_axis
        .length()
        .max(m.y_axis.length())
        .max(m.z_axis.length());
    let sheared = !m.abs_diff_eq(back, 1e-4 * size.max(1.0));
    (t, sheared)
}

/// A light kind carried by the matrix `m`: positions and corners as points, directions and
/// edges as vectors (directions keep their length's meaning: only their way matters).
#[must_use]
pub fn carry_light(kind: LightKind, m: Mat4) -> LightKind {
    let point = |p: Vec3| m.transform_point3(p);
    let vector = |v: Vec3| m.transform_vector3(v);
    match kind {
        LightKind::Directional { direction } => LightKind::Directional {
            direction: vector(direction),
        },
        LightKind::Point { position } => LightKind::Point {
            position: point(position),
        },
        LightKind::Spot {
            position,
            direction,
            inner_deg,
            outer_deg,
        } => LightKind::Spot {
            position: point(position),
            direction: vector(direction),
            inner_deg,
            outer_deg,
        },
        LightKind::Tube {
            start,
            end,
            samples,
        } => LightKind::Tube {
            start: point(start),
            end: point(end),
            samples,
        },
        LightKind::Rect {
            corner,
            edge_u,
            edge_v,
            samples,
        } => LightKind::Rect {
            corner: point(corner),
            edge_u: vector(edge_u),
            edge_v: vector(edge_v),
            samples,
        },
    }
}

/// Moves each light that has a [`LocalLight`] and a [`GlobalTransform`] to its place in the
/// world. A carried direction that a zero scale collapsed is left as it was (a light needs a
/// direction), as is any non-finite result.
pub fn place_lights(world: &mut World) {
    for (local, global, light) in world.query_mut::<(&LocalLight, &GlobalTransform, &mut Light)>() {
        let kind = carry_light(local.0, global.0);
        let candidate = Light { kind, ..*light };
        if candidate.validate().is_ok() {
            light.kind = kind;
        }
    }
}

/// Moves each camera that has a [`LocalCamera`] and a [`GlobalTransform`] with it: eye and
/// target as points, up as a vector. A result that is not a camera (a zero scale collapsing
/// the eye onto the target) leaves the camera where it was.
pub fn place_cameras(world: &mut World) {
    for (local, global, camera) in
        world.query_mut::<(&LocalCamera, &GlobalTransform, &mut Camera)>()
    {
        let m = global.0;
        let eye = m.transform_point3(local.0.eye);
        let target = m.transform_point3(local.0.target);
        let up = m.transform_vector3(local.0.up).normalize_or_zero();
        let ok = eye.is_finite()
            && target.is_finite()
            && up != Vec3::ZERO
            && (target - eye).length() > 1e-6
            && (target - eye).normalize().cross(up).length() > 1e-6;
        if ok {
            *camera = Camera {
                eye,
                target,
                up,
                ..local.0
            };
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    fn tr(t: [f32; 3], r: [f32; 3], s: [f32; 3]) -> Transform {
        Transform {
            translate: Vec3::from(t),
            rotate_deg: Vec3::from(r),
            scale: Vec3::from(s),
        }
    }

    fn posed(world: &mut World, parent: Option<Entity>, t: Transform) -> Entity {
        let e = world.spawn((t, LocalTransform(t), Pose::from(t)));
        if let Some(p) = parent {
            world.insert_one(e, Parent(p)).unwrap();
        }
        e
    }

    /// `T * Rz * Ry * Rx * S` written out from glam's elementary matrices.
    fn by_hand(t: Transform) -> Mat4 {
        let r = t.rotate_deg * (std::f32::consts::PI / 180.0);
        Mat4::from_translation(t.translate)
            * Mat4::from_rotation_z(r.z)
            * Mat4::from_rotation_y(r.y)
            * Mat4::from_rotation_x(r.x)
            * Mat4::from_scale(t.scale)
    }

    #[test]
    fn a_three_level_chain_composes_like_the_hand_written_matrices() {
        let a = tr([1.0, 2.0, 3.0], [10.0, 20.0, 30.0], [2.0, 2.0, 2.0]);
        let b = tr([0.0, 1.5, -1.0], [0.0, 90.0, 0.0], [0.5, 0.5, 0.5]);
        let c = tr([0.25, 0.0, 0.0], [45.0, 0.0, -15.0], [1.0, 3.0, 1.0]);
        let mut world = World::new();
        // Spawned child first: the order of entities must not matter.
        let gc = world.spawn((c, LocalTransform(c), Pose::from(c)));
        let root = posed(&mut world, None, a);
        let mid = posed(&mut world, Some(root), b);
        world.insert_one(gc, Parent(mid)).unwrap();
        assert!(propagate_transforms(&mut world).is_empty());
        let want = [
            (root, by_hand(a)),
            (mid, by_hand(a) * by_hand(b)),
            (gc, by_hand(a) * by_hand(b) * by_hand(c)),
        ];
        for (e, m) in want {
            let got = world.get::<&GlobalTransform>(e).unwrap().0;
            assert!(got.abs_diff_eq(m, 1e-5), "{got} vs {m}");
            // The Transform the plan reads draws the same matrix.
            let t = *world.get::<&Transform>(e).unwrap();
            assert!(t.matrix().abs_diff_eq(m, 1e-4), "{t:?}");
        }
        // A point on the grandchild lands where the three matrices put it.
        let p = Vec3::new(0.3, -0.2, 0.7);
        let world_p = world
            .get::<&GlobalTransform>(gc)
            .unwrap()
            .0
            .transform_point3(p);
        let manual = by_hand(a)
            .transform_point3(by_hand(b).transform_point3(by_hand(c).transform_point3(p)));
        assert!((world_p - manual).length() < 1e-5);
    }

    #[test]
    fn a_static_root_places_its_children_by_its_transform() {
        let mut world = World::new();
        let root_t = tr([5.0, 0.0, 0.0], [0.0, 0.0, 90.0], [1.0, 1.0, 1.0]);
        let root = world.spawn((root_t,));
        let child = posed(
            &mut world,
            Some(root),
            tr([1.0, 0.0, 0.0], [0.0; 3], [1.0; 3]),
        );
        propagate_transforms(&mut world);
        let at = world.get::<&Transform>(child).unwrap().translate;
        assert!((at - Vec3::new(5.0, 1.0, 0.0)).length() < 1e-5, "{at}");
        assert!(
            world.get::<&GlobalTransform>(root).is_err(),
            "a static root is left alone"
        );
    }

    #[test]
    fn a_light_carried_by_a_moving_parent_follows_it() {
        let mut world = World::new();
        let lamp_post = posed(&mut world, None, tr([0.0; 3], [0.0; 3], [1.0; 3]));
        let local = LightKind::Spot {
            position: Vec3::new(0.0, 2.0, 0.0),
            direction: Vec3::new(1.0, -1.0, 0.0),
            inner_deg: 10.0,
            outer_deg: 20.0,
        };
        let light = Light::new(local, Vec3::ONE).unwrap();
        let lamp = world.spawn((light, LocalLight(local), Parent(lamp_post)));
        for (x, yaw) in [(0.0f32, 0.0f32), (3.0, 90.0), (-2.0, 180.0)] {
            *world.get::<&mut Pose>(lamp_post).unwrap() =
                Pose::from(tr([x, 0.0, 0.0], [0.0, yaw, 0.0], [1.0; 3]));
            assert!(propagate_transforms(&mut world).is_empty());
            place_lights(&mut world);
            let l = *world.get::<&Light>(lamp).unwrap();
            let LightKind::Spot {
                position,
                direction,
                ..
            } = l.kind
            else {
                panic!("still a spot light")
            };
            assert!(
                (position - Vec3::new(x, 2.0, 0.0)).length() < 1e-5,
                "{position}"
            );
            let yawed = Mat4::from_rotation_y(yaw.to_radians())
                .transform_vector3(Vec3::new(1.0, -1.0, 0.0));
            assert!(
                (direction - yawed).length() < 1e-5,
                "{direction} vs {yawed}"
            );
            assert_eq!(l.intensity, Vec3::ONE);
        }
        // The viewer's switch survives the move.
        world.get::<&mut Light>(lamp).unwrap().enabled = false;
        propagate_transforms(&mut world);
        place_lights(&mut world);
        assert!(!world.get::<&Light>(lamp).unwrap().enabled);
    }

    #[test]
    fn a_camera_on_a_rig_keeps_its_view_of_the_rig() {
        let mut world = World::new();
        let rig = posed(&mut world, None, tr([0.0, 0.0, 10.0], [0.0; 3], [1.0; 3]));
        let local = Camera::s1();
        let cam = world.spawn((local, LocalCamera(local), Parent(rig)));
        propagate_transforms(&mut world);
        place_cameras(&mut world);
        let c = *world.get::<&Camera>(cam).unwrap();
        assert!((c.eye - (local.eye + Vec3::new(0.0, 0.0, 10.0))).length() < 1e-5);
        assert!((c.target - (local.target + Vec3::new(0.0, 0.0, 10.0))).length() < 1e-5);
        assert_eq!(c.fov_y_deg, local.fov_y_deg);
    }

    #[test]
    fn sheared_chains_and_loops_are_reported_not_hidden() {
        let mut world = World::new();
        let squashed = posed(&mut world, None, tr([0.0; 3], [0.0; 3], [1.0, 4.0, 1.0]));
        let turned = posed(
            &mut world,
            Some(squashed),
            tr([0.0; 3], [0.0, 0.0, 45.0], [1.0; 3]),
        );
        let w = propagate_transforms(&mut world);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains(&format!("entity {}", turned.id())) && w[0].contains("sheared"),
            "{w:?}"
        );
        let mut world = World::new();
        let a = posed(&mut world, None, Transform::default());
        let b = posed(&mut world, Some(a), Transform::default());
        world.insert_one(a, Parent(b)).unwrap();
        let w = propagate_transforms(&mut world);
        assert!(w.iter().any(|w| w.contains("loop")), "{w:?}");
        assert!(world.get::<&GlobalTransform>(a).unwrap().0.is_finite());
    }
}
