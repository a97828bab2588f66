//! Lines for the terminal whose loss is never silent: a write to stdout or stderr that fails
//! (a full disk behind `>`, a closed pipe, a revoked terminal) ends the process with exit
//! status 1, with a message on stderr when stderr still works, and never with a panic or 0.
//!
//! Also the shapes of those lines: warnings are one line of at most [`WARNING_CHARS`]
//! characters, and every line is one line, its control characters shown, not obeyed.

use std::io::{self, Write};

/// Exit status when stdout or stderr cannot be written.
pub const STREAM_FAILURE_EXIT: i32 = 1;

/// Longest warning line, in characters, `warning: ` included: a warning quoting a long name
/// or a whole file must not flood the terminal.
pub const WARNING_CHARS: usize = 200;

/// Writes `line` and a newline to stdout, flushed. On failure: an `error: stdout: ...` line on
/// stderr (if it can be written) and exit status 1.
pub fn say(line: &str) {
    let line = visible(line, &['\n', '\t']);
    let mut out = io::stdout().lock();
    let result = out
        .write_all(line.as_bytes())
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush());
    if let Err(e) = result {
        stdout_failed(&e);
    }
}

/// Flushes stdout at the end of a command; on failure as [`say`].
pub fn finish_stdout() {
    if let Err(e) = io::stdout().flush() {
        stdout_failed(&e);
    }
}

fn stdout_failed(e: &io::Error) -> ! {
    let _ = writeln!(io::stderr(), "error: stdout: {e}");
    std::process::exit(STREAM_FAILURE_EXIT);
}

/// Writes `text` to stderr as it is (no newline added), flushed. If stderr cannot be written
/// there is nowhere left to report to: exit status 1.
pub fn tell_raw(text: &str) {
    let mut err = io::stderr().lock();
    if err
        .write_all(text.as_bytes())
        .and_then(|()| err.flush())
        .is_err()
    {
        std::process::exit(STREAM_FAILURE_EXIT);
    }
}

/// Writes one line to stderr (newlines inside become spaces); on failure as [`tell_raw`].
pub fn tell(line: &str) {
    tell_raw(&format!("{}\n", one_line(line)));
}

/// Writes a warning to stderr: one line starting `warning: ` (added if missing), cut to
/// [`WARNING_CHARS`] characters; on failure as [`tell_raw`].
pub fn warn(text: &str) {
    tell(&warning_line(text));
}

/// The line [`warn`] writes for `text`.
#[must_use]
pub fn warning_line(text: &str) -> String {
    let line = one_line(text);
    let line = if line.starts_with("warning:") {
        line
    } else {
        format!("warning: {line}")
    };
    cut(&line, WARNING_CHARS)
}

/// `text` on one line: line breaks and tabs become single spaces, and every other control
/// character (and the invisible characters that reorder text) an escape, so that a message
/// quoting a file or a file name cannot clear or recolour the terminal (`ESC[2J` is shown as
/// `\e[2J`).
#[must_use]
pub fn one_line(text: &str) -> String {
    let text = if text.contains(['\n', '\r', '\t']) {
        text.split(['\n', '\r', '\t'])
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect::<Vec<_>>()
            .join(" ")
    } else {
        text.to_owned()
    };
    visible(&text, &[])
}

/// Whether `c` must not reach a terminal as it is: a control character, or a format
/// character that changes the direction or visibility of the text around it.
fn hidden(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}'
        )
}

/// `text` with the characters [`hidden`] refuses, other than those in `keep`, escaped:
/// `\e`, `\0`, `\r`, else `\u{XX}`.
fn visible(text: &str, keep: &[char]) -> String {
    if !text.chars().any(|c| hidden(c) && !keep.contains(&c)) {
        return text.to_owned();
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            c if !hidden(c) || keep.contains(&c) => out.push(c),
            '\u{1b}' => out.push_str("\\e"),
            '\0' => out.push_str("\\0"),
            '\r' => out.push_str("\\r"),
            c => out.push_str(&format!("\\u{{{:x}}}", u32::from(c))),
        }
    }
    out
}

/// `text` cut to at most `chars` characters, the last one `…` when anything was cut.
#[must_use]
pub fn cut(text: &str, chars: usize) -> String {
    match text.char_indices().nth(chars.saturating_sub(1)) {
        Some((at, _)) if text[at..].chars().nth(1).is_some() => format!("{}…", &text[..at]),
        _ => text.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_warnings_are_cut_to_one_line_of_200_characters() {
        let long = format!("a mesh named {}\nand more", "x".repeat(500));
        let line = warning_line(&long);
        assert_eq!(line.chars().count(), WARNING_CHARS);
        assert!(line.starts_with("warning: a mesh named xxx"), "{line}");
        assert!(line.ends_with('…') && !line.contains('\n'));
        assert_eq!(warning_line("warning: short"), "warning: short");
        assert_eq!(warning_line("short"), "warning: short");
    }

    #[test]
    fn terminal_controls_in_lines_are_shown_not_obeyed() {
        assert_eq!(
            one_line("bad \u{1b}[2J\u{1b}[31mname\0\u{202e}"),
            "bad \\e[2J\\e[31mname\\0\\u{202e}"
        );
        assert_eq!(warning_line("x\u{7}"), "warning: x\\u{7}");
        assert_eq!(visible("a\nb\u{1b}", &['\n']), "a\nb\\e");
    }

    #[test]
    fn cutting_respects_character_boundaries() {
        assert_eq!(cut("ééééé", 3), "éé…");
        assert_eq!(cut("ééé", 3), "ééé");
        assert_eq!(cut("", 3), "");
    }
}
