//! Extensions of the 1987 model in the forms tire-gap fits them: combined-slip weighting,
//! relaxation length, inflation pressure, speed, ply steer and conicity, rolling resistance
//! and tread temperature. Each channel has its own set, with its own parameters, expressed
//! around nominal (reference) conditions.
//!
//! Units inside, as in [`crate::formula`]: load kN, slip angle deg, slip percent; besides
//! these speed m/s, pressure kPa, temperature degC, and the other slip of combined slip in SI
//! (slip ratio for Fy and Mz, slip angle in rad for Fx). [`evaluate_extended`] is the SI
//! entry point.
//!
//! The extensions of a channel compose in one fixed order, whatever order they were added in:
//! 1. factors: inflation pressure, speed and temperature scale the peak D and the stiffness
//!    BCD; ply steer and conicity add to the shifts Sh and Sv;
//! 2. the Magic Formula at the channel's slip, lagged if the channel has a relaxation length;
//! 3. output: the combined-slip weighting multiplies it, then rolling resistance is subtracted.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::bounds;
use crate::channel::Channel;
use crate::error::{Num, ParamError, invalid};
use crate::evaluate::{LIFTED_WHEEL_LOAD_KN, evaluate};
use crate::formula::{MagicFormula, channel_factors};
use crate::interface::{InputVar, Inputs, Outputs, SignConvention, oriented};
use crate::params::{Limits, Params};
use crate::units;

/// Scale of temperature differences in the temperature effect [degC].
const TEMPERATURE_SCALE: f64 = 50.0;

/// Generates, from one list, the kinds of extension ([`Extension`]), one parameter struct per
/// kind (serde, field names = parameter names) and [`ChannelExtensions`] with one optional
/// field per kind (field name = the kind's id in parameter files).
macro_rules! extensions {
    ($( $(#[$doc:meta])* $kind:ident = $id:ident { $($param:ident),+ } ),+ $(,)?) => {
        /// A kind of extension.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Extension { $($(#[$doc])* $kind),+ }

        impl Extension {
            /// Every kind, in parameter-file order.
            pub const ALL: &'static [Extension] = &[$(Extension::$kind),+];

            /// The name in parameter files and reports, e.g. `combined_slip`.
            pub fn id(self) -> &'static str {
                match self { $(Extension::$kind => stringify!($id)),+ }
            }

            /// Parameter names, in order.
            pub fn parameter_names(self) -> &'static [&'static str] {
                match self { $(Extension::$kind => &[$(stringify!($param)),+]),+ }
            }
        }

        $(
            $(#[$doc])*
            #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
            #[serde(deny_unknown_fields)]
            #[allow(non_snake_case)]
            pub struct $kind { $(pub $param: f64),+ }
        )+

        /// The extensions of one channel, each kind at most once; an absent kind is not applied.
        #[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct ChannelExtensions {
            $(
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $id: Option<$kind>,
            )+
        }

        impl ChannelExtensions {
            /// Whether `kind` is present.
            pub fn has(&self, kind: Extension) -> bool {
                match kind { $(Extension::$kind => self.$id.is_some()),+ }
            }

            /// The parameters of `kind` in [`Extension::parameter_names`] order, if present.
            pub fn get(&self, kind: Extension) -> Option<Vec<f64>> {
                match kind { $(Extension::$kind => self.$id.map(|p| vec![$(p.$param),+])),+ }
            }

            /// Adds (or replaces) `kind` with `values` in [`Extension::parameter_names`] order.
            pub fn set(&mut self, kind: Extension, values: &[f64]) -> Result<(), ParamError> {
                let names = kind.parameter_names();
                if values.len() != names.len() {
                    return Err(ParamError::Format(format!(
                        "{} takes {} parameters ({}), not {}",
                        kind.id(),
                        names.len(),
                        names.join(", "),
                        values.len()
                    )));
                }
                let mut next = values.iter().copied();
                match kind {
                    $(Extension::$kind => {
                        self.$id = Some($kind { $($param: next.next().unwrap_or(f64::NAN)),+ })
                    })+
                }
                Ok(())
            }
        }
    };
}

extensions! {
    /// Combined slip: the output weighted by `G = cos(C atan(B s))` of the other slip s (slip
    /// ratio for Fy and Mz, slip angle [rad] for Fx).
    CombinedSlip = combined_slip { B, C },
    /// First-order lag of the channel's slip over travelled distance, relaxation length
    /// `sigma_m` [m] (0: no lag).
    RelaxationLength = relaxation_length { sigma_m },
    /// Stiffness BCD times `1 + k dp`, peak D times `1 + d dp`, `dp = (p - p0) / p0`.
    InflationPressure = inflation_pressure { k, d },
    /// Peak D times `1 + v dV`, `dV = (V - V0) / V0`.
    SpeedDependence = speed_dependence { v },
    /// Shifts at zero slip and camber: `Sh += Sh_deg` [deg], `Sv += Sv` [N or N.m] (Fy, Mz).
    PlySteerConicity = ply_steer_conicity { Sh_deg, Sv },
    /// `Fx - (q1 + q2 V / V0) Fz` [N] (Fx only).
    RollingResistance = rolling_resistance { q1, q2 },
    /// Peak D times `1 - w ((T - T0 - Topt_degC) / 50)^2`, stiffness BCD times
    /// `1 + k (T - T0) / 50` (T in degC).
    Temperature = temperature { w, Topt_degC, k },
}

impl Extension {
    /// Whether the kind may be used on a channel.
    pub fn applies_to(self, channel: Channel) -> bool {
        match self {
            Extension::PlySteerConicity => channel != Channel::Fx,
            Extension::RollingResistance => channel == Channel::Fx,
            _ => true,
        }
    }

    /// The operating condition the kind depends on, if any.
    pub fn condition(self) -> Option<ConditionVar> {
        match self {
            Extension::InflationPressure => Some(ConditionVar::Pressure),
            Extension::SpeedDependence | Extension::RollingResistance => Some(ConditionVar::Speed),
            Extension::Temperature => Some(ConditionVar::Temperature),
            Extension::CombinedSlip | Extension::RelaxationLength | Extension::PlySteerConicity => {
                None
            }
        }
    }
}

impl fmt::Display for Extension {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())
    }
}

/// Reference conditions p0, V0, T0 the extensions are expressed around.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Nominal {
    /// Pressure p0 [kPa].
    #[serde(rename = "pressure_kPa")]
    pub pressure_kpa: f64,
    /// Speed V0 [m/s].
    pub speed_mps: f64,
    /// Temperature T0 [degC].
    #[serde(rename = "temperature_degC")]
    pub temperature_c: f64,
}

/// The range of operating conditions the extensions are validated over and used in; the
/// conditions are clamped to it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct ConditionLimits {
    /// Forward speed |vx| [m/s].
    pub speed_min_mps: f64,
    pub speed_max_mps: f64,
    /// Inflation pressure [kPa].
    pub pressure_min_kPa: f64,
    pub pressure_max_kPa: f64,
    /// Tread temperature [degC].
    pub temperature_min_degC: f64,
    pub temperature_max_degC: f64,
}

