//! The slip-ratio shift: a horizontal shift of Fx growing with the load.

use crate::bounds::{Row, abs, row};
use crate::channel::Channel;
use crate::conditions::Conditions;
use crate::error::{Num, ParamError, invalid};
use crate::extensions::effect::{Check, Effect, parameters};
use crate::formula::MagicFormula;
use crate::params::Params;
use crate::real::Real;
use crate::units;

parameters! {
    /// Horizontal shift of the longitudinal curve, growing with load:
    /// `Fx = MF(kappa + Sh + Sh_per_kN Fz)`, Sh [slip ratio], Sh_per_kN [slip ratio per kN]
    /// (Fz in kN; Fx only).
    SlipRatioShift { Sh, Sh_per_kN }
}

/// The slip-ratio shift `|Sh + Sh_per_kN Fz|` over the load range [slip ratio]: the slip
/// offset of a rig that divides by a rolling radius R other than the effective one Re,
/// `(1 + kappa) Re / R - 1`. Re lies 1-3 % below the unloaded radius of a car tire and falls
/// with load (about a third of the deflection); at 0.05 the offset is a third to a half of
/// the slip at the peak of Fx: a rig set up that badly is to be corrected, not fitted.
pub const SLIP_RATIO_SHIFT_ABS_MAX: f64 = 0.05;

impl<P: Copy> SlipRatioShift<P> {
    /// The shift `Sh + Sh_per_kN Fz` [slip ratio] at the load `fz_kn` [kN].
    #[inline]
    pub(crate) fn at_load<T: Real + From<P>>(&self, fz_kn: T) -> T {
        fz_kn * T::from(self.Sh_per_kN) + T::from(self.Sh)
    }
}

impl Effect for SlipRatioShift {
    type Of<P: Copy> = SlipRatioShift<P>;

    fn applies_to(channel: Channel) -> bool {
        channel == Channel::Fx
    }

    /// Adds the shift at the load to the horizontal shift [percent].
    #[inline]
    fn shift<P: Copy, T: Real + From<P>>(
        q: &SlipRatioShift<P>,
        x: &Conditions<T>,
        mf: &mut MagicFormula<T>,
    ) {
        mf.sh += units::slip_ratio_to_percent(q.at_load(x.fz_kn));
    }

    /// The shift as the load vanishes, |Sh|, within its bound (it is finite, checked
    /// before); at the top of the load range it is checked with the limits, by
    /// [`Effect::check_with_base`].
    fn check_range(&self, c: &Check) -> Result<(), ParamError> {
        let max = SLIP_RATIO_SHIFT_ABS_MAX;
        if self.Sh.abs() > max {
            return Err(invalid(
                &c.name("Sh"),
                self.Sh,
                &format!(
                    "the slip-ratio shift |Sh + Sh_per_kN Fz| is {} as Fz -> 0; it must be at most {max} \
                     over the load range",
                    Num(self.Sh.abs())
                ),
            ));
        }
        Ok(())
    }

    /// The shift Sh + Sh_per_kN Fz at the top of the load range (it is linear in Fz).
    fn check_with_base(&self, c: &Check, p: &Params) -> Result<(), ParamError> {
        let fz_max_n = p.limits.fz_max_N;
        let shift = self.at_load(units::newtons_to_kilonewtons(fz_max_n));
        let max = SLIP_RATIO_SHIFT_ABS_MAX;
        if shift.is_nan() || shift.abs() > max {
            return Err(invalid(
                &c.name("Sh_per_kN"),
                self.Sh_per_kN,
                &format!(
                    "the slip-ratio shift |Sh + Sh_per_kN Fz| (Sh = {}) is {} at Fz = {fz_max_n} N; it \
                     must be at most {max} over the load range",
                    Num(self.Sh),
                    Num(shift.abs())
                ),
            ));
        }
        Ok(())
    }

    fn bound_rows() -> Vec<Row> {
        vec![row(
            "slip_ratio_shift |Sh + Sh_per_kN Fz| over the load range",
            abs(SLIP_RATIO_SHIFT_ABS_MAX),
            "1 (slip ratio)",
        )]
    }
}
