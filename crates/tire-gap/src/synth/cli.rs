//! The `synth` subcommand: write synthetic test-rig data (CSV) and, optionally, a JSON record
//! of the tire and effects in it.

use std::io::Write;
use std::path::PathBuf;

use clap::Args;

use super::{DEFAULT_ROWS, Effect, SynthConfig, TireKind, generate_with_truth, write_csv};
use crate::cli::{Failure, bad_input, failure, write_whole};

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
    /// Write the CSV here instead of standard output.
    #[arg(long, short, value_name = "OUT.csv")]
    pub out: Option<PathBuf>,
    /// Also write what was generated (tire, effects, magnitudes) as JSON here.
    #[arg(long, value_name = "TRUTH.json")]
    pub truth: Option<PathBuf>,
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
}

/// Runs `tire-gap synth`; files are written whole or not at all.
pub fn run(args: &SynthArgs, stdout: &mut impl Write) -> Result<(), Failure> {
    let cfg = args.config().map_err(bad_input)?;
    let (ds, truth) = generate_with_truth(&cfg);
    if let Some(path) = &args.truth {
        let text = serde_json::to_string_pretty(&truth)
            .map_err(|e| failure(format!("cannot encode the truth record: {e}")))?;
        write_whole(path, (text + "\n").as_bytes())?;
    }
    match &args.out {
        Some(path) => {
            let mut csv = Vec::new();
            write_csv(&ds, &mut csv)
                .map_err(|e| failure(format!("cannot encode the data: {e}")))?;
            write_whole(path, &csv)
        }
        None => write_csv(&ds, stdout).map_err(|e| failure(format!("cannot write the data: {e}"))),
    }
}
