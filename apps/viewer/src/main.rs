//! `phosphor-viewer`: the real-time window onto a Phosphor scene.
//!
//! ```text
//! phosphor-viewer [SCENE.toml] [--mesh FILE.obj] [--size WxH] [--shading MODE] [--frames N --screenshot FILE.png]
//!                 [--eye X,Y,Z --target X,Y,Z --up X,Y,Z --fov DEG | --azimuth DEG --elevation DEG --distance D]
//!                 [--crease-angle DEG --normals file|computed --weighting uniform|area|angle]
//! ```
//!
//! `C` prints the current camera as a `[camera]` block for a scene file; `S` saves a screenshot
//! beside the scene file. The camera and normal flags live in `view.rs`.
//!
//! This file is about rendering: what is drawn and how the title describes it. The window
//! plumbing lives in `window.rs`, the camera and key table in `input.rs`.

mod input;
mod view;
mod window;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{CommandFactory, Parser};
use phosphor_lighting::Light;
use phosphor_output::image::{Transfer, write_png};
use phosphor_output::{memory, term};
use phosphor_raster::encode::Encoder;
use phosphor_raster::{
    Antialias, Camera, Encoding, FastPhongMethod, Framebuffer, Interpolation, ShadingMode,
};
use phosphor_scene::view::camera_toml;
use phosphor_scene::{FrameOptions, Scene, ShadingChoice, render_frame};

use crate::input::{Action, KEY_HELP, ModeKey, OrbitCamera};
use crate::window::{View, WindowError, WindowOptions};

/// Window size when neither `--size` nor the scene gives one.
const DEFAULT_SIZE: (u32, u32) = (960, 540);
/// Largest accepted window side, in pixels.
const MAX_SIDE: u32 = 16_384;

/// Command line of `phosphor-viewer`.
#[derive(Debug, Parser)]
#[command(
    name = "phosphor-viewer",
    version,
    about = "Real-time viewer for Phosphor scenes (CPU scan-line rasterizer)",
    after_help = "Examples:\n  phosphor-viewer\n  phosphor-viewer assets/scenes/s1.toml\n  phosphor-viewer --mesh assets/meshes/teapot.obj --size 1280x720\n  phosphor-viewer --frames 10 --screenshot shot.png\n  phosphor-viewer assets/scenes/s1.toml --shading phong --size 1280x720 --frames 100\n  phosphor-viewer --mesh cube.obj --azimuth 45 --elevation 30\n  phosphor-viewer assets/scenes/s1.toml --eye 2,1,3 --fov 30\n\nKeys: C prints the camera as a [camera] block for a scene file, S saves a screenshot beside it,\nT switches fast-phong between taylor (Bishop and Weimer 1986) and fit, I switches gouraud and\nphong between plane and incremental (Gouraud 1971) interpolation; the title shows both.\nIn --frames mode the viewer prints `frames=N mean_ms=X fps=Y triangles=T` when it exits.\nPress H in the window for the key list."
)]
struct Args {
    /// Scene file (TOML); the embedded default scene when absent.
    scene: Option<PathBuf>,
    /// Show this mesh (OBJ, PLY, STL, glTF or GLB, by extension) under S1's lights and material
    /// instead of a scene file, framed to fit the window from a three-quarter angle (azimuth
    /// 30, elevation 20).
    #[arg(long, value_name = "FILE.obj", conflicts_with = "scene")]
    mesh: Option<PathBuf>,
    /// Window inner size in physical pixels.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Start with this shading for every object (`auto`: the scene's own choice per object).
    #[arg(long, value_name = "MODE", value_parser = parse_shading)]
    shading: Option<ShadingChoice>,
    /// Anti-aliasing of the still picture (default: the scene file's `aa`, else msaa4; with
    /// --frames, the scene file's): 4 or 16 samples per pixel, `msaa` shading each pixel once
    /// per triangle, `ssaa` every sample (about 4 or 16 times the cost). Frames drawn while
    /// you move use it only if it keeps 60 frames a second. Key A switches it.
    #[arg(
        long,
        value_name = "off|msaa4|ssaa4|msaa16|ssaa16",
        value_parser = phosphor_args::parse_antialias
    )]
    aa: Option<Antialias>,
    /// Draw this many frames, then exit.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    frames: Option<u32>,
    /// Write the last frame as PNG before exiting (after --frames frames, default 1).
    #[arg(long, value_name = "FILE.png", value_parser = parse_png_path)]
    screenshot: Option<PathBuf>,
    /// Camera flags.
    #[command(flatten)]
    camera: phosphor_args::CameraArgs,
    /// Normal flags of --mesh.
    #[command(flatten)]
    normals: phosphor_args::NormalArgs,
    /// Let --screenshot replace a read-only file, or write into a device or FIFO.
    #[arg(long)]
    force: bool,
}

