//! Hard geometry: degenerate, tiny, huge, near-plane and edge-aligned triangles. Every render
//! is checked finite, in `[0, 1]` and identical for 1 and 2 threads (`support::render_checked`);
//! coverage cases count every pixel exactly (no crack, no double hit).

#![allow(clippy::unwrap_used)]

mod support;

use phosphor::math::glam::{Mat4, Vec3};
use phosphor::mesh::primitives;
use phosphor::raster::Camera;
use support::*;

const W: u32 = 64;
const H: u32 = 48;

#[test]
fn zero_area_triangles_cover_nothing_and_shade_nothing() {
    let cam = Camera::s1();
    let (a, b) = (Vec3::new(-0.5, -0.4, 0.0), Vec3::new(0.6, 0.3, 0.0));
    let repeated = TriMesh::soup(&[
        [a, a, b], // repeated vertex
        [a, b, b], // repeated vertex, other corner
        [a, a, a], // a point
    ]);
    // Collinear in the world; after projection and 1/256-pixel snapping they may keep a
    // sliver of area, but must cover no pixel centre on this line.
    let collinear = TriMesh::soup(&[
        [a, (a + b) * 0.5, b],
        [a, b, a + (b - a) * 3.0], // the middle vertex last
    ]);
    for (mesh, label) in [(&repeated, "repeated"), (&collinear, "collinear")] {
        let hits = coverage(W, H, &cam, mesh, Mat4::IDENTITY);
        assert!(hits.iter().all(|&h| h == 0), "{label}");
        for (mode, fb, stats) in render_all_modes(W, H, mesh, &Setup::default(), label) {
            assert_eq!(stats.pixels_shaded, 0, "{label} {mode}");
            assert!(
                fb.color().iter().all(|c| *c == Vec3::ZERO),
                "{label} {mode}"
            );
            if label == "repeated" {
                assert_eq!(stats.triangles_drawn, 0, "{label} {mode}: set up");
            }
        }
    }
}

#[test]
fn needles_and_slivers_tile_a_rectangle_exactly() {
    // A rectangle cut into a fan of needles from its top-left corner to 40 points along the
    // bottom and right edges, plus slivers one 1/64 pixel wide along the top edge.
    let cam = Camera::s1();
    let rect = (4.25, 6.25, 60.25, 42.25);
    let (x0, y0, x1, y1) = rect;
    let mut tris = Vec::new();
    let mut rim: Vec<(f64, f64)> = (0..=20)
        .map(|k| (x0 + (x1 - x0) * f64::from(k) / 20.0, y1))
        .collect();
    rim.extend((1..=20).map(|k| (x1, y1 - (y1 - y0) * f64::from(k) / 20.0)));
    // The last rim point is the top-right corner; the fan stops one short of it so the
    // remaining top strip can be cut into slivers.
    let apex = (x0, y0);
    let last = rim.len() - 1;
    for k in 0..last - 1 {
        tris.push([apex, rim[k], rim[k + 1]]);
    }
    // Top strip: between the apex, rim[last - 1] and the top-right corner, cut at 1/64-pixel
    // steps along the top edge into slivers.
    let below = rim[last - 1];
    let steps = 64;
    for k in 0..steps {
        let xa = x0 + (x1 - x0) * f64::from(k) / f64::from(steps);
        let xb = x0 + (x1 - x0) * f64::from(k + 1) / f64::from(steps);
        tris.push([(xa, y0), below, (xb, y0)]);
    }
    let mesh = screen_mesh(&cam, W, H, &tris);
    let hits = coverage(W, H, &cam, &mesh, Mat4::IDENTITY);
    assert_coverage(&hits, W, |x, y| in_rect(x, y, rect), "needles");
    render_all_modes(W, H, &mesh, &Setup::default(), "needles");
}

