//! The math of each extension, and how a channel's extensions compose
//! ([`ChannelExtensions::apply_to_factors`], [`ChannelExtensions::apply_to_output`]).
//!
//! Units as in [`crate::formula`] (load kN, slip angle deg, slip percent) and the extensions'
//! units for the conditions (speed m/s, pressure kPa, temperature degC, see
//! [`crate::conditions`]). The relaxation lag is in [`super::relaxation`].

use crate::channel::Channel;
use crate::conditions::{Conditions, Nominal};
use crate::extensions::schema::{
    ChannelExtensions, CombinedSlip, InflationPressure, PlySteerConicity, RollingResistance,
    SpeedDependence, Temperature,
};
use crate::formula::{MagicFormula, channel_factors};
use crate::params::Params;
use crate::units;

/// Scale of temperature differences in the temperature effect [degC].
const TEMPERATURE_SCALE: f64 = 50.0;

/// The scales an operating condition puts on a curve: the stiffness BCD times `stiffness`
/// (s_k), the peak D times `peak` (s_d).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Scales {
    pub stiffness: f64,
    pub peak: f64,
}

impl Scales {
    /// The factor s_k / s_d on B = BCD / (C D).
    #[inline]
    pub fn on_b(self) -> f64 {
        self.stiffness / self.peak
    }

    #[inline]
    fn apply(self, mf: &mut MagicFormula) {
        mf.d *= self.peak;
        mf.b *= self.on_b();
    }
}

impl InflationPressure {
    /// At pressure `p` [kPa]: stiffness `1 + k dp`, peak `1 + d dp`, `dp = (p - p0) / p0`.
    #[inline]
    pub(crate) fn scales(&self, nominal: &Nominal, p: f64) -> Scales {
        let dp = (p - nominal.pressure_kpa) / nominal.pressure_kpa;
        Scales {
            stiffness: 1.0 + self.k * dp,
            peak: 1.0 + self.d * dp,
        }
    }
}

impl SpeedDependence {
    /// At speed `v` [m/s]: peak `1 + v dV`, `dV = (V - V0) / V0`; the stiffness stays.
    #[inline]
    pub(crate) fn scales(&self, nominal: &Nominal, v: f64) -> Scales {
        let dv = (v - nominal.speed_mps) / nominal.speed_mps;
        Scales {
            stiffness: 1.0,
            peak: 1.0 + self.v * dv,
        }
    }
}

impl Temperature {
    /// At temperature `t` [degC]: peak `1 - w ((T - T0 - Topt) / 50)^2`, stiffness
    /// `1 + k (T - T0) / 50`.
    #[inline]
    pub(crate) fn scales(&self, nominal: &Nominal, t: f64) -> Scales {
        let window = (t - self.optimum(nominal)) / TEMPERATURE_SCALE;
        let dt = (t - nominal.temperature_c) / TEMPERATURE_SCALE;
        Scales {
            stiffness: 1.0 + self.k * dt,
            peak: 1.0 - self.w * window * window,
        }
    }

    /// The temperature of the largest peak, T0 + Topt [degC].
    #[inline]
    pub(crate) fn optimum(&self, nominal: &Nominal) -> f64 {
        nominal.temperature_c + self.Topt_degC
    }
}

impl PlySteerConicity {
    /// Adds the offsets to the shifts Sh [deg] and Sv [N or N.m].
    #[inline]
    fn shift(&self, mf: &mut MagicFormula) {
        mf.sh += self.Sh_deg;
        mf.sv += self.Sv;
    }
}

impl CombinedSlip {
    /// The weight `G = cos(C atan(B s))` at the other slip `s`.
    #[inline]
    fn weight(&self, other_slip: f64) -> f64 {
        (self.C * (self.B * other_slip).atan()).cos()
    }
}

impl RollingResistance {
    /// The coefficient `q1 + q2 V / V0` at speed `v` [m/s].
    #[inline]
    pub(crate) fn coefficient(&self, nominal: &Nominal, v: f64) -> f64 {
        self.q1 + self.q2 * v / nominal.speed_mps
    }
}

impl ChannelExtensions {
    /// Applies the factor-level extensions to `mf`: pressure, speed and temperature scales,
    /// in this order, then ply steer and conicity.
    #[inline]
    pub fn apply_to_factors(&self, nominal: &Nominal, x: &Conditions, mf: &mut MagicFormula) {
        if let Some(q) = self.inflation_pressure {
            q.scales(nominal, x.pressure).apply(mf);
        }
        if let Some(q) = self.speed_dependence {
            q.scales(nominal, x.speed).apply(mf);
        }
        if let Some(q) = self.temperature {
            q.scales(nominal, x.temperature).apply(mf);
        }
        if let Some(q) = self.ply_steer_conicity {
            q.shift(mf);
        }
    }

    /// Applies the output-level extensions (weighting, then additive terms) to `y`.
    #[inline]
    pub fn apply_to_output(&self, nominal: &Nominal, x: &Conditions, y: f64) -> f64 {
        let mut y = y;
        if let Some(q) = self.combined_slip {
            y *= q.weight(x.other_slip);
        }
        if let Some(q) = self.rolling_resistance {
            y -= q.coefficient(nominal, x.speed) * units::kilonewtons_to_newtons(x.fz_kn);
        }
        y
    }

    /// The channel's output at `slip` (formula units; already lagged if it should be) with
    /// these extensions, under `x`.
    #[inline]
    pub fn evaluate(
        &self,
        params: &Params,
        channel: Channel,
        nominal: &Nominal,
        gamma_deg: f64,
        slip: f64,
        x: &Conditions,
    ) -> f64 {
        let mut mf = channel_factors(params, channel, x.fz_kn, gamma_deg);
        self.apply_to_factors(nominal, x, &mut mf);
        self.apply_to_output(nominal, x, mf.eval(slip))
    }
}
