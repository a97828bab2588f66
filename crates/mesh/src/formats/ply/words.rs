//! `ply-rs-bw`'s messages in words, and the header checked before the crate reads it.
//!
//! The crate's messages carry Rust debug text (`ParseIntError { kind: InvalidDigit }`,
//! `Scalar(Float)`, a grammar's expected-token set) and its own line breaks; a person reading
//! `error: ...` wants what is wrong with the file. [`plain`] turns each message the crate
//! writes into one clause; one it does not know loses its debug text. The crate also reads
//! each header line whole into a string, so [`check_header`] bounds them first.

use crate::error::MeshError;
use crate::open::{MAX_LINE_BYTES, long_line_message};
use crate::sanitize::quote;

/// Most bytes a header may take before `end_header`: headers are a few hundred bytes, and a
/// file without one must not be read line by line to its end.
pub(super) const MAX_HEADER_BYTES: usize = 1 << 20;

/// Checks that the header ends (`end_header`) within [`MAX_HEADER_BYTES`] and that no header
/// line is longer than [`MAX_LINE_BYTES`], before the crate buffers them.
pub(super) fn check_header(bytes: &[u8], file: &str) -> Result<(), MeshError> {
    let mut rest = bytes;
    let mut line = 1;
    loop {
        let window = &rest[..rest.len().min(MAX_LINE_BYTES + 1)];
        let Some(end) = window.iter().position(|&b| b == b'\n') else {
            if rest.len() > MAX_LINE_BYTES {
                return Err(header_error(file, line, long_line_message()));
            }
            return Ok(()); // the last line: the crate reports what is missing
        };
        if rest[..end].trim_ascii() == b"end_header" {
            return Ok(());
        }
        rest = &rest[end + 1..];
        line += 1;
        if bytes.len() - rest.len() > MAX_HEADER_BYTES {
            return Err(header_error(
                file,
                line,
                format!(
                    "no `end_header` in the first {} (not a PLY header)",
                    crate::open::limit_text(MAX_HEADER_BYTES as u64)
                ),
            ));
        }
    }
}

fn header_error(file: &str, line: usize, what: String) -> MeshError {
    MeshError::Parse {
        file: file.to_owned(),
        line,
        what: format!("header: {what}"),
    }
}

/// The text between `start` and the next `end` after it.
fn between<'a>(text: &'a str, start: &str, end: &str) -> Option<&'a str> {
    let from = text.find(start)? + start.len();
    let rest = &text[from..];
    Some(&rest[..rest.find(end)?])
}

/// What a standard-library number error says, in words: `kind: InvalidDigit` and the like.
fn number_problem(text: &str) -> &'static str {
    if text.contains("PosOverflow") || text.contains("NegOverflow") {
        "is out of range for its type"
    } else if text.contains("kind: Empty") {
        "is empty"
    } else if text.contains("ParseIntError") {
        "is not a whole number"
    } else {
        "is not a number"
    }
}

/// One of the crate's messages (on one line, without its `Line N:` prefix) as one clause in
/// words, without debug text.
pub(super) fn plain(text: &str) -> String {
    let quoted = |s: &str| quote(s, 40);
    if text.starts_with("Parse error.") {
        let value = between(text, "Value: '", "'").unwrap_or("");
        return format!("'{}' {}", quoted(value), number_problem(text));
    }
    if let Some(index) = between(text, "Couldn't parse element at index ", ":") {
        let k = index.trim().parse::<usize>().map_or(0, |i| i + 1);
        return format!("list value {k} {}", number_problem(text));
    }
    if text.starts_with("Expected element of type") {
        return "the line has fewer values than the element has properties".to_owned();
    }
    if let Some(n) = between(text, "Expected ", " list elements, but found only ") {
        let found = between(text, "found only ", ".").unwrap_or("fewer");
        return format!("the list announces {n} values, the line has {found}");
    }
    if text.starts_with("Couldn't parse element line") {
        return "not a line of numbers".to_owned();
    }
    if text.starts_with("Couldn't parse line") {
        return "not a PLY header line (`format`, `element`, `property`, `comment`, \
                `obj_info` or `end_header`)"
            .to_owned();
    }
    if text.starts_with("Expected magic number") {
        return "not a PLY file: the first line must be `ply`".to_owned();
    }
    if text.starts_with("Unexpected end of file while reading magic number") {
        return "empty file".to_owned();
    }
    if text.starts_with("Unexpected end of file while reading header") {
        return "the file ends inside the header (no `end_header` line)".to_owned();
    }
    if text.starts_with("Found contradicting format definition") {
        return "a second `format` line that differs from the first".to_owned();
    }
    if text.contains("found without preceding element") {
        return "a `property` line before any `element` line".to_owned();
    }
    if let Some(name) = between(text, "PLY property '", "'") {
        return format!(
            "property '{}' has a type this reader cannot use",
            quoted(name)
        );
    }
    if text.starts_with("List length cannot be negative") {
        return "a list length is negative".to_owned();
    }
    if text.starts_with("Index of list must be an integer type") {
        return "a list's length type must be an integer type".to_owned();
    }
    without_debug(text)
}

/// `text` cut before the crate's `; Error:` detail and before a debug structure
/// (`Name { ... }`) in what is left.
fn without_debug(text: &str) -> String {
    let mut end = text.find("; Error:").unwrap_or(text.len());
    if let Some(brace) = text[..end].find(" {") {
        // The structure's name goes too.
        end = text[..brace].rfind(' ').unwrap_or(0);
    }
    let kept = text[..end].trim().trim_end_matches(['.', ',', ';', ':']);
    quote(kept, 160)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_errors_read_as_words() {
        assert_eq!(
            plain("Parse error.; Value: 'x'; Error: ParseFloatError { kind: Invalid },"),
            "'x' is not a number"
        );
        assert_eq!(
            plain("Parse error.; Value: '99999'; Error: ParseIntError { kind: PosOverflow },"),
            "'99999' is out of range for its type"
        );
        assert_eq!(
            plain("Couldn't parse element at index 2: ParseIntError { kind: InvalidDigit }"),
            "list value 3 is not a whole number"
        );
        assert_eq!(
            plain("Expected 4 list elements, but found only 2."),
            "the list announces 4 values, the line has 2"
        );
    }

    #[test]
    fn unknown_messages_lose_their_debug_text() {
        assert_eq!(
            plain("Something odd: Foo { bar: 1 }; Error: Baz"),
            "Something odd"
        );
        assert!(!plain("x\u{1b}[2J { y }").contains('\u{1b}'));
    }

    #[test]
    fn a_header_line_without_a_break_is_refused_by_its_length() {
        let mut bytes = b"ply\nformat ascii 1.0\ncomment ".to_vec();
        bytes.resize(MAX_LINE_BYTES + 100, b'x');
        let e = check_header(&bytes, "t.ply").expect_err("long").to_string();
        assert!(
            e.starts_with("t.ply:3: header: line longer than 1 MiB"),
            "{e}"
        );
        assert!(check_header(b"ply\nend_header\n", "t.ply").is_ok());
    }
}
