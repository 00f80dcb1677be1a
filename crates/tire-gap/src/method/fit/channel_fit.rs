//! Step 1 and 2 of the method: fit the 1987 model to the data, and measure its error on
//! held-out runs against the measurement noise floor.

use std::collections::BTreeMap;

use mf87::Channel;
use serde::Serialize;

use crate::method::fit::least_squares::{FULL_BUDGET, least_squares};
use crate::method::fit::model::ChannelModel;
use crate::method::parallel::{parallel_for_each, parallel_map};
use crate::method::prepare::channel_data::ChannelData;
use crate::method::prepare::cv::{Folds, Stretch, run_pieces, training_rows};
use crate::method::stats::mean_square;
use crate::quantiles::order_statistic;
use nalgebra::DMatrix;

/// Multi-start: the start with its peak matched to the data, scaled by (peak, stiffness).
/// The measured tire is not the paper's: its friction and stiffness may differ a lot.
const STARTS: [(f64, f64); 4] = [(1.0, 1.0), (1.0, 0.6), (1.0, 1.6), (0.8, 1.0)];

/// Weight of the pull toward the start, relative to the data's root sum of squares.
const PRIOR_WEIGHT: f64 = 0.003;
/// Coefficients smaller than this are pulled on this absolute scale instead.
const PRIOR_MIN_SCALE: f64 = 0.1;

/// A fitted channel.
#[derive(Debug, Clone)]
pub struct ChannelFit {
    /// The model with the fitted parameters.
    pub model: ChannelModel,
}

impl ChannelFit {
    /// The root mean square of the residuals over every row of `data` (0 on rows it does not
    /// count), predicted a piece of whole runs at a time, the pieces in parallel: no row's
    /// prediction is kept past its piece.
    pub fn rms(&self, data: &ChannelData) -> f64 {
        let counted = |i: usize| data.counted.as_ref().is_none_or(|c| c[i]);
        let sums = parallel_map(&run_pieces(&data.run, PIECE_ROWS), |rows| {
            let predicted = self.model.predictions_in(data, rows.clone());
            rows.clone()
                .zip(predicted)
                .filter(|&(i, _)| counted(i))
                .map(|(i, p)| (p - data.measured[i]).powi(2))
                .sum::<f64>()
        });
        (sums.iter().sum::<f64>() / data.len().max(1) as f64).sqrt()
    }
}

/// Where a fit starts and how long it may run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// From the model's parameters and from scaled versions of them with the peak first
    /// matched to the data (the measured tire may differ a lot from the start).
    Multi,
    /// From the model's parameters, to convergence.
    Warm,
    /// From the model's parameters already near the optimum, on a short budget
    /// (`POLISH_BUDGET`; with the exact Jacobian, up to 3 (parameters + 1) iterations).
    Polish,
}

/// Evaluation budget of a polishing refit (see `fit::least_squares`).
const POLISH_BUDGET: usize = 3;

/// Whether a model may be the fit's answer (the FMU accepts it over the data's range).
pub type Admissible<'a> = &'a (dyn Fn(&ChannelModel) -> bool + Sync);

