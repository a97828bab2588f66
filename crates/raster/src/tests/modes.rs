//! Shading modes against each other and against the f64 reference.

use glam::{Mat4, Vec3, Vec4};
use phosphor_lighting::{Effects, Light, LightSet, Material};

use super::support::*;
use crate::encode::encode;
use crate::framebuffer::FAR_DEPTH;
use crate::{
    BumpMap, Camera, DrawItem, Encoding, Framebuffer, ProceduralBump, RenderOptions, RenderStats,
    ShadingMode, render, render_fill_only,
};

const ONE_CODE: f32 = 1.0 / 255.0;

fn share_within(d: &[f32], covered: &[bool], tol: f32) -> f64 {
    let (mut n, mut ok) = (0usize, 0usize);
    for (x, c) in d.iter().zip(covered) {
        if *c {
            n += 1;
            ok += usize::from(*x <= tol);
        }
    }
    ok as f64 / n.max(1) as f64
}

#[test]
fn flat_gouraud_and_phong_agree_on_a_flat_face_under_a_distant_light_and_viewer() {
    let quad = TestMesh {
        positions: vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        normals: vec![Vec3::Z; 4],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..TestMesh::default()
    };
    let set = LightSet::new(
        Vec3::splat(0.2),
        &[Light::directional(Vec3::new(-0.3, -0.2, -1.0), Vec3::ONE).unwrap()],
    );
    let mat = Material::s1();
    // The viewer 1000 units away: V is constant across the face to 1e-3 rad.
    let cam = Camera {
        eye: Vec3::new(0.0, 0.0, 1000.0),
        fov_y_deg: 0.05,
        near: 900.0,
        far: 1100.0,
        ..Camera::s1()
    };
    let opts = RenderOptions::default();
    let img = |mode| draw_image(48, 32, &cam, &[item(&quad, &mat, &set, mode)], &opts).0;
    let (flat, gouraud, phong) = (
        img(ShadingMode::Flat),
        img(ShadingMode::Gouraud),
        img(ShadingMode::Phong),
    );
    assert!(
        flat.color().iter().all(|c| *c != Vec3::ZERO),
        "the quad fills the image"
    );
    for d in [
        diffs(&flat, &gouraud),
        diffs(&flat, &phong),
        diffs(&gouraud, &phong),
    ] {
        let worst = d.iter().fold(0.0f32, |a, b| a.max(*b));
        // V still turns by 1e-3 rad across the face, which (V.R)^32 feels: a quarter code.
        assert!(worst < 1e-3, "modes disagree by {worst}");
    }
}

fn sphere_scene() -> (TestMesh, LightSet, Material) {
    // 128 x 80 quads: 20 224 triangles.
    (uv_sphere(1.0, 128, 80), s1_lights(), Material::s1())
}

#[test]
fn phong_matches_reference_on_a_fine_sphere() {
    let (sphere, set, mat) = sphere_scene();
    assert!(sphere.indices.len() > 20_000);
    let cam = Camera::s1();
    let opts = RenderOptions::default();
    let (phong, _) = draw_image(
        320,
        240,
        &cam,
        &[item(&sphere, &mat, &set, ShadingMode::Phong)],
        &opts,
    );
    let (reference, _) = draw_image(
        320,
        240,
        &cam,
        &[item(&sphere, &mat, &set, ShadingMode::Reference)],
        &opts,
    );
    let covered: Vec<bool> = phong.depth().iter().map(|z| *z < 1.0).collect();
    let share = share_within(&diffs(&phong, &reference), &covered, ONE_CODE);
    println!(
        "phong vs reference: {:.4}% of {} pixels within 1/255",
        share * 100.0,
        covered.iter().filter(|c| **c).count()
    );
    assert!(share >= 0.999, "only {share} within 1/255");
}

