//! The whole method: baseline fit and held-out gap, where it lies, which candidate effect
//! closes it (forward selection with paired per-run tests), and how far.

use std::collections::BTreeMap;

use mf87::{Channel, Params};
use serde::Serialize;

use crate::adequacy::{self, Limitation};
use crate::baseline::{
    ErrorSummary, SMOOTHING_WINDOW, Start, cross_validate, fit_channel, fit_some, noise_floor,
    per_run_mse, systematic,
};
use crate::cv::Folds;
use crate::data::{Dataset, Quantity};
use crate::effects::{EffectId, Nominal};
use crate::extrapolate::{self, Extrapolation};
use crate::model::{ChannelData, ChannelModel};
use crate::parallel::parallel_map;
use crate::regions::{Region, rank, regions};
use crate::stats::{channels_combined, correlation, holm, median, mse, sign_flip_greater};

/// Settings of a diagnosis.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Options {
    /// Cross-validation folds (runs are dealt to folds).
    pub folds: usize,
    /// Seed of the split of runs into folds.
    pub seed: u64,
    /// Family-wise significance level after Holm's correction.
    pub significance: f64,
    /// Smallest fraction of the current gap above the noise floor an effect must close.
    pub min_gap_closed: f64,
    /// Below this fraction of the base model's gap, a gain another candidate matches is
    /// not specific to the effect (see `ChannelTrial::unspecific`).
    pub min_base_gap_closed: f64,
    /// Smallest drop of a channel's systematic mean square error, in units of its noise
    /// variance, the first effect must bring: smaller gains are below what the rig resolves.
    pub min_noise_gain: f64,
    /// The same for effects added after the first: the misfit left once the true effects are
    /// in is mostly the formula's shape, which any added freedom reduces a little.
    pub min_noise_gain_later: f64,
    /// A runner-up explaining at least this fraction of the winner's gain is a confounder.
    pub confounding_ratio: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            folds: 5,
            seed: 1,
            significance: 0.05,
            min_gap_closed: 0.10,
            min_base_gap_closed: 0.05,
            min_noise_gain: 0.25,
            min_noise_gain_later: 1.0,
            confounding_ratio: 0.8,
        }
    }
}

/// Why a diagnosis could not be made.
#[derive(Debug, Clone, PartialEq)]
pub struct DiagnoseError(pub String);

impl std::fmt::Display for DiagnoseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// The held-out error of one channel of the base model.
#[derive(Debug, Clone, Serialize)]
pub struct ChannelBaseline {
    pub channel: &'static str,
    pub unit: &'static str,
    pub heldout: ErrorSummary,
    /// In-sample RMS of the fit on all data (`null` for the remaining error, which has none).
    pub in_sample_rms: Option<f64>,
    /// Noise floor estimate (see `baseline::noise_floor`).
    pub noise_floor: f64,
    /// sqrt(max(0, heldout rms^2 - noise^2)): the part of the error the model could explain.
    pub gap: f64,
    /// Why the gap cannot be told from the noise, when it cannot (`null`: it can): no effect
    /// has a share of it to close, and the channel is left out of scores and rankings.
    pub no_gap: Option<String>,
}

/// One candidate on one channel, in one selection round.
#[derive(Debug, Clone, Serialize)]
pub struct ChannelTrial {
    pub channel: &'static str,
    /// Held-out RMS before and after adding the effect [N or N.m].
    pub heldout_before: f64,
    pub heldout_after: f64,
    /// Fraction of the gap above the noise floor (before this round) that the effect closes;
    /// `null` when the channel has no measurable gap left (see `not_scored`).
    pub gap_closed: Option<f64>,
    /// The same gain as a fraction of the base model's gap above the noise floor.
    pub base_gap_closed: Option<f64>,
    /// Why the gain is not scored on this channel, when it is not.
    pub not_scored: Option<String>,
    /// The same gain in units of the channel's noise variance.
    pub noise_gain: f64,
    /// One-sided sign-flip p-value over runs on this channel, and the effect's p-value (its
    /// channels' combined by `stats::channels_combined`) after Holm's correction over the round's
    /// effects; `null` when none of its channels was scored.
    pub p_value: f64,
    pub p_adjusted: Option<f64>,
    pub runs: usize,
    pub significant: bool,
    /// Passed the test, but closes less than `min_base_gap_closed` of the base model's gap
    /// and another candidate closes nearly as much here: not claimed.
    pub unspecific: bool,
    /// Fitted effect parameters on all data.
    pub params: BTreeMap<String, f64>,
}

/// One candidate effect tested in a round.
#[derive(Debug, Clone, Serialize)]
pub struct Trial {
    pub effect: EffectId,
    pub form: &'static str,
    pub channels: Vec<ChannelTrial>,
    pub significant: bool,
    /// Sum over its significant channels of the gap closed (selection score).
    pub score: f64,
}

