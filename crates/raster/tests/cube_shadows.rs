//! Cube maps of a point light surrounded by casters: every face casts where it should, a
//! shadow stays whole across a seam between faces, faces with nothing to cast are not made,
//! and the lane lookup gives each lane its own face's one-lane value.
#![allow(clippy::unwrap_used)]

mod common;

use common::{extents, lanes4, view};
use glam::{Mat4, Vec3};
use phosphor_mesh::primitives::uv_sphere;
use phosphor_raster::RenderOptions;
use phosphor_raster::shadow::{Caster, CubeFace, CubeShadow, NoMap, ShadowMap, Sphere, fit_cube};

/// Radius of each caster ball, one unit from the light.
const BALL: f32 = 0.2;

/// Balls one unit from a light at the origin along `dirs`, walls (receiver spheres) three units
/// out along every axis, the cube fitted and its faces rendered at `size`.
fn cube_of(dirs: &[Vec3], size: u32) -> (Vec<ShadowMap>, Vec<CubeFace>) {
    let ball = uv_sphere(BALL, 32, 16);
    let models: Vec<Mat4> = dirs
        .iter()
        .map(|d| Mat4::from_translation(d.normalize()))
        .collect();
    let casters: Vec<Sphere> = dirs
        .iter()
        .map(|d| Sphere {
            center: d.normalize(),
            radius: BALL,
        })
        .collect();
    let walls: Vec<Sphere> = CubeFace::ALL
        .iter()
        .map(|f| Sphere {
            center: f.axis() * 3.0,
            radius: 1.5,
        })
        .collect();
    let faces = fit_cube(Vec3::ZERO, &extents(&casters), &extents(&walls), None, size).unwrap();
    let maps = faces
        .iter()
        .map(|f| {
            let list: Vec<Caster> = f
                .casters
                .iter()
                .map(|&i| Caster {
                    mesh: view(&ball),
                    model: models[i],
                })
                .collect();
            ShadowMap::render(&f.view, size, &list, &RenderOptions::default()).unwrap()
        })
        .collect();
    (maps, faces.iter().map(|f| f.face).collect())
}

fn lookup<'a>(maps: &'a [ShadowMap], faces: &[CubeFace]) -> CubeShadow<'a> {
    let mut slots = [None; 6];
    for (m, f) in maps.iter().zip(faces) {
        slots[f.index()] = Some(m);
    }
    CubeShadow {
        position: Vec3::ZERO,
        faces: slots,
    }
}

/// A unit vector perpendicular to `a`.
fn across(a: Vec3) -> Vec3 {
    a.any_orthonormal_vector()
}

#[test]
fn every_face_casts_behind_its_caster_and_nowhere_else() {
    let axes: Vec<Vec3> = CubeFace::ALL.iter().map(|f| f.axis()).collect();
    for size in [64u32, 256] {
        let (maps, faces) = cube_of(&axes, size);
        assert_eq!(faces, CubeFace::ALL, "size {size}: every face has a caster");
        let cube = lookup(&maps, &faces);
        for face in CubeFace::ALL {
            let a = face.axis();
            assert_eq!(CubeFace::of(a), face);
            // Straight behind the ball on the wall, facing the light: in the umbra (the
            // ball's shadow there is 0.6 units wide).
            let behind = a * 3.0;
            assert_eq!(cube.visibility(behind, -a), 0.0, "size {size}, {face}");
            // Well off the shadow (the umbra's half-width is 0.6 at the wall): lit.
            let side = behind + across(a) * 1.5;
            assert_eq!(cube.visibility(side, -a), 1.0, "size {size}, {face} side");
            // Between the light and the ball: lit (the ball is farther).
            assert_eq!(
                cube.visibility(a * 0.5, -a),
                1.0,
                "size {size}, {face} before"
            );
        }
    }
}

