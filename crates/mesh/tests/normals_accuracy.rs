//! Averaged vertex normals of a UV sphere (computed from its welded positions, no authored
//! normals, crease 180) against the exact radial normals, for each weighting. Prints the mean
//! and max angular error, overall and within 60 degrees of the equator:
//! `cargo test -p phosphor-mesh --test normals_accuracy -- --nocapture`.

use phosphor_mesh::{NormalOptions, Weighting, primitives};

struct Errors {
    mean: f64,
    max: f64,
    /// Max over vertices within 60 degrees of latitude of the equator.
    max_band: f64,
}

fn errors(segments: u32, rings: u32, weighting: Weighting) -> Errors {
    let sphere = primitives::uv_sphere(1.0, segments, rings);
    let mesh = sphere.with_computed_normals(&NormalOptions::smooth_all(weighting));
    assert!(mesh.is_consistent());
    let (mut sum, mut max, mut max_band) = (0.0, 0.0_f64, 0.0_f64);
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        let exact = p.as_dvec3().normalize();
        let n = n.as_dvec3();
        let angle = n.cross(exact).length().atan2(n.dot(exact));
        sum += angle;
        max = max.max(angle);
        if exact.y.abs() <= 60f64.to_radians().sin() {
            max_band = max_band.max(angle);
        }
    }
    Errors {
        mean: sum / mesh.positions.len() as f64,
        max,
        max_band,
    }
}

#[test]
fn averaged_sphere_normals_approach_the_exact_ones_for_every_weighting() {
    for (segments, rings) in [(64, 32), (128, 64), (512, 256)] {
        for w in [Weighting::Uniform, Weighting::Area, Weighting::Angle] {
            let e = errors(segments, rings, w);
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
fn welding_merges_the_seam_and_the_poles() {
    let sphere = primitives::uv_sphere(1.0, 16, 8);
    let soup = sphere.to_soup();
    // 7 interior rings of 16 + 2 poles.
    assert_eq!(soup.positions.len(), 7 * 16 + 2);
}
