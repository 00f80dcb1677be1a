//! The per-sweep floor: a least-squares cubic spline through each run (test block) on its
//! own, of the measured force against the slip the run sweeps, its knots placed along the
//! curve (as many where the force turns fast, at the stiffness through zero slip, as in its
//! flat saturated part). It follows any steady curve the run traces, so what it leaves is what
//! no steady-state model of slip, load and conditions can explain: sensor noise, the
//! hysteresis between a sweep's rising and falling halves, drift within the run. It is fitted
//! in-sample, run by run, its mean square taken over the rows less the splines' coefficients
//! (so that a short run's spline does not pass for a low floor): a lower bound of any model's
//! error, not a model. Where runs do not each trace one curve of the swept slip (a load or
//! camber that moves within the run), it can lie above a model's error; the ceiling then says
//! so instead of giving shares of a gap above it.

use mf87::Channel;
use nalgebra::{Cholesky, DMatrix, DVector};
use serde::Serialize;

use crate::method::prepare::channel_data::{ChannelData, run_stretches};
use crate::quantiles::quantile;

/// Rows per spline interval at least; between [`MIN_INTERIOR_KNOTS`] and
/// [`MAX_INTERIOR_KNOTS`] interior knots, and at most a quarter of the run's rows as
/// coefficients.
const ROWS_PER_INTERVAL: usize = 25;
const MIN_INTERIOR_KNOTS: usize = 6;
const MAX_INTERIOR_KNOTS: usize = 12;
/// Rows per spline coefficient at least.
const ROWS_PER_COEFFICIENT: usize = 4;
/// Rows of the running mean that smooths the force before the curve's length is measured
/// for the knots (noise alone would lengthen it evenly).
const KNOT_SMOOTHING_ROWS: usize = 5;
/// A run sweeps a slip that spans (5th to 95th percentile) at least this much, in the
/// formula's units (deg, percent); a run sweeping neither is fitted by its mean.
const SWEPT_SPAN: f64 = 0.5;
/// Ridge on the spline's normal equations, relative to their mean diagonal: keeps an
/// interval without rows from making them singular.
const RIDGE: f64 = 1e-8;

/// The floor of one channel.
#[derive(Debug, Clone, Serialize)]
pub struct Floor {
    pub channel: Channel,
    /// RMS of the measurement about each run's spline, over every row less the splines'
    /// coefficients [N or N.m].
    pub rms: f64,
    /// Runs fitted by a spline, and by their mean (sweeping no slip).
    pub swept_runs: usize,
    pub flat_runs: usize,
}

/// The floor of `data`'s channel over its runs.
pub fn floor(data: &ChannelData) -> Floor {
    let runs = run_stretches(&data.run);
    let own = |i: usize| data.slip[i];
    // The other slip in the formula's units of its own kind (percent, deg).
    let other = data.other_slip.as_ref().map(|o| {
        move |i: usize| match data.channel {
            Channel::Fx => mf87::units::radians_to_degrees(o[i]),
            _ => mf87::units::slip_ratio_to_percent(o[i]),
        }
    });
    let (mut sse, mut coefficients, mut swept_runs, mut flat_runs) = (0.0, 0, 0, 0);
    for stretches in runs.values() {
        let rows = || stretches.iter().flat_map(|r| r.clone());
        let gather = |col: &dyn Fn(usize) -> f64| -> Vec<f64> { rows().map(col).collect() };
        let span = |col: &dyn Fn(usize) -> f64| {
            let v = gather(col);
            match (quantile(&v, 0.05), quantile(&v, 0.95)) {
                (Some(lo), Some(hi)) => hi - lo,
                _ => 0.0,
            }
        };
        let own_span = span(&own);
        let other_span = other.as_ref().map_or(0.0, |o| span(o));
        let x: (f64, &dyn Fn(usize) -> f64) = match &other {
            Some(o) if own_span < other_span => (other_span, o),
            _ => (own_span, &own),
        };
        let y = gather(&|i| data.measured[i]);
        let residual = if x.0 >= SWEPT_SPAN {
            swept_runs += 1;
            spline_residual_sse(&gather(x.1), &y)
        } else {
            None
        };
        let (run_sse, run_coefficients) = residual.unwrap_or_else(|| {
            flat_runs += 1;
            let mean = y.iter().sum::<f64>() / y.len().max(1) as f64;
            (y.iter().map(|v| (v - mean).powi(2)).sum(), 1)
        });
        sse += run_sse;
        coefficients += run_coefficients;
    }
    let dof = data.len().saturating_sub(coefficients).max(1);
    Floor {
        channel: data.channel,
        rms: (sse / dof as f64).sqrt(),
        swept_runs,
        flat_runs,
    }
}

