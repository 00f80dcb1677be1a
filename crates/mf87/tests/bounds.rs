//! The parameter bounds (`mf87::bounds` and each effect's own) as properties: random
//! parameter sets inside them give finite outputs of a bounded size everywhere, with every
//! extension; a value pushed outside one bound is rejected naming the parameter, its value and
//! the bound; the paper's table and parameter files tire-gap fitted pass; docs/parameters.md
//! lists the bounds as the code has them.

use std::f64::consts::{FRAC_PI_2, PI};

use mf87::bounds::{self, Interval};
use mf87::extensions::{
    CamberPeak, CombinedSlip, ConditionLimits, Extensions, InflationPressure, Nominal,
    PlySteerConicity, RelaxationLength, RollingResistance, SlipRatioShift, SpeedDependence,
    Temperature,
};
use mf87::extensions::{
    combined_slip, ply_steer_conicity, relaxation_length, rolling_resistance, slip_ratio_shift,
};
use mf87::{
    Channel, Inputs, LaggedSlip, OperatingConditions, ParamError, Params, SignConvention, units,
};

/// splitmix64: a small deterministic generator, so that a failure can be replayed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Log-uniform in [lo, hi], both > 0.
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (self.uniform(lo.ln(), hi.ln())).exp()
    }

    fn sign(&mut self) -> f64 {
        if self.unit() < 0.5 { -1.0 } else { 1.0 }
    }

    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// A value of the interval, its ends included now and then.
    fn within(&mut self, i: Interval) -> f64 {
        match self.next() % 8 {
            0 => i.lo,
            1 => i.hi,
            _ => self.uniform(i.lo, i.hi),
        }
    }

    fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[(self.next() % items.len() as u64) as usize]
    }
}

/// Base coefficients aimed at the bounds: peak per load, stiffness factor B and curvature E
/// drawn over most of their allowed ranges (log-uniform where they span decades), camber terms
/// up to their limits. Not every draw is valid (B and E between the points aimed at may leave
/// their range); the caller validates.
fn random_base(rng: &mut Rng) -> Params {
    let mut p = Params::paper_table();
    p.source = None;
    p.limits.fz_max_N = rng.log_uniform(bounds::FZ_MAX_N.lo, bounds::FZ_MAX_N.hi);
    p.limits.gamma_max_deg = rng.within(bounds::GAMMA_MAX_DEG);
    let fz = units::newtons_to_kilonewtons(p.limits.fz_max_N);
    let g = p.limits.gamma_max_deg;
    for channel in Channel::ALL {
        let cap = bounds::peak_per_load_max(channel);
        let sign = if channel == Channel::Mz { -1.0 } else { 1.0 };
        let c = rng.within(bounds::SHAPE_C);
        // Peak per load at Fz -> 0 and at fz_max, same sign.
        let (m0, m1) = (
            sign * rng.log_uniform(1e-3 * cap, cap),
            sign * rng.log_uniform(1e-3 * cap, cap),
        );
        let a2 = 1000.0 * m0;
        let a1 = 1000.0 * (m1 - m0) / fz;
        let d = |f: f64| a1 * f * f + a2 * f;
        // B aimed at values at both ends of the load range.
        let (b0, b1) = (rng.log_uniform(1e-4, 1e2), rng.log_uniform(1e-4, 1e2));
        let (a3, a4, a5) = match channel {
            Channel::Fy => {
                let a5 = rng.log_uniform(1e-3, 1e3) / fz;
                let a4 = rng.uniform(0.05, 0.99) * PI / (a5 * fz).atan();
                // B at fz_max = a3 sin(a4 atan(a5 fz)) / (C D(fz)).
                let a3 = b1 * c * d(fz) / (a4 * (a5 * fz).atan()).sin();
                (a3, a4, a5)
            }
            Channel::Mz | Channel::Fx => {
                let a5 = rng.uniform(-1.0, 1.0) * bounds::EXPONENT_A5_FZ_MAX / fz;
                // B(0+) = a4 / (C a2); B(fz) = (a3 fz + a4) e^(-a5 fz) / (C (a1 fz + a2)).
                let a4 = b0 * c * a2;
                let a3 = (b1 * c * (a1 * fz + a2) * (a5 * fz).exp() - a4) / fz;
                (a3, a4, a5)
            }
        };
        // E aimed at three loads: a8 at 0, and at fz / 2 and fz.
        let e = Interval::new(-200.0, 20.0);
        let (e0, e1, e2) = (rng.within(e), rng.within(e), rng.within(e));
        let a8 = e0;
        // e1 = a6 fz^2 / 4 + a7 fz / 2 + a8, e2 = a6 fz^2 + a7 fz + a8.
        let a6 = 2.0 * (e2 - 2.0 * e1 + a8) / (fz * fz);
        let a7 = (e2 - a8 - a6 * fz * fz) / fz;
        let values = [c, a1, a2, a3, a4, a5, a6, a7, a8];
        for (i, v) in values.iter().enumerate() {
            *p.coefficient_mut(channel, i).unwrap() = *v;
        }
        if channel != Channel::Fx {
            let a9 = rng.uniform(-1.0, 1.0) * 0.5 * bounds::SHIFT_SH_MAX_DEG / g;
            let camber_cap = bounds::camber_shift_per_load_max(channel);
            let (s0, s1) = (
                rng.uniform(-1.0, 1.0) * camber_cap,
                rng.uniform(-1.0, 1.0) * camber_cap,
            );
            let a11 = 1000.0 * s0 / g;
            let a10 = 1000.0 * (s1 - s0) / (g * fz);
            let a12 = rng.uniform(-3.0, 0.99) / g;
            let a13 = rng.uniform(-30.0, 0.99) / g;
            for (i, v) in [a9, a10, a11, a12, a13].iter().enumerate() {
                *p.coefficient_mut(channel, 9 + i).unwrap() = *v;
            }
        }
    }
    p
}

