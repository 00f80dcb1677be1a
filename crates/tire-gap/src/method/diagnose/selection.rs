//! Step 4: forward selection. Each round fits the open (effect, channel) pairs, scores them,
//! combines each effect's p-values, judges and ranks the effects, names the runners-up the data
//! cannot tell from the winner, and adds the winner to the model on the channels where it was
//! significant or lowers the held-out error and extrapolates ([`joins_the_model`]). Rounds go on
//! while a winner is found and pairs are left.

use std::collections::BTreeMap;

use mf87::Channel;

use super::candidate::{
    CandidateFit, FullFit, PairFit, cross_validated, fit_full, idle_reference, in_sample_mse,
    screen_threshold,
};
use super::confounding::{confounders, correlation_on};
use super::extrapolate;
use super::joint::{self, JointFit};
use super::pairs::Pair;
use super::plausibility::Plausibility;
use super::score::{Score, score};
use super::state::ChannelState;
use super::trials::{
    combine, judge, judge_signatures, mark_overshadowed, mark_unspecific, rank_trials,
};
use super::{ChannelTrial, FitConfounding, Options, Round, Trial, Untestable};
use crate::method::diagnose::design::DesignConfounding;
use crate::method::fit::effects::Extension;
use crate::method::fit::model::ChannelModel;
use crate::method::observer::Observer;
use crate::method::parallel::parallel_map;
use crate::method::prepare::cv::Folds;
use crate::method::stats::CompactResiduals;

/// How many first-round candidates per channel keep their held-out residuals for figures.
const DETAIL_CANDIDATES: usize = 3;

/// A candidate fit with its score against its channel's current model and the mean square
/// of its held-out residuals.
struct Scored {
    fit: CandidateFit,
    score: Score,
    mse: f64,
}

/// Candidate fits of earlier rounds stay valid until their channel's model changes (`None`:
/// the fit failed).
type FitCache = BTreeMap<Pair, Option<Scored>>;

/// Candidates fitted on all data, kept over the fold assignments: a fit depends only on its
/// channel's model, which is the same wherever the same effects were added to it in the same
/// order. Keyed by the channel's position, the effects in its model, and the candidate.
pub(super) type FullFits = BTreeMap<(usize, Vec<Extension>, Extension), Option<FullFit>>;

/// What forward selection found.
pub(super) struct Selection {
    /// The channels with the selected effects in their models.
    pub(super) states: Vec<ChannelState>,
    pub(super) rounds: Vec<Round>,
    /// The selected effects, in the order they were selected.
    pub(super) verdict: Vec<Extension>,
    pub(super) confounding: Vec<FitConfounding>,
    /// Per channel, the best first-round candidates with their held-out residuals.
    pub(super) top_candidates: Vec<Vec<(Extension, CompactResiduals)>>,
    /// Candidates no longer tested because the design confounds them with a selected effect.
    pub(super) closed_by_design: Vec<Untestable>,
    /// Each selection with the channels (positions among the states) it was added on.
    pub(super) adopted: Vec<(Extension, Vec<usize>)>,
    /// The rounds of the stability check's other fold assignments, with their split seeds
    /// (set by [`super::stability::select_stably`]).
    pub(super) other_rounds: Vec<(u64, Vec<Round>)>,
}

