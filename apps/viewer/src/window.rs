//! The winit + softbuffer boilerplate: the event loop, the window, presenting pixels.
//!
//! Structure as winit 0.30 documents it (docs/conventions.md, "Dependency facts"; winit 0.30
//! `ApplicationHandler`, softbuffer 0.4): the softbuffer context is made before `run_app`, the
//! window and surface in `resumed`, and frames are drawn only in `RedrawRequested`. The loop waits
//! (`ControlFlow::Wait`): a frame is drawn only when input changed something, so an idle viewer
//! uses no CPU, except once: a view that drew a cheaper frame while the user moved (see
//! [`View::wants_refinement`]) gets one more, refined frame after [`IDLE_DELAY`] without input. What is drawn is up to a [`View`] (implemented in `main.rs`); this file knows
//! nothing of scenes.

use std::collections::BTreeSet;
use std::num::NonZeroU32;
use std::path::PathBuf;
use std::rc::Rc;
use std::time::{Duration, Instant};

use softbuffer::{Context, Surface};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseScrollDelta, StartCause, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop, OwnedDisplayHandle};
use winit::keyboard::PhysicalKey;
use winit::window::{Window, WindowId};

use phosphor_output::term;

use crate::input::{Action, MouseDrag, key_action, wheel_pixels_to_lines};
use crate::watch::Watch;

/// What the window shows and how it reacts; `main.rs` implements it with the scene renderer.
pub trait View {
    /// Draws a frame of `width` x `height` physical pixels into `out` (row-major, `0x00RRGGBB`,
    /// `out.len() == width * height`). `held`: `out` still holds the words of the frame this
    /// view drew into it last (the surface's buffer age is 1), so only what changed need be
    /// written. Returns an error message if it could not draw.
    fn draw(&mut self, width: u32, height: u32, out: &mut [u32], held: bool) -> Result<(), String>;
    /// The window title describing the last frame.
    fn title(&self) -> String;
    /// Applies a user action; returns true when the picture must be redrawn.
    fn apply(&mut self, action: Action, height: u32) -> bool;
    /// Writes the last frame drawn to `path` as PNG (atomically).
    fn save_screenshot(&self, path: &std::path::Path) -> Result<(), String>;
    /// Whether the last frame was drawn cheaper than the still picture should be (less
    /// anti-aliasing while the user moved): the loop then asks for [`View::refine`] once input
    /// has stopped for [`IDLE_DELAY`].
    fn wants_refinement(&self) -> bool;
    /// Makes the next frame the refined still picture.
    fn refine(&mut self);
    /// Whether the picture moves on its own (an animation playing): the loop then draws
    /// frame after frame instead of waiting for input.
    fn playing(&self) -> bool;
    /// The files the picture was made from, watched for live reload (outside `--frames`
    /// mode); none for a picture made from nothing on disk.
    fn watched(&self) -> BTreeSet<PathBuf>;
    /// Makes the picture again after a watched file changed; true when it must be redrawn.
    fn reload(&mut self) -> bool;
}

/// Quiet time after the last change to a watched file before the view is reloaded: an
/// editor's save is several events (truncate, write, close, or write and rename).
pub const RELOAD_QUIET: Duration = Duration::from_millis(100);

/// The event the file watcher sends the loop, from its own thread.
#[derive(Debug, Clone, Copy)]
pub struct FilesChanged;

/// Time without input after which a view that wants refinement draws its still picture.
pub const IDLE_DELAY: Duration = Duration::from_millis(150);

/// How the window is opened and when it closes on its own.
#[derive(Clone, Debug, Default)]
pub struct WindowOptions {
    /// Inner size in physical pixels.
    pub size: (u32, u32),
    /// Close after this many frames (for tests and screenshots).
    pub frames: Option<u32>,
    /// Write the last frame here as PNG before closing.
    pub screenshot: Option<PathBuf>,
}

/// Why the viewer could not run.
#[derive(Debug)]
pub enum WindowError {
    /// No display server could be reached (no `DISPLAY`, no Wayland socket, or it refused us).
    NoDisplay(String),
    /// The window opened but drawing, presenting or saving failed.
    Failed(String),
}

