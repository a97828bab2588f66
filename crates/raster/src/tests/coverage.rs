//! Fill rule and z-buffer: exact coverage of shared edges and closed meshes.

use glam::{Mat4, Vec3};
use phosphor_lighting::{LightSet, Material};

use super::support::*;
use crate::{
    Camera, DrawItem, Framebuffer, RenderOptions, ShadingMode, coverage_counts, render_fill_only,
};

const W: u32 = 32;
const H: u32 = 24;

/// A mesh of screen-space triangles (pixels), placed in the world through the S1 camera.
fn screen_mesh(cam: &Camera, tris: &[[(f64, f64); 3]]) -> TestMesh {
    let mut m = TestMesh::default();
    for t in tris {
        let base = m.positions.len() as u32;
        for &(x, y) in t {
            m.positions.push(unproject(cam, W, H, x, y, 0.5));
            m.normals.push(Vec3::Z);
        }
        m.indices.push([base, base + 1, base + 2]);
    }
    m
}

fn counts(mesh: &TestMesh, cull: bool) -> Vec<u32> {
    let (mat, set) = (Material::default(), LightSet::new(Vec3::ONE, &[]));
    let d = item(mesh, &mat, &set, ShadingMode::Flat);
    let opts = RenderOptions {
        cull_backfaces: cull,
        ..RenderOptions::default()
    };
    coverage_counts(W, H, &Camera::s1(), &[d], &opts).unwrap()
}

#[test]
fn shared_edge_through_pixel_centres_is_drawn_exactly_once() {
    let cam = Camera::s1();
    // A square split along its diagonal; corners and the diagonal on pixel centres.
    let (a, b, c, d) = ((2.5, 1.5), (22.5, 1.5), (22.5, 21.5), (2.5, 21.5));
    let quad = screen_mesh(&cam, &[[a, d, c], [a, c, b]]);
    let hits = counts(&quad, false);
    for y in 0..H {
        for x in 0..W {
            // Square [2.5, 22.5) x [1.5, 21.5): left/top edges in, right/bottom out.
            let expected = u32::from((2..22).contains(&x) && (1..21).contains(&y));
            assert_eq!(hits[(y * W + x) as usize], expected, "pixel ({x}, {y})");
        }
    }
}

#[test]
fn horizontal_shared_edge_needs_no_luck() {
    let cam = Camera::s1();
    // A quad split on its diagonal, a triangle below meeting it on the horizontal line
    // y = 10.5 (a row of centres), one to the right on the vertical line x = 20.5 (a column).
    let tris = [
        [(4.0, 2.0), (4.0, 10.5), (20.5, 10.5)],
        [(4.0, 2.0), (20.5, 10.5), (20.5, 2.0)],
        [(4.0, 10.5), (12.5, 19.0), (20.5, 10.5)],
        [(20.5, 2.0), (20.5, 10.5), (28.0, 3.0)],
    ];
    let hits = counts(&screen_mesh(&cam, &tris), false);
    assert!(hits.iter().all(|&h| h <= 1), "a pixel drawn twice");
    // Row 10 (centres on the shared edge) is drawn by the lower triangle, once.
    for x in 5..19 {
        assert_eq!(hits[(10 * W + x) as usize], 1, "({x}, 10)");
    }
    // The column x = 20 (centres on the vertical shared edge) belongs to the right triangle.
    for y in 3..9 {
        assert_eq!(hits[(y * W + 20) as usize], 1, "(20, {y})");
    }
}

#[test]
fn triangle_fan_with_random_sub_pixel_vertices_has_no_gaps_or_overlaps() {
    let cam = Camera::s1();
    let mut seed = 12345u32;
    let mut rnd = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f64 / (1u32 << 24) as f64
    };
    for _ in 0..20 {
        let centre = (16.0 + rnd(), 12.0 + rnd());
        let ring: Vec<(f64, f64)> = (0..9)
            .map(|k| {
                let a = std::f64::consts::TAU * (k as f64 + 0.3 * rnd()) / 9.0;
                (16.0 + 10.0 * a.cos() + rnd(), 12.0 + 9.0 * a.sin() + rnd())
            })
            .collect();
        let tris: Vec<_> = (0..9)
            .map(|k| [centre, ring[(k + 1) % 9], ring[k]])
            .collect();
        let hits = counts(&screen_mesh(&cam, &tris), false);
        assert!(hits.iter().all(|&h| h <= 1), "overlap");
        // Rows are convex runs: no hole inside the fan's (convex-ish, star-shaped) outline
        // near the centre.
        for y in 9..15 {
            for x in 13..19 {
                assert_eq!(hits[(y * W + x) as usize], 1, "hole at ({x}, {y})");
            }
        }
    }
}

