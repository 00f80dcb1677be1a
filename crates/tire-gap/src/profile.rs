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
    /// The process's CPU time so far, in seconds, where the platform tells.
    cpu_seconds: fn() -> Option<f64>,
    counts: Counts,
    /// Each stage's name, start and the process's CPU time then, in order.
    stages: Mutex<Vec<(String, Instant, Option<f64>)>>,
}

impl Profiler {
    /// Starts the clock and the row counts now; `cpu_seconds` tells the process's CPU time
    /// (see [`crate::cli::Host`]).
    pub fn new(cpu_seconds: fn() -> Option<f64>) -> Self {
        Profiler {
            start: Instant::now(),
            cpu_seconds,
            counts: Counts::now(),
            stages: Mutex::new(Vec::new()),
        }
    }

    /// The profile from the start until now, on `threads` threads, as text.
    pub fn report(&self, threads: usize) -> String {
        let (end, end_cpu) = (Instant::now(), (self.cpu_seconds)());
        let wall = (end - self.start).as_secs_f64();
        let counts = Counts::now().since(&self.counts);
        let stages = self.stages.lock().unwrap_or_else(|e| e.into_inner());
        let mut out = format!(
            "profile: {wall:.1} s wall on {threads} thread(s)\n  stages (wall s, and the \
             threads busy on average: CPU time over wall time):\n"
        );
        // Stages of the same name (each selection round's) are summed, in first-seen order.
        let mut summed: Vec<(String, f64, Option<f64>)> = Vec::new();
        for (k, (name, at, cpu_at)) in stages.iter().enumerate() {
            let (until, cpu_until) = stages.get(k + 1).map_or((end, end_cpu), |s| (s.1, s.2));
            let secs = (until - *at).as_secs_f64();
            let cpu = cpu_until.zip(*cpu_at).map(|(b, a)| b - a);
            match summed.iter_mut().find(|(n, ..)| n == name) {
                Some(s) => {
                    s.1 += secs;
                    s.2 = s.2.zip(cpu).map(|(a, b)| a + b);
                }
                None => summed.push((name.clone(), secs, cpu)),
            }
        }
        for (name, secs, cpu) in &summed {
            let busy = cpu.map_or(String::new(), |c| {
                format!("{:5.2}", c / secs.max(f64::MIN_POSITIVE))
            });
            out += &format!("    {secs:8.1} {busy:>5}  {name}\n");
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
                "  {name}: rows evaluated (millions) by dual width (the bare formula's time a \
                 row), and their cost at that rate: {secs:.1} s\n"
            );
            let cells: Vec<String> = WIDTHS
                .iter()
                .zip(rows)
                .zip(rates)
                .filter(|((_, n), _)| **n > 0)
                .map(|((w, n), rate)| match w {
                    0 => format!("values {:.2} ({:.0} ns)", *n as f64 / 1e6, rate * 1e9),
                    _ => format!("width {w} {:.2} ({:.0} ns)", *n as f64 / 1e6, rate * 1e9),
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
        self.stages.lock().unwrap_or_else(|e| e.into_inner()).push((
            msg.to_string(),
            Instant::now(),
            (self.cpu_seconds)(),
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::fit::evaluations::record;
    use crate::method::observer::{Observer, OnStage, Unobserved};

    #[test]
    fn the_profile_names_each_stage_once_and_prices_the_rows_counted() {
        // A process clock that runs at one and a half times the wall clock: 1.5 threads busy.
        static ORIGIN: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
        ORIGIN.get_or_init(Instant::now);
        let p = Profiler::new(|| {
            let origin = ORIGIN.get()?;
            Some(1.5 * origin.elapsed().as_secs_f64())
        });
        let pause = || std::thread::sleep(std::time::Duration::from_millis(100));
        // As the command line clocks a diagnosis: through its observer.
        let observer = OnStage {
            inner: &Unobserved,
            before_stage: |msg: &str| p.record(msg),
        };
        observer.stage("fitting", 3);
        pause();
        observer.stage("scoring", 0);
        pause();
        observer.stage("fitting", 3);
        pause();
        record(Formula::Mf87, 0, 2_000_000);
        let text = p.report(2);
        assert_eq!(text.matches("fitting").count(), 1, "{text}");
        assert!(text.contains("scoring"), "{text}");
        // Each stage's line: wall seconds, threads busy, name; the two fittings summed.
        let line = |name: &str| -> Vec<f64> {
            let l = text.lines().find(|l| l.ends_with(name)).unwrap();
            l.split_whitespace()
                .take(2)
                .map(|v| v.parse().unwrap())
                .collect()
        };
        let (fitting, scoring) = (line("fitting"), line("scoring"));
        assert!(fitting[0] >= 0.2 && scoring[0] >= 0.1, "{text}");
        for busy in [fitting[1], scoring[1]] {
            assert!((busy - 1.5).abs() < 0.05, "{text}");
        }
        // Other tests of the process may count rows at once: at least ours.
        let values: f64 = text
            .split("values ")
            .nth(1)
            .and_then(|t| t.split([',', '\n', '(']).next())
            .and_then(|t| t.trim().parse().ok())
            .unwrap();
        assert!(values >= 2.0, "{text}");
        assert!(text.contains("% of the limit"), "{text}");
    }
}
