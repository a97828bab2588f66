//! Image encoders writing into a [`Sink`]: 8-bit RGB or RGBA PNG tagged with its transfer
//! curve, and linear f32 RGB or RGBA OpenEXR. Both take pixels row by row or pixel by pixel from the caller, so
//! no second copy of a large image is made. The callbacks are trait objects so that the
//! encoders' loops are compiled (and optimised) here, not in each caller.

use std::path::Path;

use crate::file::{OutputError, Sink, write_file};

/// How 8-bit PNG codes relate to light, and the colour tags that say so, so that image
/// viewers show the picture as the renderer's window does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transfer {
    /// The sRGB curve (IEC 61966-2-1): `sRGB` chunk, with the `gAMA` (1/2.2) and `cHRM`
    /// fallbacks for older readers, and `cICP` (BT.709 primaries, sRGB transfer).
    Srgb,
    /// Codes proportional to intensity: `gAMA` of 1.0 (stored as 100000), sRGB's primaries in
    /// `cHRM`, and `cICP` (BT.709 primaries, linear transfer).
    Linear,
}

/// `cICP` code points (ITU-T H.273): colour primaries 1 (BT.709, those of sRGB), transfer
/// 13 (sRGB) or 8 (linear), matrix 0 (RGB), full range.
fn cicp(transfer: Transfer) -> [u8; 4] {
    match transfer {
        Transfer::Srgb => [1, 13, 0, 1],
        Transfer::Linear => [1, 8, 0, 1],
    }
}

/// Rows encoded per progress report.
const ROWS_PER_REPORT: u32 = 16;

/// Encodes an 8-bit RGB PNG of `width` x `height` into `sink`. `row(y, out)` fills row `y`
/// (`out.len() == 3 * width`); `progress` receives the fraction of rows done.
///
/// # Errors
/// The encoder's message (an I/O failure of `sink` included).
pub fn encode_png(
    sink: &mut dyn Sink,
    width: u32,
    height: u32,
    transfer: Transfer,
    row: &mut dyn FnMut(u32, &mut [u8]),
    progress: &mut dyn FnMut(f64),
) -> Result<(), String> {
    encode_png_channels(sink, (width, height, 3), transfer, row, progress)
}

/// [`encode_png`] with an alpha channel: 8-bit RGBA, `row(y, out)` filling
/// `out.len() == 4 * width` bytes. Alpha is linear coverage (PNG's is never gamma-encoded)
/// and the colour is not premultiplied by it, as PNG defines.
///
/// # Errors
/// The encoder's message (an I/O failure of `sink` included).
pub fn encode_png_rgba(
    sink: &mut dyn Sink,
    width: u32,
    height: u32,
    transfer: Transfer,
    row: &mut dyn FnMut(u32, &mut [u8]),
    progress: &mut dyn FnMut(f64),
) -> Result<(), String> {
    encode_png_channels(sink, (width, height, 4), transfer, row, progress)
}

/// [`encode_png`] with 3 (RGB) or 4 (RGBA) channels.
fn encode_png_channels(
    sink: &mut dyn Sink,
    (width, height, channels): (u32, u32, usize),
    transfer: Transfer,
    row: &mut dyn FnMut(u32, &mut [u8]),
    progress: &mut dyn FnMut(f64),
) -> Result<(), String> {
    let mut encoder = png::Encoder::new(sink, width, height);
    encoder.set_color(if channels == 4 {
        png::ColorType::Rgba
    } else {
        png::ColorType::Rgb
    });
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    match transfer {
        Transfer::Srgb => {
            encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
            // Written beside sRGB only when set to exactly these fallback values.
            encoder.set_source_gamma(png::ScaledFloat::from_scaled(45_455));
            encoder.set_source_chromaticities(srgb_chromaticities());
        }
        Transfer::Linear => {
            encoder.set_source_gamma(png::ScaledFloat::from_scaled(100_000));
            encoder.set_source_chromaticities(srgb_chromaticities());
        }
    }
    let png_error = |e: png::EncodingError| format!("PNG encoder: {e}");
    let mut writer = encoder.write_header().map_err(png_error)?;
    writer
        .write_chunk(png::chunk::cICP, &cicp(transfer))
        .map_err(png_error)?;
    let mut stream = writer.stream_writer().map_err(png_error)?;
    let mut line = vec![0u8; width as usize * channels];
    for y in 0..height {
        row(y, &mut line);
        std::io::Write::write_all(&mut stream, &line).map_err(|e| e.to_string())?;
        if (y + 1) % ROWS_PER_REPORT == 0 {
            progress(f64::from(y + 1) / f64::from(height));
        }
    }
    stream.finish().map_err(png_error)?;
    progress(1.0);
    Ok(())
}

