//! Shadow maps: the umbra of a sphere over a plane against its closed form, spot and point
//! lights casting where they should, no acne at grazing light, no leak at contact, and the
//! same picture for any thread count and SIMD width.
#![allow(clippy::unwrap_used)]

mod common;

use std::f32::consts::PI;

use common::{extents, lanes4, view};
use glam::{Mat4, Vec3};
use phosphor_lighting::{Effects, Light, LightSet, Material};
use phosphor_mesh::Mesh;
use phosphor_raster::shadow::{
    Caster, CubeFace, LightMaps, LightShape, NoMap, ShadowLight, ShadowMap, Sphere, fit, fit_cube,
};
use phosphor_raster::{
    Camera, DrawItem, Frame, Framebuffer, RenderOptions, ShadingMode, SimdLevel,
};

/// A map of `casters` (mesh, model, bounds) for `light`, over the receiver `receiver`.
fn map_of(
    light: &LightShape,
    casters: &[(&Mesh, Mat4, Sphere)],
    receiver: Sphere,
    size: u32,
) -> ShadowMap {
    let spheres: Vec<Sphere> = casters.iter().map(|c| c.2).collect();
    let v = fit(light, &spheres, &[receiver]).unwrap();
    let list: Vec<Caster> = casters
        .iter()
        .map(|(m, model, _)| Caster {
            mesh: view(m),
            model: *model,
        })
        .collect();
    ShadowMap::render(&v, size, &list, &RenderOptions::default()).unwrap()
}

/// Sphere of radius `R` centred `H` above the plane y = 0, light straight down.
const R: f32 = 0.5;
const H: f32 = 1.0;

/// The area of the plane's points in shadow (visibility below 1/2), counted on a grid of
/// step `step` over `[-1, 1]^2`.
fn umbra_area(map: &ShadowMap, step: f32) -> f32 {
    let n = (2.0 / step) as i32;
    let mut count = 0;
    for j in 0..n {
        for i in 0..n {
            let p = Vec3::new(
                -1.0 + (i as f32 + 0.5) * step,
                0.0,
                -1.0 + (j as f32 + 0.5) * step,
            );
            if map.visibility(p, Vec3::Y) < 0.5 {
                count += 1;
            }
        }
    }
    count as f32 * step * step
}

#[test]
fn sphere_umbra_matches_closed_form_and_tightens_with_size() {
    let sphere = phosphor_mesh::primitives::uv_sphere(R, 96, 48);
    let model = Mat4::from_translation(Vec3::new(0.0, H, 0.0));
    let light = LightShape::Directional {
        direction: -Vec3::Y,
    };
    let caster = Sphere {
        center: Vec3::new(0.0, H, 0.0),
        radius: R,
    };
    let floor = Sphere {
        center: Vec3::ZERO,
        radius: 2.0,
    };
    // Under light straight down the umbra is the sphere's silhouette: the disc of radius R,
    // here the tessellation's equator, a regular 96-gon inscribed in it.
    let exact = 0.5 * 96.0 * R * R * (2.0 * PI / 96.0).sin();
    let mut errors = Vec::new();
    for size in [16u32, 64, 256] {
        let map = map_of(&light, &[(&sphere, model, caster)], floor, size);
        let texel = 2.0 * 1.01 * R / size as f32;
        let area = umbra_area(&map, 0.002);
        let err = (area - exact).abs();
        // Stated tolerance: the disc's perimeter times half a texel (the PCF threshold at 1/2
        // puts the edge within half a texel of the silhouette), plus the counting grid's own
        // error (its step times the perimeter).
        let tolerance = 2.0 * PI * R * (0.5 * texel + 0.002);
        assert!(
            err <= tolerance,
            "size {size}: umbra {area} against {exact}, error {err} over {tolerance}"
        );
        errors.push(err);
    }
    assert!(errors[2] < errors[0], "error does not shrink: {errors:?}");
}