/// A condition range inside `allowed`, sometimes a single point.
fn random_range(rng: &mut Rng, allowed: Interval) -> (f64, f64) {
    let (a, b) = (rng.within(allowed), rng.within(allowed));
    if rng.chance(0.05) {
        (a, a)
    } else {
        (a.min(b), a.max(b))
    }
}

/// Nominal conditions and their range, inside the bounds.
fn random_conditions(rng: &mut Rng) -> Extensions {
    let (s_lo, s_hi) = random_range(rng, bounds::SPEED_MPS);
    let (p_lo, p_hi) = random_range(rng, bounds::PRESSURE_KPA);
    let (t_lo, t_hi) = random_range(rng, bounds::TEMPERATURE_DEGC);
    let nominal = Nominal {
        pressure_kpa: rng.log_uniform(bounds::PRESSURE_KPA.lo, bounds::PRESSURE_KPA.hi),
        speed_mps: rng.log_uniform(bounds::NOMINAL_SPEED_MPS.lo, bounds::NOMINAL_SPEED_MPS.hi),
        temperature_c: rng.within(bounds::TEMPERATURE_DEGC),
    };
    let limits = ConditionLimits {
        speed_min_mps: s_lo,
        speed_max_mps: s_hi,
        pressure_min_kPa: p_lo,
        pressure_max_kPa: p_hi,
        temperature_min_degC: t_lo,
        temperature_max_degC: t_hi,
    };
    Extensions::new(nominal, limits)
}

/// The largest |x - x0| / x0 of a condition range around x0 (at least a little).
fn largest_relative(lo: f64, hi: f64, x0: f64) -> f64 {
    ((lo - x0).abs().max((hi - x0).abs()) / x0).max(1e-3)
}

/// A coefficient that keeps a scale 1 + k x within [0.1, 10] for |x| <= x_max, now and then
/// one that may leave it.
fn scale_coefficient(rng: &mut Rng, x_max: f64) -> f64 {
    let reach = if rng.chance(0.95) {
        0.9
    } else {
        rng.uniform(0.9, 12.0)
    };
    rng.uniform(-1.0, 1.0) * reach / x_max
}

