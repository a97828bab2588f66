//! `phosphor-output`: what the Phosphor applications hand to the outside world, made so that
//! nothing is lost and nothing is half-written.
//!
//! - [`file`](mod@file): output files written whole or not at all (a temporary file in the target's
//!   folder, flushed, synced and renamed), through symbolic links, refusing devices and
//!   read-only files unless forced, removed on SIGINT and SIGTERM.
//! - [`image`]: PNG tagged with its transfer curve (sRGB, or linear with a gamma of 1.0) and
//!   linear OpenEXR, encoded row by row into such a file.
//! - [`term`]: stdout and stderr lines whose failure ends the process with status 1, warnings
//!   cut to one short line, control characters shown rather than obeyed.
//! - [`temp`]: temporary names that fit wherever the target's name fits, and the removal of
//!   those a killed writer left.
//! - [`memory`]: how much memory is left, to refuse an image that would not fit before it is
//!   allocated.
//!
//! ```
//! use phosphor_output::image::{Transfer, write_png};
//!
//! let dir = tempfile::tempdir()?;
//! let path = dir.path().join("ramp.png");
//! // A 4x2 grey ramp, sRGB-tagged.
//! let mut ramp = |_y: u32, row: &mut [u8]| {
//!     for (x, px) in row.chunks_mut(3).enumerate() {
//!         px.fill(x as u8 * 60);
//!     }
//! };
//! write_png(&path, false, (4, 2), Transfer::Srgb, &mut ramp, &mut |_| {})?;
//! let bytes = std::fs::read(&path)?;
//! assert!(bytes.starts_with(b"\x89PNG"));
//! assert!(bytes.windows(4).any(|w| w == b"sRGB"));
//!
//! // A folder is never replaced; the message names the path.
//! let err = write_png(dir.path(), true, (4, 2), Transfer::Srgb, &mut ramp, &mut |_| {});
//! assert!(err.unwrap_err().to_string().ends_with("is a folder"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod cleanup;
pub mod file;
pub mod image;
pub mod memory;
pub mod temp;
pub mod term;

pub use file::{OutputError, check, write_file};

#[cfg(test)]
mod tests;
