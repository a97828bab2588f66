//! Unit tests of the scene crate: scene files (every validation rule names its field), the
//! save/load round trip, the frame plan (lights dropped only where they add exactly nothing,
//! auto's choices), and the planned picture against the full kernel.

#![allow(clippy::unwrap_used)]

use std::path::Path;

use glam::Vec3;
use phosphor_lighting::{Effects, LightSet};
use phosphor_raster::{Framebuffer, ShadingMode};

use super::*;

fn err(text: &str) -> String {
    Scene::parse(text, "t.toml").unwrap_err().to_string()
}

#[test]
fn embedded_default_scene_loads_with_every_kind_of_thing() {
    let s = Scene::default_scene().unwrap();
    assert!(s.objects().len() >= 5, "{}", s.objects().len());
    assert!(s.light_count() >= 4);
    assert!(s.materials.values().any(|m| m.bump.is_some()));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn shipped_s1_scene_matches_the_s1_definition() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes/s1.toml");
    let s = Scene::load(&path).unwrap();
    assert_eq!(s.camera(), phosphor_raster::Camera::s1());
    assert_eq!(s.ambient, Vec3::ONE);
    let lights: Vec<_> = s.lights().into_iter().map(|(_, l)| l).collect();
    assert_eq!(lights, phosphor_lighting::Light::s1_lights().to_vec());
    assert_eq!(
        s.materials["s1"].material,
        phosphor_lighting::Material::s1()
    );
    assert_eq!(s.settings.encoding, phosphor_raster::Encoding::Linear);
    assert_eq!((s.settings.width, s.settings.height), (1920, 1080));
    // The file's object and `--mesh` give the same mesh.
    let obj = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/meshes/bunny.obj");
    let direct = Scene::s1_with_mesh(&obj).unwrap();
    let a = &s.world.get::<&MeshRef>(s.objects()[0]).unwrap().0.mesh;
    let b = &direct
        .world
        .get::<&MeshRef>(direct.objects()[0])
        .unwrap()
        .0
        .mesh;
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.normals, b.normals);
}

#[test]
fn camera_values_are_checked_by_field() {
    assert_eq!(
        err("[camera]\nnear = 0\n"),
        "t.toml: camera.near: must be > 0, got 0"
    );
    assert_eq!(
        err("[camera]\nnear = 2\nfar = 1\n"),
        "t.toml: camera.far: must be greater than near (2), got 1"
    );
    assert_eq!(
        err("[camera]\nfov_y_deg = 180\n"),
        "t.toml: camera.fov_y_deg: must be between 0 and 180 (exclusive), got 180"
    );
    assert_eq!(
        err("[camera]\nfov_y_deg = 0\n"),
        "t.toml: camera.fov_y_deg: must be between 0 and 180 (exclusive), got 0"
    );
    assert_eq!(
        err("[camera]\neye = [0, 0, 0]\ntarget = [0, 0, 0]\n"),
        "t.toml: camera.target: must differ from eye"
    );
    assert!(
        err("[camera]\nnear = nan\n").starts_with("t.toml: camera.near: must be a finite number")
    );
    assert!(err("[camera]\neye = [0, inf, 0]\n").starts_with("t.toml: camera.eye: must be finite"));
}

#[test]
fn light_values_are_checked_by_field() {
    let light = |body: &str| {
        format!(
            "[[lights]]\ntype = \"point\"\nposition = [0, 0, 1]\nintensity = 1\n[[lights]]\n{body}\n"
        )
    };
    assert_eq!(
        err(&light(
            "type = \"point\"\nposition = [0, 0, 1]\nintensity = [1, 2]"
        )),
        "t.toml: lights[1].intensity: expected 3 numbers, found 2"
    );
    assert_eq!(
        err(&light(
            "type = \"point\"\nposition = [0, 0, 1]\nintensity = [1, -2, 1]"
        )),
        "t.toml: lights[1].intensity: must be non-negative, got [1, -2, 1]"
    );
    assert_eq!(
        err(&light("type = \"laser\"\nintensity = 1")),
        "t.toml: lights[1].type: unknown value \"laser\" (expected \"point\", \"directional\", \"spot\", \"tube\" or \"rect\")"
    );
    assert_eq!(
        err(&light("type = \"point\"\nintensity = 1")),
        "t.toml: lights[1].position: missing"
    );
    assert!(
        err(&light(
            "type = \"point\"\nposition = [0, 0, 1]\nintensity = 1\nintensty = 2"
        ))
        .starts_with("t.toml: lights[1].intensty: unknown field")
    );
    assert!(
        err(&light("type = \"spot\"\nposition = [0, 0, 1]\ndirection = [0, 0, -1]\ninner_deg = 40\nouter_deg = 30\nintensity = 1"))
            .starts_with("t.toml: lights[1].")
    );
    assert!(
        err(&light("type = \"point\"\nposition = [0, 0, 1]\nintensity = 1\nattenuation = { model = \"offset\", k = -5 }"))
            .starts_with("t.toml: lights[1].attenuation")
    );
    assert!(
        err(&light(
            "type = \"directional\"\ndirection = [0, 0, 0]\nintensity = 1"
        ))
        .starts_with("t.toml: lights[1].direction")
    );
    assert_eq!(
        err("[ambient]\nintensity = \"bright\"\n"),
        "t.toml: ambient.intensity: expected 3 numbers, found a string"
    );
}

