//! `shade_x4` against four scalar `shade` calls, and on CPUs with AVX2 the eight-lane
//! `shade_lanes` against eight: the same bits in every lane and channel, for
//! the rasterizer's effect sets, random lights and materials (valid and not), and the edge
//! inputs each scalar branch exists for (zero, tiny, huge, non-unit, NaN and infinite normals,
//! a point at a light, the eye at the point).

use glam::Vec3;
use proptest::prelude::*;

use super::support::{Rng, random_attenuation, random_light, random_material};
use crate::{Effects, Fresnel, Light, LightKind, LightSet, Material, Vec3x4, shade, shade_x4};
#[cfg(target_arch = "x86_64")]
use crate::{Vec3s, shade_lanes};

const BASE: u32 = Effects::AMBIENT.bits()
    | Effects::DIFFUSE.bits()
    | Effects::EMISSION.bits()
    | Effects::SPOT.bits()
    | Effects::DISTRIBUTED.bits();
const S: u32 = Effects::SPECULAR.bits();
const A: u32 = Effects::ATTENUATION.bits();
const F: u32 = Effects::FRESNEL.bits();

/// Lane-by-lane, channel-by-channel bit equality with the scalar model, at four lanes and
/// (where the CPU has AVX2) eight.
fn check<const FX: u32>(set: &LightSet, mat: &Material, p: [Vec3; 4], n: [Vec3; 4], eye: Vec3) {
    check4::<FX>(set, mat, p, n, eye);
    #[cfg(target_arch = "x86_64")]
    check8::<FX>(set, mat, p, n, eye);
}

/// Eight lanes: the four points, then the same four in reverse order (so that every lane
/// position sees every kind of input).
#[cfg(target_arch = "x86_64")]
fn check8<const FX: u32>(set: &LightSet, mat: &Material, p: [Vec3; 4], n: [Vec3; 4], eye: Vec3) {
    let Some(avx2) = crate::Avx2::detect() else {
        return;
    };
    let eight =
        |v: [Vec3; 4]| -> [Vec3; 8] { std::array::from_fn(|i| v[if i < 4 { i } else { 7 - i }]) };
    let (p8, n8) = (eight(p), eight(n));
    let wide = avx2.run(|s: crate::Avx2| {
        let w = s.splat(0.0);
        let (p, n) = (Vec3s::from_vecs(w, p8), Vec3s::from_vecs(w, n8));
        shade_lanes::<FX, _>(set, mat, p, n, eye).to_vecs()
    });
    for i in 0..8 {
        let one = shade::<FX>(set, mat, p8[i], n8[i], eye);
        assert_eq!(
            wide[i].to_array().map(f32::to_bits),
            one.to_array().map(f32::to_bits),
            "FX {FX:#x} lane {i} of 8: x8 {} vs scalar {}\np {p8:?}\nn {n8:?}\neye {eye}",
            wide[i],
            one,
        );
    }
}

fn check4<const FX: u32>(set: &LightSet, mat: &Material, p: [Vec3; 4], n: [Vec3; 4], eye: Vec3) {
    let wide = shade_x4::<FX>(set, mat, Vec3x4::from(p), Vec3x4::from(n), eye).to_array();
    for i in 0..4 {
        let one = shade::<FX>(set, mat, p[i], n[i], eye);
        assert_eq!(
            wide[i].to_array().map(f32::to_bits),
            one.to_array().map(f32::to_bits),
            "FX {FX:#x} lane {i}: x4 {} vs scalar {}\np {p:?}\nn {n:?}\neye {eye}\nmat {mat:?}\nset {set:?}",
            wide[i],
            one,
        );
    }
}

/// The rasterizer's six instantiations, plus a few more corners of the effect space.
fn check_all(set: &LightSet, mat: &Material, p: [Vec3; 4], n: [Vec3; 4], eye: Vec3) {
    check::<BASE>(set, mat, p, n, eye);
    check::<{ BASE | S }>(set, mat, p, n, eye);
    check::<{ BASE | A }>(set, mat, p, n, eye);
    check::<{ BASE | S | A }>(set, mat, p, n, eye);
    check::<{ BASE | S | F }>(set, mat, p, n, eye);
    check::<{ BASE | S | F | A }>(set, mat, p, n, eye);
    check::<{ Effects::ALL.bits() }>(set, mat, p, n, eye);
    check::<{ Effects::AMBIENT.bits() | Effects::EMISSION.bits() }>(set, mat, p, n, eye);
    check::<{ S | F | A | Effects::SPOT.bits() }>(set, mat, p, n, eye);
    check::<{ Effects::DIFFUSE.bits() | A }>(set, mat, p, n, eye);
}

