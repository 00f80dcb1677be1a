//! The fit step of a selection round: a candidate effect added to a channel's current model,
//! fitted on all data and, when it could matter, on every fold, with its held-out residuals.
//!
//! The all-data fit comes first and screens: a candidate whose fit lowers the sum of squares
//! on all data by less than a share of the least gain any effect must show on held-out runs
//! cannot show that gain (a held-out gain rarely exceeds the in-sample one). An effect whose
//! every channel is such is not refitted per fold: its held-out residuals are those of each
//! fold's current model with the effect added at its all-data parameters, and it is not
//! claimed. An effect with one channel that could show the gain is refitted on all its
//! channels, since its p-value combines theirs.

use super::plausibility::Plausibility;
use super::state::ChannelState;
use crate::method::fit::channel_fit::{
    Admissible, SMOOTHING_WINDOW, Start, cross_validate, fit_channel, fit_some, held_out,
    restarted, systematic_mse,
};
use crate::method::fit::effects::{self, Extension};
use crate::method::fit::model::ChannelModel;
use crate::method::prepare::channel_data::{ChannelData, ranges_of};
use crate::method::prepare::cv::Folds;
use crate::method::stats::CompactResiduals;

/// A candidate is refitted per fold when its all-data fit gains at least this share of the
/// least held-out gain it must show.
pub(super) const SCREEN_SHARE: f64 = 0.5;

/// A candidate fitted on all data: what a round needs of it whatever the folds.
pub(super) struct FullFit {
    pub(super) model: ChannelModel,
    /// The effect's parameters fitted alone on all data (the first stage of the fit).
    pub(super) effect_alone: Vec<f64>,
    /// The fall of the channel's in-sample mean square error (on the fitting sample) from its
    /// current model [unit squared].
    pub(super) in_sample_gain: f64,
    /// Whether the fit came from the paper's base rather than the current one: the folds'
    /// fits then start from it too.
    pub(super) restarted: bool,
}

/// A candidate's fit on all data and its held-out residuals on one assignment of folds.
pub(super) struct CandidateFit {
    pub(super) full: ChannelModel,
    /// The held-out residuals until the candidate is scored (`None` afterwards: predicted
    /// again from the models when needed, see [`CandidateFit::held_out`]).
    pub(super) residuals: Option<CompactResiduals>,
    /// One model per fold, each fitted on the other folds (`None`: screened out).
    pub(super) fold_models: Option<Vec<ChannelModel>>,
    /// Why it was not refitted per fold, when it was not.
    pub(super) screened: Option<String>,
}

/// A fitted candidate of the current round: `effect` on the channel at `channel` among the
/// states.
pub(super) struct PairFit<'a> {
    pub(super) effect: Extension,
    pub(super) channel: usize,
    pub(super) fit: &'a CandidateFit,
    /// The mean square of its held-out residuals.
    pub(super) mse: f64,
}

impl CandidateFit {
    /// Its held-out residuals on `folds` for `state` (the channel it was fitted on): the kept
    /// ones, or the same values predicted again by its models; `None` when a fold's model
    /// fails to predict.
    pub(super) fn held_out(
        &self,
        state: &ChannelState,
        effect: Extension,
        folds: &Folds,
    ) -> Option<std::borrow::Cow<'_, CompactResiduals>> {
        if let Some(r) = &self.residuals {
            return Some(std::borrow::Cow::Borrowed(r));
        }
        let residuals = match &self.fold_models {
            Some(models) => held_out::<f32>(&state.data, folds, |fold| Some(models[fold].clone()))?,
            None => {
                let values = effect_values(&self.full, effect);
                held_out::<f32>(&state.data, folds, |fold| {
                    Some(with_effect_at(&state.fold_models[fold], effect, &values))
                })?
            }
        };
        Some(std::borrow::Cow::Owned(CompactResiduals::from_single(
            residuals,
        )))
    }
}

/// The positions of `effect`'s parameters in the parameter vector of `model`, which ends
/// with them.
fn effect_positions(model: &ChannelModel, effect: Extension) -> Vec<usize> {
    let n = model.theta().len();
    (n - effect.parameter_names().len()..n).collect()
}

