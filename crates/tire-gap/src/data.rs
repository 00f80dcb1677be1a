//! Measured tire data in one set of internal units, whatever the file said.
//!
//! Internal units: time s, speed m/s, load N, angles rad, slip ratio 1, pressure kPa,
//! temperature degC, forces N, moment N.m. Conversion from file units happens in
//! [`crate::io::units`] only.

use std::sync::Arc;

use serde::Serialize;

/// A quantity a column can carry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Test block id (integer).
    Run,
    /// Time within the run \[s\].
    Time,
    /// Forward speed [m/s].
    Speed,
    /// Vertical load \[N\].
    Fz,
    /// Slip angle \[rad\].
    Alpha,
    /// Longitudinal slip ratio \[1\].
    Kappa,
    /// Camber angle \[rad\].
    Gamma,
    /// Inflation pressure \[kPa\].
    Pressure,
    /// Tread temperature \[degC\].
    Temperature,
    /// Measured longitudinal force \[N\].
    Fx,
    /// Measured lateral force \[N\].
    Fy,
    /// Measured aligning moment [N.m].
    Mz,
}

impl Quantity {
    pub const ALL: [Quantity; 12] = [
        Quantity::Run,
        Quantity::Time,
        Quantity::Speed,
        Quantity::Fz,
        Quantity::Alpha,
        Quantity::Kappa,
        Quantity::Gamma,
        Quantity::Pressure,
        Quantity::Temperature,
        Quantity::Fx,
        Quantity::Fy,
        Quantity::Mz,
    ];

    /// Short name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Run => "run",
            Quantity::Time => "time",
            Quantity::Speed => "speed",
            Quantity::Fz => "Fz",
            Quantity::Alpha => "alpha",
            Quantity::Kappa => "kappa",
            Quantity::Gamma => "gamma",
            Quantity::Pressure => "pressure",
            Quantity::Temperature => "temperature",
            Quantity::Fx => "Fx",
            Quantity::Fy => "Fy",
            Quantity::Mz => "Mz",
        }
    }

    /// Whether a value (internal units) is one a tire test can give; the message names the
    /// value in readable units and the range. The bounds catch unit mistakes and corrupt
    /// samples, not unusual tests.
    pub fn plausible(self, v: f64) -> Result<(), String> {
        let right_angle = std::f64::consts::FRAC_PI_2;
        let (ok, range) = match self {
            Quantity::Speed => ((0.0..=150.0).contains(&v), "0..150 m/s"),
            Quantity::Fz => (
                (-1_000.0..=100_000.0).contains(&v),
                "-1 kN..100 kN (load is positive in compression)",
            ),
            Quantity::Alpha | Quantity::Gamma => (v.abs() <= right_angle, "-90..90 deg"),
            Quantity::Kappa => (v.abs() <= 10.0, "-10..10"),
            Quantity::Pressure => (v > 0.0 && v <= 2_000.0, "above 0 and up to 2000 kPa"),
            Quantity::Temperature => ((-60.0..=300.0).contains(&v), "-60..300 degC"),
            Quantity::Run | Quantity::Time | Quantity::Fx | Quantity::Fy | Quantity::Mz => {
                (v.is_finite(), "finite")
            }
        };
        if ok {
            return Ok(());
        }
        let shown = match self {
            Quantity::Alpha | Quantity::Gamma => {
                format!("{:.3} deg", mf87::units::radians_to_degrees(v))
            }
            Quantity::Kappa => format!("{v}"),
            _ => format!("{v} {}", self.unit()),
        };
        Err(format!(
            "{} = {shown} is outside the plausible range {range}",
            self.name()
        ))
    }

    /// How closely a rig holds a set point of the condition (internal units): a spread of
    /// levels within it is the rig's wander, not a condition the test varies. `None` for what
    /// is not a set condition.
    pub fn held_within(self) -> Option<f64> {
        Some(match self {
            Quantity::Fz => 100.0,
            Quantity::Gamma => mf87::units::degrees_to_radians(0.25),
            Quantity::Speed => 0.5,
            Quantity::Pressure => 5.0,
            Quantity::Temperature => 2.0,
            _ => return None,
        })
    }

    /// The internal unit.
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::Run => "",
            Quantity::Time => "s",
            Quantity::Speed => "m/s",
            Quantity::Fz | Quantity::Fx | Quantity::Fy => "N",
            Quantity::Alpha | Quantity::Gamma => "rad",
            Quantity::Kappa => "1",
            Quantity::Pressure => "kPa",
            Quantity::Temperature => "degC",
            Quantity::Mz => "N.m",
        }
    }
}

/// One measured data set: columns of equal length in internal units. Optional columns are
/// `None` when the file did not have them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Dataset {
    /// Where the data came from (file name), for messages and provenance.
    pub source: String,
    pub run: RunColumn,
    pub time: Option<Column>,
    pub speed: Option<Column>,
    pub fz: Column,
    pub alpha: Option<Column>,
    pub kappa: Option<Column>,
    pub gamma: Option<Column>,
    pub pressure: Option<Column>,
    pub temperature: Option<Column>,
    pub fx: Option<Column>,
    pub fy: Option<Column>,
    pub mz: Option<Column>,
}

/// A column of one quantity over the rows. Shared, not copied, by what reads it (the channels
/// of a diagnosis hold the same columns as the data set).
pub type Column = Arc<[f64]>;
/// The run id of every row.
pub type RunColumn = Arc<[i64]>;

