//! Unit tests of the diagnosis's steps, with worked values.

use mf87::{Channel, Params};

use super::candidate::CandidateFit;
use super::score::score;
use super::state::{ChannelState, gap_measurable, summary};
use super::{Options, nominal_of};
use crate::baseline::{SMOOTHING_WINDOW, systematic};
use crate::cv::splitmix;
use crate::data::Dataset;
use crate::effects::EffectId;
use crate::model::{ChannelData, ChannelModel};
use crate::stats::mse;

const RUNS: usize = 10;
const ROWS_PER_RUN: usize = 100;

/// White noise of unit variance (uniform on +-sqrt 3), repeatable.
fn white(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            let u = (splitmix(&mut s) >> 11) as f64 / (1u64 << 53) as f64;
            3f64.sqrt() * (2.0 * u - 1.0)
        })
        .collect()
}

/// A slow wave within each run: what an effect could explain.
fn wave(amplitude: f64) -> Vec<f64> {
    (0..RUNS * ROWS_PER_RUN)
        .map(|i| {
            let k = (i % ROWS_PER_RUN) as f64 / ROWS_PER_RUN as f64;
            amplitude * (std::f64::consts::TAU * k).sin()
        })
        .collect()
}

fn add(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x + y).collect()
}

/// A channel whose held-out residual is `residuals`, with a noise floor of 1 N.
fn state(residuals: Vec<f64>) -> ChannelState {
    let n = RUNS * ROWS_PER_RUN;
    let ds = Dataset {
        source: "t".into(),
        run: (0..n).map(|i| (i / ROWS_PER_RUN) as i64).collect(),
        fz: vec![4000.0; n],
        alpha: Some((0..n).map(|i| (i % 20) as f64 * 0.01).collect()),
        fy: Some(vec![0.0; n]),
        ..Dataset::default()
    };
    state_of(&ds, residuals)
}

/// The Fy channel of `ds` with the held-out residual `residuals`, a noise floor of 1 N and
/// the base model's gap that of `residuals`.
fn state_of(ds: &Dataset, residuals: Vec<f64>) -> ChannelState {
    let data = ChannelData::from_dataset(ds, Channel::Fy).unwrap();
    let model = ChannelModel::new(Params::paper_table(), Channel::Fy, false, nominal_of(ds));
    let white_part = 1.0 / SMOOTHING_WINDOW as f64;
    let base_gap_sq = mse(&systematic(&data.run, &residuals)) - white_part;
    ChannelState {
        data,
        noise: 1.0,
        full: model.clone(),
        fold_models: vec![model],
        residuals,
        base_gap_sq,
    }
}

fn candidate(state: &ChannelState, residuals: Vec<f64>) -> CandidateFit {
    CandidateFit {
        full: state.full.clone(),
        fold_models: state.fold_models.clone(),
        residuals,
    }
}

#[test]
fn a_gap_at_the_noise_floor_has_no_share_to_close() {
    let noise = white(RUNS * ROWS_PER_RUN, 7);
    let s = state(noise.clone());
    let before = systematic(&s.data.run, &s.residuals);
    // A candidate that shaves 2 % off pure noise: before, a ratio of noise to noise.
    let fit = candidate(&s, noise.iter().map(|r| 0.98 * r).collect());
    let sc = score(
        &s,
        &before,
        EffectId::Temperature,
        &fit,
        &Options::default(),
    );
    assert_eq!(sc.gap_closed, None);
    assert_eq!(sc.base_gap_closed, None);
    let reason = sc.not_scored.expect("a reason");
    assert!(reason.starts_with("no measurable gap"), "{reason}");
    // The summary says so too.
    let b = summary(&s, &s.residuals, None, &Options::default());
    assert!(b.no_gap.is_some());
}

#[test]
fn a_gap_above_the_floor_is_shared_by_worked_values() {
    // Systematic wave of amplitude 3 N (mean square 4.5, 4.5 noise variances) over unit
    // noise; the candidate leaves a tenth of the wave: it closes 1 - 0.1^2 = 99 % of it.
    let noise = white(RUNS * ROWS_PER_RUN, 11);
    let s = state(add(&noise, &wave(3.0)));
    let before = systematic(&s.data.run, &s.residuals);
    let fit = candidate(&s, add(&noise, &wave(0.3)));
    let sc = score(
        &s,
        &before,
        EffectId::Temperature,
        &fit,
        &Options::default(),
    );
    let closed = sc.gap_closed.expect("a measurable gap");
    assert!((closed - 0.99).abs() < 0.02, "{closed}");
    let base = sc.base_gap_closed.unwrap();
    assert!(
        (base - closed).abs() < 1e-12,
        "same gap before as at the base"
    );
    // The gain in noise variances: the wave's mean square 4.5 less 0.045, give or take the
    // cross term of the smoothed noise with the wave (about 0.15 standard deviation).
    assert!((sc.noise_gain - 4.455).abs() < 0.4, "{}", sc.noise_gain);
    assert_eq!(sc.not_scored, None);
    assert!(
        summary(&s, &s.residuals, None, &Options::default())
            .no_gap
            .is_none()
    );
}

#[test]
fn measurable_means_at_least_the_least_credited_gain() {
    let o = Options::default();
    assert!(!gap_measurable(0.0, 1.0, &o));
    assert!(!gap_measurable(0.24, 1.0, &o));
    assert!(gap_measurable(0.25, 1.0, &o));
    assert!(gap_measurable(25.0, 10.0, &o));
    assert!(!gap_measurable(24.0, 10.0, &o));
}
