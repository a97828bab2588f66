//! Texture maps through the built-in modes: a checkerboard floor in perspective against texel
//! values computed here independently (the ray through each pixel centre meets the plane
//! exactly; the footprint comes from that mapping's derivatives; the checkerboard's levels
//! are known in closed form), and vertex colours in every mode.
#![allow(clippy::unwrap_used)]

use glam::{DVec2, DVec3, DVec4, Mat4, Vec2, Vec3};
use phosphor_lighting::{Effects, LightSet, Material};

use phosphor_raster::texture::{Filter, Texture, Wrap};
use phosphor_raster::{
    Camera, DrawItem, Framebuffer, MeshView, RenderOptions, ShadingMode, render,
};

/// Checkerboard side in texels.
const N: u32 = 16;
/// World size of the floor square that holds the texture once (`uv` in `[0, 1]`).
const TILE: f64 = 4.0;

/// A checkerboard of squares two texels wide, so that level 1 is a checkerboard of single
/// texels and levels 2 and up are 0.5 everywhere: the value shows which levels were used.
fn checker() -> Texture {
    let texels = (0..N * N)
        .map(|k| {
            if ((k % N) / 2 + (k / N) / 2).is_multiple_of(2) {
                Vec3::ONE
            } else {
                Vec3::ZERO
            }
        })
        .collect();
    Texture::new(N, N, texels).unwrap()
}

/// Texel `(i, j)` of `level` (column, row from the top), repeating, in closed form.
fn checker_texel(level: usize, i: i64, j: i64) -> f64 {
    let on = |k: i64| if k.rem_euclid(2) == 0 { 1.0 } else { 0.0 };
    match level {
        0 => on(i.div_euclid(2) + j.div_euclid(2)),
        1 => on(i + j),
        _ => 0.5,
    }
}

/// Bilinear value of `level` at `(u, v)`.
fn bilinear(level: usize, u: f64, v: f64) -> f64 {
    let n = f64::from(N >> level.min(4));
    let (x, y) = (u * n - 0.5, (1.0 - v) * n - 0.5);
    let (i, j) = (x.floor() as i64, y.floor() as i64);
    let (fx, fy) = (x - x.floor(), y - y.floor());
    let t = |i, j| checker_texel(level, i, j);
    (t(i, j) * (1.0 - fx) + t(i + 1, j) * fx) * (1.0 - fy)
        + (t(i, j + 1) * (1.0 - fx) + t(i + 1, j + 1) * fx) * fy
}

/// The floor `y = 0`, `x` and `z` in `[-s, s]`, with `uv = (x, -z) / TILE`, two triangles.
struct Floor {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    colors: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
}

fn floor(s: f32) -> Floor {
    let positions = vec![
        Vec3::new(-s, 0.0, s),
        Vec3::new(s, 0.0, s),
        Vec3::new(s, 0.0, -s),
        Vec3::new(-s, 0.0, -s),
    ];
    let uvs = positions
        .iter()
        .map(|p| Vec2::new(p.x, -p.z) / TILE as f32)
        .collect();
    Floor {
        normals: vec![Vec3::Y; 4],
        uvs,
        colors: vec![Vec3::ONE; 4],
        positions,
        indices: vec![[0, 1, 2], [0, 2, 3]],
    }
}

fn camera() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 1.5, 4.0),
        target: Vec3::new(0.0, 0.0, -2.0),
        fov_y_deg: 50.0,
        far: 200.0,
        ..Camera::s1()
    }
}

/// Ambient light only, `ka = 1`: every mode shows the texel value itself.
fn unlit() -> (Material, LightSet) {
    let material = Material {
        ka: Vec3::ONE,
        kd: Vec3::ZERO,
        ks: Vec3::ZERO,
        emission: Vec3::ZERO,
        ..Material::s1()
    };
    (material, LightSet::new(Vec3::ONE, &[]))
}

fn draw_floor(mode: ShadingMode, texture: &Texture, colors: bool, size: (u32, u32)) -> Framebuffer {
    let f = floor(FLOOR);
    let (material, lights) = unlit();
    let mut fb = Framebuffer::new(size.0, size.1).unwrap();
    let mesh = MeshView {
        uvs: Some(&f.uvs),
        colors: colors.then_some(&f.colors[..]),
        ..MeshView::new(&f.positions, &f.normals, &f.indices)
    };
    let d = DrawItem {
        mesh,
        model: Mat4::IDENTITY,
        material: &material,
        lights: &lights,
        effects: Effects::ALL,
        mode,
        bump: None,
        texture: Some(texture),
        cull_backfaces: false,
    };
    render(&mut fb, &camera(), &[d], &RenderOptions::default());
    fb
}