/// Forward selection over the testable `pairs`, from the channels' base models; the
/// candidates' all-data fits are taken from `fulls`, and those made are added to it. With
/// `figures`, the best first-round candidates keep their held-out residuals in
/// [`Selection::top_candidates`].
#[allow(clippy::too_many_arguments)]
pub(super) fn select(
    states: Vec<ChannelState>,
    mut open: Vec<Pair>,
    fulls: &mut FullFits,
    folds: &Folds,
    options: &Options,
    design: &[DesignConfounding],
    plausibility: &Plausibility,
    figures: bool,
    observer: &dyn Observer,
) -> Selection {
    let mut s = Selection::new(states);
    // `open`: pairs not yet in the model; an effect added on some channels stays a candidate
    // on the others (its evidence there may only show once other gaps are closed).
    let mut cache = FitCache::new();
    while !open.is_empty() {
        let min_noise_gain = options.min_noise_gain_for(s.verdict.is_empty());
        fit_new_pairs(
            &s.states,
            &open,
            Cache {
                pairs: &mut cache,
                fulls,
            },
            folds,
            (min_noise_gain, options),
            plausibility,
            s.rounds.len() + 1,
            observer,
        );
        if observer.cancelled() {
            break;
        }
        let (fits, scores) = fitted_pairs(&open, &cache);
        if s.rounds.is_empty() && figures {
            s.top_candidates = top_candidates(&s.states, &fits, &scores, folds);
        }
        let trials = judged_trials(
            &s.states,
            &fits,
            &scores,
            s.verdict.is_empty(),
            (options, design, folds),
            plausibility,
        );
        let winner = trials.first().filter(|t| t.significant).map(|t| t.effect);
        let context = (folds, options, s.verdict.is_empty());
        let (joint_trials, joint_winner) = match winner {
            Some(_) => (Vec::new(), None),
            None => joint_round(
                &s.states,
                (&open, &cache, &trials),
                context,
                design,
                plausibility,
                observer,
            ),
        };
        if let Some(w) = winner {
            s.confounding.extend(confounders(
                w, &trials, &fits, &scores, &s.states, folds, options,
            ));
            let adopted = adopted_channels(w, &trials[0], &fits, &s.states, plausibility);
            adopt(w, &adopted, &mut s.states, &mut open, &mut cache, folds);
            adopted_as(w, adopted, &mut s, design, &mut open);
        }
        let selected_pair = joint_winner
            .map(|(pair, fits)| adopt_pair(pair, fits, &mut s, (&mut open, &mut cache), design));
        s.rounds.push(Round {
            trials,
            selected: winner,
            pairs: joint_trials,
            selected_pair,
        });
        if winner.is_none() && selected_pair.is_none() {
            break;
        }
    }
    s
}

impl Selection {
    /// A selection from the channels' base models, nothing selected yet.
    fn new(states: Vec<ChannelState>) -> Self {
        Selection {
            closed_by_design: Vec::new(),
            adopted: Vec::new(),
            top_candidates: vec![Vec::new(); states.len()],
            states,
            rounds: Vec::new(),
            verdict: Vec::new(),
            confounding: Vec::new(),
            other_rounds: Vec::new(),
        }
    }
}

/// No single effect won the round: the best pairs of the `open` candidates, fitted jointly
/// from their single fits in `cache` ([`joint::joints`]).
fn joint_round(
    states: &[ChannelState],
    (open, cache, trials): (&[Pair], &FitCache, &[Trial]),
    context: (&Folds, &Options, bool),
    design: &[DesignConfounding],
    plausibility: &Plausibility,
    observer: &dyn Observer,
) -> (Vec<joint::JointTrial>, Option<joint::Winner>) {
    let singles = |p: Pair| {
        let fit = &cache.get(&p)?.as_ref()?.fit;
        fit.fold_models.is_some().then_some(fit)
    };
    let j = joint::joints(
        states,
        open,
        &singles,
        trials,
        context,
        design,
        plausibility,
        observer,
    );
    (j.trials, j.winner)
}

/// The winning `pair`'s joint fits adopted into the selection's models, both members into
/// its verdict on the channels the pair won.
fn adopt_pair(
    pair: [Extension; 2],
    fits: Vec<JointFit>,
    s: &mut Selection,
    (open, cache): (&mut Vec<Pair>, &mut FitCache),
    design: &[DesignConfounding],
) -> [Extension; 2] {
    let channels: Vec<usize> = fits.iter().map(|f| f.channel).collect();
    adopt_joint(fits, &mut s.states, open, cache);
    for e in pair {
        adopted_as(e, channels.clone(), s, design, open);
    }
    pair
}

/// A round's trials, best first: the effects' combined p-values, each pair judged against
/// the minimum gains (`first`: no effect selected yet) and for plausibility, unspecific
/// effects marked.
fn judged_trials(
    states: &[ChannelState],
    fits: &[PairFit],
    scores: &[Score],
    first: bool,
    (options, design, folds): (&Options, &[DesignConfounding], &Folds),
    plausibility: &Plausibility,
) -> Vec<Trial> {
    let p_adjusted = combine(fits, scores);
    let implausible: Vec<Option<String>> = fits
        .iter()
        .map(|f| {
            let state = &states[f.channel];
            plausibility.judge(&state.data, &state.full, &f.fit.full, f.effect)
        })
        .collect();
    let mut trials = judge(
        states,
        fits,
        scores,
        &p_adjusted,
        &implausible,
        first,
        options,
    );
    judge_signatures(&mut trials, design, options);
    mark_unspecific(&mut trials, options);
    let channel_at = |channel: Channel| states.iter().position(|s| s.data.channel == channel);
    mark_overshadowed(&mut trials, &|a, b, channel| {
        correlation_on(channel_at(channel)?, a, b, fits, states, folds)
    });
    rank_trials(&mut trials);
    trials
}