#[test]
fn fast_phong_matches_phong_on_the_sphere_within_its_bound() {
    let (sphere, set, mat) = sphere_scene();
    let cam = Camera::s1();
    let opts = RenderOptions::default();
    let (fast, stats) = draw_image(
        320,
        240,
        &cam,
        &[item(&sphere, &mat, &set, ShadingMode::FastPhong)],
        &opts,
    );
    let (phong, _) = draw_image(
        320,
        240,
        &cam,
        &[item(&sphere, &mat, &set, ShadingMode::Phong)],
        &opts,
    );
    let d = diffs(&fast, &phong);
    let worst = d.iter().fold(0.0f32, |a, b| a.max(*b));
    let rmse = (d.iter().map(|x| (x * x) as f64).sum::<f64>() / d.len() as f64).sqrt();
    let covered: Vec<bool> = phong.depth().iter().map(|z| *z < 1.0).collect();
    let share = share_within(&d, &covered, 2.0 * ONE_CODE);
    println!(
        "fast-phong vs phong: max {:.5} ({:.2} codes), rmse {rmse:.6}, {:.3}% within 2/255, fallbacks {} of {} pieces",
        worst,
        worst * 255.0,
        share * 100.0,
        stats.fallbacks,
        stats.triangles_drawn
    );
    assert!(worst <= 4.0 * ONE_CODE, "worst {worst}");
    assert!(rmse <= 0.002, "rmse {rmse}");
    assert!(share >= 0.999);
    // A coarse sphere: big triangles, spread normals, the fallback at work.
    let coarse = uv_sphere(1.0, 32, 20);
    let (fast, stats) = draw_image(
        320,
        240,
        &cam,
        &[item(&coarse, &mat, &set, ShadingMode::FastPhong)],
        &opts,
    );
    let (phong, _) = draw_image(
        320,
        240,
        &cam,
        &[item(&coarse, &mat, &set, ShadingMode::Phong)],
        &opts,
    );
    let d = diffs(&fast, &phong);
    let worst = d.iter().fold(0.0f32, |a, b| a.max(*b));
    let rmse = (d.iter().map(|x| (x * x) as f64).sum::<f64>() / d.len() as f64).sqrt();
    println!(
        "coarse sphere: max {:.2} codes, rmse {rmse:.6}, fallbacks {} of {} pieces",
        worst * 255.0,
        stats.fallbacks,
        stats.triangles_drawn
    );
    assert!(stats.fallbacks > 0);
    assert!(worst <= 4.0 * ONE_CODE, "worst {worst}");
}

#[test]
fn fast_phong_does_not_blow_up_on_a_screen_filling_triangle_with_spread_normals() {
    // Normals 120 degrees apart, the triangle covering the whole view.
    let n = |a: f32| {
        Vec3::new(
            a.to_radians().sin() * 60f32.to_radians().sin(),
            a.to_radians().cos() * 60f32.to_radians().sin(),
            60f32.to_radians().cos(),
        )
    };
    let tri = TestMesh {
        positions: vec![
            Vec3::new(-4.0, -3.0, 0.0),
            Vec3::new(4.0, -3.0, 0.0),
            Vec3::new(0.0, 5.0, 0.0),
        ],
        normals: vec![n(240.0), n(120.0), n(0.0)],
        indices: vec![[0, 1, 2]],
        ..TestMesh::default()
    };
    for i in 0..3 {
        for j in 0..i {
            let angle = tri.normals[i].angle_between(tri.normals[j]).to_degrees();
            assert!(angle > 85.0, "{angle}");
        }
    }
    let set = s1_lights();
    let mat = Material::s1();
    let cam = Camera::s1();
    let opts = RenderOptions::default();
    let (fast, stats) = draw_image(
        160,
        120,
        &cam,
        &[item(&tri, &mat, &set, ShadingMode::FastPhong)],
        &opts,
    );
    let (phong, _) = draw_image(
        160,
        120,
        &cam,
        &[item(&tri, &mat, &set, ShadingMode::Phong)],
        &opts,
    );
    assert_eq!(stats.fallbacks, 1, "the fit must be refused");
    assert!(diffs(&fast, &phong).iter().all(|d| *d <= ONE_CODE));
}

