//! Output folders: `-o renders/turntable/frame_%04d.png` makes `renders/turntable/` where it
//! is missing, parents included, as `mkdir -p` would. Only the arguments are checked up front
//! (the nearest folder that exists must be a folder); the missing ones are made just before
//! the first file is written into them, so a command that fails while loading or rendering
//! leaves no folder behind, and a write that fails right after removes again the folders it
//! made, where they are still empty. Several processes may make the same folder at once (a
//! sequence split across them): a folder that appears meanwhile is used, not an error.

use std::io::ErrorKind;
use std::path::{Path, PathBuf};

use crate::CliError;

/// The folders missing above `file`, outermost first (none when its folder exists).
///
/// # Errors
/// The nearest path above `file` that exists is not a folder, or cannot be examined (input).
pub fn missing_folders(file: &Path) -> Result<Vec<PathBuf>, CliError> {
    let mut missing = Vec::new();
    let mut dir = file.parent();
    while let Some(d) = dir.filter(|d| !d.as_os_str().is_empty()) {
        match std::fs::symlink_metadata(d) {
            Ok(_) => {
                // It exists (or is a link): it must lead to a folder.
                if !std::fs::metadata(d).is_ok_and(|m| m.is_dir()) {
                    return Err(CliError::Input(format!(
                        "{}: cannot write: {} is not a folder",
                        file.display(),
                        d.display()
                    )));
                }
                break;
            }
            // A file further up shows as "not a directory" here; the walk reaches and names it.
            Err(e) if matches!(e.kind(), ErrorKind::NotFound | ErrorKind::NotADirectory) => {
                missing.push(d.to_path_buf());
            }
            Err(e) => {
                return Err(CliError::Input(format!(
                    "{}: cannot write: {}: {e}",
                    file.display(),
                    d.display()
                )));
            }
        }
        dir = d.parent();
    }
    missing.reverse();
    Ok(missing)
}

/// Makes the folders missing above `file` and returns those this call made, outermost first.
///
/// # Errors
/// A folder that cannot be made (input); the ones made before it are removed again.
pub fn make_missing(file: &Path) -> Result<Vec<PathBuf>, CliError> {
    let mut made = Vec::new();
    for dir in missing_folders(file)? {
        match std::fs::create_dir(&dir) {
            Ok(()) => made.push(dir),
            Err(e) if e.kind() == ErrorKind::AlreadyExists && dir.is_dir() => {}
            Err(e) => {
                remove_empty(&made);
                return Err(CliError::Input(format!(
                    "{}: cannot make folder {}: {e}",
                    file.display(),
                    dir.display()
                )));
            }
        }
    }
    Ok(made)
}

/// Removes `made` (outermost first, as [`make_missing`] returns them), innermost first, each
/// only if it is empty.
pub fn remove_empty(made: &[PathBuf]) {
    for dir in made.iter().rev() {
        // A folder something was written into (or that cannot be removed) stays.
        let _ = std::fs::remove_dir(dir);
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn missing_folders_are_made_outermost_first_and_removed_when_empty() {
        let root = std::env::temp_dir().join(format!("phosphor-folders-{}", std::process::id()));
        std::fs::create_dir_all(&root).unwrap();
        let file = root.join("a/b/c/frame.png");
        assert_eq!(
            missing_folders(&file).unwrap(),
            vec![root.join("a"), root.join("a/b"), root.join("a/b/c")]
        );
        let made = make_missing(&file).unwrap();
        assert_eq!(made.len(), 3);
        assert!(root.join("a/b/c").is_dir());
        assert!(missing_folders(&file).unwrap().is_empty());
        // Made already: nothing more to make, nothing reported as made.
        assert!(make_missing(&file).unwrap().is_empty());
        remove_empty(&made);
        assert!(!root.join("a").exists());
        // A file where a folder should be is named.
        std::fs::write(root.join("plain"), b"x").unwrap();
        let e = missing_folders(&root.join("plain/x/frame.png")).unwrap_err();
        assert!(e.to_string().ends_with("plain is not a folder"), "{e}");
        assert_eq!(e.exit_code(), 1);
        assert!(missing_folders(Path::new("frame.png")).unwrap().is_empty());
        std::fs::remove_dir_all(&root).unwrap();
    }
}
