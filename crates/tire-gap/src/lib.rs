//! tire-gap: where the 1987 Magic Formula departs from measured tire data, which unmodelled
//! effect causes it, and how far the gap shrinks on held-out data once it is added.
#![forbid(unsafe_code)]

pub mod adequacy;
pub mod baseline;
pub mod channel_data;
pub mod cli;
pub mod cv;
pub mod data;
pub mod design;
pub mod diagnose;
pub mod effects;
pub mod export;
pub mod extrapolate;
pub mod fit;
pub mod input;
pub mod model;
pub mod output;
pub mod parallel;
pub mod plots;
pub mod programme;
pub mod progress;
pub mod regions;
pub mod report;
pub mod resources;
pub mod run_order;
pub mod sanity;
mod splitmix;
pub mod stats;
pub mod synth;
pub mod units;

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
