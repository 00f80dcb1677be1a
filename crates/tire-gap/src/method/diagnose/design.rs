//! The test design: how the driving conditions of a programme move together across its runs.
//!
//! When two conditions rise and fall together from run to run (pressure with tread
//! temperature as the tire warms, speed with load, ...), no fit can tell their effects apart:
//! whichever wins, the other would explain the same runs. This is read from the design alone,
//! before and whatever the fits say: the correlation across runs of the runs' median levels.
//! The run order is one of the conditions, so a drift over the programme (wear, a rig
//! warming up) that follows a condition is named too.

use std::collections::HashMap;

use mf87::{Channel, units};
use serde::Serialize;

use crate::data::{Dataset, Quantity};
use crate::method::fit::effects::{self, Extension, Identifies};
use crate::method::prepare::channel_data::{ChannelData, run_stretches};
use crate::method::stats::correlation;
use crate::quantiles::{median, quantile};

/// At or above this absolute correlation of two conditions' run levels, their effects cannot
/// be told apart (they share more than 80 % of their variance across runs).
pub const CONFOUNDED_CORRELATION: f64 = 0.9;
/// Fewest runs at which a correlation of run levels means something.
pub const MIN_DESIGN_RUNS: usize = 6;

/// A driving condition of the design.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Condition {
    Load,
    Camber,
    Speed,
    Pressure,
    Temperature,
    /// The position of a run in the programme (order of first appearance in the input).
    RunOrder,
}

impl Condition {
    const ALL: [Condition; 6] = [
        Condition::Load,
        Condition::Camber,
        Condition::Speed,
        Condition::Pressure,
        Condition::Temperature,
        Condition::RunOrder,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Condition::Load => "load",
            Condition::Camber => "camber",
            Condition::Speed => "speed",
            Condition::Pressure => "pressure",
            Condition::Temperature => "temperature",
            Condition::RunOrder => "run order",
        }
    }

    fn quantity(self) -> Option<Quantity> {
        match self {
            Condition::Load => Some(Quantity::Fz),
            Condition::Camber => Some(Quantity::Gamma),
            Condition::Speed => Some(Quantity::Speed),
            Condition::Pressure => Some(Quantity::Pressure),
            Condition::Temperature => Some(Quantity::Temperature),
            Condition::RunOrder => None,
        }
    }

    /// The smallest spread of run levels that counts as varying the condition (a rig holds
    /// a set point to about this), internal units.
    fn held_within(self) -> f64 {
        self.quantity()
            .and_then(Quantity::held_within)
            .unwrap_or(0.0)
    }

    /// What a change of the condition acts through, in the model or its candidates.
    fn acts_through(self) -> String {
        match self {
            Condition::Load => "the load dependence of the 1987 model's coefficients".into(),
            Condition::Camber => "the camber terms of the 1987 model".into(),
            Condition::RunOrder => "a drift over the programme (wear, rig or tire warm-up)".into(),
            c => {
                let names: Vec<&str> = driven_by(c).iter().map(|e| e.name()).collect();
                format!("an effect of {} ({})", c.name(), names.join(", "))
            }
        }
    }
}

/// An effect of a condition is tested only when the spread of the runs' levels of it, from
/// the 10th to the 90th percentile over runs, is at least this many times the set-point
/// tolerance (`Condition::held_within`): 2 m/s of speed, 20 kPa of pressure, 8 degC of tread
/// temperature. Less cannot be told from a constant: a rig holding one set point wanders by
/// about the tolerance, and an effect fitted on that spread extrapolates from nothing (e.g. a
/// speed term fitted on 11.1 to 11.2 m/s). The percentiles ask for a tenth of the runs at
/// each end, so one odd run does not make a condition identifiable.
pub const IDENTIFIABLE_SPREAD_FACTOR: f64 = 4.0;

/// Whether and how much a condition varies across the runs, for the identifiability rule.
#[derive(Debug, Clone, PartialEq)]
pub struct Spread {
    pub condition: Condition,
    /// Runs with a level of the condition.
    pub runs: usize,
    /// 10th and 90th percentile of the run levels (internal units).
    pub p10: f64,
    pub p90: f64,
    /// The spread an effect of it needs.
    pub needed: f64,
    /// Runs whose level lies in the middle half of the spread (between its quarters).
    pub middle_runs: usize,
}

