//! Progress on a terminal (stderr), the command line's [`Observer`]: one bar per stage, with
//! its steps, elapsed time and an estimate of the time left; nothing when stderr is not a
//! terminal (piped or redirected).

use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::method::observer::Observer;

/// Shared by the threads of a stage: `step` may be called from any of them.
pub struct Progress {
    /// The current stage's bar; a new bar per stage, styled before it first draws.
    bar: Mutex<ProgressBar>,
    hidden: bool,
}

impl Default for Progress {
    fn default() -> Self {
        Self::new()
    }
}

impl Progress {
    /// Drawn on stderr when it is a terminal (indicatif's stderr target draws only then).
    pub fn new() -> Progress {
        let progress = Progress {
            bar: Mutex::new(ProgressBar::hidden()),
            hidden: ProgressDrawTarget::stderr().is_hidden(),
        };
        progress.stage("reading the input", 0);
        progress
    }

    /// Never drawn (tests).
    pub fn hidden() -> Progress {
        Progress {
            bar: Mutex::new(ProgressBar::hidden()),
            hidden: true,
        }
    }

    fn current(&self) -> MutexGuard<'_, ProgressBar> {
        // A thread that panicked holding the lock left a usable bar.
        self.bar.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A new stage of `steps` steps (0: unknown, a spinner).
    pub fn stage(&self, msg: &str, steps: u64) {
        let (template, length) = if steps == 0 {
            ("{spinner} [{elapsed}] {msg}", None)
        } else {
            (
                "{spinner} [{elapsed}] {msg} [{bar:24}] {pos}/{len}, about {eta} left",
                Some(steps),
            )
        };
        let target = if self.hidden {
            ProgressDrawTarget::hidden()
        } else {
            ProgressDrawTarget::stderr()
        };
        let next = ProgressBar::with_draw_target(length, target)
            .with_style(
                ProgressStyle::with_template(template)
                    .expect("valid template")
                    .progress_chars("=> "),
            )
            .with_message(msg.trim().to_string());
        if !self.hidden {
            next.enable_steady_tick(Duration::from_millis(200));
        }
        std::mem::replace(&mut *self.current(), next).finish_and_clear();
    }

    /// One step of the current stage done.
    pub fn step(&self) {
        self.current().inc(1);
    }

    /// A note about the input: above the bar on a terminal, else a plain line on stderr.
    pub fn note(&self, msg: &str) {
        if self.hidden {
            eprintln!("tire-gap: note: {msg}");
        } else {
            self.current().println(format!("note: {msg}"));
        }
    }

    pub fn finish(&self) {
        self.current().finish_and_clear();
    }
}

impl Observer for Progress {
    fn stage(&self, msg: &str, steps: u64) {
        Progress::stage(self, msg, steps);
    }

    fn step(&self) {
        Progress::step(self);
    }

    fn note(&self, msg: &str) {
        Progress::note(self, msg);
    }
}

impl Drop for Progress {
    /// An error ends the work early: the bar goes, so the message stands alone.
    fn drop(&mut self) {
        self.finish();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_count_their_steps_from_any_thread() {
        let p = Progress::hidden();
        p.stage("fitting", 8);
        std::thread::scope(|s| {
            for _ in 0..4 {
                s.spawn(|| {
                    p.step();
                    p.step();
                });
            }
        });
        assert_eq!(p.current().position(), 8);
        assert_eq!(p.current().length(), Some(8));
        p.stage("next", 3);
        assert_eq!(p.current().position(), 0);
        assert_eq!(p.current().length(), Some(3));
        p.stage("spinner", 0);
        assert_eq!(p.current().length(), None);
    }
}
