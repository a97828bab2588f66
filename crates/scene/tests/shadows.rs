//! Shadows in the frame plan: a map only where a caster can darken a visible receiver, the
//! same bytes as shadows off when none is made, the fields saved and loaded, the default
//! scene's contact shadows, and the same picture for any thread count.

#![allow(clippy::unwrap_used)]

use std::path::Path;

use phosphor_raster::{Encoding, Framebuffer};
use phosphor_scene::{
    Disk, FrameOptions, Scene, parse_scene, plan::plan_frame, render_frame, scene_to_toml,
};

/// A scene of `objects` (TOML `[[objects]]` blocks) under one light `light` (a `[[lights]]`
/// block's body) with shadows on.
fn scene(light: &str, objects: &str) -> Scene {
    let text = format!(
        r#"
[render]
width = 160
height = 120
encoding = "linear"
[camera]
eye = [0.0, 3.0, 6.0]
target = [0.0, 0.0, 0.0]
[ambient]
intensity = [0.2, 0.2, 0.2]
[[lights]]
name = "sun"
shadows = true
intensity = [1.0, 1.0, 1.0]
{light}
[materials.m]
kd = [0.8, 0.8, 0.8]
ks = [0.3, 0.3, 0.3]
shininess = 20
{objects}
"#
    );
    parse_scene(&text, "test.toml", Path::new("."), &Disk).unwrap()
}

const DOWN: &str = r#"type = "directional"
direction = [0.2, -1.0, 0.1]"#;

const BALL: &str = r#"
[[objects]]
name = "ball"
primitive = { shape = "sphere", radius = 0.6, segments = 32, rings = 16 }
material = "m"
transform = { translate = [0.0, 0.4, 0.0] }"#;

const FLOOR: &str = r#"
[[objects]]
name = "floor"
primitive = { shape = "plane", half_size = 3.0, subdivisions = 4 }
material = "m"
transform = { translate = [0.0, -0.5, 0.0] }"#;

fn bytes(scene: &Scene, shadows: Option<bool>, threads: usize) -> Vec<u8> {
    let mut fb = Framebuffer::new(160, 120).unwrap();
    let opts = FrameOptions {
        threads,
        shadows,
        ..FrameOptions::default()
    };
    render_frame(scene, &mut fb, &opts);
    fb.to_rgb8(Encoding::Linear)
}

fn plan_text(scene: &Scene, shadows: Option<bool>) -> (usize, String) {
    let opts = FrameOptions {
        shadows,
        ..FrameOptions::default()
    };
    let plan = plan_frame(scene, &scene.camera(), (160, 120), &opts);
    (plan.shadows.maps.len(), plan.to_string())
}

#[test]
fn a_convex_object_over_nothing_gets_no_map_and_the_same_bytes() {
    let s = scene(DOWN, BALL);
    let (maps, text) = plan_text(&s, None);
    assert_eq!(maps, 0, "{text}");
    assert!(
        text.contains("no shadow map for sun: no caster can stand between"),
        "{text}"
    );
    assert!(bytes(&s, None, 2) == bytes(&s, Some(false), 2));
}

#[test]
fn a_light_behind_every_receiver_gets_no_map() {
    // A shelf over a floor, both facing up, lit from below: the light is behind both.
    let shelf = r#"
[[objects]]
name = "shelf"
primitive = { shape = "plane", half_size = 0.5 }
material = "m"
transform = { translate = [0.0, 1.0, 0.0] }"#;
    let up = r#"type = "directional"
direction = [0.1, 1.0, 0.0]"#;
    let s = scene(up, &format!("{shelf}{FLOOR}"));
    let (maps, text) = plan_text(&s, None);
    assert_eq!(maps, 0, "{text}");
    assert!(
        text.contains("no shadow map for sun: it reaches no visible receiver"),
        "{text}"
    );
    assert!(bytes(&s, None, 2) == bytes(&s, Some(false), 2));
    // Lit from above, the shelf casts on the floor.
    let s = scene(DOWN, &format!("{shelf}{FLOOR}"));
    let (maps, text) = plan_text(&s, None);
    assert_eq!(maps, 1, "{text}");
}