#[test]
fn vertices_on_pixel_centres_and_edges_give_exact_coverage() {
    // A grid of quads (horizontal and vertical edges only) whose corners lie on pixel
    // centres (x.5) in one image and on pixel edges (integers) in the other; the top-left rule
    // puts every pixel in exactly one quad.
    let cam = Camera::s1();
    for (offset, label) in [(0.5, "centres"), (0.0, "edges")] {
        let xs: Vec<f64> = [3.0, 10.0, 11.0, 30.0, 61.0].map(|x| x + offset).to_vec();
        let ys: Vec<f64> = [2.0, 9.0, 10.0, 33.0, 45.0].map(|y| y + offset).to_vec();
        let mut tris = Vec::new();
        for i in 0..xs.len() - 1 {
            for j in 0..ys.len() - 1 {
                let (a, b) = ((xs[i], ys[j]), (xs[i + 1], ys[j]));
                let (c, d) = ((xs[i + 1], ys[j + 1]), (xs[i], ys[j + 1]));
                // Alternate diagonals so both orientations of the shared diagonal occur.
                if (i + j) % 2 == 0 {
                    tris.extend([[a, d, c], [a, c, b]]);
                } else {
                    tris.extend([[a, d, b], [b, d, c]]);
                }
            }
        }
        let mesh = screen_mesh(&cam, W, H, &tris);
        let hits = coverage(W, H, &cam, &mesh, Mat4::IDENTITY);
        let rect = (xs[0], ys[0], xs[xs.len() - 1], ys[ys.len() - 1]);
        assert_coverage(&hits, W, |x, y| in_rect(x, y, rect), label);
        render_all_modes(W, H, &mesh, &Setup::default(), label);
    }
}

#[test]
fn right_triangles_with_horizontal_and_vertical_edges_meet_without_cracks() {
    // Eight right triangles around a centre on a pixel centre: the inner edges run exactly
    // along a row and a column of pixel centres, the outer ones on pixel centres too.
    let cam = Camera::s1();
    let (cx, cy) = (32.5, 24.5);
    let (l, t, r, b) = (12.5, 8.5, 52.5, 40.5);
    let tris = [
        [(l, t), (l, cy), (cx, cy)],
        [(l, t), (cx, cy), (cx, t)],
        [(cx, t), (cx, cy), (r, t)],
        [(r, t), (cx, cy), (r, cy)],
        [(l, cy), (l, b), (cx, cy)],
        [(cx, cy), (l, b), (cx, b)],
        [(cx, cy), (cx, b), (r, b)],
        [(cx, cy), (r, b), (r, cy)],
    ];
    let mesh = screen_mesh(&cam, W, H, &tris);
    let hits = coverage(W, H, &cam, &mesh, Mat4::IDENTITY);
    assert_coverage(&hits, W, |x, y| in_rect(x, y, (l, t, r, b)), "right");
}

#[test]
fn t_junction_vertex_on_a_shared_edge_leaves_no_crack() {
    // The square's diagonal is one edge of the upper triangle; below it, two triangles meet at
    // the diagonal's midpoint M (a T-junction: M is not a vertex of the upper triangle). M
    // lies on the 1/256-pixel grid, exactly on the edge.
    let cam = Camera::s1();
    let rect = (4.25, 4.25, 60.25, 44.25);
    let (x0, y0, x1, y1) = rect;
    let (tl, tr, br, bl) = ((x0, y0), (x1, y0), (x1, y1), (x0, y1));
    let m = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let mesh = screen_mesh(&cam, W, H, &[[tl, br, tr], [tl, bl, m], [m, bl, br]]);
    let hits = coverage(W, H, &cam, &mesh, Mat4::IDENTITY);
    assert_coverage(&hits, W, |x, y| in_rect(x, y, rect), "T-junction");
    render_all_modes(W, H, &mesh, &Setup::default(), "T-junction");
}

/// A closed mesh: the shipped UV sphere of radius 1 (bit-identical seam and poles).
fn sphere() -> TriMesh {
    primitives::uv_sphere(1.0, 16, 8).into()
}

/// Asserts a closed mesh drawn without culling covers each pixel an even number of times
/// (front and back layer), at most twice for a convex one, and the covered rows are single runs.
fn assert_closed_convex_coverage(hits: &[u32], w: u32, label: &str) {
    assert!(hits.iter().any(|&h| h > 0), "{label}: nothing drawn");
    for (y, row) in hits.chunks(w as usize).enumerate() {
        assert!(
            row.iter().all(|&h| h == 0 || h == 2),
            "{label}: row {y} has a crack or a double hit: {row:?}"
        );
        let covered: Vec<usize> = (0..row.len()).filter(|&x| row[x] > 0).collect();
        if let (Some(a), Some(b)) = (covered.first(), covered.last()) {
            assert_eq!(b - a + 1, covered.len(), "{label}: hole in row {y}");
        }
    }
}

