//! How a channel's effects compose ([`ChannelExtensions::apply_to_factors`],
//! [`ChannelExtensions::apply_to_output`]), in the stages of [`Effect`], whatever the
//! effects are.
//!
//! Units as in [`crate::formula`] (load kN, slip angle deg, slip percent) and the extensions'
//! units for the conditions (speed m/s, pressure kPa, temperature degC, see
//! [`crate::conditions`]). The lag of the slip is applied before, in [`crate::evaluate_extended`].

use crate::channel::Channel;
use crate::conditions::{Conditions, Nominal};
use crate::extensions::effect::{Effect, Visit};
use crate::extensions::{ChannelExtensions, Extension};
use crate::formula::{MagicFormula, channel_factors};
use crate::params::Params;
use crate::real::Real;

/// The factor stage: every scale of D and BCD (`shifts` false), or every shift of Sh and Sv.
struct Factors<'a, T> {
    nominal: &'a Nominal,
    x: &'a Conditions<T>,
    mf: &'a mut MagicFormula<T>,
    shifts: bool,
}

impl<P: Copy, T: Real + From<P>> Visit<P> for Factors<'_, T> {
    #[inline]
    fn visit<E: Effect>(&mut self, _: Extension, q: &E::Of<P>) {
        if self.shifts {
            E::shift(q, self.x, self.mf);
        } else if let Some(condition) = E::CONDITION
            && let Some(s) = E::scales(q, self.nominal, self.x.get(condition))
        {
            s.apply(self.mf);
        }
    }
}

/// The output stage: every weight (`subtract` false), or every subtracted term.
struct Output<'a, T> {
    nominal: &'a Nominal,
    x: &'a Conditions<T>,
    y: T,
    subtract: bool,
}

impl<P: Copy, T: Real + From<P>> Visit<P> for Output<'_, T> {
    #[inline]
    fn visit<E: Effect>(&mut self, _: Extension, q: &E::Of<P>) {
        if self.subtract {
            if let Some(term) = E::subtract(q, self.nominal, self.x) {
                self.y -= term;
            }
        } else if let Some(w) = E::weight(q, self.x) {
            self.y *= w;
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

    /// Applies the output-level effects (weighting, then subtracted terms) to `y`.
    #[inline]
    pub fn apply_to_output<T: Real + From<P>>(
        &self,
        nominal: &Nominal,
        x: &Conditions<T>,
        y: T,
    ) -> T {
        let mut out = Output {
            nominal,
            x,
            y,
            subtract: false,
        };
        self.visit(&mut out);
        out.subtract = true;
        self.visit(&mut out);
        out.y
    }

    /// The channel's output at `slip` (formula units; already lagged if it should be) with
    /// these extensions, under `x`, from the channel's factors `mf` at load and camber.
    #[inline]
    pub fn evaluate_factors<T: Real + From<P>>(
        &self,
        mut mf: MagicFormula<T>,
        nominal: &Nominal,
        slip: T,
        x: &Conditions<T>,
    ) -> T {
        self.apply_to_factors(nominal, x, &mut mf);
        self.apply_to_output(nominal, x, mf.eval(slip))
    }
}

impl ChannelExtensions {
    /// The channel's output at `slip` (formula units; already lagged if it should be) with
    /// these extensions, under `x`.
    #[inline]
    pub fn evaluate<T: Real>(
        &self,
        params: &Params,
        channel: Channel,
        nominal: &Nominal,
        gamma_deg: T,
        slip: T,
        x: &Conditions<T>,
    ) -> T {
        let mf = channel_factors(params, channel, x.fz_kn, gamma_deg);
        self.evaluate_factors(mf, nominal, slip, x)
    }
}
