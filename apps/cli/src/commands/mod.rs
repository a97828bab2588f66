//! One module per subcommand; each exposes `run(&Args) -> Result<(), CliError>` (`shell` holds
//! `completions` and `man`). This module
//! holds what they share: what set the frame size, and the framebuffer.

pub mod accuracy;
pub mod bench;
pub mod info;
pub mod render;
pub mod shadow_error;
pub mod shell;

use crate::CliError;
use crate::args::{SceneSource, Size};

/// What set a command's image size, for messages: `--size`, or the scene file's `render` table.
#[must_use]
pub fn size_field(source: &SceneSource, size: Option<Size>) -> String {
    match (size, &source.scene) {
        (Some(_), _) => "--size".to_owned(),
        (None, Some(path)) => format!("{}: render.width, render.height", path.display()),
        (None, None) => "the scene's size".to_owned(),
    }
}

/// A framebuffer of the given size, or an input error.
pub fn framebuffer(width: u32, height: u32) -> Result<phosphor_raster::Framebuffer, CliError> {
    phosphor_raster::Framebuffer::new(width, height).map_err(|e| CliError::Input(e.to_string()))
}