/// A cube of half-side 0.25 centred 1 above the floor: mesh, model, bounds, and the floor's
/// bounds.
fn cube_over_floor() -> (Mesh, Mat4, Sphere, Sphere) {
    let cube = phosphor_mesh::primitives::cube(0.25);
    let model = Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0));
    let bounds = Sphere {
        center: Vec3::new(0.0, 1.0, 0.0),
        radius: 0.25 * 3f32.sqrt(),
    };
    let floor = Sphere {
        center: Vec3::ZERO,
        radius: 3.0,
    };
    (cube, model, bounds, floor)
}

/// A spot light straight above the cube of [`cube_over_floor`], and a point light above and
/// to the side.
fn spot_and_point() -> [LightShape; 2] {
    [
        LightShape::Spot {
            position: Vec3::new(0.0, 3.0, 0.0),
            direction: -Vec3::Y,
            outer_deg: 40.0,
        },
        LightShape::Point {
            position: Vec3::new(1.0, 3.0, 0.0),
        },
    ]
}

#[test]
fn spot_and_point_lights_cast_below_their_caster() {
    let (cube, model, bounds, floor) = cube_over_floor();
    for light in spot_and_point() {
        let map = map_of(&light, &[(&cube, model, bounds)], floor, 256);
        let from = match light {
            LightShape::Spot { position, .. } | LightShape::Point { position } => position,
            LightShape::Directional { .. } => unreachable!(),
        };
        // The ray from the light through the cube's centre meets the floor here.
        let t = from.y / (from.y - 1.0);
        let below = from + (Vec3::new(0.0, 1.0, 0.0) - from) * t;
        assert_eq!(map.visibility(below, Vec3::Y), 0.0, "{light:?} at {below}");
        // Well outside the cube's shadow: lit.
        for p in [Vec3::new(-1.5, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.2)] {
            assert_eq!(map.visibility(p, Vec3::Y), 1.0, "{light:?} at {p}");
        }
        // The top of the cube faces the light and is lit.
        let top = Vec3::new(0.0, 1.25, 0.0);
        assert_eq!(map.visibility(top, Vec3::Y), 1.0, "{light:?} cube top");
    }
}

#[test]
fn point_light_surrounded_by_casters_takes_a_cube() {
    let around: Vec<Sphere> = [Vec3::X, -Vec3::X, Vec3::Z, -Vec3::Z]
        .iter()
        .map(|&c| Sphere {
            center: c * 2.0,
            radius: 0.5,
        })
        .collect();
    let light = LightShape::Point {
        position: Vec3::ZERO,
    };
    // No single cone holds them; the cube's four side faces do (each ball shadows the
    // balls beside it only through its own face and its neighbours').
    assert_eq!(fit(&light, &around, &around).unwrap_err(), NoMap::TooWide);
    let faces = fit_cube(Vec3::ZERO, &extents(&around), &extents(&around), None, 256).unwrap();
    let made: Vec<CubeFace> = faces.iter().map(|f| f.face).collect();
    for face in [
        CubeFace::PosX,
        CubeFace::NegX,
        CubeFace::PosZ,
        CubeFace::NegZ,
    ] {
        assert!(made.contains(&face), "{face}: {made:?}");
    }
    assert!(!made.contains(&CubeFace::PosY) && !made.contains(&CubeFace::NegY));
}

#[test]
fn no_acne_on_a_sphere_at_grazing_light() {
    let sphere = phosphor_mesh::primitives::uv_sphere(1.0, 64, 32);
    // Light almost along the surface over most of the lit half.
    let direction = Vec3::new(1.0, -0.15, 0.2).normalize();
    let light = LightShape::Directional { direction };
    let s = Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    };
    for size in [128u32, 512] {
        let map = map_of(&light, &[(&sphere, Mat4::IDENTITY, s)], s, size);
        let mut checked = 0;
        for t in &sphere.indices {
            let [a, b, c] = t.map(|i| sphere.positions[i as usize]);
            let n = (b - a).cross(c - a).normalize_or_zero();
            let cos = n.dot(-direction);
            // Every facet facing the light, down to 10 degrees above its horizon.
            if cos > 0.18 {
                let centroid = (a + b + c) / 3.0;
                let v = map.visibility(centroid, n);
                assert_eq!(v, 1.0, "size {size}: facet at {centroid}, cos {cos}: {v}");
                checked += 1;
            }
        }
        assert!(checked > 1000, "{checked}");
    }
}

