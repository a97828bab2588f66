//! The scene renderer behind the window: the scene, the orbit camera, the toggles, and the
//! framebuffer reused from frame to frame; what is drawn and how the title describes it. The
//! keys' actions are applied in `actions.rs`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::Instant;

use phosphor_math::glam::Vec3;
use phosphor_output::image::{Transfer, write_png};
use phosphor_output::term;
use phosphor_raster::encode::Encoder;
use phosphor_raster::overlay::{Edges, Overlays};
use phosphor_raster::{
    Antialias, Camera, Encoding, FastPhongMethod, Framebuffer, Interpolation, Projection, Shown,
    WindowBuffer,
};
use phosphor_scene::animation::{Time, is_animated, update};
use phosphor_scene::preset::ViewPreset;
use phosphor_scene::view::camera_toml;
use phosphor_scene::{
    FrameOptions, Scene, ShadingChoice, draw_items, render_frame, render_frame_into,
};

use crate::input::{Action, OrbitCamera};
use crate::window::View;

/// Bytes per pixel of a window's frame: the framebuffer (RGB f32 and depth) and the 32-bit
/// pixels presented.
const WINDOW_BYTES_PER_PIXEL: u64 = 16 + 4;

/// Frames drawn while the user moves use the still picture's anti-aliasing (and its shadow
/// maps) only if a frame with them takes at most this long (60 frames a second); otherwise
/// they are drawn with one sample per pixel (and no shadows) and the still picture follows
/// when input stops.
pub const MOVING_FRAME_MS: f64 = 1000.0 / 60.0;

/// The still picture's anti-aliasing when neither `--aa` nor the scene file sets one.
pub const DEFAULT_STILL_ANTIALIAS: Antialias = Antialias::Msaa4;

/// Bytes per sample of an anti-aliased frame's sample image (RGB f32 and depth).
const SAMPLE_BYTES: u64 = 16;

/// Bytes per pixel of a window's frame drawn with `aa`.
pub fn bytes_per_pixel(aa: Antialias) -> u64 {
    let samples = if aa == Antialias::Off {
        0
    } else {
        u64::from(aa.samples())
    };
    WINDOW_BYTES_PER_PIXEL + SAMPLE_BYTES * samples
}

/// The scene renderer behind the window: the scene, the orbit camera, the toggles, and the
/// framebuffer reused from frame to frame.
pub struct Viewer {
    pub scene: Scene,
    /// The scene file and the mesh named on the command line, to name screenshots after.
    pub scene_file: Option<PathBuf>,
    pub mesh_file: Option<PathBuf>,
    /// The scene's own camera, for `R`.
    pub home: Camera,
    /// The up direction of the view: the scene camera's, or a standard view's (`V`).
    pub view_up: Vec3,
    /// Orthographic (`O`): the view's height at the orbit's first distance (it follows the
    /// zoom); `None` for perspective.
    pub ortho: Option<f32>,
    /// The standard view last chosen with `V`.
    pub preset: Option<ViewPreset>,
    /// The window size asked for, until a frame gives the size drawn.
    pub window_size: (u32, u32),
    pub orbit: OrbitCamera,
    pub shading: Option<ShadingChoice>,
    pub bump: bool,
    /// Shadows: the scene's (`None`), or on or off for every light (`--shadows`, key D).
    pub shadows: Option<bool>,
    /// Colour maps on.
    pub textures: bool,
    pub perspective_correct: bool,
    /// Anti-aliasing of the still picture (`--aa`, key A).
    pub antialias: Antialias,
    /// Whether frames drawn while the user moves may use `antialias` too: the last frame drawn
    /// with it took at most [`MOVING_FRAME_MS`].
    pub antialias_keeps_up: bool,
    /// The next frame is the refined still picture.
    pub refine_next: bool,
    /// `--frames` mode: every frame uses `antialias`, none is refined.
    pub fixed_frames: bool,
    /// The anti-aliasing the last frame was drawn with.
    pub last_antialias: Antialias,
    /// Whether frames drawn while the user moves may draw shadow maps: the last frame that
    /// drew some took at most [`MOVING_FRAME_MS`] (true until one did not).
    pub shadows_keep_up: bool,
    /// The last frame left out the shadows the still picture draws.
    pub shadows_dropped: bool,
    pub fast_phong: FastPhongMethod,
    pub interpolation: Interpolation,
    /// Wireframe (key W), grid (G) and axes (X) drawn over each frame.
    pub overlays: Overlays,
    pub fb: Option<Framebuffer>,
    /// `--force` for the screenshot.
    pub force: bool,
    /// Milliseconds of the last frame (plan + raster), and a smoothed frames-per-second.
    pub last_ms: f64,
    pub fps: f64,
    pub triangles: u64,
    pub frames: u32,
    pub total_ms: f64,
    /// Every frame's milliseconds in `--frames` mode, in order (for its median); empty in a
    /// window the user drives, which could run for days.
    pub frame_ms: Vec<f64>,
    /// What the window's buffer holds after the last frame ([`Framebuffer::write_0rgb_over`]).
    shown: Option<Shown>,
    /// The scene's clock: the instant shown, and whether it runs.
    pub clock: Clock,
    /// Warnings already printed (each once, not once per frame).
    pub told: Vec<String>,
    /// How to load the scene again when its files change (live reload); `None` for the
    /// embedded default scene.
    pub reload: Option<Reload>,
}

