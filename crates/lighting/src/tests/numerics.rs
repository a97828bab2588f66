//! Hard numeric cases: each must give finite, documented results.

use glam::{DVec3, Vec3};

use super::support::assert_close;
use crate::{
    Attenuation, Effects, Light, LightKind, LightSet, MIN_ATTENUATION_DENOMINATOR, Material, shade,
    shade_reference, shade_split,
};

const ALL: u32 = Effects::ALL.bits();

fn finite_and_non_negative(v: Vec3) -> bool {
    v.is_finite() && v.min_element() >= 0.0
}

fn lit_material() -> Material {
    Material::s1().with_emission(Vec3::splat(0.05)).unwrap()
}

#[test]
fn light_at_the_surface_point_is_capped_and_shines_along_the_normal() {
    let p = Vec3::new(0.3, -0.2, 0.1);
    for attenuation in [
        Attenuation::InverseSquare,
        Attenuation::Offset { k: 0.0 },
        Attenuation::Quadratic {
            c: 0.0,
            l: 0.0,
            q: 1.0,
        },
    ] {
        let light = Light::point(p, Vec3::ONE)
            .unwrap()
            .with_attenuation(attenuation)
            .unwrap();
        let set = LightSet::new(Vec3::ZERO, &[light]);
        let m = Material::new(Vec3::ZERO, Vec3::splat(0.5), Vec3::ZERO, 1.0).unwrap();
        let i = shade::<ALL>(&set, &m, p, Vec3::Y, p + Vec3::Y);
        // N.L = 1 (L falls back to N), f = 1 / MIN_ATTENUATION_DENOMINATOR.
        let expected = Vec3::splat(0.5 / MIN_ATTENUATION_DENOMINATOR);
        assert_close(i, expected, 1e-6, "light at p");
        let r = shade_reference(&set, &m, p.as_dvec3(), DVec3::Y, (p + Vec3::Y).as_dvec3());
        assert!(r.is_finite());
    }
}

#[test]
fn light_inside_the_object_gives_ambient_and_emission_only() {
    // A light below the surface (inside a closed object): N.L < 0, no diffuse, no specular.
    let light = Light::point(Vec3::new(0.0, -0.5, 0.0), Vec3::splat(5.0)).unwrap();
    let set = LightSet::new(Vec3::ONE, &[light]);
    let m = lit_material();
    let t = shade_split::<ALL>(&set, &m, Vec3::ZERO, Vec3::Y, Vec3::new(0.0, 3.0, 0.0));
    assert_eq!(t.diffuse, Vec3::ZERO);
    assert_eq!(t.specular, Vec3::ZERO);
    assert_close(t.ambient, m.ka + m.emission, 1e-7, "ambient + emission");
}

#[test]
fn zero_or_non_finite_normal_gives_ambient_and_emission_only() {
    let set = LightSet::new(Vec3::ONE, &Light::s1_lights());
    let m = lit_material();
    let expected = m.ka + m.emission;
    for n in [
        Vec3::ZERO,
        Vec3::splat(1e-30),
        Vec3::new(f32::NAN, 0.0, 1.0),
        Vec3::new(0.0, f32::INFINITY, 0.0),
    ] {
        let i = shade::<ALL>(&set, &m, Vec3::ZERO, n, Vec3::Z * 3.0);
        assert_close(i, expected, 1e-7, "degenerate normal");
        // 1e-30 is below f32's normalizable length but a fine f64 normal: the reference
        // shades it, so only zero and non-finite normals are compared there.
        if !n.is_finite() || n == Vec3::ZERO {
            let r = shade_reference(&set, &m, DVec3::ZERO, n.as_dvec3(), DVec3::Z * 3.0);
            assert!((r.as_vec3() - expected).abs().max_element() < 1e-6);
        }
    }
}

#[test]
fn unnormalized_normals_are_normalized() {
    let set = LightSet::new(Vec3::ONE, &Light::s1_lights());
    let m = Material::s1();
    let eye = Vec3::Z * 3.0;
    let a = shade::<ALL>(&set, &m, Vec3::Z, Vec3::Z, eye);
    let b = shade::<ALL>(&set, &m, Vec3::Z, Vec3::Z * 7.5, eye);
    assert_close(a, b, 1e-6, "scaled normal");
}

