//! A parameter set's model: each channel's factors ([`channel_factors`], in the paper's
//! units), the SI entry points [`evaluate`] (the 1987 model) and [`evaluate_extended`] (with
//! the parameter set's extensions), and the lag state the latter reads
//! ([`LaggedSlip::steady`], [`LaggedSlip::advanced`], [`LaggedSlip::rates`]). The entry points
//! clamp the inputs to their valid ranges, convert them to the paper's units and run the
//! three channels.

use crate::channel::Channel;
use crate::conditions::{ConditionLimits, Nominal, OperatingConditions};
use crate::extensions::{ChannelExtensions, LaggedSlip, relaxation_step};
use crate::formula::{MagicFormula, factors};
use crate::interface::{Inputs, Outputs, SignConvention, oriented};
use crate::params::Params;
use crate::real::{self, Real, constant, value};
use crate::units;

/// The factors of `channel` at load `fz_kn` \[kN\] and camber `gamma_deg` \[deg\].
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
    match channel {
        Channel::Fx => factors(channel, &params.Fx.values(), fz_kn, gamma_deg),
        Channel::Fy => factors(channel, &params.Fy.values(), fz_kn, gamma_deg),
        Channel::Mz => factors(channel, &params.Mz.values(), fz_kn, gamma_deg),
    }
}

/// Loads at or below this [kN] count as a lifted wheel: no force. (At 1e-13 N the forces
/// would be below 1e-9 N; the guard keeps B = BCD / (C D) away from 0/0.)
pub(crate) const LIFTED_WHEEL_LOAD_KN: f64 = 1e-16;

/// No force: a lifted wheel.
#[inline]
fn lifted<T: Real>() -> Outputs<T> {
    Outputs {
        fx: constant(0.0),
        fy: constant(0.0),
        mz: constant(0.0),
    }
}

/// Fx, Fy, Mz for SI inputs (clamped to their valid ranges first).
///
/// Inputs must be finite; a lifted wheel (Fz <= 0) gives zero forces. Over a dual number
/// (see [`crate::real`]) this gives the outputs' exact directional derivative too.
#[inline]
pub fn evaluate<T: Real>(
    params: &Params,
    inputs: &Inputs<T>,
    convention: SignConvention,
) -> Outputs<T> {
    let x = inputs.clamped(&params.limits);
    let fz_kn = units::newtons_to_kilonewtons(x.fz);
    if value(fz_kn) <= LIFTED_WHEEL_LOAD_KN {
        return lifted();
    }
    let alpha_deg = units::radians_to_degrees(x.alpha);
    let gamma_deg = units::radians_to_degrees(x.gamma);
    let sigma_pct = units::slip_ratio_to_percent(x.kappa);
    let fy = channel_factors(params, Channel::Fy, fz_kn, gamma_deg).eval(alpha_deg);
    let mz = channel_factors(params, Channel::Mz, fz_kn, gamma_deg).eval(alpha_deg);
    let fx = channel_factors(params, Channel::Fx, fz_kn, constant(0.0)).eval(sigma_pct);
    oriented(Outputs { fx, fy, mz }, convention)
}

/// The channel's output at its `slip` (SI; already lagged if it should be) with its
/// extensions `ext`, under the operating `conditions` and the other slip `other` (SI).
#[inline]
fn channel_output<T: Real>(
    ext: &ChannelExtensions,
    params: &Params,
    channel: Channel,
    (conditions, limits, nominal): (&OperatingConditions<T>, &ConditionLimits, &Nominal),
    (fz_kn, gamma): (T, T),
    (slip, other): (T, T),
) -> T {
    let x = conditions.in_extension_units(limits, fz_kn, gamma, (slip, other));
    let (slip_formula, gamma_deg) = match channel {
        Channel::Fx => (units::slip_ratio_to_percent(slip), constant(0.0)),
        Channel::Fy | Channel::Mz => (
            units::radians_to_degrees(slip),
            units::radians_to_degrees(gamma),
        ),
    };
    let mf = channel_factors(params, channel, fz_kn, gamma_deg);
    ext.evaluate_factors(mf, nominal, slip_formula, &x)
}

