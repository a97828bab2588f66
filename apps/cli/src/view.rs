//! How the scene is looked at: the camera flags (`--eye`, `--target`, `--up`, `--fov`, and the
//! orbit form `--azimuth`, `--elevation`, `--distance`), the normal flags of `--mesh`
//! (`--crease-angle`, `--normals`, `--weighting`, ...), and the automatic framing of a mesh
//! given with `--mesh`.
//!
//! Every bad value is a usage error (exit 2) on one line naming its flag, found before any file
//! is read where the value alone is at fault.

use clap::{Args, ValueEnum};
use phosphor_math::glam::Vec3;
use phosphor_mesh::{NormalOptions, NormalSource, Weighting};
use phosphor_scene::Scene;
use phosphor_scene::view::{CameraOverride, framed_camera, parse_vec3};

use crate::CliError;
use crate::args::{SceneSource, Size};
use crate::commands::{frame_size, load_source};

/// Azimuth of the view `--mesh` starts from, degrees: a three-quarter view, so that a box
/// shows three faces rather than one.
pub const MESH_AZIMUTH_DEG: f32 = 30.0;
/// Elevation of the view `--mesh` starts from, degrees (see [`MESH_AZIMUTH_DEG`]).
pub const MESH_ELEVATION_DEG: f32 = 20.0;

/// The camera flags, shared by `render`, `bench` and `accuracy`.
#[derive(Clone, Debug, Default, Args)]
#[command(
    next_help_heading = "Camera (overrides the scene's; orbit angles about --up, azimuth 0 = from +Z)"
)]
pub struct CameraArgs {
    /// Eye position.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub eye: Option<String>,
    /// The point looked at; also the orbit centre.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub target: Option<String>,
    /// Up direction.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub up: Option<String>,
    /// Vertical field of view in degrees, in (0, 180).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub fov: Option<f32>,
    /// Orbit: degrees about the up axis around the scene's centre (or --target); +90 looks from +X.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub azimuth: Option<f32>,
    /// Orbit: degrees above the plane normal to up, in (-90, 90).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub elevation: Option<f32>,
    /// Orbit: distance from the centre (> 0). Orbit values left out keep the scene camera's.
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub distance: Option<f32>,
}

/// Where `--mesh`'s normals come from (the scene file's `normals.source`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NormalsArg {
    /// The file's `vn` where every corner has one, computed otherwise.
    #[value(alias = "authored")]
    File,
    /// Always computed from the geometry.
    Computed,
}

/// How face normals are weighted at a vertex (the scene file's `normals.weighting`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum WeightingArg {
    /// Every face counts once.
    Uniform,
    /// By face area.
    Area,
    /// By the face's angle at the vertex.
    Angle,
}

/// The normal flags of `--mesh`, mirroring a scene file's `normals = { ... }`.
#[derive(Clone, Debug, Default, Args)]
#[command(next_help_heading = "Normals of --mesh (as a scene file's `normals = { ... }`)")]
pub struct NormalArgs {
    /// Faces meeting at a sharper angle (degrees, 0..=180) keep separate normals. Default: the
    /// scene files' (the OBJ's smoothing groups if it has `s` lines, else 60).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub crease_angle: Option<f32>,
    /// Authored `vn` (`file`, also `authored`) or normals computed from the geometry.
    #[arg(long, value_enum, value_name = "file|computed")]
    pub normals: Option<NormalsArg>,
    /// Weighting of face normals at a vertex.
    #[arg(long, value_enum, value_name = "uniform|area|angle")]
    pub weighting: Option<WeightingArg>,
    /// Ignore the OBJ's smoothing groups (`s` lines).
    #[arg(long)]
    pub no_smoothing_groups: bool,
    /// Never average normals across faces of different materials.
    #[arg(long)]
    pub split_by_material: bool,
}

impl NormalArgs {
    /// The first normal flag given, if any.
    fn first_given(&self) -> Option<&'static str> {
        [
            (self.crease_angle.is_some(), "--crease-angle"),
            (self.normals.is_some(), "--normals"),
            (self.weighting.is_some(), "--weighting"),
            (self.no_smoothing_groups, "--no-smoothing-groups"),
            (self.split_by_material, "--split-by-material"),
        ]
        .into_iter()
        .find_map(|(given, flag)| given.then_some(flag))
    }
}

