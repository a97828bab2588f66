//! Anti-aliasing through the whole pipeline: coverage stays watertight at every sample, a
//! resolved pixel is exactly the share of its samples a surface covers, and multisampling
//! shades a pixel inside a triangle once, as at its centre.

use glam::{Vec3, Vec4};
use phosphor_lighting::{Effects, Light, LightSet, Material};

use super::support::{TestMesh, draw_image, item, unproject};
use crate::{Antialias, Camera, RenderOptions, ShadingMode};

/// A quad of two triangles sharing a diagonal, facing the camera, covering screen pixels
/// `(x0, y0)..(x1, y1)` (fractional corners, so edges cross pixels) at NDC depth 0.5.
fn quad(cam: &Camera, (w, h): (u32, u32), (x0, y0, x1, y1): (f64, f64, f64, f64)) -> TestMesh {
    let p = |x, y| unproject(cam, w, h, x, y, 0.5);
    let mut m = TestMesh {
        positions: vec![p(x0, y1), p(x1, y1), p(x1, y0), p(x0, y0)],
        normals: vec![Vec3::Z; 4],
        ..TestMesh::default()
    };
    m.indices = vec![[0, 1, 2], [0, 2, 3]];
    m.tangents = vec![Vec4::X; 4];
    m
}

#[test]
fn supersampled_flat_quad_has_no_crack_and_quantized_edges() {
    let cam = Camera::s1();
    let size = (40, 30);
    let mesh = quad(&cam, size, (5.3, 4.6, 33.7, 25.2));
    // A directional light along the view: one flat colour over the whole quad.
    let lights = LightSet::new(
        Vec3::ZERO,
        &[Light::directional(-Vec3::Z, Vec3::ONE).unwrap()],
    );
    let material = Material::s1();
    let mut draw = item(&mesh, &material, &lights, ShadingMode::Flat);
    // Diffuse only: the same on both triangles (a highlight would differ by centroid).
    draw.effects = Effects::DIFFUSE;
    let draws = [draw];
    let opts = |aa| RenderOptions {
        antialias: aa,
        threads: 1,
        ..RenderOptions::default()
    };
    let (off, _) = draw_image(size.0, size.1, &cam, &draws, &opts(Antialias::Off));
    let colour = off.pixel(20, 15);
    assert!(colour.x > 0.1);
    for aa in [
        Antialias::Msaa4,
        Antialias::Ssaa4,
        Antialias::Msaa16,
        Antialias::Ssaa16,
    ] {
        let (fb, stats) = draw_image(size.0, size.1, &cam, &draws, &opts(aa));
        assert_eq!(stats.antialias, aa);
        let n = aa.samples() as f32;
        for y in 0..size.1 {
            for x in 0..size.0 {
                let c = fb.pixel(x, y);
                // The share of covered samples, a whole number of 1/n.
                let share = c.x / colour.x;
                let k = (share * n).round();
                assert!(
                    (share * n - k).abs() < 1e-3 && (0.0..=n).contains(&k),
                    "{aa} ({x}, {y}): {share}"
                );
                assert!((c - colour * share).abs().max_element() < 1e-5);
                // Inside the quad, and along its diagonal, every sample is covered once.
                let inside = (7..=32).contains(&x) && (6..=23).contains(&y);
                if inside {
                    assert!(
                        (c - colour).abs().max_element() < 1e-6,
                        "{aa} ({x}, {y}) {c}"
                    );
                }
            }
        }
        // Edge pixels are partly covered: the quad's left edge at x = 5.3 covers 0.7 of
        // column 5 (the samples at 5.5 and after; with 4 x 4 at 5.375, 5.625 and 5.875).
        let left = fb.pixel(5, 15).x / colour.x;
        let want = if aa.factor() == 2 { 0.5 } else { 0.75 };
        assert!((left - want).abs() < 1e-4, "{aa}: {left}");
    }
}

