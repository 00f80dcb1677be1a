//! The signature of a claim: a candidate's held-out gain must lie where its driver acts. Its
//! gain per row where the driver acts (combined slip where both slips are away from zero,
//! pressure off the nominal pressure, ...) must exceed its gain where the driver is idle, by a
//! test on the same held-out residuals as the candidate's score. A candidate whose gain lies
//! where its driver is idle absorbs misfit of another cause (the refit of the base, extra
//! freedom) and is not claimed.
//!
//! The gain is measured against the channel's current model, except for an effect whose base
//! is fitted first where its driver is idle (combined slip: the pure-slip rows): there it is
//! measured against the current model refitted, per fold, on the training rows where the
//! driver is idle. A programme whose rows mostly lie where the driver acts (a drive/brake grid
//! at three slip angles) bends the current model's curves towards those rows, so that a real
//! effect gains most where its driver is idle, by letting the base curves back; against the
//! base fitted where the driver is idle, a real effect gains where it acts and about nothing
//! where it is idle, and a candidate that only soaks up misfit of another cause gains nothing
//! where it acts that the idle rows' base does not already hold.
//!
//! The units of the test are each run's rows where the driver acts and its rows where the
//! driver is idle ("cells"), and for a driver with a range of levels (a condition through the
//! effect's fitted form, a slip's rate) its rows between the two as well.
//!
//! A driver that acts or does not (combined slip, the shifts near zero slip): a cell's gain is
//! the fall of the mean square of the systematic held-out residual (as in the score) per row,
//! over the mean square of the load there (a gain in the units of a friction coefficient
//! squared, so that runs at high load, whose errors are large in newtons, do not drown the
//! rest), and the active cells' gains must exceed the idle cells' by a one-sided two-sample
//! permutation test. A gain per row and not a share of the error there: a candidate that
//! takes a share of every row's misfit, which any refit does, gains most where the misfit is
//! largest, whatever its driver.
//!
//! A driver with a range of levels, which mostly differ from run to run: runs differ in load,
//! camber and the slips they sweep, and so in their error by an order of magnitude, whatever
//! the driver. A cell's gain is then the share of its error the candidate takes,
//! `(before - after) / (before + after + typical)` as in the score's per-run test, and the
//! cells' gains must rise with their mean level by a permutation test of a rising trend of
//! their ranks (Spearman's), which weighs every run, not only the thirds at either end, and
//! which no one run's large misfit carries. A share saturates where the candidate takes most of
//! the error, so an effect that takes most of it wherever it acts at all shows no trend of
//! shares; its gain per row over the load's mean square (as for a driver that acts or does
//! not) is then much larger where it acts than where it is idle. Both are tested, the active
//! cells against the idle ones by the second, and the smaller p-value counts twice
//! (Bonferroni over the two).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::method::fit::effects::{Activity, Signature};
use crate::method::stats::{permutation_trend, ranks};

/// Rows a run's active or idle rows need to form a cell of the test.
const CELL_ROWS_MIN: usize = 10;
/// Cells each side needs for the test.
const CELLS_MIN: usize = 2;