#[test]
fn fast_phong_refuses_a_fit_that_misses_a_narrow_highlight() {
    // A flat square, a directional light whose mirror direction is seen off the centre,
    // n_s = 1000: the highlight peaks between the ten points the fit samples, which all see
    // almost nothing. Without the specular bound the fit passed and lost a peak of 0.5.
    let square = TestMesh {
        positions: [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, y)| Vec3::new(x, y, 0.0))
            .to_vec(),
        normals: vec![Vec3::Z; 4],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..TestMesh::default()
    };
    let light = Light::directional(-Vec3::new(0.1, 0.02, 1.0), Vec3::ONE).unwrap();
    let set = LightSet::new(Vec3::ZERO, &[light]);
    let mat = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::splat(0.5), 1000.0).unwrap();
    let cam = Camera::s1();
    let opts = RenderOptions::default();
    let draw = |mode| draw_image(160, 120, &cam, &[item(&square, &mat, &set, mode)], &opts);
    let ((fast, stats), (phong, _)) = (draw(ShadingMode::FastPhong), draw(ShadingMode::Phong));
    assert!(
        phong.color().iter().any(|c| c.x > 0.4),
        "the highlight is in the image"
    );
    assert_eq!(stats.fallbacks, 2);
    assert!(diffs(&fast, &phong).iter().all(|d| *d <= ONE_CODE));
}

#[test]
fn images_are_bit_identical_for_1_2_and_all_threads() {
    let (sphere, set, mat) = sphere_scene();
    let cam = Camera::s1();
    for mode in [
        ShadingMode::Phong,
        ShadingMode::FastPhong,
        ShadingMode::Gouraud,
    ] {
        let run = |threads| {
            draw_image(
                200,
                150,
                &cam,
                &[item(&sphere, &mat, &set, mode)],
                &RenderOptions {
                    threads,
                    ..RenderOptions::default()
                },
            )
            .0
        };
        let (one, two, all) = (run(1), run(2), run(0));
        assert!(
            one.color() == two.color() && one.depth() == two.depth(),
            "{mode}"
        );
        assert!(one.color() == all.color(), "{mode}");
    }
}

#[test]
fn a_reused_framebuffer_gives_the_picture_of_a_fresh_one() {
    // Frames of different objects, modes, sizes on screen and backgrounds drawn into one
    // framebuffer (which clears only what the frame before wrote) against each drawn into a
    // fresh one: colour and depth bit for bit, on one and on two threads.
    let (sphere, set, mat) = (uv_sphere(1.0, 24, 12), s1_lights(), Material::s1());
    let big = floor();
    let cam = Camera::s1();
    let grey = Vec3::splat(0.25);
    let moved = |mode, x: f32, s: f32| DrawItem {
        model: Mat4::from_translation(Vec3::new(x, 0.0, 0.0)) * Mat4::from_scale(Vec3::splat(s)),
        ..item(&sphere, &mat, &set, mode)
    };
    let frames: Vec<(Vec<DrawItem>, Vec3)> = vec![
        (vec![moved(ShadingMode::Phong, 0.0, 1.0)], Vec3::ZERO),
        (vec![moved(ShadingMode::Flat, 1.2, 0.5)], Vec3::ZERO),
        (
            vec![item(&big, &mat, &set, ShadingMode::Gouraud)],
            Vec3::ZERO,
        ),
        (
            vec![
                moved(ShadingMode::FastPhong, -1.0, 0.4),
                moved(ShadingMode::Phong, 0.8, 0.3),
            ],
            Vec3::ZERO,
        ),
        (vec![moved(ShadingMode::Reference, 0.0, 0.2)], grey),
        (vec![], grey),
        (vec![moved(ShadingMode::Gouraud, -0.5, 0.7)], grey),
        (vec![moved(ShadingMode::Phong, 0.5, 0.6)], Vec3::ZERO),
    ];
    type Draw = fn(&mut Framebuffer, &Camera, &[DrawItem], &RenderOptions) -> RenderStats;
    let passes: [(&str, Draw); 2] = [("render", render), ("fill-only", render_fill_only)];
    for (threads, (name, draw)) in [1, 2].into_iter().flat_map(|t| passes.map(|p| (t, p))) {
        let mut reused = Framebuffer::new(96, 72).unwrap();
        for (k, (draws, background)) in frames.iter().enumerate() {
            let opts = RenderOptions {
                threads,
                background: *background,
                ..RenderOptions::default()
            };
            let mut fresh = Framebuffer::new(96, 72).unwrap();
            draw(&mut reused, &cam, draws, &opts);
            draw(&mut fresh, &cam, draws, &opts);
            assert!(
                reused.color() == fresh.color() && reused.depth() == fresh.depth(),
                "{name}, frame {k}, {threads} threads"
            );
            // What the window shows (background pixels filled, written ones converted):
            // every pixel's own conversion.
            let each: Vec<u32> = fresh
                .color()
                .iter()
                .map(|c| {
                    let [r, g, b] = [c.x, c.y, c.z].map(|v| u32::from(encode(v, Encoding::Srgb)));
                    (r << 16) | (g << 8) | b
                })
                .collect();
            let mut shown = vec![0u32; each.len()];
            reused.write_0rgb_threads(&mut shown, threads);
            assert!(shown == each, "{name}, frame {k}: presented bytes");
        }
        // An explicit clear to the last colour, then to another.
        for background in [Vec3::ZERO, grey] {
            reused.clear(background);
            assert!(
                reused.color().iter().all(|c| *c == background)
                    && reused.depth().iter().all(|z| *z == FAR_DEPTH),
                "{name}: clear after the frames"
            );
        }
    }
}

