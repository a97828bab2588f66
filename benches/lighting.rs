//! Cost per `phosphor_lighting::shade` call as effects are added (ambient only, + diffuse,
//! + specular, + Fresnel, + attenuation) with 1, 3 and 8 point lights.
//!
//! The `x4/` group: four scalar `shade` calls against one `shade_x4` call on S1's lights and
//! material.
//!
//! Run: `cargo bench --bench lighting -- --quick` (or `-- x4/ --quick` for the SIMD pair)

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use phosphor::lighting::{
    Attenuation, Effects, Fresnel, Light, LightSet, Material, Vec3x4, shade, shade_x4,
};
use phosphor::math::glam::Vec3;

const AMBIENT: u32 = Effects::AMBIENT.bits();
const DIFFUSE: u32 = AMBIENT | Effects::DIFFUSE.bits();
const SPECULAR: u32 = DIFFUSE | Effects::SPECULAR.bits();
const FRESNEL: u32 = SPECULAR | Effects::FRESNEL.bits();
const ATTENUATION: u32 = FRESNEL | Effects::ATTENUATION.bits();

/// `count` point lights around the unit sphere, with the lecture notes' 1/(K+d) attenuation.
fn lights(count: usize) -> LightSet {
    let lights: Vec<Light> = (0..count)
        .filter_map(|i| {
            let a = i as f32 * 2.4;
            let position = Vec3::new(2.0 * a.cos(), 1.0 + 0.3 * i as f32, 2.0 * a.sin() + 1.0);
            Light::point(position, Vec3::splat(1.5))
                .and_then(|l| l.with_attenuation(Attenuation::Offset { k: 1.0 }))
                .ok()
        })
        .collect();
    LightSet::new(Vec3::ONE, &lights)
}

fn bench_level<const FX: u32>(c: &mut Criterion, name: &str) {
    let mat = Material::s1()
        .with_fresnel(Fresnel::Schlick { f0: 0.04 })
        .unwrap_or_else(|_| Material::s1());
    let eye = Vec3::new(0.0, 0.0, 3.0);
    // A ring of surface points and normals on the front of a unit sphere.
    let points: Vec<(Vec3, Vec3)> = (0..64)
        .map(|i| {
            let a = i as f32 * 0.1;
            let n = Vec3::new(0.5 * a.cos(), 0.5 * a.sin(), 1.0).normalize();
            (n, n)
        })
        .collect();
    for count in [1, 3, 8] {
        let set = lights(count);
        let mut i = 0;
        c.bench_function(&format!("shade/{name}/{count}_lights"), |b| {
            b.iter(|| {
                i = (i + 1) & 63;
                let (p, n) = points[i];
                shade::<FX>(
                    black_box(&set),
                    black_box(&mat),
                    black_box(p),
                    black_box(n),
                    eye,
                )
            });
        });
    }
}

fn shading_levels(c: &mut Criterion) {
    bench_level::<AMBIENT>(c, "ambient");
    bench_level::<DIFFUSE>(c, "diffuse");
    bench_level::<SPECULAR>(c, "specular");
    bench_level::<FRESNEL>(c, "fresnel");
    bench_level::<ATTENUATION>(c, "attenuation");
}

/// The rasterizer's instantiation for S1 (ambient, diffuse, emission, spot, distributed,
/// specular, attenuation): four scalar calls against one four-lane call, same 4 pixels.
fn scalar_vs_x4(c: &mut Criterion) {
    const FX: u32 = Effects::AMBIENT.bits()
        | Effects::DIFFUSE.bits()
        | Effects::EMISSION.bits()
        | Effects::SPOT.bits()
        | Effects::DISTRIBUTED.bits()
        | Effects::SPECULAR.bits()
        | Effects::ATTENUATION.bits();
    let (set, mat, eye) = (LightSet::s1(), Material::s1(), Vec3::new(0.0, 0.0, 3.0));
    // 64 quads of unit normals on the front of a unit sphere (p = n).
    let quads: Vec<[Vec3; 4]> = (0..64)
        .map(|q| {
            [0, 1, 2, 3].map(|j| {
                let a = (4 * q + j) as f32 * 0.1;
                Vec3::new(0.5 * a.cos(), 0.5 * a.sin(), 1.0).normalize()
            })
        })
        .collect();
    let mut i = 0;
    c.bench_function("x4/s1/4x_shade", |b| {
        b.iter(|| {
            i = (i + 1) & 63;
            let q = black_box(quads[i]);
            q.map(|n| shade::<FX>(black_box(&set), black_box(&mat), n, n, eye))
        });
    });
    let wide: Vec<Vec3x4> = quads.iter().map(|&q| Vec3x4::from(q)).collect();
    let mut i = 0;
    c.bench_function("x4/s1/shade_x4", |b| {
        b.iter(|| {
            i = (i + 1) & 63;
            let q = black_box(wide[i]);
            shade_x4::<FX>(black_box(&set), black_box(&mat), q, q, eye)
        });
    });
}

criterion_group!(benches, shading_levels, scalar_vs_x4);
criterion_main!(benches);