#[test]
fn materials_and_objects_are_checked_by_field() {
    assert_eq!(
        err("[[objects]]\nprimitive = { shape = \"cube\" }\nmaterial = \"gold\"\n"),
        "t.toml: objects[0].material: unknown material \"gold\" (defined: none)"
    );
    assert_eq!(
        err("[materials.m]\nshininess = -1\n"),
        "t.toml: materials.m.shininess: must be non-negative, got -1"
    );
    assert_eq!(
        err("[materials.m]\nshininess = nan\n"),
        "t.toml: materials.m.shininess: must be a number >= 0 or inf, got NaN"
    );
    assert_eq!(
        err("[materials.m]\nshininess = -inf\n"),
        "t.toml: materials.m.shininess: must be a number >= 0 or inf, got -inf"
    );
    assert_eq!(
        err("[materials.m]\nshininess = 1e300\n"),
        "t.toml: materials.m.shininess: must be a finite number, got 1e300"
    );
    assert_eq!(
        err("[materials.m]\nks = 0.5\nfresnel = { model = \"schlick\", mode = \"replace\" }\n"),
        "t.toml: materials.m.ks: must be 1 under fresnel mode \"replace\" (W(theta) is the whole specular coefficient), got 0.5"
    );
    assert_eq!(
        err("[materials.m]\nfresnel = { model = \"schlick\", mode = \"multiply\" }\n"),
        "t.toml: materials.m.fresnel.mode: unknown value \"multiply\" (expected \"scale\", \"replace\")"
    );
    assert_eq!(
        err("[materials.m]\nkd = [0.5, 0.5, 1e40]\n"),
        "t.toml: materials.m.kd: must be finite, got 1e40"
    );
    assert!(
        err("[[objects]]\nmesh = \"no/such/file.obj\"\n")
            .starts_with("t.toml: objects[0].mesh: no/such/file.obj: cannot read")
    );
    assert!(
        err("[materials.m]\nbump = { map = \"no/such.png\" }\n")
            .starts_with("t.toml: materials.m.bump.map: no/such.png: no such file")
    );
    assert_eq!(
        err("[[objects]]\nprimitive = { shape = \"sphere\", radius = 0 }\n"),
        "t.toml: objects[0].primitive.radius: must be > 0, got 0"
    );
    assert_eq!(
        err("[[objects]]\nprimitive = { shape = \"cube\" }\nshading = \"shiny\"\n"),
        "t.toml: objects[0].shading: unknown shading \"shiny\" (expected \"auto\", \"flat\", \"gouraud\", \"fast-phong\", \"phong\" or \"reference\")"
    );
    assert!(
        err("[[objects]]\nmaterial = \"default\"\n")
            .starts_with("t.toml: objects[0]: expected exactly one of")
    );
    assert_eq!(
        err("[render]\nwidth = 0\n"),
        "t.toml: render.width: must be between 1 and 16384, got 0"
    );
    assert!(err("[scene]\n").starts_with("t.toml: scene: unknown field"));
}

