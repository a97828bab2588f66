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

/// Reads `from` on a thread into a shared string, for polling a running process's output.
fn collect(
    mut from: impl std::io::Read + Send + 'static,
) -> std::sync::Arc<std::sync::Mutex<String>> {
    let text = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
    let into = text.clone();
    std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = from.read(&mut buf) {
            if n == 0 {
                break;
            }
            into.lock()
                .expect("lock")
                .push_str(&String::from_utf8_lossy(&buf[..n]));
        }
    });
    text
}

/// Waits until `text` contains `what` `count` times, or [`TIMEOUT`] passes.
fn wait_for(text: &std::sync::Mutex<String>, what: &str, count: usize) -> bool {
    wait_for_within(text, what, count, TIMEOUT)
}

/// Kills the child when dropped, so that a failed assertion leaves no process behind.
struct Killed(std::process::Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn a_scene_saved_while_the_window_is_open_is_loaded_again() {
    let on_path = |exe: &str| {
        std::env::var_os("PATH")
            .is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join(exe).is_file()))
    };
    if !on_path("Xvfb") {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set but Xvfb is not on the PATH: the live-reload test cannot run"
        );
        eprintln!("skipped: the live-reload test needs Xvfb (Debian package `xvfb`) on the PATH");
        return;
    }
    let dir = std::env::temp_dir().join(format!("phosphor-viewer-reload-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let scene = dir.join("live.toml");
    let sphere = |kd: &str| {
        format!(
            "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nintensity = 1\n\
             [materials.m]\nkd = {kd}\n[[objects]]\nname = \"ball\"\nmaterial = \"m\"\n\
             primitive = {{ shape = \"sphere\", radius = 1.0, segments = 16, rings = 8 }}\n"
        )
    };
    std::fs::write(&scene, sphere("[0.9, 0, 0]")).expect("scene");
    // An X server of our own, on a display it picks (`-displayfd`), killed at the end.
    let mut xvfb = Command::new("Xvfb");
    xvfb.args([
        "-displayfd",
        "1",
        "-screen",
        "0",
        "640x480x24",
        "-nolisten",
        "tcp",
    ])
    .stdout(Stdio::piped())
    .stderr(Stdio::null());
    let mut xvfb = Killed(xvfb.spawn().expect("Xvfb"));
    let display = collect(xvfb.0.stdout.take().expect("Xvfb's stdout"));
    assert!(wait_for(&display, "\n", 1), "Xvfb gave no display number");
    let display = format!(":{}", display.lock().expect("lock").trim());
    let mut cmd = viewer();
    cmd.env("DISPLAY", &display)
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .args(["--size", "160x120"])
        .arg(&scene)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = Killed(cmd.spawn().expect("spawn"));
    let out = collect(child.0.stdout.take().expect("stdout"));
    let err = collect(child.0.stderr.take().expect("stderr"));
    // The key list is printed just before the window opens and the watch starts.
    assert!(wait_for(&out, "quit", 1), "{}", err.lock().expect("lock"));
    let saves = |kd: &str, what: &str, count: usize| {
        // A save every second until the viewer answers: the first may come before the watch.
        let started = Instant::now();
        while started.elapsed() < TIMEOUT {
            std::fs::write(&scene, sphere(kd)).expect("save");
            if wait_for_within(&err, what, count, Duration::from_secs(1)) {
                return true;
            }
        }
        false
    };
    assert!(
        saves("[0, 0, 0.9]", "reloaded", 1),
        "{}",
        err.lock().expect("lock")
    );
    // A broken save: the error is said, and the viewer keeps running.
    assert!(
        saves("[0, 0]", "reload failed", 1),
        "{}",
        err.lock().expect("lock")
    );
    assert!(
        child.0.try_wait().expect("wait").is_none(),
        "the viewer exited"
    );
    let said = err.lock().expect("lock").clone();
    assert!(said.contains("live.toml") && said.contains("kd"), "{said}");
    drop(child);
    drop(xvfb);
    std::fs::remove_dir_all(&dir).ok();
}

/// [`wait_for`] giving up after `limit`.
fn wait_for_within(
    text: &std::sync::Mutex<String>,
    what: &str,
    count: usize,
    limit: Duration,
) -> bool {
    let started = Instant::now();
    while started.elapsed() < limit {
        if text.lock().expect("lock").matches(what).count() >= count {
            return true;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    false
}
