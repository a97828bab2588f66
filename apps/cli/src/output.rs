//! The CLI's image files, through `phosphor-output`: written whole or not at all, PNG tagged
//! with its encoding, EXR linear, and errors that name the file and the reason. A [`Look`]
//! says how the framebuffer's linear intensities become the file's: exposure, tone curve,
//! and an alpha channel where the background is not opaque.

use std::io::Write as _;
use std::path::Path;

use phosphor_math::glam::Vec3;
use phosphor_output::image::{
    Transfer, encode_png, encode_png_rgba, write_exr, write_exr_rgba, write_png, write_png_rgba,
};
use phosphor_output::{OutputError, check};
use phosphor_raster::encode::Encoder;
use phosphor_raster::{Encoding, Framebuffer, ToneMap};

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

/// How a framebuffer's linear intensities become an image file's values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Look {
    /// PNG's transfer curve (EXR is always linear).
    pub encoding: Encoding,
    /// The exposure's factor `2^EV`, applied to PNG and EXR alike.
    pub scale: f32,
    /// How PNG brings intensities above 1 into `[0, 1]`.
    pub tone_map: ToneMap,
    /// The background's opacity: below 1 the file has an alpha channel.
    pub background_alpha: f32,
}

impl Look {
    /// Today's file: `encoding`, no exposure, clamped, opaque.
    #[must_use]
    pub fn plain(encoding: Encoding) -> Look {
        Look {
            encoding,
            scale: 1.0,
            tone_map: ToneMap::Clamp,
            background_alpha: 1.0,
        }
    }

    /// Whether the file has an alpha channel.
    #[must_use]
    pub fn has_alpha(&self) -> bool {
        self.background_alpha < 1.0
    }

    /// Whether the framebuffer must keep intensities above 1 for a file in `format`: EXR
    /// holds them, and an exposure or a tone curve other than the clamp reads them.
    #[must_use]
    pub fn needs_hdr(&self, format: Format) -> bool {
        format == Format::Exr || self.scale != 1.0 || self.tone_map != ToneMap::Clamp
    }
}

/// What fills an 8-bit row of a PNG: `(y, bytes)`.
type RowFiller<'a> = dyn FnMut(u32, &mut [u8]) + 'a;

/// Fills PNG rows of `fb` as `look` says: [`png_rows`] when it is plain, else RGB or RGBA
/// (4 bytes a pixel where [`Look::has_alpha`]).
fn look_rows<'a>((fb, colour): (&Framebuffer, &'a [Vec3]), look: &Look) -> Box<RowFiller<'a>> {
    let width = fb.width() as usize;
    if *look == Look::plain(look.encoding) {
        return Box::new(png_rows(colour, width, look.encoding));
    }
    let alpha = look.has_alpha().then(|| fb.alpha(look.background_alpha));
    let bytes = if alpha.is_some() { 4 } else { 3 };
    let encoder = Encoder::new(look.encoding);
    let (scale, tone) = (look.scale, look.tone_map);
    Box::new(move |y: u32, line: &mut [u8]| {
        let start = y as usize * width;
        for (i, px) in line.chunks_exact_mut(bytes).enumerate() {
            let at = start + i;
            let a = alpha.as_ref().map_or(1.0, |al| al[at]);
            // The framebuffer holds colour times coverage; PNG's colour is not multiplied by
            // its alpha, so it is divided out (a pixel no surface and no background covers
            // is black).
            let k = if a > 0.0 { scale / a } else { 0.0 };
            let c = colour[at] * k;
            px[0] = encoder.encode(tone.apply(c.x));
            px[1] = encoder.encode(tone.apply(c.y));
            px[2] = encoder.encode(tone.apply(c.z));
            if bytes == 4 {
                // PNG's alpha is linear coverage.
                px[3] = (a * 255.0 + 0.5) as u8;
            }
        }
    })
}

/// Fills PNG rows of `colour` (`width` pixels a row) in `encoding`.
fn png_rows(colour: &[Vec3], width: usize, encoding: Encoding) -> impl FnMut(u32, &mut [u8]) + '_ {
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

/// Writes `fb`, with the colours `colour` (its own, or a copy with an overlay drawn), to `out`
/// as `look` says: PNG (8-bit, tagged, RGBA where the background is
/// not opaque) or EXR (linear f32, premultiplied RGBA where it is not) by extension.
/// `progress` receives the fraction written.
pub fn write_image(
    (fb, colour): (&Framebuffer, &[Vec3]),
    out: &Path,
    look: &Look,
    force: bool,
    progress: &mut dyn FnMut(f64),
) -> Result<(), CliError> {
    let size = (fb.width(), fb.height());
    let width = fb.width() as usize;
    let scale = look.scale;
    let tag = transfer(look.encoding);
    let written = match (format_of(out)?, look.has_alpha()) {
        (Format::Png, false) => {
            let mut row = look_rows((fb, colour), look);
            write_png(out, force, size, tag, &mut row, progress)
        }
        (Format::Png, true) => {
            let mut row = look_rows((fb, colour), look);
            write_png_rgba(out, force, size, tag, &mut row, progress)
        }
        (Format::Exr, false) => {
            let pixel =
                |x: u32, y: u32| (colour[y as usize * width + x as usize] * scale).to_array();
            write_exr(out, force, size, &pixel, progress)
        }
        (Format::Exr, true) => {
            // OpenEXR's colour is premultiplied by its alpha, as the framebuffer's is.
            let alpha = fb.alpha(look.background_alpha);
            let pixel = |x: u32, y: u32| {
                let at = y as usize * width + x as usize;
                let [r, g, b] = (colour[at] * scale).to_array();
                [r, g, b, alpha[at]]
            };
            write_exr_rgba(out, force, size, &pixel, progress)
        }
    };
    written.map_err(|e| input_error(&e))
}

/// Writes `fb` as one PNG (8-bit, tagged, as `look` says) to standard output, and nothing
/// else. The image is encoded whole first, so that a failed encoding writes no bytes.
pub fn write_png_to_stdout(fb: &Framebuffer, colour: &[Vec3], look: &Look) -> Result<(), CliError> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    let mut row = look_rows((fb, colour), look);
    let encode = if look.has_alpha() {
        encode_png_rgba
    } else {
        encode_png
    };
    encode(
        &mut bytes,
        fb.width(),
        fb.height(),
        transfer(look.encoding),
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