/// Half the floor's side in world units.
const FLOOR: f32 = 40.0;

/// The floor's `uv` seen through pixel position `(x, y)` (pixels, row 0 at the top), or
/// `None` above the horizon or past (or within half a unit of) the floor's edge.
fn uv_at(x: f64, y: f64, size: (u32, u32)) -> Option<DVec2> {
    let (w, h) = (f64::from(size.0), f64::from(size.1));
    let inv = camera()
        .view_proj(size.0 as f32 / size.1 as f32)
        .as_dmat4()
        .inverse();
    let ndc = DVec2::new(2.0 * x / w - 1.0, 1.0 - 2.0 * y / h);
    let world = |z: f64| {
        let p = inv * DVec4::new(ndc.x, ndc.y, z, 1.0);
        p.truncate() / p.w
    };
    let (a, b): (DVec3, DVec3) = (world(0.0), world(1.0));
    let dir = b - a;
    if dir.y >= -1e-12 {
        return None;
    }
    let t = -a.y / dir.y;
    let p = a + dir * t;
    let inside = f64::from(FLOOR) - 0.5;
    (p.x.abs() < inside && p.z.abs() < inside).then(|| DVec2::new(p.x, -p.z) / TILE)
}

/// The expected colour at pixel `(x, y)` with `filter`, the footprint's level, and the
/// footprint in texels per pixel.
fn expected(filter: Filter, x: u32, y: u32, size: (u32, u32)) -> Option<(f64, f64, f64)> {
    let (cx, cy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
    let uv = uv_at(cx, cy, size)?;
    let h = 1e-3;
    let dx = (uv_at(cx + h, cy, size)? - uv_at(cx - h, cy, size)?) / (2.0 * h);
    let dy = (uv_at(cx, cy + h, size)? - uv_at(cx, cy - h, size)?) / (2.0 * h);
    let n = f64::from(N);
    let rho = (dx * n).length().max((dy * n).length());
    let lod = if rho > 1.0 { rho.log2().min(4.0) } else { 0.0 };
    let value = match filter {
        Filter::Nearest => checker_texel(
            0,
            (uv.x * n).floor() as i64,
            ((1.0 - uv.y) * n).floor() as i64,
        ),
        Filter::Bilinear => bilinear(0, uv.x, uv.y),
        Filter::Trilinear => {
            let lo = lod.floor();
            let f = lod - lo;
            bilinear(lo as usize, uv.x, uv.y) * (1.0 - f)
                + bilinear(lo as usize + 1, uv.x, uv.y) * f
        }
    };
    Some((value, lod, rho))
}

#[test]
fn a_perspective_checkerboard_matches_texels_computed_independently() {
    let size = (160, 120);
    for filter in [Filter::Nearest, Filter::Bilinear, Filter::Trilinear] {
        let texture = checker().with_filter(filter);
        for mode in [
            ShadingMode::Flat,
            ShadingMode::Gouraud,
            ShadingMode::Phong,
            ShadingMode::Reference,
        ] {
            let fb = draw_floor(mode, &texture, false, size);
            let (mut checked, mut levels) = (0, [0usize; 5]);
            for y in 0..size.1 {
                for x in 0..size.0 {
                    let Some((want, lod, rho)) = expected(filter, x, y, size) else {
                        continue;
                    };
                    // The rasterizer snaps vertices to 1/256 pixel, which moves the floor's
                    // mapping by up to that many pixels: `rho / 256` texels, where a bilinear
                    // value changes by at most 1 per texel.
                    let shift = rho.max(1.0) / 256.0;
                    // Level 0 alone (nearest, bilinear) under strong minification is aliasing
                    // by design: there the f32 plane's rounding moves uv by whole texels far
                    // away, so its values are compared where a pixel spans at most 4 texels.
                    if filter != Filter::Trilinear && rho > 4.0 {
                        continue;
                    }
                    // Nearest sampling is a step function: pixels whose uv lies within that
                    // of a texel edge may fall either way.
                    if filter == Filter::Nearest {
                        let uv = uv_at(f64::from(x) + 0.5, f64::from(y) + 0.5, size).unwrap();
                        let t = uv * f64::from(N);
                        let (fu, fv) = (t.x - t.x.round(), t.y - t.y.round());
                        if fu.abs() < 1e-3 + shift || fv.abs() < 1e-3 + shift {
                            continue;
                        }
                    }
                    let got = fb.pixel(x, y);
                    assert!(
                        (f64::from(got.x) - want).abs() < 2e-3 + shift,
                        "{mode:?} {filter:?} ({x}, {y}): got {got}, want {want} (level {lod:.3})"
                    );
                    assert_eq!(got.x, got.y);
                    checked += 1;
                    levels[lod.floor() as usize] += 1;
                }
            }
            assert!(checked > 4_000, "{mode:?} {filter:?}: {checked} pixels");
            // The view spans magnified texels near the camera and several levels far away.
            if filter == Filter::Trilinear {
                assert!(
                    levels[0] > 0 && levels[1] > 0 && levels[2] > 0,
                    "{levels:?}"
                );
            }
        }
    }
}

#[test]
fn wrap_modes_reach_the_framebuffer() {
    // The floor spans 20 copies of the texture: clamped, everything past the first copy
    // repeats an edge texel, so the far floor is one flat colour per column.
    let size = (80, 60);
    let texture = checker()
        .with_filter(Filter::Nearest)
        .with_wrap(Wrap::Clamp, Wrap::Clamp);
    let fb = draw_floor(ShadingMode::Phong, &texture, false, size);
    let mut checked = 0;
    for y in 0..size.1 {
        for x in 0..size.0 {
            let Some(uv) = uv_at(f64::from(x) + 0.5, f64::from(y) + 0.5, size) else {
                continue;
            };
            if uv.x > 1.05 && uv.y > 1.05 {
                // The top-right texel (column N - 1, row 0) of the checkerboard.
                assert_eq!(
                    fb.pixel(x, y).x as f64,
                    checker_texel(0, i64::from(N) - 1, 0)
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 100, "{checked}");
}

#[test]
fn vertex_colours_tint_every_mode() {
    // A triangle with red, green and blue corners under ambient light: the centre pixel of
    // every interpolating mode is the perspective-correct mix; flat shows the mean.
    let positions = [
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let normals = [Vec3::Z; 3];
    let colors = [Vec3::X, Vec3::Y, Vec3::Z];
    let indices = [[0u32, 1, 2]];
    let (material, lights) = unlit();
    for mode in ShadingMode::ALL {
        let mut fb = Framebuffer::new(64, 48).unwrap();
        let d = DrawItem {
            mesh: MeshView {
                colors: Some(&colors),
                ..MeshView::new(&positions, &normals, &indices)
            },
            model: Mat4::IDENTITY,
            material: &material,
            lights: &lights,
            effects: Effects::ALL,
            mode,
            bump: None,
            texture: None,
            cull_backfaces: false,
        };
        render(&mut fb, &Camera::s1(), &[d], &RenderOptions::default());
        let c = fb.pixel(32, 26);
        assert!(
            c.x > 0.05
                && c.y > 0.05
                && c.z > 0.05
                && c.x + c.y + c.z > 0.9
                && c.x + c.y + c.z < 1.1,
            "{mode:?}: {c}"
        );
        // Near the red corner, red leads (flat's mean is grey throughout).
        let near_red = fb.pixel(18, 40);
        if mode == ShadingMode::Flat {
            assert!(
                (near_red - Vec3::splat(1.0 / 3.0)).abs().max_element() < 1e-5,
                "{near_red}"
            );
        } else {
            assert!(
                near_red.x > near_red.y && near_red.x > near_red.z,
                "{mode:?}: {near_red}"
            );
        }
    }
}

#[test]
fn lit_textures_keep_the_highlight_untinted() {
    // A black texture under a bright light: ambient and diffuse vanish, the specular
    // highlight stays, in every mode that has one per pixel.
    let texture = Texture::new(1, 1, vec![Vec3::ZERO]).unwrap();
    let f = floor(2.0);
    let lights = LightSet::new(
        Vec3::splat(0.2),
        &[phosphor_lighting::Light::directional(Vec3::new(0.0, -0.34, 0.94), Vec3::ONE).unwrap()],
    );
    let material = Material::s1();
    for mode in [
        ShadingMode::Phong,
        ShadingMode::Reference,
        ShadingMode::FastPhong,
    ] {
        let mut fb = Framebuffer::new(64, 48).unwrap();
        let d = DrawItem {
            mesh: MeshView {
                uvs: Some(&f.uvs),
                ..MeshView::new(&f.positions, &f.normals, &f.indices)
            },
            model: Mat4::IDENTITY,
            material: &material,
            lights: &lights,
            effects: Effects::ALL,
            mode,
            bump: None,
            texture: Some(&texture),
            cull_backfaces: false,
        };
        render(&mut fb, &camera(), &[d], &RenderOptions::default());
        let brightest = (0..48)
            .flat_map(|y| (0..64).map(move |x| (x, y)))
            .map(|(x, y)| fb.pixel(x, y))
            .fold(Vec3::ZERO, Vec3::max);
        assert!(brightest.x > 0.2, "{mode:?}: {brightest}");
        // White highlight: not tinted by the black texture, not tinted at all.
        assert!((brightest.x - brightest.y).abs() < 1e-6, "{brightest}");
    }
}
