//! The hierarchy and animation fields of objects, lights and the camera in scene files
//! (`parent`, `spin`, `orbit`, `bob`, `animation`): read, attached to entities, written back.

use glam::{Quat, Vec3};
use hecs::Entity;
use toml::{Table, Value};

use super::number::shortest;
use super::read::{Fields, choose};
use crate::Scene;
use crate::animation::{Bob, Interpolation, Orbit, RotationKey, Spin, Track, Tracks};
use crate::components::{Name, Transform};
use crate::error::SceneError;
use crate::hierarchy::{LocalTransform, Parent, Pose};

/// The keys this module reads from a table.
pub(crate) const MOTION_KEYS: &[&str] = &["parent", "spin", "orbit", "bob", "animation"];

/// What an entity's table says about its parent and its motion.
#[derive(Default)]
pub(crate) struct Motion {
    /// The parent's name, as written.
    pub parent: Option<String>,
    /// The path of the `parent` field, for messages.
    pub parent_field: String,
    spin: Option<Spin>,
    orbit: Option<Orbit>,
    bob: Option<Bob>,
    tracks: Option<Tracks>,
    /// Whether the object is nested in another's `children` (its parent is that object).
    pub nested: bool,
}

impl Motion {
    /// Whether the entity needs a pose (it has a parent or moves).
    pub(crate) fn posed(&self) -> bool {
        self.parent.is_some()
            || self.nested
            || self.spin.is_some()
            || self.orbit.is_some()
            || self.bob.is_some()
            || self.tracks.is_some()
    }

    /// Gives `entity` its rest transform and pose (when posed) and its motion components.
    pub(crate) fn attach(self, scene: &mut Scene, entity: Entity, rest: Transform) {
        if !self.posed() {
            return;
        }
        let w = &mut scene.world;
        w.insert(entity, (LocalTransform(rest), Pose::from(rest)))
            .ok();
        if let Some(c) = self.spin {
            w.insert_one(entity, c).ok();
        }
        if let Some(c) = self.orbit {
            w.insert_one(entity, c).ok();
        }
        if let Some(c) = self.bob {
            w.insert_one(entity, c).ok();
        }
        if let Some(c) = self.tracks {
            w.insert_one(entity, c).ok();
        }
    }
}

fn period(t: &Fields<'_>) -> Result<f32, SceneError> {
    let p = t.req_f32("period_s")?;
    if p == 0.0 {
        return Err(t.error("period_s", "must not be 0"));
    }
    Ok(p)
}

fn axis(t: &Fields<'_>, default: Vec3) -> Result<Vec3, SceneError> {
    let a = t.vec3("axis")?.unwrap_or(default);
    if a.length() < 1e-12 {
        return Err(t.error("axis", "must not be zero"));
    }
    Ok(a)
}

fn interpolation(t: &Fields<'_>) -> Result<Interpolation, SceneError> {
    match t.str("interpolation")? {
        None => Ok(Interpolation::Linear),
        Some(s) => choose(
            t,
            "interpolation",
            s,
            &[
                ("linear", Interpolation::Linear),
                ("step", Interpolation::Step),
            ],
        ),
    }
}

fn track_error(t: &Fields<'_>, e: &crate::animation::TrackError) -> SceneError {
    t.error_here(e.to_string())
}

fn vec3_track(t: &Fields<'_>, scale: bool) -> Result<Track<Vec3>, SceneError> {
    let times = t
        .f32s("times")?
        .ok_or_else(|| t.error("times", "missing"))?;
    let values: Vec<Vec3> = t
        .rows("values", 3)?
        .ok_or_else(|| t.error("values", "missing"))?
        .iter()
        .map(|r| Vec3::new(r[0], r[1], r[2]))
        .collect();
    if scale && let Some(i) = values.iter().position(|v| v.abs().min_element() < 1e-12) {
        return Err(t.error(
            &format!("values[{i}]"),
            "a scale must not be zero (the object would vanish)",
        ));
    }
    let interp = interpolation(t)?;
    let repeat = t.bool("repeat")?.unwrap_or(false);
    t.finish(&["times", "values", "interpolation", "repeat"])?;
    Tracks::vec3(times, values, interp, repeat).map_err(|e| track_error(t, &e))
}

