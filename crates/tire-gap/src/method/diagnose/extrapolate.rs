//! Step 5's extrapolation check: does the winning effect still hold beyond the conditions it
//! was fitted on? Runs are ranked by the effect's driving input; the runs at one end (the
//! highest third, then the lowest third) are held out, the model with and without the effect
//! is refitted on the rest (within the FMU's bounds over the whole data's range), and both are
//! scored on the held-out end.

use std::collections::{BTreeMap, BTreeSet};

use mf87::Channel;
use serde::Serialize;

use crate::method::fit::channel_fit::{Admissible, Start, fit_channel};
use crate::method::fit::effects::{self, Extension};
use crate::method::fit::model::ChannelModel;
use crate::method::parallel::parallel_map;
use crate::method::prepare::channel_data::{ChannelData, ranges_of};

/// One held-out end of the driving input, on one channel.
#[derive(Debug, Clone, Serialize)]
pub struct Extrapolation {
    pub effect: Extension,
    pub channel: Channel,
    /// The run-level driving input, e.g. "median pressure \[kPa\]".
    pub driver: &'static str,
    /// Which end was held out, e.g. "highest third (>= 261.798)" (in the driver's unit).
    pub held_out: String,
    pub runs: usize,
    pub rows: usize,
    /// Held-out RMS [N or N.m] of the model without and with the effect, both refitted on
    /// the other runs.
    pub rms_without: f64,
    pub rms_with: f64,
    /// The extended model against the base on the held-out end (see [`outcome`]).
    pub outcome: &'static str,
}

/// Held-out RMS values within this fraction of each other extrapolate no differently.
pub const SAME_WITHIN: f64 = 0.02;

/// `better`, `worse` or `no different`: the extended model's held-out RMS against the base's.
pub fn outcome(rms_without: f64, rms_with: f64) -> &'static str {
    if rms_with < (1.0 - SAME_WITHIN) * rms_without {
        "better"
    } else if rms_with > (1.0 + SAME_WITHIN) * rms_without {
        "worse"
    } else {
        "no different"
    }
}

/// The check in words: where the extended model extrapolates worse than the base model, and
/// whether it holds elsewhere.
pub fn summary(checks: &[Extrapolation]) -> Option<String> {
    let first = checks.first()?;
    let worse: Vec<String> = checks
        .iter()
        .filter(|x| x.outcome == "worse")
        .map(|x| {
            format!(
                "{} on the {} ({:.1} -> {:.1}, {:+.0} %)",
                x.channel,
                x.held_out,
                x.rms_without,
                x.rms_with,
                100.0 * (x.rms_with / x.rms_without - 1.0)
            )
        })
        .collect();
    let better = checks.iter().filter(|x| x.outcome == "better").count();
    Some(if worse.is_empty() {
        format!(
            "{} holds beyond the conditions it was fitted on: better in {better} of {} held-out \
             ends, worse in none",
            first.effect,
            checks.len()
        )
    } else {
        format!(
            "{} extrapolates WORSE than the base model in {} of {} held-out ends: {}; its \
             fitted form should not be trusted beyond the measured range of {}",
            first.effect,
            worse.len(),
            checks.len(),
            worse.join("; "),
            first.driver
        )
    })
}

/// Per-run summary of a row-level driver: the 95th percentile for "largest" drivers, else the
/// median.
fn per_run(run: &[i64], values: &[f64], largest: bool) -> BTreeMap<i64, f64> {
    let mut by_run: BTreeMap<i64, Vec<f64>> = BTreeMap::new();
    for (r, v) in run.iter().zip(values) {
        if v.is_finite() {
            by_run.entry(*r).or_default().push(*v);
        }
    }
    by_run
        .into_iter()
        .map(|(r, mut v)| {
            v.sort_by(f64::total_cmp);
            let q = if largest { 95 } else { 50 };
            (r, v[(v.len() - 1) * q / 100])
        })
        .collect()
}

/// The RMS of `model`'s residuals on the rows of `data` in `ranges` (whole runs), read in
/// place.
fn rms(model: &ChannelModel, data: &ChannelData, ranges: &[std::ops::Range<usize>]) -> f64 {
    let (mut sum, mut rows) = (0.0, 0usize);
    for r in ranges {
        let predicted = model.predictions_in(data, r.clone());
        for (p, y) in predicted.iter().zip(&data.measured[r.clone()]) {
            sum += (p - y).powi(2);
            rows += 1;
        }
    }
    (sum / rows.max(1) as f64).sqrt()
}

/// One held-out end of the runs ranked by their driver: how many runs, its label, the rows
/// the refits are fitted on (their fitting sample) and the rows scored.
struct End {
    runs: usize,
    label: String,
    train: ChannelData,
    test: Vec<std::ops::Range<usize>>,
}

