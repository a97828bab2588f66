//! Bump-map images decoded into the raster crate's maps: height fields from the luminance,
//! and tangent-space normal maps from the RGB channels, of any format the `image` crate
//! reads with the enabled features (PNG, JPEG, OpenEXR). Both keep the texture convention:
//! the image's top row is at `v = 1`.

use std::path::Path;

use glam::Vec3;
use phosphor_raster::BumpMap;

/// The decoded image of `path` from its `bytes`, checked before decoding as every map is
/// ([`crate::textures::decode_image`]), rows from the bottom.
fn image_of(bytes: &[u8], path: &Path) -> Result<image::DynamicImage, String> {
    let img =
        crate::textures::decode_image(bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    // Rows from the bottom: the raster maps put row 0 at v = 0.
    Ok(img.flipv())
}

/// The height field of the image file `path`, from its `bytes` (read by the caller, as every
/// file a scene names: `phosphor_mesh::open`).
///
/// # Errors
/// A message naming the file: an image that does not decode, an empty one, a non-finite scale.
pub(crate) fn decode(bytes: &[u8], path: &Path, scale: f32) -> Result<BumpMap, String> {
    let luma = image_of(bytes, path)?.to_luma32f();
    let (width, height) = luma.dimensions();
    BumpMap::from_heights(luma.into_raw(), width, height, scale)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// The tangent-space normal map of the image file `path`: each texel's channels `c` in
/// `[0, 1]` (not colour-decoded: they are vector components) read as `2 c - 1`, scaled in `x`
/// and `y` by `scale` when drawn (glTF's `normalTexture.scale`, MTL's `norm -bm`).
///
/// # Errors
/// As [`decode`].
pub(crate) fn decode_normals(bytes: &[u8], path: &Path, scale: f32) -> Result<BumpMap, String> {
    let rgb = image_of(bytes, path)?.to_rgb32f();
    let (width, height) = rgb.dimensions();
    let normals = rgb
        .pixels()
        .map(|p| Vec3::from(p.0) * 2.0 - Vec3::ONE)
        .collect();
    BumpMap::from_normals(normals, width, height, scale)
        .map_err(|e| format!("{}: {e}", path.display()))
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
        // Two rows: the top one is v = 1, so it comes last.
        let tall = image::GrayImage::from_raw(1, 2, vec![255, 0]).unwrap();
        let mut png2 = Vec::new();
        tall.write_to(
            &mut std::io::Cursor::new(&mut png2),
            image::ImageFormat::Png,
        )
        .unwrap();
        let BumpMap::Image { heights, .. } = decode(&png2, Path::new("t.png"), 1.0).unwrap() else {
            panic!("an image height field");
        };
        assert_eq!(heights, vec![0.0, 1.0]);
        let e = decode(b"not an image", Path::new("/no/such/bump.png"), 1.0).unwrap_err();
        assert!(e.starts_with("/no/such/bump.png: "), "{e}");
        let e = decode(&png, Path::new("b.png"), f32::INFINITY).unwrap_err();
        assert!(e.starts_with("b.png: ") && e.contains("not finite"), "{e}");
    }

    #[test]
    fn normal_maps_read_channels_as_vectors_bottom_row_first() {
        // Top row: straight up (128, 128, 255); bottom row: leaning to +x (255, 128, 128).
        let img = image::RgbImage::from_raw(1, 2, vec![128, 128, 255, 255, 128, 128]).unwrap();
        let mut png = Vec::new();
        img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        let map = decode_normals(&png, Path::new("n.png"), 0.5).unwrap();
        let BumpMap::Normals {
            normals,
            width,
            height,
            scale,
        } = map
        else {
            panic!("a normal map");
        };
        assert_eq!((width, height, scale), (1, 2, 0.5));
        let lean = Vec3::new(1.0, 0.0039, 0.0039).normalize();
        assert!((normals[0] - lean).length() < 1e-3, "{:?}", normals[0]);
        assert!((normals[1] - Vec3::Z).length() < 1e-2, "{:?}", normals[1]);
        let e = decode_normals(b"nope", Path::new("n.png"), 1.0).unwrap_err();
        assert!(e.starts_with("n.png: "), "{e}");
    }
}
