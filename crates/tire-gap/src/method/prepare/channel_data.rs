//! One channel's measured rows, converted once to the formula's units: what the fits, the
//! candidate effects' drivers and the figures read.

use std::cell::RefCell;
use std::collections::HashMap;

use mf87::{Channel, units};

use crate::data::{Dataset, Quantity, RunColumn};

/// Camber beyond this \[deg\] somewhere in the data: the camber coefficients are fitted.
pub const CAMBER_VARIES_DEG: f64 = 0.05;

pub use crate::data::Column;

/// One channel's measured rows, converted once to the formula's units.
#[derive(Debug, Clone)]
pub struct ChannelData {
    pub channel: Channel,
    pub run: RunColumn,
    /// Load \[kN\].
    pub fz_kn: Column,
    /// Slip in the formula's units: alpha \[deg\] for Fy and Mz, sigma \[percent\] for Fx.
    pub slip: Column,
    /// Camber \[deg\] (zeros when not measured). The 1987 Fx has no camber terms; its effects
    /// and the reference fit may.
    pub gamma_deg: Column,
    /// Measured force \[N\] or moment [N.m].
    pub measured: Column,
    /// The other slip, where measured: slip ratio for Fy and Mz, slip angle \[rad\] for Fx.
    pub other_slip: Option<Column>,
    pub time: Option<Column>,
    pub speed: Option<Column>,
    pub pressure: Option<Column>,
    pub temperature: Option<Column>,
    /// The rows a fit's residuals count (`None`: all). The others only carry the history of
    /// the slip's lag into the counted rows (see [`ChannelData::fitting_sample`]).
    pub counted: Option<Vec<bool>>,
}

/// A column converted from a data set's, built once for all channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Derived {
    FzKn,
    AlphaDeg,
    SigmaPercent,
    GammaDeg,
    Zeros,
}

/// A data set's columns for its channels: its own, shared, and the converted ones built so far.
struct SharedColumns<'a> {
    ds: &'a Dataset,
    built: RefCell<HashMap<Derived, Column>>,
}

impl<'a> SharedColumns<'a> {
    fn new(ds: &'a Dataset) -> Self {
        SharedColumns {
            ds,
            built: RefCell::new(HashMap::new()),
        }
    }

    /// The column `what`, or `None` when the data set lacks the quantity it comes from.
    fn get(&self, what: Derived) -> Option<Column> {
        if let Some(c) = self.built.borrow().get(&what) {
            return Some(c.clone());
        }
        let ds = self.ds;
        let convert = |q: Quantity, f: fn(f64) -> f64| -> Option<Column> {
            Some(ds.column(q)?.iter().map(|v| f(*v)).collect())
        };
        let column: Column = match what {
            Derived::FzKn => convert(Quantity::Fz, units::newtons_to_kilonewtons)?,
            Derived::AlphaDeg => convert(Quantity::Alpha, units::radians_to_degrees)?,
            Derived::SigmaPercent => convert(Quantity::Kappa, units::slip_ratio_to_percent)?,
            Derived::GammaDeg => convert(Quantity::Gamma, units::radians_to_degrees)?,
            Derived::Zeros => vec![0.0; ds.len()].into(),
        };
        self.built.borrow_mut().insert(what, column.clone());
        Some(column)
    }

    /// One channel's rows, or `None` when the measurement or its slip is missing.
    fn channel(&self, channel: Channel) -> Option<ChannelData> {
        let copy = |q: Quantity| self.ds.column_shared(q);
        let (measured, slip, other_slip) = match channel {
            Channel::Fx => (Quantity::Fx, Derived::SigmaPercent, Quantity::Alpha),
            Channel::Fy => (Quantity::Fy, Derived::AlphaDeg, Quantity::Kappa),
            Channel::Mz => (Quantity::Mz, Derived::AlphaDeg, Quantity::Kappa),
        };
        let measured = copy(measured)?;
        let slip = self.get(slip)?;
        let gamma_deg = self
            .get(Derived::GammaDeg)
            .or_else(|| self.get(Derived::Zeros))?;
        Some(ChannelData {
            channel,
            run: self.ds.run.clone(),
            fz_kn: self.get(Derived::FzKn)?,
            slip,
            gamma_deg,
            measured,
            other_slip: copy(other_slip),
            time: copy(Quantity::Time),
            speed: copy(Quantity::Speed),
            pressure: copy(Quantity::Pressure),
            temperature: copy(Quantity::Temperature),
            counted: None,
        })
    }
}

