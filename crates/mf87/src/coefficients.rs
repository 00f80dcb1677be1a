//! The 1987 model's coefficients as serde types ([`LateralCoefficients`],
//! [`LongitudinalCoefficients`]), its validity range ([`Limits`], [`LimitVar`]), and what an
//! effect's checks see of them ([`BaseParams`]).
//! [`crate::params::Params`] holds them with the extensions.
//!
//! Field names are the paper's (`C`, `a1`..`a13`).

use serde::{Deserialize, Serialize};

use crate::units;

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
    /// Largest vertical load \[N\]; larger loads are clamped to it.
    pub fz_max_N: f64,
    /// Largest camber magnitude \[deg\]; larger cambers are clamped to it.
    pub gamma_max_deg: f64,
}

/// A limit of the validity range, in SI units at the interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LimitVar {
    /// Largest vertical load \[N\].
    FzMax,
    /// Largest camber magnitude \[rad\].
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

/// What an effect's checks see of a parameter set besides the extensions
/// ([`crate::params::Params::base`]): the coefficients of Fy and Mz (with their camber
/// shifts) and the validity range.
#[derive(Debug, Clone, Copy)]
#[allow(non_snake_case)]
pub(crate) struct BaseParams<'a> {
    pub Fy: &'a LateralCoefficients,
    pub Mz: &'a LateralCoefficients,
    pub limits: &'a Limits,
}
