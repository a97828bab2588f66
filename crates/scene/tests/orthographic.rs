//! Orthographic cameras and the standard views: a scene file's `projection` and
//! `ortho_height` are read, checked by field and written back; an orthographic picture keeps
//! an object's size at every distance; perspective stays the default, drawn as before; and a
//! scene without lights says so.

#![allow(clippy::unwrap_used)]

use glam::Vec3;
use phosphor_raster::{Camera, Framebuffer, Projection, ShadingMode};
use phosphor_scene::{FrameOptions, Scene, ShadingChoice, render_frame, scene_to_toml};

fn err(text: &str) -> String {
    Scene::parse(text, "t.toml").unwrap_err().to_string()
}

#[test]
fn projection_and_ortho_height_are_read_and_checked_by_field() {
    let s = Scene::parse(
        "[camera]\nprojection = \"orthographic\"\northo_height = 2.5\n",
        "t.toml",
    )
    .unwrap();
    assert_eq!(
        s.camera().projection,
        Projection::Orthographic { height: 2.5 }
    );
    // Without a height: what the perspective view spans at the target (S1: 3 units away).
    let s = Scene::parse("[camera]\nprojection = \"orthographic\"\n", "t.toml").unwrap();
    let Projection::Orthographic { height } = s.camera().projection else {
        panic!("not orthographic");
    };
    assert!((height - 6.0 * 22.5f32.to_radians().tan()).abs() < 1e-5);
    assert_eq!(
        Scene::parse("", "t.toml").unwrap().camera().projection,
        Projection::Perspective
    );
    assert_eq!(
        err("[camera]\nprojection = \"fisheye\"\n"),
        "t.toml: camera.projection: unknown value \"fisheye\" (expected \"perspective\", \"orthographic\")"
    );
    assert_eq!(
        err("[camera]\northo_height = 2\n"),
        "t.toml: camera.ortho_height: applies to projection = \"orthographic\" only"
    );
    assert_eq!(
        err("[camera]\nprojection = \"orthographic\"\northo_height = 0\n"),
        "t.toml: camera.ortho_height: must be > 0, got 0"
    );
}

#[test]
fn an_orthographic_scene_saves_and_loads_back_the_same_camera() {
    let text = "[camera]\neye = [1, 2, 3]\nprojection = \"orthographic\"\northo_height = 1.75\n";
    let scene = Scene::parse(text, "t.toml").unwrap();
    let saved = scene_to_toml(&scene);
    let again = Scene::parse(&saved, "saved.toml").unwrap();
    assert_eq!(again.camera(), scene.camera(), "{saved}");
}

/// Pixels covered (not the clear colour) in a 64x64 frame of a unit sphere seen from `eye`.
fn covered(camera: Camera) -> usize {
    let mut scene = Scene::parse(
        "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nintensity = 1\n\
         [[objects]]\nprimitive = { shape = \"sphere\", radius = 1.0 }\n",
        "t.toml",
    )
    .unwrap();
    scene.set_camera(camera);
    let mut fb = Framebuffer::new(64, 64).unwrap();
    let opts = FrameOptions {
        shading: Some(ShadingChoice::Mode(ShadingMode::Flat)),
        ..FrameOptions::default()
    };
    render_frame(&scene, &mut fb, &opts);
    let clear = fb.color()[0];
    fb.color().iter().filter(|c| **c != clear).count()
}

#[test]
fn an_orthographic_view_keeps_sizes_whatever_the_distance() {
    let at = |distance: f32, projection| Camera {
        eye: Vec3::new(0.0, 0.0, distance),
        far: 100.0,
        projection,
        ..Camera::s1()
    };
    let ortho = Projection::Orthographic { height: 4.0 };
    let (near, far) = (covered(at(3.0, ortho)), covered(at(30.0, ortho)));
    // The unit sphere spans half of a 4-unit view: a disc of radius 16 px, about 804 px.
    assert!((near as f32 - 804.0).abs() < 40.0, "{near}");
    assert_eq!(near, far);
    let persp = Projection::Perspective;
    assert!(covered(at(3.0, persp)) > 4 * covered(at(30.0, persp)));
}

#[test]
fn a_scene_with_objects_and_no_lights_warns_once() {
    let s = Scene::parse(
        "[[objects]]\nprimitive = { shape = \"cube\", half_size = 1.0 }\n",
        "dark.toml",
    )
    .unwrap();
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    assert!(
        s.warnings[0].starts_with("warning: dark.toml: lights: none,"),
        "{}",
        s.warnings[0]
    );
    assert!(s.warnings[0].contains("black"), "{}", s.warnings[0]);
    let lit_by_ambient = Scene::parse(
        "[ambient]\nintensity = 0.2\n[[objects]]\nprimitive = { shape = \"cube\", half_size = 1.0 }\n",
        "t.toml",
    )
    .unwrap();
    assert!(!lit_by_ambient.warnings[0].contains("black"));
    // Nothing to light, nothing to say.
    assert!(Scene::parse("", "t.toml").unwrap().warnings.is_empty());
}
