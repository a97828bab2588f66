//! A [`Scene`] back to TOML: what `load` reads, so a loaded-then-saved scene loads to the
//! same world. Paths are written as they were read; the output is written atomically.

use std::path::Path;

use glam::Vec3;
use hecs::Entity;
use phosphor_lighting::{Attenuation, Fresnel, Light, LightKind, Material, SpecularModel};
use phosphor_mesh::{NormalSource, Weighting};
use phosphor_raster::{Camera, Encoding, ProceduralBump, Projection};
use toml::{Table, Value};

use super::number::shortest;
use crate::components::{
    BumpSource, GltfNode, GltfRoot, MaterialDef, MaterialName, MeshRef, MeshSource, Name,
    Primitive, Shading, Transform,
};
use crate::components::{CastsShadows, ShadowRole};
use crate::error::SceneError;
use crate::hierarchy::{LocalCamera, LocalLight, LocalTransform};
use crate::{CullChoice, RenderSettings, Scene};

fn v3(v: Vec3) -> Value {
    Value::Array(v.to_array().iter().map(|&x| f(x)).collect())
}

fn f(x: f32) -> Value {
    Value::Float(shortest(x))
}

fn s(x: &str) -> Value {
    Value::String(x.to_owned())
}

fn render_table(r: &RenderSettings) -> Table {
    let mut t = Table::new();
    t.insert("width".into(), Value::Integer(i64::from(r.width)));
    t.insert("height".into(), Value::Integer(i64::from(r.height)));
    t.insert("shading".into(), s(r.shading.name()));
    t.insert(
        "encoding".into(),
        s(match r.encoding {
            Encoding::Srgb => "srgb",
            Encoding::Linear => "linear",
        }),
    );
    let background = if r.background_alpha == 1.0 {
        v3(r.background)
    } else {
        let [x, y, z] = r.background.to_array();
        Value::Array([x, y, z, r.background_alpha].map(f).to_vec())
    };
    t.insert("background".into(), background);
    t.insert(
        "perspective_correct".into(),
        Value::Boolean(r.perspective_correct),
    );
    t.insert(
        "cull_backfaces".into(),
        match r.cull_backfaces {
            CullChoice::Auto => s("auto"),
            CullChoice::Always => Value::Boolean(true),
            CullChoice::Never => Value::Boolean(false),
        },
    );
    t.insert("aa".into(), s(r.antialias.name()));
    t.insert(
        "gouraud_clamp".into(),
        Value::Boolean(r.gouraud_vertex_clamp),
    );
    t.insert("fast_phong".into(), s(r.fast_phong.name()));
    t.insert("interpolation".into(), s(r.interpolation.name()));
    if r.shadow_size != 0 {
        t.insert(
            "shadow_size".into(),
            Value::Integer(i64::from(r.shadow_size)),
        );
    }
    t
}

fn camera_table(c: &Camera) -> Table {
    let mut t = Table::new();
    t.insert("eye".into(), v3(c.eye));
    t.insert("target".into(), v3(c.target));
    t.insert("up".into(), v3(c.up));
    t.insert("fov_y_deg".into(), f(c.fov_y_deg));
    t.insert("near".into(), f(c.near));
    t.insert("far".into(), f(c.far));
    if let Projection::Orthographic { height } = c.projection {
        t.insert("projection".into(), s(c.projection.name()));
        t.insert("ortho_height".into(), f(height));
    }
    t
}