/// Fits all free parameters of `start` to one channel's rows (at most `FIT_ROWS_MAX` of
/// them, see [`ChannelData::fitting_sample`]). With `admissible`, the fit from each admissible
/// start stays admissible, and the best admissible fit is taken; only if no start is
/// admissible are the fits unconstrained.
pub fn fit_channel(
    all: &ChannelData,
    start: &ChannelModel,
    from: Start,
    admissible: Option<Admissible>,
) -> Option<ChannelFit> {
    let sample = all.fitting_sample();
    let data: &ChannelData = &sample;
    let theta0 = start.theta();
    // The positions the fit moves (the effects' held terms stay), the others as in `theta0`.
    let moved = start.fitted();
    let full = |sub: &[f64]| {
        let mut theta = theta0.clone();
        for (&p, &v) in moved.iter().zip(sub) {
            theta[p] = v;
        }
        theta
    };
    let starts = starts_of(start, data, from, &moved);
    // A weak pull of each base coefficient toward its start keeps flat directions of the
    // formula (e.g. a4 and a5 of Fy trading off at small a5 Fz) from wandering: a relative
    // change of 1 costs PRIOR_WEIGHT^2 of the data's sum of squares.
    let n_base = start.free.len();
    let weight = PRIOR_WEIGHT * data.measured.iter().map(|y| y * y).sum::<f64>().sqrt();
    let m = data.len();
    let budget = if from == Start::Polish {
        POLISH_BUDGET
    } else {
        FULL_BUDGET
    };
    let admits = |sub: &[f64]| admissible.is_none_or(|a| a(&start.updated(&full(sub))));
    let any_admissible = starts.iter().any(|x0| admits(x0));
    let tried: Vec<&Vec<f64>> = starts
        .iter()
        .filter(|x0| !any_admissible || admits(x0))
        .collect();
    // The base coefficients lead the parameter vector and are all moved. The starts side by
    // side; of equal fits, the first start's, as one after the other.
    parallel_map(&tried, |x0| {
        let scale = |j: usize| x0[j].abs().max(PRIOR_MIN_SCALE);
        let residuals = |sub: &[f64], out: &mut [f64]| {
            start.residuals(&full(sub), data, out);
            for j in 0..n_base {
                out[m + j] = weight * (sub[j] - x0[j]) / scale(j);
            }
        };
        let jacobian = |sub: &[f64], jac: &mut DMatrix<f64>| {
            // Rows m.. (the pull) are zero but for their own coefficient.
            for j in 0..n_base {
                jac[(m + j, j)] = weight / scale(j);
            }
            start.jacobian(&full(sub), &moved, data, jac)
        };
        least_squares(
            x0,
            m + n_base,
            budget,
            &residuals,
            Some(&jacobian),
            any_admissible.then_some(&admits as _),
        )
    })
    .into_iter()
    .flatten()
    .min_by(|a, b| a.sse.total_cmp(&b.sse))
    .map(|fit| ChannelFit {
        model: start.updated(&full(&fit.params)),
    })
}

/// The starts of a fit of `start` to `data` (several with [`Start::Multi`], else its own
/// parameters), each as the values of the positions `moved`.
fn starts_of(
    start: &ChannelModel,
    data: &ChannelData,
    from: Start,
    moved: &[usize],
) -> Vec<Vec<f64>> {
    let starts: Vec<Vec<f64>> = if from == Start::Multi {
        let peak_ratio = peak_ratio(start, data);
        STARTS
            .iter()
            .map(|&(peak, stiffness)| scaled_start(start, peak * peak_ratio, stiffness))
            .collect()
    } else {
        vec![start.theta()]
    };
    starts
        .iter()
        .map(|t| moved.iter().map(|&p| t[p]).collect())
        .collect()
}

/// Fits only the parameters at `positions` of `start`'s parameter vector (but the effects'
/// held terms), the rest held (on at most `FIT_ROWS_MAX` rows, as [`fit_channel`]). With
/// `admissible` and an admissible start, the fit stays admissible.
pub fn fit_some(
    all: &ChannelData,
    start: &ChannelModel,
    positions: &[usize],
    admissible: Option<Admissible>,
) -> Option<ChannelFit> {
    let sample = all.fitting_sample();
    let data: &ChannelData = &sample;
    let base = start.theta();
    let held = start.held();
    let positions: Vec<usize> = positions
        .iter()
        .copied()
        .filter(|p| !held.contains(p))
        .collect();
    let positions = positions.as_slice();
    let full = |sub: &[f64]| {
        let mut theta = base.clone();
        for (&p, &v) in positions.iter().zip(sub) {
            theta[p] = v;
        }
        theta
    };
    let residuals = |sub: &[f64], out: &mut [f64]| start.residuals(&full(sub), data, out);
    let x0: Vec<f64> = positions.iter().map(|&p| base[p]).collect();
    let jacobian =
        |sub: &[f64], jac: &mut DMatrix<f64>| start.jacobian(&full(sub), positions, data, jac);
    // Within the bounds when the start is (a fit from outside them cannot be held to them).
    let admits = |sub: &[f64]| admissible.is_none_or(|a| a(&start.updated(&full(sub))));
    let bounded = admissible.is_some() && admits(&x0);
    let fit = least_squares(
        &x0,
        data.len(),
        FULL_BUDGET,
        &residuals,
        Some(&jacobian),
        bounded.then_some(&admits as _),
    )?;
    Some(ChannelFit {
        model: start.updated(&full(&fit.params)),
    })
}

