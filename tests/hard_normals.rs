//! Hard normals: averages that cancel, interpolated normals through zero, degenerate faces
//! next to good ones. Normals computed by `phosphor-mesh` must be unit or the documented
//! fallback, never NaN; every render is finite, in `[0, 1]` and thread-count independent.

#![allow(clippy::unwrap_used)]

mod support;

use phosphor::math::glam::{Mat4, Vec3};
use phosphor::mesh::{NormalOptions, Weighting, parse_obj};
use phosphor::raster::Camera;
use support::*;

const W: u32 = 64;
const H: u32 = 48;

/// Parses `text` with S1's normal rule for files without `vn` or `s`: averaged over all faces
/// sharing a position (crease 180, uniform weights).
fn smooth(text: &str) -> phosphor::mesh::Mesh {
    parse_obj(
        text,
        "case.obj",
        None,
        &NormalOptions::smooth_all(Weighting::Uniform),
    )
    .unwrap()
}

fn assert_unit_normals(mesh: &phosphor::mesh::Mesh, label: &str) {
    for (i, n) in mesh.normals.iter().enumerate() {
        assert!(
            n.is_finite() && (n.length() - 1.0).abs() < 1e-5,
            "{label}: normal {i} is {n}"
        );
    }
}

#[test]
fn two_sided_sheet_whose_averaged_normals_cancel_stays_finite() {
    // The same quad twice, once per side: at each corner the face normals sum to zero.
    let obj = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\nf 4 3 2 1\n";
    let mesh = smooth(obj);
    assert_unit_normals(&mesh, "sheet");
    // Each side keeps a normal on its own side (never one pointing into the other face).
    for (t, tri) in mesh.indices.iter().enumerate() {
        let face = mesh.face_normal(t).unwrap();
        for &i in tri {
            assert!(mesh.normals[i as usize].dot(face) > 0.0, "triangle {t}");
        }
    }
    let mesh: TriMesh = mesh.into();
    let hits = coverage(W, H, &Camera::s1(), &mesh, Mat4::IDENTITY);
    assert!(hits.iter().all(|&h| h == 0 || h == 2), "one layer per side");
    render_all_modes(W, H, &mesh, &Setup::default(), "sheet");
}

#[test]
fn vertex_whose_face_normals_almost_cancel_gets_a_unit_normal() {
    // A tent folded until its two faces nearly lie on each other (1e-3 rad and 1e-6 rad
    // apart): the ridge vertices' face normals sum to almost zero.
    for gap in [1e-3f32, 1e-6] {
        let (c, s) = (gap.cos(), gap.sin());
        let obj = format!(
            "v 0 -1 0\nv 0 1 0\nv 1 -1 0\nv 1 1 0\nv {c} -1 {s}\nv {c} 1 {s}\n\
             f 1 3 4 2\nf 1 2 6 5\n"
        );
        let mesh = smooth(&obj);
        assert_unit_normals(&mesh, &format!("gap {gap}"));
        render_all_modes(
            W,
            H,
            &mesh.into(),
            &Setup::default(),
            &format!("tent {gap}"),
        );
    }
}

#[test]
fn interpolated_normals_through_zero_give_finite_pixels() {
    // Opposite normals at the ends of the bottom edge: the interpolated normal is zero at its
    // midpoint, which lies on a pixel centre, and tiny all along the column above it.
    let cam = Camera::s1();
    let at = |x, y| unproject(&cam, W, H, x, y, 0.5);
    let mut mesh = TriMesh::default();
    mesh.push_triangle(
        [at(8.5, 40.5), at(56.5, 40.5), at(32.5, 4.5)],
        [Vec3::X, -Vec3::X, Vec3::Z],
    );
    // And a triangle with all three normals summing to zero at its centroid.
    let third = |a: f32| Vec3::new(a.to_radians().cos(), a.to_radians().sin(), 0.0);
    mesh.push_triangle(
        [at(2.0, 2.0), at(20.0, 2.0), at(2.0, 20.0)],
        [third(0.0), third(120.0), third(240.0)],
    );
    for (mode, fb, _) in render_all_modes(W, H, &mesh, &Setup::default(), "through zero") {
        // The zero normal is shaded as ambient only, never black from a NaN or a sparkle:
        // every covered pixel is at least the ambient term ka * Ia = 0.1.
        for (c, z) in fb.color().iter().zip(fb.depth()) {
            if *z < 1.0 {
                assert!(c.min_element() >= 0.1 - 1e-6, "{mode}: {c}");
            }
        }
    }
}

#[test]
fn degenerate_faces_next_to_good_ones_leave_the_good_normals_alone() {
    // A flat quad, plus zero-area faces using its vertices: a repeated vertex, a collinear
    // triple along an edge, and a face through a duplicate of a corner. The averaged normals
    // must stay exactly the quad's +Z.
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0 0\nv 0 0 0\n\
               f 1 2 3 4\nf 1 1 3\nf 1 5 2\nf 6 1 3\nf 2 2 2\n";
    let mesh = smooth(obj);
    assert_unit_normals(&mesh, "degenerate neighbours");
    for (i, n) in mesh.normals.iter().enumerate() {
        assert!((*n - Vec3::Z).length() < 1e-6, "normal {i} is {n}");
    }
    // Drawn: the quad's pixels exactly once, the degenerate faces nowhere.
    let setup = Setup {
        model: Mat4::from_translation(Vec3::new(-0.5, -0.5, 0.0)),
        ..Setup::default()
    };
    let mesh: TriMesh = mesh.into();
    let hits = coverage(W, H, &setup.camera, &mesh, setup.model);
    assert!(hits.iter().all(|&h| h <= 1), "double hit");
    for (mode, _, stats) in render_all_modes(W, H, &mesh, &setup, "degenerate neighbours") {
        assert_eq!(stats.triangles_drawn, 2, "{mode}");
    }
}

#[test]
fn zero_and_non_finite_normals_in_a_mesh_view_give_finite_pixels() {
    // Normals handed straight to the rasterizer (no mesh crate): zero, NaN, infinite, huge,
    // subnormal. Each is either usable or treated as no normal (ambient only).
    let bad = [
        Vec3::ZERO,
        Vec3::NAN,
        Vec3::new(f32::INFINITY, 0.0, 0.0),
        Vec3::splat(1e30),
        Vec3::splat(1e-40),
        Vec3::new(0.0, 0.0, -1.0),
    ];
    let mut mesh = TriMesh::default();
    for (k, n) in bad.iter().enumerate() {
        let x = -1.2 + 0.4 * k as f32;
        mesh.push_triangle(
            [
                Vec3::new(x, -0.5, 0.0),
                Vec3::new(x + 0.4, -0.5, 0.0),
                Vec3::new(x + 0.2, 0.5, 0.0),
            ],
            [*n, Vec3::Z, *n],
        );
    }
    render_all_modes(W, H, &mesh, &Setup::default(), "bad normals");
}