fn light_table(name: &str, l: &Light) -> Table {
    let mut t = Table::new();
    t.insert("name".into(), s(name));
    match l.kind {
        LightKind::Directional { direction } => {
            t.insert("type".into(), s("directional"));
            t.insert("direction".into(), v3(direction));
        }
        LightKind::Point { position } => {
            t.insert("type".into(), s("point"));
            t.insert("position".into(), v3(position));
        }
        LightKind::Spot {
            position,
            direction,
            inner_deg,
            outer_deg,
        } => {
            t.insert("type".into(), s("spot"));
            t.insert("position".into(), v3(position));
            t.insert("direction".into(), v3(direction));
            t.insert("inner_deg".into(), f(inner_deg));
            t.insert("outer_deg".into(), f(outer_deg));
        }
        LightKind::Tube {
            start,
            end,
            samples,
        } => {
            t.insert("type".into(), s("tube"));
            t.insert("start".into(), v3(start));
            t.insert("end".into(), v3(end));
            t.insert("samples".into(), Value::Integer(i64::from(samples)));
        }
        LightKind::Rect {
            corner,
            edge_u,
            edge_v,
            samples,
        } => {
            t.insert("type".into(), s("rect"));
            t.insert("corner".into(), v3(corner));
            t.insert("edge_u".into(), v3(edge_u));
            t.insert("edge_v".into(), v3(edge_v));
            t.insert("samples".into(), Value::Integer(i64::from(samples)));
        }
    }
    t.insert("intensity".into(), v3(l.intensity));
    if let Some(si) = l.specular_intensity {
        t.insert("specular_intensity".into(), v3(si));
    }
    if !matches!(l.kind, LightKind::Directional { .. }) {
        let mut a = Table::new();
        match l.attenuation {
            Attenuation::None => {
                a.insert("model".into(), s("none"));
            }
            Attenuation::InverseSquare => {
                a.insert("model".into(), s("inverse-square"));
            }
            Attenuation::Offset { k } => {
                a.insert("model".into(), s("offset"));
                a.insert("k".into(), f(k));
            }
            Attenuation::Quadratic { c, l, q } => {
                a.insert("model".into(), s("quadratic"));
                a.insert("c".into(), f(c));
                a.insert("l".into(), f(l));
                a.insert("q".into(), f(q));
            }
        }
        t.insert("attenuation".into(), Value::Table(a));
    }
    t.insert("enabled".into(), Value::Boolean(l.enabled));
    t
}

fn material_table(def: &MaterialDef) -> Table {
    let m: &Material = &def.material;
    let mut t = Table::new();
    t.insert("ka".into(), v3(m.ka));
    t.insert("kd".into(), v3(m.kd));
    t.insert("ks".into(), v3(m.ks));
    t.insert("shininess".into(), f(m.shininess));
    t.insert(
        "specular".into(),
        s(match m.specular {
            SpecularModel::Phong => "phong",
            SpecularModel::Blinn => "blinn",
        }),
    );
    let mut fr = Table::new();
    match m.fresnel {
        Fresnel::None => {
            fr.insert("model".into(), s("none"));
        }
        Fresnel::Constant { w } => {
            fr.insert("model".into(), s("constant"));
            fr.insert("w".into(), f(w));
        }
        Fresnel::Schlick { f0 } => {
            fr.insert("model".into(), s("schlick"));
            fr.insert("f0".into(), f(f0));
        }
    }
    fr.insert("mode".into(), s(m.fresnel_mode.name()));
    t.insert("fresnel".into(), Value::Table(fr));
    t.insert("emission".into(), v3(m.emission));
    if let Some((src, scale)) = &def.bump {
        let mut b = Table::new();
        match src {
            BumpSource::Procedural(p) => {
                b.insert(
                    "procedural".into(),
                    s(match p {
                        ProceduralBump::Bumps => "bumps",
                        ProceduralBump::Ripples => "ripples",
                    }),
                );
            }
            BumpSource::Map { written, .. } => {
                b.insert("map".into(), s(written));
            }
            BumpSource::Normals { written, .. } => {
                b.insert("normals".into(), s(written));
            }
        }
        b.insert("scale".into(), f(*scale));
        t.insert("bump".into(), Value::Table(b));
    }
    match &def.kd_map {
        Some(crate::textures::MapSource::File { written, .. }) => {
            t.insert("kd_map".into(), s(written));
        }
        Some(crate::textures::MapSource::Checker { squares }) => {
            let mut c = Table::new();
            c.insert("procedural".into(), s("checker"));
            c.insert("squares".into(), Value::Integer(i64::from(*squares)));
            t.insert("kd_map".into(), Value::Table(c));
        }
        None => {}
    }
    t
}