#[test]
fn ids_left_by_an_earlier_frame_never_shade_a_pixel() {
    // The two-pass modes keep each thread's id buffer from band job to band job (a fresh
    // epoch in each job's ids keeps old ones from matching). A frame that
    // covers the middle of the image leaves ids there; the next frame draws one mesh of two
    // small spheres side by side, so the rows its depth pass writes span an empty gap between
    // them. No pixel of that gap (nor any other left at the far depth) may be shaded.
    let (sphere, set, mat) = (uv_sphere(1.0, 24, 12), s1_lights(), Material::s1());
    let mut pair = TestMesh::default();
    for dx in [-0.8f32, 0.8] {
        let base = pair.positions.len() as u32;
        let at = |p: Vec3| p * 0.3 + Vec3::new(dx, 0.0, 0.0);
        pair.positions
            .extend(sphere.positions.iter().map(|&p| at(p)));
        pair.normals.extend(&sphere.normals);
        pair.indices
            .extend(sphere.indices.iter().map(|t| t.map(|i| i + base)));
    }
    let cam = Camera::s1();
    // One thread: both frames run on this thread, with its id buffer.
    let opts = RenderOptions {
        threads: 1,
        ..RenderOptions::default()
    };
    for mode in [
        ShadingMode::Phong,
        ShadingMode::FastPhong,
        ShadingMode::Reference,
    ] {
        let cover = DrawItem {
            model: Mat4::from_scale(Vec3::splat(1.2)),
            ..item(&sphere, &mat, &set, mode)
        };
        let (_, covered) = draw_image(160, 120, &cam, &[cover], &opts);
        assert!(
            covered.pixels_shaded > 5_000,
            "{mode}: the first frame covers the middle"
        );
        let (fb, stats) = draw_image(160, 120, &cam, &[item(&pair, &mat, &set, mode)], &opts);
        assert!(stats.pixels_shaded > 200, "{mode}: both spheres drawn");
        let gap = (fb.color().iter().zip(fb.depth()))
            .filter(|(_, z)| **z == FAR_DEPTH)
            .filter(|(c, _)| **c != Vec3::ZERO)
            .count();
        assert_eq!(gap, 0, "{mode}: {gap} background pixels shaded");
        // The gap between the spheres is really inside the written rows.
        assert_eq!(fb.depth()[60 * 160 + 80], FAR_DEPTH, "{mode}");
    }
}

