//! Base tires: the "true" pure-slip behaviour of the tire on the rig when no effect is on.
//!
//! All three kinds are written in the paper's sign convention (alpha > 0 gives Fy > 0 and
//! Mz < 0, gamma > 0 gives Fy > 0 at zero slip, kappa > 0 gives Fx > 0) and in SI units
//! (N, rad, slip ratio). None of them has a force at zero slip and zero camber: offsets
//! (ply steer, conicity, rolling resistance) only come from effects.
//!
//! Effects reach a base tire through [`Mods`]: multipliers on friction, slip stiffness and
//! aligning-moment arm, a multiplier on the load at which the lateral stiffness law is
//! evaluated, and optionally a friction coefficient that falls with sliding speed.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use mf87::{Channel, MagicFormula, Params, channel_factors};

use super::TireKind;
use super::rng::{SynthRng, jitter, uniform};

/// Nominal load of the load-normalised forms [N].
pub(crate) const FZ_NOMINAL: f64 = 4000.0;

/// Friction that falls with sliding speed: `1 - drop (1 - exp(-Vs / v_char))`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SlideFriction {
    pub drop: f64,
    pub v_char: f64,
}

/// How effects modify a base tire at one instant. `Mods::default()` is the bare tire.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Mods {
    /// Friction multipliers (peak force).
    pub mu_x: f64,
    pub mu_y: f64,
    /// Slip-stiffness multipliers (initial slope).
    pub k_x: f64,
    pub k_y: f64,
    /// Multiplier on the load at which the lateral stiffness law is evaluated.
    pub fz_stiff: f64,
    /// Multiplier on the aligning-moment arm (pneumatic trail).
    pub trail: f64,
    /// Friction that falls with sliding speed, if any.
    pub slide: Option<SlideFriction>,
    /// Forward speed [m/s] (for the sliding speed).
    pub speed: f64,
}

impl Default for Mods {
    fn default() -> Self {
        Mods {
            mu_x: 1.0,
            mu_y: 1.0,
            k_x: 1.0,
            k_y: 1.0,
            fz_stiff: 1.0,
            trail: 1.0,
            slide: None,
            speed: 0.0,
        }
    }
}

impl Mods {
    /// The sliding-speed friction factor at a slip of magnitude `slip` (tan alpha or kappa).
    fn slide_factor(&self, slip: f64) -> f64 {
        match self.slide {
            Some(s) => 1.0 - s.drop * (1.0 - (-(self.speed * slip.abs()) / s.v_char).exp()),
            None => 1.0,
        }
    }
}

/// A base tire with its parameters.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum BaseTire {
    Mf87(Box<Params>),
    Mf52(Mf52),
    Brush(Brush),
}

impl BaseTire {
    /// A tire of `kind` with parameters drawn from `rng`.
    pub fn sample(kind: TireKind, rng: &mut SynthRng) -> BaseTire {
        match kind {
            TireKind::Mf87Perturbed => BaseTire::Mf87(Box::new(perturbed_mf87(rng))),
            TireKind::Mf52 => BaseTire::Mf52(Mf52::sample(rng)),
            TireKind::Brush => BaseTire::Brush(Brush::sample(rng)),
        }
    }

    /// Pure longitudinal force [N] at slip ratio `kappa`.
    pub fn fx0(&self, fz: f64, kappa: f64, m: &Mods) -> f64 {
        if fz <= 0.0 {
            return 0.0;
        }
        match self {
            BaseTire::Mf87(p) => {
                let mut f = channel_factors(p, Channel::Fx, fz / 1000.0, 0.0);
                let bcd = f.b * f.c * f.d * m.k_x;
                f.d *= m.mu_x * m.slide_factor(kappa);
                f.b = bcd / (f.c * f.d);
                f.eval(100.0 * kappa)
            }
            BaseTire::Mf52(t) => t.fx0(fz, kappa, m),
            BaseTire::Brush(t) => t.fx0(fz, kappa, m),
        }
    }

