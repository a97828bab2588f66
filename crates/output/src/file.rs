//! Output files that are never lost: written whole or not at all.
//!
//! A file is encoded into a temporary file created exclusively (`O_EXCL`, so never through a
//! planted symbolic link) in the target's own folder, flushed and synced with every result
//! checked, and only then renamed over the target. A full disk, a quota, a file-size limit or a
//! signal therefore leaves the old file as it was and no temporary file behind; what a writer
//! killed outright left is removed by the next write into the folder ([`crate::temp`]).
//!
//! What the output path names decides the rest, as `cp` decides it:
//! - nothing: a new file;
//! - a regular file: replaced, keeping its permissions, unless it is read-only;
//! - a symbolic link: written through to the file it points to (the link stays);
//! - a device, FIFO or socket: refused, or with `force` written in place (a stream cannot be
//!   replaced, so there is nothing to keep);
//! - a folder: always refused.

use std::fs::{self, File, Metadata, OpenOptions};
use std::io::{self, BufWriter, Cursor, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::{cleanup, temp};

/// Most symbolic links followed from the output path to its file (Linux's own limit).
const MAX_LINKS: usize = 40;

/// Buffer between an encoder and the file: large enough that a PNG's many small chunk writes
/// become few system calls.
const BUFFER_BYTES: usize = 1 << 16;

/// Why an output could not be written. `Display` is one line naming the path the user gave.
#[derive(Debug, Error)]
pub enum OutputError {
    /// Writing failed (disk full, no permission, file too large, ...); nothing was replaced.
    #[error("{}: cannot write: {reason}", path.display())]
    Write {
        /// The output path as given.
        path: PathBuf,
        /// What failed, with the operating system's reason.
        reason: String,
    },
    /// What the path names must not be replaced.
    #[error("{}: {what}", path.display())]
    Refused {
        /// The output path as given.
        path: PathBuf,
        /// What it is and why it is kept (`is a character device, not a regular file`).
        what: String,
        /// Whether `force` would write it anyway.
        forceable: bool,
    },
}

impl OutputError {
    /// Whether writing with `force` would go ahead (a read-only file, a device, a dangling
    /// link), so that an application can say which flag does that.
    #[must_use]
    pub fn forceable(&self) -> bool {
        matches!(
            self,
            OutputError::Refused {
                forceable: true,
                ..
            }
        )
    }
}

/// Where an output goes once links are followed, and how it is written there.
#[derive(Debug)]
enum Target {
    /// A new regular file at this path.
    New(PathBuf),
    /// An existing regular file, replaced by rename; its metadata gives the permissions kept.
    Replace(PathBuf, Metadata),
    /// A device, FIFO or socket, written in place (only with `force`).
    Stream(PathBuf),
}

/// Checks that `path` may be written (see the module documentation), leaving nothing behind:
/// applications call it before long work so that a refusal comes first. A temporary file is
/// made in the target's folder and removed at once, so a folder that is missing, read-only
/// or not a real one (`/proc`) is refused here.
///
/// # Errors
/// [`OutputError::Refused`] for a folder, a device, FIFO or socket, a read-only file or a
/// dangling link (the last three only without `force`); [`OutputError::Write`] when the path
/// cannot be examined (a missing folder, a loop of links) or no file can be made beside it.
pub fn check(path: &Path, force: bool) -> Result<(), OutputError> {
    match resolve(path, force)? {
        Target::Stream(_) => Ok(()),
        Target::New(target) | Target::Replace(target, _) => {
            // The folder must take the temporary file: a read-only folder, a full quota or
            // `/proc` is refused now, not after the work.
            let dir = parent_of(&target);
            let name = target.file_name().unwrap_or(target.as_os_str());
            temp::probe(&dir, name).map_err(|e| OutputError::Write {
                path: path.to_path_buf(),
                reason: format!("cannot create a temporary file in {}: {e}", dir.display()),
            })
        }
    }
}

/// Writes a file at `path` from `encode`, which receives a buffered, seekable sink and returns
/// a description of what failed, if anything. See the module documentation for what happens to
/// what the path names, and [`check`] for the refusals.
///
/// # Errors
/// As [`check`]; [`OutputError::Write`] naming the operating system's reason when creating,
/// writing, flushing, syncing or renaming fails, or `encode`'s own message. On any error the
/// path is left as it was and the temporary file is removed.
pub fn write_file(
    path: &Path,
    force: bool,
    encode: impl FnOnce(&mut dyn Sink) -> Result<(), String>,
) -> Result<(), OutputError> {
    write_through(path, force, |file| file, encode)
}

/// What an encoder writes into: bytes, and a position it may move (EXR writes its offset
/// table last, at the front).
pub trait Sink: Write + Seek {}

impl<T: Write + Seek> Sink for T {}

/// A file being written: the bytes, and the final sync that makes them durable.
pub(crate) trait Storage: Write + Seek {
    /// Flushes the bytes to the device (`fsync`).
    fn sync(&mut self) -> io::Result<()>;
}

impl Storage for File {
    fn sync(&mut self) -> io::Result<()> {
        self.sync_all()
    }
}

/// [`write_file`] with the temporary file wrapped by `wrap` (tests put a full disk there).
pub(crate) fn write_through<S: Storage>(
    path: &Path,
    force: bool,
    wrap: impl FnOnce(File) -> S,
    encode: impl FnOnce(&mut dyn Sink) -> Result<(), String>,
) -> Result<(), OutputError> {
    let fail = |reason: String| OutputError::Write {
        path: path.to_path_buf(),
        reason,
    };
    let (target, existing) = match resolve(path, force)? {
        Target::Stream(target) => return write_stream(path, &target, encode),
        Target::New(target) => (target, None),
        Target::Replace(target, meta) => (target, Some(meta)),
    };
    let dir = parent_of(&target);
    let name = target
        .file_name()
        .ok_or_else(|| fail("not a file name".to_owned()))?;
    // What a writer killed by SIGKILL left here goes first (never a running writer's).
    temp::remove_stale(&dir);
    let (file, pending) = cleanup::Pending::create(|| temp::create(&dir, name)).map_err(|e| {
        fail(format!(
            "cannot create a temporary file in {}: {e}",
            dir.display()
        ))
    })?;
    if let Some(meta) = &existing {
        keep_owner_and_mode(&file, meta).map_err(|e| fail(e.to_string()))?;
    }
    let mut sink = BufWriter::with_capacity(BUFFER_BYTES, Recorder::new(wrap(file)));
    let written = match encode(&mut sink) {
        // An encoder that swallowed an I/O error and went on must not count as a success.
        Ok(()) => match sink.into_inner() {
            Ok(recorder) => match recorder.reason() {
                Some(reason) => Err(reason),
                None => Ok(recorder),
            },
            Err(e) => Err(e.error().to_string()),
        },
        Err(what) => Err(sink.get_ref().reason().unwrap_or(what)),
    };
    // On error the buffer and the file are dropped here, and `pending` removes the file.
    let mut recorder = written.map_err(fail)?;
    recorder.inner.sync().map_err(|e| fail(e.to_string()))?;
    drop(recorder); // closed before it is renamed
    pending.persist(&target).map_err(|e| fail(e.to_string()))?;
    sync_folder(&dir);
    Ok(())
}

/// Writes a stream target in place: the whole file is encoded in memory first (the encoder
/// may seek, a stream cannot), then written and flushed.
fn write_stream(
    path: &Path,
    target: &Path,
    encode: impl FnOnce(&mut dyn Sink) -> Result<(), String>,
) -> Result<(), OutputError> {
    let fail = |reason: String| OutputError::Write {
        path: path.to_path_buf(),
        reason,
    };
    let mut bytes = Cursor::new(Vec::new());
    encode(&mut bytes).map_err(fail)?;
    let mut file = OpenOptions::new()
        .write(true)
        .open(target)
        .map_err(|e| fail(e.to_string()))?;
    file.write_all(bytes.get_ref())
        .and_then(|()| file.flush())
        .map_err(|e| fail(e.to_string()))
}

/// Follows links from `path` and sorts out what the final path names.
fn resolve(path: &Path, force: bool) -> Result<Target, OutputError> {
    let refuse = |what: String, forceable: bool| OutputError::Refused {
        path: path.to_path_buf(),
        what,
        forceable,
    };
    let fail = |reason: String| OutputError::Write {
        path: path.to_path_buf(),
        reason,
    };
    // A stream reached through a link that names no path (`/dev/stdout` to a pipe reads
    // `pipe:[1234]`) is known by what the kernel opens: written in place, as any stream.
    if let Ok(meta) = fs::metadata(path)
        && !meta.is_file()
        && !meta.is_dir()
    {
        if force {
            return Ok(Target::Stream(path.to_path_buf()));
        }
        return Err(refuse(
            format!("is a {}, not a regular file", kind_name(&meta)),
            true,
        ));
    }
    let (target, via_link) = follow_links(path).map_err(|e| fail(e.to_string()))?;
    let meta = match fs::metadata(&target) {
        Ok(meta) => meta,
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            let dir = parent_of(&target);
            if !dir.is_dir() {
                return Err(fail(format!("{}: no such folder", dir.display())));
            }
            if via_link && !force {
                return Err(refuse(
                    format!(
                        "is a dangling symbolic link (to {}); not writing through it",
                        target.display()
                    ),
                    true,
                ));
            }
            return Ok(Target::New(target));
        }
        Err(e) => return Err(fail(e.to_string())),
    };
    let kind = meta.file_type();
    if kind.is_dir() {
        return Err(refuse("is a folder".to_owned(), false));
    }
    if !kind.is_file() {
        if force {
            return Ok(Target::Stream(target));
        }
        return Err(refuse(
            format!("is a {}, not a regular file", kind_name(&meta)),
            true,
        ));
    }
    if !force && read_only(&target, &meta) {
        return Err(refuse("is read-only".to_owned(), true));
    }
    Ok(Target::Replace(target, meta))
}

