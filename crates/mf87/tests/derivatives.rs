//! Exact derivatives: the model evaluated over a dual number against central finite
//! differences of the `f64` model, at 100,000 random points over the whole valid range (every
//! extension on, and off), at the clamping limits, at the reference points, and against
//! hand-derived slopes. Tolerances: 1e-6 of max(|exact|, scale) against 1e-6-span central
//! differences (measured worst: 2.6e-8), 1e-8 against Richardson-extrapolated ones at the
//! reference points (measured worst: 3.4e-10). Derivatives in the parameters (coefficients and
//! extension parameters, what a fit needs) against central differences at random points, within
//! 1e-5 (measured worst: 3.7e-6).

use mf87::extensions::ConditionLimits;

#[path = "../benches/support/every_extension.rs"]
mod every_extension;
use every_extension::with_every_extension;
use mf87::{
    Dual64, InputVar, Inputs, LaggedSlip, OperatingConditions, Outputs, Params, SignConvention,
    evaluate, evaluate_extended, units,
};

/// The ten things the outputs depend on: four inputs, three operating conditions, three
/// lagged slips.
const VARS: usize = 10;
const NAMES: [&str; VARS] = [
    "Fz", "alpha", "kappa", "gamma", "vx", "p", "T_tread", "lag_Fx", "lag_Fy", "lag_Mz",
];

type Point = [f64; VARS];

/// Deterministic uniform numbers in [0, 1) (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// The outputs at `x`, over `f64` or a dual number.
fn outputs<T: mf87::Real>(params: &Params, x: [T; VARS], convention: SignConvention) -> Outputs<T> {
    let inputs = Inputs {
        fz: x[0],
        alpha: x[1],
        kappa: x[2],
        gamma: x[3],
    };
    if params.extensions.is_none() {
        return evaluate(params, &inputs, convention);
    }
    let conditions = OperatingConditions {
        vx: x[4],
        p: x[5],
        t_tread: x[6],
    };
    let lagged = LaggedSlip {
        fx: x[7],
        fy: x[8],
        mz: x[9],
    };
    evaluate_extended(params, &inputs, &conditions, &lagged, convention)
}

fn as_array(o: Outputs) -> [f64; 3] {
    [o.fx, o.fy, o.mz]
}

/// The exact derivative of the outputs with respect to variable `k` at `x`.
fn exact(params: &Params, x: &Point, k: usize, convention: SignConvention) -> [f64; 3] {
    let seeded: [Dual64; VARS] = std::array::from_fn(|i| {
        let d = Dual64::from_re(x[i]);
        if i == k { d.derivative() } else { d }
    });
    let o = outputs(params, seeded, convention);
    [o.fx.eps, o.fy.eps, o.mz.eps]
}

/// The central difference with step `h` in variable `k`.
fn central(params: &Params, x: &Point, k: usize, h: f64, convention: SignConvention) -> [f64; 3] {
    let (mut up, mut down) = (*x, *x);
    up[k] += h;
    down[k] -= h;
    let (a, b) = (
        as_array(outputs(params, up, convention)),
        as_array(outputs(params, down, convention)),
    );
    std::array::from_fn(|i| (a[i] - b[i]) / (2.0 * h))
}

/// Each variable's sampled range (slightly inside the valid range) and its kinks, where a
/// finite difference straddling them is not a derivative: the clamping bounds, |gamma| and
/// |vx| at 0.
struct Space {
    lo: Point,
    hi: Point,
    kinks: [Vec<f64>; VARS],
}

fn space(params: &Params) -> Space {
    let g = params.limits.gamma_max_deg.to_radians();
    let half_pi = std::f64::consts::FRAC_PI_2;
    let limits = ConditionLimits::default();
    let (p_lo, p_hi) = (limits.pressure_min_kPa * 1e3, limits.pressure_max_kPa * 1e3);
    let (t_lo, t_hi) = (
        limits.temperature_min_degC + 273.15,
        limits.temperature_max_degC + 273.15,
    );
    // Beyond the valid range on every side, so that clamped points are drawn too.
    let lo = [
        100.0,
        -1.1 * half_pi,
        -1.1,
        -1.2 * g,
        -80.0,
        p_lo - 20e3,
        t_lo - 10.0,
        -1.1,
        -1.1 * half_pi,
        -1.1 * half_pi,
    ];
    let hi = [
        params.limits.fz_max_N * 1.05,
        1.1 * half_pi,
        1.1,
        1.2 * g,
        80.0,
        p_hi + 20e3,
        t_hi + 10.0,
        1.1,
        1.1 * half_pi,
        1.1 * half_pi,
    ];
    let kinks = [
        vec![params.limits.fz_max_N],
        vec![-half_pi, half_pi],
        vec![-1.0, 1.0],
        vec![-g, 0.0, g],
        vec![-limits.speed_max_mps, 0.0, limits.speed_max_mps],
        vec![p_lo, p_hi],
        vec![t_lo, t_hi],
        vec![-1.0, 1.0],
        vec![-half_pi, half_pi],
        vec![-half_pi, half_pi],
    ];
    Space { lo, hi, kinks }
}

