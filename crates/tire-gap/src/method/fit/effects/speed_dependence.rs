//! Speed dependence: the peak friction changes with the forward speed.

use mf87::Channel;

use super::{
    Effect, Extension, Identifies, Quantity, RowDriver, RunDriver, column, where_slip_acts,
};
use super::{Form, Signature, by_form};
use crate::method::prepare::channel_data::ChannelData;

pub struct SpeedDependence;

impl Effect for SpeedDependence {
    fn kind(&self) -> Extension {
        Extension::SpeedDependence
    }

    fn form(&self) -> &'static str {
        "peak friction (1 + v dV + w dV^2), dV = (V - V0) / V0; w where runs also take a \
         middle speed"
    }

    fn needs(&self, _channel: Channel) -> &'static [Quantity] {
        &[Quantity::Speed]
    }

    /// v, w.
    fn starting_values(&self) -> &'static [f64] {
        &[0.0, 0.0]
    }

    /// The curvature w where the runs' speeds fix only a line.
    fn held(&self, _channel: Channel, identifies: Identifies) -> Vec<usize> {
        if identifies.speed_curvature {
            Vec::new()
        } else {
            vec![1]
        }
    }

    fn separating_test(&self, other: Extension) -> Option<&'static str> {
        (other == Extension::Temperature).then_some(
            "repeat sweeps at two speeds with the tread held at one temperature (pre-conditioned), \
             and at one speed at two tread temperatures",
        )
    }

    fn home_rows(&self, data: &ChannelData) -> Option<Vec<bool>> {
        where_slip_acts(data)
    }

    /// Active where the fitted form moves peak and stiffness far from their mean, idle where
    /// it moves them little, where the slip acts.
    fn signature(&self, data: &ChannelData, form: &Form) -> Result<Signature, String> {
        by_form(self.kind(), data, form, (("speed", "m/s"), &data.speed))
    }

    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver> {
        speed_run_driver(data)
    }

    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String> {
        speed_row_driver(data)
    }
}

/// The forward speed, per run: what drives the speed-dependent effects.
pub(super) fn speed_run_driver(data: &ChannelData) -> Option<RunDriver> {
    Some(RunDriver::median("median speed [m/s]", data.speed.clone()?))
}

/// The forward speed, per row.
pub(super) fn speed_row_driver(data: &ChannelData) -> Result<RowDriver, String> {
    Ok(RowDriver {
        axis: "forward speed V [m/s]".into(),
        x: column(&data.speed, "speed")?,
        range: None,
    })
}
