//! How a channel's held-out residual evolves over the run order: per run, its mean, its RMS
//! and the measured force as a multiple of the model's, and whether that multiple trends over
//! the programme (a drift such as wear: the tire gives less force run after run).

use mf87::Channel;
use serde::Serialize;

use crate::method::diagnose::design::run_order;
use crate::method::splitmix::splitmix64;
use crate::method::stats::correlation;

/// Fewest runs with a force scale for a trend over the run order.
pub const MIN_TREND_RUNS: usize = 8;
/// A run's force scale is measured only where the model's force is at least this many noise
/// floors (RMS over the run): near zero force the ratio is noise over noise.
const MIN_FORCE_IN_NOISE: f64 = 5.0;
/// Random orderings of the permutation test.
const PERMUTATIONS: u64 = 20_000;

/// One run's held-out residual.
#[derive(Debug, Clone, Serialize)]
pub struct RunResidual {
    pub run: i64,
    /// Position in the programme (order of first appearance in the input, from 0).
    pub position: usize,
    pub rows: usize,
    /// Mean and RMS of the held-out residual (measured minus predicted) [N or N.m].
    pub mean: f64,
    pub rms: f64,
    /// Least-squares `s` in `measured - predicted = s * predicted`: the measured force is
    /// (1 + s) times the model's. `null` where the model's force is too small to say.
    pub force_scale: Option<f64>,
}

/// The trend of the runs' force scale over the run order.
#[derive(Debug, Clone, Serialize)]
pub struct Trend {
    pub runs: usize,
    /// Pearson correlation of force scale with run position.
    pub correlation: f64,
    /// Least-squares change of the force scale from the first run to the last.
    pub change: f64,
    /// Two-sided permutation p-value of the correlation (run order shuffled).
    pub p_value: f64,
    /// p below the diagnosis's significance level, shared among the channels reported.
    pub significant: bool,
}

/// A channel's remaining held-out residual over the run order.
#[derive(Debug, Clone, Serialize)]
pub struct ResidualOverRuns {
    pub channel: Channel,
    pub unit: &'static str,
    pub runs: Vec<RunResidual>,
    pub trend: Option<Trend>,
    /// Why there is no trend, when there is none.
    pub no_trend: Option<String>,
}

/// The residual per run of one channel; `residuals` are held-out (measured minus predicted).
pub fn per_run(run: &[i64], measured: &[f64], residuals: &[f64], noise: f64) -> Vec<RunResidual> {
    let order = run_order(run);
    let mut sums = vec![(0usize, 0.0, 0.0, 0.0, 0.0); order.len()];
    for ((r, m), e) in run.iter().zip(measured).zip(residuals) {
        if !(m.is_finite() && e.is_finite()) {
            continue;
        }
        let predicted = m - e;
        let s = &mut sums[order[r]];
        s.0 += 1;
        s.1 += e;
        s.2 += e * e;
        s.3 += e * predicted;
        s.4 += predicted * predicted;
    }
    let mut runs: Vec<(i64, usize)> = order.into_iter().collect();
    runs.sort_by_key(|&(_, k)| k);
    runs.into_iter()
        .filter(|&(_, k)| sums[k].0 > 0)
        .map(|(r, k)| {
            let (n, se, see, sep, spp) = sums[k];
            let n_f = n as f64;
            let force_rms = (spp / n_f).sqrt();
            RunResidual {
                run: r,
                position: k,
                rows: n,
                mean: se / n_f,
                rms: (see / n_f).sqrt(),
                force_scale: (force_rms >= MIN_FORCE_IN_NOISE * noise && spp > 0.0)
                    .then(|| sep / spp),
            }
        })
        .collect()
}

