//! The score step of a selection round: how much of a channel's gap a candidate closes on
//! held-out runs, and the paired per-run test of whether it closes it where it must show.

use std::collections::BTreeMap;

use super::Options;
use super::signature::{self, Cells, SignatureTest};
use super::state::{ChannelState, gap_measurable, no_gap_reason};
use crate::method::fit::channel_fit::{RunSquares, SMOOTHING_WINDOW, run_stretches, systematic};
use crate::method::fit::effects::{self, Extension, Form, Signature};
use crate::method::fit::model::ChannelModel;
use crate::method::stats::{CompactResiduals, sign_flip_greater};

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
    /// The gain split by the driver's activity, and the test of the claim's signature.
    pub(super) signature: SignatureTest,
}

/// Scores a candidate's held-out `residuals` against the channel's current model's, both on
/// the systematic part of the held-out residual; its signature's gain is measured against
/// `reference`'s residuals where it gives them.
pub(super) fn score(
    state: &ChannelState,
    (effect, fitted): (Extension, &ChannelModel),
    residuals: &CompactResiduals,
    reference: Reference,
    options: &Options,
) -> Score {
    let home = effects::of(effect).home_rows(&state.data);
    let drawn = || signature_of(state, effect, fitted);
    score_on(state, (home, &drawn, reference), residuals, options)
}

/// `effect`'s signature on the channel of `state`, drawn with its parameters in `fitted` (a
/// model that holds it).
pub(super) fn signature_of(
    state: &ChannelState,
    effect: Extension,
    fitted: &ChannelModel,
) -> Result<Signature, String> {
    let e = effects::of(effect);
    let values = fitted
        .effects
        .iter()
        .rev()
        .find(|(x, _)| *x == effect)
        .map(|(_, q)| effects::model_values(effect, q))
        .unwrap_or_default();
    let form = Form {
        nominal: &state.full.nominal,
        values: &values,
    };
    e.signature(&state.data, &form)
}

/// A signature to draw (or why it cannot be drawn), drawn only when it is needed.
pub(super) type Drawn<'a> = &'a dyn Fn() -> Result<Signature, String>;

/// The held-out residuals a signature's gain is measured against when not the current
/// model's (see `signature`), computed only when the signature is tested; `None`: the
/// current model's.
pub(super) type Reference<'a> = &'a dyn Fn() -> Option<CompactResiduals>;

/// No reference but the current model.
pub(super) fn current_model() -> Option<CompactResiduals> {
    None
}

/// [`score`] with the paired test on the rows `home` marks (every row: `None`) and the gain
/// split by the signature `drawn` gives, measured against `reference`, both drawn and tested
/// only when the channel could be claimed by the rest of its score (see [`could_be_claimed`]):
/// drawing the signature costs a pass of the effect's form over every row, the reference a
/// fit per fold.
pub(super) fn score_on(
    state: &ChannelState,
    (home, drawn, reference): (Option<Vec<bool>>, Drawn, Reference),
    residuals: &CompactResiduals,
    options: &Options,
) -> Score {
    let rows = (
        &state.data.run[..],
        &state.data.fz_kn[..],
        &state.data.measured[..],
    );
    let squares = home_mean_squares(rows, &state.residuals, residuals, home.as_deref(), None);
    let gains = relative_gains(&squares.before, &squares.after);
    let (sys_before, sys_after) = (squares.systematic_before, squares.systematic_after);
    let noise_var = state.noise * state.noise;
    let white = noise_var / SMOOTHING_WINDOW as f64;
    // The fall of the systematic mean square error as a share of a measurable gap.
    let share_of = |gap_sq: f64| {
        gap_measurable(gap_sq, state.noise, options).then(|| (sys_before - sys_after) / gap_sq)
    };
    let gap_sq = sys_before - white;
    let gap_closed = share_of(gap_sq);
    let p_value = sign_flip_greater(&gains);
    let noise_gain = (sys_before - sys_after) / noise_var;
    let signature = match could_be_claimed(p_value, gap_closed, noise_gain, options) {
        false => signature::untestable(
            "not judged: the candidate fails the other rules on this channel".into(),
        ),
        true => match drawn() {
            Ok(s) => {
                let idle_fit = reference();
                let (before, against) = match &idle_fit {
                    Some(r) => (r, signature::Against::IdleFit),
                    None => (&state.residuals, signature::Against::CurrentModel),
                };
                let cells = home_mean_squares(rows, before, residuals, None, Some(&s));
                signature::test(&s, &cells.cells, against)
            }
            Err(why) => signature::untestable(why),
        },
    };
    Score {
        p_value,
        runs: gains.len(),
        not_scored: gap_closed
            .is_none()
            .then(|| no_gap_reason(gap_sq, state.noise, options)),
        gap_closed,
        base_gap_closed: share_of(state.base_gap_sq),
        noise_gain,
        signature,
    }
}

