//! A tiny built-in 5x7 bitmap font for the labels of the accuracy report's images.
//!
//! Why not a TrueType font through `plotters`: its default text path needs fontconfig and
//! freetype from the system, and the pure-Rust path needs a font file shipped with its licence.
//! Labels of a plot need only ASCII at one or two sizes, so ~70 glyphs of 5x7 pixels (public
//! domain, drawn for Phosphor in the style of the HD44780 character ROM) do the job with no
//! dependency and no file to find at run time.

use crate::rgb8::Rgb8Image;

/// Glyph width in font pixels.
pub const GLYPH_WIDTH: u32 = 5;
/// Glyph height in font pixels.
pub const GLYPH_HEIGHT: u32 = 7;
/// Horizontal advance per character in font pixels (glyph plus one column of space).
pub const ADVANCE: u32 = GLYPH_WIDTH + 1;

/// Rows top to bottom; bit 4 is the leftmost column.
type Glyph = [u8; 7];

const UNKNOWN: Glyph = [
    0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b00000, 0b00100,
];

#[rustfmt::skip]
const PUNCTUATION: [(char, Glyph); 15] = [
    (' ', [0, 0, 0, 0, 0, 0, 0]),
    ('.', [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b01100, 0b01100]),
    (',', [0b00000, 0b00000, 0b00000, 0b00000, 0b01100, 0b00100, 0b01000]),
    ('-', [0b00000, 0b00000, 0b00000, 0b11111, 0b00000, 0b00000, 0b00000]),
    ('+', [0b00000, 0b00100, 0b00100, 0b11111, 0b00100, 0b00100, 0b00000]),
    ('(', [0b00010, 0b00100, 0b01000, 0b01000, 0b01000, 0b00100, 0b00010]),
    (')', [0b01000, 0b00100, 0b00010, 0b00010, 0b00010, 0b00100, 0b01000]),
    ('/', [0b00000, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b00000]),
    (':', [0b00000, 0b01100, 0b01100, 0b00000, 0b01100, 0b01100, 0b00000]),
    ('=', [0b00000, 0b00000, 0b11111, 0b00000, 0b11111, 0b00000, 0b00000]),
    ('_', [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b11111]),
    ('%', [0b11000, 0b11001, 0b00010, 0b00100, 0b01000, 0b10011, 0b00011]),
    ('>', [0b01000, 0b00100, 0b00010, 0b00001, 0b00010, 0b00100, 0b01000]),
    ('|', [0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100]),
    ('?', UNKNOWN),
];

#[rustfmt::skip]
const DIGITS: [Glyph; 10] = [
    [0b01110, 0b10001, 0b10011, 0b10101, 0b11001, 0b10001, 0b01110],
    [0b00100, 0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110],
    [0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b01000, 0b11111],
    [0b11111, 0b00010, 0b00100, 0b00010, 0b00001, 0b10001, 0b01110],
    [0b00010, 0b00110, 0b01010, 0b10010, 0b11111, 0b00010, 0b00010],
    [0b11111, 0b10000, 0b11110, 0b00001, 0b00001, 0b10001, 0b01110],
    [0b00110, 0b01000, 0b10000, 0b11110, 0b10001, 0b10001, 0b01110],
    [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b01000, 0b01000],
    [0b01110, 0b10001, 0b10001, 0b01110, 0b10001, 0b10001, 0b01110],
    [0b01110, 0b10001, 0b10001, 0b01111, 0b00001, 0b00010, 0b01100],
];

