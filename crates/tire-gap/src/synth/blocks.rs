//! The test program of a flat-track rig: test blocks (runs) and their true input histories.
//!
//! Nominal program (35,600 rows at 100 Hz), each block type with its loads and cambers:
//!
//! | blocks | type | loads (N) | camber (deg) | length |
//! |---|---|---|---|---|
//! | 12 | slip-angle sweep 0 -> +12 -> -12 -> 0 deg, kappa = 0 | 1500..7000 | -4..4 | 12 s |
//! | 6 | slip-ratio sweep 0 -> +0.2..0.3 -> -0.25..-0.3 -> 0, alpha = 0 | 1500..7000 | 0 | 12 s |
//! | 6 | combined: the same kappa sweep at alpha = +-2, +-4, +-6 deg | 3000, 5500 | 0 | 10 s |
//! | 10 | sinusoidal slip angle, 2.5..3.5 deg, at 0.5, 1, 2, 4, 8 Hz | 3000, 5500 | 0 | 6 s |
//! | 2 | free rolling, load ramp 1500 -> 7000 -> 1500 N | ramp | 0 | 10 s |
//!
//! Speed (5..30 m/s), pressure (180..300 kPa) and tread temperature at the block start
//! (20..90 degC) are drawn per block by Latin-hypercube sampling, independently of each other
//! and of the block type, load and camber; the block order is shuffled. Within a block the
//! speed and load wobble slightly, the temperature drifts (-0.25..+0.35 degC/s).
//!
//! A different `rows_target` scales the block lengths (sweep rates change accordingly); well
//! above the nominal size the whole program is repeated with fresh conditions instead.

use std::f64::consts::PI;

use super::rng::{SynthRng, jitter, latin, shuffle, sign, uniform};

/// Sampling rate [Hz].
pub(crate) const SAMPLE_RATE_HZ: f64 = 100.0;
/// Range of the rig speed across blocks [m/s].
pub(crate) const SPEED_RANGE: (f64, f64) = (5.0, 30.0);
/// Range of the inflation pressure across blocks [kPa].
pub(crate) const PRESSURE_RANGE: (f64, f64) = (180.0, 300.0);
/// Range of the tread temperature at block start [degC].
pub(crate) const TEMPERATURE_RANGE: (f64, f64) = (20.0, 90.0);
/// Frequencies of the sinusoidal slip-angle blocks [Hz].
pub(crate) const SINE_FREQUENCIES_HZ: [f64; 5] = [0.5, 1.0, 2.0, 4.0, 8.0];

/// A block condition drawn by Latin-hypercube sampling, which a programme may couple to
/// another (see `plan`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DrawnCondition {
    Speed,
    Pressure,
    Temperature,
}

impl DrawnCondition {
    pub const ALL: [DrawnCondition; 3] = [
        DrawnCondition::Speed,
        DrawnCondition::Pressure,
        DrawnCondition::Temperature,
    ];

    pub fn name(self) -> &'static str {
        match self {
            DrawnCondition::Speed => "speed",
            DrawnCondition::Pressure => "pressure",
            DrawnCondition::Temperature => "temperature",
        }
    }

    pub fn from_name(name: &str) -> Option<DrawnCondition> {
        DrawnCondition::ALL.into_iter().find(|c| c.name() == name)
    }
}

/// What a block does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum BlockKind {
    /// Triangular slip-angle sweep 0 -> +amp -> -amp -> 0 [rad], free rolling.
    AlphaSweep { amp: f64 },
    /// Slip-ratio sweep 0 -> kmax -> kmin -> 0 at zero slip angle.
    KappaSweep { kmax: f64, kmin: f64 },
    /// Slip-ratio sweep 0 -> kmax -> kmin -> 0 at a fixed slip angle [rad].
    Combined { alpha: f64, kmax: f64, kmin: f64 },
    /// Sinusoidal slip angle of amplitude `amp` [rad] at `freq_hz`.
    Sine { freq_hz: f64, amp: f64 },
    /// Free rolling at zero slip, load ramped lo -> hi -> lo [N].
    FreeRolling { fz_lo: f64, fz_hi: f64 },
}

