//! The extensions by hand: each form, their order, the lag, the conditions' range, the
//! rejections and the parameter-file format.

use super::*;
use crate::channel::Channel;
use crate::evaluate::{evaluate, evaluate_extended};
use crate::interface::{Inputs, Outputs, SignConvention};
use crate::params::Params;
use crate::units;

const NOMINAL: Nominal = Nominal {
    pressure_kpa: 200.0,
    speed_mps: 10.0,
    temperature_c: 40.0,
};

/// The paper's table with `kind` = `values` on `channel` (optional parameters not given are
/// 0).
fn with(channel: Channel, kind: Extension, values: &[f64]) -> Params {
    let mut p = Params::paper_table();
    let mut ext = Extensions::new(NOMINAL, ConditionLimits::default());
    let mut values = values.to_vec();
    values.resize(kind.parameter_names().len(), 0.0);
    ext.channel_mut(channel).set(kind, &values).unwrap();
    p.extensions = Some(ext);
    p
}

fn inputs(fz: f64, alpha_deg: f64, kappa: f64, gamma_deg: f64) -> Inputs {
    Inputs {
        fz,
        alpha: alpha_deg.to_radians(),
        kappa,
        gamma: gamma_deg.to_radians(),
    }
}

/// vx [m/s], p [kPa], T [degC] as the SI conditions.
fn conditions(vx: f64, p_kpa: f64, t_c: f64) -> OperatingConditions {
    OperatingConditions {
        vx,
        p: units::kilopascals_to_pascals(p_kpa),
        t_tread: units::celsius_to_kelvin(t_c),
    }
}

fn extended(p: &Params, x: &Inputs, c: &OperatingConditions) -> Outputs {
    evaluate_extended(p, x, c, &LaggedSlip::steady(p, x), SignConvention::Paper)
}

fn base(p: &Params, x: &Inputs) -> Outputs {
    evaluate(p, x, SignConvention::Paper)
}

fn rel_close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1e-9)
}

fn of(o: &Outputs, channel: Channel) -> f64 {
    match channel {
        Channel::Fx => o.fx,
        Channel::Fy => o.fy,
        Channel::Mz => o.mz,
    }
}

#[test]
fn neutral_parameters_change_nothing() {
    let mut p = Params::paper_table();
    let mut ext = Extensions::new(NOMINAL, ConditionLimits::default());
    for channel in Channel::ALL {
        let e = ext.channel_mut(channel);
        e.combined_slip = Some(CombinedSlip {
            B: 8.0,
            C: 0.0,
            ..Default::default()
        });
        e.relaxation_length = Some(RelaxationLength { sigma_m: 0.0 });
        e.inflation_pressure = Some(InflationPressure {
            k: 0.0,
            d: 0.0,
            ..Default::default()
        });
        e.speed_dependence = Some(SpeedDependence { v: 0.0, w: 0.0 });
        e.temperature = Some(Temperature {
            w: 0.0,
            Topt_degC: 5.0,
            k: 0.0,
        });
        if channel == Channel::Fx {
            e.rolling_resistance = Some(RollingResistance { q1: 0.0, q2: 0.0 });
            e.slip_ratio_shift = Some(SlipRatioShift {
                Sh: 0.0,
                Sh_per_kN: 0.0,
                Sv: 0.0,
                Sv_per_kN: 0.0,
            });
        } else {
            e.ply_steer_conicity = Some(PlySteerConicity {
                Sh_deg: 0.0,
                Sv: 0.0,

                ..Default::default()
            });
        }
    }
    p.extensions = Some(ext);
    p.validate().unwrap();
    for x in [
        inputs(4000.0, 5.0, 0.1, 2.0),
        inputs(1500.0, -12.0, -0.4, -6.0),
        inputs(8000.0, 0.0, 0.0, 0.0),
        inputs(-10.0, 3.0, 0.0, 0.0),
    ] {
        for c in [conditions(25.0, 260.0, 80.0), conditions(-3.0, 150.0, 0.0)] {
            let lagged = LaggedSlip::steady(&p, &x).advanced(&p, &x, 0.7);
            let out = evaluate_extended(&p, &x, &c, &lagged, SignConvention::Iso);
            assert_eq!(out, evaluate(&p, &x, SignConvention::Iso));
        }
    }
}

#[test]
fn combined_slip_weighting_by_hand() {
    // cos(atan(z)) = 1 / sqrt(1 + z^2): B = 8, C = 1 at kappa = 0.1 weights Fy by 1/sqrt(1.64).
    let p = with(Channel::Fy, Extension::CombinedSlip, &[8.0, 1.0]);
    let x = inputs(4000.0, 4.0, 0.1, 0.0);
    let c = conditions(10.0, 200.0, 40.0);
    let (e, b) = (extended(&p, &x, &c), base(&p, &x));
    assert!(rel_close(e.fy, b.fy / 1.64f64.sqrt(), 1e-14), "{e:?} {b:?}");
    assert_eq!((e.fx, e.mz), (b.fx, b.mz), "other channels untouched");
    // Fx is weighted by the slip angle in rad: B = 5, alpha = 0.1 rad -> 1/sqrt(1.25).
    let p = with(Channel::Fx, Extension::CombinedSlip, &[5.0, 1.0]);
    let x = Inputs { alpha: 0.1, ..x };
    assert!(rel_close(
        extended(&p, &x, &c).fx,
        base(&p, &x).fx / 1.25f64.sqrt(),
        1e-14
    ));
}

