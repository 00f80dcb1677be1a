//! Slip-ratio shift: the Fx curve moved along the slip ratio, by an amount that may grow with
//! the load, as the later Magic Formulas' horizontal shift SHx. A rig whose slip ratio is
//! computed with a radius other than the tire's effective rolling radius reads slip at free
//! rolling, and force at what it reads as zero slip.
//!
//! It moves the curve sideways, not up: a force offset at every slip is rolling resistance's
//! (`q1 Fz`), so the two never absorb the same constant. They differ where the curve is flat:
//! beyond the peak a shift moves the force little, an offset as much as at zero slip.

use mf87::Channel;

use super::{
    Effect, Extension, Quantity, RowDriver, RunDriver, slip_near_zero, where_slip_near_zero,
};
use crate::method::channel_data::ChannelData;

pub struct SlipRatioShift;

/// The slip ratio counts as near zero below this [percent]: the linear range of Fx, where a
/// shift moves the force most (the peak lies at 10-15 %).
const NEAR_ZERO_SLIP: f64 = 3.0;

impl Effect for SlipRatioShift {
    fn kind(&self) -> Extension {
        Extension::SlipRatioShift
    }

    fn form(&self) -> &'static str {
        "Fx(kappa + Sh + Sh_per_kN Fz): the slip ratio shifted, by an amount linear in load"
    }

    fn needs(&self, _channel: Channel) -> &'static [Quantity] {
        &[]
    }

    fn starting_values(&self) -> &'static [f64] {
        &[0.0, 0.0]
    }

    /// The linear range around zero slip, free rolling included.
    fn home_rows(&self, data: &ChannelData) -> Option<Vec<bool>> {
        where_slip_near_zero(data, NEAR_ZERO_SLIP)
    }

    /// The shift moves the force through the slip stiffness, which grows with the load, and
    /// may itself change with it.
    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver> {
        Some(RunDriver::median("median load [kN]", data.fz_kn.clone()))
    }

    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String> {
        Ok(RowDriver {
            axis: format!("slip ratio sigma [%], rows with |sigma| < {NEAR_ZERO_SLIP} %"),
            x: slip_near_zero(data, NEAR_ZERO_SLIP),
            range: Some((-NEAR_ZERO_SLIP, NEAR_ZERO_SLIP)),
        })
    }
}
