//! Inflation pressure: scales of the stiffness and the peak, linear in the pressure.

use crate::conditions::{ConditionVar, Nominal};
use crate::extensions::effect::{Effect, ScaleParameters, Scales, parameters};
use crate::real::Real;

parameters! {
    /// Stiffness BCD times `1 + k dp`, peak D times `1 + d dp`, `dp = (p - p0) / p0`.
    InflationPressure { k, d }
}

impl Effect for InflationPressure {
    type Of<P: Copy> = InflationPressure<P>;
    const CONDITION: Option<ConditionVar> = Some(ConditionVar::Pressure);

    /// At pressure `p` [kPa]: stiffness `1 + k dp`, peak `1 + d dp`, `dp = (p - p0) / p0`.
    #[inline]
    fn scales<P: Copy, T: Real + From<P>>(
        q: &InflationPressure<P>,
        nominal: &Nominal,
        p: T,
    ) -> Option<Scales<T>> {
        let dp = (p - nominal.pressure_kpa) / nominal.pressure_kpa;
        Some(Scales {
            stiffness: dp * T::from(q.k) + 1.0,
            peak: dp * T::from(q.d) + 1.0,
        })
    }

    fn scale_parameters(&self) -> Option<ScaleParameters> {
        Some((("d", self.d), Some(("k", self.k))))
    }
}