#[test]
fn multisampled_phong_shades_inside_pixels_once_at_their_centre() {
    let cam = Camera::s1();
    let size = (40, 30);
    let (x0, y0, x1, y1) = (5.3, 4.6, 33.7, 25.2);
    let mut mesh = quad(&cam, size, (x0, y0, x1, y1));
    // Normals that vary over the quad, and a point light: every pixel has its own colour.
    mesh.normals = vec![
        Vec3::new(-0.4, -0.3, 1.0).normalize(),
        Vec3::new(0.4, -0.3, 1.0).normalize(),
        Vec3::new(0.4, 0.3, 1.0).normalize(),
        Vec3::new(-0.4, 0.3, 1.0).normalize(),
    ];
    let centre = unproject(&cam, size.0, size.1, 20.0, 15.0, 0.5);
    let lights = LightSet::new(
        Vec3::splat(0.1),
        &[Light::point(centre + Vec3::new(0.2, 0.3, 1.0), Vec3::ONE).unwrap()],
    );
    let material = Material::s1();
    let draws = [item(&mesh, &material, &lights, ShadingMode::Phong)];
    let opts = |aa| RenderOptions {
        antialias: aa,
        threads: 1,
        ..RenderOptions::default()
    };
    let (off, off_stats) = draw_image(size.0, size.1, &cam, &draws, &opts(Antialias::Off));
    for aa in [Antialias::Msaa4, Antialias::Msaa16] {
        let (fb, stats) = draw_image(size.0, size.1, &cam, &draws, &opts(aa));
        let k = f64::from(aa.factor());
        let mut edge_pixels = 0;
        for y in 0..size.1 {
            for x in 0..size.0 {
                // Whether the pixel's samples are all inside, all outside, or split.
                let xs = (0..aa.factor()).map(|s| f64::from(x) + (f64::from(s) + 0.5) / k);
                let ys = (0..aa.factor()).map(|s| f64::from(y) + (f64::from(s) + 0.5) / k);
                let inside_x = xs.clone().all(|v| v > x0 && v < x1);
                let inside_y = ys.clone().all(|v| v > y0 && v < y1);
                // Which side of the shared diagonal, (x0, y1) to (x1, y0), each sample is on.
                let side = |sx: f64, sy: f64| (x1 - x0) * (sy - y1) - (y0 - y1) * (sx - x0) > 0.0;
                let sides: Vec<bool> = ys
                    .clone()
                    .flat_map(|sy| xs.clone().map(move |sx| side(sx, sy)))
                    .collect();
                let one_triangle = sides.iter().all(|&s| s == sides[0]);
                let outside =
                    xs.clone().all(|v| v < x0 || v > x1) || ys.clone().all(|v| v < y0 || v > y1);
                if inside_x && inside_y && one_triangle {
                    // One shading at the pixel centre, as with one sample per pixel: the same
                    // colour to a quarter of a code (the vertices snap to 1/256 of a sample,
                    // not of a pixel, so not bit for bit; a shading a quarter pixel off the
                    // centre would differ by more near the highlight).
                    let (a, b) = (fb.pixel(x, y), off.pixel(x, y));
                    assert!(
                        (a - b).abs().max_element() < 1e-3,
                        "{aa} ({x}, {y}) {a} {b}"
                    );
                } else if !outside {
                    edge_pixels += 1;
                }
            }
        }
        // Pixels inside are shaded once (twice where the diagonal splits them), pixels on the
        // edge once per triangle: far fewer shadings than samples.
        let samples = u64::from(aa.samples());
        assert!(stats.pixels_shaded >= off_stats.pixels_shaded);
        assert!(
            stats.pixels_shaded <= off_stats.pixels_shaded + 2 * (edge_pixels + 2 * 40),
            "{aa}: {} shadings, {} pixels, {edge_pixels} on edges",
            stats.pixels_shaded,
            off_stats.pixels_shaded
        );
        assert!(stats.pixels_shaded < off_stats.pixels_shaded * samples / 2);
    }
}

