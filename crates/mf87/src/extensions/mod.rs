//! Extensions of the 1987 model in the forms tire-gap fits them: combined-slip weighting,
//! relaxation length, inflation pressure, speed, ply steer and conicity, rolling resistance,
//! tread temperature and a shift of the slip ratio. Each channel has its own set, with its
//! own parameters, expressed around nominal (reference) conditions.
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
//! Each effect is one file, `<name>.rs`: its parameter struct, its part in each stage, its
//! checks and bounds, as an implementation of `effect::Effect`. The list below names each
//! once. The generic parts:
//! - `effect`: the `Effect` trait, the `parameters!` macro for an effect's struct;
//! - `schema`: the `effects!` macro that makes [`Extension`] and [`ChannelExtensions`] from
//!   the list, and [`Extensions`] (the `extensions` section of a parameter file);
//! - `compose`: the composition above;
//! - `validation`: [`Extensions::validate`], over the effects' checks.
//!
//! The conditions types ([`Nominal`], [`ConditionLimits`], [`Conditions`],
//! [`OperatingConditions`], [`ConditionVar`]) live in `crate::conditions`, and
//! [`evaluate_extended`] beside [`crate::evaluate`]; they are re-exported here too.

pub(crate) mod compose;
pub(crate) mod effect;
pub(crate) mod schema;
pub(crate) mod validation;

// The one list of effects: `Variant = name`, the effect's struct (and `Extension` variant)
// and its name in parameter files, which is also its module `<name>.rs`. In parameter-file
// order (`Extension::ALL`); within a stage the effects apply in this order.
schema::effects! {
    CombinedSlip = combined_slip,
    RelaxationLength = relaxation_length,
    InflationPressure = inflation_pressure,
    SpeedDependence = speed_dependence,
    PlySteerConicity = ply_steer_conicity,
    RollingResistance = rolling_resistance,
    Temperature = temperature,
    SlipRatioShift = slip_ratio_shift,
}

pub use crate::conditions::{
    ConditionLimits, ConditionVar, Conditions, Nominal, OperatingConditions,
};
pub use crate::evaluate::evaluate_extended;
pub use relaxation_length::{LaggedSlip, relaxation_step};
pub use schema::Extensions;

#[cfg(test)]
mod tests;
