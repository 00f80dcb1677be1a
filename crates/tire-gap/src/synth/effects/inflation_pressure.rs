//! Inflation pressure as the generator makes it (see [`Pressure`]), its magnitudes and how it acts.

use std::collections::BTreeMap;

use mf87::extensions::Extension;

use super::{Entry, PRESSURE_NOMINAL_KPA, TrueEffect, named};
use crate::synth::blocks::TrueSample;
use crate::synth::rng::{SynthRng, uniform};
use crate::synth::tires::Mods;

pub(super) const ENTRY: Entry = Entry {
    kind: Extension::InflationPressure,
    driver: "inflation pressure (p_kPa), varied across blocks: cornering and slip stiffness, \
         peak friction, aligning-moment arm",
    sample: |rng| Box::new(Pressure::sample(rng)),
    sample_mf61: Some(|rng| Box::new(Mf61Pressure::sample(rng))),
};

/// Inflation pressure as power laws of `p / p0` (p0 = 240 kPa): friction `(p/p0)^-eta`,
/// cornering stiffness `(p/p0)^ey` evaluated at the load `Fz (p0/p)^beta` (higher pressure
/// moves the load of peak cornering stiffness up, so the net change depends on load),
/// longitudinal stiffness `(p/p0)^ex`, pneumatic trail `(p/p0)^-tau` (shorter contact patch).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pressure {
    pub mu_exp: f64,
    pub ky_exp: f64,
    pub load_shift_exp: f64,
    pub kx_exp: f64,
    pub trail_exp: f64,
}

impl Pressure {
    fn sample(rng: &mut SynthRng) -> Self {
        Pressure {
            mu_exp: uniform(rng, 0.1, 0.2),
            ky_exp: uniform(rng, 0.35, 0.55),
            load_shift_exp: uniform(rng, 0.3, 0.6),
            kx_exp: uniform(rng, 0.1, 0.3),
            trail_exp: uniform(rng, 0.2, 0.4),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("p0_kPa", PRESSURE_NOMINAL_KPA),
            ("mu_exp", -self.mu_exp),
            ("ky_exp", self.ky_exp),
            ("stiffness_load_shift_exp", -self.load_shift_exp),
            ("kx_exp", self.kx_exp),
            ("trail_exp", -self.trail_exp),
        ])
    }

    fn apply(&self, m: &mut Mods, p: f64) {
        let r = (p / PRESSURE_NOMINAL_KPA).max(0.1);
        let mu = r.powf(-self.mu_exp);
        m.mu_x *= mu;
        m.mu_y *= mu;
        m.k_y *= r.powf(self.ky_exp);
        m.fz_stiff *= r.powf(-self.load_shift_exp);
        m.k_x *= r.powf(self.kx_exp);
        m.trail *= r.powf(-self.trail_exp);
    }
}

impl TrueEffect for Pressure {
    fn params(&self) -> BTreeMap<String, f64> {
        Pressure::params(self)
    }

    fn modify(&self, m: &mut Mods, x: &TrueSample) {
        self.apply(m, x.pressure);
    }
}

/// Inflation pressure as MF 6.1 writes it, `dp = (p - p0) / p0` (p0 = 240 kPa): slip
/// stiffness `1 + ppx1 dp + ppx2 dp^2`, longitudinal friction `1 + ppx3 dp + ppx4 dp^2`,
/// cornering stiffness `1 + ppy1 dp` with the load of its largest value moved by
/// `1 + ppy2 dp`, lateral friction `1 + ppy3 dp + ppy4 dp^2`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Mf61Pressure {
    pub ppx: [f64; 4],
    pub ppy: [f64; 4],
}

impl Mf61Pressure {
    fn sample(rng: &mut SynthRng) -> Self {
        Mf61Pressure {
            ppx: [
                uniform(rng, -0.6, -0.3),
                uniform(rng, 0.0, 0.3),
                uniform(rng, -0.6, -0.3),
                uniform(rng, 0.2, 0.6),
            ],
            ppy: [
                uniform(rng, 0.3, 0.7),
                uniform(rng, 0.6, 1.2),
                uniform(rng, -0.7, -0.4),
                uniform(rng, 0.2, 0.6),
            ],
        }
    }
}

impl TrueEffect for Mf61Pressure {
    fn params(&self) -> BTreeMap<String, f64> {
        let [x1, x2, x3, x4] = self.ppx;
        let [y1, y2, y3, y4] = self.ppy;
        named(&[
            ("p0_kPa", PRESSURE_NOMINAL_KPA),
            ("ppx1", x1),
            ("ppx2", x2),
            ("ppx3", x3),
            ("ppx4", x4),
            ("ppy1", y1),
            ("ppy2", y2),
            ("ppy3", y3),
            ("ppy4", y4),
        ])
    }

    fn modify(&self, m: &mut Mods, x: &TrueSample) {
        let dp = (x.pressure - PRESSURE_NOMINAL_KPA) / PRESSURE_NOMINAL_KPA;
        let quadratic = |a: f64, b: f64| 1.0 + a * dp + b * dp * dp;
        let [x1, x2, x3, x4] = self.ppx;
        let [y1, y2, y3, y4] = self.ppy;
        m.k_x *= quadratic(x1, x2);
        m.mu_x *= quadratic(x3, x4);
        m.k_y *= 1.0 + y1 * dp;
        m.fz_stiff /= 1.0 + y2 * dp;
        m.mu_y *= quadratic(y3, y4);
    }
}
