//! Inflation pressure: stiffness and peak change with the pressure.

use mf87::Channel;

use super::{
    Effect, Extension, Identifies, Quantity, RowDriver, RunDriver, column, where_slip_acts,
};
use super::{Form, Signature, by_form};
use crate::method::prepare::channel_data::ChannelData;

pub struct InflationPressure;

impl Effect for InflationPressure {
    fn kind(&self) -> Extension {
        Extension::InflationPressure
    }

    fn form(&self) -> &'static str {
        "MF 6.1's terms: stiffness (1 + (k + k_per_kN Fz) dp + k2 dp^2) and peak \
         (1 + d dp + d2 dp^2), dp = (p - p0) / p0"
    }

    fn needs(&self, _channel: Channel) -> &'static [Quantity] {
        &[Quantity::Pressure]
    }

    /// k, d, k2, d2, k_per_kN.
    fn starting_values(&self) -> &'static [f64] {
        &[0.0, 0.0, 0.0, 0.0, 0.0]
    }

    /// The terms MF 6.1 gives each channel: on Fx the quadratic terms of stiffness and
    /// peak (ppx1..4) without a load interaction, on Fy a linear stiffness with its load
    /// interaction (ppy1, ppy2) and a quadratic peak (ppy3, ppy4), on Mz linear terms (ppz1);
    /// the load interaction also where the data hold the load.
    fn held(&self, channel: Channel, identifies: Identifies) -> Vec<usize> {
        let (k2, d2, k_per_kn) = (2, 3, 4);
        let mut held = match channel {
            Channel::Fx => vec![k_per_kn],
            Channel::Fy => vec![k2],
            Channel::Mz => vec![k2, d2, k_per_kn],
        };
        if !identifies.load && !held.contains(&k_per_kn) {
            held.push(k_per_kn);
        }
        held
    }

    fn separating_test(&self, other: Extension) -> Option<&'static str> {
        (other == Extension::Temperature).then_some(
            "sweeps at two pressures with the tread at one temperature (cold pressure set, \
             temperature logged)",
        )
    }

    fn home_rows(&self, data: &ChannelData) -> Option<Vec<bool>> {
        where_slip_acts(data)
    }

    /// Active where the fitted form moves peak and stiffness far from their mean, idle where
    /// it moves them little, where the slip acts.
    fn signature(&self, data: &ChannelData, form: &Form) -> Result<Signature, String> {
        by_form(
            self.kind(),
            data,
            form,
            (("pressure", "kPa"), &data.pressure),
        )
    }

    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver> {
        Some(RunDriver::median(
            "median pressure [kPa]",
            data.pressure.clone()?,
        ))
    }

    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String> {
        Ok(RowDriver {
            axis: "inflation pressure p [kPa]".into(),
            x: column(&data.pressure, "pressure")?,
            range: None,
        })
    }
}
