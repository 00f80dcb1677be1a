//! The ceiling of a diagnosis: how much of the held-out gap any Magic Formula explains, and
//! what no steady-state model explains.
//!
//! - [`fit_reference`]: the complete Magic Formula 6.1 ([`mf61`]) for Fx and Fy, with the
//!   terms the data can identify, fitted on all data and on the same folds as the diagnosis:
//!   its held-out error is what a modern, published Magic Formula leaves.
//! - [`floor`]: a smoothing spline through each sweep on its own (in-sample): the error it
//!   leaves (noise, hysteresis between the sweep's halves, drift within a sweep) is what no
//!   steady-state model of slip, load and conditions beats.
//!
//! The reference is an independent yardstick, not a candidate: it is never claimed, and the
//! verdict's model is the 1987 formula with the named effects.

pub mod floor;
pub mod mf61;

use std::collections::BTreeMap;
use std::ops::Range;

use mf87::Channel;
use nalgebra::DMatrix;
use num_dual::DualSVec64;
use serde::Serialize;

use crate::method::diagnose::design::{Condition, spread_by};
use crate::method::fit::evaluations::{
    self, Bare, Formula, WIDTHS, bare_seconds_per_row, mean_rates,
};
use crate::method::fit::least_squares::{FULL_BUDGET, least_squares};
use crate::method::parallel::parallel_map;
use crate::method::prepare::channel_data::ChannelData;
use crate::method::prepare::cv::Folds;
use crate::method::stats::CompactResiduals;
use crate::quantiles::quantile;
use mf61::{Needs, Row, Term, Varies};

/// The reference model's name in reports.
pub const REFERENCE_MODEL: &str = "MF 6.1";

/// A combined-slip row: the other slip at least this (slip ratio for Fy; slip angle [deg]
/// for Fx).
const COMBINED_KAPPA: f64 = 0.02;
const COMBINED_ALPHA_DEG: f64 = 1.0;
/// A pure-slip row: the other slip below this.
const PURE_KAPPA: f64 = 0.01;
const PURE_ALPHA_DEG: f64 = 0.5;
/// Combined slip is identified when at least this share of the rows is combined.
const COMBINED_SHARE: f64 = 0.05;
/// Rows per fitted coefficient at least, in any stage's rows.
const ROWS_PER_TERM: usize = 10;
/// Stiffness multipliers of the starts (the measured tire may be stiffer or softer than
/// the typical start).
const STIFFNESS_STARTS: [f64; 3] = [0.6, 1.0, 1.6];
/// Weight of the pull toward each stage's start, relative to the data's root sum of
/// squares, as the base fit's: it keeps flat directions (coefficients the data barely
/// moves) from wandering.
const PRIOR_WEIGHT: f64 = 0.003;
const PRIOR_MIN_SCALE: f64 = 0.1;
/// Columns of the Jacobian taken together as one dual number.
const CHUNK: usize = 16;

/// The MF 6.1 formula of one force, bare, for its rate: its terms' starting values, both
/// slips non-zero (combined slip).
struct Bare61(Channel);

impl Bare for Bare61 {
    fn coefficients(&self) -> Vec<f64> {
        let terms: &[Term] = match self.0 {
            Channel::Fx => &mf61::FX_TERMS,
            _ => &mf61::FY_TERMS,
        };
        terms.iter().map(|t| t.start).collect()
    }

    fn eval<T: mf87::Real>(&self, c: &[T], fz_kn: f64, gamma_deg: f64, slip: f64) -> T {
        let row = Row {
            fz: mf87::units::kilonewtons_to_newtons(fz_kn),
            kappa: mf87::units::percent_to_slip_ratio(slip) / 3.0,
            alpha: mf87::units::degrees_to_radians(slip),
            gamma: mf87::units::degrees_to_radians(gamma_deg),
            dpi: 0.0,
        };
        let fz0 = 4000.0;
        match self.0 {
            Channel::Fx => mf61::fx(c, fz0, &row),
            _ => mf61::fy(c, fz0, &row),
        }
    }
}

/// The bare MF 6.1 formula's seconds per row at each of [`WIDTHS`]: the mean over Fx and Fy.
pub fn bare61_seconds_per_row() -> [f64; WIDTHS.len()] {
    mean_rates(&[
        bare_seconds_per_row(&Bare61(Channel::Fx)),
        bare_seconds_per_row(&Bare61(Channel::Fy)),
    ])
}