#[test]
fn no_light_leaks_where_the_shadow_meets_its_caster() {
    let cube = phosphor_mesh::primitives::cube(0.5);
    let model = Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0));
    let bounds = Sphere {
        center: Vec3::new(0.0, 0.5, 0.0),
        radius: 0.5 * 3f32.sqrt(),
    };
    let floor = Sphere {
        center: Vec3::ZERO,
        radius: 3.0,
    };
    // Light at 45 degrees towards +x: the shadow lies on +x from x = 0.5 to 1.5.
    let light = LightShape::Directional {
        direction: Vec3::new(1.0, -1.0, 0.0),
    };
    let map = map_of(&light, &[(&cube, model, bounds)], floor, 512);
    for x in [0.51f32, 0.55, 0.8, 1.2, 1.45] {
        for z in [-0.4f32, 0.0, 0.4] {
            let v = map.visibility(Vec3::new(x, 0.0, z), Vec3::Y);
            assert_eq!(v, 0.0, "leak at x {x}, z {z}: {v}");
        }
    }
    for x in [1.6f32, 2.0, -0.6] {
        assert_eq!(
            map.visibility(Vec3::new(x, 0.0, 0.0), Vec3::Y),
            1.0,
            "x {x}"
        );
    }
}

/// A sphere over a floor under one directional light with a map, drawn at `opts`.
fn frame_bytes(opts: &RenderOptions, mode: ShadingMode) -> Vec<u8> {
    floor_frame(opts, mode, None, true)
}

/// [`frame_bytes`] with the floor's vertices all of colour `floor_color`, and the light's map
/// used or not.
fn floor_frame(
    opts: &RenderOptions,
    mode: ShadingMode,
    floor_color: Option<Vec3>,
    with_map: bool,
) -> Vec<u8> {
    let sphere = phosphor_mesh::primitives::uv_sphere(0.5, 48, 24);
    let floor = phosphor_mesh::primitives::plane(2.0, 4);
    let up = Mat4::from_translation(Vec3::new(0.0, 0.2, 0.0));
    let down = Mat4::from_translation(Vec3::new(0.0, -0.6, 0.0));
    let direction = Vec3::new(0.4, -1.0, -0.3);
    let sun = Light::directional(direction, Vec3::ONE).unwrap();
    let ambient = Vec3::splat(0.2);
    let all = LightSet::new(ambient, &[sun]);
    let rest = LightSet::new(ambient, &[]);
    let alone = LightSet::new(Vec3::ZERO, &[sun]);
    let light = LightShape::Directional { direction };
    let caster = Sphere {
        center: Vec3::new(0.0, 0.2, 0.0),
        radius: 0.5,
    };
    let ground = Sphere {
        center: Vec3::new(0.0, -0.6, 0.0),
        radius: 2.9,
    };
    let v = fit(&light, &[caster], &[ground, caster]).unwrap();
    let casters = [Caster {
        mesh: view(&sphere),
        model: up,
    }];
    let map = ShadowMap::render(&v, 512, &casters, opts).unwrap();
    let colors = floor_color.map(|c| vec![c; floor.positions.len()]);
    let shadowed = [ShadowLight {
        set: &alone,
        maps: LightMaps::One(&map),
        rays: None,
        rays_skip: None,
    }];
    let material = Material::s1();
    fn item<'a>(
        m: &'a Mesh,
        model: Mat4,
        material: &'a Material,
        lights: &'a LightSet,
        mode: ShadingMode,
    ) -> DrawItem<'a> {
        DrawItem {
            mesh: view(m),
            model,
            material,
            lights,
            effects: Effects::ALL,
            mode,
            bump: None,
            texture: None,
            cull_backfaces: false,
        }
    }
    let camera = Camera {
        eye: Vec3::new(0.0, 1.5, 3.0),
        target: Vec3::new(0.0, -0.3, 0.0),
        ..Camera::s1()
    };
    let mut fb = Framebuffer::new(160, 120).unwrap();
    let mut frame = Frame::new(&mut fb, &camera, opts);
    let mut floor_item = item(&floor, down, &material, &all, mode);
    floor_item.mesh.colors = colors.as_deref();
    let sphere_item = item(&sphere, up, &material, &all, mode);
    let (rest, shadowed) = if with_map {
        (&rest, &shadowed[..])
    } else {
        (&all, &[][..])
    };
    frame.draw_shadowed(&floor_item, rest, shadowed);
    frame.draw_shadowed(&sphere_item, rest, shadowed);
    frame.finish();
    fb.to_rgb8(phosphor_raster::Encoding::Linear)
}

