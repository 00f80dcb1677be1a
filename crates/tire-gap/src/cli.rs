//! The command line: argument parsing and the `diagnose`, `prepare` and (with the `synth`
//! feature) `synth` commands, over the library. A failure carries its kind; `main` maps the
//! kinds to exit codes. The options' ranges and defaults are the method's ([`Options`]).

use std::io::Write;
use std::path::PathBuf;

use clap::{Parser, Subcommand};

use crate::front::{check_targets, diagnose_loaded};
use crate::io::output::{Failure, FailureKind, bad_input, output_failure};
use crate::method::diagnose::Options;
use crate::method::fit::effects::{names_help, parse_names};
use crate::method::observer::OnStage;

/// A clap parser of a u16 within `range`.
fn within(range: std::ops::RangeInclusive<usize>) -> clap::builder::RangedI64ValueParser<u16> {
    clap::value_parser!(u16).range(*range.start() as i64..=*range.end() as i64)
}

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
    /// Write the rows a diagnosis would fit and score, as CSV (`run` = test block, `fold` =
    /// the cross-validation fold that holds it out), after the rows and channels the rules
    /// leave out: to see what was read, or to fit another model on the same folds.
    Prepare(PrepareArgs),
    /// Generate synthetic test-rig data with chosen effects switched on.
    #[cfg(feature = "synth")]
    Synth(crate::synth::cli::SynthArgs),
}

/// Arguments of `tire-gap prepare`.
#[derive(Debug, Clone, clap::Args)]
pub struct PrepareArgs {
    /// Measurement files or directories, as for `diagnose`.
    #[arg(required = true, value_name = "FILE|DIR")]
    pub inputs: Vec<PathBuf>,
    /// The CSV file to write.
    #[arg(long, value_name = "OUT.csv")]
    pub out: PathBuf,
    /// Cross-validation folds, as for `diagnose`.
    #[arg(long, default_value_t = Options::default().folds as u16, value_parser = within(Options::FOLDS))]
    pub folds: u16,
    /// Seed of the split of blocks into folds, as for `diagnose`.
    #[arg(long, default_value_t = Options::default().seed)]
    pub seed: u64,
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
    #[arg(long, default_value_t = Options::default().folds as u16, value_parser = within(Options::FOLDS))]
    pub folds: u16,
    /// Seed of the split of runs into folds whose rounds and figures the report shows.
    #[arg(long, default_value_t = Options::default().seed)]
    pub seed: u64,
    /// Fold assignments (split seeds 1..=N) that must each select an effect for the verdict
    /// to name it; 1 takes the verdict from `--seed`'s assignment alone.
    #[arg(long, default_value_t = Options::default().stability_draws as u16, value_parser = within(Options::STABILITY_DRAWS))]
    pub stability_draws: u16,
    // Help: the effect names from their one list.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "EFFECT,...",
        help = names_help(
            "Test only these candidate effects, comma-separated: ",
            ", or `all` (the default)"
        )
    )]
    pub effects: Vec<String>,
    /// Print on stderr where the time went: each stage's wall time, the rows the models were
    /// evaluated on (values and exact derivatives) and what they cost at the bare formula's
    /// rate, as a share of the time the diagnosis had on its threads.
    #[arg(long)]
    pub profile: bool,
}

impl DiagnoseArgs {
    /// The diagnosis's settings these arguments ask for.
    pub fn options(&self) -> Result<Options, String> {
        Ok(Options {
            folds: self.folds as usize,
            seed: self.seed,
            stability_draws: self.stability_draws as usize,
            effects: (!self.effects.is_empty())
                .then(|| parse_names(&self.effects))
                .transpose()?,
            candidate_figures: self.plots.is_some(),
            ..Options::default()
        })
    }
}

/// What the process gives the command line that the library's safe Rust cannot: the
/// platform's own calls, made by the command line's `main`.
#[derive(Debug, Clone, Copy)]
pub struct Host {
    /// Gives memory the program freed back to the system where its allocator keeps it;
    /// called once the input is read and at each stage, so that the reading's working space
    /// is not counted on top of the diagnosis's.
    pub release_freed: fn(),
    /// The CPU time the process has used so far on all its threads, in seconds (`None`
    /// where the platform does not tell): `--profile`'s busy threads per stage.
    pub cpu_seconds: fn() -> Option<f64>,
}

/// Runs the command line; `progress` is shown only on a terminal.
pub fn run(cli: Cli, stdout: &mut impl Write, host: Host) -> Result<(), Failure> {
    match cli.command {
        #[cfg(feature = "synth")]
        Command::Synth(args) => crate::synth::cli::run(&args, stdout),
        Command::Diagnose(args) => run_diagnose(&args, stdout, host),
        Command::Prepare(args) => run_prepare(&args, stdout),
    }
}

