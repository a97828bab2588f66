//! Camera and keys: the orbit camera and the mapping from keys and mouse motion to viewer actions.
//!
//! Kept free of window state so that the camera math and the key table are unit-tested without a
//! display. The window code (`window.rs`) feeds winit events in; the renderer (`main.rs`) applies
//! the resulting [`Action`]s.

use phosphor_math::glam::Vec3;
use phosphor_raster::ShadingMode;
use winit::event::MouseButton;
use winit::keyboard::KeyCode;

/// Radians of orbit per physical pixel of drag.
const ORBIT_RADIANS_PER_PIXEL: f32 = 0.008;
/// Zoom factor per wheel line (distance is multiplied by this per line towards the target).
const ZOOM_PER_LINE: f32 = 0.9;
/// Wheel pixels that count as one line (touchpads report pixel deltas).
const PIXELS_PER_LINE: f32 = 40.0;
/// Pitch stays this far from the poles so that the view direction never lines up with `up`.
const MAX_PITCH: f32 = 1.55;
/// Closest and farthest orbit distance, relative to the initial distance.
const MIN_DISTANCE_RATIO: f32 = 0.05;
/// See [`MIN_DISTANCE_RATIO`].
const MAX_DISTANCE_RATIO: f32 = 20.0;

/// The key list's lines above the mode keys.
const KEY_HELP_HEAD: &str = "\
phosphor-viewer keys:
  left drag            orbit around the target
  right drag, shift+left drag   pan
  wheel                zoom";

/// The key list's lines below the mode keys.
const KEY_HELP_TAIL: &str = "\
  F1..F8 (or shift+1..8)  toggle light 1..8 (in scene-file order)
  B                    toggle bump mapping
  M                    toggle colour maps (textures)
  D                    shadows: the scene's, off, on (every directional, spot and point light)
  P                    toggle perspective-correct interpolation
  A                    anti-aliasing of the still picture: off, msaa4, ssaa4, msaa16, ssaa16
  T                    fast-phong: Taylor expansion (Bishop and Weimer 1986) / six-point fit
  I                    gouraud, phong: plane / incremental scan line (Gouraud 1971)
  O                    orthographic / perspective projection
  V                    next standard view: front, right, back, left, top, bottom, iso
  W                    wireframe over the picture: every edge, crease edges only, off
  G, X                 toggle the ground grid, the axes (x red, y green, z blue)
  R                    reset the view
  C                    print the camera as a scene file's [camera] block (paste it into a scene)
  Space                play / pause the scene's clock (spins, orbits, bobs, keyframes)
  [ ]                  step the clock back / on by 0.1 s (shift: 1 s); Backspace: back to 0
  S                    save a screenshot (PNG) beside the scene file (current folder for --mesh)
  H                    print this list
  Esc, Q               quit";

/// The key list printed by `H` (and at start-up): keys 1, 2, ... pick the modes of
/// [`ShadingMode::ALL`] in its order, 0 the scene's own shading.
#[must_use]
pub fn key_help() -> String {
    let modes: Vec<String> = ShadingMode::ALL
        .iter()
        .enumerate()
        .map(|(i, m)| format!("{} {m}", i + 1))
        .collect();
    format!(
        "{KEY_HELP_HEAD}\n  {}  0 auto (the scene's own shading)\n{KEY_HELP_TAIL}",
        modes.join("  ")
    )
}

/// Shading choice selected from the keyboard; `Auto` returns to the scene's own shading.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeKey {
    /// Key 0: no override, every object uses the shading its scene asks for.
    Auto,
    /// Keys 1, 2, ...: force this mode (an index into [`ShadingMode::ALL`]).
    Mode(usize),
}