#[test]
fn closed_mesh_at_1e6_and_1e_minus_6_scale_covers_like_at_unit_scale() {
    // The same sphere and camera, everything scaled by s: the picture must not change (up to
    // rounding at the silhouette), the coverage stays closed, the pixels finite.
    let mesh = sphere();
    let unit_cam = Camera {
        eye: Vec3::new(0.3, 0.2, 3.0),
        near: 0.5,
        far: 6.0,
        ..Camera::s1()
    };
    let unit = coverage(W, H, &unit_cam, &mesh, Mat4::IDENTITY);
    let unit_count = unit.iter().filter(|&&h| h > 0).count();
    for s in [1e-6f32, 1e-3, 1e3, 1e6] {
        let cam = Camera {
            eye: unit_cam.eye * s,
            target: unit_cam.target * s,
            near: unit_cam.near * s,
            far: unit_cam.far * s,
            ..unit_cam
        };
        let model = Mat4::from_scale(Vec3::splat(s));
        let label = format!("scale {s:e}");
        let hits = coverage(W, H, &cam, &mesh, model);
        assert_closed_convex_coverage(&hits, W, &label);
        let count = hits.iter().filter(|&&h| h > 0).count();
        let changed = hits
            .iter()
            .zip(&unit)
            .filter(|(a, b)| (**a > 0) != (**b > 0))
            .count();
        assert!(
            changed <= unit_count / 50,
            "{label}: {changed} pixels differ from unit scale ({count} vs {unit_count})"
        );
        let setup = Setup {
            camera: cam,
            model,
            ..Setup::default()
        };
        for (mode, fb, _) in render_all_modes(W, H, &mesh, &setup, &label) {
            assert_eq!(
                covered_pixels(&fb),
                count,
                "{label} {mode}: depth test lost pixels"
            );
        }
    }
}

#[test]
fn unit_mesh_a_million_units_from_the_origin_stays_finite() {
    // Coordinates near 1e6 keep only ~0.06 of f32 precision: the shape may be crushed, but
    // nothing may turn NaN, Inf or depend on the thread count.
    let mesh = sphere();
    let far_away = Vec3::new(1e6, -1e6, 1e6);
    let setup = Setup {
        camera: Camera {
            eye: far_away + Vec3::new(0.0, 0.0, 3.0),
            target: far_away,
            ..Camera::s1()
        },
        model: Mat4::from_translation(far_away),
        ..Setup::default()
    };
    for (mode, fb, _) in render_all_modes(W, H, &mesh, &setup, "far from origin") {
        assert!(covered_pixels(&fb) > 0, "{mode}: the sphere vanished");
    }
}

#[test]
fn quad_crossing_the_near_plane_is_clipped_without_cracks() {
    // A floor quad from far ahead to behind the camera: both triangles cross the near plane,
    // the clipped pieces still share the diagonal exactly once.
    let cam = Camera::s1();
    let y = -0.5;
    let p = [
        Vec3::new(-2.0, y, -6.0),
        Vec3::new(2.0, y, -6.0),
        Vec3::new(2.0, y, 8.0),
        Vec3::new(-2.0, y, 8.0),
    ];
    let mesh = TriMesh {
        positions: p.to_vec(),
        normals: vec![Vec3::Y; 4],
        indices: vec![[0, 3, 2], [0, 2, 1]],
    };
    let hits = coverage(W, H, &cam, &mesh, Mat4::IDENTITY);
    assert!(hits.iter().all(|&h| h <= 1), "double hit on the diagonal");
    let mut rows = 0;
    for (y, row) in hits.chunks(W as usize).enumerate() {
        let covered: Vec<usize> = (0..row.len()).filter(|&x| row[x] > 0).collect();
        if let (Some(a), Some(b)) = (covered.first(), covered.last()) {
            assert_eq!(b - a + 1, covered.len(), "crack in row {y}");
            rows += 1;
        }
    }
    // The floor reaches the bottom of the image (it passes under the camera).
    assert!(hits[((H - 1) * W + W / 2) as usize] == 1 && rows >= H as usize / 3);
    let setup = Setup::default();
    for (mode, fb, _) in render_all_modes(W, H, &mesh, &setup, "near plane") {
        assert_eq!(
            covered_pixels(&fb),
            hits.iter().filter(|&&h| h > 0).count(),
            "{mode}"
        );
    }
}