#[test]
fn a_shadow_across_a_seam_does_not_leak() {
    // A ball straddling the edge between the +x and +y faces (and one near the corner of +x,
    // +y and +z): on the wall behind it, points just either side of the seam are both dark.
    let seam = Vec3::new(1.0, 1.0, 0.0).normalize();
    let corner = Vec3::new(1.0, 1.0, 1.0).normalize();
    for size in [64u32, 512] {
        let (maps, faces) = cube_of(&[seam, corner], size);
        let cube = lookup(&maps, &faces);
        for (dir, tilt) in [
            (seam, Vec3::new(0.0, 0.0, 1.0)),
            (corner, Vec3::new(1.0, -1.0, 0.0)),
        ] {
            for eps in [-0.01f32, -0.002, 0.0, 0.002, 0.01] {
                let d = (dir + Vec3::new(eps, -eps, 0.0) + tilt * eps).normalize();
                let p = d * 3.0;
                assert_eq!(
                    cube.visibility(p, -d),
                    0.0,
                    "size {size}: {p} on face {} leaks",
                    CubeFace::of(p)
                );
            }
        }
    }
}

#[test]
fn faces_with_nothing_to_cast_are_not_made_and_read_lit() {
    // Casters on +x and -z only: four faces are left out, and points on them are lit.
    let (maps, faces) = cube_of(&[Vec3::X, Vec3::NEG_Z], 128);
    assert_eq!(faces, [CubeFace::PosX, CubeFace::NegZ]);
    let cube = lookup(&maps, &faces);
    assert_eq!(cube.visibility(Vec3::X * 3.0, Vec3::NEG_X), 0.0);
    for face in [
        CubeFace::NegX,
        CubeFace::PosY,
        CubeFace::NegY,
        CubeFace::PosZ,
    ] {
        let p = face.axis() * 3.0;
        assert_eq!(cube.visibility(p, -face.axis()), 1.0, "{face}");
    }
    // Nothing anywhere: no face at all.
    let wall = [Sphere {
        center: Vec3::X * 3.0,
        radius: 0.5,
    }];
    let far_caster = [Sphere {
        center: Vec3::NEG_X * 3.0,
        radius: 0.5,
    }];
    assert_eq!(
        fit_cube(
            Vec3::ZERO,
            &extents(&far_caster),
            &extents(&wall),
            None,
            128
        )
        .unwrap_err(),
        NoMap::NothingBetween
    );
    let bad = [Sphere {
        center: Vec3::NAN,
        radius: 0.5,
    }];
    assert_eq!(
        fit_cube(Vec3::ZERO, &extents(&bad), &extents(&wall), None, 128).unwrap_err(),
        NoMap::Degenerate
    );
}

#[test]
fn lanes_on_different_faces_give_their_one_lane_values() {
    let dirs = [
        Vec3::X,
        Vec3::NEG_Y,
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 0.3, 1.0),
    ];
    let (maps, faces) = cube_of(&dirs, 64);
    let cube = lookup(&maps, &faces);
    // Points over every face, on the seams and corners, at the light, and not finite.
    let mut points = Vec::new();
    for j in -12..=12 {
        for i in -12..=12 {
            for f in CubeFace::ALL {
                let a = f.axis();
                let (u, v) = (across(a), a.cross(across(a)));
                points.push(a * 3.0 + u * (i as f32 * 0.25) + v * (j as f32 * 0.25));
            }
        }
    }
    points.extend([
        Vec3::ZERO,
        Vec3::NAN,
        Vec3::splat(3.0),
        Vec3::new(3.0, -3.0, 0.0),
    ]);
    let mut dark = 0;
    for (k, quad) in points.chunks_exact(4).enumerate() {
        let ns: [Vec3; 4] = std::array::from_fn(|i| -quad[i].normalize_or_zero() * (k % 3) as f32);
        let (p, n) = (lanes4(quad.try_into().unwrap()), lanes4(&ns));
        let got = cube.visibility_lanes(p, n).to_array();
        for i in 0..4 {
            let want = cube.visibility(quad[i], ns[i]);
            assert_eq!(got[i].to_bits(), want.to_bits(), "lane {i} at {}", quad[i]);
            // The one-lane value is the face's own map's.
            if quad[i].is_finite() && quad[i] != Vec3::ZERO {
                let face = CubeFace::of(quad[i]);
                let own = faces
                    .iter()
                    .position(|&f| f == face)
                    .map_or(1.0, |m| maps[m].visibility(quad[i], ns[i]));
                assert_eq!(want.to_bits(), own.to_bits(), "{} on {face}", quad[i]);
            }
            dark += usize::from(want < 1.0);
        }
    }
    assert!(dark > 20, "only {dark} points in shadow");
}
