//! Synthetic test-rig data from a tire that is not the paper's, with chosen effects switched on.
//!
//! The data imitate a flat-track tire test machine: test blocks (runs) sampled at 100 Hz,
//! each with its own speed, inflation pressure and tread temperature (drawn independently of
//! the block type, load and camber), covering slip-angle sweeps at several loads and cambers,
//! slip-ratio sweeps, combined-slip sweeps and sinusoidal slip angle at 0.5..8 Hz (see
//! [`blocks`] for the program). Every dataset has every column and varies every condition,
//! whichever effects are on, so a column's presence gives nothing away.
//!
//! The "true tire" is a base tire ([`TireKind`]) that already differs from the paper's
//! coefficient table, with the chosen [`Extension`]s applied in forms that differ from the ones
//! the diagnosis tool fits (see [`effects`]). Sensor noise is added last: Gaussian, on forces
//! and on the measured inputs ([`NOISE`]).
//!
//! Everything is reproducible from the seed: each part draws from its own ChaCha8 stream, so
//! switching an effect on changes the data by that effect alone. The random draws are
//! platform-independent; the float maths (`sin`, `exp`, `powf` of the platform's libm) may
//! differ in the last bit between platforms, so files are bit-identical on one platform and
//! equal to ~1e-15 relative across platforms.
//!
//! Output is in the internal units of [`Dataset`]; [`write_csv`] writes the CSV the tool reads,
//! [`tydex::write_tydex_programme`] a TYDEX programme (one `.tdx` file per run).
//! [`programme`] makes a programme shaped like a Tire Test Consortium run file (many sweeps
//! in one run, stepped conditions, pauses in time) and writes it as such a file.

pub mod blocks;
pub mod cli;
pub mod effects;
pub mod programme;
mod rng;
mod tires;
pub mod tydex;

#[cfg(test)]
mod tests;

use std::collections::BTreeMap;
use std::fmt;

use mf87::extensions::Extension;
use serde::Serialize;

use crate::data::{Dataset, Quantity};
pub use blocks::DrawnCondition;
use blocks::{Block, SAMPLE_RATE_HZ};
use effects::{EffectSet, TrueTire};
use rng::{normal, stream};
use tires::BaseTire;

pub use crate::io::csv_out::{csv_columns, write_csv};
pub use effects::{Forms, PRESSURE_NOMINAL_KPA, TEMPERATURE_REFERENCE_C};

/// What input drives an effect, i.e. where in the data it shows.
pub fn effect_driver(e: Extension) -> &'static str {
    effects::entry(e).driver
}

/// The base tire of the synthetic data (what the tire is when no effect is on).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TireKind {
    /// The 1987 formula itself with every coefficient of the paper's table perturbed
    /// (friction +-15-20 %, stiffness +-10-20 %, shape +-6 %, curvature +-20 %, camber +-25 %).
    /// The paper's model can fit it exactly in pure slip.
    Mf87Perturbed,
    /// A Magic-Formula-5.2-style pure-slip tire with nominal-load normalisation, MF 5.2's load,
    /// camber and drive/brake asymmetry laws and a trail-based aligning moment (parameters
    /// +-5-30 % around a typical passenger tire). Fits the 1987 formula well, not exactly.
    #[default]
    Mf52,
    /// A brush-model tire (parabolic pressure) with static-to-kinetic friction fall-off, a
    /// saturating stiffness law, camber as equivalent slip and a brush aligning moment.
    /// The least like the 1987 formula.
    Brush,
}

impl TireKind {
    pub const ALL: [TireKind; 3] = [TireKind::Mf87Perturbed, TireKind::Mf52, TireKind::Brush];

    pub fn id(self) -> &'static str {
        match self {
            TireKind::Mf87Perturbed => "mf87_perturbed",
            TireKind::Mf52 => "mf52",
            TireKind::Brush => "brush",
        }
    }

    pub fn from_id(id: &str) -> Option<TireKind> {
        TireKind::ALL.into_iter().find(|k| k.id() == id)
    }
}

impl fmt::Display for TireKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())
    }
}

/// What to generate.
#[derive(Debug, Clone, PartialEq)]
pub struct SynthConfig {
    /// Seed of every random choice (test design, tire, effect magnitudes, noise).
    pub seed: u64,
    /// Effects present in the true tire.
    pub effects: Vec<Extension>,
    /// Base tire.
    pub tire: TireKind,
    /// Approximate number of rows.
    pub rows_target: usize,
    /// Multiplier on the sensor noise of [`NOISE`] (0 = noise-free, 1 = nominal); the
    /// command line takes 0..=[`MAX_NOISE`].
    pub noise: f64,
    /// Two block conditions the programme moves together (see `blocks::plan`).
    pub coupled: Option<[DrawnCondition; 2]>,
    /// Wear over the programme: the tire's forces fall by this fraction from the first run
    /// to the last, in proportion to the run's position (0 = none).
    pub drift: f64,
    /// The forms the effects take: physical ones unlike the diagnosis's (default), or MF
    /// 6.1's where it has one (the forms the diagnosis fits).
    pub forms: Forms,
}