/// A fit reads at most this many counted rows: beyond it, more rows do not sharpen a few
/// dozen parameters, they only cost time and memory. Predictions, held-out residuals, scores
/// and tests always use every row.
pub const FIT_ROWS_MAX: usize = 25_000;
/// Consecutive counted rows per block of a fitting sample.
const BLOCK_ROWS: usize = 100;
/// Rows before each block that carry the slip's lag history in (0.5 s at 100 Hz: five
/// relaxation lengths of 0.5 m at 5 m/s) and are not counted.
const WARMUP_ROWS: usize = 50;

impl ChannelData {
    /// The channel's rows, or `None` when the measurement or its slip is missing.
    pub fn from_dataset(ds: &Dataset, channel: Channel) -> Option<ChannelData> {
        SharedColumns::new(ds).channel(channel)
    }

    /// The rows of each of `channels` the data set measures (with its slip), sharing the
    /// columns they have in common.
    pub fn channels_of(ds: &Dataset, channels: &[Channel]) -> Vec<ChannelData> {
        let shared = SharedColumns::new(ds);
        channels.iter().filter_map(|c| shared.channel(*c)).collect()
    }

    pub fn len(&self) -> usize {
        self.measured.len()
    }

    pub fn is_empty(&self) -> bool {
        self.measured.is_empty()
    }

    /// The subset at positions `keep` (positions into this channel's rows).
    pub fn subset(&self, keep: &[usize]) -> ChannelData {
        self.picked(|| keep.iter().copied())
    }

    /// The consecutive rows `rows`.
    pub fn range(&self, rows: std::ops::Range<usize>) -> ChannelData {
        self.picked(|| rows.clone())
    }

    /// The rows at the positions `rows()` gives, in that order.
    fn picked<I: Iterator<Item = usize>>(&self, rows: impl Fn() -> I) -> ChannelData {
        let pick = |v: &[f64]| -> Column { rows().map(|i| v[i]).collect() };
        let pick_opt = |v: &Option<Column>| v.as_deref().map(pick);
        ChannelData {
            channel: self.channel,
            run: rows().map(|i| self.run[i]).collect(),
            fz_kn: pick(&self.fz_kn),
            slip: pick(&self.slip),
            gamma_deg: pick(&self.gamma_deg),
            measured: pick(&self.measured),
            other_slip: pick_opt(&self.other_slip),
            time: pick_opt(&self.time),
            speed: pick_opt(&self.speed),
            pressure: pick_opt(&self.pressure),
            temperature: pick_opt(&self.temperature),
            counted: self
                .counted
                .as_ref()
                .map(|c| rows().map(|i| c[i]).collect()),
        }
    }