/// One round of forward selection.
#[derive(Debug, Clone, Serialize)]
pub struct Round {
    pub trials: Vec<Trial>,
    pub selected: Option<EffectId>,
}

/// A candidate that could not be tested, and why.
#[derive(Debug, Clone, Serialize)]
pub struct Untestable {
    pub effect: EffectId,
    pub reason: String,
}

/// A runner-up that the data cannot separate from the winner.
#[derive(Debug, Clone, Serialize)]
pub struct Confounding {
    pub winner: EffectId,
    pub runner_up: EffectId,
    /// Runner-up's score / winner's score.
    pub score_ratio: f64,
    /// Correlation of their held-out corrections on the shared channel, if any.
    pub correction_correlation: Option<f64>,
    pub separating_test: String,
}

/// Everything a diagnosis found.
#[derive(Debug, Clone, Serialize)]
pub struct Diagnosis {
    pub options: Options,
    pub rows: usize,
    pub runs: usize,
    pub nominal: Nominal,
    pub baseline: Vec<ChannelBaseline>,
    pub regions: Vec<Region>,
    pub rounds: Vec<Round>,
    pub verdict: Vec<EffectId>,
    pub confounding: Vec<Confounding>,
    pub untestable: Vec<Untestable>,
    /// What the data cannot support: rows left out, channels not diagnosed, gaps that cannot
    /// be told from the noise.
    pub limitations: Vec<Limitation>,
    /// Held-out error per channel with the selected effects.
    pub remaining: Vec<ChannelBaseline>,
    /// Where the remaining gap lies.
    pub remaining_regions: Vec<Region>,
    /// The first selected effect, refitted with one end of its driving input held out.
    pub extrapolation: Vec<Extrapolation>,
    /// The fitted model per channel (base plus selected effects).
    #[serde(skip)]
    pub models: Vec<ChannelModel>,
    /// Per-row data and held-out residuals per channel, for figures.
    #[serde(skip)]
    pub detail: Vec<ChannelDetail>,
}

/// How many first-round candidates per channel keep their held-out residuals for figures.
const DETAIL_CANDIDATES: usize = 3;

/// One channel's rows with its held-out residuals (measured minus predicted): of the base
/// model, of the final model, and of the base model plus each top first-round candidate.
/// Rows are the dataset's rows, in order, for every channel.
#[derive(Debug, Clone)]
pub struct ChannelDetail {
    pub data: ChannelData,
    /// The base model fitted on all data.
    pub base_model: ChannelModel,
    pub base_residuals: Vec<f64>,
    pub final_residuals: Vec<f64>,
    /// The best first-round candidates on this channel (by gap closed), best first.
    pub candidates: Vec<(EffectId, Vec<f64>)>,
}

/// State of one channel during selection.
struct ChannelState {
    data: ChannelData,
    noise: f64,
    full: ChannelModel,
    /// One model per fold, each fitted on the other folds.
    fold_models: Vec<ChannelModel>,
    residuals: Vec<f64>,
    /// Mean square of the base model's systematic held-out residual, less the white part.
    base_gap_sq: f64,
}

/// Whether a systematic gap (a mean square above the white part) can be told from the noise:
/// it must reach the least gain the method credits any effect with (`min_noise_gain` noise
/// variances). A share of a smaller gap would be a ratio of noise to noise.
fn gap_measurable(gap_sq: f64, noise: f64, options: &Options) -> bool {
    gap_sq > 0.0 && gap_sq >= options.min_noise_gain * noise * noise
}

/// The reason a channel's gap is not measurable, for the report.
fn no_gap_reason(gap_sq: f64, noise: f64, options: &Options) -> String {
    format!(
        "no measurable gap: the systematic part of its held-out residual exceeds \
         the white part by {:.3} noise variances, below the {} that any effect must gain; there \
         is no share of a gap to close",
        gap_sq.max(0.0) / (noise * noise),
        options.min_noise_gain
    )
}

/// Reference conditions: medians of the data (defaults where a column is missing).
pub fn nominal_of(ds: &Dataset) -> Nominal {
    let med = |q: Quantity, default: f64| {
        ds.column(q)
            .and_then(median)
            .filter(|m| *m > 0.0)
            .unwrap_or(default)
    };
    Nominal {
        pressure_kpa: med(Quantity::Pressure, 200.0),
        speed_mps: med(Quantity::Speed, 10.0),
        temperature_c: ds
            .column(Quantity::Temperature)
            .and_then(median)
            .unwrap_or(25.0),
    }
}

