//! The relaxation-length extension over time: the first-order lag
//! `d s_lag / dt = |vx| (s - s_lag) / sigma` of each channel's slip, as its rate
//! ([`LaggedSlip::rates`], for an integrator) and as its exact solution over a step with the
//! inputs held ([`relaxation_step`], [`LaggedSlip::advanced`]); the lag state of all three
//! channels ([`LaggedSlip`]) is what [`crate::evaluate_extended`] reads and a simulation
//! carries from step to step.

use serde::{Deserialize, Serialize};

use crate::channel::Channel;
use crate::interface::{InputVar, Inputs};
use crate::params::{Limits, Params};
use crate::real::{self, Real};

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

/// Each channel's slip after its relaxation lag, in SI: slip ratio for Fx, slip angle [rad]
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

/// The relaxation length [m] of `channel`, 0 without one.
fn relaxation_length_m(params: &Params, channel: Channel) -> f64 {
    params
        .extensions
        .as_ref()
        .and_then(|e| e.channel(channel).relaxation_length_m())
        .unwrap_or(0.0)
}

impl LaggedSlip {
    /// The steady state: every lagged slip equal to its (clamped) input.
    pub fn steady(params: &Params, inputs: &Inputs) -> LaggedSlip {
        let x = inputs.clamped(&params.limits);
        LaggedSlip {
            fx: x.kappa,
            fy: x.alpha,
            mz: x.alpha,
        }
    }

    /// The lag after travelling `distance_m` with `inputs` held (exact for constant inputs).
    /// The lag follows the clamped inputs; a channel without a relaxation length follows its
    /// input at once.
    pub fn advanced(&self, params: &Params, inputs: &Inputs, distance_m: f64) -> LaggedSlip {
        let x = inputs.clamped(&params.limits);
        let sigma = |channel| relaxation_length_m(params, channel);
        LaggedSlip {
            fx: relaxation_step(self.fx, x.kappa, distance_m, sigma(Channel::Fx)),
            fy: relaxation_step(self.fy, x.alpha, distance_m, sigma(Channel::Fy)),
            mz: relaxation_step(self.mz, x.alpha, distance_m, sigma(Channel::Mz)),
        }
    }
}

impl<T: Real> LaggedSlip<T> {
    /// The time derivative of each lagged slip, `|vx| (s - s_lag) / sigma` [1/s or rad/s],
    /// towards the clamped input `s`. A channel without a relaxation length has rate 0: its
    /// lag is not used (the output takes the input slip), so it stays where it is.
    pub fn rates(&self, params: &Params, inputs: &Inputs<T>, vx: T) -> LaggedSlip<T> {
        let x = inputs.clamped(&params.limits);
        let speed = real::abs(vx);
        let rate = |lagged: T, slip: T, channel| {
            let sigma = relaxation_length_m(params, channel);
            if sigma > 0.0 {
                speed * (slip - lagged) / sigma
            } else {
                T::from(0.0)
            }
        };
        LaggedSlip {
            fx: rate(self.fx, x.kappa, Channel::Fx),
            fy: rate(self.fy, x.alpha, Channel::Fy),
            mz: rate(self.mz, x.alpha, Channel::Mz),
        }
    }

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
