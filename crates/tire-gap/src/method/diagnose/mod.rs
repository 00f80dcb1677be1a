//! The whole method: baseline fit and held-out gap, where it lies, which candidate effect
//! closes it (forward selection with paired per-run tests), and how far.
//!
//! [`diagnose`] runs the method's steps in order, one file per group of steps:
//!
//! - `base`: the channels the data can support and its reference conditions; steps 1-3, the
//!   1987 model fitted on all data and per fold, its held-out error against the noise floor,
//!   and where the gap lies.
//! - `pairs`: the (effect, channel) pairs that can be tested, and why the others cannot.
//! - `selection`: step 4, forward selection, one round at a time: fit the open pairs
//!   (`candidate`), score them (`score`), combine each effect's p-values, judge each channel
//!   (the specificity rule) and rank the effects (`trials`), name the runners-up the data
//!   cannot tell from the winner (`confounding`), and adopt the winner.
//! - `assembly`: the error left with the selected effects, step 5's extrapolation check of
//!   the first of them, and the models and per-row detail for figures.
//!
//! `state` holds what the steps share (a channel's current model and held-out residuals, and
//! whether a gap can be told from the noise). What the steps know of each effect (the rows
//! where it must show, the experiment that separates two) is in `crate::method::fit::effects`.

mod assembly;
mod base;
mod candidate;
mod confounding;
pub mod design;
pub mod extrapolate;
pub mod joint;
mod pairs;
mod plausibility;
pub mod reference;
pub mod regions;
pub mod run_order;
mod score;
mod selection;
pub mod signature;
mod stability;
mod state;
mod trials;

#[cfg(test)]
mod tests;

use std::collections::BTreeMap;
use std::ops::RangeInclusive;

use mf87::Channel;
use serde::Serialize;

use crate::data::Dataset;
use crate::method::diagnose::extrapolate::Extrapolation;
use crate::method::diagnose::regions::Region;
use crate::method::diagnose::run_order::ResidualOverRuns;
use crate::method::fit::channel_fit::ErrorSummary;
use crate::method::fit::effects::{Extension, Nominal};
use crate::method::fit::model::ChannelModel;
use crate::method::fit::validity::ValidityRange;
use crate::method::observer::Observer;
use crate::method::prepare::adequacy::{self, Limitation};
use crate::method::prepare::channel_data::ChannelData;
use crate::method::prepare::cv::Folds;
use crate::method::prepare::programme;
use crate::method::stats::CompactResiduals;
use design::DesignConfounding;

pub use base::nominal_of;
use plausibility::Plausibility;
pub use stability::{EffectStability, Stability};
use state::ChannelState;

/// Settings of a diagnosis.
#[derive(Debug, Clone, Serialize)]
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
    /// Fold assignments forward selection runs on (split seeds 1, 2, ...); an effect enters
    /// the verdict only if each selects it (see `stability`). 1: the `seed`'s alone.
    pub stability_draws: usize,
    /// The candidate effects to test; `None`: every effect. The others are reported as
    /// untestable, with this as the reason.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub effects: Option<Vec<Extension>>,
    /// Keep what the figures of the candidates' driving inputs draw: the held-out residuals
    /// of each channel's best first-round candidates (4 bytes a row each, nine at most).
    /// Without it those figures are left out and the verdict is the same.
    #[serde(skip)]
    pub candidate_figures: bool,
}

impl Options {
    /// The least gain in noise variances an effect must bring: the `first` effect
    /// `min_noise_gain`, a later one `min_noise_gain_later`.
    pub fn min_noise_gain_for(&self, first: bool) -> f64 {
        if first {
            self.min_noise_gain
        } else {
            self.min_noise_gain_later
        }
    }

    /// The cross-validation folds a diagnosis takes (whole runs per fold).
    pub const FOLDS: RangeInclusive<usize> = 3..=20;
    /// The fold assignments the stability check takes.
    pub const STABILITY_DRAWS: RangeInclusive<usize> = 1..=10;

