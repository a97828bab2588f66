//! For every subset FX of the effects: on inputs whose absent terms are zeroed (coefficient
//! zero, light kind absent), `shade::<FX>` equals `shade::<ALL>`; and the planner's minimal
//! set (`effects_for`) reproduces the all-effects result exactly on any input.

use glam::Vec3;

use super::support::{Rng, assert_close, random_lights, random_material};
use crate::{
    Attenuation, Effects, Fresnel, Light, LightKind, LightSet, Material, effects_for, shade,
    shade_canonical, shade_dyn, shade_split,
};

const ALL: u32 = Effects::ALL.bits();

/// The inputs with every term that `fx` lacks zeroed.
fn zero_absent_terms(fx: Effects, mut mat: Material, lights: &[Light]) -> (Material, Vec<Light>) {
    if !fx.contains(Effects::AMBIENT) {
        mat.ka = Vec3::ZERO;
    }
    if !fx.contains(Effects::DIFFUSE) {
        mat.kd = Vec3::ZERO;
    }
    if !fx.contains(Effects::SPECULAR) {
        mat.ks = Vec3::ZERO;
    }
    if !fx.contains(Effects::FRESNEL) {
        mat.fresnel = Fresnel::None;
    }
    if !fx.contains(Effects::EMISSION) {
        mat.emission = Vec3::ZERO;
    }
    let lights = lights
        .iter()
        .filter(|l| {
            let spot = matches!(l.kind, LightKind::Spot { .. });
            let distributed = matches!(l.kind, LightKind::Tube { .. } | LightKind::Rect { .. });
            (fx.contains(Effects::SPOT) || !spot)
                && (fx.contains(Effects::DISTRIBUTED) || !distributed)
        })
        .map(|l| {
            let mut l = *l;
            if !fx.contains(Effects::ATTENUATION) {
                l.attenuation = Attenuation::None;
            }
            l
        })
        .collect();
    (mat, lights)
}

#[test]
fn every_effect_subset_equals_the_general_path_with_absent_terms_zeroed() {
    let mut rng = Rng::new(7);
    for bits in 0..=ALL {
        let fx = Effects::from_bits_truncate(bits);
        for trial in 0..6 {
            let (mat, lights) =
                zero_absent_terms(fx, random_material(&mut rng), &random_lights(&mut rng));
            let set = LightSet::new(rng.vec(0.0, 1.0), &lights);
            let (p, n, eye) = (rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0), rng.vec(-6.0, 6.0));
            let general = shade::<ALL>(&set, &mat, p, n, eye);
            let special = shade_dyn(fx, &set, &mat, p, n, eye);
            assert_close(special, general, 1e-6, &format!("{fx} trial {trial}"));
            let rounded_up = shade_canonical(fx, &set, &mat, p, n, eye);
            assert_close(
                rounded_up,
                general,
                1e-6,
                &format!("canonical {fx} trial {trial}"),
            );
            // The zeroed inputs need no effect outside fx.
            let needed = effects_for(&set, &mat);
            assert!(fx.contains(needed), "{fx}: needs {needed}");
        }
    }
}

#[test]
fn the_planners_minimal_effect_set_reproduces_the_full_model() {
    let mut rng = Rng::new(11);
    for trial in 0..2000 {
        let mut mat = random_material(&mut rng);
        // Zero a random selection of coefficients so the minimal sets vary.
        if rng.below(2) == 0 {
            mat.ks = Vec3::ZERO;
        }
        if rng.below(3) == 0 {
            mat.emission = Vec3::ZERO;
        }
        if rng.below(3) == 0 {
            mat.ka = Vec3::ZERO;
        }
        let ambient = if rng.below(3) == 0 {
            Vec3::ZERO
        } else {
            rng.vec(0.0, 1.0)
        };
        let set = LightSet::new(ambient, &random_lights(&mut rng));
        let (p, n, eye) = (rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0), rng.vec(-6.0, 6.0));
        let fx = effects_for(&set, &mat);
        let minimal = shade_dyn(fx, &set, &mat, p, n, eye);
        let general = shade::<ALL>(&set, &mat, p, n, eye);
        assert_close(minimal, general, 1e-6, &format!("trial {trial}, {fx}"));
        let canonical = shade_canonical(fx, &set, &mat, p, n, eye);
        assert_close(
            canonical,
            general,
            1e-6,
            &format!("trial {trial}, canonical {fx}"),
        );
    }
}

#[test]
fn split_terms_sum_to_shade_for_sample_subsets() {
    fn check<const FX: u32>(rng: &mut Rng) {
        for _ in 0..50 {
            let set = LightSet::new(rng.vec(0.0, 1.0), &random_lights(rng));
            let mat = random_material(rng);
            let (p, n, eye) = (rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0), rng.vec(-6.0, 6.0));
            let t = shade_split::<FX>(&set, &mat, p, n, eye);
            assert_eq!(t.total(), shade::<FX>(&set, &mat, p, n, eye));
        }
    }
    let mut rng = Rng::new(3);
    check::<ALL>(&mut rng);
    check::<{ Effects::AMBIENT.bits() | Effects::DIFFUSE.bits() }>(&mut rng);
    check::<{ Effects::DIFFUSE.bits() | Effects::SPECULAR.bits() | Effects::SPOT.bits() }>(
        &mut rng,
    );
    check::<0>(&mut rng);
}