#[test]
fn coverage_is_the_share_of_drawn_samples_and_hdr_keeps_intensities_above_one() {
    let cam = Camera::s1();
    let size = (40, 30);
    let mesh = quad(&cam, size, (5.3, 4.6, 33.7, 25.2));
    // A directional light of intensity 3 along the view: diffuse well above 1 (Gouraud's
    // vertex clamp, on by default, applies only to a framebuffer that clamps at 1).
    let lights = LightSet::new(
        Vec3::ZERO,
        &[Light::directional(-Vec3::Z, Vec3::splat(3.0)).unwrap()],
    );
    let material = Material::s1();
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        let mut draw = item(&mesh, &material, &lights, mode);
        draw.effects = Effects::DIFFUSE;
        let draws = [draw];
        for aa in Antialias::ALL {
            let opts = RenderOptions {
                antialias: aa,
                threads: 1,
                ..RenderOptions::default()
            };
            let mut unit = crate::Framebuffer::new(size.0, size.1).unwrap();
            crate::render(&mut unit, &cam, &draws, &opts);
            let mut hdr = crate::Framebuffer::new(size.0, size.1).unwrap();
            hdr.set_hdr(true);
            assert!(hdr.hdr() && !unit.hdr());
            crate::render(&mut hdr, &cam, &draws, &opts);
            let centre = hdr.pixel(20, 15);
            assert!(centre.x > 1.0, "{mode} {aa}: {centre}");
            assert_eq!(unit.pixel(20, 15), Vec3::ONE, "{mode} {aa}");
            assert!(
                hdr.color()
                    .iter()
                    .all(|c| c.is_finite() && c.min_element() >= 0.0)
            );
            let coverage = hdr.coverage();
            assert_eq!(coverage, unit.coverage(), "{mode} {aa}");
            let n = aa.samples() as f32;
            let mut partial = 0;
            for y in 0..size.1 {
                for x in 0..size.0 {
                    let a = coverage[(y * size.0 + x) as usize];
                    assert_eq!((a * n).round(), a * n, "{mode} {aa} ({x}, {y}): {a}");
                    // Where nothing is drawn the pixel is the (black) clear, and the reverse.
                    assert_eq!(a == 0.0, hdr.pixel(x, y) == Vec3::ZERO, "({x}, {y})");
                    if a > 0.0 && a < 1.0 {
                        partial += 1;
                    }
                }
            }
            assert_eq!(coverage[0], 0.0);
            assert_eq!(coverage[(15 * size.0 + 20) as usize], 1.0);
            // The left edge at x = 5.3 covers 0.7 of column 5: its centre (5.5), half or
            // three quarters of its samples on the 2 x 2 and 4 x 4 grids.
            let left = coverage[(15 * size.0 + 5) as usize];
            let want = match aa.factor() {
                1 => 1.0,
                2 => 0.5,
                _ => 0.75,
            };
            assert_eq!(left, want, "{mode} {aa}");
            assert_eq!(partial > 0, aa != Antialias::Off, "{mode} {aa}");
        }
    }
}

#[test]
fn switching_the_range_redraws_the_clear_in_the_new_range() {
    let mut fb = crate::Framebuffer::new(4, 3).unwrap();
    fb.clear(Vec3::new(2.0, 0.5, f32::INFINITY));
    assert_eq!(fb.pixel(1, 1), Vec3::new(1.0, 0.5, 1.0));
    fb.set_hdr(true);
    fb.clear(Vec3::new(2.0, 0.5, f32::INFINITY));
    assert_eq!(
        fb.pixel(3, 2),
        Vec3::new(2.0, 0.5, crate::framebuffer::HDR_MAX)
    );
    fb.set_hdr(false);
    fb.clear(Vec3::new(2.0, 0.5, f32::NAN));
    assert_eq!(fb.pixel(0, 0), Vec3::new(1.0, 0.5, 0.0));
}

