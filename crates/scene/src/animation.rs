//! Animation on a clock: a [`Time`], components that move an entity's [`Pose`] as a function
//! of it ([`Spin`], [`Orbit`], [`Bob`], keyframed [`Tracks`]), and the per-frame systems that
//! apply them.
//!
//! Every pose is a function of the absolute time alone, never of the frames before it: frame
//! `k` of a sequence is the same picture whichever process renders it, and scrubbing
//! backwards is as exact as playing forwards.
//!
//! [`update`] runs the frame's systems in their order:
//! 1. [`reset_poses`]: each pose starts from its [`LocalTransform`];
//! 2. [`apply_tracks`]: keyframed translation, rotation and scale replace the pose's own;
//! 3. [`apply_spin`], [`apply_orbit`], [`apply_bob`]: turn and offset the pose;
//! 4. [`propagate_transforms`]: poses composed down the hierarchy into world transforms;
//! 5. [`place_lights`], [`place_cameras`]: carried lights and cameras follow.
//!
//! The frame plan and the render ([`crate::render_frame`]) then read the world as it stands.
//!
//! ```
//! use glam::Vec3;
//! use phosphor_scene::animation::{Spin, Time, update};
//! use phosphor_scene::hierarchy::{LocalTransform, Pose};
//! use phosphor_scene::{Scene, Transform};
//!
//! let mut scene = Scene::empty();
//! let rest = Transform { translate: Vec3::new(0.0, 0.0, 2.0), ..Transform::default() };
//! let top = scene.world.spawn((
//!     rest,
//!     LocalTransform(rest),
//!     Pose::from(rest),
//!     Spin { axis: Vec3::Y, deg_per_s: 90.0 },
//! ));
//! update(&mut scene, Time::at(1.0));
//! let t = *scene.world.get::<&Transform>(top).unwrap();
//! assert!((t.rotate_deg.y - 90.0).abs() < 1e-3);
//! assert_eq!(t.translate, rest.translate);
//! ```
//!
//! [`LocalTransform`]: crate::hierarchy::LocalTransform
//! [`reset_poses`]: crate::hierarchy::reset_poses
//! [`propagate_transforms`]: crate::hierarchy::propagate_transforms
//! [`place_lights`]: crate::hierarchy::place_lights
//! [`place_cameras`]: crate::hierarchy::place_cameras

use glam::{EulerRot, Quat, Vec3};
use hecs::World;

use crate::Scene;
use crate::hierarchy::{Pose, place_cameras, place_lights, propagate_transforms, reset_poses};

/// The clock of a frame: seconds since the animation's start.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Time {
    /// Seconds (f64: a phase stays exact to microseconds after days of play).
    pub seconds: f64,
}

impl Time {
    /// The instant `seconds`.
    #[must_use]
    pub fn at(seconds: f64) -> Time {
        Time { seconds }
    }

    /// Frame `frame` of a sequence at `fps` frames per second starting at `start`: `start +
    /// frame / fps`, computed from the frame number (never by adding steps, which would drift).
    #[must_use]
    pub fn of_frame(start: f64, frame: u32, fps: f64) -> Time {
        Time::at(start + f64::from(frame) / fps)
    }
}

/// `rate * t` reduced to one turn (`period` units), in f64 before narrowing, so that the
/// phase of a long-running clock keeps its precision.
fn phase(rate: f64, t: f64, period: f64) -> f32 {
    (rate * t).rem_euclid(period) as f32
}

/// Turns the pose about `axis` (through its own origin, in the parent's space) at
/// `deg_per_s`: the rotation at time `t` is `deg_per_s * t` degrees, applied after the
/// pose's own rotation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spin {
    /// The axis (need not be unit; a zero axis does not turn).
    pub axis: Vec3,
    /// Degrees per second (negative turns the other way).
    pub deg_per_s: f32,
}

