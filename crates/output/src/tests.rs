//! Output files under faults: a disk that fills up at every byte offset, a failing sync, and
//! each kind of thing an output path can name.

#![allow(clippy::unwrap_used)]

use std::fs::{self, File};
use std::io::{self, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use crate::file::{OutputError, Storage, write_through};
use crate::image::{Transfer, encode_exr, encode_exr_rgba, encode_png, encode_png_rgba};
use crate::write_file;

/// A file on a disk with room for `room` bytes: a write past that fails with ENOSPC after
/// writing what fits, as a real full disk does; overwriting bytes already there succeeds.
struct DiskFull {
    file: File,
    position: u64,
    room: u64,
    sync_fails: bool,
}

impl Write for DiskFull {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let left = self.room.saturating_sub(self.position);
        if left == 0 && !buf.is_empty() {
            return Err(io::Error::from_raw_os_error(28)); // ENOSPC
        }
        let n = self.file.write(&buf[..buf.len().min(left as usize)])?;
        self.position += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

impl Seek for DiskFull {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        self.position = self.file.seek(pos)?;
        Ok(self.position)
    }
}

impl Storage for DiskFull {
    fn sync(&mut self) -> io::Result<()> {
        if self.sync_fails {
            return Err(io::Error::from_raw_os_error(5)); // EIO
        }
        self.file.sync_all()
    }
}

fn temp_dir() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

const W: u32 = 9;
const H: u32 = 7;

fn png_encoder(transfer: Transfer) -> impl Fn(&mut dyn crate::file::Sink) -> Result<(), String> {
    move |sink| {
        encode_png(
            sink,
            W,
            H,
            transfer,
            &mut |y, row| {
                for (x, px) in row.chunks_mut(3).enumerate() {
                    px.copy_from_slice(&[x as u8 * 20, y as u8 * 30, 99]);
                }
            },
            &mut |_| {},
        )
    }
}

fn exr_encoder(sink: &mut dyn crate::file::Sink) -> Result<(), String> {
    encode_exr(
        sink,
        W,
        H,
        &|x, y| [x as f32 * 0.1, y as f32 * 0.2, 1.5],
        &mut |_| {},
    )
}

#[test]
fn rgba_png_keeps_its_alpha_bytes_and_rgba_exr_encodes() {
    let mut bytes = std::io::Cursor::new(Vec::new());
    let mut row = |y: u32, out: &mut [u8]| {
        for (x, px) in out.chunks_exact_mut(4).enumerate() {
            px.copy_from_slice(&[x as u8, y as u8, 7, (x * 25 + y as usize) as u8]);
        }
    };
    encode_png_rgba(&mut bytes, W, H, Transfer::Srgb, &mut row, &mut |_| {}).unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes.into_inner()));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    assert_eq!((info.width, info.height), (W, H));
    let at = |x: usize, y: usize| &pixels[(y * W as usize + x) * 4..][..4];
    assert_eq!(at(3, 2), [3, 2, 7, 77]);
    assert_eq!(at(8, 6), [8, 6, 7, 206]);
    let mut exr = std::io::Cursor::new(Vec::new());
    let pixel = |x: u32, _: u32| [x as f32, 2.5, 0.0, 0.5];
    encode_exr_rgba(&mut exr, W, H, &pixel, &mut |_| {}).unwrap();
    let exr = exr.into_inner();
    assert!(
        exr.starts_with(&[0x76, 0x2f, 0x31, 0x01]),
        "OpenEXR magic number"
    );
    // The channel list names A beside B, G and R.
    let names = String::from_utf8_lossy(&exr[..400]).into_owned();
    assert!(names.contains("A\0") && names.contains("R\0"), "{names}");
}

/// The size of the file `encode` writes on a disk with room to spare.
fn full_size(encode: &dyn Fn(&mut dyn crate::file::Sink) -> Result<(), String>) -> u64 {
    let dir = temp_dir();
    let path = dir.path().join("probe");
    write_file(&path, false, |s| encode(s)).unwrap();
    fs::metadata(&path).unwrap().len()
}