impl Dataset {
    pub fn len(&self) -> usize {
        self.fz.len()
    }

    pub fn is_empty(&self) -> bool {
        self.fz.is_empty()
    }

    /// A real-valued column, if present (`Run` is not real-valued: use `run`).
    pub fn column(&self, q: Quantity) -> Option<&[f64]> {
        match q {
            Quantity::Fz => Some(&self.fz),
            _ => self.column_field(q)?.as_deref(),
        }
    }

    /// A real-valued column, if present, shared rather than copied.
    pub fn column_shared(&self, q: Quantity) -> Option<Column> {
        match q {
            Quantity::Fz => Some(self.fz.clone()),
            _ => self.column_field(q)?.clone(),
        }
    }

    /// The field of an optional real-valued column (`None` for `Run` and `Fz`).
    fn column_field(&self, q: Quantity) -> Option<&Option<Column>> {
        Some(match q {
            Quantity::Run | Quantity::Fz => return None,
            Quantity::Time => &self.time,
            Quantity::Speed => &self.speed,
            Quantity::Alpha => &self.alpha,
            Quantity::Kappa => &self.kappa,
            Quantity::Gamma => &self.gamma,
            Quantity::Pressure => &self.pressure,
            Quantity::Temperature => &self.temperature,
            Quantity::Fx => &self.fx,
            Quantity::Fy => &self.fy,
            Quantity::Mz => &self.mz,
        })
    }

    /// Mutable slot of a real-valued column (`Run` has none).
    pub fn column_slot(&mut self, q: Quantity) -> Option<&mut Option<Column>> {
        match q {
            Quantity::Run | Quantity::Fz => None,
            Quantity::Time => Some(&mut self.time),
            Quantity::Speed => Some(&mut self.speed),
            Quantity::Alpha => Some(&mut self.alpha),
            Quantity::Kappa => Some(&mut self.kappa),
            Quantity::Gamma => Some(&mut self.gamma),
            Quantity::Pressure => Some(&mut self.pressure),
            Quantity::Temperature => Some(&mut self.temperature),
            Quantity::Fx => Some(&mut self.fx),
            Quantity::Fy => Some(&mut self.fy),
            Quantity::Mz => Some(&mut self.mz),
        }
    }

    /// Whether a quantity is present.
    pub fn has(&self, q: Quantity) -> bool {
        q == Quantity::Run || self.column(q).is_some()
    }

    /// The rows at positions `keep`, in that order.
    pub fn select(&self, keep: &[usize]) -> Dataset {
        let pick = |v: &[f64]| keep.iter().map(|&i| v[i]).collect::<Column>();
        let pick_opt = |v: &Option<Column>| v.as_deref().map(pick);
        Dataset {
            source: self.source.clone(),
            run: keep.iter().map(|&i| self.run[i]).collect(),
            time: pick_opt(&self.time),
            speed: pick_opt(&self.speed),
            fz: pick(&self.fz),
            alpha: pick_opt(&self.alpha),
            kappa: pick_opt(&self.kappa),
            gamma: pick_opt(&self.gamma),
            pressure: pick_opt(&self.pressure),
            temperature: pick_opt(&self.temperature),
            fx: pick_opt(&self.fx),
            fy: pick_opt(&self.fy),
            mz: pick_opt(&self.mz),
        }
    }

    /// The distinct run ids in order of first appearance.
    pub fn runs(&self) -> Vec<i64> {
        runs_of(&self.run)
    }
}

/// The run ids of `run` (a run id per row), each once, in order of first appearance.
pub fn runs_of(run: &[i64]) -> Vec<i64> {
    let mut seen = Vec::new();
    let mut known = std::collections::HashSet::new();
    let mut last = None;
    for &r in run {
        // A run's rows mostly follow each other: its id is looked up once per stretch.
        if last != Some(r) && known.insert(r) {
            seen.push(r);
        }
        last = Some(r);
    }
    seen
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plausible_values() {
        assert!(Quantity::Alpha.plausible(1.5).is_ok());
        assert_eq!(
            Quantity::Alpha.plausible(1.6).unwrap_err(),
            "alpha = 91.673 deg is outside the plausible range -90..90 deg"
        );
        assert!(Quantity::Kappa.plausible(-1.0).is_ok());
        assert!(Quantity::Kappa.plausible(10.5).is_err());
        assert!(Quantity::Fz.plausible(-999.0).is_ok());
        assert!(Quantity::Fz.plausible(-1001.0).is_err());
        assert!(Quantity::Fz.plausible(100_001.0).is_err());
        assert!(Quantity::Pressure.plausible(0.0).is_err());
        assert!(Quantity::Pressure.plausible(2001.0).is_err());
        assert!(Quantity::Temperature.plausible(-61.0).is_err());
        assert!(Quantity::Temperature.plausible(301.0).is_err());
        assert!(Quantity::Speed.plausible(-0.1).is_err());
        assert!(Quantity::Speed.plausible(151.0).is_err());
        assert!(Quantity::Fy.plausible(1e9).is_ok());
        assert!(Quantity::Fy.plausible(f64::NAN).is_err());
    }

    #[test]
    fn runs_in_order_of_first_appearance() {
        let ds = Dataset {
            run: vec![3, 3, 1, 1, 3, 2, 2, 1].into(),
            ..Dataset::default()
        };
        assert_eq!(ds.runs(), [3, 1, 2]);
        assert!(Dataset::default().runs().is_empty());
    }
}
