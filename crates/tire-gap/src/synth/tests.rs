//! Tests of the synthetic data generator.

use std::ops::Range;

use super::blocks::{Block, BlockKind};
use super::*;
use crate::data::Quantity;

fn cfg(seed: u64, effects: &[Extension], tire: TireKind, noise: f64) -> SynthConfig {
    SynthConfig {
        seed,
        effects: effects.to_vec(),
        tire,
        rows_target: DEFAULT_ROWS,
        noise,
        ..SynthConfig::default()
    }
}

/// Each block with its rows in the dataset.
fn block_rows(sim: &Simulation) -> Vec<(Block, Range<usize>)> {
    let mut start = 0;
    sim.blocks
        .iter()
        .map(|b| {
            let r = start..start + b.n;
            start += b.n;
            assert!(sim.dataset.run[r.clone()].iter().all(|&run| run == b.run));
            (*b, r)
        })
        .collect()
}

fn col(ds: &Dataset, q: Quantity) -> &[f64] {
    ds.column(q).expect("column present")
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

fn std(v: &[f64]) -> f64 {
    let m = mean(v);
    (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
}

fn corr(a: &[f64], b: &[f64]) -> f64 {
    let (ma, mb) = (mean(a), mean(b));
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    cov / (a.len() as f64 * std(a) * std(b))
}

/// Least-squares slope through the origin of y over x, over rows where |x| < x_max.
fn slope(x: &[f64], y: &[f64], rows: Range<usize>, x_max: f64) -> f64 {
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for i in rows {
        if x[i].abs() < x_max {
            sxy += x[i] * y[i];
            sxx += x[i] * x[i];
        }
    }
    sxy / sxx
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn same_seed_gives_identical_data_and_csv() {
    for tire in TireKind::ALL {
        let c = cfg(7, &Extension::ALL, tire, 1.0);
        let (a, b) = (generate(&c), generate(&c));
        assert_eq!(a, b);
        let (mut ca, mut cb) = (Vec::new(), Vec::new());
        write_csv(&a, &mut ca).unwrap();
        write_csv(&b, &mut cb).unwrap();
        assert_eq!(ca, cb);
    }
}

#[test]
fn different_seeds_give_different_data() {
    let a = simulate(&cfg(1, &[], TireKind::Mf52, 1.0));
    let b = simulate(&cfg(2, &[], TireKind::Mf52, 1.0));
    assert_ne!(a.dataset.fy, b.dataset.fy);
    assert_ne!(a.truth.tire_params, b.truth.tire_params);
    let speeds = |s: &Simulation| s.blocks.iter().map(|b| b.speed).collect::<Vec<_>>();
    assert_ne!(speeds(&a), speeds(&b));
    // Same seed, another tire kind: same test program, other forces.
    let c = simulate(&cfg(1, &[], TireKind::Brush, 1.0));
    assert_eq!(a.blocks, c.blocks);
    assert_ne!(a.dataset.fy, c.dataset.fy);
}

#[test]
fn every_column_is_present_and_varies_without_any_effect() {
    let sim = simulate(&cfg(3, &[], TireKind::Mf52, 1.0));
    let ds = &sim.dataset;
    for q in Quantity::ALL {
        assert!(ds.has(q), "{} missing", q.name());
        if q != Quantity::Run {
            let c = col(ds, q);
            assert_eq!(c.len(), ds.len());
            assert!(c.iter().all(|v| v.is_finite()));
            assert!(std(c) > 0.0, "{} constant", q.name());
        }
    }
    let blocks = block_rows(&sim);
    assert_eq!(ds.runs().len(), 36);
    // Speed, pressure and temperature vary across blocks, covering their ranges.
    for (q, min_std, lo, hi) in [
        (Quantity::Speed, 6.0, 6.0, 29.0),
        (Quantity::Pressure, 30.0, 185.0, 295.0),
        (Quantity::Temperature, 17.0, 25.0, 85.0),
    ] {
        let c = col(ds, q);
        let means: Vec<f64> = blocks.iter().map(|(_, r)| mean(&c[r.clone()])).collect();
        assert!(std(&means) > min_std, "{}: {}", q.name(), std(&means));
        let (mn, mx) = means
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(mn < lo && mx > hi, "{}: {mn}..{mx}", q.name());
    }
    // Time starts at 0 in every block, at 100 Hz.
    let t = col(ds, Quantity::Time);
    for (_, r) in &blocks {
        assert_eq!(t[r.start], 0.0);
        assert!((t[r.start + 1] - 0.01).abs() < 1e-12);
    }
    // Combined slip is present in every dataset.
    let (a, k) = (col(ds, Quantity::Alpha), col(ds, Quantity::Kappa));
    let combined = (0..ds.len())
        .filter(|&i| a[i].abs() > 1.5f64.to_radians() && k[i].abs() > 0.05)
        .count();
    assert!(combined > 3000, "{combined} combined-slip rows");
    // Every sine frequency, slip angles to 12 deg, slip ratios to +-0.25, loads 1.5..7 kN,
    // cambers +-4 deg.
    for f in blocks::SINE_FREQUENCIES_HZ {
        assert!(blocks.iter().any(|(b, _)| b.sine_frequency() == Some(f)));
    }
    assert!(max_abs(a) > 11.9f64.to_radians());
    assert!(k.iter().any(|&x| x > 0.2) && k.iter().any(|&x| x < -0.25));
    let fz = &ds.fz;
    assert!(fz.iter().any(|&x| x < 1600.0) && fz.iter().any(|&x| x > 6900.0));
    assert!(max_abs(col(ds, Quantity::Gamma)) > 3.9f64.to_radians());
}

#[test]
fn block_conditions_are_not_confounded() {
    for seed in 1..=5 {
        let sim = simulate(&cfg(seed, &[], TireKind::Mf52, 1.0));
        let b = &sim.blocks;
        let v: Vec<f64> = b.iter().map(|b| b.speed).collect();
        let p: Vec<f64> = b.iter().map(|b| b.pressure).collect();
        let t: Vec<f64> = b.iter().map(|b| b.temp0).collect();
        let fz: Vec<f64> = b.iter().map(|b| b.fz).collect();
        let hf: Vec<f64> = b
            .iter()
            .map(|b| f64::from(b.sine_frequency().is_some_and(|f| f >= 4.0)))
            .collect();
        for (name, x, y) in [
            ("v-p", &v, &p),
            ("v-T", &v, &t),
            ("p-T", &p, &t),
            ("v-Fz", &v, &fz),
            ("p-Fz", &p, &fz),
            ("T-Fz", &t, &fz),
            ("v-hf", &v, &hf),
        ] {
            let r = corr(x, y);
            assert!(r.abs() < 0.5, "seed {seed}: corr {name} = {r}");
        }
    }
}

#[test]
fn row_count_is_near_the_target() {
    for (target, tol) in [
        (4_000, 0.15),
        (12_000, 0.05),
        (35_000, 0.03),
        (120_000, 0.03),
    ] {
        let c = SynthConfig {
            rows_target: target,
            ..SynthConfig::default()
        };
        let n = generate(&c).len();
        let err = (n as f64 - target as f64).abs() / target as f64;
        assert!(err < tol, "{n} rows for {target}");
    }
    assert!((34_000..=36_000).contains(&generate(&SynthConfig::default()).len()));
}

#[test]
fn noise_has_the_stated_levels() {
    let sim = |noise| simulate(&cfg(11, &Extension::ALL, TireKind::Brush, noise)).dataset;
    let (clean, noisy, loud) = (sim(0.0), sim(1.0), sim(2.0));
    let diff = |a: &Dataset, b: &Dataset, q: Quantity| -> Vec<f64> {
        col(a, q)
            .iter()
            .zip(col(b, q))
            .map(|(x, y)| x - y)
            .collect()
    };
    for (q, sd) in [
        (Quantity::Fx, NOISE.fx_n),
        (Quantity::Fy, NOISE.fy_n),
        (Quantity::Mz, NOISE.mz_nm),
        (Quantity::Fz, NOISE.fz_n),
        (Quantity::Alpha, NOISE.alpha_rad),
        (Quantity::Kappa, NOISE.kappa),
        (Quantity::Gamma, NOISE.gamma_rad),
        (Quantity::Speed, NOISE.speed_mps),
        (Quantity::Pressure, NOISE.pressure_kpa),
        (Quantity::Temperature, NOISE.temperature_c),
    ] {
        let d = diff(&noisy, &clean, q);
        assert!(
            (std(&d) / sd - 1.0).abs() < 0.03,
            "{}: {} vs {sd}",
            q.name(),
            std(&d)
        );
        assert!(mean(&d).abs() < 0.03 * sd, "{}", q.name());
        let d2 = diff(&loud, &clean, q);
        assert!((std(&d2) / (2.0 * sd) - 1.0).abs() < 0.03, "{}", q.name());
    }
    // Noise-free time and run columns are untouched.
    assert_eq!(clean.time, noisy.time);
    assert_eq!(clean.run, noisy.run);
    assert_eq!(NOISE.fy_n, 20.0);
    assert!((NOISE.alpha_rad.to_degrees() - 0.01).abs() < 1e-12);
}

#[test]
fn base_tires_differ_from_the_paper_but_are_tires() {
    let paper = mf87::Params::paper_table();
    for tire in TireKind::ALL {
        for seed in 1..=3 {
            let sim = simulate(&cfg(seed, &[], tire, 0.0));
            let ds = &sim.dataset;
            let (a, k, g) = (
                col(ds, Quantity::Alpha),
                col(ds, Quantity::Kappa),
                col(ds, Quantity::Gamma),
            );
            let (fx, fy, mz) = (
                col(ds, Quantity::Fx),
                col(ds, Quantity::Fy),
                col(ds, Quantity::Mz),
            );
            let (mut se, mut ss, mut mu_max) = (0.0, 0.0, 0.0f64);
            for (b, r) in block_rows(&sim) {
                for i in r {
                    let x = mf87::Inputs {
                        fz: ds.fz[i],
                        alpha: a[i],
                        kappa: k[i],
                        gamma: g[i],
                    };
                    let p = mf87::evaluate(&paper, &x, mf87::SignConvention::Paper);
                    match b.kind {
                        BlockKind::AlphaSweep { .. } => {
                            se += (fy[i] - p.fy).powi(2);
                            ss += fy[i].powi(2);
                            mu_max = mu_max.max(fy[i].abs() / ds.fz[i]);
                            // Paper signs at zero camber in the linear range (Mz may
                            // change sign beyond a few degrees at light load, as the
                            // paper's own Mz does).
                            let deg = a[i].to_degrees();
                            if g[i] == 0.0 && (0.5..2.0).contains(&deg) {
                                assert!(fy[i] > 0.0 && mz[i] < 0.0, "{tire} {deg}");
                            }
                            if g[i] == 0.0 && (-2.0..-0.5).contains(&deg) {
                                assert!(fy[i] < 0.0 && mz[i] > 0.0, "{tire} {deg}");
                            }
                            if g[i] == 0.0 && deg.abs() > 0.5 {
                                assert!(fy[i] * deg > 0.0, "{tire} {deg}");
                            }
                            if g[i] > 0.0 && deg.abs() < 0.05 {
                                assert!(fy[i] > 0.0, "camber thrust {tire}");
                            }
                            // No force along the wheel without slip ratio or effects.
                            assert_eq!(fx[i], 0.0);
                        }
                        BlockKind::KappaSweep { .. } => {
                            if k[i] > 0.02 {
                                assert!(fx[i] > 0.0);
                            }
                            if k[i] < -0.02 {
                                assert!(fx[i] < 0.0);
                            }
                            assert!(fy[i].abs() < 1e-9 && mz[i].abs() < 1e-9);
                        }
                        _ => {}
                    }
                }
            }
            let rel = (se / ss).sqrt();
            assert!(
                rel > 0.01 && rel < 0.25,
                "{tire} seed {seed}: relative rms {rel}"
            );
            assert!(
                (0.85..1.4).contains(&mu_max),
                "{tire} seed {seed}: mu {mu_max}"
            );
        }
    }
}

/// A dataset with one effect and the same seed's dataset without it, noise-free.
fn with_and_without(effect: Extension, tire: TireKind, seed: u64) -> (Simulation, Simulation) {
    let on = simulate(&cfg(seed, &[effect], tire, 0.0));
    let off = simulate(&cfg(seed, &[], tire, 0.0));
    // The effect changes nothing but the forces, and the rig's offsets the slip ratio it
    // reports.
    for q in [
        Quantity::Time,
        Quantity::Speed,
        Quantity::Fz,
        Quantity::Alpha,
        Quantity::Kappa,
        Quantity::Gamma,
        Quantity::Pressure,
        Quantity::Temperature,
    ] {
        if q == Quantity::Kappa && effect == Extension::SlipRatioShift {
            continue;
        }
        assert_eq!(col(&on.dataset, q), col(&off.dataset, q), "{}", q.name());
    }
    assert_eq!(on.truth.effects.len(), 1);
    assert_eq!(on.truth.effects[0].effect, effect);
    (on, off)
}

fn delta(on: &Simulation, off: &Simulation, q: Quantity) -> Vec<f64> {
    col(&on.dataset, q)
        .iter()
        .zip(col(&off.dataset, q))
        .map(|(a, b)| a - b)
        .collect()
}

#[test]
fn combined_slip_acts_only_where_both_slips_are_present() {
    for tire in TireKind::ALL {
        let (on, off) = with_and_without(Extension::CombinedSlip, tire, 5);
        let (dfx, dfy) = (
            delta(&on, &off, Quantity::Fx),
            delta(&on, &off, Quantity::Fy),
        );
        let dmz = delta(&on, &off, Quantity::Mz);
        let k = col(&on.dataset, Quantity::Kappa);
        let (mut sq, mut count, mut fx_on, mut fx_off) = (0.0, 0, 0.0, 0.0);
        for (b, r) in block_rows(&on) {
            match b.kind {
                BlockKind::Combined { alpha, .. } => {
                    for i in r {
                        if k[i].abs() > 0.05 {
                            sq += dfy[i].powi(2);
                            count += 1;
                            if alpha.abs() > 5f64.to_radians() && k[i].abs() < 0.12 {
                                fx_on += col(&on.dataset, Quantity::Fx)[i].abs();
                                fx_off += col(&off.dataset, Quantity::Fx)[i].abs();
                            }
                            // Lateral force falls as the slip ratio grows, keeping its sign.
                            let fy = col(&on.dataset, Quantity::Fy)[i];
                            let fy0 = col(&off.dataset, Quantity::Fy)[i];
                            assert!(fy.abs() < fy0.abs() && fy * alpha >= 0.0, "{tire}");
                        }
                    }
                }
                _ => {
                    // Pure slip (kappa = 0 or alpha = 0): untouched.
                    for i in r {
                        assert!(dfx[i].abs() < 1e-6 && dfy[i].abs() < 1e-6 && dmz[i].abs() < 1e-6);
                    }
                }
            }
        }
        let rms = (sq / count as f64).sqrt();
        assert!(rms > 400.0, "{tire}: rms dFy {rms}");
        // Fx falls too, most at large slip angle around its peak (well past it, the
        // friction ellipse leaves little to take).
        assert!(fx_on < 0.92 * fx_off, "{tire}: Fx {fx_on} vs {fx_off}");
    }
}

#[test]
fn relaxation_shows_in_the_fast_sinusoidal_blocks() {
    for tire in TireKind::ALL {
        let (on, off) = with_and_without(Extension::RelaxationLength, tire, 6);
        let dfy = delta(&on, &off, Quantity::Fy);
        let fy_on = col(&on.dataset, Quantity::Fy);
        let fy_off = col(&off.dataset, Quantity::Fy);
        let (mut fast, mut slow, mut sweep) = (Vec::new(), Vec::new(), Vec::new());
        let mut amplitude = Vec::new();
        for (b, r) in block_rows(&on) {
            let m = mean(&dfy[r.clone()].iter().map(|x| x.abs()).collect::<Vec<_>>());
            match (b.kind, b.sine_frequency()) {
                (_, Some(f)) if f >= 8.0 => {
                    fast.push(m);
                    // Amplitude falls at 8 Hz.
                    let ratio = std(&fy_on[r.clone()]) / std(&fy_off[r.clone()]);
                    assert!(ratio < 0.97, "{tire}: amplitude ratio {ratio} at 8 Hz");
                    amplitude.push(ratio);
                }
                (_, Some(f)) if f <= 0.5 => slow.push(m),
                (BlockKind::AlphaSweep { .. }, _) => sweep.push(m),
                _ => {}
            }
        }
        assert!(mean(&amplitude) < 0.85, "{tire}: {amplitude:?}");
        let (fast, slow, sweep) = (mean(&fast), mean(&slow), mean(&sweep));
        assert!(fast > 200.0, "{tire}: {fast}");
        // The lag matters in proportion to frequency over speed: the 0.5 Hz blocks at low speed
        // show some of it, the 8 Hz blocks much more, the slow sweeps least.
        assert!(
            fast > 2.5 * slow && fast > 5.0 * sweep,
            "{tire}: {fast} {slow} {sweep}"
        );
    }
}

#[test]
fn relaxation_gives_hysteresis_in_the_sweeps() {
    let (on, off) = with_and_without(Extension::RelaxationLength, TireKind::Mf52, 6);
    let a = col(&on.dataset, Quantity::Alpha);
    let fy = col(&on.dataset, Quantity::Fy);
    let fy0 = col(&off.dataset, Quantity::Fy);
    let mut loops = Vec::new();
    for (b, r) in block_rows(&on) {
        if let BlockKind::AlphaSweep { .. } = b.kind {
            // Up-going through 2 deg lags behind the down-going pass.
            let n = r.len();
            let rising = r.start
                + (0..n / 4)
                    .find(|&i| a[r.start + i] >= 2f64.to_radians())
                    .unwrap();
            let falling = r.start
                + (n / 4..n / 2)
                    .find(|&i| a[r.start + i] <= 2f64.to_radians())
                    .unwrap();
            assert!(fy[rising] < fy0[rising] && fy[falling] > fy0[falling]);
            loops.push(fy[falling] - fy[rising]);
        }
    }
    // Slow sweeps (about 4 deg/s): tens to hundreds of newtons, more at low speed.
    assert!(mean(&loops) > 50.0, "{loops:?}");
}

#[test]
fn pressure_changes_the_cornering_stiffness() {
    for tire in TireKind::ALL {
        let (on, off) = with_and_without(Extension::InflationPressure, tire, 8);
        let a = col(&on.dataset, Quantity::Alpha);
        let (mut dev, mut lnp) = (Vec::new(), Vec::new());
        for (b, r) in block_rows(&on) {
            if let BlockKind::AlphaSweep { .. } = b.kind {
                let ky_on = slope(
                    a,
                    col(&on.dataset, Quantity::Fy),
                    r.clone(),
                    0.5f64.to_radians(),
                );
                let ky_off = slope(
                    a,
                    col(&off.dataset, Quantity::Fy),
                    r.clone(),
                    0.5f64.to_radians(),
                );
                dev.push((ky_on / ky_off - 1.0).abs());
                lnp.push((b.pressure / PRESSURE_NOMINAL_KPA).ln().abs());
            }
        }
        assert!(
            dev.iter().cloned().fold(0.0, f64::max) > 0.04,
            "{tire}: {dev:?}"
        );
        // Not a clean function of pressure: the load shift makes the change load-dependent.
        assert!(corr(&dev, &lnp) > 0.4, "{tire}: {}", corr(&dev, &lnp));
        // Peak friction falls with pressure: compare the highest- and lowest-pressure sweeps.
        let fy_on = col(&on.dataset, Quantity::Fy);
        let fy_off = col(&off.dataset, Quantity::Fy);
        let mut peaks: Vec<(f64, f64)> = block_rows(&on)
            .into_iter()
            .filter(|(b, _)| matches!(b.kind, BlockKind::AlphaSweep { .. }))
            .map(|(b, r)| (b.pressure, max_abs(&fy_on[r.clone()]) / max_abs(&fy_off[r])))
            .collect();
        peaks.sort_by(|x, y| x.0.total_cmp(&y.0));
        assert!(
            peaks[0].1 > peaks[peaks.len() - 1].1 + 0.02,
            "{tire}: {peaks:?}"
        );
    }
}

#[test]
fn speed_lowers_peak_friction() {
    for tire in TireKind::ALL {
        let (on, off) = with_and_without(Extension::SpeedDependence, tire, 9);
        let fy_on = col(&on.dataset, Quantity::Fy);
        let fy_off = col(&off.dataset, Quantity::Fy);
        let fx_on = col(&on.dataset, Quantity::Fx);
        let fx_off = col(&off.dataset, Quantity::Fx);
        let (mut v, mut ry, mut vx, mut rx) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (b, r) in block_rows(&on) {
            match b.kind {
                BlockKind::AlphaSweep { .. } => {
                    v.push(b.speed);
                    ry.push(max_abs(&fy_on[r.clone()]) / max_abs(&fy_off[r]));
                }
                BlockKind::KappaSweep { .. } => {
                    vx.push(b.speed);
                    rx.push(max_abs(&fx_on[r.clone()]) / max_abs(&fx_off[r]));
                }
                _ => {}
            }
        }
        assert!(corr(&v, &ry) < -0.7, "{tire}: {}", corr(&v, &ry));
        assert!(corr(&vx, &rx) < -0.7, "{tire}: {}", corr(&vx, &rx));
        let spread = |x: &[f64]| {
            x.iter().cloned().fold(f64::MIN, f64::max) - x.iter().cloned().fold(f64::MAX, f64::min)
        };
        assert!(spread(&ry) > 0.05 && spread(&ry) < 0.2, "{tire}: {ry:?}");
        assert!(ry.iter().all(|&x| x < 1.0 && x > 0.75));
    }
}

#[test]
fn ply_steer_offsets_grow_faster_than_the_load() {
    for tire in TireKind::ALL {
        let (on, off) = with_and_without(Extension::PlySteerConicity, tire, 10);
        let (dfy, dmz) = (
            delta(&on, &off, Quantity::Fy),
            delta(&on, &off, Quantity::Mz),
        );
        let fz = &on.dataset.fz;
        let p = on.truth.effects[0].params["fy_at_4kN_N"];
        let (mut lo, mut hi, mut mid, mut mz_mid) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (b, r) in block_rows(&on) {
            if let BlockKind::FreeRolling { .. } = b.kind {
                for i in r {
                    if fz[i] < 1600.0 {
                        lo.push(dfy[i]);
                    } else if fz[i] > 6900.0 {
                        hi.push(dfy[i]);
                    } else if (fz[i] - 4000.0).abs() < 100.0 {
                        mid.push(dfy[i]);
                        mz_mid.push(dmz[i]);
                    }
                }
            }
        }
        let (lo, hi, mid) = (mean(&lo), mean(&hi), mean(&mid));
        assert!((mid / p - 1.0).abs() < 0.1, "{tire}: {mid} vs {p}");
        assert!(
            hi / lo > (7000.0f64 / 1550.0).powf(1.15),
            "{tire}: {lo} {hi}"
        );
        assert!((50.0..=165.0).contains(&mid.abs()), "{tire}: {mid}");
        assert!(
            (2.0..9.0).contains(&mean(&mz_mid).abs()),
            "{tire}: {}",
            mean(&mz_mid)
        );
        assert!(mean(&mz_mid) * mid < 0.0);
        // The offset fades as the tire saturates (a slip shift, not a constant force).
        let a = col(&on.dataset, Quantity::Alpha);
        let sat: Vec<f64> = (0..a.len())
            .filter(|&i| {
                a[i].abs() > 11f64.to_radians() && col(&on.dataset, Quantity::Gamma)[i] == 0.0
            })
            .map(|i| dfy[i].abs())
            .collect();
        assert!(mean(&sat) < 0.5 * mid.abs(), "{tire}: {}", mean(&sat));
    }
}

#[test]
fn rolling_resistance_pulls_fx_back_at_zero_slip() {
    for tire in TireKind::ALL {
        let (on, off) = with_and_without(Extension::RollingResistance, tire, 12);
        let dfx = delta(&on, &off, Quantity::Fx);
        assert_eq!(
            col(&on.dataset, Quantity::Fy),
            col(&off.dataset, Quantity::Fy)
        );
        assert_eq!(
            col(&on.dataset, Quantity::Mz),
            col(&off.dataset, Quantity::Mz)
        );
        let fz = &on.dataset.fz;
        let mut coef = Vec::new();
        for (b, r) in block_rows(&on) {
            if matches!(
                b.kind,
                BlockKind::AlphaSweep { .. } | BlockKind::FreeRolling { .. }
            ) {
                for i in r {
                    let c = -dfx[i] / fz[i];
                    assert!((0.005..0.02).contains(&c), "{tire}: {c}");
                    coef.push(c);
                }
            }
        }
        // Exactly the J2452-style law of the truth record: Fz^b p^a (1 + k (V/30)^2).
        let t = &on.truth.effects[0].params;
        let (v, p) = (
            col(&on.dataset, Quantity::Speed),
            col(&on.dataset, Quantity::Pressure),
        );
        for i in 0..fz.len() {
            let fr = t["coef"]
                * 4000.0
                * (fz[i] / 4000.0).powf(t["load_exp"])
                * (p[i] / PRESSURE_NOMINAL_KPA).powf(t["pressure_exp"])
                * (1.0 + t["speed_frac_at_30_mps"] * (v[i] / 30.0).powi(2));
            assert!(
                (dfx[i] + fr).abs() < 1e-9 * fr,
                "{tire}: {} vs {fr}",
                -dfx[i]
            );
        }
        assert!(mean(&coef) > 0.007);
    }
}

#[test]
fn the_rigs_offsets_read_slip_at_free_rolling_and_force_at_zero_slip() {
    for tire in TireKind::ALL {
        let (on, off) = with_and_without(Extension::SlipRatioShift, tire, 15);
        let t = &on.truth.effects[0].params;
        let (r, c) = (t["radius_ratio_Re_over_R"], t["fx_crosstalk_per_fz"]);
        assert!((0.004..=0.012).contains(&(r - 1.0).abs()), "{tire}: {r}");
        assert!((0.002..=0.006).contains(&c.abs()), "{tire}: {c}");
        // Every slip ratio read through the radius ratio: (1 + kappa) Re / R - 1.
        let (k_on, k_off) = (
            col(&on.dataset, Quantity::Kappa),
            col(&off.dataset, Quantity::Kappa),
        );
        for (m, k) in k_on.iter().zip(k_off) {
            assert!((m - ((1.0 + k) * r - 1.0)).abs() < 1e-15, "{tire}: {m} {k}");
        }
        // Fx is the same tire's force plus c Fz; Fy and Mz are untouched.
        let dfx = delta(&on, &off, Quantity::Fx);
        let fz = &on.dataset.fz;
        for (d, f) in dfx.iter().zip(fz.iter()) {
            assert!((d - c * f).abs() < 1e-9 * f, "{tire}: {d} vs {}", c * f);
        }
        for q in [Quantity::Fy, Quantity::Mz] {
            assert_eq!(col(&on.dataset, q), col(&off.dataset, q));
        }
        // Free rolling reads as slip Re / R - 1, with the force offset alone.
        let fx = col(&on.dataset, Quantity::Fx);
        for (b, rows) in block_rows(&on) {
            if let BlockKind::FreeRolling { .. } = b.kind {
                for i in rows {
                    assert!((k_on[i] - (r - 1.0)).abs() < 1e-15);
                    assert!(
                        (fx[i] - c * fz[i]).abs() < 1e-9 * fz[i],
                        "{tire}: {}",
                        fx[i]
                    );
                }
            }
        }
    }
}

#[test]
fn temperature_softens_stiffness_and_has_a_friction_window() {
    for tire in TireKind::ALL {
        let (on, off) = with_and_without(Extension::Temperature, tire, 13);
        let a = col(&on.dataset, Quantity::Alpha);
        let temp = col(&on.dataset, Quantity::Temperature);
        let t_opt = on.truth.effects[0].params["t_opt_C"];
        let (mut t, mut k, mut peak) = (Vec::new(), Vec::new(), Vec::new());
        for (b, r) in block_rows(&on) {
            if let BlockKind::AlphaSweep { .. } = b.kind {
                let ky_on = slope(
                    a,
                    col(&on.dataset, Quantity::Fy),
                    r.clone(),
                    0.5f64.to_radians(),
                );
                let ky_off = slope(
                    a,
                    col(&off.dataset, Quantity::Fy),
                    r.clone(),
                    0.5f64.to_radians(),
                );
                t.push(mean(&temp[r.clone()]));
                k.push(ky_on / ky_off);
                peak.push(
                    max_abs(&col(&on.dataset, Quantity::Fy)[r.clone()])
                        / max_abs(&col(&off.dataset, Quantity::Fy)[r]),
                );
            }
        }
        assert!(corr(&t, &k) < -0.8, "{tire}: {}", corr(&t, &k));
        // Friction window: the sweep nearest the optimum keeps more grip than the extremes.
        let nearest = (0..t.len())
            .min_by(|&i, &j| (t[i] - t_opt).abs().total_cmp(&(t[j] - t_opt).abs()))
            .unwrap();
        let coldest = (0..t.len()).min_by(|&i, &j| t[i].total_cmp(&t[j])).unwrap();
        let hottest = (0..t.len()).max_by(|&i, &j| t[i].total_cmp(&t[j])).unwrap();
        assert!(
            peak[nearest] > peak[coldest] + 0.02 || (t[coldest] - t_opt).abs() < 15.0,
            "{tire}: {peak:?} {t:?}"
        );
        assert!(
            peak[nearest] > peak[hottest] + 0.02 || (t[hottest] - t_opt).abs() < 15.0,
            "{tire}: {peak:?} {t:?}"
        );
    }
}

#[test]
fn every_effect_changes_the_data() {
    for e in Extension::ALL {
        let (on, off) = with_and_without(e, TireKind::Mf87Perturbed, 14);
        let worst = [Quantity::Fx, Quantity::Fy, Quantity::Mz]
            .into_iter()
            .map(|q| max_abs(&delta(&on, &off, q)))
            .fold(0.0, f64::max);
        // The rig's offsets act mostly through the slip ratio it reports.
        let slip = max_abs(&delta(&on, &off, Quantity::Kappa));
        assert!(worst > 30.0 || slip > 0.003, "{e}: {worst} {slip}");
    }
}

#[test]
fn mf61_forms_are_the_ones_the_diagnosis_fits_and_change_the_data() {
    // The four effects with an MF 6.1 form take it under Forms::Mf61 (its coefficients in the
    // truth) and still act; the others keep their physical form.
    let run = |effect: Extension, forms: Forms| {
        simulate(&SynthConfig {
            forms,
            ..cfg(14, &[effect], TireKind::Mf87Perturbed, 0.0)
        })
    };
    let off = simulate(&cfg(14, &[], TireKind::Mf87Perturbed, 0.0));
    for (effect, coefficient) in [
        (Extension::CombinedSlip, "rBy1"),
        (Extension::InflationPressure, "ppy2"),
        (Extension::PlySteerConicity, "pHy2"),
        (Extension::CamberPeak, "pDx3"),
    ] {
        let on = run(effect, Forms::Mf61);
        assert!(
            on.truth.effects[0].params.contains_key(coefficient),
            "{effect}: {:?}",
            on.truth.effects[0].params
        );
        assert_eq!(on.truth.forms, Forms::Mf61);
        let worst = [Quantity::Fx, Quantity::Fy]
            .into_iter()
            .map(|q| max_abs(&delta(&on, &off, q)))
            .fold(0.0, f64::max);
        assert!(worst > 30.0, "{effect}: {worst}");
        assert_ne!(
            col(&on.dataset, Quantity::Fy),
            col(&run(effect, Forms::Physical).dataset, Quantity::Fy),
            "{effect}"
        );
    }
    // Speed has no MF 6.1 form here: the same data under either.
    assert_eq!(
        col(
            &run(Extension::SpeedDependence, Forms::Mf61).dataset,
            Quantity::Fy
        ),
        col(
            &run(Extension::SpeedDependence, Forms::Physical).dataset,
            Quantity::Fy
        )
    );
}

#[test]
fn effect_magnitudes_vary_with_the_seed_within_their_ranges() {
    let lengths: Vec<f64> = (0..20)
        .map(|seed| {
            let (_, truth) = generate_with_truth(&SynthConfig {
                seed,
                effects: vec![Extension::RelaxationLength],
                rows_target: 500,
                ..SynthConfig::default()
            });
            truth.effects[0].params["length_at_4kN_m"]
        })
        .collect();
    assert!(lengths.iter().all(|l| (0.3..0.8).contains(l)));
    assert!(std(&lengths) > 0.08);
}

#[test]
fn csv_has_the_tool_format_at_full_precision() {
    let ds = generate(&SynthConfig {
        rows_target: 2000,
        effects: vec![Extension::Temperature],
        ..SynthConfig::default()
    });
    let mut out = Vec::new();
    write_csv(&ds, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("run,t_s,vx_mps,fz_N,alpha_deg,kappa,gamma_deg,p_kPa,temp_C,fx_N,fy_N,mz_Nm")
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), ds.len());
    for (i, line) in rows.iter().enumerate().step_by(97) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 12);
        assert_eq!(f[0].parse::<i64>().unwrap(), ds.run[i]);
        let num = |k: usize| f[k].parse::<f64>().unwrap();
        assert_eq!(num(1), ds.time.as_ref().unwrap()[i]);
        assert_eq!(num(3), ds.fz[i]);
        assert_eq!(num(4), ds.alpha.as_ref().unwrap()[i].to_degrees());
        assert!((num(4).to_radians() - ds.alpha.as_ref().unwrap()[i]).abs() < 1e-15);
        assert_eq!(num(5), ds.kappa.as_ref().unwrap()[i]);
        assert_eq!(num(10), ds.fy.as_ref().unwrap()[i]);
        assert_eq!(num(11), ds.mz.as_ref().unwrap()[i]);
    }
    // Missing columns are left out.
    let mut partial = ds.clone();
    partial.temperature = None;
    partial.mz = None;
    let mut out = Vec::new();
    write_csv(&partial, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert_eq!(
        text.lines().next(),
        Some("run,t_s,vx_mps,fz_N,alpha_deg,kappa,gamma_deg,p_kPa,fx_N,fy_N")
    );
    assert_eq!(text.lines().nth(1).unwrap().split(',').count(), 10);
}

#[test]
fn command_line_arguments_map_to_a_config() {
    use clap::Parser;
    #[derive(Parser)]
    struct Wrap {
        #[command(flatten)]
        args: cli::SynthArgs,
    }
    let parse = |argv: &[&str]| {
        Wrap::try_parse_from(std::iter::once("synth").chain(argv.iter().copied()))
            .unwrap()
            .args
            .config()
    };
    let c = parse(&[
        "--seed",
        "4",
        "--effects",
        "temperature,combined_slip",
        "--tire",
        "brush",
    ])
    .unwrap();
    assert_eq!(c.seed, 4);
    assert_eq!(
        c.effects,
        vec![Extension::CombinedSlip, Extension::Temperature]
    );
    assert_eq!(c.tire, TireKind::Brush);
    assert_eq!(c.rows_target, DEFAULT_ROWS);
    assert_eq!(
        parse(&["--effects", "all"]).unwrap().effects,
        Extension::ALL.to_vec()
    );
    assert!(parse(&[]).unwrap().effects.is_empty());
    assert!(
        parse(&["--effects", "warp_drive"])
            .unwrap_err()
            .contains("warp_drive")
    );
    assert!(parse(&["--tire", "slick"]).unwrap_err().contains("slick"));
    assert!(parse(&["--noise=-1"]).unwrap_err().contains("noise"));

    let args = Wrap::try_parse_from(["synth", "--rows", "1000", "--effects", "rolling_resistance"])
        .unwrap()
        .args;
    let mut out = Vec::new();
    cli::run(&args, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(text.starts_with(
        "run,t_s,vx_mps,fz_N,alpha_deg,kappa,gamma_deg,p_kPa,temp_C,fx_N,fy_N,mz_Nm\n"
    ));
    let bad = Wrap::try_parse_from(["synth", "--tire", "x"]).unwrap().args;
    assert_eq!(
        cli::run(&bad, &mut Vec::new()).unwrap_err().kind,
        crate::io::output::FailureKind::BadInput
    );
}

#[test]
fn the_tool_reads_the_csv_back() {
    let ds = generate(&SynthConfig {
        rows_target: 3000,
        effects: Extension::ALL.to_vec(),
        tire: TireKind::Brush,
        ..SynthConfig::default()
    });
    let mut out = Vec::new();
    write_csv(&ds, &mut out).unwrap();
    let loaded = crate::io::input::csv::read_str(std::str::from_utf8(&out).unwrap(), "synth.csv")
        .expect("the tool's CSV reader accepts the synthetic file");
    let back = &loaded.dataset;
    assert_eq!(back.len(), ds.len());
    assert_eq!(back.run, ds.run);
    for q in Quantity::ALL.into_iter().filter(|&q| q != Quantity::Run) {
        let (a, b) = (col(back, q), col(&ds, q));
        for (x, y) in a.iter().zip(b) {
            assert!(
                (x - y).abs() <= 1e-12 * y.abs().max(1.0),
                "{}: {x} vs {y}",
                q.name()
            );
        }
    }
}

fn parse_args(argv: &[&str]) -> cli::SynthArgs {
    use clap::Parser;
    #[derive(Parser)]
    struct Wrap {
        #[command(flatten)]
        args: cli::SynthArgs,
    }
    Wrap::try_parse_from(std::iter::once("synth").chain(argv.iter().copied()))
        .unwrap()
        .args
}

/// A fresh, missing path under the system's temporary directory.
fn scratch(name: &str) -> std::path::PathBuf {
    let p = std::env::temp_dir().join(format!("tire-gap-synth-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    let _ = std::fs::remove_file(&p);
    p
}

#[test]
fn noise_and_rows_outside_their_ranges_are_refused() {
    let err = |argv: &[&str]| parse_args(argv).config().unwrap_err();
    for (value, shown) in [
        ("1e308", "1e308"),
        ("10.5", "10.5"),
        ("-1", "-1"),
        ("inf", "inf"),
        ("NaN", "NaN"),
    ] {
        let e = err(&[&format!("--noise={value}")]);
        assert!(
            e.starts_with(&format!(
                "--noise {shown} is out of range: it must lie in 0..=10 "
            )),
            "{e}"
        );
    }
    assert_eq!(MAX_NOISE, 10.0);
    for ok in ["0", "1", "10"] {
        assert!(parse_args(&["--noise", ok]).config().is_ok(), "{ok}");
    }
    for value in ["0", "999", "2000001"] {
        assert_eq!(
            err(&["--rows", value]),
            format!("--rows {value} is out of range: it must lie in 1000..=2000000")
        );
    }
    for ok in ["1000", "2000000"] {
        assert_eq!(
            parse_args(&["--rows", ok]).config().unwrap().rows_target,
            ok.parse::<usize>().unwrap()
        );
    }

    // Through `run`: bad input, and nothing written.
    let out = scratch("refused.csv");
    let truth = scratch("refused.json");
    let args = parse_args(&[
        "--noise",
        "1e308",
        "--out",
        out.to_str().unwrap(),
        "--truth",
        truth.to_str().unwrap(),
    ]);
    let mut stdout = Vec::new();
    let e = cli::run(&args, &mut stdout).unwrap_err();
    assert_eq!(e.kind, crate::io::output::FailureKind::BadInput);
    assert!(e.message.contains("--noise 1e308"), "{}", e.message);
    assert!(stdout.is_empty() && !out.exists() && !truth.exists());
}

#[test]
fn data_at_the_largest_noise_are_plausible_and_at_100_they_are_left_out() {
    let data = |noise: f64| {
        generate(&SynthConfig {
            noise,
            effects: Extension::ALL.to_vec(),
            ..SynthConfig::default()
        })
    };
    let read = |ds: &Dataset| {
        assert!(first_non_finite(ds).is_none());
        let mut out = Vec::new();
        write_csv(ds, &mut out).unwrap();
        crate::front::read_str(
            std::str::from_utf8(&out).unwrap(),
            "synth.csv",
            crate::io::input::Format::Csv,
        )
    };
    let noisiest = data(MAX_NOISE);
    read(&noisiest).expect("the reader accepts the noisiest data synth writes");
    // The noise is there at its stated level.
    let clean = data(0.0);
    let d: Vec<f64> = col(&noisiest, Quantity::Speed)
        .iter()
        .zip(col(&clean, Quantity::Speed))
        .map(|(a, b)| a - b)
        .collect();
    assert!((std(&d) / (MAX_NOISE * NOISE.speed_mps) - 1.0).abs() < 0.03);
    // At 100 times, speeds go below zero: the reader leaves them out, row by row or as a
    // channel, and says so.
    let loaded = read(&data(100.0)).expect("implausible values are left out, not refused");
    assert!(
        loaded
            .notes
            .iter()
            .any(|n| n.contains("speed = -") && n.contains("outside the plausible range")),
        "{:?}",
        loaded.notes
    );
}

#[test]
fn non_finite_data_are_an_internal_failure_and_nothing_is_written() {
    let mut ds = generate(&SynthConfig {
        rows_target: 2000,
        ..SynthConfig::default()
    });
    assert_eq!(first_non_finite(&ds), None);
    std::sync::Arc::get_mut(ds.fy.as_mut().unwrap()).unwrap()[7] = f64::INFINITY;
    std::sync::Arc::get_mut(ds.mz.as_mut().unwrap()).unwrap()[3] = f64::NAN;
    assert_eq!(first_non_finite(&ds), Some((Quantity::Fy, 7)));
    let csv = scratch("nonfinite.csv");
    let dir = scratch("nonfinite-tdx");
    let truth = scratch("nonfinite.json");
    for output in [
        cli::Output::CsvStdout,
        cli::Output::CsvFile(csv.clone()),
        cli::Output::Tydex {
            dir: dir.clone(),
            units: tydex::TydexUnits::Si,
        },
    ] {
        let mut stdout = Vec::new();
        let e =
            cli::write_outputs(&ds, &output, Some((&truth, "{}".into())), &mut stdout).unwrap_err();
        assert_eq!(e.kind, crate::io::output::FailureKind::Output);
        assert_eq!(
            e.message,
            format!(
                "internal error: the generated data hold a non-finite value (fy_N = inf at row 8, \
                 run {}); nothing written",
                ds.run[7]
            )
        );
        assert!(stdout.is_empty());
        assert!(!csv.exists() && !dir.exists() && !truth.exists());
    }
}

#[test]
fn output_options_map_to_an_output() {
    use cli::Output;
    use tydex::TydexUnits;
    let out = |argv: &[&str]| parse_args(argv).output();
    assert_eq!(out(&[]), Ok(Output::CsvStdout));
    assert_eq!(
        out(&["--out", "a.csv"]),
        Ok(Output::CsvFile("a.csv".into()))
    );
    assert_eq!(
        out(&["--format", "tydex", "--out", "prog"]),
        Ok(Output::Tydex {
            dir: "prog".into(),
            units: TydexUnits::Engineering
        })
    );
    assert_eq!(
        out(&["--format", "tydex", "--tydex-units", "si", "-o", "prog"]),
        Ok(Output::Tydex {
            dir: "prog".into(),
            units: TydexUnits::Si
        })
    );
    assert!(
        out(&["--format", "tydex"])
            .unwrap_err()
            .contains("give it with --out DIR")
    );
    assert_eq!(
        out(&["--tydex-units", "si", "--out", "a.csv"]),
        Err("--tydex-units applies to --format tydex only".to_string())
    );
}

#[test]
fn synth_writes_a_tydex_programme_the_tool_reads_back() {
    let dir = scratch("programme");
    let args = parse_args(&[
        "--rows",
        "2000",
        "--effects",
        "temperature",
        "--format",
        "tydex",
        "--out",
        dir.to_str().unwrap(),
    ]);
    cli::run(&args, &mut Vec::new()).unwrap();
    let ds = generate(&args.config().unwrap());
    let runs = ds.runs();
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    let expected: Vec<String> = runs.iter().map(|r| format!("run_{r:04}.tdx")).collect();
    assert_eq!(names, expected);
    let paths: Vec<_> = names.iter().map(|n| dir.join(n)).collect();
    let back = crate::front::load_many(&paths).unwrap().dataset;
    assert_eq!(back.run, ds.run);
    for q in Quantity::ALL.into_iter().filter(|&q| q != Quantity::Run) {
        for (x, y) in col(&back, q).iter().zip(col(&ds, q)) {
            // A run whose slip ratio is not swept, at free rolling, reads a slip ratio of 0
            // (`prepare::free_rolling`): the cornering runs, whose slip ratio is noise.
            if q == Quantity::Kappa && *x == 0.0 && y.abs() < 1e-3 {
                continue;
            }
            assert!((x - y).abs() <= 1e-12 * y.abs(), "{}: {x} vs {y}", q.name());
        }
    }
    // A second programme into the same directory is refused before anything is generated.
    let e = cli::run(&args, &mut Vec::new()).unwrap_err();
    assert_eq!(e.kind, crate::io::output::FailureKind::BadInput);
    assert!(
        e.message.contains("already holds TYDEX files"),
        "{}",
        e.message
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn drivers_are_described_and_tire_ids_round_trip() {
    for e in Extension::ALL {
        assert!(effect_driver(e).len() > 20, "{e}");
    }
    assert_eq!(Extension::from_name("tyre"), None);
    for k in TireKind::ALL {
        assert_eq!(TireKind::from_id(k.id()), Some(k));
    }
}
