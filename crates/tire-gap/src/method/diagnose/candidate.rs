//! The fit step of a selection round: a candidate effect added to a channel's current model,
//! fitted on every fold and on all data, with its held-out residuals.

use super::plausibility::Plausibility;
use super::state::ChannelState;
use crate::method::channel_data::ChannelData;
use crate::method::channel_fit::{Start, cross_validate, fit_channel, fit_some};
use crate::method::cv::Folds;
use crate::method::effects::Extension;
use crate::method::model::ChannelModel;
use crate::method::stats::CompactResiduals;

/// A candidate's fit on every fold (effect parameters only, the fold's model held) and on all
/// data, with its held-out residuals.
pub(super) struct CandidateFit {
    pub(super) full: ChannelModel,
    pub(super) fold_models: Vec<ChannelModel>,
    pub(super) residuals: CompactResiduals,
}

/// A fitted candidate of the current round: `effect` on the channel at `channel` among the
/// states.
pub(super) struct PairFit<'a> {
    pub(super) effect: Extension,
    pub(super) channel: usize,
    pub(super) fit: &'a CandidateFit,
}

/// `effect` added to the channel's current model and fitted per fold and on all data; `None`
/// when a fit fails.
pub(super) fn fit_candidate(
    state: &ChannelState,
    effect: Extension,
    folds: &Folds,
    plausibility: &Plausibility,
) -> Option<CandidateFit> {
    let data = &state.data;
    let with = |m: &ChannelModel| m.with_effect(effect);
    let positions = |m: &ChannelModel| {
        let n = m.theta().len();
        let k = effect.parameter_names().len();
        (n - k..n).collect::<Vec<_>>()
    };
    // Warm-started from each fold's own model (fitted on the same training rows): first the
    // effect's parameters alone, then a short joint refit with the base coefficients, since
    // the base may have absorbed part of the effect (e.g. a speed trend into the load terms
    // when the runs' loads and speeds correlate), which the effect alone could not undo.
    // A joint refit that takes a base coefficient out of the FMU's bounds (e.g. a camber
    // coefficient onto the singularity of E / (1 - a13 |gamma|)) is not kept: the effect
    // alone, fitted within them, is.
    let refit = |train: &ChannelData, base: &ChannelModel| {
        let start = with(base);
        let effect_only = fit_some(train, &start, &positions(&start))?.model;
        let joint = fit_channel(train, &effect_only, Start::Polish, None)?.model;
        Some(
            if plausibility.exports(&joint) || !plausibility.exports(&effect_only) {
                joint
            } else {
                effect_only
            },
        )
    };
    let (fold_models, residuals) = cross_validate(data, folds, |train, fold| {
        refit(train, &state.fold_models[fold])
    })?;
    let full = refit(data, &state.full)?;
    Some(CandidateFit {
        full,
        fold_models,
        residuals: CompactResiduals::new(&residuals),
    })
}
