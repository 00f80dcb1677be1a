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
//! # Example
//!
//! The paper's coefficient table at 4 kN of load, free rolling, no camber:
//!
//! ```
//! use mf87::{Inputs, Params, SignConvention, evaluate};
//!
//! let params = Params::paper_table();
//! let at = |alpha_deg: f64| Inputs {
//!     fz: 4000.0,
//!     alpha: alpha_deg.to_radians(),
//!     kappa: 0.0,
//!     gamma: 0.0,
//! };
//! let one = evaluate(&params, &at(1.0), SignConvention::Paper);
//! let two = evaluate(&params, &at(2.0), SignConvention::Paper);
//! let eight = evaluate(&params, &at(8.0), SignConvention::Paper);
//! // About 1 kN of lateral force per degree of slip angle at small angles, then saturating
//! // toward the peak (the friction coefficient near 1).
//! assert!((1000.0..1020.0).contains(&one.fy) && two.fy < 2.0 * one.fy);
//! assert!(eight.fy > 3600.0 && eight.fy < 4000.0);
//! // The aligning moment opposes the slip angle and falls off beyond small angles.
//! assert!(two.mz < 0.0 && eight.mz.abs() < two.mz.abs());
//! // No slip ratio, no longitudinal force.
//! assert_eq!(two.fx, 0.0);
//! // ISO's axes flip the signs of Fy and Mz.
//! let iso = evaluate(&params, &at(2.0), SignConvention::Iso);
//! assert_eq!((iso.fy, iso.mz), (-two.fy, -two.mz));
//! ```
//!
//! # Modules
//!
//! In layers: each module uses only modules of the layers above it (and of its own layer
//! listed before it), so no two modules refer to each other, directly or round about. This
//! root only gathers the public items (re-exports), `extensions` itself those and the list of
//! effects; inside the crate items are used from the module that defines them. An effect is
//! named only in its own file and the list.
//!
//! 1. Base: [`real`]: the number type the model is written over (`f64`, or a dual number for
//!    exact derivatives) and the derivative at its kinks (clamping, |x|); [`units`]: every
//!    unit conversion (N and kN, rad and deg, slip ratio and percent, Pa and kPa, K and
//!    degC); `error`: [`ParamError`], and how a rejection names the parameter, its value and
//!    the bound; `channel`: [`Channel`], the outputs Fy, Mz, Fx, each with its coefficient
//!    row.
//! 2. The model without extensions: `conditions`: the operating conditions (speed,
//!    pressure, temperature) in SI ([`OperatingConditions`], [`ConditionVar`]) and in the
//!    extensions' units (nominal, range, one evaluation's), the only conversion between the
//!    two; `coefficients`: the coefficient table's types, [`Limits`] and [`LimitVar`], and
//!    what an effect's checks see of them; `interface`: [`Inputs`] and [`Outputs`] in SI,
//!    their variables and valid ranges, the [`SignConvention`]; [`formula`]: the 1987 Magic
//!    Formula in the paper's units from a channel's coefficients ([`MagicFormula`],
//!    [`formula::factors`]).
//! 3. [`bounds`]: the general bounds every parameter set must keep and their rows; each
//!    effect's own bounds are in its file.
//! 4. [`extensions`]: `extensions::effect`: the `Effect` trait every effect implements (its
//!    part in each stage of the composition, its checks and bounds) and its parameter
//!    struct's macro; `extensions::schema`: from the one list of effects (in `extensions`),
//!    the kinds ([`Extension`], with their names) and a channel's set, the `extensions`
//!    section ([`Extensions`]); `extensions::<effect>` (one file each, e.g.
//!    `extensions::temperature`): its parameters, math, checks and bounds
//!    (`extensions::relaxation_length` also the lag step and the lag state, [`LaggedSlip`]);
//!    `extensions::compose`: the order the effects compose in; `extensions::validation`: the
//!    checks of the extensions' own values, over the effects'.
//! 5. [`params`]: the parameter set ([`Params`]): coefficient table, limits, extensions;
//!    coefficients by channel and index.
//! 6. `evaluate`: a channel's factors from a parameter set ([`channel_factors`]), the SI
//!    entry points [`evaluate`] and [`evaluate_extended`], and the lag state over time
//!    ([`LaggedSlip::steady`], [`LaggedSlip::advanced`], [`LaggedSlip::rates`]).
//! 7. `validation`: [`Params::validate`], the base coefficients alone and with the
//!    extensions; [`coefficient_allowed`] and [`limit_allowed`], the range of one value on
//!    its own; [`bounds_table`], every bound (general and each effect's) for
//!    docs/parameters.md. `json`: parameter files: [`Params::from_json`] (validated),
//!    [`Params::to_json`], [`Params::paper_table`].
#![forbid(unsafe_code)]

pub mod bounds;
mod channel;
mod coefficients;
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
pub use evaluate::{channel_factors, evaluate, evaluate_extended};
pub use extensions::schema::Extensions;
pub use extensions::{Extension, LaggedSlip};
pub use formula::MagicFormula;
pub use interface::{InputVar, Inputs, OutputVar, Outputs, SignConvention};
pub use params::{LimitVar, Limits, Params};
pub use real::{Dual64, Real};
pub use validation::{bounds_table, coefficient_allowed, limit_allowed};
