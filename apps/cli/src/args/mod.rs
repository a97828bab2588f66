//! The command line: every subcommand and flag of the CLI contract (README, docs/conventions.md),
//! parsed by clap. The values flags take are in [`values`]; every flag is listed in `--help`
//! under a heading ([`headings`] checks that none is left out).
//!
//! Values are checked here (sizes, mode names, encodings) so that a bad value is a usage error
//! (exit 2, clap's message) before any file is read.

mod headings;
mod values;

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use phosphor_args::{
    Background, CameraArgs, INPUT_HEADING, NormalArgs, OUTPUT_HEADING, RENDERING_HEADING,
    parse_antialias, parse_background,
};
use phosphor_raster::Antialias;
use phosphor_scene::ShadingChoice;

pub use self::values::*;
use crate::frames::{FrameRange, parse_frame_range};

/// Help heading of `render`'s sequence flags.
pub const SEQUENCE_HEADING: &str = "Sequences";
/// Help heading of what `accuracy` and `bench` measure.
pub const MEASURING_HEADING: &str = "Measuring";

/// `phosphor`: headless rendering, accuracy report, mesh info and benchmarks.
#[derive(Debug, Parser)]
#[command(
    name = "phosphor",
    version,
    about = "Phosphor: CPU scan-line rendering of the classic shading models",
    after_help = "Examples:\n  phosphor render -o out.png\n  phosphor render assets/scenes/s1.toml --shading phong --size 1280x720 -o s1.png\n  phosphor accuracy --size 320x240 --out-dir accuracy/\n  phosphor info assets/meshes/teapot.obj\n  phosphor bench --shading all --size 1280x720\n  phosphor completions bash > ~/.local/share/bash-completion/completions/phosphor\n  phosphor man > phosphor.1\n\nExit codes: 0 success, 1 input error (file, scene, mesh, output), 2 usage error."
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
    /// Let a glTF file's buffers and images lie outside its own folder (`../common.bin`, or a
    /// symbolic link out of it); by default such a buffer is not read and such an image not
    /// used.
    #[arg(long, global = true)]
    pub allow_outside_assets: bool,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene (or a mesh in the standard scene S1) to a PNG or EXR file.
    #[command(
        after_help = "Examples:\n  phosphor render -o out.png                      (the embedded default scene)\n  phosphor render assets/scenes/s1.toml --shading fast-phong --size 640x480 -o s1.png\n  phosphor render assets/scenes/s1.toml --shading fast-phong --fast-phong fit -o fit.png\n  phosphor render assets/scenes/s1.toml --shading gouraud --interpolation incremental -o inc.png\n  phosphor render --mesh assets/meshes/teapot.obj --encoding linear -o teapot.png\n  phosphor render --mesh assets/meshes/teapot.obj --background transparent --aa msaa16 -o thumb.png\n  phosphor render assets/scenes/default.toml -o hdr.exr   (values above 1 kept)\n  phosphor render assets/scenes/default.toml --exposure -1 --tone-map aces -o aces.png\n  phosphor render assets/scenes/s1.toml --plan    (print the frame plan only)\n  phosphor render --mesh assets/meshes/cube.obj --azimuth 45 --elevation 30 -o cube.png\n  phosphor render --mesh assets/meshes/bunny_small.obj --wireframe=1,1,1 --grid --axes -o wire.png\n  phosphor render --mesh assets/meshes/teapot.obj --view top --ortho -o top.png\n  phosphor render assets/scenes/default.toml --eye 4,2,4 --target 0,0.5,0 --fov 35 -o view.png\n  phosphor render assets/scenes/s1.toml --turntable 36 -o out/frame_%04d.png   (makes out/)\n  phosphor render assets/scenes/s1.toml --turntable 36 --frames 0..18 -o out/frame_%04d.png\n  phosphor render assets/scenes/s1.toml -o - > frame.png   (one PNG on standard output)\n\nThe output format follows the extension: .png (8-bit, sRGB or linear, tagged as such; RGBA\nover a background that is not opaque) or .exr (linear f32, values above 1 kept). Each file\nis written whole or not at all: on any error (a full disk too) an existing file is left\nuntouched. Missing folders of the output are made, once the frame is drawn. A symbolic link\nis written through; a read-only file, a device or a FIFO only with --force."
    )]
    Render(RenderArgs),
    /// Render in every mode, compare each with `reference`, and print a table of errors and times.
    #[command(
        after_help = "Example:\n  phosphor accuracy assets/scenes/s1.toml --size 320x240 --out-dir accuracy/\n\nColumns: mode, median ms per frame, time relative to gouraud, RMSE, PSNR (dB), max abs\nerror, share of pixels off by more than 1/255 (all against `reference`, linear [0,1]), mach\n(mean jump across interior mesh edges of the value for flat, of the one-pixel slope for the\nothers, in 8-bit codes) and mach/ref (its ratio to the reference's same measure).\nRows: every mode, gouraud and phong also with screen-space interpolation, auto, reference.\nWith --out-dir: MODE.png, MODE-error.png (false-colour heat-map, labelled scale bar, white at\n8/255 or more), MODE-mach.png (edge jumps, false colour) and error-vs-time.png (RMSE on a\nlog axis against ms per frame)."
    )]
    Accuracy(AccuracyArgs),
    /// Print statistics of a mesh (OBJ, PLY, STL, glTF, GLB): positions, vertices, triangles, ...
    #[command(after_help = "Example:\n  phosphor info assets/meshes/bunny.obj")]
    Info(InfoArgs),
    /// Render repeatedly after a warm-up and print timings, one line per mode.
    #[command(
        after_help = "Example:\n  phosphor bench assets/scenes/s1.toml --shading all --size 1280x720 --frames 20\n\nOutput, one line per mode:\n  MODE median_ms=X min_ms=Y max_ms=Z frames=N"
    )]
    Bench(BenchArgs),
    /// Print a shell completion script for phosphor to standard output.
    #[command(
        after_help = "Examples:\n  phosphor completions bash > ~/.local/share/bash-completion/completions/phosphor\n  phosphor completions zsh > ~/.zfunc/_phosphor      (with fpath+=~/.zfunc)\n  phosphor completions fish > ~/.config/fish/completions/phosphor.fish\n  phosphor completions powershell >> $PROFILE"
    )]
    Completions(CompletionsArgs),
    /// Print phosphor's manual page (roff) to standard output.
    #[command(after_help = "Example:\n  phosphor man > phosphor.1 && man ./phosphor.1")]
    Man,
}