/// A screenshot path: it must end in `.png`, the only format the viewer writes.
fn parse_png_path(text: &str) -> Result<PathBuf, String> {
    let path = PathBuf::from(text);
    let is_png = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if is_png {
        Ok(path)
    } else {
        Err("must end in .png (screenshots are PNG)".to_owned())
    }
}

/// Bytes per pixel of a window's frame: the framebuffer (RGB f32 and depth) and the 32-bit
/// pixels presented.
const WINDOW_BYTES_PER_PIXEL: u64 = 16 + 4;

/// Frames drawn while the user moves use the still picture's anti-aliasing only if it takes
/// at most this long (60 frames a second); otherwise they are drawn with one sample per pixel
/// and the still picture follows when input stops.
const MOVING_FRAME_MS: f64 = 1000.0 / 60.0;

/// The still picture's anti-aliasing when neither `--aa` nor the scene file sets one.
const DEFAULT_STILL_ANTIALIAS: Antialias = Antialias::Msaa4;

/// Bytes per sample of an anti-aliased frame's sample image (RGB f32 and depth).
const SAMPLE_BYTES: u64 = 16;

/// Bytes per pixel of a window's frame drawn with `aa`.
fn bytes_per_pixel(aa: Antialias) -> u64 {
    let samples = if aa == Antialias::Off {
        0
    } else {
        u64::from(aa.samples())
    };
    WINDOW_BYTES_PER_PIXEL + SAMPLE_BYTES * samples
}

/// Parses a shading name: `auto` or one of the modes.
fn parse_shading(text: &str) -> Result<ShadingChoice, String> {
    text.parse()
}

