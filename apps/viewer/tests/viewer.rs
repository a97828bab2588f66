//! The viewer binary end to end. winit's event loop must run on the main thread, once per process,
//! so these tests spawn `phosphor-viewer` rather than calling it (docs/conventions.md, "Dependency
//! facts"). The window test looks for `xvfb-run` when it runs and skips itself, with a note on
//! stderr, where there is none (except under CI, which installs it).

use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// How long a headless run may take before the test gives up on it.
const TIMEOUT: Duration = Duration::from_secs(180);

fn viewer() -> Command {
    Command::new(env!("CARGO_BIN_EXE_phosphor-viewer"))
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs `cmd` to completion, killing it after [`TIMEOUT`].
fn run_with_timeout(mut cmd: Command) -> Output {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let started = Instant::now();
    loop {
        if child.try_wait().expect("wait").is_some() {
            return child.wait_with_output().expect("output");
        }
        if started.elapsed() > TIMEOUT {
            let _ = child.kill();
            let out = child.wait_with_output().expect("output");
            panic!("timed out after {TIMEOUT:?}; stderr: {}", text(&out.stderr));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn without_a_display_the_viewer_says_so_and_points_to_render() {
    let mut cmd = viewer();
    cmd.env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .args(["--frames", "1"]);
    let out = run_with_timeout(cmd);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.starts_with("error: no display available"),
        "{stderr}"
    );
    // One sentence: the platform's reason without its own full stop, then what to do.
    assert!(
        stderr
            .trim_end()
            .ends_with("; use `phosphor render` to render to a file"),
        "{stderr}"
    );
    assert!(!stderr.contains(".)") && !stderr.contains(".;"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
}

#[test]
fn a_bad_size_is_a_usage_error() {
    let mut cmd = viewer();
    cmd.args(["--size", "wide"]);
    let out = run_with_timeout(cmd);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains("WxH"));
}

#[test]
fn a_screenshot_that_is_not_png_is_a_one_line_usage_error() {
    let mut cmd = viewer();
    cmd.args(["--frames", "1", "--screenshot", "shot.jpg"]);
    let out = run_with_timeout(cmd);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(
        stderr,
        "error: --screenshot: invalid value 'shot.jpg': must end in .png (screenshots are PNG)\n"
    );
}

#[test]
fn a_read_only_screenshot_is_refused_before_any_window_opens() {
    let dir = std::env::temp_dir().join(format!("phosphor-viewer-ro-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let shot = dir.join("kept.png");
    std::fs::write(&shot, b"precious").expect("write");
    let mut perms = std::fs::metadata(&shot).expect("metadata").permissions();
    perms.set_readonly(true);
    std::fs::set_permissions(&shot, perms).expect("chmod");
    let mut cmd = viewer();
    cmd.env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .args(["--frames", "1", "--screenshot"])
        .arg(&shot);
    let out = run_with_timeout(cmd);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(
        stderr,
        format!(
            "error: {}: is read-only (--force writes it anyway)\n",
            shot.display()
        )
    );
    assert_eq!(std::fs::read(&shot).expect("read"), b"precious");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn usage_errors_are_one_line() {
    for args in [&["--size", "wide"][..], &["--frames", "0"], &["--bogus"]] {
        let mut cmd = viewer();
        cmd.args(args);
        let out = run_with_timeout(cmd);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: --"), "{args:?}: {stderr}");
    }
}

/// Distinct colours in an RGB8 image, counted on a coarse 4-bit-per-channel grid so that
/// shading gradients count once per band.
fn distinct_colours(img: &image::RgbImage) -> usize {
    let mut seen = std::collections::HashSet::new();
    for p in img.pixels() {
        seen.insert((p[0] >> 4, p[1] >> 4, p[2] >> 4));
    }
    seen.len()
}

/// Whether `xvfb-run` is on the PATH now (not when the test was built: installing Xvfb later
/// takes effect without a rebuild).
fn xvfb_run_on_path() -> bool {
    std::env::var_os("PATH").is_some_and(|paths| {
        std::env::split_paths(&paths).any(|dir| dir.join("xvfb-run").is_file())
    })
}

#[test]
fn headless_viewer_renders_the_default_scene_to_a_screenshot() {
    if !xvfb_run_on_path() {
        // CI installs Xvfb: there the window must be tested, not skipped.
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set but xvfb-run is not on the PATH: the window test cannot run"
        );
        eprintln!(
            "skipped: the window test needs xvfb-run (Debian package `xvfb`) on the PATH; .ci/run installs it"
        );
        return;
    }
    let dir = std::env::temp_dir().join(format!("phosphor-viewer-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let shot = dir.join("shot.png");
    let mut cmd = Command::new("xvfb-run");
    cmd.env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .args(["-a", "-s", "-screen 0 800x600x24"])
        .arg(env!("CARGO_BIN_EXE_phosphor-viewer"))
        .args(["--size", "320x180", "--frames", "10", "--screenshot"])
        .arg(&shot);
    let out = run_with_timeout(cmd);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("frames=10 "), "{stdout}");
    // Tagged sRGB, as the window shows it: an sRGB chunk before the image data.
    let bytes = std::fs::read(&shot).expect("screenshot");
    let at = |tag: &[u8]| bytes.windows(4).position(|w| w == tag);
    assert!(at(b"sRGB").zip(at(b"IDAT")).is_some_and(|(s, d)| s < d));
    let img = image::open(&shot).expect("screenshot readable").to_rgb8();
    assert_eq!(img.dimensions(), (320, 180));
    // The default scene's background is dark; objects cover a good part of the view.
    let background = img.get_pixel(2, 2).0;
    let covered = img.pixels().filter(|p| p.0 != background).count();
    assert!(
        covered > 320 * 180 / 3,
        "only {covered} pixels differ from the background"
    );
    let colours = distinct_colours(&img);
    assert!(colours >= 40, "only {colours} distinct colours");
    std::fs::remove_dir_all(&dir).ok();
}