#[rustfmt::skip]
const UPPER: [Glyph; 26] = [
    [0b01110, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001], // A
    [0b11110, 0b10001, 0b10001, 0b11110, 0b10001, 0b10001, 0b11110], // B
    [0b01110, 0b10001, 0b10000, 0b10000, 0b10000, 0b10001, 0b01110], // C
    [0b11100, 0b10010, 0b10001, 0b10001, 0b10001, 0b10010, 0b11100], // D
    [0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b11111], // E
    [0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b10000], // F
    [0b01110, 0b10001, 0b10000, 0b10111, 0b10001, 0b10001, 0b01111], // G
    [0b10001, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001], // H
    [0b01110, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110], // I
    [0b00111, 0b00010, 0b00010, 0b00010, 0b00010, 0b10010, 0b01100], // J
    [0b10001, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010, 0b10001], // K
    [0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b11111], // L
    [0b10001, 0b11011, 0b10101, 0b10101, 0b10001, 0b10001, 0b10001], // M
    [0b10001, 0b10001, 0b11001, 0b10101, 0b10011, 0b10001, 0b10001], // N
    [0b01110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110], // O
    [0b11110, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000, 0b10000], // P
    [0b01110, 0b10001, 0b10001, 0b10001, 0b10101, 0b10010, 0b01101], // Q
    [0b11110, 0b10001, 0b10001, 0b11110, 0b10100, 0b10010, 0b10001], // R
    [0b01111, 0b10000, 0b10000, 0b01110, 0b00001, 0b00001, 0b11110], // S
    [0b11111, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100], // T
    [0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110], // U
    [0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100], // V
    [0b10001, 0b10001, 0b10001, 0b10101, 0b10101, 0b10101, 0b01010], // W
    [0b10001, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001, 0b10001], // X
    [0b10001, 0b10001, 0b10001, 0b01010, 0b00100, 0b00100, 0b00100], // Y
    [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b11111], // Z
];

#[rustfmt::skip]
const LOWER: [Glyph; 26] = [
    [0b00000, 0b00000, 0b01110, 0b00001, 0b01111, 0b10001, 0b01111], // a
    [0b10000, 0b10000, 0b10110, 0b11001, 0b10001, 0b10001, 0b11110], // b
    [0b00000, 0b00000, 0b01110, 0b10000, 0b10000, 0b10001, 0b01110], // c
    [0b00001, 0b00001, 0b01101, 0b10011, 0b10001, 0b10001, 0b01111], // d
    [0b00000, 0b00000, 0b01110, 0b10001, 0b11111, 0b10000, 0b01110], // e
    [0b00110, 0b01001, 0b01000, 0b11100, 0b01000, 0b01000, 0b01000], // f
    [0b01111, 0b10001, 0b10001, 0b10011, 0b01101, 0b00001, 0b01110], // g (descends)
    [0b10000, 0b10000, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001], // h
    [0b00100, 0b00000, 0b01100, 0b00100, 0b00100, 0b00100, 0b01110], // i
    [0b00010, 0b00000, 0b00110, 0b00010, 0b00010, 0b10010, 0b01100], // j
    [0b10000, 0b10000, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010], // k
    [0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110], // l
    [0b00000, 0b00000, 0b11010, 0b10101, 0b10101, 0b10001, 0b10001], // m
    [0b00000, 0b00000, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001], // n
    [0b00000, 0b00000, 0b01110, 0b10001, 0b10001, 0b10001, 0b01110], // o
    [0b11110, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000, 0b10000], // p (descends)
    [0b01111, 0b10001, 0b10001, 0b01111, 0b00001, 0b00001, 0b00001], // q (descends)
    [0b00000, 0b00000, 0b10110, 0b11001, 0b10000, 0b10000, 0b10000], // r
    [0b00000, 0b00000, 0b01110, 0b10000, 0b01110, 0b00001, 0b11110], // s
    [0b01000, 0b01000, 0b11100, 0b01000, 0b01000, 0b01001, 0b00110], // t
    [0b00000, 0b00000, 0b10001, 0b10001, 0b10001, 0b10011, 0b01101], // u
    [0b00000, 0b00000, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100], // v
    [0b00000, 0b00000, 0b10001, 0b10001, 0b10101, 0b10101, 0b01010], // w
    [0b00000, 0b00000, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001], // x
    [0b10001, 0b10001, 0b10001, 0b10011, 0b01101, 0b00001, 0b01110], // y (descends)
    [0b00000, 0b00000, 0b11111, 0b00010, 0b00100, 0b01000, 0b11111], // z
];

/// Letters whose glyph starts at the x-height and is drawn this many font pixels lower, so that
/// their tails hang below the baseline (a 7-row cell has no room for a descender otherwise).
const DESCENDERS: &str = "gpqy";
/// How far a descender glyph is lowered, in font pixels.
const DESCENT: i64 = 2;