/// Loads a scene again, with the files it was made from (see [`Reload`]).
pub type LoadAgain = Box<dyn Fn() -> (Result<Scene, String>, BTreeSet<PathBuf>)>;

/// Live reload: how the scene is made again, the files it was made from (watched), and the
/// last reload's error, which the title shows until a reload succeeds.
pub struct Reload {
    /// Loads the scene again as the command line asked (its warnings printed).
    pub load: LoadAgain,
    /// The files to watch.
    pub files: BTreeSet<PathBuf>,
    /// Why the last reload failed, if it did.
    pub error: Option<String>,
}

/// The viewer's clock (Space plays and pauses, `[` and `]` scrub): the scene is posed at
/// `seconds` before each frame (`phosphor_scene::animation::update`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Clock {
    /// The instant shown, seconds.
    pub seconds: f64,
    /// Whether it advances with the wall clock.
    pub playing: bool,
    /// When the last playing frame was drawn (`None`: the next one starts the count).
    pub last_tick: Option<Instant>,
}

impl Clock {
    /// Advances a playing clock by the wall time since its last tick; returns the instant.
    pub fn tick(&mut self, now: Instant) -> f64 {
        if self.playing {
            if let Some(last) = self.last_tick {
                self.seconds += now.duration_since(last).as_secs_f64();
            }
            self.last_tick = Some(now);
        }
        self.seconds
    }
}

impl Viewer {
    pub fn new(scene: Scene) -> Viewer {
        let home = scene.camera();
        Viewer {
            scene_file: None,
            mesh_file: None,
            orbit: OrbitCamera::new(home.eye, home.target, home.up),
            view_up: home.up,
            ortho: match home.projection {
                Projection::Perspective => None,
                Projection::Orthographic { height } => Some(height),
            },
            preset: None,
            window_size: (960, 540),
            perspective_correct: scene.settings.perspective_correct,
            antialias: scene.settings.antialias,
            antialias_keeps_up: false,
            refine_next: false,
            fixed_frames: false,
            last_antialias: Antialias::Off,
            shadows_keep_up: true,
            shadows_dropped: false,
            fast_phong: scene.settings.fast_phong,
            interpolation: scene.settings.interpolation,
            overlays: Overlays::default(),
            scene,
            home,
            shading: None,
            bump: true,
            shadows: None,
            textures: true,
            fb: None,
            force: false,
            last_ms: 0.0,
            fps: 0.0,
            triangles: 0,
            frames: 0,
            total_ms: 0.0,
            frame_ms: Vec::new(),
            shown: None,
            clock: Clock::default(),
            told: Vec::new(),
            reload: None,
        }
    }

