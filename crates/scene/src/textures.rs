//! Colour maps: image bytes decoded to a [`Texture`] (PNG or JPEG, sRGB to linear, mipmaps
//! built once), with the size checked from the header before any texel is decoded.

use std::io::Cursor;
use std::path::PathBuf;
use std::sync::Arc;

use phosphor_raster::texture::{MAX_TEXTURE_SIDE, Texture, Wrap};

/// Most memory one decoded texture may take with its mipmaps: 2 GiB, past an 8192 x 8192
/// image (1.4 GiB); a larger image is refused before it is decoded.
pub const MAX_TEXTURE_BYTES: u64 = 2 << 30;

/// Where a scene material's colour map (`kd_map`) comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum MapSource {
    /// An image file: `kd_map = "wood.png"`, repeating.
    File {
        /// The name as written (for messages).
        written: String,
        /// The file, resolved against the scene file's folder.
        resolved: PathBuf,
    },
    /// A checkerboard made here: `kd_map = { procedural = "checker", squares = 8 }`, white
    /// and a dark grey (linear 0.25), `squares` squares along each side of the `[0, 1]` uv
    /// square, each 64 texels wide (fewer past 32 squares, so the image stays within 2048
    /// texels a side).
    Checker {
        /// Squares along a side.
        squares: u32,
    },
}

/// An object's colour map (present only on objects that have one).
#[derive(Debug, Clone)]
pub struct ColorMap(pub Arc<Texture>);

/// Decodes `bytes` (a PNG or JPEG) into a texture wrapping as `wrap`.
///
/// # Errors
/// An unknown format, a header that cannot be read, a side over
/// [`MAX_TEXTURE_SIDE`], more than [`MAX_TEXTURE_BYTES`] decoded, or a decoding error; the
/// message is for the caller to prefix with the file and material.
pub fn decode(bytes: &[u8], wrap: (Wrap, Wrap)) -> Result<Texture, String> {
    let img = decode_image(bytes)?.into_rgb8();
    let t = Texture::from_srgb8(img.width(), img.height(), 3, img.as_raw())
        .map_err(|e| e.to_string())?;
    Ok(t.with_wrap(wrap.0, wrap.1))
}

/// The image in `bytes` (its format guessed from them), refused from its header alone when a
/// side is 0 or over [`MAX_TEXTURE_SIDE`] or its texture would take over
/// [`MAX_TEXTURE_BYTES`]: every map, colour or bump, is checked before it is decoded.
pub(crate) fn decode_image(bytes: &[u8]) -> Result<image::DynamicImage, String> {
    let reader = image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    if reader.format().is_none() {
        return Err("not an image format Phosphor reads (PNG, JPEG, OpenEXR)".to_owned());
    }
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| format!("cannot read the image header: {e}"))?;
    if w == 0 || h == 0 || w > MAX_TEXTURE_SIDE || h > MAX_TEXTURE_SIDE {
        return Err(format!(
            "{w}x{h}: each side must be 1 to {MAX_TEXTURE_SIDE} texels"
        ));
    }
    let need = Texture::bytes_for(w, h);
    if need > MAX_TEXTURE_BYTES {
        return Err(format!(
            "{w}x{h} needs {} MiB decoded, over the {} MiB a texture may take",
            need >> 20,
            MAX_TEXTURE_BYTES >> 20
        ));
    }
    let mut reader = image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(w);
    limits.max_image_height = Some(h);
    limits.max_alloc = Some(MAX_TEXTURE_BYTES);
    reader.limits(limits);
    reader.decode().map_err(|e| e.to_string())
}

/// The raster's wrap mode for a mesh file's.
#[must_use]
pub fn wrap_of(w: phosphor_mesh::Wrap) -> Wrap {
    match w {
        phosphor_mesh::Wrap::Repeat => Wrap::Repeat,
        phosphor_mesh::Wrap::ClampToEdge => Wrap::Clamp,
        phosphor_mesh::Wrap::MirroredRepeat => Wrap::Mirror,
    }
}

/// A procedural checkerboard of `squares x squares` squares, `texels` texels each, in the
/// two linear colours `a` and `b`: the default scene's floor, made here rather than shipped.
#[must_use]
pub fn checkerboard(squares: u32, texels: u32, a: glam::Vec3, b: glam::Vec3) -> Texture {
    let n = (squares * texels).clamp(1, MAX_TEXTURE_SIDE);
    let texels = (0..n * n)
        .map(|k| {
            let (i, j) = ((k % n) / texels.max(1), (k / n) / texels.max(1));
            if (i + j) % 2 == 0 { a } else { b }
        })
        .collect();
    // The size is within bounds and the texel count matches by construction.
    Texture::new(n, n, texels).unwrap_or_else(|_| {
        Texture::new(1, 1, vec![a]).unwrap_or_else(|_| unreachable!("a 1x1 texture is valid"))
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    fn png(w: u32, h: u32, rgb: [u8; 3]) -> Vec<u8> {
        let img = image::RgbImage::from_pixel(w, h, image::Rgb(rgb));
        let mut out = Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    }

    fn crc32(data: &[u8]) -> u32 {
        let mut c = !0u32;
        for &b in data {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 == 1 {
                    (c >> 1) ^ 0xEDB8_8320
                } else {
                    c >> 1
                };
            }
        }
        !c
    }

    #[test]
    fn a_png_decodes_to_linear_values() {
        let t = decode(&png(4, 2, [255, 188, 0]), (Wrap::Repeat, Wrap::Clamp)).unwrap();
        assert_eq!(t.size(), (4, 2));
        let c = t.texel(0, 0, 0);
        assert_eq!(c.x, 1.0);
        assert!((c.y - 0.5029).abs() < 1e-3, "{c}");
    }

    #[test]
    fn a_jpeg_decodes() {
        let img = image::RgbImage::from_pixel(8, 8, image::Rgb([128, 128, 128]));
        let mut out = Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Jpeg).unwrap();
        let t = decode(out.get_ref(), (Wrap::Repeat, Wrap::Repeat)).unwrap();
        assert!((t.texel(0, 3, 3).x - 0.2158).abs() < 0.01);
    }

    #[test]
    fn bad_and_huge_images_are_refused_before_decoding() {
        assert!(decode(b"not an image", (Wrap::Repeat, Wrap::Repeat)).is_err());
        // A PNG header claiming 16384 x 16384: refused from the header alone.
        let mut bytes = png(1, 1, [0, 0, 0]);
        bytes[16..20].copy_from_slice(&16384u32.to_be_bytes());
        bytes[20..24].copy_from_slice(&16384u32.to_be_bytes());
        // The header chunk's CRC over its type and data.
        let crc = crc32(&bytes[12..29]);
        bytes[29..33].copy_from_slice(&crc.to_be_bytes());
        let e = decode(&bytes, (Wrap::Repeat, Wrap::Repeat)).unwrap_err();
        assert!(e.contains("16384x16384"), "{e}");
    }
}
