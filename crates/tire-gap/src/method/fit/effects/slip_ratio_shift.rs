//! Slip-ratio shift: the Fx curve moved along the slip ratio and in force, by amounts that may
//! grow with the load, as the later Magic Formulas' horizontal and vertical shifts SHx and SVx.
//! A rig whose slip ratio is computed with a radius other than the tire's effective rolling
//! radius reads slip at free rolling, and force at what it reads as zero slip; a tire whose
//! drive and brake peaks differ has its curve moved up or down, and along the slip ratio back
//! through free rolling.
//!
//! The horizontal shift moves the curve sideways: beyond the peak, where the curve is flat, it
//! moves the force little. The vertical shift moves it by a share of the load at every slip,
//! as rolling resistance's `q1 Fz` does; rolling resistance alone grows with speed. Where the
//! runs' speeds spread enough to test that growth, the vertical shift is held at 0 and the
//! force offset is left to rolling resistance; at one speed the two cannot be told apart and
//! the shift takes it.

use mf87::Channel;

use super::{Effect, Extension, Identifies, Quantity, RowDriver, RunDriver, slip_near_zero};
use super::{Form, Signature, near_zero_signature};
use crate::method::prepare::channel_data::ChannelData;

pub struct SlipRatioShift;

/// The slip ratio counts as near zero below this [percent]: the linear range of Fx, where a
/// shift moves the force most (the peak lies at 10-15 %).
const NEAR_ZERO_SLIP: f64 = 3.0;

impl Effect for SlipRatioShift {
    fn kind(&self) -> Extension {
        Extension::SlipRatioShift
    }

    fn form(&self) -> &'static str {
        "Fx(kappa + Sh + Sh_per_kN Fz) + (Sv + Sv_per_kN Fz) Fz: the curve shifted along the \
         slip ratio and in force, by amounts linear in load"
    }

    fn needs(&self, _channel: Channel) -> &'static [Quantity] {
        &[]
    }

    fn starting_values(&self) -> &'static [f64] {
        &[0.0, 0.0, 0.0, 0.0]
    }

    /// The vertical shift (Sv, Sv_per_kN) where the runs' speeds spread: see the module doc.
    fn held(&self, _channel: Channel, identifies: Identifies) -> Vec<usize> {
        if identifies.speed {
            vec![2, 3]
        } else {
            Vec::new()
        }
    }

    /// Every row: the horizontal shift shows most in the linear range around zero slip, the
    /// vertical one at every slip, most where the drive and brake peaks differ.
    fn home_rows(&self, _data: &ChannelData) -> Option<Vec<bool>> {
        None
    }

    /// Active near zero slip ratio, idle at twice that slip and beyond, where the curve is
    /// flatter and a shift along the slip moves the force little.
    fn signature(&self, data: &ChannelData, _form: &Form) -> Result<Signature, String> {
        Ok(near_zero_signature(data, NEAR_ZERO_SLIP))
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
