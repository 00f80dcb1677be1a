//! Parameter sets: the coefficient table of the paper as a serde type, and its validation.
//!
//! Field names are the paper's (`C`, `a1`..`a13`). A JSON parameter file must name every
//! coefficient of every channel and nothing else: incomplete or misspelled files are rejected.
//! An optional `extensions` section carries fitted extensions ([`crate::extensions`]).

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::extensions::Extensions;
use crate::formula::{Channel, channel_factors};

/// The paper's coefficient table (Tables 1 and 2 of SAE 870421, read with the seed errata).
pub const PAPER_TABLE_JSON: &str = include_str!("../data/pacejka87.json");

macro_rules! coefficient_set {
    ($(#[$meta:meta])* $name:ident { $($field:ident),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        #[allow(non_snake_case)]
        pub struct $name {
            $(pub $field: f64,)+
        }

        impl $name {
            /// Coefficient names, in table order; a coefficient's index is its position here.
            pub const NAMES: &'static [&'static str] = &[$(stringify!($field)),+];

            /// The coefficient at `index` (see [`Self::NAMES`]).
            pub fn get(&self, index: usize) -> Option<f64> {
                [$(self.$field),+].get(index).copied()
            }

            /// Mutable access to the coefficient at `index` (see [`Self::NAMES`]).
            pub fn get_mut(&mut self, index: usize) -> Option<&mut f64> {
                [$(&mut self.$field),+].into_iter().nth(index)
            }
        }
    };
}

coefficient_set!(
    /// Coefficients of a channel with load and camber influence (Fy, Mz).
    LateralCoefficients { C, a1, a2, a3, a4, a5, a6, a7, a8, a9, a10, a11, a12, a13 }
);

coefficient_set!(
    /// Coefficients of the longitudinal channel (Fx): load influence only.
    LongitudinalCoefficients { C, a1, a2, a3, a4, a5, a6, a7, a8 }
);

/// The range over which a parameter set is validated and the model is used.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Limits {
    /// Largest vertical load [N]; larger loads are clamped to it.
    pub fz_max_N: f64,
    /// Largest camber magnitude [deg]; larger cambers are clamped to it.
    pub gamma_max_deg: f64,
}

/// A limit of the validity range, in SI units at the interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LimitVar {
    /// Largest vertical load [N].
    FzMax,
    /// Largest camber magnitude [rad].
    GammaMax,
}

impl LimitVar {
    pub const ALL: [LimitVar; 2] = [LimitVar::FzMax, LimitVar::GammaMax];

    /// The limit's interface name.
    pub fn name(self) -> &'static str {
        match self {
            LimitVar::FzMax => "Fz_max",
            LimitVar::GammaMax => "gamma_max",
        }
    }

    pub fn from_name(name: &str) -> Option<LimitVar> {
        LimitVar::ALL.into_iter().find(|v| v.name() == name)
    }

    /// The limit in SI units (N, rad).
    pub fn get(self, limits: &Limits) -> f64 {
        match self {
            LimitVar::FzMax => limits.fz_max_N,
            LimitVar::GammaMax => crate::units::degrees_to_radians(limits.gamma_max_deg),
        }
    }

    /// Sets the limit from SI units (N, rad).
    pub fn set(self, limits: &mut Limits, value: f64) {
        match self {
            LimitVar::FzMax => limits.fz_max_N = value,
            LimitVar::GammaMax => limits.gamma_max_deg = crate::units::radians_to_degrees(value),
        }
    }
}

/// A complete parameter set of the 1987 Magic Formula.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Params {
    /// Where the coefficients come from (free text, optional).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    pub Fy: LateralCoefficients,
    pub Mz: LateralCoefficients,
    pub Fx: LongitudinalCoefficients,
    pub limits: Limits,
    /// Fitted extensions of the model; absent: the 1987 model alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extensions: Option<Extensions>,
}

/// Why a parameter set was rejected.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamError {
    /// The text is not a complete parameter set (syntax, missing or unknown field).
    Format(String),
    /// A value breaks the model within its validity range.
    Invalid {
        /// Which coefficient, limit or extension parameter, e.g. `Mz.a13`.
        name: String,
        value: f64,
        /// What was wrong and what range is allowed.
        reason: String,
    },
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamError::Format(msg) => write!(f, "not a valid parameter set: {msg}"),
            ParamError::Invalid {
                name,
                value,
                reason,
            } => write!(f, "parameter {name} = {value}: {reason}"),
        }
    }
}

impl std::error::Error for ParamError {}

/// Loads sampled when a channel's factors are checked over (0, fz_max].
const VALIDATION_LOAD_SAMPLES: usize = 256;

impl Default for Params {
    /// The paper's table.
    fn default() -> Self {
        Self::paper_table()
    }
}

impl Params {
    /// The paper's coefficient table (Tables 1 and 2 with the seed errata applied).
    pub fn paper_table() -> Params {
        Self::from_json(PAPER_TABLE_JSON).expect("the bundled coefficient table is valid")
    }

