//! The cost of the frame plan on a big world: 10,000 objects and 16 lights, against the
//! 1280x720 frame it plans ("the plan step must cost no more than a few percent of a frame").
//!
//! `cargo bench --bench plan` (set `PHOSPHOR_BENCH_QUICK=1` for a short run).

#![allow(clippy::unwrap_used, reason = "benchmark set-up on known-good data")]

use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use phosphor::lighting::{Attenuation, Light, Material};
use phosphor::math::glam::Vec3;
use phosphor::mesh::primitives::uv_sphere;
use phosphor::raster::{Camera, Framebuffer};
use phosphor::scene::{
    FrameOptions, MaterialDef, MaterialName, MeshInfo, MeshRef, MeshSource, Name, Primitive, Scene,
    SceneMesh, Transform, plan_frame, render_frame,
};

/// A 100 x 100 grid of small spheres (one shared mesh) under 16 coloured point lights.
fn big_world() -> Scene {
    let prim = Primitive::Sphere {
        radius: 0.04,
        segments: 12,
        rings: 6,
    };
    let mesh = uv_sphere(0.04, 12, 6);
    let info = MeshInfo::of(&mesh);
    let shared = Arc::new(SceneMesh {
        mesh,
        source: MeshSource::Primitive(prim),
        normals: Default::default(),
        normalized: false,
        info,
    });
    let mut scene = Scene::empty();
    scene.ambient = Vec3::splat(0.2);
    scene.set_camera(Camera {
        eye: Vec3::new(0.0, 3.0, 6.0),
        target: Vec3::ZERO,
        far: 50.0,
        ..Camera::s1()
    });
    let material = Material {
        ks: Vec3::splat(0.4),
        shininess: 16.0,
        ..Material::default()
    };
    scene.materials.insert(
        "m".into(),
        MaterialDef {
            material,
            bump: None,
            kd_map: None,
        },
    );
    for i in 0..16 {
        let a = i as f32 / 16.0 * std::f32::consts::TAU;
        let light = Light::point(
            Vec3::new(3.0 * a.cos(), 1.5, 3.0 * a.sin()),
            Vec3::new(0.3 + 0.2 * a.sin().abs(), 0.3, 0.3 + 0.2 * a.cos().abs()),
        )
        .unwrap()
        .with_attenuation(Attenuation::Offset { k: 1.0 })
        .unwrap();
        scene.world.spawn((Name(format!("light {i}")), light));
    }
    for i in 0..10_000 {
        let (x, z) = ((i % 100) as f32, (i / 100) as f32);
        scene.world.spawn((
            Name(format!("sphere {i}")),
            Transform {
                translate: Vec3::new((x - 49.5) * 0.1, 0.0, (z - 49.5) * 0.1),
                ..Transform::default()
            },
            MeshRef(shared.clone()),
            material,
            MaterialName("m".into()),
        ));
    }
    scene
}

fn plan_cost(c: &mut Criterion) {
    let quick = std::env::var_os("PHOSPHOR_BENCH_QUICK").is_some();
    let scene = big_world();
    let mut g = c.benchmark_group("plan_10k_objects_16_lights");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(if quick { 2 } else { 6 }));
    let camera = scene.camera();
    let opts = FrameOptions::default();
    g.bench_function("plan", |b| {
        b.iter(|| black_box(plan_frame(&scene, &camera, (1280, 720), &opts)))
    });
    let mut fb = Framebuffer::new(1280, 720).unwrap();
    g.bench_function("frame_1280x720", |b| {
        b.iter(|| black_box(render_frame(&scene, &mut fb, &opts).stats))
    });
    g.finish();
}

criterion_group!(benches, plan_cost);
criterion_main!(benches);
