//! Parameter sets ([`Params`]): the coefficient table of the paper, its validity range
//! ([`Limits`]) and the extensions; access to coefficients by channel and index. The
//! coefficient and limit types are in `coefficients` (re-exported here).
//!
//! Field names are the paper's (`C`, `a1`..`a13`). A JSON parameter file must name every
//! coefficient of every channel and nothing else: incomplete or misspelled files are rejected.
//! An optional `extensions` section carries fitted extensions ([`crate::extensions`]).
//! Reading and writing the files is in `json.rs`, [`Params::validate`] in `validation.rs`.

use serde::{Deserialize, Serialize};

use crate::channel::Channel;
use crate::coefficients::BaseParams;
pub use crate::coefficients::{LateralCoefficients, LimitVar, Limits, LongitudinalCoefficients};
pub use crate::error::ParamError;
use crate::extensions::schema::Extensions;

/// The paper's coefficient table (Tables 1 and 2 of SAE 870421, read with the errata of docs/errata.md).
pub const PAPER_TABLE_JSON: &str = include_str!("../data/pacejka87.json");

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
    /// What an effect's checks see of the set besides the extensions.
    pub(crate) fn base(&self) -> BaseParams<'_> {
        BaseParams {
            Fy: &self.Fy,
            Mz: &self.Mz,
            limits: &self.limits,
        }
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
