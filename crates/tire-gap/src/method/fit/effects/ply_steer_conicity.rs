//! Ply steer and conicity: force and moment offsets at zero slip and camber.

use mf87::Channel;

use super::{
    Effect, Extension, Identifies, Quantity, RowDriver, RunDriver, slip_near_zero,
    where_slip_near_zero,
};
use super::{Form, Signature, near_zero_signature};
use crate::method::prepare::channel_data::ChannelData;

pub struct PlySteerConicity;

/// The slip counts as near zero below this [deg, or percent for Fx].
const NEAR_ZERO_SLIP: f64 = 2.0;

impl Effect for PlySteerConicity {
    fn kind(&self) -> Extension {
        Extension::PlySteerConicity
    }

    fn form(&self) -> &'static str {
        "horizontal and vertical shifts at zero slip, with their load terms and the load term \
         of the camber shift"
    }

    fn needs(&self, _channel: Channel) -> &'static [Quantity] {
        &[]
    }

    /// Sh_deg, Sv, Sh_per_kN, Sv_per_kN, Sh_camber_per_kN.
    fn starting_values(&self) -> &'static [f64] {
        &[0.0, 0.0, 0.0, 0.0, 0.0]
    }

    /// The load terms where the data hold the load; the camber shift's where they hold the
    /// load or the camber.
    fn held(&self, _channel: Channel, identifies: Identifies) -> Vec<usize> {
        match (identifies.load, identifies.camber) {
            (false, _) => vec![2, 3, 4],
            (true, false) => vec![4],
            (true, true) => Vec::new(),
        }
    }

    /// Offsets at zero slip: the linear range.
    fn home_rows(&self, data: &ChannelData) -> Option<Vec<bool>> {
        where_slip_near_zero(data, NEAR_ZERO_SLIP)
    }

    /// Active near zero slip, idle at twice that slip and beyond, where a slip-angle shift
    /// moves the force little.
    fn signature(&self, data: &ChannelData, _form: &Form) -> Result<Signature, String> {
        Ok(near_zero_signature(data, NEAR_ZERO_SLIP))
    }

    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver> {
        Some(RunDriver::median("median load [kN]", data.fz_kn.clone()))
    }

    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String> {
        Ok(RowDriver {
            axis: match data.channel {
                Channel::Fx => {
                    format!("slip ratio sigma [%], rows with |sigma| < {NEAR_ZERO_SLIP} %")
                }
                Channel::Fy | Channel::Mz => {
                    format!("slip angle alpha [deg], rows with |alpha| < {NEAR_ZERO_SLIP} deg")
                }
            },
            x: slip_near_zero(data, NEAR_ZERO_SLIP),
            range: Some((-NEAR_ZERO_SLIP, NEAR_ZERO_SLIP)),
        })
    }
}
