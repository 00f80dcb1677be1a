//! Physical plausibility of a fitted candidate: an effect the FMU would refuse over the data's
//! range, or one that makes the force reverse within the measured slips, is a misfit soaked up
//! by a flexible form, not a physical effect, and never enters a verdict. The verdict's model
//! therefore always exports.

use crate::method::fit::effects::{self, Extension};
use crate::method::fit::model::ChannelModel;
use crate::method::fit::validity::ValidityRange;
use crate::method::prepare::channel_data::ChannelData;

/// The range candidates are judged over: the one the fitted model is exported for.
pub(super) struct Plausibility {
    range: ValidityRange,
}

impl Plausibility {
    pub(super) fn new(range: ValidityRange) -> Plausibility {
        Plausibility { range }
    }

    /// Whether the FMU accepts `model` over the range.
    pub(super) fn exports(&self, model: &ChannelModel) -> bool {
        self.range.parameters(std::slice::from_ref(model)).is_ok()
    }

    /// Why the `candidate` fit of `effect` (the channel's `current` model plus the effect) is
    /// not physical, if it is not:
    /// - the FMU's validation over the data's range refuses it while it accepts `current`
    ///   (parameter, value and bound named);
    /// - the effect's own check finds it unphysical on the data (see
    ///   [`effects::Effect::implausible`]).
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
        let (_, q) = candidate.effects.iter().find(|(e, _)| *e == effect)?;
        effects::of(effect).implausible(data, &effects::model_values(effect, q))
    }
}

#[cfg(test)]
mod tests {
    use mf87::{Channel, Params};

    use super::*;
    use crate::data::Dataset;
    use crate::method::fit::effects::Nominal;
    use crate::quantiles::quantile;

    /// 600 rows at one speed, with slip angles to 8 deg and slip ratios to 0.1.
    fn dataset() -> Dataset {
        let rows: Vec<f64> = (0..600).map(f64::from).collect();
        let col = |f: &dyn Fn(f64) -> f64| -> Vec<f64> { rows.iter().map(|i| f(*i)).collect() };
        Dataset {
            source: "plausibility test".into(),
            run: rows.iter().map(|i| (*i as i64) / 100).collect(),
            time: Some(col(&|i| (i % 100.0) * 0.01).into()),
            speed: Some(vec![11.1; 600].into()),
            fz: col(&|i| 3000.0 + 1000.0 * (i * 0.021).sin()).into(),
            alpha: Some(col(&|i| 8f64.to_radians() * (i * 0.05).sin()).into()),
            kappa: Some(col(&|i| 0.1 * (i * 0.037).cos()).into()),
            fx: Some(vec![0.0; 600].into()),
            fy: Some(vec![0.0; 600].into()),
            ..Dataset::default()
        }
    }

    fn model(channel: Channel, effects: &[(Extension, &[f64])]) -> ChannelModel {
        let nominal = Nominal {
            pressure_kpa: 200.0,
            speed_mps: 11.1,
            temperature_c: 25.0,
        };
        let mut m = ChannelModel::new(Params::paper_table(), channel, false, nominal);
        m.effects = effects.iter().map(|(e, q)| (*e, q.to_vec())).collect();
        m
    }

    fn judge(channel: Channel, effect: Extension, q: &[f64]) -> Option<String> {
        let ds = dataset();
        let data = ChannelData::channels_of(&ds, &[channel]).remove(0);
        Plausibility::new(ValidityRange::of(&ds)).judge(
            &data,
            &model(channel, &[]),
            &model(channel, &[(effect, q)]),
            effect,
        )
    }

    #[test]
    fn an_effect_the_fmu_refuses_is_named_with_its_bound() {
        // The fit seen on a real constant-speed programme: a 10 % offset of the load.
        let why = judge(Channel::Fx, Extension::RollingResistance, &[41.8, -41.9]).unwrap();
        assert!(why.contains("rolling_resistance"), "{why}");
        assert!(why.contains("outside the FMU's bounds"), "{why}");
        assert_eq!(
            judge(Channel::Fx, Extension::RollingResistance, &[0.012, 0.0]),
            None
        );
    }

    #[test]
    fn combined_slip_must_keep_the_force_s_sign_within_the_measured_slip() {
        // Fy by slip ratio (up to 0.1): B = 8, C = 1 gives a phase of atan(0.8) = 0.67.
        assert_eq!(
            judge(Channel::Fy, Extension::CombinedSlip, &[8.0, 1.0]),
            None
        );
        // C = 152.8 as fitted on a real programme: the FMU's own bound refuses it.
        assert!(judge(Channel::Fy, Extension::CombinedSlip, &[0.5, 152.8]).is_some());
        // Within the FMU's bound (phase 30 atan(1) < 8 pi over |kappa| <= 1), but reversing
        // the force at the measured slip ratios (30 atan(0.1) = 3.0 > pi/2).
        let why = judge(Channel::Fy, Extension::CombinedSlip, &[1.0, 30.0]).unwrap();
        assert!(why.contains("turns negative"), "{why}");
        // Just past pi/2 at the 99th percentile of |kappa| (0.0999...): refused; just below: kept.
        let b = 8.0;
        let s99 = quantile(
            &dataset()
                .kappa
                .unwrap()
                .iter()
                .map(|k| k.abs())
                .collect::<Vec<_>>(),
            0.99,
        )
        .unwrap();
        let c_edge = std::f64::consts::FRAC_PI_2 / (b * s99).atan();
        assert!(judge(Channel::Fy, Extension::CombinedSlip, &[b, 1.01 * c_edge]).is_some());
        assert!(judge(Channel::Fy, Extension::CombinedSlip, &[b, 0.99 * c_edge]).is_none());
    }
}