    /// Loads the scene again after one of its files changed, keeping the view: the orbit,
    /// the projection, the clock and every choice made with keys stay as they are, and `R`
    /// returns to the new scene's camera. A scene that fails to load leaves the last good one
    /// on screen; the error is printed and shown in the title until a reload succeeds, and
    /// the files it read are watched too (so creating a missing mesh reloads). Returns
    /// whether there was a scene to load again.
    pub fn reload_scene(&mut self) -> bool {
        let Some(reload) = &mut self.reload else {
            return false;
        };
        let (scene, files) = (reload.load)();
        match scene {
            Ok(scene) => {
                reload.files = files;
                reload.error = None;
                term::tell(&format!(
                    "reloaded {}",
                    scene
                        .source
                        .as_ref()
                        .map_or("the scene".to_owned(), |p| p.display().to_string())
                ));
                self.home = scene.camera();
                self.scene = scene;
                self.told.clear();
            }
            Err(e) => {
                reload.files.extend(files);
                term::tell(&format!(
                    "error: reload failed, the last good scene stays: {e}"
                ));
                reload.error = Some(e);
            }
        }
        true
    }

    /// Whether the scene has anything that moves with its clock.
    pub fn animated(&self) -> bool {
        is_animated(&self.scene.world)
    }

    /// The anti-aliasing of the next frame: the still picture's when it is refined, in
    /// `--frames` mode, or when frames with it keep up with [`MOVING_FRAME_MS`]; else none.
    pub fn frame_antialias(&self) -> Antialias {
        if self.fixed_frames || self.refine_next || self.antialias_keeps_up {
            self.antialias
        } else {
            Antialias::Off
        }
    }

    /// The shadows of the next frame: as chosen (`--shadows`, key D, else the scene's) when it
    /// is the refined still picture, in `--frames` mode, or when frames with shadow maps keep
    /// up with [`MOVING_FRAME_MS`]; else off.
    pub fn frame_shadows(&self) -> Option<bool> {
        if self.fixed_frames || self.refine_next || self.shadows_keep_up {
            self.shadows
        } else {
            Some(false)
        }
    }

    /// The orbiting camera; near and far follow the zoom so the scene is never cut away, and
    /// so does an orthographic view's height.
    pub fn camera(&self) -> Camera {
        let zoom = self.orbit.zoom_ratio();
        Camera {
            eye: self.orbit.eye(),
            target: self.orbit.target,
            up: self.view_up,
            near: self.home.near * zoom.min(1.0),
            far: self.home.far * zoom.max(1.0),
            projection: match self.ortho {
                None => Projection::Perspective,
                Some(height) => Projection::Orthographic {
                    height: height * zoom,
                },
            },
            ..self.home
        }
    }

    /// The size of the frames drawn: the last frame's, else the window's.
    pub fn frame_size(&self) -> (u32, u32) {
        self.fb
            .as_ref()
            .map_or(self.window_size, |fb| (fb.width(), fb.height()))
    }

    /// The current camera as a scene file's `[camera]` block (what the `C` key prints).
    pub fn camera_block(&self) -> String {
        camera_toml(&self.camera())
    }
}

/// The overlays on screen, for the title: ` | wireframe, grid, axes` or nothing.
fn overlay_title(o: &Overlays) -> String {
    let names: Vec<&str> = [
        match o.wireframe {
            None => None,
            Some((Edges::All, _)) => Some("wireframe"),
            Some((Edges::Creases { .. }, _)) => Some("creases"),
        },
        o.grid.map(|_| "grid"),
        o.axes.then_some("axes"),
    ]
    .into_iter()
    .flatten()
    .collect();
    if names.is_empty() {
        String::new()
    } else {
        format!(" | {}", names.join(", "))
    }
}