/// Moves the pose around a circle of `radius` about its rest position, in the plane normal
/// to `axis`, once every `period_s` seconds (counter-clockwise seen from the axis' tip),
/// starting at `phase_deg`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// The circle's normal (a zero axis does not move).
    pub axis: Vec3,
    /// Radius of the circle.
    pub radius: f32,
    /// Seconds per turn (not zero).
    pub period_s: f32,
    /// Where on the circle it is at time 0, degrees.
    pub phase_deg: f32,
}

/// Moves the pose up and down along `axis` by `amplitude * sin(360 * t / period_s +
/// phase_deg)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bob {
    /// The direction of travel (unit length gives `amplitude` in scene units).
    pub axis: Vec3,
    /// The largest offset.
    pub amplitude: f32,
    /// Seconds per cycle (not zero).
    pub period_s: f32,
    /// Where in the cycle it is at time 0, degrees.
    pub phase_deg: f32,
}

/// How a track goes from one key to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interpolation {
    /// Straight between the keys (rotations: the shorter arc between them).
    #[default]
    Linear,
    /// Holds each key's value until the next key's time.
    Step,
}

impl Interpolation {
    /// The name in scene files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Linear => "linear",
            Interpolation::Step => "step",
        }
    }
}

/// Keyframes: times (seconds, increasing) and one value per time. Before the first key the
/// value is the first key's, after the last the last's (glTF's rule), unless the track
/// repeats.
#[derive(Debug, Clone, PartialEq)]
pub struct Track<T> {
    /// Key times, strictly increasing, at least one.
    pub times: Vec<f32>,
    /// One value per time.
    pub values: Vec<T>,
    /// How values between keys are found.
    pub interpolation: Interpolation,
    /// Plays again from the first key after the last (the period is the last key's time;
    /// a track whose last key is at 0 holds its value).
    pub repeat: bool,
}

/// Why a track cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TrackError {
    /// No key.
    #[error("a track needs at least one key")]
    Empty,
    /// As many values as times are needed.
    #[error("{times} times but {values} values")]
    Lengths {
        /// Number of times.
        times: usize,
        /// Number of values.
        values: usize,
    },
    /// Times must be finite and strictly increasing.
    #[error("key times must be finite and strictly increasing (key {0})")]
    Times(usize),
    /// A value that is not finite.
    #[error("value {0} is not finite")]
    Value(usize),
}

impl<T: Copy> Track<T> {
    /// A checked track.
    ///
    /// # Errors
    /// [`TrackError`]: no key, mismatched lengths, times not strictly increasing, a
    /// non-finite value (`finite` says whether a value is).
    pub fn new(
        times: Vec<f32>,
        values: Vec<T>,
        interpolation: Interpolation,
        repeat: bool,
        finite: impl Fn(&T) -> bool,
    ) -> Result<Track<T>, TrackError> {
        if times.is_empty() {
            return Err(TrackError::Empty);
        }
        if times.len() != values.len() {
            return Err(TrackError::Lengths {
                times: times.len(),
                values: values.len(),
            });
        }
        for (i, t) in times.iter().enumerate() {
            if !t.is_finite() || (i > 0 && *t <= times[i - 1]) {
                return Err(TrackError::Times(i));
            }
        }
        if let Some(i) = values.iter().position(|v| !finite(v)) {
            return Err(TrackError::Value(i));
        }
        Ok(Track {
            times,
            values,
            interpolation,
            repeat,
        })
    }

    /// The value at time `t`, mixing neighbouring keys with `mix(a, b, s)` (`s` in `[0, 1]`).
    pub fn sample(&self, t: f64, mix: impl Fn(T, T, f32) -> T) -> Option<T> {
        let (first, last) = (*self.times.first()?, *self.times.last()?);
        let mut t = t;
        if self.repeat && last > 0.0 {
            t = t.rem_euclid(f64::from(last));
        }
        let t = t as f32;
        if t <= first || self.times.len() == 1 {
            return self.values.first().copied();
        }
        if t >= last {
            return self.values.last().copied();
        }
        // The key at or before t: times are increasing, so a binary search finds it.
        let i = self.times.partition_point(|k| *k <= t).saturating_sub(1);
        let (a, b) = (self.values[i], self.values[i + 1]);
        Some(match self.interpolation {
            Interpolation::Step => a,
            Interpolation::Linear => {
                let s = (t - self.times[i]) / (self.times[i + 1] - self.times[i]);
                mix(a, b, s.clamp(0.0, 1.0))
            }
        })
    }

