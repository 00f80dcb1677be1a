//! Two effects fitted jointly. When no single candidate wins a round but a channel's gap is
//! still measurable, two effects may show only together: each alone is worse where the other
//! is unmodelled (temperature beside pressure, each fitted alone bending the base to the
//! other's runs). The effects that closed the most of a gap alone are paired, each pair
//! fitted jointly on the channels both act on and scored as one candidate, with the round's
//! effects in the multiplicity count. A pair is claimed only if each member shows its own
//! signature within the pair: the pair's gain rises where that member's driver acts (see
//! `signature`), as a single effect's must.

use std::collections::BTreeMap;

use mf87::Channel;
use serde::Serialize;

use super::Options;
use super::Trial;
use super::candidate::{CandidateFit, fit_candidate};
use super::pairs::Pair;
use super::plausibility::Plausibility;
use super::score::{Score, current_model, score_on, signature_of};
use super::signature::SignatureTest;
use super::state::ChannelState;
use super::trials::{confounded_by_design, judge_rule};
use crate::method::diagnose::design::DesignConfounding;
use crate::method::fit::effects::{self, Extension};
use crate::method::observer::Observer;
use crate::method::parallel::parallel_map;
use crate::method::prepare::cv::Folds;
use crate::method::stats::{CompactResiduals, channels_combined, holm};

/// The single effects paired: the best this many of the round, two at a time.
const JOINT_EFFECTS: usize = 3;

/// Two effects fitted jointly in a round that no single effect won.
#[derive(Debug, Clone, Serialize)]
pub struct JointTrial {
    /// The pair, the one that closed more of a gap alone first.
    pub effects: [Extension; 2],
    pub channels: Vec<JointChannel>,
    pub significant: bool,
    /// Sum over its significant channels of the gap closed.
    pub score: f64,
}

/// A pair on one channel.
#[derive(Debug, Clone, Serialize)]
pub struct JointChannel {
    pub channel: Channel,
    /// Held-out RMS before and after adding the pair [N or N.m].
    pub heldout_before: f64,
    pub heldout_after: f64,
    /// Fraction of the gap above the noise floor (before the round) the pair closes.
    pub gap_closed: Option<f64>,
    /// The gain in noise variances.
    pub noise_gain: f64,
    /// One-sided sign-flip p-value over runs on this channel, and the pair's p-value (its
    /// channels' combined) after Holm's correction over the round's effects and pairs.
    pub p_value: f64,
    pub p_adjusted: Option<f64>,
    pub runs: usize,
    pub significant: bool,
    /// Why the joint fit is not physical, when it is not.
    pub implausible: Option<String>,
    /// The pair's gain split by each member's driver's activity.
    pub members: [SignatureTest; 2],
    /// Why a channel that passed every other rule is not claimed for a member's signature.
    pub not_their_signatures: Option<String>,
    /// Fitted parameters of both effects on all data.
    pub params: BTreeMap<String, f64>,
}

/// A pair fitted on one channel: its fit and scores.
pub(super) struct JointFit {
    pub(super) effects: [Extension; 2],
    pub(super) channel: usize,
    pub(super) fit: CandidateFit,
    score: Score,
    mse: f64,
    members: [SignatureTest; 2],
}

/// What a round of pairs found: every pair tried, and the fits of the winning one on the
/// channels where it is claimed.
pub(super) struct Joints {
    pub(super) trials: Vec<JointTrial>,
    pub(super) winner: Option<Winner>,
}

/// The pair that won a round, with its joint fits on the channels it won.
pub(super) type Winner = ([Extension; 2], Vec<JointFit>);

/// The single fits of the round a pair is built from: each open pair's fit, if it was
/// fitted and cross-validated on every fold.
pub(super) type Singles<'a> = dyn Fn(Pair) -> Option<&'a CandidateFit> + Sync + 'a;