/// Parses `WxH` (e.g. `640x480`) into a non-zero size.
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{text}`: expected WxH, e.g. 640x480"))?;
    let side = |s: &str| -> Result<u32, String> {
        let v: u32 = s
            .trim()
            .parse()
            .map_err(|_| format!("`{text}`: expected WxH with whole numbers, e.g. 640x480"))?;
        if v == 0 || v > MAX_SIDE {
            return Err(format!("`{text}`: each side must be 1..={MAX_SIDE}"));
        }
        Ok(v)
    };
    Ok((side(w)?, side(h)?))
}

/// The modes behind keys 1..5, in key order.
const KEY_MODES: [ShadingMode; 5] = [
    ShadingMode::Flat,
    ShadingMode::Gouraud,
    ShadingMode::Phong,
    ShadingMode::FastPhong,
    ShadingMode::Reference,
];

/// The scene renderer behind the window: the scene, the orbit camera, the toggles, and the
/// framebuffer reused from frame to frame.
struct Viewer {
    scene: Scene,
    /// The scene file and the mesh named on the command line, to name screenshots after.
    scene_file: Option<PathBuf>,
    mesh_file: Option<PathBuf>,
    /// The scene's own camera, for `R`.
    home: Camera,
    orbit: OrbitCamera,
    shading: Option<ShadingChoice>,
    bump: bool,
    perspective_correct: bool,
    /// Anti-aliasing of the still picture (`--aa`, key A).
    antialias: Antialias,
    /// Whether frames drawn while the user moves may use `antialias` too: the last frame drawn
    /// with it took at most [`MOVING_FRAME_MS`].
    antialias_keeps_up: bool,
    /// The next frame is the refined still picture.
    refine_next: bool,
    /// `--frames` mode: every frame uses `antialias`, none is refined.
    fixed_frames: bool,
    /// The anti-aliasing the last frame was drawn with.
    last_antialias: Antialias,
    fast_phong: FastPhongMethod,
    interpolation: Interpolation,
    fb: Option<Framebuffer>,
    /// `--force` for the screenshot.
    force: bool,
    /// Milliseconds of the last frame (plan + raster), and a smoothed frames-per-second.
    last_ms: f64,
    fps: f64,
    triangles: u64,
    frames: u32,
    total_ms: f64,
}

impl Viewer {
    fn new(scene: Scene) -> Viewer {
        let home = scene.camera();
        Viewer {
            scene_file: None,
            mesh_file: None,
            orbit: OrbitCamera::new(home.eye, home.target, home.up),
            perspective_correct: scene.settings.perspective_correct,
            antialias: scene.settings.antialias,
            antialias_keeps_up: false,
            refine_next: false,
            fixed_frames: false,
            last_antialias: Antialias::Off,
            fast_phong: scene.settings.fast_phong,
            interpolation: scene.settings.interpolation,
            scene,
            home,
            shading: None,
            bump: true,
            fb: None,
            force: false,
            last_ms: 0.0,
            fps: 0.0,
            triangles: 0,
            frames: 0,
            total_ms: 0.0,
        }
    }

    /// The anti-aliasing of the next frame: the still picture's when it is refined, in
    /// `--frames` mode, or when frames with it keep up with [`MOVING_FRAME_MS`]; else none.
    fn frame_antialias(&self) -> Antialias {
        if self.fixed_frames || self.refine_next || self.antialias_keeps_up {
            self.antialias
        } else {
            Antialias::Off
        }
    }

    /// The orbiting camera; near and far follow the zoom so the scene is never cut away.
    fn camera(&self) -> Camera {
        let zoom = self.orbit.zoom_ratio();
        Camera {
            eye: self.orbit.eye(),
            target: self.orbit.target,
            up: self.home.up,
            near: self.home.near * zoom.min(1.0),
            far: self.home.far * zoom.max(1.0),
            ..self.home
        }
    }

    /// The current camera as a scene file's `[camera]` block (what the `C` key prints).
    fn camera_block(&self) -> String {
        camera_toml(&self.camera())
    }
}

impl View for Viewer {
    fn draw(&mut self, width: u32, height: u32, out: &mut [u32]) -> Result<(), String> {
        let start = Instant::now();
        let fb = match self.fb.take() {
            Some(fb) if fb.width() == width && fb.height() == height => fb,
            _ => Framebuffer::new(width, height).map_err(|e| e.to_string())?,
        };
        let mut fb = fb;
        let camera = self.camera();
        self.scene.set_camera(camera);
        let opts = FrameOptions {
            shading: self.shading,
            bump: self.bump,
            perspective_correct: Some(self.perspective_correct),
            threads: 0,
            antialias: Some(self.frame_antialias()),
            fast_phong: Some(self.fast_phong),
            interpolation: Some(self.interpolation),
            ..FrameOptions::default()
        };
        let report = render_frame(&self.scene, &mut fb, &opts);
        fb.write_0rgb_threads(out, 0);
        self.fb = Some(fb);
        let ms = start.elapsed().as_secs_f64() * 1e3;
        self.last_ms = ms;
        let fps = 1e3 / ms.max(1e-3);
        self.fps = if self.frames == 0 {
            fps
        } else {
            0.8 * self.fps + 0.2 * fps
        };
        self.triangles = report.stats.triangles_drawn;
        let used = report.stats.antialias;
        if used == self.antialias && used != Antialias::Off {
            self.antialias_keeps_up = ms <= MOVING_FRAME_MS;
        }
        self.last_antialias = used;
        self.refine_next = false;
        self.frames += 1;
        self.total_ms += ms;
        Ok(())
    }

    fn title(&self) -> String {
        let mode = self
            .shading
            .map_or("scene's own (auto)".to_owned(), |s| s.name().to_owned());
        format!(
            "Phosphor | {mode}{}{}{}{}{} | {:.1} ms ({:.0} fps) | {} triangles | H: keys",
            if self.last_antialias == Antialias::Off {
                String::new()
            } else {
                format!(" | {}", self.last_antialias)
            },
            if self.bump { "" } else { " | bump off" },
            if self.perspective_correct {
                ""
            } else {
                " | screen-space"
            },
            // The methods are named only where they differ from the defaults.
            if self.fast_phong == FastPhongMethod::default() {
                String::new()
            } else {
                format!(" | fast-phong {}", self.fast_phong)
            },
            if self.interpolation == Interpolation::default() {
                String::new()
            } else {
                format!(" | {} interpolation", self.interpolation)
            },
            self.last_ms,
            self.fps,
            self.triangles
        )
    }

    fn apply(&mut self, action: Action, height: u32) -> bool {
        match action {
            Action::Help => {
                term::say(KEY_HELP);
                false
            }
            Action::Orbit { dx, dy } => {
                self.orbit.orbit(dx, dy);
                true
            }
            Action::Pan { dx, dy } => {
                self.orbit.pan(dx, dy, self.home.fov_y_deg, height);
                true
            }
            Action::Zoom(lines) => {
                self.orbit.zoom(lines);
                true
            }
            Action::Shading(ModeKey::Auto) => {
                self.shading = None;
                true
            }
            Action::Shading(ModeKey::Mode(i)) => {
                self.shading = KEY_MODES.get(i).map(|m| ShadingChoice::Mode(*m));
                true
            }
            Action::ToggleLight(n) => {
                let Some(&e) = self.scene.light_entities().get(n) else {
                    return false;
                };
                if let Ok(mut light) = self.scene.world.get::<&mut Light>(e) {
                    light.enabled = !light.enabled;
                    term::say(&format!(
                        "light {} {}",
                        n + 1,
                        if light.enabled { "on" } else { "off" }
                    ));
                }
                true
            }
            Action::ToggleBump => {
                self.bump = !self.bump;
                true
            }
            Action::TogglePerspective => {
                self.perspective_correct = !self.perspective_correct;
                true
            }
            Action::CycleAntialias => {
                let next = self.antialias.next();
                let size = self.fb.as_ref().map(|fb| (fb.width(), fb.height()));
                let room = size.map_or(Ok(()), |size| {
                    memory::check_image("anti-aliasing", size, bytes_per_pixel(next))
                });
                match room {
                    Ok(()) => {
                        self.antialias = next;
                        // Shown at once; whether moving frames keep up is measured anew.
                        self.antialias_keeps_up = false;
                        self.refine_next = true;
                        term::say(&format!("anti-aliasing {next}"));
                    }
                    Err(e) => {
                        self.antialias = Antialias::Off;
                        term::warn(&format!("{next} not used: {e}"));
                    }
                }
                true
            }
            Action::ToggleFastPhong => {
                self.fast_phong = match self.fast_phong {
                    FastPhongMethod::Taylor => FastPhongMethod::Fit,
                    FastPhongMethod::Fit => FastPhongMethod::Taylor,
                };
                true
            }
            Action::ToggleInterpolation => {
                self.interpolation = match self.interpolation {
                    Interpolation::Plane => Interpolation::Incremental,
                    Interpolation::Incremental => Interpolation::Plane,
                };
                true
            }
            Action::ResetView => {
                self.orbit = OrbitCamera::new(self.home.eye, self.home.target, self.home.up);
                true
            }
            Action::PrintCamera => {
                term::say(self.camera_block().trim_end());
                false
            }
            Action::Screenshot => {
                let saved =
                    view::screenshot_path(self.scene_file.as_deref(), self.mesh_file.as_deref())
                        .ok_or_else(|| "999 screenshots already beside the scene".to_owned())
                        .and_then(|path| self.save_screenshot(&path).map(|()| path));
                match saved {
                    Ok(path) => term::say(&format!("saved {}", path.display())),
                    Err(e) => term::warn(&format!("screenshot not saved: {e}")),
                }
                false
            }
            Action::Quit => false,
        }
    }

    fn wants_refinement(&self) -> bool {
        !self.fixed_frames && self.last_antialias != self.antialias
    }

    fn refine(&mut self) {
        self.refine_next = true;
    }

    fn save_screenshot(&self, path: &Path) -> Result<(), String> {
        let fb = self.fb.as_ref().ok_or("no frame drawn yet")?;
        // The window shows sRGB (Framebuffer::write_0rgb); the screenshot holds the same
        // bytes, tagged sRGB so that image viewers show what the window showed.
        let encoder = Encoder::new(Encoding::Srgb);
        let width = fb.width() as usize;
        let colour = fb.color();
        let mut row = |y: u32, line: &mut [u8]| {
            let start = y as usize * width;
            for (px, c) in line.chunks_exact_mut(3).zip(&colour[start..start + width]) {
                px.copy_from_slice(&[
                    encoder.encode(c.x),
                    encoder.encode(c.y),
                    encoder.encode(c.z),
                ]);
            }
        };
        let size = (fb.width(), fb.height());
        write_png(
            path,
            self.force,
            size,
            Transfer::Srgb,
            &mut row,
            &mut |_| {},
        )
        .map_err(|e| {
            if e.forceable() {
                format!("{e} (--force writes it anyway)")
            } else {
                e.to_string()
            }
        })
    }
}

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
    let args = term::parse_or_exit(Args::try_parse(), &Args::command());
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
    let size = args.size.unwrap_or(DEFAULT_SIZE);
    let frame_mesh = args.scene.is_none() && args.mesh.is_some();
    if let Err(e) = phosphor_args::frame_and_apply(&mut scene, &change, frame_mesh, size) {
        return usage(e);
    }
    let mut viewer = Viewer::new(scene);
    viewer.scene_file = args.scene.clone();
    viewer.mesh_file = args.mesh.clone();
    viewer.shading = args.shading.filter(|s| *s != ShadingChoice::Auto);
    viewer.force = args.force;
    viewer.fixed_frames = args.frames.is_some();
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
        term::say(KEY_HELP);
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
    #![allow(clippy::unwrap_used)]

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

    #[test]
    fn the_printed_camera_block_loads_back_to_the_view_on_screen() {
        let mut viewer = Viewer::new(Scene::default_scene().unwrap());
        viewer.apply(
            Action::Orbit {
                dx: 37.0,
                dy: -12.0,
            },
            540,
        );
        viewer.apply(Action::Zoom(2.5), 540);
        viewer.apply(Action::Pan { dx: 5.0, dy: 3.0 }, 540);
        let shown = viewer.camera();
        assert_ne!(shown, viewer.home, "the view moved");
        let block = viewer.camera_block();
        let loaded = Scene::parse(&block, "pasted.toml").unwrap();
        assert_eq!(loaded.camera(), shown, "{block}");
    }

    #[test]
    fn moving_frames_skip_slow_anti_aliasing_and_the_still_picture_gets_it() {
        let mut viewer = Viewer::new(Scene::default_scene().unwrap());
        viewer.antialias = Antialias::Ssaa4;
        let mut out = vec![0u32; 64 * 36];
        // First frame: not yet known to keep up, drawn with one sample; refinement wanted.
        viewer.draw(64, 36, &mut out).unwrap();
        assert_eq!(viewer.last_antialias, Antialias::Off);
        assert!(viewer.wants_refinement());
        // The refined frame uses the still picture's samples, and then nothing is wanted.
        viewer.refine();
        viewer.draw(64, 36, &mut out).unwrap();
        assert_eq!(viewer.last_antialias, Antialias::Ssaa4);
        assert!(!viewer.wants_refinement());
        // Whether it kept up depends on the machine: both outcomes, set by hand.
        viewer.antialias_keeps_up = true;
        viewer.apply(Action::Orbit { dx: 5.0, dy: 0.0 }, 36);
        assert_eq!(viewer.frame_antialias(), Antialias::Ssaa4);
        viewer.antialias_keeps_up = false;
        assert_eq!(viewer.frame_antialias(), Antialias::Off);
        // `--frames` mode draws every frame as asked and never refines.
        viewer.fixed_frames = true;
        assert_eq!(viewer.frame_antialias(), Antialias::Ssaa4);
        viewer.draw(64, 36, &mut out).unwrap();
        viewer.antialias = Antialias::Ssaa16;
        assert!(!viewer.wants_refinement());
    }
}
