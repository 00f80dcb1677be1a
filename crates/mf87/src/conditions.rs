//! The operating conditions the extensions depend on (forward speed, inflation pressure, tread
//! temperature), and the only place they change units.
//!
//! They appear in two unit systems:
//! - SI at the interface, as the FMU's inputs: [`OperatingConditions`] (vx [m/s], p [Pa],
//!   T_tread [K]) and the ranges of [`ConditionVar`];
//! - the extensions' units, in which tire-gap fits them and parameter files give them
//!   (m/s, kPa, degC): the nominal conditions ([`Nominal`]), their range ([`ConditionLimits`])
//!   and the conditions of one evaluation ([`Conditions`], with the load in kN and the other
//!   slip of combined slip).
//!
//! [`ConditionVar::to_extension_units`] and [`ConditionVar::to_si`] convert between them, with
//! [`crate::units`]; nothing else does.

use serde::{Deserialize, Serialize};

use crate::real::{self, Real};
use crate::units;

/// An operating condition the extensions may depend on: an input of the FMU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConditionVar {
    /// Forward speed vx [m/s]; the extensions use |vx|.
    Speed,
    /// Inflation pressure p \[Pa\].
    Pressure,
    /// Tread temperature \[K\].
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

    /// A value from SI (m/s, Pa, K) to the extensions' units (m/s, kPa, degC).
    #[inline]
    pub fn to_extension_units<T: Real>(self, si: T) -> T {
        match self {
            ConditionVar::Speed => si,
            ConditionVar::Pressure => units::pascals_to_kilopascals(si),
            ConditionVar::Temperature => units::kelvin_to_celsius(si),
        }
    }

    /// A value from the extensions' units (m/s, kPa, degC) to SI (m/s, Pa, K).
    #[inline]
    pub fn to_si<T: Real>(self, value: T) -> T {
        match self {
            ConditionVar::Speed => value,
            ConditionVar::Pressure => units::kilopascals_to_pascals(value),
            ConditionVar::Temperature => units::celsius_to_kelvin(value),
        }
    }

    /// Symbol and unit in the extensions' forms and messages.
    pub(crate) fn extension_symbol_and_unit(self) -> (&'static str, &'static str) {
        match self {
            ConditionVar::Speed => ("V", "m/s"),
            ConditionVar::Pressure => ("p", "kPa"),
            ConditionVar::Temperature => ("T", "degC"),
        }
    }

    /// The range [lo, hi] in SI units (m/s, Pa, K) of the value the extensions use: of |vx|
    /// for the speed.
    #[inline]
    pub fn valid_range(self, limits: &ConditionLimits) -> (f64, f64) {
        let (lo, hi) = limits.in_extension_units(self);
        (self.to_si(lo), self.to_si(hi))
    }

    /// What the extensions take of an input `value`: |vx| for the speed, else the value.
    #[inline]
    fn used<T: Real>(self, value: T) -> T {
        match self {
            ConditionVar::Speed => real::abs(value),
            ConditionVar::Pressure | ConditionVar::Temperature => value,
        }
    }

    /// Whether the extensions use an input `value` as it is (|vx| for the speed).
    pub fn in_range(self, value: f64, limits: &ConditionLimits) -> bool {
        let (lo, hi) = self.valid_range(limits);
        (lo..=hi).contains(&self.used(value))
    }

    /// The SI value the extensions use for an input `value`: |vx| for the speed, clamped to
    /// the range.
    #[inline]
    pub fn used_value<T: Real>(self, value: T, limits: &ConditionLimits) -> T {
        let (lo, hi) = self.valid_range(limits);
        real::clamp(self.used(value), lo, hi)
    }
}

/// The operating conditions in SI units, as the FMU's inputs. Only extensions use them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OperatingConditions<T = f64> {
    /// Forward speed [m/s].
    pub vx: T,
    /// Inflation pressure \[Pa\].
    pub p: T,
    /// Tread temperature \[K\].
    pub t_tread: T,
}

impl<T: Copy> OperatingConditions<T> {
    pub fn get(&self, var: ConditionVar) -> T {
        match var {
            ConditionVar::Speed => self.vx,
            ConditionVar::Pressure => self.p,
            ConditionVar::Temperature => self.t_tread,
        }
    }

    pub fn set(&mut self, var: ConditionVar, value: T) {
        match var {
            ConditionVar::Speed => self.vx = value,
            ConditionVar::Pressure => self.p = value,
            ConditionVar::Temperature => self.t_tread = value,
        }
    }

    /// The conditions as the extensions see them: clamped to `limits`, in m/s, kPa, degC,
    /// with the load `fz_kn` [kN], the camber `gamma` [rad] and the slips of combined slip
    /// (`slips`: the channel's own and the other, SI).
    #[inline]
    pub(crate) fn in_extension_units(
        &self,
        limits: &ConditionLimits,
        fz_kn: T,
        gamma: T,
        (own_slip, other_slip): (T, T),
    ) -> Conditions<T>
    where
        T: Real,
    {
        let used =
            |var: ConditionVar| var.to_extension_units(var.used_value(self.get(var), limits));
        Conditions {
            fz_kn,
            gamma,
            own_slip,
            other_slip,
            speed: used(ConditionVar::Speed),
            pressure: used(ConditionVar::Pressure),
            temperature: used(ConditionVar::Temperature),
        }
    }
}

/// Reference conditions p0, V0, T0 the extensions are expressed around.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Nominal {
    /// Pressure p0 \[kPa\].
    #[serde(rename = "pressure_kPa")]
    pub pressure_kpa: f64,
    /// Speed V0 [m/s].
    pub speed_mps: f64,
    /// Temperature T0 \[degC\].
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
    /// Inflation pressure \[kPa\].
    pub pressure_min_kPa: f64,
    pub pressure_max_kPa: f64,
    /// Tread temperature \[degC\].
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

impl ConditionLimits {
    /// The range of `condition` in the extensions' units (m/s, kPa, degC).
    #[inline]
    pub fn in_extension_units(&self, condition: ConditionVar) -> (f64, f64) {
        match condition {
            ConditionVar::Speed => (self.speed_min_mps, self.speed_max_mps),
            ConditionVar::Pressure => (self.pressure_min_kPa, self.pressure_max_kPa),
            ConditionVar::Temperature => (self.temperature_min_degC, self.temperature_max_degC),
        }
    }
}

/// The conditions of one evaluation, in the units the extensions work in.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Conditions<T = f64> {
    /// Load \[kN\].
    pub fz_kn: T,
    /// Camber \[rad\].
    pub gamma: T,
    /// The channel's own slip as the curve sees it (lagged if it has a relaxation length):
    /// slip ratio for Fx, slip angle \[rad\] for Fy and Mz.
    pub own_slip: T,
    /// The other slip: slip ratio for Fy and Mz, slip angle \[rad\] for Fx.
    pub other_slip: T,
    /// Speed [m/s].
    pub speed: T,
    /// Pressure \[kPa\].
    pub pressure: T,
    /// Temperature \[degC\].
    pub temperature: T,
}

impl<T: Copy> Conditions<T> {
    /// The value of `condition`.
    #[inline]
    pub fn get(&self, condition: ConditionVar) -> T {
        match condition {
            ConditionVar::Speed => self.speed,
            ConditionVar::Pressure => self.pressure,
            ConditionVar::Temperature => self.temperature,
        }
    }
}
