//! Relaxation length: the slip acts with a first-order lag over the distance travelled.

use mf87::Channel;

use super::{Departure, Form, Signature, column};
use super::{Effect, Extension, Quantity, RowDriver, RunDriver, where_slip_acts};
use crate::method::prepare::channel_data::ChannelData;

pub struct RelaxationLength;

/// The slip's rate of change is taken over this many rows either side (within the run): the
/// sensor noise of one sample step would swamp it.
const RATE_HALF_WINDOW: usize = 5;
/// Below this change per metre [deg or percent], a lag of up to a metre moves the slip by less
/// than 0.02 deg (0.02 %), below what a slip channel resolves: the driver is idle.
const SLOW_RATE_PER_M: f64 = 0.02;

impl Effect for RelaxationLength {
    fn kind(&self) -> Extension {
        Extension::RelaxationLength
    }

    fn form(&self) -> &'static str {
        "first-order lag of the slip over travelled distance with relaxation length sigma"
    }

    fn needs(&self, _channel: Channel) -> &'static [Quantity] {
        &[Quantity::Time, Quantity::Speed]
    }

    fn starting_values(&self) -> &'static [f64] {
        &[0.3]
    }

    /// The fitted length may go negative; the model uses its magnitude [m].
    fn magnitudes(&self) -> &'static [usize] {
        &[0]
    }

    fn separating_test(&self, other: Extension) -> Option<&'static str> {
        match other {
            Extension::SpeedDependence => Some(
                "steady-state slip sweeps (slow enough for the lag to vanish) at several speeds, \
                 and sinusoidal slip at one speed and several frequencies",
            ),
            Extension::CombinedSlip => {
                Some("quasi-static combined-slip sweeps, and transient pure-slip steps")
            }
            _ => None,
        }
    }

    /// None: speed only turns time into the distance travelled.
    fn driving_conditions(&self, _channel: Channel) -> &'static [Quantity] {
        &[]
    }

    fn home_rows(&self, data: &ChannelData) -> Option<Vec<bool>> {
        where_slip_acts(data)
    }

    /// Active where the slip changes fast per metre travelled, idle where it changes slowly
    /// (the lag's error grows with the slip's change over a relaxation length).
    fn signature(&self, data: &ChannelData, _form: &Form) -> Result<Signature, String> {
        let t = column(&data.time, "time")?;
        let v = column(&data.speed, "speed")?;
        let n = data.len();
        let same = |a: usize, b: usize| data.run[a] == data.run[b];
        let at = |i: usize| {
            let (mut lo, mut hi) = (
                i.saturating_sub(RATE_HALF_WINDOW),
                (i + RATE_HALF_WINDOW).min(n - 1),
            );
            while !same(lo, i) {
                lo += 1;
            }
            while !same(hi, i) {
                hi -= 1;
            }
            let metres = (t[hi] - t[lo]) * v[i].abs();
            match hi > lo && metres > 0.0 {
                true => ((data.slip[hi] - data.slip[lo]) / metres).abs(),
                false => f64::NAN,
            }
        };
        let unit = match data.channel {
            Channel::Fx => "%/m",
            Channel::Fy | Channel::Mz => "deg/m",
        };
        let departure = Departure {
            name: "|slip change per metre|".into(),
            unit,
            rows: n,
            at: &at,
        };
        Ok(departure.spread(SLOW_RATE_PER_M))
    }

    /// Slip change per metre travelled: what the lag acts on.
    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver> {
        let v = data.speed.as_ref()?;
        let rate = data
            .slip_rate()?
            .iter()
            .zip(v.iter())
            .map(|(r, v)| if v.abs() > 0.0 { (r / v).abs() } else { 0.0 })
            .collect();
        Some(RunDriver {
            name: "largest slip change per metre travelled",
            values: rate,
            largest: true,
            floor: f64::NEG_INFINITY,
        })
    }

    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String> {
        Ok(RowDriver {
            axis: match data.channel {
                Channel::Fx => "slip rate d sigma/dt [%/s]",
                Channel::Fy | Channel::Mz => "slip rate d alpha/dt [deg/s]",
            }
            .into(),
            x: data.slip_rate().ok_or("no time column")?.into(),
            range: None,
        })
    }
}