#[test]
fn mf61_combined_slip_weighting_by_hand() {
    // Fy at 4 deg and kappa = 0.1 with MF 6.1's terms: Bw = (B + B_camber gamma^2)
    // cos(atan(B_slip (alpha - B_shift))), Ew = E + E_per_kN Fz, Sw = Sh + Sh_per_kN Fz,
    // G = g(x + Sw) / g(Sw), g(x) = cos(C atan(Bw x - Ew (Bw x - atan(Bw x)))).
    let q = [8.0, 1.1, 3.0, 0.02, 5.0, 0.2, 0.05, 0.01, 0.002];
    let p = with(Channel::Fy, Extension::CombinedSlip, &q);
    let (alpha, kappa, gamma, fz_kn) = (4f64.to_radians(), 0.1, 2f64.to_radians(), 4.0);
    let x = inputs(4000.0, 4.0, kappa, 2.0);
    let c = conditions(10.0, 200.0, 40.0);
    let bw = (8.0 + 5.0 * gamma * gamma) * (3.0 * (alpha - 0.02f64)).atan().cos();
    let (ew, sw) = (0.2 + 0.05 * fz_kn, 0.01 + 0.002 * fz_kn);
    let g = |x: f64| (1.1 * (bw * x - ew * (bw * x - (bw * x).atan())).atan()).cos();
    let want = base(&p, &x).fy * g(kappa + sw) / g(sw);
    assert!(rel_close(extended(&p, &x, &c).fy, want, 1e-13));
    // At zero slip ratio the weight is 1, whatever the shift.
    let pure = inputs(4000.0, 4.0, 0.0, 2.0);
    assert!(rel_close(
        extended(&p, &pure, &c).fy,
        base(&p, &pure).fy,
        1e-14
    ));
}

#[test]
fn the_lateral_force_the_slip_ratio_induces_by_hand() {
    // SVyk = D (Sv + Sv_per_kN Fz + Sv_camber gamma) cos(atan(Sv_alpha alpha))
    // sin(Sv_shape atan(Sv_slope kappa)), added to the weighted Fy (B = 0: weight 1).
    let mut q = vec![0.0; 15];
    q[1] = 1.0;
    q[9..15].copy_from_slice(&[0.05, 0.01, 0.3, 2.0, 1.2, 8.0]);
    let p = with(Channel::Fy, Extension::CombinedSlip, &q);
    let x = inputs(3000.0, 3.0, -0.08, 1.5);
    let c = conditions(10.0, 200.0, 40.0);
    let d = crate::evaluate::channel_factors(&p, Channel::Fy, 3.0, 1.5).d;
    let (alpha, gamma) = (3f64.to_radians(), 1.5f64.to_radians());
    let sv = d
        * (0.05 + 0.01 * 3.0 + 0.3 * gamma)
        * (2.0 * alpha).atan().cos()
        * (1.2 * (8.0 * -0.08f64).atan()).sin();
    assert!(rel_close(
        extended(&p, &x, &c).fy,
        base(&p, &x).fy + sv,
        1e-13
    ));
    // It belongs to Fy and Mz: on Fx it is refused, naming the parameter.
    let err = combined_slip_rejected(Channel::Fx, |c| c.Sv_camber = 0.2);
    assert!(
        err.contains("extensions.Fx.combined_slip.Sv_camber") && err.contains("Fy and Mz only"),
        "{err}"
    );
}

#[test]
fn the_equivalent_slip_of_mz_by_hand() {
    // Mz's curve at alpha_eq = sqrt((alpha + Sh)^2 + (K_eq kappa)^2) [deg], scaled by
    // (alpha + Sh) / alpha_eq (B = 0: weight 1).
    let mut q = vec![0.0; 18];
    q[1] = 1.0;
    q[17] = 0.8;
    let p = with(Channel::Mz, Extension::CombinedSlip, &q);
    let c = conditions(10.0, 200.0, 40.0);
    let f = crate::evaluate::channel_factors(&p, Channel::Mz, 3.0, 1.0);
    let curve = |x: f64| {
        let phi = (1.0 - f.e) * x + f.e / f.b * (f.b * x).atan();
        f.d * (f.c * (f.b * phi).atan()).sin()
    };
    for (alpha_deg, kappa) in [(3.0, -0.08), (-3.0, 0.08), (0.5, 0.2), (0.0, 0.1)] {
        let x = inputs(3000.0, alpha_deg, kappa, 1.0);
        let s = alpha_deg + f.sh;
        let o = f64::to_degrees(0.8) * kappa;
        let eq = s.hypot(o);
        let want = s / eq * curve(eq) + f.sv;
        assert!(
            rel_close(extended(&p, &x, &c).mz, want, 1e-12),
            "alpha {alpha_deg} kappa {kappa}: {} against {want}",
            extended(&p, &x, &c).mz
        );
    }
    // At zero slip ratio it is the pure moment.
    let pure = inputs(3000.0, 3.0, 0.0, 1.0);
    assert!(rel_close(
        extended(&p, &pure, &c).mz,
        base(&p, &pure).mz,
        1e-14
    ));
    // On Fy it is refused, and beyond its range.
    let err = combined_slip_rejected(Channel::Fy, |c| c.K_eq = 0.5);
    assert!(
        err.contains("Fy.combined_slip.K_eq") && err.contains("Mz only"),
        "{err}"
    );
    let err = combined_slip_rejected(Channel::Mz, |c| c.K_eq = -0.5);
    assert!(
        err.contains("Mz.combined_slip.K_eq") && err.contains("[0, 5] rad"),
        "{err}"
    );
}

