//! `phosphor` end to end: every subcommand and flag, and the error paths with their messages and
//! exit codes (docs/conventions.md: 1 for input errors, 2 for usage errors, one `error:` line, and
//! no output file created or replaced on failure).

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn phosphor(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_phosphor"))
        .current_dir(root())
        .args(args)
        .output()
        .unwrap()
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh temporary folder for one test.
fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("phosphor-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The error contract: exit code, one line starting `error: `, containing `needle`.
fn assert_error(o: &Output, code: i32, needle: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(code), "stderr: {e}");
    let errors: Vec<&str> = e.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(errors.len(), 1, "{e}");
    assert!(errors[0].contains(needle), "{e}");
}

#[test]
fn render_default_scene_writes_a_png_of_the_asked_size() {
    let d = temp("render-default");
    let out = d.join("out.png");
    let o = phosphor(&[
        "render",
        "--size",
        "64x36",
        "--threads",
        "2",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    assert!(
        s.contains("64x36") && s.contains("triangles drawn") && s.contains("pixels shaded"),
        "{s}"
    );
    let img = image::open(&out).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (64, 36));
    assert!(
        img.pixels().any(|p| p.0 != img.get_pixel(0, 0).0),
        "a uniform image"
    );
    // No temporary file left behind.
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
}

#[test]
fn render_each_mode_and_encoding_and_exr() {
    let d = temp("render-modes");
    for mode in [
        "flat",
        "gouraud",
        "phong",
        "fast-phong",
        "reference",
        "auto",
    ] {
        let out = d.join(format!("{mode}.png"));
        let o = phosphor(&[
            "render",
            "assets/scenes/s1.toml",
            "--shading",
            mode,
            "--size",
            "48x32",
            "--encoding",
            "srgb",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{mode}: {}", stderr(&o));
        assert!(out.exists());
    }
    // Linear vs sRGB encodings differ on a mid-grey scene.
    let lin = d.join("lin.png");
    let o = phosphor(&[
        "render",
        "assets/scenes/s1.toml",
        "--shading",
        "phong",
        "--size",
        "48x32",
        "--encoding",
        "linear",
        "-o",
        lin.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(
        std::fs::read(&lin).unwrap(),
        std::fs::read(d.join("phong.png")).unwrap()
    );
    // EXR holds the linear values.
    let exr = d.join("s1.exr");
    let o = phosphor(&[
        "render",
        "--mesh",
        "assets/meshes/bunny_small.obj",
        "--size",
        "48x32",
        "-o",
        exr.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&exr).unwrap().to_rgb32f();
    assert_eq!(img.dimensions(), (48, 32));
    assert!(img.pixels().any(|p| p.0[0] > 0.05));
}

#[test]
fn render_plan_prints_modes_effects_and_lights() {
    let o = phosphor(&["render", "--plan", "--size", "64x36"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    assert!(s.starts_with("frame plan: "), "{s}");
    for needle in ["fandisk:", "effects:", "lights:", "bump", "plan time:"] {
        assert!(s.contains(needle), "{needle} missing in {s}");
    }
}

#[test]
fn threads_do_not_change_the_picture() {
    let d = temp("threads");
    let one = d.join("one.png");
    let two = d.join("two.png");
    for (n, out) in [("1", &one), ("2", &two)] {
        let o = phosphor(&[
            "render",
            "--size",
            "80x45",
            "--threads",
            n,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert_eq!(std::fs::read(one).unwrap(), std::fs::read(two).unwrap());
}

#[test]
fn render_errors_name_the_file_and_leave_the_old_output() {
    let d = temp("render-errors");
    let out = d.join("keep.png");
    std::fs::write(&out, b"precious").unwrap();
    let o = phosphor(&["render", "no/such/scene.toml", "-o", out.to_str().unwrap()]);
    assert_error(&o, 1, "no/such/scene.toml");
    let bad = d.join("bad.toml");
    std::fs::write(&bad, "[camera]\nfov_y_deg = 200\n").unwrap();
    let o = phosphor(&["render", bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_error(
        &o,
        1,
        "bad.toml: camera.fov_y_deg: must be between 0 and 180",
    );
    let obj = d.join("bad.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n").unwrap();
    let o = phosphor(&[
        "render",
        "--mesh",
        obj.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_error(&o, 1, "bad.obj:3");
    let o = phosphor(&[
        "render",
        "--mesh",
        "missing.obj",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_error(&o, 1, "missing.obj");
    assert_eq!(std::fs::read(&out).unwrap(), b"precious");
}

#[test]
fn usage_errors_exit_2() {
    let d = temp("usage");
    let out = d.join("x.png");
    let o = phosphor(&["render", "--size", "0x10", "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("between 1 and"));
    let o = phosphor(&["render", "--size", "big", "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let o = phosphor(&["render", "--shading", "shiny", "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let o = phosphor(&["render", "-o", d.join("x.jpg").to_str().unwrap()]);
    assert_error(&o, 2, "must end in .png or .exr");
    let o = phosphor(&["render"]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "output is required without --plan"
    );
    let o = phosphor(&["bench", "--frames", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!out.exists());
}

#[test]
fn unwritable_output_is_an_input_error() {
    // A folder that cannot be made (not even by root): /proc takes no new entries.
    let o = phosphor(&["render", "--size", "16x16", "-o", "/proc/phosphor-no/x.png"]);
    assert_error(
        &o,
        1,
        "/proc/phosphor-no/x.png: cannot make folder /proc/phosphor-no",
    );
    assert!(!Path::new("/proc/phosphor-no").exists());
}

#[test]
fn info_describes_a_mesh() {
    let o = phosphor(&["info", "assets/meshes/fandisk.obj"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    for needle in [
        "vertices:",
        "triangles:        12946",
        "surfaces:",
        "smoothing groups:",
        "materials:",
        "degenerate faces:",
        "bounds:",
    ] {
        assert!(s.contains(needle), "{needle} in {s}");
    }
    let o = phosphor(&["info", "assets/meshes/spider.obj"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        !stdout(&o).contains("materials:        0"),
        "spider has an MTL"
    );
    let o = phosphor(&["info", "nope.obj"]);
    assert_error(&o, 1, "nope.obj: cannot read");
}

#[test]
fn bench_prints_one_contract_line_per_mode() {
    let o = phosphor(&[
        "bench",
        "--mesh",
        "assets/meshes/bunny_small.obj",
        "--size",
        "48x32",
        "--frames",
        "2",
        "--threads",
        "1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    let lines: Vec<&str> = s.lines().collect();
    assert_eq!(lines.len(), 6, "{s}");
    for (line, mode) in lines.iter().zip([
        "flat",
        "gouraud",
        "fast-phong",
        "phong",
        "reference",
        "auto",
    ]) {
        let fields: Vec<&str> = line.split(' ').collect();
        assert_eq!(fields[0], mode, "{line}");
        assert!(
            fields[1].starts_with("median_ms=")
                && fields[2].starts_with("min_ms=")
                && fields[3].starts_with("max_ms="),
            "{line}"
        );
        assert_eq!(fields[4], "frames=2");
        let value = |f: &str| f.split_once('=').unwrap().1.parse::<f64>().unwrap();
        assert!(
            value(fields[2]) <= value(fields[1]) && value(fields[1]) <= value(fields[3]),
            "{line}"
        );
    }
    let o = phosphor(&[
        "bench",
        "--shading",
        "phong",
        "--size",
        "32x18",
        "--frames",
        "1",
    ]);
    assert!(o.status.success());
    assert!(stdout(&o).starts_with("phong median_ms="));
}

#[test]
fn help_shows_an_example_for_each_command() {
    for cmd in ["render", "accuracy", "info", "bench"] {
        let o = phosphor(&[cmd, "--help"]);
        assert!(o.status.success());
        assert!(stdout(&o).contains("Example"), "{cmd}");
    }
}