/// A curvature in a condition (a quadratic term) is fitted only when at least this many runs,
/// and a tenth of them, lie in the middle half of its spread: two levels fix a line, and one
/// odd run between them is not a third level.
pub const MIN_MIDDLE_RUNS: usize = 2;

impl Spread {
    /// Whether an effect of the condition can be told from a constant.
    pub fn identifiable(&self) -> bool {
        self.p90 - self.p10 >= self.needed
    }

    /// Whether a curvature of an effect in the condition can be told from a line: the
    /// condition is identifiable and the runs take a middle level too ([`MIN_MIDDLE_RUNS`]).
    pub fn curvature_identifiable(&self) -> bool {
        self.identifiable() && self.middle_runs >= MIN_MIDDLE_RUNS.max(self.runs.div_ceil(10))
    }

    /// Why an effect of the condition cannot be tested, in words (units of the report).
    pub fn reason(&self) -> String {
        let (unit, scale) = match self.condition {
            Condition::Camber => ("deg", units::radians_to_degrees(1.0)),
            c => (c.quantity().map_or("", Quantity::unit), 1.0),
        };
        format!(
            "{} barely varies across the runs: the runs' levels span {:.1} to {:.1} {unit} \
             (10th to 90th percentile over {} runs), and an effect of it needs a spread of at \
             least {:.1} {unit} to be told from a constant",
            self.condition.name(),
            self.p10 * scale,
            self.p90 * scale,
            self.runs,
            self.needed * scale
        )
    }
}

/// The spread of a condition's run levels (`None` without its column).
pub fn spread(ds: &Dataset, c: Condition) -> Option<Spread> {
    spread_of(&ds.run, ds.column(c.quantity()?)?, c)
}

/// The spread of the run levels of `col`, the column of condition `c`, over the runs `run`.
pub fn spread_of(run: &[i64], col: &[f64], c: Condition) -> Option<Spread> {
    spread_by(run, |i| col[i], c)
}

/// [`spread_of`] the column whose value at row `i` is `value(i)` (a column converted as it is
/// read, without a copy of it).
pub fn spread_by(run: &[i64], value: impl Fn(usize) -> f64, c: Condition) -> Option<Spread> {
    let levels = column_run_levels(run, value, &run_order(run))?;
    let (p10, p90) = (quantile(&levels, 0.1)?, quantile(&levels, 0.9)?);
    let quarter = (p90 - p10) / 4.0;
    let middle_runs = levels
        .iter()
        .filter(|&&l| p10 + quarter <= l && l <= p90 - quarter)
        .count();
    Some(Spread {
        condition: c,
        runs: levels.len(),
        p10,
        p90,
        needed: IDENTIFIABLE_SPREAD_FACTOR * c.held_within(),
        middle_runs,
    })
}

/// What the channel data `data` vary across their runs of the conditions an effect's terms
/// depend on: a term of a condition held still is not identified.
pub fn identifies(data: &ChannelData) -> Identifies {
    let identifiable = |value: &dyn Fn(usize) -> f64, c| {
        spread_by(&data.run, value, c).is_some_and(|s| s.identifiable())
    };
    let speed =
        (data.speed.as_ref()).and_then(|v| spread_by(&data.run, |i| v[i], Condition::Speed));
    Identifies {
        load: identifiable(
            &|i| units::kilonewtons_to_newtons(data.fz_kn[i]),
            Condition::Load,
        ),
        camber: identifiable(
            &|i| units::degrees_to_radians(data.gamma_deg[i]),
            Condition::Camber,
        ),
        speed: speed.as_ref().is_some_and(Spread::identifiable),
        speed_curvature: speed.as_ref().is_some_and(Spread::curvature_identifiable),
    }
}

/// The condition whose column is `q`, if it is one.
pub fn condition_of(q: Quantity) -> Option<Condition> {
    Condition::ALL.into_iter().find(|c| c.quantity() == Some(q))
}

/// The candidate effects a condition drives: those whose size its column sets on some channel
/// (see [`effects::Effect::driving_conditions`]).
pub fn driven_by(c: Condition) -> Vec<Extension> {
    let Some(q) = c.quantity() else {
        return Vec::new();
    };
    if matches!(c, Condition::Load | Condition::Camber) {
        return Vec::new();
    }
    Extension::ALL
        .into_iter()
        .filter(|&e| {
            Channel::ALL
                .into_iter()
                .any(|ch| e.applies_to(ch) && effects::of(e).driving_conditions(ch).contains(&q))
        })
        .collect()
}