/// `start` (a model ending with `effect` at its starting values) fitted on `train`: first the
/// effect's parameters alone, then a short joint refit with the base coefficients, since the
/// base may have absorbed part of the effect (e.g. a speed trend into the load terms when the
/// runs' loads and speeds correlate), which the effect alone could not undo. A joint refit
/// that takes a base coefficient out of the FMU's bounds (e.g. a camber coefficient onto the
/// singularity of E / (1 - a13 |gamma|)) is not kept: the effect alone, fitted within them,
/// is. Both stages stay within the FMU's bounds from a start inside them, for the fold fits as
/// for the all-data fit: a held-out gain is scored only for models a parameter file can hold.
/// From `Stage::Neutral` (the effect at its neutral values) the parameters the effect fits
/// first are fitted alone before the others. With `claimed` (the all-data fit, which is
/// claimed and exported), a result that fails the effect's own physical check on `train` (see
/// [`effects::Effect::implausible`]) is fitted again held to that check too.
/// Returns the fit and the effect's parameters of the first stage.
fn refit(
    train: &ChannelData,
    start: &ChannelModel,
    effect: Extension,
    plausibility: &Plausibility,
    from: Stage,
    claimed: bool,
) -> Option<(ChannelModel, Vec<f64>)> {
    let exports = |m: &ChannelModel| plausibility.exports(m);
    // Within the FMU's bounds and physical on the data (the effect's own check, e.g. a
    // combined-slip weight that stays positive over the measured other slip).
    let physical = |m: &ChannelModel| {
        exports(m)
            && m.effects
                .iter()
                .filter(|(e, _)| *e == effect)
                .all(|(_, q)| {
                    effects::of(effect)
                        .implausible(train, &effects::model_values(effect, q))
                        .is_none()
                })
    };
    let fitted = stages(train, start, effect, plausibility, from, &exports)?;
    // Held to the physical check only when the fit within the bounds fails it: the check on
    // every step can stop a fit short of the optimum it would reach.
    if claimed && !physical(&fitted.0) {
        return stages(train, start, effect, plausibility, from, &physical).or(Some(fitted));
    }
    Some(fitted)
}

/// Where a [`refit`] starts the effect's parameters.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Stage {
    /// At the effect's neutral values (no effect).
    Neutral,
    /// At values fitted before (the all-data fit's first stage).
    Fitted,
}

/// The stages of [`refit`] within `admissible`.
fn stages(
    train: &ChannelData,
    start: &ChannelModel,
    effect: Extension,
    plausibility: &Plausibility,
    from: Stage,
    admissible: Admissible,
) -> Option<(ChannelModel, Vec<f64>)> {
    let admissible = Some(admissible);
    let positions = effect_positions(start, effect);
    let base_refitted = (from == Stage::Neutral && effects::of(effect).base_first_off_home())
        .then(|| base_off_home(train, start, effect, admissible))
        .flatten();
    let start = base_refitted.as_ref().unwrap_or(start);
    // From the effect's neutral start, the parameters it fits first, alone.
    let first: Vec<usize> = effects::of(effect)
        .first_fitted(train.channel)
        .iter()
        .map(|&i| positions[i])
        .collect();
    let from_first = (from == Stage::Neutral && !first.is_empty())
        .then(|| fit_some(train, start, &first, admissible))
        .flatten()
        .map(|f| f.model);
    let start = from_first.as_ref().unwrap_or(start);
    let effect_only = fit_some(train, start, &positions, admissible)?.model;
    let alone = effect_values(&effect_only, effect);
    let joint = fit_channel(train, &effect_only, Start::Polish, admissible)?.model;
    let fit = if plausibility.exports(&joint) || !plausibility.exports(&effect_only) {
        joint
    } else {
        effect_only
    };
    Some((fit, alone))
}

/// Rows outside an effect's home, as a share of all, below which the base is not refitted on
/// them alone.
const OFF_HOME_SHARE_MIN: f64 = 0.05;
/// Rows per base coefficient at least, for the base refitted outside the home.
const OFF_HOME_ROWS_PER_TERM: usize = 20;

/// `start`'s base coefficients (the 1987 formula's, which lead its parameter vector) refitted
/// on the rows of `train` outside `effect`'s home; `None` when they are too few.
pub(super) fn base_off_home(
    train: &ChannelData,
    start: &ChannelModel,
    effect: Extension,
    admissible: Option<Admissible>,
) -> Option<ChannelModel> {
    let home = effects::of(effect).home_rows(train)?;
    let off: Vec<usize> = (0..train.len()).filter(|&i| !home[i]).collect();
    let base: Vec<usize> = (0..start.free.len()).collect();
    let enough = off.len() as f64 >= OFF_HOME_SHARE_MIN * train.len() as f64
        && off.len() >= OFF_HOME_ROWS_PER_TERM * base.len();
    if !enough {
        return None;
    }
    fit_some(
        &train.fitting_subset(&ranges_of(&off)),
        start,
        &base,
        admissible,
    )
    .map(|f| f.model)
}

