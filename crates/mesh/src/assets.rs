//! The files a mesh names (a glTF file's buffers and images), kept inside the mesh's own
//! folder.
//!
//! A glTF file downloaded with its `.bin` beside it must not make the reader open
//! `../../../../etc/passwd` or `~/.ssh/id_ed25519` through a planted symbolic link, and show
//! their bytes as a triangle's bounds. So a relative URI is resolved against the folder of
//! the glTF file, `..` steps and symbolic links followed, and the file it reaches must lie in
//! that folder or below (`confine_uri`). Absolute paths and URIs with a scheme are refused
//! before this (see the glTF reader). A folder tree that links to shared assets elsewhere can
//! still be read: an application lets it with [`allow_outside_assets`] (`phosphor
//! --allow-outside-assets`).

use std::io;
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use crate::open::{MAX_MESH_FILE_BYTES, read_file};

/// Whether files outside a mesh's folder may be read: set once by an application from its
/// command line, read by every asset load of the process.
static ALLOW_OUTSIDE: AtomicBool = AtomicBool::new(false);

/// Lets (or stops) the files a mesh names lie outside the mesh's folder, for this process:
/// what `--allow-outside-assets` does. Off unless an application turns it on.
pub fn allow_outside_assets(allow: bool) {
    ALLOW_OUTSIDE.store(allow, Ordering::Relaxed);
}

/// Whether [`allow_outside_assets`] is on.
#[must_use]
pub fn outside_assets_allowed() -> bool {
    ALLOW_OUTSIDE.load(Ordering::Relaxed)
}

/// The folder holding `path` (`.` for a bare name).
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The file that `uri` (a relative path, `%`-escapes already decoded) names for the glTF file
/// `gltf`: the glTF's folder joined with `uri`, which must stay in that folder or below,
/// lexically (no `..` above it) and once symbolic links are resolved. With `allow_outside`
/// any relative path is taken as it is. A file that does not exist is returned unresolved,
/// for the read to report.
///
/// # Errors
/// What is wrong, for the caller to prefix with the URI it quotes: it is absolute, or it
/// leads outside the folder.
pub(crate) fn confine_uri(gltf: &Path, uri: &str, allow_outside: bool) -> Result<PathBuf, String> {
    let relative = Path::new(uri);
    if relative.has_root() || relative.is_absolute() {
        return Err("is an absolute path".to_owned());
    }
    let folder = folder_of(gltf);
    let joined = folder.join(relative);
    if allow_outside {
        return Ok(joined);
    }
    let outside =
        || "leads outside the glTF file's folder (allowed with --allow-outside-assets)".to_owned();
    let mut depth = 0usize;
    for part in relative.components() {
        match part {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir => depth = depth.checked_sub(1).ok_or_else(outside)?,
            Component::RootDir | Component::Prefix(_) => return Err(outside()),
        }
    }
    // Symbolic links: compare where the folder and the file really are.
    let (Ok(real_folder), Ok(real_file)) = (folder.canonicalize(), joined.canonicalize()) else {
        return Ok(joined);
    };
    if !real_file.starts_with(&real_folder) {
        return Err(outside());
    }
    Ok(real_file)
}

/// The file `rel` (a relative URI, `%`-escapes decoded) that the mesh file `mesh` names:
/// confined to the mesh's folder unless [`allow_outside_assets`] is on (`confine_uri`). The
/// one place a glTF file's buffer and image URIs become paths: a buffer is then read by
/// [`read_asset`], an image later through
/// [`TextureSource::bytes`](crate::texture_ref::TextureSource::bytes).
///
/// # Errors
/// The refusal (`PermissionDenied`): the path is absolute, or leads outside the folder.
pub fn asset_path(mesh: &Path, rel: &str) -> io::Result<PathBuf> {
    confine_uri(mesh, rel, outside_assets_allowed())
        .map_err(|why| io::Error::new(io::ErrorKind::PermissionDenied, why))
}

/// The bytes of the file `rel` that the mesh file `mesh` names (a glTF buffer's URI): the file
/// [`asset_path`] confines, a regular file of at most [`MAX_MESH_FILE_BYTES`], opened without
/// blocking ([`crate::open::read_file`]).
///
/// # Errors
/// The refusal of [`asset_path`], or the read's error.
pub fn read_asset(mesh: &Path, rel: &str) -> io::Result<Vec<u8>> {
    read_file(&asset_path(mesh, rel)?, MAX_MESH_FILE_BYTES)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_escapes_are_refused_and_allowed_with_the_flag() {
        let gltf = Path::new("assets/meshes/a.gltf");
        let e = confine_uri(gltf, "../../../../../../../../etc/passwd", false).expect_err("escape");
        assert!(e.contains("outside the glTF file's folder"), "{e}");
        assert!(confine_uri(gltf, "sub/../../a.bin", false).is_err());
        assert_eq!(
            confine_uri(gltf, "../common.bin", true),
            Ok(PathBuf::from("assets/meshes/../common.bin"))
        );
        assert!(confine_uri(gltf, "/etc/passwd", true).is_err());
        // Inside, through `..` that stays inside: accepted (missing, so unresolved).
        assert_eq!(
            confine_uri(gltf, "sub/../b.bin", false),
            Ok(PathBuf::from("assets/meshes/sub/../b.bin"))
        );
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_out_of_the_folder_is_refused() {
        let dir = std::env::temp_dir().join(format!("phosphor-assets-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("model")).expect("dir");
        std::fs::write(dir.join("secret"), b"secret").expect("write");
        std::fs::write(dir.join("model/ok.bin"), b"ok").expect("write");
        std::os::unix::fs::symlink("../secret", dir.join("model/link.bin")).expect("link");
        let gltf = dir.join("model/a.gltf");
        let e = confine_uri(&gltf, "link.bin", false).expect_err("link out");
        assert!(e.contains("outside"), "{e}");
        assert!(confine_uri(&gltf, "link.bin", true).is_ok());
        assert_eq!(read_asset(&gltf, "ok.bin").expect("inside"), b"ok".to_vec());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
