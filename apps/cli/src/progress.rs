//! Progress bars on stderr (indicatif) for commands that take more than a second, on a
//! terminal only: what is being done, the share done, the time so far and, from the rate so
//! far, the time left.
//!
//! A command adds its bars hidden and calls [`Progress::show_after`]: only if it is still
//! running a second later, and stderr is a terminal, do the bars appear, redrawn ten times a
//! second. `render` shows one bar for a sequence, counting its frames, above the current
//! frame's bar (its stage: loading, rendering, saving with the rows written); `accuracy` one
//! bar counting the frames it draws. The renderer draws a frame in one call, so a frame's own
//! rendering is not counted within it.

use std::io::IsTerminal;
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::Duration;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Nothing is shown for commands shorter than this.
pub const QUIET_FOR: Duration = Duration::from_secs(1);
/// Redraw interval once shown.
const TICK: Duration = Duration::from_millis(100);
/// Steps of a bar that shows a fraction.
const FRACTION_STEPS: u64 = 1000;

/// A count of whole things (frames): `frames [####....] 3/36, 4.1 s, about 45 s left`.
const COUNT_TEMPLATE: &str = "{msg} [{bar:24}] {pos}/{len}, {elapsed}, about {eta} left";
/// A share of one thing: `saving out.png [####....]  50%, 2.5 s, about 3 s left`.
const FRACTION_TEMPLATE: &str = "{msg} [{bar:24}] {percent:>3}%, {elapsed}, about {eta} left";

/// Set once the command is done, to wake the thread waiting to show the bars.
type Done = Arc<(Mutex<bool>, Condvar)>;

/// A command's progress bars, hidden until [`Progress::show_after`] shows them.
pub struct Progress {
    multi: MultiProgress,
    bars: Vec<ProgressBar>,
    waiting: Option<(Done, JoinHandle<()>)>,
}

fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template)
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("##.")
}

impl Progress {
    /// No bars yet, nothing shown.
    #[must_use]
    pub fn new() -> Progress {
        Progress {
            multi: MultiProgress::with_draw_target(ProgressDrawTarget::hidden()),
            bars: Vec::new(),
            waiting: None,
        }
    }

    /// Adds a bar counting `len` things, labelled `label`.
    pub fn counter(&mut self, label: &str, len: u64) -> ProgressBar {
        self.add(
            ProgressBar::new(len).with_style(style(COUNT_TEMPLATE)),
            label,
        )
    }

    /// Adds a bar showing a fraction (see [`set_fraction`]), labelled `label`.
    pub fn fraction(&mut self, label: &str) -> ProgressBar {
        let bar = ProgressBar::new(FRACTION_STEPS).with_style(style(FRACTION_TEMPLATE));
        self.add(bar, label)
    }

    fn add(&mut self, bar: ProgressBar, label: &str) -> ProgressBar {
        let bar = self.multi.add(bar);
        bar.set_message(label.to_owned());
        self.bars.push(bar.clone());
        bar
    }

    /// Shows the bars on stderr once `delay` has passed, if the command still runs then and
    /// stderr is a terminal.
    pub fn show_after(&mut self, delay: Duration) {
        if !std::io::stderr().is_terminal() {
            return;
        }
        let done: Done = Arc::new((Mutex::new(false), Condvar::new()));
        let (multi, bars, flag) = (self.multi.clone(), self.bars.clone(), done.clone());
        let handle = std::thread::spawn(move || {
            let (lock, woken) = &*flag;
            let finished = lock.lock().unwrap_or_else(PoisonError::into_inner);
            let (finished, _) = woken
                .wait_timeout_while(finished, delay, |finished| !*finished)
                .unwrap_or_else(PoisonError::into_inner);
            if !*finished {
                show(&multi, &bars, ProgressDrawTarget::stderr());
            }
        });
        self.waiting = Some((done, handle));
    }

