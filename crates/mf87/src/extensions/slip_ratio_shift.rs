//! The slip-ratio shift: Fx's horizontal shift growing with the load, and its vertical shift
//! (MF 6.1's SHx and SVx): the curve's drive and brake halves set apart.

use crate::bounds::{Row, abs, row};
use crate::channel::Channel;
use crate::coefficients::BaseParams;
use crate::conditions::Conditions;
use crate::error::{Num, ParamError, invalid};
use crate::extensions::effect::{Check, Effect, parameters};
use crate::formula::MagicFormula;
use crate::real::Real;
use crate::units;

parameters! {
    /// Horizontal and vertical shifts of the longitudinal curve, growing with load:
    /// `Fx = MF(kappa + Sh + Sh_per_kN Fz) + (Sv + Sv_per_kN Fz) Fz`, Sh [slip ratio],
    /// Sh_per_kN [slip ratio per kN], Sv [share of the load], Sv_per_kN [share of the load per
    /// kN] (Fz in kN; Fx only). Sv and Sv_per_kN are 0 when a parameter file leaves them out.
    SlipRatioShift { Sh, Sh_per_kN; Sv, Sv_per_kN }
}

/// The slip-ratio shift `|Sh + Sh_per_kN Fz|` over the load range [slip ratio]: the slip
/// offset of a rig that divides by a rolling radius R other than the effective one Re,
/// `(1 + kappa) Re / R - 1`. Re lies 1-3 % below the unloaded radius of a car tire and falls
/// with load (about a third of the deflection); at 0.05 the offset is a third to a half of
/// the slip at the peak of Fx: a rig set up that badly is to be corrected, not fitted.
pub const SLIP_RATIO_SHIFT_ABS_MAX: f64 = 0.05;

/// The vertical shift `|Sv + Sv_per_kN Fz|` over the load range [share of the load]: MF 6.1
/// fits of rig data give up to a few tenths where the drive and brake peaks differ (it is
/// their half difference, with the horizontal shift that brings the curve back through zero).
pub const SLIP_RATIO_SHIFT_SV_MAX: f64 = 0.4;

/// What the two bounds are of, as the errors name them.
const SH: &str = "the slip-ratio shift |Sh + Sh_per_kN Fz|";
const SV: &str = "the vertical shift |Sv + Sv_per_kN Fz| [share of the load]";

impl<P: Copy> SlipRatioShift<P> {
    /// The shift `Sh + Sh_per_kN Fz` [slip ratio] at the load `fz_kn` [kN].
    #[inline]
    pub(crate) fn at_load<T: Real + From<P>>(&self, fz_kn: T) -> T {
        fz_kn * T::from(self.Sh_per_kN) + T::from(self.Sh)
    }

    /// The vertical shift `Sv + Sv_per_kN Fz` [share of the load] at the load `fz_kn` [kN].
    #[inline]
    pub(crate) fn sv_share_at_load<T: Real + From<P>>(&self, fz_kn: T) -> T {
        fz_kn * T::from(self.Sv_per_kN) + T::from(self.Sv)
    }
}

/// `Err` naming `name` = `value` unless `at` (what `what` is at `place`) is at most `max`
/// (NaN is not).
fn at_most(
    c: &Check,
    name: &str,
    value: f64,
    what: &str,
    at: f64,
    place: &str,
    max: f64,
) -> Result<(), ParamError> {
    if at <= max {
        return Ok(());
    }
    Err(invalid(
        &c.name(name),
        value,
        &format!(
            "{what} is {} {place}; it must be at most {max} over the load range",
            Num(at)
        ),
    ))
}

impl Effect for SlipRatioShift {
    type Of<P: Copy> = SlipRatioShift<P>;

    fn applies_to(channel: Channel) -> bool {
        channel == Channel::Fx
    }

    /// Adds the shifts at the load to the horizontal shift [percent] and the vertical one [N].
    #[inline]
    fn shift<P: Copy, T: Real + From<P>>(
        q: &SlipRatioShift<P>,
        x: &Conditions<T>,
        mf: &mut MagicFormula<T>,
    ) {
        mf.sh += units::slip_ratio_to_percent(q.at_load(x.fz_kn));
        mf.sv += units::kilonewtons_to_newtons(x.fz_kn) * q.sv_share_at_load(x.fz_kn);
    }

    /// The shifts as the load vanishes, |Sh| and |Sv|, within their bounds (they are finite,
    /// checked before); at the top of the load range they are checked with the limits, by
    /// [`Effect::check_with_base`].
    fn check_range(&self, c: &Check) -> Result<(), ParamError> {
        let place = "as Fz -> 0";
        at_most(c, "Sh", self.Sh, SH, self.Sh.abs(), place, SLIP_RATIO_SHIFT_ABS_MAX)?;
        at_most(c, "Sv", self.Sv, SV, self.Sv.abs(), place, SLIP_RATIO_SHIFT_SV_MAX)
    }

    /// The shifts at the top of the load range (they are linear in Fz).
    fn check_with_base(&self, c: &Check, p: &BaseParams) -> Result<(), ParamError> {
        let fz_max_n = p.limits.fz_max_N;
        let fz_max_kn = units::newtons_to_kilonewtons(fz_max_n);
        let place = format!("at Fz = {fz_max_n} N");
        at_most(
            c,
            "Sh_per_kN",
            self.Sh_per_kN,
            &format!("{SH} (Sh = {})", Num(self.Sh)),
            self.at_load(fz_max_kn).abs(),
            &place,
            SLIP_RATIO_SHIFT_ABS_MAX,
        )?;
        at_most(
            c,
            "Sv_per_kN",
            self.Sv_per_kN,
            &format!("{SV} (Sv = {})", Num(self.Sv)),
            self.sv_share_at_load(fz_max_kn).abs(),
            &place,
            SLIP_RATIO_SHIFT_SV_MAX,
        )
    }

    fn bound_rows() -> Vec<Row> {
        vec![
            row(
                "slip_ratio_shift |Sh + Sh_per_kN Fz| over the load range",
                abs(SLIP_RATIO_SHIFT_ABS_MAX),
                "1 (slip ratio)",
            ),
            row(
                "slip_ratio_shift |Sv + Sv_per_kN Fz| over the load range",
                abs(SLIP_RATIO_SHIFT_SV_MAX),
                "1 (share of the load)",
            ),
        ]
    }
}