impl Default for ConditionLimits {
    /// When a parameter file gives none: a passenger-car tire's range.
    fn default() -> Self {
        ConditionLimits {
            speed_min_mps: 0.0,
            speed_max_mps: 70.0,
            pressure_min_kPa: 100.0,
            pressure_max_kPa: 400.0,
            temperature_min_degC: -20.0,
            temperature_max_degC: 120.0,
        }
    }
}

/// The conditions of one evaluation, in the units the extensions work in.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Conditions {
    /// Load [kN].
    pub fz_kn: f64,
    /// The other slip: slip ratio for Fy and Mz, slip angle [rad] for Fx.
    pub other_slip: f64,
    /// Speed [m/s].
    pub speed: f64,
    /// Pressure [kPa].
    pub pressure: f64,
    /// Temperature [degC].
    pub temperature: f64,
}

impl ChannelExtensions {
    pub fn is_empty(&self) -> bool {
        *self == ChannelExtensions::default()
    }

    /// The kinds present, in [`Extension::ALL`] order.
    pub fn kinds(&self) -> impl Iterator<Item = Extension> + '_ {
        Extension::ALL.iter().copied().filter(|k| self.has(*k))
    }

    /// The relaxation length [m], if the channel has one.
    pub fn relaxation_length_m(&self) -> Option<f64> {
        self.relaxation_length.map(|r| r.sigma_m)
    }

    /// Applies the factor-level extensions to `mf`.
    #[inline]
    pub fn apply_to_factors(&self, nominal: &Nominal, x: &Conditions, mf: &mut MagicFormula) {
        // Scaling the peak D by s_d and the stiffness BCD by s_k: B = BCD / (C D) scales by s_k / s_d.
        let mut scale = |s_k: f64, s_d: f64| {
            mf.d *= s_d;
            mf.b *= s_k / s_d;
        };
        if let Some(q) = self.inflation_pressure {
            let dp = (x.pressure - nominal.pressure_kpa) / nominal.pressure_kpa;
            scale(1.0 + q.k * dp, 1.0 + q.d * dp);
        }
        if let Some(q) = self.speed_dependence {
            let dv = (x.speed - nominal.speed_mps) / nominal.speed_mps;
            scale(1.0, 1.0 + q.v * dv);
        }
        if let Some(q) = self.temperature {
            let window =
                (x.temperature - (nominal.temperature_c + q.Topt_degC)) / TEMPERATURE_SCALE;
            let dt = (x.temperature - nominal.temperature_c) / TEMPERATURE_SCALE;
            scale(1.0 + q.k * dt, 1.0 - q.w * window * window);
        }
        if let Some(q) = self.ply_steer_conicity {
            mf.sh += q.Sh_deg;
            mf.sv += q.Sv;
        }
    }

    /// Applies the output-level extensions (weighting, then additive terms) to `y`.
    #[inline]
    pub fn apply_to_output(&self, nominal: &Nominal, x: &Conditions, y: f64) -> f64 {
        let mut y = y;
        if let Some(q) = self.combined_slip {
            y *= (q.C * (q.B * x.other_slip).atan()).cos();
        }
        if let Some(q) = self.rolling_resistance {
            y -= (q.q1 + q.q2 * x.speed / nominal.speed_mps)
                * units::kilonewtons_to_newtons(x.fz_kn);
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

/// The extensions of all three channels with their nominal conditions and range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Extensions {
    pub nominal: Nominal,
    /// Absent from a file: [`ConditionLimits::default`].
    #[serde(default)]
    pub limits: ConditionLimits,
    #[serde(default, skip_serializing_if = "ChannelExtensions::is_empty")]
    pub Fy: ChannelExtensions,
    #[serde(default, skip_serializing_if = "ChannelExtensions::is_empty")]
    pub Mz: ChannelExtensions,
    #[serde(default, skip_serializing_if = "ChannelExtensions::is_empty")]
    pub Fx: ChannelExtensions,
}

impl Extensions {
    /// No extension on any channel yet.
    pub fn new(nominal: Nominal, limits: ConditionLimits) -> Extensions {
        Extensions {
            nominal,
            limits,
            Fy: ChannelExtensions::default(),
            Mz: ChannelExtensions::default(),
            Fx: ChannelExtensions::default(),
        }
    }

    pub fn channel(&self, channel: Channel) -> &ChannelExtensions {
        match channel {
            Channel::Fy => &self.Fy,
            Channel::Mz => &self.Mz,
            Channel::Fx => &self.Fx,
        }
    }

    pub fn channel_mut(&mut self, channel: Channel) -> &mut ChannelExtensions {
        match channel {
            Channel::Fy => &mut self.Fy,
            Channel::Mz => &mut self.Mz,
            Channel::Fx => &mut self.Fx,
        }
    }

    /// Whether no channel has any extension.
    pub fn is_empty(&self) -> bool {
        Channel::ALL.iter().all(|c| self.channel(*c).is_empty())
    }

    /// Whether some channel has a relaxation length (the lag is then state).
    pub fn has_relaxation(&self) -> bool {
        Channel::ALL
            .iter()
            .any(|c| self.channel(*c).relaxation_length.is_some())
    }

    /// Whether some extension depends on `condition`.
    pub fn uses(&self, condition: ConditionVar) -> bool {
        Channel::ALL.iter().any(|c| {
            self.channel(*c)
                .kinds()
                .any(|k| k.condition() == Some(condition))
        })
    }

    /// Checks the extensions' own values against [`crate::bounds`]: nominal conditions and
    /// their range, every parameter finite and within its bound, and each peak or stiffness
    /// scale within [`bounds::CONDITION_SCALE`] over its condition's range. What depends on
    /// the base coefficients too (the scaled peak and B, the total shifts) is checked by
    /// [`Params::validate`].
    pub fn validate(&self) -> Result<(), ParamError> {
        self.validate_specific()?;
        self.validate_magnitudes()
    }

    /// Every bound but the general cap on magnitudes ([`Self::validate_magnitudes`]), which
    /// comes last so that a value is named with the bound that means something for it.
    pub(crate) fn validate_specific(&self) -> Result<(), ParamError> {
        self.validate_nominal()?;
        self.validate_limits()?;
        for channel in Channel::ALL {
            self.validate_channel(channel)?;
        }
        Ok(())
    }

    /// Every parameter within [`bounds::EXTENSION_PARAMETER_ABS_MAX`] in magnitude.
    pub(crate) fn validate_magnitudes(&self) -> Result<(), ParamError> {
        for channel in Channel::ALL {
            let ext = self.channel(channel);
            for kind in ext.kinds() {
                let values = ext.get(kind).unwrap_or_default();
                for (name, v) in kind.parameter_names().iter().zip(values) {
                    if v.abs() > bounds::EXTENSION_PARAMETER_ABS_MAX {
                        return Err(invalid(
                            &format!("extensions.{channel}.{kind}.{name}"),
                            v,
                            &format!(
                                "must lie within +-{} (an extension parameter)",
                                bounds::EXTENSION_PARAMETER_ABS_MAX
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    fn validate_nominal(&self) -> Result<(), ParamError> {
        let n = &self.nominal;
        for (name, value, allowed, unit) in [
            ("pressure_kPa", n.pressure_kpa, bounds::PRESSURE_KPA, "kPa"),
            ("speed_mps", n.speed_mps, bounds::NOMINAL_SPEED_MPS, "m/s"),
            (
                "temperature_degC",
                n.temperature_c,
                bounds::TEMPERATURE_DEGC,
                "degC",
            ),
        ] {
            if !allowed.contains(value) {
                return Err(invalid(
                    &format!("extensions.nominal.{name}"),
                    value,
                    &format!("the nominal condition must lie in {allowed} {unit}"),
                ));
            }
        }
        Ok(())
    }

    fn validate_limits(&self) -> Result<(), ParamError> {
        let l = &self.limits;
        for (what, (min_name, min), (max_name, max), allowed, unit) in [
            (
                "speed",
                ("speed_min_mps", l.speed_min_mps),
                ("speed_max_mps", l.speed_max_mps),
                bounds::SPEED_MPS,
                "m/s",
            ),
            (
                "pressure",
                ("pressure_min_kPa", l.pressure_min_kPa),
                ("pressure_max_kPa", l.pressure_max_kPa),
                bounds::PRESSURE_KPA,
                "kPa",
            ),
            (
                "temperature",
                ("temperature_min_degC", l.temperature_min_degC),
                ("temperature_max_degC", l.temperature_max_degC),
                bounds::TEMPERATURE_DEGC,
                "degC",
            ),
        ] {
            for (name, value) in [(min_name, min), (max_name, max)] {
                if !allowed.contains(value) {
                    return Err(invalid(
                        &format!("extensions.limits.{name}"),
                        value,
                        &format!("a limit of the {what} must lie in {allowed} {unit}"),
                    ));
                }
            }
            if max < min {
                return Err(invalid(
                    &format!("extensions.limits.{max_name}"),
                    max,
                    &format!("the highest {what} must be >= {min_name} = {min}"),
                ));
            }
        }
        Ok(())
    }

    fn validate_channel(&self, channel: Channel) -> Result<(), ParamError> {
        let ext = self.channel(channel);
        for kind in ext.kinds() {
            let values = ext.get(kind).unwrap_or_default();
            let names = kind.parameter_names();
            let name = |i: usize| format!("extensions.{channel}.{kind}.{}", names[i]);
            if !kind.applies_to(channel) {
                let on: Vec<&str> = Channel::ALL
                    .iter()
                    .filter(|c| kind.applies_to(**c))
                    .map(|c| c.name())
                    .collect();
                return Err(invalid(
                    &name(0),
                    values[0],
                    &format!(
                        "{kind} does not apply to {channel} (only to {})",
                        on.join(", ")
                    ),
                ));
            }
            for (i, v) in values.iter().enumerate() {
                if !v.is_finite() {
                    return Err(invalid(&name(i), *v, "must be a finite number"));
                }
            }
        }
        let prefix = format!("extensions.{channel}");
        if let Some(r) = ext.relaxation_length
            && !bounds::RELAXATION_LENGTH_M.contains(r.sigma_m)
        {
            return Err(invalid(
                &format!("{prefix}.relaxation_length.sigma_m"),
                r.sigma_m,
                &format!(
                    "the relaxation length must lie in {} m (0: no lag)",
                    bounds::RELAXATION_LENGTH_M
                ),
            ));
        }
        if let Some(q) = ext.combined_slip {
            self.validate_combined_slip(channel, q)?;
        }
        if let Some(q) = ext.rolling_resistance {
            self.validate_rolling_resistance(channel, q)?;
        }
        if let Some(q) = ext.temperature {
            let optimum = self.nominal.temperature_c + q.Topt_degC;
            if !bounds::TEMPERATURE_DEGC.contains(optimum) {
                return Err(invalid(
                    &format!("{prefix}.temperature.Topt_degC"),
                    q.Topt_degC,
                    &format!(
                        "the optimum temperature T0 + Topt_degC = {optimum} degC must lie in {} degC",
                        bounds::TEMPERATURE_DEGC
                    ),
                ));
            }
        }
        for scales in self.scale_extremes(channel) {
            scales.check(channel, &self.limits)?;
        }
        Ok(())
    }

    /// G = cos(C atan(B s)) over the other slip's range: |B| bounded and the phase
    /// |C| atan(|B| s_max) too, so that G changes sign only a few times.
    fn validate_combined_slip(&self, channel: Channel, q: CombinedSlip) -> Result<(), ParamError> {
        let name = |p: &str| format!("extensions.{channel}.combined_slip.{p}");
        if q.B.abs() > bounds::COMBINED_SLIP_B_ABS_MAX {
            return Err(invalid(
                &name("B"),
                q.B,
                &format!("|B| must be <= {}", bounds::COMBINED_SLIP_B_ABS_MAX),
            ));
        }
        let (s_max, s_name) = match channel {
            Channel::Fx => (std::f64::consts::FRAC_PI_2, "|alpha| <= pi/2 rad"),
            Channel::Fy | Channel::Mz => (1.0, "|kappa| <= 1"),
        };
        let phase = q.C.abs() * (q.B.abs() * s_max).atan();
        if phase.is_nan() || phase > bounds::COMBINED_SLIP_PHASE_MAX {
            return Err(invalid(
                &name("C"),
                q.C,
                &format!(
                    "the phase |C| atan(|B| s) of G = cos(C atan(B s)) reaches {phase} rad over \
                     {s_name} (B = {}); it must stay <= 8 pi = {} rad",
                    Num(q.B),
                    bounds::COMBINED_SLIP_PHASE_MAX,
                    phase = Num(phase)
                ),
            ));
        }
        Ok(())
    }

    /// The coefficient q1 + q2 |vx| / V0 (linear in speed) at both ends of the speed range.
    fn validate_rolling_resistance(
        &self,
        channel: Channel,
        q: RollingResistance,
    ) -> Result<(), ParamError> {
        let (lo, hi) = (self.limits.speed_min_mps, self.limits.speed_max_mps);
        for (speed, parameter, value) in [(lo, "q1", q.q1), (hi, "q2", q.q2)] {
            let f = q.q1 + q.q2 * speed / self.nominal.speed_mps;
            if !bounds::ROLLING_RESISTANCE.contains(f) {
                return Err(invalid(
                    &format!("extensions.{channel}.rolling_resistance.{parameter}"),
                    value,
                    &format!(
                        "the rolling-resistance coefficient q1 + q2 |vx| / V0 is {f} at |vx| = {speed} m/s \
                         (q1 = {}, q2 = {}, V0 = {} m/s); it must lie in {} over the speed range [{lo}, {hi}] m/s",
                        Num(q.q1),
                        Num(q.q2),
                        self.nominal.speed_mps,
                        bounds::ROLLING_RESISTANCE,
                        f = Num(f)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The smallest and largest peak and stiffness scales of each scaling extension of
    /// `channel` over its condition's range, and of the factor s_k / s_d they put on B.
    pub(crate) fn scale_extremes(&self, channel: Channel) -> Vec<ScaleExtremes> {
        let ext = self.channel(channel);
        let scaling = [
            (
                Extension::InflationPressure,
                ext.inflation_pressure
                    .map(|q| (Some(("k", q.k)), ("d", q.d))),
            ),
            (
                Extension::SpeedDependence,
                ext.speed_dependence.map(|q| (None, ("v", q.v))),
            ),
            (
                Extension::Temperature,
                ext.temperature.map(|q| (Some(("k", q.k)), ("w", q.w))),
            ),
        ];
        let mut out = Vec::new();
        for (kind, parameters) in scaling {
            let (Some((stiffness, peak)), Some(condition)) = (parameters, kind.condition()) else {
                continue;
            };
            let mut alone = ChannelExtensions::default();
            if alone.set(kind, &ext.get(kind).unwrap_or_default()).is_err() {
                continue;
            }
            let (lo, hi) = self.limits.in_extension_units(condition);
            // The ends, the temperature window's vertex, and points between for the ratio.
            let mut points: Vec<f64> = (0..=SCALE_SAMPLES)
                .map(|i| lo + (hi - lo) * i as f64 / SCALE_SAMPLES as f64)
                .collect();
            if let Some(q) = ext.temperature.filter(|_| kind == Extension::Temperature) {
                let vertex = self.nominal.temperature_c + q.Topt_degC;
                if lo < vertex && vertex < hi {
                    points.push(vertex);
                }
            }
            let mut e = ScaleExtremes {
                kind,
                condition,
                peak_parameter: peak,
                stiffness_parameter: stiffness,
                peak: Extremes::new(),
                stiffness: Extremes::new(),
                ratio: Extremes::new(),
            };
            for at in points {
                let mut x = Conditions {
                    fz_kn: 1.0,
                    other_slip: 0.0,
                    speed: self.nominal.speed_mps,
                    pressure: self.nominal.pressure_kpa,
                    temperature: self.nominal.temperature_c,
                };
                *x.condition_mut(condition) = at;
                let mut mf = MagicFormula {
                    b: 1.0,
                    c: 1.0,
                    d: 1.0,
                    e: 0.0,
                    sh: 0.0,
                    sv: 0.0,
                };
                alone.apply_to_factors(&self.nominal, &x, &mut mf);
                e.peak.add(mf.d, at);
                e.stiffness.add(mf.b * mf.d, at);
                e.ratio.add(mf.b, at);
            }
            out.push(e);
        }
        out
    }
}

/// Points of a condition's range at which the scales are evaluated (besides the vertex of
/// the temperature window): the peak and stiffness scales are linear or quadratic (exact at
/// the ends and vertex), their ratio on B is sampled.
const SCALE_SAMPLES: usize = 64;

/// The smallest and largest value seen, and where.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Extremes {
    pub min: f64,
    pub min_at: f64,
    pub max: f64,
    pub max_at: f64,
}

impl Extremes {
    fn new() -> Extremes {
        Extremes {
            min: f64::INFINITY,
            min_at: f64::NAN,
            max: f64::NEG_INFINITY,
            max_at: f64::NAN,
        }
    }

    fn add(&mut self, value: f64, at: f64) {
        // A NaN becomes both extremes, so that every check fails on it.
        if value.is_nan() || value < self.min {
            (self.min, self.min_at) = (value, at);
        }
        if value.is_nan() || value > self.max {
            (self.max, self.max_at) = (value, at);
        }
    }
}

/// How a scaling extension's scales range over its condition.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ScaleExtremes {
    pub kind: Extension,
    pub condition: ConditionVar,
    /// The parameter of the peak scale, and of the stiffness scale if it has one.
    pub peak_parameter: (&'static str, f64),
    pub stiffness_parameter: Option<(&'static str, f64)>,
    /// Of the peak scale s_d, the stiffness scale s_k, and s_k / s_d (the factor on B).
    pub peak: Extremes,
    pub stiffness: Extremes,
    pub ratio: Extremes,
}

impl ScaleExtremes {
    /// Each scale within [`bounds::CONDITION_SCALE`].
    fn check(&self, channel: Channel, limits: &ConditionLimits) -> Result<(), ParamError> {
        let (symbol, unit) = self.condition.extension_symbol_and_unit();
        let (lo, hi) = limits.in_extension_units(self.condition);
        let kind = self.kind;
        for (scale, parameter, what) in [
            (&self.peak, Some(self.peak_parameter), "peak D"),
            (&self.stiffness, self.stiffness_parameter, "stiffness BCD"),
        ] {
            let Some((name, value)) = parameter else {
                continue;
            };
            for (s, at) in [(scale.min, scale.min_at), (scale.max, scale.max_at)] {
                if !bounds::CONDITION_SCALE.contains(s) {
                    return Err(invalid(
                        &format!("extensions.{channel}.{kind}.{name}"),
                        value,
                        &format!(
                            "the scale of the {what} is {s} at {symbol} = {at} {unit}; it must stay \
                             within {} over the range [{lo}, {hi}] {unit} (extensions.limits)",
                            bounds::CONDITION_SCALE,
                            s = Num(s)
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The parameter to name when B leaves its bounds through this scale (the stiffness
    /// scale's, else the peak's).
    pub fn b_parameter(&self) -> (&'static str, f64) {
        self.stiffness_parameter.unwrap_or(self.peak_parameter)
    }

    /// Where the condition is, for messages: e.g. `p = 400 kPa`.
    pub fn at(&self, value: f64) -> String {
        let (symbol, unit) = self.condition.extension_symbol_and_unit();
        format!("{symbol} = {value} {unit}")
    }
}

impl ConditionLimits {
    /// The range of `condition` in the extensions' units (m/s, kPa, degC).
    pub fn in_extension_units(&self, condition: ConditionVar) -> (f64, f64) {
        match condition {
            ConditionVar::Speed => (self.speed_min_mps, self.speed_max_mps),
            ConditionVar::Pressure => (self.pressure_min_kPa, self.pressure_max_kPa),
            ConditionVar::Temperature => (self.temperature_min_degC, self.temperature_max_degC),
        }
    }
}

impl Conditions {
    fn condition_mut(&mut self, condition: ConditionVar) -> &mut f64 {
        match condition {
            ConditionVar::Speed => &mut self.speed,
            ConditionVar::Pressure => &mut self.pressure,
            ConditionVar::Temperature => &mut self.temperature,
        }
    }
}

impl fmt::Display for Extensions {
    /// One line: each channel's extensions with their parameters, the nominal and the range.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut channels = Vec::new();
        for channel in Channel::ALL {
            let ext = self.channel(channel);
            let kinds: Vec<String> = ext
                .kinds()
                .map(|k| {
                    let values = ext.get(k).unwrap_or_default();
                    let params: Vec<String> = k
                        .parameter_names()
                        .iter()
                        .zip(values)
                        .map(|(n, v)| format!("{n} = {v}"))
                        .collect();
                    format!("{k} ({})", params.join(", "))
                })
                .collect();
            if !kinds.is_empty() {
                channels.push(format!("{channel}: {}", kinds.join(", ")));
            }
        }
        if channels.is_empty() {
            channels.push("none".into());
        }
        let (n, l) = (&self.nominal, &self.limits);
        write!(
            f,
            "{}; nominal p0 = {} kPa, V0 = {} m/s, T0 = {} degC; conditions clamped to |vx| in [{}, {}] m/s, \
             p in [{}, {}] kPa, T in [{}, {}] degC",
            channels.join("; "),
            n.pressure_kpa,
            n.speed_mps,
            n.temperature_c,
            l.speed_min_mps,
            l.speed_max_mps,
            l.pressure_min_kPa,
            l.pressure_max_kPa,
            l.temperature_min_degC,
            l.temperature_max_degC
        )
    }
}

/// An operating condition the extensions may depend on: an input of the FMU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConditionVar {
    /// Forward speed vx [m/s]; the extensions use |vx|.
    Speed,
    /// Inflation pressure p [Pa].
    Pressure,
    /// Tread temperature [K].
    Temperature,
}

impl ConditionVar {
    pub const ALL: [ConditionVar; 3] = [
        ConditionVar::Speed,
        ConditionVar::Pressure,
        ConditionVar::Temperature,
    ];

    /// The variable's interface name.
    pub fn name(self) -> &'static str {
        match self {
            ConditionVar::Speed => "vx",
            ConditionVar::Pressure => "p",
            ConditionVar::Temperature => "T_tread",
        }
    }

    pub fn from_name(name: &str) -> Option<ConditionVar> {
        ConditionVar::ALL.into_iter().find(|v| v.name() == name)
    }

    /// The range [lo, hi] in SI units (m/s, Pa, K) of the value the extensions use: of |vx|
    /// for the speed.
    pub fn valid_range(self, limits: &ConditionLimits) -> (f64, f64) {
        let (lo, hi) = limits.in_extension_units(self);
        let to_si: fn(f64) -> f64 = match self {
            ConditionVar::Speed => |v| v,
            ConditionVar::Pressure => units::kilopascals_to_pascals,
            ConditionVar::Temperature => units::celsius_to_kelvin,
        };
        (to_si(lo), to_si(hi))
    }

    /// Symbol and unit in the extensions' forms and messages.
    fn extension_symbol_and_unit(self) -> (&'static str, &'static str) {
        match self {
            ConditionVar::Speed => ("V", "m/s"),
            ConditionVar::Pressure => ("p", "kPa"),
            ConditionVar::Temperature => ("T", "degC"),
        }
    }

    /// Whether the extensions use an input `value` as it is (|vx| for the speed).
    pub fn in_range(self, value: f64, limits: &ConditionLimits) -> bool {
        let (lo, hi) = self.valid_range(limits);
        let used = match self {
            ConditionVar::Speed => value.abs(),
            ConditionVar::Pressure | ConditionVar::Temperature => value,
        };
        (lo..=hi).contains(&used)
    }

    /// The SI value the extensions use for an input `value`: |vx| for the speed, clamped to
    /// the range.
    pub fn used_value(self, value: f64, limits: &ConditionLimits) -> f64 {
        let (lo, hi) = self.valid_range(limits);
        match self {
            ConditionVar::Speed => value.abs().clamp(lo, hi),
            ConditionVar::Pressure | ConditionVar::Temperature => value.clamp(lo, hi),
        }
    }
}

/// The operating conditions in SI units, as the FMU's inputs. Only extensions use them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OperatingConditions {
    /// Forward speed [m/s].
    pub vx: f64,
    /// Inflation pressure [Pa].
    pub p: f64,
    /// Tread temperature [K].
    pub t_tread: f64,
}

impl OperatingConditions {
    pub fn get(&self, var: ConditionVar) -> f64 {
        match var {
            ConditionVar::Speed => self.vx,
            ConditionVar::Pressure => self.p,
            ConditionVar::Temperature => self.t_tread,
        }
    }

    pub fn set(&mut self, var: ConditionVar, value: f64) {
        match var {
            ConditionVar::Speed => self.vx = value,
            ConditionVar::Pressure => self.p = value,
            ConditionVar::Temperature => self.t_tread = value,
        }
    }

    /// The conditions as the extensions see them (clamped, in m/s, kPa, degC).
    fn in_extension_units(
        &self,
        limits: &ConditionLimits,
        fz_kn: f64,
        other_slip: f64,
    ) -> Conditions {
        let used = |var| self.used_value_of(var, limits);
        Conditions {
            fz_kn,
            other_slip,
            speed: used(ConditionVar::Speed),
            pressure: units::pascals_to_kilopascals(used(ConditionVar::Pressure)),
            temperature: units::kelvin_to_celsius(used(ConditionVar::Temperature)),
        }
    }

    fn used_value_of(&self, var: ConditionVar, limits: &ConditionLimits) -> f64 {
        var.used_value(self.get(var), limits)
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

    fn clamped(&self, limits: &Limits) -> LaggedSlip {
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

/// Fx, Fy, Mz with the parameter set's extensions, for SI inputs (clamped to their valid
/// ranges), SI operating conditions (clamped to the extensions' range) and the lagged slips.
/// Without extensions this is [`crate::evaluate`].
pub fn evaluate_extended(
    params: &Params,
    inputs: &Inputs,
    conditions: &OperatingConditions,
    lagged: &LaggedSlip,
    convention: SignConvention,
) -> Outputs {
    let Some(ext) = &params.extensions else {
        return evaluate(params, inputs, convention);
    };
    let x = inputs.clamped(&params.limits);
    let fz_kn = units::newtons_to_kilonewtons(x.fz);
    if fz_kn <= LIFTED_WHEEL_LOAD_KN {
        return Outputs::default();
    }
    let lagged = lagged.clamped(&params.limits);
    let gamma_deg = units::radians_to_degrees(x.gamma);
    // Each channel's own slip: lagged if it has a relaxation length.
    let own =
        |channel: Channel, input: f64, lagged: f64| match ext.channel(channel).relaxation_length {
            Some(_) => lagged,
            None => input,
        };
    // Combined slip weights Fy and Mz by the slip ratio, Fx by the slip angle.
    let lateral = conditions.in_extension_units(&ext.limits, fz_kn, x.kappa);
    let longitudinal = conditions.in_extension_units(&ext.limits, fz_kn, x.alpha);
    let fy = ext.Fy.evaluate(
        params,
        Channel::Fy,
        &ext.nominal,
        gamma_deg,
        units::radians_to_degrees(own(Channel::Fy, x.alpha, lagged.fy)),
        &lateral,
    );
    let mz = ext.Mz.evaluate(
        params,
        Channel::Mz,
        &ext.nominal,
        gamma_deg,
        units::radians_to_degrees(own(Channel::Mz, x.alpha, lagged.mz)),
        &lateral,
    );
    let fx = ext.Fx.evaluate(
        params,
        Channel::Fx,
        &ext.nominal,
        0.0,
        units::slip_ratio_to_percent(own(Channel::Fx, x.kappa, lagged.fx)),
        &longitudinal,
    );
    oriented(Outputs { fx, fy, mz }, convention)
}

#[cfg(test)]
mod tests {
    use super::*;

    const NOMINAL: Nominal = Nominal {
        pressure_kpa: 200.0,
        speed_mps: 10.0,
        temperature_c: 40.0,
    };

    /// The paper's table with `kind` = `values` on `channel`.
    fn with(channel: Channel, kind: Extension, values: &[f64]) -> Params {
        let mut p = Params::paper_table();
        let mut ext = Extensions::new(NOMINAL, ConditionLimits::default());
        ext.channel_mut(channel).set(kind, values).unwrap();
        p.extensions = Some(ext);
        p
    }

    fn inputs(fz: f64, alpha_deg: f64, kappa: f64, gamma_deg: f64) -> Inputs {
        Inputs {
            fz,
            alpha: alpha_deg.to_radians(),
            kappa,
            gamma: gamma_deg.to_radians(),
        }
    }

    /// vx [m/s], p [kPa], T [degC] as the SI conditions.
    fn conditions(vx: f64, p_kpa: f64, t_c: f64) -> OperatingConditions {
        OperatingConditions {
            vx,
            p: units::kilopascals_to_pascals(p_kpa),
            t_tread: units::celsius_to_kelvin(t_c),
        }
    }

    fn extended(p: &Params, x: &Inputs, c: &OperatingConditions) -> Outputs {
        evaluate_extended(p, x, c, &LaggedSlip::steady(p, x), SignConvention::Paper)
    }

    fn base(p: &Params, x: &Inputs) -> Outputs {
        evaluate(p, x, SignConvention::Paper)
    }

    fn rel_close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-9)
    }

    fn of(o: &Outputs, channel: Channel) -> f64 {
        match channel {
            Channel::Fx => o.fx,
            Channel::Fy => o.fy,
            Channel::Mz => o.mz,
        }
    }

    #[test]
    fn neutral_parameters_change_nothing() {
        let mut p = Params::paper_table();
        let mut ext = Extensions::new(NOMINAL, ConditionLimits::default());
        for channel in Channel::ALL {
            let e = ext.channel_mut(channel);
            e.combined_slip = Some(CombinedSlip { B: 8.0, C: 0.0 });
            e.relaxation_length = Some(RelaxationLength { sigma_m: 0.0 });
            e.inflation_pressure = Some(InflationPressure { k: 0.0, d: 0.0 });
            e.speed_dependence = Some(SpeedDependence { v: 0.0 });
            e.temperature = Some(Temperature {
                w: 0.0,
                Topt_degC: 5.0,
                k: 0.0,
            });
            if channel == Channel::Fx {
                e.rolling_resistance = Some(RollingResistance { q1: 0.0, q2: 0.0 });
            } else {
                e.ply_steer_conicity = Some(PlySteerConicity {
                    Sh_deg: 0.0,
                    Sv: 0.0,
                });
            }
        }
        p.extensions = Some(ext);
        p.validate().unwrap();
        for x in [
            inputs(4000.0, 5.0, 0.1, 2.0),
            inputs(1500.0, -12.0, -0.4, -6.0),
            inputs(8000.0, 0.0, 0.0, 0.0),
            inputs(-10.0, 3.0, 0.0, 0.0),
        ] {
            for c in [conditions(25.0, 260.0, 80.0), conditions(-3.0, 150.0, 0.0)] {
                let lagged = LaggedSlip::steady(&p, &x).advanced(&p, &x, 0.7);
                let out = evaluate_extended(&p, &x, &c, &lagged, SignConvention::Iso);
                assert_eq!(out, evaluate(&p, &x, SignConvention::Iso));
            }
        }
    }

    #[test]
    fn combined_slip_weighting_by_hand() {
        // cos(atan(z)) = 1 / sqrt(1 + z^2): B = 8, C = 1 at kappa = 0.1 weights Fy by 1/sqrt(1.64).
        let p = with(Channel::Fy, Extension::CombinedSlip, &[8.0, 1.0]);
        let x = inputs(4000.0, 4.0, 0.1, 0.0);
        let c = conditions(10.0, 200.0, 40.0);
        let (e, b) = (extended(&p, &x, &c), base(&p, &x));
        assert!(rel_close(e.fy, b.fy / 1.64f64.sqrt(), 1e-14), "{e:?} {b:?}");
        assert_eq!((e.fx, e.mz), (b.fx, b.mz), "other channels untouched");
        // Fx is weighted by the slip angle in rad: B = 5, alpha = 0.1 rad -> 1/sqrt(1.25).
        let p = with(Channel::Fx, Extension::CombinedSlip, &[5.0, 1.0]);
        let x = Inputs { alpha: 0.1, ..x };
        assert!(rel_close(
            extended(&p, &x, &c).fx,
            base(&p, &x).fx / 1.25f64.sqrt(),
            1e-14
        ));
    }

    #[test]
    fn peak_and_stiffness_scales_by_hand() {
        // Scaling D by s_d and BCD by s_k equals scaling the coefficients D and BCD are
        // linear in: a1, a2 by s_d; a3 (Fy) or a3, a4 (Mz, Fx) by s_k.
        let x = inputs(4500.0, 3.0, 0.05, 1.5);
        let scaled = |s_k: f64, s_d: f64| {
            let mut p = Params::paper_table();
            for c in [&mut p.Fy, &mut p.Mz] {
                (c.a1, c.a2) = (c.a1 * s_d, c.a2 * s_d);
            }
            (p.Fx.a1, p.Fx.a2) = (p.Fx.a1 * s_d, p.Fx.a2 * s_d);
            p.Fy.a3 *= s_k;
            (p.Mz.a3, p.Mz.a4) = (p.Mz.a3 * s_k, p.Mz.a4 * s_k);
            (p.Fx.a3, p.Fx.a4) = (p.Fx.a3 * s_k, p.Fx.a4 * s_k);
            base(&p, &x)
        };
        // Pressure: p0 = 200, p = 250 kPa -> dp = 0.25; k = 0.4, d = -0.2: s_k = 1.1, s_d = 0.95.
        // Speed: V0 = 10, V = 30 m/s -> dV = 2; v = -0.1: s_d = 0.8.
        // Temperature: T0 = 40, Topt = 10, T = 80 degC; w = 0.3, k = 0.2: window (80 - 50) / 50
        // = 0.6, s_d = 1 - 0.3 * 0.36 = 0.892; dt = 0.8, s_k = 1.16.
        let cases: [(Extension, &[f64], f64, f64); 3] = [
            (Extension::InflationPressure, &[0.4, -0.2], 1.1, 0.95),
            (Extension::SpeedDependence, &[-0.1], 1.0, 0.8),
            (Extension::Temperature, &[0.3, 10.0, 0.2], 1.16, 0.892),
        ];
        let c = conditions(30.0, 250.0, 80.0);
        for (kind, values, s_k, s_d) in cases {
            let expected = scaled(s_k, s_d);
            for channel in Channel::ALL {
                let got = extended(&with(channel, kind, values), &x, &c);
                let (g, e) = (of(&got, channel), of(&expected, channel));
                assert!(rel_close(g, e, 1e-12), "{kind} on {channel}: {g} vs {e}");
            }
        }
    }

    #[test]
    fn ply_steer_and_rolling_resistance_by_hand() {
        // Sh_deg = 0.5 shifts the slip angle by 0.5 deg, Sv = -100 N moves Fy down.
        let p = with(Channel::Fy, Extension::PlySteerConicity, &[0.5, -100.0]);
        let x = inputs(4000.0, 2.0, 0.0, 1.0);
        let c = conditions(10.0, 200.0, 40.0);
        let shifted = base(&p, &inputs(4000.0, 2.5, 0.0, 1.0));
        assert!(rel_close(
            extended(&p, &x, &c).fy,
            shifted.fy - 100.0,
            1e-12
        ));
        // q1 = 0.012, q2 = 0.004 at V = 20 m/s, V0 = 10: (0.012 + 0.008) 4000 N = 80 N.
        let p = with(Channel::Fx, Extension::RollingResistance, &[0.012, 0.004]);
        let x = inputs(4000.0, 0.0, 0.03, 0.0);
        let c = conditions(20.0, 200.0, 40.0);
        assert!(rel_close(
            extended(&p, &x, &c).fx,
            base(&p, &x).fx - 80.0,
            1e-14
        ));
        // Reversing uses |vx|.
        let reverse = conditions(-20.0, 200.0, 40.0);
        assert_eq!(extended(&p, &x, &reverse), extended(&p, &x, &c));
    }

    #[test]
    fn weighting_comes_before_rolling_resistance() {
        let mut p = with(Channel::Fx, Extension::RollingResistance, &[0.01, 0.0]);
        let ext = p.extensions.as_mut().unwrap();
        ext.Fx.combined_slip = Some(CombinedSlip { B: 2.0, C: 1.0 });
        let x = Inputs {
            alpha: 0.5,
            ..inputs(3000.0, 0.0, 0.04, 0.0)
        };
        let c = conditions(10.0, 200.0, 40.0);
        // G = 1 / sqrt(1 + 1) at B alpha = 1; rolling resistance 0.01 * 3000 N.
        let expected = base(&p, &x).fx / 2f64.sqrt() - 30.0;
        assert!(rel_close(extended(&p, &x, &c).fx, expected, 1e-14));
    }

    #[test]
    fn relaxation_lag_is_the_first_order_response() {
        // A slip step from 0 to s: after distance x the lag is s (1 - exp(-x / sigma)), in any
        // number of steps.
        let (s, sigma) = (0.08, 0.45);
        let mut lagged = 0.0;
        for k in 1..=40 {
            lagged = relaxation_step(lagged, s, 0.025, sigma);
            let x = 0.025 * k as f64;
            assert!(rel_close(lagged, s * (1.0 - (-x / sigma).exp()), 1e-13));
        }
        assert_eq!(
            relaxation_step(0.3, 0.1, 1.0, 0.0),
            0.1,
            "sigma = 0: no lag"
        );

        // Through the parameter set: Fy relaxes, Mz (no relaxation length) follows at once.
        let p = with(Channel::Fy, Extension::RelaxationLength, &[sigma]);
        let still = inputs(4000.0, 0.0, 0.0, 0.0);
        let moved = inputs(4000.0, 4.0, 0.0, 0.0);
        let lag = LaggedSlip::steady(&p, &still).advanced(&p, &moved, 0.3);
        let expected_alpha = moved.alpha * (1.0 - (-0.3f64 / sigma).exp());
        assert!(rel_close(lag.fy, expected_alpha, 1e-13));
        assert_eq!((lag.mz, lag.fx), (moved.alpha, 0.0));
        let c = conditions(10.0, 200.0, 40.0);
        let out = evaluate_extended(&p, &moved, &c, &lag, SignConvention::Paper);
        let at_lag = base(
            &p,
            &Inputs {
                alpha: expected_alpha,
                ..moved
            },
        );
        assert!(rel_close(out.fy, at_lag.fy, 1e-12));
        assert_eq!(out.mz, base(&p, &moved).mz);
    }

    #[test]
    fn conditions_are_clamped_to_the_range() {
        let p = with(Channel::Fx, Extension::SpeedDependence, &[-0.1]);
        let x = inputs(4000.0, 0.0, 0.1, 0.0);
        let top = conditions(70.0, 200.0, 40.0);
        assert_eq!(
            extended(&p, &x, &conditions(95.0, 200.0, 40.0)),
            extended(&p, &x, &top)
        );
        let l = ConditionLimits::default();
        assert_eq!(ConditionVar::Speed.used_value(-95.0, &l), 70.0);
        assert!(
            ConditionVar::Speed.in_range(-30.0, &l) && !ConditionVar::Speed.in_range(-95.0, &l)
        );
        assert_eq!(
            ConditionVar::Pressure.valid_range(&l),
            (100_000.0, 400_000.0)
        );
        assert_eq!(ConditionVar::Pressure.used_value(50_000.0, &l), 100_000.0);
        let (t_lo, _) = ConditionVar::Temperature.valid_range(&l);
        assert!((t_lo - 253.15).abs() < 1e-12);
    }

    fn rejected(edit: impl FnOnce(&mut Extensions)) -> String {
        let mut p = Params::paper_table();
        let mut ext = Extensions::new(NOMINAL, ConditionLimits::default());
        edit(&mut ext);
        p.extensions = Some(ext);
        p.validate().unwrap_err().to_string()
    }

    #[test]
    fn bad_values_are_rejected_with_name_value_and_range() {
        let msg = rejected(|e| e.Fy.relaxation_length = Some(RelaxationLength { sigma_m: -0.1 }));
        assert!(
            msg.contains("extensions.Fy.relaxation_length.sigma_m = -0.1")
                && msg.contains("must lie in [0, 5] m"),
            "{msg}"
        );
        let msg = rejected(|e| {
            e.Fx.rolling_resistance = Some(RollingResistance {
                q1: 0.01,
                q2: f64::NAN,
            })
        });
        assert!(
            msg.contains("extensions.Fx.rolling_resistance.q2 = NaN"),
            "{msg}"
        );
        let msg = rejected(|e| e.nominal.pressure_kpa = 0.0);
        assert!(
            msg.contains("extensions.nominal.pressure_kPa = 0")
                && msg.contains("must lie in [10, 2000] kPa"),
            "{msg}"
        );
        let msg = rejected(|e| e.nominal.speed_mps = f64::INFINITY);
        assert!(msg.contains("extensions.nominal.speed_mps = inf"), "{msg}");
        let msg = rejected(|e| e.limits.pressure_max_kPa = 50.0);
        assert!(
            msg.contains("extensions.limits.pressure_max_kPa = 50")
                && msg.contains(">= pressure_min_kPa = 100"),
            "{msg}"
        );
        let msg = rejected(|e| {
            e.Fx.ply_steer_conicity = Some(PlySteerConicity {
                Sh_deg: 0.1,
                Sv: 0.0,
            })
        });
        assert!(
            msg.contains("extensions.Fx.ply_steer_conicity.Sh_deg = 0.1")
                && msg.contains("only to Fy, Mz"),
            "{msg}"
        );
        let msg =
            rejected(|e| e.Mz.rolling_resistance = Some(RollingResistance { q1: 0.0, q2: 0.0 }));
        assert!(msg.contains("does not apply to Mz (only to Fx)"), "{msg}");
    }

    #[test]
    fn scales_must_stay_positive_over_the_range() {
        // p0 = 200 kPa, up to 400 kPa: dp = 1, so d = -3 gives a peak scale of -2 there.
        let msg =
            rejected(|e| e.Fy.inflation_pressure = Some(InflationPressure { k: 0.0, d: -3.0 }));
        assert!(
            msg.contains("extensions.Fy.inflation_pressure.d = -3")
                && msg.contains("peak D is -2 at p = 400 kPa")
                && msg.contains("range [100, 400] kPa"),
            "{msg}"
        );
        // At 100 kPa dp = -0.5: k = 2.5 makes the stiffness scale -0.25.
        let msg =
            rejected(|e| e.Mz.inflation_pressure = Some(InflationPressure { k: 2.5, d: 0.0 }));
        assert!(
            msg.contains("extensions.Mz.inflation_pressure.k = 2.5")
                && msg.contains("stiffness BCD is -0.25 at p = 100 kPa"),
            "{msg}"
        );
        // V0 = 10 m/s, down to 0: dV = -1, so v = 1 makes the peak vanish at standstill.
        let msg = rejected(|e| e.Fx.speed_dependence = Some(SpeedDependence { v: 1.0 }));
        assert!(
            msg.contains("extensions.Fx.speed_dependence.v = 1") && msg.contains("V = 0 m/s"),
            "{msg}"
        );
        // T0 = 40, Topt = 0: at 120 degC the window is 1.6, 1 - 1 * 2.56 = -1.56 (the smallest).
        let msg = rejected(|e| {
            e.Fy.temperature = Some(Temperature {
                w: 1.0,
                Topt_degC: 0.0,
                k: 0.0,
            })
        });
        assert!(
            msg.contains("extensions.Fy.temperature.w = 1")
                && msg.contains("peak D is -1.56")
                && msg.contains("T = 120 degC"),
            "{msg}"
        );
        // A narrower range makes the same values valid.
        let mut p = Params::paper_table();
        let mut ext = Extensions::new(NOMINAL, ConditionLimits::default());
        (
            ext.limits.temperature_min_degC,
            ext.limits.temperature_max_degC,
        ) = (10.0, 80.0);
        ext.Fy.temperature = Some(Temperature {
            w: 1.0,
            Topt_degC: 0.0,
            k: 0.0,
        });
        p.extensions = Some(ext);
        p.validate().unwrap();
    }

    #[test]
    fn parameter_file_format() {
        let text = r#"{
            "Fy": { "C": 1.3, "a1": -22.1, "a2": 1011.0, "a3": 1078.0, "a4": 1.82, "a5": 0.208,
                    "a6": 0.0, "a7": -0.354, "a8": 0.707, "a9": 0.028, "a10": 0.0, "a11": 14.8,
                    "a12": 0.022, "a13": 0.0 },
            "Mz": { "C": 2.4, "a1": -2.72, "a2": -2.28, "a3": -1.86, "a4": -2.73, "a5": 0.11,
                    "a6": -0.07, "a7": 0.643, "a8": -4.04, "a9": 0.015, "a10": -0.066,
                    "a11": 0.945, "a12": 0.03, "a13": 0.07 },
            "Fx": { "C": 1.65, "a1": -21.3, "a2": 1144.0, "a3": 49.6, "a4": 226.0, "a5": 0.069,
                    "a6": -0.006, "a7": 0.056, "a8": 0.486 },
            "limits": { "fz_max_N": 10000.0, "gamma_max_deg": 10.0 },
            "extensions": {
                "nominal": { "pressure_kPa": 220.0, "speed_mps": 15.0, "temperature_degC": 45.0 },
                "Fy": { "combined_slip": { "B": 9.0, "C": 1.1 },
                        "relaxation_length": { "sigma_m": 0.4 } },
                "Fx": { "rolling_resistance": { "q1": 0.011, "q2": 0.002 } }
            }
        }"#;
        let p = Params::from_json(text).unwrap();
        let ext = p.extensions.as_ref().unwrap();
        assert_eq!(ext.limits, ConditionLimits::default(), "limits default");
        assert_eq!(ext.Fy.combined_slip, Some(CombinedSlip { B: 9.0, C: 1.1 }));
        assert_eq!(ext.Fy.relaxation_length_m(), Some(0.4));
        assert!(ext.Mz.is_empty() && ext.has_relaxation());
        assert!(ext.uses(ConditionVar::Speed) && !ext.uses(ConditionVar::Pressure));
        assert_eq!(Params::from_json(&p.to_json()).unwrap(), p, "round trip");
        let json: serde_json::Value = serde_json::from_str(&p.to_json()).unwrap();
        assert!(
            json["extensions"].get("Mz").is_none(),
            "empty channels are left out"
        );
        assert_eq!(json["extensions"]["nominal"]["temperature_degC"], 45.0);
        let summary = ext.to_string();
        assert!(summary.starts_with("Fy: combined_slip (B = 9, C = 1.1), relaxation_length (sigma_m = 0.4); Fx: rolling_resistance"), "{summary}");

        // The paper's table has none, and writes none.
        assert!(Params::paper_table().extensions.is_none());
        assert!(!Params::paper_table().to_json().contains("extensions"));

        // Unknown or missing names are rejected, naming them.
        for (bad, word) in [
            (text.replace("\"sigma_m\"", "\"sigma\""), "sigma"),
            (
                text.replace("\"combined_slip\"", "\"combined\""),
                "combined",
            ),
            (
                text.replace("\"q2\": 0.002", "\"q2\": 0.002, \"q3\": 1"),
                "q3",
            ),
            (
                text.replace("\"temperature_degC\": 45.0", "\"T\": 45.0"),
                "T",
            ),
        ] {
            let err = Params::from_json(&bad).unwrap_err().to_string();
            assert!(err.contains(word), "{word}: {err}");
        }
    }

    #[test]
    fn kinds_names_and_setters_agree() {
        let ids: Vec<&str> = Extension::ALL.iter().map(|k| k.id()).collect();
        assert_eq!(
            ids,
            [
                "combined_slip",
                "relaxation_length",
                "inflation_pressure",
                "speed_dependence",
                "ply_steer_conicity",
                "rolling_resistance",
                "temperature"
            ]
        );
        let mut e = ChannelExtensions::default();
        for (i, kind) in Extension::ALL.iter().enumerate() {
            let values: Vec<f64> = (0..kind.parameter_names().len())
                .map(|j| (10 * i + j) as f64)
                .collect();
            e.set(*kind, &values).unwrap();
            assert_eq!(e.get(*kind), Some(values));
        }
        assert_eq!(e.kinds().count(), 7);
        let err = e
            .set(Extension::Temperature, &[1.0])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("temperature takes 3 parameters (w, Topt_degC, k), not 1"),
            "{err}"
        );
    }
}