/// The sum of squared residuals of a least-squares cubic spline of `y` over `x` and the
/// spline's number of coefficients; `None` when `x` has fewer than two distinct values.
fn spline_residual_sse(x: &[f64], y: &[f64]) -> Option<(f64, usize)> {
    let (lo, hi) = (quantile(x, 0.0)?, quantile(x, 1.0)?);
    if hi <= lo {
        return None;
    }
    let interior = (x.len() / ROWS_PER_INTERVAL)
        .clamp(MIN_INTERIOR_KNOTS, MAX_INTERIOR_KNOTS)
        .min((x.len() / ROWS_PER_COEFFICIENT).saturating_sub(4));
    let mut knots = vec![lo; 4];
    for q in knots_along_the_curve(x, y, interior) {
        if q > *knots.last()? + 1e-9 * (hi - lo) && q < hi {
            knots.push(q);
        }
    }
    knots.extend([hi; 4]);
    let basis = knots.len() - 4;
    let mut normal = DMatrix::<f64>::zeros(basis, basis);
    let mut rhs = DVector::<f64>::zeros(basis);
    let rows: Vec<(usize, [f64; 4])> = x.iter().map(|&v| cubic_basis(&knots, v)).collect();
    for ((first, b), &yi) in rows.iter().zip(y) {
        for a in 0..4 {
            rhs[first + a] += b[a] * yi;
            for c in 0..4 {
                normal[(first + a, first + c)] += b[a] * b[c];
            }
        }
    }
    let ridge = RIDGE * normal.trace() / basis as f64;
    for j in 0..basis {
        normal[(j, j)] += ridge.max(f64::MIN_POSITIVE);
    }
    let coef = Cholesky::new(normal)?.solve(&rhs);
    let sse = rows
        .iter()
        .zip(y)
        .map(|((first, b), yi)| {
            let fit: f64 = (0..4).map(|a| b[a] * coef[first + a]).sum();
            (yi - fit).powi(2)
        })
        .sum();
    Some((sse, basis))
}

/// `interior` knots over `x`, at equal steps of a measure that is half the rows (sorted by
/// `x`) and half the length of the curve of `y` (smoothed) against `x`, both scaled to their
/// ranges: knots crowd where the curve turns fast.
fn knots_along_the_curve(x: &[f64], y: &[f64], interior: usize) -> Vec<f64> {
    let mut order: Vec<usize> = (0..x.len()).collect();
    order.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
    let half = KNOT_SMOOTHING_ROWS / 2;
    let smooth: Vec<f64> = (0..order.len())
        .map(|k| {
            let window = &order[k.saturating_sub(half)..(k + half + 1).min(order.len())];
            window.iter().map(|&i| y[i]).sum::<f64>() / window.len() as f64
        })
        .collect();
    let x_range = match (order.first(), order.last()) {
        (Some(&first), Some(&last)) => (x[last] - x[first]).max(f64::MIN_POSITIVE),
        _ => return Vec::new(),
    };
    let (y_lo, y_hi) = smooth
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let y_range = (y_hi - y_lo).max(f64::MIN_POSITIVE);
    let mut length = vec![0.0; order.len()];
    for k in 1..order.len() {
        let dx = (x[order[k]] - x[order[k - 1]]) / x_range;
        let dy = (smooth[k] - smooth[k - 1]) / y_range;
        length[k] = length[k - 1] + dx.hypot(dy);
    }
    let total = length.last().copied().unwrap_or(0.0).max(f64::MIN_POSITIVE);
    let last = (order.len() - 1).max(1) as f64;
    let measure: Vec<f64> = (0..order.len())
        .map(|k| 0.5 * k as f64 / last + 0.5 * length[k] / total)
        .collect();
    (1..=interior)
        .filter_map(|j| {
            let target = j as f64 / (interior + 1) as f64;
            let k = measure.partition_point(|&m| m < target);
            order.get(k).map(|&i| x[i])
        })
        .collect()
}

