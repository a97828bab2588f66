//! Light kinds through `shade`: spot cones, directional lights never attenuated, distributed
//! lights equal to their point samples.

use glam::Vec3;

use super::support::assert_close;
use crate::{Attenuation, Effects, Light, LightKind, LightSet, Material, shade};

const ALL: u32 = Effects::ALL.bits();

fn matte() -> Material {
    Material::new(Vec3::ZERO, Vec3::ONE, Vec3::ZERO, 1.0).unwrap()
}

fn spot_at_angle(angle_deg: f32) -> Vec3 {
    // A spot 1 above the origin aimed so the origin is `angle_deg` off its axis.
    let a = angle_deg.to_radians();
    let direction = Vec3::new(a.sin(), -a.cos(), 0.0);
    let spot = LightKind::Spot {
        position: Vec3::Y,
        direction,
        inner_deg: 10.0,
        outer_deg: 30.0,
    };
    let set = LightSet::new(Vec3::ZERO, &[Light::new(spot, Vec3::ONE).unwrap()]);
    shade::<ALL>(&set, &matte(), Vec3::ZERO, Vec3::Y, Vec3::Y * 3.0)
}

#[test]
fn spot_cone_is_full_inside_zero_outside_and_smooth_between() {
    assert_close(spot_at_angle(0.0), Vec3::ONE, 1e-6, "on axis");
    assert_close(spot_at_angle(9.0), Vec3::ONE, 1e-6, "inside inner");
    assert_eq!(spot_at_angle(31.0), Vec3::ZERO);
    let mut last = 1.0;
    for deg in 10..=30 {
        let i = spot_at_angle(deg as f32).x;
        assert!(i <= last + 1e-6 && (0.0..=1.0).contains(&i), "{deg}: {i}");
        last = i;
    }
    // Halfway in cosine the smoothstep is 1/2.
    let (ci, co) = (10f32.to_radians().cos(), 30f32.to_radians().cos());
    let mid = (0.5 * (ci + co)).acos().to_degrees();
    assert_close(spot_at_angle(mid), Vec3::splat(0.5), 1e-4, "half way");
}

#[test]
fn directional_lights_are_never_attenuated() {
    let light = Light::directional(-Vec3::Y, Vec3::ONE)
        .unwrap()
        .with_attenuation(Attenuation::InverseSquare)
        .unwrap();
    let set = LightSet::new(Vec3::ZERO, &[light]);
    assert!(!set.effects_needed().contains(Effects::ATTENUATION));
    let i = shade::<ALL>(&set, &matte(), Vec3::splat(100.0), Vec3::Y, Vec3::Y * 300.0);
    assert_close(i, Vec3::ONE, 1e-6, "directional");
}

#[test]
fn a_tube_shades_like_point_lights_at_its_sample_midpoints() {
    let attenuation = Attenuation::Offset { k: 1.0 };
    let tube = Light::new(
        LightKind::Tube {
            start: Vec3::new(-1.0, 2.0, 0.0),
            end: Vec3::new(1.0, 2.0, 0.0),
            samples: 2,
        },
        Vec3::splat(2.0),
    )
    .unwrap()
    .with_attenuation(attenuation)
    .unwrap();
    let points = [-0.5, 0.5].map(|x| {
        Light::point(Vec3::new(x, 2.0, 0.0), Vec3::ONE)
            .unwrap()
            .with_attenuation(attenuation)
            .unwrap()
    });
    let m = Material::s1();
    let (p, n, eye) = (Vec3::new(0.2, 0.0, 0.1), Vec3::Y, Vec3::new(0.0, 1.0, 3.0));
    let a = shade::<ALL>(&LightSet::new(Vec3::ZERO, &[tube]), &m, p, n, eye);
    let b = shade::<ALL>(&LightSet::new(Vec3::ZERO, &points), &m, p, n, eye);
    assert_close(a, b, 1e-6, "tube = its samples");
    // Without the DISTRIBUTED bit the tube is skipped.
    const NO_DIST: u32 = ALL & !Effects::DISTRIBUTED.bits();
    let set = LightSet::new(Vec3::ZERO, &[tube]);
    assert_eq!(shade::<NO_DIST>(&set, &m, p, n, eye), Vec3::ZERO);
}

#[test]
fn a_rect_converges_to_its_area_integral_as_samples_grow() {
    let rect = |samples| {
        let light = Light::new(
            LightKind::Rect {
                corner: Vec3::new(-1.0, 1.0, -1.0),
                edge_u: Vec3::X * 2.0,
                edge_v: Vec3::Z * 2.0,
                samples,
            },
            Vec3::ONE,
        )
        .unwrap();
        shade::<ALL>(
            &LightSet::new(Vec3::ZERO, &[light]),
            &matte(),
            Vec3::ZERO,
            Vec3::Y,
            Vec3::Y,
        )
    };
    let coarse = rect(2).x;
    let fine = rect(64).x;
    let finer = rect(128).x;
    assert!((fine - finer).abs() < 1e-3 && (coarse - finer).abs() > (fine - finer).abs());
    // Every sample is above the point: the sum of N.L shares is below the on-axis value 1.
    assert!(finer < 1.0 && finer > 0.5);
}
