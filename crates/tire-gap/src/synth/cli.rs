//! The `synth` subcommand: write synthetic test-rig data (CSV, or a TYDEX programme of one
//! `.tdx` file per run) and, optionally, a JSON record of the tire and effects in it.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::Args;

use super::tydex::{self, TydexUnits};
use super::{
    DEFAULT_ROWS, DrawnCondition, Forms, MAX_NOISE, ROWS_RANGE, SynthConfig, TireKind,
    first_non_finite, generate_with_truth, write_csv,
};
use crate::data::Dataset;
use crate::io::output::{Failure, bad_input, output_failure, write_whole};

/// Output format of `tire-gap synth`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum OutputFormat {
    /// One CSV file (or standard output), all runs.
    #[default]
    Csv,
    /// A TYDEX measurement programme: a directory with one .tdx file per run.
    Tydex,
}

/// Arguments of `tire-gap synth`.
#[derive(Debug, Clone, Args)]
pub struct SynthArgs {
    /// Seed of every random choice: same seed, same data.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    // Help: the effect names from their one list.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "EFFECT,...",
        help = crate::method::fit::effects::names_help(
            "Effects to switch on, comma-separated: ",
            ", or `all`. None by default"
        )
    )]
    pub effects: Vec<String>,
    /// The forms the effects take: `physical` (forms unlike those the diagnosis fits) or
    /// `mf61` (MF 6.1's for combined slip, inflation pressure, the shifts and camber on the
    /// peak: the forms the diagnosis fits; the other effects stay physical).
    #[arg(long, default_value = "physical", value_name = "FORMS")]
    pub forms: String,
    /// Base tire: mf87_perturbed, mf52 or brush.
    #[arg(long, default_value = "mf52")]
    pub tire: String,
    /// Approximate number of rows, 1000..=2000000 (every test block has a minimum length,
    /// so small targets come out longer: 1000 gives about 1600).
    #[arg(long, default_value_t = DEFAULT_ROWS)]
    pub rows: usize,
    /// Sensor-noise multiplier, 0..=10 (0 = none, 1 = nominal: 20 N on Fx and Fy).
    #[arg(long, default_value_t = 1.0)]
    pub noise: f64,
    /// A poorly designed programme: two block conditions that rise and fall together
    /// across runs, as `A:B` with A and B among speed, pressure, temperature (B follows A's
    /// rank order), e.g. `temperature:pressure` for a tire whose pressure rises as it warms.
    #[arg(long, value_name = "A:B")]
    pub couple: Option<String>,
    /// Wear over the programme: the tire's forces fall by this fraction from the first run
    /// to the last, 0..=0.5 (0.05 = 5 % less force in the last run).
    #[arg(long, default_value_t = 0.0)]
    pub drift: f64,
    /// Output format: csv (one file) or tydex (a directory with one .tdx file per run,
    /// named run_0001.tdx, ... after the run id, which is also the file's MEASID).
    #[arg(long, value_enum, default_value_t = OutputFormat::Csv)]
    pub format: OutputFormat,
    /// Units of the .tdx files, only with --format tydex (default: engineering). In both,
    /// FYW and MZW are in ISO axes (y left): minus the paper's Fy and Mz.
    #[arg(long, value_enum, value_name = "UNITS")]
    pub tydex_units: Option<TydexUnits>,
    /// csv: write the file here instead of standard output. tydex (required): the
    /// directory, created if missing; one that already holds .tdx files is refused. Written
    /// whole or not at all.
    #[arg(long, short, value_name = "PATH")]
    pub out: Option<PathBuf>,
    /// Also write what was generated (tire, effects, magnitudes) as JSON here.
    #[arg(long, value_name = "TRUTH.json")]
    pub truth: Option<PathBuf>,
}

/// Where and how the data go.
#[derive(Debug, Clone, PartialEq)]
pub enum Output {
    /// CSV on standard output.
    CsvStdout,
    /// CSV in this file.
    CsvFile(PathBuf),
    /// A TYDEX programme in this directory.
    Tydex { dir: PathBuf, units: TydexUnits },
}

impl SynthArgs {
    /// The configuration these arguments ask for.
    pub fn config(&self) -> Result<SynthConfig, String> {
        let effects = crate::method::fit::effects::parse_names(&self.effects)?;
        let tire = TireKind::from_id(self.tire.trim()).ok_or_else(|| {
            format!(
                "unknown tire `{}`; known: {}",
                self.tire,
                TireKind::ALL.map(TireKind::id).join(", ")
            )
        })?;
        if !(self.noise.is_finite() && (0.0..=MAX_NOISE).contains(&self.noise)) {
            return Err(format!(
                "--noise {} is out of range: it must lie in 0..={MAX_NOISE} (a multiplier of the \
                 nominal sensor noise; the bound keeps measured speed, load and temperature \
                 plausible)",
                readable(self.noise)
            ));
        }
        if !ROWS_RANGE.contains(&self.rows) {
            return Err(format!(
                "--rows {} is out of range: it must lie in {}..={}",
                self.rows,
                ROWS_RANGE.start(),
                ROWS_RANGE.end()
            ));
        }
        if !(self.drift.is_finite() && (0.0..=MAX_DRIFT).contains(&self.drift)) {
            return Err(format!(
                "--drift {} is out of range: it must lie in 0..={MAX_DRIFT} (the fraction of \
                 force the tire loses from the first run to the last)",
                readable(self.drift)
            ));
        }
        Ok(SynthConfig {
            seed: self.seed,
            effects,
            tire,
            rows_target: self.rows,
            noise: self.noise,
            coupled: self.couple.as_deref().map(coupled).transpose()?,
            drift: self.drift,
            forms: Forms::from_name(self.forms.trim()).ok_or_else(|| {
                format!(
                    "unknown forms `{}`; known: {}",
                    self.forms,
                    Forms::ALL.map(Forms::name).join(", ")
                )
            })?,
        })
    }