    /// Pure lateral force [N] and aligning moment [N.m] at slip angle `alpha`, camber `gamma`.
    pub fn lateral(&self, fz: f64, alpha: f64, gamma: f64, m: &Mods) -> (f64, f64) {
        if fz <= 0.0 {
            return (0.0, 0.0);
        }
        match self {
            BaseTire::Mf87(p) => {
                let (fz_kn, g, a) = (fz / 1000.0, gamma.to_degrees(), alpha.to_degrees());
                let slide = m.slide_factor(alpha.tan());
                let scaled = |channel: Channel, arm: f64, sv_scale: f64| -> MagicFormula {
                    let mut f = channel_factors(p, channel, fz_kn, g);
                    let k = channel_factors(p, channel, fz_kn * m.fz_stiff, g);
                    let bcd = k.b * k.c * k.d * m.k_y * arm;
                    f.d *= m.mu_y * slide * arm;
                    f.b = bcd / (f.c * f.d);
                    f.sv *= sv_scale;
                    f
                };
                let fy = scaled(Channel::Fy, 1.0, m.k_y).eval(a);
                let mz = scaled(Channel::Mz, m.trail, 1.0).eval(a);
                (fy, mz)
            }
            BaseTire::Mf52(t) => t.lateral(fz, alpha, gamma, m),
            BaseTire::Brush(t) => t.lateral(fz, alpha, gamma, m),
        }
    }

    /// Lateral peak force [N] and cornering stiffness [N/rad] at zero sliding speed.
    pub fn lat_scale(&self, fz: f64, gamma: f64, m: &Mods) -> (f64, f64) {
        let fz = fz.max(1.0);
        match self {
            BaseTire::Mf87(p) => {
                let g = gamma.to_degrees();
                let f = channel_factors(p, Channel::Fy, fz / 1000.0, g);
                let k = channel_factors(p, Channel::Fy, fz / 1000.0 * m.fz_stiff, g);
                (
                    f.d.abs() * m.mu_y,
                    (k.b * k.c * k.d).abs() * m.k_y * 180.0 / PI,
                )
            }
            BaseTire::Mf52(t) => t.lat_scale(fz, gamma, m),
            BaseTire::Brush(t) => t.lat_scale(fz, gamma, m),
        }
    }

    /// The parameters, by name, for the truth record.
    pub fn params(&self) -> BTreeMap<String, f64> {
        match self {
            BaseTire::Mf87(p) => {
                let mut out = BTreeMap::new();
                for channel in Channel::ALL {
                    for i in 0.. {
                        let Some(v) = p.coefficient(channel, i) else {
                            break;
                        };
                        let name = Params::coefficient_names(channel)[i];
                        out.insert(format!("{channel}.{name}"), v);
                    }
                }
                out
            }
            BaseTire::Mf52(t) => t.params(),
            BaseTire::Brush(t) => t.params(),
        }
    }
}

/// The paper's table with every coefficient perturbed: friction level and load sensitivity
/// +-15-20 %, stiffness laws +-10-20 %, shape +-6 %, curvature +-20 %, camber terms +-25 %.
/// Re-drawn until the set is valid and the curvature factor E of Fx and Fy stays below 0.95
/// for 0.5..10 kN (above 1 the curve folds back).
fn perturbed_mf87(rng: &mut SynthRng) -> Params {
    let paper = Params::paper_table();
    for _ in 0..1000 {
        let mut p = paper.clone();
        p.source = Some("synthetic: the paper's table, every coefficient perturbed".into());
        // Fy and Mz share a friction level (both scale with the lateral grip).
        let grip_y = jitter(rng, 1.0, 0.15);
        for (c, grip) in [(&mut p.Fy, grip_y), (&mut p.Mz, grip_y)] {
            c.C = jitter(rng, c.C, 0.06);
            c.a1 = jitter(rng, c.a1, 0.2) * grip;
            c.a2 = jitter(rng, c.a2, 0.05) * grip;
            c.a3 = jitter(rng, c.a3, 0.2);
            c.a4 = jitter(rng, c.a4, 0.1);
            c.a5 = jitter(rng, c.a5, 0.2);
            c.a6 = jitter(rng, c.a6, 0.2);
            c.a7 = jitter(rng, c.a7, 0.2);
            c.a8 = jitter(rng, c.a8, 0.2);
            c.a9 = jitter(rng, c.a9, 0.25);
            c.a10 = jitter(rng, c.a10, 0.25);
            c.a11 = jitter(rng, c.a11, 0.25);
            c.a12 = jitter(rng, c.a12, 0.25);
            c.a13 = jitter(rng, c.a13, 0.25);
        }
        let x = &mut p.Fx;
        let grip_x = jitter(rng, 1.0, 0.15);
        x.C = jitter(rng, x.C, 0.06);
        x.a1 = jitter(rng, x.a1, 0.2) * grip_x;
        x.a2 = jitter(rng, x.a2, 0.05) * grip_x;
        x.a3 = jitter(rng, x.a3, 0.2);
        x.a4 = jitter(rng, x.a4, 0.2);
        x.a5 = jitter(rng, x.a5, 0.2);
        x.a6 = jitter(rng, x.a6, 0.2);
        x.a7 = jitter(rng, x.a7, 0.2);
        x.a8 = jitter(rng, x.a8, 0.2);
        let e_ok = (1..=20).all(|k| {
            let fz_kn = 0.5 * k as f64;
            [Channel::Fx, Channel::Fy]
                .into_iter()
                .all(|ch| channel_factors(&p, ch, fz_kn, 0.0).e < 0.95)
        });
        if e_ok && p.validate().is_ok() {
            return p;
        }
    }
    paper
}