/// A normal of one of the kinds the scalar `unit_normal` and `safe_normalize` tell apart.
fn edge_normal(rng: &mut Rng) -> Vec3 {
    let unit = rng.vec(-1.0, 1.0).try_normalize().unwrap_or(Vec3::Z);
    match rng.below(16) {
        0 => Vec3::ZERO,
        1 => Vec3::splat(-0.0),
        2 => unit * 1e-20,                    // squared length below the minimum
        3 => unit * f32::MIN_POSITIVE * 0.25, // subnormal
        4 => unit * 1e30,                     // squared length overflows
        5 => Vec3::new(f32::NAN, unit.y, unit.z), // non-finite
        6 => Vec3::new(unit.x, f32::INFINITY, unit.z), // non-finite
        7 => unit * (1.0 + 4e-7),             // within the unit tolerance
        8 => unit * (1.0 + 1e-5),             // just outside it
        9 => unit * rng.range(0.01, 10.0),    // non-unit
        10 => Vec3::splat(f32::MAX),          // overflow with all components huge
        11 => Vec3::new(-1.0, 0.0, 0.0),      // exactly axis-aligned
        _ => unit,
    }
}

/// A point near the lights, at one of them, or somewhere absurd.
fn edge_point(rng: &mut Rng, set: &LightSet, eye: Vec3) -> Vec3 {
    let positions: Vec<Vec3> = set
        .points()
        .iter()
        .chain(set.spots().iter().map(|s| &s.point))
        .chain(set.distributed_samples())
        .map(|l| l.position)
        .collect();
    match rng.below(12) {
        0 if !positions.is_empty() => positions[rng.below(positions.len() as u64) as usize],
        1 if !positions.is_empty() => {
            positions[rng.below(positions.len() as u64) as usize] + Vec3::splat(1e-17)
        }
        2 => eye,
        3 => Vec3::new(f32::NAN, 0.0, 0.0),
        4 => Vec3::new(0.0, f32::NEG_INFINITY, 1.0),
        5 => rng.vec(-1.0, 1.0) * 1e25, // distance squared overflows
        6 => rng.vec(-1.0, 1.0) * 1e19, // distance beyond MAX_LIGHT_DISTANCE
        _ => rng.vec(-3.0, 3.0),
    }
}

/// Shininess values covering the squaring path (0, 1, odd, even, 256), powf (257, fractions,
/// huge, infinite) and what `clamped_pow` maps to 0 (negative, NaN).
fn edge_material(rng: &mut Rng) -> Material {
    let mut mat = random_material(rng);
    mat.shininess = [
        0.0,
        1.0,
        2.0,
        3.0,
        5.0,
        7.0,
        32.0,
        100.0,
        255.0,
        256.0,
        257.0,
        0.5,
        2.5,
        32.25,
        1e4,
        f32::MAX,
        f32::INFINITY,
        -1.0,
        f32::NAN,
    ][rng.below(19) as usize];
    match rng.below(8) {
        // Outside the validated ranges: shading must still agree bit for bit.
        0 => mat.fresnel = Fresnel::Constant { w: -0.5 },
        1 => mat.fresnel = Fresnel::Schlick { f0: 1.0 },
        2 => mat.ks = Vec3::new(-0.0, 0.0, 1e30),
        3 => mat.kd = Vec3::new(f32::MAX, -0.0, 0.5),
        _ => {}
    }
    mat
}

