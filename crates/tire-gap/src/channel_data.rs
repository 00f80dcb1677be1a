//! One channel's measured rows, converted once to the formula's units: what the fits, the
//! candidate effects' drivers and the figures read.

use mf87::{Channel, units};

use crate::data::{Dataset, Quantity};

/// Camber beyond this [deg] somewhere in the data: the camber coefficients are fitted.
pub const CAMBER_VARIES_DEG: f64 = 0.05;

/// One channel's measured rows, converted once to the formula's units.
#[derive(Debug, Clone)]
pub struct ChannelData {
    pub channel: Channel,
    pub run: Vec<i64>,
    /// Load [kN].
    pub fz_kn: Vec<f64>,
    /// Slip in the formula's units: alpha [deg] for Fy and Mz, sigma [percent] for Fx.
    pub slip: Vec<f64>,
    /// Camber [deg] (zeros when not measured).
    pub gamma_deg: Vec<f64>,
    /// Measured force [N] or moment [N.m].
    pub measured: Vec<f64>,
    /// The other slip, where measured: slip ratio for Fy and Mz, slip angle [rad] for Fx.
    pub other_slip: Option<Vec<f64>>,
    pub time: Option<Vec<f64>>,
    pub speed: Option<Vec<f64>>,
    pub pressure: Option<Vec<f64>>,
    pub temperature: Option<Vec<f64>>,
}

impl ChannelData {
    /// The channel's rows, or `None` when the measurement or its slip is missing.
    pub fn from_dataset(ds: &Dataset, channel: Channel) -> Option<ChannelData> {
        let (measured, slip, to_formula): (_, _, fn(f64) -> f64) = match channel {
            Channel::Fx => (
                ds.fx.as_ref()?,
                ds.kappa.as_ref()?,
                units::slip_ratio_to_percent,
            ),
            Channel::Fy => (
                ds.fy.as_ref()?,
                ds.alpha.as_ref()?,
                units::radians_to_degrees,
            ),
            Channel::Mz => (
                ds.mz.as_ref()?,
                ds.alpha.as_ref()?,
                units::radians_to_degrees,
            ),
        };
        let gamma = ds.column(Quantity::Gamma);
        Some(ChannelData {
            channel,
            run: ds.run.clone(),
            fz_kn: ds
                .fz
                .iter()
                .map(|f| units::newtons_to_kilonewtons(*f))
                .collect(),
            slip: slip.iter().map(|s| to_formula(*s)).collect(),
            gamma_deg: match (channel, gamma) {
                (Channel::Fx, _) | (_, None) => vec![0.0; ds.len()],
                (_, Some(g)) => g.iter().map(|g| units::radians_to_degrees(*g)).collect(),
            },
            measured: measured.clone(),
            other_slip: match channel {
                Channel::Fx => ds.alpha.clone(),
                Channel::Fy | Channel::Mz => ds.kappa.clone(),
            },
            time: ds.time.clone(),
            speed: ds.speed.clone(),
            pressure: ds.pressure.clone(),
            temperature: ds.temperature.clone(),
        })
    }

    pub fn len(&self) -> usize {
        self.measured.len()
    }

    pub fn is_empty(&self) -> bool {
        self.measured.is_empty()
    }

    /// The subset at positions `keep` (positions into this channel's rows).
    pub fn subset(&self, keep: &[usize]) -> ChannelData {
        let pick = |v: &[f64]| keep.iter().map(|&i| v[i]).collect();
        let pick_opt = |v: &Option<Vec<f64>>| v.as_deref().map(pick);
        ChannelData {
            channel: self.channel,
            run: keep.iter().map(|&i| self.run[i]).collect(),
            fz_kn: pick(&self.fz_kn),
            slip: pick(&self.slip),
            gamma_deg: pick(&self.gamma_deg),
            measured: pick(&self.measured),
            other_slip: pick_opt(&self.other_slip),
            time: pick_opt(&self.time),
            speed: pick_opt(&self.speed),
            pressure: pick_opt(&self.pressure),
            temperature: pick_opt(&self.temperature),
        }
    }

    /// The slip rate within runs [slip units per s], by central differences over the rows of
    /// a run in file order; 0 where a row has no neighbour in its run or time does not advance.
    /// `None` without time.
    pub fn slip_rate(&self) -> Option<Vec<f64>> {
        let t = self.time.as_ref()?;
        let n = self.len();
        let same = |a: usize, b: usize| self.run[a] == self.run[b];
        Some(
            (0..n)
                .map(|i| {
                    let lo = if i > 0 && same(i - 1, i) { i - 1 } else { i };
                    let hi = if i + 1 < n && same(i + 1, i) {
                        i + 1
                    } else {
                        i
                    };
                    let dt = t[hi] - t[lo];
                    if hi > lo && dt > 0.0 {
                        (self.slip[hi] - self.slip[lo]) / dt
                    } else {
                        0.0
                    }
                })
                .collect(),
        )
    }

    /// Whether camber varies in these rows (else the camber coefficients are not identifiable).
    pub fn has_camber(&self) -> bool {
        self.gamma_deg.iter().any(|g| g.abs() > CAMBER_VARIES_DEG)
    }
}