/// `phosphor completions`.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete in.
    #[arg(value_enum, value_name = "SHELL")]
    pub shell: ShellArg,
}

/// Where the scene comes from: a scene file, a mesh in S1, or the embedded default scene.
#[derive(Clone, Debug, Default, Args)]
pub struct SceneSource {
    /// Scene file (TOML); the embedded default scene when absent.
    #[arg(value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,
    /// Render this mesh (OBJ, PLY, STL, glTF or GLB, by extension) under S1's lights and
    /// material (instead of a scene file), framed to fit the view from a three-quarter angle
    /// (azimuth 30, elevation 20).
    #[arg(
        long,
        help_heading = INPUT_HEADING,
        value_name = "FILE.obj",
        conflicts_with = "scene"
    )]
    pub mesh: Option<PathBuf>,
    /// How `--mesh`'s normals are built.
    #[command(flatten)]
    pub normals: NormalArgs,
    /// Back-face culling, overriding the scene's `cull_backfaces`: `auto` skips back faces
    /// only where that cannot change a pixel (closed solids seen from outside).
    #[arg(long, help_heading = RENDERING_HEADING, value_enum, value_name = "auto|always|never")]
    pub cull: Option<CullArg>,
    /// Anti-aliasing, overriding the scene's `render.aa`: 4 or 16 samples per pixel (a 2x2 or
    /// 4x4 grid, box-filtered); `msaa4`/`msaa16` shade each pixel once per triangle in the
    /// per-pixel modes, `ssaa4`/`ssaa16` shade every sample (about 4 or 16 times the cost).
    #[arg(
        long,
        help_heading = RENDERING_HEADING,
        value_name = "off|msaa4|ssaa4|msaa16|ssaa16",
        value_parser = parse_antialias
    )]
    pub aa: Option<Antialias>,
}

