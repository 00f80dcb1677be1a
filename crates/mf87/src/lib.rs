//! The 1987 Pacejka "Magic Formula" tire model (Bakker, Nyborg, Pacejka, SAE 870421) with
//! load and camber influence: lateral force Fy, aligning moment Mz and longitudinal force Fx.
//!
//! Pure safe Rust. The interface is SI (N, rad, slip ratio); the paper's units (kN, deg,
//! percent) are used only inside, converted in [`units`].
//!
//! [`evaluate`] is the 1987 model; [`evaluate_extended`] adds the fitted [`extensions`]
//! (combined slip, relaxation length, pressure, speed, ply steer, rolling resistance,
//! temperature) a parameter set may carry.
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
pub mod units;
mod validation;

pub use channel::Channel;
pub use conditions::{ConditionVar, OperatingConditions};
pub use error::ParamError;
pub use evaluate::{evaluate, evaluate_extended};
pub use extensions::relaxation::LaggedSlip;
pub use extensions::schema::{Extension, Extensions};
pub use formula::{MagicFormula, channel_factors};
pub use interface::{InputVar, Inputs, OutputVar, Outputs, SignConvention};
pub use params::{LimitVar, Limits, Params};