#[test]
fn the_narrowing_is_centred_within_the_swept_slip() {
    for (b_shift, refused) in [(1.5, false), (-0.5, false), (1.6, true), (-119033.0, true)] {
        let mut p = Params::paper_table();
        let mut ext = Extensions::new(NOMINAL, ConditionLimits::default());
        ext.Fy.combined_slip = Some(CombinedSlip {
            B: 10.0,
            C: 1.0,
            B_slip: 5.0,
            B_shift: b_shift,
            ..Default::default()
        });
        p.extensions = Some(ext);
        match p.validate() {
            Err(e) => {
                let e = e.to_string();
                assert!(refused, "B_shift {b_shift}: {e}");
                assert!(
                    e.contains("Fy.combined_slip.B_shift") && e.contains("+-pi/2 rad on Fy"),
                    "{e}"
                );
            }
            Ok(()) => assert!(!refused, "B_shift {b_shift} accepted"),
        }
    }
}

#[test]
fn the_moment_of_fx_about_the_deflected_patch_by_hand() {
    // On Mz: D (Sv cos(atan(Sv_alpha alpha)) + Sm sin(atan(Sm_alpha alpha)))
    // sin(Sv_shape atan(Sv_slope kappa)), added to the weighted Mz (B = 0: weight 1); odd in
    // alpha and in kappa where Sv is 0.
    let mut q = vec![0.0; 18];
    q[1] = 1.0;
    q[9] = 0.04;
    q[13..17].copy_from_slice(&[1.1, 9.0, -0.3, 5.0]);
    let p = with(Channel::Mz, Extension::CombinedSlip, &q);
    let c = conditions(10.0, 200.0, 40.0);
    for (alpha_deg, kappa) in [(3.0, -0.08), (-3.0, -0.08), (3.0, 0.08), (-6.0, 0.2)] {
        let x = inputs(3000.0, alpha_deg, kappa, 0.0);
        let d = crate::evaluate::channel_factors(&p, Channel::Mz, 3.0, 0.0).d;
        let alpha = f64::to_radians(alpha_deg);
        let term =
            d * (0.04 + -0.3 * (5.0 * alpha).atan().sin()) * (1.1 * (9.0 * kappa).atan()).sin();
        assert!(
            rel_close(extended(&p, &x, &c).mz, base(&p, &x).mz + term, 1e-13),
            "alpha {alpha_deg} kappa {kappa}"
        );
    }
    // The moment belongs to Mz: on Fy it is refused, naming the parameter.
    let err = combined_slip_rejected(Channel::Fy, |c| c.Sm = 0.2);
    assert!(
        err.contains("extensions.Fy.combined_slip.Sm") && err.contains("Mz only"),
        "{err}"
    );
    // Beyond its bound it is refused too.
    let err = combined_slip_rejected(Channel::Mz, |c| c.Sm = 3.5);
    assert!(
        err.contains("extensions.Mz.combined_slip.Sm") && err.contains("at most 3"),
        "{err}"
    );
}

#[test]
fn mf61_pressure_terms_camber_on_the_peak_and_load_dependent_shifts_by_hand() {
    let c = conditions(10.0, 260.0, 40.0);
    let dp: f64 = (260.0 - 200.0) / 200.0;
    let x = inputs(4000.0, 3.0, 0.05, 2.0);
    let base_f = crate::evaluate::channel_factors(&Params::paper_table(), Channel::Fy, 4.0, 2.0);
    // Pressure: stiffness 1 + (k + k_per_kN Fz) dp + k2 dp^2, peak 1 + d dp + d2 dp^2.
    let p = with(
        Channel::Fy,
        Extension::InflationPressure,
        &[0.3, -0.2, 0.4, 0.5, 0.05],
    );
    let (sk, sd) = (
        1.0 + (0.3 + 0.05 * 4.0) * dp + 0.4 * dp * dp,
        1.0 - 0.2 * dp + 0.5 * dp * dp,
    );
    let mut mf = base_f;
    mf.d *= sd;
    mf.b *= sk / sd;
    assert!(rel_close(extended(&p, &x, &c).fy, mf.eval(3.0), 1e-13));
    // Camber on the peak: D (1 - d gamma^2), BCD kept.
    let p = with(Channel::Fy, Extension::CamberPeak, &[4.0]);
    let s = 1.0 - 4.0 * 2f64.to_radians().powi(2);
    let mut mf = base_f;
    mf.d *= s;
    mf.b /= s;
    assert!(rel_close(extended(&p, &x, &c).fy, mf.eval(3.0), 1e-13));
    // Shifts with their load terms: Sh += Sh_deg + (Sh_per_kN + Sh_camber_per_kN gamma) Fz,
    // Sv += Sv + Sv_per_kN Fz.
    let p = with(
        Channel::Fy,
        Extension::PlySteerConicity,
        &[0.2, 30.0, 0.05, 10.0, 0.02],
    );
    let mut mf = base_f;
    mf.sh += 0.2 + (0.05 + 0.02 * 2.0) * 4.0;
    mf.sv += 30.0 + 10.0 * 4.0;
    assert!(rel_close(extended(&p, &x, &c).fy, mf.eval(3.0), 1e-13));
    // Camber lowers the peak only.
    let err = rejected(|e| e.Fx.camber_peak = Some(CamberPeak { d: -1.0 }));
    assert!(
        err.contains("extensions.Fx.camber_peak.d") && err.contains(">= 0"),
        "{err}"
    );
}