/// The reference fit of one channel.
#[derive(Debug, Clone, Serialize)]
pub struct ReferenceFit {
    pub channel: Channel,
    pub model: &'static str,
    /// Held-out RMS over every row, each fold's model on its held-out runs \[N\].
    pub heldout_rms: f64,
    /// RMS of the fit on all data \[N\].
    pub in_sample_rms: f64,
    /// The nominal load Fz0 the load terms are relative to \[N\] (the data's median).
    pub nominal_load_n: f64,
    /// The coefficients fitted (the terms the data identifies), with their values on all
    /// data.
    pub fitted: BTreeMap<&'static str, f64>,
    /// The coefficients left at their neutral values: the data do not vary what they
    /// describe (load, camber, pressure or the other slip).
    pub not_identified: Vec<&'static str>,
    /// Held-out residuals (model minus measurement), each row by its fold's model.
    #[serde(skip)]
    pub heldout: CompactResiduals,
}

/// Rows of one channel in the reference's units, with the measurement: the rows a fit or a
/// stretch of predictions reads, built from the channel's columns when needed rather than
/// all at once.
struct Rows {
    rows: Vec<Row>,
    measured: Vec<f64>,
}

/// Rows predicted at a time where a prediction covers every row.
const PIECE_ROWS: usize = 16_384;

/// Row `i` of `data` in the reference's units (`p0_kpa` the nominal pressure).
fn row_of(data: &ChannelData, p0_kpa: f64, i: usize) -> Row {
    let other = data.other_slip.as_ref().map_or(0.0, |o| o[i]);
    let (kappa, alpha) = match data.channel {
        Channel::Fx => (mf87::units::percent_to_slip_ratio(data.slip[i]), other),
        Channel::Fy | Channel::Mz => (other, mf87::units::degrees_to_radians(data.slip[i])),
    };
    let dpi = data
        .pressure
        .as_ref()
        .map_or(0.0, |p| (p[i] - p0_kpa) / p0_kpa);
    Row {
        fz: mf87::units::kilonewtons_to_newtons(data.fz_kn[i]),
        kappa,
        alpha,
        gamma: mf87::units::degrees_to_radians(data.gamma_deg[i]),
        dpi,
    }
}

impl Rows {
    /// The rows of `data` at `positions`.
    fn at(data: &ChannelData, p0_kpa: f64, positions: &[usize]) -> Rows {
        Rows {
            rows: positions.iter().map(|&i| row_of(data, p0_kpa, i)).collect(),
            measured: positions.iter().map(|&i| data.measured[i]).collect(),
        }
    }

    fn len(&self) -> usize {
        self.rows.len()
    }
}

/// The channel's formula and terms.
struct Model {
    channel: Channel,
    terms: &'static [Term],
    fz0: f64,
}

