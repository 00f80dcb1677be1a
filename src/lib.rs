//! Pacejka87Tire: the 1987 Magic Formula (crate `mf87`) as an FMI 2.0 co-simulation FMU.
//!
//! The C ABI is in [`exports`]; every call goes through [`boundary`] (panic catching, pointer
//! checks) into the safe [`instance::Instance`].
#![deny(deref_nullptr)]

pub mod exports;
pub mod instance;
pub mod parameter_file;
pub mod variables;

mod boundary;
mod logging;
mod model_state;
mod resource_uri;
mod snapshot;
mod state;
