//! Files that hold the same rows: one run saved twice (in US and in SI units, as `.dat` and
//! `.mat`, or under two names) would count twice in a diagnosis, its blocks weighing double and
//! sitting on both sides of a fold split. Nothing in the files says they are one run, so the
//! data say it: the same number of rows, and the load and every measured channel both files
//! hold agreeing far closer than any two runs of a rig do.

use super::Loaded;
use crate::data::{Dataset, Quantity};

/// The largest root-mean-square difference of a channel between two files of one run, as a
/// share of the channel's root mean square. A unit conversion's rounding (a force printed to
/// 0.01 lbf or 0.01 N) stays below 1e-5 of it; two runs of the same test differ by their
/// noise, above 1e-2.
const SAME_ROWS: f64 = 1e-3;

/// Whether `q` is compared: every channel but the run id and the time (a re-saved run may
/// count its time from another origin).
fn compared(q: Quantity) -> bool {
    !matches!(q, Quantity::Run | Quantity::Time)
}

/// `parts` without the files whose rows repeat an earlier file's, each left out with a note
/// naming both files.
pub(super) fn without_repeats(parts: Vec<Loaded>, notes: &mut Vec<String>) -> Vec<Loaded> {
    let mut kept: Vec<Loaded> = Vec::with_capacity(parts.len());
    for part in parts {
        match kept.iter().find(|k| same_rows(&k.dataset, &part.dataset)) {
            Some(first) => notes.push(format!(
                "{} holds the same {} rows as {} (every channel both hold agrees within {} \
                 of its root mean square): left out, as one run read twice would count twice",
                part.dataset.source,
                part.dataset.len(),
                first.dataset.source,
                SAME_ROWS
            )),
            None => kept.push(part),
        }
    }
    kept
}

/// Whether `a` and `b` hold the same rows: as many, a measured force in both, and every
/// compared channel both hold within [`SAME_ROWS`].
fn same_rows(a: &Dataset, b: &Dataset) -> bool {
    if a.len() != b.len() || a.is_empty() {
        return false;
    }
    let shared: Vec<(&[f64], &[f64])> = Quantity::ALL
        .into_iter()
        .filter(|&q| compared(q))
        .filter_map(|q| Some((a.column(q)?, b.column(q)?)))
        .collect();
    let a_force = [Quantity::Fx, Quantity::Fy, Quantity::Mz]
        .iter()
        .any(|&q| a.column(q).is_some() && b.column(q).is_some());
    a_force && shared.iter().all(|(x, y)| agree(x, y))
}

/// Root-mean-square difference of `x` and `y` within [`SAME_ROWS`] of `x`'s root mean square
/// (a channel at zero in both agrees).
fn agree(x: &[f64], y: &[f64]) -> bool {
    let (mut diff, mut size) = (0.0, 0.0);
    for (p, q) in x.iter().zip(y) {
        diff += (p - q) * (p - q);
        size += p * p;
    }
    diff <= SAME_ROWS * SAME_ROWS * size
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(source: &str, fz: Vec<f64>, fy: Vec<f64>) -> Loaded {
        let n = fz.len();
        Loaded {
            dataset: Dataset {
                source: source.into(),
                run: vec![1; n].into(),
                alpha: Some((0..n).map(|i| i as f64 * 0.01).collect()),
                fz: fz.into(),
                fy: Some(fy.into()),
                ..Dataset::default()
            },
            notes: vec![],
            sources: vec![],
        }
    }

    fn loads(n: usize) -> Vec<f64> {
        (0..n).map(|i| 1000.0 + 7.0 * (i % 13) as f64).collect()
    }

    fn forces(n: usize, wobble: f64) -> Vec<f64> {
        (0..n)
            .map(|i| 800.0 * (i as f64 * 0.3).sin() + wobble * (i as f64 * 1.7).cos())
            .collect()
    }

    #[test]
    fn a_run_read_twice_is_kept_once_and_a_repeat_of_the_test_twice() {
        let n = 200;
        // The same run in US units, converted back: rounding of 0.01 lbf (0.044 N).
        let us = forces(n, 0.0)
            .iter()
            .map(|f| ((f / 4.448_221_615) * 100.0).round() / 100.0 * 4.448_221_615)
            .collect();
        // A second run of the same test: the rig's noise of a few newtons.
        let again = forces(n, 5.0);
        let parts = vec![
            part("run51.mat", loads(n), forces(n, 0.0)),
            part("run51_us.dat", loads(n), us),
            part("run52.mat", loads(n), again),
        ];
        let mut notes = vec![];
        let kept = without_repeats(parts, &mut notes);
        let names: Vec<&str> = kept.iter().map(|p| p.dataset.source.as_str()).collect();
        assert_eq!(names, ["run51.mat", "run52.mat"]);
        assert_eq!(notes.len(), 1);
        assert!(
            notes[0].starts_with("run51_us.dat holds the same 200 rows as run51.mat"),
            "{notes:?}"
        );
    }

    #[test]
    fn rows_that_differ_in_number_or_in_the_load_are_not_a_repeat() {
        let n = 100;
        let mut other_load = loads(n);
        other_load[40] += 200.0;
        let parts = vec![
            part("a.mat", loads(n), forces(n, 0.0)),
            part("b.mat", loads(n - 1), forces(n - 1, 0.0)),
            part("c.mat", other_load, forces(n, 0.0)),
        ];
        let mut notes = vec![];
        assert_eq!(without_repeats(parts, &mut notes).len(), 3);
        assert!(notes.is_empty());
    }
}
