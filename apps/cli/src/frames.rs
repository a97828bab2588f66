//! Frame sequences for `render`: the turntable (`--turntable N`: frame `k` is the scene's
//! camera turned by `360 * k / N` degrees about its up axis, through its target), the subset
//! of it one process renders (`--frames`), the numbered output names (`-o out/frame_%04d.png`)
//! and standard output (`-o -`, one PNG frame).
//!
//! `--frames` takes `A..B` (half-open: A, A+1, ..., B-1, as Rust and Python count, so that
//! `0..50` and `50..100` split 100 frames without overlap), `A..=B` (inclusive) or `K` (the
//! one frame K). Files are named by the frame number within the whole turntable, so the same
//! frame gets the same name whichever process renders it.

use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::CliError;

/// Frames `start..end` (half-open) of a turntable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRange {
    /// First frame.
    pub start: u32,
    /// One past the last frame.
    pub end: u32,
    /// Whether it was written `A..=B` (for messages).
    inclusive: bool,
}

impl std::fmt::Display for FrameRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.inclusive && self.end == self.start.saturating_add(1) {
            write!(f, "{}", self.start)
        } else if self.inclusive {
            write!(f, "{}..={}", self.start, self.end.saturating_sub(1))
        } else {
            write!(f, "{}..{}", self.start, self.end)
        }
    }
}

/// Parses `--frames`: `A..B` (half-open), `A..=B` (inclusive) or `K`; never empty.
///
/// # Errors
/// A message saying which forms are understood.
pub fn parse_frame_range(text: &str) -> Result<FrameRange, String> {
    let number = |s: &str| -> Result<u32, String> {
        s.trim().parse::<u32>().map_err(|_| {
            format!("expected A..B (half-open), A..=B (inclusive) or K, with whole numbers >= 0, got `{text}`")
        })
    };
    let range = if let Some((a, b)) = text.split_once("..=") {
        let (start, last) = (number(a)?, number(b)?);
        let end = last
            .checked_add(1)
            .ok_or_else(|| format!("`{text}`: frame number too large"))?;
        FrameRange {
            start,
            end,
            inclusive: true,
        }
    } else if let Some((a, b)) = text.split_once("..") {
        FrameRange {
            start: number(a)?,
            end: number(b)?,
            inclusive: false,
        }
    } else {
        let k = number(text)?;
        FrameRange {
            start: k,
            end: k
                .checked_add(1)
                .ok_or_else(|| format!("`{text}`: frame number too large"))?,
            inclusive: true,
        }
    };
    if range.start >= range.end {
        return Err(format!("`{text}` holds no frame"));
    }
    Ok(range)
}

/// The frames one run renders: all of a turntable, a range of it, or the one still frame.
/// A range, never a list: `--turntable 4294967295` is counted, not allocated, so that a usage
/// error about it is immediate.
///
/// # Errors
/// A range reaching past the turntable (usage).
pub fn frames_to_render(
    turntable: Option<u32>,
    range: Option<FrameRange>,
) -> Result<Range<u32>, CliError> {
    match (turntable, range) {
        (None, Some(r)) => Err(CliError::Usage(format!(
            "--frames {r}: picks frames of a turntable; add --turntable N (e.g. --turntable 36 --frames {r}), or --fps F for an animation"
        ))),
        (None, None) => Ok(0..1),
        (Some(n), None) => Ok(0..n),
        (Some(n), Some(r)) => {
            if r.end > n {
                return Err(CliError::Usage(format!(
                    "--frames {r}: out of range: --turntable {n} has frames 0..{n} (0..={})",
                    n - 1
                )));
            }
            Ok(r.start..r.end)
        }
    }
}

/// The frames of an animation sequence (`--fps F --frames A..B`): exactly the range, which
/// has no end of its own to check against.
///
/// # Errors
/// `--fps` without `--frames` (usage).
pub fn animation_frames(fps: f64, range: Option<FrameRange>) -> Result<Range<u32>, CliError> {
    range.map(|r| r.start..r.end).ok_or_else(|| {
        CliError::Usage(format!(
            "--fps {fps}: say which frames with --frames A..B (e.g. --fps {fps} --frames 0..48)"
        ))
    })
}

/// An output name with at most one frame number in it (`%d` or `%0Nd`, printf-style; `%%` is
/// a literal `%`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputPattern {
    /// The name as given.
    given: PathBuf,
    /// Text before the number, text after it, and the zero-padded width (0 = as is); `None`
    /// when the name has no number (then `given` is the file, `%%` still unescaped).
    parts: Option<(String, String, usize)>,
    /// The name with `%%` unescaped, when it has no number.
    plain: PathBuf,
}

