//! A synthetic programme shaped like a Tire Test Consortium run file: many sweeps in ONE run,
//! at stepped loads, cambers and pressures (and, drive/brake, slip angles), constant speed,
//! 100 Hz, with pauses in time.
//!
//! Order, as a TTC programme runs it: for each pressure, for each camber, (drive/brake: for
//! each slip angle,) for each load, one sweep. Between two sweeps the rig ramps the load,
//! camber and held slip angle linearly to the next set point over `ramp_s` (the swept slip at
//! zero) and holds them for `dwell_s`; a new pressure comes after a pause in the recording
//! (`pressure_pause_s`, no rows), and any other change is preceded by a pause with
//! probability `pause_probability`. Cornering sweeps the slip angle 0 -> +12 -> -12 -> 0 deg at
//! zero slip ratio; drive/brake sweeps the slip ratio 0 -> +0.2 -> -0.2 -> 0 at the held slip
//! angle. The load rises by up to 3 % with the swept slip (load control), the pressure by
//! 0.5 kPa over each pressure's stretch, the tread temperature with the slip.
//!
//! With `dead_slip_ratio`, the slip-ratio channel reads -1 on every row (a wheel-speed signal
//! at zero), the forces being those of the true slip.

use std::fmt::Write as _;
use std::ops::Range;

use mf87::extensions::Extension;
use mf87::units::{degrees_to_radians, radians_to_degrees};

use super::blocks::{SAMPLE_RATE_HZ, TrueSample, ramp_through, triangle};
use super::effects::{EffectSet, Forces, TrueTire};
use super::rng::{SynthRng, normal, stream, uniform};
use super::tires::BaseTire;
use super::{NOISE, TireKind};
use crate::data::Dataset;

/// What the programme sweeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgrammeKind {
    /// Slip-angle sweeps at zero slip ratio.
    Cornering,
    /// Slip-ratio sweeps at held slip angles.
    DriveBrake,
}

/// What to generate.
#[derive(Debug, Clone, PartialEq)]
pub struct ProgrammeConfig {
    pub seed: u64,
    pub kind: ProgrammeKind,
    pub tire: TireKind,
    pub effects: Vec<Extension>,
    /// The run id of every row (a TTC file's run number).
    pub run: i64,
    pub loads_n: Vec<f64>,
    pub pressures_kpa: Vec<f64>,
    pub cambers_deg: Vec<f64>,
    /// Slip angles held during drive/brake sweeps \[deg\] (cornering ignores them).
    pub slip_angles_deg: Vec<f64>,
    pub speed_mps: f64,
    /// Length of one sweep \[s\].
    pub sweep_s: f64,
    /// Ramp from one set point to the next \[s\].
    pub ramp_s: f64,
    /// Hold at the new set point before the sweep \[s\].
    pub dwell_s: f64,
    /// Pause in the recording at every pressure change \[s\].
    pub pressure_pause_s: f64,
    /// Probability of a pause (of 2..20 s) before any other change of set point.
    pub pause_probability: f64,
    /// Multiplier on the sensor noise of [`NOISE`].
    pub noise: f64,
    /// The slip-ratio channel reads -1 throughout.
    pub dead_slip_ratio: bool,
}

impl ProgrammeConfig {
    /// 48 cornering sweeps: 4 pressures x 3 cambers x 4 loads, at 40 km/h.
    pub fn cornering(seed: u64) -> Self {
        ProgrammeConfig {
            seed,
            kind: ProgrammeKind::Cornering,
            tire: TireKind::Mf52,
            effects: Vec::new(),
            run: 1,
            loads_n: vec![1500.0, 3000.0, 4500.0, 6000.0],
            pressures_kpa: vec![180.0, 210.0, 240.0, 270.0],
            cambers_deg: vec![0.0, 2.0, 4.0],
            slip_angles_deg: vec![0.0],
            speed_mps: 40.0 / 3.6,
            sweep_s: 6.0,
            ramp_s: 1.0,
            dwell_s: 1.0,
            pressure_pause_s: 60.0,
            pause_probability: 0.15,
            noise: 1.0,
            dead_slip_ratio: false,
        }
    }

