//! Hand-computed values of each of the lecture notes' equations, to 1e-6.

use glam::Vec3;

use super::support::assert_close;
use crate::{
    Attenuation, Effects, Fresnel, FresnelMode, GLASS_F0, Light, LightSet, Material, Vec3x4, shade,
    shade_reference, shade_x4,
};

const ALL: u32 = Effects::ALL.bits();
const TOL: f32 = 1e-6;
// Light at (3, 0, 4): d = 5 from the origin, L = (0.6, 0, 0.8), N = +Z so N.L = 0.8.
const LIGHT_POS: Vec3 = Vec3::new(3.0, 0.0, 4.0);

fn material(ka: f32, kd: f32, ks: f32, ns: f32) -> Material {
    Material::new(Vec3::splat(ka), Vec3::splat(kd), Vec3::splat(ks), ns).unwrap()
}

fn at_origin(set: &LightSet, m: &Material, eye: Vec3) -> Vec3 {
    shade::<ALL>(set, m, Vec3::ZERO, Vec3::Z, eye)
}

#[test]
fn self_luminous_intensity_is_ka_as_is() {
    // The lecture notes' I = Ka (self-luminous object, no light source).
    let m = material(0.0, 0.0, 0.0, 1.0)
        .with_emission(Vec3::new(0.3, 0.2, 0.1))
        .unwrap();
    let set = LightSet::new(Vec3::ZERO, &[]);
    assert_close(
        at_origin(&set, &m, Vec3::Z),
        Vec3::new(0.3, 0.2, 0.1),
        TOL,
        "I = Ka",
    );
}

#[test]
fn ambient_intensity_is_ia_times_ka() {
    // The lecture notes' I = Ia Ka, per channel: (0.5, 0.4, 1) * (0.2, 0.5, 0.1) = (0.1, 0.2, 0.1).
    let m = Material::new(Vec3::new(0.2, 0.5, 0.1), Vec3::ZERO, Vec3::ZERO, 1.0).unwrap();
    let set = LightSet::new(Vec3::new(0.5, 0.4, 1.0), &[]);
    assert_close(
        at_origin(&set, &m, Vec3::Z),
        Vec3::new(0.1, 0.2, 0.1),
        TOL,
        "I = Ia Ka",
    );
}

#[test]
fn lambert_diffuse_is_kd_il_n_dot_l() {
    // The lecture notes' I = Kd Il (N.L) = 0.5 * 2 * 0.8 = 0.8.
    let set = LightSet::new(
        Vec3::ZERO,
        &[Light::point(LIGHT_POS, Vec3::splat(2.0)).unwrap()],
    );
    let m = material(0.0, 0.5, 0.0, 1.0);
    assert_close(
        at_origin(&set, &m, Vec3::Z * 9.0),
        Vec3::splat(0.8),
        TOL,
        "Lambert",
    );
}

#[test]
fn ambient_plus_diffuse_is_ka_ia_plus_kd_il_n_dot_l() {
    // The lecture notes' I = Ka Ia + Kd Il (N.L) = 0.1 * 0.5 + 0.5 * 2 * 0.8 = 0.85.
    let set = LightSet::new(
        Vec3::splat(0.5),
        &[Light::point(LIGHT_POS, Vec3::splat(2.0)).unwrap()],
    );
    let m = material(0.1, 0.5, 0.0, 1.0);
    assert_close(
        at_origin(&set, &m, Vec3::Z),
        Vec3::splat(0.85),
        TOL,
        "ambient + diffuse",
    );
}

#[test]
fn reflection_vector_is_two_n_dot_l_n_minus_l() {
    // The lecture notes' R = (2 N.L) N - L = 1.6 (0, 0, 1) - (0.6, 0, 0.8) = (-0.6, 0, 0.8).
    let r = phosphor_math::reflect(Vec3::Z, LIGHT_POS / 5.0);
    assert_close(r, Vec3::new(-0.6, 0.0, 0.8), TOL, "R");
}