    /// The time of the last key.
    #[must_use]
    pub fn duration(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }
}

/// Rotation keys: as written in scene files (degrees about X, then Y, then Z) or as
/// quaternions (glTF animations), kept as given so that a saved scene writes them back
/// unchanged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RotationKey {
    /// Degrees about X, then Y, then Z.
    EulerDeg(Vec3),
    /// A unit quaternion.
    Quat(Quat),
}

impl RotationKey {
    /// The rotation.
    #[must_use]
    pub fn quat(self) -> Quat {
        match self {
            RotationKey::EulerDeg(d) => {
                let r = d * (std::f32::consts::PI / 180.0);
                Quat::from_euler(EulerRot::ZYX, r.z, r.y, r.x)
            }
            RotationKey::Quat(q) => q,
        }
    }

    fn finite(&self) -> bool {
        match self {
            RotationKey::EulerDeg(d) => d.is_finite(),
            RotationKey::Quat(q) => q.is_finite() && q.length() > 1e-6,
        }
    }
}

/// Keyframed tracks of an entity's pose: each present track replaces that part of the pose
/// ([`apply_tracks`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Tracks {
    /// Translation keys.
    pub translation: Option<Track<Vec3>>,
    /// Rotation keys.
    pub rotation: Option<Track<RotationKey>>,
    /// Scale keys.
    pub scale: Option<Track<Vec3>>,
}

impl Tracks {
    /// A checked translation or scale track.
    ///
    /// # Errors
    /// See [`Track::new`].
    pub fn vec3(
        times: Vec<f32>,
        values: Vec<Vec3>,
        interpolation: Interpolation,
        repeat: bool,
    ) -> Result<Track<Vec3>, TrackError> {
        Track::new(times, values, interpolation, repeat, |v: &Vec3| {
            v.is_finite()
        })
    }

    /// A checked rotation track.
    ///
    /// # Errors
    /// See [`Track::new`].
    pub fn rotation(
        times: Vec<f32>,
        values: Vec<RotationKey>,
        interpolation: Interpolation,
        repeat: bool,
    ) -> Result<Track<RotationKey>, TrackError> {
        Track::new(times, values, interpolation, repeat, RotationKey::finite)
    }

    /// The time of the last key of any track.
    #[must_use]
    pub fn duration(&self) -> f32 {
        let t = self.translation.as_ref().map_or(0.0, Track::duration);
        let r = self.rotation.as_ref().map_or(0.0, Track::duration);
        let s = self.scale.as_ref().map_or(0.0, Track::duration);
        t.max(r).max(s)
    }
}

/// Sets each pose's translation, rotation and scale from its [`Tracks`] at `time` (only the
/// parts that have a track).
pub fn apply_tracks(world: &mut World, time: Time) {
    let t = time.seconds;
    for (tracks, pose) in world.query_mut::<(&Tracks, &mut Pose)>() {
        if let Some(v) = tracks
            .translation
            .as_ref()
            .and_then(|k| k.sample(t, Vec3::lerp))
        {
            pose.translation = v;
        }
        if let Some(v) = tracks.scale.as_ref().and_then(|k| k.sample(t, Vec3::lerp)) {
            pose.scale = v;
        }
        let slerp = |a: RotationKey, b: RotationKey, s: f32| {
            RotationKey::Quat(a.quat().slerp(b.quat(), s).normalize())
        };
        if let Some(r) = tracks.rotation.as_ref().and_then(|k| k.sample(t, slerp)) {
            pose.rotation = r.quat();
        }
    }
}

/// Turns each pose by its [`Spin`] at `time`.
pub fn apply_spin(world: &mut World, time: Time) {
    for (spin, pose) in world.query_mut::<(&Spin, &mut Pose)>() {
        let Some(axis) = spin.axis.try_normalize() else {
            continue;
        };
        let deg = phase(f64::from(spin.deg_per_s), time.seconds, 360.0);
        pose.rotation = (Quat::from_axis_angle(axis, deg.to_radians()) * pose.rotation).normalize();
    }
}