/// Steps of the central differences: 1e-6 of each variable's span.
fn steps(s: &Space) -> Point {
    std::array::from_fn(|k| 1e-6 * (s.hi[k] - s.lo[k]))
}

/// Derivative scale of variable `k`: an output's typical size over the variable's span.
fn scale(s: &Space, k: usize) -> f64 {
    10_000.0 / (s.hi[k] - s.lo[k])
}

/// Exact against central differences at `n` random points; returns the worst error relative
/// to max(|exact|, scale) and how many comparisons were made.
fn compare_at_random_points(params: &Params, n: usize, seed: u64, vars: usize) -> (f64, usize) {
    let s = space(params);
    let h = steps(&s);
    let mut rng = Rng(seed);
    let mut worst: (f64, String) = (0.0, String::new());
    let mut compared = 0;
    for _ in 0..n {
        let x: Point = std::array::from_fn(|k| rng.uniform(s.lo[k], s.hi[k]));
        let convention = if rng.next() < 0.5 {
            SignConvention::Paper
        } else {
            SignConvention::Iso
        };
        for k in 0..vars {
            if s.kinks[k].iter().any(|c| (x[k] - c).abs() < 4.0 * h[k]) {
                continue;
            }
            let (d, f) = (
                exact(params, &x, k, convention),
                central(params, &x, k, h[k], convention),
            );
            for out in 0..3 {
                let err = (d[out] - f[out]).abs() / d[out].abs().max(scale(&s, k));
                assert!(
                    d[out].is_finite(),
                    "d{}/d{} not finite at {x:?}",
                    out,
                    NAMES[k]
                );
                if err > worst.0 {
                    worst = (
                        err,
                        format!(
                            "output {out} by {}: exact {} fd {} at {x:?}",
                            NAMES[k], d[out], f[out]
                        ),
                    );
                }
                compared += 1;
            }
        }
    }
    assert!(
        worst.0 < 1e-6,
        "worst relative error {:e}: {}",
        worst.0,
        worst.1
    );
    (worst.0, compared)
}

#[test]
fn base_model_derivatives_match_central_differences_at_100k_points() {
    let (worst, compared) = compare_at_random_points(&Params::paper_table(), 100_000, 1, 4);
    assert!(compared > 1_100_000, "{compared} comparisons");
    eprintln!("base model: worst relative error {worst:e} over {compared} comparisons");
}

#[test]
fn extended_model_derivatives_match_central_differences_at_100k_points() {
    let (worst, compared) = compare_at_random_points(&with_every_extension(), 100_000, 2, VARS);
    assert!(compared > 2_800_000, "{compared} comparisons");
    eprintln!("every extension: worst relative error {worst:e} over {compared} comparisons");
}

