//! Bump-map images decoded into the raster crate's height fields: the luminance of any format
//! the `image` crate reads with the enabled features (PNG, OpenEXR).

use std::path::Path;

use phosphor_raster::BumpMap;

/// The height field of the image file `path`, from its `bytes` (read by the caller, as every
/// file a scene names: `phosphor_mesh::open`); `path` tells the format where the bytes do not.
///
/// # Errors
/// A message naming the file: an image that does not decode, an empty one, a non-finite scale.
pub(crate) fn decode(bytes: &[u8], path: &Path, scale: f32) -> Result<BumpMap, String> {
    let named = |what: &dyn std::fmt::Display| format!("{}: {what}", path.display());
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes));
    match image::ImageFormat::from_path(path) {
        Ok(format) => reader.set_format(format),
        Err(_) => reader = reader.with_guessed_format().map_err(|e| named(&e))?,
    }
    let luma = reader.decode().map_err(|e| named(&e))?.to_luma32f();
    let (width, height) = luma.dimensions();
    if width == 0 || height == 0 {
        return Err(named(&"empty image"));
    }
    BumpMap::from_heights(luma.into_raw(), width, height, scale).map_err(|e| named(&e))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn grey_levels_become_heights_and_errors_name_the_file() {
        let img = image::GrayImage::from_raw(2, 1, vec![0, 255]).unwrap();
        let mut png = Vec::new();
        img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        // No extension: the format is guessed from the bytes.
        let map = decode(&png, Path::new("height"), 0.5).unwrap();
        let BumpMap::Image {
            heights,
            width,
            height,
            scale,
        } = map
        else {
            panic!("an image height field");
        };
        assert_eq!((width, height, scale), (2, 1, 0.5));
        assert!(
            heights[0].abs() < 1e-6 && (heights[1] - 1.0).abs() < 1e-6,
            "{heights:?}"
        );
        let e = decode(b"not an image", Path::new("/no/such/bump.png"), 1.0).unwrap_err();
        assert!(e.starts_with("/no/such/bump.png: "), "{e}");
        let e = decode(&png, Path::new("b.png"), f32::INFINITY).unwrap_err();
        assert!(e.starts_with("b.png: ") && e.contains("not finite"), "{e}");
    }
}