/// `tire-gap prepare`: the prepared rows to `--out`, a summary with the readers' notes on
/// stdout.
pub fn run_prepare(args: &PrepareArgs, stdout: &mut impl Write) -> Result<(), Failure> {
    let options = Options {
        folds: args.folds as usize,
        seed: args.seed,
        ..Options::default()
    };
    let (files, mut notes) =
        crate::io::input::expand(&args.inputs).map_err(|e| bad_input(e.to_string()))?;
    if files.iter().any(|f| f == &args.out) {
        return Err(bad_input(format!(
            "--out {} is an input file",
            args.out.display()
        )));
    }
    let loaded = crate::front::load_many(&files).map_err(|e| bad_input(e.to_string()))?;
    notes.extend(loaded.notes.iter().cloned());
    let prepared = crate::method::diagnose::prepare(&loaded.dataset, &options)
        .map_err(|e| bad_input(e.to_string()))?;
    let mut csv = Vec::new();
    crate::io::csv_out::write_csv_with(&prepared.dataset, Some(("fold", &prepared.fold)), &mut csv)
        .map_err(|e| output_failure(format!("cannot encode the rows: {e}")))?;
    crate::io::output::write_whole(&args.out, &csv)?;
    notes.extend(prepared.limitations.iter().map(|l| l.reason.clone()));
    let mut out = format!(
        "{}: {} rows in {} test blocks, {}-fold split seed {}, written to {}\n",
        args.inputs
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(" "),
        prepared.dataset.len(),
        prepared.blocks.len(),
        options.folds,
        options.seed,
        args.out.display()
    );
    for n in &notes {
        out += &format!("  - {n}\n");
    }
    write!(stdout, "{out}").map_err(|e| output_failure(format!("cannot write the summary: {e}")))
}

/// `tire-gap diagnose`: output paths are checked before any work; once the diagnosis is made
/// its report is always printed, and an output that could not be written after all (a fit the
/// FMU would reject, a full disk) is named in it and gives exit code 3.
pub fn run_diagnose(
    args: &DiagnoseArgs,
    stdout: &mut impl Write,
    host: Host,
) -> Result<(), Failure> {
    let options = args.options().map_err(bad_input)?;
    let (files, notes) =
        crate::io::input::expand(&args.inputs).map_err(|e| bad_input(e.to_string()))?;
    check_targets(args.params.as_deref(), args.plots.as_deref(), &files)?;
    let bar = crate::progress::Progress::new();
    let loaded = crate::front::load_many(&files).map_err(|e| bad_input(e.to_string()))?;
    (host.release_freed)();
    let shown: Vec<String> = args
        .inputs
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    let profiler = crate::profile::Profiler::new(host.cpu_seconds);
    // Each stage clocked (with --profile), and the memory the last one freed given back.
    let observer = OnStage {
        inner: &bar,
        before_stage: |msg: &str| {
            (host.release_freed)();
            if args.profile {
                profiler.record(msg);
            }
        },
    };
    let finished = diagnose_loaded(loaded, notes, shown.join(" "), &options, &observer)?;
    if args.profile {
        bar.finish();
        eprint!("{}", profiler.report(rayon::current_num_threads()));
    }
    if args.params.is_some() || args.plots.is_some() {
        bar.stage("writing the fitted model and figures", 0);
    }
    let mut outputs = Vec::new();
    if let Some(path) = &args.params {
        outputs.push(finished.write_params(path));
    }
    if let Some(dir) = &args.plots {
        outputs.push(finished.write_plots(dir));
    }
    bar.finish();
    let missing: Vec<String> = outputs
        .iter()
        .filter_map(|o| Some(format!("{} {}: {}", o.output, o.path, o.error.as_ref()?)))
        .collect();
    let out = if args.json {
        finished.json(outputs)
    } else {
        finished.text(outputs)
    };
    writeln!(stdout, "{out}")
        .map_err(|e| output_failure(format!("cannot write the report: {e}")))?;
    if missing.is_empty() {
        Ok(())
    } else {
        Err(Failure {
            kind: FailureKind::Incomplete,
            message: format!(
                "the report is complete, but not every output was written: {}",
                missing.join("; ")
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;
    use mf87::extensions::Extension;

    use super::Cli;

    #[test]
    fn every_effect_is_named_in_the_help_of_the_options_that_take_effects() {
        let mut cli = Cli::command();
        let mut subcommands = vec!["diagnose"];
        if cfg!(feature = "synth") {
            subcommands.push("synth");
        }
        for name in subcommands {
            let sub = cli.find_subcommand_mut(name).unwrap();
            let effects = sub
                .get_arguments()
                .find(|a| a.get_id() == "effects")
                .unwrap();
            let help = effects.get_help().unwrap().to_string();
            for effect in Extension::NAMES {
                assert!(help.contains(effect), "{name} --effects: {help}");
            }
        }
    }
}