/// `D sin(C atan(B x - E (B x - atan(B x))))`.
fn magic(b: f64, c: f64, d: f64, e: f64, x: f64) -> f64 {
    let bx = b * x;
    d * (c * (bx - e * (bx - bx.atan())).atan()).sin()
}

/// A Magic-Formula-5.2-style pure-slip tire (Pacejka 2002, ch. 4.3.2) with nominal-load
/// normalisation `dfz = (Fz - Fz0) / Fz0`, camber in rad, written in the paper's signs:
///
/// - Fx: `mu_x = pdx1 + pdx2 dfz`, `Kx = Fz (pkx1 + pkx2 dfz) exp(pkx3 dfz)`,
///   `Ex = (pex1 + pex2 dfz + pex3 dfz^2)(1 - pex4 sgn kappa)` (drive/brake asymmetry).
/// - Fy: `mu_y = (pdy1 + pdy2 dfz)(1 - pdy3 gamma^2)`,
///   `Ky = pky1 Fz0 sin(2 atan(Fz / (pky2 Fz0)))(1 - pky3 |gamma|)`,
///   `Ey = (pey1 + pey2 dfz)(1 - (pey3 + pey4 gamma) sgn alpha_y)`, `Sh = phy3 gamma`,
///   `Sv = Fz (pvy3 + pvy4 dfz) gamma`.
/// - Mz: `-t Fy + Mzr` with the pneumatic trail `t = Dt cos(Ct atan(Bt a - Et (Bt a -
///   atan(Bt a)))) cos alpha` and the residual torque `Mzr = Dr cos(atan(Br a_r)) cos alpha`,
///   `Dr = Fz R0 (qdz8 + qdz9 dfz) gamma`.
///
/// Ply-steer and conicity terms (phy1, pvy1, qhz1, qdz6, ...) are zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Mf52 {
    pub r0: f64,
    pub pcx1: f64,
    pub pdx1: f64,
    pub pdx2: f64,
    pub pex1: f64,
    pub pex2: f64,
    pub pex3: f64,
    pub pex4: f64,
    pub pkx1: f64,
    pub pkx2: f64,
    pub pkx3: f64,
    pub pcy1: f64,
    pub pdy1: f64,
    pub pdy2: f64,
    pub pdy3: f64,
    pub pey1: f64,
    pub pey2: f64,
    pub pey3: f64,
    pub pey4: f64,
    pub pky1: f64,
    pub pky2: f64,
    pub pky3: f64,
    pub phy3: f64,
    pub pvy3: f64,
    pub pvy4: f64,
    pub qbz1: f64,
    pub qbz2: f64,
    pub qbz3: f64,
    pub qbz5: f64,
    pub qbz10: f64,
    pub qcz1: f64,
    pub qdz1: f64,
    pub qdz2: f64,
    pub qdz8: f64,
    pub qdz9: f64,
    pub qez1: f64,
    pub qez2: f64,
    pub qez5: f64,
}