impl Model {
    fn of(channel: Channel, fz0: f64) -> Option<Model> {
        let terms: &'static [Term] = match channel {
            Channel::Fx => &mf61::FX_TERMS,
            Channel::Fy => &mf61::FY_TERMS,
            Channel::Mz => return None,
        };
        Some(Model {
            channel,
            terms,
            fz0,
        })
    }

    fn eval<T: mf87::Real>(&self, p: &[T], row: &Row) -> T {
        match self.channel {
            Channel::Fx => mf61::fx(p, self.fz0, row),
            _ => mf61::fy(p, self.fz0, row),
        }
    }

    /// Model minus measurement at every row.
    fn residuals(&self, p: &[f64], rows: &Rows, out: &mut [f64]) {
        for (i, (row, y)) in rows.rows.iter().zip(&rows.measured).enumerate() {
            out[i] = self.eval(p, row) - y;
        }
        evaluations::record(Formula::Mf61, 0, rows.len());
    }

    /// The derivatives at every row with respect to the coefficients `free`, into the first
    /// `free.len()` columns of `jac`.
    fn jacobian(&self, p: &[f64], free: &[usize], rows: &Rows, jac: &mut DMatrix<f64>) {
        for (chunk_index, chunk) in free.chunks(CHUNK).enumerate() {
            let mut d: Vec<DualSVec64<CHUNK>> = p.iter().map(|&v| DualSVec64::from(v)).collect();
            for (k, &i) in chunk.iter().enumerate() {
                d[i] = d[i].derivative(k);
            }
            for (r, row) in rows.rows.iter().enumerate() {
                let y = self.eval(&d, row);
                for k in 0..chunk.len() {
                    let v = y.eps.0.as_ref().map_or(0.0, |e| e[k]);
                    jac[(r, chunk_index * CHUNK + k)] = v;
                }
            }
            evaluations::record(Formula::Mf61, CHUNK, rows.len());
        }
    }

    /// Whether the shape factor C stays in (0, 4), where the curve is a tire's.
    fn admissible(&self, p: &[f64]) -> bool {
        let c = match self.channel {
            Channel::Fx => p[mf61::FX_SHAPE],
            _ => p[mf61::FY_SHAPE],
        };
        c > 0.05 && c < 4.0 && p.iter().all(|v| v.is_finite())
    }

    /// Least squares over the coefficients `free` from `p0` on `rows`, with the weak pull
    /// toward `p0`; the coefficients not free keep their values.
    fn fit(&self, p0: &[f64], free: &[usize], rows: &Rows) -> Option<(Vec<f64>, f64)> {
        if free.is_empty() || rows.len() < ROWS_PER_TERM * free.len() {
            return None;
        }
        let m = rows.len();
        let weight = PRIOR_WEIGHT * rows.measured.iter().map(|y| y * y).sum::<f64>().sqrt();
        let x0: Vec<f64> = free.iter().map(|&i| p0[i]).collect();
        let scale = |j: usize| x0[j].abs().max(PRIOR_MIN_SCALE);
        let full = |x: &[f64]| {
            let mut p = p0.to_vec();
            for (&i, &v) in free.iter().zip(x) {
                p[i] = v;
            }
            p
        };
        let residuals = |x: &[f64], out: &mut [f64]| {
            self.residuals(&full(x), rows, &mut out[..m]);
            for j in 0..x.len() {
                out[m + j] = weight * (x[j] - x0[j]) / scale(j);
            }
        };
        let jacobian = |x: &[f64], jac: &mut DMatrix<f64>| {
            self.jacobian(&full(x), free, rows, jac);
            for j in 0..x.len() {
                jac[(m + j, j)] = weight / scale(j);
            }
            true
        };
        let feasible = |x: &[f64]| self.admissible(&full(x));
        let fit = least_squares(
            &x0,
            m + free.len(),
            FULL_BUDGET,
            &residuals,
            Some(&jacobian),
            Some(&feasible),
        )?;
        let p = full(&fit.params);
        let mut r = vec![0.0; m];
        self.residuals(&p, rows, &mut r);
        let sse = r.iter().map(|v| v * v).sum();
        Some((p, sse))
    }
}

/// What the channel's data vary, for the terms they identify.
fn varies(data: &ChannelData, p0_kpa: f64) -> Varies {
    let spread = |value: &dyn Fn(usize) -> f64, c: Condition| {
        spread_by(&data.run, value, c).is_some_and(|s| s.identifiable())
    };
    let n = data.len();
    let combined = (0..n)
        .filter(|&i| is_combined(data.channel, &row_of(data, p0_kpa, i)))
        .count();
    Varies {
        load: spread(&|i| row_of(data, p0_kpa, i).fz, Condition::Load),
        camber: spread(&|i| row_of(data, p0_kpa, i).gamma, Condition::Camber),
        pressure: data
            .pressure
            .as_ref()
            .is_some_and(|p| spread(&|i| p[i], Condition::Pressure)),
        combined: data.other_slip.is_some() && combined as f64 >= COMBINED_SHARE * n as f64,
    }
}

fn is_combined(channel: Channel, r: &Row) -> bool {
    match channel {
        Channel::Fx => r.alpha.abs() >= COMBINED_ALPHA_DEG.to_radians(),
        _ => r.kappa.abs() >= COMBINED_KAPPA,
    }
}

fn is_pure(channel: Channel, r: &Row) -> bool {
    match channel {
        Channel::Fx => r.alpha.abs() < PURE_ALPHA_DEG.to_radians(),
        _ => r.kappa.abs() < PURE_KAPPA,
    }
}