#[test]
fn a_ball_over_a_floor_casts_and_the_flag_overrides() {
    let s = scene(DOWN, &format!("{BALL}{FLOOR}"));
    let (maps, text) = plan_text(&s, None);
    assert_eq!(maps, 1, "{text}");
    assert!(text.contains("shadow map of sun: "), "{text}");
    // Bounding spheres are conservative: the floor's may reach above the ball along a
    // slanted light, so it may be listed as a caster too; the ball always is.
    assert!(text.contains("casters: ball"), "{text}");
    assert_eq!(plan_text(&s, Some(false)).0, 0);
    let on = bytes(&s, None, 1);
    let off = bytes(&s, Some(false), 1);
    assert!(on != off);
    // The shadow only darkens: no channel of any pixel is brighter with it.
    assert!(on.iter().zip(&off).all(|(a, b)| a <= b));
    // The floor point straight below the ball along the light is darker than with no shadow.
    let darker = on.iter().zip(&off).filter(|(a, b)| a < b).count();
    assert!(darker > 300, "{darker} channels darkened");
    // The same picture for any thread count.
    for threads in [2, 3, 4] {
        assert!(bytes(&s, None, threads) == on, "{threads} threads");
    }
}

#[test]
fn receive_and_cast_flags_turn_the_map_off() {
    // The floor casts nothing here, so the ball is the one caster.
    let floor = FLOOR.replace("material = \"m\"", "material = \"m\"\ncast_shadows = false");
    let s = scene(DOWN, &format!("{BALL}{floor}"));
    let (maps, text) = plan_text(&s, None);
    assert_eq!(maps, 1, "{text}");
    assert!(text.contains("casters: ball; receivers: floor"), "{text}");
    let not_receiving = floor.replace(
        "cast_shadows = false",
        "cast_shadows = false\nreceive_shadows = false",
    );
    let s = scene(DOWN, &format!("{BALL}{not_receiving}"));
    assert_eq!(plan_text(&s, None).0, 0);
    let ball_off = BALL.replace("material = \"m\"", "material = \"m\"\ncast_shadows = false");
    let s = scene(DOWN, &format!("{ball_off}{floor}"));
    let (maps, text) = plan_text(&s, None);
    assert_eq!(maps, 0, "{text}");
    assert!(bytes(&s, None, 2) == bytes(&s, Some(false), 2));
}

#[test]
fn shadow_fields_survive_save_and_load() {
    let floor_off = FLOOR.replace(
        "material = \"m\"",
        "material = \"m\"\nreceive_shadows = false",
    );
    let mut s = scene(DOWN, &format!("{BALL}{floor_off}"));
    s.settings.shadow_size = 512;
    let text = scene_to_toml(&s);
    assert!(text.contains("shadows = true"), "{text}");
    assert!(text.contains("receive_shadows = false"), "{text}");
    assert!(text.contains("shadow_size = 512"), "{text}");
    let back = parse_scene(&text, "saved.toml", Path::new("."), &Disk).unwrap();
    assert_eq!(scene_to_toml(&back), text);
}

#[test]
fn bad_shadow_values_are_errors_naming_the_field() {
    let bad = |text: &str| {
        parse_scene(text, "bad.toml", Path::new("."), &Disk)
            .unwrap_err()
            .to_string()
    };
    let e = bad("[render]\nshadow_size = 5\n");
    assert!(e.contains("shadow_size"), "{e}");
    let e = bad(
        "[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = [1, 1, 1]\nshadows = 3\n",
    );
    assert!(e.contains("shadows"), "{e}");
    let e = bad(&format!("{BALL}\ncast_shadows = \"yes\"\n")
        .replace("[[objects]]", "[materials.m]\nkd = [1, 1, 1]\n[[objects]]"));
    assert!(e.contains("cast_shadows"), "{e}");
}

#[test]
fn the_default_scene_makes_its_key_lights_map() {
    let s = Scene::default_scene().unwrap();
    let plan = plan_frame(&s, &s.camera(), (320, 180), &FrameOptions::default());
    assert_eq!(plan.shadows.maps.len(), 1, "{plan}");
    let text = plan.to_string();
    assert!(text.contains("shadow map of key: "), "{text}");
    assert!(text.contains("perspective view"), "{text}");
}

