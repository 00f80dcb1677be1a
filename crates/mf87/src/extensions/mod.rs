//! Extensions of the 1987 model in the forms tire-gap fits them: combined-slip weighting
//! (MF 6.1's), relaxation length, inflation pressure (MF 6.1's terms), speed, ply steer and
//! conicity with their load terms, rolling resistance, tread temperature, a shift of the slip
//! ratio and camber on the peak. Each channel has its own set, with its
//! own parameters, expressed around nominal (reference) conditions.
//!
//! Units inside, as in [`crate::formula`]: load kN, slip angle deg, slip percent; besides
//! these speed m/s, pressure kPa, temperature degC, and the other slip of combined slip in SI
//! (slip ratio for Fy and Mz, slip angle in rad for Fx). [`crate::evaluate_extended`] is the
//! SI entry point.
//!
//! The extensions of a channel compose in one fixed order, whatever order they were added in:
//! 1. factors: inflation pressure, speed, temperature and camber scale the peak D and the
//!    stiffness BCD; ply steer and conicity (Fy, Mz) add to the shifts Sh and Sv, the
//!    slip-ratio shift (Fx) to Sh;
//! 2. the Magic Formula at the channel's slip, lagged if the channel has a relaxation length;
//! 3. output: the combined-slip weighting multiplies it, the lateral force the slip ratio
//!    induces is added (Fy), then rolling resistance is subtracted.
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
//! [`OperatingConditions`], [`ConditionVar`]) live in `crate::conditions`; they are
//! re-exported here too. Each effect's module is public (its bounds, e.g.
//! `extensions::combined_slip::COMBINED_SLIP_B_ABS_MAX`); the lag items of the relaxation
//! length ([`LaggedSlip`], [`relaxation_step`], [`LAGGED_SLIP_ABS_MAX`]) are re-exported here.
//! What needs a whole parameter set ([`crate::Params`]) is above this module: a channel's
//! factors and the evaluation in `crate::evaluate`, the scaled peak and B checked in
//! `crate::validation`, the table of all bounds [`crate::bounds_table`].

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
    CamberPeak = camber_peak,
}

pub use crate::conditions::{
    ConditionLimits, ConditionVar, Conditions, Nominal, OperatingConditions,
};
pub use relaxation_length::{LAGGED_SLIP_ABS_MAX, LaggedSlip, relaxation_step};
pub use schema::Extensions;

#[cfg(test)]
mod tests;
