//! How many rows the models were evaluated on, for values and for exact derivatives (by the
//! width of the dual numbers that carry them), and what those rows cost at the bare
//! formula's rate: the floor a diagnosis's time is measured against (`tire-gap diagnose
//! --profile`). The counts are the process's: diagnoses run at once in one process add to
//! the same counts, so a profile is taken of one diagnosis at a time.

use std::hint::black_box;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use mf87::formula::factors;
use mf87::{Channel, Params, Real};
use num_dual::DualSVec64;

/// The widths rows are evaluated at: 0 for values (`f64`), else the dual numbers' number of
/// derivative lanes (those the Jacobians use).
pub const WIDTHS: [usize; 8] = [0, 1, 2, 4, 8, 16, 24, 32];

/// The formulas rows are evaluated with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Formula {
    /// The 1987 model with its effects: the base, candidate and fold fits.
    Mf87,
    /// The MF 6.1 reference fit.
    Mf61,
}

const FORMULAS: usize = 2;

static ROWS: [[AtomicU64; WIDTHS.len()]; FORMULAS] =
    [const { [const { AtomicU64::new(0) }; WIDTHS.len()] }; FORMULAS];

/// Counts `rows` evaluated with `formula` at dual width `width` (0: values; a width not in
/// [`WIDTHS`] counts as the widest).
pub(crate) fn record(formula: Formula, width: usize, rows: usize) {
    let k = WIDTHS
        .iter()
        .position(|w| *w == width)
        .unwrap_or(WIDTHS.len() - 1);
    ROWS[formula as usize][k].fetch_add(rows as u64, Ordering::Relaxed);
}

/// Rows evaluated, per formula and per entry of [`WIDTHS`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counts(pub [[u64; WIDTHS.len()]; FORMULAS]);

impl Counts {
    /// The process's counts now.
    pub fn now() -> Counts {
        Counts(std::array::from_fn(|f| {
            std::array::from_fn(|k| ROWS[f][k].load(Ordering::Relaxed))
        }))
    }

    /// The rows counted since `earlier`.
    pub fn since(&self, earlier: &Counts) -> Counts {
        Counts(std::array::from_fn(|f| {
            std::array::from_fn(|k| self.0[f][k] - earlier.0[f][k])
        }))
    }

    /// `formula`'s rows per entry of [`WIDTHS`].
    pub fn of(&self, formula: Formula) -> &[u64; WIDTHS.len()] {
        &self.0[formula as usize]
    }
}

/// A formula whose bare rate is measured: its coefficients, and its value at a row (load
/// in kN, camber in deg, slip in deg or percent) over any number type.
pub trait Bare {
    fn coefficients(&self) -> Vec<f64>;
    fn eval<T: Real>(&self, c: &[T], fz_kn: f64, gamma_deg: f64, slip: f64) -> T;
}

/// The 1987 formula of one channel, bare: its load and camber factors, then the formula at the
/// slip; no extension.
pub struct Bare87(pub Channel);

impl Bare for Bare87 {
    fn coefficients(&self) -> Vec<f64> {
        let params = Params::paper_table();
        (0..Params::coefficient_names(self.0).len())
            .map(|i| params.coefficient(self.0, i).unwrap_or(0.0))
            .collect()
    }

    fn eval<T: Real>(&self, c: &[T], fz_kn: f64, gamma_deg: f64, slip: f64) -> T {
        factors(self.0, c, T::from(fz_kn), T::from(gamma_deg)).eval(T::from(slip))
    }
}

/// Rows of the bare-rate measurement at each width.
const RATE_ROWS: usize = 50_000;

/// Times each width is measured; the rate is the median of these (one timing on a shared
/// machine varies by a tenth from run to run).
const RATE_REPEATS: usize = 5;

