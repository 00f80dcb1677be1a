//! Combined slip: the force of one slip falls as the other slip grows.

use mf87::{Channel, units};

use super::{Effect, Extension, Quantity, RowDriver, RunDriver, column};
use crate::method::channel_data::ChannelData;
use crate::method::stats::quantile;

pub struct CombinedSlip;

/// The other slip counts as not small above this: 1 deg of slip angle [rad] for Fx, a slip
/// ratio of 0.02 for Fy and Mz.
fn other_slip_threshold(channel: Channel) -> f64 {
    if channel == Channel::Fx {
        units::degrees_to_radians(1.0)
    } else {
        0.02
    }
}

impl Effect for CombinedSlip {
    fn kind(&self) -> Extension {
        Extension::CombinedSlip
    }

    fn form(&self) -> &'static str {
        "weighting G = cos(C atan(B s)) of Fy and Mz by slip ratio, of Fx by slip angle"
    }

    fn needs(&self, channel: Channel) -> &'static [Quantity] {
        match channel {
            Channel::Fx => &[Quantity::Alpha],
            Channel::Fy | Channel::Mz => &[Quantity::Kappa],
        }
    }

    fn starting_values(&self) -> &'static [f64] {
        &[8.0, 1.0]
    }

    /// A weight `G` of Fx or Fy that falls below zero within the measured other slip (99th
    /// percentile of |s|): the other slip would turn the force around (the aligning moment
    /// may change sign under combined slip, so Mz is not held to it).
    fn implausible(&self, data: &ChannelData, values: &[f64]) -> Option<String> {
        if data.channel == Channel::Mz {
            return None;
        }
        let (b, c) = (values[0], values[1]);
        let other: Vec<f64> = data
            .other_slip
            .as_deref()?
            .iter()
            .map(|s| s.abs())
            .collect();
        let s_max = quantile(&other, 0.99)?;
        let phase = c.abs() * (b.abs() * s_max).atan();
        if phase > std::f64::consts::FRAC_PI_2 {
            return Some(format!(
                "the combined-slip weight cos(C atan(B s)) with B = {b:.4}, C = {c:.4} \
                 turns negative within the measured other slip (|s| up to {s_max:.4}): \
                 C atan(B s) reaches {phase:.2} > pi/2, so the other slip would reverse \
                 {}",
                data.channel
            ));
        }
        None
    }

    /// Rows where the other slip is not small.
    fn home_rows(&self, data: &ChannelData) -> Option<Vec<bool>> {
        let threshold = other_slip_threshold(data.channel);
        data.other_slip
            .as_ref()
            .map(|o| o.iter().map(|x| x.abs() > threshold).collect())
    }

    /// Only the combined-slip runs are ranked (pure-slip runs always train).
    fn run_driver(&self, data: &ChannelData) -> Option<RunDriver> {
        let name = match data.channel {
            Channel::Fx => "largest |slip angle| [rad]",
            Channel::Fy | Channel::Mz => "largest |slip ratio| [-]",
        };
        Some(RunDriver {
            name,
            values: data.other_slip.as_ref()?.iter().map(|x| x.abs()).collect(),
            largest: true,
            floor: other_slip_threshold(data.channel),
        })
    }

    fn row_driver(&self, data: &ChannelData) -> Result<RowDriver, String> {
        Ok(match data.channel {
            Channel::Fx => RowDriver {
                axis: "slip angle alpha [deg]".into(),
                x: column(&data.other_slip, "slip angle")?
                    .iter()
                    .map(|a| units::radians_to_degrees(*a))
                    .collect(),
                range: None,
            },
            Channel::Fy | Channel::Mz => RowDriver {
                axis: "slip ratio kappa [-]".into(),
                x: column(&data.other_slip, "slip ratio")?,
                range: None,
            },
        })
    }
}