fn floor() -> TestMesh {
    // A big floor through and behind the camera: crosses the near plane.
    TestMesh {
        positions: vec![
            Vec3::new(-20.0, -1.0, 10.0),
            Vec3::new(20.0, -1.0, 10.0),
            Vec3::new(0.0, -1.0, -30.0),
        ],
        normals: vec![Vec3::Y; 3],
        uvs: vec![
            glam::Vec2::new(0.0, 0.0),
            glam::Vec2::new(4.0, 0.0),
            glam::Vec2::new(2.0, 4.0),
        ],
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 3],
        indices: vec![[0, 1, 2]],
    }
}

#[test]
fn near_plane_crossing_triangle_renders_like_the_reference() {
    let tri = floor();
    let set = LightSet::new(
        Vec3::splat(0.1),
        &[Light::point(Vec3::new(0.0, 1.0, 0.0), Vec3::splat(2.0)).unwrap()],
    );
    let mat = Material::s1();
    let cam = Camera::s1();
    let opts = RenderOptions::default();
    let (phong, stats) = draw_image(
        160,
        120,
        &cam,
        &[item(&tri, &mat, &set, ShadingMode::Phong)],
        &opts,
    );
    let (reference, _) = draw_image(
        160,
        120,
        &cam,
        &[item(&tri, &mat, &set, ShadingMode::Reference)],
        &opts,
    );
    assert_eq!(stats.triangles_drawn, 1);
    // The floor covers every row from the bottom up to where it passes the far plane
    // (distance 10: row 74.5), and nothing above.
    for x in 0..160 {
        for y in 76..120 {
            assert!(phong.depth_at(x, y) < 1.0, "hole at ({x}, {y})");
        }
        assert_eq!(
            phong.depth_at(x, 70),
            1.0,
            "beyond the far plane at column {x}"
        );
    }
    let covered: Vec<bool> = phong.depth().iter().map(|z| *z < 1.0).collect();
    let share = share_within(&diffs(&phong, &reference), &covered, ONE_CODE);
    assert!(share >= 0.999, "{share}");
    maybe_write_doc(&phong, "raster-near-clip.png");
    // Entirely behind the camera: nothing.
    let behind = DrawItem {
        model: Mat4::from_translation(Vec3::new(0.0, 0.0, 50.0)),
        ..item(&tri, &mat, &set, ShadingMode::Phong)
    };
    let (img, stats) = draw_image(64, 48, &cam, &[behind], &opts);
    assert_eq!(stats.pixels_shaded, 0);
    assert!(img.color().iter().all(|c| *c == Vec3::ZERO));
}

#[test]
fn screen_space_interpolation_differs_from_perspective_correct_on_a_receding_plane() {
    let tri = floor();
    let set = LightSet::new(
        Vec3::splat(0.1),
        &[Light::point(Vec3::new(0.0, 1.0, 0.0), Vec3::splat(2.0)).unwrap()],
    );
    let mat = Material::s1();
    let cam = Camera::s1();
    let persp = draw_image(
        160,
        120,
        &cam,
        &[item(&tri, &mat, &set, ShadingMode::Gouraud)],
        &RenderOptions::default(),
    )
    .0;
    let linear = RenderOptions {
        perspective_correct: false,
        ..RenderOptions::default()
    };
    let lin = draw_image(
        160,
        120,
        &cam,
        &[item(&tri, &mat, &set, ShadingMode::Gouraud)],
        &linear,
    )
    .0;
    let worst = diffs(&persp, &lin).iter().fold(0.0f32, |a, b| a.max(*b));
    assert!(worst > 0.01, "{worst}");
    assert!(lin.color().iter().all(|c| c.is_finite()));
}