#[test]
fn the_map_side_is_a_texel_per_two_pixels_of_the_largest_receiver() {
    use phosphor_raster::Camera;
    use phosphor_raster::shadow::Sphere;
    use phosphor_scene::shadows::{MAX_AUTO_SIZE, MIN_AUTO_SIZE, auto_size};
    let camera = Camera::s1();
    let viewport = (1280, 720);
    // A sphere `pixels` across on screen at S1's distance of 3 (an estimate, as the rule's).
    let half_height = 3.0 * (camera.fov_y_deg.to_radians() * 0.5).tan();
    let across = |pixels: f32| Sphere {
        center: phosphor_math::glam::Vec3::ZERO,
        radius: pixels / 720.0 * half_height,
    };
    let side = |pixels: f32| auto_size(&[across(pixels)], &camera, viewport);
    // 700 px: 350 texels, nearer 256 than 512 in ratio (362 is the middle).
    assert_eq!(side(700.0), 256);
    assert_eq!(side(760.0), 512);
    // The picture's width bounds the footprint: 1280 px, 640 texels, gives 512, not 1024.
    assert_eq!(side(5000.0), 512);
    assert_eq!(
        auto_size(&[across(5000.0)], &camera, (3840, 2160)),
        MAX_AUTO_SIZE
    );
    assert_eq!(side(10.0), MIN_AUTO_SIZE);
    // No receiver, or one whose size is not finite: the smallest side.
    assert_eq!(auto_size(&[], &camera, viewport), MIN_AUTO_SIZE);
    let nan = Sphere {
        center: phosphor_math::glam::Vec3::ZERO,
        radius: f32::NAN,
    };
    assert_eq!(auto_size(&[nan], &camera, viewport), MIN_AUTO_SIZE);
}

#[test]
fn a_point_light_ringed_by_casters_gets_a_cube_map() {
    // Four balls around a bulb over a floor: no single cone of 60 degrees holds them.
    let bulb = r#"type = "point"
position = [0.0, 1.0, 0.0]"#;
    let ring: String = [[1.5, 0.0], [-1.5, 0.0], [0.0, 1.5], [0.0, -1.5]]
        .iter()
        .enumerate()
        .map(|(i, [x, z])| {
            format!(
                "\n[[objects]]\nname = \"ball{i}\"\nprimitive = {{ shape = \"sphere\", radius = 0.4, segments = 24, rings = 12 }}\nmaterial = \"m\"\ntransform = {{ translate = [{x}, 0.3, {z}] }}\n"
            )
        })
        .collect();
    let s = scene(bulb, &format!("{ring}{FLOOR}"));
    let (maps, text) = plan_text(&s, None);
    assert!(maps >= 4, "{text}");
    assert!(text.contains("cube face -y"), "{text}");
    for face in ["+x", "-x", "+z", "-z"] {
        assert!(
            text.contains(&format!("cube face {face}")),
            "{face}: {text}"
        );
    }
    let on = bytes(&s, None, 1);
    let off = bytes(&s, Some(false), 1);
    // The shadows only darken, and they darken some of the floor.
    assert!(on.iter().zip(&off).all(|(a, b)| a <= b));
    let darker = on.iter().zip(&off).filter(|(a, b)| a < b).count();
    assert!(darker > 400, "{darker} channels darkened");
    for threads in [2, 3] {
        assert!(bytes(&s, None, threads) == on, "{threads} threads");
    }
}

