//! Tread temperature: peak friction has an optimum temperature, stiffness changes with it.

use mf87::Channel;

use super::{Effect, Extension, Quantity, RowDriver, RunDriver, column, where_slip_acts};
use super::{Form, Signature, by_form};
use crate::method::prepare::channel_data::ChannelData;

pub struct Temperature;

impl Effect for Temperature {
    fn kind(&self) -> Extension {
        Extension::Temperature
    }

    fn form(&self) -> &'static str {
        "peak (1 - w q / (1 + q)), q = ((T - Topt) / 50)^2, stiffness (1 + k (T - T0) / 50)"
    }

    fn needs(&self, _channel: Channel) -> &'static [Quantity] {
        &[Quantity::Temperature]
    }

    fn starting_values(&self) -> &'static [f64] {
        &[0.0, 0.0, 0.0]
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
            (("temperature", "degC"), &data.temperature),
        )
    }

    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver> {
        Some(RunDriver::median(
            "median temperature [degC]",
            data.temperature.clone()?,
        ))
    }

    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String> {
        Ok(RowDriver {
            axis: "tread temperature T [degC]".into(),
            x: column(&data.temperature, "temperature")?,
            range: None,
        })
    }
}
