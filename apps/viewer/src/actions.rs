//! What the keys and the mouse do to the viewer: [`Viewer::act`] applies an [`Action`].

use phosphor_lighting::Light;
use phosphor_math::glam::Vec3;
use phosphor_mesh::normals::DEFAULT_CREASE_ANGLE_DEG;
use phosphor_output::{memory, term};
use phosphor_raster::overlay::Edges;
use phosphor_raster::{Antialias, Camera, FastPhongMethod, Interpolation, Projection, ShadingMode};
use phosphor_scene::ShadingChoice;
use phosphor_scene::preset::{ViewPreset, preset_camera};

use crate::input::{Action, ModeKey, OrbitCamera, key_help};
use crate::view;
use crate::viewer::{Viewer, bytes_per_pixel};
use crate::window::View;

/// The wireframe's colour in the window (linear RGB): an orange that shows on dark
/// backgrounds and on lit surfaces alike.
const WIRE_COLOR: Vec3 = Vec3::new(1.0, 0.45, 0.05);

/// The grid's colour in the window (linear RGB).
const GRID_COLOR: Vec3 = Vec3::new(0.25, 0.25, 0.25);

impl Viewer {
    /// Applies a user action; returns true when the picture must be redrawn.
    pub fn act(&mut self, action: Action, height: u32) -> bool {
        match action {
            Action::Help => {
                term::say(&key_help());
                false
            }
            Action::Orbit { dx, dy } => {
                self.orbit.orbit(dx, dy);
                true
            }
            Action::Pan { dx, dy } => {
                let view_height = match self.ortho {
                    Some(h) => h * self.orbit.zoom_ratio(),
                    None => {
                        2.0 * self.orbit.distance * (self.home.fov_y_deg.to_radians() * 0.5).tan()
                    }
                };
                self.orbit.pan(dx, dy, view_height, height);
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
                self.shading = ShadingMode::ALL.get(i).map(|m| ShadingChoice::Mode(*m));
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
            Action::CycleShadows => {
                self.shadows = match self.shadows {
                    None => Some(false),
                    Some(false) => Some(true),
                    Some(true) => None,
                };
                // Shown at once; whether moving frames keep up is measured anew.
                self.shadows_keep_up = true;
                true
            }
            Action::ToggleMaps => {
                self.textures = !self.textures;
                true
            }
            Action::CycleWireframe => {
                self.overlays.wireframe = match self.overlays.wireframe {
                    None => Some((Edges::All, WIRE_COLOR)),
                    Some((Edges::All, c)) => Some((
                        Edges::Creases {
                            angle_deg: DEFAULT_CREASE_ANGLE_DEG,
                        },
                        c,
                    )),
                    Some((Edges::Creases { .. }, _)) => None,
                };
                true
            }
            Action::ToggleGrid => {
                self.overlays.grid = match self.overlays.grid {
                    None => Some(GRID_COLOR),
                    Some(_) => None,
                };
                true
            }
            Action::ToggleAxes => {
                self.overlays.axes = !self.overlays.axes;
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
                self.view_up = self.home.up;
                self.ortho = match self.home.projection {
                    Projection::Perspective => None,
                    Projection::Orthographic { height } => Some(height),
                };
                self.preset = None;
                true
            }
            Action::ToggleOrtho => {
                self.ortho = match self.ortho {
                    Some(_) => None,
                    None => Some(self.perspective_height()),
                };
                term::say(if self.ortho.is_some() {
                    "orthographic"
                } else {
                    "perspective"
                });
                true
            }
            Action::NextView => {
                let preset = self.preset.map_or(ViewPreset::Front, ViewPreset::next);
                self.show_preset(preset);
                term::say(&format!("view {preset}"));
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
            Action::PlayPause => {
                self.clock.playing = !self.clock.playing;
                self.clock.last_tick = None;
                term::say(&format!(
                    "{} at {:.2} s",
                    if self.clock.playing {
                        "playing"
                    } else {
                        "paused"
                    },
                    self.clock.seconds
                ));
                true
            }
            Action::Scrub(by) => {
                self.clock.playing = false;
                self.clock.seconds += by;
                true
            }
            Action::Rewind => {
                self.clock.seconds = 0.0;
                self.clock.last_tick = None;
                true
            }
            Action::Quit => false,
        }
    }

    /// The orthographic height at the orbit's first distance that shows, at the target, what
    /// the perspective view shows there.
    fn perspective_height(&self) -> f32 {
        let cam = Camera {
            projection: Projection::Perspective,
            ..self.camera()
        };
        cam.view_height_at_target() / self.orbit.zoom_ratio()
    }

    /// Puts the camera at the standard view `preset` of the whole scene, fitted to the frame;
    /// an orthographic view stays orthographic, its height fitted too.
    pub fn show_preset(&mut self, preset: ViewPreset) {
        let (centre, radius) = self
            .scene
            .bounding_sphere()
            .unwrap_or((self.home.target, 1.0));
        let (w, h) = self.frame_size();
        let aspect = w.max(1) as f32 / h.max(1) as f32;
        let cam = preset_camera(preset, centre, radius, self.home.fov_y_deg, aspect);
        self.orbit = OrbitCamera::new(cam.eye, cam.target, cam.up);
        self.view_up = cam.up;
        self.preset = Some(preset);
        if self.ortho.is_some() {
            self.ortho = Some(self.perspective_height());
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use phosphor_math::glam::Vec3;
    use phosphor_scene::Scene;
    use winit::keyboard::KeyCode;

    use super::*;
    use crate::input::key_action;

    #[test]
    fn o_switches_to_an_orthographic_view_of_the_same_height_and_back() {
        let mut viewer = Viewer::new(Scene::default_scene().unwrap());
        let before = viewer.camera();
        assert_eq!(before.projection, Projection::Perspective);
        assert!(viewer.act(Action::ToggleOrtho, 540));
        let ortho = viewer.camera();
        let Projection::Orthographic { height } = ortho.projection else {
            panic!("not orthographic: {ortho:?}");
        };
        assert!((height - before.view_height_at_target()).abs() < 1e-4);
        // Zooming in narrows the orthographic view as it moves a perspective eye closer.
        viewer.act(Action::Zoom(3.0), 540);
        assert!(viewer.camera().view_height_at_target() < height);
        // The [camera] block keeps the projection.
        let block = viewer.camera_block();
        let loaded = Scene::parse(&block, "pasted.toml").unwrap();
        assert_eq!(loaded.camera(), viewer.camera(), "{block}");
        viewer.act(Action::ToggleOrtho, 540);
        assert_eq!(viewer.camera().projection, Projection::Perspective);
        viewer.act(Action::ResetView, 540);
        assert_eq!(viewer.camera(), before);
    }

    #[test]
    fn the_clock_plays_pauses_and_scrubs_and_the_title_shows_it() {
        let text = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../assets/scenes/animated.toml"),
        )
        .unwrap();
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
        let scene =
            phosphor_scene::parse_scene(&text, "animated.toml", &dir, &phosphor_scene::Disk)
                .unwrap();
        let mut viewer = Viewer::new(scene);
        assert!(viewer.animated());
        assert!(!viewer.playing(), "a scene opens paused");
        assert!(
            viewer.title().contains("t 0.00 s paused"),
            "{}",
            viewer.title()
        );
        assert!(viewer.act(Action::PlayPause, 540));
        assert!(viewer.playing());
        // Scrubbing pauses and moves the clock; shift steps a second.
        viewer.act(Action::Scrub(1.0), 540);
        viewer.act(Action::Scrub(0.1), 540);
        assert!(!viewer.playing());
        assert!((viewer.clock.seconds - 1.1).abs() < 1e-12);
        assert!(
            viewer.title().contains("t 1.10 s paused"),
            "{}",
            viewer.title()
        );
        // The frame drawn is posed at the clock: the spinning turntable has turned 33 degrees.
        let mut out = vec![0u32; 64 * 36];
        viewer.draw(64, 36, &mut out, false).unwrap();
        assert_eq!(viewer.scene.time.seconds, 1.1);
        let table = viewer
            .scene
            .objects()
            .into_iter()
            .find(|&e| {
                viewer
                    .scene
                    .world
                    .get::<&phosphor_scene::Name>(e)
                    .unwrap()
                    .0
                    == "turntable"
            })
            .unwrap();
        let turned = viewer
            .scene
            .world
            .get::<&phosphor_scene::Transform>(table)
            .unwrap()
            .rotate_deg;
        assert!(
            (turned - Vec3::new(0.0, 33.0, 0.0)).length() < 1e-3,
            "{turned}"
        );
        viewer.act(Action::Rewind, 540);
        assert_eq!(viewer.clock.seconds, 0.0);
        assert_eq!(key_action(KeyCode::Space, false), Some(Action::PlayPause));
        assert_eq!(
            key_action(KeyCode::BracketLeft, true),
            Some(Action::Scrub(-1.0))
        );
        // A still scene has no clock in its title.
        let still = Viewer::new(Scene::default_scene().unwrap());
        assert!(!still.animated() && !still.title().contains("t 0.00 s"));
    }

    #[test]
    fn v_steps_through_the_standard_views_framing_the_scene() {
        let mut viewer = Viewer::new(Scene::default_scene().unwrap());
        let start = viewer.camera();
        let (centre, _) = viewer.scene.bounding_sphere().unwrap();
        viewer.act(Action::NextView, 540);
        assert_eq!(viewer.preset, Some(ViewPreset::Front));
        let front = viewer.camera();
        assert!((front.target - centre).length() < 1e-4);
        let dir = (front.eye - front.target).normalize();
        assert!(dir.distance(Vec3::Z) < 1e-4, "{dir}");
        for _ in 0..4 {
            viewer.act(Action::NextView, 540);
        }
        assert_eq!(viewer.preset, Some(ViewPreset::Top));
        let top = viewer.camera();
        assert!((top.eye - top.target).normalize().distance(Vec3::Y) < 1e-4);
        assert!(top.view().is_finite());
        viewer.act(Action::ResetView, 540);
        assert_eq!(viewer.camera(), start);
    }
}