#[test]
fn a_clamped_input_has_derivative_zero() {
    let params = with_every_extension();
    let s = space(&params);
    let inside: Point = [
        4000.0, 0.05, 0.03, 0.01, 20.0, 230e3, 320.0, 0.02, 0.04, 0.04,
    ];
    // Beyond each bound, the derivative by that variable is exactly zero.
    for k in [0, 1, 2, 3, 5, 6, 7, 8, 9] {
        let kinks = &s.kinks[k];
        let (lower, upper) = (kinks[0], kinks[kinks.len() - 1]);
        let margin = 0.01 * (s.hi[k] - s.lo[k]);
        // The load has only an upper bound (Fz <= 0 is a lifted wheel, not a clamp).
        let beyond = if k == 0 {
            vec![upper + margin]
        } else {
            vec![lower - margin, upper + margin]
        };
        for value in beyond {
            let mut x = inside;
            x[k] = value;
            let d = exact(&params, &x, k, SignConvention::Iso);
            assert_eq!(
                d, [0.0; 3],
                "d/d{} at {value}, beyond its range: {d:?}",
                NAMES[k]
            );
        }
    }
    // Speed beyond the speed range: |vx| clamped, no slope.
    let mut x = inside;
    x[4] = -75.0;
    assert_eq!(exact(&params, &x, 4, SignConvention::Paper), [0.0; 3]);
    // On a bound the slope is the one from inside.
    let mut x = inside;
    x[2] = 1.0;
    let h = 1e-7;
    let on = exact(&params, &x, 2, SignConvention::Paper);
    let mut below = x;
    below[2] -= h;
    let one_sided: [f64; 3] = {
        let (a, b) = (
            as_array(outputs(&params, x, SignConvention::Paper)),
            as_array(outputs(&params, below, SignConvention::Paper)),
        );
        std::array::from_fn(|i| (a[i] - b[i]) / h)
    };
    for i in 0..3 {
        assert!(
            (on[i] - one_sided[i]).abs() <= 1e-4 * on[i].abs().max(1.0),
            "{on:?} vs {one_sided:?}"
        );
    }
}

#[test]
fn slopes_at_zero_slip_are_the_hand_derived_stiffnesses() {
    let params = Params::paper_table();
    for fz in [1500.0, 4000.0, 7000.0] {
        let fz_kn: f64 = fz / 1000.0;
        let x: Point = [fz, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        // dFy/dalpha = BCD [N/deg] * 180/pi, BCD = a3 sin(a4 atan(a5 Fz)).
        let bcd_y = 1078.0 * (1.82 * (0.208 * fz_kn).atan()).sin();
        let d = exact(&params, &x, 1, SignConvention::Paper);
        let want = bcd_y * 180.0 / std::f64::consts::PI;
        assert!((d[1] - want).abs() <= 1e-12 * want, "{} vs {want}", d[1]);
        // dFx/dkappa = BCD [N/percent] * 100, BCD = (a3 Fz^2 + a4 Fz) e^(-a5 Fz).
        let bcd_x = (49.6 * fz_kn * fz_kn + 226.0 * fz_kn) * (-0.069 * fz_kn).exp();
        let d = exact(&params, &x, 2, SignConvention::Paper);
        assert!((d[0] - 100.0 * bcd_x).abs() <= 1e-12 * 100.0 * bcd_x);
        // At zero slip and camber the load moves no output (all are zero there).
        assert_eq!(exact(&params, &x, 0, SignConvention::Paper), [0.0; 3]);
        // The ISO convention flips the lateral slopes.
        let paper = exact(&params, &x, 1, SignConvention::Paper);
        let iso = exact(&params, &x, 1, SignConvention::Iso);
        assert_eq!((iso[1], iso[2]), (-paper[1], -paper[2]));
    }
}

#[test]
fn exact_at_the_reference_points() {
    // Richardson-extrapolated central differences (error O(h^4)) at every reference row,
    // against the dual-number derivative.
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/mf87_reference.csv");
    let text = std::fs::read_to_string(path).unwrap();
    let params = Params::paper_table();
    let s = space(&params);
    let mut worst = 0.0f64;
    let mut rows = 0;
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let v: Vec<f64> = line.split(',').map(|c| c.trim().parse().unwrap()).collect();
        let x: Point = [
            v[0],
            units::degrees_to_radians(v[1]),
            units::percent_to_slip_ratio(v[3]),
            units::degrees_to_radians(v[2]),
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
        ];
        rows += 1;
        for k in 0..4 {
            let h = 1e-4 * (s.hi[k] - s.lo[k]);
            if s.kinks[k].iter().any(|c| (x[k] - c).abs() < 4.0 * h) || x[0] < 4.0 * h {
                continue;
            }
            let d = exact(&params, &x, k, SignConvention::Paper);
            let (f1, f2) = (
                central(&params, &x, k, h, SignConvention::Paper),
                central(&params, &x, k, h / 2.0, SignConvention::Paper),
            );
            for out in 0..3 {
                let richardson = (4.0 * f2[out] - f1[out]) / 3.0;
                let err = (d[out] - richardson).abs() / d[out].abs().max(scale(&s, k));
                worst = worst.max(err);
                assert!(
                    err < 1e-8,
                    "row {line}: output {out} by {}: {} vs {richardson}",
                    NAMES[k],
                    d[out]
                );
            }
        }
    }
    assert_eq!(rows, 455);
    eprintln!("reference points: worst relative error {worst:e}");
}