/// Checks a convex silhouette: every row's covered pixels form one run, covered rows are
/// contiguous, and no pixel is covered twice.
fn assert_convex_silhouette(hits: &[u32], label: &str) {
    let mut rows = Vec::new();
    for y in 0..H {
        let row = &hits[(y * W) as usize..((y + 1) * W) as usize];
        assert!(
            row.iter().all(|&h| h <= 1),
            "{label}: double cover in row {y}"
        );
        let covered: Vec<usize> = (0..W as usize).filter(|&x| row[x] == 1).collect();
        if let (Some(&a), Some(&b)) = (covered.first(), covered.last()) {
            assert_eq!(
                b - a + 1,
                covered.len(),
                "{label}: background pixel inside row {y}"
            );
            rows.push(y);
        }
    }
    assert!(!rows.is_empty(), "{label}: nothing drawn");
    assert_eq!(
        rows.last().unwrap() - rows[0] + 1,
        rows.len() as u32,
        "{label}: empty row inside"
    );
}

#[test]
fn closed_mesh_at_many_sub_pixel_offsets_never_shows_background_inside() {
    let ico = icosahedron();
    // Faces are counter-clockwise seen from outside.
    for (i, t) in ico.indices.iter().enumerate() {
        let c = t.iter().map(|&k| ico.positions[k as usize]).sum::<Vec3>();
        assert!(ico.normals[3 * i].dot(c) > 0.0);
    }
    let (mat, set) = (Material::default(), LightSet::new(Vec3::ONE, &[]));
    let cam = Camera {
        eye: Vec3::new(0.0, 0.0, 4.0),
        ..Camera::s1()
    };
    for k in 0..40 {
        let off = Vec3::new(0.013 * k as f32, 0.007 * k as f32, 0.0);
        let model = Mat4::from_translation(off) * Mat4::from_rotation_y(0.1 * k as f32);
        let d = DrawItem {
            model,
            ..item(&ico, &mat, &set, ShadingMode::Flat)
        };
        let front = RenderOptions {
            cull_backfaces: true,
            ..RenderOptions::default()
        };
        let hits = coverage_counts(W, H, &cam, &[d], &front).unwrap();
        assert_convex_silhouette(&hits, &format!("offset {k}"));
        // Without culling the back faces cover the same silhouette once more: exactly twice.
        let all = coverage_counts(W, H, &cam, &[d], &RenderOptions::default()).unwrap();
        for (f, a) in hits.iter().zip(&all) {
            assert_eq!(*a, 2 * f, "offset {k}");
        }
        // And with the z-buffer the fill-only image covers exactly those pixels.
        let mut fb = Framebuffer::new(W, H).unwrap();
        render_fill_only(&mut fb, &cam, &[d], &RenderOptions::default());
        for (c, f) in fb.color().iter().zip(&hits) {
            assert_eq!(c.x, *f as f32);
        }
    }
}

#[test]
fn nearer_surface_wins_whatever_the_order() {
    let cam = Camera::s1();
    let quad = |z: f32| {
        let p =
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| Vec3::new(x, y, z));
        TestMesh {
            positions: p.to_vec(),
            normals: vec![Vec3::Z; 4],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            ..TestMesh::default()
        }
    };
    let (near, far) = (quad(0.5), quad(-0.5));
    let set = LightSet::new(Vec3::ONE, &[]);
    let red = Material::new(Vec3::X, Vec3::ZERO, Vec3::ZERO, 1.0).unwrap();
    let blue = Material::new(Vec3::Z, Vec3::ZERO, Vec3::ZERO, 1.0).unwrap();
    let a = item(&near, &red, &set, ShadingMode::Flat);
    let b = item(&far, &blue, &set, ShadingMode::Flat);
    for order in [[a, b], [b, a]] {
        let (fb, _) = draw_image(W, H, &cam, &order, &RenderOptions::default());
        assert_eq!(fb.pixel(W / 2, H / 2), Vec3::X);
    }
}
