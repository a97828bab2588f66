//! `phosphor` against the cases of a hostile-input campaign (issue 34): counts that would be
//! allocated before the output is checked, outputs that are found bad only after the render,
//! `/dev/stdout` to a pipe, FIFOs and escaping glTF buffers, terminal control in a file, and
//! camera values echoed as they were typed.

#![allow(clippy::unwrap_used)]

use std::fs;
use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

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

/// Runs `phosphor` with `args`; `None` if it has not ended within 60 s (it is then killed).
fn phosphor_or_hang(args: &[&str]) -> Option<Output> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_phosphor"))
        .current_dir(root())
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while started.elapsed() < Duration::from_secs(60) {
        if child.try_wait().unwrap().is_some() {
            return Some(child.wait_with_output().unwrap());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    None
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("phosphor-hostile-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
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

#[test]
fn four_billion_turntable_frames_are_a_usage_error_without_a_frame_list() {
    let o = phosphor(&[
        "render",
        "assets/scenes/s1.toml",
        "--turntable",
        "4294967295",
        "-o",
        "x.png",
    ]);
    assert_one_error(
        &o,
        2,
        "4294967295 frames are written: the name needs a frame number",
    );
}

#[test]
fn stdout_through_a_pipe_takes_the_image_and_nothing_else() {
    let o = phosphor(&["render", "--size", "16x9", "-o", "/dev/stdout", "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stdout.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");
    assert!(o.stdout.ends_with(b"IEND\xaeB`\x82"), "more than the PNG");
    assert!(
        stderr(&o).contains("rendered /dev/stdout"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn an_output_folder_that_cannot_take_a_file_is_refused_before_the_scene_is_read() {
    // The scene does not exist: an error about it would mean the output was checked after.
    let o = phosphor(&["render", "missing-scene.toml", "-o", "/proc/x.png"]);
    assert_one_error(
        &o,
        1,
        "/proc/x.png: cannot write: cannot create a temporary file in /proc",
    );
    // Missing folders are made after the render, so the folder they would be made in must
    // take a file now.
    let o = phosphor(&[
        "render",
        "missing-scene.toml",
        "--turntable",
        "2",
        "-o",
        "/proc/no/such/frame_%04d.png",
    ]);
    assert_one_error(
        &o,
        1,
        "cannot make folder /proc/no: /proc takes no new entry",
    );
}

#[test]
fn a_long_output_name_the_file_system_takes_is_written() {
    let dir = temp("long-name");
    let out = dir.join(format!("{}.png", "n".repeat(240)));
    let o = phosphor(&["render", "--size", "16x9", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.is_file());
    let _ = fs::remove_dir_all(&dir);
}

#[cfg(unix)]
#[test]
fn fifo_as_mesh_is_an_error_not_a_hang() {
    let dir = temp("fifo");
    let fifo = dir.join("pipe.stl");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    for args in [
        vec!["info", fifo.to_str().unwrap()],
        vec!["render", "--mesh", fifo.to_str().unwrap(), "--plan"],
    ] {
        let o = phosphor_or_hang(&args).expect("a FIFO must not block phosphor");
        assert_one_error(&o, 1, "a FIFO, not a regular file");
    }
    let _ = fs::remove_dir_all(&dir);
}

/// A glTF triangle in `dir/model/`, its buffer `../tri.bin` one folder up.
fn gltf_with_shared_buffer(dir: &Path) -> PathBuf {
    fs::create_dir_all(dir.join("model")).unwrap();
    let bin: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    fs::write(dir.join("tri.bin"), bin).unwrap();
    let gltf = dir.join("model/tri.gltf");
    fs::write(
        &gltf,
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],\
         \"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],\
         \"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\
         \"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]}],\
         \"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\
         \"buffers\":[{\"byteLength\":36,\"uri\":\"../tri.bin\"}]}",
    )
    .unwrap();
    gltf
}

#[test]
fn a_gltf_buffer_outside_its_folder_needs_allow_outside_assets() {
    let dir = temp("outside");
    let gltf = gltf_with_shared_buffer(&dir);
    let o = phosphor(&["info", gltf.to_str().unwrap()]);
    assert_one_error(&o, 1, "leads outside the glTF file's folder");
    let o = phosphor(&["info", "--allow-outside-assets", gltf.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("triangles:        1"));
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn terminal_control_from_a_file_never_reaches_the_terminal() {
    let dir = temp("control");
    let ply = dir.join("t.ply");
    fs::write(
        &ply,
        "ply\nformat ascii 1.0\n\u{1b}[2J \u{1b}[31m\nend_header\n",
    )
    .unwrap();
    let o = phosphor(&["info", ply.to_str().unwrap()]);
    assert_one_error(&o, 1, "\\e[2J \\e[31m");
    assert!(!o.stderr.contains(&0x1b), "{:?}", stderr(&o));
    // A file name holding one too.
    let named = dir.join("bad\u{1b}[2Jname.stl");
    fs::write(&named, b"").unwrap();
    let o = phosphor(&["info", named.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(!o.stderr.contains(&0x1b), "{:?}", stderr(&o));
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn camera_values_are_echoed_as_typed_and_a_far_eye_is_named() {
    let o = phosphor(&["render", "--elevation", "89.9999999", "-o", "x.png"]);
    assert_one_error(
        &o,
        2,
        "--elevation: must be between -90 and 90 (exclusive), got 89.9999999 (90 in single precision)",
    );
    let o = phosphor(&[
        "render",
        "assets/scenes/s1.toml",
        "--eye",
        "1e20,0,0",
        "--plan",
    ]);
    assert_one_error(
        &o,
        2,
        "--eye: puts the eye at 1e20,0,0, 1e20 from the target",
    );
    assert!(!stderr(&o).contains("(-0,0,0)"), "{}", stderr(&o));
}

#[test]
fn a_killed_writers_temporary_file_is_removed_by_the_next_render() {
    let dir = temp("stale");
    let mut child = Command::new("true").spawn().unwrap();
    child.wait().unwrap();
    let stale = dir.join(format!(".big.exr.{}.aB3xYz.tmp", child.id()));
    let f = fs::File::create(&stale).unwrap();
    f.set_modified(std::time::SystemTime::now() - Duration::from_secs(3600))
        .unwrap();
    drop(f);
    let out = dir.join("out.png");
    let o = phosphor(&["render", "--size", "16x9", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stale.exists(), "the dead writer's file is still there");
    let mut names: Vec<String> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["out.png"]);
    let mut bytes = Vec::new();
    fs::File::open(&out)
        .unwrap()
        .read_to_end(&mut bytes)
        .unwrap();
    assert!(bytes.starts_with(b"\x89PNG"));
    let _ = fs::remove_dir_all(&dir);
}