#[test]
fn peak_and_stiffness_scales_by_hand() {
    // Scaling D by s_d and BCD by s_k equals scaling the coefficients D and BCD are
    // linear in: a1, a2 by s_d; a3 (Fy) or a3, a4 (Mz, Fx) by s_k.
    let x = inputs(4500.0, 3.0, 0.05, 1.5);
    let scaled = |s_k: f64, s_d: f64| {
        let mut p = Params::paper_table();
        for c in [&mut p.Fy, &mut p.Mz] {
            (c.a1, c.a2) = (c.a1 * s_d, c.a2 * s_d);
        }
        (p.Fx.a1, p.Fx.a2) = (p.Fx.a1 * s_d, p.Fx.a2 * s_d);
        p.Fy.a3 *= s_k;
        (p.Mz.a3, p.Mz.a4) = (p.Mz.a3 * s_k, p.Mz.a4 * s_k);
        (p.Fx.a3, p.Fx.a4) = (p.Fx.a3 * s_k, p.Fx.a4 * s_k);
        base(&p, &x)
    };
    // Pressure: p0 = 200, p = 250 kPa -> dp = 0.25; k = 0.4, d = -0.2: s_k = 1.1, s_d = 0.95.
    // Speed: V0 = 10, V = 30 m/s -> dV = 2; v = -0.1: s_d = 0.8; with w = 0.03 as well,
    // s_d = 1 - 0.2 + 0.03 * 4 = 0.92.
    // Temperature: T0 = 40, Topt = 10, T = 80 degC; w = 0.3, k = 0.2: window (80 - 50) / 50
    // = 0.6, q = 0.36, s_d = 1 - 0.3 * 0.36 / 1.36 = 0.920588...; dt = 0.8, s_k = 1.16.
    let cases: [(Extension, &[f64], f64, f64); 4] = [
        (Extension::InflationPressure, &[0.4, -0.2], 1.1, 0.95),
        (Extension::SpeedDependence, &[-0.1], 1.0, 0.8),
        (Extension::SpeedDependence, &[-0.1, 0.03], 1.0, 0.92),
        (
            Extension::Temperature,
            &[0.3, 10.0, 0.2],
            1.16,
            1.0 - 0.3 * 0.36 / 1.36,
        ),
    ];
    let c = conditions(30.0, 250.0, 80.0);
    for (kind, values, s_k, s_d) in cases {
        let expected = scaled(s_k, s_d);
        for channel in Channel::ALL {
            let got = extended(&with(channel, kind, values), &x, &c);
            let (g, e) = (of(&got, channel), of(&expected, channel));
            assert!(rel_close(g, e, 1e-12), "{kind} on {channel}: {g} vs {e}");
        }
    }
    // Far from the optimum the window levels off toward 1 - w: at T = 120 degC it is 1.4,
    // q = 1.96, s_d = 1 - 0.3 * 1.96 / 2.96 = 0.80135 (a parabola would give 0.412); dt = 1.6,
    // s_k = 1.32.
    let far = conditions(30.0, 250.0, 120.0);
    let expected = scaled(1.32, 1.0 - 0.3 * 1.96 / 2.96);
    for channel in Channel::ALL {
        let p = with(channel, Extension::Temperature, &[0.3, 10.0, 0.2]);
        let (g, e) = (of(&extended(&p, &x, &far), channel), of(&expected, channel));
        assert!(
            rel_close(g, e, 1e-12),
            "temperature on {channel}: {g} vs {e}"
        );
    }
}

#[test]
fn ply_steer_and_rolling_resistance_by_hand() {
    // Sh_deg = 0.5 shifts the slip angle by 0.5 deg, Sv = -100 N moves Fy down.
    let p = with(Channel::Fy, Extension::PlySteerConicity, &[0.5, -100.0]);
    let x = inputs(4000.0, 2.0, 0.0, 1.0);
    let c = conditions(10.0, 200.0, 40.0);
    let shifted = base(&p, &inputs(4000.0, 2.5, 0.0, 1.0));
    assert!(rel_close(
        extended(&p, &x, &c).fy,
        shifted.fy - 100.0,
        1e-12
    ));
    // q1 = 0.012, q2 = 0.004 at V = 20 m/s, V0 = 10: (0.012 + 0.008) 4000 N = 80 N.
    let p = with(Channel::Fx, Extension::RollingResistance, &[0.012, 0.004]);
    let x = inputs(4000.0, 0.0, 0.03, 0.0);
    let c = conditions(20.0, 200.0, 40.0);
    assert!(rel_close(
        extended(&p, &x, &c).fx,
        base(&p, &x).fx - 80.0,
        1e-14
    ));
    // Reversing uses |vx|.
    let reverse = conditions(-20.0, 200.0, 40.0);
    assert_eq!(extended(&p, &x, &reverse), extended(&p, &x, &c));
}

#[test]
fn slip_ratio_shift_vertical_by_hand() {
    // Sv = 0.05, Sv_per_kN = -0.01: at 4 kN Fx gains (0.05 - 0.04) x 4000 N = 40 N at every
    // slip; Fy and Mz stay.
    let p = with(
        Channel::Fx,
        Extension::SlipRatioShift,
        &[0.0, 0.0, 0.05, -0.01],
    );
    let c = conditions(10.0, 200.0, 40.0);
    for kappa in [-0.3, -0.05, 0.0, 0.02, 0.1, 0.5] {
        let x = inputs(4000.0, 2.0, kappa, 1.0);
        let (with_shift, without) = (extended(&p, &x, &c), base(&p, &x));
        assert!(
            (with_shift.fx - without.fx - 40.0).abs() < 1e-9,
            "kappa = {kappa}: {} vs {}",
            with_shift.fx,
            without.fx
        );
        assert_eq!([with_shift.fy, with_shift.mz], [without.fy, without.mz]);
    }
    // At 1 kN: (0.05 - 0.01) x 1000 N.
    let x = inputs(1000.0, 0.0, 0.05, 0.0);
    assert!((extended(&p, &x, &c).fx - base(&p, &x).fx - 40.0).abs() < 1e-9);
}

