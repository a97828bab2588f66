//! Bump mapping (Blinn 1978) against height fields whose perturbed normal is known in closed
//! form.
//!
//! On a plane with unit tangent `T`, bitangent `B` and normal `N`, displacing each point by
//! `s h(u, v)` along `N` gives the surface `P(u, v) = u T + v B + s h N`, whose normal is the
//! cross product `P_u x P_v = (T + s h_u N) x (B + s h_v N)`, parallel to
//! `N - s h_u T - s h_v B`: Blinn's perturbed normal is exact there. The tests compute that
//! cross product in f64 from the analytic derivatives of `h` (not from the renderer's formula)
//! and compare it with `BumpMap::perturb`, for a height image sampled from a closed-form `h`, for
//! both built-in procedural fields against the `h` their documentation states, and through a
//! whole render in `reference` and `phong`. A tangent-space normal map baked from the same
//! `h` (each texel the unit `(-h_u, -h_v, 1)`, its `x` and `y` scaled by the map's scale when
//! drawn, as glTF's `normalTexture.scale` does) gives the same normals.

use std::f64::consts::TAU;

use phosphor::lighting::{Effects, Light, LightSet, Material, shade_reference};
use phosphor::math::glam::{DVec3, Mat4, Vec2, Vec3, Vec4};
use phosphor::raster::{
    BumpMap, Camera, DrawItem, Framebuffer, MeshView, ProceduralBump, RenderOptions, ShadingMode,
    render,
};

/// Amplitudes of the test height field `h(u, v) = 0.5 + A sin(2 pi u) + C cos(4 pi v)`,
/// periodic on the unit square as the image's wrap-around needs.
const A: f64 = 0.1;
const C: f64 = 0.05;

fn height(u: f64, v: f64) -> f64 {
    0.5 + A * (TAU * u).sin() + C * (2.0 * TAU * v).cos()
}

/// `(dh/du, dh/dv)` of [`height`], by hand.
fn height_gradient(u: f64, v: f64) -> (f64, f64) {
    (
        A * TAU * (TAU * u).cos(),
        -C * 2.0 * TAU * (2.0 * TAU * v).sin(),
    )
}

/// [`height`] sampled at the texel centres `((i + 0.5)/w, (j + 0.5)/h)`, row 0 at v = 0.
fn height_image(w: u32, h: u32, scale: f32) -> BumpMap {
    let heights = (0..h)
        .flat_map(|j| {
            (0..w).map(move |i| {
                height(
                    (f64::from(i) + 0.5) / f64::from(w),
                    (f64::from(j) + 0.5) / f64::from(h),
                ) as f32
            })
        })
        .collect();
    BumpMap::Image {
        heights,
        width: w,
        height: h,
        scale,
    }
}

/// The unit normals `(-h_u, -h_v, 1)` of [`height`] at the texel centres, row 0 at v = 0,
/// drawn with `scale`.
fn normal_image(w: u32, h: u32, scale: f32) -> BumpMap {
    let normals = (0..h)
        .flat_map(|j| {
            (0..w).map(move |i| {
                let (h_u, h_v) = height_gradient(
                    (f64::from(i) + 0.5) / f64::from(w),
                    (f64::from(j) + 0.5) / f64::from(h),
                );
                DVec3::new(-h_u, -h_v, 1.0).normalize().as_vec3()
            })
        })
        .collect();
    BumpMap::from_normals(normals, w, h, scale).expect("a valid map")
}

/// The normal of the displaced surface `P = u T + v B + s h N` (f64 cross product of its
/// partial derivatives), turned to `N`'s side. `b` is the bitangent the tangent's handedness
/// gives, `w (N x T)`.
fn displaced_normal(n: DVec3, t: DVec3, b: DVec3, s: f64, (h_u, h_v): (f64, f64)) -> DVec3 {
    let p_u = t + s * h_u * n;
    let p_v = b + s * h_v * n;
    let c = p_u.cross(p_v).normalize();
    if c.dot(n) < 0.0 { -c } else { c }
}

/// Texel spacing `d = 1/256`: the bilinear image differenced one texel apart has an error of
/// about `d^2 (1/8 + 1/6) max|h'''|` in the slope (bilinear interpolation and the central
/// difference, both second order): `1.5e-5 * 0.3 * (A (2 pi)^3 + C (4 pi)^3) = 5e-4` times the
/// scale, plus f32 rounding of the samples (`1e-7 * 256`). The normal moves by less than the
/// slope error.
const IMAGE_SIDE: u32 = 256;
const IMAGE_TOLERANCE: f64 = 1e-3;

/// uv points spread over the square, away from texel centres.
fn sample_uvs() -> impl Iterator<Item = (f64, f64)> {
    (0..97).map(|k| {
        let k = f64::from(k);
        (
            (k * 0.618_034 + 0.013).fract(),
            (k * 0.414_214 + 0.071).fract(),
        )
    })
}

#[test]
fn image_bump_on_a_plane_matches_the_displaced_surface_normal() {
    let scale = 1.0f32;
    image_case(&height_image(IMAGE_SIDE, IMAGE_SIDE, scale), scale);
}

