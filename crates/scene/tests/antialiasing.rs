//! Anti-aliasing by supersampling: edges get closer to a 16-sample render, the picture does
//! not depend on the thread count, every mode (`reference` too) sees the same samples, and the
//! scene file's `aa` is checked by field.

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
fn supersampled_edges_are_closer_to_sixteen_samples() {
    let scene = Scene::load(&asset("assets/scenes/s1.toml")).unwrap();
    let size = (160, 90);
    let (truth, used) = frame(&scene, ShadingMode::Phong, Antialias::Ssaa16, 2, size);
    assert_eq!(used, Antialias::Ssaa16);
    let (off, used) = frame(&scene, ShadingMode::Phong, Antialias::Off, 2, size);
    assert_eq!(used, Antialias::Off);
    let (four, _) = frame(&scene, ShadingMode::Phong, Antialias::Ssaa4, 2, size);
    let (e_off, e_four) = (mean_error(&off, &truth), mean_error(&four, &truth));
    assert!(e_off > 0.0);
    assert!(
        e_four < 0.6 * e_off,
        "ssaa4 error {e_four:.5} against off {e_off:.5}"
    );
    // Every value is a mean of clamped samples: finite and in [0, 1].
    assert!(
        four.iter()
            .flatten()
            .all(|v| v.is_finite() && (0.0..=1.0).contains(v))
    );
}

#[test]
fn supersampled_frames_are_identical_for_any_thread_count() {
    let scene = Scene::load(&asset("assets/scenes/s1-sphere.toml")).unwrap();
    for mode in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        let one = frame(&scene, mode, Antialias::Ssaa4, 1, (123, 77)).0;
        let two = frame(&scene, mode, Antialias::Ssaa4, 2, (123, 77)).0;
        let three = frame(&scene, mode, Antialias::Ssaa4, 3, (123, 77)).0;
        assert!(one == two && two == three, "{mode}");
    }
}

#[test]
fn reference_gets_the_same_samples_as_the_modes() {
    // With both supersampled, phong stays as close to reference as without: the comparison
    // the accuracy report makes is between pictures of the same samples.
    let scene = Scene::load(&asset("assets/scenes/s1-sphere.toml")).unwrap();
    let size = (96, 54);
    for aa in [Antialias::Off, Antialias::Ssaa4] {
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
fn a_frame_reuses_its_sample_image_and_gives_the_same_picture() {
    let scene = Scene::load(&asset("assets/scenes/s1-sphere.toml")).unwrap();
    let mut fb = Framebuffer::new(64, 36).unwrap();
    let opts = FrameOptions {
        antialias: Some(Antialias::Ssaa4),
        ..FrameOptions::default()
    };
    render_frame(&scene, &mut fb, &opts);
    let first = fb.color().to_vec();
    render_frame(&scene, &mut fb, &opts);
    assert!(fb.color() == first.as_slice());
    // Off again: one sample per pixel, a different picture at the sphere's rim.
    let off = FrameOptions {
        antialias: Some(Antialias::Off),
        ..FrameOptions::default()
    };
    let report = render_frame(&scene, &mut fb, &off);
    assert_eq!(report.stats.antialias, Antialias::Off);
    assert!(fb.color() != first.as_slice());
}

#[test]
fn the_scene_file_chooses_anti_aliasing_by_name() {
    let s = Scene::parse("[render]\naa = \"ssaa4\"\n", "t.toml").unwrap();
    assert_eq!(s.settings.antialias, Antialias::Ssaa4);
    assert_eq!(
        Scene::parse("", "t.toml").unwrap().settings.antialias,
        Antialias::Off
    );
    let e = Scene::parse("[render]\naa = \"msaa4\"\n", "t.toml")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("t.toml: render.aa: "), "{e}");
    assert!(e.contains("expected off, ssaa4 or ssaa16"), "{e}");
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