#[test]
fn bump_mapping_perturbs_phong_and_reference_alike_and_flat_ignores_it() {
    let (sphere, set, mat) = (uv_sphere(1.0, 96, 64), s1_lights(), Material::s1());
    let bump = BumpMap::Procedural {
        kind: ProceduralBump::Bumps,
        scale: 0.3,
    };
    let cam = Camera::s1();
    let opts = RenderOptions::default();
    let bumped = |mode| DrawItem {
        bump: Some(&bump),
        texture: None,
        effects: Effects::ALL,
        ..item(&sphere, &mat, &set, mode)
    };
    let (phong, s1) = draw_image(200, 150, &cam, &[bumped(ShadingMode::Phong)], &opts);
    let (reference, _) = draw_image(200, 150, &cam, &[bumped(ShadingMode::Reference)], &opts);
    let (fast, s3) = draw_image(200, 150, &cam, &[bumped(ShadingMode::FastPhong)], &opts);
    let (plain, _) = draw_image(
        200,
        150,
        &cam,
        &[item(&sphere, &mat, &set, ShadingMode::Phong)],
        &opts,
    );
    assert_eq!(s1.bump_ignored + s3.bump_ignored, 0);
    let covered: Vec<bool> = phong.depth().iter().map(|z| *z < 1.0).collect();
    assert!(share_within(&diffs(&phong, &reference), &covered, ONE_CODE) >= 0.99);
    assert!(
        fast.color() == phong.color(),
        "bumped fast-phong draws with phong"
    );
    let changed = diffs(&phong, &plain).iter().filter(|d| **d > 0.05).count();
    assert!(changed > 1000, "bumps visible: {changed}");
    maybe_write_doc(&phong, "raster-bump.png");
    let (_, s) = draw_image(64, 48, &cam, &[bumped(ShadingMode::Flat)], &opts);
    assert_eq!(s.bump_ignored, 1);
    let no_frame = TestMesh {
        uvs: vec![],
        tangents: vec![],
        ..sphere.clone()
    };
    let d = DrawItem {
        bump: Some(&bump),
        texture: None,
        ..item(&no_frame, &mat, &set, ShadingMode::Phong)
    };
    assert_eq!(draw_image(64, 48, &cam, &[d], &opts).1.bump_ignored, 1);
}

#[test]
fn huge_and_camera_surrounding_triangles_are_guard_band_clipped_and_fill_the_view() {
    let set = LightSet::new(Vec3::splat(0.5), &[]);
    let mat = Material::s1();
    let cam = Camera::s1();
    for (positions, label) in [
        // Far beyond the fixed-point range on screen, in front of the camera.
        (
            vec![
                Vec3::new(-1e6, -1e6, 0.0),
                Vec3::new(1e6, -1e6, 0.0),
                Vec3::new(0.0, 1e6, 0.0),
            ],
            "huge",
        ),
        // Around the camera: two vertices behind it, one in front; the plane fills the view.
        (
            vec![
                // Plane z = -y / 10: it crosses the view axis 3 units ahead of the eye and
                // covers the whole frustum, well inside the far plane.
                Vec3::new(-50.0, -50.0, 5.0),
                Vec3::new(50.0, -50.0, 5.0),
                Vec3::new(0.0, 50.0, -5.0),
            ],
            "surrounding",
        ),
    ] {
        let mesh = TestMesh {
            positions,
            normals: vec![Vec3::Z; 3],
            indices: vec![[0, 1, 2]],
            ..TestMesh::default()
        };
        for mode in [
            ShadingMode::Flat,
            ShadingMode::Phong,
            ShadingMode::Reference,
        ] {
            let (fb, stats) = draw_image(
                64,
                48,
                &cam,
                &[item(&mesh, &mat, &set, mode)],
                &RenderOptions::default(),
            );
            assert_eq!(stats.pixels_shaded, 64 * 48, "{label} {mode}");
            assert!(
                fb.color()
                    .iter()
                    .all(|c| (*c - Vec3::splat(0.05)).abs().max_element() < 1e-5),
                "{label} {mode}"
            );
        }
    }
}