/// `model` with its base coefficients (the 1987 formula's) back at the paper's, their peak
/// matched to the data's as the base fit's first start is; its effects as they are. A start
/// from which a fit with a new term is not held in the basin a fit without it settled in (a
/// base bent to absorb a shift it had no term for).
pub fn restarted(model: &ChannelModel, data: &ChannelData) -> ChannelModel {
    let paper = mf87::Params::paper_table();
    let coefficients: Vec<f64> = (model.free.iter())
        .zip(model.theta())
        .map(|(&i, own)| paper.coefficient(model.channel, i).unwrap_or(own))
        .collect();
    let mut fresh = model.clone();
    fresh.params = model.params_with(&coefficients);
    let matched = scaled_start(&fresh, peak_ratio(&fresh, data), 1.0);
    fresh.updated(&matched)
}

/// Ratio of the measured to the modelled peak magnitude (98th percentiles).
fn peak_ratio(model: &ChannelModel, data: &ChannelData) -> f64 {
    let predicted = model.predictions(data);
    let q = |v: &[f64]| {
        let mut a: Vec<f64> = v
            .iter()
            .map(|x| x.abs())
            .filter(|x| x.is_finite())
            .collect();
        let k = a.len() * 98 / 100;
        match k < a.len() {
            true => order_statistic(&mut a, k),
            false => 0.0,
        }
    };
    let (measured, modelled) = (q(&data.measured), q(&predicted));
    if measured > 0.0 && modelled > 0.0 {
        measured / modelled
    } else {
        1.0
    }
}

/// The model's parameters with the peak D scaled by `peak` and the stiffness BCD by
/// `stiffness` (a1, a2 scale D; a3 scales BCD for Fy; a3, a4 for Mz and Fx).
fn scaled_start(model: &ChannelModel, peak: f64, stiffness: f64) -> Vec<f64> {
    let names = mf87::Params::coefficient_names(model.channel);
    let bcd: &[&str] = match model.channel {
        Channel::Fy => &["a3"],
        Channel::Mz | Channel::Fx => &["a3", "a4"],
    };
    let mut theta = model.theta();
    for (pos, &i) in model.free.iter().enumerate() {
        match names[i] {
            "a1" | "a2" => theta[pos] *= peak,
            n if bcd.contains(&n) => theta[pos] *= stiffness,
            _ => {}
        }
    }
    theta
}

/// Per-channel error measures.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ErrorSummary {
    /// Root mean square error [N or N.m].
    pub rms: f64,
    /// Root mean square of error / load [1 for forces, m for the moment].
    pub rms_per_load: f64,
    pub rows: usize,
}

impl ErrorSummary {
    /// The residuals may be stored in single precision; the sums are taken in double.
    pub fn of<R: Copy + Into<f64>>(residuals: &[R], fz_kn: &[f64]) -> ErrorSummary {
        let n = residuals.len().max(1) as f64;
        let value = |r: &R| -> f64 { (*r).into() };
        let rms = (residuals.iter().map(|r| value(r).powi(2)).sum::<f64>() / n).sqrt();
        let per_load = residuals
            .iter()
            .zip(fz_kn)
            .filter(|(_, f)| **f > 0.0)
            .map(|(r, f)| (value(r) / mf87::units::kilonewtons_to_newtons(*f)).powi(2))
            .sum::<f64>();
        ErrorSummary {
            rms,
            rms_per_load: (per_load / n).sqrt(),
            rows: residuals.len(),
        }
    }
}

/// Per-run mean squared residual (finite rows only; runs without any are left out).
pub fn per_run_mse(run: &[i64], residuals: &[f64]) -> BTreeMap<i64, f64> {
    let n = run.len().min(residuals.len());
    let mut sums = RunSquares::default();
    for rows in run_stretches(&run[..n]) {
        sums.add(run[rows.start], residuals[rows].iter().copied());
    }
    sums.means()
}

