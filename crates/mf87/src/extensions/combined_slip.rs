//! Combined slip: the output weighted by `G = cos(C atan(B s))` of the other slip s.

use crate::bounds::{Row, abs, row};
use crate::channel::Channel;
use crate::conditions::Conditions;
use crate::error::{Num, ParamError, invalid};
use crate::extensions::effect::{Check, Effect, parameters};
use crate::real::Real;

parameters! {
    /// Combined slip: the output weighted by `G = cos(C atan(B s))` of the other slip s (slip
    /// ratio for Fy and Mz, slip angle [rad] for Fx).
    CombinedSlip { B, C }
}

/// `combined_slip.B` in magnitude [1/(slip ratio) for Fy and Mz, 1/rad for Fx]: G may fall
/// within 0.001 of slip at the steepest.
pub const COMBINED_SLIP_B_ABS_MAX: f64 = 1000.0;

/// `|C| atan(|B| s_max)` of `combined_slip` over the other slip's range (s_max = 1 for the
/// slip ratio, pi/2 rad for the slip angle): G = cos(...) changes sign at most eight times.
/// Fits of Fx by slip angle follow G ~ cos(B C s) with small B and large C and reach 3 pi.
pub const COMBINED_SLIP_PHASE_MAX: f64 = 8.0 * std::f64::consts::PI;

impl Effect for CombinedSlip {
    type Of<P: Copy> = CombinedSlip<P>;

    /// The weight `G = cos(C atan(B s))` at the other slip `s`.
    #[inline]
    fn weight<P: Copy, T: Real + From<P>>(q: &CombinedSlip<P>, x: &Conditions<T>) -> Option<T> {
        Some(((x.other_slip * T::from(q.B)).atan() * T::from(q.C)).cos())
    }

    /// G over the other slip's range: |B| bounded and the phase |C| atan(|B| s_max) too, so
    /// that G changes sign only a few times.
    fn check_range(&self, c: &Check) -> Result<(), ParamError> {
        if self.B.abs() > COMBINED_SLIP_B_ABS_MAX {
            return Err(invalid(
                &c.name("B"),
                self.B,
                &format!("|B| must be <= {}", COMBINED_SLIP_B_ABS_MAX),
            ));
        }
        let (s_max, s_name) = match c.channel {
            Channel::Fx => (std::f64::consts::FRAC_PI_2, "|alpha| <= pi/2 rad"),
            Channel::Fy | Channel::Mz => (1.0, "|kappa| <= 1"),
        };
        let phase = self.C.abs() * (self.B.abs() * s_max).atan();
        if phase.is_nan() || phase > COMBINED_SLIP_PHASE_MAX {
            return Err(invalid(
                &c.name("C"),
                self.C,
                &format!(
                    "the phase |C| atan(|B| s) of G = cos(C atan(B s)) reaches {phase} rad over \
                     {s_name} (B = {}); it must stay <= 8 pi = {} rad",
                    Num(self.B),
                    COMBINED_SLIP_PHASE_MAX,
                    phase = Num(phase)
                ),
            ));
        }
        Ok(())
    }

    fn bound_rows() -> Vec<Row> {
        vec![
            row(
                "combined_slip |B|",
                abs(COMBINED_SLIP_B_ABS_MAX),
                "1, 1/rad",
            ),
            row(
                "combined_slip |C| atan(|B| s_max)",
                format!("<= 8 pi ({COMBINED_SLIP_PHASE_MAX:.2})"),
                "rad",
            ),
        ]
    }
}
