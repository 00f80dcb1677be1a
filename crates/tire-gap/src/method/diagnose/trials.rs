//! The judging steps of a selection round: each effect's p-values combined over its channels
//! and corrected over the round's effects, each channel judged (significant, then the
//! specificity rule), and the effects ranked by the gap they close.

use mf87::Channel;

use super::candidate::PairFit;
use super::score::Score;
use super::state::ChannelState;
use super::{ChannelTrial, Options, Trial};
use crate::method::diagnose::design::DesignConfounding;
use crate::method::fit::effects::{self, Extension};
use crate::method::stats::{channels_combined, holm};

/// The signature rule: a channel that passed every other rule is claimed only if its held-out
/// gain lies where the effect's driver acts (see `signature`): on the channel, its gain per row
/// where the driver acts exceeds that where it is idle, and the test's statistic points the
/// same way ([`super::signature::SignatureTest::points_to_driver`]); and the effect's signature
/// p-value (those channels' p-values combined as the gains' are) is below the significance
/// level, also after Holm's correction over the round's effects that have such channels.
/// Effects whose drivers the `design` moves together count once in that correction: their
/// signatures are one test (the data give the same rows to both). The others lose their
/// significance and say why.
pub(super) fn judge_signatures(
    trials: &mut [Trial],
    design: &[DesignConfounding],
    options: &Options,
) {
    let alpha = options.significance;
    let own = |c: &ChannelTrial| c.significant && c.signature.points_to_driver();
    let pooled: Vec<Option<f64>> = trials
        .iter()
        .map(|t| {
            let mine: Vec<f64> = t
                .channels
                .iter()
                .filter(|c| own(c))
                .filter_map(|c| c.signature.p_value)
                .collect();
            (!mine.is_empty()).then(|| channels_combined(&mine))
        })
        .collect();
    // One test per group of effects the design confounds: its smallest p-value.
    let effects: Vec<Extension> = trials.iter().map(|t| t.effect).collect();
    let group = |k: usize| -> usize {
        (0..effects.len())
            .find(|&j| j == k || confounded_by_design(effects[j], effects[k], design))
            .unwrap_or(k)
    };
    let mut groups: Vec<(usize, f64)> = Vec::new();
    for (k, p) in pooled.iter().enumerate() {
        let Some(p) = p else { continue };
        match groups.iter_mut().find(|(g, _)| *g == group(k)) {
            Some(g) => g.1 = g.1.min(*p),
            None => groups.push((group(k), *p)),
        }
    }
    let adjusted = holm(&groups.iter().map(|g| g.1).collect::<Vec<f64>>());
    for (k, (t, pooled)) in trials.iter_mut().zip(&pooled).enumerate() {
        let effect_p = pooled.map(|p| {
            let g = groups.iter().position(|(g, _)| *g == group(k)).unwrap_or(0);
            p.max(adjusted[g])
        });
        for c in t.channels.iter_mut().filter(|c| c.significant) {
            let s = &mut c.signature;
            s.p_adjusted = effect_p;
            s.shown = s.points_to_driver() && effect_p.is_some_and(|p| p < alpha);
            if !s.shown {
                c.significant = false;
                c.not_its_signature = Some(s.refusal(alpha));
            }
        }
    }
}

/// Whether the design moves the conditions that drive `a` and `b` together across the runs.
pub(super) fn confounded_by_design(
    a: Extension,
    b: Extension,
    design: &[DesignConfounding],
) -> bool {
    design.iter().any(|c| {
        (c.effects[0].contains(&a) && c.effects[1].contains(&b))
            || (c.effects[0].contains(&b) && c.effects[1].contains(&a))
    })
}