#[test]
fn shadowed_frame_is_the_same_for_any_threads_and_width() {
    for mode in [ShadingMode::Phong, ShadingMode::Gouraud] {
        let base = frame_bytes(
            &RenderOptions {
                threads: 1,
                simd: SimdLevel::Baseline,
                ..RenderOptions::default()
            },
            mode,
        );
        for (threads, simd) in [
            (4, SimdLevel::Baseline),
            (3, SimdLevel::Auto),
            (1, SimdLevel::Avx2),
        ] {
            let other = frame_bytes(
                &RenderOptions {
                    threads,
                    simd,
                    ..RenderOptions::default()
                },
                mode,
            );
            assert!(base == other, "{mode}: {threads} threads, {simd:?}");
        }
        // The shadow is there: the floor below the sphere, along the light, is dark.
        let lit: Vec<u32> = base.chunks(3).map(|c| u32::from(c[0])).collect();
        assert!(lit.iter().any(|&c| c < 60) && lit.iter().any(|&c| c > 150));
    }
}

#[test]
fn a_vertex_coloured_receiver_takes_its_shadow_and_its_colour() {
    let opts = RenderOptions {
        threads: 1,
        ..RenderOptions::default()
    };
    let tint = Vec3::new(1.0, 0.25, 0.25);
    let plain = floor_frame(&opts, ShadingMode::Phong, None, true);
    for mode in [ShadingMode::Phong, ShadingMode::Gouraud, ShadingMode::Flat] {
        let shadowed = floor_frame(&opts, mode, Some(tint), true);
        let open = floor_frame(&opts, mode, Some(tint), false);
        // Pixels the map darkens: lit without the map, in shadow with it.
        let darkened = shadowed
            .chunks(3)
            .zip(open.chunks(3))
            .filter(|(s, o)| u32::from(s[0]) + 60 < u32::from(o[0]))
            .count();
        assert!(darkened > 300, "{mode}: only {darkened} pixels in shadow");
        // The same frame with a plain floor: the colour takes green and blue from the floor's
        // lit pixels (the specular highlight stays untinted, so only most pixels change).
        let redder = shadowed
            .chunks(3)
            .zip(plain.chunks(3))
            .filter(|(s, p)| s[0] > 40 && s[1] < p[1] && s[2] < p[2])
            .count();
        assert!(redder > 3000, "{mode}: only {redder} tinted pixels");
    }
}

