//! Mesh files other than OBJ, and the one entry point that picks a reader by extension.
//!
//! Every reader ends the way the OBJ loader does: positions welded by exact equality
//! (`-0.0 == 0.0`) so faces that share a position may be smoothed together, polygons
//! triangulated by ear clipping, then [`crate::TriangleSoup::build`] with the caller's
//! [`NormalOptions`]. None of these formats has smoothing groups, so the default options give
//! authored normals where the file has them for every vertex and a 60-degree crease otherwise,
//! exactly as for an OBJ file without `s` lines.
//!
//! Errors follow the OBJ contract: the file, then the line (text formats) or the element
//! (`facet 12`, `face 7 of 40`, `meshes[0].primitives[1]`), then what is wrong.

mod gltf;
pub use gltf::gltf_uri_bytes;
mod ply;
mod stl;

use std::collections::HashMap;
use std::path::Path;

use glam::Vec3;

use crate::assets::read_asset;
use crate::build::{TriangleSoup, weld_key};
use crate::error::MeshError;
use crate::loader::{load_obj_with_warnings, parse_obj_with_warnings};
use crate::mesh::Mesh;
use crate::normals::{NormalOptions, NormalSource};
use crate::open::{MAX_MESH_FILE_BYTES, read_file};

/// A mesh file format, chosen by the file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Wavefront OBJ (and its MTL files); also any extension not listed below.
    Obj,
    /// Stanford PLY, ASCII or binary (either byte order): `.ply`.
    Ply,
    /// STL, ASCII or binary: `.stl`.
    Stl,
    /// glTF 2.0, JSON (`.gltf`) or binary (`.glb`); the reader tells them apart by content.
    Gltf,
}

impl MeshFormat {
    /// The format for `path`'s extension (case-insensitive). Anything that is not `.ply`,
    /// `.stl`, `.gltf` or `.glb` is read as OBJ, so meshes named without the usual extension
    /// load as they always have.
    #[must_use]
    pub fn from_path(path: &Path) -> MeshFormat {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("ply") => MeshFormat::Ply,
            Some("stl") => MeshFormat::Stl,
            Some("gltf" | "glb") => MeshFormat::Gltf,
            _ => MeshFormat::Obj,
        }
    }

    /// The format's usual name, for messages and `phosphor info`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            MeshFormat::Obj => "OBJ",
            MeshFormat::Ply => "PLY",
            MeshFormat::Stl => "STL",
            MeshFormat::Gltf => "glTF 2.0",
        }
    }
}

/// Loads a mesh file of any supported format, chosen by extension ([`MeshFormat::from_path`]).
///
/// # Errors
/// The file cannot be read or is malformed; the message names the file and the line or
/// element.
pub fn load_mesh(path: &Path, opts: &NormalOptions) -> Result<Mesh, MeshError> {
    load_mesh_with_warnings(path, opts).map(|(m, _)| m)
}

/// Like [`load_mesh`], also returning warnings (one line each, `FILE[:LINE]: what`).
///
/// Every file is opened as a regular file only, without blocking, and read up to a cap
/// ([`crate::open`]). Files a mesh refers to (an OBJ's MTL, a glTF's `.bin` buffers) are read
/// relative to the mesh's directory, a glTF's confined to it ([`crate::assets`]).
///
/// # Errors
/// As [`load_mesh`].
pub fn load_mesh_with_warnings(
    path: &Path,
    opts: &NormalOptions,
) -> Result<(Mesh, Vec<String>), MeshError> {
    let format = MeshFormat::from_path(path);
    if format == MeshFormat::Obj {
        return load_obj_with_warnings(path, opts);
    }
    let file = path.display().to_string();
    let bytes = read_file(path, MAX_MESH_FILE_BYTES).map_err(|source| MeshError::Io {
        file: file.clone(),
        source,
    })?;
    let read_relative = |rel: &str| read_asset(path, rel);
    parse_mesh_bytes(&bytes, &file, format, &read_relative, opts)
}