/// The rows of `run` as stretches of consecutive rows of one run each.
pub fn run_stretches(run: &[i64]) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    let mut start = 0;
    std::iter::from_fn(move || {
        let first = *run.get(start)?;
        let end = start + run[start..].iter().take_while(|&&r| r == first).count();
        Some(std::mem::replace(&mut start, end)..end)
    })
}

/// Per run, the sum of squares of its finite values and their count, added in row order (a
/// run's sum is looked up once per stretch of its rows, not once per row).
#[derive(Debug, Default)]
pub struct RunSquares(BTreeMap<i64, (f64, usize)>);

impl RunSquares {
    /// Adds the squares of the finite `values` of run `run`.
    pub fn add(&mut self, run: i64, values: impl Iterator<Item = f64>) {
        let sum = self.0.entry(run).or_default();
        for e in values.filter(|e| e.is_finite()) {
            sum.0 += e * e;
            sum.1 += 1;
        }
    }

    /// Each run's mean square (runs without a finite value left out).
    pub fn means(self) -> BTreeMap<i64, f64> {
        self.0
            .into_iter()
            .filter(|(_, (_, n))| *n > 0)
            .map(|(r, (s, n))| (r, s / n as f64))
            .collect()
    }
}

/// Rows predicted together in the held-out residuals: enough to amortise a piece's set-up,
/// few enough that its columns stay in cache and the pieces spread over the cores.
const PIECE_ROWS: usize = 16_384;

/// A held-out residual as stored: in double precision, or in single where it is only
/// scored (see [`crate::method::stats::CompactResiduals`]).
pub trait Residual: Copy + Send + Sync {
    fn of(x: f64) -> Self;
}

impl Residual for f64 {
    fn of(x: f64) -> Self {
        x
    }
}

impl Residual for f32 {
    fn of(x: f64) -> Self {
        x as f32
    }
}

/// Models fitted per fold and the held-out residuals (measured minus predicted) of every
/// row, each predicted by the model of its fold, fitted on the other folds by
/// `fit(training rows, fold)` (their fitting sample, see [`ChannelData::fitting_subset`]).
pub fn cross_validate<T: Residual>(
    data: &ChannelData,
    folds: &Folds,
    fit: impl Fn(&ChannelData, usize) -> Option<ChannelModel> + Sync,
) -> Option<(Vec<ChannelModel>, Vec<T>)> {
    let stretches = folds.stretches(&data.run, PIECE_ROWS);
    let models: Vec<ChannelModel> = fold_models(folds, |fold| {
        fit(&data.fitting_subset(&training_rows(&stretches, fold)), fold)
    })?;
    let residuals = residuals_of(data, &stretches, &models);
    Some((models, residuals))
}

/// `model(fold)` of every fold, the folds in parallel; `None` when one is `None`.
fn fold_models(
    folds: &Folds,
    model: impl Fn(usize) -> Option<ChannelModel> + Sync,
) -> Option<Vec<ChannelModel>> {
    let each: Vec<usize> = (0..folds.k).collect();
    parallel_map(&each, |&fold| model(fold))
        .into_iter()
        .collect()
}

/// The held-out residuals (measured minus predicted) of every row, each predicted by
/// `model(fold)` for its fold (the folds in parallel).
pub fn held_out<T: Residual>(
    data: &ChannelData,
    folds: &Folds,
    model: impl Fn(usize) -> Option<ChannelModel> + Sync,
) -> Option<Vec<T>> {
    let models = fold_models(folds, model)?;
    Some(residuals_of(
        data,
        &folds.stretches(&data.run, PIECE_ROWS),
        &models,
    ))
}

