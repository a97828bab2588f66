//! Hard lighting: a light on the surface and inside an object, extreme shininess, V along R,
//! N.L = 0 exactly, many lights summing past 1, inverse-square at d near 0. Through the
//! shade functions (exact expected values) and through the rasterizer in every mode (finite,
//! in `[0, 1]`, thread-count independent).

#![allow(clippy::unwrap_used)]

mod support;

use phosphor::lighting::{
    Attenuation, Effects, Light, LightSet, MIN_ATTENUATION_DENOMINATOR, Material, SpecularModel,
    shade, shade_reference, shade_split,
};
use phosphor::math::glam::{DVec3, Vec3};
use phosphor::mesh::primitives;
use phosphor::raster::ShadingMode;
use support::*;

const W: u32 = 64;
const H: u32 = 48;
const ALL: u32 = Effects::ALL.bits();

fn lit(lights: &[Light], material: Material) -> Setup {
    Setup {
        lights: LightSet::new(Vec3::ONE, lights),
        material,
        ..Setup::default()
    }
}

const MODELS: [Attenuation; 4] = [
    Attenuation::None,
    Attenuation::InverseSquare,
    Attenuation::Offset { k: 0.0 },
    Attenuation::Quadratic {
        c: 0.0,
        l: 0.0,
        q: 1.0,
    },
];

#[test]
fn light_on_the_surface_gives_finite_pixels() {
    // A point light exactly at a vertex and one exactly at the centre of the square (d = 0
    // for the pixels and the shade points there), under every attenuation model.
    let mat = Material::s1();
    for model in MODELS {
        let at = |p: Vec3| {
            Light::point(p, Vec3::splat(2.0))
                .unwrap()
                .with_attenuation(model)
                .unwrap()
        };
        // shade at the light's own position: it shines along the normal, capped.
        let set = LightSet::new(Vec3::ONE, &[at(Vec3::ZERO)]);
        let eye = Vec3::new(0.0, 0.0, 3.0);
        let i = shade::<ALL>(&set, &mat, Vec3::ZERO, Vec3::Z, eye);
        let f = model.max_factor();
        let expected = mat.ka + f * 2.0 * (mat.kd + mat.ks);
        assert!(
            (i - expected).abs().max_element() <= 1e-5 * expected.max_element(),
            "{model:?}: {i}"
        );
        let r = shade_reference(&set, &mat, DVec3::ZERO, DVec3::Z, eye.as_dvec3());
        assert!(r.is_finite() && (r.as_vec3() - i).abs().max_element() <= 1e-3 * i.max_element());

        let setup = lit(&[at(Vec3::ZERO), at(Vec3::new(-1.0, -1.0, 0.0))], mat);
        for (mode, fb, _) in
            render_all_modes(W, H, &TriMesh::square(), &setup, &format!("{model:?}"))
        {
            // Light in the plane: N.L = 0 for every surface point but the light's own, so the
            // per-pixel modes show ambient away from it.
            if matches!(mode, ShadingMode::Phong | ShadingMode::Reference) {
                let corner = fb.pixel(W / 2 + 8, H / 2 - 8);
                assert!(
                    (corner - Vec3::splat(0.1)).abs().max_element() < 1e-6,
                    "{mode}: {corner}"
                );
            }
        }
    }
}

#[test]
fn light_inside_a_closed_object_leaves_only_ambient_outside() {
    // Outward normals, the light at the centre: N.L < 0 everywhere on the outside, so every
    // covered pixel is exactly ka Ia in every mode, whatever the attenuation.
    let sphere: TriMesh = primitives::uv_sphere(1.0, 16, 8).into();
    for model in MODELS {
        let light = Light::point(Vec3::ZERO, Vec3::splat(5.0))
            .unwrap()
            .with_attenuation(model)
            .unwrap();
        let setup = lit(&[light], Material::s1());
        for (mode, fb, _) in render_all_modes(W, H, &sphere, &setup, "inside") {
            assert!(covered_pixels(&fb) > 0);
            for (c, z) in fb.color().iter().zip(fb.depth()) {
                if *z < 1.0 {
                    assert!(
                        (*c - Vec3::splat(0.1)).abs().max_element() < 1e-6,
                        "{mode}: {c}"
                    );
                }
            }
        }
    }
}

