//! The 1987 Magic Formula: one function for all three channels, and the load and camber
//! dependence of its factors. Everything here works in the paper's units (kN, deg, percent);
//! [`crate::evaluate`] is the SI entry point.

pub use crate::channel::Channel;
use crate::params::Params;

/// The factors of one Magic Formula curve at a given load and camber.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MagicFormula {
    /// Stiffness factor [1/deg or 1/percent].
    pub b: f64,
    /// Shape factor.
    pub c: f64,
    /// Peak factor [N or N.m].
    pub d: f64,
    /// Curvature factor.
    pub e: f64,
    /// Horizontal shift [deg].
    pub sh: f64,
    /// Vertical shift [N or N.m].
    pub sv: f64,
}

impl MagicFormula {
    /// `D sin(C atan(B phi)) + Sv` with `phi = (1 - E)(x + Sh) + (E / B) atan(B (x + Sh))`.
    pub fn eval(&self, x: f64) -> f64 {
        let x = x + self.sh;
        let phi = (1.0 - self.e) * x + self.e / self.b * (self.b * x).atan();
        self.d * (self.c * (self.b * phi).atan()).sin() + self.sv
    }
}

/// How the stiffness product BCD depends on load.
#[derive(Debug, Clone, Copy)]
enum StiffnessLaw {
    /// `a3 sin(a4 atan(a5 Fz))` (Fy).
    SineArctan,
    /// `(a3 Fz^2 + a4 Fz) / e^(a5 Fz)` (Mz, with erratum 2, and Fx).
    RationalExp,
}

/// B, C, D, E at load `fz_kn` from `C, a1..a8`.
fn load_factors(c: f64, a: [f64; 8], law: StiffnessLaw, fz_kn: f64) -> MagicFormula {
    let [a1, a2, a3, a4, a5, a6, a7, a8] = a;
    let d = a1 * fz_kn * fz_kn + a2 * fz_kn;
    let bcd = match law {
        StiffnessLaw::SineArctan => a3 * (a4 * (a5 * fz_kn).atan()).sin(),
        StiffnessLaw::RationalExp => (a3 * fz_kn * fz_kn + a4 * fz_kn) / (a5 * fz_kn).exp(),
    };
    MagicFormula {
        b: bcd / (c * d),
        c,
        d,
        e: a6 * fz_kn * fz_kn + a7 * fz_kn + a8,
        sh: 0.0,
        sv: 0.0,
    }
}

/// The factors of `channel` at load `fz_kn` [kN] and camber `gamma_deg` [deg].
///
/// Camber (errata 3): `Sh = a9 gamma`, `Sv = (a10 Fz^2 + a11 Fz) gamma`,
/// `B -> B (1 - a12 |gamma|)`, `E -> E / (1 - a13 |gamma|)`. Fx has no camber terms.
pub fn channel_factors(
    params: &Params,
    channel: Channel,
    fz_kn: f64,
    gamma_deg: f64,
) -> MagicFormula {
    let (p, law) = match channel {
        Channel::Fx => {
            let p = &params.Fx;
            let a = [p.a1, p.a2, p.a3, p.a4, p.a5, p.a6, p.a7, p.a8];
            return load_factors(p.C, a, StiffnessLaw::RationalExp, fz_kn);
        }
        Channel::Fy => (&params.Fy, StiffnessLaw::SineArctan),
        Channel::Mz => (&params.Mz, StiffnessLaw::RationalExp),
    };
    let a = [p.a1, p.a2, p.a3, p.a4, p.a5, p.a6, p.a7, p.a8];
    let mut mf = load_factors(p.C, a, law, fz_kn);
    let abs_gamma = gamma_deg.abs();
    mf.sh = p.a9 * gamma_deg;
    mf.sv = (p.a10 * fz_kn * fz_kn + p.a11 * fz_kn) * gamma_deg;
    mf.b *= 1.0 - p.a12 * abs_gamma;
    mf.e /= 1.0 - p.a13 * abs_gamma;
    mf
}