/// Fx, Fy, Mz with the parameter set's extensions, for SI inputs (clamped to their valid
/// ranges), SI operating conditions (clamped to the extensions' range) and the lagged slips.
/// Without extensions this is [`crate::evaluate`]. Over a dual number (see [`crate::real`])
/// this gives the outputs' exact directional derivative too.
pub fn evaluate_extended<T: Real>(
    params: &Params,
    inputs: &Inputs<T>,
    conditions: &OperatingConditions<T>,
    lagged: &LaggedSlip<T>,
    convention: SignConvention,
) -> Outputs<T> {
    let Some(ext) = &params.extensions else {
        return evaluate(params, inputs, convention);
    };
    let x = inputs.clamped(&params.limits);
    let fz_kn = units::newtons_to_kilonewtons(x.fz);
    if value(fz_kn) <= LIFTED_WHEEL_LOAD_KN {
        return lifted();
    }
    let lagged = lagged.clamped(&params.limits);
    // Each channel's own slip: lagged if it has a relaxation length.
    let own = |channel: Channel, input: T, lagged: T| {
        if ext.channel(channel).has_lag() {
            lagged
        } else {
            input
        }
    };
    // Combined slip weights Fy and Mz by the slip ratio, Fx by the slip angle.
    let at = (conditions, &ext.limits, &ext.nominal);
    let load = (fz_kn, x.gamma);
    let fy = channel_output(
        &ext.Fy,
        params,
        Channel::Fy,
        at,
        load,
        (own(Channel::Fy, x.alpha, lagged.fy), x.kappa),
    );
    let mz = channel_output(
        &ext.Mz,
        params,
        Channel::Mz,
        at,
        load,
        (own(Channel::Mz, x.alpha, lagged.mz), x.kappa),
    );
    let fx = channel_output(
        &ext.Fx,
        params,
        Channel::Fx,
        at,
        load,
        (own(Channel::Fx, x.kappa, lagged.fx), x.alpha),
    );
    oriented(Outputs { fx, fy, mz }, convention)
}

/// The relaxation length [m] of `channel`, 0 without one.
fn relaxation_length_m(params: &Params, channel: Channel) -> f64 {
    params
        .extensions
        .as_ref()
        .and_then(|e| e.channel(channel).relaxation_length_m())
        .unwrap_or(0.0)
}

impl LaggedSlip {
    /// The steady state: every lagged slip equal to its (clamped) input.
    pub fn steady(params: &Params, inputs: &Inputs) -> LaggedSlip {
        let x = inputs.clamped(&params.limits);
        LaggedSlip {
            fx: x.kappa,
            fy: x.alpha,
            mz: x.alpha,
        }
    }

    /// The lag after travelling `distance_m` with `inputs` held (exact for constant inputs).
    /// The lag follows the clamped inputs; a channel without a relaxation length follows its
    /// input at once.
    pub fn advanced(&self, params: &Params, inputs: &Inputs, distance_m: f64) -> LaggedSlip {
        let x = inputs.clamped(&params.limits);
        let sigma = |channel| relaxation_length_m(params, channel);
        LaggedSlip {
            fx: relaxation_step(self.fx, x.kappa, distance_m, sigma(Channel::Fx)),
            fy: relaxation_step(self.fy, x.alpha, distance_m, sigma(Channel::Fy)),
            mz: relaxation_step(self.mz, x.alpha, distance_m, sigma(Channel::Mz)),
        }
    }
}