/// Every extension on every channel it applies to, each with probability `p`, with
/// parameters aimed at the bounds.
fn add_random_extensions(rng: &mut Rng, params: &Params, ext: &mut Extensions, p: f64) {
    let n = ext.nominal;
    let l = ext.limits;
    let fz_max = params.limits.fz_max_N;
    for channel in Channel::ALL {
        let mut e = *ext.channel(channel);
        if rng.chance(p) {
            let s_max = if channel == Channel::Fx {
                FRAC_PI_2
            } else {
                1.0
            };
            let b = rng.sign() * rng.log_uniform(1e-3, combined_slip::COMBINED_SLIP_B_ABS_MAX);
            let c = rng.sign() * rng.unit() * combined_slip::COMBINED_SLIP_PHASE_MAX
                / (b.abs() * s_max).atan();
            let mut cs = CombinedSlip {
                B: b,
                C: c,
                ..Default::default()
            };
            if rng.chance(0.5) {
                add_mf61_combined_terms(rng, &mut cs, channel, params);
            }
            e.combined_slip = Some(cs);
        }
        if rng.chance(p) {
            // 0 (no lag) or at least the shortest length.
            let sigma = rng.within(relaxation_length::RELAXATION_LENGTH_M);
            e.relaxation_length = Some(RelaxationLength {
                sigma_m: if sigma == 0.0 {
                    0.0
                } else {
                    sigma.max(relaxation_length::RELAXATION_LENGTH_MIN_M)
                },
            });
        }
        if rng.chance(p) {
            let dp = largest_relative(l.pressure_min_kPa, l.pressure_max_kPa, n.pressure_kpa);
            let fz_max_kn = units::newtons_to_kilonewtons(fz_max);
            e.inflation_pressure = Some(InflationPressure {
                k: scale_coefficient(rng, dp),
                d: scale_coefficient(rng, dp),
                k2: scale_coefficient(rng, dp * dp) * 0.05 * rng.unit(),
                d2: scale_coefficient(rng, dp * dp) * 0.05 * rng.unit(),
                k_per_kN: scale_coefficient(rng, dp) * 0.05 * rng.unit() / fz_max_kn,
            });
        }
        if channel != Channel::Mz && rng.chance(p) {
            let g = params.limits.gamma_max_deg.to_radians();
            e.camber_peak = Some(CamberPeak {
                d: rng.unit() * 0.85 / (g * g),
            });
        }
        if rng.chance(p) {
            let dv = largest_relative(l.speed_min_mps, l.speed_max_mps, n.speed_mps);
            e.speed_dependence = Some(SpeedDependence {
                v: scale_coefficient(rng, dv),
                w: scale_coefficient(rng, dv * dv) * 0.05 * rng.unit(),
            });
        }
        if rng.chance(p) {
            let optimum = rng.within(bounds::TEMPERATURE_DEGC);
            let topt = optimum - n.temperature_c;
            let span = |x: f64| (x - n.temperature_c) / 50.0;
            let dt = span(l.temperature_min_degC)
                .abs()
                .max(span(l.temperature_max_degC).abs())
                .max(1e-3);
            let window = ((l.temperature_min_degC - optimum).abs())
                .max((l.temperature_max_degC - optimum).abs())
                / 50.0;
            e.temperature = Some(Temperature {
                w: scale_coefficient(rng, window.powi(2).max(1e-3)),
                Topt_degC: topt,
                k: scale_coefficient(rng, dt),
            });
        }
        if channel != Channel::Fx && rng.chance(p) {
            let a9 = params.coefficient(channel, 9).unwrap();
            let room = bounds::SHIFT_SH_MAX_DEG - (a9 * params.limits.gamma_max_deg).abs();
            let sv_max = ply_steer_conicity::ply_steer_sv_share(channel) * fz_max;
            let fz_max_kn = units::newtons_to_kilonewtons(fz_max);
            let (sh, sv) = (
                rng.uniform(-1.0, 1.0) * room,
                rng.uniform(-1.0, 1.0) * sv_max,
            );
            let load_terms = rng.chance(0.5);
            let share = |x: f64| if load_terms { x } else { 0.0 };
            e.ply_steer_conicity = Some(PlySteerConicity {
                Sh_deg: sh,
                Sv: sv,
                Sh_per_kN: share(rng.uniform(-1.0, 1.0) * (room - sh.abs()) / fz_max_kn),
                Sv_per_kN: share(rng.uniform(-1.0, 1.0) * (sv_max - sv.abs()) / fz_max_kn),
                Sh_camber_per_kN: share(
                    rng.uniform(-0.1, 0.1) / (fz_max_kn * params.limits.gamma_max_deg),
                ),
            });
        }
        if channel == Channel::Fx && rng.chance(p) {
            let (v_lo, v_hi) = (l.speed_min_mps, l.speed_max_mps);
            let (f_lo, f_hi) = (
                rng.within(rolling_resistance::ROLLING_RESISTANCE),
                rng.within(rolling_resistance::ROLLING_RESISTANCE),
            );
            let q2 = if v_hi > v_lo {
                (f_hi - f_lo) * n.speed_mps / (v_hi - v_lo)
            } else {
                0.0
            };
            e.rolling_resistance = Some(RollingResistance {
                q1: f_lo - q2 * v_lo / n.speed_mps,
                q2,
            });
        }
        if channel == Channel::Fx && rng.chance(p) {
            // The shift at Fz -> 0 and at fz_max, each within the bound.
            let max = Interval::new(
                -slip_ratio_shift::SLIP_RATIO_SHIFT_ABS_MAX,
                slip_ratio_shift::SLIP_RATIO_SHIFT_ABS_MAX,
            );
            let (at_zero, at_top) = (rng.within(max), rng.within(max));
            // The vertical shift likewise [share of the load].
            let sv_max = Interval::new(
                -slip_ratio_shift::SLIP_RATIO_SHIFT_SV_MAX,
                slip_ratio_shift::SLIP_RATIO_SHIFT_SV_MAX,
            );
            let (sv_zero, sv_top) = (rng.within(sv_max), rng.within(sv_max));
            let fz_max_kn = units::newtons_to_kilonewtons(fz_max);
            e.slip_ratio_shift = Some(SlipRatioShift {
                Sh: at_zero,
                Sh_per_kN: (at_top - at_zero) / fz_max_kn,
                Sv: sv_zero,
                Sv_per_kN: (sv_top - sv_zero) / fz_max_kn,
            });
        }
        *ext.channel_mut(channel) = e;
    }
}

/// MF 6.1's terms of the combined-slip weight (and, on Fy and Mz, the induced term; on Mz the
/// moment of Fx), aimed at the bounds.
fn add_mf61_combined_terms(
    rng: &mut Rng,
    cs: &mut CombinedSlip,
    channel: Channel,
    params: &Params,
) {
    let fz_max_kn = units::newtons_to_kilonewtons(params.limits.fz_max_N);
    let g = params.limits.gamma_max_deg.to_radians();
    let b_abs_max = combined_slip::COMBINED_SLIP_B_ABS_MAX;
    cs.B_slip = rng.sign() * rng.log_uniform(1e-3, b_abs_max);
    cs.B_shift = rng.uniform(-0.5, 0.5);
    // B_camber within what the phase bound leaves: |B| + |B_camber| g^2 <= 1.5 |B| (C was
    // drawn against |B| alone, so the phase may now exceed its bound now and then).
    cs.B_camber = rng.uniform(-0.5, 0.5) * cs.B.abs() / (g * g);
    cs.E = rng.uniform(-3.0, 1.0);
    // E + E_per_kN Fz >= -4 over the load range: within its bound.
    cs.E_per_kN = rng.uniform(-1.0, 1.0) / fz_max_kn;
    // The shift within what the normalisation's phase leaves, at the largest B and E.
    let b_max = 1.5 * cs.B.abs();
    let e_max = cs.E.abs().max((cs.E + cs.E_per_kN * fz_max_kn).abs());
    let room = ((combined_slip::COMBINED_SLIP_NORM_PHASE_MAX / cs.C.abs().max(1e-9)).min(1.5))
        .tan()
        / (b_max * (1.0 + e_max))
        * 0.9;
    let sh_max = room.min(combined_slip::COMBINED_SLIP_SH_MAX);
    cs.Sh = rng.uniform(-0.5, 0.5) * sh_max;
    cs.Sh_per_kN = rng.uniform(-0.5, 0.5) * sh_max / fz_max_kn;
    if channel != Channel::Fx {
        let sv = combined_slip::COMBINED_SLIP_SV_MAX / 3.0;
        cs.Sv = rng.uniform(-1.0, 1.0) * sv;
        cs.Sv_per_kN = rng.uniform(-1.0, 1.0) * sv / fz_max_kn;
        cs.Sv_camber = rng.uniform(-1.0, 1.0) * sv / g;
        cs.Sv_alpha = rng.sign() * rng.log_uniform(1e-3, b_abs_max);
        cs.Sv_slope = rng.sign() * rng.log_uniform(1e-3, b_abs_max);
        // The shape's phase within its bound.
        cs.Sv_shape = rng.uniform(-1.0, 1.0) * combined_slip::COMBINED_SLIP_SV_PHASE_MAX
            / cs.Sv_slope.abs().atan();
    }
    if channel == Channel::Mz {
        cs.Sm = rng.uniform(-1.0, 1.0) * combined_slip::COMBINED_SLIP_SM_MAX;
        cs.Sm_alpha = rng.sign() * rng.log_uniform(1e-3, b_abs_max);
        cs.K_eq = rng.uniform(0.0, combined_slip::COMBINED_SLIP_K_EQ.hi);
    }
}