impl View for Viewer {
    fn draw(&mut self, width: u32, height: u32, out: &mut [u32], held: bool) -> Result<(), String> {
        let start = Instant::now();
        let fb = match self.fb.take() {
            Some(fb) if fb.width() == width && fb.height() == height => fb,
            _ => Framebuffer::new(width, height).map_err(|e| e.to_string())?,
        };
        let mut fb = fb;
        let seconds = self.clock.tick(start);
        if self.animated() {
            for w in update(&mut self.scene, Time::at(seconds)) {
                if !self.told.contains(&w) {
                    term::warn(&w);
                    self.told.push(w);
                }
            }
        }
        // The viewer's own camera (orbit, pan, zoom) wins over a camera on a rig.
        let camera = self.camera();
        self.scene.set_camera(camera);
        let opts = FrameOptions {
            shading: self.shading,
            bump: self.bump,
            textures: self.textures,
            perspective_correct: Some(self.perspective_correct),
            threads: 0,
            antialias: Some(self.frame_antialias()),
            fast_phong: Some(self.fast_phong),
            interpolation: Some(self.interpolation),
            shadows: self.frame_shadows(),
            ..FrameOptions::default()
        };
        // What the buffer holds from the last frame, if it still holds it: then only the
        // columns either frame wrote are converted or cleared.
        let mut shown = self.shown.take().filter(|_| held);
        let report = if self.overlays.is_empty() {
            // The frame's last bands convert their rows into the buffer while in cache.
            let window = WindowBuffer {
                words: &mut *out,
                shown: &mut shown,
            };
            render_frame_into(&self.scene, &mut fb, &opts, window)
        } else {
            let report = render_frame(&self.scene, &mut fb, &opts);
            let items = draw_items(&report.plan);
            let smooth = report.stats.antialias != Antialias::Off;
            self.overlays.draw(&mut fb, &camera, &items, smooth);
            shown = Some(fb.write_0rgb_over(out, 0, shown.as_ref()));
            report
        };
        self.shown = shown;
        for w in &report.warnings {
            if !self.told.contains(w) {
                term::warn(w);
                self.told.push(w.clone());
            }
        }
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
        if !report.shadow_times.is_empty() {
            self.shadows_keep_up = ms <= MOVING_FRAME_MS;
        }
        // Frames go without shadows only after one with maps was too slow, so a frame drawn
        // without them leaves out maps the still picture draws.
        self.shadows_dropped = opts.shadows != self.shadows;
        self.refine_next = false;
        self.frames += 1;
        self.total_ms += ms;
        if self.fixed_frames {
            self.frame_ms.push(ms);
        }
        Ok(())
    }

