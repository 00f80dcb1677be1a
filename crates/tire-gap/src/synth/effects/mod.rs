//! The synthetic forms of the unmodelled effects, and the true tire they act on.
//!
//! These forms are deliberately NOT the ones the diagnosis tool fits (MF-2002 cosine
//! weighting, first-order slip lag with a constant length, linear/quadratic pressure terms,
//! friction linear in speed, constant offsets, `(q1 + q2 V/V0) Fz` rolling resistance, a
//! quadratic temperature window, a shift of the slip ratio): the tool has to recognise the
//! physics, not our formula.
//! Each effect's magnitudes are drawn from its own random stream (one ChaCha8 stream per effect).
//!
//! One file per effect: its form, the ranges its magnitudes are drawn from, the parameters
//! recorded in the truth, what drives it in the data, and the stages of the true tire it acts
//! in (a `TrueEffect` implementation). `EFFECTS` lists them; the code here and in the
//! simulation is the same for every effect.

mod camber_peak;
mod combined_slip;
mod inflation_pressure;
mod ply_steer_conicity;
mod relaxation_length;
mod rolling_resistance;
mod slip_ratio_shift;
mod speed_dependence;
mod temperature;

use std::collections::BTreeMap;
use std::fmt::Debug;

use super::blocks::TrueSample;
use super::rng::{SynthRng, stream};
use super::tires::{BaseTire, Mods};
use mf87::extensions::Extension;

pub use temperature::TEMPERATURE_REFERENCE_C;

/// Every effect the generator makes, one line each.
const EFFECTS: [Entry; 9] = [
    combined_slip::ENTRY,
    relaxation_length::ENTRY,
    inflation_pressure::ENTRY,
    speed_dependence::ENTRY,
    ply_steer_conicity::ENTRY,
    rolling_resistance::ENTRY,
    temperature::ENTRY,
    slip_ratio_shift::ENTRY,
    camber_peak::ENTRY,
];

/// Nominal inflation pressure (kPa): the pressure effect is 1 here.
pub const PRESSURE_NOMINAL_KPA: f64 = 240.0;

/// Draws an effect's magnitudes from its own stream.
pub(crate) type Sampler = fn(&mut SynthRng) -> Box<dyn TrueEffect>;

/// An effect as the generator knows it.
pub(crate) struct Entry {
    pub kind: Extension,
    /// What input drives it, i.e. where in the data it shows.
    pub driver: &'static str,
    /// Its magnitudes drawn from its own stream.
    pub sample: Sampler,
    /// Its form as MF 6.1 writes it (the form the diagnosis fits), where the effect has one
    /// there: the truth of [`Forms::Mf61`].
    pub sample_mf61: Option<Sampler>,
}

/// Which forms the effects take in the true tire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Forms {
    /// Physical forms unlike those the diagnosis fits (see the module doc).
    #[default]
    Physical,
    /// MF 6.1's forms for combined slip (Gxa, Gyk, SVyk), inflation pressure (ppx1..4,
    /// ppy1..4), the shifts with their load terms (pHy1..2, pVy1..2) and camber on the peak
    /// (pDx3, pDy3): the forms the diagnosis fits; the other effects keep their physical
    /// forms.
    Mf61,
}

impl Forms {
    pub const ALL: [Forms; 2] = [Forms::Physical, Forms::Mf61];

    pub fn name(self) -> &'static str {
        match self {
            Forms::Physical => "physical",
            Forms::Mf61 => "mf61",
        }
    }

    pub fn from_name(name: &str) -> Option<Forms> {
        Forms::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// The generator's entry of `kind`.
pub(crate) fn entry(kind: Extension) -> &'static Entry {
    EFFECTS
        .iter()
        .find(|e| e.kind == kind)
        .expect("every mf87 extension has a synthetic form (see EFFECTS)")
}

/// One effect with its drawn magnitudes, and how it acts on the true tire. The true tire is
/// evaluated in stages, each method one stage; the defaults leave a stage as it is, so an
/// effect implements the stages it acts in.
pub(crate) trait TrueEffect: Debug {
    /// Its magnitudes by name, for the truth record.
    fn params(&self) -> BTreeMap<String, f64>;

    /// Modifies the base tire at one instant (friction, stiffness, ...), in [`EFFECTS`] order.
    fn modify(&self, _m: &mut Mods, _x: &TrueSample) {}

    /// A shift of the slip angle [rad] the tire's forces are computed at.
    fn alpha_shift(&self, _tire: &BaseTire, _m: &Mods, _x: &TrueSample) -> Option<f64> {
        None
    }

    /// The steady forces at slip angle `alpha` in place of the base tire's pure-slip ones.
    fn forces(&self, _tire: &BaseTire, _m: &Mods, _x: &TrueSample, _alpha: f64) -> Option<Forces> {
        None
    }

    /// Adds to the steady-state forces.
    fn add_to_steady(&self, _f: &mut Forces, _x: &TrueSample) {}

    /// The forces `f` after `ds` metres travelled, with the state it carries along a block.
    fn lag(&self, _state: &mut LagState, f: Forces, _x: &TrueSample, _ds: f64) -> Forces {
        f
    }

