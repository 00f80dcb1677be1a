//! What the data can support, checked before the fits: loads, rows and runs for
//! cross-validation by run, slip variation, and magnitudes that a tire can produce (a unit
//! mislabelled in the file). What cannot be estimated is an error or a named
//! [`Limitation`], never a number computed from nothing.

use std::borrow::Cow;
use std::collections::BTreeMap;

use mf87::{Channel, Params};
use serde::Serialize;

use crate::data::Dataset;
use crate::method::prepare::channel_data::{ChannelData, run_stretches};
use crate::method::prepare::cv::Folds;
use crate::method::stats::correlation;
use crate::quantiles::{median, quantile_of};

/// A part of the diagnosis the data cannot support, and why.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Limitation {
    /// What it concerns: a channel (`Fx`, `Fy`, `Mz`) or `data`.
    pub subject: String,
    pub reason: String,
}

impl Limitation {
    pub fn new(subject: impl Into<String>, reason: impl Into<String>) -> Limitation {
        Limitation {
            subject: subject.into(),
            reason: reason.into(),
        }
    }
}

/// Fewest rows of a run for its noise floor and systematic part (second differences and
/// the 5-sample average are taken within runs).
pub const MIN_RUN_ROWS: usize = 10;
/// Fewest held-out rows in each fold.
pub const MIN_FOLD_ROWS: usize = 30;
/// Fewest rows per fitted coefficient: in every fold's training rows, and on the slip curve
/// (rows with slip beyond [`MIN_SLIP`]).
pub const MIN_ROWS_PER_COEFFICIENT: usize = 10;
/// Slip beyond the linear origin, in the formula's units: 1 deg of slip angle, 1 % slip.
pub const MIN_SLIP: f64 = 1.0;
/// Largest plausible force per load: the FMU's friction bound (racing slicks on a rig's
/// abrasive belt reach about 3 at light load: FSAE tires on Calspan's rig give |Fx| / Fz up to
/// 3.4).
pub const MAX_FORCE_PER_LOAD: f64 = mf87::bounds::FRICTION_MAX;
/// Largest plausible aligning moment per load \[m\]: the FMU's lever-arm bound (pneumatic
/// trails are a few cm on cars).
pub const MAX_MOMENT_PER_LOAD_M: f64 = mf87::bounds::LEVER_ARM_MAX_M;
/// Largest plausible slope of force per load over the slip in a run that sweeps it, per deg
/// or per % (a least-squares line through the run): the stiffest tires start near 0.5 per
/// deg (30 per rad) or 0.3 per %, a racing slick at light load near 2 per deg, and the line
/// through a whole sweep lies below the tangent. A slip angle in radians under a degree unit
/// gives 57 times the real slope, a slip ratio under a percent unit 100 times.
pub const MAX_SWEEP_SLOPE: f64 = 5.0;
/// A run sweeps the channel's slip when its force follows the slip at least this closely
/// (|correlation|): a force that camber, conicity or the other slip makes does not.
pub const SWEEP_CORRELATION: f64 = 0.9;
/// Below this ratio of the 95th to the 5th percentile of the load, the load dependence of
/// the coefficients is not identified.
pub const MIN_LOAD_RATIO: f64 = 1.2;

/// The rows with load. Fz <= 0 is a lifted wheel (or a load-cell offset): the model gives
/// no force there and there is nothing to fit, so those rows are left out, with a
/// limitation saying how many. No row with load is an error.
pub fn loaded_rows(ds: &Dataset) -> Result<(Cow<'_, Dataset>, Option<Limitation>), String> {
    let keep: Vec<usize> = (0..ds.len()).filter(|&i| ds.fz[i] > 0.0).collect();
    if keep.is_empty() {
        return Err(format!(
            "{}: no row has a load (Fz > 0) in any of its {} rows: the tire carries nothing, so \
             there is no force to fit (is Fz positive in compression, in the unit its column names?)",
            ds.source,
            ds.len()
        ));
    }
    if keep.len() == ds.len() {
        return Ok((Cow::Borrowed(ds), None));
    }
    let left_out = ds.len() - keep.len();
    Ok((
        Cow::Owned(ds.select(&keep)),
        Some(Limitation::new(
            "data",
            format!(
                "{left_out} of {} rows have Fz <= 0 (wheel off the ground or a load-cell offset): \
                 left out, the model gives no force without load",
                ds.len()
            ),
        )),
    ))
}