/// Runs the viewer until the window is closed (or the frame count is reached); gives the view
/// back so the caller can report on it.
pub fn run<V: View>(view: V, options: WindowOptions) -> Result<V, WindowError> {
    let event_loop = EventLoop::<FilesChanged>::with_user_event()
        .build()
        .map_err(|e| WindowError::NoDisplay(one_line(&e)))?;
    event_loop.set_control_flow(ControlFlow::Wait);
    let watch = if options.frames.is_none() && !view.watched().is_empty() {
        let proxy = event_loop.create_proxy();
        match Watch::new(move || {
            // The loop is gone only when the window closed: nothing left to reload.
            let _ = proxy.send_event(FilesChanged);
        }) {
            Ok(mut watch) => {
                for w in watch.set(&view.watched()) {
                    term::warn(&w);
                }
                Some(watch)
            }
            Err(e) => {
                term::warn(&format!(
                    "warning: {e}; the scene is not reloaded when its files change"
                ));
                None
            }
        }
    } else {
        None
    };
    let context = Context::new(event_loop.owned_display_handle())
        .map_err(|e| WindowError::NoDisplay(one_line(&e)))?;
    let mut app = App {
        view,
        options,
        context,
        gfx: None,
        drag: MouseDrag::default(),
        shift: false,
        frames_drawn: 0,
        error: None,
        watch,
        refine_at: None,
        reload_at: None,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| WindowError::Failed(one_line(&e)))?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(app.view),
    }
}

/// Error text on one line (some platform errors carry newlines), without winit's source location
/// (`os error at /path/to/mod.rs:765: why` becomes `why`).
fn one_line(e: &dyn std::fmt::Display) -> String {
    let text = e
        .to_string()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    match text.find(".rs:") {
        Some(at) => match text[at..].find(": ") {
            Some(colon) => text[at + colon + 2..].to_string(),
            None => text,
        },
        None => text,
    }
}

/// The window and the surface presenting into it.
struct Gfx {
    window: Rc<Window>,
    surface: Surface<OwnedDisplayHandle, Rc<Window>>,
}

/// The `ApplicationHandler`: event plumbing between winit, softbuffer and the [`View`].
struct App<V: View> {
    view: V,
    options: WindowOptions,
    context: Context<OwnedDisplayHandle>,
    gfx: Option<Gfx>,
    drag: MouseDrag,
    shift: bool,
    frames_drawn: u32,
    error: Option<WindowError>,
    /// The watch over the view's files (live reload), outside `--frames` mode.
    watch: Option<Watch>,
    /// When the still picture is due, if the last frame was a cheaper one.
    refine_at: Option<Instant>,
    /// When a reload is due: [`RELOAD_QUIET`] after the last change to a watched file.
    reload_at: Option<Instant>,
}

impl<V: View> App<V> {
    /// Stops the loop, keeping the first error.
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: WindowError) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }

    /// Draws and presents one frame at the window's physical size.
    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let Some(gfx) = self.gfx.as_mut() else { return };
        // Size from inner_size(), not from Resized: X11 sends no initial Resized (ECOSYSTEM 2.1).
        let size = gfx.window.inner_size();
        let (Some(w), Some(h)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) else {
            return; // minimised
        };
        let result = gfx
            .surface
            .resize(w, h)
            .map_err(|e| one_line(&e))
            .and_then(|()| gfx.surface.buffer_mut().map_err(|e| one_line(&e)))
            .and_then(|mut buffer| {
                let held = buffer.age() == 1;
                self.view.draw(w.get(), h.get(), &mut buffer, held)?;
                buffer.present().map_err(|e| one_line(&e))
            });
        if let Err(e) = result {
            self.fail(event_loop, WindowError::Failed(e));
            return;
        }
        gfx.window.set_title(&self.view.title());
        self.frames_drawn += 1;
        // Interactive only: `--frames` runs draw exactly the frames asked for.
        if self.options.frames.is_none() {
            self.refine_at = self
                .view
                .wants_refinement()
                .then(|| Instant::now() + IDLE_DELAY);
            if self.view.playing() {
                gfx.window.request_redraw();
            }
            self.schedule(event_loop);
        }
        self.after_frame(event_loop);
    }

    /// In `--frames` mode: asks for the next frame, or saves the screenshot and exits.
    fn after_frame(&mut self, event_loop: &ActiveEventLoop) {
        let Some(limit) = self.options.frames else {
            return;
        };
        if self.frames_drawn < limit {
            if let Some(gfx) = &self.gfx {
                gfx.window.request_redraw();
            }
            return;
        }
        if let Some(path) = self.options.screenshot.clone() {
            if let Err(e) = self.view.save_screenshot(&path) {
                self.fail(event_loop, WindowError::Failed(e));
                return;
            }
        }
        event_loop.exit();
    }

    /// Waits for the next deadline (the still picture, a reload), or for input.
    fn schedule(&self, event_loop: &ActiveEventLoop) {
        let next = [self.refine_at, self.reload_at].into_iter().flatten().min();
        event_loop.set_control_flow(next.map_or(ControlFlow::Wait, ControlFlow::WaitUntil));
    }

    /// Reloads the view once the changes to its files have settled, and watches the files
    /// the reloaded view was made from.
    fn reload_if_due(&mut self) {
        if self.reload_at.is_none_or(|at| at > Instant::now()) {
            return;
        }
        self.reload_at = None;
        if self.view.reload() {
            if let Some(gfx) = &self.gfx {
                gfx.window.request_redraw();
            }
        }
        if let Some(watch) = &mut self.watch {
            for w in watch.set(&self.view.watched()) {
                term::warn(&w);
            }
        }
    }

    /// Applies an action and schedules a frame if the picture changed.
    fn act(&mut self, event_loop: &ActiveEventLoop, action: Action) {
        if action == Action::Quit {
            event_loop.exit();
            return;
        }
        let height = self
            .gfx
            .as_ref()
            .map_or(1, |g| g.window.inner_size().height.max(1));
        if self.view.apply(action, height) {
            if let Some(gfx) = &self.gfx {
                gfx.window.request_redraw();
            }
        }
    }
}