/// One test block with its set points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Block {
    pub run: i64,
    pub kind: BlockKind,
    /// Load set point [N] (unused by `FreeRolling`).
    pub fz: f64,
    /// Camber [rad].
    pub gamma: f64,
    /// Speed [m/s].
    pub speed: f64,
    /// Inflation pressure [kPa].
    pub pressure: f64,
    /// Tread temperature at the start [degC] and its drift [degC/s].
    pub temp0: f64,
    pub temp_rate: f64,
    /// Number of samples.
    pub n: usize,
    /// Load wobble: relative amplitude, frequency [Hz], phase [rad].
    pub load_wobble: (f64, f64, f64),
    /// Speed wobble: relative amplitude, frequency [Hz], phase [rad].
    pub speed_wobble: (f64, f64, f64),
}

/// The true (unmeasured) state of the rig at one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TrueSample {
    pub t: f64,
    pub speed: f64,
    pub fz: f64,
    pub alpha: f64,
    pub kappa: f64,
    pub gamma: f64,
    pub pressure: f64,
    pub temp: f64,
}

/// 0 -> 1 -> -1 -> 0 over u in [0, 1].
pub(crate) fn triangle(u: f64) -> f64 {
    if u < 0.25 {
        4.0 * u
    } else if u < 0.75 {
        2.0 - 4.0 * u
    } else {
        4.0 * u - 4.0
    }
}

/// 0 -> hi -> lo -> 0 over u in [0, 1] at a constant rate (hi > 0 > lo).
pub(crate) fn ramp_through(u: f64, hi: f64, lo: f64) -> f64 {
    let total = 2.0 * hi - 2.0 * lo;
    let s = u * total;
    if s < hi {
        s
    } else if s < 2.0 * hi - lo {
        2.0 * hi - s
    } else {
        s - total
    }
}

impl Block {
    /// The true state at sample `i`.
    pub fn sample(&self, i: usize) -> TrueSample {
        let t = i as f64 / SAMPLE_RATE_HZ;
        let u = if self.n > 1 {
            i as f64 / (self.n - 1) as f64
        } else {
            0.0
        };
        let wobble = |(amp, f, ph): (f64, f64, f64)| 1.0 + amp * (2.0 * PI * f * t + ph).sin();
        let mut fz = self.fz * wobble(self.load_wobble);
        let (mut alpha, mut kappa) = (0.0, 0.0);
        match self.kind {
            BlockKind::AlphaSweep { amp } => alpha = amp * triangle(u),
            BlockKind::KappaSweep { kmax, kmin } => kappa = ramp_through(u, kmax, kmin),
            BlockKind::Combined {
                alpha: a,
                kmax,
                kmin,
            } => {
                alpha = a;
                kappa = ramp_through(u, kmax, kmin);
            }
            BlockKind::Sine { freq_hz, amp } => alpha = amp * (2.0 * PI * freq_hz * t).sin(),
            BlockKind::FreeRolling { fz_lo, fz_hi } => {
                let up = 1.0 - (2.0 * u - 1.0).abs();
                fz = (fz_lo + (fz_hi - fz_lo) * up) * wobble(self.load_wobble);
            }
        }
        TrueSample {
            t,
            speed: self.speed * wobble(self.speed_wobble),
            fz,
            alpha,
            kappa,
            gamma: self.gamma,
            pressure: self.pressure,
            temp: (self.temp0 + self.temp_rate * t).clamp(10.0, 110.0),
        }
    }

    /// Whether this is a sinusoidal block, and its frequency.
    #[cfg(test)]
    pub fn sine_frequency(&self) -> Option<f64> {
        match self.kind {
            BlockKind::Sine { freq_hz, .. } => Some(freq_hz),
            _ => None,
        }
    }
}