#[test]
fn bad_input_never_panics_nor_writes_nan() {
    let mesh = TestMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::NAN, Vec3::Y, Vec3::splat(1e30)],
        normals: vec![Vec3::ZERO, Vec3::NAN, Vec3::Z, Vec3::Z, Vec3::Z],
        indices: vec![
            [0, 1, 2],
            [0, 1, 3],
            [0, 1, 99],
            [0, 0, 0],
            [0, 3, 4],
            [1, 3, 4],
        ],
        ..TestMesh::default()
    };
    let (set, mat) = (s1_lights(), Material::s1());
    for mode in crate::ShadingMode::ALL {
        for cull in [false, true] {
            let opts = RenderOptions {
                cull_backfaces: cull,
                ..RenderOptions::default()
            };
            let (fb, _) = draw_image(
                40,
                30,
                &Camera::s1(),
                &[item(&mesh, &mat, &set, mode)],
                &opts,
            );
            assert!(
                fb.color()
                    .iter()
                    .all(|c| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0)
            );
        }
    }
}

#[test]
fn docs_modes_side_by_side() {
    // Writes docs/raster-modes.png (flat, gouraud, phong, fast-phong, reference) on request.
    if std::env::var_os("PHOSPHOR_WRITE_DOCS").is_none() {
        return;
    }
    let (sphere, set, mat) = (uv_sphere(1.0, 24, 16), s1_lights(), Material::s1());
    let cam = Camera {
        eye: Vec3::new(0.0, 0.0, 2.8),
        ..Camera::s1()
    };
    let (w, h) = (160u32, 160u32);
    let mut strip = crate::Framebuffer::new(w * 5, h).unwrap();
    // Written pixel by pixel below, not by the renderer: no pixel is known to hold a clear.
    strip.clean = None;
    for (k, mode) in [
        ShadingMode::Flat,
        ShadingMode::Gouraud,
        ShadingMode::Phong,
        ShadingMode::FastPhong,
        ShadingMode::Reference,
    ]
    .into_iter()
    .enumerate()
    {
        let (fb, _) = draw_image(
            w,
            h,
            &cam,
            &[item(&sphere, &mat, &set, mode)],
            &RenderOptions::default(),
        );
        for y in 0..h {
            for x in 0..w {
                strip.color[(y * w * 5 + k as u32 * w + x) as usize] = fb.pixel(x, y);
            }
        }
    }
    maybe_write_doc(&strip, "raster-modes.png");
}

#[test]
#[ignore = "timing report, run with --ignored --nocapture"]
fn timing_sphere_1080p_per_mode() {
    let (sphere, set, mat) = (uv_sphere(1.0, 256, 140), s1_lights(), Material::s1());
    let cam = Camera::s1();
    let mut fb = crate::Framebuffer::new(1920, 1080).unwrap();
    for threads in [1, 2] {
        let opts = RenderOptions {
            threads,
            ..RenderOptions::default()
        };
        for mode in [
            ShadingMode::Flat,
            ShadingMode::Gouraud,
            ShadingMode::Phong,
            ShadingMode::FastPhong,
        ] {
            let d = [item(&sphere, &mat, &set, mode)];
            crate::render(&mut fb, &cam, &d, &opts);
            let t = std::time::Instant::now();
            let frames = 5;
            let mut stats = crate::RenderStats::default();
            for _ in 0..frames {
                stats = crate::render(&mut fb, &cam, &d, &opts);
            }
            let ms = t.elapsed().as_secs_f64() * 1e3 / frames as f64;
            println!(
                "{mode} threads={threads} {ms:.2} ms/frame ({} tris, {} px, {} fallbacks)",
                stats.triangles_in, stats.pixels_shaded, stats.fallbacks
            );
        }
        let d = [item(&sphere, &mat, &set, ShadingMode::Flat)];
        let t = std::time::Instant::now();
        crate::render_fill_only(&mut fb, &cam, &d, &opts);
        println!(
            "fill-only threads={threads} {:.2} ms",
            t.elapsed().as_secs_f64() * 1e3
        );
    }
}