    /// The options a front end sets, each within its range; else what was found and what is
    /// allowed.
    pub fn validate(&self) -> Result<(), String> {
        for (name, value, range) in [
            ("folds", self.folds, Self::FOLDS),
            (
                "stability_draws",
                self.stability_draws,
                Self::STABILITY_DRAWS,
            ),
        ] {
            if !range.contains(&value) {
                return Err(format!(
                    "{name} = {value} is out of range: it must lie in {}..={}",
                    range.start(),
                    range.end()
                ));
            }
        }
        Ok(())
    }
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
            stability_draws: 3,
            effects: None,
            candidate_figures: true,
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

/// Why a diagnosis ended without a result.
#[derive(Debug, Clone, PartialEq)]
pub enum Stopped {
    /// The data cannot support it (what and why in words).
    Failed(DiagnoseError),
    /// Its observer asked it to stop.
    Cancelled,
}

impl From<DiagnoseError> for Stopped {
    fn from(e: DiagnoseError) -> Self {
        Stopped::Failed(e)
    }
}

impl std::fmt::Display for Stopped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stopped::Failed(e) => e.fmt(f),
            Stopped::Cancelled => f.write_str("the diagnosis was cancelled"),
        }
    }
}

/// The held-out error of one channel of the base model.
#[derive(Debug, Clone, Serialize)]
pub struct ChannelBaseline {
    pub channel: Channel,
    pub unit: &'static str,
    pub heldout: ErrorSummary,
    /// In-sample RMS of the fit on all data (`null` for the remaining error, which has none).
    pub in_sample_rms: Option<f64>,
    /// Noise floor estimate (see `channel_fit::noise_floor`).
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
    pub channel: Channel,
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
    /// Why the fit is not physical, when it is not (see `plausibility`): not claimed.
    pub implausible: Option<String>,
    /// Why it was not refitted per fold, when it was not: its fit on all data gains too
    /// little to show the least held-out gain; its held-out residuals are those of each
    /// fold's model with the effect at its all-data parameters, and it is not claimed.
    pub screened: Option<String>,
    /// Its held-out gain split by its driver's activity, and the test that the gain lies
    /// where the driver acts.
    pub signature: signature::SignatureTest,
    /// Why a channel that passed every other rule is not claimed for its signature (its gain
    /// lies where its driver is idle: it absorbs misfit of another cause), when it is not.
    pub not_its_signature: Option<String>,
    /// Why a channel that showed its signature is not claimed because a rival refused for
    /// its own signature takes the same misfit more fully (see `trials::mark_overshadowed`),
    /// when it is not.
    pub overshadowed: Option<String>,
    /// Fitted effect parameters on all data.
    pub params: BTreeMap<String, f64>,
}

/// One candidate effect tested in a round.
#[derive(Debug, Clone, Serialize)]
pub struct Trial {
    pub effect: Extension,
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
    pub selected: Option<Extension>,
    /// When no single effect won and a gap was left: the best pairs of effects fitted jointly.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub pairs: Vec<joint::JointTrial>,
    /// The pair selected, when one was.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub selected_pair: Option<[Extension; 2]>,
}

/// A claimed effect with the evidence specific to it: on each channel it was added on, its
/// held-out gain split by its driver's activity (from the round that selected it, alone or as
/// a member of a pair, on the fold assignment the report shows).
#[derive(Debug, Clone, Serialize)]
pub struct Claim {
    pub effect: Extension,
    /// The selection round (from 1).
    pub round: usize,
    /// The other member, when it was selected as one of a pair of effects fitted jointly.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub with: Option<Extension>,
    pub channels: Vec<ClaimChannel>,
    /// How the test plan moves the effect's driver, in words, and whether it moves it enough
    /// to be a driver (see `pairs::plan_of`).
    pub plan: String,
    pub plan_moves: bool,
    /// The split seed of the fold assignment whose round this is, when the first assignment
    /// did not select the effect (the stability check's others did).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
}