/// The held-out residuals of the channel's current model refitted per fold on the training
/// rows outside `effect`'s home (where its driver is idle), for an effect whose base is fitted
/// first there: what its signature's gain is measured against (see `signature`). `None` for
/// any other effect, or when a fold has too few such rows.
pub(super) fn idle_reference(
    state: &ChannelState,
    effect: Extension,
    folds: &Folds,
    plausibility: &Plausibility,
) -> Option<CompactResiduals> {
    if !effects::of(effect).base_first_off_home() {
        return None;
    }
    let admissible = |m: &ChannelModel| plausibility.exports(m);
    let (_, residuals) = cross_validate::<f32>(&state.data, folds, |train, fold| {
        base_off_home(train, &state.fold_models[fold], effect, Some(&admissible))
    })?;
    Some(CompactResiduals::from_single(residuals))
}

/// Mean square of `model`'s residuals over the counted rows of `data`'s fitting sample.
pub(super) fn in_sample_mse(model: &ChannelModel, data: &ChannelData) -> f64 {
    let sample = data.fitting_sample();
    let mut r = vec![0.0; sample.len()];
    model.residuals(&model.theta(), &sample, &mut r);
    let counted = sample
        .counted
        .as_ref()
        .map_or(sample.len(), |c| c.iter().filter(|c| **c).count());
    r.iter().map(|r| r * r).sum::<f64>() / counted.max(1) as f64
}

/// `effect` added to the channel's current model and fitted on all data; `None` when a fit
/// fails.
/// `base_mse` is the current model's [`in_sample_mse`], the same for every candidate of the
/// channel.
pub(super) fn fit_full(
    state: &ChannelState,
    base_mse: f64,
    effect: Extension,
    plausibility: &Plausibility,
) -> Option<FullFit> {
    let from = |start: &ChannelModel| {
        refit(
            &state.data,
            &start.with_effect(effect),
            effect,
            plausibility,
            Stage::Neutral,
            true,
        )
    };
    // Each fit with its in-sample mean square error.
    let with_mse = |(m, alone): (ChannelModel, Vec<f64>)| {
        let mse = in_sample_mse(&m, &state.data);
        (m, alone, mse)
    };
    let warm = from(&state.full).map(with_mse);
    let warm_mse = warm.as_ref().map(|w| w.2);
    // From the paper's base too, where the fit from the current one gains much but leaves
    // well above the noise, taken only where it fits clearly better: the current base, bent
    // to absorb what it had no term for, can hold the fit with the new term in a basin far
    // from the one the term opens.
    let worth = warm_mse.is_none_or(|mse| {
        base_mse - mse >= RESTART_GAIN_SHARE * base_mse
            && mse >= RESTART_ABOVE_NOISE * state.noise * state.noise
    });
    let fresh = worth
        .then(|| from(&restarted(&state.full, &state.data)))
        .flatten()
        .map(with_mse)
        .filter(|fresh| warm_mse.is_none_or(|mse| fresh.2 < RESTART_BETTER * mse));
    let restarted = fresh.is_some();
    let (model, effect_alone, mse) = fresh.or(warm)?;
    let in_sample_gain = base_mse - mse;
    Some(FullFit {
        model,
        effect_alone,
        in_sample_gain,
        restarted,
    })
}

/// A fit from the paper's base is taken when its in-sample mean square error is below this
/// share of the fit's from the current base.
const RESTART_BETTER: f64 = 0.9;
/// It is tried when the fit from the current base lowers the in-sample mean square error by
/// at least this share...
const RESTART_GAIN_SHARE: f64 = 0.1;
/// ... and leaves it at least this many noise variances.
const RESTART_ABOVE_NOISE: f64 = 2.0;