/// `phosphor render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene to render.
    #[command(flatten)]
    pub source: SceneSource,
    /// Shading mode for every object (overrides the scene file).
    #[arg(long, help_heading = RENDERING_HEADING, value_name = "MODE", value_parser = shading_parser())]
    pub shading: Option<ShadingChoice>,
    /// Image size (overrides the scene file).
    #[arg(long, help_heading = RENDERING_HEADING, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<Size>,
    /// Worker threads; 0 = all cores; at most 4 per core (overrides the scene file).
    #[arg(long, help_heading = RENDERING_HEADING, value_name = "N")]
    pub threads: Option<usize>,
    /// Background, overriding the scene's `render.background`: a linear colour R,G,B (as in
    /// a scene file), R,G,B,A with an opacity A in [0, 1], or `transparent`. Where it is not
    /// opaque, PNG gets an alpha channel (the share of each pixel's samples the geometry
    /// covers, over the background's opacity) and EXR an A channel.
    #[arg(
        long,
        help_heading = RENDERING_HEADING,
        value_name = "R,G,B|transparent",
        allow_hyphen_values = true,
        value_parser = parse_background
    )]
    pub background: Option<Background>,
    /// PNG encoding (overrides the scene file; EXR is always linear).
    #[arg(long, help_heading = OUTPUT_HEADING, value_enum, value_name = "srgb|linear")]
    pub encoding: Option<EncodingArg>,
    /// Exposure in stops: intensities are scaled by 2^EV before they are written (PNG and
    /// EXR). Either this or --tone-map keeps intensities above 1 in the frame.
    #[arg(
        long,
        help_heading = OUTPUT_HEADING,
        value_name = "EV",
        default_value = "0",
        allow_hyphen_values = true,
        value_parser = parse_exposure
    )]
    pub exposure: f32,
    /// How PNG brings intensities above 1 into range: `clamp` clips them (the default, the
    /// picture of earlier versions), `reinhard` is x/(1+x), `aces` Narkowicz 2015's fit of
    /// the ACES filmic curve (docs/outputs.md). EXR keeps them as they are.
    #[arg(
        long,
        help_heading = OUTPUT_HEADING,
        value_enum,
        value_name = "clamp|reinhard|aces",
        default_value = "clamp"
    )]
    pub tone_map: ToneMapArg,
    /// Draw every triangle's edges as one-pixel lines over the picture where they are seen
    /// (depth-tested; anti-aliased unless --aa off): black, or the linear colour given as
    /// `--wireframe=R,G,B`.
    #[arg(
        long,
        help_heading = RENDERING_HEADING,
        value_name = "R,G,B",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "0,0,0",
        value_parser = parse_wire_color
    )]
    pub wireframe: Option<phosphor_math::glam::Vec3>,
    /// The wireframe's edges: `all`, or `creases` (where faces meet at more than 60 degrees,
    /// and open borders), or `creases:DEG` at another angle (0 to 180).
    #[arg(
        long,
        help_heading = RENDERING_HEADING,
        value_name = "all|creases[:DEG]",
        requires = "wireframe",
        value_parser = parse_wire_edges
    )]
    pub wire_edges: Option<phosphor_raster::overlay::Edges>,
    /// A ground grid under the scene, in round steps, hidden behind objects: grey, or the
    /// linear colour given as `--grid=R,G,B`.
    #[arg(
        long,
        help_heading = RENDERING_HEADING,
        value_name = "R,G,B",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "0.25,0.25,0.25",
        value_parser = parse_wire_color
    )]
    pub grid: Option<phosphor_math::glam::Vec3>,
    /// The world's axes as a triad in the lower-left corner: x red, y green, z blue.
    #[arg(long, help_heading = RENDERING_HEADING)]
    pub axes: bool,
    /// Variants of fast-phong, gouraud and phong.
    #[command(flatten)]
    pub variants: VariantArgs,
    /// The SIMD level.
    #[command(flatten)]
    pub simd: SimdArgs,
    /// Shadows.
    #[command(flatten)]
    pub shadows: ShadowArgs,
    /// Print the frame plan (per object: mode, effects simulated, lights kept) to stdout.
    #[arg(long, help_heading = OUTPUT_HEADING)]
    pub plan: bool,
    /// Render N frames turning the camera about its up axis through its target: frame k at
    /// 360*k/N degrees from the scene's camera (after the camera flags).
    #[arg(
        long,
        help_heading = SEQUENCE_HEADING,
        value_name = "N",
        value_parser = clap::value_parser!(u32).range(1..)
    )]
    pub turntable: Option<u32>,
    /// The instant rendered, in seconds on the scene's clock (spins, orbits, bobs and
    /// keyframed tracks); with --fps, the time of frame 0. Default 0.
    #[arg(
        long,
        help_heading = SEQUENCE_HEADING,
        value_name = "T",
        value_parser = parse_seconds
    )]
    pub time: Option<f64>,
    /// Render the scene's animation as a sequence at F frames per second: frame k at time
    /// T + k/F (T from --time). Takes --frames A..B; named and split as --turntable is.
    #[arg(
        long,
        help_heading = SEQUENCE_HEADING,
        value_name = "F",
        value_parser = parse_fps,
        conflicts_with = "turntable"
    )]
    pub fps: Option<f64>,
    /// With --turntable or --fps, only these frames: A..B (half-open, B not included), A..=B
    /// (inclusive) or K (one frame). Frame numbers and file names are those of the whole
    /// sequence.
    #[arg(
        long,
        help_heading = SEQUENCE_HEADING,
        value_name = "A..B",
        value_parser = parse_frame_range
    )]
    pub frames: Option<FrameRange>,
    /// Output image, .png or .exr (may be left out with --plan); `-` writes one PNG frame to
    /// standard output. Several frames need a printf-style frame number: out/frame_%04d.png.
    #[arg(
        short,
        long,
        help_heading = OUTPUT_HEADING,
        value_name = "OUT.png|OUT.exr|-",
        required_unless_present = "plan"
    )]
    pub output: Option<PathBuf>,
    /// Camera flags.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Replace a read-only output file, or write into a device or FIFO.
    #[arg(long, help_heading = OUTPUT_HEADING)]
    pub force: bool,
}

