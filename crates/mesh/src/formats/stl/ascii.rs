//! ASCII STL, read line by line: every `solid` of the file, keywords in any case, blank lines
//! anywhere, the solid's name as any bytes (Latin-1 names are common), facet normals not read
//! (as in binary files: the crease test recomputes them, and writers leave them zero or NaN).
//!
//! ```text
//! solid NAME
//!   facet normal NX NY NZ
//!     outer loop
//!       vertex X Y Z      (three times)
//!     endloop
//!   endfacet
//! endsolid NAME
//! ```

use glam::Vec3;

use crate::error::MeshError;
use crate::open::{MAX_LINE_BYTES, long_line, long_line_message};
use crate::sanitize::quote_bytes;

/// Most characters of a line quoted in a message.
const QUOTED: usize = 40;

/// A non-blank line: its 1-based number, its text and its words.
type Line<'a> = (usize, &'a [u8], Vec<&'a [u8]>);

/// The non-blank lines of `bytes`, numbered from 1, each split into words.
struct Lines<'a> {
    rest: &'a [u8],
    line: usize,
}

impl<'a> Lines<'a> {
    /// The next non-blank line: its number, its text and its words.
    fn next_line(&mut self) -> Option<Line<'a>> {
        while !self.rest.is_empty() {
            let end = self
                .rest
                .iter()
                .position(|&b| b == b'\n')
                .unwrap_or(self.rest.len());
            let text = &self.rest[..end];
            self.rest = self.rest.get(end + 1..).unwrap_or(&[]);
            self.line += 1;
            let words: Vec<&[u8]> = text
                .split(|b| b.is_ascii_whitespace())
                .filter(|w| !w.is_empty())
                .collect();
            if !words.is_empty() {
                return Some((self.line, text, words));
            }
        }
        None
    }
}

/// Whether `word` is `keyword` in any case.
fn is(word: Option<&&[u8]>, keyword: &str) -> bool {
    word.is_some_and(|w| w.eq_ignore_ascii_case(keyword.as_bytes()))
}

/// Whether the first non-blank word of `bytes` (after a byte-order mark) is `solid`, in any
/// case, and the next line's first word is `facet` or `endsolid` (or there is no next line,
/// and the first ends with a line break and holds no control character): the shape of an
/// ASCII STL, which a binary file whose free-text header says `solid` does not have.
pub(super) fn looks_ascii(bytes: &[u8]) -> bool {
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let mut lines = Lines {
        rest: text,
        line: 0,
    };
    let Some((_, first_line, first)) = lines.next_line() else {
        return false;
    };
    if !is(first.first(), "solid") {
        return false;
    }
    match lines.next_line() {
        Some((_, _, words)) => is(words.first(), "facet") || is(words.first(), "endsolid"),
        // One line only: a text line that ends (an empty solid), or else the start of a
        // binary header, cut before its line break or with none.
        None => {
            text.contains(&b'\n')
                && first_line
                    .iter()
                    .all(|&b| b >= 0x20 || b"\t\r\x0c".contains(&b))
        }
    }
}

/// An error at `line`.
fn at(file: &str, line: usize, what: String) -> MeshError {
    MeshError::Parse {
        file: file.to_owned(),
        line,
        what,
    }
}

/// The corners of every facet of every solid in an ASCII STL, three per triangle, and the
/// warnings (a last solid without `endsolid`).
pub(super) fn parse(bytes: &[u8], file: &str) -> Result<(Vec<Vec3>, Vec<String>), MeshError> {
    if let Some(line) = long_line(bytes, MAX_LINE_BYTES) {
        return Err(at(file, line, long_line_message()));
    }
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let mut lines = Lines {
        rest: text,
        line: 0,
    };
    let mut corners = Vec::new();
    let mut warnings = Vec::new();
    let mut facet = 0usize;
    while let Some((line, text, words)) = lines.next_line() {
        if !is(words.first(), "solid") {
            return Err(at(
                file,
                line,
                format!(
                    "expected `solid`, found '{}'",
                    quote_bytes(text.trim_ascii(), QUOTED)
                ),
            ));
        }
        // Facets until `endsolid`.
        loop {
            let Some((line, text, words)) = lines.next_line() else {
                warnings.push(format!(
                    "{file}: the last solid has no `endsolid` line; its {facet} facets are read"
                ));
                break;
            };
            if is(words.first(), "endsolid") {
                break;
            }
            if !is(words.first(), "facet") {
                return Err(at(
                    file,
                    line,
                    format!(
                        "facet {}: expected `facet` or `endsolid`, found '{}'",
                        facet + 1,
                        quote_bytes(text.trim_ascii(), QUOTED)
                    ),
                ));
            }
            facet += 1;
            read_facet(&mut lines, file, facet, &mut corners)?;
        }
    }
    if corners.is_empty() {
        return Err(MeshError::NoFaces {
            file: file.to_owned(),
        });
    }
    Ok((corners, warnings))
}