/// The pairs of a round no single effect won (`trials`, judged and ranked): the best
/// [`JOINT_EFFECTS`] effects by the gap they closed alone, two at a time, but pairs the
/// design confounds, each fitted jointly where both are open, scored and judged. `first`: no
/// effect selected yet (the least gain is `min_noise_gain`, else `min_noise_gain_later`).
#[allow(clippy::too_many_arguments)]
pub(super) fn joints(
    states: &[ChannelState],
    open: &[Pair],
    singles: &Singles,
    trials: &[Trial],
    (folds, options, first): (&Folds, &Options, bool),
    design: &[DesignConfounding],
    plausibility: &Plausibility,
    observer: &dyn Observer,
) -> Joints {
    let effects = best_alone(trials);
    let mut jobs: Vec<([Extension; 2], usize)> = Vec::new();
    for (k, &a) in effects.iter().enumerate() {
        for &b in &effects[k + 1..] {
            if confounded_by_design(a, b, design) {
                continue;
            }
            for ci in 0..states.len() {
                let open_with = |e| {
                    open.contains(&Pair {
                        effect: e,
                        channel: ci,
                    })
                };
                let fitted = |e| {
                    singles(Pair {
                        effect: e,
                        channel: ci,
                    })
                    .is_some()
                };
                if open_with(a) && open_with(b) && fitted(a) && fitted(b) {
                    jobs.push(([a, b], ci));
                }
            }
        }
    }
    if jobs.is_empty() || observer.cancelled() {
        return Joints {
            trials: Vec::new(),
            winner: None,
        };
    }
    observer.stage(
        "no single effect won: fitting the best pairs of effects jointly",
        jobs.len() as u64,
    );
    let fitted: Vec<JointFit> = parallel_map(&jobs, |&(pair, ci)| {
        let fit = (!observer.cancelled())
            .then(|| joint_fit(&states[ci], pair, ci, singles, folds, plausibility, options))
            .flatten();
        observer.step();
        fit
    })
    .into_iter()
    .flatten()
    .collect();
    judge(states, fitted, trials, first, options, plausibility)
}

/// The effects of the round that closed the most of a channel's measurable gap alone, best
/// first, at most [`JOINT_EFFECTS`]: fitted physically, cross-validated, and gaining.
fn best_alone(trials: &[Trial]) -> Vec<Extension> {
    let mut ranked: Vec<(f64, Extension)> = trials
        .iter()
        .filter_map(|t| {
            let best = t
                .channels
                .iter()
                .filter(|c| c.implausible.is_none() && c.screened.is_none())
                .filter_map(|c| c.gap_closed)
                .fold(f64::NEG_INFINITY, f64::max);
            (best > 0.0).then_some((best, t.effect))
        })
        .collect();
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
    ranked
        .into_iter()
        .take(JOINT_EFFECTS)
        .map(|(_, e)| e)
        .collect()
}

/// `pair` fitted jointly on the channel at `ci`: the second effect added to the first's fit
/// (on all data and on every fold, then a joint refit with the base), scored against the
/// channel's current model, its gain split by each member's driver.
fn joint_fit(
    state: &ChannelState,
    pair: [Extension; 2],
    ci: usize,
    singles: &Singles,
    folds: &Folds,
    plausibility: &Plausibility,
    options: &Options,
) -> Option<JointFit> {
    let single = |e: Extension| {
        singles(Pair {
            effect: e,
            channel: ci,
        })
    };
    let alone = |e: Extension| -> Option<ChannelState> {
        let fit = single(e)?;
        Some(ChannelState {
            full: fit.full.clone(),
            fold_models: fit.fold_models.clone()?,
            residuals: fit.held_out(state, e, folds)?.into_owned(),
            ..state.clone()
        })
    };
    let first = alone(pair[0])?;
    let mut fit = fit_candidate(&first, pair[1], folds, plausibility)?;
    let residuals: CompactResiduals = fit.residuals.take()?;
    let home = joint_home(state, pair);
    let pair_has_none = || Err("a pair's signature is its members'".to_string());
    let score = score_on(
        state,
        (home, &pair_has_none, &current_model),
        &residuals,
        options,
    );
    // A member's signature: the pair's gain split by that member's driver. (Against the other
    // member fitted alone it would mostly measure that fit's failure where the member is
    // unmodelled, which is why the pair was fitted.)
    let member = |e: Extension| -> SignatureTest {
        let home = effects::of(e).home_rows(&state.data);
        let drawn = || signature_of(state, e, &fit.full);
        score_on(state, (home, &drawn, &current_model), &residuals, options).signature
    };
    let members = [member(pair[0]), member(pair[1])];
    let mse = residuals.mse();
    fit.residuals = Some(residuals);
    Some(JointFit {
        effects: pair,
        channel: ci,
        fit,
        score,
        mse,
        members,
    })
}