/// Fills the disk at every byte offset of the file `encode` writes: each attempt fails with
/// one line naming the path and the OS reason, the old file keeps its bytes and no temporary
/// file is left; with room for the whole file it succeeds.
fn every_offset_keeps_the_old_file(
    name: &str,
    encode: &dyn Fn(&mut dyn crate::file::Sink) -> Result<(), String>,
) {
    let size = full_size(encode);
    assert!(size > 50, "{name}: {size} bytes");
    let dir = temp_dir();
    let path = dir.path().join(name);
    fs::write(&path, b"the old picture").unwrap();
    for room in 0..size {
        let err = write_through(
            &path,
            false,
            |file| DiskFull {
                file,
                position: 0,
                room,
                sync_fails: false,
            },
            |s| encode(s),
        )
        .unwrap_err();
        let text = err.to_string();
        assert!(
            text.starts_with(&format!("{}: cannot write: ", path.display()))
                && text.contains("No space left on device")
                && !text.contains('\n'),
            "{name} at {room}: {text}"
        );
        assert_eq!(
            fs::read(&path).unwrap(),
            b"the old picture",
            "{name} at {room}"
        );
        assert_eq!(names_in(dir.path()), [name], "{name} at {room}");
    }
    write_through(
        &path,
        false,
        |file| DiskFull {
            file,
            position: 0,
            room: size,
            sync_fails: false,
        },
        |s| encode(s),
    )
    .unwrap();
    assert_eq!(fs::metadata(&path).unwrap().len(), size);
}

#[test]
fn a_full_disk_at_any_byte_of_a_png_leaves_the_old_file() {
    every_offset_keeps_the_old_file("out.png", &png_encoder(Transfer::Srgb));
}

#[test]
fn a_full_disk_at_any_byte_of_an_exr_leaves_the_old_file() {
    every_offset_keeps_the_old_file("out.exr", &exr_encoder);
}

#[test]
fn a_failed_sync_leaves_the_old_file() {
    let dir = temp_dir();
    let path = dir.path().join("out.png");
    fs::write(&path, b"old").unwrap();
    let encode = png_encoder(Transfer::Linear);
    let err = write_through(
        &path,
        false,
        |file| DiskFull {
            file,
            position: 0,
            room: u64::MAX,
            sync_fails: true,
        },
        |s| encode(s),
    )
    .unwrap_err();
    assert!(err.to_string().contains("Input/output error"), "{err}");
    assert_eq!(fs::read(&path).unwrap(), b"old");
    assert_eq!(names_in(dir.path()), ["out.png"]);
}

#[test]
fn an_encoder_that_swallows_a_write_error_does_not_count_as_written() {
    let dir = temp_dir();
    let path = dir.path().join("out.png");
    fs::write(&path, b"old").unwrap();
    let err = write_through(
        &path,
        false,
        |file| DiskFull {
            file,
            position: 0,
            room: 0,
            sync_fails: false,
        },
        |s| {
            let _ = s.write_all(&[0; 100_000]); // error ignored, as a careless encoder would
            Ok(())
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("No space left"), "{err}");
    assert_eq!(fs::read(&path).unwrap(), b"old");
}

/// Decodes the chunk types of a PNG file, in order.
fn chunk_types(bytes: &[u8]) -> Vec<String> {
    let mut at = 8;
    let mut types = Vec::new();
    while at + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        types.push(String::from_utf8_lossy(&bytes[at + 4..at + 8]).into_owned());
        at += 12 + len;
    }
    types
}

/// The data of the first chunk of type `kind`.
fn chunk<'a>(bytes: &'a [u8], kind: &[u8]) -> Option<&'a [u8]> {
    let mut at = 8;
    while at + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        if &bytes[at + 4..at + 8] == kind {
            return Some(&bytes[at + 8..at + 8 + len]);
        }
        at += 12 + len;
    }
    None
}