fn primitive_table(p: &Primitive) -> Table {
    let mut t = Table::new();
    let int = |x: u32| Value::Integer(i64::from(x));
    match *p {
        Primitive::Sphere {
            radius,
            segments,
            rings,
        } => {
            t.insert("shape".into(), s("sphere"));
            t.insert("radius".into(), f(radius));
            t.insert("segments".into(), int(segments));
            t.insert("rings".into(), int(rings));
        }
        Primitive::Cube { half_size } => {
            t.insert("shape".into(), s("cube"));
            t.insert("half_size".into(), f(half_size));
        }
        Primitive::Cylinder {
            radius,
            height,
            segments,
        } => {
            t.insert("shape".into(), s("cylinder"));
            t.insert("radius".into(), f(radius));
            t.insert("height".into(), f(height));
            t.insert("segments".into(), int(segments));
        }
        Primitive::Torus {
            major,
            minor,
            segments,
            sides,
        } => {
            t.insert("shape".into(), s("torus"));
            t.insert("major".into(), f(major));
            t.insert("minor".into(), f(minor));
            t.insert("segments".into(), int(segments));
            t.insert("sides".into(), int(sides));
        }
        Primitive::Plane {
            half_size,
            subdivisions,
        } => {
            t.insert("shape".into(), s("plane"));
            t.insert("half_size".into(), f(half_size));
            t.insert("subdivisions".into(), int(subdivisions));
        }
    }
    t
}

/// What an object's table says, gathered from a mesh object or a glTF root.
struct ObjectTable<'a> {
    name: &'a str,
    /// The world transform (the `LocalTransform` is written where there is one).
    transform: Transform,
    source: &'a MeshSource,
    material: &'a str,
    normalized: bool,
    normals: &'a phosphor_mesh::NormalOptions,
    shading: Option<&'a Shading>,
}

fn object_table(scene: &Scene, e: Entity, o: &ObjectTable<'_>) -> Table {
    let mut t = Table::new();
    t.insert("name".into(), s(o.name));
    match o.source {
        MeshSource::File { written, .. } => {
            t.insert("mesh".into(), s(written.as_str()));
        }
        MeshSource::Primitive(p) => {
            t.insert("primitive".into(), Value::Table(primitive_table(p)));
        }
    }
    t.insert("material".into(), s(o.material));
    t.insert("normalize".into(), Value::Boolean(o.normalized));
    if let Some(sh) = o.shading {
        t.insert("shading".into(), s(sh.0.name()));
    }
    if let Ok(role) = scene.world.get::<&ShadowRole>(e) {
        t.insert("cast_shadows".into(), Value::Boolean(role.cast));
        t.insert("receive_shadows".into(), Value::Boolean(role.receive));
    }
    let n = o.normals;
    let mut nt = Table::new();
    nt.insert(
        "weighting".into(),
        s(match n.weighting {
            Weighting::Uniform => "uniform",
            Weighting::Area => "area",
            Weighting::Angle => "angle",
        }),
    );
    if let Some(a) = n.crease_angle_deg {
        nt.insert("crease_angle_deg".into(), f(a));
    }
    nt.insert(
        "smoothing_groups".into(),
        Value::Boolean(n.use_smoothing_groups),
    );
    nt.insert(
        "split_by_material".into(),
        Value::Boolean(n.split_by_material),
    );
    nt.insert(
        "source".into(),
        s(match n.source {
            NormalSource::Authored => "file",
            NormalSource::Computed => "computed",
        }),
    );
    t.insert("normals".into(), Value::Table(nt));
    let tr = scene
        .world
        .get::<&LocalTransform>(e)
        .map_or(o.transform, |l| l.0);
    super::motion::write_motion(scene, e, &mut t);
    let mut tt = Table::new();
    tt.insert("translate".into(), v3(tr.translate));
    tt.insert("rotate_deg".into(), v3(tr.rotate_deg));
    tt.insert("scale".into(), v3(tr.scale));
    t.insert("transform".into(), Value::Table(tt));
    t
}

