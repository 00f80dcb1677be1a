//! Speed dependence: a scale of the peak, linear in the speed.

use crate::conditions::{ConditionVar, Conditions, Nominal};
use crate::extensions::effect::{Effect, ScaleParameters, Scales, parameters};
use crate::real::Real;

parameters! {
    /// Peak D times `1 + v dV`, `dV = (V - V0) / V0`.
    SpeedDependence { v }
}

impl Effect for SpeedDependence {
    type Of<P: Copy> = SpeedDependence<P>;
    const CONDITION: Option<ConditionVar> = Some(ConditionVar::Speed);

    /// At speed V [m/s]: peak `1 + v dV`, `dV = (V - V0) / V0`; the stiffness stays.
    #[inline]
    fn scales<P: Copy, T: Real + From<P>>(
        q: &SpeedDependence<P>,
        nominal: &Nominal,
        x: &Conditions<T>,
    ) -> Option<Scales<T>> {
        let dv = (x.speed - nominal.speed_mps) / nominal.speed_mps;
        Some(Scales {
            stiffness: T::from(1.0),
            peak: dv * T::from(q.v) + 1.0,
        })
    }

    fn scale_parameters(&self) -> Option<ScaleParameters> {
        Some((("v", self.v), None))
    }
}