fn rotation_track(t: &Fields<'_>) -> Result<Track<RotationKey>, SceneError> {
    let times = t
        .f32s("times")?
        .ok_or_else(|| t.error("times", "missing"))?;
    let values: Vec<RotationKey> = match (t.rows("values", 3)?, t.rows("quaternions", 4)?) {
        (Some(v), None) => v
            .iter()
            .map(|r| RotationKey::EulerDeg(Vec3::new(r[0], r[1], r[2])))
            .collect(),
        (None, Some(q)) => q
            .iter()
            .map(|r| RotationKey::Quat(Quat::from_xyzw(r[0], r[1], r[2], r[3])))
            .collect(),
        _ => {
            return Err(t.error_here(
                "expected exactly one of `values` (degrees about X, Y, Z) or `quaternions` ([x, y, z, w])",
            ));
        }
    };
    let interp = interpolation(t)?;
    let repeat = t.bool("repeat")?.unwrap_or(false);
    t.finish(&["times", "values", "quaternions", "interpolation", "repeat"])?;
    Tracks::rotation(times, values, interp, repeat).map_err(|e| track_error(t, &e))
}

/// Reads `parent`, `spin`, `orbit`, `bob` and `animation` from `f`.
pub(crate) fn motion(f: &Fields<'_>) -> Result<Motion, SceneError> {
    let mut m = Motion {
        parent: f.str("parent")?.map(str::to_owned),
        parent_field: f.path_of("parent"),
        ..Motion::default()
    };
    if let Some(t) = f.table("spin")? {
        m.spin = Some(Spin {
            axis: axis(&t, Vec3::Y)?,
            deg_per_s: t.req_f32("deg_per_s")?,
        });
        t.finish(&["axis", "deg_per_s"])?;
    }
    if let Some(t) = f.table("orbit")? {
        m.orbit = Some(Orbit {
            axis: axis(&t, Vec3::Y)?,
            radius: t.req_f32("radius")?,
            period_s: period(&t)?,
            phase_deg: t.f32("phase_deg")?.unwrap_or(0.0),
        });
        t.finish(&["axis", "radius", "period_s", "phase_deg"])?;
    }
    if let Some(t) = f.table("bob")? {
        m.bob = Some(Bob {
            axis: axis(&t, Vec3::Y)?,
            amplitude: t.req_f32("amplitude")?,
            period_s: period(&t)?,
            phase_deg: t.f32("phase_deg")?.unwrap_or(0.0),
        });
        t.finish(&["axis", "amplitude", "period_s", "phase_deg"])?;
    }
    if let Some(a) = f.table("animation")? {
        let tracks = Tracks {
            translation: a
                .table("translation")?
                .map(|t| vec3_track(&t, false))
                .transpose()?,
            rotation: a
                .table("rotation")?
                .map(|t| rotation_track(&t))
                .transpose()?,
            scale: a
                .table("scale")?
                .map(|t| vec3_track(&t, true))
                .transpose()?,
        };
        a.finish(&["translation", "rotation", "scale"])?;
        m.tracks = Some(tracks);
    }
    Ok(m)
}

/// Gives each pending child its [`Parent`]: the object named so. A name no object has, a
/// name two objects share, an entity that would be its own ancestor: each an error naming
/// the child's `parent` field.
pub(crate) fn resolve_parents(
    scene: &mut Scene,
    file: &str,
    pending: Vec<(Entity, String, String)>,
    objects: &[(String, Entity)],
) -> Result<(), SceneError> {
    for (child, name, field) in &pending {
        let found: Vec<Entity> = objects
            .iter()
            .filter(|(n, _)| n == name)
            .map(|(_, e)| *e)
            .collect();
        let parent = match found.as_slice() {
            [one] => *one,
            [] => {
                let mut names: Vec<&str> = objects.iter().map(|(n, _)| n.as_str()).collect();
                names.truncate(20);
                return Err(SceneError::field(
                    file,
                    field.clone(),
                    format!(
                        "no object is named \"{name}\" (objects: {})",
                        if names.is_empty() {
                            "none".to_owned()
                        } else {
                            names.join(", ")
                        }
                    ),
                ));
            }
            _ => {
                return Err(SceneError::field(
                    file,
                    field.clone(),
                    format!(
                        "{} objects are named \"{name}\"; a parent's name must be unique",
                        found.len()
                    ),
                ));
            }
        };
        if parent == *child {
            return Err(SceneError::field(
                file,
                field.clone(),
                format!("\"{name}\" is this object itself"),
            ));
        }
        scene.world.insert_one(*child, Parent(parent)).ok();
    }
    for (child, name, field) in &pending {
        // Walk up: a chain longer than the entities holds a loop (glTF nodes included).
        let mut at = *child;
        for _ in 0..=scene.world.len() {
            match scene.world.get::<&Parent>(at).map(|p| p.0) {
                Ok(p) if p == *child => {
                    return Err(SceneError::field(
                        file,
                        field.clone(),
                        format!("\"{name}\" is a descendant of this object (parents form a loop)"),
                    ));
                }
                Ok(p) => at = p,
                Err(_) => break,
            }
        }
    }
    Ok(())
}

