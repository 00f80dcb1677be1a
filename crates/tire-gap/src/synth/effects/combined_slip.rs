//! Combined slip as the generator makes it (see [`CombinedSlip`]), its magnitudes and how it acts.

use std::collections::BTreeMap;

use mf87::extensions::Extension;

use super::{Entry, Forces, TrueEffect, named};
use crate::synth::blocks::TrueSample;
use crate::synth::rng::{SynthRng, uniform};
use crate::synth::tires::{BaseTire, Mods};

pub(super) const ENTRY: Entry = Entry {
    kind: Extension::CombinedSlip,
    driver: "slip angle and slip ratio together (alpha and kappa both non-zero): combined-slip sweeps",
    sample: |rng| Box::new(CombinedSlip::sample(rng)),
    sample_mf61: Some(|rng| Box::new(Mf61Combined::sample(rng))),
};

/// Combined slip by the normalised-slip (similarity) method of Pacejka and Sharp, with
/// theoretical slips `sx = kappa / (1 + kappa)`, `sy = tan(alpha - alpha0) / (1 + kappa)`
/// (alpha0: where the pure Fy crosses zero, so camber thrust and ply steer are kept) each
/// normalised by the slip at which its pure force peaks (found numerically, in the direction
/// of the slip, times a tire-specific factor `norm`), and `s = |(sx / sx_peak, sy / sy_peak)|`:
///
/// `Fx = (|sx_n| / s) Fx0(kappa_eq)`, `Fy = (|sy_n| / s) Fy0(alpha_eq)` where the equivalent
/// pure slips have the same normalised magnitude `s`. The aligning moment is scaled the same
/// way about its value at alpha0, plus the moment of Fx about the laterally deflected contact
/// patch, `-Fx Fy / c_lat`. At kappa = 0 or alpha = alpha0 it returns the pure-slip forces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CombinedSlip {
    /// Factor on the peak slips used for normalisation (0.8..1.2).
    pub norm: f64,
    /// Lateral carcass stiffness [N/m] (250..400 kN/m).
    pub c_lat: f64,
}

/// Where a unimodal `f` peaks in |f| on [0, hi] (golden-section search).
fn peak_location(f: impl Fn(f64) -> f64, hi: f64) -> f64 {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (0.0, hi);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c).abs(), f(d).abs());
    for _ in 0..40 {
        if fc > fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c).abs();
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d).abs();
        }
    }
    (a + b) / 2.0
}

impl CombinedSlip {
    fn sample(rng: &mut SynthRng) -> Self {
        CombinedSlip {
            norm: uniform(rng, 0.8, 1.2),
            c_lat: uniform(rng, 250e3, 400e3),
        }
    }

    fn params(&self) -> BTreeMap<String, f64> {
        named(&[("norm", self.norm), ("c_lat_N_per_m", self.c_lat)])
    }

    /// Slip angle where the pure lateral force is zero (Newton, from the linear estimate).
    fn alpha_zero(tire: &BaseTire, fz: f64, gamma: f64, m: &Mods) -> f64 {
        let fy = |a: f64| tire.lateral(fz, a, gamma, m).0;
        let (_, k) = tire.lat_scale(fz, gamma, m);
        let mut a = (-fy(0.0) / k).clamp(-0.1, 0.1);
        for _ in 0..12 {
            let f = fy(a);
            if f.abs() < 1e-7 {
                break;
            }
            let h = 1e-6;
            let slope = (fy(a + h) - fy(a - h)) / (2.0 * h);
            if slope.abs() < 1e-9 {
                break;
            }
            a = (a - f / slope).clamp(-0.15, 0.15);
        }
        a
    }

    fn forces(
        &self,
        tire: &BaseTire,
        fz: f64,
        alpha: f64,
        kappa: f64,
        gamma: f64,
        m: &Mods,
    ) -> Forces {
        let alpha0 = Self::alpha_zero(tire, fz, gamma, m);
        let sx = kappa / (1.0 + kappa);
        let sy = (alpha - alpha0).tan() / (1.0 + kappa);
        // Peak slips, as theoretical slips, on the side the slip is on.
        let dir_x = if sx < 0.0 { -1.0 } else { 1.0 };
        let kappa_peak = peak_location(|k| tire.fx0(fz, dir_x * k, m), 0.6);
        let sx_ref = self.norm * kappa_peak / (1.0 + dir_x * kappa_peak);
        let dir_y = if sy < 0.0 { -1.0 } else { 1.0 };
        let alpha_peak = peak_location(|a| tire.lateral(fz, alpha0 + dir_y * a, gamma, m).0, 0.6);
        let sy_ref = self.norm * alpha_peak.tan();
        let (sxn, syn) = (sx / sx_ref, sy / sy_ref);
        let s = sxn.hypot(syn);
        let (_, mz_at_zero) = tire.lateral(fz, alpha0, gamma, m);
        if s < 1e-12 {
            return Forces {
                fx: 0.0,
                fy: 0.0,
                mz: mz_at_zero,
            };
        }
        let sx_eq = (s * sx_ref).min(0.9).copysign(sx);
        let kappa_eq = sx_eq / (1.0 - sx_eq);
        let alpha_eq = alpha0 + (s * sy_ref).atan().copysign(sy);
        let fx = sxn.abs() / s * tire.fx0(fz, kappa_eq, m);
        let (fy_eq, mz_eq) = tire.lateral(fz, alpha_eq, gamma, m);
        let wy = syn.abs() / s;
        let fy = wy * fy_eq;
        let mz = mz_at_zero + wy * (mz_eq - mz_at_zero) - fx * fy / self.c_lat;
        Forces { fx, fy, mz }
    }
}

