//! Where an effect's driver acts and where it is idle, per row: the signature a claim of the
//! effect must show. An effect that is really there gains most, per row, where its driver
//! acts (combined slip where both slips are away from zero, pressure off the nominal
//! pressure, ...); a candidate that only soaks up misfit of another cause gains as much or
//! more where its driver is idle, since the gain then comes from the refit of the base or from
//! extra freedom, not from the effect's form.

use serde::Serialize;

/// Whether a row's driver acts, is idle, lies between the two, or takes no part (not
/// measured, or where no effect of its kind can show).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Activity {
    Neither,
    Idle,
    Between,
    Active,
}

/// An effect's driver on one channel's rows: which rows it acts on and which it leaves idle.
#[derive(Debug, Clone)]
pub struct Signature {
    /// The driver, in words with its unit, e.g. "|slip angle| \[deg\]".
    pub driver: String,
    /// The rows where it acts, in words with their bound, e.g. "|slip angle| > 1.00 deg".
    pub active: String,
    /// The rows where it is idle, in words with their bound.
    pub idle: String,
    /// Per row of the channel's data.
    pub rows: Vec<Activity>,
    /// For a driver with a range of levels, how far it departs from where it is idle, per
    /// row (the test then asks the gain to rise with it over every row that takes part,
    /// those between idle and active too); `None` for a driver that acts or does not.
    pub level: Option<Vec<f32>>,
}

/// A driver measured as a departure from where it is idle, per row.
pub(super) struct Departure<'a> {
    /// Its name in the descriptions, e.g. "|p - 220.0 kPa|".
    pub name: String,
    /// Its unit, e.g. "kPa".
    pub unit: &'static str,
    /// Rows of the channel's data.
    pub rows: usize,
    /// The departure at a row; NaN where the row takes no part (e.g. the channel's own slip
    /// is near zero, so no effect on stiffness or peak can show).
    pub at: &'a dyn Fn(usize) -> f64,
}

impl Departure<'_> {
    /// Each row's activity: idle up to `idle_up_to`, active from `active_from`, `between`
    /// in between.
    fn classify(&self, idle_up_to: f64, active_from: f64, between: Activity) -> Vec<Activity> {
        (0..self.rows)
            .map(|i| {
                let d = (self.at)(i);
                if !d.is_finite() {
                    Activity::Neither
                } else if d <= idle_up_to {
                    Activity::Idle
                } else if d >= active_from {
                    Activity::Active
                } else {
                    between
                }
            })
            .collect()
    }

    /// Idle up to `idle_up_to`, active above `active_above` (a physical bound: the driver is
    /// zero where it is idle, as the other slip in pure slip).
    pub(super) fn bounds(&self, idle_up_to: f64, active_above: f64) -> Signature {
        let active_from = active_above.max(idle_up_to) * (1.0 + f64::EPSILON) + f64::MIN_POSITIVE;
        let rows = self.classify(idle_up_to, active_from, Activity::Neither);
        Signature {
            driver: format!("{} [{}]", self.name, self.unit),
            active: format!("{} > {} {}", self.name, fixed(active_above), self.unit),
            idle: format!("{} <= {} {}", self.name, fixed(idle_up_to), self.unit),
            rows,
            level: None,
        }
    }

    /// A driver that varies over a range of levels (a condition's departure from its nominal
    /// level, a slip's rate): idle where it departs by at most the larger of `tolerance` (what
    /// a rig holds a set point to) and its lower tercile, active from the larger of twice the
    /// tolerance and its upper tercile (order statistics of the rows' departures), strictly
    /// above the idle bound, the rows between them
    /// [`Activity::Between`], each row with its level. A driver that departs equally on every
    /// row (two pressures either side of the nominal one) has no idle rows or no active ones,
    /// and its signature cannot be tested.
    pub(super) fn spread(&self, tolerance: f64) -> Signature {
        let values = || (0..self.rows).map(|i| (self.at)(i));
        let n = values().filter(|v| v.is_finite()).count();
        // The terciles as order statistics (no value between two rows is a bound).
        let rank = |k: usize| {
            crate::quantiles::order_statistic_of(values, k.min(n.saturating_sub(1)))
                .unwrap_or(f64::NAN)
        };
        let idle_up_to = tolerance.max(rank(n.saturating_sub(1) / 3));
        let active_from = (2.0 * tolerance).max(rank((2 * n.saturating_sub(1)).div_ceil(3)));
        // At or above the upper tercile, but never a row that is idle.
        let rows = self.classify(idle_up_to, active_from, Activity::Between);
        let level = (0..self.rows).map(|i| (self.at)(i) as f32).collect();
        Signature {
            driver: format!("{} [{}]", self.name, self.unit),
            active: format!("{} >= {} {}", self.name, fixed(active_from), self.unit),
            idle: format!("{} <= {} {}", self.name, fixed(idle_up_to), self.unit),
            rows,
            level: Some(level),
        }
    }
}