#[test]
fn shininess_0_1_10000_huge_and_infinite_give_bounded_specular() {
    // V exactly along R (normal, light and eye all on +Z): (V.R)^n_s = 1 for every n_s, for
    // Phong and Blinn, the perfect mirror (n_s = inf) included. Off the mirror direction
    // n_s = 0 still gives 1 (no fall-off) and the huge and infinite exponents give 0.
    let set = LightSet::new(
        Vec3::ZERO,
        &[Light::directional(-Vec3::Z, Vec3::ONE).unwrap()],
    );
    let (p, n) = (Vec3::ZERO, Vec3::Z);
    let on_r = Vec3::new(0.0, 0.0, 2.0);
    let off_r = Vec3::new(2.0, 0.0, 2.0);
    for shininess in [0.0, 1.0, 1e4, 1e30, f32::MAX, f32::INFINITY] {
        for model in [SpecularModel::Phong, SpecularModel::Blinn] {
            let mat = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::splat(0.5), shininess)
                .unwrap()
                .with_specular(model);
            let peak = shade_split::<ALL>(&set, &mat, p, n, on_r).specular;
            assert_eq!(peak, Vec3::splat(0.5), "n_s {shininess} {model:?} on R");
            let off = shade_split::<ALL>(&set, &mat, p, n, off_r).specular;
            assert!(off.is_finite() && off.max_element() <= 0.5, "{off}");
            if shininess == 0.0 {
                assert_eq!(off, Vec3::splat(0.5), "n_s 0 has no fall-off");
            }
            if shininess >= 1e4 {
                assert_eq!(off, Vec3::ZERO, "n_s {shininess} off R");
            }
        }
        // And rendered: S1's sphere and lights, that shininess.
        let sphere: TriMesh = primitives::uv_sphere(1.0, 16, 8).into();
        let setup = lit(
            &Light::s1_lights(),
            Material {
                shininess,
                ..Material::s1()
            },
        );
        render_all_modes(W, H, &sphere, &setup, &format!("n_s {shininess}"));
    }
    // A NaN n_s is refused with a message naming the field.
    let e = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::ONE, f32::NAN).unwrap_err();
    assert!(e.to_string().contains("shininess"), "{e}");
}

#[test]
fn view_along_the_mirror_direction_peaks_on_the_centre_at_most_ks_il() {
    // The eye on +Z, a light from the eye's direction: R = V at the square's centre, the
    // image centre (between four pixel centres). With n_s = 10000 the lobe is about two
    // pixels wide: every mode stays finite and in [0, 1] and never exceeds ks Il = 0.5, and
    // the modes that evaluate the model per pixel put the peak on the four centre pixels.
    let light = Light::directional(-Vec3::Z, Vec3::ONE).unwrap();
    let mat = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::splat(0.5), 1e4).unwrap();
    let setup = lit(&[light], mat);
    for (mode, fb, _) in render_all_modes(W, H, &TriMesh::square(), &setup, "V along R") {
        let brightest = fb
            .color()
            .iter()
            .map(|c| c.max_element())
            .fold(0.0, f32::max);
        assert!(brightest <= 0.5 + 1e-6, "{mode}: {brightest}");
        if matches!(mode, ShadingMode::Phong | ShadingMode::Reference) {
            let centre =
                [(31, 23), (32, 23), (31, 24), (32, 24)].map(|(x, y)| fb.pixel(x, y).max_element());
            assert!(
                centre.iter().all(|c| *c >= brightest * 0.999 && *c > 0.2),
                "{mode}: {centre:?}"
            );
        }
    }
}

