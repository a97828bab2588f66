//! The 8-bit RGB image that the heat-maps, plots and labels are drawn into and written from.

/// An 8-bit RGB image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rgb8Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major RGB bytes, `width * height * 3` of them.
    pub data: Vec<u8>,
}
