//! STL, ASCII or binary, through `stl_io`.
//!
//! STL stores every triangle with its own three corners; the corners are welded by exact
//! equality so faces that share a position can be smoothed (the 60-degree crease of the
//! defaults keeps a part's edges sharp). The facet normals are not used: they are per face,
//! which is what the crease test recomputes anyway, and many writers leave them zero.
//!
//! Binary or ASCII is decided before `stl_io` sees the file: a file exactly `84 + 50 * count`
//! bytes long is binary, and so is one that does not start with `solid` or holds control
//! characters (a truncated binary file). Deciding by the `solid` keyword alone (as `stl_io`
//! does) misreads the binary files whose free-text header begins with `solid`, which several
//! CAD exporters write.

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

/// True when the file reads as ASCII STL: its first word is `solid` (after a byte-order mark
/// or blanks) and its first kilobyte holds no control character. A binary file's triangle
/// count alone has a zero byte for fewer than 16 million triangles, so a binary file whose
/// header says `solid` (complete or truncated) is not taken for text.
fn looks_ascii(bytes: &[u8]) -> bool {
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let start = text
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(text.len());
    text[start..].starts_with(b"solid")
        && text
            .iter()
            .take(1024)
            .all(|&b| b >= 0x20 || b"\t\n\r\x0c".contains(&b))
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
    let corners = if exact_binary || !looks_ascii(bytes) {
        binary(bytes, file, &mut warnings)?
    } else {
        ascii(bytes, file)?
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

/// The corners of every facet of an ASCII STL, three per triangle.
fn ascii(bytes: &[u8], file: &str) -> Result<Vec<Vec3>, MeshError> {
    // `stl_io` wants the first line to start with `solid ` exactly; a file whose first line is
    // a bare `solid`, or has a byte-order mark or leading blanks, gets that line replaced
    // (the solid's name is not used, and line numbers stay the same).
    let data: Cow<'_, [u8]> = if bytes.starts_with(b"solid ") {
        Cow::Borrowed(bytes)
    } else {
        let first_end = bytes
            .iter()
            .position(|&b| b == b'\n')
            .unwrap_or(bytes.len());
        let mut owned = b"solid \n".to_vec();
        owned.extend_from_slice(bytes.get(first_end + 1..).unwrap_or(&[]));
        Cow::Owned(owned)
    };
    let mut cursor = Cursor::new(data.as_ref());
    let reader = stl_io::create_stl_reader(&mut cursor)
        .map_err(|e| line_error(file, 1, one_line(&e.to_string())))?;
    let mut corners = Vec::new();
    for (i, facet) in reader.enumerate() {
        let facet = facet.map_err(|e| {
            line_error(
                file,
                bad_line(&data, i),
                format!("facet {}: {}", i + 1, one_line(&e.to_string())),
            )
        })?;
        corners.extend(facet.vertices.iter().map(|v| Vec3::from_array(v.0)));
    }
    if corners.is_empty() {
        return Err(MeshError::NoFaces {
            file: file.to_owned(),
        });
    }
    Ok(corners)
}

fn line_error(file: &str, line: usize, what: String) -> MeshError {
    MeshError::Parse {
        file: file.to_owned(),
        line,
        what,
    }
}

/// The 1-based line of the first malformed line of facet `index` (0-based), or the last line
/// when the file ends inside it. `stl_io` reports no position; like it, this reads seven
/// non-blank lines per facet after the `solid` line, and runs only after an error.
fn bad_line(text: &[u8], index: usize) -> usize {
    let number = |w: &[u8]| {
        std::str::from_utf8(w)
            .ok()
            .and_then(|w| w.parse::<f32>().ok())
            .is_some_and(f32::is_finite)
    };
    let well_formed = |k: usize, words: &[&[u8]]| match (k, words) {
        (0, [b"endsolid", ..]) => true,
        (0, [b"facet", b"normal", x, y, z]) | (2..=4, [b"vertex", x, y, z]) => {
            number(x) && number(y) && number(z)
        }
        (1, [b"outer", b"loop"]) | (5, [b"endloop"]) | (6, [b"endfacet"]) => true,
        _ => false,
    };
    let first = 1 + 7 * index;
    let mut last = 1;
    let non_blank = text
        .split(|&b| b == b'\n')
        .enumerate()
        .map(|(n, line)| {
            let words: Vec<&[u8]> = line
                .split(|b| b.is_ascii_whitespace())
                .filter(|w| !w.is_empty())
                .collect();
            (n + 1, words)
        })
        .filter(|(_, words)| !words.is_empty());
    for (k, (line, words)) in non_blank.enumerate().take(first + 7) {
        if k >= first && !well_formed(k - first, &words) {
            return line;
        }
        last = line;
    }
    last
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