/// Checks that cross-validation by run can be done: at least as many runs as folds (and 3),
/// runs long enough for a noise floor, enough held-out rows per fold and enough training
/// rows per fold for `coefficients` fitted coefficients.
pub fn check_runs(ds: &Dataset, folds: &Folds, coefficients: usize) -> Result<(), String> {
    let (runs, k) = (folds.runs(), folds.k);
    if runs < k.max(3) {
        let hint = if runs >= 3 {
            format!(" (with {runs} runs use --folds {runs})")
        } else {
            " (a `run` column with test block ids; a TYDEX file per run; a TTC programme is \
             split into its sweeps, so a file of fewer holds no pause and no step of load, \
             pressure, camber, speed or held slip angle: see docs/programmes.md)"
                .to_string()
        };
        return Err(format!(
            "{} holds {runs} run(s); {k}-fold cross-validation by run needs at least {} runs, \
             every fold a whole run{hint}",
            ds.source,
            k.max(3)
        ));
    }
    let mut rows_of: BTreeMap<i64, usize> = BTreeMap::new();
    for r in ds.run.iter() {
        *rows_of.entry(*r).or_default() += 1;
    }
    let in_long_runs: usize = rows_of.values().filter(|&&n| n >= MIN_RUN_ROWS).sum();
    if 2 * in_long_runs < ds.len() {
        let mut lengths: Vec<usize> = rows_of.values().copied().collect();
        lengths.sort_unstable();
        return Err(format!(
            "{}: the noise floor cannot be measured: most rows sit in runs of fewer than \
             {MIN_RUN_ROWS} rows (median {} rows per run, {runs} runs); it is taken from \
             consecutive samples within a run. A run is one test block of consecutive samples: \
             are the run ids given per row?",
            ds.source,
            lengths[lengths.len() / 2]
        ));
    }
    let min_training = MIN_ROWS_PER_COEFFICIENT * coefficients;
    for fold in 0..k {
        let (train, test) = folds.split_ranges(&ds.run, fold);
        let rows = |ranges: Vec<std::ops::Range<usize>>| ranges.iter().map(|r| r.len()).sum();
        let (train, test): (usize, usize) = (rows(train), rows(test));
        if test < MIN_FOLD_ROWS || train < min_training {
            return Err(format!(
                "{}: too few rows for {k}-fold cross-validation: fold {} holds {} held-out rows \
                 (at least {MIN_FOLD_ROWS}) and {} training rows (at least {min_training}, \
                 {MIN_ROWS_PER_COEFFICIENT} per fitted coefficient); {} rows in all",
                ds.source,
                fold + 1,
                test,
                train,
                ds.len()
            ));
        }
    }
    Ok(())
}

/// Coefficients fitted for a channel: all of them, the camber ones only when camber varies.
pub fn fitted_coefficients(data: &ChannelData) -> usize {
    let all = Params::coefficient_names(data.channel).len();
    match data.channel {
        Channel::Fy | Channel::Mz if !data.has_camber() => all - 5,
        _ => all,
    }
}

/// What the channel's slip is called and in which unit it is held here.
fn slip_words(channel: Channel) -> (&'static str, &'static str, &'static str) {
    match channel {
        // (name, unit, what a mislabelled file would hold and how to say it)
        Channel::Fx => (
            "slip",
            "%",
            "a slip ratio under a percent unit: give it as a ratio (kappa, or 1 in TYDEX)",
        ),
        Channel::Fy | Channel::Mz => (
            "slip angle",
            "deg",
            "radians under a degree unit: give the unit as rad (alpha_rad, or rad in TYDEX)",
        ),
    }
}