/// The fits a round draws on: this assignment's candidate fits, and the all-data fits of
/// every assignment.
struct Cache<'a> {
    pairs: &'a mut FitCache,
    fulls: &'a mut FullFits,
}

/// The fit step: the open pairs not in the cache, fitted on all data (unless `fulls` has
/// them) and cross-validated, in parallel. An effect none of whose open pairs reaches its
/// channel's screening threshold (the least gains a candidate must show, see `candidate`) is
/// screened out; a cached pair screened out before is cross-validated again once its effect
/// is no longer.
#[allow(clippy::too_many_arguments)]
fn fit_new_pairs(
    states: &[ChannelState],
    open: &[Pair],
    cache: Cache,
    folds: &Folds,
    (min_noise_gain, options): (f64, &Options),
    plausibility: &Plausibility,
    round: usize,
    observer: &dyn Observer,
) {
    let min_gap_closed = options.min_gap_closed;
    let key = |p: &Pair| {
        let effects = states[p.channel].full.effects.iter().map(|(e, _)| *e);
        (p.channel, effects.collect::<Vec<_>>(), p.effect)
    };
    let to_fit: Vec<Pair> = open
        .iter()
        .copied()
        .filter(|p| !cache.pairs.contains_key(p) && !cache.fulls.contains_key(&key(p)))
        .collect();
    if !to_fit.is_empty() {
        observer.stage(
            &format!("selection round {round}: fitting candidate-channel pairs on all data"),
            to_fit.len() as u64,
        );
    }
    let fitted = full_fits(states, &to_fit, plausibility, observer);
    cache.fulls.extend(to_fit.iter().map(key).zip(fitted));
    let fulls: &FullFits = cache.fulls;
    let thresholds: Vec<f64> = states
        .iter()
        .map(|s| screen_threshold(s, min_noise_gain, min_gap_closed))
        .collect();
    let full_of = |p: &Pair| fulls.get(&key(p)).and_then(Option::as_ref);
    let contenders: Vec<Extension> = open
        .iter()
        .filter(|p| full_of(p).is_some_and(|f| f.in_sample_gain >= thresholds[p.channel]))
        .map(|p| p.effect)
        .collect();
    let jobs: Vec<Pair> = open
        .iter()
        .copied()
        .filter(|p| match cache.pairs.get(p) {
            None => true,
            Some(fit) => {
                contenders.contains(&p.effect)
                    && fit.as_ref().is_some_and(|f| f.fit.screened.is_some())
            }
        })
        .collect();
    if !jobs.is_empty() {
        observer.stage(
            &format!("selection round {round}: cross-validating candidate-channel pairs"),
            jobs.len() as u64,
        );
    }
    let crossed = parallel_map(&jobs, |p| {
        let state = &states[p.channel];
        let screened_below = (!contenders.contains(&p.effect)).then_some(thresholds[p.channel]);
        let crossed = full_of(p)
            .filter(|_| !observer.cancelled())
            .and_then(|fit| {
                cross_validated(state, fit, p.effect, folds, screened_below, plausibility)
            })
            .and_then(|fit| scored(state, p, fit, (folds, plausibility), options));
        observer.step();
        crossed
    });
    cache.pairs.extend(jobs.into_iter().zip(crossed));
}

/// A cross-validated candidate scored against its channel's current model. Its held-out
/// residuals are dropped once scored, so a round holds only those being scored however many
/// candidates it fits; adoption, the confounding check and the figures predict them again
/// from its models when they need them (see [`CandidateFit::held_out`]).
fn scored(
    state: &ChannelState,
    p: &Pair,
    mut fit: CandidateFit,
    (folds, plausibility): (&Folds, &Plausibility),
    options: &Options,
) -> Option<Scored> {
    let residuals = fit.residuals.take()?;
    let reference = || idle_reference(state, p.effect, folds, plausibility);
    let score = score(
        state,
        (p.effect, &fit.full),
        &residuals,
        &reference,
        options,
    );
    let mse = residuals.mse();
    Some(Scored { fit, score, mse })
}

