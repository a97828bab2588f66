//! OBJ loading: tobj for geometry and MTL, [`crate::scan`] for smoothing groups and
//! line-numbered errors, ear clipping for polygons, then [`crate::TriangleSoup::build`] for
//! normals and tangents.
//!
//! Positions are welded by exact equality across tobj's models (tobj re-emits positions per
//! `o`/`g`/`usemtl` model; docs/conventions.md, "Dependency facts"), so faces on both sides of a
//! group or material boundary share a position and may be smoothed together when the rule allows
//! it. Texture coordinates are kept only when every polygon corner names a `vt`, authored normals
//! only when every corner names a `vn` (otherwise normals are computed). Vertex colours
//! (`v x y z r g b`, on every `v` line or none) are taken as linear RGB, clamped to `[0, 1]`.

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::Path;

use glam::{Vec2, Vec3};

use crate::build::{TriangleSoup, unit_color, weld_key};
use crate::error::MeshError;
use crate::mesh::{Mesh, MtlMaterial};
use crate::mtl::{self, MaterialMaps};
use crate::normals::{NormalOptions, NormalSource};
use crate::open::{MAX_LINE_BYTES, MAX_MESH_FILE_BYTES, long_line, long_line_message, read_file};
use crate::sanitize::quote;
use crate::scan::{Scan, scan};
use crate::triangulate::triangulate;

/// Loads an OBJ file (and the MTL files its `mtllib` lines name, relative to the OBJ).
///
/// A missing MTL or an undefined material is not an error (docs/conventions.md, "Scene files"): the
/// mesh gets the default material; [`load_obj_with_warnings`] returns those warnings.
pub fn load_obj(path: &Path, opts: &NormalOptions) -> Result<Mesh, MeshError> {
    load_obj_with_warnings(path, opts).map(|(m, _)| m)
}