/// Two conditions the design moves together.
#[derive(Debug, Clone, Serialize)]
pub struct DesignConfounding {
    pub conditions: [Condition; 2],
    /// Pearson correlation of their run levels (run medians) across runs.
    pub run_correlation: f64,
    pub runs: usize,
    /// The candidate effects each condition drives.
    pub effects: [Vec<Extension>; 2],
    /// Of those, the ones the diagnosis selected.
    pub selected: Vec<Extension>,
    /// What the data cannot tell apart, in words.
    pub cannot_tell_apart: String,
    /// The experiment that would separate them.
    pub separating_experiment: String,
}

/// The run levels of a condition: the median of each run, runs in order of first appearance.
fn run_levels(ds: &Dataset, order: &HashMap<i64, usize>, c: Condition) -> Option<Vec<f64>> {
    if c == Condition::RunOrder {
        return Some((0..order.len()).map(|k| k as f64).collect());
    }
    let col = ds.column(c.quantity()?)?;
    column_run_levels(&ds.run, |i| col[i], order)
}

/// The median of the column whose value at row `i` is `value(i)` in each run of `run`, runs
/// in `order`; `None` when a run has no finite value. Each run's values are gathered in turn
/// from its stretches of rows, so at most one run's values are held at a time.
fn column_run_levels(
    run: &[i64],
    value: impl Fn(usize) -> f64,
    order: &HashMap<i64, usize>,
) -> Option<Vec<f64>> {
    let mut stretches: Vec<Vec<std::ops::Range<usize>>> = vec![Vec::new(); order.len()];
    for (id, rows) in run_stretches(run) {
        stretches[order[&id]] = rows;
    }
    let mut values = Vec::new();
    stretches
        .iter()
        .map(|rows| {
            values.clear();
            values.extend(rows.iter().flat_map(|r| r.clone()).map(&value));
            median(&values)
        })
        .collect()
}

/// Each run's position in order of first appearance.
pub fn run_order(run: &[i64]) -> HashMap<i64, usize> {
    crate::data::runs_of(run)
        .into_iter()
        .enumerate()
        .map(|(k, r)| (r, k))
        .collect()
}

/// The pairs of conditions whose run levels correlate at [`CONFOUNDED_CORRELATION`] or more,
/// among the conditions the programme varies; none below [`MIN_DESIGN_RUNS`] runs.
pub fn confounded_conditions(ds: &Dataset) -> Vec<DesignConfounding> {
    let order = run_order(&ds.run);
    let runs = order.len();
    if runs < MIN_DESIGN_RUNS {
        return Vec::new();
    }
    let varied: Vec<(Condition, Vec<f64>)> = Condition::ALL
        .into_iter()
        .filter_map(|c| {
            let levels = run_levels(ds, &order, c)?;
            let (lo, hi) = levels
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(*x), hi.max(*x))
                });
            (hi - lo > c.held_within()).then_some((c, levels))
        })
        .collect();
    let mut found = Vec::new();
    for (i, (a, la)) in varied.iter().enumerate() {
        for (b, lb) in &varied[i + 1..] {
            let Some(r) = correlation(la, lb) else {
                continue;
            };
            if r.abs() < CONFOUNDED_CORRELATION {
                continue;
            }
            found.push(DesignConfounding {
                conditions: [*a, *b],
                run_correlation: r,
                runs,
                effects: [driven_by(*a), driven_by(*b)],
                selected: Vec::new(),
                cannot_tell_apart: format!("{} from {}", a.acts_through(), b.acts_through()),
                separating_experiment: separating_experiment(*a, *b),
            });
        }
    }
    found
}

/// `found` with the driven effects the diagnosis selected (its `verdict`) marked.
pub fn with_selected(
    mut found: Vec<DesignConfounding>,
    verdict: &[Extension],
) -> Vec<DesignConfounding> {
    for c in &mut found {
        c.selected = c
            .effects
            .iter()
            .flatten()
            .copied()
            .filter(|e| verdict.contains(e))
            .collect();
    }
    found
}

