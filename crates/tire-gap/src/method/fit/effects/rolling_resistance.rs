//! Rolling resistance: a force against rolling that grows with load and speed.

use mf87::Channel;

use super::speed_dependence::{speed_row_driver, speed_run_driver};
use super::{Departure, Form, Signature, column, where_slip_near_zero};
use super::{Effect, Extension, Quantity, RowDriver, RunDriver};
use crate::method::prepare::channel_data::ChannelData;

/// The slip ratio below which a row rolls freely \[%\].
const FREE_ROLLING: f64 = 1.0;

pub struct RollingResistance;

impl Effect for RollingResistance {
    fn kind(&self) -> Extension {
        Extension::RollingResistance
    }

    fn form(&self) -> &'static str {
        "Fx - (q1 + q2 V / V0) Fz"
    }

    fn needs(&self, _channel: Channel) -> &'static [Quantity] {
        &[Quantity::Speed]
    }

    fn starting_values(&self) -> &'static [f64] {
        &[0.0, 0.0]
    }

    /// Force against rolling at zero slip: |sigma| < 1 %.
    fn separating_test(&self, other: Extension) -> Option<&'static str> {
        match other {
            Extension::SpeedDependence | Extension::Temperature => {
                Some("free-rolling runs (zero slip) at several speeds and temperatures")
            }
            Extension::SlipRatioShift => Some(
                "free-rolling runs at several speeds (rolling resistance grows with speed, the \
                 shifts of the Fx curve do not), with the effective rolling radius measured \
                 (distance per wheel revolution) and used for the slip ratio, so that free \
                 rolling reads zero slip",
            ),
            _ => None,
        }
    }

    fn home_rows(&self, data: &ChannelData) -> Option<Vec<bool>> {
        where_slip_near_zero(data, FREE_ROLLING)
    }

    /// Active at the highest speeds, idle at the lowest, on the free-rolling rows: the force
    /// grows with speed, which sets it apart from a force offset of any other cause (its
    /// constant part, `q1 Fz`, is a vertical shift like any other, and a shift of the
    /// slip-ratio curve makes the same offset at free rolling), and the base model has none of
    /// it at any speed, so its gain per row rises with the speed itself, not with a departure
    /// from the nominal one. Free rolling, where the force is all there is of Fx, keeps the
    /// rows compared alike: a plan that sweeps the slip ratio at its lower speeds only would
    /// otherwise set the base refit's gains in those sweeps against the cornering runs.
    fn signature(&self, data: &ChannelData, _form: &Form) -> Result<Signature, String> {
        let v = column(&data.speed, "speed")?;
        let rolling = where_slip_near_zero(data, FREE_ROLLING).unwrap_or_default();
        let at = |i: usize| if rolling[i] { v[i].abs() } else { f64::NAN };
        let departure = Departure {
            name: "|speed|".into(),
            unit: "m/s",
            rows: data.len(),
            at: &at,
        };
        let mut s = departure.spread(Quantity::Speed.held_within().unwrap_or(0.0));
        s.level = None;
        let rolling = format!(" at free rolling (|slip ratio| < {FREE_ROLLING} %)");
        s.active.push_str(&rolling);
        s.idle.push_str(&rolling);
        Ok(s)
    }

    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver> {
        speed_run_driver(data)
    }

    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String> {
        speed_row_driver(data)
    }
}