/// Something the user asked the viewer to do.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    /// Rotate around the target by this many physical pixels of drag.
    Orbit {
        /// Horizontal drag in pixels (right is positive).
        dx: f32,
        /// Vertical drag in pixels (down is positive).
        dy: f32,
    },
    /// Move the target in the view plane by this many physical pixels of drag.
    Pan {
        /// Horizontal drag in pixels.
        dx: f32,
        /// Vertical drag in pixels.
        dy: f32,
    },
    /// Zoom by wheel lines (positive = closer).
    Zoom(f32),
    /// Switch the shading of every object.
    Shading(ModeKey),
    /// Toggle light `n` (0-based, scene-file order).
    ToggleLight(usize),
    /// Toggle bump mapping.
    ToggleBump,
    /// Cycle shadows: the scene's, off, on.
    CycleShadows,
    /// Toggle colour maps.
    ToggleMaps,
    /// Toggle perspective-correct interpolation.
    TogglePerspective,
    /// Switch anti-aliasing to the next choice (off, msaa4, ssaa4, msaa16, ssaa16).
    CycleAntialias,
    /// Switch fast Phong between the Taylor expansion and the six-point fit.
    ToggleFastPhong,
    /// Switch gouraud and phong between plane and incremental interpolation.
    ToggleInterpolation,
    /// Switch between perspective and orthographic projection.
    ToggleOrtho,
    /// Cycle the wireframe overlay: off, every edge, crease edges only.
    CycleWireframe,
    /// Toggle the ground grid.
    ToggleGrid,
    /// Toggle the axes' triad.
    ToggleAxes,
    /// Go to the next standard view (front, right, back, left, top, bottom, iso).
    NextView,
    /// Back to the scene's camera.
    ResetView,
    /// Print the current camera as a scene file's `[camera]` block.
    PrintCamera,
    /// Save the last frame as a PNG beside the scene file.
    Screenshot,
    /// Play or pause the scene's clock.
    PlayPause,
    /// Move the scene's clock by this many seconds (pauses it).
    Scrub(f64),
    /// Set the scene's clock back to 0.
    Rewind,
    /// Print the key list.
    Help,
    /// Close the viewer.
    Quit,
}

/// Maps a pressed key (physical position, US layout names) to an action.
///
/// Physical keys are used so that shift+1 is "light 1" on every layout, not `!`.
#[must_use]
pub fn key_action(code: KeyCode, shift: bool) -> Option<Action> {
    let digit = match code {
        KeyCode::Digit0 | KeyCode::Numpad0 => Some(0),
        KeyCode::Digit1 | KeyCode::Numpad1 => Some(1),
        KeyCode::Digit2 | KeyCode::Numpad2 => Some(2),
        KeyCode::Digit3 | KeyCode::Numpad3 => Some(3),
        KeyCode::Digit4 | KeyCode::Numpad4 => Some(4),
        KeyCode::Digit5 | KeyCode::Numpad5 => Some(5),
        KeyCode::Digit6 | KeyCode::Numpad6 => Some(6),
        KeyCode::Digit7 | KeyCode::Numpad7 => Some(7),
        KeyCode::Digit8 | KeyCode::Numpad8 => Some(8),
        _ => None,
    };
    if let Some(d) = digit {
        return match (shift, d) {
            (true, 1..=8) => Some(Action::ToggleLight(d - 1)),
            (true, _) => None,
            (false, 0) => Some(Action::Shading(ModeKey::Auto)),
            (false, d) if d <= ShadingMode::ALL.len() => {
                Some(Action::Shading(ModeKey::Mode(d - 1)))
            }
            (false, _) => None,
        };
    }
    match code {
        KeyCode::F1 => Some(Action::ToggleLight(0)),
        KeyCode::F2 => Some(Action::ToggleLight(1)),
        KeyCode::F3 => Some(Action::ToggleLight(2)),
        KeyCode::F4 => Some(Action::ToggleLight(3)),
        KeyCode::F5 => Some(Action::ToggleLight(4)),
        KeyCode::F6 => Some(Action::ToggleLight(5)),
        KeyCode::F7 => Some(Action::ToggleLight(6)),
        KeyCode::F8 => Some(Action::ToggleLight(7)),
        KeyCode::KeyB => Some(Action::ToggleBump),
        KeyCode::KeyM => Some(Action::ToggleMaps),
        KeyCode::KeyD => Some(Action::CycleShadows),
        KeyCode::KeyP => Some(Action::TogglePerspective),
        KeyCode::KeyA => Some(Action::CycleAntialias),
        KeyCode::KeyT => Some(Action::ToggleFastPhong),
        KeyCode::KeyI => Some(Action::ToggleInterpolation),
        KeyCode::KeyO => Some(Action::ToggleOrtho),
        KeyCode::KeyW => Some(Action::CycleWireframe),
        KeyCode::KeyG => Some(Action::ToggleGrid),
        KeyCode::KeyX => Some(Action::ToggleAxes),
        KeyCode::KeyV => Some(Action::NextView),
        KeyCode::KeyR => Some(Action::ResetView),
        KeyCode::KeyC => Some(Action::PrintCamera),
        KeyCode::KeyS => Some(Action::Screenshot),
        KeyCode::KeyH => Some(Action::Help),
        KeyCode::Space => Some(Action::PlayPause),
        KeyCode::BracketLeft => Some(Action::Scrub(if shift { -1.0 } else { -0.1 })),
        KeyCode::BracketRight => Some(Action::Scrub(if shift { 1.0 } else { 0.1 })),
        KeyCode::Backspace => Some(Action::Rewind),
        KeyCode::Escape | KeyCode::KeyQ => Some(Action::Quit),
        _ => None,
    }
}