impl Claim {
    /// The claim of `effect` (selected `with` another, as a pair, or alone) in `round`, on
    /// its channels with the gap each closed and its signature there; its plan is set later.
    fn new(
        (effect, with): (Extension, Option<Extension>),
        round: usize,
        channels: impl Iterator<Item = (Channel, Option<f64>, signature::SignatureTest)>,
    ) -> Self {
        Claim {
            effect,
            round,
            with,
            plan: String::new(),
            plan_moves: false,
            seed: None,
            channels: channels
                .map(|(channel, gap_closed, signature)| ClaimChannel {
                    channel,
                    gap_closed,
                    signature,
                })
                .collect(),
        }
    }
}

/// One channel of a claim.
#[derive(Debug, Clone, Serialize)]
pub struct ClaimChannel {
    pub channel: Channel,
    /// Fraction of the gap left before its round that it closed there.
    pub gap_closed: Option<f64>,
    /// Its gain split by its driver's activity (for a pair's member, the pair's gain split by
    /// the member's driver).
    pub signature: signature::SignatureTest,
}

/// A candidate that passed every rule but its signature, on one channel: not claimed there.
#[derive(Debug, Clone, Serialize)]
pub struct SignatureRefusal {
    pub effect: Extension,
    pub channel: Channel,
    /// The round (from 1) where it was refused first.
    pub round: usize,
    /// Where its gain lies, in words ("absorbs misfit of another cause: ...").
    pub reason: String,
    pub signature: signature::SignatureTest,
}

/// The claims of the `verdict` in the first fold assignment's `rounds`, and the candidates
/// refused there for their signature; an effect of the verdict the first assignment did not
/// select is claimed from the first of the `other_rounds` that did, with its seed.
fn verdict_claims(
    rounds: &[Round],
    other_rounds: &[(u64, Vec<Round>)],
    verdict: &[Extension],
) -> (Vec<Claim>, Vec<SignatureRefusal>) {
    let (mut claims, refused) = claims_of(rounds, verdict);
    for (seed, rounds) in other_rounds {
        let missing: Vec<Extension> = verdict
            .iter()
            .copied()
            .filter(|e| !claims.iter().any(|c| c.effect == *e))
            .collect();
        if missing.is_empty() {
            break;
        }
        let (more, _) = claims_of(rounds, &missing);
        claims.extend(more.into_iter().map(|c| Claim {
            seed: Some(*seed),
            ..c
        }));
    }
    (claims, refused)
}

/// The claims of the `verdict` selected in `rounds`, and the candidates refused for their
/// signature (the first time each effect was, per channel).
fn claims_of(rounds: &[Round], verdict: &[Extension]) -> (Vec<Claim>, Vec<SignatureRefusal>) {
    let mut claims = Vec::new();
    let mut refused: Vec<SignatureRefusal> = Vec::new();
    for (k, r) in rounds.iter().enumerate() {
        let round = k + 1;
        for t in &r.trials {
            if r.selected == Some(t.effect) && verdict.contains(&t.effect) {
                let channels = t.channels.iter().filter(|c| c.significant);
                claims.push(Claim::new(
                    (t.effect, None),
                    round,
                    channels.map(|c| (c.channel, c.gap_closed, c.signature.clone())),
                ));
            }
            for c in &t.channels {
                let Some(reason) = &c.not_its_signature else {
                    continue;
                };
                if refused
                    .iter()
                    .any(|x| x.effect == t.effect && x.channel == c.channel)
                {
                    continue;
                }
                refused.push(SignatureRefusal {
                    effect: t.effect,
                    channel: c.channel,
                    round,
                    reason: reason.clone(),
                    signature: c.signature.clone(),
                });
            }
        }
        let Some(pair) = r.selected_pair else {
            continue;
        };
        let Some(t) = r.pairs.iter().find(|t| t.effects == pair) else {
            continue;
        };
        for (m, &effect) in pair.iter().enumerate() {
            if !verdict.contains(&effect) {
                continue;
            }
            let channels = t.channels.iter().filter(|c| c.significant);
            claims.push(Claim::new(
                (effect, Some(pair[1 - m])),
                round,
                channels.map(|c| (c.channel, c.gap_closed, c.members[m].clone())),
            ));
        }
    }
    (claims, refused)
}