/// The path at the end of `path`'s chain of symbolic links, and whether there was a link.
fn follow_links(path: &Path) -> io::Result<(PathBuf, bool)> {
    let mut current = path.to_path_buf();
    for hops in 0..=MAX_LINKS {
        match fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = fs::read_link(&current)?;
                current = if link.is_absolute() {
                    link
                } else {
                    parent_of(&current).join(link)
                };
            }
            _ => return Ok((current, hops > 0)),
        }
    }
    Err(io::Error::other("too many levels of symbolic links"))
}

/// The folder holding `path` (`.` for a bare file name).
fn parent_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Whether the file must be kept: it has no write permission bit at all (which the owner,
/// or an administrator, set on purpose even though the folder would let a rename replace it),
/// or this process may not open it for writing.
fn read_only(path: &Path, meta: &Metadata) -> bool {
    meta.permissions().readonly()
        || OpenOptions::new()
            .write(true)
            .open(path)
            .is_err_and(|e| e.kind() == io::ErrorKind::PermissionDenied)
}

/// Gives the replacement the replaced file's permissions and, where allowed, its owner.
fn keep_owner_and_mode(file: &File, meta: &Metadata) -> io::Result<()> {
    file.set_permissions(meta.permissions())?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        let mine = file.metadata()?;
        if (mine.uid(), mine.gid()) != (meta.uid(), meta.gid()) {
            // Only an administrator may give a file away; anyone else's replacement is
            // theirs, as `cp` over a removed file would be. Not an error either way.
            let _ = std::os::unix::fs::fchown(file, Some(meta.uid()), Some(meta.gid()));
        }
    }
    Ok(())
}

