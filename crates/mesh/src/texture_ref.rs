//! References to texture images named by a material: a file or bytes embedded in the mesh
//! file, and how the image repeats outside `[0, 1]`. Nothing here decodes an image: the
//! caller (the scene) reads and decodes the image a [`TextureRef`] names.

use std::path::PathBuf;
use std::sync::Arc;

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
    /// the `.gltf` file); not read yet, so it may not exist.
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
