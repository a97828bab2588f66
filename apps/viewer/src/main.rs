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
mod watch;
mod window;

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{CommandFactory, Parser};
use phosphor_output::{memory, term};
use phosphor_raster::Antialias;
use phosphor_scene::view::CameraOverride;
use phosphor_scene::{Scene, ShadingChoice};

use crate::args::Args;
use crate::input::key_help;
use crate::viewer::{DEFAULT_STILL_ANTIALIAS, Reload, Viewer, bytes_per_pixel};
use crate::window::{WindowError, WindowOptions};

/// Window size when neither `--size` nor the scene gives one.
const DEFAULT_SIZE: (u32, u32) = (960, 540);

/// Why [`load`] made no scene.
enum Failure {
    /// A camera flag that cannot be applied (exit status 2).
    Usage(String),
    /// The scene or mesh could not be loaded (exit status 1).
    Load(String),
}

impl Failure {
    fn message(self) -> String {
        match self {
            Failure::Usage(e) | Failure::Load(e) => e,
        }
    }
}

/// What the command line asks to show, as [`load`] makes it.
struct Source {
    scene: Option<PathBuf>,
    mesh: Option<PathBuf>,
    normals: phosphor_mesh::NormalOptions,
    background: Option<phosphor_args::Background>,
    camera: phosphor_args::CameraArgs,
    change: CameraOverride,
    size: (u32, u32),
}

/// The scene named on the command line (a `--mesh` under S1's lights, with the normals its
/// flags ask for), or the embedded default, with the background and camera flags applied and
/// its warnings printed; and the files it was made from, for live reload (none for the
/// embedded scene).
fn load(src: &Source) -> (Result<Scene, Failure>, BTreeSet<PathBuf>) {
    let (scene, files) = match (&src.scene, &src.mesh) {
        (Some(p), _) => phosphor_scene::load_scene_noting(p),
        (None, Some(m)) => {
            let scene = Scene::s1_lights_with_mesh(m, src.normals);
            let mut files = BTreeSet::from([m.clone()]);
            if let Ok(scene) = &scene {
                files.extend(phosphor_scene::image_files(scene));
            }
            (scene, files)
        }
        (None, None) => (Scene::default_scene(), BTreeSet::new()),
    };
    let mut scene = match scene {
        Ok(scene) => scene,
        Err(e) => return (Err(Failure::Load(e.to_string())), files),
    };
    for w in &scene.warnings {
        term::warn(w);
    }
    if let Some(background) = src.background {
        background.apply(&mut scene);
    }
    let frame_mesh = src.scene.is_none() && src.mesh.is_some();
    let framed =
        phosphor_args::frame_and_apply(&mut scene, &src.camera, &src.change, frame_mesh, src.size);
    match framed {
        Ok(()) => (Ok(scene), files),
        Err(e) => (Err(Failure::Usage(e)), files),
    }
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
    let source = Source {
        scene: args.scene.clone(),
        mesh: args.mesh.clone(),
        normals,
        background: args.background,
        camera: args.camera.clone(),
        change,
        size,
    };
    let (scene, files) = load(&source);
    let scene = match scene {
        Ok(s) => s,
        Err(Failure::Usage(e)) => return usage(e),
        Err(Failure::Load(e)) => return fail(&e),
    };
    let mut viewer = Viewer::new(scene);
    if !files.is_empty() {
        viewer.reload = Some(Reload {
            load: Box::new(move || {
                let (scene, files) = load(&source);
                (scene.map_err(Failure::message), files)
            }),
            files,
            error: None,
        });
    }
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
                // The median, as `phosphor bench` reports, so the two compare frame for frame.
                let mut ms = viewer.frame_ms.clone();
                ms.sort_by(f64::total_cmp);
                let median = ms.get(ms.len() / 2).copied().unwrap_or(mean);
                term::say(&format!(
                    "frames={} mean_ms={mean:.2} median_ms={median:.2} fps={:.1} triangles={}",
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