#[test]
fn a_normal_map_baked_from_the_heights_gives_the_same_normals() {
    // Scaled in the map (glTF's scale), not in the bake: exact for a height field, since
    // `(-s h_u, -s h_v, 1)` is parallel to the scaled unit normal.
    for scale in [1.0f32, 0.4, 2.5] {
        image_case(&normal_image(IMAGE_SIDE, IMAGE_SIDE, scale), scale);
    }
}

fn image_case(map: &BumpMap, scale: f32) {
    // The plane z = 0 with T = +X and a right-handed frame (w = +1): B = N x T = +Y.
    let (n, t) = (DVec3::Z, DVec3::X);
    let b = n.cross(t);
    let mut worst = 0.0f64;
    for (u, v) in sample_uvs() {
        let got = map
            .perturb(
                Vec3::Z,
                Vec4::new(1.0, 0.0, 0.0, 1.0),
                Vec2::new(u as f32, v as f32),
            )
            .as_dvec3();
        let want = displaced_normal(n, t, b, f64::from(scale), height_gradient(u, v));
        worst = worst.max((got - want).length());
        assert!(
            (got - want).length() < IMAGE_TOLERANCE,
            "uv ({u}, {v}): perturb {got}, displaced surface {want}"
        );
    }
    // The test is not vacuous: the normals tilt far more than the tolerance.
    let tilted = sample_uvs()
        .map(|(u, v)| displaced_normal(n, t, b, f64::from(scale), height_gradient(u, v)).z)
        .fold(1.0f64, f64::min);
    assert!(tilted < 0.99, "largest tilt cos {tilted}");
    assert!(
        worst > 0.0,
        "perturb equals the f64 normal to the bit: suspicious"
    );
}

#[test]
fn left_handed_rotated_frame_with_a_skewed_tangent_matches_too() {
    // For height images and normal maps alike.
    // N and T rotated off the axes, T not orthogonal to N (perturb orthogonalizes it), and a
    // left-handed frame (w = -1): B = -(N x T).
    let scale = 0.6f32;
    for map in [
        height_image(IMAGE_SIDE, IMAGE_SIDE, scale),
        normal_image(IMAGE_SIDE, IMAGE_SIDE, scale),
    ] {
        left_handed_case(&map, scale);
    }
}

fn left_handed_case(map: &BumpMap, scale: f32) {
    let n = DVec3::new(0.3, -0.5, 0.8).normalize();
    let t_axis = DVec3::new(1.0, 0.4, 0.0).cross(n).normalize();
    let skewed = t_axis * 2.0 + n * 0.3;
    let b = -n.cross(t_axis);
    for (u, v) in sample_uvs() {
        let got = map
            .perturb(
                n.as_vec3(),
                Vec4::new(skewed.x as f32, skewed.y as f32, skewed.z as f32, -1.0),
                Vec2::new(u as f32, v as f32),
            )
            .as_dvec3();
        let want = displaced_normal(n, t_axis, b, f64::from(scale), height_gradient(u, v));
        assert!(
            (got - want).length() < IMAGE_TOLERANCE,
            "uv ({u}, {v}): perturb {got}, displaced surface {want}"
        );
    }
}

/// `(dh/du, dh/dv)` of `h` by f64 central differences (step 1e-6: error about 1e-10 for these
/// fields).
fn numeric_gradient(h: impl Fn(f64, f64) -> f64, u: f64, v: f64) -> (f64, f64) {
    let e = 1e-6;
    (
        (h(u + e, v) - h(u - e, v)) / (2.0 * e),
        (h(u, v + e) - h(u, v - e)) / (2.0 * e),
    )
}

#[test]
fn procedural_fields_tilt_the_normal_as_their_documented_heights_do() {
    // The height fields as `ProceduralBump` documents them.
    let bumps = |u: f64, v: f64| {
        let w = TAU * 8.0;
        (w * u).sin() * (w * v).sin() / w
    };
    let ripples = |u: f64, v: f64| {
        let w = TAU * 12.0;
        let r = ((u - 0.5).powi(2) + (v - 0.5).powi(2)).sqrt();
        (w * r).sin() / w
    };
    let scale = 0.8f32;
    let (n, t) = (DVec3::Z, DVec3::X);
    let b = n.cross(t);
    for (kind, h) in [
        (ProceduralBump::Bumps, &bumps as &dyn Fn(f64, f64) -> f64),
        (ProceduralBump::Ripples, &ripples),
    ] {
        let map = BumpMap::Procedural { kind, scale };
        for (u, v) in sample_uvs() {
            let got = map
                .perturb(
                    Vec3::Z,
                    Vec4::new(1.0, 0.0, 0.0, 1.0),
                    Vec2::new(u as f32, v as f32),
                )
                .as_dvec3();
            let want = displaced_normal(n, t, b, f64::from(scale), numeric_gradient(h, u, v));
            // f32 evaluation of sin/cos at arguments up to 2 pi 12 sqrt(2): about 1e-5.
            assert!(
                (got - want).length() < 1e-4,
                "{kind:?} uv ({u}, {v}): perturb {got}, displaced surface {want}"
            );
        }
    }
}

