//! The lecture notes' formulas, each against a value computed by hand or its closed form:
//! flat shading at the polygon's centre, and Gouraud 1971's screen-space interpolation
//! `I4 = (y4 - y2)/(y1 - y2) I1 + (y1 - y4)/(y1 - y2) I2`, `I5` likewise on the other edge,
//! `Ip = (x5 - xp)/(x5 - x4) I4 + (xp - x4)/(x5 - x4) I5`.

#![allow(clippy::unwrap_used)]

mod support;

use phosphor::lighting::{Attenuation, Effects, Light, LightSet, Material, shade};
use phosphor::math::glam::{Mat4, Vec3};
use phosphor::raster::{Camera, Framebuffer, RenderOptions, ShadingMode, render};
use support::*;

#[test]
fn flat_shades_the_whole_facet_with_the_model_at_its_centroid() {
    // Triangle (-0.6, -0.6, 0), (0.9, -0.6, 0), (-0.6, 0.9, 0): centroid (-0.1, -0.1, 0), face
    // normal +z. Point light at (-0.1, 1.4, 2): from the centroid (0, 1.5, 2), d = 2.5,
    // L = (0, 0.6, 0.8), N.L = 0.8; f = 1/(1 + d) = 2/7.
    // I = ka Ia + f Il kd N.L = 0.1 * 0.5 + (2/7) * 1.5 * 0.6 * 0.8 = 0.05 + 0.72 * 2/7.
    let expected = 0.05 + 0.72 * 2.0 / 7.0; // 0.255714...
    let light = Light::point(Vec3::new(-0.1, 1.4, 2.0), Vec3::splat(1.5))
        .unwrap()
        .with_attenuation(Attenuation::Offset { k: 1.0 })
        .unwrap();
    let setup = Setup {
        lights: LightSet::new(Vec3::splat(0.5), &[light]),
        material: Material::new(Vec3::splat(0.1), Vec3::splat(0.6), Vec3::ZERO, 1.0).unwrap(),
        camera: Camera::s1(),
        model: Mat4::IDENTITY,
    };
    // Vertex normals tilted away from the face normal: flat must not read them.
    let mut mesh = TriMesh::default();
    mesh.push_triangle(
        [
            Vec3::new(-0.6, -0.6, 0.0),
            Vec3::new(0.9, -0.6, 0.0),
            Vec3::new(-0.6, 0.9, 0.0),
        ],
        [
            Vec3::new(0.5, 0.0, 1.0).normalize(),
            Vec3::new(0.0, 0.5, 1.0).normalize(),
            Vec3::new(-0.5, 0.0, 1.0).normalize(),
        ],
    );
    let (fb, _) = render_checked(
        96,
        72,
        &setup.camera,
        &[draw(&mesh, &setup, ShadingMode::Flat)],
        "flat facet",
    );
    let covered: Vec<Vec3> = fb
        .color()
        .iter()
        .zip(fb.depth())
        .filter(|(_, z)| **z < 1.0)
        .map(|(c, _)| *c)
        .collect();
    assert!(covered.len() > 200, "{} pixels", covered.len());
    for c in covered {
        assert!(
            (c - Vec3::splat(expected)).abs().max_element() < 1e-6,
            "{c} against {expected}"
        );
    }
}

#[test]
fn screen_space_gouraud_is_the_notes_scan_line_closed_form() {
    let (w, h) = (128u32, 96u32);
    let camera = Camera::s1();
    // Vertices on exact 1/256 pixel positions, 1 at the top, 2 lower left, 3 lower right.
    let xy = [(40.25, 8.5), (10.75, 80.0), (118.5, 60.25)];
    let mut mesh = screen_mesh(&camera, w, h, &[xy]);
    // Different normals give different vertex intensities under one directional light.
    mesh.normals = vec![
        Vec3::new(0.3, 0.2, 1.0).normalize(),
        Vec3::new(-0.6, -0.1, 1.0).normalize(),
        Vec3::new(0.1, -0.7, 1.0).normalize(),
    ];
    let setup = Setup {
        lights: LightSet::new(
            Vec3::splat(0.2),
            &[Light::directional(Vec3::new(-0.4, -0.3, -1.0), Vec3::ONE).unwrap()],
        ),
        material: Material::new(Vec3::splat(0.1), Vec3::splat(0.7), Vec3::ZERO, 1.0).unwrap(),
        camera,
        model: Mat4::IDENTITY,
    };
    const FX: u32 = Effects::ALL.bits();
    let eye = camera.eye;
    let i: Vec<f64> = (0..3)
        .map(|k| {
            f64::from(
                shade::<FX>(
                    &setup.lights,
                    &setup.material,
                    mesh.positions[k],
                    mesh.normals[k],
                    eye,
                )
                .x,
            )
        })
        .collect();
    assert!(i[0] != i[1] && i[1] != i[2], "{i:?}");
    let mut fb = Framebuffer::new(w, h).unwrap();
    render(
        &mut fb,
        &camera,
        &[draw(&mesh, &setup, ShadingMode::Gouraud)],
        &RenderOptions {
            perspective_correct: false,
            threads: 1,
            ..RenderOptions::default()
        },
    );
    let [(x1, y1), (x2, y2), (x3, y3)] = xy;
    let (i1, i2, i3) = (i[0], i[1], i[2]);
    let mut compared = 0;
    for py in 0..h {
        let ys = f64::from(py) + 0.5;
        if !(ys > y1 && ys < y3) {
            // Rows crossing edges 1-2 and 1-3 only (above vertex 3), the notes' figure.
            continue;
        }
        // I4 on edge 1-2, I5 on edge 1-3 at scan line ys.
        let x4 = x1 + (x2 - x1) * (ys - y1) / (y2 - y1);
        let i4 = (ys - y2) / (y1 - y2) * i1 + (y1 - ys) / (y1 - y2) * i2;
        let x5 = x1 + (x3 - x1) * (ys - y1) / (y3 - y1);
        let i5 = (ys - y3) / (y1 - y3) * i1 + (y1 - ys) / (y1 - y3) * i3;
        for px in 0..w {
            let xp = f64::from(px) + 0.5;
            if fb.depth()[(py * w + px) as usize] >= 1.0 {
                continue;
            }
            let ip = (x5 - xp) / (x5 - x4) * i4 + (xp - x4) / (x5 - x4) * i5;
            let got = f64::from(fb.color()[(py * w + px) as usize].x);
            assert!(
                (got - ip).abs() < 2e-5,
                "pixel ({px}, {py}): {got} against Ip = {ip} (I4 {i4} at {x4}, I5 {i5} at {x5})"
            );
            compared += 1;
        }
    }
    assert!(compared > 500, "{compared} pixels compared");
}
