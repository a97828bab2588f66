//! A progress line on stderr for commands that take more than a second, on a terminal only:
//! what is being done, the fraction done, the time so far and, where the work done so far
//! gives a rate, the time left.
//!
//! The fraction is what the command can count: for `render`, its stages (loading, rendering,
//! saving) with the rows written while saving; for `accuracy`, the frames drawn. The renderer
//! draws a frame in one call, so a single frame's own progress is not counted.

use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// Nothing is shown for commands shorter than this.
const QUIET_FOR: Duration = Duration::from_secs(1);
/// Redraw interval.
const TICK: Duration = Duration::from_millis(100);
/// Width of the bar in characters.
const BAR: usize = 24;

/// What the line shows.
#[derive(Debug, Clone)]
struct Shown {
    label: String,
    /// Fraction of the whole command done, `[0, 1]`.
    fraction: f64,
    /// Time left, when known.
    left: Option<Duration>,
    /// Characters of the line now on the terminal (0: none), so that it can be erased.
    drawn: usize,
}

/// A progress line drawn by a thread of its own until [`Progress::finish`].
pub struct Progress {
    shown: Arc<Mutex<Shown>>,
    done: Arc<AtomicBool>,
    handle: Option<std::thread::JoinHandle<()>>,
    started: Instant,
}

impl Progress {
    /// Starts the line (drawn only if stderr is a terminal, and only after a second).
    pub fn start(label: &str) -> Progress {
        let shown = Arc::new(Mutex::new(Shown {
            label: label.to_owned(),
            fraction: 0.0,
            left: None,
            drawn: 0,
        }));
        let done = Arc::new(AtomicBool::new(false));
        let started = Instant::now();
        let handle = std::io::stderr().is_terminal().then(|| {
            let shown = shown.clone();
            let done = done.clone();
            std::thread::spawn(move || draw_until(&shown, &done, started))
        });
        Progress {
            shown,
            done,
            handle,
            started,
        }
    }

    /// Shows `label` at `fraction` of the whole command, with the time left if known.
    pub fn set(&self, label: &str, fraction: f64, left: Option<Duration>) {
        let mut s = self.shown.lock().unwrap_or_else(PoisonError::into_inner);
        s.label.clear();
        s.label.push_str(label);
        s.fraction = fraction.clamp(0.0, 1.0);
        s.left = left;
    }

    /// Erases the line, if drawn, so that a message can be printed; the next tick redraws it
    /// below that message.
    pub fn clear_line(&self) {
        let mut s = self.shown.lock().unwrap_or_else(PoisonError::into_inner);
        if s.drawn > 0 {
            let _ = write!(std::io::stderr(), "\r{}\r", " ".repeat(s.drawn));
            s.drawn = 0;
        }
    }

    /// Time since [`Progress::start`].
    pub fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// Erases the line and stops the thread.
    pub fn finish(mut self) {
        self.stop();
    }

    fn stop(&mut self) {
        self.done.store(true, Ordering::Relaxed);
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Time left at a constant rate: `elapsed` took `done` of the work.
#[must_use]
pub fn time_left(elapsed: Duration, done: f64) -> Option<Duration> {
    (done > 0.0 && done <= 1.0).then(|| elapsed.mul_f64((1.0 - done) / done))
}

fn draw_until(shown: &Mutex<Shown>, done: &AtomicBool, started: Instant) {
    while !done.load(Ordering::Relaxed) {
        std::thread::sleep(TICK);
        let t = started.elapsed();
        if t < QUIET_FOR || done.load(Ordering::Relaxed) {
            continue;
        }
        // The lock is held while drawing, so that `clear_line` never races a redraw.
        let mut s = shown.lock().unwrap_or_else(PoisonError::into_inner);
        let line = render_line(&s, t);
        let width = s.drawn.max(line.chars().count());
        // A progress line that cannot be drawn is not worth ending the command for: the
        // command's own messages report a broken stderr.
        let _ = write!(std::io::stderr(), "\r{line:<width$}");
        s.drawn = width;
    }
    let s = shown.lock().unwrap_or_else(PoisonError::into_inner);
    if s.drawn > 0 {
        let _ = write!(std::io::stderr(), "\r{}\r", " ".repeat(s.drawn));
    }
}

fn render_line(s: &Shown, elapsed: Duration) -> String {
    let filled = ((s.fraction * BAR as f64).round() as usize).min(BAR);
    let left = s
        .left
        .map_or_else(String::new, |l| format!(", about {} left", seconds(l)));
    format!(
        "{} [{}{}] {:3.0}% {}{left}",
        s.label,
        "#".repeat(filled),
        ".".repeat(BAR - filled),
        s.fraction * 100.0,
        seconds(elapsed)
    )
}

/// A duration for people: `0.4 s`, `12 s`, `3 min 05 s`.
#[must_use]
pub fn seconds(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s < 10.0 {
        format!("{s:.1} s")
    } else if s < 60.0 {
        format!("{s:.0} s")
    } else {
        let whole = s.round() as u64;
        format!("{} min {:02} s", whole / 60, whole % 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_shows_fraction_time_and_time_left() {
        let s = Shown {
            label: "saving".to_owned(),
            fraction: 0.5,
            left: Some(Duration::from_secs(3)),
            drawn: 0,
        };
        let line = render_line(&s, Duration::from_millis(2500));
        assert_eq!(
            line,
            "saving [############............]  50% 2.5 s, about 3.0 s left"
        );
    }

    #[test]
    fn time_left_follows_the_rate_so_far() {
        let t = time_left(Duration::from_secs(2), 0.25);
        assert_eq!(t, Some(Duration::from_secs(6)));
        assert_eq!(time_left(Duration::from_secs(2), 0.0), None);
        assert_eq!(seconds(Duration::from_secs(125)), "2 min 05 s");
    }
}