/// Like [`load_obj`], also returning warnings (one line each, `FILE[:LINE]: what`).
pub fn load_obj_with_warnings(
    path: &Path,
    opts: &NormalOptions,
) -> Result<(Mesh, Vec<String>), MeshError> {
    let file = path.display().to_string();
    let bytes = read_file(path, MAX_MESH_FILE_BYTES).map_err(|source| MeshError::Io {
        file: file.clone(),
        source,
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        MeshError::Parse {
            file: file.clone(),
            line: valid.iter().filter(|&&b| b == b'\n').count() + 1,
            what: "not valid UTF-8".to_owned(),
        }
    })?;
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let warnings = RefCell::new(Vec::new());
    let maps = RefCell::new(Vec::new());
    let loader = |mtl: &Path| {
        let full = dir.join(mtl);
        match read_mtl(&full) {
            Ok(b) => load_mtl(&b, &full, &maps, &warnings).inspect_err(|e| {
                warn(
                    &warnings,
                    format!("{}: {e}; using the default material", full.display()),
                );
            }),
            Err(why) => {
                warn(
                    &warnings,
                    format!("{}: {why}; using the default material", full.display()),
                );
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    };
    let mesh = parse_with(&text, &file, loader, opts, &warnings, &maps)?;
    Ok((mesh, warnings.into_inner()))
}

/// Parses OBJ text; `name` is used in messages, `mtl` is the text of the MTL file the OBJ's
/// `mtllib` names (`None`: no materials). `name` is also taken as the OBJ's path: texture
/// maps resolve against the folder of `name`'s folder joined with the `mtllib` name, as
/// [`load_obj`] resolves them against the MTL file's folder.
pub fn parse_obj(
    text: &str,
    name: &str,
    mtl: Option<&str>,
    opts: &NormalOptions,
) -> Result<Mesh, MeshError> {
    parse_obj_with_warnings(text, name, mtl, opts).map(|(m, _)| m)
}

/// Like [`parse_obj`], also returning warnings (missing MTL, undefined materials).
pub fn parse_obj_with_warnings(
    text: &str,
    name: &str,
    mtl: Option<&str>,
    opts: &NormalOptions,
) -> Result<(Mesh, Vec<String>), MeshError> {
    let warnings = RefCell::new(Vec::new());
    let maps = RefCell::new(Vec::new());
    let obj_dir = Path::new(name).parent().unwrap_or(Path::new(""));
    let loader = |mtl_name: &Path| match mtl.map(|t| (t, mtl_lines(t.as_bytes()))) {
        Some((_, Err(why))) => {
            warn(
                &warnings,
                format!("{name}: MTL: {why}; using the default material"),
            );
            Err(tobj::LoadError::OpenFileFailed)
        }
        Some((t, Ok(()))) => load_mtl(t.as_bytes(), &obj_dir.join(mtl_name), &maps, &warnings)
            .inspect_err(|e| {
                warn(
                    &warnings,
                    format!("{name}: MTL: {e}; using the default material"),
                );
            }),
        None => {
            warn(
                &warnings,
                format!("{name}: mtllib given but no MTL text; using the default material"),
            );
            Err(tobj::LoadError::OpenFileFailed)
        }
    };
    let mesh = parse_with(text, name, loader, opts, &warnings, &maps)?;
    Ok((mesh, warnings.into_inner()))
}

/// Reads an MTL file's bytes (`path` names it and its folder resolves texture maps): colours
/// through tobj, texture maps through [`mtl::scan`], whose maps are appended to `maps` in
/// `newmtl` order when tobj accepts the library.
fn load_mtl(
    bytes: &[u8],
    path: &Path,
    maps: &RefCell<Vec<MaterialMaps>>,
    warnings: &RefCell<Vec<String>>,
) -> tobj::MTLLoadResult {
    let bytes = strip_bom_bytes(bytes);
    let Ok(text) = std::str::from_utf8(bytes) else {
        // tobj names the problem.
        return tobj::load_mtl_buf(&mut &bytes[..]);
    };
    let result = tobj::load_mtl_buf(&mut mtl::for_tobj(text).as_bytes());
    if result.is_ok() {
        let mut found = Vec::new();
        let dir = path.parent().unwrap_or(Path::new(""));
        let scanned = mtl::scan(text, &path.display().to_string(), dir, &mut found);
        maps.borrow_mut().extend(scanned);
        for w in found {
            warn(warnings, w);
        }
    }
    result
}

/// Largest MTL file read, in bytes: a material library is a few kilobytes, and a bad one is
/// only a warning, so a huge file named by `mtllib` is refused before it is read.
pub const MAX_MTL_BYTES: u64 = 64 << 20;

/// Longest warning, in characters: warnings quote file names and tobj's messages, and one
/// line each must stay readable.
pub const MAX_WARNING_CHARS: usize = 200;

/// Characters kept from the end of a cut warning, where the reason and the consequence are.
const WARNING_TAIL_CHARS: usize = 80;

/// Pushes `msg`, cut to [`MAX_WARNING_CHARS`] characters: its start (the file and line) and
/// its end (what is wrong, what happens instead), the cut in between marked by `...`.
fn warn(warnings: &RefCell<Vec<String>>, msg: String) {
    // Names and tobj's messages quote the file: its control characters are escaped.
    let msg = quote(&msg, usize::MAX);
    let count = msg.chars().count();
    let msg = if count > MAX_WARNING_CHARS {
        let head = MAX_WARNING_CHARS - 3 - WARNING_TAIL_CHARS;
        let mut cut: String = msg.chars().take(head).collect();
        cut.push_str("...");
        cut.extend(msg.chars().skip(count - WARNING_TAIL_CHARS));
        cut
    } else {
        msg
    };
    warnings.borrow_mut().push(msg);
}

/// Faces warned about one by one; the rest are counted in one more line.
const SHORT_FACE_WARNINGS: usize = 10;

/// Warns about `f` statements with fewer than 3 corners (tobj drops them silently).
fn report_short_faces(short: &[(usize, usize)], file: &str, warnings: &RefCell<Vec<String>>) {
    for &(line, corners) in short.iter().take(SHORT_FACE_WARNINGS) {
        let noun = if corners == 1 { "corner" } else { "corners" };
        warn(
            warnings,
            format!("{file}:{line}: face with {corners} {noun} skipped (a face needs 3 or more)"),
        );
    }
    if short.len() > SHORT_FACE_WARNINGS {
        warn(
            warnings,
            format!(
                "{file}: {} more faces with fewer than 3 corners skipped",
                short.len() - SHORT_FACE_WARNINGS
            ),
        );
    }
}

/// `text` without a leading UTF-8 byte-order mark.
fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// `bytes` without a leading UTF-8 byte-order mark.
fn strip_bom_bytes(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)
}

/// Reads an MTL file: a regular file of at most [`MAX_MTL_BYTES`], opened without blocking
/// (a FIFO or device named by `mtllib` would block or never end), lines of at most
/// [`MAX_LINE_BYTES`]. The error is the reason, for a warning.
fn read_mtl(path: &Path) -> Result<Vec<u8>, String> {
    let bytes = read_file(path, MAX_MTL_BYTES).map_err(|e| format!("cannot read: {e}"))?;
    mtl_lines(&bytes)?;
    Ok(bytes)
}

/// Refuses MTL text with a line over [`MAX_LINE_BYTES`] (tobj copies every line).
fn mtl_lines(bytes: &[u8]) -> Result<(), String> {
    match long_line(bytes, MAX_LINE_BYTES) {
        Some(line) => Err(format!("line {line}: {}", long_line_message())),
        None => Ok(()),
    }
}

fn convert_material(m: &tobj::Material) -> MtlMaterial {
    let d = MtlMaterial::default();
    let rgb = |c: Option<[f32; 3]>, default: Vec3| {
        c.map(Vec3::from_array)
            .filter(|v| v.is_finite() && v.min_element() >= 0.0)
            .unwrap_or(default)
    };
    MtlMaterial {
        name: m.name.clone(),
        ka: rgb(m.ambient, d.ka),
        kd: rgb(m.diffuse, d.kd),
        ks: rgb(m.specular, d.ks),
        ns: m
            .shininess
            .filter(|s| s.is_finite() && *s >= 0.0)
            .unwrap_or(d.ns),
        ..d
    }
}

fn invalid(file: &str, what: impl Into<String>) -> MeshError {
    MeshError::Invalid {
        file: file.to_owned(),
        what: what.into(),
    }
}

fn parse_with<ML: Fn(&Path) -> tobj::MTLLoadResult>(
    text: &str,
    file: &str,
    mtl_loader: ML,
    opts: &NormalOptions,
    warnings: &RefCell<Vec<String>>,
    maps: &RefCell<Vec<MaterialMaps>>,
) -> Result<Mesh, MeshError> {
    // A UTF-8 byte-order mark is not part of the first statement.
    let text = strip_bom(text);
    let scanned = scan(text, file)?;
    report_short_faces(&scanned.short_faces, file, warnings);
    if scanned.faces.is_empty() {
        return Err(MeshError::NoFaces {
            file: file.to_owned(),
        });
    }
    let load_opts = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, materials) = tobj::load_obj_buf(&mut text.as_bytes(), &load_opts, mtl_loader)
        .map_err(|e| invalid(file, format!("tobj: {e}")))?;
    let mut materials: Vec<MtlMaterial> = materials
        .map(|m| m.iter().map(convert_material).collect())
        .unwrap_or_default();
    let maps = maps.take();
    if maps.len() == materials.len() {
        for (m, maps) in materials.iter_mut().zip(maps) {
            m.kd_map = maps.kd_map;
            m.ks_map = maps.ks_map;
            m.normal_map = maps.normal_map;
            m.unused = maps.unused;
        }
    } else {
        warn(
            warnings,
            format!(
                "{file}: MTL: {} materials but {} newmtl blocks scanned; texture maps not read",
                materials.len(),
                maps.len()
            ),
        );
    }
    for (line, name) in &scanned.usemtl {
        if !materials.iter().any(|m| &m.name == name) {
            warn(
                warnings,
                format!(
                    "{file}:{line}: material '{name}' is not defined; using the default material"
                ),
            );
        }
    }
    let mut soup = assemble(&models, &scanned, materials.len(), file)?;
    if opts.source == NormalSource::Computed {
        soup.normals = None;
    }
    let mut mesh = soup.build(opts);
    // A mesh with no drawable face is an error (docs/conventions.md, "Scene files"). Faces with
    // repeated or collinear corners have zero area: they would load, then render nothing at all.
    let degenerate = mesh.degenerate_count();
    if degenerate == mesh.indices.len() {
        return Err(invalid(
            file,
            format!("no drawable face: all {degenerate} triangles have zero area"),
        ));
    }
    mesh.materials = materials;
    for m in models.iter().filter(|m| !m.mesh.indices.is_empty()) {
        if !mesh.groups.contains(&m.name) {
            mesh.groups.push(m.name.clone());
        }
    }
    Ok(mesh)
}

