//! Where a diagnosis's time goes (`tire-gap diagnose --profile`): each stage's wall time, the
//! rows the models were evaluated on (values and exact derivatives, by the width of the dual
//! numbers), and what those rows cost at the bare formula's rate, as a share of the time the
//! diagnosis had on its threads. The clock hears of each stage through the front end's
//! observer (see [`crate::method::observer::OnStage`]).

use std::sync::Mutex;
use std::time::Instant;

use crate::method::diagnose::reference::bare61_seconds_per_row;
use crate::method::fit::evaluations::{
    Counts, Formula, WIDTHS, bare87_seconds_per_row, seconds_at,
};

/// Clocks the stages a diagnosis announces (see [`Profiler::record`]).
pub struct Profiler {
    start: Instant,
    counts: Counts,
    /// Each stage's name and start, in order.
    stages: Mutex<Vec<(String, Instant)>>,
}

impl Default for Profiler {
    fn default() -> Self {
        Self::new()
    }
}

impl Profiler {
    /// Starts the clock and the row counts now.
    pub fn new() -> Self {
        Profiler {
            start: Instant::now(),
            counts: Counts::now(),
            stages: Mutex::new(Vec::new()),
        }
    }

    /// The profile from the start until now, on `threads` threads, as text.
    pub fn report(&self, threads: usize) -> String {
        let end = Instant::now();
        let wall = (end - self.start).as_secs_f64();
        let counts = Counts::now().since(&self.counts);
        let stages = self.stages.lock().unwrap_or_else(|e| e.into_inner());
        let mut out =
            format!("profile: {wall:.1} s wall on {threads} thread(s)\n  stages (wall s):\n");
        // Stages of the same name (each selection round's) are summed, in first-seen order.
        let mut summed: Vec<(String, f64)> = Vec::new();
        for (k, (name, at)) in stages.iter().enumerate() {
            let until = stages.get(k + 1).map_or(end, |s| s.1);
            let secs = (until - *at).as_secs_f64();
            match summed.iter_mut().find(|(n, _)| n == name) {
                Some(s) => s.1 += secs,
                None => summed.push((name.clone(), secs)),
            }
        }
        for (name, secs) in &summed {
            out += &format!("    {secs:8.1}  {name}\n");
        }
        let mut bare = 0.0;
        for (formula, name, rates) in [
            (Formula::Mf87, "1987 model", bare87_seconds_per_row()),
            (Formula::Mf61, "MF 6.1 reference", bare61_seconds_per_row()),
        ] {
            let rows = counts.of(formula);
            let secs = seconds_at(rows, &rates);
            bare += secs;
            out += &format!(
                "  {name}: rows evaluated (millions) by dual width, and their cost at the bare \
                 formula's rate ({:.0} ns a value row, {:.0} ns at width 16): {secs:.1} s\n",
                rates[0] * 1e9,
                rates[WIDTHS.iter().position(|w| *w == 16).unwrap_or(0)] * 1e9
            );
            let cells: Vec<String> = WIDTHS
                .iter()
                .zip(rows)
                .filter(|(_, n)| **n > 0)
                .map(|(w, n)| match w {
                    0 => format!("values {:.2}", *n as f64 / 1e6),
                    _ => format!("width {w} {:.2}", *n as f64 / 1e6),
                })
                .collect();
            out += &format!("    {}\n", cells.join(", "));
        }
        let capacity = wall * threads as f64;
        out += &format!(
            "  bare-rate cost {bare:.1} s of {capacity:.1} thread-seconds: {:.0} % of the limit\n",
            100.0 * bare / capacity.max(f64::MIN_POSITIVE)
        );
        out
    }
}

impl Profiler {
    /// Notes that the stage `msg` starts now.
    pub fn record(&self, msg: &str) {
        self.stages
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push((msg.to_string(), Instant::now()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::fit::evaluations::record;
    use crate::method::observer::{Observer, OnStage, Unobserved};

    #[test]
    fn the_profile_names_each_stage_once_and_prices_the_rows_counted() {
        let p = Profiler::new();
        // As the command line clocks a diagnosis: through its observer.
        let observer = OnStage {
            inner: &Unobserved,
            before_stage: |msg: &str| p.record(msg),
        };
        observer.stage("fitting", 3);
        observer.stage("scoring", 0);
        observer.stage("fitting", 3);
        record(Formula::Mf87, 0, 2_000_000);
        let text = p.report(2);
        assert_eq!(text.matches("fitting").count(), 1, "{text}");
        assert!(text.contains("scoring"), "{text}");
        // Other tests of the process may count rows at once: at least ours.
        let values: f64 = text
            .split("values ")
            .nth(1)
            .and_then(|t| t.split([',', '\n']).next())
            .and_then(|t| t.trim().parse().ok())
            .unwrap();
        assert!(values >= 2.0, "{text}");
        assert!(text.contains("% of the limit"), "{text}");
    }
}