/// Default approximate number of rows.
pub const DEFAULT_ROWS: usize = 35_000;

/// Row targets the command line accepts. The program has about 1,300 rows at least, whatever
/// the target (every block has a minimum length), so smaller targets would mean nothing; at
/// the top the data set and its CSV (about 200 bytes a row) stay within a few hundred MB,
/// at twice the largest benchmark (1M rows).
pub const ROWS_RANGE: std::ops::RangeInclusive<usize> = 1_000..=2_000_000;

/// The largest noise multiplier the command line accepts: 200 N on Fx and Fy, 0.3 m/s on
/// speed, 100 N on Fz, 4 degC on temperature. At that level the measured speed, load and
/// temperature stay more than 15 standard deviations inside the ranges tire-gap reads as
/// plausible (the slowest blocks run at 5 m/s); at 100 times nominal, speeds would go
/// negative and the tool would refuse its own data.
pub const MAX_NOISE: f64 = 10.0;

impl Default for SynthConfig {
    fn default() -> Self {
        SynthConfig {
            seed: 0,
            effects: Vec::new(),
            tire: TireKind::default(),
            rows_target: DEFAULT_ROWS,
            noise: 1.0,
            coupled: None,
            drift: 0.0,
            forms: Forms::Physical,
        }
    }
}

/// Standard deviations of the additive Gaussian sensor noise at `noise = 1`, internal units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NoiseLevels {
    pub fx_n: f64,
    pub fy_n: f64,
    pub mz_nm: f64,
    pub fz_n: f64,
    pub alpha_rad: f64,
    pub kappa: f64,
    pub gamma_rad: f64,
    pub speed_mps: f64,
    pub pressure_kpa: f64,
    pub temperature_c: f64,
}

/// Nominal sensor noise: 20 N on Fx and Fy (0.5 % of a 4 kN load), 0.8 N.m on Mz, 10 N on
/// Fz, 0.01 deg on slip angle, 0.0001 on slip ratio, 0.005 deg on camber, 0.03 m/s, 0.3 kPa,
/// 0.4 degC. Through the slip stiffnesses the input noise alone is worth about 10-20 N of
/// force noise (0.01 deg x 1 kN/deg, 0.0001 x 100-200 kN).
pub const NOISE: NoiseLevels = NoiseLevels {
    fx_n: 20.0,
    fy_n: 20.0,
    mz_nm: 0.8,
    fz_n: 10.0,
    alpha_rad: 0.01 * std::f64::consts::PI / 180.0,
    kappa: 1e-4,
    gamma_rad: 0.005 * std::f64::consts::PI / 180.0,
    speed_mps: 0.03,
    pressure_kpa: 0.3,
    temperature_c: 0.4,
};

/// What the generator put into a dataset: the base tire and the effects with their forms and
/// magnitudes (for provenance and for judging a diagnosis).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SynthTruth {
    pub seed: u64,
    pub tire: TireKind,
    pub tire_params: BTreeMap<String, f64>,
    pub effects: Vec<EffectTruth>,
    pub noise: NoiseLevels,
    /// Conditions moved together across runs, if any.
    pub coupled: Option<[DrawnCondition; 2]>,
    /// Fraction of force lost from the first run to the last (wear).
    pub drift: f64,
    /// The forms the effects take.
    pub forms: Forms,
    pub rows: usize,
    pub runs: usize,
}

/// One effect as generated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EffectTruth {
    pub effect: Extension,
    /// What drives it ([`effect_driver`]).
    pub driver: &'static str,
    pub params: BTreeMap<String, f64>,
}

/// Synthetic data for `cfg`.
pub fn generate(cfg: &SynthConfig) -> Dataset {
    simulate(cfg).dataset
}

/// Synthetic data for `cfg` and a record of what is in it.
pub fn generate_with_truth(cfg: &SynthConfig) -> (Dataset, SynthTruth) {
    let sim = simulate(cfg);
    (sim.dataset, sim.truth)
}

/// The full result, with the test program (for tests).
pub(crate) struct Simulation {
    pub dataset: Dataset,
    pub truth: SynthTruth,
    /// The test program, in data order (read by the tests).
    #[cfg_attr(not(test), allow(dead_code))]
    pub blocks: Vec<Block>,
}