/// The normal options `--mesh` builds its mesh with (`mesh`: whether `--mesh` was given).
///
/// # Errors
/// A normal flag without `--mesh`, or a crease angle outside 0..=180 (usage).
pub fn normal_options(args: &NormalArgs, mesh: bool) -> Result<NormalOptions, CliError> {
    let mut opts = NormalOptions::default();
    if let Some(flag) = args.first_given() {
        if !mesh {
            return Err(CliError::Usage(format!(
                "{flag}: applies to --mesh only (a scene file sets `normals = {{ ... }}` per object)"
            )));
        }
    }
    if let Some(a) = args.crease_angle {
        if !(0.0..=180.0).contains(&a) {
            return Err(CliError::Usage(format!(
                "--crease-angle: must be between 0 and 180, got {a}"
            )));
        }
        opts.crease_angle_deg = Some(a);
    }
    if let Some(n) = args.normals {
        opts.source = match n {
            NormalsArg::File => NormalSource::Authored,
            NormalsArg::Computed => NormalSource::Computed,
        };
    }
    if let Some(w) = args.weighting {
        opts.weighting = match w {
            WeightingArg::Uniform => Weighting::Uniform,
            WeightingArg::Area => Weighting::Area,
            WeightingArg::Angle => Weighting::Angle,
        };
    }
    opts.use_smoothing_groups = !args.no_smoothing_groups;
    opts.split_by_material = args.split_by_material;
    Ok(opts)
}

/// The camera change the flags ask for, with every value checked on its own.
///
/// # Errors
/// A malformed, non-finite or out-of-range value (usage), naming its flag.
pub fn camera_override(args: &CameraArgs) -> Result<CameraOverride, CliError> {
    let vector = |flag: &str, text: &Option<String>| -> Result<Option<Vec3>, CliError> {
        text.as_deref()
            .map(parse_vec3)
            .transpose()
            .map_err(|e| CliError::Usage(format!("{flag}: {e}")))
    };
    let o = CameraOverride {
        eye: vector("--eye", &args.eye)?,
        target: vector("--target", &args.target)?,
        up: vector("--up", &args.up)?,
        fov_y_deg: args.fov,
        azimuth_deg: args.azimuth,
        elevation_deg: args.elevation,
        distance: args.distance,
    };
    o.check().map_err(|e| CliError::Usage(e.to_string()))?;
    Ok(o)
}

/// Loads the scene, sizes the frame, frames a `--mesh` and applies the camera flags: the scene
/// as a command sees it, and the frame's width and height. A scene file's camera is left
/// exactly as written unless a camera flag changes it.
///
/// # Errors
/// Usage errors for bad flags (before any file is read where possible), input errors for the
/// files.
pub fn prepare(
    source: &SceneSource,
    camera: &CameraArgs,
    size: Option<Size>,
) -> Result<(Scene, u32, u32), CliError> {
    let change = camera_override(camera)?;
    normal_options(&source.normals, source.mesh.is_some())?;
    let mut scene = load_source(source)?;
    let (width, height) = frame_size(&scene, size);
    let aa = scene.settings.antialias;
    if !aa.fits(width, height) {
        let k = u64::from(aa.factor());
        let what = format!(
            "{aa} at {width}x{height} draws {}x{} samples, over the largest side {}",
            u64::from(width) * k,
            u64::from(height) * k,
            phosphor_raster::framebuffer::MAX_SIDE
        );
        return Err(match (source.aa, &source.scene) {
            (Some(_), _) => CliError::Usage(format!("--aa: {what}")),
            (None, Some(path)) => CliError::Input(format!("{}: render.aa: {what}", path.display())),
            (None, None) => CliError::Input(format!("render.aa: {what}")),
        });
    }
    let bounds = scene.bounding_sphere();
    if source.scene.is_none() && source.mesh.is_some() {
        let (centre, radius) = bounds.unwrap_or((Vec3::ZERO, 1.0));
        let fov = scene.camera().fov_y_deg;
        scene.set_camera(framed_camera(
            centre,
            radius,
            Vec3::Y,
            MESH_AZIMUTH_DEG,
            MESH_ELEVATION_DEG,
            fov,
            width as f32 / height as f32,
        ));
    }
    let cam = change
        .apply(scene.camera(), bounds)
        .map_err(|e| CliError::Usage(e.to_string()))?;
    scene.set_camera(cam);
    Ok((scene, width, height))
}