/// A candidate's gain on one channel split by its driver's activity, and the test of its
/// signature.
#[derive(Debug, Clone, Serialize)]
pub struct SignatureTest {
    /// The driver, and the rows where it acts and is idle, in words with their bounds.
    pub driver: String,
    pub active: String,
    pub idle: String,
    /// What the gain is measured against: the channel's current model, or that model
    /// refitted on the rows where the driver is idle; `null` when the test was not made.
    pub against: Option<Against>,
    /// Rows, and runs with enough of them to count (ten), where the driver acts / is idle.
    pub active_rows: usize,
    pub idle_rows: usize,
    pub active_runs: usize,
    pub idle_runs: usize,
    /// The fall of the systematic held-out mean square error per row where the driver acts
    /// and where it is idle [N^2 or (N.m)^2].
    pub gain_per_row_active: f64,
    pub gain_per_row_idle: f64,
    /// The same split as the test weighs it: the mean over the runs that count of each run's
    /// fall of the mean square per row over the mean square of its load in kN [(N/kN)^2, or
    /// (N.m/kN)^2 for Mz], where the driver acts and where it is idle. The raw gains per row
    /// above can point the other way when a few runs at high load carry them.
    pub run_gain_active: f64,
    pub run_gain_idle: f64,
    /// The share of the gain on those rows (active and idle) that lies where the driver is
    /// idle; `null` when the two together do not gain.
    pub idle_share: Option<f64>,
    /// One-sided permutation p-value on this channel; `null`: not testable.
    pub p_value: Option<f64>,
    /// The effect's signature p-value, its claimed channels' combined, Holm-corrected over the
    /// round's effects (set when the round is judged).
    pub p_adjusted: Option<f64>,
    /// Why the signature cannot be tested here, when it cannot.
    pub not_testable: Option<String>,
    /// Whether the gain lies where the driver acts (set when the round is judged).
    pub shown: bool,
}

/// Per run and activity, the sums of squares of the current model's and the candidate's
/// systematic held-out residuals, their rows and the sum of the driver's levels.
#[derive(Debug, Default)]
pub(super) struct Cells(BTreeMap<(i64, Activity), Cell>);

/// One cell's sums.
#[derive(Debug, Default, Clone, Copy)]
struct Cell {
    before: f64,
    after: f64,
    rows: usize,
    level: f64,
    load_sq: f64,
    force_sq: f64,
}

impl Cell {
    /// The fall of the mean square per row over the mean square load.
    fn gain(&self) -> f64 {
        (self.before - self.after) / self.load_sq.max(f64::MIN_POSITIVE)
    }
}

impl Cells {
    /// Adds one row of `run` where the driver is `activity` at `level`, under load `fz`: the
    /// systematic residuals `before` and `after`.
    pub(super) fn add(
        &mut self,
        (run, activity, level): (i64, Activity, f64),
        (fz, force): (f64, f64),
        before: f64,
        after: f64,
    ) {
        if activity == Activity::Neither || !before.is_finite() || !after.is_finite() {
            return;
        }
        let c = self.0.entry((run, activity)).or_default();
        c.before += before * before;
        c.after += after * after;
        c.rows += 1;
        c.level += level;
        c.load_sq += fz * fz;
        c.force_sq += force * force;
    }
}

/// What a gain is measured against; in JSON, in words ([`Against::words`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Against {
    /// The channel's current model: every effect but those below.
    CurrentModel,
    /// That model refitted per fold on the training rows where the driver is idle: an effect
    /// whose base is fitted first where its driver is idle.
    IdleFit,
}

impl Serialize for Against {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.words())
    }
}

impl Against {
    /// In words, as JSON gives it.
    pub fn words(self) -> &'static str {
        match self {
            Against::CurrentModel => "the channel's current model",
            Against::IdleFit => {
                "the channel's current model refitted per fold on the rows where the driver is \
                 idle"
            }
        }
    }
}

