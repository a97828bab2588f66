//! Command-line arguments shared by Phosphor's programs (`phosphor` and `phosphor-viewer`):
//! the camera flags (`--eye --target --up --fov`, or the orbit form `--azimuth --elevation
//! --distance`, the standard views `--view`, the projection `--ortho`), the normal flags of
//! `--mesh`, `--aa`, the check of a mesh's extension, the automatic framing of a mesh, and the
//! help headings every flag is listed under, so that both programs take the same flags with
//! the same checks and messages.
//!
//! Every check returns a one-line message naming its flag; each program turns it into its own
//! usage error (exit 2). clap's own errors become such a line too ([`usage`]).
//!
//! ```
//! use clap::Parser;
//! use phosphor_args::{CameraArgs, camera_override};
//!
//! #[derive(Parser)]
//! struct Cli {
//!     #[command(flatten)]
//!     camera: CameraArgs,
//! }
//!
//! let cli = Cli::parse_from(["demo", "--azimuth", "45", "--elevation", "30"]);
//! let change = camera_override(&cli.camera).unwrap();
//! assert_eq!(change.azimuth_deg, Some(45.0));
//! let bad = Cli::parse_from(["demo", "--fov", "0"]);
//! assert!(camera_override(&bad.camera).unwrap_err().starts_with("--fov: "));
//! ```

pub mod usage;

use std::path::Path;

use clap::{Args, ValueEnum};
use phosphor_math::glam::Vec3;
use phosphor_mesh::{NormalOptions, NormalSource, Weighting};
use phosphor_raster::{Antialias, Camera, Projection, UnknownAntialias};
use phosphor_scene::Scene;
use phosphor_scene::preset::{ViewPreset, preset_camera};
use phosphor_scene::view::{CameraOption, CameraOverride, framed_camera, parse_vec3};

/// Help heading of the camera flags.
pub const CAMERA_HEADING: &str =
    "Camera (overrides the scene's; orbit angles about --up, azimuth 0 = from +Z)";
/// Help heading of the normal flags of `--mesh`.
pub const NORMALS_HEADING: &str = "Normals of --mesh (as a scene file's `normals = { ... }`)";
/// Help heading of what is shown: the scene file or mesh.
pub const INPUT_HEADING: &str = "Input";
/// Help heading of how a frame is drawn: shading, anti-aliasing, culling, size, threads.
pub const RENDERING_HEADING: &str = "Rendering";
/// Help heading of what is written: files, their encoding, `--force`.
pub const OUTPUT_HEADING: &str = "Output";

/// The extensions a mesh file may have (any case); a name without one is read as OBJ.
pub const MESH_EXTENSIONS: [&str; 5] = ["obj", "ply", "stl", "gltf", "glb"];

/// Azimuth of the view `--mesh` starts from, degrees (a three-quarter view, as
/// `phosphor render --mesh`).
pub const MESH_AZIMUTH_DEG: f32 = 30.0;
/// Elevation of the view `--mesh` starts from, degrees.
pub const MESH_ELEVATION_DEG: f32 = 20.0;

/// The camera flags, shared by `phosphor render`, `bench`, `accuracy` and the viewer.
#[derive(Clone, Debug, Default, Args)]
pub struct CameraArgs {
    /// Eye position.
    #[arg(long, help_heading = CAMERA_HEADING, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub eye: Option<String>,
    /// The point looked at; also the orbit centre.
    #[arg(long, help_heading = CAMERA_HEADING, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub target: Option<String>,
    /// Up direction.
    #[arg(long, help_heading = CAMERA_HEADING, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub up: Option<String>,
    /// Vertical field of view in degrees, in (0, 180).
    #[arg(long, help_heading = CAMERA_HEADING, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_given)]
    pub fov: Option<Given>,
    /// Orbit: degrees about the up axis around the scene's centre (or --target); +90 looks from +X.
    #[arg(long, help_heading = CAMERA_HEADING, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_given)]
    pub azimuth: Option<Given>,
    /// Orbit: degrees above the plane normal to up, in (-90, 90).
    #[arg(long, help_heading = CAMERA_HEADING, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_given)]
    pub elevation: Option<Given>,
    /// Orbit: distance from the centre (> 0). Orbit values left out keep the scene camera's.
    #[arg(long, help_heading = CAMERA_HEADING, value_name = "D", allow_hyphen_values = true, value_parser = parse_given)]
    pub distance: Option<Given>,
    /// Orthographic projection (parallel rays): the image spans what the perspective view
    /// spans at the target, so --distance zooms. The lighting's viewer stays at the eye.
    #[arg(long, help_heading = CAMERA_HEADING)]
    pub ortho: bool,
    /// A standard view of the whole scene, framed to fit: front (from +Z), back, left, right
    /// (from +X), top (down from +Y), bottom or iso (from the +X+Y+Z diagonal).
    #[arg(
        long,
        help_heading = CAMERA_HEADING,
        value_name = "front|back|left|right|top|bottom|iso",
        value_parser = parse_view,
        conflicts_with_all = ["eye", "up", "azimuth", "elevation"]
    )]
    pub view: Option<ViewPreset>,
}