impl<T: Real> LaggedSlip<T> {
    /// The time derivative of each lagged slip, `|vx| (s - s_lag) / sigma` [1/s or rad/s],
    /// towards the clamped input `s`. A channel without a relaxation length has rate 0: its
    /// lag is not used (the output takes the input slip), so it stays where it is.
    pub fn rates(&self, params: &Params, inputs: &Inputs<T>, vx: T) -> LaggedSlip<T> {
        let x = inputs.clamped(&params.limits);
        let speed = real::abs(vx);
        let rate = |lagged: T, slip: T, channel| {
            let sigma = relaxation_length_m(params, channel);
            if sigma > 0.0 {
                speed * (slip - lagged) / sigma
            } else {
                T::from(0.0)
            }
        };
        LaggedSlip {
            fx: rate(self.fx, x.kappa, Channel::Fx),
            fy: rate(self.fy, x.alpha, Channel::Fy),
            mz: rate(self.mz, x.alpha, Channel::Mz),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper(fz: f64, alpha_deg: f64, kappa: f64, gamma_deg: f64) -> Outputs {
        let inputs = Inputs {
            fz,
            alpha: alpha_deg.to_radians(),
            kappa,
            gamma: gamma_deg.to_radians(),
        };
        evaluate(&Params::paper_table(), &inputs, SignConvention::Paper)
    }

    fn rel_close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-12)
    }

    #[test]
    fn errata_worked_examples_at_4kn() {
        // docs/errata.md: Fy(5 deg, 0) = 3389.600985 N, Mz(5 deg, 2 deg) = -29.02908832 N.m,
        // Fx(10 %) = 4234.444513 N.
        assert!(rel_close(
            paper(4000.0, 5.0, 0.0, 0.0).fy,
            3389.600985,
            1e-9
        ));
        assert!(rel_close(
            paper(4000.0, 5.0, 0.0, 2.0).mz,
            -29.02908832,
            1e-9
        ));
        assert!(rel_close(
            paper(4000.0, 0.0, 0.1, 0.0).fx,
            4234.444513,
            1e-9
        ));
    }

    #[test]
    fn hand_computed_cornering_stiffness() {
        // At alpha -> 0 and zero camber, dFy/dalpha = BCD = a3 sin(a4 atan(a5 Fz)) [N/deg].
        let fz_kn: f64 = 4.0;
        let bcd = 1078.0 * (1.82 * (0.208 * fz_kn).atan()).sin();
        let h = 1e-4;
        let slope = (paper(4000.0, h, 0.0, 0.0).fy - paper(4000.0, -h, 0.0, 0.0).fy) / (2.0 * h);
        assert!(rel_close(slope, bcd, 1e-6), "{slope} vs {bcd}");
        // Longitudinal slip stiffness BCD = (a3 Fz^2 + a4 Fz) e^(-a5 Fz) [N/percent].
        let bcd_x = (49.6 * fz_kn * fz_kn + 226.0 * fz_kn) * (-0.069 * fz_kn).exp();
        let slope_x = (paper(4000.0, 0.0, 1e-6, 0.0).fx - paper(4000.0, 0.0, -1e-6, 0.0).fx) / 2e-4;
        assert!(rel_close(slope_x, bcd_x, 1e-6), "{slope_x} vs {bcd_x}");
    }

    #[test]
    fn odd_symmetry_at_zero_camber() {
        for fz in [500.0, 2000.0, 4000.0, 8000.0] {
            for a in [0.3, 1.0, 4.0, 12.0, 40.0] {
                let (p, n) = (paper(fz, a, a / 100.0, 0.0), paper(fz, -a, -a / 100.0, 0.0));
                assert!(rel_close(p.fy, -n.fy, 1e-12) && rel_close(p.mz, -n.mz, 1e-12));
                assert!(rel_close(p.fx, -n.fx, 1e-12));
                assert!(
                    p.fy > 0.0 && p.fx > 0.0,
                    "paper convention: alpha>0 -> Fy>0"
                );
            }
        }
    }