    /// Runs `f` (which prints lines) with the bars taken off the terminal, then draws them
    /// again below what it printed.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.multi.suspend(f)
    }

    /// Stops waiting to show the bars and erases them.
    pub fn finish(mut self) {
        self.stop();
    }

    fn stop(&mut self) {
        if let Some((done, handle)) = self.waiting.take() {
            let (lock, woken) = &*done;
            *lock.lock().unwrap_or_else(PoisonError::into_inner) = true;
            woken.notify_all();
            let _ = handle.join();
        }
        for bar in &self.bars {
            bar.finish_and_clear();
        }
        // A bar that cannot be erased is not worth failing the command for.
        let _ = self.multi.clear();
    }
}

impl Default for Progress {
    fn default() -> Self {
        Progress::new()
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Draws `bars` on `target` from now on, redrawn every [`TICK`].
fn show(multi: &MultiProgress, bars: &[ProgressBar], target: ProgressDrawTarget) {
    multi.set_draw_target(target);
    for bar in bars {
        bar.enable_steady_tick(TICK);
    }
}

/// Sets a bar made by [`Progress::fraction`] to `fraction` (clamped to [0, 1]), labelled `label`.
pub fn set_fraction(bar: &ProgressBar, label: &str, fraction: f64) {
    bar.set_message(label.to_owned());
    let steps = (fraction.clamp(0.0, 1.0) * FRACTION_STEPS as f64).round() as u64;
    bar.set_position(steps);
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use std::io;

    use indicatif::TermLike;

    use super::*;

    /// A terminal that keeps what is written to it.
    #[derive(Debug, Default, Clone)]
    struct Screen(Arc<Mutex<String>>);

    impl TermLike for Screen {
        fn width(&self) -> u16 {
            120
        }
        fn move_cursor_up(&self, _: usize) -> io::Result<()> {
            Ok(())
        }
        fn move_cursor_down(&self, _: usize) -> io::Result<()> {
            Ok(())
        }
        fn move_cursor_right(&self, _: usize) -> io::Result<()> {
            Ok(())
        }
        fn move_cursor_left(&self, _: usize) -> io::Result<()> {
            Ok(())
        }
        fn write_line(&self, s: &str) -> io::Result<()> {
            self.write_str(&format!("{s}\n"))
        }
        fn write_str(&self, s: &str) -> io::Result<()> {
            self.0.lock().unwrap().push_str(s);
            Ok(())
        }
        fn clear_line(&self) -> io::Result<()> {
            Ok(())
        }
        fn flush(&self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_sequence_shows_one_bar_of_its_frames_above_the_frames_stage() {
        let screen = Screen::default();
        let mut progress = Progress::new();
        let frames = progress.counter("frames", 3);
        let stage = progress.fraction("loading");
        show(
            &progress.multi,
            &progress.bars,
            ProgressDrawTarget::term_like(Box::new(screen.clone())),
        );
        for k in 0..3 {
            set_fraction(&stage, &format!("saving frame {k}"), 0.5);
            frames.inc(1);
        }
        std::thread::sleep(TICK * 3);
        let text = screen.0.lock().unwrap().clone();
        assert!(text.contains("frames ["), "{text}");
        assert!(text.contains("] 3/3, "), "{text}");
        assert!(text.contains("saving frame 2 ["), "{text}");
        assert!(text.contains(" 50%, "), "{text}");
        progress.finish();
    }

    #[test]
    fn nothing_is_drawn_before_the_bars_are_shown() {
        let mut progress = Progress::new();
        let frames = progress.counter("frames", 2);
        frames.inc(2);
        assert!(progress.multi.is_hidden());
        progress.finish();
        // On a stderr that is not a terminal (as under `cargo test`), nothing waits to show.
        let mut progress = Progress::new();
        progress.show_after(Duration::ZERO);
        assert_eq!(progress.waiting.is_some(), std::io::stderr().is_terminal());
    }

    #[test]
    fn fractions_are_clamped_to_the_bar() {
        let mut progress = Progress::new();
        let bar = progress.fraction("x");
        set_fraction(&bar, "x", 2.0);
        assert_eq!(bar.position(), FRACTION_STEPS);
        set_fraction(&bar, "x", f64::NAN.max(-1.0));
        assert_eq!(bar.position(), 0);
    }
}
