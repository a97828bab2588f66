//! glTF node hierarchies as entities: a glTF file made here (JSON written by hand, a `.bin`
//! buffer or a GLB) with a three-level node chain and an animation, loaded through a scene
//! file and `--mesh`'s S1, checked against hand-composed matrices at and between keys.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use glam::{Mat4, Quat, Vec3};
use phosphor_raster::Framebuffer;
use phosphor_scene::animation::{Time, update};
use phosphor_scene::hierarchy::GlobalTransform;
use phosphor_scene::view::framed_camera;
use phosphor_scene::{
    FrameOptions, MeshRef, Name, Scene, Transform, plan_frame, render_frame, scene_to_toml,
};

fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "phosphor-scene-gltf-nodes-{test}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A glTF buffer being filled: float data appended as buffer views and accessors.
#[derive(Default)]
struct Buffer {
    bytes: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Buffer {
    /// Appends `data` as one accessor of `kind` (`SCALAR`, `VEC3`, `VEC4`); its index.
    fn add(&mut self, kind: &str, data: &[f32]) -> usize {
        let width = match kind {
            "SCALAR" => 1,
            "VEC3" => 3,
            _ => 4,
        };
        let offset = self.bytes.len();
        for x in data {
            self.bytes.extend_from_slice(&x.to_le_bytes());
        }
        let len = self.bytes.len() - offset;
        self.views.push(format!(
            "{{\"buffer\":0,\"byteOffset\":{offset},\"byteLength\":{len}}}"
        ));
        let count = data.len() / width;
        let mut bounds = String::new();
        if kind != "VEC4" {
            // POSITION and animation inputs need min and max.
            let (mut lo, mut hi) = (vec![f32::MAX; width], vec![f32::MIN; width]);
            for e in data.chunks(width) {
                for k in 0..width {
                    lo[k] = lo[k].min(e[k]);
                    hi[k] = hi[k].max(e[k]);
                }
            }
            let list = |v: &[f32]| {
                v.iter()
                    .map(|x| {
                        if x.is_finite() {
                            x.to_string()
                        } else {
                            "0".into()
                        }
                    })
                    .collect::<Vec<_>>()
                    .join(",")
            };
            bounds = format!(",\"min\":[{}],\"max\":[{}]", list(&lo), list(&hi));
        }
        self.accessors.push(format!(
            "{{\"bufferView\":{},\"componentType\":5126,\"count\":{count},\"type\":\"{kind}\"{bounds}}}",
            self.views.len() - 1
        ));
        self.accessors.len() - 1
    }
}

fn quat_json(q: Quat) -> String {
    format!("[{},{},{},{}]", q.x, q.y, q.z, q.w)
}

fn y30() -> Quat {
    Quat::from_rotation_y(30f32.to_radians())
}

/// The hand's own matrix, given as a glTF `matrix`.
fn hand_matrix() -> Mat4 {
    Mat4::from_translation(Vec3::new(0.25, 0.0, 0.0))
        * Mat4::from_rotation_x(45f32.to_radians())
        * Mat4::from_scale(Vec3::new(1.0, 3.0, 1.0))
}

/// What to change in the robot.
#[derive(Default, Clone, Copy)]
struct Twist {
    /// A NaN in the second rotation key.
    nan_key: bool,
    /// Key times 0, 1, 1 (not increasing).
    repeated_time: bool,
    /// `nodes[0].children` names node 9.
    bad_child: bool,
    /// The animation targets node 9.
    bad_target: bool,
    /// The buffer is a file that does not exist.
    missing_buffer: bool,
    /// The rotation accessor claims more keys than its view holds.
    short_view: bool,
    /// The base's translation is a CUBICSPLINE channel.
    cubic: bool,
    /// The first channel names sampler 5.
    bad_sampler: bool,
    /// The first sampler's input is accessor 99.
    bad_input: bool,
}

/// A glTF: `base` (a triangle) -> `joint` (no mesh, its rotation animated) -> `hand` (a
/// triangle, placed by a matrix), and `empty` (no mesh) beside the joint. The base's
/// translation steps through three keys. Returns the JSON (buffer `robot.bin`) and the buffer.
fn robot(t: Twist) -> (String, Vec<u8>) {
    let mut b = Buffer::default();
    let positions = b.add("VEC3", &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let times = b.add(
        "SCALAR",
        if t.repeated_time {
            &[0.0, 1.0, 1.0]
        } else {
            &[0.0, 1.0, 2.0]
        },
    );
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let mut quats = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, s, s, 0.0, 0.0, 1.0, 0.0];
    if t.nan_key {
        quats[4] = f32::NAN;
    }
    let rotations = b.add("VEC4", &quats);
    if t.short_view {
        b.views[rotations] = b.views[rotations].replace("\"byteLength\":48", "\"byteLength\":40");
    }
    let steps = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
    let (translations, interpolation) = if t.cubic {
        // In-tangent, value, out-tangent per key: tangents that are not the values.
        let keyed: Vec<f32> = steps
            .chunks(3)
            .flat_map(|v| [[9.0, 9.0, 9.0], [v[0], v[1], v[2]], [-9.0, -9.0, -9.0]].concat())
            .collect();
        (b.add("VEC3", &keyed), "CUBICSPLINE")
    } else {
        (b.add("VEC3", &steps), "STEP")
    };
    let child = if t.bad_child { 9 } else { 1 };
    let target = if t.bad_target { 9 } else { 1 };
    let sampler = if t.bad_sampler { 5 } else { 0 };
    let input = if t.bad_input { 99 } else { times };
    let uri = if t.missing_buffer {
        "gone.bin"
    } else {
        "robot.bin"
    };
    let json = format!(
        "{{\"asset\":{{\"version\":\"2.0\"}},\"scene\":0,\"scenes\":[{{\"nodes\":[0]}}],\
         \"nodes\":[\
           {{\"name\":\"base\",\"mesh\":0,\"translation\":[1,2,3],\"rotation\":{},\"scale\":[2,2,2],\"children\":[{child},3]}},\
           {{\"name\":\"joint\",\"translation\":[0,1.5,-1],\"children\":[2]}},\
           {{\"name\":\"hand\",\"mesh\":0,\"matrix\":[{}]}},\
           {{\"name\":\"empty\",\"translation\":[5,5,5]}}],\
         \"meshes\":[{{\"name\":\"tri\",\"primitives\":[{{\"attributes\":{{\"POSITION\":{positions}}}}}]}}],\
         \"animations\":[{{\"channels\":[\
             {{\"sampler\":{sampler},\"target\":{{\"node\":{target},\"path\":\"rotation\"}}}},\
             {{\"sampler\":1,\"target\":{{\"node\":0,\"path\":\"translation\"}}}}],\
           \"samplers\":[\
             {{\"input\":{input},\"output\":{rotations},\"interpolation\":\"LINEAR\"}},\
             {{\"input\":{times},\"output\":{translations},\"interpolation\":\"{interpolation}\"}}]}}],\
         \"accessors\":[{}],\"bufferViews\":[{}],\
         \"buffers\":[{{\"byteLength\":{},\"uri\":\"{uri}\"}}]}}",
        quat_json(y30()),
        hand_matrix()
            .to_cols_array()
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(","),
        b.accessors.join(","),
        b.views.join(","),
        b.bytes.len(),
    );
    (json, b.bytes)
}

const SCENE: &str = "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nintensity = 1\n\
                     [[objects]]\nname = \"robot\"\nmesh = \"robot.gltf\"\n\
                     transform = { translate = [0, 0, -5], rotate_deg = [0, 45, 0] }\n";

fn write_robot(dir: &Path, t: Twist) -> PathBuf {
    let (json, bin) = robot(t);
    std::fs::write(dir.join("robot.gltf"), json).unwrap();
    std::fs::write(dir.join("robot.bin"), bin).unwrap();
    std::fs::write(dir.join("s.toml"), SCENE).unwrap();
    dir.join("s.toml")
}

fn entity(scene: &Scene, name: &str) -> hecs::Entity {
    scene
        .world
        .query::<(hecs::Entity, &Name)>()
        .iter()
        .find(|(_, n)| n.0 == name)
        .map(|(e, _)| e)
        .unwrap_or_else(|| panic!("no entity named {name}"))
}

fn global(scene: &Scene, name: &str) -> Mat4 {
    scene
        .world
        .get::<&GlobalTransform>(entity(scene, name))
        .unwrap()
        .0
}

/// The world matrices of base, joint and hand at time `t`, composed by hand.
fn expected(t: f32) -> [Mat4; 3] {
    let object = Mat4::from_translation(Vec3::new(0.0, 0.0, -5.0))
        * Mat4::from_rotation_y(45f32.to_radians());
    let step = if t < 1.0 {
        Vec3::new(1.0, 2.0, 3.0)
    } else if t < 2.0 {
        Vec3::new(4.0, 5.0, 6.0)
    } else {
        Vec3::new(7.0, 8.0, 9.0)
    };
    let base = object
        * Mat4::from_translation(step)
        * Mat4::from_quat(y30())
        * Mat4::from_scale(Vec3::splat(2.0));
    // Keys 0, 90 and 180 degrees about Z at 0, 1 and 2 s: slerp turns evenly between them.
    let angle = 90.0 * t.clamp(0.0, 2.0);
    let joint = base
        * Mat4::from_translation(Vec3::new(0.0, 1.5, -1.0))
        * Mat4::from_rotation_z(angle.to_radians());
    [base, joint, joint * hand_matrix()]
}

fn assert_near(got: Mat4, want: Mat4, what: &str) {
    assert!(got.abs_diff_eq(want, 1e-4), "{what}:\n{got}\nvs\n{want}");
}

#[test]
fn nodes_become_entities_placed_like_hand_composed_matrices() {
    let dir = temp_dir("chain");
    let mut scene = Scene::load(&write_robot(&dir, Twist::default())).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // The two mesh nodes are objects; the joint is transform-only; the empty node is dropped.
    let mut drawn: Vec<String> = scene
        .objects()
        .iter()
        .map(|&e| scene.world.get::<&Name>(e).unwrap().0.clone())
        .collect();
    drawn.sort();
    assert_eq!(drawn, ["robot/base", "robot/hand"]);
    assert!(
        scene
            .world
            .get::<&MeshRef>(entity(&scene, "robot/joint"))
            .is_err()
    );
    assert!(
        !scene
            .world
            .query::<&Name>()
            .iter()
            .any(|n| n.0 == "robot/empty")
    );
    // At the keys (0, 1, 2 s), between them, before the first and after the last.
    for t in [0.0, 0.25, 0.5, 1.0, 1.5, 1.75, 2.0, 3.0, -1.0] {
        update(&mut scene, Time::at(f64::from(t)));
        let [base, joint, hand] = expected(t);
        assert_near(global(&scene, "robot/base"), base, &format!("base at {t}"));
        assert_near(
            global(&scene, "robot/joint"),
            joint,
            &format!("joint at {t}"),
        );
        assert_near(global(&scene, "robot/hand"), hand, &format!("hand at {t}"));
        // The transform the plan draws with is the same matrix.
        for (name, want) in [("robot/base", base), ("robot/hand", hand)] {
            let tr = *scene.world.get::<&Transform>(entity(&scene, name)).unwrap();
            assert!(tr.matrix().abs_diff_eq(want, 1e-3), "{name} at {t}: {tr:?}");
        }
    }
    // The frame plan sees both mesh nodes, where they are.
    update(&mut scene, Time::at(0.5));
    let (centre, radius) = scene.bounding_sphere().unwrap();
    let camera = framed_camera(centre, radius, Vec3::Y, 30.0, 20.0, 45.0, 4.0 / 3.0);
    let plan = plan_frame(&scene, &camera, (64, 48), &FrameOptions::default());
    let mut planned: Vec<(String, Mat4)> = plan
        .objects
        .iter()
        .map(|o| (o.name.clone(), o.model))
        .collect();
    planned.sort_by(|a, b| a.0.cmp(&b.0));
    assert_eq!(planned.len(), 2, "culled: {:?}", plan.culled);
    let [base, _, hand] = expected(0.5);
    assert_eq!(planned[0].0, "robot/base");
    assert!(planned[0].1.abs_diff_eq(base, 1e-3));
    assert_eq!(planned[1].0, "robot/hand");
    assert!(planned[1].1.abs_diff_eq(hand, 1e-3));
    // And the renderer draws both triangles.
    scene.set_camera(camera);
    let mut fb = Framebuffer::new(64, 48).unwrap();
    let report = render_frame(&scene, &mut fb, &FrameOptions::default());
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    assert_eq!(report.stats.triangles_in, 2);
    assert!(report.stats.pixels_shaded > 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_scene_object_moves_the_whole_tree() {
    let dir = temp_dir("root-motion");
    write_robot(&dir, Twist::default());
    let spun = format!("{SCENE}spin = {{ axis = [0, 1, 0], deg_per_s = 90 }}\n");
    std::fs::write(dir.join("s.toml"), spun).unwrap();
    let mut scene = Scene::load(&dir.join("s.toml")).unwrap();
    update(&mut scene, Time::at(0.5));
    // The spin turns the object about its own Y after its rest rotation: 45 + 45 degrees.
    let rest = Mat4::from_translation(Vec3::new(0.0, 0.0, -5.0))
        * Mat4::from_rotation_y(45f32.to_radians());
    let turned = Mat4::from_translation(Vec3::new(0.0, 0.0, -5.0))
        * Mat4::from_rotation_y(90f32.to_radians());
    // The tree below the object is as before, in the turned object's space.
    let [base, _, hand] = expected(0.5).map(|m| turned * rest.inverse() * m);
    assert_near(global(&scene, "robot/base"), base, "base");
    assert_near(global(&scene, "robot/hand"), hand, "hand");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_glb_gives_the_same_world_as_the_gltf() {
    let dir = temp_dir("glb");
    let path = write_robot(&dir, Twist::default());
    let mut want = Scene::load(&path).unwrap();
    let (json, bin) = robot(Twist::default());
    // The GLB's buffer is its binary chunk: no uri.
    let json = json.replace(",\"uri\":\"robot.bin\"", "");
    let pad = |mut v: Vec<u8>, with: u8| {
        while !v.len().is_multiple_of(4) {
            v.push(with);
        }
        v
    };
    let (json, bin) = (pad(json.into_bytes(), b' '), pad(bin, 0));
    let mut glb = b"glTF".to_vec();
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
    glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json);
    glb.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin);
    std::fs::write(dir.join("robot.glb"), glb).unwrap();
    std::fs::remove_file(dir.join("robot.bin")).unwrap();
    std::fs::write(dir.join("s.toml"), SCENE.replace("robot.gltf", "robot.glb")).unwrap();
    let mut got = Scene::load(&path).unwrap();
    assert!(got.warnings.is_empty(), "{:?}", got.warnings);
    for t in [0.5, 1.5] {
        update(&mut want, Time::at(t));
        update(&mut got, Time::at(t));
        for name in ["robot/base", "robot/joint", "robot/hand"] {
            assert_near(global(&got, name), global(&want, name), name);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cubic_spline_channels_play_their_value_keys() {
    let dir = temp_dir("cubic");
    let cubic = Twist {
        cubic: true,
        ..Twist::default()
    };
    let mut scene = Scene::load(&write_robot(&dir, cubic)).unwrap();
    assert!(
        scene.warnings.iter().any(|w| w.contains("CUBICSPLINE")),
        "{:?}",
        scene.warnings
    );
    // At the keys: the values (not the tangents); between: straight between them.
    for (t, at) in [
        (0.0, Vec3::new(1.0, 2.0, 3.0)),
        (1.0, Vec3::new(4.0, 5.0, 6.0)),
        (1.5, Vec3::new(5.5, 6.5, 7.5)),
    ] {
        update(&mut scene, Time::at(t));
        let got = global(&scene, "robot/base");
        let object = Mat4::from_translation(Vec3::new(0.0, 0.0, -5.0))
            * Mat4::from_rotation_y(45f32.to_radians());
        let want = object
            * Mat4::from_translation(at)
            * Mat4::from_quat(y30())
            * Mat4::from_scale(Vec3::splat(2.0));
        assert_near(got, want, &format!("base at {t}"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn saving_writes_the_file_once_and_loads_back_to_the_same_tree() {
    let dir = temp_dir("save");
    let mut scene = Scene::load(&write_robot(&dir, Twist::default())).unwrap();
    let text = scene_to_toml(&scene);
    assert_eq!(text.matches("[[objects]]").count(), 1, "{text}");
    assert!(text.contains("mesh = \"robot.gltf\""), "{text}");
    assert!(!text.contains("robot/"), "{text}");
    std::fs::write(dir.join("saved.toml"), text).unwrap();
    let mut back = Scene::load(&dir.join("saved.toml")).unwrap();
    update(&mut scene, Time::at(1.5));
    update(&mut back, Time::at(1.5));
    for name in ["robot/base", "robot/joint", "robot/hand"] {
        assert_near(global(&back, name), global(&scene, name), name);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn s1_mesh_keeps_the_nodes_and_fits_the_tree_in_the_unit_sphere() {
    let dir = temp_dir("s1");
    write_robot(&dir, Twist::default());
    let scene = Scene::s1_with_mesh(&dir.join("robot.gltf")).unwrap();
    assert_eq!(scene.objects().len(), 2);
    let mut farthest = 0.0f32;
    for e in scene.objects() {
        let m = scene.world.get::<&GlobalTransform>(e).unwrap().0;
        let mesh = scene.world.get::<&MeshRef>(e).unwrap().0.clone();
        for p in &mesh.mesh.positions {
            farthest = farthest.max(m.transform_point3(*p).length());
        }
    }
    // Centred on its bounds: the farthest corner is at 1 (it need not be centred on it).
    assert!(farthest > 0.5 && farthest <= 1.0 + 1e-4, "{farthest}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_gltf_files_are_errors_naming_the_file_and_the_element() {
    let dir = temp_dir("bad");
    for (twist, wants) in [
        (
            Twist {
                nan_key: true,
                ..Twist::default()
            },
            &["animations[0].channels[0]", "not finite"][..],
        ),
        (
            Twist {
                repeated_time: true,
                ..Twist::default()
            },
            &["animations[0].channels[0]", "strictly increasing"][..],
        ),
        (
            Twist {
                bad_child: true,
                ..Twist::default()
            },
            &["nodes[0].children"][..],
        ),
        (
            Twist {
                bad_target: true,
                ..Twist::default()
            },
            &["animations[0].channels[0]"][..],
        ),
        (
            Twist {
                missing_buffer: true,
                ..Twist::default()
            },
            &["gone.bin"][..],
        ),
        (
            Twist {
                short_view: true,
                ..Twist::default()
            },
            &["animations[0].channels[0]", "bufferViews[2]"][..],
        ),
        (
            Twist {
                bad_sampler: true,
                ..Twist::default()
            },
            &["animations[0].channels[0]"][..],
        ),
        (
            Twist {
                bad_input: true,
                ..Twist::default()
            },
            &["animations[0]"][..],
        ),
    ] {
        let path = write_robot(&dir, twist);
        let e = Scene::load(&path).unwrap_err().to_string();
        assert!(e.contains("s.toml: objects[0].mesh: "), "{e}");
        assert!(e.contains("robot.gltf: "), "{e}");
        for w in wants {
            assert!(e.contains(w), "{w}: {e}");
        }
        // The same file through --mesh: the same error, never a panic.
        let e = Scene::s1_with_mesh(&dir.join("robot.gltf"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("robot.gltf: "), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn objects_and_lights_can_hang_from_a_gltf_node() {
    let dir = temp_dir("node-parent");
    write_robot(&dir, Twist::default());
    // A sphere held by the hand, a lamp on the joint; both follow the animated joint.
    let text = format!(
        "{SCENE}\
         [[objects]]\nname = \"ball\"\nparent = \"robot/hand\"\n\
         transform = {{ translate = [0.5, 0, 0] }}\n\
         primitive = {{ shape = \"sphere\", radius = 0.1, segments = 8, rings = 4 }}\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = 1\nparent = \"robot/joint\"\n"
    );
    std::fs::write(dir.join("s.toml"), &text).unwrap();
    let mut scene = Scene::load(&dir.join("s.toml")).unwrap();
    for t in [0.0f32, 0.5, 1.5] {
        update(&mut scene, Time::at(f64::from(t)));
        let [_, joint, hand] = expected(t);
        assert_near(
            global(&scene, "ball"),
            hand * Mat4::from_translation(Vec3::new(0.5, 0.0, 0.0)),
            &format!("ball at {t}"),
        );
        let position = scene
            .lights()
            .into_iter()
            .find_map(|(_, l)| match l.kind {
                phosphor_lighting::LightKind::Point { position } => Some(position),
                _ => None,
            })
            .expect("the lamp");
        let want = joint.transform_point3(Vec3::Y);
        assert!(
            position.abs_diff_eq(want, 1e-4),
            "lamp at {t}: {position} vs {want}"
        );
    }
    // Saved, the child names the node, and loads back to the same world.
    let saved = scene_to_toml(&scene);
    assert!(saved.contains("parent = \"robot/hand\""), "{saved}");
    std::fs::write(dir.join("saved.toml"), saved).unwrap();
    let mut back = Scene::load(&dir.join("saved.toml")).unwrap();
    update(&mut scene, Time::at(0.7));
    update(&mut back, Time::at(0.7));
    assert_near(global(&back, "ball"), global(&scene, "ball"), "ball saved");
    // A name that is no node is an error naming the field and listing what exists.
    std::fs::write(
        dir.join("bad.toml"),
        text.replace("robot/hand", "robot/foot"),
    )
    .unwrap();
    let e = Scene::load(&dir.join("bad.toml")).unwrap_err().to_string();
    assert!(
        e.contains("objects[1].parent") && e.contains("robot/hand"),
        "{e}"
    );
    // The glTF's tree cannot be hung below its own node.
    let looped = text.replace(
        "name = \"robot\"\n",
        "name = \"robot\"\nparent = \"ball\"\n",
    );
    std::fs::write(dir.join("loop.toml"), looped).unwrap();
    let e = Scene::load(&dir.join("loop.toml")).unwrap_err().to_string();
    assert!(e.contains("loop"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
