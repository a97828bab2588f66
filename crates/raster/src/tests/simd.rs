//! Every SIMD level this CPU runs gives the same picture, bit for bit: `phong`'s by-pixel pass,
//! `gouraud`'s vertices and the small triangles' coverage and depth in lanes (`flat`, and every
//! depth pass) with `wide`'s vectors (the baseline) and with AVX2, across
//! perspective and screen-linear attributes, multisampling, culling, thread counts and image
//! widths that leave partly filled groups; stepped triangles and textured draws too.

use glam::Vec3;
use phosphor_lighting::{Fresnel, Material, SpecularModel};

use super::support::{draw_image, item, s1_lights, uv_sphere};
use crate::{Antialias, Camera, Framebuffer, RenderOptions, ShadingMode, SimdLevel};

fn bits(fb: &Framebuffer) -> Vec<[u32; 3]> {
    fb.color()
        .iter()
        .map(|c| c.to_array().map(f32::to_bits))
        .collect()
}

/// The levels this CPU runs, each named once (`Auto` resolves to one of them).
fn levels() -> Vec<SimdLevel> {
    [SimdLevel::Baseline, SimdLevel::Avx2]
        .into_iter()
        .filter(|l| l.resolve() == *l)
        .collect()
}

#[test]
fn every_level_this_cpu_runs_draws_the_same_bits() {
    let levels = levels();
    assert_eq!(levels[0], SimdLevel::Baseline);
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        assert_eq!(levels, [SimdLevel::Baseline, SimdLevel::Avx2]);
    }
    let cam = Camera::s1();
    let mesh = uv_sphere(0.8, 48, 24);
    let lights = s1_lights();
    let materials = [
        Material::s1(),
        Material::s1().with_specular(SpecularModel::Blinn),
        Material::s1()
            .with_fresnel(Fresnel::Schlick { f0: 0.04 })
            .unwrap(),
    ];
    for (material, mode) in materials.iter().flat_map(|m| {
        [ShadingMode::Phong, ShadingMode::Gouraud, ShadingMode::Flat].map(|mode| (m, mode))
    }) {
        let draws = [item(&mesh, material, &lights, mode)];
        for (size, perspective, aa, cull, threads) in [
            ((97, 61), true, Antialias::Off, false, 1),
            ((97, 61), false, Antialias::Off, true, 2),
            ((64, 48), true, Antialias::Msaa4, false, 3),
            ((53, 41), true, Antialias::Msaa16, true, 1),
        ] {
            let render = |simd| {
                let opts = RenderOptions {
                    threads,
                    perspective_correct: perspective,
                    cull_backfaces: cull,
                    antialias: aa,
                    background: Vec3::new(0.1, 0.2, 0.3),
                    simd,
                    ..RenderOptions::default()
                };
                draw_image(size.0, size.1, &cam, &draws, &opts)
            };
            let (base, base_stats) = render(SimdLevel::Baseline);
            assert_eq!(base_stats.simd, SimdLevel::Baseline);
            assert!(base_stats.pixels_shaded > 500, "{base_stats:?}");
            for &level in &levels[1..] {
                let (fb, stats) = render(level);
                assert_eq!(stats.simd, level);
                assert_eq!(stats.pixels_shaded, base_stats.pixels_shaded);
                assert!(
                    bits(&fb) == bits(&base),
                    "{level} differs from the baseline: {mode:?} {size:?} perspective {perspective} {aa:?}"
                );
            }
        }
    }
}