/// A candidate that could not be tested, and why.
#[derive(Debug, Clone, Serialize)]
pub struct Untestable {
    pub effect: Extension,
    pub reason: String,
}

/// What the data cannot tell apart: conditions the design moves together across runs, and
/// runners-up of a selection round that explain nearly as much as the winner.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Confounding {
    /// From the design alone, whatever the fits say.
    pub design: Vec<DesignConfounding>,
    /// From the fits.
    pub fits: Vec<FitConfounding>,
}

/// A runner-up that the data cannot separate from the winner.
#[derive(Debug, Clone, Serialize)]
pub struct FitConfounding {
    pub winner: Extension,
    pub runner_up: Extension,
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
    /// The runs (test blocks) of the data set with their conditions and folds.
    pub blocks: Vec<crate::method::prepare::programme::Block>,
    /// Held-out blocks outside the conditions their training covers: still scored, but their
    /// error there is an extrapolation, not a gap.
    pub not_covered: Vec<crate::method::prepare::cv::NotCovered>,
    pub nominal: Nominal,
    pub baseline: Vec<ChannelBaseline>,
    pub regions: Vec<Region>,
    pub rounds: Vec<Round>,
    pub verdict: Vec<Extension>,
    /// The claimed effects with where their held-out gain lies.
    pub claims: Vec<Claim>,
    /// Candidates that passed every rule but their signature, not claimed there.
    pub signature_refusals: Vec<SignatureRefusal>,
    /// The selections over re-drawn fold assignments the verdict is taken from (`null`: one
    /// assignment only).
    pub stability: Option<Stability>,
    pub confounding: Confounding,
    pub untestable: Vec<Untestable>,
    /// What the data cannot support: rows left out, channels not diagnosed, gaps that cannot
    /// be told from the noise.
    pub limitations: Vec<Limitation>,
    /// Held-out error per channel with the selected effects.
    pub remaining: Vec<ChannelBaseline>,
    /// Where the remaining gap lies.
    pub remaining_regions: Vec<Region>,
    /// The channels with a measurable gap left: their held-out residual over the run order.
    pub remaining_over_runs: Vec<ResidualOverRuns>,
    /// The first selected effect, refitted with one end of its driving input held out.
    pub extrapolation: Vec<Extrapolation>,
    /// Per channel: how much of the held-out gap a complete MF 6.1 fitted on the same folds
    /// explains, how much of that the named effects explain, and the per-sweep floor no
    /// steady-state model beats.
    pub ceiling: Vec<crate::method::diagnose::reference::Ceiling>,
    /// The fitted model per channel (base plus selected effects).
    #[serde(skip)]
    pub models: Vec<ChannelModel>,
    /// Per-row data and held-out residuals per channel, for figures.
    #[serde(skip)]
    pub detail: Vec<ChannelDetail>,
}

/// One channel's rows with its held-out residuals (measured minus predicted): of the base
/// model, of the final model, and of the base model plus each top first-round candidate.
/// Rows are the dataset's rows, in order, for every channel.
#[derive(Debug, Clone)]
pub struct ChannelDetail {
    pub data: ChannelData,
    /// The base model fitted on all data.
    pub base_model: ChannelModel,
    pub base_residuals: CompactResiduals,
    pub final_residuals: CompactResiduals,
    /// The best first-round candidates on this channel (by gap closed), best first.
    pub candidates: Vec<(Extension, CompactResiduals)>,
}

