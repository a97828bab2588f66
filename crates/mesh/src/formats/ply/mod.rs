//! Stanford PLY, ASCII or binary (little or big endian), through `ply-rs-bw`.
//!
//! The crate parses the header and each element; this module drives it one element at a time,
//! so an error names the line (ASCII) or the element and its number (binary). Read: the
//! `vertex` element's `x y z` (any numeric type), when all three are present `nx ny nz`, and
//! when all three are present the colour `red green blue` (else `r g b`, else `diffuse_red
//! diffuse_green diffuse_blue`): `uchar` divided by 255, `ushort` by 65535, `uint` by
//! 2^32 - 1, `float` and `double` as they are, clamped to `[0, 1]` and taken as linear RGB (a
//! signed integer type is a warning, and no colours); the `face` element's `vertex_indices` (or
//! `vertex_index`) list of any integer type. Other properties (`alpha`, confidence) and
//! elements (edges) are read past. Faces with more than three corners are triangulated by ear
//! clipping as OBJ polygons are.

use glam::Vec3;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    BeginList, Header, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};

use super::{Welder, element_error, finish};
use crate::build::{TriangleSoup, unit_color};
use crate::error::MeshError;
use crate::mesh::Mesh;
use crate::normals::NormalOptions;
use crate::triangulate::triangulate;

mod payload;
mod words;

use payload::{Payload, clip, message};

/// Names the face list may have (both are in use: Stanford's scans use `vertex_indices`).
const FACE_LISTS: [&str; 2] = ["vertex_indices", "vertex_index"];

/// The names a vertex colour's channels may have, in order of preference.
const COLOR_NAMES: [[&str; 3]; 3] = [
    ["red", "green", "blue"],
    ["r", "g", "b"],
    ["diffuse_red", "diffuse_green", "diffuse_blue"],
];

/// One `vertex` element: position, normal and colour channels, as read (f64 so doubles lose
/// nothing early; colours as written, scaled once the header's type is known).
#[derive(Default)]
struct PlyVertex {
    position: [f64; 3],
    normal: [f64; 3],
    /// Per set of [`COLOR_NAMES`], its three channels.
    rgb: [[f64; 3]; 3],
}

impl PlyVertex {
    fn set(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        let slot = match name {
            "x" => &mut self.position[0],
            "y" => &mut self.position[1],
            "z" => &mut self.position[2],
            "nx" => &mut self.normal[0],
            "ny" => &mut self.normal[1],
            "nz" => &mut self.normal[2],
            _ => {
                let found = COLOR_NAMES.iter().enumerate().find_map(|(set, names)| {
                    names.iter().position(|n| *n == name).map(|c| (set, c))
                });
                match found {
                    Some((set, channel)) => &mut self.rgb[set][channel],
                    None => return PropertyAccessResult::Ignored,
                }
            }
        };
        *slot = value;
        PropertyAccessResult::Set
    }
}

/// The value of a numeric scalar property.
fn scalar(property: &Property) -> Option<f64> {
    Some(match *property {
        Property::Char(v) => f64::from(v),
        Property::UChar(v) => f64::from(v),
        Property::Short(v) => f64::from(v),
        Property::UShort(v) => f64::from(v),
        Property::Int(v) => f64::from(v),
        Property::UInt(v) => f64::from(v),
        Property::Float(v) => f64::from(v),
        Property::Double(v) => v,
        _ => return None,
    })
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        Self::default()
    }
    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        match scalar(&property) {
            Some(v) => self.set(name, v),
            None => PropertyAccessResult::Ignored,
        }
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.set(name, f64::from(value))
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        self.set(name, value)
    }
}

/// One `face` element: its corner indices, as written (the common `int` and `uint` lists are
/// filled in place, the narrower integer types go through `set_property`).
#[derive(Default)]
struct PlyFace {
    signed: Vec<i32>,
    unsigned: Vec<u32>,
}

impl PlyFace {
    fn corners(&self) -> impl Iterator<Item = i64> + '_ {
        self.signed
            .iter()
            .map(|&i| i64::from(i))
            .chain(self.unsigned.iter().map(|&i| i64::from(i)))
    }
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        Self::default()
    }
    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if !FACE_LISTS.contains(&name) {
            return PropertyAccessResult::Ignored;
        }
        self.signed = match property {
            Property::ListChar(v) => v.into_iter().map(i32::from).collect(),
            Property::ListUChar(v) => v.into_iter().map(i32::from).collect(),
            Property::ListShort(v) => v.into_iter().map(i32::from).collect(),
            Property::ListUShort(v) => v.into_iter().map(i32::from).collect(),
            Property::ListInt(v) => v,
            Property::ListUInt(v) => {
                self.unsigned = v;
                return PropertyAccessResult::Set;
            }
            _ => return PropertyAccessResult::UnsupportedType,
        };
        PropertyAccessResult::Set
    }
    fn begin_list_int(&mut self, name: &str, _len: usize) -> BeginList<'_, i32> {
        if FACE_LISTS.contains(&name) {
            BeginList::Fill(&mut self.signed)
        } else {
            BeginList::UseSetter
        }
    }
    fn begin_list_uint(&mut self, name: &str, _len: usize) -> BeginList<'_, u32> {
        if FACE_LISTS.contains(&name) {
            BeginList::Fill(&mut self.unsigned)
        } else {
            BeginList::UseSetter
        }
    }
}

