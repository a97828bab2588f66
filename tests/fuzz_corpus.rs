//! Replays the fuzz corpus (`fuzz/corpus/obj_loader/`, inputs kept from fuzzing runs and
//! hand-made hard cases) through the OBJ loader as an ordinary test, so CI checks every input
//! the fuzzer once found interesting without needing cargo-fuzz or a nightly toolchain.
//!
//! Each file must give a consistent mesh or an error whose message starts with the file's
//! name, and must never panic. The scene loader's corpus (`fuzz/corpus/scene_loader/`) is
//! replayed the same way: a scene that renders finite pixels, or an error naming the file.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use phosphor::mesh::{NormalOptions, load_obj, parse_obj};
use phosphor::raster::Framebuffer;
use phosphor::scene::{FrameOptions, Scene, render_frame};

fn corpus(target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/corpus")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
}

/// What the fuzz target does with one input: `parse_obj` on the bytes as text (lossy for
/// invalid UTF-8, as the target does), under the default and S1 normal options.
fn check_parse(bytes: &[u8], name: &str) {
    let text = String::from_utf8_lossy(bytes);
    for opts in [NormalOptions::default(), NormalOptions::s1()] {
        match parse_obj(&text, name, None, &opts) {
            Ok(mesh) => {
                assert!(mesh.is_consistent(), "{name}: inconsistent mesh");
                assert!(!mesh.indices.is_empty(), "{name}: Ok without faces");
                assert!(
                    mesh.positions.iter().all(|p| p.is_finite())
                        && mesh.normals.iter().all(|n| n.is_finite()),
                    "{name}: non-finite vertex data"
                );
            }
            Err(e) => {
                let msg = e.to_string();
                assert!(
                    msg.starts_with(&format!("{name}:")),
                    "{name}: message {msg:?}"
                );
                assert!(!msg.contains('\n'), "{name}: message spans lines: {msg:?}");
            }
        }
    }
}

#[test]
fn every_obj_corpus_file_parses_or_fails_with_a_message_naming_it() {
    let files = corpus("obj_loader");
    assert!(files.len() >= 10, "the corpus went missing: {files:?}");
    for path in files {
        let bytes = std::fs::read(&path).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        check_parse(&bytes, &name);
        // And from disk, where invalid UTF-8 is an error naming the file and line.
        let shown = path.display().to_string();
        if let Err(e) = load_obj(&path, &NormalOptions::default()) {
            assert!(e.to_string().starts_with(&format!("{shown}:")), "{e}");
        }
    }
}

#[test]
fn every_scene_corpus_file_loads_and_renders_or_fails_with_a_message_naming_it() {
    let files = corpus("scene_loader");
    assert!(files.len() >= 10, "the corpus went missing: {files:?}");
    let mut loaded = 0;
    for path in files {
        let bytes = std::fs::read(&path).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        // As the fuzz target does: lossy text, relative paths against the working folder.
        match Scene::parse(&String::from_utf8_lossy(&bytes), &name) {
            Err(e) => {
                let msg = e.to_string();
                assert!(msg.starts_with(&name), "{name}: message {msg:?}");
                assert!(!msg.contains('\n'), "{name}: message spans lines: {msg:?}");
            }
            Ok(scene) => {
                loaded += 1;
                let mut fb = Framebuffer::new(16, 12).unwrap();
                let opts = FrameOptions {
                    threads: 1,
                    ..FrameOptions::default()
                };
                render_frame(&scene, &mut fb, &opts);
                assert!(
                    fb.color()
                        .iter()
                        .all(|c| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0),
                    "{name}: pixels out of range"
                );
            }
        }
    }
    assert!(
        loaded >= 3,
        "the corpus should hold scenes that load, not only errors"
    );
}