/// Runs that vary one condition with the other held, for each pair.
fn separating_experiment(a: Condition, b: Condition) -> String {
    use Condition::*;
    match (a, b) {
        (Pressure, Temperature) => {
            "sweeps at two or more pressures with the tread at one temperature (pressure set \
             cold, tread pre-conditioned), and at one pressure at two or more tread \
             temperatures"
                .into()
        }
        (Speed, Temperature) => {
            "sweeps at two or more speeds with the tread held at one temperature, and at one \
             speed at two or more tread temperatures"
                .into()
        }
        (x, RunOrder) => format!(
            "runs that repeat one {} level early, midway and late in the programme (a \
             reference run repeated), and {} levels in shuffled order",
            x.name(),
            x.name()
        ),
        _ => format!(
            "runs that vary {} with {} held constant, and {} with {} held constant \
             (a crossed design: every {} level at every {} level)",
            a.name(),
            b.name(),
            b.name(),
            a.name(),
            a.name(),
            b.name()
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Six rows per run; per run the given pressure and temperature levels.
    fn programme(levels: &[(f64, f64)]) -> Dataset {
        let mut ds = Dataset::default();
        let (mut p, mut t) = (Vec::new(), Vec::new());
        let (mut run, mut fz) = (Vec::new(), Vec::new());
        for (k, (pk, tk)) in levels.iter().enumerate() {
            for i in 0..6 {
                run.push(k as i64 + 10);
                fz.push(4000.0 + 10.0 * i as f64);
                p.push(pk + 0.1 * i as f64);
                t.push(tk - 0.1 * i as f64);
            }
        }
        (ds.run, ds.fz) = (run.into(), fz.into());
        ds.pressure = Some(p.into());
        ds.temperature = Some(t.into());
        ds
    }

    #[test]
    fn pressure_following_temperature_is_named_with_its_correlation() {
        // Pressure rises with temperature as the tire warms (gas law, from 200 kPa at 20 C).
        let levels: Vec<(f64, f64)> = [20.0, 70.0, 35.0, 90.0, 50.0, 60.0, 25.0, 80.0]
            .iter()
            .map(|&t| (200.0 * (273.15 + t) / 293.15, t))
            .collect();
        let found = with_selected(
            confounded_conditions(&programme(&levels)),
            &[Extension::Temperature],
        );
        assert_eq!(found.len(), 1, "{found:?}");
        let c = &found[0];
        assert_eq!(c.conditions, [Condition::Pressure, Condition::Temperature]);
        assert!(c.run_correlation > 0.999, "{}", c.run_correlation);
        assert_eq!(c.runs, 8);
        assert_eq!(c.effects[0], vec![Extension::InflationPressure]);
        assert_eq!(c.effects[1], vec![Extension::Temperature]);
        assert_eq!(c.selected, vec![Extension::Temperature]);
        assert!(c.cannot_tell_apart.contains("inflation_pressure"));
        assert!(c.separating_experiment.contains("one temperature"));
    }

    #[test]
    fn independent_conditions_and_held_ones_are_not_named() {
        // Pressure independent of temperature (a Latin square of levels).
        let levels = [
            (180.0, 60.0),
            (300.0, 40.0),
            (240.0, 90.0),
            (200.0, 20.0),
            (260.0, 80.0),
            (220.0, 30.0),
            (280.0, 50.0),
            (190.0, 70.0),
        ];
        assert!(confounded_conditions(&programme(&levels)).is_empty());
        // Pressure held (spread below the set-point tolerance), temperature rising with the
        // run order: the drift pair is named, the held pressure is not.
        let levels: Vec<(f64, f64)> = (0..8)
            .map(|k| (220.0 + 0.3 * (k % 2) as f64, 20.0 + 8.0 * k as f64))
            .collect();
        let found = confounded_conditions(&programme(&levels));
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(
            found[0].conditions,
            [Condition::Temperature, Condition::RunOrder]
        );
        assert!(found[0].cannot_tell_apart.contains("drift"));
    }

    #[test]
    fn run_levels_gather_a_run_that_comes_back() {
        let run = [5, 5, 3, 3, 3, 5, 7];
        let col = [1.0, 2.0, 10.0, 20.0, 30.0, 9.0, -4.0];
        let order = run_order(&run);
        assert_eq!(order, HashMap::from([(5, 0), (3, 1), (7, 2)]));
        assert_eq!(
            column_run_levels(&run, |i| col[i], &order),
            Some(vec![2.0, 20.0, -4.0])
        );
    }

    #[test]
    fn too_few_runs_judge_nothing() {
        let levels: Vec<(f64, f64)> = (0..5)
            .map(|k| (200.0 + 10.0 * k as f64, 20.0 + 10.0 * k as f64))
            .collect();
        assert!(confounded_conditions(&programme(&levels)).is_empty());
    }

    /// The spread of speed over runs of five rows each at the given levels.
    fn speed_spread(speeds: &[f64]) -> Spread {
        let run: Vec<i64> = (0..speeds.len() as i64 * 5).map(|i| i / 5).collect();
        let col: Vec<f64> = run.iter().map(|&r| speeds[r as usize]).collect();
        spread_of(&run, &col, Condition::Speed).unwrap()
    }

    #[test]
    fn a_condition_is_identifiable_only_when_its_run_levels_spread_enough() {
        let levels = speed_spread;
        // 40.0 to 40.4 km/h over 20 runs, as on a real constant-speed programme.
        let held: Vec<f64> = (0..20).map(|k| (40.0 + 0.02 * k as f64) / 3.6).collect();
        let s = levels(&held);
        assert!(!s.identifiable());
        assert_eq!(s.needed, 2.0);
        let why = s.reason();
        assert!(
            why.contains("speed barely varies") && why.contains("2.0 m/s"),
            "{why}"
        );
        // Two speeds, half the runs each: identifiable.
        let two: Vec<f64> = (0..20)
            .map(|k| if k % 2 == 0 { 10.0 } else { 20.0 })
            .collect();
        assert!(levels(&two).identifiable());
        // One odd run among 20 does not make it so (10th to 90th percentile).
        let mut odd = held.clone();
        odd[7] = 25.0;
        assert!(!levels(&odd).identifiable());
        // Pressure needs 20 kPa, temperature 8 degC.
        let run: Vec<i64> = (0..40).map(|i| i / 4).collect();
        // Ten runs 3 kPa apart: the 10th to 90th percentile spans 21.6 kPa; 2 kPa apart, 14.4.
        let p: Vec<f64> = run.iter().map(|&r| 200.0 + 3.0 * r as f64).collect();
        assert!(
            spread_of(&run, &p, Condition::Pressure)
                .unwrap()
                .identifiable()
        );
        let p: Vec<f64> = run.iter().map(|&r| 200.0 + 2.0 * r as f64).collect();
        assert!(
            !spread_of(&run, &p, Condition::Pressure)
                .unwrap()
                .identifiable()
        );
    }

    #[test]
    fn a_curvature_needs_runs_at_a_middle_level() {
        let spread = speed_spread;
        let cycle = |levels: &[f64], runs: usize| -> Vec<f64> {
            (0..runs).map(|k| levels[k % levels.len()]).collect()
        };
        // Two speeds: a line, no curvature.
        let two = spread(&cycle(&[10.0, 30.0], 20));
        assert!(two.identifiable() && !two.curvature_identifiable());
        assert_eq!(two.middle_runs, 0);
        // Three speeds, a third of the runs each: 20 m/s lies in the middle half of 10..30.
        let three = spread(&cycle(&[10.0, 20.0, 30.0], 21));
        assert_eq!(three.middle_runs, 7);
        assert!(three.curvature_identifiable());
        // One run at a middle speed among 20 is not a level.
        let mut one = cycle(&[10.0, 30.0], 20);
        one[5] = 20.0;
        assert!(!spread(&one).curvature_identifiable());
        // Two among 40 are fewer than a tenth of the runs.
        let mut two_of_forty = cycle(&[10.0, 30.0], 40);
        (two_of_forty[5], two_of_forty[6]) = (20.0, 20.0);
        let s = spread(&two_of_forty);
        assert_eq!(s.middle_runs, 2);
        assert!(!s.curvature_identifiable());
        // A middle level needs the condition to vary at all.
        let held = spread(&cycle(&[11.0, 11.2, 11.4], 21));
        assert!(!held.identifiable() && !held.curvature_identifiable());
    }
}