#[test]
fn long_runs_evaluated_in_lanes_give_the_same_bits_at_every_level() {
    // A coarse sphere's rows are runs of tens of pixels of one triangle: the by-pixel pass
    // evaluates them four pixels to a lane group, filling four lanes at the baseline and
    // eight with AVX2, and steps the runs' last pixels one by one. Both levels must cut the
    // runs alike, and give each pixel the same bits.
    let levels = levels();
    let cam = Camera::s1();
    let mesh = uv_sphere(0.8, 10, 6);
    let lights = s1_lights();
    let material = Material::s1();
    let draws = [item(&mesh, &material, &lights, ShadingMode::Phong)];
    for (size, perspective, threads) in [((203, 151), true, 1), ((190, 140), false, 2)] {
        let render = |simd| {
            let opts = RenderOptions {
                threads,
                perspective_correct: perspective,
                background: Vec3::new(0.1, 0.2, 0.3),
                simd,
                ..RenderOptions::default()
            };
            draw_image(size.0, size.1, &cam, &draws, &opts)
        };
        let (base, base_stats) = render(SimdLevel::Baseline);
        assert!(base_stats.pixels_shaded > 5_000, "{base_stats:?}");
        for &level in &levels[1..] {
            let (fb, stats) = render(level);
            assert_eq!(stats.pixels_shaded, base_stats.pixels_shaded);
            assert!(
                bits(&fb) == bits(&base),
                "{level} differs from the baseline: {size:?} perspective {perspective}"
            );
        }
    }
}

#[test]
fn stepped_and_textured_draws_give_the_same_bits_at_every_level() {
    // Stepped triangles (fast-phong's two methods, flat textured) are shaded from a queue of
    // one triangle's pixels, and textured draws step sixteen attributes in the by-pixel loop:
    // both in four lanes at the baseline and eight with AVX2.
    use crate::FastPhongMethod;
    use crate::texture::Texture;
    let levels = levels();
    let cam = Camera::s1();
    // Coarse, so that fast-phong's fit (triangles of 128 px or more) is tried; fine for
    // Taylor, which S1's point lights defeat on large triangles.
    let (coarse, fine) = (uv_sphere(0.8, 12, 8), uv_sphere(0.8, 48, 24));
    let lights = s1_lights();
    let material = Material::s1();
    let texels = (0..64 * 64)
        .map(|k: u32| {
            let (i, j) = (k % 64, k / 64);
            Vec3::new(
                i as f32 / 63.0,
                j as f32 / 63.0,
                ((i / 8 + j / 8) % 2) as f32,
            )
        })
        .collect();
    let texture = Texture::new(64, 64, texels).unwrap();
    let mut cases = Vec::new();
    for method in FastPhongMethod::ALL {
        cases.push((ShadingMode::FastPhong, method, false));
    }
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        cases.push((mode, FastPhongMethod::Fit, true));
    }
    for (mode, method, textured) in cases {
        let mesh = if method == FastPhongMethod::Taylor {
            &fine
        } else {
            &coarse
        };
        let mut draw = item(mesh, &material, &lights, mode);
        if textured {
            draw.texture = Some(&texture);
        }
        let draws = [draw];
        for (size, aa, threads) in [
            ((160, 100), Antialias::Off, 1),
            ((128, 96), Antialias::Msaa4, 3),
        ] {
            let render = |simd| {
                let opts = RenderOptions {
                    threads,
                    antialias: aa,
                    fast_phong: method,
                    simd,
                    ..RenderOptions::default()
                };
                draw_image(size.0, size.1, &cam, &draws, &opts)
            };
            let (base, base_stats) = render(SimdLevel::Baseline);
            assert!(base_stats.pixels_shaded > 500, "{base_stats:?}");
            if mode == ShadingMode::FastPhong {
                // Some triangles are stepped, not all fall back to phong.
                assert!(
                    base_stats.fallbacks < base_stats.triangles_drawn,
                    "{method:?} {base_stats:?}"
                );
            }
            for &level in &levels[1..] {
                let (fb, stats) = render(level);
                assert_eq!(stats.pixels_shaded, base_stats.pixels_shaded);
                assert!(
                    bits(&fb) == bits(&base),
                    "{level} differs from the baseline: {mode:?} {method:?} textured {textured} {aa:?}"
                );
            }
        }
    }
}
