//! Reading an input file (a mesh, a file a mesh names, a scene, later a texture) so that no
//! file can hang or exhaust the reader: regular files only, opened without blocking, read up
//! to a size cap.
//!
//! A FIFO opened for reading blocks until a writer appears, and a device such as `/dev/zero`
//! never ends. So the path is looked at first (`stat`, which neither opens nor blocks), then
//! opened with `O_NONBLOCK` (a FIFO swapped in between still cannot block the open), and the
//! opened handle is looked at again (`fstat`): anything but a regular file is refused on one
//! line naming what it is. The size is checked against the caller's cap before a byte is
//! read, the buffer is reserved fallibly (memory the system refuses is an error, not an
//! abort), and the read itself stops one byte past the cap (a file that grows meanwhile).
//!
//! ```
//! use phosphor_mesh::open::{read_file, MAX_MESH_FILE_BYTES};
//!
//! let dir = std::env::temp_dir();
//! let err = read_file(&dir, MAX_MESH_FILE_BYTES).unwrap_err();
//! assert_eq!(err.to_string(), "a folder, not a regular file");
//! ```

use std::fs::{File, Metadata, OpenOptions};
use std::io::{self, Read};
use std::path::Path;

/// Largest mesh file read (OBJ, PLY, STL, glTF or GLB), and the most bytes the buffers of one
/// glTF file may hold together: 2 GiB, past the largest scanned models in common use (the
/// Stanford Lucy PLY is 0.5 GB) and within what 32-bit indices address.
pub const MAX_MESH_FILE_BYTES: u64 = 2 << 30;

/// Longest line of a text format (OBJ, MTL, ASCII PLY and STL): 1 MiB, room for a face of
/// 100,000 corners. Readers split lines into words and copy them; a 1 GB file without a line
/// break must be refused, not buffered and split.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The first line of `bytes` longer than `max` bytes: its 1-based number. Looks at each byte
/// once.
#[must_use]
pub fn long_line(bytes: &[u8], max: usize) -> Option<usize> {
    let mut line = 1;
    let mut rest = bytes;
    loop {
        match rest
            .iter()
            .take(max.saturating_add(1))
            .position(|&b| b == b'\n')
        {
            Some(end) => {
                rest = &rest[end + 1..];
                line += 1;
            }
            None if rest.len() > max => return Some(line),
            None => return None,
        }
    }
}

/// The message for a line over [`MAX_LINE_BYTES`].
#[must_use]
pub fn long_line_message() -> String {
    format!(
        "line longer than {} (no text format needs one)",
        limit_text(MAX_LINE_BYTES as u64)
    )
}

/// Why a file was not read: what it is, or how large, in words (`a FIFO, not a regular
/// file`). `kind` is what `std::io` would call it, so callers keep one error type.
fn refusal(kind: io::ErrorKind, what: String) -> io::Error {
    io::Error::new(kind, what)
}

/// `bytes` as a limit is written in messages: `2 GiB`, `64 MiB`, `512 KiB`, `100 bytes`.
#[must_use]
pub fn limit_text(bytes: u64) -> String {
    for (shift, unit) in [(30, "GiB"), (20, "MiB"), (10, "KiB")] {
        if bytes >= 1 << shift && bytes.is_multiple_of(1 << shift) {
            return format!("{} {unit}", bytes >> shift);
        }
    }
    format!("{bytes} bytes")
}

/// What a file that is not regular is, in words.
fn kind_name(meta: &Metadata) -> &'static str {
    let kind = meta.file_type();
    if kind.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    "a special file"
}

/// Refuses what `meta` says is not a regular file, or is over `max_bytes`.
fn check(meta: &Metadata, max_bytes: u64) -> io::Result<u64> {
    if !meta.is_file() {
        return Err(refusal(
            io::ErrorKind::InvalidInput,
            format!("{}, not a regular file", kind_name(meta)),
        ));
    }
    if meta.len() > max_bytes {
        return Err(too_large(meta.len(), max_bytes));
    }
    Ok(meta.len())
}

fn too_large(len: u64, max_bytes: u64) -> io::Error {
    refusal(
        io::ErrorKind::FileTooLarge,
        format!("{len} bytes, over the {} limit", limit_text(max_bytes)),
    )
}

/// Opens `path` for reading as a regular file of at most `max_bytes`, never blocking; returns
/// the file and its length. The one place every reader of an input file goes through.
///
/// # Errors
/// The operating system's error (missing, no permission), or a refusal naming what the path
/// is (`a FIFO, not a regular file`) or its size against the cap.
pub fn open_regular(path: &Path, max_bytes: u64) -> io::Result<(File, u64)> {
    // A look before opening: opening some devices has effects of its own.
    check(&std::fs::metadata(path)?, max_bytes)?;
    let mut options = OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        // Opening a FIFO for reading would wait for a writer; with O_NONBLOCK it returns at
        // once, and the check of the opened handle below refuses it.
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    // The handle, not the path: what was opened is what is read.
    let len = check(&file.metadata()?, max_bytes)?;
    Ok((file, len))
}

/// The bytes of the regular file `path`, at most `max_bytes` of them (see [`open_regular`]).
///
/// # Errors
/// As [`open_regular`]; memory the system refuses for the buffer; a read error.
pub fn read_file(path: &Path, max_bytes: u64) -> io::Result<Vec<u8>> {
    let (file, len) = open_regular(path, max_bytes)?;
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(usize::try_from(len).unwrap_or(usize::MAX))
        .map_err(|_| {
            refusal(
                io::ErrorKind::OutOfMemory,
                format!("{len} bytes: out of memory"),
            )
        })?;
    // The file may grow between the check and the read: never take more than the cap.
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large(bytes.len() as u64, max_bytes));
    }
    Ok(bytes)
}

/// The text of the regular file `path` (UTF-8), at most `max_bytes` (see [`read_file`]).
///
/// # Errors
/// As [`read_file`]; bytes that are not UTF-8 (`InvalidData`, naming the line).
pub fn read_text(path: &Path, max_bytes: u64) -> io::Result<String> {
    String::from_utf8(read_file(path, max_bytes)?).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = valid.iter().filter(|&&b| b == b'\n').count() + 1;
        refusal(
            io::ErrorKind::InvalidData,
            format!("line {line}: not valid UTF-8"),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_are_written_in_binary_units() {
        assert_eq!(limit_text(MAX_MESH_FILE_BYTES), "2 GiB");
        assert_eq!(limit_text(64 << 20), "64 MiB");
        assert_eq!(limit_text(1000), "1000 bytes");
    }

    #[test]
    fn long_lines_are_found_by_number() {
        assert_eq!(long_line(b"ab\ncd\n", 2), None);
        assert_eq!(long_line(b"ab\ncde\nf", 2), Some(2));
        assert_eq!(long_line(b"abc", 2), Some(1));
        assert_eq!(long_line(b"", 2), None);
    }

    #[test]
    fn a_folder_is_refused_by_name() {
        let e = read_file(&std::env::temp_dir(), 10).expect_err("a folder");
        assert_eq!(e.to_string(), "a folder, not a regular file");
    }

    #[cfg(unix)]
    #[test]
    fn dev_zero_is_refused_before_a_byte_is_read() {
        let e = read_file(Path::new("/dev/zero"), MAX_MESH_FILE_BYTES).expect_err("a device");
        assert_eq!(e.to_string(), "a character device, not a regular file");
    }
}
