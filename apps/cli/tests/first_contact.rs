//! What a new user meets first: output folders made on demand (and never left empty), the
//! slips of a first session (a PNG for a terminal, `--frames` alone, a file that is no mesh),
//! the standard views and the orthographic camera from the command line, and the shell
//! completions and manual page.

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
    let d = std::env::temp_dir().join(format!("phosphor-first-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Exit `code` and one `error:` line starting with `start`.
fn assert_error(o: &Output, code: i32, start: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(e.starts_with(start), "{e}");
}

#[test]
fn render_makes_missing_output_folders_for_stills_and_sequences() {
    let d = temp("folders");
    let still = d.join("a/b/still.png");
    let o = phosphor(&["render", "--size", "32x18", "-o", still.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(still.is_file());
    let frames = d.join("seq/deeper/frame_%02d.png");
    let o = phosphor(&[
        "render",
        "--size",
        "32x18",
        "--turntable",
        "3",
        "-o",
        frames.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for k in 0..3 {
        assert!(d.join(format!("seq/deeper/frame_{k:02}.png")).is_file());
    }
}

#[test]
fn a_render_that_fails_before_writing_leaves_no_folder_behind() {
    let d = temp("no-folders");
    let missing_scene = d.join("missing.toml");
    let out = d.join("made/not/x.png");
    let o = phosphor(&[
        "render",
        missing_scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(!d.join("made").exists(), "a folder was left behind");
    // A bad extension is refused before anything, and a file in the way is named.
    let o = phosphor(&["render", "-o", d.join("made/x.jpg").to_str().unwrap()]);
    assert_error(&o, 2, "error: ");
    assert!(stderr(&o).contains(".png or .exr"), "{}", stderr(&o));
    std::fs::write(d.join("plain"), b"x").unwrap();
    let o = phosphor(&["render", "-o", d.join("plain/x.png").to_str().unwrap()]);
    assert_error(&o, 1, "error: ");
    assert!(
        stderr(&o).contains("plain is not a folder"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1, "only `plain`");
}

#[test]
fn frames_without_turntable_says_to_add_it() {
    let o = phosphor(&["render", "--frames", "2", "-o", "x.png"]);
    assert_error(
        &o,
        2,
        "error: --frames 2: picks frames of a turntable; add --turntable N",
    );
}

#[test]
fn a_file_that_is_not_a_mesh_is_an_unknown_extension() {
    let o = phosphor(&[
        "render",
        "--mesh",
        "assets/meshes/SOURCES.md",
        "-o",
        "x.png",
    ]);
    assert_error(
        &o,
        2,
        "error: --mesh: assets/meshes/SOURCES.md: unknown extension `.md`",
    );
    let o = phosphor(&["info", "assets/meshes/SOURCES.md"]);
    assert_error(&o, 2, "error: assets/meshes/SOURCES.md: unknown extension");
}

#[test]
fn png_to_standard_output_refuses_a_terminal() {
    // `script` (util-linux) gives the command a terminal as stdout; without it, say so.
    let Ok(probe) = Command::new("script").arg("--version").output() else {
        eprintln!("skipped: `script` (util-linux) is not installed");
        return;
    };
    assert!(probe.status.success());
    let command = format!(
        "{} render --size 8x8 -o - ; echo \"exit=$?\"",
        env!("CARGO_BIN_EXE_phosphor")
    );
    let o = Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .current_dir(root())
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("error: -o -: standard output is a terminal;"),
        "{text}"
    );
    assert!(text.contains("exit=2"), "{text}");
    let signature = b"\x89PNG";
    assert!(
        !o.stdout.windows(4).any(|w| w == signature),
        "image bytes reached the terminal: {text}"
    );
}

#[test]
fn standard_views_and_ortho_render_from_the_command_line() {
    let d = temp("views");
    let shot = |name: &str, extra: &[&str]| -> Vec<u8> {
        let out = d.join(name);
        let mut args = vec![
            "render",
            "--mesh",
            "assets/meshes/cube.obj",
            "--size",
            "48x48",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = phosphor(&args);
        assert!(o.status.success(), "{extra:?}: {}", stderr(&o));
        std::fs::read(&out).unwrap()
    };
    let front = shot("front.png", &["--view", "front"]);
    let top = shot("top.png", &["--view", "top"]);
    let front_ortho = shot("front-ortho.png", &["--view", "front", "--ortho"]);
    assert_ne!(front, top);
    assert_ne!(front, front_ortho);
    // The default (perspective, --mesh framing) is what it was without the new flags.
    assert_eq!(shot("plain.png", &[]), shot("plain-again.png", &[]));
    let o = phosphor(&["render", "--view", "side", "-o", "x.png"]);
    assert_error(&o, 2, "error: --view: invalid value 'side'");
    let o = phosphor(&["render", "--view", "top", "--eye", "1,2,3", "-o", "x.png"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn completions_and_the_manual_page_name_the_subcommands() {
    for shell in ["bash", "zsh", "fish", "powershell"] {
        let o = phosphor(&["completions", shell]);
        assert!(o.status.success(), "{shell}: {}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains("render"), "{shell}: {text}");
        assert!(text.len() > 1000, "{shell}: {} bytes", text.len());
    }
    let o = phosphor(&["man"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = String::from_utf8_lossy(&o.stdout);
    assert!(
        page.contains(".TH phosphor") && page.contains("render"),
        "{page}"
    );
    let o = phosphor(&["completions", "tcsh"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}