/// The held-out residuals of every row, predicted by `models[fold]` for its fold, a
/// stretch of rows at a time (the stretches in parallel). A stretch holds whole runs, so a
/// lagged slip has the same history as in its fold's rows predicted together.
fn residuals_of<T: Residual>(
    data: &ChannelData,
    stretches: &[Stretch],
    models: &[ChannelModel],
) -> Vec<T> {
    let mut out = vec![T::of(0.0); data.len()];
    // The stretches are consecutive and cover every row: each fills its own part of `out`.
    let mut pieces: Vec<(&Stretch, &mut [T])> = Vec::with_capacity(stretches.len());
    let mut rest = out.as_mut_slice();
    for s in stretches {
        let (mine, after) = rest.split_at_mut(s.rows.len());
        pieces.push((s, mine));
        rest = after;
    }
    parallel_for_each(&mut pieces, |(s, mine)| {
        let predicted = models[s.fold].predictions_in(data, s.rows.clone());
        let measured = &data.measured[s.rows.clone()];
        for ((r, y), p) in mine.iter_mut().zip(measured).zip(predicted) {
            *r = T::of(y - p);
        }
    });
    out
}

/// The noise floor of a series within runs [its unit]: the robust (median absolute deviation)
/// scale of second differences of consecutive samples, divided by sqrt(6) (the second
/// difference of white noise has variance 6 sigma^2). Applied to residuals, it measures their
/// white part: sensor noise on the force and the noise of the measured slip and load carried
/// through the model, which no tire effect can explain. It assumes the systematic part is
/// smooth at the sampling rate; steps between runs are left out.
pub fn noise_floor<T: Copy + Into<f64>>(run: &[i64], series: &[T]) -> f64 {
    let y = |i: usize| -> f64 { series[i].into() };
    let mut d2: Vec<f64> = (1..series.len().saturating_sub(1))
        .filter(|&i| run[i - 1] == run[i] && run[i] == run[i + 1])
        .map(|i| (y(i + 1) - 2.0 * y(i) + y(i - 1)).abs())
        .filter(|d| d.is_finite())
        .collect();
    if d2.is_empty() {
        return f64::NAN;
    }
    let middle = d2.len() / 2;
    let median = order_statistic(&mut d2, middle);
    1.4826 * median / 6f64.sqrt()
}

/// Samples averaged (centred, within runs) to take the systematic part of a residual.
pub const SMOOTHING_WINDOW: usize = 5;

/// The systematic part of a residual series: a centred moving average over
/// [`SMOOTHING_WINDOW`] samples within each run. It keeps what a tire effect could explain
/// (smooth in time) and divides the variance of white noise by the window length. The
/// residuals may be stored in single precision; the averages are taken in double.
pub fn systematic<T: Copy + Into<f64>>(run: &[i64], residuals: &[T]) -> Vec<f64> {
    systematic_values(run, residuals).collect()
}

/// The mean square of [`systematic`] (its finite values, as [`crate::method::stats::mse`]), the same number,
/// without the series held in memory.
pub fn systematic_mse<T: Copy + Into<f64>>(run: &[i64], residuals: &[T]) -> f64 {
    mean_square(systematic_values(run, residuals))
}

