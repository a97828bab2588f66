//! `phosphor-viewer`: the real-time window onto a Phosphor scene.
//!
//! ```text
//! phosphor-viewer [SCENE.toml] [--mesh FILE.obj] [--size WxH] [--shading MODE] [--frames N --screenshot FILE.png]
//!                 [--eye X,Y,Z --target X,Y,Z --up X,Y,Z --fov DEG | --azimuth DEG --elevation DEG --distance D]
//!                 [--view front|back|left|right|top|bottom|iso] [--ortho]
//!                 [--crease-angle DEG --normals file|computed --weighting uniform|area|angle]
//! ```
//!
//! `C` prints the current camera as a `[camera]` block for a scene file; `S` saves a screenshot
//! beside the scene file; `O` switches to an orthographic projection and back, `V` steps
//! through the standard views.
//!
//! This file starts the viewer: the command line (`args.rs`), the scene, the window. What is
//! drawn and how the title describes it is in `viewer.rs`, what the keys do in `actions.rs`,
//! the window plumbing in `window.rs`, the camera and key table in `input.rs`.

mod actions;
mod args;
mod input;
mod view;
mod viewer;
mod window;

use std::process::ExitCode;

use clap::{CommandFactory, Parser};
use phosphor_output::{memory, term};
use phosphor_raster::Antialias;
use phosphor_scene::{Scene, ShadingChoice};

use crate::args::Args;
use crate::input::key_help;
use crate::viewer::{DEFAULT_STILL_ANTIALIAS, Viewer, bytes_per_pixel};
use crate::window::{WindowError, WindowOptions};

/// Window size when neither `--size` nor the scene gives one.
const DEFAULT_SIZE: (u32, u32) = (960, 540);

/// The scene named on the command line (a `--mesh` under S1's lights, with the normals its
/// flags ask for), or the embedded default.
fn load(args: &Args, normals: phosphor_mesh::NormalOptions) -> Result<Scene, String> {
    let scene = match (&args.scene, &args.mesh) {
        (Some(p), _) => Scene::load(p),
        (None, Some(m)) => Scene::s1_lights_with_mesh(m, normals),
        (None, None) => Scene::default_scene(),
    }
    .map_err(|e| e.to_string())?;
    for w in &scene.warnings {
        term::warn(w);
    }
    Ok(scene)
}

/// One `error:` line on stderr and exit status 1.
/// The message when no display can be reached, one sentence: the platform's reason (its own
/// closing full stop dropped, so the sentence does not end twice) and what to do instead.
fn no_display(why: &str) -> String {
    let why = why.trim().trim_end_matches(['.', ';', ':']).trim_end();
    if why.is_empty() {
        "no display available; use `phosphor render` to render to a file".to_owned()
    } else {
        format!("no display available: {why}; use `phosphor render` to render to a file")
    }
}

fn fail(message: &str) -> ExitCode {
    term::tell(&format!("error: {message}"));
    ExitCode::from(1)
}

fn main() -> ExitCode {
    // Usage errors: one line naming the flag, exit 2; --help and --version: stdout, exit 0.
    let args = phosphor_args::usage::parse_or_exit(Args::try_parse(), &Args::command());
    let usage = |e: String| {
        term::tell(&format!("error: {e}"));
        ExitCode::from(2)
    };
    let (change, normals) = match (
        phosphor_args::camera_override(&args.camera),
        phosphor_args::normal_options(&args.normals, args.mesh.is_some()),
    ) {
        (Ok(c), Ok(n)) => (c, n),
        (Err(e), _) | (_, Err(e)) => return usage(e),
    };
    if let Some(mesh) = &args.mesh
        && let Err(e) = phosphor_args::check_mesh_path(Some("--mesh"), mesh)
    {
        return usage(e);
    }
    if let Some(path) = &args.screenshot {
        // A refused screenshot is said before the window opens, not after the frames.
        if let Err(e) = phosphor_output::check(path, args.force) {
            return fail(&if e.forceable() {
                format!("{e} (--force writes it anyway)")
            } else {
                e.to_string()
            });
        }
    }
    let size = args.size.unwrap_or(DEFAULT_SIZE);
    let field = if args.size.is_some() {
        "--size"
    } else {
        "the window size"
    };
    let aa_bytes = bytes_per_pixel(args.aa.unwrap_or(Antialias::Off));
    if let Err(e) = memory::check_image(field, size, aa_bytes) {
        return fail(&e);
    }
    let mut scene = match load(&args, normals) {
        Ok(s) => s,
        Err(e) => return fail(&e),
    };
    if let Some(background) = args.background {
        background.apply(&mut scene);
    }
    let size = args.size.unwrap_or(DEFAULT_SIZE);
    let frame_mesh = args.scene.is_none() && args.mesh.is_some();
    if let Err(e) =
        phosphor_args::frame_and_apply(&mut scene, &args.camera, &change, frame_mesh, size)
    {
        return usage(e);
    }
    let mut viewer = Viewer::new(scene);
    viewer.window_size = size;
    viewer.scene_file = args.scene.clone();
    viewer.mesh_file = args.mesh.clone();
    viewer.shading = args.shading.filter(|s| *s != ShadingChoice::Auto);
    viewer.force = args.force;
    viewer.fixed_frames = args.frames.is_some();
    viewer.shadows = args.shadows;
    viewer.antialias = match args.aa {
        Some(aa) => aa,
        // Frames for measurements and screenshots draw what the scene asks for; a person
        // looking gets a smooth still picture.
        None if viewer.fixed_frames || viewer.antialias != Antialias::Off => viewer.antialias,
        None => DEFAULT_STILL_ANTIALIAS,
    };
    // The scene file's `aa` is known only now; the default still picture's is dropped, not
    // refused, where memory is short.
    if let Err(e) = memory::check_image(field, size, bytes_per_pixel(viewer.antialias)) {
        if args.aa.is_some() || viewer.fixed_frames {
            return fail(&e);
        }
        viewer.antialias = Antialias::Off;
    }
    if args.frames.is_none() {
        term::say(&key_help());
    }
    let options = WindowOptions {
        size,
        frames: args.frames.or(args.screenshot.as_ref().map(|_| 1)),
        screenshot: args.screenshot,
    };
    let frames_mode = options.frames.is_some();
    match window::run(viewer, options) {
        Ok(viewer) => {
            if frames_mode && viewer.frames > 0 {
                let mean = viewer.total_ms / f64::from(viewer.frames);
                term::say(&format!(
                    "frames={} mean_ms={mean:.2} fps={:.1} triangles={}",
                    viewer.frames,
                    1e3 / mean.max(1e-3),
                    viewer.triangles
                ));
            }
            term::finish_stdout();
            ExitCode::SUCCESS
        }
        Err(WindowError::NoDisplay(why)) => fail(&no_display(&why)),
        Err(WindowError::Failed(why)) => fail(&why),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_no_display_message_is_one_clean_sentence() {
        assert_eq!(
            no_display("neither WAYLAND_DISPLAY nor DISPLAY is set."),
            "no display available: neither WAYLAND_DISPLAY nor DISPLAY is set; use \
             `phosphor render` to render to a file"
        );
        assert!(!no_display("x.").contains(".;"));
        assert_eq!(
            no_display(" "),
            "no display available; use `phosphor render` to render to a file"
        );
    }
}