/// Two unit vectors spanning the plane normal to the unit `axis` (`u x v = axis`).
fn plane_of(axis: Vec3) -> (Vec3, Vec3) {
    // X projected into the plane where it is not along the axis (so an orbit about Y starts
    // on +X), else Z.
    let helper = if axis.cross(Vec3::X).length() > 1e-3 {
        Vec3::X
    } else {
        Vec3::Z
    };
    let u = (helper - axis * axis.dot(helper)).normalize();
    (u, axis.cross(u))
}

/// Offsets each pose's translation along its [`Orbit`]'s circle at `time`.
pub fn apply_orbit(world: &mut World, time: Time) {
    for (orbit, pose) in world.query_mut::<(&Orbit, &mut Pose)>() {
        let Some(axis) = orbit.axis.try_normalize() else {
            continue;
        };
        if orbit.period_s == 0.0 || !orbit.period_s.is_finite() {
            continue;
        }
        let turns = phase(1.0 / f64::from(orbit.period_s), time.seconds, 1.0);
        let a = turns * std::f32::consts::TAU + orbit.phase_deg.to_radians();
        let (u, v) = plane_of(axis);
        // Counter-clockwise seen from the axis' tip: from u towards axis x u.
        pose.translation += orbit.radius * (a.cos() * u + a.sin() * v);
    }
}

/// Offsets each pose's translation by its [`Bob`] at `time`.
pub fn apply_bob(world: &mut World, time: Time) {
    for (bob, pose) in world.query_mut::<(&Bob, &mut Pose)>() {
        if bob.period_s == 0.0 || !bob.period_s.is_finite() {
            continue;
        }
        let turns = phase(1.0 / f64::from(bob.period_s), time.seconds, 1.0);
        let a = turns * std::f32::consts::TAU + bob.phase_deg.to_radians();
        pose.translation += bob.axis * (bob.amplitude * a.sin());
    }
}

/// Runs the frame's systems on `scene` at `time`, in the order of the module docs, and sets
/// [`Scene::time`]. Returns the hierarchy's warnings ([`propagate_transforms`]).
pub fn update(scene: &mut Scene, time: Time) -> Vec<String> {
    scene.time = time;
    let world = &mut scene.world;
    reset_poses(world);
    apply_tracks(world, time);
    apply_spin(world, time);
    apply_orbit(world, time);
    apply_bob(world, time);
    let warnings = propagate_transforms(world);
    place_lights(world);
    place_cameras(world);
    warnings
}