/// Seconds per row of `formula`, single-threaded, at each of [`WIDTHS`] (dual numbers with
/// every lane seeded), on `RATE_ROWS` rows spread over load 2..6 kN, camber +-3 deg and
/// slip +-10: the median of `RATE_REPEATS` timings.
pub fn bare_seconds_per_row(formula: &impl Bare) -> [f64; WIDTHS.len()] {
    let c = formula.coefficients();
    std::array::from_fn(|k| match WIDTHS[k] {
        0 => time_width::<f64>(formula, &c, |v, _| v),
        1 => time_width::<DualSVec64<1>>(formula, &c, seeded),
        2 => time_width::<DualSVec64<2>>(formula, &c, seeded),
        4 => time_width::<DualSVec64<4>>(formula, &c, seeded),
        8 => time_width::<DualSVec64<8>>(formula, &c, seeded),
        16 => time_width::<DualSVec64<16>>(formula, &c, seeded),
        24 => time_width::<DualSVec64<24>>(formula, &c, seeded),
        _ => time_width::<DualSVec64<32>>(formula, &c, seeded),
    })
}

/// Coefficient `k` as a dual number whose lane `k mod N` is seeded.
fn seeded<const N: usize>(v: f64, k: usize) -> DualSVec64<N> {
    DualSVec64::from(v).derivative(k % N)
}

fn time_width<T: Real>(formula: &impl Bare, c: &[f64], lift: impl Fn(f64, usize) -> T) -> f64 {
    let c: Vec<T> = c.iter().enumerate().map(|(i, v)| lift(*v, i)).collect();
    let u = |i: usize, a: f64| (i as f64 * a).fract();
    let mut timings: Vec<f64> = (0..RATE_REPEATS)
        .map(|_| {
            let start = Instant::now();
            let mut sum = T::from(0.0);
            for i in 0..RATE_ROWS {
                let fz_kn = 2.0 + 4.0 * u(i, 0.618_033_988_7);
                let gamma_deg = -3.0 + 6.0 * u(i, 0.414_213_562_4);
                let slip = -10.0 + 20.0 * u(i, 0.732_050_807_6);
                sum += formula.eval(&c, black_box(fz_kn), gamma_deg, slip);
            }
            black_box(sum);
            start.elapsed().as_secs_f64() / RATE_ROWS as f64
        })
        .collect();
    timings.sort_by(f64::total_cmp);
    timings[RATE_REPEATS / 2]
}

/// Seconds `rows` (per entry of [`WIDTHS`]) take at the rates `seconds_per_row`, one thread.
pub fn seconds_at(rows: &[u64; WIDTHS.len()], seconds_per_row: &[f64; WIDTHS.len()]) -> f64 {
    rows.iter()
        .zip(seconds_per_row)
        .map(|(n, s)| *n as f64 * s)
        .sum()
}

/// The bare 1987 formula's seconds per row at each width: the mean over the three channels.
pub fn bare87_seconds_per_row() -> [f64; WIDTHS.len()] {
    let per: Vec<[f64; WIDTHS.len()]> = Channel::ALL
        .iter()
        .map(|&c| bare_seconds_per_row(&Bare87(c)))
        .collect();
    mean_rates(&per)
}

/// The mean of several formulas' seconds per row, width by width.
pub fn mean_rates(per: &[[f64; WIDTHS.len()]]) -> [f64; WIDTHS.len()] {
    std::array::from_fn(|k| per.iter().map(|s| s[k]).sum::<f64>() / per.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_add_up_by_width_and_a_dual_row_costs_more_than_a_value() {
        let before = Counts::now();
        record(Formula::Mf87, 0, 10);
        record(Formula::Mf87, 8, 3);
        record(Formula::Mf61, 40, 2);
        let delta = Counts::now().since(&before);
        // Other tests of the process may count rows at once: at least ours.
        assert!(delta.of(Formula::Mf87)[0] >= 10 && delta.of(Formula::Mf87)[4] >= 3);
        assert!(delta.of(Formula::Mf61)[7] >= 2);
        let s = bare_seconds_per_row(&Bare87(Channel::Fy));
        assert!(s[0] > 0.0 && s[0] < 1e-5, "{s:?}");
        assert!(s[7] > s[0], "{s:?}");
        let mut rows = [0; WIDTHS.len()];
        rows[0] = 1000;
        assert_eq!(seconds_at(&rows, &s), 1000.0 * s[0]);
    }
}
