//! Rolling resistance: a term linear in the speed and the load subtracted from Fx.

use crate::bounds::{Interval, Row, row};
use crate::channel::Channel;
use crate::conditions::{ConditionVar, Conditions, Nominal};
use crate::error::{Num, ParamError, invalid};
use crate::extensions::effect::{Check, Effect, parameters};
use crate::real::Real;
use crate::units;

parameters! {
    /// `Fx - (q1 + q2 V / V0) Fz` \[N\] (Fx only).
    RollingResistance { q1, q2 }
}

/// Rolling-resistance coefficient `q1 + q2 |vx| / V0` over the speed range: 0.005..0.03 on
/// roads, 0.3 in deep sand; slightly negative values allow a fitted Fx offset.
pub const ROLLING_RESISTANCE: Interval = Interval::new(-0.05, 0.3);

impl<P: Copy> RollingResistance<P> {
    /// The coefficient `q1 + q2 V / V0` at speed `v` [m/s].
    #[inline]
    pub(crate) fn coefficient<T: Real + From<P>>(&self, nominal: &Nominal, v: T) -> T {
        v * T::from(self.q2) / nominal.speed_mps + T::from(self.q1)
    }
}

impl Effect for RollingResistance {
    type Of<P: Copy> = RollingResistance<P>;
    const CONDITION: Option<ConditionVar> = Some(ConditionVar::Speed);

    fn applies_to(channel: Channel) -> bool {
        channel == Channel::Fx
    }

    /// `(q1 + q2 V / V0) Fz` [N].
    #[inline]
    fn subtract<P: Copy, T: Real + From<P>>(
        q: &RollingResistance<P>,
        nominal: &Nominal,
        x: &Conditions<T>,
    ) -> Option<T> {
        Some(q.coefficient(nominal, x.speed) * units::kilonewtons_to_newtons(x.fz_kn))
    }

    /// The coefficient q1 + q2 |vx| / V0 (linear in speed) at both ends of the speed range.
    fn check_range(&self, c: &Check) -> Result<(), ParamError> {
        let (lo, hi) = (c.limits.speed_min_mps, c.limits.speed_max_mps);
        for (speed, parameter, value) in [(lo, "q1", self.q1), (hi, "q2", self.q2)] {
            let f = self.coefficient(c.nominal, speed);
            if !ROLLING_RESISTANCE.contains(f) {
                return Err(invalid(
                    &c.name(parameter),
                    value,
                    &format!(
                        "the rolling-resistance coefficient q1 + q2 |vx| / V0 is {f} at |vx| = {speed} m/s \
                         (q1 = {}, q2 = {}, V0 = {} m/s); it must lie in {} over the speed range [{lo}, {hi}] m/s",
                        Num(self.q1),
                        Num(self.q2),
                        c.nominal.speed_mps,
                        ROLLING_RESISTANCE,
                        f = Num(f)
                    ),
                ));
            }
        }
        Ok(())
    }

    fn bound_rows() -> Vec<Row> {
        vec![row(
            "rolling resistance q1 + q2 |vx| / V0",
            ROLLING_RESISTANCE.to_string(),
            "1",
        )]
    }
}
