//! tire-gap: where the 1987 Magic Formula departs from measured tire data, which unmodelled
//! effect causes it, and how far the gap shrinks on held-out data once it is added.
#![forbid(unsafe_code)]

pub mod cli;
pub mod data;
pub mod front;
pub mod io;
pub mod method;
pub mod profile;
pub mod progress;
pub mod quantiles;
#[cfg(feature = "synth")]
pub mod synth;