impl<V: View> ApplicationHandler<FilesChanged> for App<V> {
    fn new_events(&mut self, event_loop: &ActiveEventLoop, cause: StartCause) {
        self.reload_if_due();
        // The idle delay ran out with no input since the last frame: draw the still picture.
        if let StartCause::ResumeTimeReached { .. } = cause
            && self.refine_at.is_some_and(|at| at <= Instant::now())
        {
            self.refine_at = None;
            if self.view.wants_refinement() {
                self.view.refine();
                if let Some(gfx) = &self.gfx {
                    gfx.window.request_redraw();
                }
            }
        }
        self.schedule(event_loop);
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, _: FilesChanged) {
        self.reload_at = Some(Instant::now() + RELOAD_QUIET);
        self.schedule(event_loop);
    }

    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        let (w, h) = self.options.size;
        let attributes = Window::default_attributes()
            .with_title(self.view.title())
            .with_inner_size(PhysicalSize::new(w.max(1), h.max(1)));
        let window = match event_loop.create_window(attributes) {
            Ok(window) => Rc::new(window),
            Err(e) => return self.fail(event_loop, WindowError::NoDisplay(one_line(&e))),
        };
        let surface = match Surface::new(&self.context, window.clone()) {
            Ok(surface) => surface,
            Err(e) => return self.fail(event_loop, WindowError::Failed(one_line(&e))),
        };
        window.request_redraw();
        self.gfx = Some(Gfx { window, surface });
    }

    fn suspended(&mut self, _event_loop: &ActiveEventLoop) {
        self.gfx = None;
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            // Physical size changed (also after a scale change): draw at the new size.
            WindowEvent::Resized(_) | WindowEvent::ScaleFactorChanged { .. } => {
                if let Some(gfx) = &self.gfx {
                    gfx.window.request_redraw();
                }
            }
            WindowEvent::ModifiersChanged(modifiers) => {
                self.shift = modifiers.state().shift_key();
                self.drag.set_shift(self.shift);
            }
            WindowEvent::KeyboardInput { event, .. } => {
                if event.state != ElementState::Pressed || event.repeat {
                    return;
                }
                if let PhysicalKey::Code(code) = event.physical_key {
                    if let Some(action) = key_action(code, self.shift) {
                        self.act(event_loop, action);
                    }
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                self.drag.button(button, state == ElementState::Pressed);
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some(action) = self.drag.moved(position.x, position.y) {
                    self.act(event_loop, action);
                }
            }
            WindowEvent::CursorLeft { .. } => self.drag.cursor_left(),
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => wheel_pixels_to_lines(p.y),
                };
                if lines != 0.0 {
                    self.act(event_loop, Action::Zoom(lines));
                }
            }
            _ => {}
        }
    }
}
