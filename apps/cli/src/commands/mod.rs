//! One module per subcommand; each exposes `run(&Args) -> Result<(), CliError>` (`shell` holds
//! `completions` and `man`). This module
//! holds what they share: the shading choice, what set the frame size, and the framebuffer.

pub mod accuracy;
pub mod bench;
pub mod info;
pub mod render;
pub mod shell;

use phosphor_raster::ShadingMode;
use phosphor_scene::ShadingChoice;

use crate::CliError;
use crate::args::{ModeArg, SceneSource, Size};

/// A command-line shading choice as the scene crate's.
#[must_use]
pub fn shading_choice(m: ModeArg) -> ShadingChoice {
    match m {
        ModeArg::Flat => ShadingChoice::Mode(ShadingMode::Flat),
        ModeArg::Gouraud => ShadingChoice::Mode(ShadingMode::Gouraud),
        ModeArg::Phong => ShadingChoice::Mode(ShadingMode::Phong),
        ModeArg::FastPhong => ShadingChoice::Mode(ShadingMode::FastPhong),
        ModeArg::Reference => ShadingChoice::Mode(ShadingMode::Reference),
        ModeArg::Auto => ShadingChoice::Auto,
    }
}

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