#[test]
fn slip_ratio_shift_by_hand() {
    // Sh = 0.012, Sh_per_kN = 0.002: at 4 kN the curve is read at kappa + 0.02.
    let p = with(Channel::Fx, Extension::SlipRatioShift, &[0.012, 0.002]);
    let c = conditions(10.0, 200.0, 40.0);
    let at = |fz: f64, kappa: f64| extended(&p, &inputs(fz, 0.0, kappa, 0.0), &c).fx;
    // At kappa = -0.02 it is read at its own zero, where Fx is 0: free rolling reads as slip.
    assert!(at(4000.0, -0.02).abs() < 1e-9, "{}", at(4000.0, -0.02));
    // At kappa = 0.08 it is read at 10 %: docs/errata.md's reference value, 4234.444513 N.
    assert!(rel_close(at(4000.0, 0.08), 4234.444513, 1e-9));
    // At zero slip: the unshifted force at 2 %, below the slip stiffness BCD times 2 % (the
    // curve bends towards its peak) but not far.
    let bcd = (49.6 * 16.0 + 226.0 * 4.0) * (-0.069f64 * 4.0).exp();
    let at_zero = at(4000.0, 0.0);
    assert!(rel_close(
        at_zero,
        base(&p, &inputs(4000.0, 0.0, 0.02, 0.0)).fx,
        1e-12
    ));
    assert!((0.8 * 2.0 * bcd..2.0 * bcd).contains(&at_zero), "{at_zero}");
    // The slope at the shifted zero is the unshifted one at zero: BCD [N/percent] x 100.
    let h = 1e-6;
    let slope = (at(4000.0, -0.02 + h) - at(4000.0, -0.02 - h)) / (2.0 * h);
    assert!(
        rel_close(slope, 100.0 * bcd, 1e-6),
        "{slope} vs {}",
        100.0 * bcd
    );
    // At 2500 N the shift is 0.012 + 0.005 = 0.017.
    let x = inputs(2500.0, 3.0, 0.05, 1.0);
    let (e, b) = (
        extended(&p, &x, &c),
        base(&p, &inputs(2500.0, 3.0, 0.067, 1.0)),
    );
    assert!(rel_close(e.fx, b.fx, 1e-12), "{} vs {}", e.fx, b.fx);
    assert_eq!(
        (e.fy, e.mz),
        (base(&p, &x).fy, base(&p, &x).mz),
        "Fy, Mz untouched"
    );
    // A lifted wheel has no force.
    assert_eq!(at(0.0, 0.03), 0.0);
    // Rolling resistance is subtracted from the shifted curve: -0.01 x 4000 N at its zero.
    let mut both = p.clone();
    let ext = both.extensions.as_mut().unwrap();
    ext.Fx.rolling_resistance = Some(RollingResistance { q1: 0.01, q2: 0.0 });
    let x = inputs(4000.0, 0.0, -0.02, 0.0);
    assert!((extended(&both, &x, &c).fx + 40.0).abs() < 1e-9);
}

#[test]
fn weighting_comes_before_rolling_resistance() {
    let mut p = with(Channel::Fx, Extension::RollingResistance, &[0.01, 0.0]);
    let ext = p.extensions.as_mut().unwrap();
    ext.Fx.combined_slip = Some(CombinedSlip {
        B: 2.0,
        C: 1.0,
        ..Default::default()
    });
    let x = Inputs {
        alpha: 0.5,
        ..inputs(3000.0, 0.0, 0.04, 0.0)
    };
    let c = conditions(10.0, 200.0, 40.0);
    // G = 1 / sqrt(1 + 1) at B alpha = 1; rolling resistance 0.01 * 3000 N.
    let expected = base(&p, &x).fx / 2f64.sqrt() - 30.0;
    assert!(rel_close(extended(&p, &x, &c).fx, expected, 1e-14));
}

#[test]
fn relaxation_lag_is_the_first_order_response() {
    // A slip step from 0 to s: after distance x the lag is s (1 - exp(-x / sigma)), in any
    // number of steps.
    let (s, sigma) = (0.08, 0.45);
    let mut lagged = 0.0;
    for k in 1..=40 {
        lagged = relaxation_step(lagged, s, 0.025, sigma);
        let x = 0.025 * k as f64;
        assert!(rel_close(lagged, s * (1.0 - (-x / sigma).exp()), 1e-13));
    }
    assert_eq!(
        relaxation_step(0.3, 0.1, 1.0, 0.0),
        0.1,
        "sigma = 0: no lag"
    );

    // Through the parameter set: Fy relaxes, Mz (no relaxation length) follows at once.
    let p = with(Channel::Fy, Extension::RelaxationLength, &[sigma]);
    let still = inputs(4000.0, 0.0, 0.0, 0.0);
    let moved = inputs(4000.0, 4.0, 0.0, 0.0);
    let lag = LaggedSlip::steady(&p, &still).advanced(&p, &moved, 0.3);
    let expected_alpha = moved.alpha * (1.0 - (-0.3f64 / sigma).exp());
    assert!(rel_close(lag.fy, expected_alpha, 1e-13));
    assert_eq!((lag.mz, lag.fx), (moved.alpha, 0.0));
    let c = conditions(10.0, 200.0, 40.0);
    let out = evaluate_extended(&p, &moved, &c, &lag, SignConvention::Paper);
    let at_lag = base(
        &p,
        &Inputs {
            alpha: expected_alpha,
            ..moved
        },
    );
    assert!(rel_close(out.fy, at_lag.fy, 1e-12));
    assert_eq!(out.mz, base(&p, &moved).mz);
}