fn summary(
    state: &ChannelState,
    residuals: &[f64],
    in_sample_rms: Option<f64>,
    options: &Options,
) -> ChannelBaseline {
    let heldout = ErrorSummary::of(residuals, &state.data.fz_kn);
    let white = state.noise * state.noise / SMOOTHING_WINDOW as f64;
    let gap_sq = mse(&systematic(&state.data.run, residuals)) - white;
    ChannelBaseline {
        channel: state.data.channel.name(),
        unit: if state.data.channel == Channel::Mz {
            "N.m"
        } else {
            "N"
        },
        heldout,
        in_sample_rms,
        noise_floor: state.noise,
        gap: (heldout.rms.powi(2) - state.noise.powi(2)).max(0.0).sqrt(),
        no_gap: (!gap_measurable(gap_sq, state.noise, options))
            .then(|| no_gap_reason(gap_sq, state.noise, options)),
    }
}

/// The rows where an effect, if present, must show (its "home"): the paired test is run there,
/// so a candidate that merely soaks up a misfit of the base formula elsewhere is not claimed.
/// `None`: every row.
fn home_rows(effect: EffectId, data: &ChannelData) -> Option<Vec<bool>> {
    match effect {
        // Offsets at zero slip: the linear range, |alpha| < 2 deg.
        EffectId::PlySteerConicity => Some(data.slip.iter().map(|a| a.abs() < 2.0).collect()),
        // Force against rolling at zero slip: |sigma| < 1 %.
        EffectId::RollingResistance => Some(data.slip.iter().map(|s| s.abs() < 1.0).collect()),
        // Combined slip: rows where the other slip is not small.
        EffectId::CombinedSlip => {
            let threshold = if data.channel == Channel::Fx {
                1f64.to_radians()
            } else {
                0.02
            };
            data.other_slip
                .as_ref()
                .map(|o| o.iter().map(|x| x.abs() > threshold).collect())
        }
        // Effects on stiffness, peak or the slip's history act on the force the slip makes:
        // they cannot show where the channel's own slip is near zero (Fx in pure cornering).
        // |alpha| >= 1 deg for Fy and Mz, |sigma| >= 1 % for Fx.
        EffectId::RelaxationLength
        | EffectId::InflationPressure
        | EffectId::SpeedDependence
        | EffectId::Temperature => Some(data.slip.iter().map(|s| s.abs() >= 1.0).collect()),
    }
}

/// Whether a column varies enough to test an effect driven by it.
fn varies(ds: &Dataset, q: Quantity) -> bool {
    let Some(v) = ds.column(q) else { return false };
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(*x), hi.max(*x))
        });
    hi - lo > 1e-6 * hi.abs().max(1.0)
}

/// Why `effect` cannot be tested on `channel` with this data, if it cannot.
fn untestable_reason(ds: &Dataset, effect: EffectId, channel: Channel) -> Option<String> {
    for q in effect.needs(channel) {
        if !ds.has(*q) {
            return Some(format!("no {} column", q.name()));
        }
        if *q != Quantity::Time && !varies(ds, *q) {
            return Some(format!("{} does not vary in the data", q.name()));
        }
    }
    None
}

/// A candidate's fit on every fold (effect parameters only, the fold's model held) and on all
/// data, with its held-out residuals.
struct CandidateFit {
    full: ChannelModel,
    fold_models: Vec<ChannelModel>,
    residuals: Vec<f64>,
}

fn fit_candidate(state: &ChannelState, effect: EffectId, folds: &Folds) -> Option<CandidateFit> {
    let data = &state.data;
    let with = |m: &ChannelModel| m.with_effect(effect);
    let positions = |m: &ChannelModel| {
        let n = m.theta().len();
        let k = effect.parameters(m.channel).len();
        (n - k..n).collect::<Vec<_>>()
    };
    // Warm-started from each fold's own model (fitted on the same training rows): first the
    // effect's parameters alone, then a short joint refit with the base coefficients, since
    // the base may have absorbed part of the effect (e.g. a speed trend into the load terms
    // when the runs' loads and speeds correlate), which the effect alone could not undo.
    let refit = |train: &ChannelData, base: &ChannelModel| {
        let start = with(base);
        let effect_only = fit_some(train, &start, &positions(&start))?.model;
        Some(fit_channel(train, &effect_only, Start::Polish)?.model)
    };
    let (fold_models, residuals) = cross_validate(data, folds, |train, fold| {
        refit(train, &state.fold_models[fold])
    })?;
    let full = refit(data, &state.full)?;
    Some(CandidateFit {
        full,
        fold_models,
        residuals,
    })
}