/// Any other element: read past.
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}

/// What the header says this reader needs.
struct Layout {
    vertices: usize,
    has_normals: bool,
    /// The set of [`COLOR_NAMES`] the colours have, and the divisor of each channel.
    colors: Option<(usize, [f64; 3])>,
    /// What the header holds that is read past with a warning.
    warnings: Vec<String>,
}

/// The divisor that maps a colour channel of `ty` to `[0, 1]`; `None` for signed integers,
/// whose range no writer agrees on.
fn color_divisor(ty: &ScalarType) -> Option<f64> {
    match ty {
        ScalarType::UChar => Some(255.0),
        ScalarType::UShort => Some(65535.0),
        ScalarType::UInt => Some(f64::from(u32::MAX)),
        ScalarType::Float | ScalarType::Double => Some(1.0),
        ScalarType::Char | ScalarType::Short | ScalarType::Int => None,
    }
}

/// Checks the `vertex` and `face` elements' properties before any data is read, so a file
/// this reader cannot use is named for its header, not for a confusing payload error.
fn layout(header: &Header, file: &str) -> Result<Layout, MeshError> {
    let header_error = |what: String| element_error(file, "header", what);
    let vertex = header
        .elements
        .get("vertex")
        .ok_or_else(|| header_error("no `element vertex`".to_owned()))?;
    let scalar_named = |name: &str| {
        vertex
            .properties
            .get(name)
            .map(|p| matches!(p.data_type, PropertyType::Scalar(_)))
    };
    for axis in ["x", "y", "z"] {
        match scalar_named(axis) {
            Some(true) => {}
            Some(false) => {
                return Err(header_error(format!(
                    "vertex property `{axis}` is a list, expected a number"
                )));
            }
            None => {
                return Err(header_error(format!("vertex has no property `{axis}`")));
            }
        }
    }
    let has_normals = ["nx", "ny", "nz"]
        .iter()
        .all(|n| scalar_named(n) == Some(true));
    let mut warnings = Vec::new();
    let colors = COLOR_NAMES.iter().enumerate().find_map(|(set, names)| {
        let types: Vec<&ScalarType> = names
            .iter()
            .filter_map(|n| match &vertex.properties.get(*n)?.data_type {
                PropertyType::Scalar(ty) => Some(ty),
                PropertyType::List(..) => None,
            })
            .collect();
        let [r, g, b] = types[..] else {
            return None;
        };
        match (color_divisor(r), color_divisor(g), color_divisor(b)) {
            (Some(r), Some(g), Some(b)) => Some((set, [r, g, b])),
            _ => {
                warnings.push(format!(
                    "{file}: header: vertex colour `{}` has a signed integer type; colours not read",
                    names.join(" ")
                ));
                None
            }
        }
    });
    if let Some(face) = header.elements.get("face") {
        let list = FACE_LISTS
            .iter()
            .find_map(|n| face.properties.get(*n))
            .ok_or_else(|| {
                header_error("face has no `vertex_indices` (or `vertex_index`) list".to_owned())
            })?;
        match list.data_type {
            PropertyType::List(_, ScalarType::Float | ScalarType::Double) => {
                return Err(header_error(format!(
                    "face property `{}` lists floating-point numbers, expected integers",
                    list.name
                )));
            }
            PropertyType::Scalar(_) => {
                return Err(header_error(format!(
                    "face property `{}` is a number, expected a list",
                    list.name
                )));
            }
            PropertyType::List(..) => {}
        }
    }
    Ok(Layout {
        vertices: vertex.count,
        has_normals,
        colors,
        warnings,
    })
}

