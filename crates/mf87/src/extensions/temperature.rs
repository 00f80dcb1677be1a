//! Tread temperature: a window of the peak around an optimum, a stiffness linear in the
//! temperature. The window is quadratic near its top and levels off far from it (at `1 - w`),
//! as friction does on either side of a compound's working range, so a window fitted on one
//! side of the optimum does not plunge on the other.

use crate::bounds::{Row, TEMPERATURE_DEGC, row};
use crate::conditions::{ConditionVar, Conditions, Nominal};
use crate::error::{ParamError, invalid};
use crate::extensions::effect::{Check, Effect, ScaleParameters, Scales, parameters};
use crate::real::Real;

parameters! {
    /// Peak D times `1 - w q / (1 + q)` with `q = ((T - T0 - Topt_degC) / 50)^2`, stiffness
    /// BCD times `1 + k (T - T0) / 50` (T in degC).
    Temperature { w, Topt_degC, k }
}

/// Scale of temperature differences in the temperature effect [degC].
const TEMPERATURE_SCALE: f64 = 50.0;

impl<P: Copy> Temperature<P> {
    /// The temperature of the largest peak, T0 + Topt [degC].
    #[inline]
    pub(crate) fn optimum<T: Real + From<P>>(&self, nominal: &Nominal) -> T {
        T::from(self.Topt_degC) + nominal.temperature_c
    }
}

impl Effect for Temperature {
    type Of<P: Copy> = Temperature<P>;
    const CONDITION: Option<ConditionVar> = Some(ConditionVar::Temperature);

    /// At temperature `t` [degC]: peak `1 - w q / (1 + q)`, `q = ((T - T0 - Topt) / 50)^2`,
    /// stiffness `1 + k (T - T0) / 50`.
    #[inline]
    fn scales<P: Copy, T: Real + From<P>>(
        q: &Temperature<P>,
        nominal: &Nominal,
        x: &Conditions<T>,
    ) -> Option<Scales<T>> {
        let t = x.temperature;
        let window = (t - q.optimum::<T>(nominal)) / TEMPERATURE_SCALE;
        let q_window = window * window;
        let dt = (t - nominal.temperature_c) / TEMPERATURE_SCALE;
        Some(Scales {
            stiffness: dt * T::from(q.k) + 1.0,
            peak: -(q_window / (q_window + 1.0) * T::from(q.w)) + 1.0,
        })
    }

    /// The optimum temperature within [`TEMPERATURE_DEGC`].
    fn check_nominal(&self, c: &Check) -> Result<(), ParamError> {
        let optimum = self.optimum(c.nominal);
        if !TEMPERATURE_DEGC.contains(optimum) {
            return Err(invalid(
                &c.name("Topt_degC"),
                self.Topt_degC,
                &format!(
                    "the optimum temperature T0 + Topt_degC = {optimum} degC must lie in {} degC",
                    TEMPERATURE_DEGC
                ),
            ));
        }
        Ok(())
    }

    fn scale_parameters(&self) -> Option<ScaleParameters> {
        Some((("w", self.w), Some(("k", self.k))))
    }

    /// The peak window's top, the optimum.
    fn scale_vertices(&self, nominal: &Nominal, _fz_kn: f64) -> Vec<f64> {
        vec![self.optimum(nominal)]
    }

    fn bound_rows() -> Vec<Row> {
        vec![row(
            "optimum temperature T0 + Topt_degC",
            TEMPERATURE_DEGC.to_string(),
            "degC",
        )]
    }
}