/// The rows where either member must show (every row when either shows everywhere).
fn joint_home(state: &ChannelState, pair: [Extension; 2]) -> Option<Vec<bool>> {
    let a = effects::of(pair[0]).home_rows(&state.data)?;
    let b = effects::of(pair[1]).home_rows(&state.data)?;
    Some(a.iter().zip(&b).map(|(x, y)| *x || *y).collect())
}

/// The pairs' trials judged: each pair's channels combined and Holm-corrected with the round's
/// effects (`trials`), each channel held to the rules a single effect is held to, then each
/// member's signature (Holm over every member test of the channels that passed the rest);
/// the winner is the significant pair that closes the most.
fn judge(
    states: &[ChannelState],
    fitted: Vec<JointFit>,
    trials: &[Trial],
    first: bool,
    options: &Options,
    plausibility: &Plausibility,
) -> Joints {
    let mut pairs: Vec<[Extension; 2]> = fitted.iter().map(|f| f.effects).collect();
    pairs.dedup();
    let joint_adjusted = pairs_adjusted(&pairs, &fitted, trials);
    let mut channels: Vec<(usize, JointChannel)> = fitted
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let pi = pairs.iter().position(|p| *p == f.effects).unwrap_or(0);
            let state = &states[f.channel];
            let c = channel(state, f, joint_adjusted[pi], first, options, plausibility);
            (k, c)
        })
        .collect();
    judge_members(&mut channels, |k| fitted[k].effects, options);
    let mut trials: Vec<JointTrial> = pairs
        .iter()
        .map(|pair| {
            let mine: Vec<JointChannel> = channels
                .iter()
                .filter(|(k, _)| fitted[*k].effects == *pair)
                .map(|(_, c)| c.clone())
                .collect();
            let score = mine
                .iter()
                .filter(|c| c.significant)
                .filter_map(|c| c.gap_closed)
                .map(|g| g.max(0.0))
                .sum();
            JointTrial {
                effects: *pair,
                significant: mine.iter().any(|c| c.significant),
                channels: mine,
                score,
            }
        })
        .collect();
    trials.sort_by(|a, b| b.score.total_cmp(&a.score));
    let winner = trials.first().filter(|t| t.significant).map(|t| {
        let won: Vec<Channel> = t
            .channels
            .iter()
            .filter(|c| c.significant)
            .map(|c| c.channel)
            .collect();
        let fits = fitted
            .into_iter()
            .filter(|f| f.effects == t.effects && won.contains(&states[f.channel].data.channel))
            .collect();
        (t.effects, fits)
    });
    Joints { trials, winner }
}

/// Each pair's p-value, its channels combined, Holm-corrected in one family with the round's
/// effects' own (`trials`); `None` for a pair no channel of which was scored.
fn pairs_adjusted(
    pairs: &[[Extension; 2]],
    fitted: &[JointFit],
    trials: &[Trial],
) -> Vec<Option<f64>> {
    let pooled_of = |p: Vec<f64>| (!p.is_empty()).then(|| channels_combined(&p));
    let singles: Vec<f64> = trials
        .iter()
        .filter_map(|t| {
            let scored = t.channels.iter().filter(|c| c.gap_closed.is_some());
            pooled_of(scored.map(|c| c.p_value).collect())
        })
        .collect();
    let joint_pooled: Vec<Option<f64>> = pairs
        .iter()
        .map(|pair| {
            let mine = fitted.iter().filter(|f| f.effects == *pair);
            pooled_of(
                mine.filter(|f| f.score.gap_closed.is_some())
                    .map(|f| f.score.p_value)
                    .collect(),
            )
        })
        .collect();
    let family: Vec<f64> = singles
        .iter()
        .copied()
        .chain(joint_pooled.iter().flatten().copied())
        .collect();
    let mut adjusted = holm(&family).into_iter().skip(singles.len());
    joint_pooled
        .iter()
        .map(|p| p.and_then(|_| adjusted.next()))
        .collect()
}

