//! Text from a file, made safe to quote in a message.
//!
//! A file is written by whoever made it: a header line holding `ESC[2J` would clear the
//! terminal of the person reading the error, a NUL or a line break would cut or forge a line,
//! a right-to-left override would reorder what follows. So every quote of a file's text in a
//! message goes through [`quote`]: control characters (C0, DEL, C1) and the invisible
//! formatting characters that reorder text become visible escapes (`\e`, `\0`, `\u{202e}`),
//! and the quote is cut to a stated length, the cut marked `...`.

/// Whether `c` must not reach a terminal as it is: control characters, and the format
/// characters that change the direction or visibility of the text around them.
fn hidden(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}' | '\u{feff}'
        )
}

/// The visible form of a character [`hidden`] refuses.
fn escape(c: char, out: &mut String) {
    match c {
        '\n' => out.push_str("\\n"),
        '\r' => out.push_str("\\r"),
        '\t' => out.push_str("\\t"),
        '\0' => out.push_str("\\0"),
        '\u{1b}' => out.push_str("\\e"),
        c => out.push_str(&format!("\\u{{{:x}}}", u32::from(c))),
    }
}

/// `text` with its control and direction characters escaped (see the module documentation),
/// at most `max_chars` characters long (escapes count as what they print), `...` marking a
/// cut.
///
/// ```
/// use phosphor_mesh::sanitize::quote;
///
/// assert_eq!(quote("a\u{1b}[2Jb\0", 40), "a\\e[2Jb\\0");
/// assert_eq!(quote("abcdefgh", 5), "ab...");
/// ```
#[must_use]
pub fn quote(text: &str, max_chars: usize) -> String {
    let mut out = String::new();
    let mut count = 0usize;
    // Byte length of `out` at the last piece boundary within `max_chars - 3` characters: where
    // a cut goes, so that no escape is split.
    let mut cut_at = 0usize;
    let mut piece = String::new();
    for c in text.chars() {
        piece.clear();
        if hidden(c) {
            escape(c, &mut piece);
        } else {
            piece.push(c);
        }
        count += piece.chars().count();
        if count > max_chars {
            out.truncate(cut_at);
            out.push_str(&"..."[..max_chars.min(3)]);
            return out;
        }
        out.push_str(&piece);
        if count + 3 <= max_chars {
            cut_at = out.len();
        }
    }
    out
}

/// [`quote`] of bytes that may not be UTF-8 (a header line of a binary file): invalid
/// sequences become U+FFFD first.
#[must_use]
pub fn quote_bytes(bytes: &[u8], max_chars: usize) -> String {
    quote(&String::from_utf8_lossy(bytes), max_chars)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn terminal_controls_are_escaped() {
        assert_eq!(quote("\u{1b}[2J \u{1b}[31m", 40), "\\e[2J \\e[31m");
        assert_eq!(
            quote("a\u{202e}b\u{7f}\u{9b}", 40),
            "a\\u{202e}b\\u{7f}\\u{9b}"
        );
        assert_eq!(quote("x\ny\r\t", 40), "x\\ny\\r\\t");
        assert_eq!(quote_bytes(b"ok\xff", 40), "ok\u{fffd}");
    }

    #[test]
    fn quotes_are_cut_to_their_length_with_a_marker() {
        assert_eq!(quote("abcdef", 6), "abcdef");
        assert_eq!(quote("abcdefg", 6), "abc...");
        assert_eq!(quote(&"é".repeat(100), 10).chars().count(), 10);
        // An escape is not split by the cut.
        let q = quote(&"\0".repeat(100), 10);
        assert_eq!(q, "\\0\\0\\0...");
        assert!(quote(&"x".repeat(10_000), 200).chars().count() <= 200);
        assert_eq!(quote("", 5), "");
    }
}