/// The trend of `runs`' force scale over their position, tested at `significance`; or why
/// there is none.
pub fn trend(runs: &[RunResidual], significance: f64) -> Result<Trend, String> {
    let (x, y): (Vec<f64>, Vec<f64>) = runs
        .iter()
        .filter_map(|r| Some((r.position as f64, r.force_scale?)))
        .unzip();
    if x.len() < MIN_TREND_RUNS {
        return Err(format!(
            "{} run(s) with enough force to measure a force scale; a trend over the run order \
             needs {MIN_TREND_RUNS}",
            x.len()
        ));
    }
    let r = correlation(&x, &y).ok_or("the force scale is the same in every run")?;
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let span = x.last().unwrap_or(&0.0) - x.first().unwrap_or(&0.0);
    let p_value = permutation_p(&x, &y, r.abs());
    Ok(Trend {
        runs: x.len(),
        correlation: r,
        change: sxy / sxx * span,
        p_value,
        significant: p_value < significance,
    })
}

/// Two-sided permutation p-value of |correlation(x, y)| >= `observed` with `y` shuffled.
fn permutation_p(x: &[f64], y: &[f64], observed: f64) -> f64 {
    let mut state = 0x7e4d_0bde_4a11_u64;
    let mut shuffled = y.to_vec();
    let mut hits = 0u64;
    for _ in 0..PERMUTATIONS {
        for i in (1..shuffled.len()).rev() {
            let j = (splitmix64(&mut state) % (i as u64 + 1)) as usize;
            shuffled.swap(i, j);
        }
        if correlation(x, &shuffled).is_some_and(|c| c.abs() >= observed - 1e-12) {
            hits += 1;
        }
    }
    (hits + 1) as f64 / (PERMUTATIONS + 1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 12 runs of 50 rows, model force a 2 kN sine; the measured force `(1 + s_k)` times it.
    fn programme(scale: impl Fn(usize) -> f64) -> (Vec<i64>, Vec<f64>, Vec<f64>) {
        let (mut run, mut measured, mut residual) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..12 {
            for i in 0..50 {
                let predicted = 2000.0 * (i as f64 * 0.3).sin();
                let m = (1.0 + scale(k)) * predicted;
                run.push(100 - k as i64);
                measured.push(m);
                residual.push(m - predicted);
            }
        }
        (run, measured, residual)
    }

    #[test]
    fn a_steady_loss_of_grip_is_a_significant_trend_of_its_size() {
        // 0.5 % less force per run: -5.5 % from the first run to the last.
        let (run, m, e) = programme(|k| -0.005 * k as f64);
        let runs = per_run(&run, &m, &e, 20.0);
        assert_eq!(runs.len(), 12);
        assert_eq!((runs[0].run, runs[0].position, runs[0].rows), (100, 0, 50));
        assert!((runs[11].force_scale.unwrap() + 0.055).abs() < 1e-12);
        let t = trend(&runs, 0.05).unwrap();
        assert!((t.change + 0.055).abs() < 1e-12, "{t:?}");
        assert!((t.correlation + 1.0).abs() < 1e-12);
        // Only the two orderings that keep the runs sorted (either way) reach |r| = 1.
        assert!(t.p_value < 1e-3 && t.significant, "{t:?}");
    }

    #[test]
    fn scatter_without_order_is_no_trend() {
        let wobble = [
            0.01, -0.02, 0.015, -0.005, 0.0, 0.02, -0.015, 0.005, -0.01, 0.012, -0.018, 0.008,
        ];
        let (run, m, e) = programme(|k| wobble[k]);
        let t = trend(&per_run(&run, &m, &e, 20.0), 0.05).unwrap();
        assert!(t.p_value > 0.2 && !t.significant, "{t:?}");
    }

    #[test]
    fn runs_without_force_have_no_scale_and_too_few_give_no_trend() {
        let (run, m, e) = programme(|k| -0.005 * k as f64);
        // A noise floor of 300 N: the 1.4 kN RMS force is below 5 floors.
        let runs = per_run(&run, &m, &e, 300.0);
        assert!(runs.iter().all(|r| r.force_scale.is_none()));
        let err = trend(&runs, 0.05).unwrap_err();
        assert!(err.starts_with("0 run(s)"), "{err}");
    }
}
