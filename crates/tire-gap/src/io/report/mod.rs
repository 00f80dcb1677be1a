//! The diagnosis as a terminal report ([`text`]) and as one JSON object ([`json`]).

mod json;
mod text;

use serde::Serialize;

use crate::io::input::SourceFile;

pub use json::{
    BlockRow, BlocksReport, EffectEntry, JsonReport, NotCoveredRow, blocks_report, effect_entries,
    json,
};
pub use text::{run_list, text};

/// Where the result came from.
#[derive(Debug, Clone, Serialize)]
pub struct Provenance {
    /// The input as given (file or directory names).
    pub input: String,
    /// SHA-256 of the input (`input::combined_sha256`).
    pub input_sha256: String,
    /// Every file read, with the runs it holds.
    pub inputs: Vec<SourceFile>,
    pub split_seed: u64,
    pub folds: usize,
    pub tool: &'static str,
    pub version: &'static str,
}

/// What happened to an output asked for on the command line (`--params`, `--plots`).
#[derive(Debug, Clone, Serialize)]
pub struct OutputStatus {
    /// `params` or `plots`.
    pub output: &'static str,
    pub path: String,
    pub written: bool,
    /// Why it was not written, when it was not.
    pub error: Option<String>,
    /// Parts left out (figures whose data is missing), each with its reason.
    pub notes: Vec<String>,
}

/// Everything a report says besides the diagnosis: where the data came from, what the reader
/// noticed, and what became of the outputs.
#[derive(Debug, Clone, Serialize)]
pub struct Context {
    pub provenance: Provenance,
    /// The readers' notes on the input (dropped channels, encodings, runs found from time...).
    pub notes: Vec<String>,
    pub outputs: Vec<OutputStatus>,
}
