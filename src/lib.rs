//! Pacejka87Tire: the 1987 Magic Formula (crate `mf87`) as an FMU for co-simulation and Model
//! Exchange, FMI 2.0 and FMI 3.0 (one binary, one instance type: the standard it was made
//! through and the interface decide which calls it takes).
//!
//! The modules, from the C ABI inwards; each imports only modules listed after it:
//! - [`exports`]: every `fmi2*` function; checks the arguments and calls the instance.
//! - [`exports3`]: every `fmi3*` function, the same way.
//! - `values3`: FMI 3.0 variables (value references, arrays) translated to the instance's.
//! - `boundary`: catches panics, finds the instance and checks the state machine, turns C
//!   arrays into slices.
//! - [`instance`]: one instance and the FMI calls on it: life cycle, get/set, clamping
//!   warnings, stepping, messages to the host.
//! - `derivatives`: exact directional derivatives, the model over a dual number.
//! - `fmu_states`: FMU states as opaque pointers, and their serialized form.
//! - `instance_values`: the instance's values (what an FMU state copies), their start values,
//!   the model evaluation.
//! - [`parameter_file`]: locating, reading and parsing `parameterFile`.
//! - `resource_uri`: `file:` URIs to paths.
//! - `call_sequence`: the state machine: which call is allowed in which state.
//! - `logging`: the host's logger and the status codes.
//! - [`variables`]: the variables and log categories, with the tables build.rs generates from
//!   the model description.
#![deny(deref_nullptr)]

pub mod exports;
pub mod exports3;
pub mod instance;
pub mod parameter_file;
pub mod variables;

mod boundary;
mod call_sequence;
mod derivatives;
mod fmu_states;
mod instance_values;
mod logging;
mod resource_uri;
mod values3;
