//! One module per subcommand; each exposes `run(&Args) -> Result<(), CliError>` (`shell` holds
//! `completions` and `man`). This module
//! holds what they share: where the scene comes from, and the frame size and options.

pub mod accuracy;
pub mod bench;
pub mod info;
pub mod render;
pub mod shell;

use phosphor_raster::ShadingMode;
use phosphor_scene::{CullChoice, Scene, ShadingChoice};

use crate::CliError;
use crate::args::{CullArg, ModeArg, SceneSource, Size};

/// Loads the scene a command names: a scene file, a mesh in S1, or the embedded default.
/// Warnings (missing MTL, ignored bump maps, samples cut to the budget) go to stderr, one
/// short line each.
pub fn load_source(source: &SceneSource) -> Result<Scene, CliError> {
    let mut scene = match (&source.scene, &source.mesh) {
        (Some(path), _) => Scene::load(path),
        (None, Some(mesh)) => {
            Scene::s1_lights_with_mesh(mesh, crate::view::normal_options(&source.normals, true)?)
        }
        (None, None) => Scene::default_scene(),
    }
    .map_err(|e| CliError::Input(e.to_string()))?;
    if let Some(cull) = source.cull {
        scene.settings.cull_backfaces = match cull {
            CullArg::Auto => CullChoice::Auto,
            CullArg::Always => CullChoice::Always,
            CullArg::Never => CullChoice::Never,
        };
    }
    if let Some(aa) = source.aa {
        scene.settings.antialias = aa;
    }
    for w in &scene.warnings {
        phosphor_output::term::warn(w);
    }
    Ok(scene)
}

/// The frame size: `--size`, else the scene's `[render]` size.
#[must_use]
pub fn frame_size(scene: &Scene, size: Option<Size>) -> (u32, u32) {
    size.map_or((scene.settings.width, scene.settings.height), |s| {
        (s.width, s.height)
    })
}

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