/// The next non-blank line of facet `facet`, which must start with the words of `what` (in
/// any case): its number and words.
fn expect<'a>(
    lines: &mut Lines<'a>,
    file: &str,
    facet: usize,
    what: &str,
) -> Result<(usize, Vec<&'a [u8]>), MeshError> {
    let Some((line, text, words)) = lines.next_line() else {
        return Err(at(
            file,
            lines.line,
            format!("facet {facet}: the file ends before `{what}` (truncated)"),
        ));
    };
    let keywords: Vec<&str> = what.split(' ').collect();
    let matches = keywords.len() <= words.len()
        && keywords
            .iter()
            .zip(&words)
            .all(|(k, w)| w.eq_ignore_ascii_case(k.as_bytes()));
    if !matches {
        return Err(at(
            file,
            line,
            format!(
                "facet {facet}: expected `{what}`, found '{}'",
                quote_bytes(text.trim_ascii(), QUOTED)
            ),
        ));
    }
    Ok((line, words))
}

/// The body of facet number `facet` after its `facet` line: `outer loop`, three vertices,
/// `endloop`, `endfacet`.
fn read_facet(
    lines: &mut Lines<'_>,
    file: &str,
    facet: usize,
    corners: &mut Vec<Vec3>,
) -> Result<(), MeshError> {
    expect(lines, file, facet, "outer loop")?;
    for k in 1..=3 {
        let (line, words) = expect(lines, file, facet, "vertex")?;
        let mut p = [0.0f32; 3];
        if words.len() != 4 {
            return Err(at(
                file,
                line,
                format!(
                    "facet {facet}: vertex {k}: expected 3 numbers, found {}",
                    words.len() - 1
                ),
            ));
        }
        for (c, word) in p.iter_mut().zip(&words[1..]) {
            let value = std::str::from_utf8(word)
                .ok()
                .and_then(|w| w.parse::<f32>().ok());
            *c = match value {
                Some(v) if v.is_finite() => v,
                Some(_) => {
                    return Err(at(
                        file,
                        line,
                        format!(
                            "facet {facet}: vertex {k}: NaN or infinite coordinate '{}'",
                            quote_bytes(word, QUOTED)
                        ),
                    ));
                }
                None => {
                    return Err(at(
                        file,
                        line,
                        format!(
                            "facet {facet}: vertex {k}: '{}' is not a number",
                            quote_bytes(word, QUOTED)
                        ),
                    ));
                }
            };
        }
        corners.push(Vec3::from_array(p));
    }
    expect(lines, file, facet, "endloop")?;
    expect(lines, file, facet, "endfacet")?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const FACET: &str = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                         vertex 0 1 0\nendloop\nendfacet\n";

    #[test]
    fn every_solid_is_read() {
        let text = format!("solid a\n{FACET}endsolid a\nsolid b\n{FACET}{FACET}endsolid b\n");
        let (corners, warnings) = parse(text.as_bytes(), "t.stl").expect("reads");
        assert_eq!(corners.len(), 9);
        assert!(warnings.is_empty());
    }

    #[test]
    fn shape_tells_ascii_from_a_binary_header_that_says_solid() {
        assert!(looks_ascii(format!("SOLID x\n{FACET}").as_bytes()));
        assert!(looks_ascii(b"\n\n  solid\nendsolid\n"));
        assert!(!looks_ascii(
            b"solid exported by CAD\0\0\0\x01\x02\x03\n\x7f\x00"
        ));
        assert!(!looks_ascii(b"facet"));
    }

    #[test]
    fn a_missing_endsolid_at_the_end_is_a_warning() {
        let text = format!("solid a\n{FACET}");
        let (corners, warnings) = parse(text.as_bytes(), "t.stl").expect("reads");
        assert_eq!(corners.len(), 3);
        assert_eq!(warnings.len(), 1);
    }
}