/// A value from inside the range, at its ends, or outside (inputs are clamped).
fn around(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    match rng.next() % 6 {
        0 => lo,
        1 => hi,
        2 => hi + (hi - lo).max(1.0) * rng.unit(),
        3 => lo - (hi - lo).max(1.0) * rng.unit(),
        _ => rng.uniform(lo, hi),
    }
}

/// The largest |Fx|, |Fy|, |Mz| the bounds allow at load `fz` [N] (clamped to fz_max).
fn output_bound(params: &Params, fz: f64) -> [f64; 3] {
    let fz = fz.clamp(0.0, params.limits.fz_max_N);
    let fz_max = params.limits.fz_max_N;
    let rolling = rolling_resistance::ROLLING_RESISTANCE
        .lo
        .abs()
        .max(rolling_resistance::ROLLING_RESISTANCE.hi);
    // The combined-slip weight G reaches its largest with a shift; Fy gains the force the
    // slip ratio induces.
    let g_max = combined_slip::COMBINED_SLIP_WEIGHT_MAX;
    let induced = |ch: Channel, share: f64| share * bounds::peak_per_load_max(ch) * fz;
    let lateral = |ch: Channel| {
        g_max
            * ((bounds::peak_per_load_max(ch) + bounds::camber_shift_per_load_max(ch)) * fz
                + ply_steer_conicity::ply_steer_sv_share(ch) * fz_max)
    };
    [
        (g_max * bounds::peak_per_load_max(Channel::Fx) + rolling) * fz,
        lateral(Channel::Fy) + induced(Channel::Fy, combined_slip::COMBINED_SLIP_SV_MAX),
        lateral(Channel::Mz)
            + induced(
                Channel::Mz,
                combined_slip::COMBINED_SLIP_SV_MAX + combined_slip::COMBINED_SLIP_SM_MAX,
            ),
    ]
}

/// Evaluates `params` at `n` random inputs and conditions (and at their extremes), with a
/// random relaxation lag; every output must be finite and within [`output_bound`].
fn assert_finite_and_bounded(rng: &mut Rng, params: &Params, n: usize, case: usize) {
    let l = params.limits;
    let g = l.gamma_max_deg.to_radians();
    let c = params
        .extensions
        .as_ref()
        .map(|e| e.limits)
        .unwrap_or_default();
    for _ in 0..n {
        let fz = match rng.next() % 5 {
            0 => l.fz_max_N,
            1 => l.fz_max_N * rng.log_uniform(1e-12, 1.0),
            2 => l.fz_max_N * rng.uniform(1.0, 3.0),
            _ => l.fz_max_N * rng.unit(),
        };
        let inputs = Inputs {
            fz,
            alpha: around(rng, -FRAC_PI_2, FRAC_PI_2),
            kappa: around(rng, -1.0, 1.0),
            gamma: around(rng, -g, g),
        };
        let conditions = OperatingConditions {
            vx: rng.sign() * around(rng, c.speed_min_mps, c.speed_max_mps),
            p: units::kilopascals_to_pascals(around(rng, c.pressure_min_kPa, c.pressure_max_kPa)),
            t_tread: units::celsius_to_kelvin(around(
                rng,
                c.temperature_min_degC,
                c.temperature_max_degC,
            )),
        };
        // A lag somewhere on its way from another slip.
        let from = Inputs {
            alpha: rng.uniform(-FRAC_PI_2, FRAC_PI_2),
            kappa: rng.uniform(-1.0, 1.0),
            ..inputs
        };
        let lagged = LaggedSlip::steady(params, &from).advanced(
            params,
            &inputs,
            rng.log_uniform(1e-6, 100.0),
        );
        let convention = rng.pick(&[SignConvention::Paper, SignConvention::Iso]);
        let o = mf87::evaluate_extended(params, &inputs, &conditions, &lagged, convention);
        let limit = output_bound(params, fz);
        for (what, value, limit) in [
            ("Fx", o.fx, limit[0]),
            ("Fy", o.fy, limit[1]),
            ("Mz", o.mz, limit[2]),
        ] {
            assert!(
                value.is_finite() && value.abs() <= limit * (1.0 + 1e-9),
                "case {case}: {what} = {value} (bound {limit}) at {inputs:?} {conditions:?} {lagged:?}\n{}",
                params.to_json()
            );
        }
        let base = mf87::evaluate(params, &inputs, convention);
        assert!(base.fx.is_finite() && base.fy.is_finite() && base.mz.is_finite());
    }
}

const CASES: usize = 2000;

