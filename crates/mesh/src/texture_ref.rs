//! References to texture images named by a material: a file or bytes embedded in the mesh
//! file, and how the image repeats outside `[0, 1]`. Nothing here decodes an image: the
//! caller (the scene) decodes the image a [`TextureRef`] names, whose bytes
//! [`TextureSource::bytes`] reads as every input file is read ([`crate::open`]).

use std::io;
use std::path::PathBuf;
use std::sync::Arc;

use crate::open::read_file;

/// Largest texture image file read, in bytes: 256 MiB, past a 16384 x 16384 PNG of photo
/// content; an image is encoded, so its decoded size is the decoder's to bound.
pub const MAX_IMAGE_BYTES: u64 = 256 << 20;

/// What a texture lookup does with a coordinate outside `[0, 1]`, per axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image tiles (OBJ's default, glTF `REPEAT`).
    #[default]
    Repeat,
    /// The edge texel extends outwards (MTL `-clamp on`, glTF `CLAMP_TO_EDGE`).
    ClampToEdge,
    /// The image tiles, every other copy mirrored (glTF `MIRRORED_REPEAT`).
    MirroredRepeat,
}

/// Where a texture image's bytes are.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TextureSource {
    /// A file, already resolved against the folder of the file that named it (the MTL file,
    /// the `.gltf` file, whose images stay in its folder as its buffers do:
    /// [`crate::assets::asset_path`]); not read yet, so it may not exist.
    File(PathBuf),
    /// Bytes inside the mesh file (a glTF `data:` URI or a buffer view of a GLB), still encoded.
    Embedded {
        /// The image's name, else `images[N]`.
        name: String,
        /// The media type the file gives (`image/png`, `image/jpeg`), if any.
        mime: Option<String>,
        /// The encoded image, shared by every material that uses it.
        bytes: Arc<[u8]>,
    },
}

/// A texture image as a material names it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextureRef {
    /// Where the image is.
    pub source: TextureSource,
    /// Wrapping along `u`.
    pub wrap_u: Wrap,
    /// Wrapping along `v`.
    pub wrap_v: Wrap,
    /// The reference as the file wrote it (a file name, `images[2]`), for messages.
    pub written: String,
}

impl TextureSource {
    /// The encoded image: the embedded bytes, or the file's, read as a regular file of at most
    /// [`MAX_IMAGE_BYTES`] opened without blocking ([`crate::open::read_file`]).
    ///
    /// # Errors
    /// The file is missing, not a regular file, over the cap, or unreadable; the message
    /// says which, for the caller to prefix with the file's name.
    pub fn bytes(&self) -> io::Result<Arc<[u8]>> {
        match self {
            TextureSource::File(path) => read_file(path, MAX_IMAGE_BYTES).map(Arc::from),
            TextureSource::Embedded { bytes, .. } => Ok(bytes.clone()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_image_file_is_read_as_every_input_is() {
        let e = TextureSource::File(std::env::temp_dir())
            .bytes()
            .expect_err("a folder");
        assert_eq!(e.to_string(), "a folder, not a regular file");
        let bytes: Arc<[u8]> = Arc::from(&[1u8, 2][..]);
        let embedded = TextureSource::Embedded {
            name: "images[0]".to_owned(),
            mime: None,
            bytes: bytes.clone(),
        };
        assert!(Arc::ptr_eq(&embedded.bytes().expect("embedded"), &bytes));
    }
}
