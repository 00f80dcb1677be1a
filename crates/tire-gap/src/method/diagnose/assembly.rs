//! The assembly: the error left with the selected effects and where it lies, step 5's
//! extrapolation check of the first selected effect, and the models and per-row detail kept
//! for figures.

use super::base::BaseForFigures;
use super::plausibility::Plausibility;
use super::state::{ChannelState, gap_regions, summary};
use super::{ChannelBaseline, ChannelDetail, Options, Stopped};
use crate::method::diagnose::extrapolate::{self, Extrapolation};
use crate::method::diagnose::reference::{self, Ceiling};
use crate::method::diagnose::regions::Region;
use crate::method::diagnose::run_order::{self, ResidualOverRuns};
use crate::method::fit::effects::Extension;
use crate::method::fit::effects::Nominal;
use crate::method::fit::model::ChannelModel;
use crate::method::observer::Observer;
use crate::method::parallel::parallel_map;
use crate::method::prepare::cv::Folds;
use crate::method::stats::CompactResiduals;

/// The held-out error per channel with the selected effects, and where it lies.
pub(super) struct Remaining {
    pub(super) summary: Vec<ChannelBaseline>,
    pub(super) regions: Vec<Region>,
    /// The channels with a measurable gap left: their residual over the run order.
    pub(super) over_runs: Vec<ResidualOverRuns>,
}

pub(super) fn remaining(states: &[ChannelState], options: &Options) -> Remaining {
    let summary: Vec<ChannelBaseline> = parallel_map(states, |s| summary(s, None, options));
    let regions = gap_regions(states, &summary);
    let with_gap: Vec<(&ChannelState, &ChannelBaseline)> = states
        .iter()
        .zip(&summary)
        .filter(|(_, b)| b.no_gap.is_none())
        .collect();
    // The significance level is shared among the channels tested (Bonferroni).
    let level = options.significance / with_gap.len().max(1) as f64;
    let over_runs = parallel_map(&with_gap, |(s, b)| {
        let runs = run_order::per_run(
            &s.data.run,
            &s.data.measured,
            &s.residuals.to_vec(),
            s.noise,
        );
        let (trend, no_trend) = match run_order::trend(&runs, level) {
            Ok(t) => (Some(t), None),
            Err(why) => (None, Some(why)),
        };
        ResidualOverRuns {
            channel: b.channel,
            unit: b.unit,
            runs,
            trend,
            no_trend,
        }
    });
    Remaining {
        summary,
        regions,
        over_runs,
    }
}

/// Step 5: the first selected effect refitted with one end of its driving input held out,
/// on the channels whose model has it, within the FMU's bounds as every fit of the diagnosis;
/// none when no effect was selected.
pub(super) fn extrapolation(
    verdict: &[Extension],
    states: &[ChannelState],
    plausibility: &Plausibility,
    observer: &dyn Observer,
) -> Vec<Extrapolation> {
    let Some(&winner) = verdict.first() else {
        return Vec::new();
    };
    let with: Vec<&ChannelState> = states
        .iter()
        .filter(|s| s.full.effects.iter().any(|(e, _)| *e == winner))
        .collect();
    observer.stage(
        &format!("extrapolation check of {winner}"),
        with.len() as u64,
    );
    parallel_map(&with, |s| {
        if observer.cancelled() {
            return Vec::new();
        }
        let exports = |m: &ChannelModel| plausibility.exports(m);
        let checked = extrapolate::check(winner, &s.data, &s.full, &exports);
        observer.step();
        checked
    })
    .into_iter()
    .flatten()
    .collect()
}

/// The fitted model per channel, and its rows with the held-out residuals for figures.
pub(super) struct FinalModels {
    pub(super) models: Vec<ChannelModel>,
    pub(super) detail: Vec<ChannelDetail>,
}

/// The channels' final models and detail; `base` and `candidates` are per channel, in the
/// states' order.
pub(super) fn models_and_detail(
    states: Vec<ChannelState>,
    base: Vec<BaseForFigures>,
    candidates: Vec<Vec<(Extension, CompactResiduals)>>,
) -> FinalModels {
    let mut fitted = FinalModels {
        models: Vec::with_capacity(states.len()),
        detail: Vec::with_capacity(states.len()),
    };
    for ((s, base), candidates) in states.into_iter().zip(base).zip(candidates) {
        fitted.detail.push(ChannelDetail {
            data: s.data,
            base_model: base.model,
            base_residuals: base.residuals,
            final_residuals: s.residuals,
            candidates,
        });
        fitted.models.push(s.full);
    }
    fitted
}

/// The ceiling of each channel ([`crate::method::diagnose::reference`]): the MF 6.1 reference fitted
/// on the same folds, the per-sweep floor, and how much of the gap each explains. As the last
/// stage, it ends a cancelled diagnosis (the stages before skip their jobs once cancelled).
pub(super) fn ceilings(
    states: &[ChannelState],
    base: &[BaseForFigures],
    folds: &Folds,
    nominal: &Nominal,
    observer: &dyn Observer,
) -> Result<Vec<Ceiling>, Stopped> {
    observer.stage(
        &format!("the {} reference fit", reference::REFERENCE_MODEL),
        states.len() as u64,
    );
    let fits = parallel_map(states, |s| {
        if observer.cancelled() {
            return None;
        }
        let fit = reference::fit_reference(&s.data, folds, nominal.pressure_kpa);
        observer.step();
        fit
    });
    if observer.cancelled() {
        return Err(Stopped::Cancelled);
    }
    Ok(states
        .iter()
        .zip(base)
        .zip(fits)
        .map(|((s, b), fit)| Ceiling::of(&s.data, &b.residuals, &s.residuals, fit))
        .collect())
}
