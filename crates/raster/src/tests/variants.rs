//! The variants of the approximate modes: Bishop and Weimer 1986's Taylor fast Phong (against
//! the six-point fit and the reference) and Gouraud 1971's incremental scan line (against the
//! plane evaluation).

use glam::Vec3;
use phosphor_lighting::{Light, LightSet, Material};

use super::support::*;
use crate::{
    Camera, FAST_PHONG_TOLERANCE, FastPhongMethod, Framebuffer, Interpolation, RenderOptions,
    RenderStats, ShadingMode,
};

const ONE_CODE: f32 = 1.0 / 255.0;

fn worst(a: &Framebuffer, b: &Framebuffer) -> f32 {
    diffs(a, b).into_iter().fold(0.0, f32::max)
}

/// One triangle whose screen corners are `corners` (pixels) at the depth of `cam`'s target, its vertex normals the face normal (towards the eye) tilted by `spread`.
fn screen_triangle(
    cam: &Camera,
    (w, h): (u32, u32),
    corners: [(f64, f64); 3],
    spread: f32,
) -> TestMesh {
    // At the depth of the camera's target.
    let clip = cam.view_proj(w as f32 / h as f32) * cam.target.extend(1.0);
    let p = corners.map(|(x, y)| unproject(cam, w, h, x, y, clip.z / clip.w));
    let mut face = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
    if face.dot(cam.eye - p[0]) < 0.0 {
        face = -face;
    }
    let tilt = [Vec3::X, Vec3::Y, -Vec3::X - Vec3::Y];
    TestMesh {
        positions: p.to_vec(),
        normals: tilt.map(|t| (face + t * spread).normalize()).to_vec(),
        indices: vec![[0, 1, 2]],
        ..TestMesh::default()
    }
}

fn fast(method: FastPhongMethod) -> RenderOptions {
    RenderOptions {
        fast_phong: method,
        ..RenderOptions::default()
    }
}

fn polynomial_triangles(s: &RenderStats) -> u64 {
    s.triangles_drawn - s.fallbacks
}

#[test]
fn taylor_polynomial_draws_triangles_of_every_size_class_within_its_bound() {
    let (w, h) = (640, 480);
    // Bishop and Weimer's setting: a distant viewer (S1's camera with a 0.5 degree field of
    // view) and a directional light, S1's material (highlight on).
    let cam = Camera {
        fov_y_deg: 0.5,
        ..Camera::s1()
    };
    let set = LightSet::new(
        Vec3::splat(0.1),
        &[Light::directional(Vec3::new(-0.3, -0.2, -1.0), Vec3::ONE).unwrap()],
    );
    let mat = Material::s1();
    // Right triangles with legs of 2, 10, 32 and 320 pixels: areas 2, 50, 512, 51 200.
    for (leg, spread) in [(2.0, 0.02), (10.0, 0.02), (32.0, 0.02), (320.0, 0.01)] {
        let (x0, y0) = (100.3, 80.6);
        let corners = [(x0, y0), (x0 + leg, y0), (x0, y0 + leg)];
        let tri = screen_triangle(&cam, (w, h), corners, spread);
        let draw = |mode, opts: &RenderOptions| {
            draw_image(w, h, &cam, &[item(&tri, &mat, &set, mode)], opts)
        };
        let (taylor, stats) = draw(ShadingMode::FastPhong, &fast(FastPhongMethod::Taylor));
        let (reference, _) = draw(ShadingMode::Reference, &RenderOptions::default());
        let (phong, _) = draw(ShadingMode::Phong, &RenderOptions::default());
        let err = worst(&taylor, &reference);
        let phong_err = worst(&phong, &reference);
        println!(
            "leg {leg:>5} px: {} px shaded, polynomial {} of {}, worst vs reference {:.2} codes (phong {:.2})",
            stats.pixels_shaded,
            polynomial_triangles(&stats),
            stats.triangles_drawn,
            err * 255.0,
            phong_err * 255.0
        );
        assert_eq!(stats.triangles_drawn, 1, "leg {leg}");
        assert_eq!(polynomial_triangles(&stats), 1, "leg {leg}: fell back");
        assert!(stats.pixels_shaded > 0, "leg {leg}");
        // The bound the set-up checks (one code at ten points) plus phong's own error against
        // the reference, with one code for the stretch between the checks.
        assert!(
            err <= 2.0 * FAST_PHONG_TOLERANCE + phong_err,
            "leg {leg}: {err}"
        );
    }
}

#[test]
fn taylor_fast_phong_stays_within_its_bound_of_reference_on_the_s1_sphere() {
    // S1's sphere, lights and material (point lights with attenuation: the light directions
    // and the viewer are taken at each triangle's centroid, and the checks refuse where that
    // shows).
    let sphere = uv_sphere(1.0, 128, 80);
    let (set, mat) = (s1_lights(), Material::s1());
    let cam = Camera::s1();
    let draw = |mode, opts: &RenderOptions| {
        draw_image(320, 240, &cam, &[item(&sphere, &mat, &set, mode)], opts)
    };
    let (reference, _) = draw(ShadingMode::Reference, &RenderOptions::default());
    let (phong, _) = draw(ShadingMode::Phong, &RenderOptions::default());
    let phong_err = worst(&phong, &reference);
    for method in FastPhongMethod::ALL {
        let (img, stats) = draw(ShadingMode::FastPhong, &fast(method));
        let err = worst(&img, &reference);
        println!(
            "{method}: {} of {} pieces refused (exact phong), worst vs reference {:.2} codes (phong {:.2})",
            stats.fallbacks,
            stats.triangles_drawn,
            err * 255.0,
            phong_err * 255.0
        );
        assert!(
            err <= 2.0 * FAST_PHONG_TOLERANCE + phong_err,
            "{method}: {err}"
        );
        if method == FastPhongMethod::Taylor {
            // Most of the sphere is drawn by the polynomials (the Taylor set-up is tried on
            // every triangle, so the pieces not refused are the polynomial ones).
            assert!(
                polynomial_triangles(&stats) * 2 > stats.triangles_drawn,
                "{stats:?}"
            );
        }
    }
}

#[test]
fn incremental_scan_line_covers_the_same_pixels_with_the_same_depth() {
    let (set, mat) = (s1_lights(), Material::s1());
    let cam = Camera::s1();
    for sphere in [uv_sphere(1.0, 128, 80), uv_sphere(1.0, 12, 8)] {
        for mode in [ShadingMode::Gouraud, ShadingMode::Phong] {
            for perspective_correct in [true, false] {
                let draw = |interpolation| {
                    let opts = RenderOptions {
                        interpolation,
                        perspective_correct,
                        ..RenderOptions::default()
                    };
                    draw_image(320, 240, &cam, &[item(&sphere, &mat, &set, mode)], &opts)
                };
                let (plane, ps) = draw(Interpolation::Plane);
                let (inc, is) = draw(Interpolation::Incremental);
                assert_eq!(ps.pixels_shaded, is.pixels_shaded, "{mode}");
                let bits =
                    |fb: &Framebuffer| fb.depth().iter().map(|d| d.to_bits()).collect::<Vec<_>>();
                assert!(bits(&plane) == bits(&inc), "{mode}: depth differs");
                let err = worst(&plane, &inc);
                println!(
                    "{mode} ({} triangles, perspective {perspective_correct}): incremental vs plane worst {:.3} codes",
                    sphere.indices.len(),
                    err * 255.0
                );
                // On ordinary triangles the f32 walk stays within a code of the planes.
                assert!(err <= ONE_CODE, "{mode}: {err}");
            }
        }
    }
}