    /// The rows a fit reads: all of them up to [`FIT_ROWS_MAX`] (and a little beyond, up to
    /// where each stretch holds one block with its warm-up); otherwise [`FIT_ROWS_MAX`]
    /// counted rows in blocks of consecutive rows spread over the whole data set (one per
    /// stretch of rows, at a position within it that varies from stretch to stretch, so runs
    /// of equal length are not all sampled at the same phase), each after uncounted warm-up
    /// rows. Rows that are a fitting sample already (that say which rows count) are their
    /// own.
    pub fn fitting_sample(&self) -> std::borrow::Cow<'_, ChannelData> {
        if self.counted.is_some() {
            return std::borrow::Cow::Borrowed(self);
        }
        match sample_plan(self.len()) {
            None => std::borrow::Cow::Borrowed(self),
            Some((keep, counted)) => {
                let mut sample = self.subset(&keep);
                sample.counted = Some(counted);
                std::borrow::Cow::Owned(sample)
            }
        }
    }

    /// The fitting sample (as [`ChannelData::fitting_sample`]) of the rows in `ranges`
    /// (ascending and disjoint, e.g. a fold's training rows), without first copying or
    /// listing them all. Of rows that are a fitting sample already, the rows themselves.
    pub fn fitting_subset(&self, ranges: &[std::ops::Range<usize>]) -> ChannelData {
        let n = ranges.iter().map(|r| r.len()).sum();
        let plan = match self.counted {
            Some(_) => None,
            None => sample_plan(n),
        };
        match plan {
            None => self.subset(&ranges.iter().cloned().flatten().collect::<Vec<usize>>()),
            Some((keep, counted)) => {
                // `keep` ascends: walk the ranges once.
                let mut rows = Vec::with_capacity(keep.len());
                let (mut r, mut before) = (0, 0);
                for k in keep {
                    while k >= before + ranges[r].len() {
                        before += ranges[r].len();
                        r += 1;
                    }
                    rows.push(ranges[r].start + (k - before));
                }
                let mut sample = self.subset(&rows);
                sample.counted = Some(counted);
                sample
            }
        }
    }

    /// The slip rate within runs [slip units per s], by central differences over the rows of
    /// a run in file order; 0 where a row has no neighbour in its run or time does not advance.
    /// `None` without time.
    pub fn slip_rate(&self) -> Option<Vec<f64>> {
        let rate = self.slip_rate_at()?;
        Some((0..self.len()).map(rate).collect())
    }

    /// [`ChannelData::slip_rate`] at a row, worked out as it is asked for (no series of
    /// every row); `None` without time.
    pub fn slip_rate_at(&self) -> Option<impl Fn(usize) -> f64 + '_> {
        let t = self.time.as_ref()?;
        let n = self.len();
        let same = |a: usize, b: usize| self.run[a] == self.run[b];
        Some(move |i: usize| {
            let lo = if i > 0 && same(i - 1, i) { i - 1 } else { i };
            let hi = if i + 1 < n && same(i + 1, i) {
                i + 1
            } else {
                i
            };
            let dt = t[hi] - t[lo];
            if hi > lo && dt > 0.0 {
                (self.slip[hi] - self.slip[lo]) / dt
            } else {
                0.0
            }
        })
    }

    /// Whether camber varies in these rows (else the camber coefficients are not identifiable).
    pub fn has_camber(&self) -> bool {
        self.gamma_deg.iter().any(|g| g.abs() > CAMBER_VARIES_DEG)
    }
}

/// Each run's rows of `run_of_row` as the stretches of consecutive rows it holds, runs by
/// id: a few ranges a run, not a list of every row.
pub fn run_stretches(
    run_of_row: &[i64],
) -> std::collections::BTreeMap<i64, Vec<std::ops::Range<usize>>> {
    let mut runs: std::collections::BTreeMap<i64, Vec<std::ops::Range<usize>>> =
        std::collections::BTreeMap::new();
    let mut start = 0;
    for i in 1..=run_of_row.len() {
        if i == run_of_row.len() || run_of_row[i] != run_of_row[start] {
            runs.entry(run_of_row[start]).or_default().push(start..i);
            start = i;
        }
    }
    runs
}

/// Ascending positions as ranges of consecutive rows.
pub fn ranges_of(positions: &[usize]) -> Vec<std::ops::Range<usize>> {
    merged(positions.iter().map(|&i| i..i + 1))
}

/// Ascending, disjoint ranges with those that touch joined into one.
pub fn merged(
    ranges: impl IntoIterator<Item = std::ops::Range<usize>>,
) -> Vec<std::ops::Range<usize>> {
    let mut out: Vec<std::ops::Range<usize>> = Vec::new();
    for next in ranges {
        match out.last_mut() {
            Some(r) if r.end == next.start => r.end = next.end,
            _ => out.push(next),
        }
    }
    out
}