    /// A force subtracted from Fx [N] after the lag (a force against rolling).
    fn fx_subtracted(&self, _x: &TrueSample) -> Option<f64> {
        None
    }

    /// The slip ratio the rig reports for the slip ratio `kappa`.
    fn measured_kappa(&self, kappa: f64) -> f64 {
        kappa
    }

    /// What the rig's load cell adds to Fx [N].
    fn fx_offset(&self, _x: &TrueSample) -> Option<f64> {
        None
    }
}

/// Forces and moment [N, N, N.m].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Forces {
    pub fx: f64,
    pub fy: f64,
    pub mz: f64,
}

/// What an effect carries from row to row within a block: a filter's two stages for each of
/// Fx, Fy, Mz, set from the first row's input.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LagState {
    stages: Option<[[f64; 2]; 3]>,
}

fn named(pairs: &[(&str, f64)]) -> BTreeMap<String, f64> {
    pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

/// The effects switched on, with their magnitudes, in [`Extension::ALL`] order.
#[derive(Debug, Default)]
pub(crate) struct EffectSet {
    on: Vec<(Extension, Box<dyn TrueEffect>)>,
}

impl EffectSet {
    /// Magnitudes for `seed`; each effect from its own stream, so they do not depend on which
    /// other effects are on; in `forms`.
    pub fn sample(seed: u64, on: &[Extension], forms: Forms) -> EffectSet {
        let on = Extension::ALL
            .into_iter()
            .filter(|e| on.contains(e))
            .map(|e| {
                let rng = &mut stream(seed, &format!("effect:{}", e.name()));
                let entry = entry(e);
                let sample = match (forms, entry.sample_mf61) {
                    (Forms::Mf61, Some(mf61)) => mf61,
                    _ => entry.sample,
                };
                (e, sample(rng))
            })
            .collect();
        EffectSet { on }
    }

    /// The parameters of each effect that is on.
    pub fn params(&self) -> Vec<(Extension, BTreeMap<String, f64>)> {
        self.on.iter().map(|(e, x)| (*e, x.params())).collect()
    }

    fn iter(&self) -> impl Iterator<Item = &dyn TrueEffect> {
        self.on.iter().map(|(_, x)| x.as_ref())
    }

    /// Modifiers of the base tire at one instant.
    fn mods(&self, x: &TrueSample) -> Mods {
        let mut m = Mods {
            speed: x.speed,
            ..Mods::default()
        };
        for e in self.iter() {
            e.modify(&mut m, x);
        }
        m
    }
}

/// The tire on the rig: a base tire with effects.
#[derive(Debug)]
pub(crate) struct TrueTire {
    pub base: BaseTire,
    pub effects: EffectSet,
}

impl TrueTire {
    /// Steady-state forces (before any lag and rolling resistance).
    pub fn steady(&self, x: &TrueSample) -> Forces {
        let m = self.effects.mods(x);
        let mut alpha = x.alpha;
        for e in self.effects.iter() {
            if let Some(shift) = e.alpha_shift(&self.base, &m, x) {
                alpha += shift;
            }
        }
        let forces = self
            .effects
            .iter()
            .find_map(|e| e.forces(&self.base, &m, x, alpha));
        let mut f = forces.unwrap_or_else(|| {
            let (fy, mz) = self.base.lateral(x.fz, alpha, x.gamma, &m);
            Forces {
                fx: self.base.fx0(x.fz, x.kappa, &m),
                fy,
                mz,
            }
        });
        for e in self.effects.iter() {
            e.add_to_steady(&mut f, x);
        }
        f
    }

    /// A block's start: one state per effect.
    pub fn block_start(&self) -> Vec<LagState> {
        vec![LagState::default(); self.effects.on.len()]
    }

    /// The forces `f` after `ds` metres travelled (unchanged without a lagging effect).
    pub fn lagged(&self, state: &mut [LagState], f: Forces, x: &TrueSample, ds: f64) -> Forces {
        self.effects
            .iter()
            .zip(state)
            .fold(f, |f, (e, s)| e.lag(s, f, x, ds))
    }

    /// The forces to subtract from Fx [N] (0 without such an effect).
    pub fn fx_subtracted(&self, x: &TrueSample) -> f64 {
        self.effects
            .iter()
            .filter_map(|e| e.fx_subtracted(x))
            .reduce(|a, b| a + b)
            .unwrap_or(0.0)
    }

    /// The slip ratio the rig reports (the true one without rig offsets).
    pub fn measured_kappa(&self, x: &TrueSample) -> f64 {
        self.effects
            .iter()
            .fold(x.kappa, |kappa, e| e.measured_kappa(kappa))
    }

    /// What the rig's load cell adds to Fx [N] (0 without rig offsets).
    pub fn fx_offset(&self, x: &TrueSample) -> f64 {
        self.effects
            .iter()
            .filter_map(|e| e.fx_offset(x))
            .reduce(|a, b| a + b)
            .unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_extension_has_one_synthetic_form() {
        for kind in Extension::ALL {
            let n = EFFECTS.iter().filter(|e| e.kind == kind).count();
            assert_eq!(n, 1, "{kind}");
            assert!(entry(kind).driver.len() > 20, "{kind}");
        }
        assert_eq!(EFFECTS.len(), Extension::ALL.len());
    }
}