fn f(x: f32) -> Value {
    Value::Float(shortest(x))
}

fn v3(v: Vec3) -> Value {
    Value::Array(v.to_array().iter().map(|&x| f(x)).collect())
}

fn track_table<T: Copy>(t: &Track<T>, key: &str, value: impl Fn(T) -> Value) -> Table {
    let mut out = Table::new();
    out.insert(
        "times".into(),
        Value::Array(t.times.iter().map(|&x| f(x)).collect()),
    );
    out.insert(
        key.into(),
        Value::Array(t.values.iter().map(|&v| value(v)).collect()),
    );
    out.insert(
        "interpolation".into(),
        Value::String(t.interpolation.name().to_owned()),
    );
    out.insert("repeat".into(), Value::Boolean(t.repeat));
    out
}

/// Writes the parent and motion of `entity` into its table `t`.
pub(crate) fn write_motion(scene: &Scene, entity: Entity, t: &mut Table) {
    let w = &scene.world;
    if let Ok(p) = w.get::<&Parent>(entity)
        && let Ok(n) = w.get::<&Name>(p.0)
    {
        t.insert("parent".into(), Value::String(n.0.clone()));
    }
    if let Ok(s) = w.get::<&Spin>(entity) {
        let mut x = Table::new();
        x.insert("axis".into(), v3(s.axis));
        x.insert("deg_per_s".into(), f(s.deg_per_s));
        t.insert("spin".into(), Value::Table(x));
    }
    if let Ok(o) = w.get::<&Orbit>(entity) {
        let mut x = Table::new();
        x.insert("axis".into(), v3(o.axis));
        x.insert("radius".into(), f(o.radius));
        x.insert("period_s".into(), f(o.period_s));
        x.insert("phase_deg".into(), f(o.phase_deg));
        t.insert("orbit".into(), Value::Table(x));
    }
    if let Ok(b) = w.get::<&Bob>(entity) {
        let mut x = Table::new();
        x.insert("axis".into(), v3(b.axis));
        x.insert("amplitude".into(), f(b.amplitude));
        x.insert("period_s".into(), f(b.period_s));
        x.insert("phase_deg".into(), f(b.phase_deg));
        t.insert("bob".into(), Value::Table(x));
    }
    if let Ok(k) = w.get::<&Tracks>(entity) {
        let mut a = Table::new();
        if let Some(tr) = &k.translation {
            a.insert(
                "translation".into(),
                Value::Table(track_table(tr, "values", v3)),
            );
        }
        if let Some(r) = &k.rotation {
            // One form per track: quaternions if any key is one (glTF), else degrees.
            let quats = r.values.iter().any(|v| matches!(v, RotationKey::Quat(_)));
            let table = if quats {
                track_table(r, "quaternions", |v| {
                    let q = v.quat();
                    Value::Array([q.x, q.y, q.z, q.w].iter().map(|&x| f(x)).collect())
                })
            } else {
                track_table(r, "values", |v| match v {
                    RotationKey::EulerDeg(d) => v3(d),
                    RotationKey::Quat(_) => Value::Array(Vec::new()),
                })
            };
            a.insert("rotation".into(), Value::Table(table));
        }
        if let Some(s) = &k.scale {
            a.insert("scale".into(), Value::Table(track_table(s, "values", v3)));
        }
        t.insert("animation".into(), Value::Table(a));
    }
}
