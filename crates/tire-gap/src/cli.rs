//! The command line: argument parsing and the `diagnose` and (with the `synth` feature)
//! `synth` commands, over the library. Exit codes: 0 done, 1 internal failure or unwritable output, 2 bad input, 3 the
//! report is printed but an output asked for could not be written.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::{Parser, Subcommand};

use crate::data::Dataset;
use crate::exit;
use crate::io::output::check_file_target;
use crate::io::report::{self, Context, OutputStatus, Provenance};
use crate::method::diagnose::{Diagnosis, Options, diagnose};

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
    /// Diagnose measured data: CSV with unit-suffixed columns, TYDEX .tdx, or TTC run files
    /// (.dat or .mat, each a programme split into its test blocks). Several files, and
    /// directories of them, are read as one data set of one tire.
    Diagnose(DiagnoseArgs),
    /// Generate synthetic test-rig data with chosen effects switched on.
    #[cfg(feature = "synth")]
    Synth(crate::synth::cli::SynthArgs),
}

/// Arguments of `tire-gap diagnose`.
#[derive(Debug, Clone, clap::Args)]
pub struct DiagnoseArgs {
    /// Measurement files, or directories whose .csv, .tdx, .dat and .mat files are all read;
    /// one data set, each file's runs kept apart.
    #[arg(required = true, value_name = "FILE|DIR")]
    pub inputs: Vec<PathBuf>,
    /// Print one JSON object on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
    /// Write the fitted parameters (FMU parameter-file format) to this file.
    #[arg(long, value_name = "OUT.json")]
    pub params: Option<PathBuf>,
    /// Write SVG figures and an index.html into this directory (created if missing).
    #[arg(long, value_name = "DIR")]
    pub plots: Option<PathBuf>,
    /// Cross-validation folds (whole runs per fold).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u16).range(3..=20))]
    pub folds: u16,
    /// Seed of the split of runs into folds whose rounds and figures the report shows.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Fold assignments (split seeds 1..=N) that must each select an effect for the verdict
    /// to name it; 1 takes the verdict from `--seed`'s assignment alone.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u16).range(1..=10))]
    pub stability_draws: u16,
}

use crate::io::output::{Failure, bad_input, failure, write_whole};

/// Runs the command line; `progress` is shown only on a terminal.
pub fn run(cli: Cli, stdout: &mut impl Write) -> Result<(), Failure> {
    match cli.command {
        #[cfg(feature = "synth")]
        Command::Synth(args) => crate::synth::cli::run(&args, stdout),
        Command::Diagnose(args) => run_diagnose(&args, stdout),
    }
}

/// `tire-gap diagnose`: output paths are checked before any work; once the diagnosis is made
/// its report is always printed, and an output that could not be written after all (a fit the
/// FMU would reject, a full disk) is named in it and gives exit code 3.
pub fn run_diagnose(args: &DiagnoseArgs, stdout: &mut impl Write) -> Result<(), Failure> {
    let (files, mut notes) =
        crate::io::input::expand(&args.inputs).map_err(|e| bad_input(e.to_string()))?;
    if let Some(path) = &args.params {
        check_file_target(path, "--params", &files)?;
    }
    if let Some(dir) = &args.plots {
        crate::io::plots::check_dir(dir, &files)?;
    }
    let bar = crate::progress::Progress::new();
    let loaded = crate::io::input::load_many(&files).map_err(|e| bad_input(e.to_string()))?;
    notes.extend(loaded.notes.iter().cloned());
    // What a diagnosis of this size needs, before the work starts.
    let rows = loaded.dataset.len();
    if let Some(note) = crate::io::resources::check(rows, crate::io::resources::available_memory())
        .map_err(bad_input)?
    {
        notes.push(note);
    }
    for note in &notes {
        bar.note(note);
    }
    let options = Options {
        folds: args.folds as usize,
        seed: args.seed,
        stability_draws: args.stability_draws as usize,
        ..Options::default()
    };
    let diagnosis =
        diagnose(&loaded.dataset, &options, &bar).map_err(|e| bad_input(e.to_string()))?;
    let shown: Vec<String> = args
        .inputs
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    let provenance = Provenance {
        input: shown.join(" "),
        input_sha256: crate::io::input::combined_sha256(&loaded.sources),
        inputs: loaded.sources.clone(),
        split_seed: args.seed,
        folds: options.folds,
        tool: "tire-gap",
        version: env!("CARGO_PKG_VERSION"),
    };
    let heading = format!("tire-gap diagnose {}", provenance.input);
    if args.params.is_some() || args.plots.is_some() {
        bar.stage("writing the fitted model and figures", 0);
    }
    let outputs = write_outputs(&diagnosis, &loaded.dataset, args, &heading);
    bar.finish();
    let context = Context {
        provenance,
        notes,
        outputs,
    };
    let out = if args.json {
        report::json(&diagnosis, &context)
    } else {
        report::text(&diagnosis, &context)
    };
    writeln!(stdout, "{out}").map_err(|e| failure(format!("cannot write the report: {e}")))?;
    let missing: Vec<String> = context
        .outputs
        .iter()
        .filter_map(|o| Some(format!("{} {}: {}", o.output, o.path, o.error.as_ref()?)))
        .collect();
    if missing.is_empty() {
        Ok(())
    } else {
        Err(Failure {
            code: exit::INCOMPLETE,
            message: format!(
                "the report is complete, but not every output was written: {}",
                missing.join("; ")
            ),
        })
    }
}

/// Writes the outputs asked for: the parameter file, when the FMU would accept the fitted
/// model, and the figures; each with what became of it.
pub fn write_outputs(
    diagnosis: &Diagnosis,
    ds: &Dataset,
    args: &DiagnoseArgs,
    heading: &str,
) -> Vec<OutputStatus> {
    let mut outputs = Vec::new();
    if let Some(path) = &args.params {
        let written = crate::method::export::parameter_file(diagnosis, ds)
            .map_err(|e| format!("the fitted model is not a parameter file the FMU accepts: {e}"))
            .and_then(|text| write_whole(path, text.as_bytes()).map_err(|f| f.message));
        outputs.push(status("params", path, written, Vec::new()));
    }
    if let Some(dir) = &args.plots {
        let figures = crate::io::plots::render(diagnosis);
        let written = crate::io::plots::write(dir, &figures, heading).map_err(|f| f.message);
        outputs.push(status("plots", dir, written, figures.skipped));
    }
    outputs
}

fn status(
    output: &'static str,
    path: &Path,
    written: Result<(), String>,
    notes: Vec<String>,
) -> OutputStatus {
    OutputStatus {
        output,
        path: path.display().to_string(),
        written: written.is_ok(),
        error: written.err(),
        notes,
    }
}
