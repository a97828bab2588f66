//! `phosphor` end to end for `--aa`: anti-aliased pictures, the plan naming the samples, and
//! one-line errors for bad names and sample images over the largest side.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn phosphor(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_phosphor"))
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("phosphor-aa-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Renders S1 at 96x54 with `aa` to a PNG and returns its bytes.
fn render(dir: &Path, aa: &str, threads: &str) -> Vec<u8> {
    let out = dir.join(format!("{aa}-{threads}.png"));
    let o = phosphor(&[
        "render",
        "assets/scenes/s1.toml",
        "--size",
        "96x54",
        "--aa",
        aa,
        "--threads",
        threads,
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{aa}: {}", stderr(&o));
    let said = String::from_utf8_lossy(&o.stdout);
    let counted = match aa {
        "off" => "pixels shaded",
        "msaa4" | "msaa16" => "pixel-triangle pairs shaded",
        _ => "samples shaded",
    };
    assert!(said.contains(counted), "{said}");
    std::fs::read(&out).unwrap()
}

#[test]
fn anti_aliased_renders_differ_from_off_and_not_between_thread_counts() {
    let dir = temp("render");
    let off = render(&dir, "off", "1");
    let four = render(&dir, "ssaa4", "1");
    assert_ne!(off, four);
    assert_eq!(four, render(&dir, "ssaa4", "2"));
    assert_ne!(four, render(&dir, "ssaa16", "2"));
    // (At 96x54 the bunny's triangles are smaller than a pixel, so msaa4 may equal ssaa4.)
    let multi = render(&dir, "msaa4", "1");
    assert_ne!(multi, off);
    assert_eq!(multi, render(&dir, "msaa4", "2"));
}

#[test]
fn the_plan_names_the_samples_per_pixel() {
    let o = phosphor(&["render", "--plan", "--size", "32x18", "--aa", "ssaa16"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("anti-aliasing: ssaa16, 16 samples per pixel"),
        "{text}"
    );
}

#[test]
fn bad_anti_aliasing_is_one_usage_line_naming_the_flag() {
    for (args, needle) in [
        (
            vec!["render", "--plan", "--aa", "msaa8"],
            "expected off, msaa4, ssaa4, msaa16 or ssaa16",
        ),
        (
            vec!["render", "--plan", "--aa", "ssaa16", "--size", "9000x100"],
            "ssaa16 at 9000x100 draws 36000x400 samples",
        ),
    ] {
        let o = phosphor(&args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(e.starts_with("error: ") && e.contains("--aa"), "{e}");
        assert!(e.contains(needle), "{e}");
    }
}