/// Runs the whole method on `ds`, telling `observer` of each stage and step; ends early,
/// with [`Stopped::Cancelled`], once the observer asks it to stop.
pub fn diagnose(
    all: &Dataset,
    options: &Options,
    observer: &dyn Observer,
) -> Result<Diagnosis, Stopped> {
    let (ds, left_out) = adequacy::loaded_rows(all).map_err(DiagnoseError)?;
    let ds: &Dataset = &ds;
    let dealt = Dealt::new(programme::blocks(all), ds, left_out.is_some(), options);
    let folds = &dealt.folds;
    let mut limitations: Vec<Limitation> = left_out.into_iter().collect();
    let channels = base::channels_to_diagnose(ds, folds, &mut limitations)?;
    let nominal = nominal_of(ds);
    note_few_runs_for_design(folds.runs(), &mut limitations);
    // 1-3: base fit, held-out error, noise floor, where the gap lies; the channels in parallel.
    // Every fit stays within the FMU's bounds over the data's range.
    let plausibility = Plausibility::new(ValidityRange::of(ds));
    let base_channels = base::fit_channels(
        ds,
        channels,
        folds,
        nominal,
        &plausibility,
        &mut limitations,
        observer,
    )?;
    let base = base::baseline(base_channels, options, &mut limitations);
    // 4: candidates, forward selection.
    let (untestable, design, (selection, verdict, stability)) = dealt.select(
        ds,
        (base.states, &base.baseline),
        options,
        &plausibility,
        observer,
    );
    // 5 and the rest: the error left, the extrapolation check, models and detail for figures.
    let remaining = assembly::remaining(&selection.states, options);
    let extrapolation =
        assembly::extrapolation(&verdict, &selection.states, &plausibility, observer);
    let ceiling = assembly::ceilings(
        &selection.states,
        &base.for_figures,
        folds,
        &nominal,
        observer,
    )?;
    let final_models =
        assembly::models_and_detail(selection.states, base.for_figures, selection.top_candidates);
    let confounding = claimed_confounding(design, selection.confounding, &verdict);
    let (mut claims, signature_refusals) =
        verdict_claims(&selection.rounds, &selection.other_rounds, &verdict);
    let untestable = [untestable, selection.closed_by_design].concat();
    for c in &mut claims {
        (c.plan, c.plan_moves) = dealt.plan_of(ds, c);
    }
    Ok(Diagnosis {
        options: options.clone(),
        rows: ds.len(),
        runs: folds.runs(),
        blocks: dealt.blocks,
        not_covered: dealt.not_covered,
        nominal,
        baseline: base.baseline,
        regions: base.regions,
        rounds: selection.rounds,
        verdict,
        claims,
        signature_refusals,
        stability,
        confounding,
        untestable,
        limitations,
        remaining: remaining.summary,
        remaining_regions: remaining.regions,
        remaining_over_runs: remaining.over_runs,
        extrapolation,
        ceiling,
        models: final_models.models,
        detail: final_models.detail,
    })
}

/// The rows a diagnosis of `ds` fits and scores, with their folds.
pub struct Prepared {
    /// The rows that carry load, each run a test block.
    pub dataset: Dataset,
    /// The fold holding each row out (`options.seed`'s assignment of blocks to folds).
    pub fold: Vec<usize>,
    /// Every block of the data set, each with its fold when it has loaded rows.
    pub blocks: Vec<crate::method::prepare::programme::Block>,
    /// What was left out (rows without load).
    pub limitations: Vec<Limitation>,
}

/// The rows a diagnosis of `ds` with `options` fits and scores (those with load; each run a
/// test block), and the fold that holds each out: what a diagnosis is made on, for an
/// independent fit on the same folds (the scipy benchmark) or a look at the blocks.
pub fn prepare(ds: &Dataset, options: &Options) -> Result<Prepared, DiagnoseError> {
    let blocks = crate::method::prepare::programme::blocks(ds);
    let (loaded, left_out) = adequacy::loaded_rows(ds).map_err(DiagnoseError)?;
    let dealt = Dealt::new(blocks, &loaded, left_out.is_some(), options);
    let fold = loaded.run.iter().map(|r| dealt.folds.fold_of(*r)).collect();
    Ok(Prepared {
        dataset: loaded.into_owned(),
        fold,
        blocks: dealt.blocks,
        limitations: left_out.into_iter().collect(),
    })
}