    /// 72 drive/brake sweeps: 3 pressures x 2 cambers x 3 slip angles x 4 loads.
    pub fn drive_brake(seed: u64) -> Self {
        ProgrammeConfig {
            kind: ProgrammeKind::DriveBrake,
            pressures_kpa: vec![200.0, 240.0, 280.0],
            cambers_deg: vec![0.0, 2.0],
            slip_angles_deg: vec![0.0, -3.0, -6.0],
            ..ProgrammeConfig::cornering(seed)
        }
    }

    /// Number of sweeps.
    pub fn sweeps(&self) -> usize {
        let held = match self.kind {
            ProgrammeKind::Cornering => 1,
            ProgrammeKind::DriveBrake => self.slip_angles_deg.len(),
        };
        self.pressures_kpa.len() * self.cambers_deg.len() * held * self.loads_n.len()
    }
}

/// One sweep as generated: its rows and set point (internal units).
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    pub rows: Range<usize>,
    pub fz: f64,
    pub pressure: f64,
    pub gamma: f64,
    /// The held slip angle (0 in cornering) \[rad\].
    pub alpha: f64,
}

/// A generated programme: one run, and where its sweeps are.
#[derive(Debug, Clone, PartialEq)]
pub struct Programme {
    pub dataset: Dataset,
    pub sweeps: Vec<Sweep>,
    /// Pauses in time (at pressure changes and drawn ones).
    pub pauses: usize,
}

/// A set point.
#[derive(Debug, Clone, Copy, PartialEq)]
struct SetPoint {
    fz: f64,
    pressure: f64,
    gamma: f64,
    alpha: f64,
}

/// The set points in programme order.
fn set_points(cfg: &ProgrammeConfig) -> Vec<SetPoint> {
    let held: Vec<f64> = match cfg.kind {
        ProgrammeKind::Cornering => vec![0.0],
        ProgrammeKind::DriveBrake => cfg.slip_angles_deg.clone(),
    };
    let mut out = Vec::new();
    for &p in &cfg.pressures_kpa {
        for &g in &cfg.cambers_deg {
            for &a in &held {
                for &fz in &cfg.loads_n {
                    out.push(SetPoint {
                        fz,
                        pressure: p,
                        gamma: degrees_to_radians(g),
                        alpha: degrees_to_radians(a),
                    });
                }
            }
        }
    }
    out
}

/// Generates the programme of `cfg`.
pub fn generate_programme(cfg: &ProgrammeConfig) -> Programme {
    let tire = TrueTire {
        base: BaseTire::sample(cfg.tire, &mut stream(cfg.seed, cfg.tire.id())),
        effects: EffectSet::sample(cfg.seed, &cfg.effects, super::Forms::Physical),
    };
    let pause_rng = &mut stream(cfg.seed, "programme:pauses");
    let noise_rng = &mut stream(cfg.seed, "programme:noise");
    let k = if cfg.noise.is_finite() {
        cfg.noise.max(0.0)
    } else {
        0.0
    };
    let dt = 1.0 / SAMPLE_RATE_HZ;
    let rows_of = |s: f64| ((s * SAMPLE_RATE_HZ).round() as usize).max(1);
    let mut cols: [Vec<f64>; 11] = Default::default();
    let mut t = 0.0;
    let mut pressure_start = 0.0;
    let mut sweeps = Vec::new();
    let mut pauses = 0;
    let mut previous: Option<SetPoint> = None;
    let points = set_points(cfg);
    for sp in &points {
        // Pause, ramp and dwell from the previous set point: (rows, set point of each row).
        let from = previous.unwrap_or(*sp);
        let pause = pause_before(cfg, previous, sp, pause_rng);
        if pause > 0.0 {
            t += pause;
            pauses += 1;
        }
        if previous.is_none_or(|p| p.pressure != sp.pressure) {
            pressure_start = t;
        }
        let ramp = if previous.is_some() {
            rows_of(cfg.ramp_s)
        } else {
            0
        };
        let dwell = rows_of(cfg.dwell_s);
        let sweep = rows_of(cfg.sweep_s);
        for i in 0..ramp + dwell + sweep {
            let stretch = Stretch {
                from,
                to: *sp,
                ramp,
                dwell,
                sweep,
                pressure_start,
            };
            let x = stretch.sample(cfg, i, t);
            let mut f = tire.steady(&x);
            f.fx -= tire.fx_subtracted(&x);
            let row = recorded(cfg, &x, f, |sd: f64| k * sd * normal(noise_rng));
            for (c, v) in cols.iter_mut().zip(row) {
                c.push(v);
            }
            if i == ramp + dwell {
                sweeps.push(Sweep {
                    rows: cols[0].len() - 1..cols[0].len() - 1 + sweep,
                    fz: sp.fz,
                    pressure: sp.pressure,
                    gamma: sp.gamma,
                    alpha: sp.alpha,
                });
            }
            t += dt;
        }
        previous = Some(*sp);
    }
    Programme {
        dataset: programme_dataset(cfg, points.len(), cols),
        sweeps,
        pauses,
    }
}