impl OutputPattern {
    /// Parses `path`. A name that is not UTF-8 is taken as it is (it cannot hold a pattern).
    ///
    /// # Errors
    /// A `%` that is not `%d`, `%0Nd` or `%%`, or two frame numbers (usage).
    pub fn parse(path: &Path) -> Result<OutputPattern, CliError> {
        let Some(text) = path.to_str() else {
            return Ok(OutputPattern {
                given: path.to_path_buf(),
                parts: None,
                plain: path.to_path_buf(),
            });
        };
        let bad = |what: &str| {
            CliError::Usage(format!(
                "-o {text}: {what} (a frame number is written %d or %0Nd, e.g. %04d; a literal % is %%)"
            ))
        };
        let mut before = String::new();
        let mut after = String::new();
        let mut width: Option<usize> = None;
        let mut chars = text.chars().peekable();
        while let Some(c) = chars.next() {
            let out = if width.is_some() {
                &mut after
            } else {
                &mut before
            };
            if c != '%' {
                out.push(c);
                continue;
            }
            if chars.peek() == Some(&'%') {
                chars.next();
                out.push('%');
                continue;
            }
            let mut digits = String::new();
            while let Some(d) = chars.peek().copied().filter(char::is_ascii_digit) {
                digits.push(d);
                chars.next();
            }
            if chars.next() != Some('d') {
                return Err(bad("a `%` that is not %d, %0Nd or %%"));
            }
            let w = match digits.as_str() {
                "" => 0,
                d if d.starts_with('0') && d.len() > 1 => d[1..]
                    .parse::<usize>()
                    .ok()
                    .filter(|w| *w <= 10)
                    .ok_or_else(|| bad("the width of %0Nd must be 1 to 10"))?,
                _ => return Err(bad("a width without a leading 0 (write %04d, not %4d)")),
            };
            if width.replace(w).is_some() {
                return Err(bad("more than one frame number"));
            }
        }
        let plain = PathBuf::from(&before);
        Ok(OutputPattern {
            given: path.to_path_buf(),
            parts: width.map(|w| (before, after, w)),
            plain,
        })
    }

    /// Whether the name holds a frame number.
    #[must_use]
    pub fn is_numbered(&self) -> bool {
        self.parts.is_some()
    }

    /// The name as given, for messages.
    #[must_use]
    pub fn given(&self) -> &Path {
        &self.given
    }

    /// The file of frame `frame`.
    #[must_use]
    pub fn path(&self, frame: u32) -> PathBuf {
        match &self.parts {
            Some((before, after, width)) => {
                PathBuf::from(format!("{before}{frame:0width$}{after}"))
            }
            None => self.plain.clone(),
        }
    }
}

/// Where `render` writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Output {
    /// Nothing (`--plan` alone).
    None,
    /// One PNG on standard output (`-o -`).
    Stdout,
    /// Files, one per frame.
    Files(OutputPattern),
}

