//! Anti-aliasing by supersampling and multisampling: edges get closer to a 16-sample render,
//! multisampling shades each pixel once per triangle, the picture does not depend on the
//! thread count or on what the framebuffer drew before, every mode (`reference` too) sees the
//! same samples, and the scene file's `aa` is checked by field.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use phosphor_raster::{Antialias, Framebuffer, ShadingMode};
use phosphor_scene::{FrameOptions, Scene, ShadingChoice, render_frame};

fn asset(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// The linear colours of `scene` at `size` in `mode` with `aa` on `threads` threads, and the
/// anti-aliasing the frame reports.
fn frame(
    scene: &Scene,
    mode: ShadingMode,
    aa: Antialias,
    threads: usize,
    size: (u32, u32),
) -> (Vec<[f32; 3]>, Antialias) {
    let mut fb = Framebuffer::new(size.0, size.1).unwrap();
    let opts = FrameOptions {
        shading: Some(ShadingChoice::Mode(mode)),
        threads,
        antialias: Some(aa),
        ..FrameOptions::default()
    };
    let report = render_frame(scene, &mut fb, &opts);
    (
        fb.color().iter().map(|c| c.to_array()).collect(),
        report.stats.antialias,
    )
}

/// Mean absolute difference per channel.
fn mean_error(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |i| f64::from((p[i] - q[i]).abs())))
        .sum();
    sum / (a.len() * 3) as f64
}

#[test]
fn anti_aliased_edges_are_closer_to_sixteen_samples() {
    let scene = Scene::load(&asset("assets/scenes/s1.toml")).unwrap();
    let size = (160, 90);
    let (truth, used) = frame(&scene, ShadingMode::Phong, Antialias::Ssaa16, 2, size);
    assert_eq!(used, Antialias::Ssaa16);
    let (off, used) = frame(&scene, ShadingMode::Phong, Antialias::Off, 2, size);
    assert_eq!(used, Antialias::Off);
    let e_off = mean_error(&off, &truth);
    assert!(e_off > 0.0);
    let mut errors = Vec::new();
    for aa in [Antialias::Msaa4, Antialias::Ssaa4, Antialias::Msaa16] {
        let (img, used) = frame(&scene, ShadingMode::Phong, aa, 2, size);
        assert_eq!(used, aa);
        let e = mean_error(&img, &truth);
        assert!(e < 0.6 * e_off, "{aa} error {e:.5} against off {e_off:.5}");
        // Every value is a mean of clamped samples: finite and in [0, 1].
        assert!(
            img.iter()
                .flatten()
                .all(|v| v.is_finite() && (0.0..=1.0).contains(v))
        );
        errors.push(e);
    }
    // Multisampling covers the same samples as supersampling and shades inside a pixel once:
    // msaa4 is about as close as ssaa4, and msaa16 (ssaa16's own coverage) closer still.
    let [msaa4, ssaa4, msaa16] = errors[..] else {
        unreachable!()
    };
    assert!(
        msaa4 < 1.25 * ssaa4,
        "msaa4 {msaa4:.5} against ssaa4 {ssaa4:.5}"
    );
    assert!(
        msaa16 < 0.5 * msaa4,
        "msaa16 {msaa16:.5} against msaa4 {msaa4:.5}"
    );
}

#[test]
fn multisampling_shades_each_pixel_once_per_triangle() {
    // Inside a triangle a pixel's samples share one shading, so msaa shades far fewer times
    // than ssaa4 and not many more than once per pixel: the extra shadings are the pixels on
    // edges, where two triangles share a pixel. Twice the size has four times the pixels but
    // only about twice the edge pixels.
    let scene = Scene::load(&asset("assets/scenes/s1-sphere.toml")).unwrap();
    let shaded = |aa, size: (u32, u32)| {
        let mut fb = Framebuffer::new(size.0, size.1).unwrap();
        let opts = FrameOptions {
            shading: Some(ShadingChoice::Mode(ShadingMode::Phong)),
            antialias: Some(aa),
            ..FrameOptions::default()
        };
        render_frame(&scene, &mut fb, &opts).stats.pixels_shaded
    };
    let small = (480, 270);
    let (off, msaa4, ssaa4, msaa16) = (
        shaded(Antialias::Off, small),
        shaded(Antialias::Msaa4, small),
        shaded(Antialias::Ssaa4, small),
        shaded(Antialias::Msaa16, small),
    );
    assert!(off > 10_000);
    assert!(ssaa4 > 3 * off, "ssaa4 {ssaa4}, off {off}");
    assert!(
        msaa4 > off && 10 * msaa4 < 16 * off,
        "msaa4 {msaa4}, off {off}"
    );
    assert!(
        msaa16 > msaa4 && 10 * msaa16 < 19 * off,
        "msaa16 {msaa16}, off {off}"
    );
    let large = (960, 540);
    let (off2, msaa4_2) = (
        shaded(Antialias::Off, large),
        shaded(Antialias::Msaa4, large),
    );
    assert!(off2 > 3 * off);
    assert!(
        10 * (msaa4_2 - off2) < 26 * (msaa4 - off),
        "extra shadings {} at {large:?} against {} at {small:?}",
        msaa4_2 - off2,
        msaa4 - off
    );
}

