//! The score step of a selection round: how much of a channel's gap a candidate closes on
//! held-out runs, and the paired per-run test of whether it closes it where it must show.

use std::collections::BTreeMap;

use super::Options;
use super::state::{ChannelState, gap_measurable, no_gap_reason};
use crate::method::fit::channel_fit::{RunSquares, SMOOTHING_WINDOW, run_stretches, systematic};
use crate::method::fit::effects::{self, Extension};
use crate::method::parallel::parallel_map;
use crate::method::stats::CompactResiduals;
use crate::method::stats::{mse, sign_flip_greater};

/// How a candidate fared on one channel.
#[derive(Debug, Clone)]
pub(super) struct Score {
    /// One-sided sign-flip p-value of per-run relative improvements in the effect's home rows.
    pub(super) p_value: f64,
    /// Runs compared.
    pub(super) runs: usize,
    /// Fraction of the systematic gap above the noise floor closed, now and of the base's;
    /// `None` when that gap is not measurable (`not_scored` says why).
    pub(super) gap_closed: Option<f64>,
    pub(super) base_gap_closed: Option<f64>,
    /// The fall of the systematic mean square error, in noise variances.
    pub(super) noise_gain: f64,
    pub(super) not_scored: Option<String>,
}

/// Scores a candidate's held-out `residuals` against the channel's current model, both on
/// the systematic part of the held-out residual (`systematic_before` is the current model's).
pub(super) fn score(
    state: &ChannelState,
    systematic_before: &[f64],
    effect: Extension,
    residuals: &CompactResiduals,
    options: &Options,
) -> Score {
    let home = effects::of(effect).home_rows(&state.data);
    let (before, after, sys_after) = home_mean_squares(
        &state.data.run,
        systematic_before,
        residuals,
        home.as_deref(),
    );
    let gains = relative_gains(&before, &after);
    let sys_before = mse(systematic_before);
    let noise_var = state.noise * state.noise;
    let white = noise_var / SMOOTHING_WINDOW as f64;
    // The fall of the systematic mean square error as a share of a measurable gap.
    let share_of = |gap_sq: f64| {
        gap_measurable(gap_sq, state.noise, options).then(|| (sys_before - sys_after) / gap_sq)
    };
    let gap_sq = sys_before - white;
    let gap_closed = share_of(gap_sq);
    Score {
        p_value: sign_flip_greater(&gains),
        runs: gains.len(),
        not_scored: gap_closed
            .is_none()
            .then(|| no_gap_reason(gap_sq, state.noise, options)),
        gap_closed,
        base_gap_closed: share_of(state.base_gap_sq),
        noise_gain: (sys_before - sys_after) / noise_var,
    }
}

/// Mean squares per run.
pub(super) type RunMeans = BTreeMap<i64, f64>;

/// Each run's gain, `(before - after) / (before + after + typical)` of its mean squares, over
/// the runs in both, with `typical` the runs' mean of before and after. A gain lies between -1
/// and 1, so no run carries the test alone, whether it gains or loses, and a run with a large
/// misfit of another kind does not drown the others, while runs whose error is already small
/// (e.g. Fx in pure cornering) weigh little instead of adding their noise at full weight.
/// Swapping before and after negates every gain: when the two are exchangeable (no effect),
/// each gain is as likely to take either sign, which is what the sign-flip test assumes.
pub(super) fn relative_gains(before: &RunMeans, after: &RunMeans) -> Vec<f64> {
    let both: Vec<(f64, f64)> = before
        .iter()
        .filter_map(|(r, b)| Some((*b, *after.get(r)?)))
        .collect();
    let typical = both.iter().map(|(b, a)| b + a).sum::<f64>() / (2 * both.len().max(1)) as f64;
    both.iter()
        .map(|(b, a)| (b - a) / (b + a + typical).max(f64::MIN_POSITIVE))
        .collect()
}

/// Per-run mean squares at home (the rows `home` marks; all without it) of the current
/// model's systematic residual and the candidate's, and the candidate's systematic mean
/// square over every row. One pass over the runs' stretches of rows (a moving average never
/// crosses a run), each sum taken in row order.
fn home_mean_squares(
    run: &[i64],
    systematic_before: &[f64],
    residuals: &CompactResiduals,
    home: Option<&[bool]>,
) -> (RunMeans, RunMeans, f64) {
    let at_home = |i: usize, x: f64| match home {
        Some(h) if !h[i] => f64::NAN,
        _ => x,
    };
    let (mut before, mut after) = (RunSquares::default(), RunSquares::default());
    let (mut sum_after, mut finite_after) = (0.0, 0usize);
    let mut stretch = Vec::new();
    for rows in run_stretches(run) {
        stretch.clear();
        stretch.extend(rows.clone().map(|i| residuals.get(i)));
        let smoothed = systematic(&run[rows.clone()], &stretch);
        for x in smoothed.iter().filter(|x| x.is_finite()) {
            sum_after += x * x;
            finite_after += 1;
        }
        let r = run[rows.start];
        before.add(r, rows.clone().map(|i| at_home(i, systematic_before[i])));
        after.add(r, rows.zip(smoothed).map(|(i, x)| at_home(i, x)));
    }
    let sys_after = sum_after / finite_after.max(1) as f64;
    (before.means(), after.means(), sys_after)
}

/// Each channel's current held-out residual, its systematic part: what candidates are scored
/// against (white noise cannot be explained by any effect).
pub(super) fn systematic_before(states: &[ChannelState]) -> Vec<Vec<f64>> {
    parallel_map(states, |s| systematic(&s.data.run, &s.residuals))
}