/// A candidate's share of the gap closed, for ranking (unscored ones last).
fn rank_key(score: &Score) -> f64 {
    score.gap_closed.unwrap_or(f64::NEG_INFINITY)
}

/// The [`DETAIL_CANDIDATES`] items with the highest keys and the rest, each best first (ties
/// in the given order).
fn best_and_rest<T>(mut ranked: Vec<(f64, T)>) -> (Vec<T>, Vec<T>) {
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut items: Vec<T> = ranked.into_iter().map(|(_, t)| t).collect();
    let rest = items.split_off(DETAIL_CANDIDATES.min(items.len()));
    (items, rest)
}

/// The all-data fits of the pairs `to_fit` (each `None` once the observer cancels).
fn full_fits(
    states: &[ChannelState],
    to_fit: &[Pair],
    plausibility: &Plausibility,
    observer: &dyn Observer,
) -> Vec<Option<FullFit>> {
    // The current models' in-sample error, once per channel rather than per candidate.
    let base_mse: Vec<f64> = match to_fit.is_empty() {
        true => Vec::new(),
        false => parallel_map(states, |s| in_sample_mse(&s.full, &s.data)),
    };
    parallel_map(to_fit, |p| {
        let fit = (!observer.cancelled())
            .then(|| {
                fit_full(
                    &states[p.channel],
                    base_mse[p.channel],
                    p.effect,
                    plausibility,
                )
            })
            .flatten();
        observer.step();
        fit
    })
}

/// The open pairs whose fit succeeded, in the order of `open`, with their scores.
fn fitted_pairs<'a>(open: &[Pair], cache: &'a FitCache) -> (Vec<PairFit<'a>>, Vec<Score>) {
    open.iter()
        .filter_map(|p| {
            let scored = cache.get(p)?.as_ref()?;
            let fit = PairFit {
                effect: p.effect,
                channel: p.channel,
                fit: &scored.fit,
                mse: scored.mse,
            };
            Some((fit, scored.score.clone()))
        })
        .unzip()
}

/// For figures: per channel, the `DETAIL_CANDIDATES` fits that close the most of its gap
/// (unscored ones last), best first, with their held-out residuals.
fn top_candidates(
    states: &[ChannelState],
    fits: &[PairFit],
    scores: &[Score],
    folds: &Folds,
) -> Vec<Vec<(Extension, CompactResiduals)>> {
    (0..states.len())
        .map(|ci| {
            let mine: Vec<(f64, usize)> = fits
                .iter()
                .enumerate()
                .filter(|(_, f)| f.channel == ci)
                .map(|(k, _)| (rank_key(&scores[k]), k))
                .collect();
            best_and_rest(mine)
                .0
                .into_iter()
                .filter_map(|k| {
                    let f = &fits[k];
                    let residuals = f.fit.held_out(&states[ci], f.effect, folds)?;
                    Some((f.effect, residuals.into_owned()))
                })
                .collect()
        })
        .collect()
}

/// The channels the winner `w` joins the model on (`winner` is its trial; see
/// [`joins_the_model`]). On a channel where it is not significant it joins only if it also
/// extrapolates: refitted without the runs at either end of its driving input, it predicts
/// them no worse than the model without it ([`extrapolate::check`]); weak evidence does not
/// carry a form beyond the conditions it was fitted on.
fn adopted_channels(
    w: Extension,
    winner: &Trial,
    fits: &[PairFit],
    states: &[ChannelState],
    plausibility: &Plausibility,
) -> Vec<usize> {
    let joining: Vec<(&PairFit, bool)> = fits
        .iter()
        .filter(|f| f.effect == w)
        .filter_map(|f| {
            let c = winner
                .channels
                .iter()
                .find(|c| c.channel == states[f.channel].data.channel)?;
            joins_the_model(c).then_some((f, c.significant))
        })
        .collect();
    let extrapolates = parallel_map(&joining, |&(f, significant)| {
        significant || {
            let exports = |m: &ChannelModel| plausibility.exports(m);
            extrapolate::check(w, &states[f.channel].data, &f.fit.full, &exports)
                .iter()
                .all(|x| x.outcome != "worse")
        }
    });
    joining
        .iter()
        .zip(extrapolates)
        .filter(|(_, ok)| *ok)
        .map(|((f, _), _)| f.channel)
        .collect()
}