impl TrueEffect for CombinedSlip {
    fn params(&self) -> BTreeMap<String, f64> {
        CombinedSlip::params(self)
    }

    fn forces(&self, tire: &BaseTire, m: &Mods, x: &TrueSample, alpha: f64) -> Option<Forces> {
        Some(CombinedSlip::forces(
            self, tire, x.fz, alpha, x.kappa, x.gamma, m,
        ))
    }
}

/// Combined slip as MF 6.1 writes it: `Fx = Gxa Fx0`, `Fy = Gyk Fy0 + SVyk`, `Mz = Gyk Mz0`
/// with `Gxa = g(tan(alpha) + rHx1) / g(rHx1)`, `Bxa = rBx1 cos(atan(rBx2 kappa))`,
/// `Gyk = g(kappa + rHy1) / g(rHy1)`, `Byk = rBy1 cos(atan(rBy2 (tan(alpha) - rBy3)))`,
/// `g(x) = cos(C atan(B x - E (B x - atan(B x))))`, and
/// `SVyk = Dy (rVy1 + rVy3 gamma) cos(atan(rVy4 tan(alpha))) sin(rVy5 atan(rVy6 kappa))`
/// (Dy the lateral peak).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Mf61Combined {
    /// rBx1, rBx2, rCx1, rEx1, rHx1.
    pub x: [f64; 5],
    /// rBy1, rBy2, rBy3, rCy1, rEy1, rHy1.
    pub y: [f64; 6],
    /// rVy1, rVy3, rVy4, rVy5, rVy6.
    pub v: [f64; 5],
}

/// `cos(C atan(B x - E (B x - atan(B x))))`.
fn g(b: f64, c: f64, e: f64, x: f64) -> f64 {
    let bx = b * x;
    (c * (bx - e * (bx - bx.atan())).atan()).cos()
}

impl Mf61Combined {
    fn sample(rng: &mut SynthRng) -> Self {
        let mut u = |lo: f64, hi: f64| uniform(rng, lo, hi);
        let x = [
            u(8.0, 16.0),
            u(5.0, 12.0),
            u(0.95, 1.1),
            u(-0.4, 0.2),
            u(-0.01, 0.01),
        ];
        let y = [
            u(5.0, 12.0),
            u(3.0, 8.0),
            u(-0.02, 0.02),
            u(0.95, 1.1),
            u(-0.4, 0.2),
            u(-0.01, 0.01),
        ];
        let v = [
            u(-0.06, 0.06),
            u(-0.3, 0.3),
            u(5.0, 30.0),
            u(1.5, 2.2),
            u(10.0, 30.0),
        ];
        Mf61Combined { x, y, v }
    }
}

impl TrueEffect for Mf61Combined {
    fn params(&self) -> BTreeMap<String, f64> {
        let names = [
            "rBx1", "rBx2", "rCx1", "rEx1", "rHx1", "rBy1", "rBy2", "rBy3", "rCy1", "rEy1", "rHy1",
            "rVy1", "rVy3", "rVy4", "rVy5", "rVy6",
        ];
        let values = self.x.iter().chain(&self.y).chain(&self.v);
        names
            .iter()
            .zip(values)
            .map(|(n, v)| (n.to_string(), *v))
            .collect()
    }

    fn forces(&self, tire: &BaseTire, m: &Mods, x: &TrueSample, alpha: f64) -> Option<Forces> {
        let [bx1, bx2, cx, ex, hx] = self.x;
        let [by1, by2, by3, cy, ey, hy] = self.y;
        let [v1, v3, v4, v5, v6] = self.v;
        let (ta, k) = (alpha.tan(), x.kappa);
        let bxa = bx1 * (bx2 * k).atan().cos();
        let gxa = g(bxa, cx, ex, ta + hx) / g(bxa, cx, ex, hx);
        let byk = by1 * (by2 * (ta - by3)).atan().cos();
        let gyk = g(byk, cy, ey, k + hy) / g(byk, cy, ey, hy);
        let (fy0, mz0) = tire.lateral(x.fz, alpha, x.gamma, m);
        let (dy, _) = tire.lat_scale(x.fz, x.gamma, m);
        let svyk = dy * (v1 + v3 * x.gamma) * (v4 * ta).atan().cos() * (v5 * (v6 * k).atan()).sin();
        Some(Forces {
            fx: gxa * tire.fx0(x.fz, k, m),
            fy: gyk * fy0 + svyk,
            mz: gyk * mz0,
        })
    }
}
