//! Live reload: the files a scene was made from are watched with `notify`, and a change to one
//! of them calls `wake` (from the watcher's thread), which the window turns into a reload once
//! the writes have settled.
//!
//! Each file's folder is watched rather than the file itself: editors save by writing a new
//! file and renaming it over the old one, which ends a watch on the file but not on its
//! folder. Changes to other files in those folders (a screenshot saved beside the scene) are
//! ignored.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

use notify::event::{AccessKind, AccessMode};
use notify::{EventKind, RecommendedWatcher, RecursiveMode, Watcher};

/// A watch over a set of files.
pub struct Watch {
    watcher: RecommendedWatcher,
    /// The files, as [`absolute`] gives them, shared with the watcher's callback.
    files: Arc<Mutex<BTreeSet<PathBuf>>>,
    /// The folders being watched.
    dirs: BTreeSet<PathBuf>,
}

impl Watch {
    /// A watch over no files yet; `wake` is called, from another thread, when a watched file
    /// changes.
    ///
    /// # Errors
    /// The platform's reason when no watcher can be made (no inotify instance left).
    pub fn new(wake: impl Fn() + Send + 'static) -> Result<Watch, String> {
        let files = Arc::new(Mutex::new(BTreeSet::new()));
        let seen = files.clone();
        let watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
            let Ok(event) = event else { return };
            if !changes_content(&event.kind) {
                return;
            }
            let files = seen.lock().unwrap_or_else(PoisonError::into_inner);
            if event.paths.iter().any(|p| files.contains(&absolute(p))) {
                wake();
            }
        })
        .map_err(|e| format!("cannot watch files: {e}"))?;
        Ok(Watch {
            watcher,
            files,
            dirs: BTreeSet::new(),
        })
    }

    /// Watches `files` instead of the files watched so far. Returns a warning for each folder
    /// that cannot be watched (gone, or unreadable); the others are watched all the same.
    pub fn set(&mut self, files: &BTreeSet<PathBuf>) -> Vec<String> {
        let files: BTreeSet<PathBuf> = files.iter().map(|f| absolute(f)).collect();
        let dirs: BTreeSet<PathBuf> = files
            .iter()
            .filter_map(|f| f.parent().map(Path::to_path_buf))
            .collect();
        for gone in self.dirs.difference(&dirs) {
            // A folder removed since is no longer watched anyway.
            let _ = self.watcher.unwatch(gone);
        }
        let mut warnings = Vec::new();
        let mut watched = BTreeSet::new();
        for dir in &dirs {
            if self.dirs.contains(dir) {
                watched.insert(dir.clone());
                continue;
            }
            match self.watcher.watch(dir, RecursiveMode::NonRecursive) {
                Ok(()) => {
                    watched.insert(dir.clone());
                }
                Err(e) => warnings.push(format!(
                    "warning: {}: cannot watch for changes: {e}",
                    dir.display()
                )),
            }
        }
        self.dirs = watched;
        *self.files.lock().unwrap_or_else(PoisonError::into_inner) = files;
        warnings
    }
}

/// Whether an event may have changed a file's content: a write, a file created, removed or
/// renamed, or a file closed after writing. Reads and metadata-only access are not.
fn changes_content(kind: &EventKind) -> bool {
    match kind {
        EventKind::Create(_) | EventKind::Modify(_) | EventKind::Remove(_) => true,
        EventKind::Access(AccessKind::Close(AccessMode::Write)) => true,
        EventKind::Access(_) | EventKind::Any | EventKind::Other => false,
    }
}

/// `path` made absolute with its folder's symbolic links resolved, as the watcher reports
/// paths in the folders it watches; the file itself need not exist (it may be mid-save).
pub fn absolute(path: &Path) -> PathBuf {
    let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    match (path.parent(), path.file_name()) {
        (Some(dir), Some(name)) => match dir.canonicalize() {
            Ok(dir) => dir.join(name),
            Err(_) => path,
        },
        _ => path,
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use std::sync::mpsc;
    use std::time::Duration;

    fn temp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("phosphor-watch-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// Drains the wake-ups that arrive within `wait`; returns how many.
    fn wakes(rx: &mpsc::Receiver<()>, wait: Duration) -> usize {
        let mut n = 0;
        while rx.recv_timeout(wait).is_ok() {
            n += 1;
        }
        n
    }

    #[test]
    fn a_watched_file_wakes_on_a_write_and_a_save_by_rename_and_others_do_not() {
        let d = temp("files");
        let scene = d.join("scene.toml");
        let other = d.join("shot.png");
        std::fs::write(&scene, "a").unwrap();
        let (tx, rx) = mpsc::channel();
        let tx = Mutex::new(tx);
        let mut watch = Watch::new(move || {
            let _ = tx.lock().unwrap().send(());
        })
        .unwrap();
        assert!(watch.set(&BTreeSet::from([scene.clone()])).is_empty());
        let settle = Duration::from_millis(300);
        // Another file in the same folder: nothing.
        std::fs::write(&other, "png").unwrap();
        assert_eq!(wakes(&rx, settle), 0);
        // A write in place.
        std::fs::write(&scene, "b").unwrap();
        assert!(wakes(&rx, settle) > 0);
        // A save by rename, as editors do: the watch outlives the replaced file.
        let tmp = d.join(".scene.toml.swp");
        std::fs::write(&tmp, "c").unwrap();
        std::fs::rename(&tmp, &scene).unwrap();
        assert!(wakes(&rx, settle) > 0);
        std::fs::write(&scene, "d").unwrap();
        assert!(wakes(&rx, settle) > 0);
        // Watching nothing: no more wake-ups.
        assert!(watch.set(&BTreeSet::new()).is_empty());
        std::fs::write(&scene, "e").unwrap();
        assert_eq!(wakes(&rx, settle), 0);
        // A folder that does not exist is a warning, not an error.
        let warnings = watch.set(&BTreeSet::from([d.join("gone").join("x.obj")]));
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("gone"), "{warnings:?}");
        let _ = std::fs::remove_dir_all(&d);
    }
}
