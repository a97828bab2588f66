//! Load, save, load: the bundled scenes and generated ones come back as the same world, and
//! numbers are written as the shortest decimal that reads back exactly.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use glam::Vec3;
use phosphor_lighting::{Light, Material};
use phosphor_scene::animation::{Bob, Orbit, Spin, Tracks};
use phosphor_scene::hierarchy::{LocalCamera, LocalLight, LocalTransform, Parent};
use phosphor_scene::{
    Disk, MaterialName, MeshRef, Name, Primitive, Scene, Shading, Transform, parse_scene,
    scene_to_toml,
};
use proptest::prelude::*;

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes")
}

/// What a component of `e` is, printed: equal worlds print equal.
fn parts(s: &Scene, e: hecs::Entity) -> String {
    let w = &s.world;
    let name_of = |p: hecs::Entity| w.get::<&Name>(p).map(|n| n.0.clone()).ok();
    let mut out = String::new();
    macro_rules! put {
        ($t:ty) => {
            if let Ok(c) = w.get::<&$t>(e) {
                out.push_str(&format!("{} = {:?}\n", stringify!($t), *c));
            }
        };
    }
    put!(Name);
    put!(Transform);
    put!(LocalTransform);
    put!(MaterialName);
    put!(Material);
    put!(Shading);
    put!(Light);
    put!(LocalLight);
    put!(LocalCamera);
    put!(Spin);
    put!(Orbit);
    put!(Bob);
    put!(Tracks);
    put!(phosphor_raster::Camera);
    if let Ok(p) = w.get::<&Parent>(e) {
        out.push_str(&format!("parent = {:?}\n", name_of(p.0)));
    }
    if let Ok(m) = w.get::<&MeshRef>(e) {
        let m = &m.0;
        out.push_str(&format!(
            "mesh = {:?} {:?} {} {} triangles, positions {:?}\n",
            m.source,
            m.normals,
            m.normalized,
            m.mesh.indices.len(),
            m.mesh.positions.iter().take(64).collect::<Vec<_>>()
        ));
    }
    out
}

/// The whole world and the resources beside it, entity by entity in scene order.
fn describe(s: &Scene) -> String {
    let mut ids: Vec<hecs::Entity> = s.world.iter().map(|e| e.entity()).collect();
    ids.sort_by_key(|e| e.id());
    let mut out = format!("{:?}\n{:?}\n{:?}\n", s.settings, s.ambient, s.materials);
    for e in ids {
        out.push_str(&parts(s, e));
        out.push_str("--\n");
    }
    out
}

fn round_trip(text: &str, dir: &Path) -> (Scene, Scene, String) {
    let a = parse_scene(text, "a.toml", dir, &Disk).unwrap();
    let saved = scene_to_toml(&a);
    let b = parse_scene(&saved, "b.toml", dir, &Disk)
        .unwrap_or_else(|e| panic!("the saved scene does not load: {e}\n{saved}"));
    (a, b, saved)
}

#[test]
fn bundled_scenes_load_save_and_load_to_the_same_world() {
    let mut seen = 0;
    for entry in std::fs::read_dir(scenes_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let (a, b, saved) = round_trip(&text, &scenes_dir());
        assert_eq!(describe(&a), describe(&b), "{}", path.display());
        assert_eq!(scene_to_toml(&b), saved, "{}", path.display());
        seen += 1;
    }
    assert!(seen >= 3, "only {seen} bundled scenes");
}

#[test]
fn numbers_are_written_as_the_shortest_exact_decimal() {
    let text = "[materials.red]\nkd = [0.2, 0.1, 0.7]\nshininess = 12.3\n\
        [[objects]]\nname = \"a\"\nprimitive = { shape = \"cube\", half_size = 0.3 }\nmaterial = \"red\"\n\
        transform = { translate = [0.1, -1e-7, 3.3333333], scale = 1.1 }\n";
    let (_, b, saved) = round_trip(text, Path::new(""));
    for want in [
        "kd = [0.2, 0.1, 0.7]",
        "shininess = 12.3",
        "half_size = 0.3",
        "scale = [1.1, 1.1, 1.1]",
        "[materials.red]",
    ] {
        assert!(saved.contains(want), "{want} in\n{saved}");
    }
    assert!(!saved.contains("0000000"), "{saved}");
    let t = *b.world.get::<&Transform>(b.objects()[0]).unwrap();
    assert_eq!(t.translate, Vec3::new(0.1, -1e-7, 3.333_333_3));
}

#[test]
fn a_scene_built_in_code_saves_its_materials_and_loads_back() {
    let mut scene = Scene::empty();
    let cube = scene.primitive(Primitive::Cube { half_size: 0.5 }).unwrap();
    let red = scene
        .add_material(
            "red",
            Material {
                kd: Vec3::new(0.8, 0.1, 0.1),
                ..Material::default()
            },
        )
        .unwrap();
    let base = scene.object("base", &cube, &red).spawn();
    scene
        .object("top", &cube, &red)
        .translate(Vec3::new(0.0, 1.0, 0.0))
        .rotate_deg(Vec3::new(0.0, 45.0, 0.0))
        .spawn();
    scene
        .light("sun", Light::directional(-Vec3::Y, Vec3::ONE).unwrap())
        .spawn();
    // An object spawned by hand, without a material name: saved with a material of its own.
    let m = MeshRef(scene.world.get::<&MeshRef>(base).unwrap().0.clone());
    scene.world.spawn((
        Name("loose".into()),
        Transform::default(),
        m,
        Material::s1(),
    ));
    let saved = scene_to_toml(&scene);
    let b = Scene::parse(&saved, "saved.toml").unwrap();
    assert_eq!(b.materials["red"], scene.materials["red"]);
    assert_eq!(b.objects().len(), 3);
    assert_eq!(
        *b.world.get::<&Material>(b.objects()[2]).unwrap(),
        Material::s1()
    );
    assert_eq!(scene_to_toml(&b), saved);
}