/// The row the rig records of the true inputs `x` and forces `f`, each noisy channel with a
/// draw of `n(sd)` (the slip ratio first, then the others in column order; no draw for a
/// dead slip ratio).
fn recorded(
    cfg: &ProgrammeConfig,
    x: &TrueSample,
    f: Forces,
    mut n: impl FnMut(f64) -> f64,
) -> [f64; 11] {
    let kappa_read = if cfg.dead_slip_ratio {
        -1.0
    } else {
        x.kappa + n(NOISE.kappa)
    };
    [
        x.t,
        x.speed + n(NOISE.speed_mps),
        x.fz + n(NOISE.fz_n),
        x.alpha + n(NOISE.alpha_rad),
        kappa_read,
        x.gamma + n(NOISE.gamma_rad),
        x.pressure + n(NOISE.pressure_kpa),
        x.temp + n(NOISE.temperature_c),
        f.fx + n(NOISE.fx_n),
        f.fy + n(NOISE.fy_n),
        f.mz + n(NOISE.mz_nm),
    ]
}

/// The pause in the recording before set point `sp` [s]: `pressure_pause_s` at a new
/// pressure, else one of 2..20 s with probability `pause_probability` (none before the first).
fn pause_before(
    cfg: &ProgrammeConfig,
    previous: Option<SetPoint>,
    sp: &SetPoint,
    pause_rng: &mut SynthRng,
) -> f64 {
    let mut pause = 0.0;
    if previous.is_some_and(|p| p.pressure != sp.pressure) {
        pause = cfg.pressure_pause_s;
    } else if previous.is_some() && uniform(pause_rng, 0.0, 1.0) < cfg.pause_probability {
        pause = uniform(pause_rng, 2.0, 20.0);
    }
    pause
}

/// The rows from one set point to the next: ramp, dwell, then the sweep.
struct Stretch {
    from: SetPoint,
    to: SetPoint,
    ramp: usize,
    dwell: usize,
    sweep: usize,
    /// When the current pressure was set [s].
    pressure_start: f64,
}

impl Stretch {
    /// The true inputs of row `i` of the stretch, at time `t`.
    fn sample(&self, cfg: &ProgrammeConfig, i: usize, t: f64) -> TrueSample {
        let (from, sp) = (self.from, self.to);
        let (ramp, dwell, sweep) = (self.ramp, self.dwell, self.sweep);
        let amp = degrees_to_radians(12.0);
        let u = (i as f64 / ramp.max(1) as f64).min(1.0);
        let lerp = |a: f64, b: f64| a + (b - a) * u;
        let (mut alpha, mut kappa, mut swept) = (lerp(from.alpha, sp.alpha), 0.0, 0.0);
        if i >= ramp + dwell {
            let s = (i - ramp - dwell) as f64 / (sweep - 1).max(1) as f64;
            match cfg.kind {
                ProgrammeKind::Cornering => {
                    alpha = amp * triangle(s);
                    swept = alpha / amp;
                }
                ProgrammeKind::DriveBrake => {
                    kappa = ramp_through(s, 0.2, -0.2);
                    swept = kappa / 0.2;
                }
            }
        }
        TrueSample {
            t,
            speed: cfg.speed_mps * (1.0 + 0.002 * (0.7 * t).sin()),
            fz: lerp(from.fz, sp.fz) * (1.0 + 0.03 * swept * swept),
            alpha,
            kappa,
            gamma: lerp(from.gamma, sp.gamma),
            pressure: sp.pressure + 0.5 * ((t - self.pressure_start) / 600.0).min(1.0),
            temp: 35.0 + 20.0 * swept * swept + 0.01 * t.min(1500.0),
        }
    }
}