/// Checks the output against the frames to write: `-o -` takes one PNG frame, no `--plan`
/// (whose text would mix with the image) and no terminal (`stdout_is_terminal`: a picture's
/// bytes would scramble it); several frames need a numbered name.
///
/// # Errors
/// The combination that cannot work (usage).
pub fn output_for(
    out: Option<&Path>,
    frames: usize,
    plan: bool,
    stdout_is_terminal: bool,
) -> Result<Output, CliError> {
    let Some(out) = out else {
        return Ok(Output::None);
    };
    if out.as_os_str() == "-" {
        if stdout_is_terminal {
            return Err(CliError::Usage(
                "-o -: standard output is a terminal; send the PNG to a file or a program (`-o - > out.png`, `-o - | display`)"
                    .to_owned(),
            ));
        }
        if frames > 1 {
            return Err(CliError::Usage(format!(
                "-o -: standard output takes one frame, {frames} were asked for (use --frames K, or a numbered file name)"
            )));
        }
        if plan {
            return Err(CliError::Usage(
                "-o -: cannot be combined with --plan (both would go to standard output)"
                    .to_owned(),
            ));
        }
        return Ok(Output::Stdout);
    }
    let pattern = OutputPattern::parse(out)?;
    if frames > 1 && !pattern.is_numbered() {
        return Err(CliError::Usage(format!(
            "-o {}: {frames} frames are written: the name needs a frame number, e.g. frame_%04d.png",
            out.display()
        )));
    }
    Ok(Output::Files(pattern))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    fn range(text: &str) -> (u32, u32) {
        let r = parse_frame_range(text).unwrap();
        (r.start, r.end)
    }

    #[test]
    fn frame_ranges_are_half_open_inclusive_or_single() {
        assert_eq!(range("0..50"), (0, 50));
        assert_eq!(range("50..=99"), (50, 100));
        assert_eq!(range("7"), (7, 8));
        assert_eq!(range(" 3 .. 5"), (3, 5));
        for bad in ["", "5..5", "6..3", "a..b", "-1..3", "1..2..3", "..4", "3.."] {
            assert!(parse_frame_range(bad).is_err(), "{bad}");
        }
        assert!(parse_frame_range("4294967295..=4294967295").is_err());
    }

    #[test]
    fn frames_must_lie_within_the_turntable() {
        let r = |t| parse_frame_range(t).unwrap();
        assert_eq!(frames_to_render(None, None).unwrap(), 0..1);
        let e = frames_to_render(None, Some(r("2"))).unwrap_err();
        assert_eq!(
            e.to_string(),
            "--frames 2: picks frames of a turntable; add --turntable N (e.g. --turntable 36 --frames 2), or --fps F for an animation"
        );
        assert_eq!(e.exit_code(), 2);
        assert_eq!(frames_to_render(Some(3), None).unwrap(), 0..3);
        assert_eq!(frames_to_render(Some(8), Some(r("6..8"))).unwrap(), 6..8);
        assert_eq!(frames_to_render(Some(8), Some(r("7"))).unwrap(), 7..8);
        let e = frames_to_render(Some(8), Some(r("6..=8"))).unwrap_err();
        assert_eq!(
            e.to_string(),
            "--frames 6..=8: out of range: --turntable 8 has frames 0..8 (0..=7)"
        );
        assert_eq!(e.exit_code(), 2);
    }

    #[test]
    fn turntable_of_four_billion_frames_is_counted_not_listed() {
        // A list of them was 16 GB, collected before `-o` was checked.
        let frames = frames_to_render(Some(u32::MAX), None).unwrap();
        assert_eq!(frames.len(), u32::MAX as usize);
        let e = output_for(Some(Path::new("x.png")), frames.len(), false, false).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("4294967295 frames"), "{e}");
    }

    #[test]
    fn patterns_number_frames_printf_style() {
        let p = OutputPattern::parse(Path::new("out/frame_%04d.png")).unwrap();
        assert!(p.is_numbered());
        assert_eq!(p.path(7), PathBuf::from("out/frame_0007.png"));
        assert_eq!(p.path(12345), PathBuf::from("out/frame_12345.png"));
        let p = OutputPattern::parse(Path::new("100%%_%d.png")).unwrap();
        assert_eq!(p.path(3), PathBuf::from("100%_3.png"));
        let p = OutputPattern::parse(Path::new("still%%.png")).unwrap();
        assert!(!p.is_numbered());
        assert_eq!(p.path(3), PathBuf::from("still%.png"));
        for bad in ["a%s.png", "a%4d.png", "a%d%d.png", "a%.png", "a%011d.png"] {
            assert!(OutputPattern::parse(Path::new(bad)).is_err(), "{bad}");
        }
    }

    #[test]
    fn outputs_fit_the_number_of_frames() {
        assert_eq!(output_for(None, 3, true, false).unwrap(), Output::None);
        assert_eq!(
            output_for(Some(Path::new("-")), 1, false, false).unwrap(),
            Output::Stdout
        );
        assert!(output_for(Some(Path::new("-")), 2, false, false).is_err());
        assert!(output_for(Some(Path::new("-")), 1, true, false).is_err());
        assert!(output_for(Some(Path::new("x.png")), 1, false, false).is_ok());
        let e = output_for(Some(Path::new("x.png")), 2, false, false).unwrap_err();
        assert!(e.to_string().contains("%04d"), "{e}");
        assert!(output_for(Some(Path::new("x%03d.png")), 2, false, false).is_ok());
    }

    #[test]
    fn standard_output_on_a_terminal_is_refused_and_files_are_not_affected() {
        let e = output_for(Some(Path::new("-")), 1, false, true).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("-o -: standard output is a terminal;"),
            "{e}"
        );
        assert_eq!(e.exit_code(), 2);
        assert!(output_for(Some(Path::new("x.png")), 1, false, true).is_ok());
    }
}