/// Whether the round's winner may join the model on the channel of `c`: where it was significant,
/// and where it lowers the held-out error without being significant, pooled over the rows and on
/// the runs' mean (the per-run test's p-value below one half; a pooled gain that most runs do not
/// share is a few runs' misfit), from a plausible fit, scored, refitted per fold and not refused
/// for its signature, so that a later candidate there is judged against a model that already has
/// the selected effect and cannot take the misfit it leaves (a speed effect significant on the
/// forces leaves on Mz a misfit that grows with the camber, which a camber term would take). It is
/// claimed only where it was significant; where it is not, it must also extrapolate
/// ([`adopted_channels`]).
pub(super) fn joins_the_model(c: &ChannelTrial) -> bool {
    c.significant
        || (c.gap_closed.is_some_and(|g| g > 0.0)
            && c.p_value < 0.5
            && c.not_scored.is_none()
            && c.implausible.is_none()
            && c.screened.is_none()
            && c.not_its_signature.is_none())
}

/// Records `w` as selected on `channels` (positions among the states), adds it to the verdict
/// and closes the pairs the design confounds with it.
fn adopted_as(
    w: Extension,
    channels: Vec<usize>,
    s: &mut Selection,
    design: &[DesignConfounding],
    open: &mut Vec<Pair>,
) {
    s.adopted.push((w, channels));
    if !s.verdict.contains(&w) {
        s.verdict.push(w);
    }
    close_confounded(w, design, open, &mut s.closed_by_design);
}

/// The adopt step of a pair of effects: each channel's joint fit becomes its model; both
/// effects' pairs on it are closed, and its other candidate fits dropped.
fn adopt_joint(
    fits: Vec<JointFit>,
    states: &mut [ChannelState],
    open: &mut Vec<Pair>,
    cache: &mut FitCache,
) {
    for f in fits {
        let ci = f.channel;
        let s = &mut states[ci];
        s.full = f.fit.full;
        if let Some(models) = f.fit.fold_models {
            s.fold_models = models;
        }
        if let Some(r) = f.fit.residuals {
            s.residuals = r;
        }
        open.retain(|p| !(p.channel == ci && f.effects.contains(&p.effect)));
        cache.retain(|p, _| p.channel != ci);
    }
}

/// Closes the open pairs of effects whose driving condition the design moves with the
/// selected `w`'s: whatever they gained now would be `w`'s effect counted twice.
fn close_confounded(
    w: Extension,
    design: &[DesignConfounding],
    open: &mut Vec<Pair>,
    closed: &mut Vec<Untestable>,
) {
    for c in design {
        for (mine, other) in [(0, 1), (1, 0)] {
            if !c.effects[mine].contains(&w) {
                continue;
            }
            for &e in &c.effects[other] {
                if e == w || !open.iter().any(|p| p.effect == e) {
                    continue;
                }
                open.retain(|p| p.effect != e);
                closed.push(Untestable {
                    effect: e,
                    reason: format!(
                        "confounded by design with {w}, which was selected: {} moves with {} \
                         across the runs (r = {:.2}), so the data cannot tell {e} from {w}",
                        c.conditions[other].name(),
                        c.conditions[mine].name(),
                        c.run_correlation
                    ),
                });
            }
        }
    }
}

/// The adopt step: the winner's fit becomes the model of each of `channels`; the pair is
/// closed, and the channel's other candidate fits, made against its old model, are dropped.
fn adopt(
    w: Extension,
    channels: &[usize],
    states: &mut [ChannelState],
    open: &mut Vec<Pair>,
    cache: &mut FitCache,
    folds: &Folds,
) {
    for &ci in channels {
        let pair = Pair {
            effect: w,
            channel: ci,
        };
        if let Some(Some(Scored { fit, .. })) = cache.remove(&pair) {
            let residuals = fit.held_out(&states[ci], w, folds).map(|r| r.into_owned());
            let s = &mut states[ci];
            s.full = fit.full;
            if let Some(models) = fit.fold_models {
                s.fold_models = models;
            }
            if let Some(r) = residuals {
                s.residuals = r;
            }
        }
        open.retain(|p| *p != pair);
        cache.retain(|p, _| p.channel != ci);
    }
}