/// Turns button and cursor events into orbit and pan actions.
#[derive(Debug, Default)]
pub struct MouseDrag {
    left: bool,
    right: bool,
    shift: bool,
    last: Option<(f64, f64)>,
}

impl MouseDrag {
    /// Records the shift modifier (shift + left drag pans).
    pub fn set_shift(&mut self, shift: bool) {
        self.shift = shift;
    }

    /// Records a button press or release.
    pub fn button(&mut self, button: MouseButton, pressed: bool) {
        match button {
            MouseButton::Left => self.left = pressed,
            MouseButton::Right | MouseButton::Middle => self.right = pressed,
            _ => {}
        }
    }

    /// Forgets the cursor (it left the window), so the next move does not jump.
    pub fn cursor_left(&mut self) {
        self.last = None;
    }

    /// Records a cursor position (physical pixels); returns the drag action it makes, if any.
    pub fn moved(&mut self, x: f64, y: f64) -> Option<Action> {
        let previous = self.last.replace((x, y));
        let (px, py) = previous?;
        let (dx, dy) = ((x - px) as f32, (y - py) as f32);
        if dx == 0.0 && dy == 0.0 {
            return None;
        }
        if self.right || (self.left && self.shift) {
            Some(Action::Pan { dx, dy })
        } else if self.left {
            Some(Action::Orbit { dx, dy })
        } else {
            None
        }
    }
}

/// Converts a wheel delta in pixels to lines.
#[must_use]
pub fn wheel_pixels_to_lines(pixels: f64) -> f32 {
    pixels as f32 / PIXELS_PER_LINE
}

/// A camera orbiting a target: yaw and pitch around it at a distance, plus pan of the target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at and orbited around.
    pub target: Vec3,
    /// Distance from the eye to the target.
    pub distance: f32,
    /// Rotation around `up`, radians.
    pub yaw: f32,
    /// Elevation above the plane normal to `up`, radians, within +-[`MAX_PITCH`].
    pub pitch: f32,
    /// World up direction (unit).
    pub up: Vec3,
    /// Distance at construction, to scale the clip planes with zoom.
    initial_distance: f32,
    /// Basis of the plane normal to `up`: yaw 0 looks along -`forward0`.
    right0: Vec3,
    /// See `right0`.
    back0: Vec3,
}

impl OrbitCamera {
    /// Builds the orbit that reproduces the view from `eye` towards `target` with `up`.
    ///
    /// Degenerate input (eye on the target, non-finite, `up` parallel to the view) falls back to
    /// a distance of 1 and a basis built from the world axes, so the result is always usable.
    #[must_use]
    pub fn new(eye: Vec3, target: Vec3, up: Vec3) -> OrbitCamera {
        let up = up.try_normalize().unwrap_or(Vec3::Y);
        let offset = eye - target;
        let distance = offset.length();
        let distance = if distance.is_finite() && distance > 1e-6 {
            distance
        } else {
            1.0
        };
        let dir = offset.try_normalize().unwrap_or(Vec3::Z);
        // Basis of the horizontal plane: `back0` is the horizontal part of the eye direction.
        let horizontal = dir - up * dir.dot(up);
        let back0 = horizontal
            .try_normalize()
            .or_else(|| up.any_orthonormal_vector().try_normalize())
            .unwrap_or(Vec3::Z);
        let right0 = up.cross(back0).try_normalize().unwrap_or(Vec3::X);
        let pitch = dir
            .dot(up)
            .clamp(-1.0, 1.0)
            .asin()
            .clamp(-MAX_PITCH, MAX_PITCH);
        OrbitCamera {
            target: if target.is_finite() {
                target
            } else {
                Vec3::ZERO
            },
            distance,
            yaw: 0.0,
            pitch,
            up,
            initial_distance: distance,
            right0,
            back0,
        }
    }

