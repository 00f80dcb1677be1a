//! Camber on the peak: the peak force falls with the square of the camber.

use mf87::Channel;

use super::{Effect, Extension, Identifies, Quantity, RowDriver, RunDriver, where_slip_acts};
use super::{Form, Signature, by_form};
use crate::method::prepare::channel_data::ChannelData;

pub struct CamberPeak;

impl Effect for CamberPeak {
    fn kind(&self) -> Extension {
        Extension::CamberPeak
    }

    fn form(&self) -> &'static str {
        "peak (1 - d gamma^2), gamma [rad]"
    }

    fn needs(&self, _channel: Channel) -> &'static [Quantity] {
        &[Quantity::Gamma]
    }

    fn starting_values(&self) -> &'static [f64] {
        &[0.0]
    }

    /// Its one term, where the data hold the camber still.
    fn held(&self, _channel: Channel, identifies: Identifies) -> Vec<usize> {
        if identifies.camber {
            Vec::new()
        } else {
            vec![0]
        }
    }

    /// The peak shows where the slip is beyond the linear range.
    fn home_rows(&self, data: &ChannelData) -> Option<Vec<bool>> {
        where_slip_acts(data)
    }

    /// Active where the fitted form moves the peak far from its mean (large camber, the peak
    /// falling with its square), idle where it moves it little, where the slip acts.
    fn signature(&self, data: &ChannelData, form: &Form) -> Result<Signature, String> {
        let gamma = Some(data.gamma_deg.clone());
        by_form(self.kind(), data, form, (("camber", "deg"), &gamma))
    }

    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver> {
        Some(RunDriver::median(
            "median |camber| [deg]",
            data.gamma_deg.iter().map(|g| g.abs()).collect(),
        ))
    }

    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String> {
        Ok(RowDriver {
            axis: "camber |gamma| [deg]".into(),
            x: data.gamma_deg.iter().map(|g| g.abs()).collect(),
            range: None,
        })
    }
}