/// The least in-sample gain for which a candidate is refitted per fold: [`SCREEN_SHARE`] of
/// the least held-out gain a candidate must show, `min_noise_gain` noise variances of the
/// channel and `min_gap_closed` of its gap (the systematic mean square of its held-out
/// residuals above their white part).
pub(super) fn screen_threshold(
    state: &ChannelState,
    min_noise_gain: f64,
    min_gap_closed: f64,
) -> f64 {
    let noise_var = state.noise * state.noise;
    let white = noise_var / SMOOTHING_WINDOW as f64;
    let gap_sq = systematic_mse(&state.data.run, state.residuals.as_single()) - white;
    SCREEN_SHARE * (min_noise_gain * noise_var).max(min_gap_closed * gap_sq)
}

/// `base` with the effect added at the parameter values `values`.
fn with_effect_at(base: &ChannelModel, effect: Extension, values: &[f64]) -> ChannelModel {
    let start = base.with_effect(effect);
    let mut theta = start.theta();
    for (&p, v) in effect_positions(&start, effect).iter().zip(values) {
        theta[p] = *v;
    }
    start.updated(&theta)
}

/// The effect's parameters in `fit` (a model ending with them).
fn effect_values(fit: &ChannelModel, effect: Extension) -> Vec<f64> {
    let theta = fit.theta();
    theta[theta.len() - effect.parameter_names().len()..].to_vec()
}

/// The candidate `fit` cross-validated on `folds`: refitted on each fold's training runs
/// (from the fold's current model with the effect at its parameters fitted alone on all
/// data), or, with
/// `screened_below` (the threshold of its channel that none of the effect's channels
/// reached), screened out; `None` when a fold's fit fails.
pub(super) fn cross_validated(
    state: &ChannelState,
    fit: &FullFit,
    effect: Extension,
    folds: &Folds,
    screened_below: Option<f64>,
    plausibility: &Plausibility,
) -> Option<CandidateFit> {
    if let Some(threshold) = screened_below {
        let values = effect_values(&fit.model, effect);
        let transplanted = |fold: usize| with_effect_at(&state.fold_models[fold], effect, &values);
        let residuals = held_out::<f32>(&state.data, folds, |fold| Some(transplanted(fold)))?;
        let noise_var = state.noise * state.noise;
        return Some(CandidateFit {
            full: fit.model.clone(),
            residuals: Some(CompactResiduals::from_single(residuals)),
            fold_models: None,
            screened: Some(format!(
                "screened out, not refitted per fold: on all data it lowers the mean square \
                 error by {:.3} noise variances, below the {:.3} ({SCREEN_SHARE} of the least \
                 held-out gain, in noise variances or as a share of the gap) a candidate \
                 needs, and so do its other channels; held-out residuals with its all-data \
                 parameters",
                fit.in_sample_gain / noise_var,
                threshold / noise_var
            )),
        });
    }
    let (fold_models, residuals) = cross_validate::<f32>(&state.data, folds, |train, fold| {
        // From the all-data fit where it came from the paper's base (the fold's base model
        // holds the basin that fit left).
        if fit.restarted {
            return refit(
                train,
                &fit.model,
                effect,
                plausibility,
                Stage::Fitted,
                false,
            )
            .map(|(m, _)| m);
        }
        // Else from the all-data values where the FMU accepts them on the fold's base model,
        // else from the effect's neutral values.
        let base = &state.fold_models[fold];
        let fitted = with_effect_at(base, effect, &fit.effect_alone);
        // As on all data: the fold's base refitted on its training rows outside the effect's
        // home first, where the effect asks for it.
        let fitted = match effects::of(effect).base_first_off_home() {
            true => base_off_home(train, &fitted, effect, Some(&|m| plausibility.exports(m)))
                .unwrap_or(fitted),
            false => fitted,
        };
        let (start, from) = match plausibility.exports(&fitted) {
            true => (fitted, Stage::Fitted),
            false => (base.with_effect(effect), Stage::Neutral),
        };
        refit(train, &start, effect, plausibility, from, false).map(|(m, _)| m)
    })?;
    Some(CandidateFit {
        full: fit.model.clone(),
        residuals: Some(CompactResiduals::from_single(residuals)),
        fold_models: Some(fold_models),
        screened: None,
    })
}

/// `effect` added to the channel's current model, fitted on all data and on every fold;
/// `None` when a fit fails.
pub(super) fn fit_candidate(
    state: &ChannelState,
    effect: Extension,
    folds: &Folds,
    plausibility: &Plausibility,
) -> Option<CandidateFit> {
    let base_mse = in_sample_mse(&state.full, &state.data);
    let fit = fit_full(state, base_mse, effect, plausibility)?;
    cross_validated(state, &fit, effect, folds, None, plausibility)
}