/// The positions in `ranges` (ascending, disjoint) a fit reads: every one up to the base
/// fit's cap, else that many spread evenly over them.
fn sample(ranges: &[Range<usize>]) -> Vec<usize> {
    let cap = crate::method::prepare::channel_data::FIT_ROWS_MAX;
    let n: usize = ranges.iter().map(|r| r.len()).sum();
    if n <= cap {
        return ranges.iter().flat_map(|r| r.clone()).collect();
    }
    let step = n as f64 / cap as f64;
    // The k-th position of the ranges taken together, k ascending: a cursor over the ranges.
    let (mut at, mut before) = (0, 0);
    (0..cap)
        .map(|k| {
            let k = (k as f64 * step) as usize;
            while k >= before + ranges[at].len() {
                before += ranges[at].len();
                at += 1;
            }
            ranges[at].start + (k - before)
        })
        .collect()
}

/// The terms of the stages: the pure-slip core, the pure-slip terms the data identify, the
/// combined-slip terms, then all together.
fn stage_terms(terms: &[Term], varies: Varies) -> [Vec<usize>; 4] {
    let of = |pick: &dyn Fn(&Needs) -> bool| -> Vec<usize> {
        (0..terms.len())
            .filter(|&i| terms[i].needs.met_by(varies) && pick(&terms[i].needs))
            .collect()
    };
    let core = of(&|n| *n == Needs::default());
    let pure = of(&|n| !n.combined);
    let combined = of(&|n| n.combined);
    let all = of(&|_| true);
    [core, pure, combined, all]
}