/// The highest (`high`) or lowest `third` of `runs` (run id and driver level, in rising
/// order) held out of `data`.
fn end(data: &ChannelData, runs: &[(i64, f64)], third: usize, high: bool) -> End {
    let (held, label): (BTreeSet<i64>, String) = if high {
        let cut = runs[runs.len() - third].1;
        (
            runs[runs.len() - third..].iter().map(|r| r.0).collect(),
            format!("highest third (>= {cut:.3})"),
        )
    } else {
        let cut = runs[third - 1].1;
        (
            runs[..third].iter().map(|r| r.0).collect(),
            format!("lowest third (<= {cut:.3})"),
        )
    };
    let (test, train): (Vec<usize>, Vec<usize>) =
        (0..data.len()).partition(|&i| held.contains(&data.run[i]));
    End {
        runs: held.len(),
        label,
        train: data.fitting_subset(&ranges_of(&train)),
        test: ranges_of(&test),
    }
}

/// The check for `effect` on one channel whose final model `with` contains it; both refits
/// stay `admissible`, as the diagnosis's own fits do.
pub fn check(
    effect: Extension,
    data: &ChannelData,
    with: &ChannelModel,
    admissible: Admissible,
) -> Vec<Extrapolation> {
    let Some(driver) = effects::of(effect).run_driver(data) else {
        return Vec::new();
    };
    let levels = per_run(&data.run, &driver.values, driver.largest);
    let mut runs: Vec<(i64, f64)> = levels
        .into_iter()
        .filter(|(_, v)| *v > driver.floor)
        .collect();
    runs.sort_by(|a, b| a.1.total_cmp(&b.1));
    let third = runs.len() / 3;
    // At least two runs on each side, and the driver must differ between the ends.
    if third < 2 || runs[third - 1].1 >= runs[runs.len() - third].1 {
        return Vec::new();
    }
    let mut without = with.clone();
    without.effects.retain(|(e, _)| *e != effect);
    let ends: Vec<End> = [true, false]
        .into_iter()
        .map(|high| end(data, &runs, third, high))
        .collect();
    // The four refits (each end, without and with the effect) side by side, each scored on
    // its end's held-out runs.
    let jobs: Vec<(usize, &ChannelModel)> = (0..ends.len())
        .flat_map(|e| [(e, &without), (e, with)])
        .collect();
    let scored = parallel_map(&jobs, |&(e, model)| {
        let End { train, test, .. } = &ends[e];
        // What the remaining runs identify: an effect's terms of a condition they hold still
        // go back to neutral rather than extrapolate from nothing.
        let identifies = crate::method::diagnose::design::identifies(train);
        fit_channel(
            train,
            &model.restricted(identifies),
            Start::Warm,
            Some(admissible),
        )
        .map(|f| rms(&f.model, data, test))
    });
    ends.iter()
        .zip(scored.chunks(2))
        .filter_map(
            |(
                End {
                    runs, label, test, ..
                },
                rms,
            )| {
                let (rms_without, rms_with) = (rms[0]?, rms[1]?);
                Some(Extrapolation {
                    effect,
                    channel: data.channel,
                    driver: driver.name,
                    held_out: label.clone(),
                    runs: *runs,
                    rows: test.iter().map(|r| r.len()).sum(),
                    rms_without,
                    rms_with,
                    outcome: outcome(rms_without, rms_with),
                })
            },
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn end(channel: Channel, without: f64, with: f64) -> Extrapolation {
        Extrapolation {
            effect: Extension::Temperature,
            channel,
            driver: "median temperature [degC]",
            held_out: "lowest third (<= 42.5)".into(),
            runs: 4,
            rows: 400,
            rms_without: without,
            rms_with: with,
            outcome: outcome(without, with),
        }
    }

    #[test]
    fn the_check_says_in_words_where_the_effect_extrapolates_worse() {
        assert_eq!(outcome(100.0, 90.0), "better");
        assert_eq!(outcome(100.0, 101.0), "no different");
        assert_eq!(outcome(100.0, 103.0), "worse");
        let fine = summary(&[end(Channel::Fy, 200.0, 150.0), end(Channel::Mz, 5.0, 5.05)]).unwrap();
        assert!(
            fine.contains("holds") && fine.contains("better in 1 of 2"),
            "{fine}"
        );
        // The real programme's Fx: 2,122 -> 2,717 N.
        let bad = summary(&[
            end(Channel::Fx, 2122.0, 2717.0),
            end(Channel::Fy, 200.0, 150.0),
        ])
        .unwrap();
        assert!(bad.contains("WORSE") && bad.contains("1 of 2"), "{bad}");
        assert!(
            bad.contains("Fx on the lowest third") && bad.contains("+28 %"),
            "{bad}"
        );
        assert_eq!(summary(&[]), None);
    }
}
