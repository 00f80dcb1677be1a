//! Speed dependence: a scale of the peak, quadratic in the speed (friction of rubber falls
//! with the speed, most at low speed, and levels off).

use crate::conditions::{ConditionVar, Conditions, Nominal};
use crate::extensions::effect::{Effect, ScaleParameters, Scales, parameters};
use crate::real::Real;

parameters! {
    /// Peak D times `1 + v dV + w dV^2`, `dV = (V - V0) / V0`. `w` is 0 when a parameter
    /// file leaves it out.
    SpeedDependence { v; w }
}

impl Effect for SpeedDependence {
    type Of<P: Copy> = SpeedDependence<P>;
    const CONDITION: Option<ConditionVar> = Some(ConditionVar::Speed);

    /// At speed V [m/s]: peak `1 + v dV + w dV^2`, `dV = (V - V0) / V0`; the stiffness stays.
    #[inline]
    fn scales<P: Copy, T: Real + From<P>>(
        q: &SpeedDependence<P>,
        nominal: &Nominal,
        x: &Conditions<T>,
    ) -> Option<Scales<T>> {
        let dv = (x.speed - nominal.speed_mps) / nominal.speed_mps;
        Some(Scales {
            stiffness: T::from(1.0),
            peak: dv * (T::from(q.v) + dv * T::from(q.w)) + 1.0,
        })
    }

    fn scale_parameters(&self) -> Option<ScaleParameters> {
        Some((("v", self.v), None))
    }

    /// The vertex of the quadratic in the speed.
    fn scale_vertices(&self, nominal: &Nominal, _fz_kn: f64) -> Vec<f64> {
        let vertex = nominal.speed_mps * (1.0 - self.v / (2.0 * self.w));
        (self.w != 0.0 && vertex.is_finite())
            .then_some(vertex)
            .into_iter()
            .collect()
    }
}
