//! Property tests: finite results within the bounds the model implies, and agreement of the
//! f32 kernel with the f64 reference.

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use super::support::{Rng, random_lights, random_material};
use crate::{Effects, LightSet, Material, shade, shade_reference};

const ALL: u32 = Effects::ALL.bits();

/// `emission + ka Ia + sum |Il| (kd + ks max W) max f` per channel.
fn upper_bound(set: &LightSet, mat: &Material) -> Vec3 {
    let w = mat.fresnel.max_w().max(1.0);
    let per_light = |il: Vec3, il_s: Vec3, f_max: f32| (il * mat.kd + il_s * mat.ks * w) * f_max;
    let f = |c: [f32; 3]| crate::attenuation::factor_from_coefficients(c, 0.0);
    let mut bound = mat.emission + mat.ka * set.ambient();
    for l in set.directional() {
        bound += per_light(l.il, l.il_specular, 1.0);
    }
    for l in set.points().iter().chain(set.distributed_samples()) {
        bound += per_light(l.il, l.il_specular, f(l.attenuation));
    }
    for s in set.spots() {
        bound += per_light(s.point.il, s.point.il_specular, f(s.point.attenuation));
    }
    bound
}

fn finite_f32() -> impl Strategy<Value = f32> {
    prop::num::f32::NORMAL | prop::num::f32::SUBNORMAL | prop::num::f32::ZERO
}

fn any_vec() -> impl Strategy<Value = Vec3> {
    (finite_f32(), finite_f32(), finite_f32()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

proptest! {
    #[test]
    fn shading_is_finite_and_within_the_model_bounds(
        seed in any::<u64>(),
        p in prop::array::uniform3(-3.0f32..3.0),
        n in prop::array::uniform3(-1.0f32..1.0),
        eye in prop::array::uniform3(-8.0f32..8.0),
    ) {
        let mut rng = Rng::new(seed);
        let mat = random_material(&mut rng);
        let set = LightSet::new(rng.vec(0.0, 2.0), &random_lights(&mut rng));
        let (p, n, eye) = (Vec3::from(p), Vec3::from(n), Vec3::from(eye));
        let i = shade::<ALL>(&set, &mat, p, n, eye);
        let bound = upper_bound(&set, &mat);
        prop_assert!(i.is_finite() && i.min_element() >= 0.0);
        prop_assert!(i.cmple(bound * (1.0 + 1e-5) + Vec3::splat(1e-6)).all(), "{} > {}", i, bound);
    }

    #[test]
    fn the_f32_kernel_agrees_with_the_f64_reference(
        seed in any::<u64>(),
        p in prop::array::uniform3(-1.0f32..1.0),
        n in prop::array::uniform3(-1.0f32..1.0),
        eye in prop::array::uniform3(-8.0f32..8.0),
    ) {
        let mut rng = Rng::new(seed);
        let mat = random_material(&mut rng);
        let set = LightSet::new(rng.vec(0.0, 2.0), &random_lights(&mut rng));
        let (p, n, eye) = (Vec3::from(p), Vec3::from(n), Vec3::from(eye));
        prop_assume!(n.length() > 1e-3);
        let fast = shade::<ALL>(&set, &mat, p, n, eye).as_dvec3();
        let exact = shade_reference(&set, &mat, p.as_dvec3(), n.as_dvec3(), eye.as_dvec3());
        let scale = 1.0 + upper_bound(&set, &mat).max_element() as f64;
        // N.L = 0 is a discontinuity of the specular term: skip points on its edge.
        let near_edge = set.points().iter().chain(set.distributed_samples())
            .map(|l| l.position).chain(set.spots().iter().map(|s| s.point.position))
            .any(|q| (q - p).normalize_or_zero().dot(n.normalize()).abs() < 1e-3)
            || set.directional().iter().any(|d| d.to_light.dot(n.normalize()).abs() < 1e-3);
        prop_assume!(!near_edge);
        prop_assert!((fast - exact).abs().max_element() <= 1e-4 * scale, "{} vs {}", fast, exact);
    }

    #[test]
    fn any_finite_input_gives_finite_output(
        p in any_vec(), n in any_vec(), eye in any_vec(),
        light_pos in any_vec(), il in any_vec(), k in any_vec(), ns in finite_f32(),
        mirror in any::<bool>(),
    ) {
        let il = il.abs();
        let k = k.abs();
        // Half the cases are the perfect mirror, n_s = inf.
        let shininess = if mirror { f32::INFINITY } else { ns.abs() };
        let mat = Material { ka: k, kd: k, ks: k, shininess, ..Material::s1() };
        let lights = [
            crate::Light::point(light_pos, il).unwrap()
                .with_attenuation(crate::Attenuation::InverseSquare).unwrap(),
            crate::Light::point(light_pos, il).unwrap(),
        ];
        let set = LightSet::new(il, &lights);
        let i = shade::<ALL>(&set, &mat, p, n, eye);
        prop_assert!(i.is_finite() && i.min_element() >= 0.0);
        let r = shade_reference(&set, &mat, p.as_dvec3(), n.as_dvec3(), eye.as_dvec3());
        prop_assert!(r.is_finite() && r.min_element() >= 0.0);
        let _ = DVec3::ZERO;
    }
}
