//! Longitudinal shifts: the Fx curve moved along the slip ratio and along the force, as the
//! later Magic Formulas' SHx and SVx have it. A rig whose slip ratio is computed with a radius
//! other than the effective rolling radius reads slip at free rolling; a load cell with
//! crosstalk reads force at zero slip.
//!
//! Its force offset `Sv Fz` is the same term as rolling resistance's `q1 Fz`: on a channel
//! that has both, only their sum is determined. Forward selection adds one effect at a time,
//! each first fitted alone against the current model, so the one added second starts where
//! the first left the shared constant and gains only through what it has of its own: a slip
//! offset (`Sh`) here, a speed trend (`q2`) there. See `separating_test` for the experiment.

use mf87::Channel;

use super::{Effect, Extension, Quantity, RowDriver, RunDriver};
use crate::channel_data::ChannelData;

pub struct LongitudinalShifts;

/// The slip ratio counts as near zero below this [percent]: the linear range of Fx, where a
/// slip offset moves the force most (the peak lies at 10-15 %).
const NEAR_ZERO_SLIP: f64 = 3.0;

impl Effect for LongitudinalShifts {
    fn kind(&self) -> Extension {
        Extension::LongitudinalShifts
    }

    fn form(&self) -> &'static str {
        "Fx(kappa + Sh) + Sv Fz: offsets of the slip ratio and of the force"
    }

    fn needs(&self, _channel: Channel) -> &'static [Quantity] {
        &[]
    }

    fn starting_values(&self) -> &'static [f64] {
        &[0.0, 0.0]
    }

    /// The linear range around zero slip, free rolling included.
    fn home_rows(&self, data: &ChannelData) -> Option<Vec<bool>> {
        Some(data.slip.iter().map(|s| s.abs() < NEAR_ZERO_SLIP).collect())
    }

    /// The offsets grow with the load (the force offset is a share of it, the slip offset
    /// acts through the slip stiffness).
    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver> {
        Some(RunDriver::median("median load [kN]", data.fz_kn.clone()))
    }

    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String> {
        Ok(RowDriver {
            axis: format!("slip ratio sigma [%], rows with |sigma| < {NEAR_ZERO_SLIP} %"),
            x: data
                .slip
                .iter()
                .map(|&s| {
                    if s.abs() < NEAR_ZERO_SLIP {
                        s
                    } else {
                        f64::NAN
                    }
                })
                .collect(),
            range: Some((-NEAR_ZERO_SLIP, NEAR_ZERO_SLIP)),
        })
    }
}
