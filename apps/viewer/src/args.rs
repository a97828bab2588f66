//! The viewer's command line: the scene, the window, the frames to draw, and the camera and
//! normal flags it shares with `phosphor render` ([`phosphor_args`]). Every flag is listed in
//! `--help` under the heading of its concern (the test below walks them all).

use std::path::PathBuf;

use clap::Parser;
use phosphor_args::{INPUT_HEADING, RENDERING_HEADING};
use phosphor_raster::Antialias;
use phosphor_scene::ShadingChoice;

/// Help heading of `--frames`, `--screenshot` and `--force`.
pub const FRAMES_HEADING: &str = "Frames and screenshots (close after N frames)";

/// `on` or `off`.
///
/// # Errors
/// Anything else.
pub fn parse_on_off(text: &str) -> Result<bool, String> {
    match text {
        "on" => Ok(true),
        "off" => Ok(false),
        other => Err(format!("expected on or off, got '{other}'")),
    }
}

/// Largest accepted window side, in pixels.
pub const MAX_SIDE: u32 = 16_384;

/// Command line of `phosphor-viewer`.
#[derive(Debug, Parser)]
#[command(
    name = "phosphor-viewer",
    version,
    about = "Real-time viewer for Phosphor scenes (CPU scan-line rasterizer)",
    after_help = "Examples:\n  phosphor-viewer\n  phosphor-viewer assets/scenes/s1.toml\n  phosphor-viewer --mesh assets/meshes/teapot.obj --size 1280x720\n  phosphor-viewer --frames 10 --screenshot shot.png\n  phosphor-viewer assets/scenes/s1.toml --shading phong --size 1280x720 --frames 100\n  phosphor-viewer --mesh assets/meshes/cube.obj --azimuth 45 --elevation 30\n  phosphor-viewer --mesh assets/meshes/teapot.obj --view front --ortho\n  phosphor-viewer assets/scenes/s1.toml --eye 2,1,3 --fov 30\n\nKeys: C prints the camera as a [camera] block for a scene file, S saves a screenshot beside it,\nT switches fast-phong between taylor (Bishop and Weimer 1986) and fit, I switches gouraud and\nphong between plane and incremental (Gouraud 1971) interpolation; the title shows both.\nO switches between perspective and orthographic, V steps through the standard views.\nIn --frames mode the viewer prints `frames=N mean_ms=X median_ms=M fps=Y triangles=T` when it exits.\nPress H in the window for the key list."
)]
pub struct Args {
    /// Scene file (TOML); the embedded default scene when absent.
    pub scene: Option<PathBuf>,
    /// Show this mesh (OBJ, PLY, STL, glTF or GLB, by extension) under S1's lights and material
    /// instead of a scene file, framed to fit the window from a three-quarter angle (azimuth
    /// 30, elevation 20).
    #[arg(
        long,
        help_heading = INPUT_HEADING,
        value_name = "FILE.obj",
        conflicts_with = "scene"
    )]
    pub mesh: Option<PathBuf>,
    /// Window inner size in physical pixels.
    #[arg(long, help_heading = RENDERING_HEADING, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Start with this shading for every object (`auto`: the scene's own choice per object).
    #[arg(long, help_heading = RENDERING_HEADING, value_name = "MODE", value_parser = parse_shading)]
    pub shading: Option<ShadingChoice>,
    /// Anti-aliasing of the still picture (default: the scene file's `aa`, else msaa4; with
    /// --frames, the scene file's): 4 or 16 samples per pixel, `msaa` shading each pixel once
    /// per triangle, `ssaa` every sample (about 4 or 16 times the cost). Frames drawn while
    /// you move use it only if it keeps 60 frames a second. Key A switches it.
    #[arg(
        long,
        help_heading = RENDERING_HEADING,
        value_name = "off|msaa4|ssaa4|msaa16|ssaa16",
        value_parser = phosphor_args::parse_antialias
    )]
    pub aa: Option<Antialias>,
    /// Shadow maps for every directional, spot and point light (on) or none (off), overriding
    /// the scene's `shadows = true` per light (default: as the scene says). Key D cycles the
    /// scene's, off and on.
    #[arg(long, help_heading = RENDERING_HEADING, value_name = "on|off", value_parser = parse_on_off)]
    pub shadows: Option<bool>,
    /// Background, overriding the scene's `render.background`: a linear colour R,G,B,
    /// R,G,B,A with an opacity A in [0, 1], or `transparent`. The window shows a background
    /// that is not opaque over black (its colour times its opacity).
    #[arg(
        long,
        help_heading = RENDERING_HEADING,
        value_name = "R,G,B|transparent",
        allow_hyphen_values = true,
        value_parser = phosphor_args::parse_background
    )]
    pub background: Option<phosphor_args::Background>,
    /// Draw this many frames, then exit.
    #[arg(
        long,
        help_heading = FRAMES_HEADING,
        value_name = "N",
        value_parser = clap::value_parser!(u32).range(1..)
    )]
    pub frames: Option<u32>,
    /// Write the last frame as PNG before exiting (after --frames frames, default 1).
    #[arg(
        long,
        help_heading = FRAMES_HEADING,
        value_name = "FILE.png",
        value_parser = parse_png_path
    )]
    pub screenshot: Option<PathBuf>,
    /// Camera flags.
    #[command(flatten)]
    pub camera: phosphor_args::CameraArgs,
    /// Normal flags of --mesh.
    #[command(flatten)]
    pub normals: phosphor_args::NormalArgs,
    /// Let --screenshot replace a read-only file, or write into a device or FIFO.
    #[arg(long, help_heading = FRAMES_HEADING)]
    pub force: bool,
}

/// A screenshot path: it must end in `.png`, the only format the viewer writes.
pub fn parse_png_path(text: &str) -> Result<PathBuf, String> {
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

/// Parses a shading name: `auto` or one of the modes.
pub fn parse_shading(text: &str) -> Result<ShadingChoice, String> {
    text.parse()
}

/// Parses `WxH` (e.g. `640x480`) into a non-zero size.
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
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

#[cfg(test)]
mod tests {
    use clap::CommandFactory;
    use phosphor_args::{CAMERA_HEADING, NORMALS_HEADING};

    use super::*;

    /// The heading each flag belongs under.
    fn expected(flag: &str) -> Option<&'static str> {
        Some(match flag {
            "mesh" => INPUT_HEADING,
            "size" | "shading" | "aa" | "shadows" | "background" => RENDERING_HEADING,
            "frames" | "screenshot" | "force" => FRAMES_HEADING,
            "eye" | "target" | "up" | "fov" | "azimuth" | "elevation" | "distance" | "ortho"
            | "view" => CAMERA_HEADING,
            "crease_angle"
            | "normals"
            | "weighting"
            | "no_smoothing_groups"
            | "split_by_material" => NORMALS_HEADING,
            _ => return None,
        })
    }

    #[test]
    fn every_viewer_flag_is_under_its_concerns_heading() {
        let command = Args::command();
        let mut checked = 0;
        for arg in command.get_arguments() {
            let id = arg.get_id().as_str();
            if arg.is_positional() || matches!(id, "help" | "version") {
                continue;
            }
            let want = expected(id);
            assert!(
                want.is_some(),
                "--{id}: no heading expected; add it to this test"
            );
            assert_eq!(arg.get_help_heading(), want, "--{id}");
            checked += 1;
        }
        assert!(checked >= 20, "only {checked} flags seen");
    }
}