#[test]
fn phong_specular_is_ks_il_v_dot_r_to_the_ns() {
    let set = LightSet::new(Vec3::ZERO, &[Light::point(LIGHT_POS, Vec3::ONE).unwrap()]);
    let m = material(0.0, 0.0, 0.5, 8.0);
    // Viewer along R = (-0.6, 0, 0.8): V.R = 1, I = Ks Il = 0.5.
    let on_r = Vec3::new(-0.6, 0.0, 0.8) * 5.0;
    assert_close(at_origin(&set, &m, on_r), Vec3::splat(0.5), TOL, "V on R");
    // Viewer along N: V.R = 0.8, I = 0.5 * 0.8^8 = 0.08388608.
    assert_close(
        at_origin(&set, &m, Vec3::Z * 5.0),
        Vec3::splat(0.083_886_08),
        TOL,
        "V on N",
    );
    // The f64 reference agrees.
    let r = shade_reference(
        &set,
        &m,
        glam::DVec3::ZERO,
        glam::DVec3::Z,
        glam::DVec3::Z * 5.0,
    );
    assert!((r.x - 0.083_886_08).abs() < 1e-9);
}

#[test]
fn offset_attenuation_divides_by_k_plus_d() {
    // The lecture notes' I = Ia ka + Il [kd (n.s) + ks (v.r)^t] / (K + d), K = 1, d = 5:
    // 0.2 * 0.5 + 2 * [0.5 * 0.8 + 0.5 * 0.8^8] / 6.
    let light = Light::point(LIGHT_POS, Vec3::splat(2.0))
        .unwrap()
        .with_attenuation(Attenuation::Offset { k: 1.0 })
        .unwrap();
    let set = LightSet::new(Vec3::splat(0.5), &[light]);
    let m = material(0.2, 0.5, 0.5, 8.0);
    let expected = 0.1 + 2.0 * (0.4 + 0.5 * 0.167_772_16) / 6.0;
    assert_close(
        at_origin(&set, &m, Vec3::Z),
        Vec3::splat(expected),
        TOL,
        "1/(K+d)",
    );
}

#[test]
fn several_lights_sum_their_reflected_intensities() {
    // The lecture notes' "the sum of the reflected light intensities must be used".
    let a = Light::point(LIGHT_POS, Vec3::splat(2.0)).unwrap();
    let b = Light::directional(-Vec3::Z, Vec3::new(1.0, 0.5, 0.0)).unwrap();
    let m = material(0.0, 0.5, 0.0, 1.0);
    let both = at_origin(&LightSet::new(Vec3::ZERO, &[a, b]), &m, Vec3::Z);
    let expected = Vec3::splat(0.8) + 0.5 * Vec3::new(1.0, 0.5, 0.0);
    assert_close(both, expected, TOL, "sum over lights");
}

#[test]
fn specular_intensity_can_differ_from_diffuse_as_opengl_allows() {
    let light = Light::point(LIGHT_POS, Vec3::splat(2.0))
        .unwrap()
        .with_specular_intensity(Vec3::new(1.0, 0.0, 0.0))
        .unwrap();
    let set = LightSet::new(Vec3::ZERO, &[light]);
    let m = material(0.0, 0.5, 0.5, 8.0);
    let i = at_origin(&set, &m, Vec3::new(-0.6, 0.0, 0.8));
    assert_close(
        i,
        Vec3::new(0.8 + 0.5, 0.8, 0.8),
        TOL,
        "separate specular Il",
    );
}

#[test]
fn s1_front_point_matches_the_s1_formula_by_hand() {
    // S1 (docs/conventions.md): I = ka Ia + sum Il (kd max(N.L,0) + ks max(R.V,0)^32) / (1 + d), at
    // the front of the unit sphere p = N = (0,0,1), eye (0,0,3). Evaluated term by term in f64
    // outside this crate: (0.432668737, 0.349501553, 0.266334369).
    let i = shade::<ALL>(
        &LightSet::s1(),
        &Material::s1(),
        Vec3::Z,
        Vec3::Z,
        Vec3::Z * 3.0,
    );
    let expected = Vec3::new(0.432_668_74, 0.349_501_55, 0.266_334_37);
    assert_close(i, expected, TOL, "S1 front point");
}

/// A directional light at 60 degrees incidence (`N.L = cos theta = 0.5`), the viewer on `R`
/// (`V.R = 1`) or on `N` (`V.R = 0.5`), glass's Schlick `W(theta) = 0.04 + 0.96 (1 - 0.5)^5 =
/// 0.07`.
fn fresnel_setup() -> (LightSet, Vec3, Vec3) {
    let to_light = Vec3::new(0.75f32.sqrt(), 0.0, 0.5);
    let set = LightSet::new(
        Vec3::ZERO,
        &[Light::directional(-to_light, Vec3::splat(2.0)).unwrap()],
    );
    let on_r = Vec3::new(-to_light.x, 0.0, to_light.z) * 4.0;
    (set, on_r, Vec3::Z * 4.0)
}

