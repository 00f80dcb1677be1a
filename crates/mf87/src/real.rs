//! The number type the model is written over: `f64` for values, a dual number
//! ([`num_dual::Dual64`]) for exact first derivatives, so the formula is written once.
//!
//! A dual number's `==` compares its value only: whether a term is absent (value and every
//! derivative part zero, so that leaving it out changes neither) is [`Real::is_exact_zero`].
//!
//! Where the model is not differentiable, the derivative is defined here:
//! - [`clamp`]: 1 inside the range and on its bounds, 0 beyond them (a clamped input does
//!   not move the output);
//! - [`abs`]: `sign(x)`, and 0 at `x = 0` (the mean of the two one-sided slopes, what a
//!   central difference sees).

use num_dual::DualNum;
#[cfg(feature = "vector-duals")]
use num_dual::DualSVec64;

pub use num_dual::Dual64;

/// A real number, or a dual number carrying one directional derivative ([`Dual64`]) or,
/// with the feature `vector-duals`, several (`DualSVec64`, the parameter Jacobians of a fit).
pub trait Real: DualNum<Primitive = f64> + Copy {
    /// Whether the value and every derivative part are zero: a term that is an exact zero
    /// may be left out without changing the value or a derivative. (At a parameter's value
    /// of 0 with its derivative seeded, `x == 0.0` is true, but the term is not absent.)
    fn is_exact_zero(self) -> bool;
}

impl Real for f64 {
    #[inline]
    fn is_exact_zero(self) -> bool {
        self == 0.0
    }
}

impl Real for Dual64 {
    #[inline]
    fn is_exact_zero(self) -> bool {
        self.re == 0.0 && self.eps == 0.0
    }
}

#[cfg(feature = "vector-duals")]
impl<const N: usize> Real for DualSVec64<N> {
    #[inline]
    fn is_exact_zero(self) -> bool {
        self.re == 0.0 && self.eps.0.is_none_or(|d| d.iter().all(|v| *v == 0.0))
    }
}

/// The value part.
#[inline]
pub fn value<T: Real>(x: T) -> f64 {
    x.re()
}

/// A constant (no derivative).
#[inline]
pub fn constant<T: Real>(x: f64) -> T {
    T::from(x)
}

/// `x` clamped to `[lo, hi]`; for `f64` the same as [`f64::clamp`].
#[inline]
pub fn clamp<T: Real>(x: T, lo: f64, hi: f64) -> T {
    let v = x.re();
    if v < lo {
        T::from(lo)
    } else if v > hi {
        T::from(hi)
    } else {
        x
    }
}

/// `|x|`, with derivative 0 at `x = 0`; for `f64` the same as [`f64::abs`].
#[inline]
pub fn abs<T: Real>(x: T) -> T {
    let v = x.re();
    if v > 0.0 {
        x
    } else if v < 0.0 {
        -x
    } else {
        T::from(v.abs())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seeded(x: f64) -> Dual64 {
        Dual64::from_re(x).derivative()
    }

    #[test]
    fn clamp_and_abs_match_f64_and_define_the_kinks() {
        for x in [-3.0, -1.0, -0.0, 0.0, 0.5, 2.0, 7.0, f64::NAN] {
            let c: f64 = clamp(x, -1.0, 2.0);
            assert!(c.to_bits() == x.clamp(-1.0, 2.0).to_bits() || (c.is_nan() && x.is_nan()));
            let a: f64 = abs(x);
            assert!(a.to_bits() == x.abs().to_bits() || (a.is_nan() && x.is_nan()));
        }
        assert_eq!(clamp(seeded(0.5), -1.0, 2.0).eps, 1.0);
        assert_eq!(clamp(seeded(2.0), -1.0, 2.0).eps, 1.0);
        assert_eq!(clamp(seeded(2.5), -1.0, 2.0).eps, 0.0);
        assert_eq!(clamp(seeded(-4.0), -1.0, 2.0).re, -1.0);
        assert_eq!(abs(seeded(-2.0)).eps, -1.0);
        assert_eq!(abs(seeded(3.0)).eps, 1.0);
        assert_eq!(abs(seeded(0.0)).eps, 0.0);
    }

    #[test]
    fn an_exact_zero_has_no_derivative_either() {
        assert!(0.0f64.is_exact_zero() && !1e-300f64.is_exact_zero());
        assert!(Dual64::from(0.0).is_exact_zero());
        // A parameter at 0 with its derivative seeded is not absent.
        assert!(!seeded(0.0).is_exact_zero());
        assert!(!Dual64::from(2.0).is_exact_zero());
        #[cfg(feature = "vector-duals")]
        {
            let v = DualSVec64::<3>::from(0.0);
            assert!(v.is_exact_zero());
            assert!(!v.derivative(1).is_exact_zero());
        }
    }
}
