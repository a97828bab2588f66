//! Limits checked before work starts: worker threads, and memory for the image.

use phosphor_output::memory;
use phosphor_output::term::warn;
use phosphor_raster::Antialias;

use crate::CliError;

/// Most worker threads per core. More threads than cores only add switching and memory (each
/// has a stack and a share of the bands); thousands of them take longer to start and join
/// than a small frame takes to draw.
pub const THREADS_PER_CORE: usize = 4;

/// The cores this process may use.
#[must_use]
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
}

/// `--threads` as the renderer gets it: 0 (all cores) and counts up to
/// [`THREADS_PER_CORE`] per core as given; above, the cap, with a warning.
#[must_use]
pub fn threads(requested: Option<usize>) -> usize {
    let requested = requested.unwrap_or(0);
    let (threads, warning) = capped_threads(requested, cores());
    if let Some(w) = warning {
        warn(&w);
    }
    threads
}

/// The thread count for `requested` on `cores` cores, and the warning when it is capped.
fn capped_threads(requested: usize, cores: usize) -> (usize, Option<String>) {
    let cap = THREADS_PER_CORE * cores.max(1);
    if requested <= cap {
        return (requested, None);
    }
    let warning = format!(
        "--threads: {requested} is more than {THREADS_PER_CORE} per core ({cores} core{}); using {cap}",
        if cores == 1 { "" } else { "s" }
    );
    (cap, Some(warning))
}

/// Bytes per pixel of the framebuffer: linear RGB f32 and an f32 depth.
pub const FRAMEBUFFER_BYTES_PER_PIXEL: u64 = 16;

/// Bytes per pixel of the sample image an anti-aliased frame adds (RGB f32 and depth per
/// sample; none without anti-aliasing).
#[must_use]
pub fn sample_bytes_per_pixel(aa: Antialias) -> u64 {
    if aa == Antialias::Off {
        0
    } else {
        FRAMEBUFFER_BYTES_PER_PIXEL * u64::from(aa.samples())
    }
}

/// Refuses an image that would not fit in the memory left, before it is allocated
/// (see [`memory::check_image`]); `field` names what set the size.
pub fn check_memory(field: &str, size: (u32, u32), bytes_per_pixel: u64) -> Result<(), CliError> {
    memory::check_image(field, size, bytes_per_pixel).map_err(CliError::Input)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_counts_above_four_per_core_are_capped_with_a_warning() {
        assert_eq!(capped_threads(0, 2), (0, None));
        assert_eq!(capped_threads(8, 2), (8, None));
        let (n, w) = capped_threads(5000, 2);
        assert_eq!(n, 8);
        assert_eq!(
            w.as_deref(),
            Some("--threads: 5000 is more than 4 per core (2 cores); using 8")
        );
        assert_eq!(capped_threads(5, 1).0, 4);
    }
}