#[test]
fn conditions_are_clamped_to_the_range() {
    let p = with(Channel::Fx, Extension::SpeedDependence, &[-0.1]);
    let x = inputs(4000.0, 0.0, 0.1, 0.0);
    let top = conditions(70.0, 200.0, 40.0);
    assert_eq!(
        extended(&p, &x, &conditions(95.0, 200.0, 40.0)),
        extended(&p, &x, &top)
    );
    let l = ConditionLimits::default();
    assert_eq!(ConditionVar::Speed.used_value(-95.0, &l), 70.0);
    assert!(ConditionVar::Speed.in_range(-30.0, &l) && !ConditionVar::Speed.in_range(-95.0, &l));
    assert_eq!(
        ConditionVar::Pressure.valid_range(&l),
        (100_000.0, 400_000.0)
    );
    assert_eq!(ConditionVar::Pressure.used_value(50_000.0, &l), 100_000.0);
    let (t_lo, _) = ConditionVar::Temperature.valid_range(&l);
    assert!((t_lo - 253.15).abs() < 1e-12);
}

/// The validation error of combined slip on `channel` with `B` and `C` 1 and `edit`'s values.
fn combined_slip_rejected(channel: Channel, edit: impl FnOnce(&mut CombinedSlip)) -> String {
    rejected(|e| {
        let mut c = CombinedSlip {
            B: 1.0,
            C: 1.0,
            ..Default::default()
        };
        edit(&mut c);
        e.channel_mut(channel).combined_slip = Some(c);
    })
}

fn rejected(edit: impl FnOnce(&mut Extensions)) -> String {
    let mut p = Params::paper_table();
    let mut ext = Extensions::new(NOMINAL, ConditionLimits::default());
    edit(&mut ext);
    p.extensions = Some(ext);
    p.validate().unwrap_err().to_string()
}

#[test]
fn bad_values_are_rejected_with_name_value_and_range() {
    let msg = rejected(|e| e.Fy.relaxation_length = Some(RelaxationLength { sigma_m: -0.1 }));
    assert!(
        msg.contains("extensions.Fy.relaxation_length.sigma_m = -0.1")
            && msg.contains("must be 0 (no lag) or lie in [0.001, 5] m"),
        "{msg}"
    );
    let msg = rejected(|e| {
        e.Fx.rolling_resistance = Some(RollingResistance {
            q1: 0.01,
            q2: f64::NAN,
        })
    });
    assert!(
        msg.contains("extensions.Fx.rolling_resistance.q2 = NaN"),
        "{msg}"
    );
    let msg = rejected(|e| e.nominal.pressure_kpa = 0.0);
    assert!(
        msg.contains("extensions.nominal.pressure_kPa = 0")
            && msg.contains("must lie in [10, 2000] kPa"),
        "{msg}"
    );
    let msg = rejected(|e| e.nominal.speed_mps = f64::INFINITY);
    assert!(msg.contains("extensions.nominal.speed_mps = inf"), "{msg}");
    let msg = rejected(|e| e.limits.pressure_max_kPa = 50.0);
    assert!(
        msg.contains("extensions.limits.pressure_max_kPa = 50")
            && msg.contains(">= pressure_min_kPa = 100"),
        "{msg}"
    );
    let msg = rejected(|e| {
        e.Fx.ply_steer_conicity = Some(PlySteerConicity {
            Sh_deg: 0.1,
            Sv: 0.0,

            ..Default::default()
        })
    });
    assert!(
        msg.contains("extensions.Fx.ply_steer_conicity.Sh_deg = 0.1")
            && msg.contains("only to Fy, Mz"),
        "{msg}"
    );
    let msg = rejected(|e| e.Mz.rolling_resistance = Some(RollingResistance { q1: 0.0, q2: 0.0 }));
    assert!(msg.contains("does not apply to Mz (only to Fx)"), "{msg}");
    let msg = rejected(|e| e.Mz.camber_peak = Some(CamberPeak { d: 1.0 }));
    assert!(
        msg.contains("extensions.Mz.camber_peak.d = 1")
            && msg.contains("does not apply to Mz (only to Fy, Fx)"),
        "{msg}"
    );
    let shift = |sh: f64, per_kn: f64| {
        Some(SlipRatioShift {
            Sh: sh,
            Sh_per_kN: per_kn,
            ..Default::default()
        })
    };
    let msg = rejected(|e| e.Fy.slip_ratio_shift = shift(0.01, 0.0));
    assert!(
        msg.contains("extensions.Fy.slip_ratio_shift.Sh = 0.01")
            && msg.contains("does not apply to Fy (only to Fx)"),
        "{msg}"
    );
    let msg = rejected(|e| e.Fx.slip_ratio_shift = shift(-0.06, 0.0));
    assert!(
        msg.contains("extensions.Fx.slip_ratio_shift.Sh = -0.06")
            && msg.contains("is 0.06 as Fz -> 0; it must be at most 0.05"),
        "{msg}"
    );
    // fz_max = 10 kN: 0.01 + 0.0045 x 10 = 0.055 at the top of the load range.
    let msg = rejected(|e| e.Fx.slip_ratio_shift = shift(0.01, 0.0045));
    assert!(
        msg.contains("extensions.Fx.slip_ratio_shift.Sh_per_kN = 0.0045")
            && msg.contains("at Fz = 10000 N; it must be at most 0.05"),
        "{msg}"
    );
    // The vertical shift: 0.45 of the load as it vanishes; 0.1 + 0.031 x 10 = 0.41 at the top.
    let vertical = |sv: f64, per_kn: f64| {
        Some(SlipRatioShift {
            Sv: sv,
            Sv_per_kN: per_kn,
            ..Default::default()
        })
    };
    let msg = rejected(|e| e.Fx.slip_ratio_shift = vertical(-0.45, 0.0));
    assert!(
        msg.contains("extensions.Fx.slip_ratio_shift.Sv = -0.45")
            && msg.contains("as Fz -> 0; it must be at most 0.4"),
        "{msg}"
    );
    let msg = rejected(|e| e.Fx.slip_ratio_shift = vertical(0.1, 0.031));
    assert!(
        msg.contains("extensions.Fx.slip_ratio_shift.Sv_per_kN = 0.031")
            && msg.contains("at Fz = 10000 N; it must be at most 0.4"),
        "{msg}"
    );
    let msg = rejected(|e| e.Fx.slip_ratio_shift = shift(f64::INFINITY, 0.0));
    assert!(
        msg.contains("extensions.Fx.slip_ratio_shift.Sh = inf")
            && msg.contains("must be a finite number"),
        "{msg}"
    );
    // A shift that changes sign over the load range stays within the bound at both ends.
    let mut p = Params::paper_table();
    let mut ext = Extensions::new(NOMINAL, ConditionLimits::default());
    ext.Fx.slip_ratio_shift = shift(-0.04, 0.008);
    p.extensions = Some(ext);
    p.validate().unwrap();
}