/// A slip near zero: active where `|slip| < active_below` (the linear range, where a shift of
/// the curve moves the force most), idle where `|slip| >= idle_from` (beyond it). `name` and
/// `unit` describe the slip (the formula's units: deg, or percent for Fx).
pub(super) fn near_zero(
    slip: &[f64],
    name: &str,
    unit: &str,
    active_below: f64,
    idle_from: f64,
) -> Signature {
    let rows = slip
        .iter()
        .map(|s| match s.abs() {
            a if a < active_below => Activity::Active,
            a if a >= idle_from => Activity::Idle,
            _ => Activity::Neither,
        })
        .collect();
    Signature {
        driver: format!("{name} near zero [{unit}]"),
        active: format!("{name} < {} {unit}", fixed(active_below)),
        idle: format!("{name} >= {} {unit}", fixed(idle_from)),
        rows,
        level: None,
    }
}

/// A bound in the descriptions: as many decimals as a number of its size needs.
fn fixed(x: f64) -> String {
    match x.abs() {
        a if a >= 100.0 => format!("{x:.0}"),
        a if a >= 10.0 => format!("{x:.1}"),
        a if a >= 0.1 => format!("{x:.2}"),
        _ => format!("{x:.3}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spread_driver_is_idle_near_its_nominal_level_and_acts_far_from_it() {
        // Three pressure levels: 180, 220 (nominal), 260 kPa, a third of the rows each.
        let p: Vec<f64> = (0..300).map(|i| 180.0 + 40.0 * (i / 100) as f64).collect();
        let at = |i: usize| (p[i] - 220.0).abs();
        let d = Departure {
            name: "|p - 220.0 kPa|".into(),
            unit: "kPa",
            rows: p.len(),
            at: &at,
        };
        let s = d.spread(5.0);
        assert_eq!(s.level.as_ref().unwrap()[0], 40.0);
        assert!(s.rows[100..200].iter().all(|a| *a == Activity::Idle));
        assert!(s.rows[..100].iter().all(|a| *a == Activity::Active));
        assert!(s.rows[200..].iter().all(|a| *a == Activity::Active));
        assert_eq!(s.idle, "|p - 220.0 kPa| <= 5.00 kPa");
        assert_eq!(s.active, "|p - 220.0 kPa| >= 40.0 kPa");
        // Two levels either side of the nominal one: every row departs alike, none is active.
        let at = |_: usize| 20.0;
        let d = Departure { at: &at, ..d };
        let s = d.spread(5.0);
        assert!(s.rows.iter().all(|a| *a == Activity::Idle));
    }

    #[test]
    fn a_continuous_driver_splits_at_its_terciles_and_rows_without_it_take_no_part() {
        let at = |i: usize| {
            if i.is_multiple_of(10) {
                f64::NAN
            } else {
                i as f64
            }
        };
        let d = Departure {
            name: "|T - 0 degC|".into(),
            unit: "degC",
            rows: 100,
            at: &at,
        };
        let s = d.spread(2.0);
        let count = |a: Activity| s.rows.iter().filter(|r| **r == a).count();
        assert_eq!(s.rows[0], Activity::Neither);
        assert_eq!(s.rows[10], Activity::Neither);
        // 90 rows with a value: a third idle, a third active.
        assert_eq!(count(Activity::Idle), 30);
        assert_eq!(count(Activity::Active), 30);
        assert_eq!(count(Activity::Between), 30);
        assert!(s.rows[1] == Activity::Idle && s.rows[99] == Activity::Active);
    }

    #[test]
    fn bounds_and_near_zero_classify_by_the_bounds_they_name() {
        let other = [0.0, 0.004, 0.01, 0.015, 0.03];
        let at = |i: usize| other[i];
        let d = Departure {
            name: "|slip ratio|".into(),
            unit: "-",
            rows: other.len(),
            at: &at,
        };
        let s = d.bounds(0.005, 0.02);
        use Activity::*;
        assert_eq!(s.rows, [Idle, Idle, Neither, Neither, Active]);
        assert_eq!(s.active, "|slip ratio| > 0.020 -");
        let s = near_zero(
            &[-0.5, 1.9, 2.0, 5.0, -6.0],
            "|slip angle|",
            "deg",
            2.0,
            5.0,
        );
        assert_eq!(s.rows, [Active, Active, Neither, Idle, Idle]);
        assert_eq!(s.idle, "|slip angle| >= 5.00 deg");
    }
}