#[test]
fn random_parameter_sets_inside_the_bounds_give_finite_bounded_outputs() {
    let mut rng = Rng(87);
    let (mut valid_base, mut valid_extended, mut extensions_seen) = (0, 0, 0);
    for case in 0..CASES {
        let mut params = random_base(&mut rng);
        if params.validate().is_err() {
            continue;
        }
        valid_base += 1;
        assert_finite_and_bounded(&mut rng, &params, 40, case);
        // Through the JSON format too.
        let reloaded = Params::from_json(&params.to_json()).unwrap();
        assert_eq!(reloaded, params);

        let mut ext = random_conditions(&mut rng);
        add_random_extensions(&mut rng, &params, &mut ext, 0.5);
        params.extensions = Some(ext);
        if params.validate().is_err() {
            continue;
        }
        valid_extended += 1;
        extensions_seen += Channel::ALL
            .iter()
            .map(|c| {
                params
                    .extensions
                    .as_ref()
                    .unwrap()
                    .channel(*c)
                    .kinds()
                    .count()
            })
            .sum::<usize>();
        assert_finite_and_bounded(&mut rng, &params, 40, case);
    }
    // The generator must mostly hit the valid region, or the test shows little.
    assert!(
        valid_base > CASES / 2 && valid_extended > CASES / 4,
        "valid: {valid_base} base, {valid_extended} with extensions of {CASES}"
    );
    assert!(extensions_seen > 5 * valid_extended, "{extensions_seen}");
}

/// How to push one parameter of a valid set outside one bound: the parameter's name, the
/// value it gets and a piece of the message naming the bound. `None` if the set does not
/// allow it (e.g. a degenerate range).
type Push = fn(&mut Rng, &mut Params) -> Option<(String, f64, String)>;

fn channel_of(rng: &mut Rng, lateral_only: bool) -> Channel {
    if lateral_only {
        rng.pick(&[Channel::Fy, Channel::Mz])
    } else {
        rng.pick(&Channel::ALL)
    }
}

fn set(p: &mut Params, channel: Channel, index: usize, value: f64) -> (String, f64) {
    *p.coefficient_mut(channel, index).unwrap() = value;
    let name = Params::coefficient_names(channel)[index];
    (format!("{channel}.{name}"), value)
}

fn ext(p: &mut Params) -> &mut Extensions {
    p.extensions.get_or_insert_with(|| {
        Extensions::new(
            Nominal {
                pressure_kpa: 220.0,
                speed_mps: 15.0,
                temperature_c: 40.0,
            },
            ConditionLimits::default(),
        )
    })
}

/// 1 plus a random margin: how far past a bound a value is pushed.
fn past(rng: &mut Rng) -> f64 {
    1.0 + rng.log_uniform(1e-6, 10.0)
}

