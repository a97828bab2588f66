//! README's examples run as written: every `phosphor ...` line of README's `sh` blocks (with
//! its continuation lines, pipes and redirections) runs through `sh` in a fresh folder holding
//! a copy of `assets/`, against the binary built here, and must exit 0 without an error line.
//! Lines for `phosphor-viewer` need a display: README marks them `# needs a display`, and
//! they are skipped (an unmarked one fails this test, so that none is skipped by accident).

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The marker README puts on an example that opens a window.
const NEEDS_DISPLAY: &str = "# needs a display";

/// The commands of README's `sh` blocks, continuation lines joined.
fn sh_commands(readme: &str) -> Vec<String> {
    let mut commands = Vec::new();
    let mut in_sh = false;
    let mut pending = String::new();
    for line in readme.lines() {
        let t = line.trim();
        if t.starts_with("```") {
            in_sh = !in_sh && t == "```sh";
            continue;
        }
        if !in_sh || (pending.is_empty() && (t.is_empty() || t.starts_with('#'))) {
            continue;
        }
        match t.strip_suffix('\\') {
            Some(part) => {
                pending.push_str(part.trim_end());
                pending.push(' ');
            }
            None => {
                pending.push_str(t);
                commands.push(std::mem::take(&mut pending));
            }
        }
    }
    commands
}

/// Copies the folder `from` into `to`, recursively.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap();
        }
    }
}

#[test]
fn every_phosphor_example_in_the_readme_runs_as_written() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let dir = std::env::temp_dir().join(format!("phosphor-readme-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    copy_dir(&root().join("assets"), &dir.join("assets"));
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_phosphor"));
    let path = std::env::join_paths(std::iter::once(bin.parent().unwrap().to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .unwrap();
    let (mut ran, mut skipped) = (Vec::new(), Vec::new());
    for command in sh_commands(&readme) {
        if command.starts_with("phosphor-viewer") {
            assert!(
                command.contains(NEEDS_DISPLAY),
                "README example opens a window but is not marked `{NEEDS_DISPLAY}`: {command}"
            );
            skipped.push(command);
            continue;
        }
        let runs_phosphor = command.starts_with("phosphor ") || command.contains("| xargs");
        if !runs_phosphor {
            continue; // cargo, the benchmark scripts
        }
        let out = Command::new("sh")
            .args(["-c", &command])
            .current_dir(&dir)
            .env("PATH", &path)
            .env("HOME", &dir)
            .env("SLURM_ARRAY_TASK_ID", "1")
            .env("JOB_COMPLETION_INDEX", "2")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "`{command}` failed: {stderr}");
        assert!(!stderr.contains("error:"), "`{command}`: {stderr}");
        ran.push(command);
    }
    assert!(
        ran.len() >= 15,
        "only {} examples found: {ran:?}",
        ran.len()
    );
    assert!(!skipped.is_empty(), "the viewer examples were not seen");
    // What the sequence examples promise: the folder made, the frames named by number.
    assert!(dir.join("out/frame_0000.png").is_file());
    assert!(dir.join("out/frame_0035.png").is_file());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sh_blocks_are_split_into_commands_with_their_continuations() {
    let text = "intro `phosphor no`\n```sh\n# a comment\nphosphor a \\\n    --b c   # d\n\nphosphor e\n```\n```toml\nphosphor f\n```\n";
    assert_eq!(
        sh_commands(text),
        vec!["phosphor a --b c   # d".to_owned(), "phosphor e".to_owned()]
    );
}
