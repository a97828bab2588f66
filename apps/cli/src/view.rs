//! How the scene is looked at: the camera flags and the normal flags of `--mesh`
//! ([`phosphor_args`], shared with the viewer), checked as usage errors, and the scene a
//! command renders: loaded, sized, a `--mesh` framed, the camera flags applied.
//!
//! Every bad value is a usage error (exit 2) on one line naming its flag, found before any file
//! is read where the value alone is at fault.

use phosphor_args::{CameraArgs, NormalArgs, camera_override, check_mesh_path, frame_and_apply};
use phosphor_mesh::NormalOptions;
use phosphor_scene::{CullChoice, Scene};

use crate::CliError;
use crate::args::{CullArg, SceneSource, Size};

/// The normal options `--mesh` builds its mesh with (`mesh`: whether `--mesh` was given).
///
/// # Errors
/// A normal flag without `--mesh`, or a crease angle outside 0..=180 (usage).
pub fn normal_options(args: &NormalArgs, mesh: bool) -> Result<NormalOptions, CliError> {
    phosphor_args::normal_options(args, mesh).map_err(CliError::Usage)
}

/// Loads the scene, sizes the frame, frames a `--mesh` and applies the camera flags: the scene
/// as a command sees it, and the frame's width and height. A scene file's camera is left
/// exactly as written unless a camera flag changes it.
///
/// # Errors
/// Usage errors for bad flags (before any file is read where possible), input errors for the
/// files.
pub fn prepare(
    source: &SceneSource,
    camera: &CameraArgs,
    size: Option<Size>,
) -> Result<(Scene, u32, u32), CliError> {
    let change = camera_override(camera).map_err(CliError::Usage)?;
    normal_options(&source.normals, source.mesh.is_some())?;
    if let Some(mesh) = &source.mesh {
        check_mesh_path(Some("--mesh"), mesh).map_err(CliError::Usage)?;
    }
    let mut scene = load_source(source)?;
    let (width, height) = frame_size(&scene, size);
    let aa = scene.settings.antialias;
    if !aa.fits(width, height) {
        let k = u64::from(aa.factor());
        let what = format!(
            "{aa} at {width}x{height} draws {}x{} samples, over the largest side {}",
            u64::from(width) * k,
            u64::from(height) * k,
            phosphor_raster::framebuffer::MAX_SIDE
        );
        return Err(match (source.aa, &source.scene) {
            (Some(_), _) => CliError::Usage(format!("--aa: {what}")),
            (None, Some(path)) => CliError::Input(format!("{}: render.aa: {what}", path.display())),
            (None, None) => CliError::Input(format!("render.aa: {what}")),
        });
    }
    let frame_mesh = source.scene.is_none() && source.mesh.is_some();
    frame_and_apply(&mut scene, camera, &change, frame_mesh, (width, height))
        .map_err(CliError::Usage)?;
    Ok((scene, width, height))
}

/// Loads the scene a command names: a scene file, a mesh in S1, or the embedded default.
/// Warnings (missing MTL, ignored bump maps, samples cut to the budget) go to stderr, one
/// short line each.
pub fn load_source(source: &SceneSource) -> Result<Scene, CliError> {
    let mut scene = match (&source.scene, &source.mesh) {
        (Some(path), _) => Scene::load(path),
        (None, Some(mesh)) => {
            Scene::s1_lights_with_mesh(mesh, normal_options(&source.normals, true)?)
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