const PUSHES: &[(&str, Push)] = &[
    ("fz_max above", |rng, p| {
        let v = bounds::FZ_MAX_N.hi * past(rng);
        p.limits.fz_max_N = v;
        Some(("limits.fz_max_N".into(), v, "[10, 100000] N".into()))
    }),
    ("fz_max below", |rng, p| {
        let v = bounds::FZ_MAX_N.lo / past(rng);
        p.limits.fz_max_N = v;
        Some(("limits.fz_max_N".into(), v, "[10, 100000] N".into()))
    }),
    ("gamma_max above", |rng, p| {
        let v = bounds::GAMMA_MAX_DEG.hi * past(rng);
        p.limits.gamma_max_deg = v;
        Some(("limits.gamma_max_deg".into(), v, "[0.1, 89] deg".into()))
    }),
    ("C", |rng, p| {
        let ch = channel_of(rng, false);
        let v = if rng.chance(0.5) {
            bounds::SHAPE_C.hi * past(rng)
        } else {
            bounds::SHAPE_C.lo / past(rng) * rng.sign()
        };
        let (name, v) = set(p, ch, 0, v);
        Some((name, v, "C must lie in [0.1, 5]".into()))
    }),
    ("peak at low load", |rng, p| {
        let ch = channel_of(rng, false);
        let cap = bounds::peak_per_load_max(ch);
        let a2 = p.coefficient(ch, 2).unwrap();
        // Further out with the same sign: the high end moves the same way, so D keeps its sign.
        let v = a2.signum() * 1000.0 * cap * past(rng);
        let (name, v) = set(p, ch, 2, v);
        Some((name, v, format!("must be at most {cap}")))
    }),
    ("peak at fz_max", |rng, p| {
        let ch = channel_of(rng, false);
        let cap = bounds::peak_per_load_max(ch);
        let a2 = p.coefficient(ch, 2).unwrap();
        let fz = p.limits.fz_max_N / 1000.0;
        let v = (a2.signum() * 1000.0 * cap * past(rng) - a2) / fz;
        let (name, v) = set(p, ch, 1, v);
        Some((name, v, format!("must be at most {cap}")))
    }),
    ("Fy stiffness phase", |rng, p| {
        let fz = p.limits.fz_max_N / 1000.0;
        let turn = (p.Fy.a5 * fz).atan();
        let v = PI * past(rng) / turn;
        let (name, v) = set(p, Channel::Fy, 4, v);
        Some((name, v, "below pi".into()))
    }),
    ("stiffness exponent", |rng, p| {
        let ch = rng.pick(&[Channel::Mz, Channel::Fx]);
        let fz = p.limits.fz_max_N / 1000.0;
        let v = rng.sign() * bounds::EXPONENT_A5_FZ_MAX * past(rng) / fz;
        let (name, v) = set(p, ch, 5, v);
        Some((name, v, "must be at most 10".into()))
    }),
    ("camber on B", |rng, p| {
        let ch = channel_of(rng, true);
        let v = past(rng) / p.limits.gamma_max_deg;
        let (name, v) = set(p, ch, 12, v);
        Some((name, v, "1 - a12 |gamma| must stay > 0".into()))
    }),
    ("camber Sh", |rng, p| {
        let ch = channel_of(rng, true);
        let v = rng.sign() * bounds::SHIFT_SH_MAX_DEG * past(rng) / p.limits.gamma_max_deg;
        let (name, v) = set(p, ch, 9, v);
        Some((name, v, "must be at most 10 deg".into()))
    }),
    ("camber Sv", |rng, p| {
        let ch = channel_of(rng, true);
        let cap = bounds::camber_shift_per_load_max(ch);
        let v = rng.sign() * 1000.0 * cap * past(rng) / p.limits.gamma_max_deg;
        let (name, v) = set(p, ch, 11, v);
        Some((name, v, format!("must be at most {cap}")))
    }),
    ("B", |rng, p| {
        // B scales with a3 (and a4 for Mz, Fx): beyond 1000 everywhere when B >= 1e-5 was.
        let ch = channel_of(rng, false);
        let factor = 1e8 * past(rng);
        if ch != Channel::Fy {
            let a4 = p.coefficient(ch, 4).unwrap();
            *p.coefficient_mut(ch, 4).unwrap() = a4 * factor;
        }
        let a3 = p.coefficient(ch, 3).unwrap();
        let (name, v) = set(p, ch, 3, a3 * factor);
        Some((name, v, "must lie in [0.00001, 1000]".into()))
    }),
    ("E", |rng, p| {
        let ch = channel_of(rng, false);
        let v = rng.sign() * 10.0 * bounds::CURVATURE_E.hi * past(rng);
        let (name, v) = set(p, ch, 8, v);
        Some((name, v, "must lie in [-1000000, 1000000]".into()))
    }),
    ("coefficient magnitude", |rng, p| {
        // A large negative a13 only makes E smaller: no other bound sees it.
        let ch = channel_of(rng, true);
        let v = -bounds::COEFFICIENT_ABS_MAX * past(rng);
        let (name, v) = set(p, ch, 13, v);
        Some((name, v, "within +-1000000000".into()))
    }),
    ("nominal speed", |rng, p| {
        let v = bounds::NOMINAL_SPEED_MPS.lo / past(rng) / 1e3f64.powf(rng.unit());
        ext(p).nominal.speed_mps = v;
        Some((
            "extensions.nominal.speed_mps".into(),
            v,
            "[0.5, 150] m/s".into(),
        ))
    }),
    ("nominal pressure", |rng, p| {
        let v = bounds::PRESSURE_KPA.hi * past(rng);
        ext(p).nominal.pressure_kpa = v;
        Some((
            "extensions.nominal.pressure_kPa".into(),
            v,
            "[10, 2000] kPa".into(),
        ))
    }),
    ("nominal temperature", |rng, p| {
        let v = bounds::TEMPERATURE_DEGC.lo - 300.0 * (past(rng) - 1.0) - 1e-3;
        ext(p).nominal.temperature_c = v;
        Some((
            "extensions.nominal.temperature_degC".into(),
            v,
            "[-60, 250] degC".into(),
        ))
    }),
    ("speed limit", |rng, p| {
        let v = bounds::SPEED_MPS.hi * past(rng);
        ext(p).limits.speed_max_mps = v;
        Some((
            "extensions.limits.speed_max_mps".into(),
            v,
            "[0, 150] m/s".into(),
        ))
    }),
    ("relaxation length", |rng, p| {
        let ch = channel_of(rng, false);
        let v = relaxation_length::RELAXATION_LENGTH_M.hi * past(rng);
        ext(p).channel_mut(ch).relaxation_length = Some(RelaxationLength { sigma_m: v });
        Some((
            format!("extensions.{ch}.relaxation_length.sigma_m"),
            v,
            "[0.001, 5] m".into(),
        ))
    }),
    ("rolling resistance", |rng, p| {
        let v = rolling_resistance::ROLLING_RESISTANCE.hi * past(rng);
        ext(p).Fx.rolling_resistance = Some(RollingResistance { q1: v, q2: 0.0 });
        Some((
            "extensions.Fx.rolling_resistance.q1".into(),
            v,
            "it must lie in [-0.05, 0.3] over the speed range".into(),
        ))
    }),
    ("slip-ratio shift at zero load", |rng, p| {
        let v = rng.sign() * slip_ratio_shift::SLIP_RATIO_SHIFT_ABS_MAX * past(rng);
        ext(p).Fx.slip_ratio_shift = Some(SlipRatioShift {
            Sh: v,
            ..Default::default()
        });
        Some((
            "extensions.Fx.slip_ratio_shift.Sh".into(),
            v,
            "as Fz -> 0; it must be at most 0.05".into(),
        ))
    }),
    ("slip-ratio shift at fz_max", |rng, p| {
        let fz = p.limits.fz_max_N / 1000.0;
        let v = rng.sign() * slip_ratio_shift::SLIP_RATIO_SHIFT_ABS_MAX * past(rng) / fz;
        ext(p).Fx.slip_ratio_shift = Some(SlipRatioShift {
            Sh_per_kN: v,
            ..Default::default()
        });
        Some((
            "extensions.Fx.slip_ratio_shift.Sh_per_kN".into(),
            v,
            "it must be at most 0.05 over the load range".into(),
        ))
    }),
    ("vertical shift at zero load", |rng, p| {
        let v = rng.sign() * slip_ratio_shift::SLIP_RATIO_SHIFT_SV_MAX * past(rng);
        ext(p).Fx.slip_ratio_shift = Some(SlipRatioShift {
            Sv: v,
            ..Default::default()
        });
        Some((
            "extensions.Fx.slip_ratio_shift.Sv".into(),
            v,
            "as Fz -> 0; it must be at most 0.4".into(),
        ))
    }),
    ("vertical shift at fz_max", |rng, p| {
        let fz = p.limits.fz_max_N / 1000.0;
        let v = rng.sign() * slip_ratio_shift::SLIP_RATIO_SHIFT_SV_MAX * past(rng) / fz;
        ext(p).Fx.slip_ratio_shift = Some(SlipRatioShift {
            Sv_per_kN: v,
            ..Default::default()
        });
        Some((
            "extensions.Fx.slip_ratio_shift.Sv_per_kN".into(),
            v,
            "it must be at most 0.4 over the load range".into(),
        ))
    }),
    ("combined slip B", |rng, p| {
        let ch = channel_of(rng, false);
        let v = rng.sign() * combined_slip::COMBINED_SLIP_B_ABS_MAX * past(rng);
        ext(p).channel_mut(ch).combined_slip = Some(CombinedSlip {
            B: v,
            C: 0.0,
            ..Default::default()
        });
        Some((
            format!("extensions.{ch}.combined_slip.B"),
            v,
            "|B| must be <= 1000".into(),
        ))
    }),
    ("combined slip phase", |rng, p| {
        let ch = channel_of(rng, false);
        let b = rng.log_uniform(1e-3, 1e3);
        let s_max = if ch == Channel::Fx { FRAC_PI_2 } else { 1.0 };
        let v = combined_slip::COMBINED_SLIP_PHASE_MAX * past(rng) / (b * s_max).atan();
        ext(p).channel_mut(ch).combined_slip = Some(CombinedSlip {
            B: b,
            C: v,
            ..Default::default()
        });
        Some((
            format!("extensions.{ch}.combined_slip.C"),
            v,
            "it must stay <= 8 pi".into(),
        ))
    }),
    ("ply steer Sh", |rng, p| {
        let ch = channel_of(rng, true);
        let v = rng.sign() * bounds::SHIFT_SH_MAX_DEG * past(rng);
        ext(p).channel_mut(ch).ply_steer_conicity = Some(PlySteerConicity {
            Sh_deg: v,
            Sv: 0.0,
            ..Default::default()
        });
        Some((
            format!("extensions.{ch}.ply_steer_conicity.Sh_deg"),
            v,
            "must be at most 10 deg".into(),
        ))
    }),
    ("ply steer Sv", |rng, p| {
        let ch = channel_of(rng, true);
        let share = ply_steer_conicity::ply_steer_sv_share(ch);
        let v = rng.sign() * share * p.limits.fz_max_N * past(rng);
        ext(p).channel_mut(ch).ply_steer_conicity = Some(PlySteerConicity {
            Sh_deg: 0.0,
            Sv: v,
            ..Default::default()
        });
        Some((
            format!("extensions.{ch}.ply_steer_conicity.Sv"),
            v,
            format!("must be at most {share}"),
        ))
    }),
    ("peak scale", |rng, p| {
        // Pressure 100..400 kPa around 200: dp up to 1, so d > 9 puts the scale above 10.
        let ch = channel_of(rng, false);
        let v = (bounds::CONDITION_SCALE.hi - 1.0) * past(rng);
        ext(p).channel_mut(ch).inflation_pressure = Some(InflationPressure {
            k: 0.0,
            d: v,
            ..Default::default()
        });
        let e = ext(p);
        e.nominal.pressure_kpa = 200.0;
        (e.limits.pressure_min_kPa, e.limits.pressure_max_kPa) = (100.0, 400.0);
        Some((
            format!("extensions.{ch}.inflation_pressure.d"),
            v,
            "it must stay within [0.1, 10] over the range [100, 400] kPa".into(),
        ))
    }),
    ("optimum temperature", |rng, p| {
        let ch = channel_of(rng, false);
        let e = ext(p);
        let v = bounds::TEMPERATURE_DEGC.hi - e.nominal.temperature_c
            + 100.0 * (past(rng) - 1.0)
            + 1e-3;
        e.channel_mut(ch).temperature = Some(Temperature {
            w: 0.0,
            Topt_degC: v,
            k: 0.0,
        });
        Some((
            format!("extensions.{ch}.temperature.Topt_degC"),
            v,
            "must lie in [-60, 250] degC".into(),
        ))
    }),
    ("extension magnitude", |rng, p| {
        // Over a single temperature the stiffness term k (T - T0) / 50 is 0: only the general
        // cap sees k.
        let ch = channel_of(rng, false);
        let e = ext(p);
        let t0 = e.nominal.temperature_c;
        (e.limits.temperature_min_degC, e.limits.temperature_max_degC) = (t0, t0);
        let v = rng.sign() * bounds::EXTENSION_PARAMETER_ABS_MAX * past(rng);
        e.channel_mut(ch).temperature = Some(Temperature {
            w: 0.0,
            Topt_degC: 0.0,
            k: v,
        });
        Some((
            format!("extensions.{ch}.temperature.k"),
            v,
            "within +-1000000".into(),
        ))
    }),
    ("peak with the scales", |rng, p| {
        // A speed scale within its own bound that carries the peak past its cap.
        let ch = channel_of(rng, false);
        let fz = p.limits.fz_max_N / 1000.0;
        let (a1, a2) = (p.coefficient(ch, 1).unwrap(), p.coefficient(ch, 2).unwrap());
        let peak = (a2.abs()).max((a1 * fz + a2).abs()) / 1000.0;
        let needed = bounds::peak_per_load_max(ch) / peak * past(rng);
        if needed > 0.95 * bounds::CONDITION_SCALE.hi {
            return None;
        }
        let e = ext(p);
        e.nominal.speed_mps = 10.0;
        (e.limits.speed_min_mps, e.limits.speed_max_mps) = (10.0, 20.0);
        // 1 + v (V - 10) / 10 runs from 1 to 1 + v over 10..20 m/s: within its own bound.
        let v = needed - 1.0;
        e.channel_mut(ch).speed_dependence = Some(SpeedDependence { v, w: 0.0 });
        Some((
            format!("extensions.{ch}.speed_dependence.v"),
            v,
            "with the peak scales at their largest".into(),
        ))
    }),
];

