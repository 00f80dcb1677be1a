//! Extensions of the 1987 model in the forms tire-gap fits them: combined-slip weighting,
//! relaxation length, inflation pressure, speed, ply steer and conicity, rolling resistance,
//! tread temperature and a shift of the slip ratio. Each channel has its own set, with its own parameters, expressed
//! around nominal (reference) conditions.
//!
//! Units inside, as in [`crate::formula`]: load kN, slip angle deg, slip percent; besides
//! these speed m/s, pressure kPa, temperature degC, and the other slip of combined slip in SI
//! (slip ratio for Fy and Mz, slip angle in rad for Fx). [`evaluate_extended`] is the SI
//! entry point.
//!
//! The extensions of a channel compose in one fixed order, whatever order they were added in:
//! 1. factors: inflation pressure, speed and temperature scale the peak D and the stiffness
//!    BCD; ply steer and conicity (Fy, Mz) add to the shifts Sh and Sv, the slip-ratio shift
//!    (Fx) to Sh;
//! 2. the Magic Formula at the channel's slip, lagged if the channel has a relaxation length;
//! 3. output: the combined-slip weighting multiplies it, then rolling resistance is subtracted.
//!
//! This module only gathers the public items of its parts:
//! - `schema`: the kinds ([`Extension`]) and their parameter structs, [`ChannelExtensions`],
//!   [`Extensions`] (the `extensions` section of a parameter file);
//! - `physics`: the math of each kind and the composition above;
//! - `relaxation`: the lag step ([`relaxation_step`]) and its state ([`LaggedSlip`]);
//! - `validation`: [`Extensions::validate`].
//!
//! The conditions types ([`Nominal`], [`ConditionLimits`], [`Conditions`],
//! [`OperatingConditions`], [`ConditionVar`]) live in `crate::conditions`, and
//! [`evaluate_extended`] beside [`crate::evaluate`]; they are re-exported here too.

pub(crate) mod physics;
pub(crate) mod relaxation;
pub(crate) mod schema;
pub(crate) mod validation;

pub use crate::conditions::{
    ConditionLimits, ConditionVar, Conditions, Nominal, OperatingConditions,
};
pub use crate::evaluate::evaluate_extended;
pub use relaxation::{LaggedSlip, relaxation_step};
pub use schema::{
    ChannelExtensions, CombinedSlip, Extension, Extensions, InflationPressure, PlySteerConicity,
    RelaxationLength, RollingResistance, SlipRatioShift, SpeedDependence, Temperature,
};

#[cfg(test)]
mod tests;
