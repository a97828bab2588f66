//! Averaged vertex normals of a UV sphere and a torus (computed from their welded positions, no
//! authored normals, crease 180) against the exact normals of the true surfaces, for each
//! weighting. Prints the mean and max angular error (for the sphere also the max within 60
//! degrees of the equator, away from the poles):
//! `cargo test -p phosphor-mesh --test normals_accuracy -- --nocapture`.

use glam::DVec3;
use phosphor_mesh::{Mesh, NormalOptions, Weighting, primitives};

const WEIGHTINGS: [Weighting; 3] = [Weighting::Uniform, Weighting::Area, Weighting::Angle];

/// The torus' radii: tube centre circle 1, tube 0.3.
const TORUS_MAJOR: f64 = 1.0;
const TORUS_MINOR: f64 = 0.3;

struct Errors {
    mean: f64,
    max: f64,
    /// Max over the vertices where `in_band` holds.
    max_band: f64,
}

/// Angular errors of `primitive`'s normals recomputed with `weighting` against `exact(p)`.
fn errors(
    primitive: &Mesh,
    weighting: Weighting,
    exact: impl Fn(DVec3) -> DVec3,
    in_band: impl Fn(DVec3) -> bool,
) -> Errors {
    let mesh = primitive.with_computed_normals(&NormalOptions::smooth_all(weighting));
    assert!(mesh.is_consistent());
    let (mut sum, mut max, mut max_band) = (0.0, 0.0_f64, 0.0_f64);
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        let p = p.as_dvec3();
        let exact = exact(p);
        let n = n.as_dvec3();
        let angle = n.cross(exact).length().atan2(n.dot(exact));
        sum += angle;
        max = max.max(angle);
        if in_band(p) {
            max_band = max_band.max(angle);
        }
    }
    Errors {
        mean: sum / mesh.positions.len() as f64,
        max,
        max_band,
    }
}

fn sphere_errors(segments: u32, rings: u32, weighting: Weighting) -> Errors {
    errors(
        &primitives::uv_sphere(1.0, segments, rings),
        weighting,
        DVec3::normalize,
        |p| p.normalize().y.abs() <= 60f64.to_radians().sin(),
    )
}

/// The torus' exact normal at `p`: away from the nearest point of the tube centre circle.
fn torus_normal(p: DVec3) -> DVec3 {
    let centre = DVec3::new(p.x, 0.0, p.z).normalize() * TORUS_MAJOR;
    (p - centre).normalize()
}

fn torus_errors(segments: u32, sides: u32, weighting: Weighting) -> Errors {
    errors(
        &primitives::torus(TORUS_MAJOR as f32, TORUS_MINOR as f32, segments, sides),
        weighting,
        torus_normal,
        |_| true,
    )
}

#[test]
fn averaged_sphere_normals_approach_the_exact_ones_for_every_weighting() {
    for (segments, rings) in [(64, 32), (128, 64), (512, 256)] {
        for w in WEIGHTINGS {
            let e = sphere_errors(segments, rings, w);
            println!(
                "uv_sphere({segments}x{rings}) {w:?}: mean {:.2e} rad, max {:.2e} rad, max within 60 deg of the equator {:.2e} rad",
                e.mean, e.max, e.max_band
            );
            if segments >= 128 {
                assert!(e.mean < 1e-3, "{w:?}: mean {}", e.mean);
            }
            if segments >= 512 {
                assert!(e.max_band < 1e-3, "{w:?}: max in band {}", e.max_band);
            }
            if w == Weighting::Angle && segments >= 128 {
                assert!(e.max < 1e-3, "{w:?}: max {}", e.max);
            }
            // The pole rings converge linearly (see crate docs); bound them loosely.
            assert!(e.max < 20.0 / f64::from(segments), "{w:?}: max {}", e.max);
        }
    }
}

#[test]
fn averaged_torus_normals_approach_the_exact_ones_for_every_weighting() {
    let mut previous_max = [f64::INFINITY; 3];
    for (segments, sides) in [(64, 32), (128, 64), (512, 256)] {
        for (k, w) in WEIGHTINGS.into_iter().enumerate() {
            let e = torus_errors(segments, sides, w);
            println!(
                "torus({segments}x{sides}) {w:?}: mean {:.2e} rad, max {:.2e} rad",
                e.mean, e.max
            );
            // No poles: every vertex sees a regular, mirror-symmetric fan. From 128x64 on
            // every weighting is within 1e-3 rad everywhere.
            if segments >= 128 {
                assert!(e.max < 1e-3, "{w:?}: max {}", e.max);
            }
            if w == Weighting::Uniform {
                // Exact up to the rounding of f32 positions (about 1e-5 rad at 512x256, where
                // edges are 7e-3 long): no convergence left to measure.
                assert!(e.max < 1e-4, "{w:?}: max {}", e.max);
            } else {
                // Second order: doubling the tessellation divides the max by about 4.
                assert!(e.max < previous_max[k] / 3.0, "{w:?}: max {}", e.max);
            }
            previous_max[k] = e.max;
        }
    }
}

#[test]
fn welding_merges_the_seam_and_the_poles() {
    let sphere = primitives::uv_sphere(1.0, 16, 8);
    let soup = sphere.to_soup();
    // 7 interior rings of 16 + 2 poles.
    assert_eq!(soup.positions.len(), 7 * 16 + 2);
}

#[test]
fn welding_closes_the_torus_in_both_directions() {
    let torus = primitives::torus(1.0, 0.3, 16, 8);
    assert_eq!(torus.to_soup().positions.len(), 16 * 8);
}