/// The signature test of a candidate from its `cells` on `signature`'s rows, its gain
/// measured `against` that model.
pub(super) fn test(signature: &Signature, cells: &Cells, against: Against) -> SignatureTest {
    let kept: Vec<(Activity, Cell)> = cells
        .0
        .iter()
        .filter(|(_, c)| c.rows >= CELL_ROWS_MIN)
        .map(|((_, a), c)| (*a, *c))
        .collect();
    let count = |want: Activity| kept.iter().filter(|(a, _)| *a == want).count();
    let (active_runs, idle_runs) = (count(Activity::Active), count(Activity::Idle));
    // Gain summed over the rows of every cell, kept or not.
    let gain = |want: Activity| -> (f64, usize) {
        cells
            .0
            .iter()
            .filter(|((_, a), _)| *a == want)
            .fold((0.0, 0), |(g, n), (_, c)| {
                (g + c.before - c.after, n + c.rows)
            })
    };
    let ((gain_active, active_rows), (gain_idle, idle_rows)) =
        (gain(Activity::Active), gain(Activity::Idle));
    let not_testable = match (active_runs < CELLS_MIN, idle_runs < CELLS_MIN) {
        (false, false) => None,
        (a, _) => Some(format!(
            "the driver {} on the rows of {} run(s) only (of at least {CELL_ROWS_MIN} rows each; \
             the test needs {CELLS_MIN}): where it acts ({}) {active_runs} runs, where it is idle \
             ({}) {idle_runs} runs",
            if a { "acts" } else { "is idle" },
            if a { active_runs } else { idle_runs },
            signature.active,
            signature.idle,
        )),
    };
    let total = gain_active + gain_idle;
    let run_gain = |want: Activity| {
        let (sum, n) = kept
            .iter()
            .filter(|(a, _)| *a == want)
            .fold((0.0, 0), |(g, n), (_, c)| (g + c.gain(), n + 1));
        sum / f64::from(n.max(1))
    };
    SignatureTest {
        driver: signature.driver.clone(),
        active: signature.active.clone(),
        idle: signature.idle.clone(),
        against: Some(against),
        active_rows,
        idle_rows,
        active_runs,
        idle_runs,
        gain_per_row_active: gain_active / active_rows.max(1) as f64,
        gain_per_row_idle: gain_idle / idle_rows.max(1) as f64,
        run_gain_active: run_gain(Activity::Active),
        run_gain_idle: run_gain(Activity::Idle),
        idle_share: (total > 0.0).then(|| (gain_idle / total).clamp(0.0, 1.0)),
        p_value: not_testable.is_none().then(|| p_value(signature, &kept)),
        p_adjusted: None,
        not_testable,
        shown: false,
    }
}

/// The one-sided p-value of the signature over the `kept` cells, as the module says: whether
/// the active cells gain more per row over the load's mean square than the idle ones, and for
/// a driver with a range of levels also whether the shares of their error the cells' gains
/// take rise with their levels, the smaller p-value of the two doubled.
fn p_value(signature: &Signature, kept: &[(Activity, Cell)]) -> f64 {
    let (acts, gains): (Vec<f64>, Vec<f64>) = kept
        .iter()
        .filter(|(a, _)| *a != Activity::Between)
        .map(|(a, c)| (f64::from(*a == Activity::Active), c.gain()))
        .unzip();
    let by_activity = permutation_trend(&acts, &gains);
    match signature.level {
        Some(_) => {
            let (levels, shares) = levels_and_shares(kept);
            let by_level = permutation_trend(&levels, &shares);
            (2.0 * by_activity.min(by_level)).min(1.0)
        }
        None => by_activity,
    }
}

/// The ranks of the `kept` cells' mean levels and of the shares of their error the candidate
/// takes.
fn levels_and_shares(kept: &[(Activity, Cell)]) -> (Vec<f64>, Vec<f64>) {
    let levels: Vec<f64> = kept.iter().map(|(_, c)| c.level / c.rows as f64).collect();
    let mean_square = |c: &Cell| (c.before / c.rows as f64, c.after / c.rows as f64);
    let typical = kept
        .iter()
        .map(|(_, c)| mean_square(c).0 + mean_square(c).1)
        .sum::<f64>()
        / (2 * kept.len().max(1)) as f64;
    let shares: Vec<f64> = kept
        .iter()
        .map(|(_, c)| {
            let (b, a) = mean_square(c);
            (b - a) / (b + a + typical).max(f64::MIN_POSITIVE)
        })
        .collect();
    (ranks(&levels), ranks(&shares))
}

/// A test that could not be made: the signature itself cannot be drawn (`why`).
pub(super) fn untestable(why: String) -> SignatureTest {
    SignatureTest {
        driver: String::new(),
        active: String::new(),
        idle: String::new(),
        against: None,
        active_rows: 0,
        idle_rows: 0,
        active_runs: 0,
        idle_runs: 0,
        gain_per_row_active: 0.0,
        gain_per_row_idle: 0.0,
        run_gain_active: 0.0,
        run_gain_idle: 0.0,
        idle_share: None,
        p_value: None,
        p_adjusted: None,
        not_testable: Some(why),
        shown: false,
    }
}

