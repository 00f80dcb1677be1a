//! Rolling resistance as the generator makes it (see [`Rolling`]), its magnitudes and how it acts.

use std::collections::BTreeMap;

use mf87::extensions::Extension;

use super::{Entry, PRESSURE_NOMINAL_KPA, TrueEffect, named};
use crate::synth::blocks::TrueSample;
use crate::synth::rng::{SynthRng, uniform};
use crate::synth::tires::FZ_NOMINAL;

pub(super) const ENTRY: Entry = Entry {
    kind: Extension::RollingResistance,
    driver: "vertical load (with speed and pressure) at zero slip ratio: a negative Fx",
    sample: |rng| Box::new(Rolling::sample(rng)),
    sample_mf61: None,
};

/// Rolling resistance in the SAE J2452 style,
/// `Fr = c Fz0 (Fz / Fz0)^b (p / p0)^a (1 + k (V / 30 m/s)^2)`, acting against rolling
/// (Fx decreases by Fr for forward speed), at every slip. c is 0.008..0.012, b 0.85..0.95,
/// a -0.45..-0.3, k 0.15..0.35.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rolling {
    pub coef: f64,
    pub load_exp: f64,
    pub pressure_exp: f64,
    pub speed_frac: f64,
}

impl Rolling {
    fn sample(rng: &mut SynthRng) -> Self {
        Rolling {
            coef: uniform(rng, 0.008, 0.012),
            load_exp: uniform(rng, 0.85, 0.95),
            pressure_exp: -uniform(rng, 0.3, 0.45),
            speed_frac: uniform(rng, 0.15, 0.35),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("coef", self.coef),
            ("load_exp", self.load_exp),
            ("pressure_exp", self.pressure_exp),
            ("speed_frac_at_30_mps", self.speed_frac),
        ])
    }

    /// Rolling resistance force [N] (positive; subtracted from Fx).
    pub fn force(&self, fz: f64, v: f64, p: f64) -> f64 {
        if fz <= 0.0 {
            return 0.0;
        }
        self.coef
            * FZ_NOMINAL
            * (fz / FZ_NOMINAL).powf(self.load_exp)
            * (p / PRESSURE_NOMINAL_KPA).max(0.1).powf(self.pressure_exp)
            * (1.0 + self.speed_frac * (v / 30.0).powi(2))
            * v.signum()
    }
}

impl TrueEffect for Rolling {
    fn params(&self) -> BTreeMap<String, f64> {
        Rolling::params(self)
    }

    fn fx_subtracted(&self, x: &TrueSample) -> Option<f64> {
        Some(self.force(x.fz, x.speed, x.pressure))
    }
}