fn edge_lights(rng: &mut Rng) -> Vec<Light> {
    let count = rng.below(7) as usize;
    (0..count)
        .map(|_| {
            let mut light = random_light(rng);
            match rng.below(10) {
                0 => light.intensity = Vec3::splat(1e38),
                1 => {
                    // Inner and outer cones equal: the MIN_SPOT_COS_WIDTH hard edge.
                    light.kind = LightKind::Spot {
                        position: rng.vec(-3.0, 3.0),
                        direction: rng.vec(-1.0, 1.0) + Vec3::splat(1e-3),
                        inner_deg: 30.0,
                        outer_deg: 30.0,
                    };
                    light.attenuation = random_attenuation(rng);
                }
                2 => {
                    light.kind = LightKind::Directional {
                        direction: rng.vec(-1.0, 1.0) * 1e30,
                    }
                }
                3 => {
                    light.kind = LightKind::Point {
                        position: rng.vec(-1.0, 1.0) * 1e20,
                    }
                }
                _ => {}
            }
            light
        })
        .collect()
}

fn random_case(seed: u64) {
    let mut rng = Rng::new(seed);
    let set = LightSet::new(rng.vec(0.0, 2.0), &edge_lights(&mut rng));
    let mat = edge_material(&mut rng);
    let eye = rng.vec(-8.0, 8.0);
    // Half the quads have ordinary unit normals in all lanes (the fast path), half mix kinds.
    let mixed = rng.below(2) == 0;
    let n = [0; 4].map(|_| {
        if mixed {
            edge_normal(&mut rng)
        } else {
            rng.vec(-1.0, 1.0).try_normalize().unwrap_or(Vec3::Y)
        }
    });
    let p = [0; 4].map(|_| {
        if mixed {
            edge_point(&mut rng, &set, eye)
        } else {
            rng.vec(-3.0, 3.0)
        }
    });
    check_all(&set, &mat, p, n, eye);
}

#[test]
fn shade_x4_matches_scalar_shade_bit_for_bit_on_random_scenes() {
    for seed in 0..4000 {
        random_case(seed);
    }
}

#[test]
fn shade_x4_matches_scalar_shade_on_the_s1_scene_over_a_sphere() {
    let (set, eye) = (LightSet::s1(), Vec3::new(0.0, 0.0, 3.0));
    for mat in [
        Material::s1(),
        Material::s1().with_specular(crate::SpecularModel::Blinn),
        Material::s1()
            .with_fresnel(Fresnel::Schlick { f0: 0.04 })
            .unwrap(),
    ] {
        for k in 0..256 {
            let quad = [0, 1, 2, 3].map(|j| {
                let a = (4 * k + j) as f32 * 0.05;
                Vec3::new(a.cos() * a.sin(), (0.7 * a).cos(), a.sin().abs() + 0.1).normalize()
            });
            check_all(&set, &mat, quad, quad, eye);
        }
    }
}

#[test]
fn vec3x4_round_trips_and_splats() {
    let v = [
        Vec3::X,
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::splat(-0.0),
        Vec3::NAN,
    ];
    let w = Vec3x4::from(v);
    let back: [Vec3; 4] = w.into();
    for i in 0..4 {
        assert_eq!(
            back[i].to_array().map(f32::to_bits),
            v[i].to_array().map(f32::to_bits)
        );
        assert_eq!(
            w.lane(i).to_array().map(f32::to_bits),
            v[i].to_array().map(f32::to_bits)
        );
    }
    assert_eq!(Vec3x4::splat(Vec3::Y).to_array(), [Vec3::Y; 4]);
    assert_eq!(Vec3x4::ZERO.to_array(), [Vec3::ZERO; 4]);
    let d = Vec3x4::from(v).dot(Vec3x4::splat(Vec3::ONE)).to_array();
    assert_eq!(d[1], 6.0);
}

fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => -4.0f32..4.0,
        1 => prop::num::f32::ANY,
        1 => Just(0.0f32),
        1 => Just(-0.0f32),
    ]
}

fn any_vec() -> impl Strategy<Value = Vec3> {
    (any_f32(), any_f32(), any_f32()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Arbitrary bit patterns (NaN, Inf, subnormal, signed zeros) for points, normals and eye.
    #[test]
    fn shade_x4_matches_scalar_shade_for_arbitrary_floats(
        seed in any::<u64>(),
        p in prop::array::uniform4(any_vec()),
        n in prop::array::uniform4(any_vec()),
        eye in any_vec(),
    ) {
        let mut rng = Rng::new(seed);
        let set = LightSet::new(rng.vec(0.0, 2.0), &edge_lights(&mut rng));
        let mat = edge_material(&mut rng);
        check_all(&set, &mat, p, n, eye);
    }
}