    fn title(&self) -> String {
        let mode = self
            .shading
            .map_or("scene's own (auto)".to_owned(), |s| s.name().to_owned());
        format!(
            "Phosphor | {}{}{mode}{}{}{}{}{}{}{}{}{} | {:.1} ms ({:.0} fps) | {} triangles | H: keys",
            match self.reload.as_ref().and_then(|r| r.error.as_ref()) {
                Some(e) => format!("reload failed: {e} | "),
                None => String::new(),
            },
            if self.animated() {
                format!(
                    "t {:.2} s {} | ",
                    self.clock.seconds,
                    if self.clock.playing {
                        "playing"
                    } else {
                        "paused (Space plays)"
                    }
                )
            } else {
                String::new()
            },
            if self.last_antialias == Antialias::Off {
                String::new()
            } else {
                format!(" | {}", self.last_antialias)
            },
            if self.ortho.is_some() {
                " | orthographic"
            } else {
                ""
            },
            if self.bump { "" } else { " | bump off" },
            match self.shadows {
                _ if self.shadows_dropped => " | shadows when still",
                None => "",
                Some(true) => " | shadows on",
                Some(false) => " | shadows off",
            },
            if self.textures { "" } else { " | maps off" },
            overlay_title(&self.overlays),
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
        self.act(action, height)
    }

    fn playing(&self) -> bool {
        self.clock.playing && self.animated()
    }

    fn wants_refinement(&self) -> bool {
        !self.fixed_frames && (self.last_antialias != self.antialias || self.shadows_dropped)
    }

    fn refine(&mut self) {
        self.refine_next = true;
    }

    fn watched(&self) -> BTreeSet<PathBuf> {
        self.reload
            .as_ref()
            .map_or_else(BTreeSet::new, |r| r.files.clone())
    }

    fn reload(&mut self) -> bool {
        self.reload_scene()
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

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    /// A sphere in front of S1's camera, lit from the front, in material colour `kd`.
    fn sphere_scene(kd: [f32; 3]) -> String {
        format!(
            "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nintensity = 1\n\
             [materials.m]\nka = 0\nkd = {kd:?}\nks = 0\n\
             [[objects]]\nname = \"ball\"\nmaterial = \"m\"\n\
             primitive = {{ shape = \"sphere\", radius = 1.0, segments = 16, rings = 8 }}\n"
        )
    }

    /// The centre pixel of a 32x24 frame, as 0x00RRGGBB channels.
    fn centre(viewer: &mut Viewer) -> [u32; 3] {
        let mut out = vec![0u32; 32 * 24];
        viewer.draw(32, 24, &mut out, false).unwrap();
        let p = out[12 * 32 + 16];
        [(p >> 16) & 255, (p >> 8) & 255, p & 255]
    }

    #[test]
    fn a_reload_keeps_the_view_and_a_failed_one_keeps_the_last_good_scene() {
        let dir =
            std::env::temp_dir().join(format!("phosphor-viewer-reload-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("scene.toml");
        std::fs::write(&path, sphere_scene([0.9, 0.0, 0.0])).unwrap();
        let again = path.clone();
        let load: LoadAgain = Box::new(move || {
            let (scene, files) = phosphor_scene::load_scene_noting(&again);
            (scene.map_err(|e| e.to_string()), files)
        });
        let (scene, files) = load();
        let mut viewer = Viewer::new(scene.unwrap());
        viewer.reload = Some(Reload {
            load,
            files,
            error: None,
        });
        assert_eq!(viewer.watched(), BTreeSet::from([path.clone()]));
        let [r, _, b] = centre(&mut viewer);
        assert!(r > 4 * b.max(1), "red first: {r} {b}");
        viewer.apply(Action::Orbit { dx: 3.0, dy: 2.0 }, 24);
        let view = viewer.camera();
        // The material changed on disk: the new scene, the same view.
        std::fs::write(&path, sphere_scene([0.0, 0.0, 0.9])).unwrap();
        assert!(viewer.reload());
        assert_eq!(viewer.camera(), view);
        let [r, _, b] = centre(&mut viewer);
        assert!(b > 4 * r.max(1), "blue after the reload: {r} {b}");
        assert!(!viewer.title().contains("reload failed"));
        // A scene that no longer loads: the last good one stays, the title says why.
        std::fs::write(&path, "[[objects]\n").unwrap();
        assert!(viewer.reload());
        let error = viewer
            .reload
            .as_ref()
            .and_then(|r| r.error.clone())
            .unwrap();
        assert!(error.contains("scene.toml"), "{error}");
        assert!(
            viewer.title().contains("reload failed"),
            "{}",
            viewer.title()
        );
        let [r, _, b] = centre(&mut viewer);
        assert!(b > 4 * r.max(1), "still blue: {r} {b}");
        assert_eq!(viewer.camera(), view);
        // Fixed again: the error is gone.
        std::fs::write(&path, sphere_scene([0.0, 0.9, 0.0])).unwrap();
        assert!(viewer.reload());
        assert!(!viewer.title().contains("reload failed"));
        let [r, g, _] = centre(&mut viewer);
        assert!(g > 4 * r.max(1), "green: {r} {g}");
        // The embedded scene has nothing to reload.
        let mut embedded = Viewer::new(Scene::default_scene().unwrap());
        assert!(embedded.watched().is_empty() && !embedded.reload());
        let _ = std::fs::remove_dir_all(&dir);
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
        viewer.draw(64, 36, &mut out, false).unwrap();
        assert_eq!(viewer.last_antialias, Antialias::Off);
        assert!(viewer.wants_refinement());
        // The refined frame uses the still picture's samples, and then nothing is wanted.
        viewer.refine();
        viewer.draw(64, 36, &mut out, false).unwrap();
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
        viewer.draw(64, 36, &mut out, false).unwrap();
        viewer.antialias = Antialias::Ssaa16;
        assert!(!viewer.wants_refinement());
    }

    #[test]
    fn moving_frames_drop_slow_shadows_and_the_still_picture_draws_them() {
        let mut viewer = Viewer::new(Scene::default_scene().unwrap());
        let mut out = vec![0u32; 64 * 36];
        // The default scene's key light casts shadows: the first frame draws its map, and
        // whether it kept up depends on the machine.
        viewer.draw(64, 36, &mut out, false).unwrap();
        assert!(!viewer.shadows_dropped);
        // Too slow: moving frames go without shadows and ask for the still picture.
        viewer.shadows_keep_up = false;
        viewer.apply(Action::Orbit { dx: 5.0, dy: 0.0 }, 36);
        assert_eq!(viewer.frame_shadows(), Some(false));
        viewer.draw(64, 36, &mut out, false).unwrap();
        assert!(viewer.shadows_dropped && viewer.wants_refinement());
        // The still picture has them again, and then nothing more is wanted.
        viewer.refine();
        assert_eq!(viewer.frame_shadows(), None);
        viewer.draw(64, 36, &mut out, false).unwrap();
        assert!(!viewer.shadows_dropped && !viewer.wants_refinement());
        // Shadows switched off with key D are never dropped, so never refined.
        viewer.shadows = Some(false);
        viewer.shadows_keep_up = false;
        viewer.draw(64, 36, &mut out, false).unwrap();
        assert!(!viewer.shadows_dropped);
        // `--frames` mode draws every frame as asked.
        viewer.shadows = Some(true);
        viewer.fixed_frames = true;
        assert_eq!(viewer.frame_shadows(), Some(true));
    }

    /// The window's buffer, kept from frame to frame and filled by each frame's last bands,
    /// holds the whole image's words after every frame: the view moving, with and without
    /// anti-aliasing and an overlay.
    #[test]
    fn a_kept_window_buffer_holds_each_frames_whole_image() {
        let mut viewer = Viewer::new(Scene::default_scene().unwrap());
        viewer.fixed_frames = true;
        let (w, h) = (80u32, 45u32);
        let mut out = vec![0u32; (w * h) as usize];
        for k in 0..8 {
            viewer.antialias = if k % 2 == 0 {
                Antialias::Off
            } else {
                Antialias::Msaa4
            };
            if k == 5 || k == 6 {
                viewer.apply(Action::ToggleGrid, h);
            }
            viewer.draw(w, h, &mut out, k > 0).unwrap();
            let fb = viewer.fb.as_ref().unwrap();
            let mut whole = vec![0u32; out.len()];
            fb.write_0rgb_threads(&mut whole, 1);
            assert_eq!(out, whole, "frame {k}");
            viewer.apply(Action::Orbit { dx: 9.0, dy: 4.0 }, h);
        }
    }

    #[test]
    fn keys_w_g_x_draw_the_overlays_over_the_window_and_off_again() {
        let mut viewer = Viewer::new(Scene::default_scene().unwrap());
        viewer.fixed_frames = true;
        let (w, h) = (96u32, 54u32);
        let mut plain = vec![0u32; (w * h) as usize];
        viewer.draw(w, h, &mut plain, false).unwrap();
        // `out` is kept from frame to frame, as a window's buffer is: after the first frame
        // only what changed is written into it.
        let mut out = vec![0u32; (w * h) as usize];
        let differs = |a: &[u32], b: &[u32]| a.iter().zip(b).filter(|(x, y)| x != y).count();
        // W: every edge, then crease edges only (fewer pixels), then off.
        viewer.apply(Action::CycleWireframe, h);
        viewer.draw(w, h, &mut out, false).unwrap();
        let every = differs(&plain, &out);
        assert!(viewer.title().contains("| wireframe"), "{}", viewer.title());
        viewer.apply(Action::CycleWireframe, h);
        viewer.draw(w, h, &mut out, true).unwrap();
        let creases = differs(&plain, &out);
        assert!(viewer.title().contains("| creases"));
        assert!(
            every > 200 && creases > 50 && creases < every,
            "{every} {creases}"
        );
        viewer.apply(Action::CycleWireframe, h);
        viewer.draw(w, h, &mut out, true).unwrap();
        assert_eq!(differs(&plain, &out), 0, "off again");
        // G and X: the grid and the corner triad, named in the title together.
        viewer.apply(Action::ToggleGrid, h);
        viewer.apply(Action::ToggleAxes, h);
        viewer.draw(w, h, &mut out, true).unwrap();
        assert!(differs(&plain, &out) > 20);
        assert!(
            viewer.title().contains("| grid, axes"),
            "{}",
            viewer.title()
        );
        // Off again, and the window's partial clear leaves nothing of them behind.
        viewer.apply(Action::ToggleGrid, h);
        viewer.apply(Action::ToggleAxes, h);
        viewer.draw(w, h, &mut out, true).unwrap();
        assert_eq!(differs(&plain, &out), 0);
    }
}