/// The confounding the report names: of the design, and the runner-up notes of the fits
/// whose winner the verdict claims (the primary may have selected an effect the draws did not
/// keep).
fn claimed_confounding(
    design: Vec<DesignConfounding>,
    fits: Vec<FitConfounding>,
    verdict: &[Extension],
) -> Confounding {
    Confounding {
        design: design::with_selected(design, verdict),
        fits: fits
            .into_iter()
            .filter(|c| verdict.contains(&c.winner))
            .collect(),
    }
}

/// The test blocks and the folds dealt by the conditions of the blocks that carry load.
struct Dealt {
    /// Every block, each with the fold holding it out when it has loaded rows.
    blocks: Vec<crate::method::prepare::programme::Block>,
    /// The blocks of the loaded rows, which the folds are dealt from.
    loaded_blocks: Vec<crate::method::prepare::programme::Block>,
    folds: Folds,
    not_covered: Vec<crate::method::prepare::cv::NotCovered>,
}

impl Dealt {
    /// The testable candidates of the base model's `states` (those that are not, with why),
    /// the design's confounded conditions, and the forward selection, drawn again on new
    /// fold assignments for its stability.
    fn select(
        &self,
        ds: &Dataset,
        (states, baseline): (Vec<ChannelState>, &[ChannelBaseline]),
        options: &Options,
        plausibility: &Plausibility,
        observer: &dyn Observer,
    ) -> (Vec<Untestable>, Vec<DesignConfounding>, stability::Selected) {
        let testable = pairs::testable_pairs(ds, &self.loaded_blocks, &states, baseline, options);
        let design = design::confounded_conditions(ds);
        let selected = stability::select_stably(
            states,
            testable.pairs,
            &self.folds,
            |seed| Folds::stratified(&self.loaded_blocks, options.folds, seed),
            options,
            &design,
            plausibility,
            observer,
        );
        (testable.untestable, design, selected)
    }

    /// How the test plan moves the driver of `claim` (on its first channel), and whether
    /// enough for a claim.
    fn plan_of(&self, ds: &Dataset, claim: &Claim) -> (String, bool) {
        let channel = claim.channels.first().map_or(Channel::Fy, |ch| ch.channel);
        pairs::plan_of(ds, &self.loaded_blocks, claim.effect, channel)
    }

    /// Deals the folds for `blocks` (of all rows); `loaded` is the data set of the loaded
    /// rows, `rows_left_out` whether it lacks some rows of the whole.
    fn new(
        mut blocks: Vec<crate::method::prepare::programme::Block>,
        loaded: &Dataset,
        rows_left_out: bool,
        options: &Options,
    ) -> Self {
        let loaded_blocks = match rows_left_out {
            true => crate::method::prepare::programme::blocks(loaded),
            false => blocks.clone(),
        };
        let folds = Folds::stratified(&loaded_blocks, options.folds, options.seed);
        let not_covered = folds.coverage(&loaded_blocks);
        for b in &mut blocks {
            b.fold = loaded_blocks
                .iter()
                .any(|l| l.run == b.run)
                .then(|| folds.fold_of(b.run));
        }
        Dealt {
            blocks,
            loaded_blocks,
            folds,
            not_covered,
        }
    }
}

/// Notes that design confounding is not judged from fewer than
/// [`design::MIN_DESIGN_RUNS`] runs.
fn note_few_runs_for_design(runs: usize, limitations: &mut Vec<Limitation>) {
    if runs < design::MIN_DESIGN_RUNS {
        limitations.push(Limitation::new(
            "data",
            format!(
                "{runs} runs: whether driving conditions move together across runs (design \
                 confounding) is judged from {} runs or more",
                design::MIN_DESIGN_RUNS
            ),
        ));
    }
}