#[test]
fn pngs_say_which_transfer_curve_their_codes_follow() {
    let dir = temp_dir();
    for (transfer, gamma, cicp_transfer) in [
        (Transfer::Srgb, 45_455u32, 13u8),
        (Transfer::Linear, 100_000, 8),
    ] {
        let path = dir.path().join("tagged.png");
        let encode = png_encoder(transfer);
        write_file(&path, false, |s| encode(s)).unwrap();
        let bytes = fs::read(&path).unwrap();
        let types = chunk_types(&bytes);
        assert_eq!(types.first().map(String::as_str), Some("IHDR"));
        let idat = types.iter().position(|t| t == "IDAT").unwrap();
        let before = |t: &str| types.iter().position(|x| x == t).is_some_and(|i| i < idat);
        assert!(
            before("gAMA") && before("cHRM") && before("cICP"),
            "{types:?}"
        );
        assert_eq!(before("sRGB"), transfer == Transfer::Srgb, "{types:?}");
        let g = chunk(&bytes, b"gAMA").unwrap();
        assert_eq!(u32::from_be_bytes(g.try_into().unwrap()), gamma);
        assert_eq!(chunk(&bytes, b"cICP").unwrap(), [1, cicp_transfer, 0, 1]);
        // And the pixels decode as written.
        let decoder = png::Decoder::new(io::BufReader::new(File::open(&path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        reader.next_frame(&mut buf).unwrap();
        assert_eq!(&buf[..6], [0, 0, 99, 20, 0, 99]);
    }
}

#[cfg(unix)]
mod unix {
    use std::os::unix::fs::{PermissionsExt, symlink};

    use super::*;

    fn write_text(path: &Path, force: bool, text: &'static [u8]) -> Result<(), OutputError> {
        write_file(path, force, |s| {
            s.write_all(text).map_err(|e| e.to_string())
        })
    }

    #[test]
    fn a_symbolic_link_is_written_through_and_stays_a_link() {
        let dir = temp_dir();
        let real = dir.path().join("real.png");
        fs::write(&real, b"old").unwrap();
        let link = dir.path().join("link.png");
        symlink("real.png", &link).unwrap();
        write_text(&link, false, b"new").unwrap();
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read(&real).unwrap(), b"new");
        assert_eq!(names_in(dir.path()), ["link.png", "real.png"]);
        // A chain of links, one of them absolute.
        let link2 = dir.path().join("link2.png");
        symlink(&link, &link2).unwrap();
        write_text(&link2, false, b"newer").unwrap();
        assert_eq!(fs::read(&real).unwrap(), b"newer");
    }

    #[test]
    fn a_dangling_link_is_refused_unless_forced() {
        let dir = temp_dir();
        let link = dir.path().join("link.png");
        symlink("gone.png", &link).unwrap();
        let err = write_text(&link, false, b"new").unwrap_err();
        assert!(err.forceable(), "{err}");
        assert!(err.to_string().contains("dangling symbolic link"), "{err}");
        assert!(!dir.path().join("gone.png").exists());
        write_text(&link, true, b"new").unwrap();
        assert_eq!(fs::read(dir.path().join("gone.png")).unwrap(), b"new");
    }

    #[test]
    fn a_loop_of_links_is_an_error_not_a_hang() {
        let dir = temp_dir();
        let a = dir.path().join("a.png");
        let b = dir.path().join("b.png");
        symlink(&b, &a).unwrap();
        symlink(&a, &b).unwrap();
        let err = write_text(&a, true, b"x").unwrap_err();
        assert!(err.to_string().contains("symbolic links"), "{err}");
    }

    #[test]
    fn a_read_only_file_is_kept_unless_forced_and_keeps_its_mode() {
        let dir = temp_dir();
        let path = dir.path().join("ro.png");
        fs::write(&path, b"old").unwrap();
        fs::set_permissions(&path, fs::Permissions::from_mode(0o444)).unwrap();
        let err = write_text(&path, false, b"new").unwrap_err();
        assert_eq!(err.to_string(), format!("{}: is read-only", path.display()));
        assert!(err.forceable());
        assert_eq!(fs::read(&path).unwrap(), b"old");
        write_text(&path, true, b"new").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"new");
        let mode = fs::metadata(&path).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o444);
    }

    #[test]
    fn a_replaced_file_keeps_its_permissions_and_a_new_one_is_readable_by_others() {
        let dir = temp_dir();
        let path = dir.path().join("kept.png");
        fs::write(&path, b"old").unwrap();
        fs::set_permissions(&path, fs::Permissions::from_mode(0o640)).unwrap();
        write_text(&path, false, b"new").unwrap();
        assert_eq!(
            fs::metadata(&path).unwrap().permissions().mode() & 0o777,
            0o640
        );
        let fresh = dir.path().join("fresh.png");
        write_text(&fresh, false, b"new").unwrap();
        // 0666 less the umask: never tempfile's private 0600.
        assert_ne!(
            fs::metadata(&fresh).unwrap().permissions().mode() & 0o044,
            0
        );
    }

    #[test]
    fn devices_and_folders_are_refused_and_a_forced_device_is_written_in_place() {
        let err = write_text(Path::new("/dev/null"), false, b"x").unwrap_err();
        assert_eq!(
            err.to_string(),
            "/dev/null: is a character device, not a regular file"
        );
        assert!(err.forceable());
        write_text(Path::new("/dev/null"), true, b"x").unwrap();
        assert!(!fs::metadata("/dev/null").unwrap().file_type().is_file());
        let dir = temp_dir();
        let err = write_text(dir.path(), true, b"x").unwrap_err();
        assert!(!err.forceable() && err.to_string().ends_with("is a folder"));
        let err = write_text(&dir.path().join("no/such/x.png"), false, b"x").unwrap_err();
        assert!(err.to_string().contains("no such folder"), "{err}");
    }

    #[test]
    fn a_pipe_named_through_proc_is_written_in_place_when_forced() {
        // `/dev/stdout` to a pipe is `/proc/self/fd/1`, a link to `pipe:[1234]`: no path.
        use std::io::Read as _;
        use std::os::fd::AsRawFd as _;
        let (mut reader, writer) = std::io::pipe().unwrap();
        let path = PathBuf::from(format!("/proc/self/fd/{}", writer.as_raw_fd()));
        let err = write_text(&path, false, b"x").unwrap_err();
        assert!(err.forceable() && err.to_string().contains("FIFO"), "{err}");
        write_text(&path, true, b"through the pipe").unwrap();
        drop(writer);
        let mut got = String::new();
        reader.read_to_string(&mut got).unwrap();
        assert_eq!(got, "through the pipe");
    }

    #[test]
    fn a_temporary_name_fits_wherever_the_target_name_fits() {
        let dir = temp_dir();
        // 250 bytes: within the 255 every common file system takes; `.NAME.XXXXXX.tmp`
        // would not be.
        let out = dir.path().join(format!("{}.png", "n".repeat(246)));
        write_text(&out, false, b"long").unwrap();
        assert_eq!(fs::read(&out).unwrap(), b"long");
        assert_eq!(names_in(dir.path()).len(), 1);
    }

    #[test]
    fn checking_refuses_a_folder_that_cannot_take_a_file() {
        let err = crate::check(Path::new("/proc/out.png"), true).unwrap_err();
        assert!(
            err.to_string().starts_with(
                "/proc/out.png: cannot write: cannot create a temporary file in /proc"
            ),
            "{err}"
        );
    }

    #[test]
    fn a_dead_writers_temporary_file_is_removed_by_the_next_write() {
        let dir = temp_dir();
        let mut child = std::process::Command::new("true").spawn().unwrap();
        child.wait().unwrap();
        let dead = child.id();
        let me = std::process::id();
        let old = std::time::SystemTime::now() - std::time::Duration::from_secs(600);
        let make = |name: String, modified: Option<std::time::SystemTime>| {
            let f = File::create(dir.path().join(&name)).unwrap();
            if let Some(t) = modified {
                f.set_modified(t).unwrap();
            }
            name
        };
        let stale = make(format!(".big.exr.{dead}.aB3xYz.tmp"), Some(old));
        let running = make(format!(".big.exr.{me}.aB3xYz.tmp"), Some(old));
        let init = make(".big.exr.1.aB3xYz.tmp".to_owned(), Some(old));
        let fresh = make(format!(".big.exr.{dead}.Qq0000.tmp"), None);
        let other = make(format!(".notes.{dead}.tmp"), Some(old));
        write_text(&dir.path().join("out.png"), false, b"new").unwrap();
        let names = names_in(dir.path());
        assert!(!names.contains(&stale), "{names:?}");
        for kept in [running, init, fresh, other, "out.png".to_owned()] {
            assert!(names.contains(&kept), "{kept} in {names:?}");
        }
    }

    #[test]
    fn a_planted_link_at_a_temporary_name_is_never_followed() {
        // Temporary names are random and created exclusively; a link planted at any name
        // the writer could pick is left alone, and so is its target.
        let dir = temp_dir();
        let victim = dir.path().join("victim");
        fs::write(&victim, b"keep").unwrap();
        for i in 0..50 {
            symlink(&victim, dir.path().join(format!(".out.png.{i}.tmp"))).unwrap();
        }
        write_text(&dir.path().join("out.png"), false, b"new").unwrap();
        assert_eq!(fs::read(&victim).unwrap(), b"keep");
        assert_eq!(names_in(dir.path()).len(), 52);
    }
}

#[test]
fn checking_a_path_writes_nothing() {
    let dir = temp_dir();
    let path: PathBuf = dir.path().join("later.png");
    crate::check(&path, false).unwrap();
    assert!(names_in(dir.path()).is_empty());
}
