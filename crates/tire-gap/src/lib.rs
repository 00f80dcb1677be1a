//! tire-gap: where the 1987 Magic Formula departs from measured tire data, which unmodelled
//! effect causes it, and how far the gap shrinks on held-out data once it is added.
#![forbid(unsafe_code)]

pub mod cli;
pub mod data;
pub mod front;
pub mod io;
pub mod method;
pub mod progress;
#[cfg(feature = "synth")]
pub mod synth;

/// Exit codes of the command-line tool.
pub mod exit {
    /// Success.
    pub const OK: u8 = 0;
    /// Internal failure (a bug, or the output could not be written).
    pub const FAILURE: u8 = 1;
    /// Bad input: unreadable file, missing column, bad value, bad arguments, data that
    /// cannot support a diagnosis.
    pub const BAD_INPUT: u8 = 2;
    /// The report is printed, but an output asked for (parameter file, figures) could not be
    /// written; the report says which and why.
    pub const INCOMPLETE: u8 = 3;
}
