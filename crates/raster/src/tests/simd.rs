//! Every SIMD level this CPU runs gives the same picture, bit for bit: `phong`'s by-pixel pass
//! and `gouraud`'s vertices at four lanes (the baseline) and at eight (AVX2), across
//! perspective and screen-linear attributes, multisampling, culling, thread counts and image
//! widths that leave partly filled groups.

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
    for (material, mode) in materials
        .iter()
        .flat_map(|m| [(m, ShadingMode::Phong), (m, ShadingMode::Gouraud)])
    {
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