#[test]
fn syntax_and_mesh_errors_name_the_line() {
    assert!(
        err("[camera]\neye = [0, 0\n").starts_with("t.toml:2: "),
        "{}",
        err("[camera]\neye = [0, 0\n")
    );
    let dir = std::env::temp_dir().join(format!("phosphor-scene-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    std::fs::write(dir.join("s.toml"), "[[objects]]\nmesh = \"bad.obj\"\n").unwrap();
    let e = Scene::load(&dir.join("s.toml")).unwrap_err().to_string();
    assert!(e.contains("s.toml: objects[0].mesh: "), "{e}");
    assert!(e.contains("bad.obj:4: "), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn loaded_then_saved_scene_loads_to_the_same_world() {
    let a = Scene::default_scene().unwrap();
    let text = scene_to_toml(&a);
    // Paths in the default scene are relative to assets/scenes; load from there.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
    let b = parse_scene(&text, "saved.toml", &dir, &Disk).unwrap();
    assert_eq!(scene_to_toml(&b), text);
    assert_eq!(a.camera(), b.camera());
    assert_eq!(a.lights(), b.lights());
    assert_eq!(a.materials, b.materials);
    for (ea, eb) in a.objects().into_iter().zip(b.objects()) {
        let ma = a.world.get::<&MeshRef>(ea).unwrap().0.clone();
        let mb = b.world.get::<&MeshRef>(eb).unwrap().0.clone();
        assert_eq!(ma.mesh.positions, mb.mesh.positions);
        assert_eq!(ma.mesh.normals, mb.mesh.normals);
        assert_eq!(
            *a.world.get::<&Transform>(ea).unwrap(),
            *b.world.get::<&Transform>(eb).unwrap()
        );
        assert_eq!(
            *a.world.get::<&phosphor_lighting::Material>(ea).unwrap(),
            *b.world.get::<&phosphor_lighting::Material>(eb).unwrap()
        );
    }
}

#[test]
fn perfect_mirror_and_fresnel_replace_load_save_and_render_finite() {
    let text = "[[lights]]\ntype = \"point\"\nposition = [2, 2, 2]\nintensity = 3\n\
        [materials.mirror]\nkd = 0.2\nshininess = inf\n\
        fresnel = { model = \"schlick\", f0 = 0.04, mode = \"replace\" }\n\
        [[objects]]\nprimitive = { shape = \"sphere\", segments = 24, rings = 12 }\n\
        material = \"mirror\"\n";
    let a = Scene::parse(text, "mirror.toml").unwrap();
    let m = a.materials["mirror"].material;
    assert_eq!(m.shininess, f32::INFINITY);
    assert_eq!(m.fresnel_mode, phosphor_lighting::FresnelMode::Replace);
    assert_eq!(m.ks, Vec3::ONE, "replace without ks holds ks at 1");
    let saved = scene_to_toml(&a);
    assert!(saved.contains("shininess = inf"), "{saved}");
    assert!(saved.contains("mode = \"replace\""), "{saved}");
    let b = Scene::parse(&saved, "saved.toml").unwrap();
    assert_eq!(a.materials, b.materials);
    for mode in ShadingMode::ALL {
        let mut fb = Framebuffer::new(40, 30).unwrap();
        let opts = FrameOptions {
            shading: Some(ShadingChoice::Mode(mode)),
            ..FrameOptions::default()
        };
        render_frame(&a, &mut fb, &opts);
        assert!(
            fb.color()
                .iter()
                .all(|c| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0),
            "{mode}"
        );
    }
}

#[test]
fn a_failed_save_leaves_the_old_file() {
    let s = Scene::default_scene().unwrap();
    let missing = Path::new("/nonexistent-dir-phosphor/scene.toml");
    let e = save_scene(&s, missing).unwrap_err().to_string();
    assert!(
        e.starts_with("/nonexistent-dir-phosphor/scene.toml: cannot write"),
        "{e}"
    );
}

/// Renders `scene` through the plan, and through the full kernel: every enabled light,
/// every effect on (BUMP as planned), the same modes. Returns both framebuffers.
fn planned_and_full(scene: &Scene, mode: ShadingMode) -> (Framebuffer, Framebuffer, FramePlan) {
    let (w, h) = (96, 72);
    let opts = FrameOptions {
        shading: Some(ShadingChoice::Mode(mode)),
        threads: 1,
        ..FrameOptions::default()
    };
    let mut planned = Framebuffer::new(w, h).unwrap();
    let report = render_frame(scene, &mut planned, &opts);
    let all: Vec<_> = scene.lights().into_iter().map(|(_, l)| l).collect();
    let full_set = LightSet::new(scene.ambient, &all);
    let mut items = draw_items(&report.plan);
    for it in &mut items {
        it.lights = &full_set;
        it.effects = Effects::ALL.with(Effects::BUMP, it.effects.contains(Effects::BUMP));
    }
    let mut full = Framebuffer::new(w, h).unwrap();
    phosphor_raster::render(
        &mut full,
        &scene.camera(),
        &items,
        &raster_options(scene, &opts),
    );
    (planned, full, report.plan)
}

/// The planned picture must equal the full kernel's, pixel for pixel. One exception, by design:
/// where the plan dropped a light (it adds exactly zero), `fast-phong`'s per-triangle fit check
/// no longer counts that light's specular upper bound, so it may keep a fit the full kernel
/// refuses (and redraws with `phong`); the two then stay within the fast-phong tolerance.
fn assert_same_picture(
    planned: &Framebuffer,
    full: &Framebuffer,
    mode: ShadingMode,
    plan: &FramePlan,
    label: &str,
) {
    let dropped = plan
        .objects
        .iter()
        .any(|o| o.lights.len() < plan.light_names.len());
    let pairs = || planned.color().iter().zip(full.color());
    let differing = pairs().filter(|(a, b)| a != b).count();
    if mode == ShadingMode::FastPhong && dropped {
        let sq: f64 = pairs()
            .map(|(a, b)| f64::from((*a - *b).length_squared()) / 3.0)
            .sum();
        let rmse = (sq / planned.color().len() as f64).sqrt();
        assert!(
            rmse <= f64::from(phosphor_raster::FAST_PHONG_TOLERANCE),
            "{label} {mode}: {differing} pixels differ, rmse {rmse}\n{plan}"
        );
    } else {
        assert_eq!(
            differing, 0,
            "{label} {mode}: {differing} pixels differ\n{plan}"
        );
    }
}

const BASE: &str = r#"
[camera]
eye = [0, 0.5, 3]
[ambient]
intensity = 0.5
"#;

#[test]
fn planned_picture_equals_the_full_kernel_when_terms_are_switched_off() {
    let cases: &[(&str, &str)] = &[
        (
            "no specular (ks = 0)",
            "[materials.m]\nkd = [0.8, 0.6, 0.4]\nks = 0\n[[lights]]\ntype = \"point\"\nposition = [2, 2, 2]\nintensity = 2\nattenuation = { model = \"offset\", k = 1 }\n",
        ),
        (
            "no ambient (ka = 0)",
            "[materials.m]\nka = 0\nks = 0.5\nshininess = 20\n[[lights]]\ntype = \"point\"\nposition = [2, 2, 2]\nintensity = 2\n",
        ),
        (
            "no diffuse (kd = 0)",
            "[materials.m]\nkd = 0\nks = 0.7\nshininess = 10\n[[lights]]\ntype = \"point\"\nposition = [2, 2, 2]\nintensity = 2\n",
        ),
        (
            "directional lights only (no attenuation)",
            "[materials.m]\nks = 0.5\nshininess = 32\n[[lights]]\ntype = \"directional\"\ndirection = [-1, -1, -1]\nintensity = [1, 0.5, 0.2]\n[[lights]]\ntype = \"directional\"\ndirection = [1, 0, -1]\nintensity = [0.2, 0.4, 1]\n",
        ),
        (
            "spot that misses the object",
            "[materials.m]\nks = 0.5\nshininess = 32\n[[lights]]\ntype = \"point\"\nposition = [2, 2, 2]\nintensity = 1\n[[lights]]\ntype = \"spot\"\nposition = [0, 5, 0]\ndirection = [1, 0, 0]\ninner_deg = 5\nouter_deg = 10\nintensity = 4\nattenuation = { model = \"inverse-square\" }\n",
        ),
        (
            "zero-intensity and disabled lights",
            "[materials.m]\nks = 0.5\nshininess = 32\n[[lights]]\ntype = \"point\"\nposition = [2, 2, 2]\nintensity = 1\n[[lights]]\ntype = \"point\"\nposition = [-2, 2, 2]\nintensity = 0\nattenuation = { model = \"inverse-square\" }\n[[lights]]\ntype = \"tube\"\nstart = [0, 3, 0]\nend = [1, 3, 0]\nintensity = 3\nenabled = false\n",
        ),
        (
            "emission only, no lights",
            "[materials.m]\nka = 0\nkd = 0.5\nemission = [0.2, 0.1, 0.05]\n",
        ),
        (
            "no fresnel variation",
            "[materials.m]\nks = 0.6\nshininess = 16\nfresnel = { model = \"none\" }\n[[lights]]\ntype = \"spot\"\nposition = [0, 3, 3]\ndirection = [0, -1, -1]\ninner_deg = 20\nouter_deg = 40\nintensity = 3\n",
        ),
    ];
    let objects = "[[objects]]\nprimitive = { shape = \"sphere\", radius = 1, segments = 24, rings = 12 }\nmaterial = \"m\"\n[[objects]]\nprimitive = { shape = \"plane\", half_size = 3 }\nmaterial = \"m\"\ntransform = { translate = [0, -1, 0] }\n";
    for (label, body) in cases {
        let scene = Scene::parse(&format!("{BASE}{body}{objects}"), "t.toml").unwrap();
        for mode in ShadingMode::ALL {
            let (planned, full, plan) = planned_and_full(&scene, mode);
            assert!(
                planned.color().iter().any(|c| c.max_element() > 0.0),
                "{label}: empty picture"
            );
            assert_same_picture(&planned, &full, mode, &plan, label);
        }
    }
}

#[test]
fn a_plane_lit_from_behind_drops_that_light_and_keeps_the_picture() {
    let scene = Scene::parse(
        &format!(
            "{BASE}[materials.m]\nks = 0.5\nshininess = 8\n[[lights]]\nname = \"front\"\ntype = \"point\"\nposition = [0, 2, 2]\nintensity = 1\n[[lights]]\nname = \"under\"\ntype = \"point\"\nposition = [0, -3, 0]\nintensity = 5\nattenuation = {{ model = \"inverse-square\" }}\n[[objects]]\nprimitive = {{ shape = \"plane\", half_size = 2 }}\nmaterial = \"m\"\ntransform = {{ translate = [0, -1, 0] }}\n"
        ),
        "t.toml",
    )
    .unwrap();
    for mode in ShadingMode::ALL {
        let (planned, full, plan) = planned_and_full(&scene, mode);
        assert_eq!(plan.objects[0].lights, vec![0], "{plan}");
        assert!(!plan.objects[0].effects.contains(Effects::ATTENUATION));
        assert_same_picture(&planned, &full, mode, &plan, "plane lit from behind");
    }
}

#[test]
fn objects_outside_the_frustum_are_culled() {
    let scene = Scene::parse(
        &format!(
            "{BASE}[[objects]]\nname = \"seen\"\nprimitive = {{ shape = \"cube\" }}\n[[objects]]\nname = \"behind\"\nprimitive = {{ shape = \"cube\" }}\ntransform = {{ translate = [0, 0, 10] }}\n[[objects]]\nname = \"far left\"\nprimitive = {{ shape = \"cube\" }}\ntransform = {{ translate = [-50, 0, 0] }}\n"
        ),
        "t.toml",
    )
    .unwrap();
    let plan = plan_frame(
        &scene,
        &scene.camera(),
        (640, 480),
        &FrameOptions::default(),
    );
    assert_eq!(plan.objects.len(), 1);
    assert_eq!(
        plan.culled,
        vec!["behind".to_owned(), "far left".to_owned()]
    );
}

fn auto_mode(body: &str) -> (ShadingMode, String) {
    let scene = Scene::parse(&format!("{BASE}{body}"), "t.toml").unwrap();
    let plan = plan_frame(
        &scene,
        &scene.camera(),
        (640, 480),
        &FrameOptions::default(),
    );
    (plan.objects[0].mode, plan.objects[0].reason.clone())
}

#[test]
fn auto_follows_the_notes_flat_shading_conditions() {
    let sun = "[[lights]]\ntype = \"directional\"\ndirection = [-1, -1, -1]\nintensity = 1\n";
    let near = "[[lights]]\ntype = \"point\"\nposition = [1.5, 1.5, 1.5]\nintensity = 1\n";
    // A polyhedron, matte, under the sun: N.L is constant per face, so flat is exact.
    let (m, why) = auto_mode(&format!(
        "{sun}[materials.m]\nks = 0\n[[objects]]\nprimitive = {{ shape = \"cube\" }}\nmaterial = \"m\"\n"
    ));
    assert_eq!(m, ShadingMode::Flat, "{why}");
    // The same cube beside a point light: N.L varies over a face.
    let (m, why) = auto_mode(&format!(
        "{near}[materials.m]\nks = 0\n[[objects]]\nprimitive = {{ shape = \"cube\" }}\nmaterial = \"m\"\n"
    ));
    assert_ne!(m, ShadingMode::Flat, "{why}");
    // A fine matte sphere under the sun: the terminator crosses triangles, where gouraud's
    // error is first order (3.5 codes measured), so phong.
    let (m, why) = auto_mode(&format!(
        "{sun}[materials.m]\nks = 0\n[[objects]]\nprimitive = {{ shape = \"sphere\", segments = 128, rings = 64 }}\nmaterial = \"m\"\n"
    ));
    assert_eq!(m, ShadingMode::Phong, "{why}");
    assert!(why.contains("gouraud bound over one code"), "{why}");
    // A coarse, very shiny sphere: the highlight is smaller than a triangle.
    let (m, why) = auto_mode(&format!(
        "{sun}[materials.m]\nks = 1\nshininess = 500\n[[objects]]\nprimitive = {{ shape = \"sphere\", segments = 12, rings = 6 }}\nmaterial = \"m\"\n"
    ));
    assert_eq!(m, ShadingMode::Phong, "{why}");
    // A coarse sphere with a broad highlight: fast Phong's fit is not bounded between its
    // check points, so auto never picks it.
    let (m, why) = auto_mode(&format!(
        "{sun}[materials.m]\nks = 0.5\nshininess = 1\n[[objects]]\nprimitive = {{ shape = \"sphere\", segments = 24, rings = 12 }}\nmaterial = \"m\"\n"
    ));
    assert_eq!(m, ShadingMode::Phong, "{why}");
    // A plane under the sun: flat and exact, with a finite reason (never `inf`).
    let (m, why) = auto_mode(&format!(
        "{sun}[materials.m]\nks = 0.5\n[[objects]]\nprimitive = {{ shape = \"plane\" }}\nmaterial = \"m\"\ntransform = {{ rotate_deg = [30, 0, 0] }}\n"
    ));
    assert!(!why.contains("inf") && !why.contains("NaN"), "{why}");
    assert_ne!(m, ShadingMode::FastPhong, "{why}");
    // Bump maps need per-pixel normals.
    let (m, why) = auto_mode(&format!(
        "{sun}[materials.m]\nbump = {{ procedural = \"bumps\" }}\n[[objects]]\nprimitive = {{ shape = \"sphere\" }}\nmaterial = \"m\"\n"
    ));
    assert_eq!(m, ShadingMode::Phong, "{why}");
}

#[test]
fn default_scene_renders_finite_and_varied() {
    let scene = Scene::default_scene().unwrap();
    // Large enough for `auto` to find triangles that pay for fast Phong's fit (the crate's).
    let mut fb = Framebuffer::new(640, 360).unwrap();
    let report = render_frame(&scene, &mut fb, &FrameOptions::default());
    assert!(
        fb.color()
            .iter()
            .all(|c| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0)
    );
    // Every reason is finite: no `inf` or `NaN` in the plan's explanation.
    let text = report.plan.to_string();
    assert!(!text.contains("inf") && !text.contains("NaN"), "{text}");
    assert!(report.stats.pixels_shaded > 640 * 360 / 4);
}

#[test]
fn pixels_per_triangle_is_the_projected_disc_over_the_front_half() {
    // S1's sphere: radius 1 seen from 3 with a 45 degree field of view at 1920x1080 projects to
    // a disc of radius 540 / (tan 22.5 deg * sqrt 8) = 460.9 px.
    let r_px = 540.0 / (22.5f32.to_radians().tan() * 8f32.sqrt());
    let disc = std::f32::consts::PI * r_px * r_px;
    let seen_from = |z: f32| {
        pixels_per_triangle(
            (Vec3::ZERO, 1.0),
            Vec3::new(0.0, 0.0, z),
            45.0,
            (1920, 1080),
            10_000,
        )
    };
    let px = seen_from(3.0);
    assert!(
        (px - disc / 5000.0).abs() < 1e-3 * px,
        "{px} vs {}",
        disc / 5000.0
    );
    // Twice as far: a quarter of the pixels (nearly: the disc is the sphere's silhouette).
    let far = seen_from(6.0);
    assert!(far < px * 0.26 && far > px * 0.2, "{far} vs {px}");
    // Inside the sphere, or with no triangles: the viewport bounds it, and it stays finite.
    let inside = pixels_per_triangle((Vec3::ZERO, 5.0), Vec3::ZERO, 45.0, (640, 480), 2);
    assert_eq!(inside, 640.0 * 480.0);
    for (r, n) in [(f32::NAN, 10), (1.0, 0), (f32::INFINITY, 10)] {
        let v = pixels_per_triangle(
            (Vec3::ZERO, r),
            Vec3::new(0.0, 0.0, 3.0),
            45.0,
            (640, 480),
            n,
        );
        assert!(v.is_finite() && v >= 0.0, "{r} {n}: {v}");
    }
}

/// Objects with the largest primitive counts a scene file allows.
fn big_primitives(shapes: &[&str]) -> String {
    shapes
        .iter()
        .enumerate()
        .map(|(i, shape)| {
            format!("[[objects]]\nprimitive = {shape}\ntransform = {{ translate = [{i}, 0, 0] }}\n")
        })
        .collect()
}

#[test]
fn primitives_over_the_memory_budget_are_refused_naming_the_count_before_allocating() {
    // Four distinct spheres at 4096 x 4096 would take about 10 GB: the second one is refused.
    let sphere = "{ shape = \"sphere\", radius = 1, segments = 4096, rings = 4096 }";
    let sphere2 = "{ shape = \"sphere\", radius = 2, segments = 4096, rings = 4096 }";
    let e = err(&big_primitives(&[sphere, sphere2, sphere, sphere2]));
    assert!(
        e.starts_with("t.toml: objects[1].primitive.segments: the mesh needs 2.5 GB"),
        "{e}"
    );
    assert!(e.contains("earlier objects take 2.5 GB"), "{e}");
    // Rings sizes the sphere when it is the larger count; the torus' sides likewise.
    let rings = "{ shape = \"sphere\", segments = 3000, rings = 4096 }";
    let e = err(&big_primitives(&[sphere, rings]));
    assert!(e.starts_with("t.toml: objects[1].primitive.rings: "), "{e}");
    let sides = "{ shape = \"torus\", segments = 4000, sides = 4096 }";
    let e = err(&big_primitives(&[sphere, sides]));
    assert!(
        e.starts_with("t.toml: objects[1].primitive.sides: the mesh needs"),
        "{e}"
    );
    let plane = "{ shape = \"plane\", subdivisions = 4096 }";
    let e = err(&big_primitives(&[plane, sphere]));
    assert!(
        e.starts_with("t.toml: objects[1].primitive.segments: "),
        "{e}"
    );
    let e = err(&big_primitives(&[sphere, plane]));
    assert!(
        e.starts_with("t.toml: objects[1].primitive.subdivisions: "),
        "{e}"
    );
}

#[test]
fn primitive_footprints_bound_the_built_meshes() {
    for p in [
        Primitive::Sphere {
            radius: 1.0,
            segments: 24,
            rings: 12,
        },
        Primitive::Cube { half_size: 1.0 },
        Primitive::Cylinder {
            radius: 1.0,
            height: 1.0,
            segments: 17,
        },
        Primitive::Torus {
            major: 1.0,
            minor: 0.3,
            segments: 20,
            sides: 9,
        },
        Primitive::Plane {
            half_size: 1.0,
            subdivisions: 5,
        },
    ] {
        let f = p.footprint();
        let m = p.try_build(f.bytes()).unwrap();
        assert_eq!(m, p.build());
        assert_eq!(m.positions.len() as u64, f.vertices, "{p:?}");
        assert!(m.indices.len() as u64 <= f.triangles, "{p:?}");
        assert!(p.try_build(f.bytes() - 1).is_err() || matches!(p, Primitive::Cube { .. }));
    }
}

#[test]
fn distributed_samples_over_the_budget_are_cut_with_a_warning_naming_the_field() {
    let mut text = String::new();
    for _ in 0..8 {
        text.push_str(
            "[[lights]]\ntype = \"rect\"\ncorner = [0, 2, 0]\nedge_u = [1, 0, 0]\nedge_v = [0, 0, 1]\nintensity = 1\nsamples = 256\n",
        );
    }
    text.push_str("[[lights]]\ntype = \"point\"\nposition = [0, 3, 0]\nintensity = 1\n");
    let s = Scene::parse(&text, "many.toml").unwrap();
    assert_eq!(s.warnings.len(), 8, "{:?}", s.warnings);
    assert!(
        s.warnings[0].starts_with("warning: many.toml: lights[0].samples: 256 cut to 5 ("),
        "{}",
        s.warnings[0]
    );
    assert!(s.warnings[7].contains("lights[7].samples"));
    let total: u64 = s.lights().iter().map(|(_, l)| point_samples(l)).sum();
    assert!(total <= MAX_DISTRIBUTED_SAMPLES, "{total}");
    // Names and order survive the cut.
    assert_eq!(s.lights()[8].0, "light 8");
    // Within the budget nothing is said.
    let s = Scene::parse(&text.replace("samples = 256", "samples = 5"), "few.toml").unwrap();
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn out_of_range_sample_counts_are_echoed_as_written() {
    assert_eq!(
        err(
            "[[lights]]\ntype = \"tube\"\nstart = [0, 0, 0]\nend = [1, 0, 0]\nintensity = 1\nsamples = 4294967295\n"
        ),
        "t.toml: lights[0].samples: must be in [1, 256], got 4294967295"
    );
}

#[test]
fn gouraud_clamp_is_a_render_setting_checked_by_field() {
    assert!(
        Scene::parse("", "t.toml")
            .unwrap()
            .settings
            .gouraud_vertex_clamp
    );
    let s = Scene::parse("[render]\ngouraud_clamp = false\n", "t.toml").unwrap();
    assert!(!s.settings.gouraud_vertex_clamp);
    let e = err("[render]\ngouraud_clamp = \"no\"\n");
    assert!(e.starts_with("t.toml: render.gouraud_clamp: "), "{e}");
}

#[test]
fn background_takes_an_opacity_checked_by_field_and_saved() {
    let s = Scene::parse("", "t.toml").unwrap();
    assert_eq!(
        (s.settings.background, s.settings.background_alpha),
        (Vec3::ZERO, 1.0)
    );
    let s = Scene::parse("[render]\nbackground = [0.2, 0.4, 0.6, 0.5]\n", "t.toml").unwrap();
    assert_eq!(s.settings.background, Vec3::new(0.2, 0.4, 0.6));
    assert_eq!(s.settings.background_alpha, 0.5);
    // The clear is premultiplied: colour times opacity.
    let opts = raster_options(&s, &FrameOptions::default());
    assert_eq!(opts.background, Vec3::new(0.1, 0.2, 0.3));
    // Saved with its opacity, and read back the same.
    let text = scene_to_toml(&s);
    assert!(text.contains("background = [0.2, 0.4, 0.6, 0.5]"), "{text}");
    let again = Scene::parse(&text, "saved.toml").unwrap();
    assert_eq!(again.settings, s.settings);
    let s = Scene::parse("[render]\nbackground = \"transparent\"\n", "t.toml").unwrap();
    assert_eq!(
        (s.settings.background, s.settings.background_alpha),
        (Vec3::ZERO, 0.0)
    );
    let s = Scene::parse("[render]\nbackground = [1, 1, 1]\n", "t.toml").unwrap();
    assert_eq!(
        (s.settings.background, s.settings.background_alpha),
        (Vec3::ONE, 1.0)
    );
    assert!(!scene_to_toml(&s).contains("background = [1.0, 1.0, 1.0, 1.0]"));
    for (bad, says) in [
        ("[0, 0, 0, 1.5]", "alpha must be in [0, 1], got 1.5"),
        ("[0, 0, 0, -0.1]", "alpha must be in [0, 1]"),
        ("[-1, 0, 0, 1]", "colour must be non-negative"),
        ("[0, 0, 0, nan]", "must be finite"),
        ("\"clear\"", "\"transparent\""),
        ("[0, 0]", "expected 3 numbers"),
    ] {
        let e = err(&format!("[render]\nbackground = {bad}\n"));
        assert!(e.starts_with("t.toml: render.background"), "{bad}: {e}");
        assert!(e.contains(says), "{bad}: {e}");
    }
}

#[test]
fn ka_kd_gives_the_notes_ambient_term_ia_kd() {
    // No lights: every covered pixel is I = Ia Kd = 0.5 * (0.8, 0.6, 0.4).
    let scene = Scene::parse(
        &format!(
            "{BASE}[materials.m]\nka = \"kd\"\nkd = [0.8, 0.6, 0.4]\n[[objects]]\nprimitive = {{ shape = \"cube\" }}\nmaterial = \"m\"\n"
        ),
        "t.toml",
    )
    .unwrap();
    let mut fb = Framebuffer::new(64, 48).unwrap();
    let report = render_frame(&scene, &mut fb, &FrameOptions::default());
    assert!(report.stats.pixels_shaded > 100);
    let expected = Vec3::new(0.4, 0.3, 0.2);
    let covered: Vec<Vec3> = fb
        .color()
        .iter()
        .zip(fb.depth())
        .filter(|(_, d)| **d < 1.0)
        .map(|(c, _)| *c)
        .collect();
    assert!(!covered.is_empty());
    for c in covered {
        assert!((c - expected).abs().max_element() < 1e-6, "{c}");
    }
    // Any other string is an error naming the field.
    let err = Scene::parse(
        &format!("{BASE}[materials.m]\nka = \"ks\"\n[[objects]]\nprimitive = {{ shape = \"cube\" }}\nmaterial = \"m\"\n"),
        "t.toml",
    )
    .expect_err("an error");
    assert!(err.to_string().contains("ka"), "{err}");
}

#[test]
fn auto_takes_gouraud_where_the_bound_proves_it() {
    // A dome (the cap of a fine sphere within about 50 degrees of +y), matte, under a light
    // from straight above: every normal lit, no terminator, smooth: gouraud's bound is under
    // one code (linear encoding), and flat's is not (a curved surface).
    let sphere = phosphor_mesh::primitives::uv_sphere(1.0, 128, 64);
    let mut dome = sphere.clone();
    dome.indices
        .retain(|t| t.iter().all(|&i| sphere.positions[i as usize].y > 0.65));
    assert!(dome.indices.len() > 500);
    let info = crate::components::MeshInfo::of(&dome);
    let set = LightSet::new(
        Vec3::splat(0.2),
        &[phosphor_lighting::Light::directional(-Vec3::Y, Vec3::ONE).unwrap()],
    );
    let material =
        phosphor_lighting::Material::new(Vec3::splat(0.1), Vec3::splat(0.6), Vec3::ZERO, 1.0)
            .unwrap();
    let input = |encoding| AutoInput {
        material: &material,
        effects: phosphor_lighting::effects_for(&set, &material),
        set: &set,
        mesh: &dome,
        info: &info,
        model: glam::Mat4::IDENTITY,
        eye: Vec3::new(0.0, 3.0, 2.0),
        bumped: false,
        tinted: false,
        vertex_clamp: true,
        encoding,
        skip_back_faces: false,
    };
    let (m, why) = crate::plan::choose_mode(&input(phosphor_raster::Encoding::Linear));
    assert_eq!(m, ShadingMode::Gouraud, "{why}");
    assert!(why.contains("gouraud proven within"), "{why}");
    // The same dome with a tinted surface is left to phong: the bound covers untinted shading.
    let tinted = AutoInput {
        tinted: true,
        ..input(phosphor_raster::Encoding::Linear)
    };
    assert_eq!(crate::plan::choose_mode(&tinted).0, ShadingMode::Phong);
}