/// The four cubic B-splines that are non-zero at `x` on the clamped knot vector `t`: the
/// index of the first and their values (Cox-de Boor).
fn cubic_basis(t: &[f64], x: f64) -> (usize, [f64; 4]) {
    let last_span = t.len() - 5;
    // The span t[s] <= x < t[s + 1], within 3..=last_span.
    let mut s = 3;
    while s < last_span && x >= t[s + 1] {
        s += 1;
    }
    let mut n = [0.0; 4];
    n[0] = 1.0;
    let (mut left, mut right) = ([0.0; 4], [0.0; 4]);
    for j in 1..=3 {
        left[j] = x - t[s + 1 - j];
        right[j] = t[s + j] - x;
        let mut saved = 0.0;
        for r in 0..j {
            let denom = right[r + 1] + left[j - r];
            let temp = if denom != 0.0 { n[r] / denom } else { 0.0 };
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
    (s - 3, n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Dataset;

    #[test]
    fn the_basis_sums_to_one_and_a_cubic_is_fitted_exactly() {
        let t = [0.0, 0.0, 0.0, 0.0, 1.0, 2.5, 4.0, 4.0, 4.0, 4.0];
        for x in [0.0, 0.3, 1.0, 2.0, 3.99, 4.0] {
            let (_, b) = cubic_basis(&t, x);
            assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{x}: {b:?}");
        }
        let x: Vec<f64> = (0..400).map(|i| -10.0 + i as f64 * 0.05).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|v| 3.0 + v - 0.2 * v * v + 0.01 * v.powi(3))
            .collect();
        let (sse, coefficients) = spline_residual_sse(&x, &y).unwrap();
        assert!(sse < 1e-12 * 400.0);
        assert_eq!(coefficients, MAX_INTERIOR_KNOTS + 4);
    }

    #[test]
    fn short_steep_sweeps_leave_only_their_noise() {
        // Runs of 56 rows sweeping the slip ratio over +-0.25 and back: a force that turns
        // from -5 to +5 kN within +-0.03, with uniform noise of 40 N standard deviation.
        let (runs, rows) = (20, 56);
        let amplitude = 40.0 * 3f64.sqrt();
        let mut state = 7;
        let (mut run, mut kappa, mut fx) = (Vec::new(), Vec::new(), Vec::new());
        for r in 0..runs {
            for i in 0..rows {
                let phase = i as f64 / rows as f64;
                let k =
                    0.25 * (1.0 - 4.0 * (phase - 0.5).abs()) * if r % 2 == 0 { 1.0 } else { -1.0 };
                let u = (crate::method::splitmix::splitmix64(&mut state) >> 11) as f64
                    / (1u64 << 53) as f64;
                run.push(r as i64);
                kappa.push(k);
                fx.push(5000.0 * (1.6 * (12.0 * k).atan()).sin() + amplitude * (2.0 * u - 1.0));
            }
        }
        let total = run.len();
        let ds = Dataset {
            run: run.into(),
            fz: vec![4000.0; total].into(),
            kappa: Some(kappa.into()),
            fx: Some(fx.into()),
            ..Dataset::default()
        };
        let data = ChannelData::from_dataset(&ds, Channel::Fx).unwrap();
        let f = floor(&data);
        assert_eq!(f.swept_runs, runs);
        assert!((f.rms / 40.0 - 1.0).abs() < 0.2, "{} vs 40", f.rms);
    }

    #[test]
    fn the_floor_keeps_noise_and_hysteresis_and_drops_the_curve() {
        // Two runs sweeping the slip angle up and down: a tire curve, plus 30 N of
        // hysteresis (+30 rising, -30 falling) and a flat run at zero slip with noise.
        let n = 2000;
        let mut run = Vec::new();
        let (mut alpha, mut fy) = (Vec::new(), Vec::new());
        for i in 0..n {
            let phase = (i % 1000) as f64 / 1000.0;
            let a = 10.0 * (2.0 * std::f64::consts::PI * phase).sin();
            let rising = (2.0 * std::f64::consts::PI * phase).cos() > 0.0;
            run.push((i / 1000) as i64);
            alpha.push(a.to_radians());
            fy.push(2000.0 * (1.3 * (0.2 * a).atan()).sin() + if rising { 30.0 } else { -30.0 });
        }
        for i in 0..500 {
            run.push(9);
            alpha.push(0.0);
            fy.push(if i % 2 == 0 { 10.0 } else { -10.0 });
        }
        let total = run.len();
        let ds = Dataset {
            run: run.into(),
            fz: vec![3000.0; total].into(),
            alpha: Some(alpha.into()),
            fy: Some(fy.into()),
            ..Dataset::default()
        };
        let data = ChannelData::from_dataset(&ds, Channel::Fy).unwrap();
        let f = floor(&data);
        assert_eq!((f.swept_runs, f.flat_runs), (2, 1));
        // The hysteresis (30 N on 2000 rows) and the noise (10 N on 500) are what is left.
        let want = ((2000.0 * 900.0 + 500.0 * 100.0) / 2500.0_f64).sqrt();
        assert!((f.rms / want - 1.0).abs() < 0.05, "{} vs {want}", f.rms);
    }
}
