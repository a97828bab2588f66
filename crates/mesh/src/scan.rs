//! The light second pass over the OBJ text.
//!
//! tobj parses the geometry but drops smoothing groups (`s N`, `s off`) and reports errors without
//! a line number (docs/conventions.md, "Dependency facts"). This scan reads each line once,
//! validates what tobj would parse (numbers, indices) so that an error can name its line, and
//! records for every polygon (an `f` or `l` line with three or more vertices, the ones tobj keeps
//! with `ignore_points` and `ignore_lines`) its line and smoothing group, in file order. It is
//! deliberately stricter than tobj: whatever it accepts, tobj accepts.

use crate::error::MeshError;

/// One polygon as the scan saw it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ScannedFace {
    /// 1-based line of the `f`/`l` statement.
    pub line: usize,
    /// Smoothing group in effect (0 = off or none).
    pub group: u32,
}

/// What the scan learned about the file.
#[derive(Debug, Default)]
pub(crate) struct Scan {
    /// Polygons in file order.
    pub faces: Vec<ScannedFace>,
    /// The file has at least one `s` line.
    pub has_smoothing_groups: bool,
    /// Every polygon corner names a `vt`.
    pub all_corners_have_uv: bool,
    /// Every polygon corner names a `vn`.
    pub all_corners_have_normal: bool,
    /// `usemtl` names with their lines, to warn about undefined materials.
    pub usemtl: Vec<(usize, String)>,
    /// The file has a `mtllib` line.
    pub has_mtllib: bool,
    /// `f` statements with fewer than 3 corners, which tobj drops: (line, corners).
    pub short_faces: Vec<(usize, usize)>,
    /// Every `v` line has a colour (`v x y z r g b`); the scan refuses colours on some only.
    pub has_vertex_colors: bool,
}

struct Counts {
    v: usize,
    vt: usize,
    vn: usize,
    colored: Option<bool>,
}

fn err(file: &str, line: usize, what: impl Into<String>) -> MeshError {
    MeshError::Parse {
        file: file.to_owned(),
        line,
        what: what.into(),
    }
}

/// Parses `n` finite numbers from `words`.
fn numbers<'a>(
    words: &mut impl Iterator<Item = &'a str>,
    n: usize,
    what: &str,
    file: &str,
    line: usize,
) -> Result<Vec<f32>, MeshError> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let Some(w) = words.next() else {
            return Err(err(
                file,
                line,
                format!("{what}: expected {n} numbers, found {i}"),
            ));
        };
        let x: f32 = w.parse().map_err(|_| {
            err(
                file,
                line,
                format!("{what}: malformed number '{}'", clip(w)),
            )
        })?;
        if !x.is_finite() {
            return Err(err(
                file,
                line,
                format!("{what}: NaN or infinite value '{}'", clip(w)),
            ));
        }
        out.push(x);
    }
    Ok(out)
}

/// At most 32 characters of user text in a message, control characters escaped.
fn clip(s: &str) -> String {
    crate::sanitize::quote(s, 32)
}

/// Resolves one 1-based (or negative, relative) index against `count` elements seen so far.
fn index(token: &str, count: usize, kind: &str, file: &str, line: usize) -> Result<(), MeshError> {
    let x: isize = token.parse().map_err(|_| {
        err(
            file,
            line,
            format!("malformed {kind} index '{}'", clip(token)),
        )
    })?;
    if x == 0 {
        return Err(err(
            file,
            line,
            format!("{kind} index 0 (OBJ indices start at 1)"),
        ));
    }
    // Positive: 1..=count; negative: -1 is the last one defined, so -count..=-1.
    if x.unsigned_abs() > count {
        return Err(err(
            file,
            line,
            format!("{kind} index {x} out of range ({count} defined so far)"),
        ));
    }
    Ok(())
}

fn vertex_line<'a>(
    words: &mut impl Iterator<Item = &'a str>,
    counts: &mut Counts,
    file: &str,
    line: usize,
) -> Result<(), MeshError> {
    let xyz = numbers(words, 3, "vertex", file, line)?;
    let rest: Vec<&str> = words.collect();
    let colored = match rest.len() {
        0 => false,
        1 => {
            let w = numbers(&mut rest.iter().copied(), 1, "vertex w", file, line)?[0];
            if w == 0.0 {
                return Err(err(file, line, "vertex w is 0"));
            }
            if xyz.iter().any(|c| !(c / w).is_finite()) {
                return Err(err(
                    file,
                    line,
                    "vertex: coordinate divided by w is infinite",
                ));
            }
            false
        }
        3 => {
            numbers(&mut rest.iter().copied(), 3, "vertex colour", file, line)?;
            true
        }
        n => {
            return Err(err(
                file,
                line,
                format!("vertex: {} values (expected 3, 4 or 6)", n + 3),
            ));
        }
    };
    // tobj indexes colours by vertex index: colours on some vertices only would misalign them.
    match counts.colored {
        Some(c) if c != colored => {
            return Err(err(
                file,
                line,
                "vertex colours on some vertices but not all",
            ));
        }
        _ => counts.colored = Some(colored),
    }
    counts.v += 1;
    Ok(())
}

