//! The command line: argument parsing and the `diagnose` and `synth` commands, over the
//! library. Exit codes: 0 done, 1 internal failure or unwritable output, 2 bad input.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::{Parser, Subcommand};
use sha2::{Digest, Sha256};

use crate::diagnose::{Options, diagnose};
use crate::exit;
use crate::report::{self, Provenance};

#[derive(Debug, Parser)]
#[command(
    name = "tire-gap",
    version,
    about = "Where the 1987 Magic Formula departs from measured tire data, which unmodelled effect causes it, and how far the gap shrinks once it is added"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Diagnose measured data (CSV with unit-suffixed columns, or TYDEX .tdx).
    Diagnose {
        /// The measurement file.
        file: PathBuf,
        /// Print one JSON object on stdout instead of the text report.
        #[arg(long)]
        json: bool,
        /// Write the fitted parameters (FMU parameter-file format) to this file.
        #[arg(long, value_name = "OUT.json")]
        params: Option<PathBuf>,
        /// Write SVG figures and an index.html into this directory (created if missing).
        #[arg(long, value_name = "DIR")]
        plots: Option<PathBuf>,
        /// Cross-validation folds (whole runs per fold).
        #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u16).range(3..=20))]
        folds: u16,
        /// Seed of the split of runs into folds.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Generate synthetic test-rig data with chosen effects switched on.
    Synth(crate::synth::cli::SynthArgs),
}

/// An error to report and the exit code it maps to.
#[derive(Debug)]
pub struct Failure {
    pub code: u8,
    pub message: String,
}

pub fn bad_input(message: impl Into<String>) -> Failure {
    Failure {
        code: exit::BAD_INPUT,
        message: message.into(),
    }
}

pub fn failure(message: impl Into<String>) -> Failure {
    Failure {
        code: exit::FAILURE,
        message: message.into(),
    }
}

/// Writes `text` to `path` through a temporary file, so no partial file is left behind.
pub fn write_whole(path: &Path, text: &[u8]) -> Result<(), Failure> {
    let tmp = path.with_extension("partial");
    std::fs::write(&tmp, text)
        .and_then(|_| std::fs::rename(&tmp, path))
        .map_err(|e| failure(format!("cannot write {}: {e}", path.display())))
}

/// Runs the command line; `progress` is shown only on a terminal.
pub fn run(cli: Cli, stdout: &mut impl Write) -> Result<(), Failure> {
    match cli.command {
        Command::Synth(args) => crate::synth::cli::run(&args, stdout),
        Command::Diagnose {
            file,
            json,
            params,
            plots,
            folds,
            seed,
        } => {
            let bytes =
                std::fs::read(&file).map_err(|e| bad_input(format!("{}: {e}", file.display())))?;
            let input_sha256 = Sha256::digest(&bytes)
                .iter()
                .map(|b| format!("{b:02x}"))
                .collect();
            let loaded =
                crate::input::load_bytes(&file, bytes).map_err(|e| bad_input(e.to_string()))?;
            // A directory that cannot be made fails now, not after the diagnosis.
            if let Some(dir) = &plots {
                crate::plots::check_dir(dir)?;
            }
            let bar = crate::progress::Progress::new();
            for note in &loaded.notes {
                bar.note(note);
            }
            let options = Options {
                folds: folds as usize,
                seed,
                ..Options::default()
            };
            let diagnosis = diagnose(&loaded.dataset, &options, |msg| bar.message(msg))
                .map_err(|e| bad_input(e.to_string()))?;
            bar.finish();
            let provenance = Provenance {
                input: file.display().to_string(),
                input_sha256,
                split_seed: seed,
                folds: options.folds,
                tool: "tire-gap",
                version: env!("CARGO_PKG_VERSION"),
            };
            if let Some(path) = params {
                let text =
                    crate::export::parameter_file(&diagnosis, &loaded.dataset).map_err(failure)?;
                write_whole(&path, text.as_bytes())?;
            }
            if let Some(dir) = &plots {
                let figures = crate::plots::render(&diagnosis);
                for note in &figures.skipped {
                    eprintln!("tire-gap: note: {note}");
                }
                let heading = format!("tire-gap diagnose {}", file.display());
                crate::plots::write(dir, &figures, &heading)?;
            }
            let out = if json {
                report::json(&diagnosis, &provenance)
            } else {
                report::text(&diagnosis, &provenance)
            };
            writeln!(stdout, "{out}").map_err(|e| failure(format!("cannot write the report: {e}")))
        }
    }
}