    /// Parses and validates a JSON parameter set.
    pub fn from_json(text: &str) -> Result<Params, ParamError> {
        let params: Params =
            serde_json::from_str(text).map_err(|e| ParamError::Format(e.to_string()))?;
        params.validate()?;
        Ok(params)
    }

    /// The parameter set as pretty JSON, in the format [`Params::from_json`] reads.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("parameters serialize")
    }

    /// A coefficient by channel and index (index into the channel's `NAMES`).
    pub fn coefficient(&self, channel: Channel, index: usize) -> Option<f64> {
        match channel {
            Channel::Fy => self.Fy.get(index),
            Channel::Mz => self.Mz.get(index),
            Channel::Fx => self.Fx.get(index),
        }
    }

    /// Mutable access to a coefficient by channel and index.
    pub fn coefficient_mut(&mut self, channel: Channel, index: usize) -> Option<&mut f64> {
        match channel {
            Channel::Fy => self.Fy.get_mut(index),
            Channel::Mz => self.Mz.get_mut(index),
            Channel::Fx => self.Fx.get_mut(index),
        }
    }

    /// A channel's coefficient names (`C`, `a1`, ...), in parameter-file order: a
    /// coefficient's index is its position here.
    pub fn coefficient_names(channel: Channel) -> &'static [&'static str] {
        match channel {
            Channel::Fy | Channel::Mz => LateralCoefficients::NAMES,
            Channel::Fx => LongitudinalCoefficients::NAMES,
        }
    }

    /// The index of a coefficient name (`C`, `a1`, ...) in a channel, if the channel has it.
    pub fn coefficient_index(channel: Channel, name: &str) -> Option<usize> {
        Self::coefficient_names(channel)
            .iter()
            .position(|n| *n == name)
    }

    /// Checks that the set gives finite, well-defined forces everywhere in its validity range:
    /// loads in (0, fz_max_N] and cambers within +-gamma_max_deg; and the extensions, if any,
    /// over their range of conditions ([`Extensions::validate`]).
    pub fn validate(&self) -> Result<(), ParamError> {
        self.validate_limits()?;
        for channel in Channel::ALL {
            self.validate_channel(channel)?;
        }
        if let Some(ext) = &self.extensions {
            ext.validate()?;
        }
        Ok(())
    }

    fn validate_limits(&self) -> Result<(), ParamError> {
        let Limits {
            fz_max_N,
            gamma_max_deg,
        } = self.limits;
        if !(fz_max_N.is_finite() && fz_max_N > 0.0) {
            return Err(invalid(
                "limits.fz_max_N",
                fz_max_N,
                "must be a finite load > 0 N",
            ));
        }
        if !(gamma_max_deg.is_finite() && gamma_max_deg > 0.0 && gamma_max_deg < 90.0) {
            return Err(invalid(
                "limits.gamma_max_deg",
                gamma_max_deg,
                "must lie in (0, 90) deg",
            ));
        }
        Ok(())
    }

    fn validate_channel(&self, channel: Channel) -> Result<(), ParamError> {
        let names = Self::coefficient_names(channel);
        let name = |i: usize| format!("{channel}.{}", names[i]);
        let coef = |i: usize| self.coefficient(channel, i).unwrap_or(f64::NAN);
        for i in 0..names.len() {
            if !coef(i).is_finite() {
                return Err(invalid(&name(i), coef(i), "must be a finite number"));
            }
        }
        if coef(0) == 0.0 {
            return Err(invalid(
                &name(0),
                0.0,
                "C must not be 0 (B = BCD / (C D) would divide by zero)",
            ));
        }
        let fz_max_kn = crate::units::newtons_to_kilonewtons(self.limits.fz_max_N);
        // D / Fz = a1 Fz + a2 is linear in Fz: no zero inside (0, fz_max] iff both ends agree.
        let (a1, a2) = (coef(1), coef(2));
        let d_slope_max = a1 * fz_max_kn + a2;
        if a2 == 0.0 || d_slope_max == 0.0 || a2.signum() != d_slope_max.signum() {
            return Err(invalid(
                &name(2),
                a2,
                &format!(
                    "the peak D = a1 Fz^2 + a2 Fz (a1 = {a1}) reaches 0 for a load in (0, {} N]; \
                     C D must not vanish inside the validity range",
                    self.limits.fz_max_N
                ),
            ));
        }
        if let Channel::Fy | Channel::Mz = channel {
            let gamma_max = self.limits.gamma_max_deg;
            for (index, what) in [(12, "B (1 - a12 |gamma|)"), (13, "E / (1 - a13 |gamma|)")] {
                let a = coef(index);
                if 1.0 - a * gamma_max <= 0.0 {
                    return Err(invalid(
                        &name(index),
                        a,
                        &format!(
                            "1 - {} |gamma| must stay > 0 for |gamma| <= gamma_max_deg = {gamma_max} \
                             (needs {} < {}), else {what} breaks down",
                            names[index],
                            names[index],
                            1.0 / gamma_max
                        ),
                    ));
                }
            }
        }
        // B = BCD / (C D) must be finite and non-zero (phi divides by B) over the load range,
        // at both camber extremes.
        for k in 1..=VALIDATION_LOAD_SAMPLES {
            let fz_kn = fz_max_kn * k as f64 / VALIDATION_LOAD_SAMPLES as f64;
            for gamma_deg in [0.0, self.limits.gamma_max_deg] {
                let mf = channel_factors(self, channel, fz_kn, gamma_deg);
                if !(mf.b.is_finite() && mf.b != 0.0 && mf.e.is_finite()) {
                    return Err(invalid(
                        &name(3),
                        coef(3),
                        &format!(
                            "the stiffness factor B = BCD / (C D) is {} at Fz = {} N, gamma = {gamma_deg} deg; \
                             it must be finite and non-zero over (0, {} N]",
                            mf.b,
                            crate::units::kilonewtons_to_newtons(fz_kn),
                            self.limits.fz_max_N
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

fn invalid(name: &str, value: f64, reason: &str) -> ParamError {
    ParamError::Invalid {
        name: name.to_string(),
        value,
        reason: reason.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_table_has_errata_values() {
        let p = Params::paper_table();
        // Erratum 1: Fy a8 is 0.707, not the Mz row's -4.04.
        assert_eq!(p.Fy.a8, 0.707);
        assert_eq!(p.Mz.a8, -4.04);
        assert_eq!((p.Fy.C, p.Mz.C, p.Fx.C), (1.30, 2.40, 1.65));
    }

    #[test]
    fn json_round_trip_is_lossless() {
        let p = Params::paper_table();
        assert_eq!(Params::from_json(&p.to_json()).unwrap(), p);
    }

    #[test]
    fn incomplete_or_unknown_fields_are_rejected() {
        let mut v: serde_json::Value = serde_json::from_str(PAPER_TABLE_JSON).unwrap();
        v["Fy"].as_object_mut().unwrap().remove("a7");
        let err = Params::from_json(&v.to_string()).unwrap_err();
        assert!(err.to_string().contains("a7"), "{err}");

        let mut v: serde_json::Value = serde_json::from_str(PAPER_TABLE_JSON).unwrap();
        v["Fx"]["a9"] = serde_json::json!(0.0);
        let err = Params::from_json(&v.to_string()).unwrap_err();
        assert!(err.to_string().contains("a9"), "{err}");
    }

    #[test]
    fn coefficient_access_by_name_and_index_agree() {
        let mut p = Params::paper_table();
        let i = Params::coefficient_index(Channel::Mz, "a13").unwrap();
        assert_eq!(p.coefficient(Channel::Mz, i), Some(0.070));
        *p.coefficient_mut(Channel::Mz, i).unwrap() = 0.05;
        assert_eq!(p.Mz.a13, 0.05);
        assert_eq!(Params::coefficient_index(Channel::Fx, "a13"), None);
        assert_eq!(Params::coefficient_index(Channel::Fx, "C"), Some(0));
    }

    fn rejected(edit: impl FnOnce(&mut Params)) -> String {
        let mut p = Params::paper_table();
        edit(&mut p);
        p.validate().unwrap_err().to_string()
    }

    #[test]
    fn zero_peak_is_rejected_with_name_and_value() {
        let msg = rejected(|p| p.Fy.C = 0.0);
        assert!(msg.contains("Fy.C = 0"), "{msg}");
        let msg = rejected(|p| p.Fx.a2 = 0.0);
        assert!(msg.contains("Fx.a2 = 0"), "{msg}");
        // D of Fy changes sign at 1011 / 22.1 = 45.7 kN: inside the range if fz_max is 50 kN.
        let msg = rejected(|p| p.limits.fz_max_N = 50_000.0);
        assert!(msg.contains("Fy.a2"), "{msg}");
    }

    #[test]
    fn camber_singularity_inside_range_is_rejected() {
        // 1 - a13 |gamma| = 0 at 14.3 deg for the paper's Mz: reject a range that reaches it.
        let msg = rejected(|p| p.limits.gamma_max_deg = 15.0);
        assert!(msg.contains("Mz.a13"), "{msg}");
        let msg = rejected(|p| p.Fy.a12 = 0.2);
        assert!(msg.contains("Fy.a12 = 0.2"), "{msg}");
    }

    #[test]
    fn non_finite_coefficients_and_limits_are_rejected() {
        let msg = rejected(|p| p.Mz.a5 = f64::NAN);
        assert!(msg.contains("Mz.a5 = NaN"), "{msg}");
        let msg = rejected(|p| p.limits.fz_max_N = f64::INFINITY);
        assert!(msg.contains("limits.fz_max_N"), "{msg}");
    }

    #[test]
    fn vanishing_stiffness_is_rejected() {
        let msg = rejected(|p| p.Fy.a3 = 0.0);
        assert!(
            msg.contains("Fy.a3 = 0") && msg.contains("B = BCD"),
            "{msg}"
        );
    }
}