/// Whether anything in `world` moves with time (a spin, orbit, bob or track).
#[must_use]
pub fn is_animated(world: &World) -> bool {
    world.query::<&Spin>().iter().next().is_some()
        || world.query::<&Orbit>().iter().next().is_some()
        || world.query::<&Bob>().iter().next().is_some()
        || world.query::<&Tracks>().iter().next().is_some()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::components::Transform;
    use crate::hierarchy::LocalTransform;

    fn bare(rest: Transform, extra: impl hecs::DynamicBundle) -> (World, hecs::Entity) {
        let mut world = World::new();
        let e = world.spawn((LocalTransform(rest), Pose::from(rest)));
        world.insert(e, extra).unwrap();
        (world, e)
    }

    fn pose(world: &World, e: hecs::Entity) -> Pose {
        *world.get::<&Pose>(e).unwrap()
    }

    #[test]
    fn reset_poses_starts_each_frame_from_the_rest_transform() {
        let rest = Transform {
            translate: Vec3::new(1.0, 2.0, 3.0),
            ..Transform::default()
        };
        let (mut world, e) = bare(rest, ());
        world.get::<&mut Pose>(e).unwrap().translation = Vec3::ZERO;
        reset_poses(&mut world);
        assert_eq!(pose(&world, e).translation, rest.translate);
    }

    #[test]
    fn spin_turns_by_rate_times_time_after_the_rest_rotation() {
        let rest = Transform {
            rotate_deg: Vec3::new(90.0, 0.0, 0.0),
            ..Transform::default()
        };
        let spin = Spin {
            axis: Vec3::new(0.0, 2.0, 0.0),
            deg_per_s: 30.0,
        };
        let (mut world, e) = bare(rest, (spin,));
        for t in [0.0, 1.0, 2.5, 13.0, -4.0] {
            reset_poses(&mut world);
            apply_spin(&mut world, Time::at(t));
            let want = Quat::from_rotation_y((30.0 * t as f32).to_radians())
                * Quat::from_rotation_x(90f32.to_radians());
            let got = pose(&world, e).rotation;
            assert!(got.dot(want).abs() > 1.0 - 1e-6, "t = {t}: {got} vs {want}");
        }
    }

    #[test]
    fn orbit_circles_the_rest_position_once_per_period() {
        let rest = Transform {
            translate: Vec3::new(0.0, 1.0, 0.0),
            ..Transform::default()
        };
        let orbit = Orbit {
            axis: Vec3::Y,
            radius: 2.0,
            period_s: 4.0,
            phase_deg: 0.0,
        };
        let (mut world, e) = bare(rest, (orbit,));
        // A quarter turn about +Y (right-handed) takes +X to -Z.
        for (t, want) in [
            (0.0, Vec3::new(2.0, 1.0, 0.0)),
            (1.0, Vec3::new(0.0, 1.0, -2.0)),
            (2.0, Vec3::new(-2.0, 1.0, 0.0)),
            (4.0, Vec3::new(2.0, 1.0, 0.0)),
            (401.0, Vec3::new(0.0, 1.0, -2.0)),
        ] {
            reset_poses(&mut world);
            apply_orbit(&mut world, Time::at(t));
            let got = pose(&world, e).translation;
            assert!((got - want).length() < 1e-4, "t = {t}: {got} vs {want}");
        }
    }

    #[test]
    fn bob_moves_along_its_axis_by_a_sine() {
        let bob = Bob {
            axis: Vec3::Z,
            amplitude: 0.5,
            period_s: 2.0,
            phase_deg: 0.0,
        };
        let (mut world, e) = bare(Transform::default(), (bob,));
        for (t, z) in [
            (0.0, 0.0),
            (0.5, 0.5),
            (1.0, 0.0),
            (1.5, -0.5),
            (0.25, 0.5 * 0.5f32.sqrt()),
        ] {
            reset_poses(&mut world);
            apply_bob(&mut world, Time::at(t));
            let got = pose(&world, e).translation;
            assert!(
                (got - Vec3::new(0.0, 0.0, z)).length() < 1e-5,
                "t = {t}: {got}"
            );
        }
    }

    #[test]
    fn linear_tracks_hit_their_keys_and_mix_between_them() {
        let tr = Tracks::vec3(
            vec![1.0, 2.0, 4.0],
            vec![
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 4.0, 0.0),
            ],
            Interpolation::Linear,
            false,
        )
        .unwrap();
        let tracks = Tracks {
            translation: Some(tr),
            ..Tracks::default()
        };
        let (mut world, e) = bare(Transform::default(), (tracks,));
        for (t, want) in [
            (0.0, Vec3::ZERO), // before the first key: the first
            (1.0, Vec3::ZERO), // at keys: the keys
            (2.0, Vec3::new(2.0, 0.0, 0.0)),
            (4.0, Vec3::new(2.0, 4.0, 0.0)),
            (1.5, Vec3::new(1.0, 0.0, 0.0)), // halfway
            (3.0, Vec3::new(2.0, 2.0, 0.0)),
            (9.0, Vec3::new(2.0, 4.0, 0.0)), // after the last: the last
        ] {
            reset_poses(&mut world);
            apply_tracks(&mut world, Time::at(t));
            let got = pose(&world, e).translation;
            assert!((got - want).length() < 1e-6, "t = {t}: {got} vs {want}");
        }
    }

    #[test]
    fn step_tracks_hold_and_repeating_tracks_wrap() {
        let sc = Tracks::vec3(
            vec![0.0, 1.0, 2.0],
            vec![Vec3::ONE, Vec3::splat(2.0), Vec3::splat(3.0)],
            Interpolation::Step,
            true,
        )
        .unwrap();
        let rot = Tracks::rotation(
            vec![0.0, 2.0],
            vec![
                RotationKey::EulerDeg(Vec3::ZERO),
                RotationKey::EulerDeg(Vec3::new(0.0, 90.0, 0.0)),
            ],
            Interpolation::Linear,
            true,
        )
        .unwrap();
        let tracks = Tracks {
            scale: Some(sc),
            rotation: Some(rot),
            ..Tracks::default()
        };
        let (mut world, e) = bare(Transform::default(), (tracks,));
        for (t, s, yaw) in [
            (0.0, 1.0, 0.0),
            (0.99, 1.0, 44.55),
            (1.0, 2.0, 45.0),
            (1.5, 2.0, 67.5),
            (2.5, 1.0, 22.5), // wrapped: 0.5 into the next play
            (5.0, 2.0, 45.0),
        ] {
            reset_poses(&mut world);
            apply_tracks(&mut world, Time::at(t));
            let p = pose(&world, e);
            assert_eq!(p.scale, Vec3::splat(s), "t = {t}");
            let want = Quat::from_rotation_y((yaw as f32).to_radians());
            assert!(
                p.rotation.dot(want).abs() > 1.0 - 1e-6,
                "t = {t}: {}",
                p.rotation
            );
        }
    }

    #[test]
    fn bad_tracks_are_refused_with_the_reason() {
        let v = |n| vec![Vec3::ZERO; n];
        let lin = Interpolation::Linear;
        assert_eq!(
            Tracks::vec3(vec![], v(0), lin, false),
            Err(TrackError::Empty)
        );
        assert_eq!(
            Tracks::vec3(vec![0.0, 1.0], v(1), lin, false),
            Err(TrackError::Lengths {
                times: 2,
                values: 1
            })
        );
        assert_eq!(
            Tracks::vec3(vec![0.0, 0.0], v(2), lin, false),
            Err(TrackError::Times(1))
        );
        assert_eq!(
            Tracks::vec3(vec![f32::NAN], v(1), lin, false),
            Err(TrackError::Times(0))
        );
        assert_eq!(
            Tracks::vec3(vec![0.0], vec![Vec3::splat(f32::INFINITY)], lin, false),
            Err(TrackError::Value(0))
        );
    }

    #[test]
    fn frame_times_come_from_the_frame_number() {
        // Frame 3 at 24 fps from 0.5 s, and frame 12 from 0: the same instant, 0.625 s.
        assert_eq!(Time::of_frame(0.5, 3, 24.0), Time::at(0.625));
        assert_eq!(Time::of_frame(0.0, 15, 24.0), Time::at(0.625));
    }

    #[test]
    fn update_runs_the_systems_in_order_and_records_the_time() {
        let mut scene = Scene::empty();
        let rest = Transform::default();
        let tracks = Tracks {
            translation: Some(
                Tracks::vec3(
                    vec![0.0, 1.0],
                    vec![Vec3::ZERO, Vec3::X],
                    Interpolation::Linear,
                    false,
                )
                .unwrap(),
            ),
            ..Tracks::default()
        };
        let bob = Bob {
            axis: Vec3::Y,
            amplitude: 1.0,
            period_s: 4.0,
            phase_deg: 0.0,
        };
        let e = scene
            .world
            .spawn((rest, LocalTransform(rest), Pose::from(rest), tracks, bob));
        assert!(is_animated(&scene.world));
        assert!(update(&mut scene, Time::at(1.0)).is_empty());
        assert_eq!(scene.time, Time::at(1.0));
        // The track sets the translation, then the bob adds to it (not the other way round).
        let t = *scene.world.get::<&Transform>(e).unwrap();
        assert!(
            (t.translate - Vec3::new(1.0, 1.0, 0.0)).length() < 1e-5,
            "{t:?}"
        );
    }
}