fn glass(ks: f32) -> Material {
    material(0.0, 0.0, ks, 8.0)
        .with_fresnel(Fresnel::Schlick { f0: GLASS_F0 })
        .unwrap()
}

#[test]
fn fresnel_replace_is_the_notes_w_theta_il_cos_phi() {
    // The lecture notes' I_spec = W(theta) Il cos^ns phi: W = 0.07, Il = 2.
    let (set, on_r, on_n) = fresnel_setup();
    let m = glass(0.5).with_fresnel_mode(FresnelMode::Replace);
    assert_eq!(m.ks, Vec3::ONE, "replace holds ks at 1");
    // On R: 0.07 * 2 * 1 = 0.14.
    assert_close(at_origin(&set, &m, on_r), Vec3::splat(0.14), TOL, "on R");
    // On N: 0.07 * 2 * 0.5^8 = 0.000546875.
    assert_close(
        at_origin(&set, &m, on_n),
        Vec3::splat(0.000_546_875),
        TOL,
        "on N",
    );
    let r = shade_reference(&set, &m, glam::DVec3::ZERO, glam::DVec3::Z, on_r.as_dvec3());
    assert!((r.x - 0.14).abs() < 1e-7, "reference {r}");
}

#[test]
fn fresnel_scale_multiplies_ks_by_w_theta() {
    // ks W(theta) Il (V.R)^ns = 0.5 * 0.07 * 2 * 1 = 0.07 on R.
    let (set, on_r, _) = fresnel_setup();
    let m = glass(0.5);
    assert_eq!(m.fresnel_mode, FresnelMode::Scale);
    assert_close(at_origin(&set, &m, on_r), Vec3::splat(0.07), TOL, "on R");
    // Scale with ks = 1 is replace: the same bits.
    let scale_one = glass(1.0);
    let replace = glass(0.5).with_fresnel_mode(FresnelMode::Replace);
    assert_eq!(
        at_origin(&set, &scale_one, on_r),
        at_origin(&set, &replace, on_r)
    );
    // Head-on incidence (N.L = 1): W = f0 = 0.04, so glass reflects 4 percent under replace.
    let head_on = LightSet::new(
        Vec3::ZERO,
        &[Light::directional(-Vec3::Z, Vec3::ONE).unwrap()],
    );
    assert_close(
        at_origin(&head_on, &replace, Vec3::Z),
        Vec3::splat(0.04),
        TOL,
        "head-on",
    );
}

#[test]
fn replace_with_another_ks_is_rejected_by_name() {
    let mut m = glass(0.5);
    m.fresnel_mode = FresnelMode::Replace;
    let e = m.validate().unwrap_err();
    assert!(
        e.to_string()
            .starts_with("ks: must be 1 under fresnel mode \"replace\""),
        "{e}"
    );
    assert!(m.with_fresnel_mode(FresnelMode::Replace).validate().is_ok());
    for mode in [FresnelMode::Scale, FresnelMode::Replace] {
        assert_eq!(mode.to_string().parse::<FresnelMode>(), Ok(mode));
    }
    assert!("multiply".parse::<FresnelMode>().is_err());
}

#[test]
fn perfect_reflector_is_seen_only_along_r() {
    // The lecture notes' perfect reflector, n_s infinite: Ks Il on R (V.R = 1), nothing on N
    // (V.R = 0.8), in the scalar, four-wide and f64 models alike.
    let set = LightSet::new(Vec3::ZERO, &[Light::point(LIGHT_POS, Vec3::ONE).unwrap()]);
    let m = material(0.0, 0.0, 0.5, f32::INFINITY);
    let on_r = Vec3::new(-0.6, 0.0, 0.8) * 5.0;
    let on_n = Vec3::Z * 5.0;
    assert_close(at_origin(&set, &m, on_r), Vec3::splat(0.5), TOL, "on R");
    assert_eq!(at_origin(&set, &m, on_n), Vec3::ZERO, "on N");
    for (eye, want) in [(on_r, 0.5), (on_n, 0.0)] {
        let r = shade_reference(&set, &m, glam::DVec3::ZERO, glam::DVec3::Z, eye.as_dvec3());
        assert!((r.x - want).abs() < 1e-6, "reference {r} for eye {eye}");
        let p = Vec3x4::splat(Vec3::ZERO);
        let n = Vec3x4::splat(Vec3::Z);
        for lane in shade_x4::<ALL>(&set, &m, p, n, eye).to_array() {
            assert_eq!(lane, at_origin(&set, &m, eye), "x4 for eye {eye}");
        }
    }
}