/// Parses a PLY file's bytes; `file` names it in messages.
pub(super) fn parse(
    bytes: &[u8],
    file: &str,
    opts: &NormalOptions,
) -> Result<(Mesh, Vec<String>), MeshError> {
    if bytes.is_empty() {
        return Err(MeshError::NoFaces {
            file: file.to_owned(),
        });
    }
    words::check_header(bytes, file)?;
    let mut reader = Reader::new(bytes);
    let header = Parser::<Skip>::new()
        .read_header(&mut reader)
        .map_err(|e| match e.line() {
            Some(line) => {
                // The crate's message goes on with the parser's internal state; its first
                // sentence and the offending line say it all.
                let why = message(&e);
                let why = why.split("; ").next().unwrap_or(&why);
                let text = bytes
                    .split(|&b| b == b'\n')
                    .nth(line.saturating_sub(1))
                    .map(String::from_utf8_lossy)
                    .unwrap_or_default();
                MeshError::Parse {
                    file: file.to_owned(),
                    line,
                    what: format!(
                        "header: {}: '{}'",
                        why.trim_end_matches('.'),
                        clip(text.trim())
                    ),
                }
            }
            None => element_error(file, "header", message(&e)),
        })?;
    let layout = layout(&header, file)?;
    let rest: &[u8] = reader.get_ref();
    let header_len = bytes.len() - rest.len();
    let header_lines = bytes[..header_len].iter().filter(|&&b| b == b'\n').count();
    let mut payload = Payload::new(rest, header.encoding, header_lines, file)?;

    let mut positions: Vec<Vec3> = Vec::with_capacity(layout.vertices.min(1 << 20));
    let mut normals: Vec<Vec3> = Vec::new();
    let mut colors: Vec<Vec3> = Vec::new();
    // Faces flat: `corners[face_starts[f]..face_starts[f + 1]]`.
    let mut corners: Vec<u32> = Vec::new();
    let mut face_starts: Vec<usize> = vec![0];
    let mut short_faces = 0usize;
    let (vertex_parser, face_parser, skip_parser) = (
        Parser::<PlyVertex>::new(),
        Parser::<PlyFace>::new(),
        Parser::<Skip>::new(),
    );
    for (name, def) in &header.elements {
        if def.properties.is_empty() {
            // Nothing to read; a huge count must not spin (the file cannot be checked).
            continue;
        }
        for i in 0..def.count {
            match name.as_str() {
                "vertex" => {
                    let (v, place) = payload.read(&vertex_parser, def, i, file)?;
                    let p = v.position.map(|c| c as f32);
                    if !p.iter().all(|c| c.is_finite()) {
                        return Err(place.error(file, "NaN or infinite coordinate"));
                    }
                    positions.push(Vec3::from_array(p));
                    if layout.has_normals {
                        let n = v.normal.map(|c| c as f32);
                        if !n.iter().all(|c| c.is_finite()) {
                            return Err(place.error(file, "NaN or infinite normal"));
                        }
                        normals.push(Vec3::from_array(n));
                    }
                    if let Some((set, divisor)) = layout.colors {
                        let c = [0, 1, 2].map(|k| (v.rgb[set][k] / divisor[k]) as f32);
                        if !c.iter().all(|x| x.is_finite()) {
                            return Err(place.error(file, "NaN or infinite colour"));
                        }
                        colors.push(unit_color(Vec3::from_array(c)));
                    }
                }
                "face" => {
                    let (f, place) = payload.read(&face_parser, def, i, file)?;
                    let start = corners.len();
                    for c in f.corners() {
                        match u32::try_from(c) {
                            Ok(c) if (c as usize) < layout.vertices => corners.push(c),
                            _ => {
                                return Err(place.error(
                                    file,
                                    format!(
                                        "vertex index {c} out of range ({} vertices, \
                                         numbered from 0)",
                                        layout.vertices
                                    ),
                                ));
                            }
                        }
                    }
                    if corners.len() - start < 3 {
                        corners.truncate(start);
                        short_faces += 1;
                    } else {
                        face_starts.push(corners.len());
                    }
                }
                _ => {
                    payload.read(&skip_parser, def, i, file)?;
                }
            }
        }
    }

    let mut warnings = layout.warnings;
    if short_faces > 0 {
        warnings.push(format!(
            "{file}: {short_faces} faces with fewer than 3 vertices skipped"
        ));
    }
    let mut soup = TriangleSoup::default();
    let mut welder = Welder::default();
    let ids: Vec<u32> = positions.iter().map(|&p| welder.id(&mut soup, p)).collect();
    let mut normal_ix = Vec::with_capacity(corners.len() / 3);
    let mut add = |soup: &mut TriangleSoup, vertex: [u32; 3], face: usize| {
        soup.triangles.push(vertex.map(|v| ids[v as usize]));
        normal_ix.push(vertex);
        soup.polygon_ids.push(face as u32);
        soup.material_ids.push(0);
    };
    for (face, range) in face_starts.windows(2).enumerate() {
        let polygon = &corners[range[0]..range[1]];
        if let [a, b, c] = *polygon {
            // Scans are triangles: no polygon to clip.
            add(&mut soup, [a, b, c], face);
            continue;
        }
        let points: Vec<Vec3> = polygon.iter().map(|&c| positions[c as usize]).collect();
        for t in triangulate(&points) {
            add(&mut soup, t.map(|k| polygon[k]), face);
        }
    }
    if layout.colors.is_some() {
        // Colours are per file vertex, as normals are: the same corner indices.
        soup.colors = Some((colors, normal_ix.clone()));
    }
    if layout.has_normals {
        soup.normals = Some((normals, normal_ix));
    }
    let mesh = finish(soup, file, opts)?;
    Ok((mesh, warnings))
}

#[cfg(test)]
mod tests;