impl SignatureTest {
    /// Whether the gain on this channel points to the driver: tested, and the test's own
    /// statistic on the driver's side (its one-sided p-value below one half: the cells' gains,
    /// as the test weighs them, larger or rising where the driver acts). Not the raw gain per
    /// row, which one run of large misfit carries. Whether that is more than chance is judged
    /// for the effect, over the channels it is claimed on.
    pub fn points_to_driver(&self) -> bool {
        self.p_value.is_some_and(|p| p < 0.5)
    }

    /// Why a channel that passed every other rule is not claimed for its signature, in words:
    /// its gain lies where its driver is idle ("absorbs misfit of another cause": per row, and
    /// as the test weighs it), or it does not clearly favour the rows where the driver acts, or
    /// it cannot be tested.
    pub fn refusal(&self, significance: f64) -> String {
        if let Some(why) = &self.not_testable {
            return format!("its signature cannot be tested: {why}");
        }
        let where_idle = format!(
            "{:.3e} a row where its driver is idle ({}, {} rows) against {:.3e} where it acts \
             ({}, {} rows)",
            self.gain_per_row_idle,
            self.idle,
            self.idle_rows,
            self.gain_per_row_active,
            self.active,
            self.active_rows
        );
        if self.gain_per_row_idle >= self.gain_per_row_active && !self.points_to_driver() {
            let share = self
                .idle_share
                .map_or(String::new(), |s| format!("{:.0} % of ", 100.0 * s));
            return format!(
                "absorbs misfit of another cause: {share}its gain lies where its driver is idle, \
                 {where_idle}"
            );
        }
        match (self.points_to_driver(), self.p_adjusted) {
            (true, Some(p)) => format!(
                "its gain does not lie clearly where its driver acts (the effect's signature \
                 p={p:.2e}, needs < {significance}): {where_idle}"
            ),
            _ => format!(
                "its gain does not lie where its driver acts (p={:.2e} on this channel): \
                 {where_idle}",
                self.p_value.unwrap_or(1.0)
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A signature over `runs` runs of 40 rows: the first 20 rows of each idle, the rest active.
    fn half_and_half(runs: usize) -> Signature {
        let rows = (0..runs * 40)
            .map(|i| match i % 40 < 20 {
                true => Activity::Idle,
                false => Activity::Active,
            })
            .collect();
        Signature {
            driver: "d".into(),
            active: "a".into(),
            idle: "i".into(),
            rows,
            level: None,
        }
    }

    /// Cells whose rows fall from `before` to `after_idle` where idle and `after_active`
    /// where active, with a run-to-run wobble.
    fn cells(s: &Signature, after_idle: f64, after_active: f64) -> Cells {
        let mut c = Cells::default();
        for (i, a) in s.rows.iter().enumerate() {
            let run = (i / 40) as i64;
            let wobble = 1.0 + 0.05 * ((run * 7) % 5) as f64;
            let after = if *a == Activity::Idle {
                after_idle
            } else {
                after_active
            };
            c.add((run, *a, 0.0), (1.0, 1.0), 10.0 * wobble, after * wobble);
        }
        c
    }

    #[test]
    fn a_gain_where_the_driver_acts_shows_the_signature() {
        let s = half_and_half(8);
        let t = test(&s, &cells(&s, 9.5, 3.0), Against::CurrentModel);
        assert_eq!((t.active_runs, t.idle_runs), (8, 8));
        assert_eq!((t.active_rows, t.idle_rows), (160, 160));
        assert!(t.p_value.unwrap() < 0.01, "{t:?}");
        assert!(t.gain_per_row_active > t.gain_per_row_idle);
        // (100 - 90.25) / (100 - 90.25 + 100 - 9) of the gain on the idle rows, before wobble.
        assert!(t.idle_share.unwrap() < 0.15, "{t:?}");
    }

    #[test]
    fn what_a_gain_is_measured_against_reads_in_words_in_json() {
        let s = half_and_half(4);
        let t = test(&s, &cells(&s, 9.5, 3.0), Against::IdleFit);
        let json = serde_json::to_value(&t).unwrap();
        assert_eq!(
            json["against"],
            "the channel's current model refitted per fold on the rows where the driver is idle"
        );
        let json = serde_json::to_value(untestable(String::new())).unwrap();
        assert!(json["against"].is_null(), "{json}");
    }

    #[test]
    fn a_gain_where_the_driver_is_idle_absorbs_misfit_of_another_cause() {
        let s = half_and_half(8);
        let t = test(&s, &cells(&s, 3.0, 9.5), Against::CurrentModel);
        assert!(t.p_value.unwrap() > 0.5, "{t:?}");
        let why = t.refusal(0.05);
        assert!(
            why.starts_with("absorbs misfit of another cause: 9"),
            "{why}"
        );
        // An even gain does not show it either.
        let t = test(&s, &cells(&s, 5.0, 5.0), Against::CurrentModel);
        assert!(t.p_value.unwrap() > 0.05, "{t:?}");
    }

    #[test]
    fn a_level_driver_shows_by_its_gain_per_row_when_the_shares_do_not_rise() {
        // Per run, 20 idle rows at level 1 under a load of 10, 20 between at level 5 under 3,
        // 20 active at level 10 under 1. Everywhere the candidate takes the same share of an
        // error of the same size in newtons: the shares do not rise with the level, while the
        // gain per row over the load's mean square is 100 times larger where the driver acts
        // than where it is idle.
        let runs = 8;
        let activity = |k: usize| [Activity::Idle, Activity::Between, Activity::Active][k / 20];
        let level = |k: usize| [1.0, 5.0, 10.0][k / 20];
        let rows = (0..runs * 60).map(|i| activity(i % 60)).collect();
        let levels = (0..runs * 60).map(|i| level(i % 60) as f32).collect();
        let s = Signature {
            driver: "d".into(),
            active: "a".into(),
            idle: "i".into(),
            rows,
            level: Some(levels),
        };
        let mut c = Cells::default();
        for (i, a) in s.rows.iter().enumerate() {
            let run = (i / 60) as i64;
            let wobble = 1.0 + 0.05 * ((run * 7) % 5) as f64;
            let load = match a {
                Activity::Idle => 10.0,
                Activity::Between => 3.0,
                _ => 1.0,
            };
            let row = (run, *a, level(i % 60));
            c.add(row, (load, 1.0), 30.0 * wobble, 21.2 * wobble);
        }
        let t = test(&s, &c, Against::CurrentModel);
        let kept: Vec<(Activity, Cell)> = c.0.iter().map(|((_, a), c)| (*a, *c)).collect();
        let (levels, shares) = levels_and_shares(&kept);
        let by_level = permutation_trend(&levels, &shares);
        assert!(by_level > 0.05, "{by_level}");
        let per_load = |a: Activity| kept.iter().find(|(x, _)| *x == a).unwrap().1.gain();
        assert!(
            (per_load(Activity::Active) / per_load(Activity::Idle) - 100.0).abs() < 1e-9,
            "{t:?}"
        );
        let p = t.p_value.unwrap();
        assert!(p < 0.01, "{t:?}");
        assert!(
            p >= 2.0 * 1.0 / 20_001.0,
            "the smaller p-value counts twice: {p}"
        );
    }

    #[test]
    fn too_few_runs_on_one_side_cannot_be_tested() {
        let s = half_and_half(1);
        let t = test(&s, &cells(&s, 9.5, 3.0), Against::CurrentModel);
        assert_eq!(t.p_value, None);
        let why = t.not_testable.unwrap();
        assert!(
            why.starts_with("the driver acts on the rows of 1 run(s) only"),
            "{why}"
        );
    }
}
