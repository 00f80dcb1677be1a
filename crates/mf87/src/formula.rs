//! The 1987 Magic Formula: one function for all three channels, and the load and camber
//! dependence of its factors. Everything here works in the paper's units (kN, deg, percent);
//! [`crate::evaluate`] is the SI entry point.

pub use crate::channel::Channel;
use crate::params::Params;
use crate::real::{Real, abs, constant};

/// The factors of one Magic Formula curve at a given load and camber, over `f64` or a dual
/// number (see [`crate::real`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MagicFormula<T = f64> {
    /// Stiffness factor [1/deg or 1/percent].
    pub b: T,
    /// Shape factor.
    pub c: T,
    /// Peak factor [N or N.m].
    pub d: T,
    /// Curvature factor.
    pub e: T,
    /// Horizontal shift [deg].
    pub sh: T,
    /// Vertical shift [N or N.m].
    pub sv: T,
}

impl<T: Real> MagicFormula<T> {
    /// `D sin(C atan(B phi)) + Sv` with `phi = (1 - E)(x + Sh) + (E / B) atan(B (x + Sh))`.
    #[inline]
    pub fn eval(&self, x: T) -> T {
        let x = x + self.sh;
        let phi = (-self.e + 1.0) * x + self.e / self.b * (self.b * x).atan();
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
#[inline]
fn load_factors<T: Real>(c: f64, a: [f64; 8], law: StiffnessLaw, fz_kn: T) -> MagicFormula<T> {
    let [a1, a2, a3, a4, a5, a6, a7, a8] = a;
    let d = fz_kn * a1 * fz_kn + fz_kn * a2;
    let bcd = match law {
        StiffnessLaw::SineArctan => ((fz_kn * a5).atan() * a4).sin() * a3,
        StiffnessLaw::RationalExp => (fz_kn * a3 * fz_kn + fz_kn * a4) / (fz_kn * a5).exp(),
    };
    MagicFormula {
        b: bcd / (d * c),
        c: constant(c),
        d,
        e: fz_kn * a6 * fz_kn + fz_kn * a7 + a8,
        sh: constant(0.0),
        sv: constant(0.0),
    }
}

/// The factors of `channel` at load `fz_kn` [kN] and camber `gamma_deg` [deg].
///
/// Camber (errata 3): `Sh = a9 gamma`, `Sv = (a10 Fz^2 + a11 Fz) gamma`,
/// `B -> B (1 - a12 |gamma|)`, `E -> E / (1 - a13 |gamma|)`. Fx has no camber terms.
#[inline]
pub fn channel_factors<T: Real>(
    params: &Params,
    channel: Channel,
    fz_kn: T,
    gamma_deg: T,
) -> MagicFormula<T> {
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
    let abs_gamma = abs(gamma_deg);
    mf.sh = gamma_deg * p.a9;
    mf.sv = (fz_kn * p.a10 * fz_kn + fz_kn * p.a11) * gamma_deg;
    mf.b *= -(abs_gamma * p.a12) + 1.0;
    mf.e /= -(abs_gamma * p.a13) + 1.0;
    mf
}