/// The scene as TOML text.
#[must_use]
pub fn scene_to_toml(scene: &Scene) -> String {
    let mut root = Table::new();
    root.insert("render".into(), Value::Table(render_table(&scene.settings)));
    let camera_entity = scene.entities_with::<Camera>().first().copied();
    // A camera on a rig is written where it sits in its parent's space.
    let camera = camera_entity
        .and_then(|e| scene.world.get::<&LocalCamera>(e).ok().map(|c| c.0))
        .unwrap_or_else(|| scene.camera());
    let mut camera_t = camera_table(&camera);
    if let Some(e) = camera_entity {
        super::motion::write_motion(scene, e, &mut camera_t);
    }
    root.insert("camera".into(), Value::Table(camera_t));
    let mut ambient = Table::new();
    ambient.insert("intensity".into(), v3(scene.ambient));
    root.insert("ambient".into(), Value::Table(ambient));
    // A carried light is written where it sits in its parent's space.
    let lights: Vec<Value> = scene
        .light_entities()
        .into_iter()
        .zip(scene.lights())
        .map(|(e, (name, mut l))| {
            if let Ok(local) = scene.world.get::<&LocalLight>(e) {
                l.kind = local.0;
            }
            let mut t = light_table(&name, &l);
            if scene.world.get::<&CastsShadows>(e).is_ok() {
                t.insert("shadows".into(), Value::Boolean(true));
            }
            super::motion::write_motion(scene, e, &mut t);
            Value::Table(t)
        })
        .collect();
    root.insert("lights".into(), Value::Array(lights));
    let mut materials = Table::new();
    for (name, def) in &scene.materials {
        materials.insert(name.clone(), Value::Table(material_table(def)));
    }
    let mut objects = Vec::new();
    // Objects without a name, transform or material are not drawn either
    // (`render::unrenderable` warns of them); an object whose material is not in the table
    // (spawned by hand, without a `MaterialName`) gets an entry of its own.
    // The entities a glTF's nodes made come from the file again when it loads: only their
    // root is written.
    let mut written: Vec<Entity> = scene
        .objects()
        .into_iter()
        .chain(scene.entities_with::<GltfRoot>())
        .filter(|&e| scene.world.get::<&GltfNode>(e).is_err())
        .collect();
    written.sort_by_key(|e| e.id());
    written.dedup();
    for e in written {
        if let Ok(root) = scene.world.get::<&GltfRoot>(e) {
            let Ok(name) = scene.world.get::<&Name>(e) else {
                continue;
            };
            let tr = scene
                .world
                .get::<&Transform>(e)
                .map(|t| *t)
                .unwrap_or_default();
            let mat = scene
                .world
                .get::<&MaterialName>(e)
                .map_or_else(|_| "default".to_owned(), |m| m.0.clone());
            let shading = scene.world.get::<&Shading>(e).ok().map(|s| *s);
            let what = ObjectTable {
                name: &name.0,
                transform: tr,
                source: &root.source,
                material: &mat,
                normalized: root.normalized,
                normals: &root.normals,
                shading: shading.as_ref(),
            };
            objects.push(Value::Table(object_table(scene, e, &what)));
            continue;
        }
        let mut q = scene.world.query_one::<(
            &Name,
            &Transform,
            &MeshRef,
            &Material,
            Option<&MaterialName>,
            Option<&Shading>,
        )>(e);
        let Ok((name, tr, mesh, coefficients, mat, shading)) = q.get() else {
            continue;
        };
        let mat = match mat {
            Some(m) if scene.materials.contains_key(&m.0) || m.0 == "default" => m.0.clone(),
            _ => {
                let own = format!("{} (own)", name.0);
                materials.insert(
                    own.clone(),
                    Value::Table(material_table(&MaterialDef::from(*coefficients))),
                );
                own
            }
        };
        let what = ObjectTable {
            name: &name.0,
            transform: *tr,
            source: &mesh.0.source,
            material: &mat,
            normalized: mesh.0.normalized,
            normals: &mesh.0.normals,
            shading,
        };
        objects.push(Value::Table(object_table(scene, e, &what)));
    }
    root.insert("materials".into(), Value::Table(materials));
    root.insert("objects".into(), Value::Array(objects));
    toml::to_string(&root).unwrap_or_default()
}

/// Writes the scene to `path` atomically (a temporary file beside it, then a rename), so a
/// failed save never leaves a half-written file over a good one.
pub fn save_scene(scene: &Scene, path: &Path) -> Result<(), SceneError> {
    let file = path.display().to_string();
    let text = scene_to_toml(scene);
    let tmp = path.with_extension("toml.tmp");
    let result = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, path));
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        SceneError::Write {
            file,
            what: e.to_string(),
        }
    })
}
