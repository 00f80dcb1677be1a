//! How a channel's effects compose ([`ChannelExtensions::apply_to_factors`],
//! [`ChannelExtensions::apply_to_output`], [`ChannelExtensions::evaluate_factors`]), in the
//! stages of [`Effect`], whatever the effects are.
//!
//! Units as in [`crate::formula`] (load kN, slip angle deg, slip percent) and the extensions'
//! units for the conditions (speed m/s, pressure kPa, temperature degC, see
//! [`crate::conditions`]). The factors come from a parameter set and the lag of the slip is applied before, in
//! [`crate::evaluate_extended`].

use crate::conditions::{Conditions, Nominal};
use crate::extensions::effect::{Effect, Visit};
use crate::extensions::{ChannelExtensions, Extension};
use crate::formula::MagicFormula;
use crate::real::Real;

// The visits below are out of line on purpose. Inlined, the compiler computes a small
// effect's terms before the test of whether the effect is present, on the unset bytes of an
// absent one; those often read as subnormal numbers, whose arithmetic takes microcode assists
// of hundreds of cycles (a fit's row cost several times more with one effect present than
// with all). Measured in `cargo bench -p tire-gap --bench rows` and `mf87/evaluate_extended`.

/// The factor stage: every scale of D and BCD (`shifts` false), or every shift of Sh and Sv.
struct Factors<'a, T> {
    nominal: &'a Nominal,
    x: &'a Conditions<T>,
    mf: &'a mut MagicFormula<T>,
    shifts: bool,
}

impl<P: Copy, T: Real + From<P>> Visit<P> for Factors<'_, T> {
    #[inline(never)]
    fn visit<E: Effect>(&mut self, _: Extension, q: &E::Of<P>) {
        if self.shifts {
            E::shift(q, self.x, self.mf);
        } else if let Some(s) = E::scales(q, self.nominal, self.x) {
            s.apply(self.mf);
        }
    }
}

/// The curve's stage: the other slip the curve is taken at, summed over the effects.
struct EquivalentSlip<'a, T> {
    x: &'a Conditions<T>,
    other: Option<T>,
}

impl<P: Copy, T: Real + From<P>> Visit<P> for EquivalentSlip<'_, T> {
    #[inline(never)]
    fn visit<E: Effect>(&mut self, _: Extension, q: &E::Of<P>) {
        if let Some(o) = E::equivalent_slip(q, self.x) {
            self.other = Some(self.other.map_or(o, |sum| sum + o));
        }
    }
}

/// A step of the output stage.
#[derive(Clone, Copy, PartialEq)]
enum OutputStep {
    Weight,
    Add,
    Subtract,
}

/// The output stage: every weight, every added term, or every subtracted term.
struct Output<'a, T> {
    nominal: &'a Nominal,
    x: &'a Conditions<T>,
    mf: &'a MagicFormula<T>,
    y: T,
    step: OutputStep,
}

impl<P: Copy, T: Real + From<P>> Visit<P> for Output<'_, T> {
    #[inline(never)]
    fn visit<E: Effect>(&mut self, _: Extension, q: &E::Of<P>) {
        match self.step {
            OutputStep::Weight => {
                if let Some(w) = E::weight(q, self.x) {
                    self.y *= w;
                }
            }
            OutputStep::Add => {
                if let Some(term) = E::add(q, self.x, self.mf) {
                    self.y += term;
                }
            }
            OutputStep::Subtract => {
                if let Some(term) = E::subtract(q, self.nominal, self.x) {
                    self.y -= term;
                }
            }
        }
    }
}

impl<P: Copy> ChannelExtensions<P> {
    /// Applies the factor-level effects to `mf`: every scale of the peak D and the stiffness
    /// BCD, then every shift of Sh and Sv (each in [`Extension::ALL`] order).
    #[inline]
    pub fn apply_to_factors<T: Real + From<P>>(
        &self,
        nominal: &Nominal,
        x: &Conditions<T>,
        mf: &mut MagicFormula<T>,
    ) {
        for shifts in [false, true] {
            self.visit(&mut Factors {
                nominal,
                x,
                mf: &mut *mf,
                shifts,
            });
        }
    }

    /// Applies the output-level effects to `y`, the output of the curve with factors `mf`:
    /// the weights, then the added terms, then the subtracted ones.
    #[inline]
    pub fn apply_to_output<T: Real + From<P>>(
        &self,
        nominal: &Nominal,
        x: &Conditions<T>,
        mf: &MagicFormula<T>,
        y: T,
    ) -> T {
        let mut out = Output {
            nominal,
            x,
            mf,
            y,
            step: OutputStep::Weight,
        };
        for step in [OutputStep::Weight, OutputStep::Add, OutputStep::Subtract] {
            out.step = step;
            self.visit(&mut out);
        }
        out.y
    }

    /// The channel's output at `slip` (formula units; already lagged if it should be) with
    /// these extensions, under `x`, from the channel's factors `mf` at load and camber: the
    /// factors, the curve (at an equivalent slip if an effect gives one), the output stage.
    #[inline]
    pub fn evaluate_factors<T: Real + From<P>>(
        &self,
        mut mf: MagicFormula<T>,
        nominal: &Nominal,
        slip: T,
        x: &Conditions<T>,
    ) -> T {
        self.apply_to_factors(nominal, x, &mut mf);
        let mut equivalent = EquivalentSlip { x, other: None };
        self.visit(&mut equivalent);
        let y = match equivalent.other {
            Some(o) => mf.eval_equivalent(slip, o),
            None => mf.eval(slip),
        };
        self.apply_to_output(nominal, x, &mf, y)
    }
}