impl Mf52 {
    fn sample(rng: &mut SynthRng) -> Mf52 {
        let mut j = |v: f64, rel: f64| jitter(rng, v, rel);
        Mf52 {
            r0: j(0.31, 0.05),
            pcx1: j(1.62, 0.05),
            pdx1: j(1.12, 0.08),
            pdx2: j(-0.09, 0.3),
            pex1: j(0.2, 0.3),
            pex2: j(0.25, 0.3),
            pex3: j(-0.05, 0.3),
            pex4: j(0.12, 0.3),
            pkx1: j(22.0, 0.12),
            pkx2: j(5.0, 0.3),
            pkx3: j(-0.3, 0.3),
            pcy1: j(1.35, 0.05),
            pdy1: j(1.0, 0.08),
            pdy2: j(-0.12, 0.3),
            pdy3: j(3.0, 0.3),
            pey1: j(-0.6, 0.2),
            pey2: j(-0.4, 0.3),
            pey3: j(0.1, 0.3),
            pey4: j(-3.0, 0.3),
            pky1: j(16.0, 0.12),
            pky2: j(1.8, 0.1),
            pky3: j(0.5, 0.3),
            phy3: j(0.02, 0.3),
            pvy3: j(0.9, 0.2),
            pvy4: j(-0.2, 0.3),
            qbz1: j(10.0, 0.1),
            qbz2: j(-1.5, 0.3),
            qbz3: j(0.5, 0.3),
            qbz5: j(-0.3, 0.3),
            qbz10: j(0.6, 0.2),
            qcz1: j(1.25, 0.05),
            qdz1: j(0.095, 0.15),
            qdz2: j(-0.01, 0.3),
            qdz8: j(0.12, 0.2),
            qdz9: j(0.05, 0.3),
            qez1: j(-1.5, 0.2),
            qez2: j(0.3, 0.3),
            qez5: j(0.5, 0.3),
        }
    }

    fn dfz(fz: f64) -> f64 {
        (fz - FZ_NOMINAL) / FZ_NOMINAL
    }

    fn long_scale(&self, fz: f64, m: &Mods) -> (f64, f64) {
        let dfz = Self::dfz(fz);
        let d = (self.pdx1 + self.pdx2 * dfz) * fz * m.mu_x;
        let k = fz * (self.pkx1 + self.pkx2 * dfz) * (self.pkx3 * dfz).exp() * m.k_x;
        (d, k)
    }

    fn fx0(&self, fz: f64, kappa: f64, m: &Mods) -> f64 {
        let (d, k) = self.long_scale(fz, m);
        let d = d * m.slide_factor(kappa);
        let dfz = Self::dfz(fz);
        let e = ((self.pex1 + self.pex2 * dfz + self.pex3 * dfz * dfz)
            * (1.0 - self.pex4 * kappa.signum()))
        .min(0.95);
        magic(k / (self.pcx1 * d), self.pcx1, d, e, kappa)
    }

    fn lat_scale(&self, fz: f64, gamma: f64, m: &Mods) -> (f64, f64) {
        let dfz = Self::dfz(fz);
        let d = (self.pdy1 + self.pdy2 * dfz) * (1.0 - self.pdy3 * gamma * gamma) * fz * m.mu_y;
        let fz_k = fz * m.fz_stiff;
        let k = self.pky1
            * FZ_NOMINAL
            * (2.0 * (fz_k / (self.pky2 * FZ_NOMINAL)).atan()).sin()
            * (1.0 - self.pky3 * gamma.abs())
            * m.k_y;
        (d, k)
    }

    fn lateral(&self, fz: f64, alpha: f64, gamma: f64, m: &Mods) -> (f64, f64) {
        let dfz = Self::dfz(fz);
        let (d, k) = self.lat_scale(fz, gamma, m);
        let d = d * m.slide_factor(alpha.tan());
        let c = self.pcy1;
        let b = k / (c * d);
        let sh = self.phy3 * gamma;
        let sv = fz * (self.pvy3 + self.pvy4 * dfz) * gamma * m.k_y;
        let ay = alpha + sh;
        let e = ((self.pey1 + self.pey2 * dfz)
            * (1.0 - (self.pey3 + self.pey4 * gamma) * ay.signum()))
        .min(0.95);
        let fy = magic(b, c, d, e, ay) + sv;

        // Aligning moment: pneumatic trail times Fy plus residual torque.
        let bt =
            (self.qbz1 + self.qbz2 * dfz + self.qbz3 * dfz * dfz) * (1.0 + self.qbz5 * gamma.abs());
        let ct = self.qcz1;
        let dt = fz * (self.qdz1 + self.qdz2 * dfz) * self.r0 / FZ_NOMINAL * m.trail;
        let at = alpha;
        let et = ((self.qez1 + self.qez2 * dfz)
            * (1.0 + self.qez5 * gamma * (2.0 / PI) * (bt * ct * at).atan()))
        .min(0.95);
        let btat = bt * at;
        let trail = dt * (ct * (btat - et * (btat - btat.atan())).atan()).cos() * alpha.cos();
        let br = self.qbz10 * b * c;
        let ar = alpha + sh + sv / k;
        let dr = fz * self.r0 * (self.qdz8 + self.qdz9 * dfz) * gamma * m.trail;
        let mzr = dr * (br * ar).atan().cos() * alpha.cos();
        (fy, -trail * fy + mzr)
    }