/// The plane z = 0, `[-1, 1]^2`, uv = `((x + 1)/2, (y + 1)/2)`, tangent +X, normal +Z.
struct Plane {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    tangents: Vec<Vec4>,
    indices: Vec<[u32; 3]>,
}

fn plane() -> Plane {
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    Plane {
        positions: corners.map(|(x, y)| Vec3::new(x, y, 0.0)).to_vec(),
        normals: vec![Vec3::Z; 4],
        uvs: corners
            .map(|(x, y)| Vec2::new((x + 1.0) / 2.0, (y + 1.0) / 2.0))
            .to_vec(),
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
        indices: vec![[0, 1, 2], [0, 2, 3]],
    }
}

#[test]
fn rendered_bumped_plane_matches_the_closed_form_shading() {
    let (w, h) = (96u32, 72u32);
    let camera = Camera::s1();
    let lights = LightSet::new(
        Vec3::splat(0.2),
        &[
            Light::directional(Vec3::new(-1.0, -0.3, -1.0), Vec3::splat(0.9)).expect("light"),
            Light::point(Vec3::new(-1.0, 1.5, 2.0), Vec3::splat(1.5)).expect("light"),
        ],
    );
    let material =
        Material::new(Vec3::splat(0.1), Vec3::splat(0.6), Vec3::splat(0.3), 12.0).expect("valid");
    let scale = 0.5f32;
    let maps = [
        height_image(IMAGE_SIDE, IMAGE_SIDE, scale),
        normal_image(IMAGE_SIDE, IMAGE_SIDE, scale),
    ];
    let mesh = plane();
    for map in &maps {
        rendered_case(&mesh, &lights, &material, map, scale, (w, h), &camera);
    }
}

fn rendered_case(
    mesh: &Plane,
    lights: &LightSet,
    material: &Material,
    map: &BumpMap,
    scale: f32,
    (w, h): (u32, u32),
    camera: &Camera,
) {
    let draw = |mode| DrawItem {
        mesh: MeshView {
            positions: &mesh.positions,
            normals: &mesh.normals,
            uvs: Some(&mesh.uvs),
            tangents: Some(&mesh.tangents),
            colors: None,
            indices: &mesh.indices,
        },
        model: Mat4::IDENTITY,
        material,
        lights,
        effects: Effects::ALL,
        mode,
        bump: Some(map),
        texture: None,
        cull_backfaces: false,
    };
    // Where the pixel centre's ray from the S1 eye (0, 0, 3), looking down -Z, meets z = 0.
    let half_height = 3.0 * (22.5f64).to_radians().tan();
    let aspect = f64::from(w) / f64::from(h);
    let on_plane = |x: u32, y: u32| {
        let ndc_x = (f64::from(x) + 0.5) / f64::from(w) * 2.0 - 1.0;
        let ndc_y = 1.0 - (f64::from(y) + 0.5) / f64::from(h) * 2.0;
        DVec3::new(ndc_x * half_height * aspect, ndc_y * half_height, 0.0)
    };
    // Both within 1e-3 (measured: 2.6e-4 in each), dominated by the image's slope error
    // (IMAGE_TOLERANCE times the scale at most) rather than by the modes' own arithmetic.
    for (mode, tolerance) in [(ShadingMode::Reference, 1e-3), (ShadingMode::Phong, 1e-3)] {
        let mut fb = Framebuffer::new(w, h).expect("size");
        render(&mut fb, camera, &[draw(mode)], &RenderOptions::default());
        let (mut checked, mut worst, mut varied) = (0, 0.0f64, (f64::MAX, 0.0f64));
        for y in 0..h {
            for x in 0..w {
                let p = on_plane(x, y);
                // Skip pixels within a pixel of the square's border.
                if p.x.abs() > 0.95 || p.y.abs() > 0.95 {
                    continue;
                }
                let (u, v) = ((p.x + 1.0) / 2.0, (p.y + 1.0) / 2.0);
                let n = displaced_normal(
                    DVec3::Z,
                    DVec3::X,
                    DVec3::Y,
                    f64::from(scale),
                    height_gradient(u, v),
                );
                let want = shade_reference(lights, material, p, n, DVec3::new(0.0, 0.0, 3.0))
                    .min(DVec3::ONE);
                let got = fb.pixel(x, y).as_dvec3();
                let err = (got - want).abs().max_element();
                worst = worst.max(err);
                varied = (varied.0.min(want.x), varied.1.max(want.x));
                assert!(
                    err < tolerance,
                    "{mode}: pixel ({x}, {y}) uv ({u:.4}, {v:.4}): {got} vs closed form {want}"
                );
                checked += 1;
            }
        }
        assert!(checked > 2000, "{mode}: only {checked} pixels checked");
        // The bumps show: the closed-form shading varies across the plane by far more than
        // the tolerance.
        assert!(
            varied.1 - varied.0 > 0.2,
            "{mode}: shading only spans {varied:?}"
        );
        println!("{mode}: {checked} pixels, worst error {worst:.2e}");
    }
}
