//! A progress indicator on a terminal (stderr); silent when stderr is not a terminal.

use indicatif::{ProgressBar, ProgressStyle};

pub struct Progress {
    bar: ProgressBar,
}

impl Default for Progress {
    fn default() -> Self {
        Self::new()
    }
}

impl Progress {
    pub fn new() -> Progress {
        // indicatif draws to stderr only when it is a terminal.
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed}] {msg}").expect("valid template"),
        );
        bar.enable_steady_tick(std::time::Duration::from_millis(120));
        Progress { bar }
    }

    pub fn message(&self, msg: &str) {
        self.bar.set_message(msg.trim().to_string());
    }

    /// A note about the input: above the spinner on a terminal, else a plain line on stderr.
    pub fn note(&self, msg: &str) {
        if self.bar.is_hidden() {
            eprintln!("tire-gap: note: {msg}");
        } else {
            self.bar.println(format!("note: {msg}"));
        }
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