/// The channel's force (or moment) per load, 99th percentile over the rows of at least a
/// quarter of the median load; why it is beyond any tire, when it is.
fn load_share(data: &ChannelData) -> Result<f64, String> {
    let channel = data.channel;
    let Some(median_load) = quantile_of(|| data.fz_kn.iter().copied(), 0.5) else {
        return Err(format!("{channel}: no finite load"));
    };
    let per_load = || {
        data.measured
            .iter()
            .zip(data.fz_kn.iter())
            .filter(|(_, fz)| **fz >= 0.25 * median_load)
            .map(|(y, fz)| y.abs() / mf87::units::kilonewtons_to_newtons(*fz))
    };
    let load_share = quantile_of(per_load, 0.99).unwrap_or(0.0);
    let (cap, unit) = match channel {
        Channel::Mz => (MAX_MOMENT_PER_LOAD_M, " m times"),
        Channel::Fx | Channel::Fy => (MAX_FORCE_PER_LOAD, " times"),
    };
    if load_share > cap {
        return Err(format!(
            "{channel} reaches {load_share:.3}{unit} the load Fz (99th percentile over the loaded \
             rows), more than any tire gives (at most {cap}{unit}): are {channel} and Fz in the \
             units their columns name?"
        ));
    }
    Ok(load_share)
}

/// The slope of force per load over slip in the runs that sweep the slip (median over those
/// runs, with their number); `None` when no run sweeps it.
fn sweep_slope(data: &ChannelData) -> Option<(f64, usize)> {
    let slopes: Vec<f64> = run_stretches(&data.run)
        .values()
        .map(|stretches| {
            stretches
                .iter()
                .flat_map(|r| r.clone())
                .collect::<Vec<usize>>()
        })
        .filter(|rows| rows.len() >= MIN_RUN_ROWS)
        .filter_map(|rows| {
            let x: Vec<f64> = rows.iter().map(|&i| data.slip[i]).collect();
            let y: Vec<f64> = rows.iter().map(|&i| data.measured[i]).collect();
            let r = correlation(&x, &y)?;
            let load = rows.iter().map(|&i| data.fz_kn[i]).sum::<f64>() / rows.len() as f64;
            (r.abs() >= SWEEP_CORRELATION && load > 0.0).then(|| {
                let slope = r * std_dev(&y) / std_dev(&x);
                slope.abs() / mf87::units::kilonewtons_to_newtons(load)
            })
        })
        .collect();
    Some((median(&slopes)?, slopes.len()))
}

fn std_dev(v: &[f64]) -> f64 {
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
}

/// Why the channel's magnitudes are beyond any tire, when they are: a force beyond any
/// friction, or a slip whose unit its sweeps doubt ([`slip_unit_doubt`]).
fn implausible_magnitudes(data: &ChannelData) -> Option<String> {
    match load_share(data) {
        Err(why) => Some(why),
        Ok(_) => slip_unit_doubt(data),
    }
}

/// Why the unit of the slip of Fx or Fy is doubted, when it is: in the runs whose force
/// follows the slip (its own sweeps), a slope of force per load over slip steeper than any
/// tire's. `None` for Mz (whose slip angle is Fy's) and when no run sweeps the slip.
pub fn slip_unit_doubt(data: &ChannelData) -> Option<String> {
    let channel = data.channel;
    let (slip_name, slip_unit, mislabel) = slip_words(channel);
    let (slope, runs) = sweep_slope(data).filter(|_| channel != Channel::Mz)?;
    (slope > MAX_SWEEP_SLOPE).then(|| {
        format!(
            "in the {runs} runs whose {channel} follows the {slip_name} (|correlation| >= \
             {SWEEP_CORRELATION}), {channel} changes by {slope:.1} times the load per \
             {slip_unit} of {slip_name} (median), steeper than any tire (at most \
             {MAX_SWEEP_SLOPE}); the {slip_name} looks like {mislabel}"
        )
    })
}

