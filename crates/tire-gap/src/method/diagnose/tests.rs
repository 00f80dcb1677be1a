//! Unit tests of the diagnosis's steps, with worked values.

use mf87::{Channel, Params};

use super::Options;
use super::candidate::{
    CandidateFit, PairFit, base_off_home, cross_validated, fit_candidate, fit_full, in_sample_mse,
};
use super::plausibility::Plausibility;
use super::score::{RunMeans, Score, current_model, relative_gains, score};
use super::state::{ChannelState, gap_measurable, summary};
use super::trials::{combine, mark_overshadowed, mark_unspecific, rank_trials};
use super::{ChannelTrial, Trial, nominal_of};
use crate::data::Dataset;
use crate::method::fit::channel_fit::{SMOOTHING_WINDOW, Start, fit_channel, systematic};
use crate::method::fit::effects::{self, Extension};
use crate::method::fit::model::ChannelModel;
use crate::method::fit::validity::ValidityRange;
use crate::method::prepare::channel_data::ChannelData;
use crate::method::prepare::cv::Folds;
use crate::method::splitmix::splitmix64;
use crate::method::stats::{CompactResiduals, mse};

const RUNS: usize = 10;
const ROWS_PER_RUN: usize = 100;

/// White noise of unit variance (uniform on +-sqrt 3), repeatable.
fn white(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            let u = (splitmix64(&mut s) >> 11) as f64 / (1u64 << 53) as f64;
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
        fz: vec![4000.0; n].into(),
        alpha: Some((0..n).map(|i| (i % 20) as f64 * 0.01).collect()),
        fy: Some(vec![0.0; n].into()),
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
    // As a diagnosis keeps them: in single precision, the gap measured on what is kept.
    let residuals = CompactResiduals::new(&residuals);
    let base_gap_sq = mse(&systematic(&data.run, residuals.as_single())) - white_part;
    ChannelState {
        data,
        noise: 1.0,
        full: model.clone(),
        fold_models: vec![model],
        residuals,
        base_gap_sq,
    }
}

/// A test candidate's residuals (always kept).
fn kept(fit: &CandidateFit) -> &CompactResiduals {
    fit.residuals
        .as_ref()
        .expect("a test candidate keeps its residuals")
}

fn candidate(state: &ChannelState, residuals: Vec<f64>) -> CandidateFit {
    CandidateFit {
        full: state.full.clone(),
        fold_models: Some(state.fold_models.clone()),
        residuals: Some(CompactResiduals::new(&residuals)),
        screened: None,
    }
}

#[test]
fn a_gap_at_the_noise_floor_has_no_share_to_close() {
    let noise = white(RUNS * ROWS_PER_RUN, 7);
    let s = state(noise.clone());
    // A candidate that shaves 2 % off pure noise: before, a ratio of noise to noise.
    let fit = candidate(&s, noise.iter().map(|r| 0.98 * r).collect());
    let sc = score(
        &s,
        (Extension::Temperature, &fit.full),
        kept(&fit),
        &current_model,
        &Options::default(),
    );
    assert_eq!(sc.gap_closed, None);
    assert_eq!(sc.base_gap_closed, None);
    let reason = sc.not_scored.expect("a reason");
    assert!(reason.starts_with("no measurable gap"), "{reason}");
    // The summary says so too.
    let b = summary(&s, None, &Options::default());
    assert!(b.no_gap.is_some());
}