#[test]
fn whole_pixels_kept_once_give_the_image_of_every_sample_written() {
    use crate::bands::LAYERLESS;
    use crate::framebuffer::layer::WHOLE;
    use crate::{Framebuffer, Interpolation, render};

    let (cam, (w, h)) = (Camera::s1(), (97, 71));
    let Spheres {
        coarse,
        fine,
        material,
        lights,
    } = Spheres::new();
    // Frames in a row into the same framebuffers: draws that write whole pixels (`phong`),
    // samples one by one (`flat`, `gouraud`, the incremental scan line) and both, over one
    // another; a new background, the high range, and a supersampled frame between.
    let frames = [
        (
            ShadingMode::Phong,
            ShadingMode::Flat,
            Interpolation::Plane,
            0,
        ),
        (
            ShadingMode::Flat,
            ShadingMode::Phong,
            Interpolation::Plane,
            0,
        ),
        (
            ShadingMode::Phong,
            ShadingMode::Phong,
            Interpolation::Incremental,
            1,
        ),
        (
            ShadingMode::Gouraud,
            ShadingMode::Phong,
            Interpolation::Plane,
            2,
        ),
        (
            ShadingMode::Phong,
            ShadingMode::FastPhong,
            Interpolation::Plane,
            3,
        ),
        (
            ShadingMode::Phong,
            ShadingMode::Phong,
            Interpolation::Plane,
            0,
        ),
    ];
    for aa in [Antialias::Msaa4, Antialias::Msaa16] {
        for threads in [1, 3] {
            let mut fbs = [
                Framebuffer::new(w, h).unwrap(),
                Framebuffer::new(w, h).unwrap(),
            ];
            for (k, &(first, second, interpolation, twist)) in frames.iter().enumerate() {
                let mut a = item(&coarse, &material, &lights, first);
                a.model = placed(0.1 * k as f32, 0.0, 1.0 + 0.3 * k as f32);
                let mut b = item(&fine, &material, &lights, second);
                b.model = placed(-0.2, 0.15 * k as f32, 0.8);
                let opts = RenderOptions {
                    threads,
                    antialias: if twist == 3 { Antialias::Ssaa4 } else { aa },
                    interpolation,
                    background: Vec3::new(0.1, 0.2, 0.3 + 0.2 * f32::from(twist == 1)),
                    ..RenderOptions::default()
                };
                for (i, fb) in fbs.iter_mut().enumerate() {
                    fb.set_hdr(twist == 2);
                    LAYERLESS.set(i == 1);
                    render(fb, &cam, &[a, b], &opts);
                    LAYERLESS.set(false);
                }
                let what = format!("{aa} x{threads} frame {k}");
                let [layered, plain] = &fbs;
                let (a, b) = (bits(layered), bits(plain));
                let differs = a.iter().zip(&b).position(|(a, b)| a != b);
                assert_eq!(differs, None, "{what}: first value that differs");
                assert_eq!(a.len(), b.len(), "{what}");
                assert_eq!(layered.coverage(), plain.coverage(), "{what}: coverage");
                // The layer held whole pixels where the coarse sphere was shaded by pixel, and
                // no draw shading during traversal (`fast-phong` steps its polynomial) split
                // its bands afterwards; the reference had none.
                let layer = |fb: &Framebuffer| fb.samples.as_ref().and_then(|s| s.layer.clone());
                if matches!(k, 0 | 5) {
                    let kept = layer(layered).is_some_and(|l| l.split.contains(&WHOLE));
                    assert!(kept, "{what}: no whole pixel kept");
                }
                assert!(layer(plain).is_none(), "{what}");
                // Something was drawn, and edges were resolved from their samples.
                let shares = layered.coverage();
                assert!(shares.iter().any(|&s| s > 0.0 && s < 1.0), "{what}");
            }
        }
    }
}