/// How a candidate fared on one channel.
struct Score {
    /// One-sided sign-flip p-value of per-run relative improvements in the effect's home rows.
    p_value: f64,
    /// Runs compared.
    runs: usize,
    /// Fraction of the systematic gap above the noise floor closed, now and of the base's;
    /// `None` when that gap is not measurable (`not_scored` says why).
    gap_closed: Option<f64>,
    base_gap_closed: Option<f64>,
    noise_gain: f64,
    not_scored: Option<String>,
}

/// Scores a candidate fit against the channel's current model, both on the systematic part
/// of the held-out residual (`systematic_before` is the current model's).
fn score(
    state: &ChannelState,
    systematic_before: &[f64],
    effect: EffectId,
    fit: &CandidateFit,
    options: &Options,
) -> Score {
    let run = &state.data.run;
    let systematic_after = systematic(run, &fit.residuals);
    let home = home_rows(effect, &state.data);
    let at_home = |r: &[f64]| -> Vec<f64> {
        match &home {
            Some(h) => r
                .iter()
                .zip(h)
                .map(|(x, keep)| if *keep { *x } else { f64::NAN })
                .collect(),
            None => r.to_vec(),
        }
    };
    let before = per_run_mse(run, &at_home(systematic_before));
    let after = per_run_mse(run, &at_home(&systematic_after));
    // Each run's gain relative to its own error plus the runs' mean error: below 1, so no
    // run can carry the test alone and a run with a large misfit of another kind does not
    // drown the others, while runs whose error is already small (e.g. Fx in pure cornering)
    // weigh little instead of adding their noise at full weight.
    let typical = before.values().sum::<f64>() / before.len().max(1) as f64;
    let gains: BTreeMap<i64, f64> = before
        .iter()
        .filter_map(|(r, b)| {
            Some((
                *r,
                (b - after.get(r)?) / (b + typical).max(f64::MIN_POSITIVE),
            ))
        })
        .collect();
    let (sys_before, sys_after) = (mse(systematic_before), mse(&systematic_after));
    let noise_var = state.noise * state.noise;
    let white = noise_var / SMOOTHING_WINDOW as f64;
    // The fall of the systematic mean square error as a share of a measurable gap.
    let share_of = |gap_sq: f64| {
        gap_measurable(gap_sq, state.noise, options).then(|| (sys_before - sys_after) / gap_sq)
    };
    let gap_sq = sys_before - white;
    let gap_closed = share_of(gap_sq);
    Score {
        p_value: sign_flip_greater(&gains.values().copied().collect::<Vec<f64>>()),
        runs: gains.len(),
        not_scored: gap_closed
            .is_none()
            .then(|| no_gap_reason(gap_sq, state.noise, options)),
        gap_closed,
        base_gap_closed: share_of(state.base_gap_sq),
        noise_gain: (sys_before - sys_after) / noise_var,
    }
}

/// The separating experiment for a pair of effects the data cannot tell apart.
fn separating_test(a: EffectId, b: EffectId) -> String {
    use EffectId::*;
    let (a, b) = if a <= b { (a, b) } else { (b, a) };
    match (a, b) {
        (SpeedDependence, Temperature) => {
            "repeat sweeps at two speeds with the tread held at one temperature (pre-conditioned), \
             and at one speed at two tread temperatures"
                .into()
        }
        (RelaxationLength, SpeedDependence) => {
            "steady-state slip sweeps (slow enough for the lag to vanish) at several speeds, and \
             sinusoidal slip at one speed and several frequencies"
                .into()
        }
        (CombinedSlip, RelaxationLength) => {
            "quasi-static combined-slip sweeps, and transient pure-slip steps".into()
        }
        (InflationPressure, Temperature) => {
            "sweeps at two pressures with the tread at one temperature (cold pressure set, \
             temperature logged)"
                .into()
        }
        (SpeedDependence, RollingResistance) | (RollingResistance, Temperature) => {
            "free-rolling runs (zero slip) at several speeds and temperatures".into()
        }
        _ => format!(
            "runs that vary the input of {} while holding the input of {} constant, and the reverse",
            a.id(),
            b.id()
        ),
    }
}

/// The base model of one channel: fitted on all data, and per fold for held-out residuals.
struct BaseFit {
    in_sample_rms: f64,
    noise: f64,
    full: ChannelModel,
    fold_models: Vec<ChannelModel>,
    residuals: Vec<f64>,
    base_gap_sq: f64,
}

impl BaseFit {
    fn into_state(self, data: ChannelData) -> ChannelState {
        ChannelState {
            data,
            noise: self.noise,
            full: self.full,
            fold_models: self.fold_models,
            residuals: self.residuals,
            base_gap_sq: self.base_gap_sq,
        }
    }
}

