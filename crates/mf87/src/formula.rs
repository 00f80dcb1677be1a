//! The 1987 Magic Formula: one function for all three channels, and the load and camber
//! dependence of its factors from a channel's coefficients. Everything here works in the
//! paper's units (kN, deg, percent); [`crate::channel_factors`] takes the coefficients from a
//! parameter set, [`crate::evaluate`] is the SI entry point.

pub use crate::channel::Channel;
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
    /// Horizontal shift \[deg\].
    pub sh: T,
    /// Vertical shift [N or N.m].
    pub sv: T,
}

impl<T: Real> MagicFormula<T> {
    /// `D sin(C atan(B phi)) + Sv` with `phi = (1 - E)(x + Sh) + (E / B) atan(B (x + Sh))`.
    #[inline]
    pub fn eval(&self, x: T) -> T {
        self.curve(x + self.sh) + self.sv
    }

    /// `D sin(C atan(B phi))`, `phi = (1 - E) x + (E / B) atan(B x)`: the curve without its
    /// shifts.
    #[inline]
    fn curve(&self, x: T) -> T {
        let phi = (-self.e + 1.0) * x + self.e / self.b * (self.b * x).atan();
        self.d * (self.c * (self.b * phi).atan()).sin()
    }

    /// The curve at the equivalent slip `x_eq = sqrt((x + Sh)^2 + o^2)` (MF 6.1's
    /// `alpha_eq` of the aligning moment, `o` the other slip in this slip's units), signed and
    /// scaled back by `(x + Sh) / x_eq`: `(x + Sh) / x_eq (y(x_eq) - Sv) + Sv`. Smooth where
    /// `o` is not 0; at `o = 0` it is [`MagicFormula::eval`] (whose curve is odd about
    /// `-Sh`), as are its derivatives (`x_eq` is even in `o`).
    #[inline]
    pub fn eval_equivalent(&self, x: T, o: T) -> T {
        if o.re() == 0.0 {
            return self.eval(x);
        }
        let x = x + self.sh;
        let x_eq = (x * x + o * o).sqrt();
        x / x_eq * self.curve(x_eq) + self.sv
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

/// B, C, D, E at load `fz_kn` from `C, a1..a8` (`c[0..9]`).
#[inline]
fn load_factors<P: Copy, T: Real + From<P>>(
    c: &[P],
    law: StiffnessLaw,
    fz_kn: T,
) -> MagicFormula<T> {
    let k = |i: usize| T::from(c[i]);
    let d = fz_kn * k(1) * fz_kn + fz_kn * k(2);
    let bcd = match law {
        StiffnessLaw::SineArctan => ((fz_kn * k(5)).atan() * k(4)).sin() * k(3),
        StiffnessLaw::RationalExp => (fz_kn * k(3) * fz_kn + fz_kn * k(4)) / (fz_kn * k(5)).exp(),
    };
    MagicFormula {
        b: bcd / (d * k(0)),
        c: k(0),
        d,
        e: fz_kn * k(6) * fz_kn + fz_kn * k(7) + k(8),
        sh: constant(0.0),
        sv: constant(0.0),
    }
}

/// The factors of `channel` at load `fz_kn` \[kN\] and camber `gamma_deg` \[deg\] from the
/// channel's coefficients `c` in [`crate::Params::coefficient_names`] order, over any number type `P` the model's type `T` is
/// made from: `f64`, or `T` itself for derivatives with respect to the coefficients
/// ([`crate::channel_factors`] takes them from a parameter set).
///
/// Camber (errata 3): `Sh = a9 gamma`, `Sv = (a10 Fz^2 + a11 Fz) gamma`,
/// `B -> B (1 - a12 |gamma|)`, `E -> E / (1 - a13 |gamma|)`. Fx has no camber terms.
#[inline]
pub fn factors<P: Copy, T: Real + From<P>>(
    channel: Channel,
    c: &[P],
    fz_kn: T,
    gamma_deg: T,
) -> MagicFormula<T> {
    let law = match channel {
        Channel::Fx => return load_factors(c, StiffnessLaw::RationalExp, fz_kn),
        Channel::Fy => StiffnessLaw::SineArctan,
        Channel::Mz => StiffnessLaw::RationalExp,
    };
    let k = |i: usize| T::from(c[i]);
    let mut mf = load_factors(c, law, fz_kn);
    let abs_gamma = abs(gamma_deg);
    mf.sh = gamma_deg * k(9);
    mf.sv = (fz_kn * k(10) * fz_kn + fz_kn * k(11)) * gamma_deg;
    mf.b *= -(abs_gamma * k(12)) + 1.0;
    mf.e /= -(abs_gamma * k(13)) + 1.0;
    mf
}
