//! Camber on the peak, as MF 6.1 has it for Fx (pDx3) and Fy (pDy3): the peak falls with the
//! square of the camber, the stiffness stays (B rises as D falls). Forces only: MF 6.1's
//! camber terms of the aligning moment act on its pneumatic trail and residual torque
//! (qDz3, qDz4, qDz8..11), not on a peak of the whole moment, and the 1987 Mz has camber
//! terms of its own.

use crate::bounds::{CONDITION_SCALE, Row, row};
use crate::channel::Channel;
use crate::coefficients::BaseParams;
use crate::conditions::{Conditions, Nominal};
use crate::error::{Num, ParamError, invalid};
use crate::extensions::effect::{Check, Effect, Scales, parameters};
use crate::real::Real;

parameters! {
    /// Peak D times `1 - d gamma^2` (gamma \[rad\]); the stiffness BCD stays.
    CamberPeak { d }
}

impl Effect for CamberPeak {
    type Of<P: Copy> = CamberPeak<P>;

    fn applies_to(channel: Channel) -> bool {
        channel != Channel::Mz
    }

    /// At camber gamma: peak `1 - d gamma^2`, stiffness 1.
    #[inline]
    fn scales<P: Copy, T: Real + From<P>>(
        q: &CamberPeak<P>,
        _nominal: &Nominal,
        x: &Conditions<T>,
    ) -> Option<Scales<T>> {
        Some(Scales {
            stiffness: T::from(1.0),
            peak: -(T::from(q.d) * x.gamma * x.gamma) + 1.0,
        })
    }

    /// Camber lowers the peak, never raises it: `d >= 0` (what a tire does; the peak bounds
    /// then hold as without it), and the scale stays within the bounds of a condition's scale
    /// up to gamma_max.
    fn check_with_base(&self, c: &Check, base: &BaseParams) -> Result<(), ParamError> {
        let gamma_max = base.limits.gamma_max_deg.to_radians();
        let lowest = 1.0 - self.d * gamma_max * gamma_max;
        if self.d < 0.0 || !CONDITION_SCALE.contains(lowest) {
            return Err(invalid(
                &c.name("d"),
                self.d,
                &format!(
                    "camber may only lower the peak: d must be >= 0 and the scale 1 - d gamma^2 \\
                     stay within {CONDITION_SCALE} up to gamma_max = {} deg (it is {} there)",
                    Num(base.limits.gamma_max_deg),
                    Num(lowest)
                ),
            ));
        }
        Ok(())
    }

    fn bound_rows() -> Vec<Row> {
        vec![row(
            "camber_peak d; 1 - d gamma_max^2",
            format!(">= 0; {CONDITION_SCALE}"),
            "1/rad^2; 1",
        )]
    }
}