#[test]
fn a_value_outside_a_bound_is_rejected_naming_parameter_value_and_bound() {
    let mut rng = Rng(1987);
    let mut tried = vec![0; PUSHES.len()];
    let mut case = 0;
    while tried.iter().any(|n| *n < 15) {
        case += 1;
        assert!(case < 20_000, "too few valid sets: {tried:?}");
        let base = random_base(&mut rng);
        if base.validate().is_err() {
            continue;
        }
        for (i, (what, push)) in PUSHES.iter().enumerate() {
            let mut p = base.clone();
            let Some((name, value, bound)) = push(&mut rng, &mut p) else {
                continue;
            };
            tried[i] += 1;
            match p.validate() {
                Err(ParamError::Invalid {
                    name: n,
                    value: v,
                    reason,
                }) => {
                    assert!(
                        n == name && v.to_bits() == value.to_bits() && reason.contains(&bound),
                        "{what}: expected {name} = {value} and {bound:?}, got {n} = {v}: {reason}\n{}",
                        p.to_json()
                    );
                    // The message carries all three.
                    let message = p.validate().unwrap_err().to_string();
                    assert!(message.starts_with(&format!("parameter {name} = ")));
                }
                other => panic!("{what}: {name} = {value} not rejected: {other:?}"),
            }
        }
    }
}

