//! The rig's slip-ratio and Fx offsets as the generator makes it (see [`RigOffsets`]), its magnitudes and how it acts.

use std::collections::BTreeMap;

use mf87::extensions::Extension;

use super::{Entry, TrueEffect, named};
use crate::synth::blocks::TrueSample;
use crate::synth::rng::{SynthRng, sign, uniform};

pub(super) const ENTRY: Entry = Entry {
    kind: Extension::SlipRatioShift,
    driver: "the rig's slip ratio (kappa) from a rolling radius off the effective one, and its Fx \
         load cell's crosstalk from Fz: free rolling reads as slip, with a force offset \
         growing with the load",
    sample: |rng| Box::new(RigOffsets::sample(rng)),
    sample_mf61: None,
};

/// The rig's own offsets of the longitudinal curve: its slip ratio computed with a rolling
/// radius `R` off the tire's effective rolling radius `Re` by a fraction, so that it reads
/// `kappa_m = (1 + kappa) Re / R - 1` (free rolling reads as slip `Re / R - 1`, and every
/// slip is stretched by `Re / R`), and its Fx load cell's crosstalk from the load,
/// `Fx_m = Fx + c Fz`. `Re / R - 1` is 0.004..0.012 and `c` 0.002..0.006 in magnitude, each
/// with a random sign.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RigOffsets {
    /// `Re / R`.
    pub radius_ratio: f64,
    /// `c` [N/N].
    pub crosstalk: f64,
}

impl RigOffsets {
    fn sample(rng: &mut SynthRng) -> Self {
        let radius_error = sign(rng) * uniform(rng, 0.004, 0.012);
        RigOffsets {
            radius_ratio: 1.0 + radius_error,
            crosstalk: sign(rng) * uniform(rng, 0.002, 0.006),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("radius_ratio_Re_over_R", self.radius_ratio),
            ("fx_crosstalk_per_fz", self.crosstalk),
        ])
    }

    /// The slip ratio the rig reports for the true slip ratio `kappa`.
    pub fn measured_kappa(&self, kappa: f64) -> f64 {
        (1.0 + kappa) * self.radius_ratio - 1.0
    }

    /// What the load cell adds to Fx at load `fz` [N].
    pub fn fx_offset(&self, fz: f64) -> f64 {
        self.crosstalk * fz
    }
}

impl TrueEffect for RigOffsets {
    fn params(&self) -> BTreeMap<String, f64> {
        RigOffsets::params(self)
    }

    fn measured_kappa(&self, kappa: f64) -> f64 {
        RigOffsets::measured_kappa(self, kappa)
    }

    fn fx_offset(&self, x: &TrueSample) -> Option<f64> {
        Some(RigOffsets::fx_offset(self, x.fz))
    }
}