/// A block template of the nominal program: kind, load [N], camber [deg], length [s].
struct Template {
    kind: BlockKind,
    fz: f64,
    gamma_deg: f64,
    seconds: f64,
}

/// The nominal program, with the per-replicate random parts (sweep ends, signs) drawn.
fn nominal_program(rng: &mut SynthRng) -> Vec<Template> {
    let mut out = Vec::new();
    let sweep = BlockKind::AlphaSweep {
        amp: 12f64.to_radians(),
    };
    for (fz, gamma_deg) in [
        (1500.0, 0.0),
        (3000.0, 0.0),
        (4500.0, 0.0),
        (6000.0, 0.0),
        (7000.0, 0.0),
        (3000.0, -4.0),
        (3000.0, 4.0),
        (4500.0, -2.0),
        (4500.0, 2.0),
        (6000.0, -4.0),
        (6000.0, 4.0),
        (7000.0, -2.0),
    ] {
        out.push(Template {
            kind: sweep,
            fz,
            gamma_deg,
            seconds: 12.0,
        });
    }
    for fz in [1500.0, 3000.0, 4000.0, 5000.0, 6000.0, 7000.0] {
        out.push(Template {
            kind: BlockKind::KappaSweep {
                kmax: uniform(rng, 0.2, 0.3),
                kmin: -uniform(rng, 0.25, 0.3),
            },
            fz,
            gamma_deg: 0.0,
            seconds: 12.0,
        });
    }
    for fz in [3000.0, 5500.0] {
        for alpha_deg in [2.0, 4.0, 6.0] {
            out.push(Template {
                kind: BlockKind::Combined {
                    alpha: sign(rng) * f64::to_radians(alpha_deg),
                    kmax: uniform(rng, 0.15, 0.25),
                    kmin: -uniform(rng, 0.2, 0.3),
                },
                fz,
                gamma_deg: 0.0,
                seconds: 10.0,
            });
        }
    }
    for fz in [3000.0, 5500.0] {
        for freq_hz in SINE_FREQUENCIES_HZ {
            out.push(Template {
                kind: BlockKind::Sine {
                    freq_hz,
                    amp: uniform(rng, 2.5, 3.5).to_radians(),
                },
                fz,
                gamma_deg: 0.0,
                seconds: 6.0,
            });
        }
    }
    for _ in 0..2 {
        out.push(Template {
            kind: BlockKind::FreeRolling {
                fz_lo: 1500.0,
                fz_hi: 7000.0,
            },
            fz: 1.0,
            gamma_deg: 0.0,
            seconds: 10.0,
        });
    }
    out
}

/// Rows of the nominal program (for scaling to `rows_target`).
pub(crate) const NOMINAL_ROWS: usize = 35_600;

