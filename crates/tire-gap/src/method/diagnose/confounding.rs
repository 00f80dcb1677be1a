//! The confounding step of a selection round: the runners-up the data cannot tell from the
//! winner, by their share of its gain or by how alike their corrections are.

use super::candidate::PairFit;
use super::score::Score;
use super::state::ChannelState;
use super::{FitConfounding, Options, Trial};
use crate::method::fit::effects::{Extension, separating_test};
use crate::method::prepare::cv::Folds;
use crate::method::stats::correlation;

/// Corrections correlated at least this much confound a runner-up whose gain reaches
/// [`CORRELATED_RATIO`] of the winner's.
const CORRELATED: f64 = 0.8;
const CORRELATED_RATIO: f64 = 0.5;

/// The runners-up confounded with the winner `w`, the first of the ranked `trials`: those
/// whose gain reaches `confounding_ratio` of the winner's score, or [`CORRELATED_RATIO`] of it
/// with corrections correlated at [`CORRELATED`] or more.
pub(super) fn confounders(
    w: Extension,
    trials: &[Trial],
    fits: &[PairFit],
    scores: &[Score],
    states: &[ChannelState],
    folds: &Folds,
    options: &Options,
) -> Vec<FitConfounding> {
    // The runner-up's gain: the gap it closes on all its channels, losses as 0.
    let best_other = |t: &Trial| {
        t.channels
            .iter()
            .filter_map(|c| c.gap_closed)
            .map(|g| g.max(0.0))
            .sum::<f64>()
    };
    let w_score = trials[0].score;
    let mut found = Vec::new();
    for t in trials.iter().skip(1) {
        let ratio = best_other(t) / w_score.max(1e-12);
        // The correlation (two series of held-out predictions) only where it can count.
        if ratio < options.confounding_ratio.min(CORRELATED_RATIO) {
            continue;
        }
        let corr = correction_correlation(w, t.effect, fits, scores, states, folds);
        if ratio >= options.confounding_ratio
            || corr.is_some_and(|c| c >= CORRELATED && ratio >= CORRELATED_RATIO)
        {
            found.push(FitConfounding {
                winner: w,
                runner_up: t.effect,
                score_ratio: ratio,
                correction_correlation: corr,
                separating_test: separating_test(w, t.effect),
            });
        }
    }
    found
}

/// The correlation of the winner's and the runner-up's held-out corrections (the current
/// residual less the candidate's) on the first of the winner's channels where both are
/// scored; `None` when there is no such channel.
fn correction_correlation(
    winner: Extension,
    runner_up: Extension,
    fits: &[PairFit],
    scores: &[Score],
    states: &[ChannelState],
    folds: &Folds,
) -> Option<f64> {
    // Correlations only on channels with a measurable gap left.
    let scored = |e: Extension, ci: usize| {
        fits.iter()
            .zip(scores)
            .any(|(f, s)| f.effect == e && f.channel == ci && s.gap_closed.is_some())
    };
    fits.iter()
        .filter(|f| f.effect == winner && scored(winner, f.channel) && scored(runner_up, f.channel))
        .find_map(|fw| correlation_on(fw.channel, winner, runner_up, fits, states, folds))
}

/// The correlation of two candidates' held-out corrections (the current residual less the
/// candidate's) on the channel at `ci` among the states; `None` when either is not fitted
/// there.
pub(super) fn correlation_on(
    ci: usize,
    a: Extension,
    b: Extension,
    fits: &[PairFit],
    states: &[ChannelState],
    folds: &Folds,
) -> Option<f64> {
    let fit_of = |e: Extension| fits.iter().find(|f| f.effect == e && f.channel == ci);
    let s = &states[ci];
    let correction = |f: &PairFit| -> Option<Vec<f64>> {
        let theirs = f.fit.held_out(s, f.effect, folds)?;
        Some(
            s.residuals
                .iter()
                .zip(theirs.iter())
                .map(|(a, b)| a - b)
                .collect(),
        )
    };
    correlation(&correction(fit_of(a)?)?, &correction(fit_of(b)?)?)
}
