//! `phosphor` against a hostile environment: full disks, file-size and memory limits,
//! signals, symbolic links, read-only and special files, unwritable stdout and stderr, and
//! inputs that ask for too much (threads, light samples). Nothing is lost, nothing hangs,
//! every failure is one line and a known exit code.

#![allow(clippy::unwrap_used)]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_phosphor")
}

fn phosphor(args: &[&str]) -> Output {
    Command::new(bin())
        .current_dir(root())
        .args(args)
        .output()
        .unwrap()
}

/// `phosphor` under `prlimit` (util-linux) with the given limit, e.g. `--fsize=100`.
fn limited(limit: &str, args: &[&str]) -> Output {
    let probe = Command::new("prlimit").arg("--version").output();
    assert!(
        probe.is_ok(),
        "prlimit (util-linux) is required for the resource-limit tests"
    );
    Command::new("prlimit")
        .arg(limit)
        .arg(bin())
        .current_dir(root())
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("phosphor-out-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Exit `code` and stderr exactly one line, starting `error: ` and containing `needle`.
fn assert_one_error(o: &Output, code: i32, needle: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(code), "stderr: {e}");
    let lines: Vec<&str> = e.lines().collect();
    assert_eq!(lines.len(), 1, "{e}");
    assert!(lines[0].starts_with("error: "), "{e}");
    assert!(lines[0].contains(needle), "{needle} not in: {e}");
}

/// A scene of one small sphere, 6x4 pixels: quick to load and render.
fn tiny_scene(dir: &Path) -> PathBuf {
    let path = dir.join("tiny.toml");
    fs::write(
        &path,
        "[render]\nwidth = 6\nheight = 4\n[[lights]]\ntype = \"point\"\nposition = [0, 2, 2]\nintensity = 1\n[[objects]]\nprimitive = { shape = \"sphere\", radius = 1.0, segments = 8, rings = 4 }\n",
    )
    .unwrap();
    path
}

/// Fills the "disk" (a file-size limit) at byte offsets of the output: every run exits 1 with
/// one line naming the file and the reason, the old file keeps its bytes, and nothing else
/// is left in the folder.
fn limited_writes_keep_the_old_file(ext: &str, stride: usize) {
    let dir = temp(&format!("fsize-{ext}"));
    let scene = tiny_scene(&dir);
    let probe = dir.join(format!("probe.{ext}"));
    let o = phosphor(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        probe.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let size = fs::metadata(&probe).unwrap().len() as usize;
    fs::remove_file(&probe).unwrap();
    let out = dir.join(format!("out.{ext}"));
    fs::write(&out, b"the old picture").unwrap();
    let mut offsets: Vec<usize> = (0..size).step_by(stride).collect();
    offsets.push(size - 1);
    for limit in offsets {
        let o = limited(
            &format!("--fsize={limit}"),
            &[
                "render",
                scene.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ],
        );
        assert_one_error(
            &o,
            1,
            &format!("{}: cannot write: File too large", out.display()),
        );
        assert_eq!(fs::read(&out).unwrap(), b"the old picture", "at {limit}");
        assert_eq!(
            names_in(&dir),
            ["out.".to_owned() + ext, "tiny.toml".to_owned()]
        );
    }
    let o = limited(
        &format!("--fsize={size}"),
        &[
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(fs::metadata(&out).unwrap().len() as usize, size);
}

#[test]
fn a_full_disk_at_every_byte_of_a_png_keeps_the_old_file() {
    limited_writes_keep_the_old_file("png", 1);
}

#[test]
fn a_full_disk_while_writing_an_exr_keeps_the_old_file_and_says_why() {
    limited_writes_keep_the_old_file("exr", 7);
}

/// Sends `signal` to a render while its temporary file exists: the process ends by that
/// signal, the temporary file is gone and the old file keeps its bytes.
fn interrupted_write_leaves_no_temporary_file(signal: &str, number: i32) {
    use std::os::unix::process::ExitStatusExt as _;
    let dir = temp(&format!("signal-{signal}"));
    let out = dir.join("big.exr");
    fs::write(&out, b"the old picture").unwrap();
    let scene = dir.join("empty.toml");
    fs::write(&scene, "[render]\nwidth = 3000\nheight = 3000\n").unwrap();
    // Catch the process while its temporary file exists; retry if it was too quick.
    for _ in 0..5 {
        let mut child = Command::new(bin())
            .args([
                "render",
                scene.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let started = Instant::now();
        let mut caught = false;
        while started.elapsed() < Duration::from_secs(120) {
            if child.try_wait().unwrap().is_some() {
                break;
            }
            if names_in(&dir).iter().any(|n| n.ends_with(".tmp")) {
                // The shell's own `kill`, so no procps package is needed.
                let sent = Command::new("sh")
                    .args(["-c", &format!("kill -{signal} {}", child.id())])
                    .status()
                    .unwrap();
                assert!(sent.success());
                caught = true;
                break;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        let status = child.wait().unwrap();
        if caught {
            assert_eq!(status.signal(), Some(number), "{status:?}");
            assert_eq!(names_in(&dir), ["big.exr", "empty.toml"]);
            assert_eq!(fs::read(&out).unwrap(), b"the old picture");
            return;
        }
        fs::write(&out, b"the old picture").unwrap();
    }
    panic!("the write was never caught in progress");
}

#[test]
fn a_terminated_write_leaves_no_temporary_file() {
    interrupted_write_leaves_no_temporary_file("TERM", 15);
}

#[test]
fn an_interrupted_write_leaves_no_temporary_file() {
    interrupted_write_leaves_no_temporary_file("INT", 2);
}

#[test]
fn a_symbolic_link_is_written_through_and_stays_a_link() {
    let dir = temp("symlink");
    let real = dir.join("real.png");
    fs::write(&real, b"old").unwrap();
    let link = dir.join("link.png");
    std::os::unix::fs::symlink("real.png", &link).unwrap();
    let o = phosphor(&["render", "--size", "16x9", "-o", link.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert!(fs::read(&real).unwrap().starts_with(b"\x89PNG"));
    assert_eq!(names_in(&dir), ["link.png", "real.png"]);
}

#[test]
fn a_read_only_output_is_kept_unless_forced() {
    use std::os::unix::fs::PermissionsExt as _;
    let dir = temp("read-only");
    let out = dir.join("keep.png");
    fs::write(&out, b"precious").unwrap();
    fs::set_permissions(&out, fs::Permissions::from_mode(0o444)).unwrap();
    let o = phosphor(&["render", "--size", "16x9", "-o", out.to_str().unwrap()]);
    assert_one_error(&o, 1, "keep.png: is read-only (--force writes it anyway)");
    assert_eq!(fs::read(&out).unwrap(), b"precious");
    let o = phosphor(&[
        "render",
        "--size",
        "16x9",
        "--force",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(fs::read(&out).unwrap().starts_with(b"\x89PNG"));
    assert_eq!(
        fs::metadata(&out).unwrap().permissions().mode() & 0o777,
        0o444
    );
}

#[test]
fn a_device_is_refused_unless_forced() {
    let o = phosphor(&["render", "--size", "16x9", "-o", "/dev/null"]);
    assert_one_error(
        &o,
        1,
        "/dev/null: is a character device, not a regular file",
    );
    let o = phosphor(&["render", "--size", "16x9", "--force", "-o", "/dev/null"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let dir = temp("folder");
    let o = phosphor(&[
        "render",
        "--size",
        "16x9",
        "--force",
        "-o",
        dir.to_str().unwrap(),
    ]);
    assert_one_error(&o, 1, "is a folder");
}

fn dev_full() -> Stdio {
    Stdio::from(
        fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap(),
    )
}

#[test]
fn stdout_that_cannot_be_written_is_an_error() {
    let o = Command::new(bin())
        .current_dir(root())
        .args(["info", "assets/meshes/bunny_small.obj"])
        .stdout(dev_full())
        .output()
        .unwrap();
    assert_one_error(&o, 1, "stdout: No space left on device");
    let o = Command::new(bin())
        .current_dir(root())
        .args(["render", "--help"])
        .stdout(dev_full())
        .output()
        .unwrap();
    assert_one_error(&o, 1, "stdout");
}

#[test]
fn stderr_that_cannot_be_written_ends_with_status_1_not_a_panic() {
    for args in [
        &["render", "no/such/scene.toml", "-o", "x.png"][..],
        &["render", "--size", "0x0", "-o", "x.png"],
        &["info", "nope.obj"],
    ] {
        let o = Command::new(bin())
            .current_dir(root())
            .args(args)
            .stderr(dev_full())
            .output()
            .unwrap();
        let code = o.status.code();
        assert!(code == Some(1) || code == Some(2), "{args:?}: {code:?}");
    }
}

#[test]
fn every_usage_error_is_one_line_naming_the_flag() {
    for (args, needle) in [
        (&["render"][..], "error: -o/--output: required"),
        (
            &["render", "--size", "0x10", "-o", "x.png"],
            "error: --size: invalid value '0x10': ",
        ),
        (
            &["render", "--size", "big", "-o", "x.png"],
            "error: --size: invalid value 'big'",
        ),
        (
            &["render", "--shading", "shiny", "-o", "x.png"],
            "error: --shading: invalid value 'shiny' (expected flat, gouraud",
        ),
        (
            &["render", "--wat", "-o", "x.png"],
            "error: --wat: unknown argument",
        ),
        (
            &["render", "--threads", "many", "-o", "x.png"],
            "error: --threads: invalid value 'many'",
        ),
        (
            &["render", "a.toml", "--mesh", "b.obj", "-o", "x.png"],
            "error: SCENE.toml: cannot be used with --mesh",
        ),
        (
            &["bench", "--frames", "0"],
            "error: --frames: invalid value '0'",
        ),
        (&["rendr"], "error: rendr: unknown command"),
        (
            &[],
            "error: a command is required: render, accuracy, info, bench, completions, man",
        ),
    ] {
        let o = phosphor(args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert_eq!(e.lines().count(), 1, "{args:?}: {e}");
        assert!(e.starts_with(needle), "{args:?}: {e}");
    }
}

#[test]
fn sample_counts_are_echoed_as_written() {
    let dir = temp("samples");
    let scene = dir.join("s.toml");
    fs::write(
        &scene,
        "[[lights]]\ntype = \"rect\"\ncorner = [0, 2, 0]\nedge_u = [1, 0, 0]\nedge_v = [0, 0, 1]\nintensity = 1\nsamples = 4294967295\n",
    )
    .unwrap();
    let o = phosphor(&["render", scene.to_str().unwrap(), "-o", "/tmp/never.png"]);
    assert_one_error(
        &o,
        1,
        "lights[0].samples: must be in [1, 256], got 4294967295",
    );
}

#[test]
fn warnings_are_one_line_of_at_most_200_characters() {
    let dir = temp("long-warning");
    fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let name = "m".repeat(400);
    let scene = dir.join("s.toml");
    fs::write(
        &scene,
        format!("[materials.{name}]\nbump = {{ procedural = \"bumps\" }}\n[[objects]]\nmesh = \"tri.obj\"\nmaterial = \"{name}\"\n"),
    )
    .unwrap();
    let out = dir.join("o.png");
    let o = phosphor(&[
        "render",
        scene.to_str().unwrap(),
        "--size",
        "8x8",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    let warnings: Vec<&str> = e.lines().filter(|l| l.starts_with("warning: ")).collect();
    assert!(!warnings.is_empty(), "{e}");
    for w in warnings {
        assert!(
            w.chars().count() <= 200,
            "{} characters: {w}",
            w.chars().count()
        );
    }
}

#[test]
fn thread_counts_are_capped_with_a_warning() {
    let dir = temp("threads");
    let out = dir.join("t.png");
    let o = phosphor(&[
        "render",
        "--size",
        "64x64",
        "--threads",
        "5000",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.lines()
            .any(|l| l.starts_with("warning: --threads: 5000 is more than 4 per core")),
        "{e}"
    );
}

#[test]
fn distributed_light_samples_over_the_budget_are_cut_with_a_warning() {
    let dir = temp("budget");
    let mut text = String::from("[[objects]]\nprimitive = { shape = \"plane\" }\n");
    for _ in 0..8 {
        text.push_str("[[lights]]\ntype = \"rect\"\ncorner = [0, 2, 0]\nedge_u = [1, 0, 0]\nedge_v = [0, 0, 1]\nintensity = 1\nsamples = 256\n");
    }
    let scene = dir.join("rects.toml");
    fs::write(&scene, text).unwrap();
    let out = dir.join("r.png");
    let o = phosphor(&[
        "render",
        scene.to_str().unwrap(),
        "--size",
        "32x24",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.lines().any(|l| l.starts_with("warning: ")
            && l.contains("rects.toml: lights[0].samples: 256 cut to")),
        "{e}"
    );
}

#[test]
fn an_image_too_large_for_the_memory_limit_is_an_error_before_allocation() {
    let dir = temp("memory");
    let out = dir.join("big.exr");
    let o = limited(
        "--as=3000000000",
        &[
            "render",
            "--size",
            "16384x16384",
            "-o",
            out.to_str().unwrap(),
        ],
    );
    assert_one_error(&o, 1, "--size: 16384x16384 needs 4.4 GB of memory");
    assert!(names_in(&dir).is_empty());
}

/// The data of the first PNG chunk of type `kind`.
fn chunk<'a>(bytes: &'a [u8], kind: &[u8]) -> Option<&'a [u8]> {
    let mut at = 8;
    while at + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        if &bytes[at + 4..at + 8] == kind {
            return Some(&bytes[at + 8..at + 8 + len]);
        }
        at += 12 + len;
    }
    None
}

#[test]
fn pngs_are_tagged_with_their_encoding() {
    let dir = temp("tags");
    let srgb = dir.join("srgb.png");
    let o = phosphor(&["render", "--size", "16x9", "-o", srgb.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = fs::read(&srgb).unwrap();
    assert!(chunk(&bytes, b"sRGB").is_some());
    assert_eq!(chunk(&bytes, b"cICP"), Some(&[1u8, 13, 0, 1][..]));
    // S1 is linear: gamma 1.0, no sRGB chunk.
    let linear = dir.join("s1.png");
    let o = phosphor(&[
        "render",
        "--mesh",
        "assets/meshes/bunny_small.obj",
        "--size",
        "16x9",
        "-o",
        linear.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = fs::read(&linear).unwrap();
    assert!(chunk(&bytes, b"sRGB").is_none());
    assert_eq!(chunk(&bytes, b"gAMA"), Some(&100_000u32.to_be_bytes()[..]));
    assert_eq!(chunk(&bytes, b"cICP"), Some(&[1u8, 8, 0, 1][..]));
}

#[test]
fn the_closing_line_gives_the_whole_time_and_the_renders_share() {
    let dir = temp("timing");
    let out = dir.join("t.png");
    let o = phosphor(&["render", "--size", "32x18", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    let line = s.lines().find(|l| l.starts_with("rendered ")).unwrap();
    let (head, _) = line.split_once("): ").unwrap();
    let numbers: Vec<f64> = head
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .filter_map(|t| t.parse().ok())
        .collect();
    // rendered OUT in TOTAL ms (load L ms, render R ms = P%, save S ms)
    assert!(
        head.contains(" ms (load ") && head.contains(", render ") && head.contains("%, save "),
        "{line}"
    );
    let n = numbers.len();
    let (total, load, render, share, save) = (
        numbers[n - 5],
        numbers[n - 4],
        numbers[n - 3],
        numbers[n - 2],
        numbers[n - 1],
    );
    assert!(load + render + save <= total + 0.2, "{line}");
    assert!((share - 100.0 * render / total).abs() <= 1.0, "{line}");
}