    /// The eye position for the current yaw, pitch and distance.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        let horizontal = self.back0 * cy + self.right0 * sy;
        self.target + (horizontal * cp + self.up * sp) * self.distance
    }

    /// Ratio of the current distance to the initial one (to scale near and far planes).
    #[must_use]
    pub fn zoom_ratio(&self) -> f32 {
        self.distance / self.initial_distance
    }

    /// Rotates by a drag of `dx`, `dy` pixels (drag right turns the scene right).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * ORBIT_RADIANS_PER_PIXEL;
        self.pitch = (self.pitch + dy * ORBIT_RADIANS_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Moves the target so that the scene follows a drag of `dx`, `dy` pixels, for a view
    /// that spans `view_height` world units at the target over `height` pixels.
    pub fn pan(&mut self, dx: f32, dy: f32, view_height: f32, height: u32) {
        let eye = self.eye();
        let forward = (self.target - eye).try_normalize().unwrap_or(-self.back0);
        let right = forward
            .cross(self.up)
            .try_normalize()
            .unwrap_or(self.right0);
        let cam_up = right.cross(forward);
        // World units per pixel at the target's depth.
        let per_pixel = view_height / height.max(1) as f32;
        if per_pixel.is_finite() {
            self.target += (-right * dx + cam_up * dy) * per_pixel;
        }
    }

    /// Zooms by `lines` wheel lines (positive = closer), within a range around the start.
    pub fn zoom(&mut self, lines: f32) {
        if !lines.is_finite() {
            return;
        }
        let d = self.distance * ZOOM_PER_LINE.powf(lines);
        self.distance = d.clamp(
            self.initial_distance * MIN_DISTANCE_RATIO,
            self.initial_distance * MAX_DISTANCE_RATIO,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-4
    }

    #[test]
    fn orbit_camera_reproduces_the_initial_eye() {
        for eye in [
            Vec3::new(0.0, 0.0, 3.0),
            Vec3::new(2.0, 1.5, -4.0),
            Vec3::new(-1.0, -2.0, 0.5),
        ] {
            let cam = OrbitCamera::new(eye, Vec3::new(0.1, 0.2, 0.3), Vec3::Y);
            assert!(close(cam.eye(), eye), "{:?} vs {eye:?}", cam.eye());
        }
    }

    #[test]
    fn orbit_keeps_the_distance_and_pitch_stays_off_the_poles() {
        let mut cam = OrbitCamera::new(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y);
        cam.orbit(123.0, 10_000.0);
        assert!((cam.eye().length() - 3.0).abs() < 1e-4);
        assert!(cam.pitch <= MAX_PITCH);
        let dir = cam.eye().normalize();
        assert!(dir.dot(Vec3::Y) < 0.9999, "view never parallel to up");
    }

    #[test]
    fn degenerate_camera_input_gives_a_finite_orbit() {
        let cam = OrbitCamera::new(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
        assert!(cam.eye().is_finite());
        let cam = OrbitCamera::new(Vec3::new(0.0, 5.0, 0.0), Vec3::ZERO, Vec3::Y);
        assert!(cam.eye().is_finite());
    }

    #[test]
    fn zoom_moves_closer_and_is_bounded() {
        let mut cam = OrbitCamera::new(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y);
        cam.zoom(1.0);
        assert!(cam.distance < 3.0);
        cam.zoom(1e6);
        assert!((cam.distance - 3.0 * MIN_DISTANCE_RATIO).abs() < 1e-5);
        cam.zoom(f32::NAN);
        assert!(cam.distance.is_finite());
    }

    #[test]
    fn pan_moves_the_target_in_the_view_plane() {
        let mut cam = OrbitCamera::new(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y);
        cam.pan(10.0, 0.0, 2.0, 100);
        assert!(cam.target.x < 0.0, "drag right moves the scene right");
        // 10 of 100 pixels over a view 2 units tall: 0.2 units.
        assert!((cam.target.x + 0.2).abs() < 1e-5, "{}", cam.target.x);
        assert!(cam.target.z.abs() < 1e-5 && cam.target.y.abs() < 1e-5);
    }

    #[test]
    fn digit_keys_pick_modes_and_shift_digits_toggle_lights() {
        assert_eq!(
            key_action(KeyCode::Digit3, false),
            Some(Action::Shading(ModeKey::Mode(2)))
        );
        assert_eq!(
            key_action(KeyCode::Digit0, false),
            Some(Action::Shading(ModeKey::Auto))
        );
        assert_eq!(
            key_action(KeyCode::Digit3, true),
            Some(Action::ToggleLight(2))
        );
        assert_eq!(key_action(KeyCode::F8, false), Some(Action::ToggleLight(7)));
        assert_eq!(key_action(KeyCode::Digit9, false), None);
        assert_eq!(key_action(KeyCode::Digit6, false), None);
        // The key list names the modes in key order.
        let help = key_help();
        for (i, m) in ShadingMode::ALL.iter().enumerate() {
            assert!(help.contains(&format!("{} {m}  ", i + 1)), "{help}");
        }
        assert_eq!(key_action(KeyCode::KeyB, false), Some(Action::ToggleBump));
        assert_eq!(key_action(KeyCode::KeyM, false), Some(Action::ToggleMaps));
        assert_eq!(key_action(KeyCode::KeyD, false), Some(Action::CycleShadows));
        assert_eq!(
            key_action(KeyCode::KeyA, false),
            Some(Action::CycleAntialias)
        );
    }

    #[test]
    fn c_prints_the_camera_and_s_saves_a_screenshot_and_both_are_listed() {
        assert_eq!(key_action(KeyCode::KeyC, false), Some(Action::PrintCamera));
        assert_eq!(key_action(KeyCode::KeyS, false), Some(Action::Screenshot));
        let help = key_help();
        let listed = |key: &str| help.lines().any(|l| l.trim_start().starts_with(key));
        assert!(listed("C ") && listed("S "), "{help}");
        assert!(listed("T ") && listed("I "), "{help}");
        assert!(listed("O ") && listed("V "), "{help}");
        assert_eq!(key_action(KeyCode::KeyO, false), Some(Action::ToggleOrtho));
        assert_eq!(
            key_action(KeyCode::KeyW, false),
            Some(Action::CycleWireframe)
        );
        assert_eq!(key_action(KeyCode::KeyG, false), Some(Action::ToggleGrid));
        assert_eq!(key_action(KeyCode::KeyX, false), Some(Action::ToggleAxes));
        assert_eq!(key_action(KeyCode::KeyV, false), Some(Action::NextView));
        assert_eq!(
            key_action(KeyCode::KeyT, false),
            Some(Action::ToggleFastPhong)
        );
        assert_eq!(
            key_action(KeyCode::KeyI, false),
            Some(Action::ToggleInterpolation)
        );
    }

    #[test]
    fn drag_with_right_button_or_shift_pans() {
        let mut drag = MouseDrag::default();
        assert_eq!(drag.moved(0.0, 0.0), None);
        drag.button(MouseButton::Left, true);
        assert_eq!(
            drag.moved(5.0, 0.0),
            Some(Action::Orbit { dx: 5.0, dy: 0.0 })
        );
        drag.set_shift(true);
        assert_eq!(drag.moved(5.0, 2.0), Some(Action::Pan { dx: 0.0, dy: 2.0 }));
        drag.set_shift(false);
        drag.button(MouseButton::Left, false);
        drag.button(MouseButton::Right, true);
        assert_eq!(drag.moved(6.0, 2.0), Some(Action::Pan { dx: 1.0, dy: 0.0 }));
    }
}