#[test]
fn value_part_agrees_with_the_f64_model() {
    // num-dual divides by multiplying with the reciprocal, so the value part may differ from
    // the f64 model in the last bits; the FMU's outputs always come from the f64 model. The
    // bits are those of the output's terms, which are of the size of the load (Fx near zero
    // can be the weighted force less the rolling resistance, each hundreds of N).
    let params = with_every_extension();
    let s = space(&params);
    let mut rng = Rng(3);
    for _ in 0..10_000 {
        let x: Point = std::array::from_fn(|k| rng.uniform(s.lo[k], s.hi[k]));
        let plain = as_array(outputs(&params, x, SignConvention::Iso));
        let dual = outputs(&params, x.map(Dual64::from_re), SignConvention::Iso);
        for (p, d) in plain.iter().zip([dual.fx.re, dual.fy.re, dual.mz.re]) {
            assert!(
                (p - d).abs() <= 1e-13 * p.abs().max(x[0].abs()).max(1.0),
                "{p} vs {d} at {x:?}"
            );
        }
    }
    // The first four variables are the model's inputs, in their order.
    assert_eq!(
        InputVar::ALL.map(InputVar::name),
        [NAMES[0], NAMES[1], NAMES[2], NAMES[3]]
    );
}

/// The relaxation states' rates `|vx| (s - lag) / sigma` at `x` (inputs, vx, lags).
fn rates<T: mf87::Real>(params: &Params, x: [T; VARS]) -> [T; 3] {
    let inputs = Inputs {
        fz: x[0],
        alpha: x[1],
        kappa: x[2],
        gamma: x[3],
    };
    let lagged = LaggedSlip {
        fx: x[7],
        fy: x[8],
        mz: x[9],
    };
    let r = lagged.rates(params, &inputs, x[4]);
    [r.fx, r.fy, r.mz]
}

#[test]
fn relaxation_rates_derivatives_match_central_differences_at_100k_points() {
    let params = with_every_extension();
    let s = space(&params);
    let h = steps(&s);
    let mut rng = Rng(4);
    let mut worst = 0.0f64;
    for _ in 0..100_000 {
        let x: Point = std::array::from_fn(|k| rng.uniform(s.lo[k], s.hi[k]));
        for k in 0..VARS {
            if s.kinks[k].iter().any(|c| (x[k] - c).abs() < 4.0 * h[k]) {
                continue;
            }
            let seeded: [Dual64; VARS] = std::array::from_fn(|i| {
                let d = Dual64::from_re(x[i]);
                if i == k { d.derivative() } else { d }
            });
            let exact = rates(&params, seeded).map(|d| d.eps);
            let (mut up, mut down) = (x, x);
            up[k] += h[k];
            down[k] -= h[k];
            let (a, b) = (rates(&params, up), rates(&params, down));
            for i in 0..3 {
                let fd = (a[i] - b[i]) / (2.0 * h[k]);
                // The rates are at most |vx| max / sigma ~ 200 per unit of slip.
                let err = (exact[i] - fd).abs() / exact[i].abs().max(1.0);
                worst = worst.max(err);
                assert!(
                    err < 1e-6,
                    "d rate {i} / d {}: {} vs {fd} at {x:?}",
                    NAMES[k],
                    exact[i]
                );
            }
        }
    }
    eprintln!("relaxation rates: worst relative error {worst:e}");
}