/// Steps 1-2 for one channel: the 1987 model fitted on all data (several starts) and on each
/// fold's training runs, its held-out residuals and their noise floor.
fn fit_base(
    data: &ChannelData,
    folds: &Folds,
    paper: &Params,
    nominal: Nominal,
) -> Result<BaseFit, DiagnoseError> {
    let channel = data.channel;
    let start = ChannelModel::new(paper.clone(), channel, data.has_camber(), nominal);
    let fit = fit_channel(data, &start, Start::Multi).ok_or_else(|| {
        DiagnoseError(format!(
            "the fit of {channel} failed (non-finite model values)"
        ))
    })?;
    // A fold whose training fit fails keeps the all-data fit.
    let (fold_models, residuals) = cross_validate(data, folds, |train, _| {
        Some(
            fit_channel(train, &fit.model, Start::Warm)
                .map_or_else(|| fit.model.clone(), |f| f.model),
        )
    })
    .ok_or_else(|| DiagnoseError(format!("cross-validation of {channel} failed")))?;
    let noise = noise_floor(&data.run, &residuals);
    let white = noise * noise / SMOOTHING_WINDOW as f64;
    let base_gap_sq = (mse(&systematic(&data.run, &residuals)) - white).max(0.0);
    Ok(BaseFit {
        in_sample_rms: (fit.sse / data.len() as f64).sqrt(),
        noise,
        full: fit.model,
        fold_models,
        residuals,
        base_gap_sq,
    })
}

/// The measured channels the data can support, with the limitations of those it cannot.
fn channels_to_diagnose(
    ds: &Dataset,
    folds: &Folds,
    limitations: &mut Vec<Limitation>,
) -> Result<Vec<ChannelData>, DiagnoseError> {
    let measured: Vec<ChannelData> = [Channel::Fx, Channel::Fy, Channel::Mz]
        .into_iter()
        .filter_map(|channel| ChannelData::from_dataset(ds, channel))
        .collect();
    if measured.is_empty() {
        return Err(DiagnoseError(
            "no measured channel with its slip: nothing to fit".into(),
        ));
    }
    let coefficients = measured
        .iter()
        .map(adequacy::fitted_coefficients)
        .max()
        .unwrap_or(0);
    adequacy::check_runs(ds, folds, coefficients).map_err(DiagnoseError)?;
    let mut channels = Vec::new();
    for data in measured {
        match adequacy::check_channel(&data, folds)
            .map_err(|e| DiagnoseError(format!("{}: implausible data: {e}", ds.source)))?
        {
            Some(limitation) => limitations.push(limitation),
            None => channels.push(data),
        }
    }
    if channels.is_empty() {
        let reasons: Vec<String> = limitations
            .iter()
            .map(|l| format!("{}: {}", l.subject, l.reason))
            .collect();
        return Err(DiagnoseError(format!(
            "{}: no channel can be diagnosed: {}",
            ds.source,
            reasons.join("; ")
        )));
    }
    limitations.extend(adequacy::load_range(ds));
    Ok(channels)
}