/// Checks one measured channel; a limitation when it cannot be diagnosed: its magnitudes
/// are beyond any tire (a unit mislabelled in the file, judged on the channel's own sweeps),
/// or its slip barely leaves the origin, in all data or in some fold's training runs, so the
/// slip curve cannot be fitted (or not without the runs it is held out on).
pub fn check_channel(data: &ChannelData, folds: &Folds) -> Option<Limitation> {
    let channel = data.channel;
    if let Some(why) = implausible_magnitudes(data) {
        return Some(Limitation::new(
            channel.name(),
            format!("not diagnosed, implausible: {why}"),
        ));
    }
    let (slip_name, slip_unit, _) = slip_words(channel);
    let abs_slip = || data.slip.iter().map(|s| s.abs());
    let slip_reach = quantile_of(abs_slip, 0.99).unwrap_or(0.0);
    let coefficients = fitted_coefficients(data);
    let needed = MIN_ROWS_PER_COEFFICIENT * coefficients;
    // Rows on the slip curve per fold.
    let mut on_curve_in = vec![0usize; folds.k];
    for (s, r) in abs_slip().zip(data.run.iter()) {
        if s >= MIN_SLIP {
            on_curve_in[folds.fold_of(*r)] += 1;
        }
    }
    let on_curve: usize = on_curve_in.iter().sum();
    if on_curve < needed {
        return Some(Limitation::new(
            channel.name(),
            format!(
                "not diagnosed: only {on_curve} rows have a {slip_name} of at least {MIN_SLIP} \
                 {slip_unit} (99th percentile of |{slip_name}|: {slip_reach:.3} {slip_unit}); \
                 its slip curve has {coefficients} coefficients and needs at least {needed}"
            ),
        ));
    }
    if let Some((fold, training)) = on_curve_in
        .iter()
        .enumerate()
        .map(|(f, n)| (f, on_curve - n))
        .find(|(_, training)| *training < needed)
    {
        return Some(Limitation::new(
            channel.name(),
            format!(
                "not diagnosed: its slip curve is swept in too few runs to hold one out: without \
                 fold {}'s runs only {training} rows have a {slip_name} of at least {MIN_SLIP} \
                 {slip_unit}, fewer than the {needed} its {coefficients} coefficients need (more \
                 runs that sweep the {slip_name} would let it be scored on held-out runs)",
                fold + 1
            ),
        ));
    }
    None
}

/// A limitation when the load barely varies: the load terms of the coefficients are then
/// not identified, and the fitted model holds near that load only.
pub fn load_range(ds: &Dataset) -> Option<Limitation> {
    let fz = || ds.fz.iter().copied();
    let (lo, hi) = (quantile_of(fz, 0.05)?, quantile_of(fz, 0.95)?);
    (hi < MIN_LOAD_RATIO * lo).then(|| {
        Limitation::new(
            "data",
            format!(
                "the load barely varies (5th to 95th percentile {lo:.0} to {hi:.0} N): the load \
                 dependence of the coefficients is not identified; the fitted model holds near \
                 this load only"
            ),
        )
    })
}