/// Validates a face line; returns (corners, all have uv, all have normal).
fn face_line<'a>(
    words: impl Iterator<Item = &'a str>,
    counts: &Counts,
    file: &str,
    line: usize,
) -> Result<(usize, bool, bool), MeshError> {
    let (mut n, mut uv, mut nrm) = (0, true, true);
    for word in words {
        let parts: Vec<&str> = word.split('/').collect();
        if parts.len() > 3 {
            return Err(err(
                file,
                line,
                format!("face corner '{}' has more than 3 indices", clip(word)),
            ));
        }
        match parts.first() {
            Some(p) if !p.is_empty() => index(p, counts.v, "vertex", file, line)?,
            _ => {
                return Err(err(
                    file,
                    line,
                    format!("face corner '{}' has no vertex index", clip(word)),
                ));
            }
        }
        match parts.get(1) {
            Some(t) if !t.is_empty() => index(t, counts.vt, "texture", file, line)?,
            _ => uv = false,
        }
        match parts.get(2) {
            Some(t) if !t.is_empty() => index(t, counts.vn, "normal", file, line)?,
            _ => nrm = false,
        }
        n += 1;
    }
    if n == 0 {
        return Err(err(file, line, "face with no vertices"));
    }
    Ok((n, uv, nrm))
}

/// Scans `text` (the OBJ file `file`); see the module docs.
pub(crate) fn scan(text: &str, file: &str) -> Result<Scan, MeshError> {
    let mut out = Scan {
        all_corners_have_uv: true,
        all_corners_have_normal: true,
        ..Scan::default()
    };
    let mut counts = Counts {
        v: 0,
        vt: 0,
        vn: 0,
        colored: None,
    };
    let mut group = 0u32;
    for (i, text_line) in text.lines().enumerate() {
        let line = i + 1;
        // tobj copies every line and splits it into words: a line is bounded first.
        if text_line.len() > crate::open::MAX_LINE_BYTES {
            return Err(err(file, line, crate::open::long_line_message()));
        }
        let mut words = text_line.split_whitespace();
        match words.next() {
            Some("v") => vertex_line(&mut words, &mut counts, file, line)?,
            Some("vt") => {
                numbers(&mut words, 2, "texture coordinate", file, line)?;
                counts.vt += 1;
            }
            Some("vn") => {
                numbers(&mut words, 3, "normal", file, line)?;
                counts.vn += 1;
            }
            Some(kind @ ("f" | "l")) => {
                let (n, uv, nrm) = face_line(words, &counts, file, line)?;
                // Fewer than 3 corners is a point or a line: tobj drops it, so do we, and an
                // `f` that says face but is not one gets a warning.
                if n < 3 && kind == "f" {
                    out.short_faces.push((line, n));
                }
                if n >= 3 {
                    out.faces.push(ScannedFace { line, group });
                    out.all_corners_have_uv &= uv;
                    out.all_corners_have_normal &= nrm;
                }
            }
            Some("s") => {
                out.has_smoothing_groups = true;
                group = match words.next() {
                    Some("off") | None => 0,
                    Some(w) => w.parse().map_err(|_| {
                        err(
                            file,
                            line,
                            format!("malformed smoothing group '{}'", clip(w)),
                        )
                    })?,
                };
            }
            Some("usemtl") => {
                if words.next().is_none() {
                    return Err(err(file, line, "usemtl without a material name"));
                }
                let name = text_line
                    .trim()
                    .split_once(' ')
                    .map_or("", |(_, n)| n.trim());
                out.usemtl.push((line, name.to_owned()));
            }
            Some("mtllib") => out.has_mtllib = true,
            _ => {}
        }
    }
    out.has_vertex_colors = counts.colored == Some(true);
    if out.faces.is_empty() {
        out.all_corners_have_uv = false;
        out.all_corners_have_normal = false;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smoothing_groups_follow_faces_in_file_order() {
        let s = scan(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\ns 1\nf 1 2 3\ns off\nf 1 2 3\nl 1 2\ns 2\nf 1 2 3\n",
            "t.obj",
        )
        .expect("valid");
        let groups: Vec<u32> = s.faces.iter().map(|f| f.group).collect();
        assert_eq!(groups, vec![1, 0, 2]);
        assert!(s.has_smoothing_groups);
        assert_eq!(s.faces[2].line, 10);
    }

    #[test]
    fn relative_indices_are_resolved_against_what_precedes() {
        assert!(scan("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n", "t").is_ok());
        assert_eq!(
            scan("v 0 0 0\nv 1 0 0\nf -3 -2 -1\n", "t")
                .map_err(|e| e.line())
                .err(),
            Some(Some(3))
        );
    }
}
