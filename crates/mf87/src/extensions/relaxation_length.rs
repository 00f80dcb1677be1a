//! The relaxation length: its parameter, its bounds, and the lag over time, the first-order
//! lag `d s_lag / dx = (s - s_lag) / sigma` of each channel's slip over travelled distance,
//! exact over a step with the slip held ([`relaxation_step`]); the lag state of all three
//! channels ([`LaggedSlip`]) is what [`crate::evaluate_extended`] reads and a simulation
//! carries from step to step. With a parameter set's limits and relaxation lengths, its
//! steady state, step and rate ([`LaggedSlip::steady`], [`LaggedSlip::advanced`],
//! [`LaggedSlip::rates`]) are beside [`crate::evaluate_extended`].

use serde::{Deserialize, Serialize};

use crate::bounds::{Interval, Row, abs, row};
use crate::channel::Channel;
use crate::coefficients::Limits;
use crate::error::{ParamError, invalid};
use crate::extensions::effect::{Check, Effect, parameters};
use crate::interface::InputVar;
use crate::real::{self, Real};

parameters! {
    /// First-order lag of the channel's slip over travelled distance, relaxation length
    /// `sigma_m` \[m\] (0: no lag).
    RelaxationLength { sigma_m }
}

/// `relaxation_length.sigma_m` \[m\]: car tires 0.2..1 m, truck tires up to about 2 m; 0 is
/// no lag, else at least [`RELAXATION_LENGTH_MIN_M`].
pub const RELAXATION_LENGTH_M: Interval = Interval::new(0.0, 5.0);

/// The shortest relaxation length other than 0 \[m\]: 1 mm, a hundredth of a contact patch.
/// The lag's rate is |vx| (s - s_lag) / sigma: with the speed, slips and lagged slips within
/// their bounds it stays below 150 m/s x 200 / 1 mm = 3e7 per second (and its derivatives
/// finite); a length of a few ulps above 0 would overflow it to infinity.
pub const RELAXATION_LENGTH_MIN_M: f64 = 1e-3;

/// Whether `sigma_m` is an allowed relaxation length: 0 (no lag) or within
/// [`RELAXATION_LENGTH_MIN_M`] and the top of [`RELAXATION_LENGTH_M`].
pub fn relaxation_length_allowed(sigma_m: f64) -> bool {
    sigma_m == 0.0
        || Interval::new(RELAXATION_LENGTH_MIN_M, RELAXATION_LENGTH_M.hi).contains(sigma_m)
}

/// Each lagged slip (the relaxation states) in magnitude [slip ratio or rad]: the lag follows
/// the clamped slip (|kappa| <= 1, |alpha| <= pi/2), so only an integrator's overshoot takes
/// it beyond them; 100 leaves room for that and keeps the lag's rate finite.
pub const LAGGED_SLIP_ABS_MAX: f64 = 100.0;

impl Effect for RelaxationLength {
    type Of<P: Copy> = RelaxationLength<P>;

    #[inline]
    fn relaxation_length_m<P: Copy>(q: &RelaxationLength<P>) -> Option<P> {
        Some(q.sigma_m)
    }

    fn check_allowed(&self, c: &Check) -> Result<(), ParamError> {
        if !relaxation_length_allowed(self.sigma_m) {
            return Err(invalid(
                &c.name("sigma_m"),
                self.sigma_m,
                &format!(
                    "the relaxation length must be 0 (no lag) or lie in [{}, {}] m",
                    RELAXATION_LENGTH_MIN_M, RELAXATION_LENGTH_M.hi
                ),
            ));
        }
        Ok(())
    }

    fn bound_rows() -> Vec<Row> {
        vec![
            row(
                "relaxation_length.sigma_m",
                format!(
                    "0 or [{RELAXATION_LENGTH_MIN_M}, {}]",
                    RELAXATION_LENGTH_M.hi
                ),
                "m",
            ),
            row(
                "each relaxation state (lagged slip)",
                abs(LAGGED_SLIP_ABS_MAX),
                "1, rad",
            ),
        ]
    }
}

/// One step of the first-order relaxation lag `d s_lag / dx = (s - s_lag) / sigma` over a
/// travelled distance `distance_m` with the slip `slip` held: exact for a constant slip.
/// `sigma_m <= 0` is no lag. Over a dual number, exact in `lagged`, `slip` and `sigma_m`.
#[inline]
pub fn relaxation_step<T: Real>(lagged: T, slip: T, distance_m: f64, sigma_m: T) -> T {
    if real::value(sigma_m) <= 0.0 {
        slip
    } else {
        lagged + (slip - lagged) * (-(T::from(-distance_m) / sigma_m).exp() + 1.0)
    }
}

/// Each channel's slip after its relaxation lag, in SI: slip ratio for Fx, slip angle \[rad\]
/// for Fy and Mz. Channels without a relaxation length ignore it.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct LaggedSlip<T = f64> {
    pub fx: T,
    pub fy: T,
    pub mz: T,
}

impl<T: Copy> LaggedSlip<T> {
    /// The lagged slip of `channel`.
    pub fn get(&self, channel: Channel) -> T {
        match channel {
            Channel::Fx => self.fx,
            Channel::Fy => self.fy,
            Channel::Mz => self.mz,
        }
    }

    pub fn get_mut(&mut self, channel: Channel) -> &mut T {
        match channel {
            Channel::Fx => &mut self.fx,
            Channel::Fy => &mut self.fy,
            Channel::Mz => &mut self.mz,
        }
    }
}

impl<T: Real> LaggedSlip<T> {
    /// Each lagged slip clamped to its input's valid range.
    pub(crate) fn clamped(&self, limits: &Limits) -> LaggedSlip<T> {
        let clamp = |v: T, var: InputVar| {
            let (lo, hi) = var.valid_range(limits);
            real::clamp(v, lo, hi)
        };
        LaggedSlip {
            fx: clamp(self.fx, InputVar::Kappa),
            fy: clamp(self.fy, InputVar::Alpha),
            mz: clamp(self.mz, InputVar::Alpha),
        }
    }
}
