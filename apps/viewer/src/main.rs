//! `phosphor-viewer`: the real-time window onto a Phosphor scene.
//!
//! ```text
//! phosphor-viewer [SCENE.toml] [--mesh FILE.obj] [--size WxH] [--frames N --screenshot FILE.png]
//! ```
//!
//! This file is about rendering: what is drawn and how the title describes it. The window
//! plumbing lives in `window.rs`, the camera and key table in `input.rs`.

#[allow(dead_code)] // the orbit camera is used once the scene crate lands
mod input;
mod window;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;

use crate::input::{Action, KEY_HELP};
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
    after_help = "Examples:\n  phosphor-viewer\n  phosphor-viewer assets/scenes/s1.toml\n  phosphor-viewer --mesh assets/meshes/teapot.obj --size 1280x720\n  phosphor-viewer --frames 10 --screenshot shot.png\n\nPress H in the window for the key list."
)]
struct Args {
    /// Scene file (TOML); the embedded default scene when absent.
    scene: Option<PathBuf>,
    /// Show this OBJ mesh in the standard scene S1 instead of a scene file.
    #[arg(long, value_name = "FILE.obj", conflicts_with = "scene")]
    mesh: Option<PathBuf>,
    /// Window inner size in physical pixels.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Draw this many frames, then exit.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    frames: Option<u32>,
    /// Write the last frame as PNG before exiting (after --frames frames, default 1).
    #[arg(long, value_name = "FILE.png")]
    screenshot: Option<PathBuf>,
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

/// The scene renderer behind the window (placeholder pattern until the scene crate lands).
struct Viewer {
    last: Vec<u32>,
    size: (u32, u32),
    angle: f32,
}

impl View for Viewer {
    fn draw(&mut self, width: u32, height: u32, out: &mut [u32]) -> Result<(), String> {
        for (i, px) in out.iter_mut().enumerate() {
            let x = (i as u32 % width) * 255 / width;
            let y = (i as u32 / width) * 255 / height;
            *px = (x << 16) | (y << 8) | ((self.angle as u32) & 255);
        }
        self.last = out.to_vec();
        self.size = (width, height);
        Ok(())
    }

    fn title(&self) -> String {
        "Phosphor (H: keys)".to_string()
    }

    fn apply(&mut self, action: Action, _height: u32) -> bool {
        match action {
            Action::Help => {
                println!("{KEY_HELP}");
                false
            }
            Action::Orbit { dx, .. } => {
                self.angle += dx;
                true
            }
            _ => true,
        }
    }

    fn save_screenshot(&self, path: &Path) -> Result<(), String> {
        let mut rgb = Vec::with_capacity(self.last.len() * 3);
        for px in &self.last {
            rgb.extend_from_slice(&[(px >> 16) as u8, (px >> 8) as u8, *px as u8]);
        }
        let tmp = path.with_extension("png.tmp");
        image::save_buffer_with_format(
            &tmp,
            &rgb,
            self.size.0,
            self.size.1,
            image::ColorType::Rgb8,
            image::ImageFormat::Png,
        )
        .map_err(|e| format!("{}: {e}", path.display()))?;
        std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    let viewer = Viewer {
        last: Vec::new(),
        size: (1, 1),
        angle: 0.0,
    };
    let options = WindowOptions {
        size: args.size.unwrap_or(DEFAULT_SIZE),
        frames: args.frames.or(args.screenshot.as_ref().map(|_| 1)),
        screenshot: args.screenshot,
    };
    match window::run(viewer, options) {
        Ok(()) => ExitCode::SUCCESS,
        Err(WindowError::NoDisplay(why)) => {
            eprintln!(
                "error: no display available ({why}); use `phosphor render` to render to a file"
            );
            ExitCode::from(1)
        }
        Err(WindowError::Failed(why)) => {
            eprintln!("error: {why}");
            ExitCode::from(1)
        }
    }
}
