//! STL, ASCII or binary: binary through `stl_io`, ASCII by [`ascii`].
//!
//! STL stores every triangle with its own three corners; the corners are welded by exact
//! equality so faces that share a position can be smoothed (the 60-degree crease of the
//! defaults keeps a part's edges sharp). The facet normals are not used, in either encoding:
//! they are per face, which is what the crease test recomputes anyway, and many writers leave
//! them zero (or NaN).
//!
//! Binary or ASCII is decided before anything is parsed, by the size rule first: a file
//! exactly `84 + 50 * count` bytes long (`count` the little-endian `u32` at byte 80) is binary.
//! Otherwise a file shaped as ASCII STL is ASCII: its first word `solid` in any case (after a
//! byte-order mark and blank lines), the next line's first word `facet` or `endsolid`. Anything
//! else is binary (a truncated one, reported as such). Deciding by the `solid` keyword alone
//! (as `stl_io` does) misreads the binary files whose free-text header begins with `solid`,
//! which several CAD exporters write; deciding by control characters misreads an ASCII file
//! with one stray NUL byte as a binary one announcing billions of triangles.

mod ascii;

use std::borrow::Cow;
use std::io::Cursor;

use glam::Vec3;

use super::{Welder, element_error, finish, one_line};
use crate::build::TriangleSoup;
use crate::error::MeshError;
use crate::mesh::Mesh;
use crate::normals::NormalOptions;

/// Binary STL: an 80-byte header and a little-endian `u32` triangle count.
const BINARY_HEADER: usize = 84;
/// Binary STL: normal and three corners (12 `f32`) and a 2-byte attribute per triangle.
const BINARY_FACET: usize = 50;

/// The size a binary STL with the count in `bytes[80..84]` has.
fn binary_size(bytes: &[u8]) -> Option<u64> {
    let count: [u8; 4] = bytes.get(80..BINARY_HEADER)?.try_into().ok()?;
    Some(BINARY_HEADER as u64 + BINARY_FACET as u64 * u64::from(u32::from_le_bytes(count)))
}

/// Parses an STL file's bytes; `file` names it in messages.
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
    let len = bytes.len() as u64;
    let exact_binary = binary_size(bytes) == Some(len);
    let mut warnings = Vec::new();
    let corners = if exact_binary || !ascii::looks_ascii(bytes) {
        binary(bytes, file, &mut warnings)?
    } else {
        let (corners, ascii_warnings) = ascii::parse(bytes, file)?;
        warnings.extend(ascii_warnings);
        corners
    };
    let mut soup = TriangleSoup::default();
    let mut welder = Welder::default();
    for tri in corners.chunks_exact(3) {
        let ids = [tri[0], tri[1], tri[2]].map(|p| welder.id(&mut soup, p));
        soup.triangles.push(ids);
        soup.material_ids.push(0);
    }
    let mesh = finish(soup, file, opts)?;
    Ok((mesh, warnings))
}

/// The corners of every facet of a binary STL, three per triangle.
fn binary(bytes: &[u8], file: &str, warnings: &mut Vec<String>) -> Result<Vec<Vec3>, MeshError> {
    let len = bytes.len() as u64;
    let Some(expected) = binary_size(bytes) else {
        return Err(element_error(
            file,
            "header",
            format!(
                "truncated binary STL: {len} bytes, the header alone takes {BINARY_HEADER} \
                 (an ASCII STL starts with `solid`)"
            ),
        ));
    };
    let count = (expected - BINARY_HEADER as u64) / BINARY_FACET as u64;
    if len < expected {
        let complete = (len - BINARY_HEADER as u64) / BINARY_FACET as u64;
        return Err(element_error(
            file,
            format!("facet {} of {count}", complete + 1),
            format!(
                "truncated binary STL: the header announces {count} triangles ({expected} \
                 bytes), the file has {len} bytes"
            ),
        ));
    }
    if len > expected {
        warnings.push(format!(
            "{file}: {} bytes after the last of {count} triangles ignored",
            len - expected
        ));
    }
    if count == 0 {
        return Err(MeshError::NoFaces {
            file: file.to_owned(),
        });
    }
    // `stl_io` picks ASCII for a file starting with `solid `; the 80 header bytes are free
    // text, so a binary file that starts that way is handed over with its first byte changed.
    let data: Cow<'_, [u8]> = if bytes.starts_with(b"solid") {
        let mut owned = bytes[..expected as usize].to_vec();
        owned[0] = b'S';
        Cow::Owned(owned)
    } else {
        Cow::Borrowed(&bytes[..expected as usize])
    };
    let mut cursor = Cursor::new(data.as_ref());
    let reader = stl_io::create_stl_reader(&mut cursor)
        .map_err(|e| element_error(file, "header", one_line(&e.to_string())))?;
    let mut corners = Vec::with_capacity(count as usize * 3);
    for (i, facet) in reader.enumerate() {
        let element = || format!("facet {} of {count}", i + 1);
        let facet = facet.map_err(|e| element_error(file, element(), one_line(&e.to_string())))?;
        for (k, v) in facet.vertices.iter().enumerate() {
            let p = Vec3::from_array(v.0);
            if !p.is_finite() {
                return Err(element_error(
                    file,
                    element(),
                    format!("vertex {}: NaN or infinite coordinate", k + 1),
                ));
            }
            corners.push(p);
        }
    }
    Ok(corners)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn size_decides_binary_even_when_the_header_says_solid() {
        let mut bytes = b"solid but binary".to_vec();
        bytes.resize(80, b' ');
        bytes.extend_from_slice(&1u32.to_le_bytes());
        for v in [
            [0.0f32; 3],
            [0.0, 0.0, 1.0],
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ] {
            for c in v {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
        bytes.extend_from_slice(&[0, 0]);
        let (m, _) = parse(&bytes, "t.stl", &NormalOptions::default()).expect("binary");
        assert_eq!(m.indices.len(), 1);
    }

    #[test]
    fn bare_solid_first_line_is_ascii() {
        let text = "solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                    vertex 0 1 0\nendloop\nendfacet\nendsolid\n";
        let (m, _) = parse(text.as_bytes(), "t.stl", &NormalOptions::default()).expect("ascii");
        assert_eq!(m.indices.len(), 1);
    }

    #[test]
    fn ascii_errors_name_the_facet_line() {
        let text = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                    vertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\n\
                    vertex 0 0 0\nvertex 1 nan 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let e = parse(text.as_bytes(), "t.stl", &NormalOptions::default())
            .expect_err("NaN")
            .to_string();
        assert!(e.starts_with("t.stl:12: facet 2: "), "{e}");
    }
}
