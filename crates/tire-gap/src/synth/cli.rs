//! The `synth` subcommand: write synthetic test-rig data (CSV, or a TYDEX programme of one
//! `.tdx` file per run) and, optionally, a JSON record of the tire and effects in it.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::Args;

use super::tydex::{self, TydexUnits};
use super::{DEFAULT_ROWS, Effect, SynthConfig, TireKind, generate_with_truth, write_csv};
use crate::cli::{Failure, bad_input, failure, write_whole};
use crate::data::Dataset;

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
    /// Effects to switch on, comma-separated: combined_slip, relaxation_length,
    /// inflation_pressure, speed_dependence, ply_steer_conicity, rolling_resistance,
    /// temperature, or `all`. None by default.
    #[arg(long, value_delimiter = ',', value_name = "EFFECT,...")]
    pub effects: Vec<String>,
    /// Base tire: mf87_perturbed, mf52 or brush.
    #[arg(long, default_value = "mf52")]
    pub tire: String,
    /// Approximate number of rows.
    #[arg(long, default_value_t = DEFAULT_ROWS)]
    pub rows: usize,
    /// Sensor-noise multiplier (0 = none, 1 = nominal).
    #[arg(long, default_value_t = 1.0)]
    pub noise: f64,
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
        let mut effects = Vec::new();
        for name in &self.effects {
            let name = name.trim();
            if name.is_empty() {
                continue;
            }
            if name == "all" {
                effects.extend(Effect::ALL);
                continue;
            }
            let e = Effect::from_id(name).ok_or_else(|| {
                format!(
                    "unknown effect `{name}`; known: {}, all",
                    Effect::ALL.map(Effect::id).join(", ")
                )
            })?;
            effects.push(e);
        }
        effects.sort();
        effects.dedup();
        let tire = TireKind::from_id(self.tire.trim()).ok_or_else(|| {
            format!(
                "unknown tire `{}`; known: {}",
                self.tire,
                TireKind::ALL.map(TireKind::id).join(", ")
            )
        })?;
        if !(self.noise.is_finite() && self.noise >= 0.0) {
            return Err(format!(
                "--noise must be a finite number >= 0, got {}",
                self.noise
            ));
        }
        if self.rows == 0 || self.rows > 50_000_000 {
            return Err(format!(
                "--rows must lie in 1..=50000000, got {}",
                self.rows
            ));
        }
        Ok(SynthConfig {
            seed: self.seed,
            effects,
            tire,
            rows_target: self.rows,
            noise: self.noise,
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
                .map_err(|e| failure(format!("cannot encode the truth record: {e}")))?,
        )),
        None => None,
    };
    write_outputs(&ds, &output, truth, stdout)
}

/// Writes the data, then the truth record (path, JSON text).
pub fn write_outputs(
    ds: &Dataset,
    output: &Output,
    truth: Option<(&Path, String)>,
    stdout: &mut impl Write,
) -> Result<(), Failure> {
    match output {
        Output::CsvStdout => {
            write_csv(ds, stdout).map_err(|e| failure(format!("cannot write the data: {e}")))?
        }
        Output::CsvFile(path) => {
            let mut csv = Vec::new();
            write_csv(ds, &mut csv).map_err(|e| failure(format!("cannot encode the data: {e}")))?;
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
