//! The 1987 Pacejka "Magic Formula" tire model (Bakker, Nyborg, Pacejka, SAE 870421) with
//! load and camber influence: lateral force Fy, aligning moment Mz and longitudinal force Fx.
//!
//! Pure safe Rust. The interface is SI (N, rad, slip ratio); the paper's units (kN, deg,
//! percent) are used only inside, converted in [`units`].
//!
//! [`evaluate`] is the 1987 model; [`evaluate_extended`] adds the fitted [`extensions`]
//! (combined slip, relaxation length, pressure, speed, ply steer, rolling resistance,
//! temperature, slip-ratio shift) a parameter set may carry.
//!
//! # Modules
//!
//! Each module uses only modules listed above it, but for `bounds`, which re-exports each
//! effect's own bounds and puts their rows in its table. This root only gathers the public
//! items (re-exports), `extensions` itself those and the list of effects; inside the crate
//! items are used from the module that defines them.
//!
//! - [`real`]: the number type the model is written over (`f64`, or a dual number for exact
//!   derivatives) and the derivative at its kinks (clamping, |x|).
//! - [`units`]: every unit conversion (N and kN, rad and deg, slip ratio and percent, Pa and
//!   kPa, K and degC).
//! - `error`: [`ParamError`], and how a rejection names the parameter, its value and the
//!   bound.
//! - `channel`: [`Channel`], the outputs Fy, Mz, Fx, each with its coefficient row.
//! - [`bounds`]: the bounds every parameter set must keep, and their table for
//!   docs/parameters.md; each effect's own bounds are in its file (re-exported here).
//! - `conditions`: the operating conditions (speed, pressure, temperature) in SI
//!   ([`OperatingConditions`], [`ConditionVar`]) and in the extensions' units (nominal,
//!   range, one evaluation's); the only conversion between the two.
//! - `extensions::effect`: the `Effect` trait every effect implements (its
//!   part in each stage of the composition, its checks and bounds) and its parameter struct's
//!   macro; `extensions::schema`: from the one list of effects (in `extensions`), the kinds
//!   ([`Extension`], with their names) and a channel's set, the `extensions` section
//!   ([`Extensions`]).
//! - [`params`]: the parameter set ([`Params`]): coefficient table, [`Limits`], extensions;
//!   coefficients by channel and index.
//! - `interface`: [`Inputs`] and [`Outputs`] in SI, their variables and valid ranges, the
//!   [`SignConvention`].
//! - [`formula`]: the 1987 Magic Formula in the paper's units ([`MagicFormula`],
//!   [`channel_factors`]).
//! - `extensions::<effect>` (one file each, e.g. `extensions::temperature`): its parameters,
//!   math, checks and bounds; `extensions::relaxation_length` also the lag step and its state
//!   ([`LaggedSlip`]). `extensions::compose`: the order the effects compose in.
//! - `evaluate`: the SI entry points [`evaluate`] and [`evaluate_extended`].
//! - `extensions::validation`: the checks of the extensions' own values, over the effects'.
//! - `validation`: [`Params::validate`], the base coefficients alone and with the extensions;
//!   [`coefficient_allowed`] and [`limit_allowed`], the range of one value on its own.
//! - `json`: parameter files: [`Params::from_json`] (validated), [`Params::to_json`],
//!   [`Params::paper_table`].
#![forbid(unsafe_code)]

pub mod bounds;
mod channel;
mod conditions;
mod error;
mod evaluate;
pub mod extensions;
pub mod formula;
mod interface;
mod json;
pub mod params;
pub mod real;
pub mod units;
mod validation;

pub use channel::Channel;
pub use conditions::{ConditionVar, OperatingConditions};
pub use error::ParamError;
pub use evaluate::{evaluate, evaluate_extended};
pub use extensions::Extension;
pub use extensions::relaxation_length::LaggedSlip;
pub use extensions::schema::Extensions;
pub use formula::{MagicFormula, channel_factors};
pub use interface::{InputVar, Inputs, OutputVar, Outputs, SignConvention};
pub use params::{LimitVar, Limits, Params};
pub use real::{Dual64, Real};
pub use validation::{coefficient_allowed, limit_allowed};
