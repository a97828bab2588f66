//! Any scene text gives a scene or an error naming the file, never a panic; and any scene that
//! loads renders to finite pixels in [0, 1].

#![allow(clippy::unwrap_used)]

use phosphor_raster::Framebuffer;
use phosphor_scene::{FrameOptions, Scene, render_frame};
use proptest::prelude::*;

/// Values that probe the checks: odd numbers, wrong types, wrong lengths.
fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("0".to_owned()),
        Just("-1".to_owned()),
        Just("1e39".to_owned()),
        Just("nan".to_owned()),
        Just("inf".to_owned()),
        Just("1e-40".to_owned()),
        Just("\"sphere\"".to_owned()),
        Just("\"point\"".to_owned()),
        Just("\"phong\"".to_owned()),
        Just("true".to_owned()),
        Just("[1, 2]".to_owned()),
        Just("[0, 0, 0]".to_owned()),
        Just("[1e30, -1e30, 0]".to_owned()),
        Just("{ shape = \"sphere\", segments = 3, rings = 2 }".to_owned()),
        Just("{ model = \"inverse-square\" }".to_owned()),
        Just("{ procedural = \"ripples\", scale = 1e9 }".to_owned()),
        (-1e3f64..1e3).prop_map(|x| format!("{x}")),
        prop::collection::vec(-10.0f64..10.0, 3)
            .prop_map(|v| format!("[{}, {}, {}]", v[0], v[1], v[2])),
    ]
}

fn key() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "type",
        "position",
        "direction",
        "intensity",
        "attenuation",
        "inner_deg",
        "outer_deg",
        "start",
        "end",
        "samples",
        "eye",
        "target",
        "up",
        "fov_y_deg",
        "near",
        "far",
        "ka",
        "kd",
        "ks",
        "shininess",
        "bump",
        "fresnel",
        "primitive",
        "material",
        "transform",
        "width",
        "height",
        "shading",
        "mesh",
    ])
}

fn table_header() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "[render]",
        "[camera]",
        "[ambient]",
        "[[lights]]",
        "[materials.m]",
        "[[objects]]",
    ])
}

fn scene_text() -> impl Strategy<Value = String> {
    prop::collection::vec(
        (
            table_header(),
            prop::collection::vec((key(), value()), 0..5),
        ),
        0..6,
    )
    .prop_map(|tables| {
        let mut s = String::new();
        for (h, kv) in tables {
            s.push_str(h);
            s.push('\n');
            let mut seen = std::collections::HashSet::new();
            for (k, v) in kv {
                if seen.insert(k) {
                    s.push_str(&format!("{k} = {v}\n"));
                }
            }
        }
        s
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn scene_text_never_panics_and_errors_name_the_file(text in scene_text()) {
        match Scene::parse(&text, "fuzz.toml") {
            Err(e) => prop_assert!(e.to_string().starts_with("fuzz.toml"), "{e}"),
            Ok(scene) => {
                let mut fb = Framebuffer::new(24, 16).unwrap();
                render_frame(&scene, &mut fb, &FrameOptions { threads: 1, ..FrameOptions::default() });
                prop_assert!(fb.color().iter().all(|c| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0));
            }
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        let text = String::from_utf8_lossy(&bytes);
        if let Err(e) = Scene::parse(&text, "bytes.toml") {
            prop_assert!(e.to_string().starts_with("bytes.toml"));
        }
    }
}

/// The generator must reach the renderer, or the first property would test parsing only.
#[test]
fn generated_scenes_sometimes_load() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let loaded = (0..400)
        .filter(|_| {
            let text = scene_text().new_tree(&mut runner).unwrap().current();
            Scene::parse(&text, "fuzz.toml").is_ok()
        })
        .count();
    assert!(loaded >= 20, "only {loaded} of 400 generated scenes loaded");
}
