//! Physical plausibility of a fitted candidate: an effect the FMU would refuse over the data's
//! range, or one that makes the force reverse within the measured slips, is a misfit soaked up
//! by a flexible form, not a physical effect, and never enters a verdict. The verdict's model
//! therefore always exports.

use mf87::Channel;

use crate::channel_data::ChannelData;
use crate::effects::{self, Extension};
use crate::export::ValidityRange;
use crate::model::ChannelModel;
use crate::stats::quantile;

/// The range candidates are judged over: the one the fitted model is exported for.
pub(super) struct Plausibility {
    range: ValidityRange,
}

impl Plausibility {
    pub(super) fn new(range: ValidityRange) -> Plausibility {
        Plausibility { range }
    }

    /// Why the `candidate` fit of `effect` (the channel's `current` model plus the effect) is
    /// not physical, if it is not:
    /// - the FMU's validation over the data's range refuses it while it accepts `current`
    ///   (parameter, value and bound named);
    /// - a combined-slip weight `G = cos(C atan(B s))` of Fx or Fy that falls below zero
    ///   within the measured other slip (99th percentile of |s|): the other slip would turn
    ///   the force around (the aligning moment may change sign under combined slip, so Mz is
    ///   not held to it).
    pub(super) fn judge(
        &self,
        data: &ChannelData,
        current: &ChannelModel,
        candidate: &ChannelModel,
        effect: Extension,
    ) -> Option<String> {
        if let Err(e) = self.range.parameters(std::slice::from_ref(candidate))
            && self.range.parameters(std::slice::from_ref(current)).is_ok()
        {
            return Some(format!("outside the FMU's bounds: {e}"));
        }
        if effect == Extension::CombinedSlip && data.channel != Channel::Mz {
            let q = candidate.effects.iter().find(|(e, _)| *e == effect)?;
            let v = effects::model_values(effect, &q.1);
            let (b, c) = (v[0], v[1]);
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
        }
        None
    }
}