/// `phosphor accuracy`.
#[derive(Debug, Args)]
pub struct AccuracyArgs {
    /// The scene to measure.
    #[command(flatten)]
    pub source: SceneSource,
    /// Image size (overrides the scene file).
    #[arg(long, help_heading = RENDERING_HEADING, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<Size>,
    /// Write each mode's image and error heat-map here as PNG (created if missing).
    #[arg(long, help_heading = OUTPUT_HEADING, value_name = "DIR")]
    pub out_dir: Option<PathBuf>,
    /// Variants measured: with a flag, only that variant of its modes; without, every variant
    /// gets a row of its own.
    #[command(flatten)]
    pub variants: VariantArgs,
    /// Frames timed per mode: each is timed until N frames are drawn or half a second has
    /// passed, whichever comes first (at least 3); min, median and max are reported.
    #[arg(
        long,
        help_heading = MEASURING_HEADING,
        value_name = "N",
        default_value_t = 20,
        value_parser = clap::value_parser!(u32).range(1..)
    )]
    pub frames: u32,
    /// Also write every row to this CSV file (mode, frames, ms min/median/max, errors).
    #[arg(long, help_heading = OUTPUT_HEADING, value_name = "FILE.csv")]
    pub csv: Option<PathBuf>,
    /// Camera flags.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Replace read-only files in --out-dir.
    #[arg(long, help_heading = OUTPUT_HEADING)]
    pub force: bool,
}

/// `phosphor info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The mesh file to describe (OBJ, PLY, STL, glTF or GLB, by extension).
    #[arg(value_name = "FILE.obj")]
    pub mesh: PathBuf,
}

/// `phosphor bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The scene to time.
    #[command(flatten)]
    pub source: SceneSource,
    /// Mode to time, or `all` (every mode, one line each).
    #[arg(long, help_heading = MEASURING_HEADING, value_name = "MODE|all", default_value = "all", value_parser = bench_mode_parser())]
    pub shading: BenchMode,
    /// Image size (overrides the scene file).
    #[arg(long, help_heading = RENDERING_HEADING, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<Size>,
    /// Worker threads; 0 = all cores; at most 4 per core (overrides the scene file).
    #[arg(long, help_heading = RENDERING_HEADING, value_name = "N")]
    pub threads: Option<usize>,
    /// Variants of fast-phong, gouraud and phong.
    #[command(flatten)]
    pub variants: VariantArgs,
    /// The SIMD level.
    #[command(flatten)]
    pub simd: SimdArgs,
    /// Shadows.
    #[command(flatten)]
    pub shadows: ShadowArgs,
    /// Timed frames per mode (after one untimed warm-up frame).
    #[arg(
        long,
        help_heading = MEASURING_HEADING,
        value_name = "N",
        default_value_t = 10,
        value_parser = clap::value_parser!(u32).range(1..)
    )]
    pub frames: u32,
    /// Camera flags.
    #[command(flatten)]
    pub camera: CameraArgs,
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn command_line_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn sizes_parse_as_width_by_height() {
        assert_eq!(
            parse_size("64x48"),
            Ok(Size {
                width: 64,
                height: 48
            })
        );
        assert_eq!(parse_size("1920X1080").map(|s| s.width), Ok(1920));
    }

    #[test]
    fn bad_sizes_are_rejected_with_a_reason() {
        for bad in [
            "", "64", "64x", "x48", "0x48", "64x0", "-1x5", "64x48x2", "1e3x5", "99999x1",
        ] {
            let err = parse_size(bad).expect_err(bad);
            assert!(
                err.contains("WxH") || err.contains("between"),
                "{bad}: {err}"
            );
        }
    }
}
