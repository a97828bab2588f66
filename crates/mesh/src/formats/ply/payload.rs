//! The PLY payload, one element at a time, with the place of each for messages.

use ply_rs_bw::parser::{ParseError, Parser};
use ply_rs_bw::ply::{ElementDef, Encoding, PropertyAccess};

use super::super::{element_error, one_line};
use crate::error::MeshError;
use crate::open::{MAX_LINE_BYTES, long_line, long_line_message};

/// Where the reader is, for messages: the element (`face 7 of 40`, named only when an error
/// needs it: a label per element would cost more than reading it), and its line in an ASCII
/// file.
pub(super) struct Place<'a> {
    def: &'a ElementDef,
    index: usize,
    line: Option<usize>,
}

impl Place<'_> {
    pub(super) fn error(&self, file: &str, what: impl Into<String>) -> MeshError {
        let element = format!("{} {} of {}", self.def.name, self.index + 1, self.def.count);
        match self.line {
            Some(line) => MeshError::Parse {
                file: file.to_owned(),
                line,
                what: format!("{element}: {}", what.into()),
            },
            None => element_error(file, element, what),
        }
    }
}

/// The crate's message without its own `Line N: ` prefix (this module names the place).
pub(super) fn message(e: &ParseError) -> String {
    let text = e.to_string();
    let text = match e.line() {
        Some(line) => text
            .strip_prefix(&format!("Line {line}: "))
            .map(str::to_owned)
            .unwrap_or_else(|| text.clone()),
        None => text,
    };
    super::words::plain(&one_line(&text))
}

/// At most 40 characters of `text` (and a `...` marking a cut), control characters
/// escaped, for messages.
pub(super) fn clip(text: &str) -> String {
    crate::sanitize::quote(text, 43)
}

/// Reads elements of one definition, one at a time, from the payload that `rest` holds.
pub(super) struct Payload<'a> {
    rest: &'a [u8],
    encoding: Encoding,
    /// 1-based line of the next ASCII line.
    line: usize,
}

impl<'a> Payload<'a> {
    /// The payload `rest` after a header of `header_lines` lines. An ASCII payload with a line
    /// over [`MAX_LINE_BYTES`] is refused first, by that line's number: the crate splits a
    /// line into words, so a line is bounded before it is read.
    pub(super) fn new(
        rest: &'a [u8],
        encoding: Encoding,
        header_lines: usize,
        file: &str,
    ) -> Result<Self, MeshError> {
        if encoding == Encoding::Ascii
            && let Some(k) = long_line(rest, MAX_LINE_BYTES)
        {
            return Err(MeshError::Parse {
                file: file.to_owned(),
                line: header_lines + k,
                what: long_line_message(),
            });
        }
        Ok(Payload {
            rest,
            encoding,
            line: header_lines + 1,
        })
    }

    /// Element `index` of `def`, and where it was.
    pub(super) fn read<'d, E: PropertyAccess>(
        &mut self,
        parser: &Parser<E>,
        def: &'d ElementDef,
        index: usize,
        file: &str,
    ) -> Result<(E, Place<'d>), MeshError> {
        match self.encoding {
            Encoding::Ascii => {
                // Blank lines between elements are tolerated (some writers end with one).
                loop {
                    let Some(end) = self.rest.iter().position(|&b| b == b'\n') else {
                        if self.rest.iter().all(u8::is_ascii_whitespace) {
                            let place = Place {
                                def,
                                index,
                                line: Some(self.line),
                            };
                            return Err(place.error(file, "the file ends before it (truncated)"));
                        }
                        break;
                    };
                    if self.rest[..end].iter().all(u8::is_ascii_whitespace) {
                        self.rest = &self.rest[end + 1..];
                        self.line += 1;
                    } else {
                        break;
                    }
                }
                let end = self
                    .rest
                    .iter()
                    .position(|&b| b == b'\n')
                    .map_or(self.rest.len(), |e| e + 1);
                let (raw, rest) = self.rest.split_at(end);
                self.rest = rest;
                let place = Place {
                    def,
                    index,
                    line: Some(self.line),
                };
                self.line += 1;
                let text =
                    std::str::from_utf8(raw).map_err(|_| place.error(file, "not valid UTF-8"))?;
                let value = parser.read_ascii_element(text, def).map_err(|e| {
                    let why = message(&e);
                    // The crate quotes the line inside a nested message; keep its last reason.
                    let why = why.rsplit("Error: ").next().unwrap_or(&why).trim();
                    place.error(file, format!("cannot read '{}': {why}", clip(text.trim())))
                })?;
                Ok((value, place))
            }
            Encoding::BinaryLittleEndian | Encoding::BinaryBigEndian => {
                let place = Place {
                    def,
                    index,
                    line: None,
                };
                let value = if self.encoding == Encoding::BinaryLittleEndian {
                    parser.read_little_endian_element(&mut self.rest, def)
                } else {
                    parser.read_big_endian_element(&mut self.rest, def)
                };
                let value = value.map_err(|e| {
                    if e.kind() == std::io::ErrorKind::UnexpectedEof {
                        place.error(file, "the file ends inside it (truncated)")
                    } else {
                        place.error(file, message(&e))
                    }
                })?;
                Ok((value, place))
            }
        }
    }
}