/// The sRGB (BT.709) primaries and D65 white point.
fn srgb_chromaticities() -> png::SourceChromaticities {
    let s = png::ScaledFloat::from_scaled;
    png::SourceChromaticities {
        white: (s(31_270), s(32_900)),
        red: (s(64_000), s(33_000)),
        green: (s(30_000), s(60_000)),
        blue: (s(15_000), s(6_000)),
    }
}

/// The EXR encoder's error as a message: an I/O failure of the sink as itself.
fn exr_error(e: exr::error::Error) -> String {
    match e {
        exr::error::Error::Io(io) => io.to_string(),
        other => format!("EXR encoder: {other}"),
    }
}

/// Encodes a linear f32 RGB OpenEXR of `width` x `height` into `sink`; `pixel(x, y)` gives the
/// colour at column `x`, row `y` (row 0 at the top); `progress` receives the fraction done.
///
/// # Errors
/// The encoder's message (an I/O failure of `sink` included).
pub fn encode_exr(
    sink: &mut dyn Sink,
    width: u32,
    height: u32,
    pixel: &(dyn Fn(u32, u32) -> [f32; 3] + Sync),
    progress: &mut dyn FnMut(f64),
) -> Result<(), String> {
    use exr::prelude::{Image, SpecificChannels, Vec2, WritableImage};
    let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
        // Positions are below width and height, which are u32.
        let [r, g, b] = pixel(p.x() as u32, p.y() as u32);
        (r, g, b)
    });
    Image::from_channels((width as usize, height as usize), channels)
        .write()
        .non_parallel()
        .on_progress(progress)
        .to_buffered(sink)
        .map_err(exr_error)
}

/// Encodes a linear f32 RGBA OpenEXR: [`encode_exr`] with alpha, `pixel(x, y)` giving
/// `[r, g, b, a]` with the colour premultiplied by `a`, as OpenEXR defines.
///
/// # Errors
/// The encoder's message (an I/O failure of `sink` included).
pub fn encode_exr_rgba(
    sink: &mut dyn Sink,
    width: u32,
    height: u32,
    pixel: &(dyn Fn(u32, u32) -> [f32; 4] + Sync),
    progress: &mut dyn FnMut(f64),
) -> Result<(), String> {
    use exr::prelude::{Image, SpecificChannels, Vec2, WritableImage};
    let channels = SpecificChannels::rgba(|p: Vec2<usize>| {
        // Positions are below width and height, which are u32.
        let [r, g, b, a] = pixel(p.x() as u32, p.y() as u32);
        (r, g, b, a)
    });
    Image::from_channels((width as usize, height as usize), channels)
        .write()
        .non_parallel()
        .on_progress(progress)
        .to_buffered(sink)
        .map_err(exr_error)
}

/// Writes an 8-bit RGB PNG to `path` through [`write_file`]; see [`encode_png`].
///
/// # Errors
/// As [`write_file`].
pub fn write_png(
    path: &Path,
    force: bool,
    (width, height): (u32, u32),
    transfer: Transfer,
    row: &mut dyn FnMut(u32, &mut [u8]),
    progress: &mut dyn FnMut(f64),
) -> Result<(), OutputError> {
    write_file(path, force, |sink| {
        encode_png(sink, width, height, transfer, row, progress)
    })
}

/// Writes a linear f32 RGB OpenEXR to `path` through [`write_file`]; see [`encode_exr`].
///
/// # Errors
/// As [`write_file`].
pub fn write_exr(
    path: &Path,
    force: bool,
    (width, height): (u32, u32),
    pixel: &(dyn Fn(u32, u32) -> [f32; 3] + Sync),
    progress: &mut dyn FnMut(f64),
) -> Result<(), OutputError> {
    write_file(path, force, |sink| {
        encode_exr(sink, width, height, pixel, progress)
    })
}

/// Writes an 8-bit RGBA PNG to `path` through [`write_file`]; see [`encode_png_rgba`].
///
/// # Errors
/// As [`write_file`].
pub fn write_png_rgba(
    path: &Path,
    force: bool,
    (width, height): (u32, u32),
    transfer: Transfer,
    row: &mut dyn FnMut(u32, &mut [u8]),
    progress: &mut dyn FnMut(f64),
) -> Result<(), OutputError> {
    write_file(path, force, |sink| {
        encode_png_rgba(sink, width, height, transfer, row, progress)
    })
}

/// Writes a linear f32 RGBA OpenEXR to `path` through [`write_file`]; see
/// [`encode_exr_rgba`].
///
/// # Errors
/// As [`write_file`].
pub fn write_exr_rgba(
    path: &Path,
    force: bool,
    (width, height): (u32, u32),
    pixel: &(dyn Fn(u32, u32) -> [f32; 4] + Sync),
    progress: &mut dyn FnMut(f64),
) -> Result<(), OutputError> {
    write_file(path, force, |sink| {
        encode_exr_rgba(sink, width, height, pixel, progress)
    })
}