/// A number given on the command line: the single-precision value the renderer uses, and the
/// text as typed, which messages echo (`--elevation 89.9999999` is 90 in single precision; a
/// message saying `got 90` would blame a value nobody typed).
#[derive(Clone, Debug, PartialEq)]
pub struct Given {
    /// The value, in single precision.
    pub value: f32,
    /// The text as typed.
    pub text: String,
}

impl Given {
    /// A value given as `text` (for tests and callers that build arguments themselves).
    #[must_use]
    pub fn new(value: f32, text: &str) -> Given {
        Given {
            value,
            text: text.to_owned(),
        }
    }

    /// The text as typed, followed by the single-precision value where it reads differently
    /// in a range message (`89.9999999 (90 in single precision)`).
    #[must_use]
    pub fn echo(&self) -> String {
        let exact = self.text.trim().parse::<f64>().ok();
        if exact.is_some_and(|x| x.is_finite() && x != f64::from(self.value)) {
            format!("{} ({} in single precision)", self.text, self.value)
        } else {
            self.text.clone()
        }
    }
}

/// Parses a number flag, keeping its text.
///
/// # Errors
/// Text that is not a number.
pub fn parse_given(text: &str) -> Result<Given, String> {
    let value = text
        .trim()
        .parse::<f32>()
        .map_err(|_| format!("expected a number, got `{text}`"))?;
    Ok(Given::new(value, text))
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
pub struct NormalArgs {
    /// Faces meeting at a sharper angle (degrees, 0..=180) keep separate normals. Default: the
    /// scene files' (the OBJ's smoothing groups if it has `s` lines, else 60).
    #[arg(long, help_heading = NORMALS_HEADING, value_name = "DEG", allow_hyphen_values = true)]
    pub crease_angle: Option<f32>,
    /// Authored `vn` (`file`, also `authored`) or normals computed from the geometry.
    #[arg(long, help_heading = NORMALS_HEADING, value_enum, value_name = "file|computed")]
    pub normals: Option<NormalsArg>,
    /// Weighting of face normals at a vertex.
    #[arg(long, help_heading = NORMALS_HEADING, value_enum, value_name = "uniform|area|angle")]
    pub weighting: Option<WeightingArg>,
    /// Ignore the OBJ's smoothing groups (`s` lines).
    #[arg(long, help_heading = NORMALS_HEADING)]
    pub no_smoothing_groups: bool,
    /// Never average normals across faces of different materials.
    #[arg(long, help_heading = NORMALS_HEADING)]
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
/// A normal flag without `--mesh`, or a crease angle outside 0..=180, naming the flag.
pub fn normal_options(args: &NormalArgs, mesh: bool) -> Result<NormalOptions, String> {
    let mut opts = NormalOptions::default();
    if let Some(flag) = args.first_given() {
        if !mesh {
            return Err(format!(
                "{flag}: applies to --mesh only (a scene file sets `normals = {{ ... }}` per object)"
            ));
        }
    }
    if let Some(a) = args.crease_angle {
        if !(0.0..=180.0).contains(&a) {
            return Err(format!(
                "--crease-angle: must be between 0 and 180, got {a}"
            ));
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

/// The camera change the flags ask for, every value checked on its own.
///
/// # Errors
/// A malformed, non-finite or out-of-range value, naming its flag.
pub fn camera_override(args: &CameraArgs) -> Result<CameraOverride, String> {
    let vector = |flag: &str, text: &Option<String>| -> Result<Option<Vec3>, String> {
        text.as_deref()
            .map(parse_vec3)
            .transpose()
            .map_err(|e| format!("{flag}: {e}"))
    };
    let value = |g: &Option<Given>| g.as_ref().map(|g| g.value);
    let o = CameraOverride {
        eye: vector("--eye", &args.eye)?,
        target: vector("--target", &args.target)?,
        up: vector("--up", &args.up)?,
        fov_y_deg: value(&args.fov),
        azimuth_deg: value(&args.azimuth),
        elevation_deg: value(&args.elevation),
        distance: value(&args.distance),
    };
    o.check().map_err(|e| {
        // A range message ends `got VALUE`: the value as typed, not as rounded.
        let given = match e.option {
            CameraOption::Fov => &args.fov,
            CameraOption::Azimuth => &args.azimuth,
            CameraOption::Elevation => &args.elevation,
            CameraOption::Distance => &args.distance,
            _ => &None,
        };
        match (given, e.what.rfind("got ")) {
            (Some(g), Some(at)) => format!("{}: {}got {}", e.option, &e.what[..at], g.echo()),
            _ => e.to_string(),
        }
    })?;
    Ok(o)
}

/// Frames the scene for a window of `size` and applies the camera flags: `--view` puts the
/// camera at a standard view fitted to the whole scene (at `--fov` where given); otherwise a
/// `--mesh` scene (`frame_mesh`) is seen from azimuth 30, elevation 20, fitted the same way.
/// Then the camera change applies, and `--ortho` makes the projection orthographic. A scene
/// camera that is orthographic already stays so, its height fitted anew when framed.
///
/// # Errors
/// A camera change that cannot be made (eye on the target, view parallel to up), naming the flag.
pub fn frame_and_apply(
    scene: &mut Scene,
    args: &CameraArgs,
    change: &CameraOverride,
    frame_mesh: bool,
    size: (u32, u32),
) -> Result<(), String> {
    let bounds = scene.bounding_sphere();
    let (centre, radius) = bounds.unwrap_or((Vec3::ZERO, 1.0));
    let aspect = size.0.max(1) as f32 / size.1.max(1) as f32;
    let was_orthographic = matches!(scene.camera().projection, Projection::Orthographic { .. });
    let fov = scene.camera().fov_y_deg;
    if let Some(view) = args.view {
        let fov = change.fov_y_deg.unwrap_or(fov);
        scene.set_camera(preset_camera(view, centre, radius, fov, aspect));
    } else if frame_mesh {
        scene.set_camera(framed_camera(
            centre,
            radius,
            Vec3::Y,
            MESH_AZIMUTH_DEG,
            MESH_ELEVATION_DEG,
            fov,
            aspect,
        ));
    }
    let framed = args.view.is_some() || frame_mesh;
    let mut cam = change
        .apply(scene.camera(), bounds)
        .map_err(|e| e.to_string())?;
    if (args.ortho && !was_orthographic) || (was_orthographic && framed) {
        cam = orthographic(cam);
    }
    scene.set_camera(cam);
    Ok(())
}

/// `camera` made orthographic, spanning what its perspective view spans at the target.
#[must_use]
pub fn orthographic(camera: Camera) -> Camera {
    let perspective = Camera {
        projection: Projection::Perspective,
        ..camera
    };
    Camera {
        projection: Projection::Orthographic {
            height: perspective.view_height_at_target(),
        },
        ..camera
    }
}

/// Parses a view name for `--view`.
///
/// # Errors
/// An unknown name, listing the known ones.
pub fn parse_view(text: &str) -> Result<ViewPreset, String> {
    text.parse()
}

/// Checks that `path` names a mesh by its extension: one of [`MESH_EXTENSIONS`] (any case),
/// or none (read as OBJ). `flag` names the flag in the message, if there is one.
///
/// # Errors
/// `FLAG: PATH: unknown extension `.md` (...)`.
pub fn check_mesh_path(flag: Option<&str>, path: &Path) -> Result<(), String> {
    let Some(ext) = path.extension() else {
        return Ok(());
    };
    let ext = ext.to_string_lossy();
    if MESH_EXTENSIONS.iter().any(|e| ext.eq_ignore_ascii_case(e)) {
        return Ok(());
    }
    Err(format!(
        "{}{}: unknown extension `.{ext}` (a mesh is .obj, .ply, .stl, .gltf or .glb)",
        flag.map_or_else(String::new, |f| format!("{f}: ")),
        path.display()
    ))
}

/// Parses an anti-aliasing name for `--aa`.
///
/// # Errors
/// An unknown name, listing the known ones.
pub fn parse_antialias(text: &str) -> Result<Antialias, String> {
    text.parse().map_err(|e: UnknownAntialias| e.to_string())
}

/// A background given on the command line: a linear colour and its opacity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Background {
    /// Linear colour, each channel finite and non-negative (as a scene file's `background`).
    pub color: Vec3,
    /// Opacity in `[0, 1]`: 0 for `transparent`, 1 unless a fourth number is given.
    pub alpha: f32,
}

impl Background {
    /// Sets `scene`'s background (its `render.background`) to this one.
    pub fn apply(self, scene: &mut Scene) {
        scene.settings.background = self.color;
        scene.settings.background_alpha = self.alpha;
    }
}

/// Parses `--background`: `R,G,B` (linear, non-negative, as a scene file's `background`),
/// `R,G,B,A` with an opacity `A` in `[0, 1]`, or `transparent` (black, opacity 0).
///
/// # Errors
/// Anything else, saying what was expected.
pub fn parse_background(text: &str) -> Result<Background, String> {
    if text == "transparent" {
        return Ok(Background {
            color: Vec3::ZERO,
            alpha: 0.0,
        });
    }
    let expected = || format!("expected R,G,B, R,G,B,A or transparent, got `{text}`");
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if !(3..=4).contains(&parts.len()) {
        return Err(expected());
    }
    let mut v = [1.0f32; 4];
    for (o, p) in v.iter_mut().zip(&parts) {
        *o = p.parse().map_err(|_| expected())?;
        if !o.is_finite() {
            return Err(format!("every number must be finite, got `{text}`"));
        }
    }
    let color = Vec3::new(v[0], v[1], v[2]);
    if color.min_element() < 0.0 {
        return Err(format!("colour must be non-negative, got `{text}`"));
    }
    if !(0.0..=1.0).contains(&v[3]) {
        return Err(format!("opacity must be in [0, 1], got {}", parts[3]));
    }
    Ok(Background { color, alpha: v[3] })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn backgrounds_parse_with_an_opacity_and_bad_ones_say_why() {
        let b = parse_background("0.2,0.4, 1").unwrap();
        assert_eq!((b.color, b.alpha), (Vec3::new(0.2, 0.4, 1.0), 1.0));
        let b = parse_background("1,1,1,0.25").unwrap();
        assert_eq!((b.color, b.alpha), (Vec3::ONE, 0.25));
        let b = parse_background("transparent").unwrap();
        assert_eq!((b.color, b.alpha), (Vec3::ZERO, 0.0));
        for (bad, says) in [
            ("1,2", "expected R,G,B"),
            ("1,2,3,4,5", "expected R,G,B"),
            ("red", "expected R,G,B"),
            ("1,x,3", "expected R,G,B"),
            ("nan,0,0", "finite"),
            ("inf,0,0", "finite"),
            ("-1,0,0", "non-negative"),
            ("0,0,0,2", "opacity must be in [0, 1]"),
            ("0,0,0,-0.5", "opacity"),
        ] {
            let e = parse_background(bad).unwrap_err();
            assert!(e.contains(says), "{bad}: {e}");
        }
        let mut scene = Scene::empty();
        parse_background("0,1,0,0.5").unwrap().apply(&mut scene);
        assert_eq!(scene.settings.background, Vec3::Y);
        assert_eq!(scene.settings.background_alpha, 0.5);
    }

    #[test]
    fn camera_flags_are_checked_and_name_the_flag() {
        let bad = CameraArgs {
            eye: Some("1,2".to_owned()),
            ..CameraArgs::default()
        };
        assert!(camera_override(&bad).unwrap_err().starts_with("--eye: "));
        let bad = CameraArgs {
            fov: Some(Given::new(0.0, "0")),
            ..CameraArgs::default()
        };
        assert!(camera_override(&bad).unwrap_err().starts_with("--fov: "));
        let bad = NormalArgs {
            crease_angle: Some(f32::NAN),
            ..NormalArgs::default()
        };
        assert!(
            normal_options(&bad, true)
                .unwrap_err()
                .starts_with("--crease-angle: ")
        );
        let without_mesh = NormalArgs {
            split_by_material: true,
            ..NormalArgs::default()
        };
        assert!(
            normal_options(&without_mesh, false)
                .unwrap_err()
                .contains("--mesh only")
        );
        assert!(normal_options(&without_mesh, true).is_ok());
    }

    #[test]
    fn values_are_echoed_exactly_as_given() {
        let bad = CameraArgs {
            elevation: Some(parse_given("89.9999999").unwrap()),
            ..CameraArgs::default()
        };
        assert_eq!(
            camera_override(&bad).unwrap_err(),
            "--elevation: must be between -90 and 90 (exclusive), got 89.9999999 (90 in single \
             precision)"
        );
        let bad = CameraArgs {
            fov: Some(parse_given("180.0").unwrap()),
            ..CameraArgs::default()
        };
        assert_eq!(
            camera_override(&bad).unwrap_err(),
            "--fov: must be between 0 and 180 (exclusive), got 180.0"
        );
        assert!(parse_given("ninety").is_err());
    }

    #[test]
    fn mesh_paths_need_a_mesh_extension_or_none() {
        for ok in ["a.obj", "b.PLY", "c.stl", "d.gltf", "e.GLB", "no-extension"] {
            assert_eq!(
                check_mesh_path(Some("--mesh"), Path::new(ok)),
                Ok(()),
                "{ok}"
            );
        }
        assert_eq!(
            check_mesh_path(Some("--mesh"), Path::new("assets/meshes/SOURCES.md")).unwrap_err(),
            "--mesh: assets/meshes/SOURCES.md: unknown extension `.md` (a mesh is .obj, .ply, .stl, .gltf or .glb)"
        );
        assert!(
            check_mesh_path(None, Path::new("x.txt"))
                .unwrap_err()
                .starts_with("x.txt: unknown extension")
        );
    }

    #[test]
    fn views_and_ortho_frame_the_whole_scene() {
        let args = |view: Option<ViewPreset>, ortho: bool| CameraArgs {
            view,
            ortho,
            ..CameraArgs::default()
        };
        let framed = |a: &CameraArgs| {
            let mut scene = Scene::default_scene().unwrap();
            let change = camera_override(a).unwrap();
            frame_and_apply(&mut scene, a, &change, false, (320, 240)).unwrap();
            (scene.camera(), scene.bounding_sphere().unwrap())
        };
        let (top, (centre, radius)) = framed(&args(Some(ViewPreset::Top), false));
        assert_eq!(top.target, centre);
        assert!(top.eye.y > centre.y + radius, "{top:?}");
        assert_eq!(top.projection, Projection::Perspective);
        let (ortho_top, _) = framed(&args(Some(ViewPreset::Top), true));
        let Projection::Orthographic { height } = ortho_top.projection else {
            panic!("not orthographic: {ortho_top:?}");
        };
        // The bounding sphere's diameter fits the image's height, with a small margin.
        assert!(
            height > 2.0 * radius && height < 2.4 * radius,
            "{height} vs {radius}"
        );
        // Without --view nor --ortho the scene's own camera stays exactly as it is.
        let (own, _) = framed(&CameraArgs::default());
        assert_eq!(own, Scene::default_scene().unwrap().camera());
    }

    #[test]
    fn anti_aliasing_names_are_parsed_or_listed() {
        assert_eq!(parse_antialias("ssaa4"), Ok(Antialias::Ssaa4));
        assert_eq!(parse_antialias("msaa4"), Ok(Antialias::Msaa4));
        assert!(
            parse_antialias("msaa8")
                .unwrap_err()
                .contains("off, msaa4, ssaa4, msaa16 or ssaa16")
        );
    }
}