/// The recorded columns (time, speed, load, alpha, kappa, gamma, pressure, temperature, Fx,
/// Fy, Mz) as the programme's data set, all in run `cfg.run`.
fn programme_dataset(cfg: &ProgrammeConfig, sweeps: usize, cols: [Vec<f64>; 11]) -> Dataset {
    let n = cols[0].len();
    let [
        time,
        speed,
        fz,
        alpha,
        kappa,
        gamma,
        pressure,
        temperature,
        fx,
        fy,
        mz,
    ] = cols;
    Dataset {
        source: format!(
            "synthetic {} programme (seed={}, tire={}, {} sweeps{})",
            match cfg.kind {
                ProgrammeKind::Cornering => "cornering",
                ProgrammeKind::DriveBrake => "drive/brake",
            },
            cfg.seed,
            cfg.tire.id(),
            sweeps,
            if cfg.dead_slip_ratio {
                ", dead slip ratio"
            } else {
                ""
            }
        ),
        run: vec![cfg.run; n].into(),
        time: Some(time.into()),
        speed: Some(speed.into()),
        fz: fz.into(),
        alpha: Some(alpha.into()),
        kappa: Some(kappa.into()),
        gamma: Some(gamma.into()),
        pressure: Some(pressure.into()),
        temperature: Some(temperature.into()),
        fx: Some(fx.into()),
        fy: Some(fy.into()),
        mz: Some(mz.into()),
    }
}

/// `ds` as a TTC ASCII run file (the format `input::ttc` reads): title line, channel names,
/// units, one row per sample, in SAE axes (`SA = -alpha`, `FZ = -Fz`). Channels: `ET V SA IA
/// P FX FY FZ MZ TSTC SR`, those `ds` lacks left out; values in shortest round-trip form.
pub fn write_ttc(ds: &Dataset, title: &str) -> String {
    let map = |c: &Option<crate::data::Column>, f: fn(f64) -> f64| {
        c.as_deref()
            .map(|c| c.iter().map(|v| f(*v)).collect::<Vec<f64>>())
    };
    let columns: Vec<(&str, &str, Vec<f64>)> = [
        ("ET", "s", map(&ds.time, |v| v)),
        ("V", "kph", map(&ds.speed, |v| 3.6 * v)),
        ("SA", "deg", map(&ds.alpha, |v| -radians_to_degrees(v))),
        ("IA", "deg", map(&ds.gamma, radians_to_degrees)),
        ("P", "kPa", map(&ds.pressure, |v| v)),
        ("FX", "N", map(&ds.fx, |v| v)),
        ("FY", "N", map(&ds.fy, |v| v)),
        ("FZ", "N", Some(ds.fz.iter().map(|v| -v).collect())),
        ("MZ", "N-m", map(&ds.mz, |v| v)),
        ("TSTC", "degC", map(&ds.temperature, |v| v)),
        ("SR", "none", map(&ds.kappa, |v| v)),
    ]
    .into_iter()
    .filter_map(|(name, unit, values)| Some((name, unit, values?)))
    .collect();
    let mut out = String::with_capacity(ds.len() * 16 * columns.len());
    let names: Vec<&str> = columns.iter().map(|c| c.0).collect();
    let units: Vec<&str> = columns.iter().map(|c| c.1).collect();
    let _ = writeln!(out, "{title}\n{}\n{}", names.join("\t"), units.join("\t"));
    for i in 0..ds.len() {
        for (k, (_, _, values)) in columns.iter().enumerate() {
            if k > 0 {
                out.push('\t');
            }
            let _ = write!(out, "{}", values[i]);
        }
        out.push('\n');
    }
    out
}