/// Parses the bytes of a mesh file in `format`; `name` is used in messages, `read_relative`
/// returns the bytes of a file the mesh refers to by a path relative to its own directory
/// (an OBJ's `mtllib`, a glTF buffer's `uri`). Returns the mesh and its warnings.
///
/// ```
/// use phosphor_mesh::{MeshFormat, NormalOptions, parse_mesh_bytes};
///
/// let stl = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
///            vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
/// let none = |_: &str| Err(std::io::Error::from(std::io::ErrorKind::NotFound));
/// let (mesh, _) =
///     parse_mesh_bytes(stl.as_bytes(), "t.stl", MeshFormat::Stl, &none, &NormalOptions::default())?;
/// assert_eq!(mesh.indices.len(), 1);
/// # Ok::<(), phosphor_mesh::MeshError>(())
/// ```
///
/// # Errors
/// The bytes are malformed; the message starts with `name` and names the line or element.
pub fn parse_mesh_bytes(
    bytes: &[u8],
    name: &str,
    format: MeshFormat,
    read_relative: &dyn Fn(&str) -> std::io::Result<Vec<u8>>,
    opts: &NormalOptions,
) -> Result<(Mesh, Vec<String>), MeshError> {
    match format {
        MeshFormat::Obj => parse_obj_bytes(bytes, name, read_relative, opts),
        MeshFormat::Ply => ply::parse(bytes, name, opts),
        MeshFormat::Stl => stl::parse(bytes, name, opts),
        MeshFormat::Gltf => gltf::parse(bytes, name, read_relative, opts),
    }
}

/// OBJ from bytes: UTF-8 text, and the first `mtllib` file if `read_relative` finds it (a
/// missing MTL is a warning, as in [`crate::load_obj`]).
fn parse_obj_bytes(
    bytes: &[u8],
    name: &str,
    read_relative: &dyn Fn(&str) -> std::io::Result<Vec<u8>>,
    opts: &NormalOptions,
) -> Result<(Mesh, Vec<String>), MeshError> {
    let text = std::str::from_utf8(bytes).map_err(|e| MeshError::Parse {
        file: name.to_owned(),
        line: bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1,
        what: "not valid UTF-8".to_owned(),
    })?;
    let mtl = text
        .lines()
        .map(str::trim_start)
        .find_map(|l| l.strip_prefix("mtllib "))
        .and_then(|m| read_relative(m.trim()).ok())
        .and_then(|b| String::from_utf8(b).ok());
    parse_obj_with_warnings(text, name, mtl.as_deref(), opts)
}

/// Positions welded by exact equality while a reader adds them.
#[derive(Default)]
struct Welder {
    ids: HashMap<[u32; 3], u32>,
}

impl Welder {
    /// The welded id of `p` in `soup.positions`, adding it when new.
    fn id(&mut self, soup: &mut TriangleSoup, p: Vec3) -> u32 {
        let next = soup.positions.len() as u32;
        *self.ids.entry(weld_key(p)).or_insert_with(|| {
            soup.positions.push(p);
            next
        })
    }
}

/// An error naming an element of a binary file (or of a text file with no line to give).
fn element_error(file: &str, element: impl Into<String>, what: impl Into<String>) -> MeshError {
    MeshError::Element {
        file: file.to_owned(),
        element: element.into(),
        what: what.into(),
    }
}

/// A library's message on one line: its own line breaks and tabs become `; `.
fn one_line(message: &str) -> String {
    message
        .split(['\n', '\t'])
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// The mesh of a finished soup, with the OBJ loader's rules: no triangle at all is
/// [`MeshError::NoFaces`], only zero-area triangles is an error too (they would load, then
/// render nothing), and [`NormalSource::Computed`] drops authored normals.
fn finish(mut soup: TriangleSoup, file: &str, opts: &NormalOptions) -> Result<Mesh, MeshError> {
    if soup.triangles.is_empty() {
        return Err(MeshError::NoFaces {
            file: file.to_owned(),
        });
    }
    if opts.source == NormalSource::Computed {
        soup.normals = None;
    }
    let mesh = soup.build(opts);
    let degenerate = mesh.degenerate_count();
    if degenerate == mesh.indices.len() {
        return Err(MeshError::Invalid {
            file: file.to_owned(),
            what: format!("no drawable face: all {degenerate} triangles have zero area"),
        });
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_pick_the_format_case_insensitively() {
        for (name, format) in [
            ("a.ply", MeshFormat::Ply),
            ("a.PLY", MeshFormat::Ply),
            ("dir.v2/a.Stl", MeshFormat::Stl),
            ("a.gltf", MeshFormat::Gltf),
            ("a.GLB", MeshFormat::Gltf),
            ("a.obj", MeshFormat::Obj),
            ("a.txt", MeshFormat::Obj),
            ("noext", MeshFormat::Obj),
        ] {
            assert_eq!(MeshFormat::from_path(Path::new(name)), format, "{name}");
        }
    }

    #[test]
    fn library_messages_become_one_line() {
        assert_eq!(
            one_line("Couldn't parse.\n\tString: 'x'\n\tError: bad, "),
            "Couldn't parse.; String: 'x'; Error: bad,"
        );
    }
}