#[test]
fn anti_aliased_frames_are_identical_for_any_thread_count() {
    let scene = Scene::load(&asset("assets/scenes/s1-sphere.toml")).unwrap();
    for aa in [Antialias::Msaa4, Antialias::Ssaa4, Antialias::Msaa16] {
        for mode in [
            ShadingMode::Flat,
            ShadingMode::Gouraud,
            ShadingMode::Phong,
            ShadingMode::FastPhong,
        ] {
            let one = frame(&scene, mode, aa, 1, (123, 77)).0;
            let two = frame(&scene, mode, aa, 2, (123, 77)).0;
            let three = frame(&scene, mode, aa, 3, (123, 77)).0;
            assert!(one == two && two == three, "{aa} {mode}");
        }
    }
}

#[test]
fn reference_gets_the_same_samples_as_the_modes() {
    // With both anti-aliased, phong stays as close to reference as without: the comparison
    // the accuracy report makes is between pictures of the same samples. (Multisampled phong
    // shades an edge pixel's samples of one triangle at their centroid, reference each
    // sample: the difference stays within the same bound.)
    let scene = Scene::load(&asset("assets/scenes/s1-sphere.toml")).unwrap();
    let size = (96, 54);
    for aa in [Antialias::Off, Antialias::Msaa4, Antialias::Ssaa4] {
        let (phong, _) = frame(&scene, ShadingMode::Phong, aa, 2, size);
        let (reference, used) = frame(&scene, ShadingMode::Reference, aa, 2, size);
        assert_eq!(used, aa);
        let worst = phong
            .iter()
            .zip(&reference)
            .flat_map(|(p, q)| (0..3).map(move |i| (p[i] - q[i]).abs()))
            .fold(0.0f32, f32::max);
        assert!(worst < 2.0 / 255.0, "{aa}: worst {worst}");
    }
}

#[test]
fn a_reused_framebuffer_gives_the_picture_a_fresh_one_gives() {
    // The resolve rewrites only what a frame or the one before drew: a framebuffer that drew
    // other scenes with other choices must end with the same bytes as a fresh one.
    let sphere = Scene::load(&asset("assets/scenes/s1-sphere.toml")).unwrap();
    let bunny = Scene::load(&asset("assets/scenes/s1.toml")).unwrap();
    let size = (64, 36);
    let opts = |aa| FrameOptions {
        antialias: Some(aa),
        ..FrameOptions::default()
    };
    let mut fb = Framebuffer::new(size.0, size.1).unwrap();
    let sequence = [
        (&sphere, Antialias::Ssaa4),
        (&sphere, Antialias::Ssaa4),
        (&bunny, Antialias::Msaa4),
        (&sphere, Antialias::Off),
        (&bunny, Antialias::Msaa4),
        (&sphere, Antialias::Msaa4),
        (&bunny, Antialias::Msaa16),
        (&bunny, Antialias::Off),
        (&sphere, Antialias::Msaa16),
    ];
    let mut last = Vec::new();
    for (k, &(scene, aa)) in sequence.iter().enumerate() {
        let report = render_frame(scene, &mut fb, &opts(aa));
        assert_eq!(report.stats.antialias, aa);
        let mut fresh = Framebuffer::new(size.0, size.1).unwrap();
        render_frame(scene, &mut fresh, &opts(aa));
        assert!(fb.color() == fresh.color(), "frame {k}: {aa}");
        assert!(fb.depth() == fresh.depth(), "frame {k}: {aa} depth");
        // Consecutive frames of another scene or choice differ, so the check above is not
        // vacuous.
        let repeat = k > 0 && std::ptr::eq(sequence[k - 1].0, scene) && sequence[k - 1].1 == aa;
        assert_eq!(fb.color() == last.as_slice(), repeat, "frame {k}");
        last = fb.color().to_vec();
    }
}

#[test]
fn the_scene_file_chooses_anti_aliasing_by_name() {
    let s = Scene::parse("[render]\naa = \"ssaa4\"\n", "t.toml").unwrap();
    assert_eq!(s.settings.antialias, Antialias::Ssaa4);
    assert_eq!(
        Scene::parse("", "t.toml").unwrap().settings.antialias,
        Antialias::Off
    );
    let s = Scene::parse("[render]\naa = \"msaa4\"\n", "t.toml").unwrap();
    assert_eq!(s.settings.antialias, Antialias::Msaa4);
    let e = Scene::parse("[render]\naa = \"msaa8\"\n", "t.toml")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("t.toml: render.aa: "), "{e}");
    assert!(
        e.contains("expected off, msaa4, ssaa4, msaa16 or ssaa16"),
        "{e}"
    );
    let e = Scene::parse(
        "[render]\nwidth = 10000\nheight = 100\naa = \"ssaa16\"\n",
        "t.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("t.toml: render.aa: ssaa16 draws 40000x400 samples"),
        "{e}"
    );
}