    #[test]
    fn camber_mirror_symmetry() {
        // Mirroring the tire left-right flips alpha, gamma, Fy and Mz together.
        for (a, g) in [(2.0, 3.0), (-5.0, 1.0), (8.0, -4.0)] {
            let (p, m) = (paper(4000.0, a, 0.0, g), paper(4000.0, -a, 0.0, -g));
            assert!(rel_close(p.fy, -m.fy, 1e-12) && rel_close(p.mz, -m.mz, 1e-12));
        }
        // Camber thrust at zero slip is Sv + shift: positive for gamma > 0 in the paper's axes.
        assert!(paper(4000.0, 0.0, 0.0, 2.0).fy > 0.0);
    }

    #[test]
    fn continuity_in_every_input() {
        // Tiny steps in any one input (N, deg, 1, deg), including across 0 where |gamma|
        // has a kink, move no output by more than 0.01 N or N.m.
        let steps = [1e-3, 1e-6, 1e-8, 1e-6];
        let points = [
            [3000.0, 3.0, 0.05, 1.0],
            [800.0, 0.0, 0.0, 0.0],
            [6500.0, -12.0, -0.3, -4.0],
            [4000.0, 60.0, 0.9, 9.0],
        ];
        for p in points {
            for (k, h) in steps.iter().enumerate() {
                let mut q = p;
                q[k] += h;
                let (a, b) = (paper(p[0], p[1], p[2], p[3]), paper(q[0], q[1], q[2], q[3]));
                for (u, v) in [(a.fx, b.fx), (a.fy, b.fy), (a.mz, b.mz)] {
                    assert!(
                        (u - v).abs() < 1e-2,
                        "jump {u} -> {v} in input {k} at {p:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn lifted_wheel_and_vanishing_load() {
        for fz in [0.0, -1.0, -5000.0] {
            assert_eq!(paper(fz, 5.0, 0.1, 2.0), Outputs::default());
        }
        // Forces scale with load near zero: |F| <= k Fz for small Fz, so F -> 0 continuously.
        let mut prev = f64::INFINITY;
        for fz in [1.0, 1e-3, 1e-6, 1e-9, 1e-12] {
            let o = paper(fz, 5.0, 0.1, 2.0);
            let worst = o.fx.abs().max(o.fy.abs()).max(o.mz.abs());
            assert!(o.fx.is_finite() && o.fy.is_finite() && o.mz.is_finite());
            assert!(worst <= 20.0 * fz, "{worst} at {fz} N");
            assert!(worst < prev);
            prev = worst;
        }
    }

    #[test]
    fn inputs_outside_validity_are_clamped() {
        let p = Params::paper_table();
        assert_eq!(paper(4000.0, 95.0, 0.0, 0.0), paper(4000.0, 90.0, 0.0, 0.0));
        assert_eq!(paper(4000.0, 0.0, 1.7, 0.0), paper(4000.0, 0.0, 1.0, 0.0));
        let g = p.limits.gamma_max_deg;
        assert_eq!(paper(4000.0, 3.0, 0.0, g + 5.0), paper(4000.0, 3.0, 0.0, g));
        assert_eq!(
            paper(25_000.0, 3.0, 0.2, 0.0),
            paper(p.limits.fz_max_N, 3.0, 0.2, 0.0)
        );
    }

    #[test]
    fn iso_convention_flips_lateral_outputs_only() {
        let p = Params::paper_table();
        let x = Inputs {
            fz: 4000.0,
            alpha: 0.05,
            kappa: 0.08,
            gamma: 0.03,
        };
        let paper = evaluate(&p, &x, SignConvention::Paper);
        let iso = evaluate(&p, &x, SignConvention::Iso);
        assert_eq!((iso.fx, iso.fy, iso.mz), (paper.fx, -paper.fy, -paper.mz));
        // ISO physics: alpha > 0 gives Fy < 0 and Mz > 0; camber thrust toward the lean.
        assert!(iso.fy < 0.0 && iso.mz > 0.0);
        let camber_only = Inputs { alpha: 0.0, ..x };
        assert!(evaluate(&p, &camber_only, SignConvention::Iso).fy < 0.0);
    }
}
