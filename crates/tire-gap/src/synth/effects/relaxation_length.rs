//! Relaxation as the generator makes it (see [`Relaxation`]), its magnitudes and how it acts.

use std::collections::BTreeMap;

use mf87::extensions::Extension;

use super::{Entry, Forces, LagState, TrueEffect, named};
use crate::synth::blocks::TrueSample;
use crate::synth::rng::{SynthRng, uniform};
use crate::synth::tires::FZ_NOMINAL;

pub(super) const ENTRY: Entry = Entry {
    kind: Extension::RelaxationLength,
    driver: "rate of change of slip per metre travelled (slip-angle frequency over speed): \
         sinusoidal slip-angle blocks at high frequency and low speed",
    sample: |rng| Box::new(Relaxation::sample(rng)),
    sample_mf61: None,
};

/// Relaxation as a lag of the FORCES (not the slip) in travelled distance, second order: two
/// first-order stages in series with lengths `L/(1+r)` and `r L/(1+r)`, so the total lag
/// length is `L`. The length grows with load, `L = L_ref (Fz / 4 kN)^e`. Fy and Mz share `L`,
/// Fx relaxes over `long_ratio * L`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Relaxation {
    /// Lateral relaxation length at 4 kN [m] (0.3..0.8).
    pub length_ref: f64,
    /// Load exponent e (0.6..0.8).
    pub load_exp: f64,
    /// Ratio r of the second stage to the first (0.15..0.35).
    pub pole_ratio: f64,
    /// Longitudinal length over lateral (0.25..0.45).
    pub long_ratio: f64,
}

impl Relaxation {
    fn sample(rng: &mut SynthRng) -> Self {
        Relaxation {
            length_ref: uniform(rng, 0.3, 0.8),
            load_exp: uniform(rng, 0.6, 0.8),
            pole_ratio: uniform(rng, 0.15, 0.35),
            long_ratio: uniform(rng, 0.25, 0.45),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("length_at_4kN_m", self.length_ref),
            ("load_exp", self.load_exp),
            ("pole_ratio", self.pole_ratio),
            ("long_ratio", self.long_ratio),
        ])
    }

    /// Lateral relaxation length [m] at load `fz`.
    pub fn length(&self, fz: f64) -> f64 {
        self.length_ref * (fz.max(100.0) / FZ_NOMINAL).powf(self.load_exp)
    }

    /// Advance by `ds` metres towards the steady-state `target`.
    pub fn step(&self, state: &mut LagState, target: Forces, fz: f64, ds: f64) -> Forces {
        let inputs = [target.fx, target.fy, target.mz];
        let stages = state
            .stages
            .get_or_insert([[inputs[0]; 2], [inputs[1]; 2], [inputs[2]; 2]]);
        let l_y = self.length(fz);
        let r = self.pole_ratio;
        for (ch, (st, u)) in stages.iter_mut().zip(inputs).enumerate() {
            let l = if ch == 0 { self.long_ratio * l_y } else { l_y };
            let (l1, l2) = (l / (1.0 + r), r * l / (1.0 + r));
            let (a1, a2) = ((-ds / l1).exp(), (-ds / l2).exp());
            st[0] = a1 * st[0] + (1.0 - a1) * u;
            st[1] = a2 * st[1] + (1.0 - a2) * st[0];
        }
        Forces {
            fx: stages[0][1],
            fy: stages[1][1],
            mz: stages[2][1],
        }
    }
}

impl TrueEffect for Relaxation {
    fn params(&self) -> BTreeMap<String, f64> {
        Relaxation::params(self)
    }

    fn lag(&self, state: &mut LagState, f: Forces, x: &TrueSample, ds: f64) -> Forces {
        self.step(state, f, x.fz, ds)
    }
}