/// Whether a channel's noise floor was measured: finite, and above zero unless the residual
/// itself is zero (a floor of exactly zero under a non-zero residual means the samples are
/// quantized or repeated, not noise-free).
pub fn noise_floor_limitation(channel: Channel, noise: f64, rms: f64) -> Option<Limitation> {
    (!(noise.is_finite() && (noise > 0.0 || rms == 0.0))).then(|| {
        Limitation::new(
            channel.name(),
            format!(
                "not diagnosed: its noise floor cannot be measured (the scale of the held-out \
                 residual's second differences within runs is {noise}; are the samples \
                 repeated or quantized?), so no gap or gain can be judged against it"
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel_data(
        channel: Channel,
        slip: Vec<f64>,
        fz_n: f64,
        measured: Vec<f64>,
    ) -> ChannelData {
        let n = slip.len();
        let ds = Dataset {
            source: "t".into(),
            run: (0..n).map(|i| (i / 50) as i64).collect(),
            fz: vec![fz_n; n].into(),
            alpha: Some(slip.iter().map(|s| s.to_radians()).collect()),
            kappa: Some(slip.iter().map(|s| s / 100.0).collect()),
            fx: Some(measured.clone().into()),
            fy: Some(measured.clone().into()),
            mz: Some(measured.into()),
            ..Dataset::default()
        };
        ChannelData::from_dataset(&ds, channel).unwrap()
    }

    /// A sweep of +-`reach` deg with a tanh-shaped force reaching `mu` Fz.
    fn sweep(reach: f64, mu: f64, fz: f64) -> (Vec<f64>, Vec<f64>) {
        let slip: Vec<f64> = (0..400)
            .map(|i| reach * ((i as f64) / 20.0).sin())
            .collect();
        let force = slip.iter().map(|s| mu * fz * (s / 3.0).tanh()).collect();
        (slip, force)
    }

    fn check(d: &ChannelData) -> Option<Limitation> {
        check_channel(d, &Folds::new(&d.run, 5, 1))
    }

    #[test]
    fn a_real_sweep_passes() {
        let (slip, force) = sweep(12.0, 1.0, 4000.0);
        let d = channel_data(Channel::Fy, slip, 4000.0, force);
        assert_eq!(check(&d), None);
    }

    #[test]
    fn a_slip_curve_swept_in_one_run_cannot_be_held_out() {
        // 8 runs of 50 rows; only the first two sweep the slip angle.
        let (mut slip, force) = sweep(12.0, 1.0, 4000.0);
        slip[100..].iter_mut().for_each(|s| *s = 0.0);
        let mut d = channel_data(Channel::Fy, slip.clone(), 4000.0, force.clone());
        d.measured = force
            .iter()
            .zip(&slip)
            .map(|(f, s)| if *s == 0.0 { 0.0 } else { *f })
            .collect();
        let l = check(&d).expect("a limitation");
        assert!(
            l.reason.contains("swept in too few runs to hold one out"),
            "{l:?}"
        );
        assert!(l.reason.contains("without fold"), "{l:?}");
    }

    #[test]
    fn radians_under_a_degree_label_are_named() {
        // The same sweep with its slip angle written in radians but read as degrees.
        let (slip, force) = sweep(12.0, 1.0, 4000.0);
        let slip = slip.iter().map(|s| s.to_radians()).collect();
        let l = check(&channel_data(Channel::Fy, slip, 4000.0, force)).expect("a limitation");
        assert_eq!(l.subject, "Fy");
        assert!(
            l.reason
                .starts_with("not diagnosed, implausible: in the 5 runs whose Fy follows")
                && l.reason.contains("looks like radians under a degree unit"),
            "{l:?}"
        );
    }

    #[test]
    fn a_force_that_camber_makes_at_zero_slip_is_no_unit_doubt() {
        // Camber thrust of 0.3 Fz with the slip angle at 0 +- 0.03 deg of noise: the force
        // does not follow the slip, so the slip's unit is not judged by it.
        let slip: Vec<f64> = (0..400)
            .map(|i| 0.03 * ((i * 7919 % 97) as f64 / 48.0 - 1.0))
            .collect();
        let force = (0..400)
            .map(|i| 1200.0 + 40.0 * (i as f64 / 30.0).sin())
            .collect();
        let d = channel_data(Channel::Fy, slip, 4000.0, force);
        let l = check(&d).expect("no slip curve to fit");
        assert!(l.reason.contains("only 0 rows have a slip angle"), "{l:?}");
    }

    #[test]
    fn force_beyond_any_friction_is_named() {
        // Load in kN written under an N label: forces 1000 times the load.
        let (slip, force) = sweep(12.0, 1.0, 4000.0);
        let l = check(&channel_data(Channel::Fy, slip, 4.0, force)).expect("a limitation");
        assert!(
            l.reason
                .starts_with("not diagnosed, implausible: Fy reaches 999.")
                && l.reason.contains("times the load Fz"),
            "{l:?}"
        );
    }

    #[test]
    fn no_slip_is_a_limitation_not_a_verdict() {
        let d = channel_data(Channel::Fx, vec![0.0; 400], 4000.0, vec![15.0; 400]);
        let l = check(&d).expect("a limitation");
        assert_eq!(l.subject, "Fx");
        assert!(
            l.reason.contains("only 0 rows have a slip of at least 1 %"),
            "{l:?}"
        );
        assert!(l.reason.contains("needs at least 90"), "{l:?}");
    }

    #[test]
    fn rows_without_load_are_left_out_or_refused() {
        let ds = Dataset {
            source: "t".into(),
            run: vec![1, 1, 2].into(),
            fz: vec![3000.0, -5.0, 0.0].into(),
            ..Dataset::default()
        };
        let (kept, note) = loaded_rows(&ds).unwrap();
        assert_eq!(kept.fz, vec![3000.0].into());
        assert_eq!(kept.run, vec![1].into());
        assert!(note.unwrap().reason.starts_with("2 of 3 rows have Fz <= 0"));
        let none = Dataset {
            fz: vec![0.0, -1.0].into(),
            run: vec![1, 2].into(),
            ..ds
        };
        assert!(
            loaded_rows(&none)
                .unwrap_err()
                .contains("no row has a load")
        );
    }

    #[test]
    fn runs_and_folds_are_checked() {
        let ds = |runs: usize, rows_per_run: usize| Dataset {
            source: "t".into(),
            run: (0..runs * rows_per_run)
                .map(|i| (i / rows_per_run) as i64)
                .collect(),
            fz: vec![3000.0; runs * rows_per_run].into(),
            ..Dataset::default()
        };
        let check = |d: &Dataset, k: usize| check_runs(d, &Folds::new(&d.run, k, 1), 14);
        assert!(check(&ds(20, 100), 5).is_ok());
        // 3 runs cannot fill 5 folds; the hint names the folds they can.
        let e = check(&ds(3, 100), 5).unwrap_err();
        assert!(
            e.contains("holds 3 run(s); 5-fold") && e.contains("--folds 3"),
            "{e}"
        );
        // One row per run: no noise floor.
        let e = check(&ds(400, 1), 5).unwrap_err();
        assert!(e.contains("the noise floor cannot be measured"), "{e}");
        assert!(e.contains("median 1 rows per run"), "{e}");
        // Runs long enough, but too few rows to fit 14 coefficients per fold.
        let e = check(&ds(5, 20), 5).unwrap_err();
        assert!(e.contains("too few rows for 5-fold"), "{e}");
    }

    #[test]
    fn narrow_load_range_is_a_limitation() {
        let mut ds = Dataset {
            fz: (0..100).map(|i| 4000.0 + i as f64).collect(),
            ..Dataset::default()
        };
        assert!(load_range(&ds).unwrap().reason.contains("barely varies"));
        ds.fz = (0..100).map(|i| 2000.0 + 50.0 * i as f64).collect();
        assert_eq!(load_range(&ds), None);
    }

    #[test]
    fn noise_floor_must_be_measured() {
        assert!(noise_floor_limitation(Channel::Fy, f64::NAN, 3.0).is_some());
        assert!(noise_floor_limitation(Channel::Fy, 0.0, 3.0).is_some());
        assert!(noise_floor_limitation(Channel::Fy, 0.0, 0.0).is_none());
        assert!(noise_floor_limitation(Channel::Fy, 2.0, 3.0).is_none());
    }
}
