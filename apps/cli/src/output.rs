//! The CLI's image files, through `phosphor-output`: written whole or not at all, PNG tagged
//! with its encoding, EXR linear, and errors that name the file and the reason.

use std::io::Write as _;
use std::path::Path;

use phosphor_output::image::{Transfer, encode_png, write_exr, write_png};
use phosphor_output::{OutputError, check};
use phosphor_raster::encode::Encoder;
use phosphor_raster::{Encoding, Framebuffer};

use crate::CliError;
use crate::rgb8::Rgb8Image;

/// An output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// 8-bit PNG, sRGB or linear.
    Png,
    /// Linear f32 OpenEXR.
    Exr,
}

/// The format of `path`: its extension; a device or FIFO without one (`-o /dev/stdout
/// --force`) gets PNG. Anything else is a usage error.
pub fn format_of(path: &Path) -> Result<Format, CliError> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("png") => Ok(Format::Png),
        Some("exr") => Ok(Format::Exr),
        None if std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) => {
            Ok(Format::Png)
        }
        _ => Err(CliError::Usage(format!(
            "{}: output must end in .png or .exr",
            path.display()
        ))),
    }
}

/// An output error as the CLI reports it: one line naming the file, with the flag that
/// overrides a refusal.
fn input_error(e: &OutputError) -> CliError {
    if e.forceable() {
        CliError::Input(format!("{e} (--force writes it anyway)"))
    } else {
        CliError::Input(e.to_string())
    }
}

/// Whether `out` is the file standard output writes to (`-o /dev/stdout`, or a file stdout
/// is redirected to): then the image is all that may go there, and the command's own lines
/// go to stderr.
#[must_use]
pub fn is_stdout(out: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::fd::AsFd as _;
        use std::os::unix::fs::MetadataExt as _;
        let Ok(fd) = std::io::stdout().as_fd().try_clone_to_owned() else {
            return false;
        };
        let (Ok(stdout), Ok(target)) = (std::fs::File::from(fd).metadata(), std::fs::metadata(out))
        else {
            return false;
        };
        (stdout.dev(), stdout.ino()) == (target.dev(), target.ino())
    }
    #[cfg(not(unix))]
    {
        let _ = out;
        false
    }
}

/// Checks before any work that `out` may be written and has a known format.
pub fn check_output(out: &Path, force: bool) -> Result<Format, CliError> {
    check(out, force).map_err(|e| input_error(&e))?;
    format_of(out)
}

/// The PNG tag of an encoding.
fn transfer(encoding: Encoding) -> Transfer {
    match encoding {
        Encoding::Srgb => Transfer::Srgb,
        Encoding::Linear => Transfer::Linear,
    }
}

/// Fills PNG rows of `fb` in `encoding`.
fn png_rows(fb: &Framebuffer, encoding: Encoding) -> impl FnMut(u32, &mut [u8]) + '_ {
    let width = fb.width() as usize;
    let colour = fb.color();
    let encoder = Encoder::new(encoding);
    move |y: u32, line: &mut [u8]| {
        let start = y as usize * width;
        for (px, c) in line.chunks_exact_mut(3).zip(&colour[start..start + width]) {
            px.copy_from_slice(&[
                encoder.encode(c.x),
                encoder.encode(c.y),
                encoder.encode(c.z),
            ]);
        }
    }
}

/// Writes `fb` to `out`: PNG (8-bit, `encoding`, tagged) or EXR (linear f32) by extension.
/// `progress` receives the fraction written.
pub fn write_image(
    fb: &Framebuffer,
    out: &Path,
    encoding: Encoding,
    force: bool,
    progress: &mut dyn FnMut(f64),
) -> Result<(), CliError> {
    let size = (fb.width(), fb.height());
    let width = fb.width() as usize;
    let colour = fb.color();
    let written = match format_of(out)? {
        Format::Png => {
            let mut row = png_rows(fb, encoding);
            write_png(out, force, size, transfer(encoding), &mut row, progress)
        }
        Format::Exr => {
            let pixel = |x: u32, y: u32| colour[y as usize * width + x as usize].to_array();
            write_exr(out, force, size, &pixel, progress)
        }
    };
    written.map_err(|e| input_error(&e))
}

/// Writes `fb` as one PNG (8-bit, `encoding`, tagged) to standard output, and nothing else.
/// The image is encoded whole first, so that a failed encoding writes no bytes.
pub fn write_png_to_stdout(fb: &Framebuffer, encoding: Encoding) -> Result<(), CliError> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    let mut row = png_rows(fb, encoding);
    encode_png(
        &mut bytes,
        fb.width(),
        fb.height(),
        transfer(encoding),
        &mut row,
        &mut |_| {},
    )
    .map_err(|e| CliError::Input(format!("standard output: {e}")))?;
    let mut stdout = std::io::stdout().lock();
    stdout
        .write_all(bytes.get_ref())
        .and_then(|()| stdout.flush())
        .map_err(|e| CliError::Input(format!("standard output: cannot write: {e}")))
}

/// Writes an 8-bit sRGB image (a heat-map, a plot) to `out` as PNG.
pub fn write_rgb8(out: &Path, img: &Rgb8Image, force: bool) -> Result<(), CliError> {
    let stride = img.width as usize * 3;
    let mut row = |y: u32, line: &mut [u8]| {
        let start = y as usize * stride;
        line.copy_from_slice(&img.data[start..start + stride]);
    };
    write_png(
        out,
        force,
        (img.width, img.height),
        Transfer::Srgb,
        &mut row,
        &mut |_| {},
    )
    .map_err(|e| input_error(&e))
}

/// Writes `bytes` (a CSV table) to `out`, whole or not at all, as every output is.
pub fn write_bytes(out: &Path, bytes: &[u8], force: bool) -> Result<(), CliError> {
    phosphor_output::write_file(out, force, |sink| {
        sink.write_all(bytes).map_err(|e| e.to_string())
    })
    .map_err(|e| input_error(&e))
}
