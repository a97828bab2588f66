//! Backgrounds and high-dynamic-range output from the command line: a transparent background
//! gives PNG an alpha channel that is the exact coverage (0 outside the object, 255 inside,
//! the share of samples on an anti-aliased edge) and EXR an A channel; EXR keeps intensities
//! above 1; `--exposure` scales by `2^EV` and `--tone-map` brings highlights into range;
//! `--wireframe` draws the edges over the picture (smooth in an anti-aliased frame), `--grid`
//! and `--axes` their guides; bad values are one usage error naming the
//! flag.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn phosphor(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_phosphor"))
        .current_dir(root())
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("phosphor-hdr-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Renders `args` into `dir/name` and returns the path; the run must succeed.
fn render(dir: &Path, name: &str, args: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let mut all = vec!["render"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", out.to_str().unwrap()]);
    let o = phosphor(&all);
    assert!(o.status.success(), "{all:?}: {}", stderr(&o));
    out
}

/// The cube in S1 (linear PNG codes), 64x48, anti-aliased.
const CUBE: [&str; 6] = [
    "--mesh",
    "assets/meshes/cube.obj",
    "--size",
    "64x48",
    "--aa",
    "msaa4",
];

/// A scene whose sphere is lit well above 1 by a point light of intensity 6.
fn bright_scene(dir: &Path) -> PathBuf {
    let path = dir.join("bright.toml");
    std::fs::write(
        &path,
        "[render]\nwidth = 48\nheight = 32\nencoding = \"linear\"\n[[lights]]\ntype = \"point\"\nposition = [0, 2, 4]\nintensity = 6\n[[objects]]\nprimitive = { shape = \"sphere\", radius = 1.0, segments = 24, rings = 12 }\n",
    )
    .unwrap();
    path
}

#[test]
fn a_transparent_background_gives_png_the_coverage_as_alpha() {
    let d = temp("alpha");
    let opaque = render(&d, "opaque.png", &CUBE);
    let mut args = CUBE.to_vec();
    args.extend(["--background", "transparent"]);
    let clear = render(&d, "clear.png", &args);
    let opaque = image::open(&opaque).unwrap();
    assert!(
        !opaque.color().has_alpha(),
        "an opaque background stays RGB"
    );
    let opaque = opaque.to_rgb8();
    let clear = image::open(&clear).unwrap();
    assert!(clear.color().has_alpha());
    let clear = clear.to_rgba8();
    assert_eq!(clear.dimensions(), (64, 48));
    assert_eq!(clear.get_pixel(0, 0).0[3], 0, "corner");
    assert_eq!(clear.get_pixel(32, 24).0[3], 255, "centre of the cube");
    let mut edges = 0;
    for (x, y, p) in clear.enumerate_pixels() {
        let [r, g, b, a] = p.0;
        let o = opaque.get_pixel(x, y).0;
        match a {
            0 => assert_eq!([r, g, b], [0, 0, 0], "({x}, {y})"),
            255 => assert_eq!(
                [r, g, b],
                o,
                "({x}, {y}): covered pixels are the opaque ones"
            ),
            _ => {
                edges += 1;
                // Over black the opaque picture is the colour times the coverage (linear codes).
                for (c, o) in [r, g, b].into_iter().zip(o) {
                    let over_black = f32::from(c) * f32::from(a) / 255.0;
                    assert!(
                        (over_black - f32::from(o)).abs() <= 1.5,
                        "({x}, {y}): {c} at alpha {a} against {o}"
                    );
                }
            }
        }
    }
    assert!(edges > 20, "only {edges} partly covered pixels");
    // Without anti-aliasing a pixel is covered or not.
    let sharp = render(
        &d,
        "sharp.png",
        &[
            "--mesh",
            "assets/meshes/cube.obj",
            "--size",
            "64x48",
            "--background",
            "0,0,0,0",
        ],
    );
    let sharp = image::open(&sharp).unwrap().to_rgba8();
    assert!(sharp.pixels().all(|p| p.0[3] == 0 || p.0[3] == 255));
    assert!(sharp.pixels().any(|p| p.0[3] == 255));
}

#[test]
fn a_half_opaque_background_and_opaque_flags_keep_the_picture() {
    let d = temp("opaque");
    let plain = render(&d, "plain.png", &CUBE);
    let mut args = CUBE.to_vec();
    args.extend([
        "--background",
        "0,0,0",
        "--exposure",
        "0",
        "--tone-map",
        "clamp",
    ]);
    let flagged = render(&d, "flagged.png", &args);
    assert_eq!(
        std::fs::read(&plain).unwrap(),
        std::fs::read(&flagged).unwrap()
    );
    // A grey background at half opacity: alpha 128 (of 255) where nothing is drawn, and the
    // background's own colour there.
    let mut args = CUBE.to_vec();
    args.extend(["--background", "0.5,0.25,1,0.5"]);
    let half = image::open(render(&d, "half.png", &args))
        .unwrap()
        .to_rgba8();
    assert_eq!(half.get_pixel(0, 0).0, [128, 64, 255, 128]);
    assert_eq!(half.get_pixel(32, 24).0[3], 255);
}

#[test]
fn exr_keeps_intensities_above_one_and_an_alpha_channel() {
    let d = temp("exr");
    let scene = bright_scene(&d);
    let scene = scene.to_str().unwrap();
    let exr = image::open(render(&d, "bright.exr", &[scene]))
        .unwrap()
        .to_rgba32f();
    let peak = exr.pixels().map(|p| p.0[0]).fold(0.0f32, f32::max);
    assert!(peak > 1.5, "peak {peak}");
    assert!(exr.pixels().all(|p| p.0.iter().all(|v| v.is_finite())));
    // The same frame as PNG is clamped: the peak is code 255, and many pixels share it.
    let png = image::open(render(&d, "bright.png", &[scene]))
        .unwrap()
        .to_rgb8();
    let saturated = png.pixels().filter(|p| p.0[0] == 255).count();
    assert!(saturated > 10, "{saturated}");
    // Exposure scales EXR by 2^EV.
    let half = render(&d, "half.exr", &[scene, "--exposure", "-1"]);
    let half = image::open(half).unwrap().to_rgba32f();
    for (a, b) in exr.pixels().zip(half.pixels()) {
        assert!(
            (a.0[0] * 0.5 - b.0[0]).abs() <= 1e-3 * a.0[0].max(1.0),
            "{a:?} {b:?}"
        );
    }
    // Transparent: A is 0 in the corner and 1 on the sphere, the colour premultiplied.
    let clear = render(
        &d,
        "clear.exr",
        &[scene, "--background", "transparent", "--aa", "ssaa16"],
    );
    let clear = image::open(clear).unwrap().to_rgba32f();
    assert_eq!(clear.get_pixel(0, 0).0, [0.0; 4]);
    assert_eq!(clear.get_pixel(24, 16).0[3], 1.0);
    let partial = clear
        .pixels()
        .filter(|p| p.0[3] > 0.0 && p.0[3] < 1.0)
        .count();
    assert!(partial > 10, "{partial}");
    assert!(clear.pixels().any(|p| p.0[0] > 1.5));
}

#[test]
fn tone_maps_bring_highlights_into_range_and_exposure_scales_png() {
    let d = temp("tone");
    let scene = bright_scene(&d);
    let scene = scene.to_str().unwrap();
    let clamp = image::open(render(&d, "clamp.png", &[scene]))
        .unwrap()
        .to_rgb8();
    let exr = image::open(render(&d, "linear.exr", &[scene]))
        .unwrap()
        .to_rgb32f();
    for tone in ["reinhard", "aces"] {
        let name = format!("{tone}.png");
        let png = render(&d, &name, &[scene, "--tone-map", tone]);
        let png = image::open(png).unwrap().to_rgb8();
        // The brightest pixels keep their order (the curves rise) where the clamp merges them.
        let mut pairs: Vec<(f32, u8)> = exr
            .pixels()
            .zip(png.pixels())
            .map(|(e, p)| (e.0[0], p.0[0]))
            .collect();
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert!(
            pairs.windows(2).all(|w| w[0].1 <= w[1].1),
            "{tone} is monotone"
        );
        let bright: Vec<u8> = pairs.iter().filter(|p| p.0 > 1.0).map(|p| p.1).collect();
        assert!(bright.len() > 10, "{tone}");
        let distinct = bright.windows(2).filter(|w| w[0] != w[1]).count();
        assert!(distinct > 3, "{tone}: highlights merged");
        // Black stays black.
        assert_eq!(png.get_pixel(0, 0).0, [0, 0, 0]);
    }
    assert!(
        clamp
            .pixels()
            .zip(exr.pixels())
            .all(|(p, e)| e.0[0] < 1.0 || p.0[0] == 255)
    );
    // Exposure -1 halves the linear codes of pixels the clamp did not touch.
    let dark = image::open(render(&d, "dark.png", &[scene, "--exposure", "-1"])).unwrap();
    let dark = dark.to_rgb8();
    let mut seen = 0;
    for (e, (p, q)) in exr.pixels().zip(clamp.pixels().zip(dark.pixels())) {
        if e.0[0] < 0.99 {
            let half = f32::from(p.0[0]) / 2.0;
            assert!((half - f32::from(q.0[0])).abs() <= 1.0, "{p:?} {q:?}");
            seen += 1;
        } else if e.0[0] > 2.2 {
            assert!(q.0[0] == 255, "{e:?} {q:?}");
        }
    }
    assert!(seen > 100);
}

#[test]
fn bad_backgrounds_exposures_and_tone_maps_are_usage_errors_naming_the_flag() {
    for (args, start) in [
        (
            &["--background", "1,2"][..],
            "error: --background: invalid value '1,2'",
        ),
        (
            &["--background", "0,0,0,2"][..],
            "error: --background: invalid value '0,0,0,2'",
        ),
        (
            &["--background", "-1,0,0"][..],
            "error: --background: invalid value '-1,0,0'",
        ),
        (
            &["--exposure", "nan"][..],
            "error: --exposure: invalid value 'nan'",
        ),
        (
            &["--exposure", "inf"][..],
            "error: --exposure: invalid value 'inf'",
        ),
        (
            &["--exposure", "200"][..],
            "error: --exposure: invalid value '200'",
        ),
        (
            &["--tone-map", "filmic"][..],
            "error: --tone-map: invalid value 'filmic'",
        ),
    ] {
        let mut all = vec!["render"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["-o", "x.png"]);
        let o = phosphor(&all);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{all:?}: {e}");
        assert_eq!(e.lines().count(), 1, "{all:?}: {e}");
        assert!(e.starts_with(start), "{all:?}: {e}");
    }
    let d = temp("bad");
    let exr = d.join("x.exr");
    let o = phosphor(&["render", "--tone-map", "aces", "-o", exr.to_str().unwrap()]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.starts_with("error: --tone-map aces: applies to PNG only"),
        "{e}"
    );
    assert!(!exr.exists());
    // A scene's background is checked by field, an input error.
    let scene = d.join("bad.toml");
    std::fs::write(&scene, "[render]\nbackground = [0, 0, 0, 3]\n").unwrap();
    let o = phosphor(&["render", scene.to_str().unwrap(), "-o", "x.png"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("render.background: alpha must be in [0, 1], got 3"),
        "{e}"
    );
}

/// The pixels of `a` and `b` (same size) that differ, as `(x, y, a's, b's)`.
fn changes(a: &image::RgbImage, b: &image::RgbImage) -> Vec<(u32, u32, [u8; 3], [u8; 3])> {
    a.enumerate_pixels()
        .zip(b.pixels())
        .filter(|((_, _, p), q)| p != q)
        .map(|((x, y, p), q)| (x, y, p.0, q.0))
        .collect()
}

#[test]
fn wireframe_draws_edges_over_the_picture_and_changes_nothing_else() {
    let d = temp("wire");
    let open = |name: &str, extra: &[&str], aa: &str| {
        let mut args = CUBE[..4].to_vec();
        args.extend_from_slice(&["--aa", aa]);
        args.extend_from_slice(extra);
        image::open(render(&d, name, &args)).unwrap().to_rgb8()
    };
    let plain = open("plain.png", &[], "off");
    let wired = open("wired.png", &["--wireframe=1,0,0"], "off");
    let lines = changes(&plain, &wired);
    // The cube's visible edges: three faces' outlines and diagonals, dozens of pixels, each
    // taking the line's colour whole without anti-aliasing.
    assert!(lines.len() > 60, "{} line pixels", lines.len());
    assert!(lines.iter().all(|c| c.3 == [255, 0, 0]));
    // Crease edges only: the outlines without the faces' diagonals.
    let creases = open(
        "creases.png",
        &["--wireframe=1,0,0", "--wire-edges", "creases"],
        "off",
    );
    let crease_lines = changes(&plain, &creases);
    assert!(
        crease_lines.len() > 40 && crease_lines.len() + 20 < lines.len(),
        "{} of {}",
        crease_lines.len(),
        lines.len()
    );
    assert!(crease_lines.iter().all(|c| c.3 == [255, 0, 0]));
    // Alone, the flag draws black lines.
    let black = open("black.png", &["--wireframe"], "off");
    let changed = changes(&plain, &black);
    assert!(changed.len() > 60 && changed.iter().all(|c| c.3 == [0, 0, 0]));
    // An anti-aliased frame gets smooth lines: every changed pixel moves towards red, and
    // the pixels either side of a line take part of it.
    let plain4 = open("plain4.png", &[], "msaa4");
    let smooth = changes(
        &plain4,
        &open("smooth.png", &["--wireframe=1,0,0"], "msaa4"),
    );
    assert!(
        smooth
            .iter()
            .all(|(_, _, p, q)| q[0] >= p[0] && q[1] <= p[1] && q[2] <= p[2])
    );
    let partial = smooth.iter().filter(|c| c.3 != [255, 0, 0]).count();
    assert!(
        partial > 20 && smooth.len() > lines.len(),
        "{partial} of {}",
        smooth.len()
    );
    for bad in [
        "--wireframe=1,2",
        "--wireframe=0,0,0,1",
        "--wireframe=nan,0,0",
    ] {
        let o = phosphor(&["render", bad, "-o", "x.png"]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{bad}: {e}");
        assert!(
            e.starts_with("error: --wireframe: invalid value"),
            "{bad}: {e}"
        );
    }
    for bad in ["creases:200", "creases:x", "sides"] {
        let o = phosphor(&["render", "--wireframe", "--wire-edges", bad, "-o", "x.png"]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{bad}: {e}");
        assert!(
            e.starts_with("error: --wire-edges: invalid value"),
            "{bad}: {e}"
        );
    }
    let o = phosphor(&["render", "--wire-edges", "all", "-o", "x.png"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--wireframe"), "{}", stderr(&o));
}

#[test]
fn the_grid_shows_around_the_object_and_the_axes_stay_in_their_corner() {
    let d = temp("guides");
    let open = |name: &str, extra: &[&str]| {
        let mut args = CUBE[..4].to_vec();
        args.extend_from_slice(&["--aa", "off"]);
        args.extend_from_slice(extra);
        image::open(render(&d, name, &args)).unwrap().to_rgb8()
    };
    let plain = open("plain.png", &[]);
    let grid = changes(&plain, &open("grid.png", &["--grid=0,1,0"]));
    assert!(grid.len() > 30, "{}", grid.len());
    assert!(grid.iter().all(|c| c.3 == [0, 255, 0]));
    // Over a transparent background the grid's lines are opaque, and only they and the cube.
    let mut args = CUBE[..4].to_vec();
    args.extend_from_slice(&["--aa", "off", "--grid=0,1,0", "--background", "transparent"]);
    let clear = image::open(render(&d, "clear.png", &args))
        .unwrap()
        .to_rgba8();
    let plain_clear = {
        let mut args = CUBE[..4].to_vec();
        args.extend_from_slice(&["--aa", "off", "--background", "transparent"]);
        image::open(render(&d, "plain_clear.png", &args))
            .unwrap()
            .to_rgba8()
    };
    let on_grid = |x, y| grid.iter().any(|c| (c.0, c.1) == (x, y));
    let mut lines = 0;
    for (x, y, p) in clear.enumerate_pixels() {
        if plain_clear.get_pixel(x, y).0[3] == 255 {
            assert_eq!(p.0[3], 255, "({x}, {y}): the cube");
        } else if on_grid(x, y) {
            assert_eq!(p.0, [0, 255, 0, 255], "({x}, {y}): a grid line");
            lines += 1;
        } else {
            assert_eq!(p.0, [0, 0, 0, 0], "({x}, {y}): the background");
        }
    }
    assert!(lines > 30, "{lines}");
    let axes = changes(&plain, &open("axes.png", &["--axes"]));
    assert!(axes.len() >= 6, "{}", axes.len());
    // 64x48: the triad's arms are 6 pixels long from (9, 39).
    assert!(
        axes.iter().all(|&(x, y, _, _)| x < 16 && y > 32),
        "{axes:?}"
    );
    // x red, y green, z blue: each arm has its axis's channel strongest.
    for ch in 0..3 {
        assert!(
            axes.iter()
                .any(|c| (0..3).all(|k| k == ch || c.3[ch] > c.3[k])),
            "channel {ch}"
        );
    }
}