/// Resolving and reading out into a window's buffer band by band, from the last draw or
/// from the first, give the images and words of the frame's end resolve and a readout after
/// the frame.
#[test]
fn resolving_and_reading_out_band_by_band_give_the_frames_end_images() {
    use crate::{Frame, Framebuffer, Interpolation, Shown, WindowBuffer};

    let (cam, (w, h)) = (Camera::s1(), (97, 71));
    let Spheres {
        coarse,
        fine,
        material,
        lights,
    } = Spheres::new();
    // Frames in a row into the same framebuffers, the objects moving (so each frame's end
    // clears what the last one drew elsewhere), a new background, the high range, each
    // anti-aliasing choice and none; three draws a frame, the last drawing nothing in some
    // bands and the first nothing at all in frame 4.
    let frames = [
        (
            Antialias::Msaa4,
            ShadingMode::Phong,
            Interpolation::Plane,
            0,
        ),
        (Antialias::Msaa4, ShadingMode::Flat, Interpolation::Plane, 1),
        (
            Antialias::Ssaa4,
            ShadingMode::Gouraud,
            Interpolation::Plane,
            0,
        ),
        (
            Antialias::Msaa16,
            ShadingMode::Phong,
            Interpolation::Incremental,
            2,
        ),
        (
            Antialias::Msaa4,
            ShadingMode::FastPhong,
            Interpolation::Plane,
            3,
        ),
        (Antialias::Off, ShadingMode::Phong, Interpolation::Plane, 0),
        (
            Antialias::Ssaa16,
            ShadingMode::Phong,
            Interpolation::Plane,
            0,
        ),
        (
            Antialias::Msaa4,
            ShadingMode::Phong,
            Interpolation::Plane,
            0,
        ),
    ];
    for threads in [1, 3] {
        // At the frame's end; from the last draw on; from the first draw on.
        let mut fbs: [Framebuffer; 3] = std::array::from_fn(|_| Framebuffer::new(w, h).unwrap());
        // Each one's window buffer and what it holds: read out after the frame, or by it.
        let mut words: [Vec<u32>; 3] = std::array::from_fn(|_| vec![0; (w * h) as usize]);
        let mut held: [Option<Shown>; 3] = Default::default();
        for (k, &(aa, mode, interpolation, twist)) in frames.iter().enumerate() {
            let mut a = item(&coarse, &material, &lights, ShadingMode::Phong);
            a.model = placed(0.1 * k as f32, 0.0, 1.0 + 0.2 * k as f32);
            if twist == 3 {
                a.model = placed(9.0, 9.0, 1.0);
            }
            let mut b = item(&fine, &material, &lights, mode);
            b.model = placed(-0.2, 0.15 * k as f32, 0.8);
            let mut c = item(&coarse, &material, &lights, mode);
            c.model = placed(-0.5 + 0.05 * k as f32, -0.4, 0.3);
            let opts = RenderOptions {
                threads,
                antialias: aa,
                interpolation,
                background: Vec3::new(0.1, 0.2, 0.3 + 0.2 * f32::from(twist == 1)),
                ..RenderOptions::default()
            };
            let outs = words.iter_mut().zip(held.iter_mut());
            for (from, (fb, (words, shown))) in fbs.iter_mut().zip(outs).enumerate() {
                if k % 3 == 2 {
                    // A buffer whose words are not known (a surface's buffer age 0).
                    *shown = None;
                }
                fb.set_hdr(twist == 2);
                let mut frame = Frame::new(fb, &cam, &opts);
                if from > 0 {
                    frame.show_in(WindowBuffer {
                        words: &mut *words,
                        shown: &mut *shown,
                    });
                }
                for (i, d) in [a, b, c].iter().enumerate() {
                    if (from == 1 && i == 2) || (from == 2 && i == 0) {
                        frame.resolve_as_drawn();
                    }
                    frame.draw_item(d);
                }
                frame.finish();
                if from == 0 {
                    *shown = Some(fb.write_0rgb_over(words, threads, shown.as_ref()));
                }
            }
            let what = format!("x{threads} frame {k} ({aa})");
            let [end, last, first] = &fbs;
            for (name, other) in [("last draw", last), ("first draw", first)] {
                let (a, b) = (bits(end), bits(other));
                let differs = a.iter().zip(&b).position(|(a, b)| a != b);
                assert_eq!(
                    differs, None,
                    "{what}, from the {name}: first value that differs"
                );
                assert_eq!(
                    end.dirty, other.dirty,
                    "{what}, from the {name}: dirty columns"
                );
                assert_eq!(end.clean, other.clean, "{what}, from the {name}");
            }
            for (name, i) in [("last draw", 1), ("first draw", 2)] {
                let differs = words[0].iter().zip(&words[i]).position(|(a, b)| a != b);
                assert_eq!(
                    differs, None,
                    "{what}, read out from the {name}: first word"
                );
                let (a, b) = (format!("{:?}", held[0]), format!("{:?}", held[i]));
                assert_eq!(
                    a, b,
                    "{what}, read out from the {name}: what the buffer holds"
                );
            }
            // The held buffers kept the words of a whole readout.
            let mut whole = vec![0; words[0].len()];
            fbs[0].write_0rgb_threads(&mut whole, 1);
            assert_eq!(words[0], whole, "{what}");
            // Something was drawn, and edges were resolved from their samples.
            if aa != Antialias::Off {
                let shares = end.coverage();
                assert!(shares.iter().any(|&s| s > 0.0 && s < 1.0), "{what}");
            }
        }
    }
}