#[test]
fn extreme_shininess_stays_finite_and_in_its_bounds() {
    // Light straight above, viewer straight above: V exactly along R = N.
    let set = LightSet::new(
        Vec3::ZERO,
        &[Light::point(Vec3::Z * 2.0, Vec3::ONE).unwrap()],
    );
    for ns in [0.0, 1.0, 10_000.0, f32::MAX] {
        let m = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::ONE, ns).unwrap();
        let on_r = shade::<ALL>(&set, &m, Vec3::ZERO, Vec3::Z, Vec3::Z * 5.0);
        // (V.R)^ns = 1^ns = 1 for every ns.
        assert_close(on_r, Vec3::ONE, 1e-6, "V along R");
        let off = shade::<ALL>(&set, &m, Vec3::ZERO, Vec3::Z, Vec3::new(1.0, 0.0, 1.0));
        assert!(finite_and_non_negative(off));
        if ns == 0.0 {
            // x^0 = 1: no fall-off at all.
            assert_close(off, Vec3::ONE, 1e-6, "ns = 0");
        }
        if ns >= 10_000.0 {
            assert!(off.max_element() < 1e-30, "narrow lobe: {off}");
        }
        let blinn = m.with_specular(crate::SpecularModel::Blinn);
        let v = shade::<ALL>(&set, &blinn, Vec3::ZERO, Vec3::Z, Vec3::Z * 5.0);
        assert_close(v, Vec3::ONE, 1e-6, "Blinn V along R");
    }
}

#[test]
fn grazing_light_with_n_dot_l_exactly_zero_adds_nothing() {
    let light = Light::directional(Vec3::X, Vec3::ONE).unwrap();
    let set = LightSet::new(Vec3::ZERO, &[light]);
    let m = Material::new(Vec3::ZERO, Vec3::ONE, Vec3::ONE, 0.0).unwrap();
    // N.L = 0 exactly; with ns = 0 the lobe would be 1, but the specular term is 0 here.
    let i = shade::<ALL>(&set, &m, Vec3::ZERO, Vec3::Y, Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(i, Vec3::ZERO);
}

#[test]
fn eye_at_the_surface_point_views_along_the_normal() {
    let set = LightSet::new(Vec3::ONE, &Light::s1_lights());
    let i = shade::<ALL>(&set, &Material::s1(), Vec3::Z, Vec3::Z, Vec3::Z);
    let j = shade::<ALL>(&set, &Material::s1(), Vec3::Z, Vec3::Z, Vec3::Z * 2.0);
    assert_close(i, j, 1e-6, "eye at p");
}

#[test]
fn zero_intensity_lights_are_dropped_and_negative_ones_rejected() {
    let zero = Light::point(Vec3::Z, Vec3::ZERO).unwrap();
    assert!(LightSet::new(Vec3::ZERO, &[zero]).is_empty());
    assert!(Light::point(Vec3::Z, Vec3::new(0.0, -0.1, 0.0)).is_err());
    // A negative intensity written into the public field is dropped, never shaded.
    let bad = Light {
        intensity: Vec3::splat(-1.0),
        ..zero
    };
    assert!(LightSet::new(Vec3::ZERO, &[bad]).is_empty());
    // A negative ambient is treated as zero.
    let set = LightSet::new(Vec3::splat(-1.0), &[]);
    assert_eq!(
        shade::<ALL>(&set, &Material::s1(), Vec3::ZERO, Vec3::Z, Vec3::Z),
        Vec3::ZERO
    );
}

#[test]
fn overflowing_inputs_never_produce_nan_or_inf() {
    let big = Vec3::splat(f32::MAX);
    let lights = [
        Light::point(Vec3::splat(-1e38), big).unwrap(),
        Light::point(Vec3::ZERO, big)
            .unwrap()
            .with_attenuation(Attenuation::InverseSquare)
            .unwrap(),
        Light::directional(Vec3::splat(-f32::MAX), big).unwrap(),
        Light::new(
            LightKind::Tube {
                start: Vec3::splat(1e38),
                end: Vec3::splat(-1e38),
                samples: 3,
            },
            big,
        )
        .unwrap(),
    ];
    let set = LightSet::new(big, &lights);
    let m = Material::new(big, big, big, f32::MAX)
        .unwrap()
        .with_emission(big)
        .unwrap();
    for p in [Vec3::ZERO, Vec3::splat(1e38), Vec3::splat(-3e38)] {
        for eye in [Vec3::ZERO, Vec3::splat(3e38)] {
            let i = shade::<ALL>(&set, &m, p, Vec3::ONE, eye);
            assert!(finite_and_non_negative(i), "{i}");
            let t = shade_split::<ALL>(&set, &m, p, Vec3::ONE, eye);
            assert!(finite_and_non_negative(
                t.ambient + t.diffuse.min(Vec3::ONE)
            ));
            let r = shade_reference(&set, &m, p.as_dvec3(), DVec3::ONE, eye.as_dvec3());
            assert!(r.is_finite() && r.min_element() >= 0.0);
        }
    }
}
