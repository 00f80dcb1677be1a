//! Camber on the peak as the generator makes it (see [`CamberPeak`]), its magnitudes and how
//! it acts.

use std::collections::BTreeMap;

use mf87::extensions::Extension;

use super::{Entry, TrueEffect, named};
use crate::synth::blocks::TrueSample;
use crate::synth::rng::{SynthRng, uniform};
use crate::synth::tires::Mods;

pub(super) const ENTRY: Entry = Entry {
    kind: Extension::CamberPeak,
    driver: "camber (gamma_deg), varied across blocks: peak friction, longitudinal more than \
         lateral",
    sample: |rng| Box::new(CamberPeak::sample(rng)),
    sample_mf61: Some(|rng| Box::new(Mf61CamberPeak::sample(rng))),
};

/// Camber at which the losses are stated [rad] (4 deg).
const REFERENCE_CAMBER: f64 = 0.069_813_170_079_773_18;

/// Camber narrows the contact patch: friction falls as a power of |camber|,
/// `1 - loss (|gamma| / 4 deg)^n` with n between 1.3 and 1.7 (not the square of MF 6.1's
/// pDx3), the longitudinal more than the lateral.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CamberPeak {
    /// Friction losses at 4 deg of camber: longitudinal (0.04..0.09), lateral (0.02..0.05).
    pub loss_x: f64,
    pub loss_y: f64,
    /// The power of |camber| (1.3..1.7).
    pub power: f64,
}

impl CamberPeak {
    fn sample(rng: &mut SynthRng) -> Self {
        CamberPeak {
            loss_x: uniform(rng, 0.04, 0.09),
            loss_y: uniform(rng, 0.02, 0.05),
            power: uniform(rng, 1.3, 1.7),
        }
    }
}

impl TrueEffect for CamberPeak {
    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("loss_x_at_4_deg", self.loss_x),
            ("loss_y_at_4_deg", self.loss_y),
            ("power", self.power),
        ])
    }

    fn modify(&self, m: &mut Mods, x: &TrueSample) {
        let r = (x.gamma.abs() / REFERENCE_CAMBER).powf(self.power);
        m.mu_x *= (1.0 - self.loss_x * r).max(0.5);
        m.mu_y *= (1.0 - self.loss_y * r).max(0.5);
    }
}

/// Camber on the peak as MF 6.1 writes it: `mu_x (1 - pDx3 gamma^2)`, `mu_y (1 - pDy3
/// gamma^2)` (gamma [rad]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Mf61CamberPeak {
    /// pDx3 (8..20) and pDy3 (4..10) [1/rad^2]: 4 to 10 % and 2 to 5 % of the peak at 4 deg.
    pub pdx3: f64,
    pub pdy3: f64,
}

impl Mf61CamberPeak {
    fn sample(rng: &mut SynthRng) -> Self {
        Mf61CamberPeak {
            pdx3: uniform(rng, 8.0, 20.0),
            pdy3: uniform(rng, 4.0, 10.0),
        }
    }
}

impl TrueEffect for Mf61CamberPeak {
    fn params(&self) -> BTreeMap<String, f64> {
        named(&[("pDx3", self.pdx3), ("pDy3", self.pdy3)])
    }

    fn modify(&self, m: &mut Mods, x: &TrueSample) {
        let g2 = x.gamma * x.gamma;
        m.mu_x *= 1.0 - self.pdx3 * g2;
        m.mu_y *= 1.0 - self.pdy3 * g2;
    }
}