#[test]
fn closed_mesh_around_the_camera_covers_every_pixel_exactly_once() {
    // The eye inside a closed box and inside a sphere: every viewing ray leaves through
    // exactly one face, so without culling each pixel is hit exactly once, and shading (lights
    // inside too) stays finite.
    let cam = Camera {
        eye: Vec3::new(0.1, -0.2, 0.05),
        target: Vec3::new(1.0, 0.3, -2.0),
        ..Camera::s1()
    };
    let box_mesh: TriMesh = primitives::cube(2.0).into();
    let sphere_mesh: TriMesh = primitives::uv_sphere(3.0, 24, 12).into();
    for (mesh, label) in [(box_mesh, "box"), (sphere_mesh, "sphere")] {
        let hits = coverage(W, H, &cam, &mesh, Mat4::IDENTITY);
        assert_coverage(&hits, W, |_, _| 1, label);
        let setup = Setup {
            camera: cam,
            ..Setup::default()
        };
        for (mode, fb, _) in render_all_modes(W, H, &mesh, &setup, label) {
            assert_eq!(covered_pixels(&fb), (W * H) as usize, "{label} {mode}");
        }
    }
}

#[test]
fn triangle_behind_the_camera_draws_nothing() {
    let cam = Camera::s1();
    let behind = TriMesh::soup(&[
        // Wholly behind the eye (z > 3), facing it and not.
        [
            Vec3::new(-1.0, -1.0, 4.0),
            Vec3::new(1.0, -1.0, 4.0),
            Vec3::new(0.0, 1.0, 4.0),
        ],
        [
            Vec3::new(-1.0, -1.0, 5.0),
            Vec3::new(0.0, 1.0, 5.0),
            Vec3::new(1.0, -1.0, 5.0),
        ],
        // In the eye's plane (w = 0 for every vertex).
        [
            Vec3::new(-1.0, -1.0, 3.0),
            Vec3::new(1.0, -1.0, 3.0),
            Vec3::new(0.0, 1.0, 3.0),
        ],
        // Between the eye and the near plane.
        [
            Vec3::new(-0.01, -0.01, 2.95),
            Vec3::new(0.01, -0.01, 2.95),
            Vec3::new(0.0, 0.01, 2.95),
        ],
    ]);
    assert!(
        coverage(W, H, &cam, &behind, Mat4::IDENTITY)
            .iter()
            .all(|&h| h == 0)
    );
    for (mode, fb, stats) in render_all_modes(W, H, &behind, &Setup::default(), "behind") {
        assert_eq!(stats.triangles_drawn, 0, "{mode}");
        assert!(fb.color().iter().all(|c| *c == Vec3::ZERO), "{mode}");
    }
}

#[test]
fn huge_screen_filling_triangles_cover_every_pixel_exactly_once() {
    // Triangles far larger than the screen (up to 1e30 units across) in front of the camera:
    // guard-band clipping must keep the fixed-point set-up exact.
    let cam = Camera::s1();
    for s in [1e2f32, 1e4, 1e6, 1e12, 1e20, 1e30] {
        let mesh = TriMesh::soup(&[[
            Vec3::new(-s, -s, 0.0),
            Vec3::new(s, -s, 0.0),
            Vec3::new(0.0, s, 0.0),
        ]]);
        let label = format!("size {s:e}");
        let hits = coverage(W, H, &cam, &mesh, Mat4::IDENTITY);
        assert_coverage(&hits, W, |_, _| 1, &label);
        for (mode, fb, _) in render_all_modes(W, H, &mesh, &Setup::default(), &label) {
            assert_eq!(covered_pixels(&fb), (W * H) as usize, "{label} {mode}");
        }
    }
}