/// The values of [`systematic`], one row after the other.
fn systematic_values<'a, T: Copy + Into<f64>>(
    run: &'a [i64],
    residuals: &'a [T],
) -> impl Iterator<Item = f64> + 'a {
    let half = SMOOTHING_WINDOW / 2;
    let n = residuals.len();
    (0..n).map(move |i| {
        let lo = (i.saturating_sub(half)..i)
            .rev()
            .take_while(|&j| run[j] == run[i])
            .last()
            .unwrap_or(i);
        let hi = (i + 1..(i + half + 1).min(n))
            .take_while(|&j| run[j] == run[i])
            .last()
            .unwrap_or(i);
        let window = &residuals[lo..=hi];
        window.iter().map(|x| (*x).into()).sum::<f64>() / window.len() as f64
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Dataset;
    use mf87::Params;

    /// A tire that is not the paper's: stiffer and with less grip, plus noise.
    fn measured(noise: f64) -> Dataset {
        let mut truth = Params::paper_table();
        truth.Fy.a1 *= 0.85;
        truth.Fy.a2 *= 0.85;
        truth.Fy.a3 *= 1.3;
        let mut ds = Dataset::default();
        let mut seed = 7u64;
        let mut gauss = || {
            // Sum of uniforms: approximately normal, deterministic.
            (0..12)
                .map(|_| {
                    seed = seed
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    (seed >> 11) as f64 / (1u64 << 53) as f64
                })
                .sum::<f64>()
                - 6.0
        };
        let (mut runs, mut fzs, mut alphas, mut fys) = (vec![], vec![], vec![], vec![]);
        for (run, fz) in [1500.0, 3000.0, 4500.0, 6000.0, 2500.0, 5000.0]
            .iter()
            .enumerate()
        {
            for i in 0..400 {
                let alpha = (12.0 * ((i as f64) / 200.0 - 1.0)).to_radians();
                let o = mf87::evaluate(
                    &truth,
                    &mf87::Inputs {
                        fz: *fz,
                        alpha,
                        kappa: 0.0,
                        gamma: 0.0,
                    },
                    mf87::SignConvention::Paper,
                );
                runs.push(run as i64);
                fzs.push(*fz);
                alphas.push(alpha);
                fys.push(o.fy + noise * gauss());
            }
        }
        (ds.run, ds.fz) = (runs.into(), fzs.into());
        (ds.alpha, ds.fy) = (Some(alphas.into()), Some(fys.into()));
        ds
    }

    fn nominal() -> crate::method::fit::effects::Nominal {
        crate::method::fit::effects::Nominal {
            pressure_kpa: 220.0,
            speed_mps: 15.0,
            temperature_c: 40.0,
        }
    }

    #[test]
    fn fit_recovers_a_different_tire_and_heldout_error_is_the_noise() {
        let ds = measured(20.0);
        let data = ChannelData::from_dataset(&ds, Channel::Fy).unwrap();
        let start = ChannelModel::new(Params::paper_table(), Channel::Fy, false, nominal());
        let fit = fit_channel(&data, &start, Start::Multi, None).unwrap();
        let rms = fit.rms(&data);
        assert!((rms - 20.0).abs() < 2.0, "in-sample rms {rms}");
        let folds = Folds::new(&data.run, 3, 1);
        let (models, held) = cross_validate::<f64>(&data, &folds, |train, _| {
            fit_channel(train, &fit.model, Start::Warm, None).map(|f| f.model)
        })
        .unwrap();
        // Each row's residual is its fold model's prediction with the fold's rows together.
        for (fold, model) in models.iter().enumerate() {
            let (_, test) = folds.split(&data.run, fold);
            let predicted = model.predictions(&data.subset(&test));
            for (&i, p) in test.iter().zip(predicted) {
                assert_eq!(held[i], data.measured[i] - p, "row {i}");
            }
        }
        let summary = ErrorSummary::of(&held, &data.fz_kn);
        assert!(
            summary.rms < 25.0 && summary.rms > 18.0,
            "held-out rms {}",
            summary.rms
        );
        let floor = noise_floor(&data.run, &data.measured);
        assert!((floor - 20.0).abs() < 2.5, "noise floor {floor}");
        let floor = noise_floor(&data.run, &held);
        assert!(
            (floor - 20.0).abs() < 2.5,
            "noise floor of the residual {floor}"
        );
        // Averaging 5 samples divides white noise variance by 5.
        let smooth = systematic(&data.run, &held);
        let ratio = (smooth.iter().map(|r| r * r).sum::<f64>()
            / held.iter().map(|r| r * r).sum::<f64>())
        .sqrt();
        assert!((ratio - 0.2f64.sqrt()).abs() < 0.05, "{ratio}");
        // Streamed, the same mean square to the bit; single precision too.
        let stored = crate::method::stats::mse(&smooth);
        assert_eq!(systematic_mse(&data.run, &held).to_bits(), stored.to_bits());
        let single: Vec<f32> = held.iter().map(|&r| r as f32).collect();
        let stored = crate::method::stats::mse(&systematic(&data.run, &single));
        assert_eq!(
            systematic_mse(&data.run, &single).to_bits(),
            stored.to_bits()
        );
        // Non-finite values are left out of the mean square.
        let mut gapped = held.clone();
        gapped[7] = f64::NAN;
        let stored = crate::method::stats::mse(&systematic(&data.run, &gapped));
        assert!(stored.is_finite());
        assert_eq!(
            systematic_mse(&data.run, &gapped).to_bits(),
            stored.to_bits()
        );
    }
}