/// The PCF lookup as its definition reads, one point at a time with every texel's position
/// tested: the oracle for the lane lookup (which reads a padded map instead).
fn visibility_by_definition(map: &ShadowMap, p: Vec3, n: Vec3) -> f32 {
    use phosphor_raster::shadow::{BIAS_CONSTANT, BIAS_SLOPE, MAX_BIAS_SLOPE, Projection};
    let light = map.light();
    let size = map.size();
    let v = light.view.transform_point3(p);
    let dist = -v.z;
    let (sx, sy, texel) = match light.projection {
        Projection::Orthographic { half_width } => (
            v.x / half_width,
            v.y / half_width,
            2.0 * half_width / size as f32,
        ),
        Projection::Perspective { tan_half } => {
            if dist.is_nan() || dist <= 0.0 {
                return 1.0;
            }
            let k = dist * tan_half;
            (v.x / k, v.y / k, 2.0 * tan_half / size as f32 * dist)
        }
    };
    if !(sx.is_finite() && sy.is_finite() && dist.is_finite()) {
        return 1.0;
    }
    let len2 = n.length_squared();
    let c = if len2 > 0.0 && len2.is_finite() {
        n.dot(light.to_light(p)) / len2.sqrt()
    } else {
        1.0
    };
    let slope = if c > 0.0 {
        ((1.0 - c * c).max(0.0).sqrt() / c).min(MAX_BIAS_SLOPE)
    } else {
        MAX_BIAS_SLOPE
    };
    let compare = dist - texel * (BIAS_CONSTANT + BIAS_SLOPE * slope);
    let s = size as f32;
    let fx = (sx + 1.0) * 0.5 * s - 0.5;
    let fy = (1.0 - sy) * 0.5 * s - 0.5;
    if !(fx > -3.0 && fy > -3.0 && fx < s + 2.0 && fy < s + 2.0) {
        return 1.0;
    }
    let (x0, y0) = (fx.floor(), fy.floor());
    let (tx, ty) = (fx - x0, fy - y0);
    let wx = [(1.0 - tx), 1.0, 1.0, tx];
    let wy = [(1.0 - ty), 1.0, 1.0, ty];
    let mut lit = 0.0;
    for (j, wy) in wy.iter().enumerate() {
        let y = y0 as i64 - 1 + j as i64;
        let mut row = 0.0;
        for (i, wx) in wx.iter().enumerate() {
            let x = x0 as i64 - 1 + i as i64;
            let inside = x >= 0 && y >= 0 && x < i64::from(size) && y < i64::from(size);
            if !inside || compare <= map.distance_at(x as u32, y as u32) {
                row += wx;
            }
        }
        lit += row * wy;
    }
    (lit / 9.0).clamp(0.0, 1.0)
}

#[test]
fn lane_lookup_is_the_definition_bit_for_bit() {
    let (cube, model, bounds, floor) = cube_over_floor();
    let [spot, point] = spot_and_point();
    let directional = LightShape::Directional {
        direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
    };
    let lights = [directional, spot, point];
    // Normals: up, grazing, facing away, zero, NaN, huge.
    let normals = [
        Vec3::Y,
        Vec3::new(1.0, 0.02, 0.0),
        -Vec3::Y,
        Vec3::ZERO,
        Vec3::NAN,
        Vec3::splat(1e30),
    ];
    for light in lights {
        let map = map_of(&light, &[(&cube, model, bounds)], floor, 64);
        let mut points = Vec::new();
        // A grid over and past the floor (the map's edges and outside it), at several
        // heights (the cube's faces, above the light), and points that are not finite.
        for j in -40..=40 {
            for i in -40..=40 {
                for h in [0.0, 0.75, 1.0, 1.25, 4.0] {
                    points.push(Vec3::new(i as f32 * 0.1, h, j as f32 * 0.1));
                }
            }
        }
        points.extend([Vec3::NAN, Vec3::INFINITY, Vec3::new(0.0, 3.0, 0.0)]);
        let mut shaded = 0;
        for (k, &p) in points.iter().enumerate() {
            let n = normals[k % normals.len()];
            let want = visibility_by_definition(&map, p, n);
            let got = map.visibility(p, n);
            assert_eq!(got.to_bits(), want.to_bits(), "{light:?} at {p} normal {n}");
            shaded += usize::from(want > 0.0 && want < 1.0);
        }
        assert!(shaded > 20, "{light:?}: only {shaded} penumbra points");
        // Four different points per vector: each lane is its own one-lane lookup.
        for (k, quad) in points.chunks_exact(4).enumerate() {
            let ns: [Vec3; 4] = std::array::from_fn(|i| normals[(k + i) % normals.len()]);
            let (p, n) = (lanes4(quad.try_into().unwrap()), lanes4(&ns));
            let got = map.visibility_lanes(p, n).to_array();
            for i in 0..4 {
                let want = map.visibility(quad[i], ns[i]);
                assert_eq!(got[i].to_bits(), want.to_bits(), "lane {i} at {}", quad[i]);
            }
        }
    }
}