#[test]
fn scales_must_stay_positive_over_the_range() {
    // p0 = 200 kPa, up to 400 kPa: dp = 1, so d = -3 gives a peak scale of -2 there.
    let msg = rejected(|e| {
        e.Fy.inflation_pressure = Some(InflationPressure {
            k: 0.0,
            d: -3.0,
            ..Default::default()
        })
    });
    assert!(
        msg.contains("extensions.Fy.inflation_pressure.d = -3")
            && msg.contains("peak D is -2 at p = 400 kPa")
            && msg.contains("range [100, 400] kPa"),
        "{msg}"
    );
    // At 100 kPa dp = -0.5: k = 2.5 makes the stiffness scale -0.25.
    let msg = rejected(|e| {
        e.Mz.inflation_pressure = Some(InflationPressure {
            k: 2.5,
            d: 0.0,
            ..Default::default()
        })
    });
    assert!(
        msg.contains("extensions.Mz.inflation_pressure.k = 2.5")
            && msg.contains("stiffness BCD is -0.25 at p = 100 kPa"),
        "{msg}"
    );
    // V0 = 10 m/s, down to 0: dV = -1, so v = 1 makes the peak vanish at standstill.
    let msg = rejected(|e| e.Fx.speed_dependence = Some(SpeedDependence { v: 1.0, w: 0.0 }));
    assert!(
        msg.contains("extensions.Fx.speed_dependence.v = 1") && msg.contains("V = 0 m/s"),
        "{msg}"
    );
    // A quadratic's lowest point inside the range: v = -1, w = 0.25 has its vertex at
    // dV = 2 (V = 30 m/s), where the peak scale is 1 - 2 + 1 = 0, though it is 1 at V0
    // and 2 at 0 m/s.
    let msg = rejected(|e| e.Fy.speed_dependence = Some(SpeedDependence { v: -1.0, w: 0.25 }));
    assert!(
        msg.contains("extensions.Fy.speed_dependence.v = -1")
            && msg.contains("peak D is 0 at V = 30 m/s"),
        "{msg}"
    );
    // T0 = 40, Topt = 0: at 120 degC the window is 1.6, q = 2.56, 1 - 2 * 2.56 / 3.56 =
    // -0.438 (the smallest).
    let msg = rejected(|e| {
        e.Fy.temperature = Some(Temperature {
            w: 2.0,
            Topt_degC: 0.0,
            k: 0.0,
        })
    });
    assert!(
        msg.contains("extensions.Fy.temperature.w = 2")
            && msg.contains("peak D is -0.438")
            && msg.contains("T = 120 degC"),
        "{msg}"
    );
    // A narrower range makes the same values valid.
    let mut p = Params::paper_table();
    let mut ext = Extensions::new(NOMINAL, ConditionLimits::default());
    (
        ext.limits.temperature_min_degC,
        ext.limits.temperature_max_degC,
    ) = (10.0, 80.0);
    ext.Fy.temperature = Some(Temperature {
        w: 2.0,
        Topt_degC: 0.0,
        k: 0.0,
    });
    p.extensions = Some(ext);
    p.validate().unwrap();
}

