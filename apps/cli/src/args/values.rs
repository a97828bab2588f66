//! The values flags take: shading modes, culling, variants, SIMD level, encoding, sizes.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Args, ValueEnum};
use phosphor_args::RENDERING_HEADING;
use phosphor_raster::ShadingMode;
use phosphor_scene::ShadingChoice;

/// Largest accepted image side, in pixels (a 16k x 16k f32 framebuffer is already 3 GiB).
pub const MAX_SIDE: u32 = 16_384;

/// Back-face culling on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CullArg {
    /// Only closed, outward-oriented meshes seen from outside (the same picture).
    Auto,
    /// Every object (open meshes show holes where their back is seen).
    Always,
    /// No object: both sides of every triangle are drawn.
    Never,
}

/// What a shading mode does, for `--help`.
fn mode_help(mode: ShadingMode) -> &'static str {
    match mode {
        ShadingMode::Flat => "Once per triangle",
        ShadingMode::Gouraud => "Per vertex, intensities interpolated",
        ShadingMode::Phong => "Per pixel with interpolated normals",
        ShadingMode::FastPhong => {
            "A quadratic per triangle stepped by forward differences (see --fast-phong); else phong"
        }
        ShadingMode::Reference => "Ground truth: per pixel in f64",
    }
}

/// The name of `bench --shading`'s choice of every mode.
const ALL_NAME: &str = "all";

/// The values of a shading flag: every mode of [`ShadingMode::ALL`] in its order, then
/// `auto`, then `extra`.
fn shading_values(extra: Option<PossibleValue>) -> Vec<PossibleValue> {
    ShadingMode::ALL
        .into_iter()
        .map(|m| PossibleValue::new(m.name()).help(mode_help(m)))
        .chain([PossibleValue::new(ShadingChoice::Auto.name())
            .help("Per object, the cheapest mode that is good enough")])
        .chain(extra)
        .collect()
}

/// The shading choice named `name`, one of [`shading_values`]'s (else `auto`).
fn named_choice(name: &str) -> ShadingChoice {
    ShadingMode::ALL
        .into_iter()
        .find(|m| m.name() == name)
        .map_or(ShadingChoice::Auto, ShadingChoice::Mode)
}

/// The parser of `--shading`: one of the modes, or `auto`.
pub fn shading_parser() -> impl TypedValueParser<Value = ShadingChoice> {
    PossibleValuesParser::new(shading_values(None)).map(|s| named_choice(&s))
}

/// Bench's shading choice: one mode (or `auto`), or all of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BenchMode {
    /// One choice.
    One(ShadingChoice),
    /// Every mode of [`ShadingMode::ALL`], then `auto`, one line each.
    All,
}

impl BenchMode {
    /// The choices timed, in order.
    #[must_use]
    pub fn choices(self) -> Vec<ShadingChoice> {
        match self {
            BenchMode::One(choice) => vec![choice],
            BenchMode::All => ShadingMode::ALL
                .into_iter()
                .map(ShadingChoice::Mode)
                .chain([ShadingChoice::Auto])
                .collect(),
        }
    }
}

/// The parser of `bench --shading`: one of the modes, `auto`, or `all`.
pub fn bench_mode_parser() -> impl TypedValueParser<Value = BenchMode> {
    let all = PossibleValue::new(ALL_NAME).help("Every mode above, one line each");
    PossibleValuesParser::new(shading_values(Some(all))).map(|s| {
        if s == ALL_NAME {
            BenchMode::All
        } else {
            BenchMode::One(named_choice(&s))
        }
    })
}

/// How fast-phong makes its quadratic (`--fast-phong`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FastPhongArg {
    /// Bishop and Weimer 1986: the diffuse and specular terms expanded in a Taylor series to
    /// second degree about each triangle's centroid.
    Taylor,
    /// A quadratic through the exact terms at the vertices and edge midpoints of each
    /// triangle of 128 pixels or more.
    Fit,
}

/// How gouraud and phong interpolate (`--interpolation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum InterpolationArg {
    /// Planes evaluated afresh at each span start (no drift down a tall triangle).
    Plane,
    /// Gouraud 1971's incremental scan line: values stepped per scan line and per pixel in f32.
    Incremental,
}

/// The vector width of per-pixel lighting (`--simd`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SimdArg {
    /// The widest this CPU runs.
    Auto,
    /// Four lanes (SSE2 on x86-64).
    Baseline,
    /// Eight lanes with AVX2 (an error on a CPU without it).
    Avx2,
}

