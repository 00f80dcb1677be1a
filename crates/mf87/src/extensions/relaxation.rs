//! The relaxation-length extension over time: one step of the first-order lag
//! ([`relaxation_step`]), and the lag state of all three channels ([`LaggedSlip`]) that
//! [`crate::evaluate_extended`] reads and a simulation carries from step to step.

use serde::{Deserialize, Serialize};

use crate::channel::Channel;
use crate::interface::{InputVar, Inputs};
use crate::params::{Limits, Params};

/// One step of the first-order relaxation lag `d s_lag / dx = (s - s_lag) / sigma` over a
/// travelled distance `distance_m` with the slip `slip` held: exact for a constant slip.
/// `sigma_m <= 0` is no lag.
#[inline]
pub fn relaxation_step(lagged: f64, slip: f64, distance_m: f64, sigma_m: f64) -> f64 {
    if sigma_m <= 0.0 {
        slip
    } else {
        lagged + (slip - lagged) * (1.0 - (-distance_m / sigma_m).exp())
    }
}

/// Each channel's slip after its relaxation lag, in SI: slip ratio for Fx, slip angle [rad]
/// for Fy and Mz. Channels without a relaxation length ignore it.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct LaggedSlip {
    pub fx: f64,
    pub fy: f64,
    pub mz: f64,
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
        let sigma = |channel| {
            params
                .extensions
                .as_ref()
                .and_then(|e| e.channel(channel).relaxation_length_m())
                .unwrap_or(0.0)
        };
        LaggedSlip {
            fx: relaxation_step(self.fx, x.kappa, distance_m, sigma(Channel::Fx)),
            fy: relaxation_step(self.fy, x.alpha, distance_m, sigma(Channel::Fy)),
            mz: relaxation_step(self.mz, x.alpha, distance_m, sigma(Channel::Mz)),
        }
    }

    /// Each lagged slip clamped to its input's valid range.
    pub(crate) fn clamped(&self, limits: &Limits) -> LaggedSlip {
        let clamp = |v: f64, var: InputVar| {
            let (lo, hi) = var.valid_range(limits);
            v.clamp(lo, hi)
        };
        LaggedSlip {
            fx: clamp(self.fx, InputVar::Kappa),
            fy: clamp(self.fy, InputVar::Alpha),
            mz: clamp(self.mz, InputVar::Alpha),
        }
    }
}