/// Derivatives in the parameters (what a fit needs): each coefficient of each channel and each
/// extension parameter seeded in turn, through `factors` and `evaluate_factors` over dual
/// parameters, against central differences of the `f64` model, at random points.
#[test]
fn parameter_derivatives_match_central_differences() {
    use mf87::extensions::{ChannelExtensions, Conditions, Extension, Nominal};
    use mf87::formula::factors;
    use mf87::{Channel, Real};

    let nominal = Nominal {
        pressure_kpa: 200.0,
        speed_mps: 15.0,
        temperature_c: 40.0,
    };
    // Every extension the channel takes, away from neutral values; or (`start`) combined slip
    // where a fit starts it, with its optional terms at an exact 0 (a seeded derivative there
    // must not be lost where the model leaves out a term that is 0).
    let extension_values = |kind: Extension, start: bool| -> Vec<f64> {
        (0..kind.parameter_names().len())
            .map(|i| match kind {
                Extension::CombinedSlip if start => [
                    8.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 10.0,
                    0.0, 10.0, 0.5,
                ][i],
                Extension::CombinedSlip => [
                    6.0, 1.1, 3.0, 0.01, 2.0, 0.1, 0.02, 0.01, 0.002, 0.05, 0.01, 0.1, 2.0, 1.2,
                    8.0, 0.2, 3.0, 0.7,
                ][i],
                Extension::RelaxationLength => 0.3,
                Extension::Temperature => [0.2, 5.0, 0.05][i],
                Extension::SlipRatioShift => [0.01, 0.003, 0.02, -0.004][i],
                _ => 0.03 * (i as f64 + 1.0),
            })
            .collect()
    };
    // The output with coefficients `c` and extension parameters `q` (kinds in ALL order).
    fn output<T: Real>(
        channel: Channel,
        c: &[T],
        q: &[(Extension, Vec<T>)],
        nominal: &Nominal,
        x: [f64; 7],
    ) -> T {
        let mut ext = ChannelExtensions::<T>::default();
        for (kind, v) in q {
            ext.set(*kind, v).unwrap();
        }
        let [fz_kn, gamma, slip, other, speed, pressure, temperature] = x.map(T::from);
        let mf = factors(channel, c, fz_kn, gamma);
        let own_si = match channel {
            Channel::Fx => slip * 0.01,
            _ => slip * std::f64::consts::PI / 180.0,
        };
        let conditions = Conditions {
            fz_kn,
            gamma: gamma * std::f64::consts::PI / 180.0,
            own_slip: own_si,
            other_slip: other,
            speed,
            pressure,
            temperature,
        };
        ext.evaluate_factors(mf, nominal, slip, &conditions)
    }
    let params = Params::paper_table();
    let mut rng = Rng(7);
    let mut worst: f64 = 0.0;
    for (channel, start) in [Channel::Fx, Channel::Fy, Channel::Mz]
        .into_iter()
        .flat_map(|c| [(c, false), (c, true)])
    {
        let c: Vec<f64> = (0..Params::coefficient_names(channel).len())
            .map(|i| params.coefficient(channel, i).unwrap())
            .collect();
        let q: Vec<(Extension, Vec<f64>)> = Extension::ALL
            .into_iter()
            .filter(|k| k.applies_to(channel) && *k != Extension::RelaxationLength)
            .map(|k| (k, extension_values(k, start)))
            .collect();
        let n_q: usize = q.iter().map(|(_, v)| v.len()).sum();
        for _ in 0..200 {
            let x = [
                rng.uniform(1.0, 8.0),
                rng.uniform(-5.0, 5.0),
                rng.uniform(-12.0, 12.0),
                rng.uniform(-0.2, 0.2),
                rng.uniform(2.0, 40.0),
                rng.uniform(150.0, 260.0),
                rng.uniform(10.0, 90.0),
            ];
            for j in 0..c.len() + n_q {
                // Parameter j: a coefficient, or the (j - c.len())-th extension parameter.
                let lift =
                    |shift: f64, seed: bool| -> (Vec<Dual64>, Vec<(Extension, Vec<Dual64>)>) {
                        let mut k = 0;
                        let mut var = |v: f64| {
                            let d = if k == j {
                                let d = Dual64::from_re(v + shift);
                                if seed { d.derivative() } else { d }
                            } else {
                                Dual64::from_re(v)
                            };
                            k += 1;
                            d
                        };
                        let cd = c.iter().map(|&v| var(v)).collect();
                        let qd = q
                            .iter()
                            .map(|(kind, v)| (*kind, v.iter().map(|&v| var(v)).collect()))
                            .collect();
                        (cd, qd)
                    };
                let (cd, qd) = lift(0.0, true);
                let exact = output(channel, &cd, &qd, &nominal, x).eps;
                let value_of = |shift: f64| {
                    let (cd, qd) = lift(shift, false);
                    output(channel, &cd, &qd, &nominal, x).re
                };
                let h = 1e-6 * c.get(j).map_or(1.0, |v| v.abs().max(1.0));
                let central = (value_of(h) - value_of(-h)) / (2.0 * h);
                let error = (exact - central).abs() / exact.abs().max(1.0);
                worst = worst.max(error);
                assert!(
                    error < 1e-5,
                    "{channel} parameter {j} (start {start}) at {x:?}: exact {exact}, central {central}"
                );
            }
        }
    }
    eprintln!("worst relative error in the parameter derivatives: {worst:.1e}");
}
