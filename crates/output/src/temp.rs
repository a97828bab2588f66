//! The temporary files an output is written into: their names, a check that one can be made
//! before any work, and the removal of those that a writer killed outright left behind.
//!
//! A temporary file is named `.NAME.PID.XXXXXX.tmp` in the target's folder: `NAME` the
//! target's file name, `PID` the writing process, `XXXXXX` random. Two rules follow:
//! - **It fits wherever the target's name fits.** A name of up to [`WHOLE_NAME_BYTES`] bytes
//!   is kept whole (the temporary name is then at most 90 bytes, within every file system's
//!   limit); a longer one is cut at a character boundary so that the temporary name is no
//!   longer than the target's own name.
//! - **What a dead writer left is found by its pattern.** SIGKILL (or a power cut) ends a
//!   writer before it can remove its temporary file, which may be hundreds of megabytes. On
//!   Linux, each write into a folder first removes the files there that have the pattern,
//!   belong to this user, are regular files, have not been written to for
//!   [`STALE_AFTER`], and whose `PID` names no running process. A running writer's file is
//!   never touched: its process exists (and it keeps writing to the file).

use std::ffi::OsStr;
use std::fs;
use std::path::Path;
use std::time::Duration;

use tempfile::NamedTempFile;

/// Longest target name kept whole in its temporary name.
pub const WHOLE_NAME_BYTES: usize = 64;

/// How long a temporary file must have gone unwritten before a later run may take it for a
/// dead writer's: longer than any pause of a live writer between two blocks.
pub const STALE_AFTER: Duration = Duration::from_secs(60);

/// Random characters in a temporary name.
const RANDOM_CHARS: usize = 6;

/// The part of `name` (a target's file name) a temporary name keeps: all of it up to
/// [`WHOLE_NAME_BYTES`], else cut so that `.KEPT.PID.XXXXXX.tmp` is no longer than `name`.
fn kept(name: &str, pid: u32) -> &str {
    if name.len() <= WHOLE_NAME_BYTES {
        return name;
    }
    let extra = format!("..{pid}.").len() + RANDOM_CHARS + ".tmp".len();
    let mut end = name.len().saturating_sub(extra).max(1);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    &name[..end]
}

/// Creates the temporary file for the target named `name` in `dir` (exclusively, never
/// through a planted link; mode 0666 less the umask, as any program's output).
pub(crate) fn create(dir: &Path, name: &OsStr) -> std::io::Result<NamedTempFile> {
    let pid = std::process::id();
    let name = name.to_string_lossy();
    let prefix = format!(".{}.{pid}.", kept(&name, pid));
    let mut builder = tempfile::Builder::new();
    builder
        .prefix(&prefix)
        .suffix(".tmp")
        .rand_bytes(RANDOM_CHARS);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        // tempfile's own default (0600) would hide the picture from other users.
        builder.permissions(fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(dir)
}

/// Checks that a temporary file for `name` can be made in `dir` (the folder exists, is
/// writable, is not `/proc`), by making one and removing it at once. The probe is watched
/// like any temporary file, so that a signal arriving while it exists removes it too.
pub(crate) fn probe(dir: &Path, name: &OsStr) -> std::io::Result<()> {
    let (file, pending) = crate::cleanup::Pending::create(|| create(dir, name))?;
    drop(file);
    pending.remove()
}

/// The process id in a temporary name of the pattern `.NAME.PID.XXXXXX.tmp`, if it is one.
fn writer_of(file_name: &str) -> Option<u32> {
    let rest = file_name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (rest, random) = rest.rsplit_once('.')?;
    if random.len() != RANDOM_CHARS || !random.bytes().all(|b| b.is_ascii_alphanumeric()) {
        return None;
    }
    let (name, pid) = rest.rsplit_once('.')?;
    if name.is_empty() || pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// Removes from `dir` the temporary files of writers that no longer run (see the module
/// documentation). Best effort and silent: an entry that cannot be read or removed stays.
pub(crate) fn remove_stale(dir: &Path) {
    // Whether a process runs is known from /proc; elsewhere nothing is removed.
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name.to_str().and_then(writer_of) else {
            continue;
        };
        if pid == std::process::id() || Path::new(&format!("/proc/{pid}")).exists() {
            continue;
        }
        let Ok(meta) = fs::symlink_metadata(entry.path()) else {
            continue;
        };
        let idle = meta
            .modified()
            .ok()
            .and_then(|t| t.elapsed().ok())
            .is_some_and(|d| d >= STALE_AFTER);
        if meta.is_file() && idle && mine(&meta) {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// Whether this process's user owns the file.
#[cfg(unix)]
fn mine(meta: &fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    fs::metadata("/proc/self").is_ok_and(|me| me.uid() == meta.uid())
}

#[cfg(not(unix))]
fn mine(_: &fs::Metadata) -> bool {
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_are_recognised_by_their_pattern() {
        assert_eq!(writer_of(".out.png.1234.aB3xYz.tmp"), Some(1234));
        assert_eq!(writer_of(".a.b.c.exr.7.000000.tmp"), Some(7));
        for not in [
            ".out.png.aB3xYz.tmp",
            "out.png.1234.aB3xYz.tmp",
            ".out.png.12x4.aB3xYz.tmp",
            ".out.png.1234.aB3x.tmp",
            "..1234.aB3xYz.tmp",
            ".out.png.1234.aB3xYz.tmp.png",
        ] {
            assert_eq!(writer_of(not), None, "{not}");
        }
    }

    #[test]
    fn a_long_name_gives_a_temporary_name_no_longer_than_itself() {
        let name = "x".repeat(244);
        let temp = format!(".{}.{}.abcdef.tmp", kept(&name, 4_194_304), 4_194_304);
        assert!(temp.len() <= name.len(), "{}", temp.len());
        assert_eq!(kept("short.png", 1), "short.png");
        let wide = "é".repeat(100);
        assert!(kept(&wide, 99).len() < wide.len());
    }
}
