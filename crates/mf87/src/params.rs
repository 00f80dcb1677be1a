//! Parameter sets: the coefficient table of the paper as serde types ([`Params`]), its
//! validity range ([`Limits`]) and access to coefficients by channel and index.
//!
//! Field names are the paper's (`C`, `a1`..`a13`). A JSON parameter file must name every
//! coefficient of every channel and nothing else: incomplete or misspelled files are rejected.
//! An optional `extensions` section carries fitted extensions ([`crate::extensions`]).
//! Reading and writing the files is in `json.rs`, [`Params::validate`] in `validation.rs`.

use serde::{Deserialize, Serialize};

use crate::channel::Channel;
pub use crate::error::ParamError;
use crate::extensions::schema::Extensions;
use crate::units;

/// The paper's coefficient table (Tables 1 and 2 of SAE 870421, read with the errata of docs/errata.md).
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

            /// Every coefficient, in [`Self::NAMES`] order.
            pub fn values(&self) -> [f64; $name::NAMES.len()] {
                [$(self.$field),+]
            }

            /// The coefficient at `index` (see [`Self::NAMES`]).
            pub fn get(&self, index: usize) -> Option<f64> {
                self.values().get(index).copied()
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
            LimitVar::GammaMax => units::degrees_to_radians(limits.gamma_max_deg),
        }
    }

    /// Sets the limit from SI units (N, rad).
    pub fn set(self, limits: &mut Limits, value: f64) {
        match self {
            LimitVar::FzMax => limits.fz_max_N = value,
            LimitVar::GammaMax => limits.gamma_max_deg = units::radians_to_degrees(value),
        }
    }
}

/// A complete parameter set of the 1987 Magic Formula.
///
/// Read with [`Params::from_json`] (which validates), checked with [`Params::validate`].
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

impl Params {
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
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