/// Which of `n` rows a fitting sample keeps, and which of those it counts; `None`: all rows.
/// Up to [`FIT_ROWS_MAX`] rows, all; up to where each stretch holds one block with its
/// warm-up, every row kept and [`FIT_ROWS_MAX`] of them, evenly spaced, counted (a lagged
/// slip has every row's history; a model without a lag reads only the counted rows).
fn sample_plan(n: usize) -> Option<(Vec<usize>, Vec<bool>)> {
    if n <= FIT_ROWS_MAX {
        return None;
    }
    let blocks = FIT_ROWS_MAX / BLOCK_ROWS;
    let stretch = n / blocks;
    if stretch <= BLOCK_ROWS + WARMUP_ROWS {
        let mut counted = vec![false; n];
        for k in 0..FIT_ROWS_MAX {
            counted[k * n / FIT_ROWS_MAX] = true;
        }
        return Some(((0..n).collect(), counted));
    }
    let mut state = 0x005a_3b1e_u64;
    let mut keep = Vec::with_capacity(blocks * (BLOCK_ROWS + WARMUP_ROWS));
    let mut counted = Vec::with_capacity(keep.capacity());
    for b in 0..blocks {
        let slack = (stretch - BLOCK_ROWS - WARMUP_ROWS) as u64;
        let start =
            b * stretch + (crate::method::splitmix::splitmix64(&mut state) % slack) as usize;
        for i in start..start + WARMUP_ROWS + BLOCK_ROWS {
            keep.push(i);
            counted.push(i >= start + WARMUP_ROWS);
        }
    }
    Some((keep, counted))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(n: usize) -> ChannelData {
        let ds = Dataset {
            run: (0..n).map(|i| (i / 1000) as i64).collect(),
            fz: vec![4000.0; n].into(),
            alpha: Some((0..n).map(|i| i as f64).collect()),
            fy: Some(vec![0.0; n].into()),
            ..Dataset::default()
        };
        ChannelData::from_dataset(&ds, Channel::Fy).unwrap()
    }

    #[test]
    fn a_fitting_sample_counts_at_most_the_cap_in_blocks_spread_over_all_rows() {
        // Up to the cap: every row.
        assert!(matches!(
            rows(FIT_ROWS_MAX).fitting_sample(),
            std::borrow::Cow::Borrowed(_)
        ));
        // Up to a block with its warm-up per stretch: every row kept, the cap counted, every
        // row but at most one between two counted ones.
        let n = FIT_ROWS_MAX / BLOCK_ROWS * (BLOCK_ROWS + WARMUP_ROWS);
        let middle = rows(n);
        let sample = middle.fitting_sample();
        assert_eq!(sample.len(), n);
        let counted = sample.counted.as_ref().unwrap();
        assert_eq!(counted.iter().filter(|c| **c).count(), FIT_ROWS_MAX);
        assert!(counted[0] && counted.windows(3).all(|w| w.iter().any(|c| *c)));
        let all = rows(1_000_000);
        let sample = all.fitting_sample();
        let counted = sample.counted.as_ref().unwrap();
        assert_eq!(counted.iter().filter(|c| **c).count(), FIT_ROWS_MAX);
        assert_eq!(
            sample.len(),
            FIT_ROWS_MAX / BLOCK_ROWS * (BLOCK_ROWS + WARMUP_ROWS)
        );
        // Rows keep their order; each block is consecutive rows after its warm-up.
        let position = |k: usize| sample.slip[k].to_radians().round() as usize;
        let block = BLOCK_ROWS + WARMUP_ROWS;
        for b in 0..FIT_ROWS_MAX / BLOCK_ROWS {
            let first = position(b * block);
            for k in 0..block {
                assert_eq!(position(b * block + k), first + k);
                assert_eq!(counted[b * block + k], k >= WARMUP_ROWS);
            }
            // One block in each stretch of the data.
            let stretch = all.len() / (FIT_ROWS_MAX / BLOCK_ROWS);
            assert_eq!(first / stretch, b);
        }
        // Not all at the same phase of equal stretches.
        let phases: std::collections::BTreeSet<usize> = (0..20)
            .map(|b| position(b * block) % (all.len() / (FIT_ROWS_MAX / BLOCK_ROWS)))
            .collect();
        assert!(phases.len() > 10, "{phases:?}");
        // A subset's sample is the sample of the subset.
        let odd: Vec<usize> = (0..all.len()).filter(|i| i % 2 == 1).collect();
        let direct = all.fitting_subset(&ranges_of(&odd));
        let copied = all.subset(&odd);
        let twice = copied.fitting_sample();
        assert_eq!(direct.slip, twice.slip);
        assert_eq!(direct.counted, twice.counted);
        // A sample is its own sample: a fit given one counts the rows it says.
        let again = direct.fitting_sample();
        assert!(matches!(again, std::borrow::Cow::Borrowed(_)));
        assert_eq!(again.counted, direct.counted);
        let some: Vec<usize> = (0..direct.len()).step_by(3).collect();
        let part = direct.fitting_subset(&ranges_of(&some));
        assert_eq!(part.slip, direct.subset(&some).slip);
        assert_eq!(part.counted, direct.subset(&some).counted);
    }
}
