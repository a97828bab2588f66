//! Where the `S` key's screenshots go. (The camera and normal flags the viewer shares with
//! `phosphor render` are in `phosphor_args`.)

use std::path::{Path, PathBuf};

/// Where the `S` key saves its next screenshot: beside the scene file (in the current folder for
/// `--mesh` and the embedded scene), named after the scene or mesh, `NAME-001.png`, then
/// `-002`, ..., never over an existing file. `None` only when 999 of them already exist.
#[must_use]
pub fn screenshot_path(scene_file: Option<&Path>, mesh: Option<&Path>) -> Option<PathBuf> {
    let (dir, stem) = match (scene_file, mesh) {
        (Some(f), _) => (
            f.parent().map(Path::to_path_buf).unwrap_or_default(),
            f.file_stem(),
        ),
        (None, Some(m)) => (PathBuf::new(), m.file_stem()),
        (None, None) => (PathBuf::new(), None),
    };
    let stem = stem.map_or_else(
        || "phosphor".to_owned(),
        |s| s.to_string_lossy().into_owned(),
    );
    (1..=999)
        .map(|n| dir.join(format!("{stem}-{n:03}.png")))
        .find(|p| !p.exists())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn screenshots_go_beside_the_scene_and_never_overwrite() {
        let dir =
            std::env::temp_dir().join(format!("phosphor-viewer-shots-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("room.toml");
        let first = screenshot_path(Some(&scene), None).unwrap();
        assert_eq!(first, dir.join("room-001.png"));
        std::fs::write(&first, b"taken").unwrap();
        assert_eq!(
            screenshot_path(Some(&scene), None).unwrap(),
            dir.join("room-002.png")
        );
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(
            screenshot_path(None, Some(Path::new("assets/meshes/nonexistent-cube.obj"))),
            Some(PathBuf::from("nonexistent-cube-001.png"))
        );
    }
}
