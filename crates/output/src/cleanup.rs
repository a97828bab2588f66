//! Temporary files removed on every way out: an error (the guard's drop), and an interrupt or
//! termination (SIGINT, SIGTERM, SIGHUP), after which the process still ends by that signal.
//!
//! A file-size limit (SIGXFSZ) is caught too, so that the write that crossed it fails with
//! "File too large" and is reported like a full disk, instead of killing the process with the
//! temporary file left behind.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

use tempfile::{NamedTempFile, TempPath};

/// Temporary files being written, removed by the signal thread if a signal comes first.
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn pending() -> MutexGuard<'static, Vec<PathBuf>> {
    PENDING.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A temporary file that is removed unless it is persisted.
pub(crate) struct Pending {
    temp: Option<TempPath>,
}

impl Pending {
    /// Creates a temporary file with `make` and starts watching it. The signals are watched
    /// first and the list stays locked while the file is made, so that a signal arriving
    /// meanwhile waits for the file to be listed and then removes it.
    ///
    /// # Errors
    /// `make`'s.
    pub(crate) fn create(
        make: impl FnOnce() -> std::io::Result<NamedTempFile>,
    ) -> std::io::Result<(File, Pending)> {
        install();
        let mut list = pending();
        let (file, temp) = make()?.into_parts();
        list.push(temp.to_path_buf());
        Ok((file, Pending { temp: Some(temp) }))
    }

    /// Renames the file to `target`. The list stays locked through the rename, so a signal
    /// either removes the temporary file before it, or finds it gone after.
    pub(crate) fn persist(mut self, target: &Path) -> std::io::Result<()> {
        // On failure the returned TempPath is dropped, which removes the file.
        self.unlisted(|temp| temp.persist(target).map_err(|e| e.error))
            .unwrap_or_else(|| Err(std::io::Error::other("temporary file already gone")))
    }

    /// Removes the file now, with the list locked, and says if the removal failed.
    pub(crate) fn remove(mut self) -> std::io::Result<()> {
        self.unlisted(TempPath::close).unwrap_or(Ok(()))
    }

    /// Takes the file off the list and hands it to `act` with the list still locked, so
    /// that no signal acts on it in between; `None` if it was already taken.
    fn unlisted<R>(&mut self, act: impl FnOnce(TempPath) -> R) -> Option<R> {
        let temp = self.temp.take()?;
        let mut list = pending();
        let path = temp.to_path_buf();
        list.retain(|p| *p != path);
        Some(act(temp))
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        self.unlisted(drop); // dropping a TempPath removes the file
    }
}

/// Starts the signal thread once per process. If the handlers cannot be installed the
/// process keeps the default behaviour (the error paths still clean up).
#[cfg(unix)]
fn install() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGXFSZ};
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let Ok(mut signals) =
            signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP, SIGXFSZ])
        else {
            return;
        };
        let spawned = std::thread::Builder::new()
            .name("phosphor-output-signals".to_owned())
            .spawn(move || {
                for signal in signals.forever() {
                    if signal == SIGXFSZ {
                        continue; // the write that crossed the limit fails with EFBIG instead
                    }
                    // Held until the process ends: no rename can start after the removal.
                    let list = pending();
                    for path in list.iter() {
                        let _ = std::fs::remove_file(path);
                    }
                    // Ends the process as the signal would have (exit status 128 + signal).
                    let _ = signal_hook::low_level::emulate_default_handler(signal);
                    std::process::exit(128 + signal);
                }
            });
        drop(spawned);
    });
}

#[cfg(not(unix))]
fn install() {}