/// The test program for about `rows_target` rows. With `coupled = Some([a, b])` the
/// condition `b` rises and falls with `a` across blocks: the same draws, reordered to `a`'s
/// rank order (a poorly designed programme: rank correlation 1).
pub(crate) fn plan(
    rows_target: usize,
    coupled: Option<[DrawnCondition; 2]>,
    rng: &mut SynthRng,
) -> Vec<Block> {
    let scale = rows_target as f64 / NOMINAL_ROWS as f64;
    let replicates = scale.round().max(1.0) as usize;
    let stretch = scale / replicates as f64;
    let mut blocks = Vec::new();
    for _ in 0..replicates {
        for tpl in nominal_program(rng) {
            let mut seconds = tpl.seconds * stretch;
            if let BlockKind::Sine { freq_hz, .. } = tpl.kind {
                // At least one full period, so hysteresis loops close.
                seconds = seconds.max(1.0 / freq_hz);
            }
            let n = ((seconds * SAMPLE_RATE_HZ).round() as usize).max(20);
            blocks.push(Block {
                run: 0,
                kind: tpl.kind,
                fz: if matches!(tpl.kind, BlockKind::FreeRolling { .. }) {
                    1.0
                } else {
                    jitter(rng, tpl.fz, 0.03)
                },
                gamma: tpl.gamma_deg.to_radians(),
                speed: 0.0,
                pressure: 0.0,
                temp0: 0.0,
                temp_rate: uniform(rng, -0.25, 0.35),
                n,
                load_wobble: (
                    uniform(rng, 0.002, 0.006),
                    uniform(rng, 0.2, 0.8),
                    uniform(rng, 0.0, 2.0 * PI),
                ),
                speed_wobble: (
                    uniform(rng, 0.001, 0.003),
                    uniform(rng, 0.1, 0.4),
                    uniform(rng, 0.0, 2.0 * PI),
                ),
            });
        }
    }
    let n = blocks.len();
    let mut draws = [
        latin(rng, n, SPEED_RANGE.0, SPEED_RANGE.1),
        latin(rng, n, PRESSURE_RANGE.0, PRESSURE_RANGE.1),
        latin(rng, n, TEMPERATURE_RANGE.0, TEMPERATURE_RANGE.1),
    ];
    if let Some([a, b]) = coupled {
        let (a, b) = (a as usize, b as usize);
        let mut ranks: Vec<usize> = (0..n).collect();
        ranks.sort_by(|&i, &j| draws[a][i].total_cmp(&draws[a][j]));
        let mut sorted = draws[b].clone();
        sorted.sort_by(f64::total_cmp);
        for (k, &i) in ranks.iter().enumerate() {
            draws[b][i] = sorted[k];
        }
    }
    let [speeds, pressures, temps] = draws;
    for (k, b) in blocks.iter_mut().enumerate() {
        b.speed = speeds[k];
        b.pressure = pressures[k];
        b.temp0 = temps[k];
    }
    shuffle(rng, &mut blocks);
    for (k, b) in blocks.iter_mut().enumerate() {
        b.run = k as i64 + 1;
    }
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sweeps_hit_their_ends_and_return_to_zero() {
        assert_eq!(triangle(0.0), 0.0);
        assert_eq!(triangle(0.25), 1.0);
        assert_eq!(triangle(0.75), -1.0);
        assert!(triangle(1.0).abs() < 1e-12);
        assert!((ramp_through(0.0, 0.3, -0.2)).abs() < 1e-12);
        let total = 2.0 * 0.3 + 2.0 * 0.2;
        assert!((ramp_through(0.3 / total, 0.3, -0.2) - 0.3).abs() < 1e-12);
        assert!((ramp_through(0.8 / total, 0.3, -0.2) + 0.2).abs() < 1e-12);
        assert!(ramp_through(1.0, 0.3, -0.2).abs() < 1e-12);
    }

    #[test]
    fn a_coupled_condition_follows_the_rank_of_its_partner() {
        let plain = plan(5_000, None, &mut super::super::rng::stream(3, "design"));
        let coupled = plan(
            5_000,
            Some([DrawnCondition::Temperature, DrawnCondition::Pressure]),
            &mut super::super::rng::stream(3, "design"),
        );
        // The same blocks and draws; only the pressures are reordered.
        let sorted = |v: Vec<f64>| {
            let mut v = v;
            v.sort_by(f64::total_cmp);
            v
        };
        let p = |b: &[Block]| b.iter().map(|b| b.pressure).collect::<Vec<_>>();
        assert_eq!(sorted(p(&plain)), sorted(p(&coupled)));
        for (x, y) in plain.iter().zip(&coupled) {
            assert_eq!((x.temp0, x.speed, x.n), (y.temp0, y.speed, y.n));
        }
        for x in &coupled {
            for y in &coupled {
                if x.temp0 < y.temp0 {
                    assert!(x.pressure < y.pressure);
                }
            }
        }
    }

    #[test]
    fn nominal_rows_match_the_program() {
        let mut rng = super::super::rng::stream(1, "t");
        let rows: f64 = nominal_program(&mut rng)
            .iter()
            .map(|t| t.seconds * SAMPLE_RATE_HZ)
            .sum();
        assert_eq!(rows as usize, NOMINAL_ROWS);
    }
}