/// Whether a channel's score could let it be claimed, by the rules that need nothing but the
/// score (see `trials::judge_rule`): its own p-value, the least share of the gap and the
/// least gain in noise variances of any round.
fn could_be_claimed(
    p_value: f64,
    gap_closed: Option<f64>,
    noise_gain: f64,
    options: &Options,
) -> bool {
    p_value < options.significance
        && gap_closed.is_some_and(|g| g >= options.min_gap_closed)
        && noise_gain >= options.min_noise_gain.min(options.min_noise_gain_later)
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

/// What [`home_mean_squares`] finds.
struct HomeSquares {
    /// Per run, the mean square at home of the current model's systematic residual.
    before: RunMeans,
    /// Per run, the same of the candidate's.
    after: RunMeans,
    /// The systematic mean squares over every row, the current model's and the candidate's.
    systematic_before: f64,
    systematic_after: f64,
    /// Per run, the squares where the effect's driver acts and where it is idle.
    cells: Cells,
}

/// Per-run mean squares at home (the rows `home` marks; all without it) of the systematic
/// parts of the current model's held-out residuals (`current`) and the candidate's, and both
/// systematic mean squares over every row, and the squares by the driver's `activity` per
/// run. One pass over the runs' stretches of rows (a moving average never crosses a run), each
/// sum taken in row order.
fn home_mean_squares(
    (run, fz_kn, measured): (&[i64], &[f64], &[f64]),
    current: &CompactResiduals,
    residuals: &CompactResiduals,
    home: Option<&[bool]>,
    signature: Option<&Signature>,
) -> HomeSquares {
    let at_home = |i: usize, x: f64| match home {
        Some(h) if !h[i] => f64::NAN,
        _ => x,
    };
    let (mut before, mut after) = (RunSquares::default(), RunSquares::default());
    let (mut whole_before, mut whole_after) = (Squares::default(), Squares::default());
    let mut cells = Cells::default();
    for rows in run_stretches(run) {
        let runs = &run[rows.clone()];
        let smoothed_before = systematic(runs, &current.as_single()[rows.clone()]);
        let smoothed = systematic(runs, &residuals.as_single()[rows.clone()]);
        whole_before.add(&smoothed_before);
        whole_after.add(&smoothed);
        let r = run[rows.start];
        if let Some(s) = signature {
            for (k, i) in rows.clone().enumerate() {
                let level = s.level.as_ref().map_or(0.0, |l| f64::from(l[i]));
                let row = (r, s.rows[i], level);
                cells.add(
                    row,
                    (fz_kn[i], measured[i]),
                    smoothed_before[k],
                    smoothed[k],
                );
            }
        }
        let starts = rows.clone().zip(smoothed_before);
        before.add(r, starts.map(|(i, x)| at_home(i, x)));
        after.add(r, rows.zip(smoothed).map(|(i, x)| at_home(i, x)));
    }
    HomeSquares {
        before: before.means(),
        after: after.means(),
        systematic_before: whole_before.mean(),
        systematic_after: whole_after.mean(),
        cells,
    }
}

/// A running sum of the squares of finite values and their count.
#[derive(Default)]
struct Squares {
    sum: f64,
    finite: usize,
}

impl Squares {
    fn add(&mut self, values: &[f64]) {
        for x in values.iter().filter(|x| x.is_finite()) {
            self.sum += x * x;
            self.finite += 1;
        }
    }

    /// The mean square, as [`crate::method::stats::mse`] gives it (0 with no finite value).
    fn mean(&self) -> f64 {
        self.sum / self.finite.max(1) as f64
    }
}