/// The all-data fit: data-driven starts, then the stages; the best of the stiffness starts.
fn fit_all(model: &Model, data: &ChannelData, p0_kpa: f64, varies: Varies) -> Option<Vec<f64>> {
    let [core, pure, combined, all] = stage_terms(model.terms, varies);
    let every_row = std::iter::once(0..data.len()).collect::<Vec<_>>();
    let sampled = sample(&every_row);
    let pure_positions: Vec<usize> = sampled
        .iter()
        .copied()
        .filter(|&i| is_pure(model.channel, &row_of(data, p0_kpa, i)))
        .collect();
    let on_all = Rows::at(data, p0_kpa, &sampled);
    let on_pure = if pure_positions.len() >= ROWS_PER_TERM * pure.len() {
        Rows::at(data, p0_kpa, &pure_positions)
    } else {
        Rows::at(data, p0_kpa, &sampled)
    };
    let mut start: Vec<f64> = model.terms.iter().map(|t| t.start).collect();
    // The combined terms stay neutral (weights 1, no induced force) unless identified.
    for (i, t) in model.terms.iter().enumerate() {
        if t.needs.combined && !t.needs.met_by(varies) {
            start[i] = neutral_combined(model.channel, i, t.start);
        }
    }
    let (peak, stiffness) = match model.channel {
        Channel::Fx => mf61::FX_PEAK_STIFFNESS,
        _ => mf61::FY_PEAK_STIFFNESS,
    };
    start[peak] = peak_per_load(&on_pure).unwrap_or(start[peak]);
    let best_core = STIFFNESS_STARTS
        .iter()
        .filter_map(|&k| {
            let mut s = start.clone();
            s[stiffness] *= k;
            model.fit(&s, &core, &on_pure)
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let mut p = best_core.0;
    for (free, on) in [(&pure, &on_pure), (&combined, &on_all), (&all, &on_all)] {
        if let Some((q, _)) = model.fit(&p, free, on) {
            p = q;
        }
    }
    Some(p)
}

/// A combined-slip coefficient's value when combined slip is not fitted: the weights' B
/// zero (G = 1), the induced force's size zero.
fn neutral_combined(channel: Channel, i: usize, start: f64) -> f64 {
    let name = match channel {
        Channel::Fx => mf61::FX_TERMS[i].name,
        _ => mf61::FY_TERMS[i].name,
    };
    match name {
        "rBx1" | "rBy1" | "rVy1" => 0.0,
        _ => start,
    }
}

/// The 99th percentile of |F| / Fz: the start of the peak friction.
fn peak_per_load(rows: &Rows) -> Option<f64> {
    let ratio: Vec<f64> = rows
        .rows
        .iter()
        .zip(&rows.measured)
        .filter(|(r, _)| r.fz > 0.0)
        .map(|(r, y)| y.abs() / r.fz)
        .collect();
    quantile(&ratio, 0.99).filter(|v| *v > 0.05)
}

/// The reference fit of `data` (Fx or Fy; `None` for Mz, which the reference does not
/// cover, or when the fit fails): on all data, then each fold's model refitted from it on
/// its training runs and scored on its held-out runs. `p0_kpa` is the nominal pressure.
pub fn fit_reference(data: &ChannelData, folds: &Folds, p0_kpa: f64) -> Option<ReferenceFit> {
    let fz0 = quantile(&data.fz_kn, 0.5).map(mf87::units::kilonewtons_to_newtons)?;
    let model = Model::of(data.channel, fz0)?;
    let varies = varies(data, p0_kpa);
    let all_fit = fit_all(&model, data, p0_kpa, varies)?;
    let free = stage_terms(model.terms, varies)[3].clone();
    let folds_k: Vec<usize> = (0..folds.k).collect();
    let per_fold = parallel_map(&folds_k, |&fold| {
        // The rows as stretches, not a list of every row.
        let (train, test) = folds.split_ranges(&data.run, fold);
        let on_train = Rows::at(data, p0_kpa, &sample(&train));
        let p = model
            .fit(&all_fit, &free, &on_train)
            .map_or_else(|| all_fit.clone(), |f| f.0);
        (test, p)
    });
    // The held-out residuals, each fold's rows by its model, and the fit's on all rows, a
    // piece of rows at a time (the pieces in parallel).
    let residuals_at = |p: &[f64], piece: &[usize]| {
        let rows = Rows::at(data, p0_kpa, piece);
        let mut r = vec![0.0; rows.len()];
        model.residuals(p, &rows, &mut r);
        r
    };
    let held_pieces: Vec<(&[f64], Vec<Range<usize>>)> = per_fold
        .iter()
        .flat_map(|(test, p)| {
            pieces_of(test, PIECE_ROWS)
                .into_iter()
                .map(move |c| (p.as_slice(), c))
        })
        .collect();
    // Held-out residuals kept in single precision as they are made (see CompactResiduals).
    let mut heldout = vec![0.0f32; data.len()];
    let held = parallel_map(&held_pieces, |(p, piece)| {
        let r = residuals_at(p, &rows_of(piece).collect::<Vec<usize>>());
        r.into_iter().map(|v| v as f32).collect::<Vec<f32>>()
    });
    for ((_, piece), r) in held_pieces.iter().zip(held) {
        for (i, v) in rows_of(piece).zip(r) {
            heldout[i] = v;
        }
    }
    // Every row, a piece at a time: each piece's sum of squares, added in order.
    let starts: Vec<usize> = (0..data.len()).step_by(PIECE_ROWS).collect();
    let in_sample_sq = parallel_map(&starts, |&start| {
        let piece: Vec<usize> = (start..(start + PIECE_ROWS).min(data.len())).collect();
        residuals_at(&all_fit, &piece)
            .iter()
            .fold(0.0, |s, v| s + v * v)
    })
    .iter()
    .sum::<f64>();
    let heldout = CompactResiduals::from_single(heldout);
    let heldout_rms = heldout.mse().sqrt();
    let in_sample_rms = (in_sample_sq / data.len().max(1) as f64).sqrt();
    let fitted = free
        .iter()
        .map(|&i| (model.terms[i].name, all_fit[i]))
        .collect();
    let not_identified = (0..model.terms.len())
        .filter(|i| !free.contains(i))
        .map(|i| model.terms[i].name)
        .collect();
    Some(ReferenceFit {
        channel: data.channel,
        model: REFERENCE_MODEL,
        heldout_rms,
        in_sample_rms,
        nominal_load_n: fz0,
        fitted,
        not_identified,
        heldout,
    })
}

/// The rows of a piece of [`pieces_of`], in order.
fn rows_of(piece: &[Range<usize>]) -> impl Iterator<Item = usize> + '_ {
    piece.iter().flat_map(|r| r.clone())
}

/// `ranges` (ascending, disjoint) cut into pieces of `size` rows (the last fewer), in order.
fn pieces_of(ranges: &[Range<usize>], size: usize) -> Vec<Vec<Range<usize>>> {
    let mut pieces: Vec<Vec<Range<usize>>> = Vec::new();
    let mut filled = size;
    for r in ranges {
        let mut start = r.start;
        while start < r.end {
            if filled == size {
                pieces.push(Vec::new());
                filled = 0;
            }
            let end = r.end.min(start + (size - filled));
            pieces.last_mut().expect("a piece is open").push(start..end);
            filled += end - start;
            start = end;
        }
    }
    pieces
}

/// Regions named where the reference leads the verdict's model.
const AHEAD_REGIONS: usize = 3;
/// Below this share of the reference's gain, the named effects leave a gap the reference
/// closes, which the report says in words.
pub const EFFECTS_SHORT_OF_REFERENCE: f64 = 0.8;

/// A region where the reference's held-out error is lower than the verdict's.
#[derive(Debug, Clone, Serialize)]
pub struct Ahead {
    pub dimension: &'static str,
    pub label: String,
    pub share_rows: f64,
    /// Share of the whole drop in squared error from the verdict's model to the reference.
    pub share_of_drop: f64,
    /// Held-out RMS there, of the verdict's model and of the reference [N or N.m].
    pub verdict_rms: f64,
    pub reference_rms: f64,
}

/// How much of one channel's held-out gap any Magic Formula explains, how much of that the
/// named effects explain, and what is left.
#[derive(Debug, Clone, Serialize)]
pub struct Ceiling {
    pub channel: Channel,
    pub unit: &'static str,
    /// Held-out RMS of the 1987 model and of the verdict's model (with the named effects).
    pub baseline_rms: f64,
    pub verdict_rms: f64,
    /// The reference fit (`null` for Mz, which it does not cover, or when it failed).
    pub reference: Option<ReferenceFit>,
    pub floor: floor::Floor,
    /// Shares of the baseline's mean square above the floor that the reference and the
    /// verdict's model close (`null` without a reference, or when the floor is not below
    /// every model's held-out error: see [`Ceiling::floor_above_a_model`]).
    pub reference_closes: Option<f64>,
    pub verdict_closes: Option<f64>,
    /// Whether the floor lies at or above a model's held-out error: the runs do not each trace
    /// one curve of the swept slip that a spline follows, and no shares above it are given.
    pub floor_above_a_model: bool,
    /// The verdict's drop in mean square as a share of the reference's (`null` without a
    /// reference, or when the reference gains nothing).
    pub share_of_reference: Option<f64>,
    /// Where the reference leads the verdict's model most (when the named effects fall short
    /// of it).
    pub reference_ahead: Vec<Ahead>,
    /// The same in words.
    pub words: String,
}

impl Ceiling {
    /// One channel's ceiling from its held-out residuals of the base model and the verdict's.
    pub fn of(
        data: &ChannelData,
        base_residuals: &CompactResiduals,
        verdict_residuals: &CompactResiduals,
        reference: Option<ReferenceFit>,
    ) -> Ceiling {
        let ms =
            |r: &CompactResiduals| r.iter().map(|v| v * v).sum::<f64>() / r.len().max(1) as f64;
        let floor = floor::floor(data);
        let (base, verdict, floor_ms) =
            (ms(base_residuals), ms(verdict_residuals), floor.rms.powi(2));
        let reference_ms = reference.as_ref().map(|r| r.heldout_rms.powi(2));
        let lowest = reference_ms.map_or(base.min(verdict), |r| base.min(verdict).min(r));
        let floor_above_a_model = floor_ms >= lowest;
        let share = |ms: f64| (!floor_above_a_model).then(|| (base - ms) / (base - floor_ms));
        let share_of_reference = reference_ms
            .filter(|r| base - r > 0.0)
            .map(|r| (base - verdict) / (base - r));
        let reference_ahead = match (&reference, share_of_reference) {
            (Some(r), Some(share)) if share < EFFECTS_SHORT_OF_REFERENCE => {
                ahead(data, verdict_residuals, &r.heldout)
            }
            _ => Vec::new(),
        };
        let mut ceiling = Ceiling {
            channel: data.channel,
            unit: if data.channel == Channel::Mz {
                "N.m"
            } else {
                "N"
            },
            baseline_rms: base.sqrt(),
            verdict_rms: verdict.sqrt(),
            reference_closes: reference_ms.and_then(share),
            verdict_closes: share(verdict),
            floor_above_a_model,
            share_of_reference,
            reference,
            floor,
            reference_ahead,
            words: String::new(),
        };
        ceiling.words = ceiling.in_words();
        ceiling
    }

    /// The ceiling in sentences.
    fn in_words(&self) -> String {
        let (ch, u) = (self.channel, self.unit);
        let pct = |x: f64| format!("{:.0} %", 100.0 * x);
        let mut s = format!(
            "{ch}: held-out RMS {:.1} {u} with the 1987 model, {:.1} {u} with the verdict's effects",
            self.baseline_rms, self.verdict_rms
        );
        match &self.reference {
            Some(r) => {
                s += &format!(
                    ", {:.1} {u} with {} fitted on the same folds",
                    r.heldout_rms, r.model
                )
            }
            None => s += &format!(" (no {REFERENCE_MODEL} reference for {ch})"),
        }
        s += &format!("; the per-sweep floor is {:.1} {u}. ", self.floor.rms);
        let Some(verdict_closes) = self.verdict_closes else {
            s += "The floor is not below every model's held-out error here: the runs do not \
                  each trace one curve of the swept slip that a spline through the run follows \
                  (too few rows per run, or a load or camber that moves within it), so no \
                  shares of the gap above it are given.";
            return s;
        };
        if let Some(closes) = self.reference_closes {
            s += &format!(
                "Any Magic Formula closes {} of the gap above the floor ({REFERENCE_MODEL}); ",
                pct(closes)
            );
        }
        let named = if self.reference_closes.is_some() {
            "the"
        } else {
            "The"
        };
        s += &format!("{named} named effects close {}", pct(verdict_closes));
        if let Some(share) = self.share_of_reference {
            s += &format!(", {} of what {REFERENCE_MODEL} closes", pct(share));
        }
        let left = self
            .reference_closes
            .map_or(1.0 - verdict_closes, |c| 1.0 - c);
        s += &format!(
            "; {} is left to what no Magic Formula fitted here explains (hysteresis between a \
             sweep's halves, noise, drift, unmodelled physics).",
            pct(left.max(0.0))
        );
        if !self.reference_ahead.is_empty() {
            let wheres: Vec<String> = self
                .reference_ahead
                .iter()
                .map(|a| {
                    format!(
                        "{} {} ({} of the difference on {} of the rows; {:.1} -> {:.1} {u})",
                        a.dimension,
                        a.label,
                        pct(a.share_of_drop),
                        pct(a.share_rows),
                        a.verdict_rms,
                        a.reference_rms
                    )
                })
                .collect();
            s += &format!(
                " {REFERENCE_MODEL} closes a gap that no candidate effect does, most in: {}.",
                wheres.join("; ")
            );
        }
        s
    }
}

/// The regions where the reference's held-out squared error falls most below the verdict's,
/// by share of that drop beyond their share of rows.
fn ahead(
    data: &ChannelData,
    verdict: &CompactResiduals,
    reference: &CompactResiduals,
) -> Vec<Ahead> {
    let v = crate::method::diagnose::regions::regions(data, verdict.as_single());
    let r = crate::method::diagnose::regions::regions(data, reference.as_single());
    let sq = |x: &crate::method::diagnose::regions::Region| x.rms * x.rms * x.rows as f64;
    let total: f64 =
        verdict.iter().map(|x| x * x).sum::<f64>() - reference.iter().map(|x| x * x).sum::<f64>();
    if total <= 0.0 {
        return Vec::new();
    }
    let mut out: Vec<Ahead> = v
        .iter()
        .zip(&r)
        .filter(|(a, b)| a.dimension == b.dimension && a.label == b.label)
        .filter(|(a, _)| a.share_rows >= 0.01)
        .map(|(a, b)| Ahead {
            dimension: a.dimension,
            label: a.label.clone(),
            share_rows: a.share_rows,
            share_of_drop: (sq(a) - sq(b)) / total,
            verdict_rms: a.rms,
            reference_rms: b.rms,
        })
        .collect();
    out.sort_by(|a, b| {
        (b.share_of_drop - b.share_rows).total_cmp(&(a.share_of_drop - a.share_rows))
    });
    out.truncate(AHEAD_REGIONS);
    out.retain(|a| a.share_of_drop > a.share_rows);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Dataset;

    /// Fy of runs sweeping the slip angle while the load steps from 2 to 6 kN halfway through
    /// each: a spline against the slip cannot follow both load levels.
    fn load_stepping_runs() -> ChannelData {
        let (mut run, mut alpha, mut fz, mut fy) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for r in 0..4 {
            for i in 0..400 {
                let a = -10.0 + 20.0 * (i % 200) as f64 / 200.0;
                let load = if i < 200 { 2000.0 } else { 6000.0 };
                run.push(r);
                alpha.push(f64::to_radians(a));
                fz.push(load);
                fy.push(load * (1.4 * (0.3 * a).atan()).sin());
            }
        }
        let ds = Dataset {
            run: run.into(),
            fz: fz.into(),
            alpha: Some(alpha.into()),
            fy: Some(fy.into()),
            ..Dataset::default()
        };
        ChannelData::from_dataset(&ds, Channel::Fy).unwrap()
    }

    #[test]
    fn a_sample_of_ranges_is_the_rows_spread_evenly_over_them() {
        let cap = crate::method::prepare::channel_data::FIT_ROWS_MAX;
        // Few rows: every one. Many, in ranges of uneven lengths with gaps: `cap` of them,
        // the k-th at position k * (rows / cap) of the rows taken together.
        let few = [3..10, 20..21, 40..45];
        assert_eq!(
            sample(&few),
            few.iter().flat_map(|r| r.clone()).collect::<Vec<_>>()
        );
        let many: Vec<Range<usize>> = (0..900)
            .map(|k| 1000 * k + k % 7..1000 * k + 40 + 31 * (k % 13))
            .collect();
        let rows: Vec<usize> = many.iter().flat_map(|r| r.clone()).collect();
        assert!(rows.len() > cap);
        let step = rows.len() as f64 / cap as f64;
        let expected: Vec<usize> = (0..cap).map(|k| rows[(k as f64 * step) as usize]).collect();
        assert_eq!(sample(&many), expected);
    }

    #[test]
    fn pieces_cut_the_rows_in_order_at_the_size() {
        let ranges = [0..5, 7..8, 10..17];
        let pieces = pieces_of(&ranges, 4);
        let all: Vec<usize> = ranges.iter().flat_map(|r| r.clone()).collect();
        let cut: Vec<Vec<usize>> = all.chunks(4).map(<[usize]>::to_vec).collect();
        let rows: Vec<Vec<usize>> = pieces.iter().map(|p| rows_of(p).collect()).collect();
        assert_eq!(rows, cut);
        assert!(pieces_of(&[], 4).is_empty());
    }

    /// `n` held-out residuals of `value` each.
    fn flat(value: f64, n: usize) -> CompactResiduals {
        CompactResiduals::new(&vec![value; n])
    }

    #[test]
    fn a_floor_above_a_models_error_gives_no_shares_and_says_why() {
        let data = load_stepping_runs();
        let n = data.len();
        // A model that knows the load leaves 50 N; the 1987 model 400 N.
        let ceiling = Ceiling::of(&data, &flat(400.0, n), &flat(50.0, n), None);
        assert!(ceiling.floor.rms > 50.0, "{}", ceiling.floor.rms);
        assert!(ceiling.floor_above_a_model);
        assert_eq!(ceiling.verdict_closes, None);
        assert!(
            ceiling.words.contains("not below every model's"),
            "{}",
            ceiling.words
        );
        assert!(!ceiling.words.contains("inf"));
    }

    #[test]
    fn a_floor_below_the_models_gives_the_shares_above_it() {
        let data = load_stepping_runs();
        let n = data.len();
        let floor_ms = floor::floor(&data).rms.powi(2);
        let (base, verdict) = (floor_ms + 100.0, floor_ms + 25.0);
        let (base, verdict) = (flat(base.sqrt(), n), flat(verdict.sqrt(), n));
        let ceiling = Ceiling::of(&data, &base, &verdict, None);
        assert!(!ceiling.floor_above_a_model);
        let closes = ceiling.verdict_closes.unwrap();
        // Of the gap above the floor, (100 - 25) / 100, as the residuals are kept (single
        // precision, about 7 digits of mean squares well above the gaps).
        let (b, v) = (base.get(0).powi(2), verdict.get(0).powi(2));
        assert!((closes - (b - v) / (b - floor_ms)).abs() < 1e-9, "{closes}");
        assert!((closes - 0.75).abs() < 0.01, "{closes}");
        assert!(ceiling.words.contains("close 75 %"), "{}", ceiling.words);
    }
}
