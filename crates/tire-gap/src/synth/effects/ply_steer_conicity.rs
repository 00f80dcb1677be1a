//! Ply steer and conicity as the generator makes it (see [`PlySteer`]), its magnitudes and how it acts.

use std::collections::BTreeMap;

use mf87::extensions::Extension;

use super::{Entry, Forces, TrueEffect, named};
use crate::synth::blocks::TrueSample;
use crate::synth::rng::{SynthRng, sign, uniform};
use crate::synth::tires::{BaseTire, FZ_NOMINAL, Mods};

pub(super) const ENTRY: Entry = Entry {
    kind: Extension::PlySteerConicity,
    driver: "vertical load at zero slip angle and camber: lateral force and aligning moment offsets",
    sample: |rng| Box::new(PlySteer::sample(rng)),
    sample_mf61: Some(|rng| Box::new(Mf61Shifts::sample(rng))),
};

/// Ply steer and conicity as a slip-angle shift whose force grows faster than the load,
/// `dFy(Fz) = F_ref (Fz / 4 kN)^n` (n 1.2..1.4; the shift is `dFy / Ky`, so the offset fades
/// once the tire saturates and also moves Mz through the trail), plus a residual aligning
/// torque `M_ref (Fz / 4 kN)^m` (m 1.3..1.7). F_ref is 60..150 N with a random sign; M_ref is
/// 1.5..3.5 N.m in the direction of the trail's share `-t dFy`, so the aligning-moment offset
/// at 4 kN totals about 3..8 N.m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PlySteer {
    pub fy_ref: f64,
    pub fy_load_exp: f64,
    pub mz_ref: f64,
    pub mz_load_exp: f64,
}

impl PlySteer {
    fn sample(rng: &mut SynthRng) -> Self {
        let fy_ref = sign(rng) * uniform(rng, 60.0, 150.0);
        PlySteer {
            fy_ref,
            fy_load_exp: uniform(rng, 1.2, 1.4),
            // Same direction as the trail's share (-t dFy), so they add up.
            mz_ref: -fy_ref.signum() * uniform(rng, 1.5, 3.5),
            mz_load_exp: uniform(rng, 1.3, 1.7),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("fy_at_4kN_N", self.fy_ref),
            ("fy_load_exp", self.fy_load_exp),
            ("mz_at_4kN_Nm", self.mz_ref),
            ("mz_load_exp", self.mz_load_exp),
        ])
    }

    /// Lateral force offset at small slip [N].
    pub fn fy(&self, fz: f64) -> f64 {
        self.fy_ref * (fz.max(0.0) / FZ_NOMINAL).powf(self.fy_load_exp)
    }

    /// Residual aligning torque [N.m].
    pub fn mz(&self, fz: f64) -> f64 {
        self.mz_ref * (fz.max(0.0) / FZ_NOMINAL).powf(self.mz_load_exp)
    }
}

impl TrueEffect for PlySteer {
    fn params(&self) -> BTreeMap<String, f64> {
        PlySteer::params(self)
    }

    /// The lateral offset as a slip-angle shift: `dFy / Ky` at zero camber.
    fn alpha_shift(&self, tire: &BaseTire, m: &Mods, x: &TrueSample) -> Option<f64> {
        let (_, ky) = tire.lat_scale(x.fz, 0.0, m);
        Some(self.fy(x.fz) / ky)
    }

    fn add_to_steady(&self, f: &mut Forces, x: &TrueSample) {
        f.mz += self.mz(x.fz);
    }
}

/// The shifts at zero slip as MF 6.1 writes them, `dfz = (Fz - 4 kN) / 4 kN`: the slip angle
/// shifted by `pHy1 + pHy2 dfz` [rad], the lateral force by `Fz (pVy1 + pVy2 dfz)`, and a
/// residual aligning torque `Fz R0 (qDz6 + qDz7 dfz)` (R0 = [`MF61_R0_M`]).
/// The unloaded radius R0 [m] of MF 6.1's residual aligning torque.
const MF61_R0_M: f64 = 0.3;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Mf61Shifts {
    pub phy: [f64; 2],
    pub pvy: [f64; 2],
    pub qdz: [f64; 2],
}

impl Mf61Shifts {
    fn sample(rng: &mut SynthRng) -> Self {
        let mut signed = |lo: f64, hi: f64| sign(rng) * uniform(rng, lo, hi);
        Mf61Shifts {
            phy: [signed(0.002, 0.005), signed(0.001, 0.003)],
            pvy: [signed(0.015, 0.035), signed(0.01, 0.03)],
            qdz: [signed(0.002, 0.005), signed(0.001, 0.003)],
        }
    }

    fn dfz(fz: f64) -> f64 {
        (fz - FZ_NOMINAL) / FZ_NOMINAL
    }
}

impl TrueEffect for Mf61Shifts {
    fn params(&self) -> BTreeMap<String, f64> {
        named(&[
            ("pHy1", self.phy[0]),
            ("pHy2", self.phy[1]),
            ("pVy1", self.pvy[0]),
            ("pVy2", self.pvy[1]),
            ("qDz6", self.qdz[0]),
            ("qDz7", self.qdz[1]),
        ])
    }

    fn alpha_shift(&self, _tire: &BaseTire, _m: &Mods, x: &TrueSample) -> Option<f64> {
        Some(self.phy[0] + self.phy[1] * Self::dfz(x.fz))
    }

    fn add_to_steady(&self, f: &mut Forces, x: &TrueSample) {
        let dfz = Self::dfz(x.fz);
        f.fy += x.fz * (self.pvy[0] + self.pvy[1] * dfz);
        f.mz += x.fz * MF61_R0_M * (self.qdz[0] + self.qdz[1] * dfz);
    }
}