#[test]
fn parameter_file_format() {
    let text = r#"{
        "Fy": { "C": 1.3, "a1": -22.1, "a2": 1011.0, "a3": 1078.0, "a4": 1.82, "a5": 0.208,
                "a6": 0.0, "a7": -0.354, "a8": 0.707, "a9": 0.028, "a10": 0.0, "a11": 14.8,
                "a12": 0.022, "a13": 0.0 },
        "Mz": { "C": 2.4, "a1": -2.72, "a2": -2.28, "a3": -1.86, "a4": -2.73, "a5": 0.11,
                "a6": -0.07, "a7": 0.643, "a8": -4.04, "a9": 0.015, "a10": -0.066,
                "a11": 0.945, "a12": 0.03, "a13": 0.07 },
        "Fx": { "C": 1.65, "a1": -21.3, "a2": 1144.0, "a3": 49.6, "a4": 226.0, "a5": 0.069,
                "a6": -0.006, "a7": 0.056, "a8": 0.486 },
        "limits": { "fz_max_N": 10000.0, "gamma_max_deg": 10.0 },
        "extensions": {
            "nominal": { "pressure_kPa": 220.0, "speed_mps": 15.0, "temperature_degC": 45.0 },
            "Fy": { "combined_slip": { "B": 9.0, "C": 1.1 },
                    "relaxation_length": { "sigma_m": 0.4 } },
            "Fx": { "rolling_resistance": { "q1": 0.011, "q2": 0.002 },
                    "slip_ratio_shift": { "Sh": -0.012, "Sh_per_kN": 0.001 } }
        }
    }"#;
    let p = Params::from_json(text).unwrap();
    let ext = p.extensions.as_ref().unwrap();
    assert_eq!(ext.limits, ConditionLimits::default(), "limits default");
    assert_eq!(
        ext.Fy.combined_slip,
        Some(CombinedSlip {
            B: 9.0,
            C: 1.1,
            ..Default::default()
        })
    );
    assert_eq!(ext.Fy.relaxation_length_m(), Some(0.4));
    assert_eq!(
        ext.Fx.slip_ratio_shift,
        Some(SlipRatioShift {
            Sh: -0.012,
            Sh_per_kN: 0.001,
            ..Default::default()
        })
    );
    assert!(ext.Mz.is_empty() && ext.has_relaxation());
    assert!(ext.uses(ConditionVar::Speed) && !ext.uses(ConditionVar::Pressure));
    assert_eq!(Params::from_json(&p.to_json()).unwrap(), p, "round trip");
    let json: serde_json::Value = serde_json::from_str(&p.to_json()).unwrap();
    assert!(
        json["extensions"].get("Mz").is_none(),
        "empty channels are left out"
    );
    assert_eq!(json["extensions"]["nominal"]["temperature_degC"], 45.0);
    let summary = ext.to_string();
    assert!(summary.starts_with("Fy: combined_slip (B = 9, C = 1.1), relaxation_length (sigma_m = 0.4); Fx: rolling_resistance"), "{summary}");

    // The paper's table has none, and writes none.
    assert!(Params::paper_table().extensions.is_none());
    assert!(!Params::paper_table().to_json().contains("extensions"));

    // Unknown or missing names are rejected, naming them.
    for (bad, word) in [
        (text.replace("\"sigma_m\"", "\"sigma\""), "sigma"),
        (
            text.replace("\"combined_slip\"", "\"combined\""),
            "combined",
        ),
        (
            text.replace("\"q2\": 0.002", "\"q2\": 0.002, \"q3\": 1"),
            "q3",
        ),
        (
            text.replace("\"temperature_degC\": 45.0", "\"T\": 45.0"),
            "T",
        ),
    ] {
        let err = Params::from_json(&bad).unwrap_err().to_string();
        assert!(err.contains(word), "{word}: {err}");
    }
}

#[test]
fn kinds_names_and_setters_agree() {
    let ids: Vec<&str> = Extension::ALL.iter().map(|k| k.name()).collect();
    assert_eq!(
        ids,
        [
            "combined_slip",
            "relaxation_length",
            "inflation_pressure",
            "speed_dependence",
            "ply_steer_conicity",
            "rolling_resistance",
            "temperature",
            "slip_ratio_shift",
            "camber_peak"
        ]
    );
    // from_name() inverts name(), serde writes and reads it, and the parameter
    // file's field of each kind is its name.
    assert_eq!(Extension::NAMES.to_vec(), ids);
    for kind in Extension::ALL {
        assert_eq!(kind.to_string(), kind.name());
        assert_eq!(Extension::from_name(kind.name()), Some(kind));
        let json = serde_json::to_string(&kind).unwrap();
        assert_eq!(json, format!("\"{}\"", kind.name()));
        assert_eq!(serde_json::from_str::<Extension>(&json).unwrap(), kind);
        let mut e = ChannelExtensions::default();
        e.set(kind, &vec![0.0; kind.parameter_names().len()])
            .unwrap();
        let fields = serde_json::to_value(e).unwrap();
        assert!(fields.get(kind.name()).is_some(), "{fields}");
    }
    assert_eq!(Extension::from_name("combined"), None);
    let err = serde_json::from_str::<Extension>("\"combined\"").unwrap_err();
    assert!(err.to_string().contains("combined_slip"), "{err}");
    let mut e = ChannelExtensions::default();
    for (i, kind) in Extension::ALL.iter().enumerate() {
        let values: Vec<f64> = (0..kind.parameter_names().len())
            .map(|j| (10 * i + j) as f64)
            .collect();
        e.set(*kind, &values).unwrap();
        assert_eq!(e.get(*kind), Some(values));
    }
    assert_eq!(e.kinds().count(), Extension::ALL.len());
    let err = e
        .set(Extension::Temperature, &[1.0])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("temperature takes 3 parameters (w, Topt_degC, k), not 1"),
        "{err}"
    );
}
