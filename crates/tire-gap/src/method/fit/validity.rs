//! The range a fitted model holds over: the data's loads, cambers and conditions with a margin,
//! and the fitted models as parameters the FMU accepts over it.

use mf87::extensions::{ConditionLimits, Extensions};
use mf87::{Channel, Params, bounds};

use crate::data::{Dataset, Quantity};
use crate::method::fit::effects;
use crate::method::fit::model::ChannelModel;
use crate::method::prepare::channel_data::CAMBER_VARIES_DEG;

/// Margin around the measured range of a condition, as a share of its span, on each side.
const CONDITION_MARGIN: f64 = 0.1;

/// The range a fitted model is exported for: the data's loads, cambers and conditions, with a
/// margin. A candidate fit is judged against it too: one the FMU would refuse over it is not
/// a physical effect and never enters a verdict.
#[derive(Debug, Clone)]
pub struct ValidityRange {
    fz_max_n: f64,
    gamma_max_deg: Option<f64>,
    conditions: ConditionLimits,
}

impl ValidityRange {
    pub fn of(ds: &Dataset) -> ValidityRange {
        // Fitted coefficients say nothing beyond the data's range (a camber coefficient fitted
        // on +-4 deg may be singular at the paper's 10 deg).
        let fz_max = ds.fz.iter().copied().fold(0.0, f64::max);
        let g_max = ds.gamma.as_deref().map_or(0.0, |g| {
            g.iter().map(|x| x.abs().to_degrees()).fold(0.0, f64::max)
        });
        ValidityRange {
            fz_max_n: (1.1 * fz_max).clamp(1000.0, bounds::FZ_MAX_N.hi),
            // Without camber in the data the paper's camber coefficients and range stay.
            gamma_max_deg: (g_max > CAMBER_VARIES_DEG)
                .then(|| (1.1 * g_max).clamp(bounds::GAMMA_MAX_DEG.lo, bounds::GAMMA_MAX_DEG.hi)),
            conditions: condition_limits(ds),
        }
    }

    /// The models (the paper's table for channels without one) over this range, validated
    /// as the FMU validates a parameter file.
    pub fn parameters(&self, models: &[ChannelModel]) -> Result<Params, String> {
        let mut params = Params::paper_table();
        for model in models {
            let fitted = model.params_with(&model.theta());
            match model.channel {
                Channel::Fx => params.Fx = fitted.Fx,
                Channel::Fy => params.Fy = fitted.Fy,
                Channel::Mz => params.Mz = fitted.Mz,
            }
        }
        params.limits.fz_max_N = self.fz_max_n;
        if let Some(g) = self.gamma_max_deg {
            params.limits.gamma_max_deg = g;
        }
        params.extensions = extensions(models, &self.conditions)?;
        params.validate().map_err(|e| {
            format!("the fitted parameters are not valid over the data's range: {e}")
        })?;
        Ok(params)
    }
}

/// Every channel model's effects with their fitted parameters, or `None` if there are none.
fn extensions(
    models: &[ChannelModel],
    conditions: &ConditionLimits,
) -> Result<Option<Extensions>, String> {
    let Some(first) = models.iter().find(|m| !m.effects.is_empty()) else {
        return Ok(None);
    };
    let mut ext = Extensions::new(first.nominal, *conditions);
    for model in models.iter().filter(|m| !m.effects.is_empty()) {
        if model.nominal != first.nominal {
            return Err(format!(
                "the {} and {} models are fitted around different nominal conditions",
                first.channel, model.channel
            ));
        }
        *ext.channel_mut(model.channel) =
            effects::channel_extensions(model.effects.iter().map(|(e, q)| (*e, q.as_slice())));
    }
    Ok(Some(ext))
}

/// The measured range of speed, pressure and temperature, widened by a margin; the defaults
/// for conditions not measured (no effect can depend on those).
pub(crate) fn condition_limits(ds: &Dataset) -> ConditionLimits {
    let measured = |q: Quantity| -> Option<(f64, f64)> {
        let (lo, hi) = ds
            .column(q)?
            .iter()
            .filter(|x| x.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(*x), hi.max(*x))
            });
        (lo <= hi).then_some((lo, hi))
    };
    let widened = |(lo, hi): (f64, f64)| {
        let margin = CONDITION_MARGIN * (hi - lo);
        (lo - margin, hi + margin)
    };
    let mut limits = ConditionLimits::default();
    if let Some(range) = measured(Quantity::Speed) {
        let (lo, hi) = widened(range);
        (limits.speed_min_mps, limits.speed_max_mps) = (lo.max(0.0), hi);
    }
    if let Some(range) = measured(Quantity::Pressure) {
        // Below the data by at most half the lowest pressure: it stays above zero.
        let (lo, hi) = widened(range);
        (limits.pressure_min_kPa, limits.pressure_max_kPa) = (lo.max(0.5 * range.0), hi);
    }
    if let Some(range) = measured(Quantity::Temperature) {
        (limits.temperature_min_degC, limits.temperature_max_degC) = widened(range);
    }
    limits
}