/// The glyph of `c`; characters the font lacks draw as `?`.
fn glyph(c: char) -> Glyph {
    match c {
        '0'..='9' => DIGITS[c as usize - '0' as usize],
        'A'..='Z' => UPPER[c as usize - 'A' as usize],
        'a'..='z' => LOWER[c as usize - 'a' as usize],
        _ => PUNCTUATION
            .iter()
            .find(|(p, _)| *p == c)
            .map_or(UNKNOWN, |(_, g)| *g),
    }
}

/// Width in pixels of `text` drawn at `scale` (no trailing space column).
#[must_use]
pub fn text_width(text: &str, scale: u32) -> u32 {
    let n = text.chars().count() as u32;
    (n * ADVANCE).saturating_sub(1) * scale
}

/// Height in pixels of a line of text at `scale`, without descenders (which reach
/// `2 * scale` lower).
#[must_use]
pub const fn text_height(scale: u32) -> u32 {
    GLYPH_HEIGHT * scale
}

/// Sets one pixel; coordinates outside the image are ignored.
pub fn put(img: &mut Rgb8Image, x: i64, y: i64, colour: [u8; 3]) {
    if x < 0 || y < 0 || x >= i64::from(img.width) || y >= i64::from(img.height) {
        return;
    }
    let o = (y as usize * img.width as usize + x as usize) * 3;
    img.data[o..o + 3].copy_from_slice(&colour);
}

/// Draws `text` with its top-left corner at (`x`, `y`), each font pixel `scale` x `scale`
/// image pixels. Clipped at the image's edges.
pub fn draw_text(img: &mut Rgb8Image, x: i64, y: i64, text: &str, scale: u32, colour: [u8; 3]) {
    let s = i64::from(scale.max(1));
    for (i, c) in text.chars().enumerate() {
        let g = glyph(c);
        let gx = x + i as i64 * i64::from(ADVANCE) * s;
        let gy = y + if DESCENDERS.contains(c) {
            DESCENT * s
        } else {
            0
        };
        for (row, bits) in g.iter().enumerate() {
            for col in 0..GLYPH_WIDTH {
                if bits & (1 << (GLYPH_WIDTH - 1 - col)) == 0 {
                    continue;
                }
                for dy in 0..s {
                    for dx in 0..s {
                        put(
                            img,
                            gx + i64::from(col) * s + dx,
                            gy + row as i64 * s + dy,
                            colour,
                        );
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blank(width: u32, height: u32) -> Rgb8Image {
        Rgb8Image {
            width,
            height,
            data: vec![0; (width * height * 3) as usize],
        }
    }

    fn lit(img: &Rgb8Image) -> usize {
        img.data.chunks(3).filter(|p| p[0] > 0).count()
    }

    #[test]
    fn every_glyph_the_report_uses_is_drawn_and_distinct() {
        let chars: Vec<char> = ('0'..='9')
            .chain('A'..='Z')
            .chain('a'..='z')
            .chain(".,-+()/:=_%>|".chars())
            .collect();
        let mut seen = std::collections::HashSet::new();
        for c in chars {
            let g = glyph(c);
            assert!(g.iter().any(|&r| r != 0), "{c} is blank");
            assert!(g.iter().all(|&r| r < 32), "{c} is wider than 5");
            // `p` is `P` lowered: what is drawn is the glyph and its drop.
            assert!(
                seen.insert((g, DESCENDERS.contains(c))),
                "{c} looks like another glyph"
            );
        }
    }

    #[test]
    fn text_is_drawn_at_its_place_and_scale() {
        let mut img = blank(40, 20);
        draw_text(&mut img, 2, 3, "1", 2, [255, 255, 255]);
        // '1' has 10 lit font pixels; at scale 2 each is 4 image pixels.
        assert_eq!(lit(&img), 10 * 4);
        // Its top row is one pixel, column 2 of the glyph: image x 2 + 4..6, y 3..5.
        assert_eq!(img.data[((3 * 40 + 6) * 3) as usize], 255);
        assert_eq!(img.data[((3 * 40 + 2) * 3) as usize], 0);
        assert_eq!(text_width("ab", 2), (2 * ADVANCE - 1) * 2);
    }

    #[test]
    fn text_beyond_the_edges_is_clipped() {
        let mut img = blank(4, 4);
        draw_text(&mut img, -3, -3, "W8?", 3, [1, 2, 3]);
        assert_eq!(img.data.len(), 48);
    }
}