/// Welds tobj's models into one soup, triangulating polygons; smoothing groups from the scan.
fn assemble(
    models: &[tobj::Model],
    scanned: &Scan,
    material_count: usize,
    file: &str,
) -> Result<TriangleSoup, MeshError> {
    let mut soup = TriangleSoup::default();
    let mut weld: HashMap<[u32; 3], u32> = HashMap::new();
    let (mut uvs, mut uv_ix) = (Vec::new(), Vec::new());
    let (mut vns, mut vn_ix) = (Vec::new(), Vec::new());
    let (mut colors, mut color_ix) = (Vec::new(), Vec::new());
    let mut use_color = scanned.has_vertex_colors;
    let mut use_uv = scanned.all_corners_have_uv;
    let mut use_vn = scanned.all_corners_have_normal;
    let mut groups = Vec::new();
    let mut face = 0usize;
    for model in models {
        let m = &model.mesh;
        let faces: Vec<usize> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3]
        } else {
            m.face_arities.iter().map(|&a| a as usize).collect()
        };
        use_uv &= m.texcoord_indices.len() == m.indices.len();
        use_vn &= m.normal_indices.len() == m.indices.len();
        // tobj gives one colour per position it emits for the model, in the same order.
        use_color &= m.vertex_color.len() == m.positions.len();
        let color_base = colors.len() as u32;
        colors.extend(
            m.vertex_color
                .chunks_exact(3)
                .map(|c| unit_color(Vec3::new(c[0], c[1], c[2]))),
        );
        let (uv_base, vn_base) = (uvs.len() as u32, vns.len() as u32);
        uvs.extend(m.texcoords.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])));
        vns.extend(
            m.normals
                .chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2])),
        );
        let position = |i: u32| {
            let i = i as usize * 3;
            m.positions
                .get(i..i + 3)
                .map(|c| Vec3::new(c[0], c[1], c[2]))
        };
        let material = m.material_id.filter(|&id| id < material_count).unwrap_or(0) as u32;
        let mut start = 0usize;
        for arity in faces {
            let corners = m
                .indices
                .get(start..start + arity)
                .ok_or_else(|| invalid(file, "tobj returned fewer indices than faces"))?;
            let Some(info) = scanned.faces.get(face) else {
                return Err(invalid(
                    file,
                    "face count differs between tobj and the line scan",
                ));
            };
            let mut ids = Vec::with_capacity(arity);
            let mut points = Vec::with_capacity(arity);
            for &c in corners {
                let p = position(c).ok_or_else(|| invalid(file, "tobj index out of range"))?;
                let next = soup.positions.len() as u32;
                ids.push(*weld.entry(weld_key(p)).or_insert_with(|| {
                    soup.positions.push(p);
                    next
                }));
                points.push(p);
            }
            for t in triangulate(&points) {
                soup.triangles.push(t.map(|k| ids[k]));
                let at =
                    |v: &Vec<u32>, base: u32, k: usize| v.get(start + k).map_or(0, |&i| base + i);
                uv_ix.push(t.map(|k| at(&m.texcoord_indices, uv_base, k)));
                vn_ix.push(t.map(|k| at(&m.normal_indices, vn_base, k)));
                color_ix.push(t.map(|k| color_base + corners[k]));
                groups.push(info.group);
                soup.material_ids.push(material);
                soup.polygon_ids.push(face as u32);
            }
            start += arity;
            face += 1;
        }
    }
    if face != scanned.faces.len() {
        return Err(invalid(
            file,
            "face count differs between tobj and the line scan",
        ));
    }
    if use_uv && !uvs.is_empty() {
        soup.uvs = Some((uvs, uv_ix));
    }
    if use_color && !colors.is_empty() {
        soup.colors = Some((colors, color_ix));
    }
    if use_vn && !vns.is_empty() {
        soup.normals = Some((vns, vn_ix));
    }
    if scanned.has_smoothing_groups {
        soup.smoothing_groups = Some(groups);
    }
    Ok(soup)
}