/// One pair's channel judged by the rules of a single effect's (see `trials`): the pair's
/// adjusted p-value and this channel's below the significance level, the least gains, a fit
/// physical for both members, a lower held-out mean square error.
fn channel(
    state: &ChannelState,
    f: &JointFit,
    p_adjusted: Option<f64>,
    first: bool,
    options: &Options,
    plausibility: &Plausibility,
) -> JointChannel {
    let implausible = f
        .effects
        .iter()
        .find_map(|e| plausibility.judge(&state.data, &state.full, &f.fit.full, *e));
    let (before, after) = (state.residuals.mse(), f.mse);
    let significant = judge_rule((&f.score, p_adjusted), (before, after), first, options)
        && implausible.is_none();
    let names = f.fit.full.names();
    let theta = f.fit.full.theta();
    let n: usize = f.effects.iter().map(|e| e.parameter_names().len()).sum();
    let params = names[names.len() - n..]
        .iter()
        .cloned()
        .zip(theta[theta.len() - n..].iter().copied())
        .collect();
    JointChannel {
        channel: state.data.channel,
        heldout_before: before.sqrt(),
        heldout_after: after.sqrt(),
        gap_closed: f.score.gap_closed,
        noise_gain: f.score.noise_gain,
        p_value: f.score.p_value,
        p_adjusted,
        runs: f.score.runs,
        significant,
        implausible,
        members: f.members.clone(),
        not_their_signatures: None,
        params,
    }
}

/// Each member's signature on the channels that passed the rest, as a single effect's is
/// judged (see `trials::judge_signatures`): on each channel its gain over the other member
/// alone points to its driver, and its p-values over those channels, combined, are below the
/// significance level after Holm's correction over every member of every pair tried.
fn judge_members(
    channels: &mut [(usize, JointChannel)],
    effects_of: impl Fn(usize) -> [Extension; 2],
    options: &Options,
) {
    let alpha = options.significance;
    let mut members: Vec<([Extension; 2], usize)> = Vec::new();
    for (k, c) in channels.iter().filter(|(_, c)| c.significant) {
        for m in 0..2 {
            if !members.contains(&(effects_of(*k), m)) && c.members[m].points_to_driver() {
                members.push((effects_of(*k), m));
            }
        }
    }
    let pooled: Vec<f64> = members
        .iter()
        .map(|(pair, m)| {
            let mine: Vec<f64> = channels
                .iter()
                .filter(|(k, c)| c.significant && effects_of(*k) == *pair)
                .filter(|(_, c)| c.members[*m].points_to_driver())
                .filter_map(|(_, c)| c.members[*m].p_value)
                .collect();
            channels_combined(&mine)
        })
        .collect();
    let adjusted = holm(&pooled);
    for (k, c) in channels.iter_mut().filter(|(_, c)| c.significant) {
        let pair = effects_of(*k);
        for (m, member) in c.members.iter_mut().enumerate() {
            let p = members
                .iter()
                .position(|x| *x == (pair, m))
                .map(|i| adjusted[i]);
            member.p_adjusted = p;
            member.shown = member.points_to_driver() && p.is_some_and(|p| p < alpha);
        }
        if let Some(m) = c.members.iter().position(|m| !m.shown) {
            c.significant = false;
            c.not_their_signatures = Some(format!(
                "{} within the pair: {}",
                pair[m],
                c.members[m].refusal(alpha)
            ));
        }
    }
}