/// Runs the whole method on `ds`.
pub fn diagnose(
    ds: &Dataset,
    options: &Options,
    mut progress: impl FnMut(&str),
) -> Result<Diagnosis, DiagnoseError> {
    let (ds, left_out) = adequacy::loaded_rows(ds).map_err(DiagnoseError)?;
    let ds: &Dataset = &ds;
    let mut limitations: Vec<Limitation> = left_out.into_iter().collect();
    let folds = Folds::new(&ds.run, options.folds, options.seed);
    let channels = channels_to_diagnose(ds, &folds, &mut limitations)?;
    let nominal = nominal_of(ds);
    let paper = Params::paper_table();

    // 1-2: base fit, held-out error, noise floor; the channels in parallel.
    progress(&format!(
        "fitting the 1987 model to {} ({} rows)",
        channels
            .iter()
            .map(|d| d.channel.name())
            .collect::<Vec<_>>()
            .join(", "),
        ds.len()
    ));
    let fitted = parallel_map(&channels, |data| fit_base(data, &folds, &paper, nominal));
    let mut states: Vec<(f64, ChannelState)> = Vec::new();
    for (data, fit) in channels.into_iter().zip(fitted) {
        let fit = fit?;
        let rms = mse(&fit.residuals).sqrt();
        match adequacy::noise_floor_limitation(data.channel, fit.noise, rms) {
            Some(limitation) => limitations.push(limitation),
            None => states.push((fit.in_sample_rms, fit.into_state(data))),
        }
    }
    if states.is_empty() {
        return Err(DiagnoseError(format!(
            "{}: no channel can be diagnosed: {}",
            ds.source,
            limitations
                .iter()
                .map(|l| format!("{}: {}", l.subject, l.reason))
                .collect::<Vec<_>>()
                .join("; ")
        )));
    }
    let baseline: Vec<ChannelBaseline> = states
        .iter()
        .map(|(rms, s)| summary(s, &s.residuals, Some(*rms), options))
        .collect();
    for b in &baseline {
        if let Some(reason) = &b.no_gap {
            limitations.push(Limitation::new(
                b.channel,
                format!("{reason}; no effect is tested on it"),
            ));
        }
    }
    // Regions rank where a gap lies: channels without one hold only noise.
    let base_regions = rank(
        states
            .iter()
            .zip(&baseline)
            .filter(|(_, b)| b.no_gap.is_none())
            .flat_map(|((_, s), _)| regions(&s.data, &s.residuals))
            .collect(),
    );
    let mut states: Vec<ChannelState> = states.into_iter().map(|(_, s)| s).collect();
    // For figures: the base fit per channel, and the top first-round candidates.
    let base: Vec<(ChannelModel, Vec<f64>)> = states
        .iter()
        .map(|s| (s.full.clone(), s.residuals.clone()))
        .collect();
    let mut top_candidates: Vec<Vec<(EffectId, Vec<f64>)>> = vec![Vec::new(); states.len()];

    // 4: candidates, forward selection. Each (effect, channel) pair is tested where the
    // effect acts on the channel and the data has what it needs.
    let mut untestable = Vec::new();
    let mut pairs: Vec<(EffectId, usize)> = Vec::new();
    for effect in EffectId::ALL {
        let mut reasons = Vec::new();
        for (ci, state) in states.iter().enumerate() {
            let ch = state.data.channel;
            if !effect.applies_to(ch) {
                continue;
            }
            if baseline[ci].no_gap.is_some() {
                reasons.push(format!("{ch}: no measurable gap above the noise floor"));
                continue;
            }
            match untestable_reason(ds, effect, ch) {
                None => pairs.push((effect, ci)),
                Some(r) => reasons.push(format!("{ch}: {r}")),
            }
        }
        if !pairs.iter().any(|(e, _)| *e == effect) {
            let reason = if reasons.is_empty() {
                "none of the channels it acts on is measured".to_string()
            } else {
                reasons.join("; ")
            };
            untestable.push(Untestable { effect, reason });
        }
    }
    // Pairs not yet in the model: an effect added on some channels stays a candidate on the
    // others (its evidence there may only show once other gaps are closed).
    let mut open = pairs.clone();
    // Candidate fits of earlier rounds stay valid until their channel's model changes.
    let mut cache: BTreeMap<(EffectId, usize), Option<CandidateFit>> = BTreeMap::new();

    let mut rounds = Vec::new();
    let mut verdict = Vec::new();
    let mut confounding = Vec::new();
    while !open.is_empty() {
        let jobs: Vec<(EffectId, usize)> = open
            .iter()
            .copied()
            .filter(|k| !cache.contains_key(k))
            .collect();
        progress(&format!(
            "selection round {}: fitting {} candidate-channel pairs",
            rounds.len() + 1,
            jobs.len()
        ));
        let fitted = parallel_map(&jobs, |&(effect, ci)| {
            fit_candidate(&states[ci], effect, &folds)
        });
        cache.extend(jobs.into_iter().zip(fitted));
        let fits: Vec<(EffectId, usize, &CandidateFit)> = open
            .iter()
            .filter_map(|&(e, ci)| Some((e, ci, cache.get(&(e, ci))?.as_ref()?)))
            .collect();
        // Judged on the systematic part: white noise cannot be explained by any effect.
        let systematic_before: Vec<Vec<f64>> = states
            .iter()
            .map(|s| systematic(&s.data.run, &s.residuals))
            .collect();
        let scores: Vec<Score> = fits
            .iter()
            .map(|(effect, ci, fit)| {
                score(&states[*ci], &systematic_before[*ci], *effect, fit, options)
            })
            .collect();
        if rounds.is_empty() {
            for (ci, top) in top_candidates.iter_mut().enumerate() {
                let mut mine: Vec<(f64, usize)> = fits
                    .iter()
                    .enumerate()
                    .filter(|(_, (_, c, _))| *c == ci)
                    .map(|(k, _)| (scores[k].gap_closed.unwrap_or(f64::NEG_INFINITY), k))
                    .collect();
                mine.sort_by(|a, b| b.0.total_cmp(&a.0));
                *top = mine
                    .iter()
                    .take(DETAIL_CANDIDATES)
                    .map(|&(_, k)| (fits[k].0, fits[k].2.residuals.clone()))
                    .collect();
            }
        }
        let p_values: Vec<f64> = scores.iter().map(|s| s.p_value).collect();
        // One test per effect: its channels' p-values combined (`channels_combined`: Fisher or
        // Bonferroni, whichever is stronger), Holm-corrected over the round's effects. An
        // average of the channels' gains would let a channel the effect does not touch hide one
        // it does.
        let mut round_effects: Vec<EffectId> = fits.iter().map(|f| f.0).collect();
        round_effects.sort();
        round_effects.dedup();
        // Channels without a measurable gap left take no part.
        let pooled: Vec<Option<f64>> = round_effects
            .iter()
            .map(|e| {
                let mine: Vec<f64> = fits
                    .iter()
                    .zip(&scores)
                    .filter(|(f, s)| f.0 == *e && s.gap_closed.is_some())
                    .map(|(_, s)| s.p_value)
                    .collect();
                (!mine.is_empty()).then(|| channels_combined(&mine))
            })
            .collect();
        let tested: Vec<f64> = pooled.iter().flatten().copied().collect();
        let mut tested_adjusted = holm(&tested).into_iter();
        let pooled_adjusted: Vec<Option<f64>> = pooled
            .iter()
            .map(|p| p.and_then(|_| tested_adjusted.next()))
            .collect();
        let adjusted: Vec<Option<f64>> = fits
            .iter()
            .map(|f| {
                let i = round_effects.iter().position(|e| *e == f.0)?;
                pooled_adjusted[i]
            })
            .collect();
        let mut trials: Vec<Trial> = Vec::new();
        for (k, (effect, ci, fit)) in fits.iter().enumerate() {
            let s = &states[*ci];
            let (before, after) = (mse(&s.residuals), mse(&fit.residuals));
            let Score {
                gap_closed,
                base_gap_closed,
                noise_gain,
                ref not_scored,
                ..
            } = scores[k];
            // The effect is significant, and this channel shows it on its own, by an amount
            // that matters against both the gap left and the sensor noise.
            let min_noise_gain = if verdict.is_empty() {
                options.min_noise_gain
            } else {
                options.min_noise_gain_later
            };
            let significant = adjusted[k].is_some_and(|p| p < options.significance)
                && p_values[k] < options.significance
                && gap_closed.is_some_and(|g| g >= options.min_gap_closed)
                && noise_gain >= min_noise_gain;
            let names = fit.full.names();
            let theta = fit.full.theta();
            let n_eff = effect.parameters(s.data.channel).len();
            let params = names[names.len() - n_eff..]
                .iter()
                .cloned()
                .zip(theta[theta.len() - n_eff..].iter().copied())
                .collect();
            let trial = ChannelTrial {
                channel: s.data.channel.name(),
                heldout_before: before.sqrt(),
                heldout_after: after.sqrt(),
                gap_closed,
                base_gap_closed,
                not_scored: not_scored.clone(),
                noise_gain,
                p_value: p_values[k],
                p_adjusted: adjusted[k],
                runs: scores[k].runs,
                significant,
                unspecific: false,
                params,
            };
            match trials.iter_mut().find(|t| t.effect == *effect) {
                Some(t) => t.channels.push(trial),
                None => trials.push(Trial {
                    effect: *effect,
                    form: effect.form(),
                    channels: vec![trial],
                    significant: false,
                    score: 0.0,
                }),
            }
        }
        // Specificity: a gain that is small against the base model's gap, and that another
        // candidate matches on the same channel, is extra freedom soaking up misfit of the
        // formula's shape, not evidence of this effect.
        let gains_on = |channel: &str, other_than: EffectId| -> f64 {
            trials
                .iter()
                .filter(|u| u.effect != other_than)
                .flat_map(|u| u.channels.iter().filter(|c| c.channel == channel))
                .filter_map(|c| c.gap_closed)
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let unspecific: Vec<(EffectId, &'static str)> = trials
            .iter()
            .flat_map(|t| {
                t.channels
                    .iter()
                    .filter(|c| {
                        let (Some(gap), Some(base)) = (c.gap_closed, c.base_gap_closed) else {
                            return false;
                        };
                        c.significant
                            && base < options.min_base_gap_closed
                            && gains_on(c.channel, t.effect) >= options.confounding_ratio * gap
                    })
                    .map(|c| (t.effect, c.channel))
            })
            .collect();
        for t in &mut trials {
            for c in &mut t.channels {
                if unspecific.contains(&(t.effect, c.channel)) {
                    c.significant = false;
                    c.unspecific = true;
                }
            }
        }
        for t in &mut trials {
            t.significant = t.channels.iter().any(|c| c.significant);
            t.score = t
                .channels
                .iter()
                .filter(|c| c.significant)
                .filter_map(|c| c.gap_closed)
                .map(|g| g.max(0.0))
                .sum();
        }
        trials.sort_by(|a, b| {
            b.score.total_cmp(&a.score).then_with(|| {
                let best = |t: &Trial| {
                    t.channels
                        .iter()
                        .filter_map(|c| c.gap_closed)
                        .fold(f64::MIN, f64::max)
                };
                best(b).total_cmp(&best(a))
            })
        });
        let winner = trials.first().filter(|t| t.significant).map(|t| t.effect);
        if let Some(w) = winner {
            let best_other = |t: &Trial| {
                t.channels
                    .iter()
                    .filter_map(|c| c.gap_closed)
                    .map(|g| g.max(0.0))
                    .sum::<f64>()
            };
            // Correlations only on channels with a measurable gap left.
            let scored = |e: EffectId, ci: usize| {
                fits.iter()
                    .zip(&scores)
                    .any(|((fe, fc, _), s)| *fe == e && *fc == ci && s.gap_closed.is_some())
            };
            let w_score = trials[0].score;
            for t in trials.iter().skip(1) {
                let ratio = best_other(t) / w_score.max(1e-12);
                let corr = fits
                    .iter()
                    .filter(|(e, ci, _)| *e == w && scored(w, *ci) && scored(t.effect, *ci))
                    .find_map(|(_, ci, fw)| {
                        let (_, _, fr) = fits.iter().find(|(e, c, _)| *e == t.effect && c == ci)?;
                        let s = &states[*ci];
                        let dw: Vec<f64> = s
                            .residuals
                            .iter()
                            .zip(&fw.residuals)
                            .map(|(a, b)| a - b)
                            .collect();
                        let dr: Vec<f64> = s
                            .residuals
                            .iter()
                            .zip(&fr.residuals)
                            .map(|(a, b)| a - b)
                            .collect();
                        correlation(&dw, &dr)
                    });
                if ratio >= options.confounding_ratio
                    || corr.is_some_and(|c| c >= 0.8 && ratio >= 0.5)
                {
                    confounding.push(Confounding {
                        winner: w,
                        runner_up: t.effect,
                        score_ratio: ratio,
                        correction_correlation: corr,
                        separating_test: separating_test(w, t.effect),
                    });
                }
            }
            // Add the winner on the channels where it was significant.
            let adopted: Vec<usize> =
                fits.iter()
                    .filter(|(effect, ci, _)| {
                        *effect == w
                            && trials[0].channels.iter().any(|c| {
                                c.significant && c.channel == states[*ci].data.channel.name()
                            })
                    })
                    .map(|(_, ci, _)| *ci)
                    .collect();
            for ci in adopted {
                if let Some(Some(fit)) = cache.remove(&(w, ci)) {
                    let s = &mut states[ci];
                    s.full = fit.full;
                    s.fold_models = fit.fold_models;
                    s.residuals = fit.residuals;
                }
                open.retain(|&(e, c)| (e, c) != (w, ci));
                cache.retain(|&(_, c), _| c != ci);
            }
            if !verdict.contains(&w) {
                verdict.push(w);
            }
        }
        rounds.push(Round {
            trials,
            selected: winner,
        });
        if winner.is_none() {
            break;
        }
    }

    let remaining_summary: Vec<ChannelBaseline> = states
        .iter()
        .map(|s| summary(s, &s.residuals, None, options))
        .collect();
    let remaining_regions = rank(
        states
            .iter()
            .zip(&remaining_summary)
            .filter(|(_, r)| r.no_gap.is_none())
            .flat_map(|(s, _)| regions(&s.data, &s.residuals))
            .collect(),
    );
    let extrapolation = match verdict.first() {
        Some(&winner) => {
            progress(&format!("extrapolation check of {winner}"));
            let with: Vec<&ChannelState> = states
                .iter()
                .filter(|s| s.full.effects.iter().any(|(e, _)| *e == winner))
                .collect();
            parallel_map(&with, |s| extrapolate::check(winner, &s.data, &s.full))
                .into_iter()
                .flatten()
                .collect()
        }
        None => Vec::new(),
    };
    let (models, detail): (Vec<ChannelModel>, Vec<ChannelDetail>) = states
        .into_iter()
        .zip(base)
        .zip(top_candidates)
        .map(|((s, (base_model, base_residuals)), candidates)| {
            let detail = ChannelDetail {
                data: s.data,
                base_model,
                base_residuals,
                final_residuals: s.residuals,
                candidates,
            };
            (s.full, detail)
        })
        .unzip();
    Ok(Diagnosis {
        options: *options,
        rows: ds.len(),
        runs: folds.runs(),
        nominal,
        baseline,
        regions: base_regions,
        rounds,
        verdict,
        confounding,
        untestable,
        limitations,
        remaining: remaining_summary,
        remaining_regions,
        extrapolation,
        models,
        detail,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cv::splitmix;

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
        let data = ChannelData::from_dataset(&ds, Channel::Fy).unwrap();
        let model = ChannelModel::new(Params::paper_table(), Channel::Fy, false, nominal_of(&ds));
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
}