#[test]
fn a_cube_makes_no_face_that_only_flat_objects_reach() {
    // A bulb over a floor, a wall behind reaching above the bulb and below the floor, and a
    // ball beside the bulb. The floor and the wall can shadow each other where the wall
    // passes under the floor, so both are casters; but only the wall reaches the upward face,
    // and it cannot shadow itself: no caster can darken a receiver through that face.
    let bulb = r#"type = "point"
position = [0.0, 1.0, 0.0]"#;
    let objects = format!(
        "{FLOOR}
[[objects]]
name = \"wall\"
primitive = {{ shape = \"plane\", half_size = 4.0, subdivisions = 4 }}
material = \"m\"
transform = {{ translate = [0.0, 1.5, -2.5], rotate_deg = [90, 0, 0] }}

[[objects]]
name = \"ball\"
primitive = {{ shape = \"sphere\", radius = 0.4, segments = 24, rings = 12 }}
material = \"m\"
transform = {{ translate = [1.5, 0.3, 0.0] }}
"
    );
    let s = scene(bulb, &objects);
    let (maps, text) = plan_text(&s, None);
    assert!(maps >= 1, "{text}");
    assert!(!text.contains("cube face +y"), "{text}");
    assert!(text.contains("cube face +x"), "{text}");
    // The ball's shadow still falls on the floor.
    let on = bytes(&s, None, 1);
    let off = bytes(&s, Some(false), 1);
    let darker = on.iter().zip(&off).filter(|(a, b)| a < b).count();
    assert!(darker > 100, "{darker} channels darkened");
}

/// `scene` drawn in `mode` with shadows on or off, at 480x360.
fn bytes_in(
    scene: &Scene,
    mode: phosphor_raster::ShadingMode,
    shadows: bool,
    threads: usize,
) -> Vec<u8> {
    let mut fb = Framebuffer::new(480, 360).unwrap();
    let opts = FrameOptions {
        threads,
        shadows: Some(shadows),
        shading: Some(phosphor_scene::ShadingChoice::Mode(mode)),
        ..FrameOptions::default()
    };
    render_frame(scene, &mut fb, &opts);
    fb.to_rgb8(Encoding::Linear)
}

#[test]
fn reference_traces_exact_shadow_rays_that_the_maps_follow() {
    use phosphor_raster::ShadingMode::{Phong, Reference};
    // A ball over a floor under the sun, and a bulb ringed by balls (a cube map).
    let bulb = r#"type = "point"
position = [0.0, 1.0, 0.0]"#;
    let ring = r#"
[[objects]]
name = "a"
primitive = { shape = "sphere", radius = 0.4, segments = 24, rings = 12 }
material = "m"
transform = { translate = [1.5, 0.3, 0.0] }
[[objects]]
name = "b"
primitive = { shape = "sphere", radius = 0.4, segments = 24, rings = 12 }
material = "m"
transform = { translate = [-1.5, 0.3, 0.0] }
[[objects]]
name = "c"
primitive = { shape = "sphere", radius = 0.4, segments = 24, rings = 12 }
material = "m"
transform = { translate = [0.0, 0.3, -1.5] }"#;
    for s in [
        scene(DOWN, &format!("{BALL}{FLOOR}")),
        scene(bulb, &format!("{ring}{FLOOR}")),
    ] {
        let rays = bytes_in(&s, Reference, true, 1);
        let unshadowed = bytes_in(&s, Reference, false, 1);
        let maps = bytes_in(&s, Phong, true, 1);
        // The rays only darken, and darken a good part of the floor.
        assert!(rays.iter().zip(&unshadowed).all(|(a, b)| a <= b));
        let dark = rays.iter().zip(&unshadowed).filter(|(a, b)| a < b).count();
        assert!(dark > 3000, "{dark} channels darkened");
        // The maps agree with the rays but along the shadows' edges (their filtered
        // penumbra, three texels of the 256-texel maps each way, under 8 pixels here): every
        // pixel off by more than 2 codes lies within 8 pixels of a pixel whose ray-traced
        // shadow state differs from its own.
        let (w, h) = (480usize, 360usize);
        let dark_at = |x: usize, y: usize| {
            let i = 3 * (y * w + x);
            (0..3).any(|c| rays[i + c] < unshadowed[i + c])
        };
        let near_edge = |x: usize, y: usize| {
            let here = dark_at(x, y);
            let (x0, y0) = (x.saturating_sub(8), y.saturating_sub(8));
            (y0..(y + 9).min(h)).any(|v| (x0..(x + 9).min(w)).any(|u| dark_at(u, v) != here))
        };
        let mut off = 0;
        for y in 0..h {
            for x in 0..w {
                let i = 3 * (y * w + x);
                if (0..3).any(|c| maps[i + c].abs_diff(rays[i + c]) > 2) {
                    off += 1;
                    assert!(near_edge(x, y), "pixel ({x}, {y}) off away from every edge");
                }
            }
        }
        assert!(
            off > 0,
            "the maps' penumbra differs from the hard shadow somewhere"
        );
        // The same picture for any thread count.
        assert!(bytes_in(&s, Reference, true, 3) == rays);
    }
}