/// What a non-regular file is, in words.
fn kind_name(meta: &Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        let kind = meta.file_type();
        if kind.is_char_device() {
            return "character device";
        }
        if kind.is_block_device() {
            return "block device";
        }
        if kind.is_fifo() {
            return "FIFO";
        }
        if kind.is_socket() {
            return "socket";
        }
    }
    let _ = meta;
    "special file"
}

/// Makes the rename itself durable. Best effort: the file is complete and in place already,
/// and some file systems cannot sync a folder at all.
fn sync_folder(dir: &Path) {
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
}

/// Passes writes through and keeps the first I/O error, so that the message names the
/// operating system's reason even when an encoder reports it as its own kind of failure.
pub(crate) struct Recorder<S> {
    pub(crate) inner: S,
    first_error: Option<String>,
}

impl<S> Recorder<S> {
    fn new(inner: S) -> Self {
        Recorder {
            inner,
            first_error: None,
        }
    }

    /// The first I/O error seen, in words.
    fn reason(&self) -> Option<String> {
        self.first_error.clone()
    }

    fn note<T>(&mut self, result: io::Result<T>) -> io::Result<T> {
        if let Err(e) = &result {
            if self.first_error.is_none() && e.kind() != io::ErrorKind::Interrupted {
                self.first_error = Some(e.to_string());
            }
        }
        result
    }
}

impl<S: Write> Write for Recorder<S> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let r = self.inner.write(buf);
        self.note(r)
    }

    fn flush(&mut self) -> io::Result<()> {
        let r = self.inner.flush();
        self.note(r)
    }
}

impl<S: Seek> Seek for Recorder<S> {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        let r = self.inner.seek(pos);
        self.note(r)
    }
}
