//! Scene files nest objects in `children = [ { ... } ]` arrays as well as naming a `parent`:
//! the same hierarchy either way, saved in the `parent = "NAME"` form.

#![allow(clippy::unwrap_used)]

use glam::Vec3;
use phosphor_scene::hierarchy::Parent;
use phosphor_scene::{Name, Scene, Transform, scene_to_toml};

const NESTED: &str = r#"
[[lights]]
type = "directional"
direction = [0, 0, -1]
intensity = 1

[[objects]]
name = "table"
primitive = { shape = "cube" }
transform = { translate = [1, 0, 0], rotate_deg = [0, 90, 0] }
children = [
  { name = "cup", primitive = { shape = "sphere", radius = 0.2 }, transform = { translate = [0, 1, 0] }, children = [
    { name = "spoon", primitive = { shape = "cube", half_size = 0.05 }, transform = { translate = [0, 0, 1] } },
  ] },
  { name = "plate", primitive = { shape = "plane" }, transform = { translate = [2, 0, 0] } },
]

[[objects]]
name = "floor"
primitive = { shape = "plane" }
"#;

/// The same scene with `parent = "NAME"`.
const FLAT: &str = r#"
[[lights]]
type = "directional"
direction = [0, 0, -1]
intensity = 1

[[objects]]
name = "table"
primitive = { shape = "cube" }
transform = { translate = [1, 0, 0], rotate_deg = [0, 90, 0] }

[[objects]]
name = "cup"
parent = "table"
primitive = { shape = "sphere", radius = 0.2 }
transform = { translate = [0, 1, 0] }

[[objects]]
name = "spoon"
parent = "cup"
primitive = { shape = "cube", half_size = 0.05 }
transform = { translate = [0, 0, 1] }

[[objects]]
name = "plate"
parent = "table"
primitive = { shape = "plane" }
transform = { translate = [2, 0, 0] }

[[objects]]
name = "floor"
primitive = { shape = "plane" }
"#;

fn world(scene: &Scene) -> Vec<(String, Option<String>, Vec3)> {
    scene
        .objects()
        .into_iter()
        .map(|e| {
            let name = scene.world.get::<&Name>(e).unwrap().0.clone();
            let parent = scene
                .world
                .get::<&Parent>(e)
                .ok()
                .map(|p| scene.world.get::<&Name>(p.0).unwrap().0.clone());
            let at = scene.world.get::<&Transform>(e).unwrap().translate;
            (name, parent, at)
        })
        .collect()
}

#[test]
fn nested_children_are_the_parent_form_written_inside_out() {
    let nested = Scene::parse(NESTED, "nested.toml").unwrap();
    let flat = Scene::parse(FLAT, "flat.toml").unwrap();
    let got = world(&nested);
    let want = world(&flat);
    assert_eq!(got.len(), 5);
    for ((gn, gp, ga), (wn, wp, wa)) in got.iter().zip(&want) {
        assert_eq!((gn, gp), (wn, wp));
        assert!((*ga - *wa).length() < 1e-5, "{gn}: {ga} vs {wa}");
    }
    // The table turns its children by 90 degrees about Y: the spoon's +Z lands on +X.
    let spoon = got.iter().find(|(n, _, _)| n == "spoon").unwrap().2;
    assert!(
        (spoon - Vec3::new(2.0, 1.0, 0.0)).length() < 1e-5,
        "{spoon}"
    );
}

#[test]
fn nested_children_save_as_parent_names_and_load_back() {
    let nested = Scene::parse(NESTED, "nested.toml").unwrap();
    let text = scene_to_toml(&nested);
    assert!(!text.contains("children"), "{text}");
    assert!(text.contains("parent = \"cup\""), "{text}");
    let back = Scene::parse(&text, "saved.toml").unwrap();
    assert_eq!(world(&back), world(&nested));
}

#[test]
fn nested_children_are_checked_like_top_level_objects() {
    let both = NESTED.replace(
        "{ name = \"plate\",",
        "{ name = \"plate\", parent = \"floor\",",
    );
    let e = Scene::parse(&both, "n.toml").unwrap_err().to_string();
    assert!(
        e.starts_with("n.toml: objects[0].children[1].parent: "),
        "{e}"
    );
    let e = Scene::parse(
        "[[objects]]\nprimitive = { shape = \"cube\" }\nchildren = 3\n",
        "n.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("n.toml: objects[0].children: "), "{e}");
    let e = Scene::parse(
        "[[objects]]\nprimitive = { shape = \"cube\" }\nchildren = [{ primitive = { shape = \"cone\" } }]\n",
        "n.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("n.toml: objects[0].children[0].primitive.shape: "),
        "{e}"
    );
}