/// The adjusted p-value of each fit's effect (`None`: none of the effect's channels was
/// scored). One test per effect: its channels' p-values combined (`channels_combined`: Fisher
/// or Bonferroni, whichever is stronger), Holm-corrected over the round's effects. An average
/// of the channels' gains would let a channel the effect does not touch hide one it does.
pub(super) fn combine(fits: &[PairFit], scores: &[Score]) -> Vec<Option<f64>> {
    let mut round_effects: Vec<Extension> = fits.iter().map(|f| f.effect).collect();
    round_effects.sort();
    round_effects.dedup();
    // Channels without a measurable gap left take no part.
    let pooled: Vec<Option<f64>> = round_effects
        .iter()
        .map(|e| {
            let mine: Vec<f64> = fits
                .iter()
                .zip(scores)
                .filter(|(f, s)| f.effect == *e && s.gap_closed.is_some())
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
    fits.iter()
        .map(|f| {
            let i = round_effects.iter().position(|e| *e == f.effect)?;
            pooled_adjusted[i]
        })
        .collect()
}

/// The rules of significance a candidate's channel is held to by its score: significant when
/// the candidate is (`p_adjusted`), and this channel shows it on its own, by an amount that
/// matters against both the gap left and the sensor noise (`min_noise_gain` noise variances
/// for the `first` effect, else `min_noise_gain_later`), and the channel's held-out mean
/// square error falls from `before` to `after` (not only its systematic part: an effect that
/// smooths the error while adding to it is not claimed there).
pub(super) fn judge_rule(
    (score, p_adjusted): (&Score, Option<f64>),
    (before, after): (f64, f64),
    first: bool,
    options: &Options,
) -> bool {
    let min_noise_gain = options.min_noise_gain_for(first);
    p_adjusted.is_some_and(|p| p < options.significance)
        && score.p_value < options.significance
        && score
            .gap_closed
            .is_some_and(|g| g >= options.min_gap_closed)
        && score.noise_gain >= min_noise_gain
        && after < before
}

/// One fitted pair judged: significant by its score ([`judge_rule`]), with a physical fit
/// (`implausible` is `None`) that was cross-validated (not screened).
fn channel_trial(
    state: &ChannelState,
    fit: &PairFit,
    score: &Score,
    p_adjusted: Option<f64>,
    implausible: Option<String>,
    first: bool,
    options: &Options,
) -> ChannelTrial {
    let (before, after) = (state.residuals.mse(), fit.mse);
    let significant = judge_rule((score, p_adjusted), (before, after), first, options)
        && implausible.is_none()
        && fit.fit.screened.is_none();
    let names = fit.fit.full.names();
    let theta = fit.fit.full.theta();
    let n_eff = fit.effect.parameter_names().len();
    let params = names[names.len() - n_eff..]
        .iter()
        .cloned()
        .zip(theta[theta.len() - n_eff..].iter().copied())
        .collect();
    ChannelTrial {
        channel: state.data.channel,
        heldout_before: before.sqrt(),
        heldout_after: after.sqrt(),
        gap_closed: score.gap_closed,
        base_gap_closed: score.base_gap_closed,
        not_scored: score.not_scored.clone(),
        noise_gain: score.noise_gain,
        p_value: score.p_value,
        p_adjusted,
        runs: score.runs,
        significant,
        unspecific: false,
        implausible,
        screened: fit.fit.screened.clone(),
        signature: score.signature.clone(),
        not_its_signature: None,
        overshadowed: None,
        params,
    }
}

/// The round's trials: every fitted pair judged, grouped by effect in the order of the fits.
/// Effects are not yet marked significant nor scored (see `rank_trials`).
pub(super) fn judge(
    states: &[ChannelState],
    fits: &[PairFit],
    scores: &[Score],
    p_adjusted: &[Option<f64>],
    implausible: &[Option<String>],
    first: bool,
    options: &Options,
) -> Vec<Trial> {
    let mut trials: Vec<Trial> = Vec::new();
    for (k, fit) in fits.iter().enumerate() {
        let state = &states[fit.channel];
        let trial = channel_trial(
            state,
            fit,
            &scores[k],
            p_adjusted[k],
            implausible[k].clone(),
            first,
            options,
        );
        match trials.iter_mut().find(|t| t.effect == fit.effect) {
            Some(t) => t.channels.push(trial),
            None => trials.push(Trial {
                effect: fit.effect,
                form: effects::of(fit.effect).form(),
                channels: vec![trial],
                significant: false,
                score: 0.0,
            }),
        }
    }
    trials
}

/// Specificity: a gain that is small against the base model's gap (below
/// `min_base_gap_closed` of it), and that another candidate matches on the same channel (at
/// least `confounding_ratio` of it), is extra freedom soaking up misfit of the formula's
/// shape, not evidence of this effect: such a channel is marked unspecific and not
/// significant. Every channel is judged on the significance the trials came with.
pub(super) fn mark_unspecific(trials: &mut [Trial], options: &Options) {
    // The largest gain of any other candidate on `channel`.
    let gains_on = |channel: Channel, other_than: Extension| -> f64 {
        trials
            .iter()
            .filter(|u| u.effect != other_than)
            .flat_map(|u| u.channels.iter().filter(|c| c.channel == channel))
            .filter_map(|c| c.gap_closed)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let unspecific: Vec<(Extension, Channel)> = trials
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
    for t in trials.iter_mut() {
        for c in &mut t.channels {
            if unspecific.contains(&(t.effect, c.channel)) {
                c.significant = false;
                c.unspecific = true;
            }
        }
    }
}

/// A rival takes the same misfit more fully when it closes at least this multiple of the
/// candidate's share of the gap on the channel...
const OVERSHADOW_RATIO: f64 = 1.1;
/// ... and their held-out corrections correlate at least this much.
const OVERSHADOW_CORRELATION: f64 = 0.5;

/// The overshadow rule: a channel that passed every rule, its signature too, is not claimed
/// when a rival on the same channel, refused only for its own signature, closes at least
/// [`OVERSHADOW_RATIO`] times its share of the gap with corrections correlated at
/// [`OVERSHADOW_CORRELATION`] or more (`correlation` of two effects' held-out corrections on a
/// channel). Its gain is then a part of a misfit its form only partly fits, whose shape
/// another form fits better but whose cause that form's signature does not confirm (a force
/// offset at every slip that a shift along the slip ratio takes near zero slip, where its own
/// driver acts, but not beyond the peak): neither is claimed, and the misfit stays unexplained.
pub(super) fn mark_overshadowed(
    trials: &mut [Trial],
    correlation: &dyn Fn(Extension, Extension, Channel) -> Option<f64>,
) {
    let mut marks: Vec<(Extension, Channel, String)> = Vec::new();
    for t in trials.iter() {
        for c in t.channels.iter().filter(|c| c.significant) {
            let Some(own) = c.gap_closed.filter(|g| *g > 0.0) else {
                continue;
            };
            let rival = trials
                .iter()
                .filter(|u| u.effect != t.effect)
                .flat_map(|u| u.channels.iter().map(move |r| (u.effect, r)))
                .filter(|(_, r)| r.channel == c.channel && r.not_its_signature.is_some())
                .filter_map(|(e, r)| Some((e, r.gap_closed?)))
                .filter(|(_, g)| *g >= OVERSHADOW_RATIO * own)
                .find_map(|(e, g)| {
                    let r = correlation(t.effect, e, c.channel)?;
                    (r >= OVERSHADOW_CORRELATION).then_some((e, g, r))
                });
            if let Some((e, g, r)) = rival {
                marks.push((
                    t.effect,
                    c.channel,
                    format!(
                        "its gain is a part of what {} takes more fully (it closes {:.0} % of \
                         the gap left here against {:.0} %; their held-out corrections \
                         correlate, r = {r:.2}), and {} does not show its signature: the \
                         cause of this misfit is not named",
                        e.name(),
                        100.0 * g,
                        100.0 * own,
                        e.name()
                    ),
                ));
            }
        }
    }
    for (effect, channel, why) in marks {
        let t = trials.iter_mut().find(|t| t.effect == effect);
        for c in t.into_iter().flat_map(|t| t.channels.iter_mut()) {
            if c.channel == channel {
                c.significant = false;
                c.overshadowed = Some(why.clone());
            }
        }
    }
}

/// An effect is significant on any significant channel, and scores the gap it closes there
/// (summed, losses as 0). Trials are ranked by score, ties by the largest gap closed on any
/// channel, best first.
pub(super) fn rank_trials(trials: &mut [Trial]) {
    for t in trials.iter_mut() {
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
}
