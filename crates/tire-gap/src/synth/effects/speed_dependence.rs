//! Speed dependence as the generator makes it (see [`Speed`]), its magnitudes and how it acts.

use std::collections::BTreeMap;

use mf87::extensions::Extension;

use super::{Entry, TrueEffect, named};
use crate::synth::blocks::TrueSample;
use crate::synth::rng::{SynthRng, uniform};
use crate::synth::tires::{Mods, SlideFriction};

pub(super) const ENTRY: Entry = Entry {
    kind: Extension::SpeedDependence,
    driver: "forward speed (vx_mps), varied across blocks, and sliding speed: peak friction",
    sample: |rng| Box::new(Speed::sample(rng)),
    sample_mf61: None,
};

/// Speed dependence of friction, two parts: a saturating exponential in rolling speed,
/// `1 - A (1 - exp(-V / Vc))` (most of the loss at low speed; A set so that friction falls by
/// `drop` between 5 and 30 m/s), and a fall with the sliding speed `Vs = V |slip|`,
/// `1 - d (1 - exp(-Vs / vs))`, which also bends the force curve beyond its peak more at high
/// speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Speed {
    /// Friction loss from rolling speed between 5 and 30 m/s (0.06..0.10).
    pub drop: f64,
    /// Characteristic speed Vc [m/s] (6..14).
    pub v_char: f64,
    /// Sliding-speed friction loss d (0.03..0.06) and speed vs [m/s] (1.5..3).
    pub slide: SlideFriction,
}

impl Speed {
    fn sample(rng: &mut SynthRng) -> Self {
        Speed {
            drop: uniform(rng, 0.06, 0.1),
            v_char: uniform(rng, 6.0, 14.0),
            slide: SlideFriction {
                drop: uniform(rng, 0.03, 0.06),
                v_char: uniform(rng, 1.5, 3.0),
            },
        }
    }

    fn amplitude(&self) -> f64 {
        self.drop / ((-5.0 / self.v_char).exp() - (-30.0 / self.v_char).exp())
    }

    /// Rolling-speed friction factor.
    pub fn factor(&self, v: f64) -> f64 {
        1.0 - self.amplitude() * (1.0 - (-v.max(0.0) / self.v_char).exp())
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("drop_5_to_30_mps", self.drop),
            ("amplitude", self.amplitude()),
            ("v_char_mps", self.v_char),
            ("slide_drop", self.slide.drop),
            ("slide_v_char_mps", self.slide.v_char),
        ])
    }

    fn apply(&self, m: &mut Mods, v: f64) {
        let g = self.factor(v);
        m.mu_x *= g;
        m.mu_y *= g;
        m.slide = Some(self.slide);
    }
}

impl TrueEffect for Speed {
    fn params(&self) -> BTreeMap<String, f64> {
        Speed::params(self)
    }

    fn modify(&self, m: &mut Mods, x: &TrueSample) {
        self.apply(m, x.speed);
    }
}