    fn params(&self) -> BTreeMap<String, f64> {
        let fields: [(&str, f64); 38] = [
            ("R0", self.r0),
            ("pcx1", self.pcx1),
            ("pdx1", self.pdx1),
            ("pdx2", self.pdx2),
            ("pex1", self.pex1),
            ("pex2", self.pex2),
            ("pex3", self.pex3),
            ("pex4", self.pex4),
            ("pkx1", self.pkx1),
            ("pkx2", self.pkx2),
            ("pkx3", self.pkx3),
            ("pcy1", self.pcy1),
            ("pdy1", self.pdy1),
            ("pdy2", self.pdy2),
            ("pdy3", self.pdy3),
            ("pey1", self.pey1),
            ("pey2", self.pey2),
            ("pey3", self.pey3),
            ("pey4", self.pey4),
            ("pky1", self.pky1),
            ("pky2", self.pky2),
            ("pky3", self.pky3),
            ("phy3", self.phy3),
            ("pvy3", self.pvy3),
            ("pvy4", self.pvy4),
            ("qbz1", self.qbz1),
            ("qbz2", self.qbz2),
            ("qbz3", self.qbz3),
            ("qbz5", self.qbz5),
            ("qbz10", self.qbz10),
            ("qcz1", self.qcz1),
            ("qdz1", self.qdz1),
            ("qdz2", self.qdz2),
            ("qdz8", self.qdz8),
            ("qdz9", self.qdz9),
            ("qez1", self.qez1),
            ("qez2", self.qez2),
            ("qez5", self.qez5),
        ];
        fields.iter().map(|(k, v)| (k.to_string(), *v)).collect()
    }
}

/// A brush-model tire with a parabolic contact pressure (Pacejka 2002, ch. 3.2) and a
/// friction coefficient that falls from its static value mu_s to a kinetic value mu_k as the
/// slip grows, which gives the force a peak and a fall-off:
///
/// - `F(s) = mu Fz (3 l - 3 l |l| + l^3)` with `l = C s / (3 mu Fz)` for `|l| < 1`, else
///   `mu Fz sgn s`; `mu(s) = mu_k + (mu_s - mu_k) / (1 + (s / s_c)^2)`,
///   `s_c = q 3 mu_s Fz / C`.
/// - Fx: theoretical slip `s = kappa / (1 + kappa)`, `Cx = cx Fz exp(-cx3 dfz)`.
/// - Fy: `s = tan alpha + eg sin gamma` (camber as equivalent slip),
///   `Cy = Kmax (1 - exp(-Fz / Fk))(1 - cg |gamma|)`, `mu_s ~ (Fz / Fz0)^-n`.
/// - Mz: `-mu Fz a l (1 - |l|)^3` (zero at full sliding), contact half-length
///   `a = a0 (Fz / Fz0)^0.6`, plus a camber twisting torque
///   `km a Fz sin gamma / (1 + (tan alpha / 0.12)^2)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Brush {
    pub cx: f64,
    pub cx3: f64,
    pub mu_sx: f64,
    pub kinetic_x: f64,
    pub k_max: f64,
    pub f_k: f64,
    pub cg: f64,
    pub mu_sy: f64,
    pub mu_load_exp: f64,
    pub kinetic_y: f64,
    pub q: f64,
    pub eg: f64,
    pub a0: f64,
    pub km: f64,
}