/// `--shadows on|off`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OnOff {
    /// On.
    On,
    /// Off.
    Off,
}

/// Shadows of render and bench.
#[derive(Debug, Args, Clone, Copy, Default)]
pub struct ShadowArgs {
    /// Shadow maps for every directional, spot and point light (on) or none (off), overriding
    /// the scene's `shadows = true` per light (default: as the scene says).
    #[arg(long, help_heading = RENDERING_HEADING, value_enum, value_name = "on|off")]
    pub shadows: Option<OnOff>,
}

impl ShadowArgs {
    /// The override, if any.
    #[must_use]
    pub fn shadows(&self) -> Option<bool> {
        self.shadows.map(|s| s == OnOff::On)
    }
}

/// The SIMD level of render and bench.
#[derive(Debug, Args, Clone, Copy, Default)]
pub struct SimdArgs {
    /// The vector width of per-pixel lighting (default auto: the widest this CPU runs). The
    /// picture is the same at every level; this compares their speed.
    #[arg(long, help_heading = RENDERING_HEADING, value_enum, value_name = "auto|baseline|avx2")]
    pub simd: Option<SimdArg>,
}

impl SimdArgs {
    /// The SIMD level asked for; `--simd avx2` on a CPU without AVX2 is a usage error.
    ///
    /// # Errors
    /// A level this CPU does not run.
    pub fn simd(&self) -> Result<phosphor_raster::SimdLevel, String> {
        let level = match self.simd {
            None | Some(SimdArg::Auto) => phosphor_raster::SimdLevel::Auto,
            Some(SimdArg::Baseline) => phosphor_raster::SimdLevel::Baseline,
            Some(SimdArg::Avx2) => phosphor_raster::SimdLevel::Avx2,
        };
        if level.available() {
            Ok(level)
        } else {
            Err(format!(
                "--simd {level}: this CPU does not run it (use auto or baseline)"
            ))
        }
    }
}

/// The variant flags of the approximate modes, shared by render, bench and accuracy.
#[derive(Debug, Args, Clone, Copy, Default)]
pub struct VariantArgs {
    /// How fast-phong makes its per-triangle quadratic (overrides the scene file; default
    /// fit): `fit` = a six-point fit, `taylor` = Bishop and Weimer 1986's Taylor expansion.
    #[arg(long, help_heading = RENDERING_HEADING, value_enum, value_name = "fit|taylor")]
    pub fast_phong: Option<FastPhongArg>,
    /// How gouraud and phong interpolate across a triangle (overrides the scene file; default
    /// plane): `plane` = evaluated at each span start, `incremental` = Gouraud 1971's
    /// per-scan-line increments in f32.
    #[arg(long, help_heading = RENDERING_HEADING, value_enum, value_name = "plane|incremental")]
    pub interpolation: Option<InterpolationArg>,
}

impl VariantArgs {
    /// The fast-Phong method asked for, if any.
    #[must_use]
    pub fn fast_phong(&self) -> Option<phosphor_raster::FastPhongMethod> {
        self.fast_phong.map(|m| match m {
            FastPhongArg::Taylor => phosphor_raster::FastPhongMethod::Taylor,
            FastPhongArg::Fit => phosphor_raster::FastPhongMethod::Fit,
        })
    }

    /// The interpolation asked for, if any.
    #[must_use]
    pub fn interpolation(&self) -> Option<phosphor_raster::Interpolation> {
        self.interpolation.map(|m| match m {
            InterpolationArg::Plane => phosphor_raster::Interpolation::Plane,
            InterpolationArg::Incremental => phosphor_raster::Interpolation::Incremental,
        })
    }
}

/// PNG encoding of the linear framebuffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EncodingArg {
    /// sRGB transfer curve (the default for scene files).
    Srgb,
    /// Values stored as they are (the default for S1).
    Linear,
}

/// An image size in pixels, `WxH` on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size {
    /// Width in pixels, 1..=[`MAX_SIDE`].
    pub width: u32,
    /// Height in pixels, 1..=[`MAX_SIDE`].
    pub height: u32,
}

