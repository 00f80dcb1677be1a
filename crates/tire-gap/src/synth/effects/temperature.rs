//! Tread temperature as the generator makes it (see [`Temperature`]), its magnitudes and how it acts.

use std::collections::BTreeMap;

use mf87::extensions::Extension;

use super::{Entry, TrueEffect, named};
use crate::synth::blocks::TrueSample;
use crate::synth::rng::{SynthRng, uniform};
use crate::synth::tires::Mods;

/// Reference tread temperature of the stiffness softening (degC).
pub const TEMPERATURE_REFERENCE_C: f64 = 50.0;

pub(super) const ENTRY: Entry = Entry {
    kind: Extension::Temperature,
    driver: "tread temperature (temp_C), varied across blocks and drifting within them: \
         peak friction and slip stiffness",
    sample: |rng| Box::new(Temperature::sample(rng)),
    sample_mf61: None,
};

/// Tread temperature: an asymmetric Gaussian window on friction,
/// `1 - A (1 - exp(-((T - Topt) / w)^2))` with `w` wider on the cold side than on the hot
/// side (Topt 45..70 degC, A 0.15..0.22, w 30..40 cold / 18..28 hot), and a linear softening
/// of both slip stiffnesses, `1 - s (T - 50 degC)` (s 0.0012..0.0025 per degC).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Temperature {
    pub t_opt: f64,
    pub loss: f64,
    pub width_cold: f64,
    pub width_hot: f64,
    pub stiff_slope: f64,
}

impl Temperature {
    fn sample(rng: &mut SynthRng) -> Self {
        Temperature {
            t_opt: uniform(rng, 45.0, 70.0),
            loss: uniform(rng, 0.15, 0.22),
            width_cold: uniform(rng, 30.0, 40.0),
            width_hot: uniform(rng, 18.0, 28.0),
            stiff_slope: uniform(rng, 0.0012, 0.0025),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("t_opt_C", self.t_opt),
            ("friction_loss", self.loss),
            ("width_cold_C", self.width_cold),
            ("width_hot_C", self.width_hot),
            ("stiffness_slope_per_C", -self.stiff_slope),
            ("stiffness_ref_C", TEMPERATURE_REFERENCE_C),
        ])
    }

    /// Friction factor at temperature `t`.
    pub fn friction(&self, t: f64) -> f64 {
        let w = if t < self.t_opt {
            self.width_cold
        } else {
            self.width_hot
        };
        1.0 - self.loss * (1.0 - (-((t - self.t_opt) / w).powi(2)).exp())
    }

    /// Stiffness factor at temperature `t`.
    pub fn stiffness(&self, t: f64) -> f64 {
        (1.0 - self.stiff_slope * (t - TEMPERATURE_REFERENCE_C)).max(0.5)
    }

    fn apply(&self, m: &mut Mods, t: f64) {
        let (f, k) = (self.friction(t), self.stiffness(t));
        m.mu_x *= f;
        m.mu_y *= f;
        m.k_x *= k;
        m.k_y *= k;
    }
}

impl TrueEffect for Temperature {
    fn params(&self) -> BTreeMap<String, f64> {
        Temperature::params(self)
    }

    fn modify(&self, m: &mut Mods, x: &TrueSample) {
        self.apply(m, x.temp);
    }
}