pub(crate) fn simulate(cfg: &SynthConfig) -> Simulation {
    let blocks = blocks::plan(
        cfg.rows_target,
        cfg.coupled,
        &mut stream(cfg.seed, "design"),
    );
    let tire = TrueTire {
        base: BaseTire::sample(cfg.tire, &mut stream(cfg.seed, cfg.tire.id())),
        effects: EffectSet::sample(cfg.seed, &cfg.effects, cfg.forms),
    };
    let rows: usize = blocks.iter().map(|b| b.n).sum();
    let (run, fz, cols) = measure(cfg, &blocks, &tire, rows);
    let [
        time,
        speed,
        alpha,
        kappa,
        gamma,
        pressure,
        temperature,
        fx,
        fy,
        mz,
    ] = cols;
    let ds = Dataset {
        source: source_name(cfg),
        run: run.into(),
        fz: fz.into(),
        time: Some(time.into()),
        speed: Some(speed.into()),
        alpha: Some(alpha.into()),
        kappa: Some(kappa.into()),
        gamma: Some(gamma.into()),
        pressure: Some(pressure.into()),
        temperature: Some(temperature.into()),
        fx: Some(fx.into()),
        fy: Some(fy.into()),
        mz: Some(mz.into()),
    };
    let truth = SynthTruth {
        seed: cfg.seed,
        tire: cfg.tire,
        tire_params: tire.base.params(),
        effects: tire
            .effects
            .params()
            .into_iter()
            .map(|(effect, params)| EffectTruth {
                effect,
                driver: effect_driver(effect),
                params,
            })
            .collect(),
        noise: NOISE,
        coupled: cfg.coupled,
        drift: cfg.drift,
        forms: cfg.forms,
        rows,
        runs: blocks.len(),
    };
    Simulation {
        dataset: ds,
        truth,
        blocks,
    }
}

/// The dataset's source: seed, tire, effects, noise and the programme's departures.
fn source_name(cfg: &SynthConfig) -> String {
    format!(
        "synthetic(seed={}, tire={}, effects=[{}], noise={}{})",
        cfg.seed,
        cfg.tire.id(),
        cfg.effects
            .iter()
            .map(|e| e.name())
            .collect::<Vec<_>>()
            .join(","),
        cfg.noise,
        programme_note(cfg)
    )
}

/// What the rig records of `tire` over `blocks` (`rows` in all): the run ids, the measured
/// load, and time, speed, alpha, kappa, gamma, pressure, temperature, Fx, Fy, Mz, with noise
/// and wear.
fn measure(
    cfg: &SynthConfig,
    blocks: &[Block],
    tire: &TrueTire,
    rows: usize,
) -> (Vec<i64>, Vec<f64>, [Vec<f64>; 10]) {
    let noise_rng = &mut stream(cfg.seed, "noise");
    let k = if cfg.noise.is_finite() {
        cfg.noise.max(0.0)
    } else {
        0.0
    };
    let (mut run, mut fz) = (Vec::with_capacity(rows), Vec::with_capacity(rows));
    let mut cols: [Vec<f64>; 10] = std::array::from_fn(|_| Vec::with_capacity(rows));
    let dt = 1.0 / SAMPLE_RATE_HZ;
    let last = blocks.len().saturating_sub(1).max(1) as f64;
    for (position, block) in blocks.iter().enumerate() {
        let worn = 1.0 - cfg.drift * position as f64 / last;
        let mut lag = tire.block_start();
        for i in 0..block.n {
            let x = block.sample(i);
            let mut f = tire.steady(&x);
            f = tire.lagged(&mut lag, f, &x, x.speed * dt);
            f.fx -= tire.fx_subtracted(&x);
            let (fx, fy, mz) = (worn * f.fx + tire.fx_offset(&x), worn * f.fy, worn * f.mz);
            // Always ten draws per row, in a fixed order, whatever `noise` is.
            let mut n = |sd: f64| k * sd * normal(noise_rng);
            run.push(block.run);
            fz.push(x.fz + n(NOISE.fz_n));
            let measured = [
                x.t,
                x.speed + n(NOISE.speed_mps),
                x.alpha + n(NOISE.alpha_rad),
                tire.measured_kappa(&x) + n(NOISE.kappa),
                x.gamma + n(NOISE.gamma_rad),
                x.pressure + n(NOISE.pressure_kpa),
                x.temp + n(NOISE.temperature_c),
                fx + n(NOISE.fx_n),
                fy + n(NOISE.fy_n),
                mz + n(NOISE.mz_nm),
            ];
            for (col, v) in cols.iter_mut().zip(measured) {
                col.push(v);
            }
        }
    }
    (run, fz, cols)
}

/// The programme's departures from the default design, for the source name.
fn programme_note(cfg: &SynthConfig) -> String {
    let mut note = String::new();
    if cfg.forms != Forms::Physical {
        note += &format!(", forms={}", cfg.forms.name());
    }
    if let Some([a, b]) = cfg.coupled {
        note += &format!(", coupled={}:{}", a.name(), b.name());
    }
    if cfg.drift != 0.0 {
        note += &format!(", drift={}", cfg.drift);
    }
    note
}

/// Where `ds` holds a non-finite value (first column in [`Quantity::ALL`] order, first row);
/// `None` when every value is finite.
pub fn first_non_finite(ds: &Dataset) -> Option<(Quantity, usize)> {
    Quantity::ALL.into_iter().find_map(|q| {
        let col = ds.column(q)?;
        col.iter().position(|v| !v.is_finite()).map(|row| (q, row))
    })
}