/// Parses `WxH` (e.g. `640x480`); both sides whole numbers in 1..=[`MAX_SIDE`].
pub fn parse_size(text: &str) -> Result<Size, String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WxH, e.g. 640x480, got `{text}`"))?;
    let side = |s: &str| -> Result<u32, String> {
        let v: u32 = s
            .parse()
            .map_err(|_| format!("expected WxH with whole numbers, e.g. 640x480, got `{text}`"))?;
        if v == 0 || v > MAX_SIDE {
            return Err(format!(
                "each side must be between 1 and {MAX_SIDE}, got `{text}`"
            ));
        }
        Ok(v)
    };
    Ok(Size {
        width: side(w)?,
        height: side(h)?,
    })
}

/// The shells `phosphor completions` writes for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ShellArg {
    /// Bash.
    Bash,
    /// Zsh.
    Zsh,
    /// Fish.
    Fish,
    /// PowerShell.
    Powershell,
}

/// `--time`: a finite number of seconds.
///
/// # Errors
/// A message naming what was expected.
pub fn parse_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(t) if t.is_finite() && t.abs() <= 1e9 => Ok(t),
        _ => Err(format!(
            "expected seconds, a finite number such as 1.5, got `{text}`"
        )),
    }
}

/// `--fps`: frames per second, a finite number > 0.
///
/// # Errors
/// A message naming what was expected.
pub fn parse_fps(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(f) if f.is_finite() && f > 0.0 && f <= 1e6 => Ok(f),
        _ => Err(format!(
            "expected frames per second, a number > 0 such as 24, got `{text}`"
        )),
    }
}

/// Largest `--exposure` in stops either way: `2^64` keeps [`phosphor_raster::framebuffer::HDR_MAX`]
/// times the scale a finite `f32`.
pub const MAX_EXPOSURE: f32 = 64.0;

/// `--exposure`: stops, a finite number in `[-64, 64]`.
///
/// # Errors
/// A message naming what was expected.
pub fn parse_exposure(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(ev) if ev.is_finite() && ev.abs() <= MAX_EXPOSURE => Ok(ev),
        _ => Err(format!(
            "expected stops, a finite number from -{MAX_EXPOSURE} to {MAX_EXPOSURE} such as -1.5, got `{text}`"
        )),
    }
}

/// `--tone-map`: how PNG brings intensities above 1 into range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ToneMapArg {
    /// Clip at 1 (what every earlier version wrote).
    Clamp,
    /// Reinhard 2002: x / (1 + x).
    Reinhard,
    /// Narkowicz 2015's fit of the ACES filmic curve.
    Aces,
}

impl ToneMapArg {
    /// The raster crate's curve.
    #[must_use]
    pub fn tone_map(self) -> phosphor_raster::ToneMap {
        match self {
            ToneMapArg::Clamp => phosphor_raster::ToneMap::Clamp,
            ToneMapArg::Reinhard => phosphor_raster::ToneMap::Reinhard,
            ToneMapArg::Aces => phosphor_raster::ToneMap::Aces,
        }
    }
}

/// `--wireframe=R,G,B`: a linear colour, three finite non-negative numbers.
///
/// # Errors
/// A message naming what was expected.
pub fn parse_wire_color(text: &str) -> Result<phosphor_math::glam::Vec3, String> {
    match phosphor_args::parse_background(text) {
        Ok(b) if b.alpha == 1.0 && text.split(',').count() == 3 => Ok(b.color),
        Ok(_) => Err(format!("expected R,G,B, got `{text}`")),
        Err(e) => Err(e.replace("R,G,B, R,G,B,A or transparent", "R,G,B")),
    }
}

/// `--wire-edges all|creases|creases:DEG`: which edges the wireframe draws; `creases` at the
/// mesh crate's default crease angle, or at `DEG` (finite, 0 to 180).
///
/// # Errors
/// A message naming what was expected.
pub fn parse_wire_edges(text: &str) -> Result<phosphor_raster::overlay::Edges, String> {
    use phosphor_raster::overlay::Edges;
    let angle = match text.split_once(':') {
        None if text == "all" => return Ok(Edges::All),
        None if text == "creases" => phosphor_mesh::normals::DEFAULT_CREASE_ANGLE_DEG,
        Some(("creases", deg)) => match deg.trim().parse::<f32>() {
            Ok(a) if (0.0..=180.0).contains(&a) => a,
            _ => {
                return Err(format!(
                    "expected an angle from 0 to 180 after `creases:`, got `{deg}`"
                ));
            }
        },
        _ => {
            return Err(format!(
                "expected all, creases or creases:DEG, got `{text}`"
            ));
        }
    };
    Ok(Edges::Creases { angle_deg: angle })
}