#[test]
fn the_testers_cases_fail_to_load_naming_parameter_value_and_bound() {
    let table = mf87::params::PAPER_TABLE_JSON
        .trim_end()
        .trim_end_matches('}');
    let with = |extensions: &str| format!("{table}, \"extensions\": {extensions} }}");
    let nominal = |v0: &str| {
        format!(
            r#""nominal": {{ "pressure_kPa": 220, "speed_mps": {v0}, "temperature_degC": 40 }}"#
        )
    };
    let cases = [
        (
            // Gave Fx = -inf (q2 |vx| / V0 overflows).
            with(&format!(
                r#"{{ {}, "Fx": {{ "rolling_resistance": {{ "q1": 0.01, "q2": 0.002 }} }} }}"#,
                nominal("5e-324")
            )),
            "parameter extensions.nominal.speed_mps = 5e-324: the nominal condition must lie in [0.5, 150] m/s",
        ),
        (
            // Gave Fx = -8e7 N.
            with(&format!(
                r#"{{ {}, "Fx": {{ "rolling_resistance": {{ "q1": 0.01, "q2": 0.002 }} }} }}"#,
                nominal("1e-6")
            )),
            "parameter extensions.nominal.speed_mps = 1e-6: the nominal condition must lie in [0.5, 150] m/s",
        ),
        (
            // Gave Fy = 1e300.
            with(&format!(
                r#"{{ {}, "Fy": {{ "ply_steer_conicity": {{ "Sh_deg": 0, "Sv": 1e300 }} }} }}"#,
                nominal("15")
            )),
            "parameter extensions.Fy.ply_steer_conicity.Sv = 1e300: the offset |Sv| must be at most 0.1 x fz_max = 1000 N",
        ),
        (
            // Gave Fx = -6.7e303.
            with(&format!(
                r#"{{ {}, "Fx": {{ "rolling_resistance": {{ "q1": 1e300, "q2": 1e300 }} }} }}"#,
                nominal("15")
            )),
            "parameter extensions.Fx.rolling_resistance.q1 = 1e300: the rolling-resistance coefficient q1 + q2 |vx| / V0 \
             is 1e300 at |vx| = 0 m/s",
        ),
    ];
    for (text, expected) in cases {
        let err = Params::from_json(&text).unwrap_err().to_string();
        assert!(err.starts_with(expected), "{err}\nexpected: {expected}");
    }
}

#[test]
fn the_paper_table_and_tire_gap_fits_pass() {
    Params::paper_table().validate().unwrap();
    // Parameter files tire-gap wrote for synthetic rig data (mf52 and brush tires, 10k rows):
    // they carry what unconstrained fits produce, e.g. E above 1, |a13| gamma_max near 30,
    // B of 0.003 at vanishing load, a combined-slip weighting with C = 60 and B = 0.1, E of
    // -1047 (a13 just below 1 / gamma_max), and temperature windows with relaxation.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fits");
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        let params = Params::from_json(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut rng = Rng(files);
        assert_finite_and_bounded(&mut rng, &params, 2000, files as usize);
        files += 1;
    }
    assert!(files >= 5, "{files} files in {}", dir.display());
}

#[test]
fn the_docs_list_every_bound() {
    let doc = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/parameters.md");
    let text = std::fs::read_to_string(&doc).unwrap();
    // Markdown tables escape the bars of |x|.
    let cell = |s: &str| s.replace('|', "\\|");
    for row in mf87::bounds_table() {
        let line = format!(
            "| {} | {} | {} |",
            cell(row.what),
            cell(&row.allowed),
            row.unit
        );
        assert!(
            text.contains(&line),
            "docs/parameters.md lacks the row\n{line}\n(bounds_table, or the page, changed)"
        );
    }
}