/// A window's buffer that is not the image's length, and a frame with no draw, are read out
/// at the frame's end: the words of a readout after the frame.
#[test]
fn a_window_buffer_the_bands_cannot_fill_is_read_out_at_the_frames_end() {
    use crate::{Frame, Framebuffer, Shown, WindowBuffer};

    let (cam, (w, h)) = (Camera::s1(), (61, 43));
    let Spheres {
        fine,
        material,
        lights,
        ..
    } = Spheres::new();
    let d = item(&fine, &material, &lights, ShadingMode::Phong);
    for aa in [Antialias::Off, Antialias::Msaa4] {
        for (len, draws) in [((w * h) as usize - 5, 1), ((w * h) as usize, 0)] {
            let opts = RenderOptions {
                antialias: aa,
                background: Vec3::new(0.3, 0.2, 0.1),
                ..RenderOptions::default()
            };
            let mut fb = Framebuffer::new(w, h).unwrap();
            let (mut words, mut shown) = (vec![7; len], None::<Shown>);
            let mut frame = Frame::new(&mut fb, &cam, &opts);
            frame.show_in(WindowBuffer {
                words: &mut words,
                shown: &mut shown,
            });
            frame.resolve_as_drawn();
            for _ in 0..draws {
                frame.draw_item(&d);
            }
            frame.finish();
            let mut after = vec![7; len];
            let want = fb.write_0rgb_over(&mut after, 1, None);
            let what = format!("{aa}, {len} words, {draws} draws");
            assert_eq!(words, after, "{what}");
            assert_eq!(format!("{shown:?}"), format!("{:?}", Some(want)), "{what}");
            if draws > 0 {
                assert!(
                    words.iter().any(|&v| v != words[0]),
                    "{what}: nothing drawn"
                );
            }
        }
    }
}

/// Two UV spheres of one size, one of large triangles (they leave whole pixels in a pixel
/// layer) and one of small ones (they split pixels), with S1's material and lights: the
/// frames-in-a-row tests draw them moving over one another.
struct Spheres {
    coarse: TestMesh,
    fine: TestMesh,
    material: Material,
    lights: LightSet,
}

impl Spheres {
    fn new() -> Spheres {
        use super::support::{s1_lights, uv_sphere};
        Spheres {
            coarse: uv_sphere(0.35, 6, 4),
            fine: uv_sphere(0.35, 48, 32),
            material: Material::s1(),
            lights: s1_lights(),
        }
    }
}

/// Scale `s`, then a move by `(x, y)`.
fn placed(x: f32, y: f32, s: f32) -> glam::Mat4 {
    glam::Mat4::from_translation(Vec3::new(x, y, 0.0)) * glam::Mat4::from_scale(Vec3::splat(s))
}

/// Every colour's and depth's bits, to compare images exactly.
fn bits(fb: &crate::Framebuffer) -> Vec<u32> {
    let c = fb.color().iter().flat_map(|c| c.to_array());
    c.chain(fb.depth().iter().copied())
        .map(f32::to_bits)
        .collect()
}
