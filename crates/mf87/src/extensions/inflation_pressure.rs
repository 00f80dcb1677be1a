//! Inflation pressure, in the form of the later Magic Formulas (MF 6.1's ppx1..4, ppy1..4):
//! scales of the stiffness and the peak, quadratic in the pressure, the stiffness's with a
//! load interaction (MF 6.1's ppy2 moves the load of the largest cornering stiffness with the
//! pressure: here the stiffness's pressure sensitivity changes with the load).

use crate::conditions::{ConditionVar, Conditions, Nominal};
use crate::extensions::effect::{Effect, ScaleParameters, Scales, parameters};
use crate::real::Real;

parameters! {
    /// Stiffness BCD times `1 + (k + k_per_kN Fz) dp + k2 dp^2`, peak D times
    /// `1 + d dp + d2 dp^2`, `dp = (p - p0) / p0`, Fz in kN. `k2`, `d2` and `k_per_kN` are
    /// 0 when a parameter file leaves them out.
    InflationPressure { k, d; k2, d2, k_per_kN }
}

impl<P: Copy> InflationPressure<P> {
    /// The stiffness's linear coefficient at the load `fz_kn`.
    #[inline]
    fn k_at<T: Real + From<P>>(&self, fz_kn: T) -> T {
        T::from(self.k) + T::from(self.k_per_kN) * fz_kn
    }
}

impl Effect for InflationPressure {
    type Of<P: Copy> = InflationPressure<P>;
    const CONDITION: Option<ConditionVar> = Some(ConditionVar::Pressure);

    /// At pressure p [kPa] and load Fz: stiffness `1 + (k + k_per_kN Fz) dp + k2 dp^2`, peak
    /// `1 + d dp + d2 dp^2`.
    #[inline]
    fn scales<P: Copy, T: Real + From<P>>(
        q: &InflationPressure<P>,
        nominal: &Nominal,
        x: &Conditions<T>,
    ) -> Option<Scales<T>> {
        let dp = (x.pressure - nominal.pressure_kpa) / nominal.pressure_kpa;
        Some(Scales {
            stiffness: dp * (q.k_at(x.fz_kn) + dp * T::from(q.k2)) + 1.0,
            peak: dp * (T::from(q.d) + dp * T::from(q.d2)) + 1.0,
        })
    }

    fn scale_parameters(&self) -> Option<ScaleParameters> {
        Some((("d", self.d), Some(("k", self.k))))
    }

    /// The vertices of the two quadratics in the pressure, at the load `fz_kn`.
    fn scale_vertices(&self, nominal: &Nominal, fz_kn: f64) -> Vec<f64> {
        let p0 = nominal.pressure_kpa;
        let vertex = |linear: f64, quadratic: f64| {
            (quadratic != 0.0).then(|| p0 * (1.0 - linear / (2.0 * quadratic)))
        };
        [
            vertex(self.k_at::<f64>(fz_kn), self.k2),
            vertex(self.d, self.d2),
        ]
        .into_iter()
        .flatten()
        .filter(|v| v.is_finite())
        .collect()
    }
}