#[test]
fn a_gap_above_the_floor_is_shared_by_worked_values() {
    // Systematic wave of amplitude 3 N (mean square 4.5, 4.5 noise variances) over unit
    // noise; the candidate leaves a tenth of the wave: it closes 1 - 0.1^2 = 99 % of it.
    let noise = white(RUNS * ROWS_PER_RUN, 11);
    let s = state(add(&noise, &wave(3.0)));
    let fit = candidate(&s, add(&noise, &wave(0.3)));
    let sc = score(
        &s,
        (Extension::Temperature, &fit.full),
        kept(&fit),
        &current_model,
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
    assert!(summary(&s, None, &Options::default()).no_gap.is_none());
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

/// Four runs of ten rows: runs 0-2 at 0.1 rad (5.7 deg) of slip angle, run 3 at zero slip.
fn four_runs() -> Dataset {
    let n = 40;
    Dataset {
        source: "t".into(),
        run: (0..n).map(|i| i as i64 / 10).collect(),
        fz: vec![4000.0; n].into(),
        alpha: Some((0..n).map(|i| if i < 30 { 0.1 } else { 0.0 }).collect()),
        fy: Some(vec![0.0; n].into()),
        ..Dataset::default()
    }
}

/// `per_run[r]` on each of run r's ten rows.
fn per_run(per_run: [f64; 4]) -> Vec<f64> {
    (0..40).map(|i| per_run[i / 10]).collect()
}

#[test]
fn a_score_by_worked_values() {
    // Residuals constant within each run, so their systematic part (a moving average within
    // runs) is the same constant: before 2, 2, 1, 3 per run, after 1, 1, 1, 0.
    let mut s = state_of(&four_runs(), per_run([2.0, 2.0, 1.0, 3.0]));
    s.base_gap_sq = 7.5;
    assert_eq!(
        systematic(&s.data.run, s.residuals.as_single()),
        s.residuals.to_vec()
    );
    let fit = candidate(&s, per_run([1.0, 1.0, 1.0, 0.0]));
    let o = Options::default();

    // Temperature must show where |alpha| >= 1 deg: runs 0-2; run 3 is not compared.
    // Per-run mean squares there: before 4, 4, 1; after 1, 1, 1; typical, their mean, 2.
    // Relative gains (before - after) / (before + after + typical): 3/7, 3/7, 0/4 = 0.
    // Sign-flip test: the zero gain drops out; of the 4 sign patterns of (3/7, 3/7) only
    // (+, +) reaches the observed sum: p = 1/4, over 3 runs compared.
    let sc = score(
        &s,
        (Extension::Temperature, &fit.full),
        kept(&fit),
        &current_model,
        &o,
    );
    assert_eq!(sc.runs, 3);
    assert_eq!(sc.p_value, 0.25);
    // The gap is measured on every row, run 3 included: systematic mean square before
    // (10 * 4 + 10 * 4 + 10 * 1 + 10 * 9) / 40 = 4.5, after (10 + 10 + 10 + 0) / 40 = 0.75,
    // a fall of 3.75 noise variances (noise 1). White part 1 / 5 = 0.2: gap 4.5 - 0.2 = 4.3,
    // of which 3.75 / 4.3 = 0.872 is closed; of the base model's gap, 3.75 / 7.5 = 0.5.
    assert!((sc.noise_gain - 3.75).abs() < 1e-12, "{}", sc.noise_gain);
    let closed = sc.gap_closed.expect("a measurable gap");
    assert!((closed - 3.75 / 4.3).abs() < 1e-12, "{closed}");
    assert!((sc.base_gap_closed.unwrap() - 0.5).abs() < 1e-12);
    assert_eq!(sc.not_scored, None);

    // Ply steer must show where |alpha| < 2 deg: run 3 alone. Before 9, after 0, typical 4.5:
    // gain 9 / 13.5 = 2/3; one positive gain has p = 1/2. The gap measures do not change.
    let sc = score(
        &s,
        (Extension::PlySteerConicity, &fit.full),
        kept(&fit),
        &current_model,
        &o,
    );
    assert_eq!(sc.runs, 1);
    assert_eq!(sc.p_value, 0.5);
    assert!((sc.gap_closed.unwrap() - 3.75 / 4.3).abs() < 1e-12);

    // A run that gets worse: after 1, 1, 1.5, 0. Run 2's mean square goes from 1 to 2.25;
    // typical (9 + 4.25) / 6 = 2.2083: gains 3 / 7.2083 = 0.4162 twice and
    // -1.25 / 5.4583 = -0.2290, sum 0.6034. Patterns reaching it: (+, +, +) and (+, +, -)
    // only, since flipping a 0.4162 for the 0.2290 lowers the sum: p = 2/8. (Weighed by its
    // own error alone, -1.25 / 1 would outweigh 3/4: p would be 4/8.)
    let worse = candidate(&s, per_run([1.0, 1.0, 1.5, 0.0]));
    let sc = score(
        &s,
        (Extension::Temperature, &worse.full),
        kept(&worse),
        &current_model,
        &o,
    );
    assert_eq!(sc.runs, 3);
    assert_eq!(sc.p_value, 0.25);
    // Systematic mean square after: (10 + 10 + 22.5 + 0) / 40 = 1.0625, a fall of 3.4375.
    assert!((sc.noise_gain - 3.4375).abs() < 1e-12, "{}", sc.noise_gain);
    assert!((sc.gap_closed.unwrap() - 3.4375 / 4.3).abs() < 1e-12);
}

#[test]
fn a_run_gain_is_bounded_and_changes_sign_when_before_and_after_swap() {
    let before = RunMeans::from([(1, 4.0), (2, 1.0), (3, 0.0), (5, 7.0)]);
    let after = RunMeans::from([(1, 1.0), (2, 100.0), (3, 0.0), (4, 3.0)]);
    // Runs 1, 2 and 3 are in both; typical = (4 + 1 + 0 + 1 + 100 + 0) / 6 = 17.667.
    let gains = relative_gains(&before, &after);
    let typical = 106.0 / 6.0;
    let expected = [3.0 / (5.0 + typical), -99.0 / (101.0 + typical), 0.0];
    assert_eq!(gains.len(), 3);
    for (g, e) in gains.iter().zip(expected) {
        assert!((g - e).abs() < 1e-15, "{g} against {e}");
    }
    // A run that blows up weighs less than one that gains all it can, in either direction.
    assert!(gains[1] > -1.0 && gains[1] < -0.8, "{}", gains[1]);
    let swapped = relative_gains(&after, &before);
    assert_eq!(swapped, gains.iter().map(|g| -g).collect::<Vec<_>>());
}

/// Rows of `channel` with its own slip `slip` (the formula's units) and the other slip
/// `other` (slip ratio for Fy, slip angle [rad] for Fx), or none.
fn rows(channel: Channel, slip: &[f64], other: Option<&[f64]>) -> ChannelData {
    let n = slip.len();
    ChannelData {
        channel,
        run: vec![0; n].into(),
        fz_kn: vec![4.0; n].into(),
        slip: slip.into(),
        gamma_deg: vec![0.0; n].into(),
        measured: vec![0.0; n].into(),
        other_slip: other.map(Into::into),
        time: None,
        speed: None,
        pressure: None,
        temperature: None,
        counted: None,
    }
}

fn home_rows(effect: Extension, data: &ChannelData) -> Option<Vec<bool>> {
    effects::of(effect).home_rows(data)
}

#[test]
fn home_rows_by_worked_values() {
    let (t, f) = (true, false);
    let slip = [-2.5, -1.0, -0.5, 0.0, 0.99, 1.0, 2.0, 3.0];
    let fy = rows(
        Channel::Fy,
        &slip,
        Some(&[0.0, 0.02, -0.03, 0.1, 0.0, 0.0, 0.0, 0.0]),
    );
    // Effects on the force the slip makes: |slip| >= 1 (deg, or % for Fx).
    for e in [
        Extension::RelaxationLength,
        Extension::InflationPressure,
        Extension::SpeedDependence,
        Extension::Temperature,
    ] {
        assert_eq!(home_rows(e, &fy), Some(vec![t, t, f, f, f, t, t, t]), "{e}");
    }
    // Ply steer: the linear range, |alpha| < 2 deg (2 itself is out).
    assert_eq!(
        home_rows(Extension::PlySteerConicity, &fy),
        Some(vec![f, t, t, t, t, t, f, f])
    );
    // Rolling resistance: zero slip, |slip| < 1 (1 itself is out).
    assert_eq!(
        home_rows(Extension::RollingResistance, &fy),
        Some(vec![f, f, t, t, t, f, f, f])
    );
    // Combined slip on Fy: slip ratio |kappa| > 0.02 (0.02 itself is out).
    assert_eq!(
        home_rows(Extension::CombinedSlip, &fy),
        Some(vec![f, f, t, t, f, f, f, f])
    );
    // On Fx the other slip is the slip angle [rad]: |alpha| > 1 deg = 0.01745 rad.
    let fx = rows(Channel::Fx, &[5.0; 4], Some(&[0.017, 0.018, -0.02, 0.0]));
    assert_eq!(
        home_rows(Extension::CombinedSlip, &fx),
        Some(vec![f, t, t, f])
    );
    // Without the other slip there is no home (and the effect cannot be tested).
    assert_eq!(
        home_rows(Extension::CombinedSlip, &rows(Channel::Fy, &slip, None)),
        None
    );
}

/// A judged channel: `gap` and `base` are the shares closed of the current and of the base
/// model's gap.
fn judged(
    channel: Channel,
    gap: Option<f64>,
    base: Option<f64>,
    significant: bool,
) -> ChannelTrial {
    ChannelTrial {
        channel,
        heldout_before: 1.0,
        heldout_after: 1.0,
        gap_closed: gap,
        base_gap_closed: base,
        not_scored: None,
        noise_gain: 1.0,
        p_value: 0.001,
        p_adjusted: Some(0.001),
        runs: 10,
        significant,
        unspecific: false,
        implausible: None,
        screened: None,
        signature: shown_signature(),
        not_its_signature: None,
        overshadowed: None,
        params: Default::default(),
    }
}

/// A signature whose gain points to the driver, with one-sided p-value 0.01.
fn shown_signature() -> super::signature::SignatureTest {
    super::signature::SignatureTest {
        gain_per_row_active: 2.0,
        gain_per_row_idle: 1.0,
        run_gain_active: 2.0,
        run_gain_idle: 1.0,
        p_value: Some(0.01),
        not_testable: None,
        ..super::signature::untestable(String::new())
    }
}

fn trial(effect: Extension, channels: Vec<ChannelTrial>) -> Trial {
    Trial {
        effect,
        form: effects::of(effect).form(),
        channels,
        significant: false,
        score: 0.0,
    }
}

/// (significant, unspecific) of `effect` on `channel`.
fn verdict_of(trials: &[Trial], effect: Extension, channel: Channel) -> (bool, bool) {
    let t = trials.iter().find(|t| t.effect == effect).unwrap();
    let c = t.channels.iter().find(|c| c.channel == channel).unwrap();
    (c.significant, c.unspecific)
}

#[test]
fn a_winner_joins_the_model_where_it_lowers_the_held_out_error() {
    use super::selection::joins_the_model;
    // Significant: joins (and is claimed).
    assert!(joins_the_model(&judged(
        Channel::Fy,
        Some(0.9),
        Some(0.9),
        true
    )));
    // Not significant, but a held-out gain: joins, not claimed.
    let gain = judged(Channel::Mz, Some(0.26), Some(0.26), false);
    assert!(joins_the_model(&gain));
    // No gain, or no gap to score: stays out.
    assert!(!joins_the_model(&judged(
        Channel::Mz,
        Some(-0.02),
        Some(-0.02),
        false
    )));
    assert!(!joins_the_model(&judged(Channel::Mz, None, None, false)));
    // A gain from a fit that is not physical, screened, or lies where its driver is idle:
    // stays out.
    let out = |f: fn(&mut ChannelTrial)| {
        let mut c = gain.clone();
        f(&mut c);
        joins_the_model(&c)
    };
    assert!(!out(|c| c.implausible = Some("peak scale below 0.1".into())));
    assert!(!out(|c| c.screened = Some("gains too little".into())));
    assert!(!out(|c| c.not_its_signature = Some("absorbs misfit".into())));
    assert!(!out(|c| c.not_scored = Some("no measurable gap".into())));
    // A pooled gain that the runs do not share (per-run p-value 1): stays out.
    assert!(!out(|c| c.p_value = 1.0));
}

#[test]
fn specificity_by_worked_values() {
    use Extension::{InflationPressure, SpeedDependence, Temperature};
    // Defaults: unspecific below 0.05 of the base gap when another candidate on the same
    // channel closes at least 0.8 of the gain.
    let o = Options::default();
    let mut trials = vec![
        trial(
            Temperature,
            vec![
                // Fy: 0.04 < 0.05 of the base gap; the best other on Fy closes 0.30 (inflation,
                // significant or not, it counts) >= 0.8 * 0.30 = 0.24: unspecific.
                judged(Channel::Fy, Some(0.30), Some(0.04), true),
                // Fx: 0.01 of the base gap, but the best other closes 0.39 < 0.8 * 0.5 = 0.4.
                judged(Channel::Fx, Some(0.5), Some(0.01), true),
                // Mz: the best other closes 0.4 = 0.8 * 0.5 exactly: a tie is unspecific.
                judged(Channel::Mz, Some(0.5), Some(0.04), true),
            ],
        ),
        trial(
            SpeedDependence,
            vec![
                // Not significant: not judged.
                judged(Channel::Fy, Some(0.25), Some(0.01), false),
                judged(Channel::Fx, Some(0.39), Some(0.2), false),
                judged(Channel::Mz, Some(0.4), Some(0.3), false),
            ],
        ),
        trial(
            InflationPressure,
            vec![
                // 0.06 >= 0.05 of the base gap: specific, however closely others match.
                judged(Channel::Fy, Some(0.30), Some(0.06), true),
                // Not scored: not judged.
                judged(Channel::Fx, None, None, true),
            ],
        ),
    ];
    mark_unspecific(&mut trials, &o);
    assert_eq!(verdict_of(&trials, Temperature, Channel::Fy), (false, true));
    assert_eq!(verdict_of(&trials, Temperature, Channel::Fx), (true, false));
    assert_eq!(verdict_of(&trials, Temperature, Channel::Mz), (false, true));
    assert_eq!(
        verdict_of(&trials, SpeedDependence, Channel::Fy),
        (false, false)
    );
    assert_eq!(
        verdict_of(&trials, InflationPressure, Channel::Fy),
        (true, false)
    );
    assert_eq!(
        verdict_of(&trials, InflationPressure, Channel::Fx),
        (true, false)
    );
}

#[test]
fn specificity_judges_every_channel_before_clearing_any() {
    use Extension::{SpeedDependence, Temperature};
    // Two significant candidates matching each other on Fy, both below 0.05 of the base gap:
    // temperature 0.30 against speed's 0.28 >= 0.8 * 0.30 = 0.24, speed 0.28 against
    // temperature's 0.30 >= 0.8 * 0.28 = 0.224. Both are unspecific: neither wins by being
    // judged second.
    let mut trials = vec![
        trial(
            Temperature,
            vec![judged(Channel::Fy, Some(0.30), Some(0.02), true)],
        ),
        trial(
            SpeedDependence,
            vec![judged(Channel::Fy, Some(0.28), Some(0.03), true)],
        ),
    ];
    mark_unspecific(&mut trials, &Options::default());
    assert_eq!(verdict_of(&trials, Temperature, Channel::Fy), (false, true));
    assert_eq!(
        verdict_of(&trials, SpeedDependence, Channel::Fy),
        (false, true)
    );
}

#[test]
fn overshadow_by_worked_values() {
    use Extension::{CombinedSlip, RollingResistance, SlipRatioShift, Temperature};
    let refused = |gap: f64| ChannelTrial {
        not_its_signature: Some("its gain does not lie clearly where its driver acts".into()),
        ..judged(Channel::Fx, Some(gap), Some(gap), false)
    };
    let trials = || {
        vec![
            // Fx: 0.69 closed; rolling resistance closes 0.98 >= 1.1 * 0.69 = 0.759 and was
            // refused only for its signature.
            trial(
                SlipRatioShift,
                vec![judged(Channel::Fx, Some(0.69), Some(0.69), true)],
            ),
            trial(RollingResistance, vec![refused(0.98)]),
            // Fx: 0.90 closed; rolling resistance's 0.98 < 1.1 * 0.90 = 0.99: not overshadowed.
            trial(
                CombinedSlip,
                vec![judged(Channel::Fx, Some(0.90), Some(0.90), true)],
            ),
            // Fy: no rival on the channel.
            trial(
                Temperature,
                vec![judged(Channel::Fy, Some(0.30), Some(0.30), true)],
            ),
        ]
    };
    let significant = |t: &[Trial], e: Extension| verdict_of(t, e, Channel::Fx).0;
    // Corrections correlated at 0.52 >= 0.5: the shift's gain is a part of rolling
    // resistance's, and neither is claimed.
    let mut t = trials();
    mark_overshadowed(&mut t, &|_, _, _| Some(0.52));
    assert!(!significant(&t, SlipRatioShift));
    let shift = &t[0].channels[0];
    assert!(
        shift
            .overshadowed
            .as_deref()
            .unwrap()
            .contains("rolling_resistance")
    );
    assert!(significant(&t, CombinedSlip));
    assert!(verdict_of(&t, Temperature, Channel::Fy).0);
    // Corrections that do not correlate (0.49 < 0.5), or no correlation to be had: the gains
    // are of different misfits, and the shift keeps its claim.
    for r in [Some(0.49), None] {
        let mut t = trials();
        mark_overshadowed(&mut t, &|_, _, _| r);
        assert!(significant(&t, SlipRatioShift) && t[0].channels[0].overshadowed.is_none());
    }
}

#[test]
fn ranking_by_worked_values() {
    use Extension::{InflationPressure, RelaxationLength, SpeedDependence, Temperature};
    let mut trials = vec![
        // Score: significant channels' gains, losses as 0: 0.375 + 0 = 0.375 (Mz's 0.875 is
        // not significant, but is its largest gain, for ties).
        trial(
            Temperature,
            vec![
                judged(Channel::Fy, Some(0.375), None, true),
                judged(Channel::Fx, Some(-0.25), None, true),
                judged(Channel::Mz, Some(0.875), None, false),
            ],
        ),
        // 0.25 + 0.125 = 0.375, a tie with temperature, whose largest gain 0.875 > 0.25 wins.
        trial(
            SpeedDependence,
            vec![
                judged(Channel::Fy, Some(0.25), None, true),
                judged(Channel::Fx, Some(0.125), None, true),
            ],
        ),
        // Nothing significant: score 0, not significant.
        trial(
            InflationPressure,
            vec![judged(Channel::Fy, Some(0.5), None, false)],
        ),
        // 0.5: first.
        trial(
            RelaxationLength,
            vec![judged(Channel::Fy, Some(0.5), None, true)],
        ),
    ];
    rank_trials(&mut trials);
    let ranked: Vec<(Extension, f64, bool)> = trials
        .iter()
        .map(|t| (t.effect, t.score, t.significant))
        .collect();
    assert_eq!(
        ranked,
        [
            (RelaxationLength, 0.5, true),
            (Temperature, 0.375, true),
            (SpeedDependence, 0.375, true),
            (InflationPressure, 0.0, false),
        ]
    );
}

/// A score with p-value `p`, scored (a measurable gap) or not.
fn p_score(p: f64, scored: bool) -> Score {
    Score {
        p_value: p,
        runs: 10,
        gap_closed: scored.then_some(0.5),
        base_gap_closed: scored.then_some(0.5),
        noise_gain: 1.0,
        not_scored: None,
        signature: super::signature::untestable(String::new()),
    }
}

#[test]
fn p_values_combine_by_worked_values() {
    use Extension::{CombinedSlip, SpeedDependence, Temperature};
    let s = state(vec![0.0; RUNS * ROWS_PER_RUN]);
    let fit = candidate(&s, vec![0.0; RUNS * ROWS_PER_RUN]);
    let on = |effect, channel| PairFit {
        effect,
        channel,
        fit: &fit,
        mse: 0.0,
    };
    let fits = [
        on(Temperature, 0),
        on(SpeedDependence, 0),
        on(Temperature, 1),
        on(CombinedSlip, 0),
    ];
    let scores = [
        p_score(0.01, true),
        p_score(0.015, true),
        p_score(0.5, true),
        p_score(0.001, false),
    ];
    // Temperature over its two channels: Fisher's x/2 = -(ln 0.01 + ln 0.5) = ln 200 = 5.298,
    // p = e^-5.298 (1 + 5.298) = 6.298 / 200 = 0.0315; Bonferroni 2 * 0.01 = 0.02 is stronger:
    // 2 * 0.02 = 0.04. Speed: its one channel's 0.015. Combined slip: its one channel has no
    // measurable gap, so it is not tested (nor counted by Holm).
    // Holm over the two tested: 0.015 * 2 = 0.03, then max(0.03, 0.04 * 1) = 0.04.
    let adjusted = combine(&fits, &scores);
    let want = [Some(0.04), Some(0.03), Some(0.04), None];
    for (a, w) in adjusted.iter().zip(want) {
        match (a, w) {
            (Some(a), Some(w)) => assert!((a - w).abs() < 1e-15, "{adjusted:?}"),
            _ => assert_eq!(*a, w),
        }
    }
}

#[test]
fn the_screening_line_is_half_the_least_held_out_gain() {
    use super::candidate::{SCREEN_SHARE, screen_threshold};
    // Pure unit noise: no gap, so the line is half of min_noise_gain noise variances.
    let s = state(white(RUNS * ROWS_PER_RUN, 5));
    let line = screen_threshold(&s, 0.25, 0.10);
    assert!((line - SCREEN_SHARE * 0.25).abs() < 1e-12, "{line}");
    // A wave of amplitude 3 N (mean square 4.5) over it: a tenth of that gap is larger than
    // 0.25 noise variances, so the line is half of it (give or take the smoothing's share of
    // the noise and its cross term with the wave).
    let s = state(add(&white(RUNS * ROWS_PER_RUN, 11), &wave(3.0)));
    let line = screen_threshold(&s, 0.25, 0.10);
    assert!((line - SCREEN_SHARE * 0.45).abs() < 0.03, "{line}");
    // A later round's larger noise gain takes over.
    let line = screen_threshold(&s, 1.0, 0.10);
    assert!((line - SCREEN_SHARE).abs() < 1e-12, "{line}");
}

/// Ten runs of slip-ratio sweeps at 4 kN, each at its own speed (5 to 23 m/s), whose Fx is
/// the paper's model less a rolling resistance `q2 V / V0 Fz` far beyond the FMU's bound on
/// the coefficient.
fn rolling_beyond_the_bound(q2: f64) -> (Dataset, ChannelModel) {
    let n = RUNS * ROWS_PER_RUN;
    let mut ds = Dataset {
        source: "t".into(),
        run: (0..n).map(|i| (i / ROWS_PER_RUN) as i64).collect(),
        speed: Some(
            (0..n)
                .map(|i| 5.0 + 2.0 * (i / ROWS_PER_RUN) as f64)
                .collect(),
        ),
        fz: vec![4000.0; n].into(),
        kappa: Some(
            (0..n)
                .map(|i| -0.1 + 0.2 * (i % ROWS_PER_RUN) as f64 / ROWS_PER_RUN as f64)
                .collect(),
        ),
        fx: Some(vec![0.0; n].into()),
        ..Dataset::default()
    };
    let model = ChannelModel::new(Params::paper_table(), Channel::Fx, false, nominal_of(&ds));
    let mut truth = model.clone();
    truth.effects = vec![(Extension::RollingResistance, vec![0.0, q2])];
    let data = ChannelData::from_dataset(&ds, Channel::Fx).unwrap();
    ds.fx = Some(truth.predictions(&data).into());
    (ds, model)
}

/// The Fx channel of [`rolling_beyond_the_bound`] with the paper's model on every fold, its
/// folds and its bounds.
fn rolling_state(q2: f64) -> (ChannelState, Folds, Plausibility) {
    let (ds, model) = rolling_beyond_the_bound(q2);
    let data = ChannelData::from_dataset(&ds, Channel::Fx).unwrap();
    let folds = Folds::new(&data.run, 5, 1);
    let plausibility = Plausibility::new(ValidityRange::of(&ds));
    let state = ChannelState {
        residuals: CompactResiduals::new(&vec![0.0; data.len()]),
        data,
        noise: 1.0,
        full: model.clone(),
        fold_models: vec![model; folds.k],
        base_gap_sq: 1.0,
    };
    (state, folds, plausibility)
}

#[test]
fn fold_fits_that_score_a_candidate_are_ones_the_fmu_accepts() {
    // Unbounded, the fold fits would take the coefficient to about 0.8 V / V0 (bound 0.3).
    let (state, folds, plausibility) = rolling_state(0.8);
    let fit = fit_candidate(&state, Extension::RollingResistance, &folds, &plausibility).unwrap();
    let fold_models = fit.fold_models.unwrap();
    assert_eq!(fold_models.len(), 5);
    for m in fold_models.iter().chain([&fit.full]) {
        assert!(plausibility.exports(m), "{:?}", m.effects);
        // Pushed against the bound by the data, not left at the neutral start.
        let q = &m.effects[0].1;
        assert!(q[0] + q[1] > 0.1, "{q:?}");
    }
}

#[test]
fn a_candidate_without_its_residuals_predicts_the_same_ones_again() {
    // Refitted per fold and screened out (each fold's model with the all-data values): the
    // residuals a round drops are predicted again, to the bit, when a later step needs them.
    let (state, folds, plausibility) = rolling_state(0.2);
    let effect = Extension::RollingResistance;
    let base_mse = in_sample_mse(&state.full, &state.data);
    let full = fit_full(&state, base_mse, effect, &plausibility).unwrap();
    for screened_below in [None, Some(1.0)] {
        let mut fit =
            cross_validated(&state, &full, effect, &folds, screened_below, &plausibility).unwrap();
        assert_eq!(fit.screened.is_some(), screened_below.is_some());
        let kept = fit.residuals.take().unwrap();
        assert!(
            kept.iter().any(|r| r.abs() > 1.0),
            "the effect is there to fit"
        );
        let again = fit.held_out(&state, effect, &folds).unwrap().into_owned();
        assert_eq!(again, kept);
    }
}

#[test]
fn options_outside_their_ranges_are_named_with_the_range() {
    let with = |folds, stability_draws| Options {
        folds,
        stability_draws,
        ..Options::default()
    };
    assert!(Options::default().validate().is_ok());
    for (folds, draws) in [(3, 1), (20, 10)] {
        assert!(with(folds, draws).validate().is_ok(), "{folds} {draws}");
    }
    assert_eq!(
        with(2, 3).validate().unwrap_err(),
        "folds = 2 is out of range: it must lie in 3..=20"
    );
    assert_eq!(
        with(5, 11).validate().unwrap_err(),
        "stability_draws = 11 is out of range: it must lie in 1..=10"
    );
    assert!(with(21, 0).validate().is_err());
}

/// Lateral sweeps of the paper's tire at 4 kN, half of them at a slip ratio of 0.15 where the
/// force is 60 % of the pure curve's; the 1987 model at the paper's values.
fn pure_and_weighted_sweeps() -> (ChannelData, ChannelModel) {
    let n = RUNS * ROWS_PER_RUN;
    let combined = |i: usize| i / ROWS_PER_RUN >= RUNS / 2;
    let mut ds = Dataset {
        source: "t".into(),
        run: (0..n).map(|i| (i / ROWS_PER_RUN) as i64).collect(),
        fz: vec![4000.0; n].into(),
        alpha: Some(
            (0..n)
                .map(|i| {
                    (-8.0 + 16.0 * (i % ROWS_PER_RUN) as f64 / ROWS_PER_RUN as f64).to_radians()
                })
                .collect(),
        ),
        kappa: Some(
            (0..n)
                .map(|i| if combined(i) { 0.15 } else { 0.0 })
                .collect(),
        ),
        fy: Some(vec![0.0; n].into()),
        ..Dataset::default()
    };
    let model = ChannelModel::new(Params::paper_table(), Channel::Fy, false, nominal_of(&ds));
    let data = ChannelData::from_dataset(&ds, Channel::Fy).unwrap();
    let pure = model.predictions(&data);
    ds.fy = Some(
        (0..n)
            .map(|i| if combined(i) { 0.6 * pure[i] } else { pure[i] })
            .collect(),
    );
    (ChannelData::from_dataset(&ds, Channel::Fy).unwrap(), model)
}

#[test]
fn combined_slip_starts_from_the_base_refitted_on_the_pure_slip_rows() {
    let (data, paper) = pure_and_weighted_sweeps();
    let pure: Vec<usize> = (0..data.len() / 2).collect();
    let truth = paper.predictions(&data);
    let rms_on_pure = |m: &ChannelModel| {
        let p = m.predictions(&data);
        (pure.iter().map(|&i| (p[i] - truth[i]).powi(2)).sum::<f64>() / pure.len() as f64).sqrt()
    };
    let peak = truth.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    // Fitted on every row, the 1987 curve lowers its peak toward the weighted rows.
    let all_rows = fit_channel(&data, &paper, Start::Warm, None).unwrap().model;
    assert!(
        rms_on_pure(&all_rows) > 0.1 * peak,
        "{}",
        rms_on_pure(&all_rows)
    );
    // Refitted on the rows outside combined slip's home, it is the pure curve again (the
    // weight at its start is 1 there).
    let start = all_rows.with_effect(Extension::CombinedSlip);
    let refitted = base_off_home(&data, &start, Extension::CombinedSlip, None).unwrap();
    assert!(
        rms_on_pure(&refitted) < 0.01 * peak,
        "{}",
        rms_on_pure(&refitted)
    );
    // Not refitted when the pure rows are too few.
    let few = data.subset(&(RUNS * ROWS_PER_RUN / 2 - 10..RUNS * ROWS_PER_RUN).collect::<Vec<_>>());
    assert!(base_off_home(&few, &start, Extension::CombinedSlip, None).is_none());
}

#[cfg(feature = "synth")]
#[test]
fn the_extrapolation_check_refits_within_the_bounds_it_is_given() {
    use crate::method::diagnose::extrapolate;
    use crate::synth::{SynthConfig, generate};
    use std::sync::atomic::{AtomicUsize, Ordering};
    let ds = generate(&SynthConfig {
        seed: 5,
        effects: vec![Extension::Temperature],
        rows_target: 4000,
        ..SynthConfig::default()
    });
    let data = ChannelData::from_dataset(&ds, Channel::Fy).unwrap();
    let with = ChannelModel::new(
        Params::paper_table(),
        Channel::Fy,
        data.has_camber(),
        nominal_of(&ds),
    )
    .with_effect(Extension::Temperature);
    // Every step of both refits, at both ends, asks whether its model may be the answer.
    let asked = AtomicUsize::new(0);
    let counting = |_: &ChannelModel| {
        asked.fetch_add(1, Ordering::Relaxed);
        true
    };
    let ends = extrapolate::check(Extension::Temperature, &data, &with, &counting);
    assert_eq!(ends.len(), 2);
    assert!(asked.load(Ordering::Relaxed) >= 4, "{asked:?}");
    // Held to the base model (no temperature term may move off neutral), the extended refit
    // is the base refit: both ends extrapolate no differently.
    let neutral = |m: &ChannelModel| m.effects.iter().all(|(_, p)| p.iter().all(|v| *v == 0.0));
    for end in extrapolate::check(Extension::Temperature, &data, &with, &neutral) {
        assert!(
            (end.rms_with - end.rms_without).abs() <= 1e-9 * end.rms_without,
            "{}: {} against {}",
            end.held_out,
            end.rms_with,
            end.rms_without
        );
    }
}

#[test]
fn a_channel_is_claimed_only_where_its_gain_points_to_its_driver() {
    use super::signature::SignatureTest;
    use super::trials::judge_signatures;
    use Extension::{CombinedSlip, SpeedDependence, Temperature};
    // Combined slip gains three times as much a row where its driver is idle.
    let absorbing = SignatureTest {
        gain_per_row_active: 1.0,
        gain_per_row_idle: 3.0,
        run_gain_active: 1.0,
        run_gain_idle: 3.0,
        idle_share: Some(0.75),
        p_value: Some(0.9),
        ..shown_signature()
    };
    // Speed points to its driver, but weakly.
    let weak = SignatureTest {
        p_value: Some(0.3),
        ..shown_signature()
    };
    let with = |signature: SignatureTest, channel| ChannelTrial {
        signature,
        ..judged(channel, Some(0.5), Some(0.5), true)
    };
    let mut trials = vec![
        trial(
            Temperature,
            vec![
                with(shown_signature(), Channel::Fx),
                with(shown_signature(), Channel::Fy),
            ],
        ),
        trial(CombinedSlip, vec![with(absorbing, Channel::Fx)]),
        trial(SpeedDependence, vec![with(weak, Channel::Fy)]),
        // Not significant by its score: its signature is not judged.
        trial(
            Extension::InflationPressure,
            vec![judged(Channel::Fy, Some(0.5), Some(0.5), false)],
        ),
    ];
    judge_signatures(&mut trials, &[], &Options::default());
    // Temperature over its two channels at 0.01: Fisher's x/2 = -2 ln 0.01 = 9.2103,
    // p = e^-9.2103 (1 + 9.2103) = 1.0210e-3, stronger than Bonferroni's 0.02; doubled
    // 2.0421e-3. Speed: its one channel's 0.3. Holm over the two: 2 * 2.0421e-3 = 4.0841e-3,
    // then max(4.0841e-3, 0.3) = 0.3. Combined slip does not point to its driver: not counted.
    for c in &trials[0].channels {
        assert!(c.significant && c.signature.shown, "{c:?}");
        let p = c.signature.p_adjusted.unwrap();
        assert!((p - 4.0841e-3).abs() < 1e-6, "{p}");
    }
    let cs = &trials[1].channels[0];
    assert!(!cs.significant && cs.signature.p_adjusted.is_none());
    let why = cs.not_its_signature.as_deref().unwrap();
    assert!(
        why.starts_with("absorbs misfit of another cause: 75 % of its gain lies where"),
        "{why}"
    );
    let speed = &trials[2].channels[0];
    assert!(!speed.significant);
    let why = speed.not_its_signature.as_deref().unwrap();
    assert!(
        why.contains("does not lie clearly") && why.contains("p=3.00e-1"),
        "{why}"
    );
    let pressure = &trials[3].channels[0];
    assert!(pressure.not_its_signature.is_none() && pressure.signature.p_adjusted.is_none());
}
