//! Automatic back-face culling: the frame plan skips back faces only where that cannot change a
//! pixel, and the pictures with and without it are byte-identical.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use phosphor_raster::{Encoding, Framebuffer, ShadingMode};
use phosphor_scene::{
    CullChoice, FrameOptions, Scene, ShadingChoice, plan::plan_frame, render_frame,
};

fn asset(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// Renders `scene` at `size` with culling `choice` and shading `mode`; returns the 8-bit
/// picture and the triangles the rasterizer drew.
fn picture(
    scene: &mut Scene,
    choice: CullChoice,
    mode: ShadingMode,
    size: (u32, u32),
) -> (Vec<u8>, u64) {
    scene.settings.cull_backfaces = choice;
    let mut fb = Framebuffer::new(size.0, size.1).unwrap();
    let opts = FrameOptions {
        shading: Some(ShadingChoice::Mode(mode)),
        threads: 1,
        ..FrameOptions::default()
    };
    let report = render_frame(scene, &mut fb, &opts);
    (fb.to_rgb8(Encoding::Linear), report.stats.triangles_drawn)
}

#[test]
fn culled_s1_bunny_is_byte_identical_and_draws_fewer_triangles() {
    let mut scene = Scene::load(&asset("assets/scenes/s1.toml")).unwrap();
    let plan = plan_frame(
        &scene,
        &scene.camera(),
        (480, 270),
        &FrameOptions::default(),
    );
    assert!(plan.objects[0].cull_backfaces, "{}", plan);
    assert!(plan.to_string().contains("back faces: culled"), "{plan}");
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        let (both, drawn_both) = picture(&mut scene, CullChoice::Never, mode, (480, 270));
        let (culled, drawn_culled) = picture(&mut scene, CullChoice::Auto, mode, (480, 270));
        assert!(both == culled, "{mode}: culling changed the picture");
        assert!(
            drawn_culled * 10 < drawn_both * 6,
            "{mode}: {drawn_culled} of {drawn_both} triangles drawn"
        );
    }
}

#[test]
fn culled_default_scene_and_s1_sphere_are_byte_identical() {
    for (scene, size) in [
        (Scene::default_scene().unwrap(), (320, 180)),
        (
            Scene::load(&asset("assets/scenes/s1-sphere.toml")).unwrap(),
            (320, 180),
        ),
    ] {
        let mut scene = scene;
        for mode in [
            ShadingMode::Gouraud,
            ShadingMode::Phong,
            ShadingMode::FastPhong,
        ] {
            let (both, _) = picture(&mut scene, CullChoice::Never, mode, size);
            let (culled, _) = picture(&mut scene, CullChoice::Auto, mode, size);
            assert!(both == culled, "{mode}: culling changed the picture");
        }
    }
}

fn one_object_scene(object: &str, camera: &str) -> Scene {
    let text = format!(
        "{camera}\n[ambient]\nintensity = [0.1, 0.1, 0.1]\n\
         [[lights]]\ntype = \"point\"\nposition = [2, 2, 2]\nintensity = [1, 1, 1]\n\
         [materials.m]\nkd = [0.8, 0.6, 0.4]\n\
         [[objects]]\nmaterial = \"m\"\n{object}\n"
    );
    Scene::parse(&text, "t.toml").unwrap()
}

fn culled(scene: &Scene) -> (bool, &'static str) {
    let plan = plan_frame(scene, &scene.camera(), (64, 48), &FrameOptions::default());
    (plan.objects[0].cull_backfaces, plan.objects[0].cull_reason)
}

#[test]
fn auto_keeps_back_faces_where_they_can_be_seen() {
    let sphere = "primitive = { shape = \"sphere\", radius = 1.0, segments = 32, rings = 16 }";
    let outside = "[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]";
    assert!(culled(&one_object_scene(sphere, outside)).0);
    // The eye inside the solid sees its inside: back faces.
    let inside = "[camera]\neye = [0, 0, 0.5]\ntarget = [0, 0, -1]";
    let (cull, why) = culled(&one_object_scene(sphere, inside));
    assert!(!cull, "{why}");
    // The near plane cuts the solid: its inside shows through the cut.
    let grazing = "[camera]\neye = [0, 0, 1.05]\ntarget = [0, 0, 0]\nnear = 0.1";
    assert!(!culled(&one_object_scene(sphere, grazing)).0);
    // An open surface shows its back.
    let plane = "primitive = { shape = \"plane\", half_size = 1.0, subdivisions = 2 }";
    assert!(!culled(&one_object_scene(plane, outside)).0);
    // A mirroring transform turns the winding over.
    let mirrored = format!("{sphere}\ntransform = {{ scale = [-1, 1, 1] }}");
    let (cull, why) = culled(&one_object_scene(&mirrored, outside));
    assert!(!cull, "{why}");
}

#[test]
fn an_open_mesh_seen_from_behind_keeps_its_pixels_under_auto() {
    // A plane seen from below: `always` culls it away, `auto` draws it as `never` does.
    let plane = "primitive = { shape = \"plane\", half_size = 1.0, subdivisions = 2 }";
    let below = "[camera]\neye = [0, -3, 0.01]\ntarget = [0, 0, 0]";
    let mut scene = one_object_scene(plane, below);
    let (never, _) = picture(&mut scene, CullChoice::Never, ShadingMode::Phong, (64, 48));
    let (auto, _) = picture(&mut scene, CullChoice::Auto, ShadingMode::Phong, (64, 48));
    let (always, _) = picture(&mut scene, CullChoice::Always, ShadingMode::Phong, (64, 48));
    assert!(never == auto);
    assert!(
        never.iter().any(|&b| b > 0),
        "the plane is visible from below"
    );
    assert!(
        always.iter().all(|&b| b == 0),
        "always culls the plane's back"
    );
}

#[test]
fn scene_files_name_the_culling_choice() {
    let scene = Scene::parse("[render]\ncull_backfaces = \"auto\"\n", "t.toml").unwrap();
    assert_eq!(scene.settings.cull_backfaces, CullChoice::Auto);
    let scene = Scene::parse("[render]\ncull_backfaces = true\n", "t.toml").unwrap();
    assert_eq!(scene.settings.cull_backfaces, CullChoice::Always);
    let scene = Scene::parse("[render]\ncull_backfaces = false\n", "t.toml").unwrap();
    assert_eq!(scene.settings.cull_backfaces, CullChoice::Never);
    let err = Scene::parse("[render]\ncull_backfaces = \"some\"\n", "t.toml")
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("render.cull_backfaces"), "{err}");
}