    /// The output these arguments ask for.
    pub fn output(&self) -> Result<Output, String> {
        match (self.format, &self.out) {
            (OutputFormat::Csv, _) if self.tydex_units.is_some() => {
                Err("--tydex-units applies to --format tydex only".to_string())
            }
            (OutputFormat::Csv, None) => Ok(Output::CsvStdout),
            (OutputFormat::Csv, Some(path)) => Ok(Output::CsvFile(path.clone())),
            (OutputFormat::Tydex, None) => Err(
                "--format tydex writes a directory of .tdx files: give it with --out DIR"
                    .to_string(),
            ),
            (OutputFormat::Tydex, Some(dir)) => Ok(Output::Tydex {
                dir: dir.clone(),
                units: self.tydex_units.unwrap_or_default(),
            }),
        }
    }
}

/// The largest wear drift the command line accepts: half the force lost over the programme.
pub const MAX_DRIFT: f64 = 0.5;

/// `A:B` of `--couple`.
fn coupled(text: &str) -> Result<[DrawnCondition; 2], String> {
    let known = || DrawnCondition::ALL.map(DrawnCondition::name).join(", ");
    let (a, b) = text.split_once(':').ok_or_else(|| {
        format!(
            "--couple {text:?}: give two conditions as A:B, each one of {}",
            known()
        )
    })?;
    let parse = |name: &str| {
        DrawnCondition::from_name(name.trim()).ok_or_else(|| {
            format!(
                "--couple {text:?}: unknown condition `{}`; known: {}",
                name.trim(),
                known()
            )
        })
    };
    let (a, b) = (parse(a)?, parse(b)?);
    if a == b {
        return Err(format!(
            "--couple {text:?}: a condition cannot be coupled to itself"
        ));
    }
    Ok([a, b])
}

/// A number as typed: `1e308` rather than 309 digits.
fn readable(x: f64) -> String {
    if x.is_finite() && x != 0.0 && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        x.to_string()
    }
}

/// Runs `tire-gap synth`; files are written whole or not at all.
pub fn run(args: &SynthArgs, stdout: &mut impl Write) -> Result<(), Failure> {
    let cfg = args.config().map_err(bad_input)?;
    let output = args.output().map_err(bad_input)?;
    // A directory that would be refused fails now, not after the generation.
    if let Output::Tydex { dir, .. } = &output {
        tydex::check_programme_dir(dir)?;
    }
    let (ds, truth) = generate_with_truth(&cfg);
    let truth = match &args.truth {
        Some(path) => Some((
            path.as_path(),
            serde_json::to_string_pretty(&truth)
                .map_err(|e| output_failure(format!("cannot encode the truth record: {e}")))?,
        )),
        None => None,
    };
    write_outputs(&ds, &output, truth, stdout)
}

/// Writes the data, then the truth record (path, JSON text), after checking that every
/// value is finite: nothing is written otherwise.
pub fn write_outputs(
    ds: &Dataset,
    output: &Output,
    truth: Option<(&Path, String)>,
    stdout: &mut impl Write,
) -> Result<(), Failure> {
    if let Some((q, row)) = first_non_finite(ds) {
        let value = ds.column(q).map_or(f64::NAN, |c| c[row]);
        return Err(output_failure(format!(
            "internal error: the generated data hold a non-finite value ({} = {value} at row {}, \
             run {}); nothing written",
            crate::io::input::csv::canonical(q),
            row + 1,
            ds.run[row]
        )));
    }
    match output {
        Output::CsvStdout => write_csv(ds, stdout)
            .map_err(|e| output_failure(format!("cannot write the data: {e}")))?,
        Output::CsvFile(path) => {
            let mut csv = Vec::new();
            write_csv(ds, &mut csv)
                .map_err(|e| output_failure(format!("cannot encode the data: {e}")))?;
            write_whole(path, &csv)?;
        }
        Output::Tydex { dir, units } => {
            tydex::write_tydex_programme(ds, *units, dir)?;
        }
    }
    if let Some((path, text)) = truth {
        write_whole(path, (text + "\n").as_bytes())?;
    }
    Ok(())
}