/// A TOML number that reads back as exactly `x`.
fn n(x: f32) -> String {
    format!("{x:?}")
}

fn v(x: [f32; 3]) -> String {
    format!("[{}, {}, {}]", n(x[0]), n(x[1]), n(x[2]))
}

#[derive(Debug, Clone)]
struct Obj {
    shape: u8,
    material: u8,
    t: [f32; 3],
    r: [f32; 3],
    s: f32,
    parent: Option<usize>,
    spin: Option<f32>,
    bob: Option<(f32, f32)>,
    keys: Option<Vec<(f32, [f32; 3])>>,
    step: bool,
}

fn obj() -> impl Strategy<Value = Obj> {
    let f = -50.0f32..50.0;
    (
        (0u8..3, 0u8..3, [f.clone(), f.clone(), f.clone()]),
        (
            [-360.0f32..360.0, -360.0f32..360.0, -360.0f32..360.0],
            0.01f32..10.0,
        ),
        (
            proptest::option::of(0usize..8),
            proptest::option::of(-720.0f32..720.0),
            proptest::option::of((0.0f32..3.0, 0.1f32..10.0)),
        ),
        (
            proptest::option::of(proptest::collection::vec(
                (0.001f32..5.0, [f.clone(), f.clone(), f]),
                1..5,
            )),
            any::<bool>(),
        ),
    )
        .prop_map(
            |((shape, material, t), (r, s), (parent, spin, bob), (keys, step))| Obj {
                shape,
                material,
                t,
                r,
                s,
                parent,
                spin,
                bob,
                keys,
                step,
            },
        )
}

fn scene_text(objects: &[Obj], lamp_parent: Option<usize>, lamp: [f32; 3], kd: f32) -> String {
    let mut s = format!(
        "[ambient]\nintensity = {}\n[materials.m0]\nkd = {}\n[materials.m1]\nks = 0.5\nshininess = 20\n",
        n(kd / 10.0),
        n(kd)
    );
    s.push_str(&format!(
        "[[lights]]\nname = \"lamp\"\ntype = \"point\"\nposition = {}\nintensity = 1\n",
        v(lamp)
    ));
    if let (Some(p), false) = (lamp_parent, objects.is_empty()) {
        s.push_str(&format!("parent = \"o{}\"\n", p % objects.len()));
        s.push_str("bob = { amplitude = 0.5, period_s = 2 }\n");
    }
    for (i, o) in objects.iter().enumerate() {
        let shape = match o.shape {
            0 => "{ shape = \"cube\", half_size = 0.5 }",
            1 => "{ shape = \"sphere\", segments = 8, rings = 4 }",
            _ => "{ shape = \"torus\", segments = 8, sides = 4 }",
        };
        s.push_str(&format!(
            "[[objects]]\nname = \"o{i}\"\nprimitive = {shape}\nmaterial = \"{}\"\n",
            ["m0", "m1", "default"][usize::from(o.material)]
        ));
        s.push_str(&format!(
            "transform = {{ translate = {}, rotate_deg = {}, scale = {} }}\n",
            v(o.t),
            v(o.r),
            n(o.s)
        ));
        // Parents come earlier in the file, so generated hierarchies never loop.
        if let Some(p) = o.parent.filter(|_| i > 0) {
            s.push_str(&format!("parent = \"o{}\"\n", p % i));
        }
        if let Some(d) = o.spin {
            s.push_str(&format!(
                "spin = {{ axis = [0, 1, 1], deg_per_s = {} }}\n",
                n(d)
            ));
        }
        if let Some((a, p)) = o.bob {
            s.push_str(&format!(
                "bob = {{ amplitude = {}, period_s = {} }}\n",
                n(a),
                n(p)
            ));
        }
        if let Some(keys) = &o.keys {
            let mut t = 0.0f32;
            let (times, values): (Vec<String>, Vec<String>) = keys
                .iter()
                .map(|(dt, x)| {
                    t += dt;
                    (n(t), v(*x))
                })
                .unzip();
            s.push_str(&format!(
                "[objects.animation.translation]\ntimes = [{}]\nvalues = [{}]\ninterpolation = \"{}\"\n",
                times.join(", "),
                values.join(", "),
                if o.step { "step" } else { "linear" }
            ));
        }
    }
    s
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn generated_scenes_load_save_and_load_to_the_same_world(
        objects in proptest::collection::vec(obj(), 0..6),
        lamp_parent in proptest::option::of(0usize..8),
        lamp in [-10.0f32..10.0, -10.0f32..10.0, -10.0f32..10.0],
        kd in 0.0f32..1.0,
    ) {
        let text = scene_text(&objects, lamp_parent, lamp, kd);
        let (a, b, saved) = round_trip(&text, Path::new(""));
        prop_assert_eq!(describe(&a), describe(&b), "{}", text);
        prop_assert_eq!(scene_to_toml(&b), saved);
    }
}