#[test]
fn gouraud_without_the_vertex_clamp_interpolates_the_models_values() {
    // A strong light makes some vertex intensities exceed 1: the clamped form interpolates 1
    // there, the unclamped one the model's values, clamped only at the pixel. Where all three
    // vertices stay below 1 the two agree; nowhere is the clamped form brighter.
    let sphere = uv_sphere(1.0, 24, 12);
    let lights = LightSet::new(
        Vec3::splat(0.05),
        &[Light::point(Vec3::new(1.5, 1.5, 2.0), Vec3::splat(6.0)).unwrap()],
    );
    let material = Material::s1();
    let draws = [item(&sphere, &material, &lights, ShadingMode::Gouraud)];
    let cam = Camera::s1();
    let opts = |clamp| RenderOptions {
        gouraud_vertex_clamp: clamp,
        threads: 1,
        ..RenderOptions::default()
    };
    let (clamped, _) = draw_image(96, 72, &cam, &draws, &opts(true));
    let (raw, _) = draw_image(96, 72, &cam, &draws, &opts(false));
    let (mut brighter, mut same) = (0, 0);
    for (c, r) in clamped.color().iter().zip(raw.color()) {
        assert!(r.is_finite() && r.max_element() <= 1.0 && r.min_element() >= 0.0);
        assert!((*c - *r).max_element() <= 1e-6, "clamped {c} above raw {r}");
        if (*r - *c).max_element() > ONE_CODE {
            brighter += 1;
        } else {
            same += 1;
        }
    }
    assert!(
        brighter > 20,
        "{brighter} pixels brighter without the clamp"
    );
    assert!(same > brighter, "{same} pixels agree");
}

/// A framebuffer drawn frame after frame, each clear rewriting only the columns the last frame
/// wrote, ends every frame with the colours and depths of a fresh one: objects that move, grow,
/// leave the image and come back, in a one-pass mode, a two-pass mode and the incremental
/// scan line, with and without multisampling, on one and on several threads.
#[test]
fn frames_drawn_over_the_last_match_a_fresh_framebuffer() {
    use crate::{Antialias, Interpolation};

    let cam = Camera::s1();
    let (w, h) = (61, 43);
    let sphere = uv_sphere(0.35, 12, 8);
    let material = Material::s1();
    let lights = s1_lights();
    let places = [
        (Vec3::new(0.0, 0.0, 0.0), 1.0),
        (Vec3::new(0.6, 0.2, 0.0), 0.5),
        (Vec3::new(-0.9, -0.5, 0.3), 1.5),
        (Vec3::new(5.0, 0.0, 0.0), 1.0),
        (Vec3::new(0.1, 0.7, -0.4), 0.3),
        (Vec3::new(0.0, 0.0, 0.0), 2.5),
    ];
    for (mode, interpolation) in [
        (ShadingMode::Flat, Interpolation::Plane),
        (ShadingMode::Gouraud, Interpolation::Incremental),
        (ShadingMode::Phong, Interpolation::Plane),
    ] {
        for antialias in [Antialias::Off, Antialias::Msaa4] {
            for threads in [1, 3] {
                let opts = RenderOptions {
                    threads,
                    antialias,
                    interpolation,
                    background: Vec3::new(0.1, 0.2, 0.3),
                    ..RenderOptions::default()
                };
                let mut kept = Framebuffer::new(w, h).unwrap();
                for (k, &(at, scale)) in places.iter().enumerate() {
                    let mut d = item(&sphere, &material, &lights, mode);
                    d.model = Mat4::from_translation(at) * Mat4::from_scale(Vec3::splat(scale));
                    // Two draws, the second over the first, as a scene draws its objects.
                    let mut e = d;
                    e.model = Mat4::from_translation(at + Vec3::new(0.2, -0.1, 0.3)) * d.model;
                    let draws = [d, e];
                    render(&mut kept, &cam, &draws, &opts);
                    let mut fresh = Framebuffer::new(w, h).unwrap();
                    render(&mut fresh, &cam, &draws, &opts);
                    let what =
                        format!("{mode:?} {interpolation:?} {antialias} x{threads} frame {k}");
                    assert_eq!(kept.color(), fresh.color(), "{what}: colours");
                    for y in 0..h {
                        for x in 0..w {
                            let (a, b) = (kept.depth_at(x, y), fresh.depth_at(x, y));
                            assert_eq!(a.to_bits(), b.to_bits(), "{what}: depth at ({x}, {y})");
                        }
                    }
                }
            }
        }
    }
}
