//! Property tests over families of hard inputs: random triangles (degenerate, tiny, huge,
//! behind the camera) through every shading mode, and random normals, points and lights
//! through the shade functions. 64 cases each, so CI stays fast; failures shrink to a minimal
//! case that proptest prints.

#![allow(clippy::unwrap_used)]

mod support;

use phosphor::lighting::{
    Attenuation, Effects, Fresnel, Light, LightKind, LightSet, Material, SpecularModel, shade,
    shade_reference, shade_split,
};
use phosphor::math::glam::Vec3;
use phosphor::raster::{DrawItem, ShadingMode};
use proptest::prelude::*;
use support::*;

const ALL: u32 = Effects::ALL.bits();

/// A coordinate at any scale from 1e-7 to 1e30, either sign, or exactly 0.
fn coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => -3.0f32..3.0,
        1 => Just(0.0f32),
        1 => (-1.0f32..1.0, -7i32..31).prop_map(|(m, e)| m * 10f32.powi(e)),
    ]
}

fn point() -> impl Strategy<Value = Vec3> {
    (coordinate(), coordinate(), coordinate()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Any vector: unit, zero, tiny, huge, non-unit.
fn any_normal() -> impl Strategy<Value = Vec3> {
    prop_oneof![
        4 => point(),
        1 => Just(Vec3::ZERO),
        1 => Just(Vec3::splat(1e-40)),
    ]
}

/// A triangle: three free corners, or a degenerate one (repeated or collinear corners).
fn triangle() -> impl Strategy<Value = [Vec3; 3]> {
    prop_oneof![
        4 => [point(), point(), point()],
        1 => (point(), point()).prop_map(|(a, b)| [a, a, b]),
        1 => (point(), point(), 0.0f32..3.0).prop_map(|(a, b, t)| [a, b, a + (b - a) * t]),
    ]
}

fn mesh() -> impl Strategy<Value = TriMesh> {
    prop::collection::vec(
        (triangle(), [any_normal(), any_normal(), any_normal()]),
        1..6,
    )
    .prop_map(|tris| {
        let mut m = TriMesh::default();
        for (p, n) in tris {
            m.push_triangle(p, n);
        }
        m
    })
}

fn attenuation() -> impl Strategy<Value = Attenuation> {
    prop_oneof![
        Just(Attenuation::None),
        Just(Attenuation::InverseSquare),
        (0.0f32..2.0).prop_map(|k| Attenuation::Offset { k }),
        (0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0).prop_map(|(c, l, q)| Attenuation::Quadratic {
            c,
            l,
            q
        }),
    ]
}

fn light() -> impl Strategy<Value = Light> {
    let il = (0.0f32..10.0).prop_map(Vec3::splat);
    prop_oneof![
        (point(), il.clone(), attenuation())
            .prop_map(|(p, il, a)| Light::point(p, il).unwrap().with_attenuation(a).unwrap()),
        (point(), il.clone()).prop_map(|(d, il)| {
            // Directions must be non-zero; a zero draw becomes straight down.
            let d = if d.length_squared() > 1e-30 {
                d
            } else {
                -Vec3::Y
            };
            Light::directional(d, il).unwrap()
        }),
        (
            point(),
            point(),
            0.0f32..90.0,
            0.0f32..90.0,
            il,
            attenuation()
        )
            .prop_map(|(p, axis, a, b, il, att)| {
                let axis = if axis.length_squared() > 1e-30 {
                    axis
                } else {
                    Vec3::Z
                };
                let kind = LightKind::Spot {
                    position: p,
                    direction: axis,
                    inner_deg: a.min(b),
                    outer_deg: a.max(b),
                };
                Light::new(kind, il).unwrap().with_attenuation(att).unwrap()
            }),
    ]
}

fn material() -> impl Strategy<Value = Material> {
    (
        0.0f32..1.0,
        0.0f32..1.0,
        0.0f32..1.0,
        prop_oneof![Just(0.0f32), 0.0f32..200.0, Just(1e4), Just(f32::MAX)],
        any::<bool>(),
        prop_oneof![
            Just(Fresnel::None),
            (0.0f32..1.0).prop_map(|f0| Fresnel::Schlick { f0 })
        ],
    )
        .prop_map(|(ka, kd, ks, shininess, blinn, fresnel)| {
            Material::new(Vec3::splat(ka), Vec3::splat(kd), Vec3::splat(ks), shininess)
                .unwrap()
                .with_specular(if blinn {
                    SpecularModel::Blinn
                } else {
                    SpecularModel::Phong
                })
                .with_fresnel(fresnel)
                .unwrap()
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_triangles_give_finite_pixels_in_every_mode(
        mesh in mesh(),
        lights in prop::collection::vec(light(), 0..4),
        material in material(),
    ) {
        let setup = Setup { lights: LightSet::new(Vec3::splat(0.5), &lights), material, ..Setup::default() };
        // All modes in one frame (one draw each) and each mode alone, 1 and 2 threads.
        let draws: Vec<DrawItem> = ShadingMode::ALL.into_iter().map(|m| draw(&mesh, &setup, m)).collect();
        render_checked(40, 30, &setup.camera, &draws, "all modes");
        render_all_modes(40, 30, &mesh, &setup, "random triangles");
        let hits = coverage(40, 30, &setup.camera, &mesh, setup.model);
        prop_assert!(hits.iter().all(|&h| h as usize <= mesh.indices.len()));
    }

    #[test]
    fn random_normals_points_and_lights_shade_finite_and_bounded(
        p in point(),
        n in any_normal(),
        eye in point(),
        lights in prop::collection::vec(light(), 0..6),
        material in material(),
    ) {
        let set = LightSet::new(Vec3::splat(0.5), &lights);
        let terms = shade_split::<ALL>(&set, &material, p, n, eye);
        let total = shade::<ALL>(&set, &material, p, n, eye);
        for v in [terms.ambient, terms.diffuse, terms.specular, total] {
            prop_assert!(v.is_finite() && v.min_element() >= 0.0, "{:?}", terms);
        }
        // The model's bound: emission + ka Ia + sum max f(d) Il (kd + ks max W).
        let bound: f32 = 0.5 * material.ka.x
            + lights.iter().map(|l| {
                let f = if matches!(l.kind, LightKind::Directional { .. }) { 1.0 } else { l.attenuation.max_factor() };
                f * l.intensity.x * (material.kd.x + material.ks.x * material.fresnel.max_w())
            }).sum::<f32>();
        prop_assert!(total.x <= bound * (1.0 + 1e-5) + 1e-6, "{} > {}", total.x, bound);
        let r = shade_reference(&set, &material, p.as_dvec3(), n.as_dvec3(), eye.as_dvec3());
        prop_assert!(r.is_finite() && r.min_element() >= 0.0);
        prop_assert!(r.x <= f64::from(bound) * (1.0 + 1e-5) + 1e-6, "reference {} > {}", r.x, bound);
    }
}