#[test]
fn n_dot_l_exactly_zero_gives_exactly_ambient() {
    // Lights in the plane of the square (directional along it, point lights on its plane):
    // N.L = 0 exactly at every surface point, so neither diffuse nor specular contributes.
    let lights = [
        Light::directional(Vec3::X, Vec3::splat(3.0)).unwrap(),
        Light::directional(Vec3::new(1.0, -2.0, 0.0), Vec3::splat(3.0)).unwrap(),
        Light::point(Vec3::new(5.0, 0.3, 0.0), Vec3::splat(3.0)).unwrap(),
        Light::point(Vec3::new(-0.2, 0.1, 0.0), Vec3::splat(3.0)).unwrap(),
    ];
    // Through shade: exactly the ambient term.
    let set = LightSet::new(Vec3::ONE, &lights);
    let mat = Material::s1();
    for p in [Vec3::new(0.3, -0.7, 0.0), Vec3::new(-0.9, 0.9, 0.0)] {
        let i = shade::<ALL>(&set, &mat, p, Vec3::Z, Vec3::new(0.0, 0.0, 3.0));
        assert_eq!(i, mat.ka, "at {p}");
    }
    for (mode, fb, _) in render_all_modes(W, H, &TriMesh::square(), &lit(&lights, mat), "N.L = 0") {
        for (c, z) in fb.color().iter().zip(fb.depth()) {
            if *z < 1.0 {
                assert!((*c - mat.ka).abs().max_element() < 1e-6, "{mode}: {c}");
            }
        }
    }
}

#[test]
fn sixteen_lights_summing_past_one_clamp_to_exactly_one() {
    // 16 directional lights within 40 degrees of the view axis, Il = 1 each: the diffuse sum
    // is above 5 in every channel, so every covered pixel is clamped to exactly 1.
    let lights: Vec<Light> = (0..16)
        .map(|k| {
            let a = std::f32::consts::TAU * k as f32 / 16.0;
            let tilt = 40f32.to_radians() * (k % 4 + 1) as f32 / 4.0;
            let to_light = Vec3::new(tilt.sin() * a.cos(), tilt.sin() * a.sin(), tilt.cos());
            Light::directional(-to_light, Vec3::ONE).unwrap()
        })
        .collect();
    let setup = lit(&lights, Material::s1());
    let raw = shade::<ALL>(
        &setup.lights,
        &setup.material,
        Vec3::ZERO,
        Vec3::Z,
        Vec3::new(0.0, 0.0, 3.0),
    );
    assert!(raw.min_element() > 5.0 && raw.is_finite(), "{raw}");
    for (mode, fb, _) in render_all_modes(W, H, &TriMesh::square(), &setup, "16 lights") {
        assert!(covered_pixels(&fb) > 0);
        for (c, z) in fb.color().iter().zip(fb.depth()) {
            if *z < 1.0 {
                assert_eq!(*c, Vec3::ONE, "{mode}");
            }
        }
    }
}

#[test]
fn inverse_square_near_zero_distance_is_capped_and_finite() {
    // A light ever closer to the surface under 1/d^2: the factor grows until the cap
    // 1/MIN_ATTENUATION_DENOMINATOR and never becomes infinite.
    let mat = Material::s1();
    let eye = Vec3::new(0.0, 0.0, 3.0);
    let cap = 1.0 / MIN_ATTENUATION_DENOMINATOR;
    let mut last = 0.0;
    for d in [
        1.0f32, 1e-1, 1e-2, 1e-3, 1e-6, 1e-12, 1e-20, 1e-38, 1e-45, 0.0,
    ] {
        let light = Light::point(Vec3::new(0.0, 0.0, d), Vec3::ONE)
            .unwrap()
            .with_attenuation(Attenuation::InverseSquare)
            .unwrap();
        let set = LightSet::new(Vec3::ZERO, &[light]);
        let diffuse = shade_split::<ALL>(&set, &mat, Vec3::ZERO, Vec3::Z, eye).diffuse;
        assert!(diffuse.is_finite(), "d {d}: {diffuse}");
        let factor = diffuse.x / mat.kd.x;
        assert!(
            factor >= last * (1.0 - 1e-6),
            "d {d}: the factor fell to {factor}"
        );
        assert!(
            factor <= cap * (1.0 + 1e-6),
            "d {d}: factor {factor} above the cap"
        );
        last = factor;
        let r = shade_reference(&set, &mat, DVec3::ZERO, DVec3::Z, eye.as_dvec3());
        assert!(r.is_finite() && r.max_element() <= f64::from(cap) * 2.0);
        // Rendered: the light just above the square's centre.
        let setup = Setup {
            lights: set,
            material: mat,
            ..Setup::default()
        };
        render_all_modes(W, H, &TriMesh::square(), &setup, &format!("d {d}"));
    }
    assert!(
        (last - cap).abs() <= cap * 1e-6,
        "at d = 0 the factor is the cap"
    );
}