impl Brush {
    fn sample(rng: &mut SynthRng) -> Brush {
        Brush {
            cx: uniform(rng, 19.0, 26.0),
            cx3: uniform(rng, 0.1, 0.25),
            mu_sx: uniform(rng, 1.05, 1.2),
            kinetic_x: uniform(rng, 0.72, 0.82),
            k_max: uniform(rng, 75_000.0, 90_000.0),
            f_k: uniform(rng, 3000.0, 4200.0),
            cg: uniform(rng, 0.5, 1.0),
            mu_sy: uniform(rng, 0.98, 1.12),
            mu_load_exp: uniform(rng, 0.08, 0.14),
            kinetic_y: uniform(rng, 0.74, 0.84),
            q: uniform(rng, 0.55, 0.8),
            eg: uniform(rng, 0.08, 0.13),
            a0: uniform(rng, 0.085, 0.1),
            km: uniform(rng, 0.5, 0.8),
        }
    }

    /// Brush force for slip `s`, stiffness `c`, static and kinetic friction: the force, the
    /// normalised slip `l` (|l| >= 1 at full sliding) and the friction coefficient used.
    fn force(s: f64, c: f64, mu_s: f64, mu_k: f64, q: f64, fz: f64) -> (f64, f64, f64) {
        let s_c = q * 3.0 * mu_s * fz / c;
        let mu = mu_k + (mu_s - mu_k) / (1.0 + (s / s_c).powi(2));
        let l = c * s / (3.0 * mu * fz);
        if l.abs() >= 1.0 {
            (mu * fz * s.signum(), l, mu)
        } else {
            (mu * fz * (3.0 * l - 3.0 * l * l.abs() + l * l * l), l, mu)
        }
    }

    fn long_scale(&self, fz: f64, m: &Mods) -> (f64, f64) {
        let dfz = (fz - FZ_NOMINAL) / FZ_NOMINAL;
        (
            self.mu_sx * fz * m.mu_x,
            self.cx * fz * (-self.cx3 * dfz).exp() * m.k_x,
        )
    }

    fn fx0(&self, fz: f64, kappa: f64, m: &Mods) -> f64 {
        let (d, c) = self.long_scale(fz, m);
        let s = kappa / (1.0 + kappa);
        let mu_s = d / fz * m.slide_factor(s);
        Brush::force(s, c, mu_s, mu_s * self.kinetic_x, self.q, fz).0
    }

    fn lat_scale(&self, fz: f64, gamma: f64, m: &Mods) -> (f64, f64) {
        let mu = self.mu_sy * (fz / FZ_NOMINAL).powf(-self.mu_load_exp) * m.mu_y;
        let fz_k = fz * m.fz_stiff;
        let c =
            self.k_max * (1.0 - (-fz_k / self.f_k).exp()) * (1.0 - self.cg * gamma.abs()) * m.k_y;
        (mu * fz, c)
    }

    fn lateral(&self, fz: f64, alpha: f64, gamma: f64, m: &Mods) -> (f64, f64) {
        let (d, c) = self.lat_scale(fz, gamma, m);
        let s = alpha.tan() + self.eg * gamma.sin();
        let mu_s = d / fz * m.slide_factor(alpha.tan());
        let mu_k = mu_s * self.kinetic_y;
        let (fy, l, mu) = Brush::force(s, c, mu_s, mu_k, self.q, fz);
        let a = self.a0 * (fz / FZ_NOMINAL).powf(0.6) * m.trail;
        let mz_slip = if l.abs() < 1.0 {
            -mu * fz * a * l * (1.0 - l.abs()).powi(3)
        } else {
            0.0
        };
        let twist = self.km * a * fz * gamma.sin() / (1.0 + (alpha.tan() / 0.12).powi(2));
        (fy, mz_slip + twist)
    }

    fn params(&self) -> BTreeMap<String, f64> {
        [
            ("cx", self.cx),
            ("cx3", self.cx3),
            ("mu_sx", self.mu_sx),
            ("kinetic_x", self.kinetic_x),
            ("k_max_N_per_rad", self.k_max),
            ("f_k_N", self.f_k),
            ("cg", self.cg),
            ("mu_sy", self.mu_sy),
            ("mu_load_exp", self.mu_load_exp),
            ("kinetic_y", self.kinetic_y),
            ("q", self.q),
            ("eg", self.eg),
            ("a0_m", self.a0),
            ("km", self.km),
        ]
        .iter()
        .map(|(k, v)| (k.to_string(), *v))
        .collect()
    }
}
