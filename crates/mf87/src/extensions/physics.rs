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
    SlipRatioShift, SpeedDependence, Temperature,
};
use crate::formula::{MagicFormula, channel_factors};
use crate::params::Params;
use crate::real::Real;
use crate::units;

/// Scale of temperature differences in the temperature effect [degC].
const TEMPERATURE_SCALE: f64 = 50.0;

/// The scales an operating condition puts on a curve: the stiffness BCD times `stiffness`
/// (s_k), the peak D times `peak` (s_d).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Scales<T = f64> {
    pub stiffness: T,
    pub peak: T,
}

impl<T: Real> Scales<T> {
    /// The factor s_k / s_d on B = BCD / (C D).
    #[inline]
    pub fn on_b(self) -> T {
        self.stiffness / self.peak
    }

    #[inline]
    fn apply(self, mf: &mut MagicFormula<T>) {
        mf.d *= self.peak;
        mf.b *= self.on_b();
    }
}

impl<P: Copy> InflationPressure<P> {
    /// At pressure `p` [kPa]: stiffness `1 + k dp`, peak `1 + d dp`, `dp = (p - p0) / p0`.
    #[inline]
    pub(crate) fn scales<T: Real + From<P>>(&self, nominal: &Nominal, p: T) -> Scales<T> {
        let dp = (p - nominal.pressure_kpa) / nominal.pressure_kpa;
        Scales {
            stiffness: dp * T::from(self.k) + 1.0,
            peak: dp * T::from(self.d) + 1.0,
        }
    }
}

impl<P: Copy> SpeedDependence<P> {
    /// At speed `v` [m/s]: peak `1 + v dV`, `dV = (V - V0) / V0`; the stiffness stays.
    #[inline]
    pub(crate) fn scales<T: Real + From<P>>(&self, nominal: &Nominal, v: T) -> Scales<T> {
        let dv = (v - nominal.speed_mps) / nominal.speed_mps;
        Scales {
            stiffness: T::from(1.0),
            peak: dv * T::from(self.v) + 1.0,
        }
    }
}

impl<P: Copy> Temperature<P> {
    /// At temperature `t` [degC]: peak `1 - w ((T - T0 - Topt) / 50)^2`, stiffness
    /// `1 + k (T - T0) / 50`.
    #[inline]
    pub(crate) fn scales<T: Real + From<P>>(&self, nominal: &Nominal, t: T) -> Scales<T> {
        let window = (t - self.optimum::<T>(nominal)) / TEMPERATURE_SCALE;
        let dt = (t - nominal.temperature_c) / TEMPERATURE_SCALE;
        Scales {
            stiffness: dt * T::from(self.k) + 1.0,
            peak: -(window * T::from(self.w) * window) + 1.0,
        }
    }

    /// The temperature of the largest peak, T0 + Topt [degC].
    #[inline]
    pub(crate) fn optimum<T: Real + From<P>>(&self, nominal: &Nominal) -> T {
        T::from(self.Topt_degC) + nominal.temperature_c
    }
}

impl<P: Copy> PlySteerConicity<P> {
    /// Adds the offsets to the shifts Sh [deg] and Sv [N or N.m].
    #[inline]
    fn shift<T: Real + From<P>>(&self, mf: &mut MagicFormula<T>) {
        mf.sh += T::from(self.Sh_deg);
        mf.sv += T::from(self.Sv);
    }
}

impl<P: Copy> SlipRatioShift<P> {
    /// The shift `Sh + Sh_per_kN Fz` [slip ratio] at the load `fz_kn` [kN].
    #[inline]
    pub(crate) fn at_load<T: Real + From<P>>(&self, fz_kn: T) -> T {
        fz_kn * T::from(self.Sh_per_kN) + T::from(self.Sh)
    }

    /// Adds the shift at the load `fz_kn` [kN] to the horizontal shift [percent].
    #[inline]
    fn shift<T: Real + From<P>>(&self, fz_kn: T, mf: &mut MagicFormula<T>) {
        mf.sh += units::slip_ratio_to_percent(self.at_load(fz_kn));
    }
}

impl<P: Copy> CombinedSlip<P> {
    /// The weight `G = cos(C atan(B s))` at the other slip `s`.
    #[inline]
    fn weight<T: Real + From<P>>(&self, other_slip: T) -> T {
        ((other_slip * T::from(self.B)).atan() * T::from(self.C)).cos()
    }
}

impl<P: Copy> RollingResistance<P> {
    /// The coefficient `q1 + q2 V / V0` at speed `v` [m/s].
    #[inline]
    pub(crate) fn coefficient<T: Real + From<P>>(&self, nominal: &Nominal, v: T) -> T {
        v * T::from(self.q2) / nominal.speed_mps + T::from(self.q1)
    }
}

impl<P: Copy> ChannelExtensions<P> {
    /// Applies the factor-level extensions to `mf`: pressure, speed and temperature scales,
    /// in this order, then the shifts (ply steer and conicity, the slip-ratio shift).
    #[inline]
    pub fn apply_to_factors<T: Real + From<P>>(
        &self,
        nominal: &Nominal,
        x: &Conditions<T>,
        mf: &mut MagicFormula<T>,
    ) {
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
        if let Some(q) = self.slip_ratio_shift {
            q.shift(x.fz_kn, mf);
        }
    }

    /// Applies the output-level extensions (weighting, then additive terms) to `y`.
    #[inline]
    pub fn apply_to_output<T: Real + From<P>>(
        &self,
        nominal: &Nominal,
        x: &Conditions<T>,
        y: T,
    ) -> T {
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
    /// these extensions, under `x`, from the channel's factors `mf` at load and camber.
    #[inline]
    pub fn evaluate_factors<T: Real + From<P>>(
        &self,
        mut mf: MagicFormula<T>,
        nominal: &Nominal,
        slip: T,
        x: &Conditions<T>,
    ) -> T {
        self.apply_to_factors(nominal, x, &mut mf);
        self.apply_to_output(nominal, x, mf.eval(slip))
    }
}

impl ChannelExtensions {
    /// The channel's output at `slip` (formula units; already lagged if it should be) with
    /// these extensions, under `x`.
    #[inline]
    pub fn evaluate<T: Real>(
        &self,
        params: &Params,
        channel: Channel,
        nominal: &Nominal,
        gamma_deg: T,
        slip: T,
        x: &Conditions<T>,
    ) -> T {
        let mf = channel_factors(params, channel, x.fz_kn, gamma_deg);
        self.evaluate_factors(mf, nominal, slip, x)
    }
}
