//! The 1987 model of one channel, prepared for fitting: the channel's coefficients and its
//! effects' parameters as one parameter vector, evaluated on a [`ChannelData`].

use mf87::extensions::relaxation_step;
use mf87::formula::{MagicFormula, factors};
use mf87::{Channel, Params, Real};
use nalgebra::DMatrix;
use num_dual::DualSVec64;

use crate::method::fit::effects::{self, Conditions, Extension, Identifies, Nominal};
use crate::method::fit::evaluations::{self, Formula};
use crate::method::parallel::parallel_for_each;
use crate::method::prepare::channel_data::{ChannelData, Column};
use crate::method::prepare::cv::run_pieces;

/// Camber coefficients of the lateral channels: a9..a13 (indices 9..=13 in `NAMES`).
const CAMBER_COEFFICIENTS: std::ops::RangeInclusive<usize> = 9..=13;

/// The model of one channel: the 1987 formula with its free coefficients, plus any effects.
/// Its parameter vector is the free coefficients followed by each effect's parameters.
#[derive(Debug, Clone)]
pub struct ChannelModel {
    pub channel: Channel,
    /// The full parameter set; free coefficients are overwritten from the parameter vector.
    pub params: Params,
    /// Indices (into the channel's coefficient names) of the free coefficients.
    pub free: Vec<usize>,
    /// The effects added, in order, with their current parameter values.
    pub effects: Vec<(Extension, Vec<f64>)>,
    pub nominal: Nominal,
    /// What the data vary of the load and camber: the effects' terms of a condition held
    /// still are held at their starting values ([`effects::Effect::held`]).
    pub identifies: Identifies,
}

impl ChannelModel {
    /// The base model: all coefficients free, except camber ones when camber does not vary.
    pub fn new(
        params: Params,
        channel: Channel,
        camber_identifiable: bool,
        nominal: Nominal,
    ) -> ChannelModel {
        let free = (0..Params::coefficient_names(channel).len())
            .filter(|i| {
                channel == Channel::Fx || camber_identifiable || !CAMBER_COEFFICIENTS.contains(i)
            })
            .collect();
        ChannelModel {
            channel,
            params,
            free,
            effects: Vec::new(),
            nominal,
            identifies: Identifies::ALL,
        }
    }

    /// This model with the effects' terms identified as `identifies` says.
    pub fn identifying(mut self, identifies: Identifies) -> ChannelModel {
        self.identifies = identifies;
        self
    }

    /// This model for data that identify what `identifies` says: the effects' terms it holds
    /// back to their starting values (e.g. a camber term refitted on runs at one camber).
    pub fn restricted(&self, identifies: Identifies) -> ChannelModel {
        let mut m = self.clone().identifying(identifies);
        for (e, q) in &mut m.effects {
            let effect = effects::of(*e);
            let start = effect.starting_values_on(self.channel);
            for i in effect.held(self.channel, identifies) {
                q[i] = start[i];
            }
        }
        m
    }

    /// Positions in the parameter vector of the effects' parameters held at their starting
    /// values (see [`effects::Effect::held`]).
    pub fn held(&self) -> Vec<usize> {
        let mut at = self.free.len();
        let mut held = Vec::new();
        for (e, q) in &self.effects {
            held.extend(
                effects::of(*e)
                    .held(self.channel, self.identifies)
                    .into_iter()
                    .map(|i| at + i),
            );
            at += q.len();
        }
        held
    }

    /// Positions in the parameter vector that fits move: all but the held ones.
    pub fn fitted(&self) -> Vec<usize> {
        let held = self.held();
        (0..self.theta().len())
            .filter(|p| !held.contains(p))
            .collect()
    }

    /// This model with `effect` added at its starting values.
    pub fn with_effect(&self, effect: Extension) -> ChannelModel {
        let mut m = self.clone();
        let start = effects::of(effect).starting_values_on(self.channel);
        m.effects.push((effect, start));
        m
    }

    /// Parameter names, e.g. `Fy.a3`, `Fy.speed_dependence.v`.
    pub fn names(&self) -> Vec<String> {
        let names = Params::coefficient_names(self.channel);
        let mut out: Vec<String> = self
            .free
            .iter()
            .map(|&i| format!("{}.{}", self.channel, names[i]))
            .collect();
        for (e, _) in &self.effects {
            for (n, _) in effects::of(*e).parameters() {
                out.push(format!("{}.{}.{n}", self.channel, e.name()));
            }
        }
        out
    }

    /// The current parameter vector.
    pub fn theta(&self) -> Vec<f64> {
        let mut t: Vec<f64> = self
            .free
            .iter()
            .map(|&i| self.params.coefficient(self.channel, i).unwrap_or(f64::NAN))
            .collect();
        for (_, q) in &self.effects {
            t.extend(q);
        }
        t
    }

    /// This model with its parameters set from `theta`.
    pub fn updated(&self, theta: &[f64]) -> ChannelModel {
        let mut m = self.clone();
        m.params = self.params_with(theta);
        let mut rest = &theta[self.free.len()..];
        for (_, q) in &mut m.effects {
            let (mine, others) = rest.split_at(q.len());
            q.copy_from_slice(mine);
            rest = others;
        }
        m
    }

    /// The parameter set with the free coefficients taken from `theta`.
    pub fn params_with(&self, theta: &[f64]) -> Params {
        let mut p = self.params.clone();
        for (&i, &v) in self.free.iter().zip(theta) {
            if let Some(c) = p.coefficient_mut(self.channel, i) {
                *c = v;
            }
        }
        p
    }

    /// Predictions for every row of `data` with the model's own parameters.
    pub fn predictions(&self, data: &ChannelData) -> Vec<f64> {
        let mut out = vec![0.0; data.len()];
        self.predict(&self.theta(), data, &mut out);
        out
    }

    /// The predictions of the consecutive rows `span` of `data`, as of those rows taken
    /// alone (a lagged slip starts at the span's first row): `predictions(&data.range(span))`
    /// without the copy of the rows.
    pub fn predictions_in(&self, data: &ChannelData, span: std::ops::Range<usize>) -> Vec<f64> {
        let theta = self.theta();
        let mut out = vec![0.0; span.len()];
        let evaluated = self.evaluate_span(&theta, data, span, Rows::All, |i, y| out[i] = y);
        evaluations::record(Formula::Mf87, 0, evaluated);
        out
    }

    /// Model minus measurement for every row of `data` with parameters `theta`, into the
    /// first `data.len()` entries of `out`; 0 on rows the data does not count (see
    /// [`ChannelData::counted`]).
    pub fn residuals(&self, theta: &[f64], data: &ChannelData, out: &mut [f64]) {
        let out = &mut out[..data.len()];
        self.predict_rows(theta, data, Rows::Counted, out);
        for (r, y) in out.iter_mut().zip(data.measured.iter()) {
            *r -= y;
        }
        if let Some(counted) = &data.counted {
            for (r, c) in out.iter_mut().zip(counted) {
                if !c {
                    *r = 0.0;
                }
            }
        }
    }

    /// Predictions for every row of `data` with parameters `theta`: the model as mf87
    /// evaluates it with these effects as extensions (what the FMU runs).
    pub fn predict(&self, theta: &[f64], data: &ChannelData, out: &mut [f64]) {
        self.predict_rows(theta, data, Rows::All, out);
    }

    /// As [`ChannelModel::predict`], on the `rows` asked for (0 on the others), a span of
    /// rows at a time (the spans in parallel, see [`ChannelModel::spans`]).
    fn predict_rows(&self, theta: &[f64], data: &ChannelData, rows: Rows, out: &mut [f64]) {
        let spans = self.spans(data);
        let mut parts: Vec<_> = spans.iter().zip(cut(&spans, out)).collect();
        parallel_for_each(&mut parts, |(span, part)| {
            let evaluated = self.evaluate_span(theta, data, (*span).clone(), rows, |k, y| {
                part[k] = y;
            });
            evaluations::record(Formula::Mf87, 0, evaluated);
        });
    }

    /// The rows of `data` cut into consecutive spans that a fit's evaluations take side by
    /// side, each as if alone and with the same values as all rows together: spans of about
    /// [`SPAN_ROWS`] rows, ending where a run ends when the slip is lagged (the lag restarts
    /// at every run).
    fn spans(&self, data: &ChannelData) -> Vec<std::ops::Range<usize>> {
        let ext = effects::channel_extensions(self.effects.iter().map(|(e, q)| (*e, &q[..])));
        if ext.relaxation_length_m().is_some() {
            return run_pieces(&data.run, SPAN_ROWS);
        }
        (0..data.len())
            .step_by(SPAN_ROWS)
            .map(|start| start..(start + SPAN_ROWS).min(data.len()))
            .collect()
    }
}

/// Rows of a span of a fit's evaluations (see [`ChannelModel::spans`]): a fit's 25,000 rows
/// in about a dozen, so that the cores a fit's neighbours leave idle take part of it.
const SPAN_ROWS: usize = 2048;

/// `out` cut at the ends of `spans` (consecutive ranges from row 0): each span's part, in
/// order; rows past the last span are left out.
fn cut<'a, T>(spans: &[std::ops::Range<usize>], mut out: &'a mut [T]) -> Vec<&'a mut [T]> {
    let mut parts = Vec::with_capacity(spans.len());
    for span in spans {
        let (part, rest) = std::mem::take(&mut out).split_at_mut(span.len());
        parts.push(part);
        out = rest;
    }
    parts
}

/// Rows `spans` of the columns `columns` of `jac`, each span with its part of every one of
/// those columns (in their order).
fn column_parts<'a>(
    jac: &'a mut DMatrix<f64>,
    columns: std::ops::Range<usize>,
    spans: &'a [std::ops::Range<usize>],
) -> Vec<(&'a std::ops::Range<usize>, Vec<&'a mut [f64]>)> {
    let nrows = jac.nrows();
    let mut parts: Vec<_> = spans
        .iter()
        .map(|s| (s, Vec::with_capacity(columns.len())))
        .collect();
    let selected = jac
        .as_mut_slice()
        .chunks_mut(nrows.max(1))
        .skip(columns.start)
        .take(columns.len());
    for column in selected {
        for ((_, part), piece) in parts.iter_mut().zip(cut(spans, column)) {
            part.push(piece);
        }
    }
    parts
}

/// Which rows of a fitting sample an evaluation needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rows {
    /// Every row.
    All,
    /// The rows a fit counts (see [`ChannelData::counted`]); the others are evaluated only
    /// when a slip lag carries their history into the counted rows, else given 0.
    Counted,
}

impl Rows {
    /// Whether row `i` can be left out (given 0), with or without a lagged slip.
    fn skipped(self, data: &ChannelData, lagged: bool) -> impl Fn(usize) -> bool + '_ {
        let uncounted = match (self, lagged) {
            (Rows::Counted, false) => data.counted.as_deref(),
            _ => None,
        };
        move |i| uncounted.is_some_and(|c| !c[i])
    }
}

/// Largest number of parameters whose derivatives are taken together as one dual number.
const MAX_SEEDED: usize = 32;

/// The factors of the formula (B, C, D, E, Sh, Sv), through which the coefficients reach the
/// output.
const FACTORS: usize = 6;

/// Parameters past which [`ChannelModel::jacobian`] takes the chain rule through the factors
/// (when the factors and the effects' parameters fit in this many lanes). Below it, the load
/// and camber factors, which every coefficient enters, cost most of a row and one pass is as
/// fast: the chain rule pays where an effect's own terms are costly and many (combined slip's
/// weighting functions), measured in `benches/rows.rs`.
const CHAINED_ABOVE: usize = 24;

/// The width of dual number that holds `n` derivatives: 1, 2, 4, 8, 16, 24 or `MAX_SEEDED`.
fn dual_width(n: usize) -> usize {
    match n {
        0..=1 => 1,
        2 => 2,
        3..=4 => 4,
        5..=8 => 8,
        9..=16 => 16,
        17..=24 => 24,
        _ => MAX_SEEDED,
    }
}

impl ChannelModel {
    /// The derivatives of the predictions for every row of `data` with respect to the
    /// parameters `theta[seeded[k]]`, into column `k` of `jac` (rows `0..data.len()`),
    /// exact (forward-mode dual numbers through mf87's formula and extensions). Always `true`
    /// (the signature of [`crate::method::fit::least_squares::Jacobian`]).
    ///
    /// The coefficients reach the output only through the six factors of the formula at
    /// the row's load and camber, so when that is cheaper the derivatives are taken in two
    /// passes joined by the chain rule: the factors by the coefficients, then the output by
    /// the factors and the effects' parameters, the costly part (curve and effects) over a
    /// dual number of 6 + effect parameters rather than all of them
    /// (`jacobian_chained`). Otherwise one pass, at most `MAX_SEEDED` parameters to a dual
    /// number ([`ChannelModel::jacobian_forward`]).
    pub fn jacobian(
        &self,
        theta: &[f64],
        seeded: &[usize],
        data: &ChannelData,
        jac: &mut DMatrix<f64>,
    ) -> bool {
        let coefficients = seeded.iter().filter(|&&p| p < self.free.len()).count();
        let chained = (coefficients, FACTORS + seeded.len() - coefficients);
        if coefficients > 0 && seeded.len() > CHAINED_ABOVE && chained.1 <= CHAINED_ABOVE {
            macro_rules! chained {
                ($($a:literal),* ; $b:tt) => {
                    match dual_width(chained.0) {
                        $($a => chained!(@b $a; $b),)*
                        _ => return self.jacobian_forward(theta, seeded, data, jac),
                    }
                };
                (@b $a:literal; [$($b:literal),*]) => {
                    match dual_width(chained.1) {
                        $($b => self.jacobian_chained::<$a, $b>(theta, seeded, data, jac),)*
                        _ => return self.jacobian_forward(theta, seeded, data, jac),
                    }
                };
            }
            chained!(8, 16, 24; [8, 16, 24]);
            return true;
        }
        self.jacobian_forward(theta, seeded, data, jac)
    }

    /// [`ChannelModel::jacobian`] in one pass per `MAX_SEEDED` parameters, never by the
    /// chain rule (for comparison: `benches/rows.rs`).
    pub fn jacobian_forward(
        &self,
        theta: &[f64],
        seeded: &[usize],
        data: &ChannelData,
        jac: &mut DMatrix<f64>,
    ) -> bool {
        // More parameters than one dual number holds: in chunks, each into its columns.
        for (k, chunk) in seeded.chunks(MAX_SEEDED).enumerate() {
            let col0 = k * MAX_SEEDED;
            // Dual numbers as wide as the parameters asked for (an effect's own fit seeds 1
            // to 15); widths in steps of 2, though fewer lanes, measured slower overall.
            match dual_width(chunk.len()) {
                1 => self.jacobian_n::<1>(theta, chunk, data, (jac, col0)),
                2 => self.jacobian_n::<2>(theta, chunk, data, (jac, col0)),
                4 => self.jacobian_n::<4>(theta, chunk, data, (jac, col0)),
                8 => self.jacobian_n::<8>(theta, chunk, data, (jac, col0)),
                16 => self.jacobian_n::<16>(theta, chunk, data, (jac, col0)),
                24 => self.jacobian_n::<24>(theta, chunk, data, (jac, col0)),
                _ => self.jacobian_n::<MAX_SEEDED>(theta, chunk, data, (jac, col0)),
            }
        }
        true
    }

    /// [`ChannelModel::jacobian`] by the chain rule through the factors: the factors at each
    /// row as dual numbers of width `A` in the seeded coefficients; the output as a dual
    /// number of width `B` in the six factors (lanes 0..6) and the seeded effect parameters
    /// (the lanes after); each coefficient's column the factors' derivatives by it weighted
    /// by the output's by them.
    fn jacobian_chained<const A: usize, const B: usize>(
        &self,
        theta: &[f64],
        seeded: &[usize],
        data: &ChannelData,
        jac: &mut DMatrix<f64>,
    ) {
        let n_free = self.free.len();
        let dual_a: Vec<DualSVec64<A>> = theta.iter().map(|&v| DualSVec64::from(v)).collect();
        let mut c = self.coefficients(&dual_a);
        let mut q: Vec<DualSVec64<B>> = theta[n_free..]
            .iter()
            .map(|&v| DualSVec64::from(v))
            .collect();
        // (column of jac, lane) of each seeded coefficient and effect parameter.
        let (mut by_coefficient, mut by_effect) = (Vec::new(), Vec::new());
        for (col, &p) in seeded.iter().enumerate() {
            if p < n_free {
                let lane = by_coefficient.len();
                c[self.free[p]] = c[self.free[p]].derivative(lane);
                by_coefficient.push((col, lane));
            } else {
                let lane = FACTORS + by_effect.len();
                q[p - n_free] = q[p - n_free].derivative(lane);
                by_effect.push((col, lane));
            }
        }
        let seed = |v: DualSVec64<A>, lane: usize| DualSVec64::<B>::from(v.re).derivative(lane);
        let counted = |i: usize| data.counted.as_ref().is_none_or(|c| c[i]);
        let spans = self.spans(data);
        let mut parts = column_parts(jac, 0..seeded.len(), &spans);
        parallel_for_each(&mut parts, |(span, columns)| {
            let evaluated = self.evaluate_rows_by(
                &q,
                data,
                (*span).clone(),
                Rows::Counted,
                |fz_kn, gamma_deg| {
                    let by_c = factors(self.channel, &c, fz_kn.into(), gamma_deg.into());
                    let by_factor = MagicFormula {
                        b: seed(by_c.b, 0),
                        c: seed(by_c.c, 1),
                        d: seed(by_c.d, 2),
                        e: seed(by_c.e, 3),
                        sh: seed(by_c.sh, 4),
                        sv: seed(by_c.sv, 5),
                    };
                    (by_factor, by_c)
                },
                |k, y, by_c| match (&y.eps.0, by_c) {
                    (Some(dy), Some(f)) if counted(span.start + k) => {
                        let factors = [f.b, f.c, f.d, f.e, f.sh, f.sv];
                        for &(col, lane) in &by_coefficient {
                            columns[col][k] = factors
                                .iter()
                                .zip(dy.iter())
                                .filter_map(|(f, dy_df)| f.eps.0.as_ref().map(|d| dy_df * d[lane]))
                                .sum();
                        }
                        for &(col, lane) in &by_effect {
                            columns[col][k] = dy[lane];
                        }
                    }
                    _ => columns.iter_mut().for_each(|column| column[k] = 0.0),
                },
            );
            evaluations::record(Formula::Mf87, dual_width(seeded.len()), evaluated);
        });
    }

    fn jacobian_n<const N: usize>(
        &self,
        theta: &[f64],
        seeded: &[usize],
        data: &ChannelData,
        (jac, col0): (&mut DMatrix<f64>, usize),
    ) {
        let mut t: Vec<DualSVec64<N>> = theta.iter().map(|&v| DualSVec64::from(v)).collect();
        for (k, &p) in seeded.iter().enumerate() {
            t[p] = t[p].derivative(k);
        }
        let counted = |i: usize| data.counted.as_ref().is_none_or(|c| c[i]);
        let spans = self.spans(data);
        let mut parts = column_parts(jac, col0..col0 + seeded.len(), &spans);
        parallel_for_each(&mut parts, |(span, columns)| {
            let evaluated = self.evaluate_span(&t, data, (*span).clone(), Rows::Counted, |k, y| {
                let d = y.eps.0.as_ref().filter(|_| counted(span.start + k));
                for (lane, column) in columns.iter_mut().enumerate() {
                    column[k] = d.map_or(0.0, |d| d[lane]);
                }
            });
            evaluations::record(Formula::Mf87, N, evaluated);
        });
    }

    /// The model at every row of `data` with parameters `theta` over any number type, each
    /// value handed to `sink(row, value)`, skipping (as 0) what `rows` allows:
    /// [`ChannelModel::predict`] over `f64`, derivatives over dual numbers. Returns the number
    /// of rows evaluated (not skipped).
    pub fn evaluate_rows<T: Real>(
        &self,
        theta: &[T],
        data: &ChannelData,
        rows: Rows,
        sink: impl FnMut(usize, T),
    ) -> usize {
        self.evaluate_span(theta, data, 0..data.len(), rows, sink)
    }

    /// As [`ChannelModel::evaluate_rows`] on the consecutive rows `span` of `data` taken
    /// alone, each value handed to `sink(row within the span, value)`.
    fn evaluate_span<T: Real>(
        &self,
        theta: &[T],
        data: &ChannelData,
        span: std::ops::Range<usize>,
        rows: Rows,
        mut sink: impl FnMut(usize, T),
    ) -> usize {
        let c = self.coefficients(theta);
        self.evaluate_rows_by(
            &theta[self.free.len()..],
            data,
            span,
            rows,
            |fz_kn, gamma_deg| {
                let mf = factors(self.channel, &c, T::from(fz_kn), T::from(gamma_deg));
                (mf, ())
            },
            |i, y, _| sink(i, y),
        )
    }

    /// The channel's full coefficient vector with the free ones taken from `theta`.
    fn coefficients<T: Real>(&self, theta: &[T]) -> Vec<T> {
        let names = Params::coefficient_names(self.channel).len();
        let mut c: Vec<T> = (0..names)
            .map(|i| T::from(self.params.coefficient(self.channel, i).unwrap_or(f64::NAN)))
            .collect();
        for (&i, v) in self.free.iter().zip(theta) {
            c[i] = *v;
        }
        c
    }

    /// As [`ChannelModel::evaluate_rows`], with the effects' parameters `effect_params` and
    /// each row's factors from `factors_at(load [kN], camber [deg])`, which also returns what
    /// the `sink` is handed with the row's value (`None` on a row skipped).
    fn evaluate_rows_by<T: Real, A>(
        &self,
        effect_params: &[T],
        data: &ChannelData,
        span: std::ops::Range<usize>,
        rows: Rows,
        mut factors_at: impl FnMut(f64, f64) -> (MagicFormula<T>, A),
        mut sink: impl FnMut(usize, T, Option<A>),
    ) -> usize {
        let mut rest = effect_params;
        let mut effects: Vec<(Extension, &[T])> = Vec::with_capacity(self.effects.len());
        for (e, q) in &self.effects {
            let (mine, others) = rest.split_at(q.len());
            effects.push((*e, mine));
            rest = others;
        }
        let ext = effects::channel_extensions(effects);
        // Only a lagged slip is built as a column; otherwise each row's slip is made a `T` when
        // read (a column of dual numbers would be copied through memory for nothing).
        let lagged: Option<Vec<T>> = ext
            .relaxation_length_m()
            .map(|sigma_m| lagged_slip(data, span.clone(), sigma_m));
        let column = |c: &Option<Column>, i: usize, default: f64| {
            T::from(c.as_ref().map_or(default, |v| v[i]))
        };
        let skipped = rows.skipped(data, lagged.is_some());
        // The own slip in SI for the extensions: slip ratio from percent, rad from deg.
        let to_si = match self.channel {
            Channel::Fx => mf87::units::percent_to_slip_ratio(1.0),
            Channel::Fy | Channel::Mz => mf87::units::degrees_to_radians(1.0),
        };
        let mut evaluated = 0;
        for (k, i) in span.enumerate() {
            let slip = match &lagged {
                Some(l) => l[k],
                None => T::from(data.slip[i]),
            };
            if data.fz_kn[i] <= 0.0 || skipped(i) {
                sink(k, T::from(0.0), None);
                continue;
            }
            evaluated += 1;
            let (mf, carried) = factors_at(data.fz_kn[i], data.gamma_deg[i]);
            if ext.is_empty() {
                sink(k, mf.eval(slip), Some(carried));
                continue;
            }
            let x = Conditions {
                fz_kn: T::from(data.fz_kn[i]),
                gamma: T::from(mf87::units::degrees_to_radians(data.gamma_deg[i])),
                own_slip: slip * to_si,
                other_slip: column(&data.other_slip, i, 0.0),
                speed: column(&data.speed, i, self.nominal.speed_mps),
                pressure: column(&data.pressure, i, self.nominal.pressure_kpa),
                temperature: column(&data.temperature, i, self.nominal.temperature_c),
            };
            let y = ext.evaluate_factors(mf, &self.nominal, slip, &x);
            sink(k, y, Some(carried));
        }
        evaluated
    }
}

/// The slip of the rows `span` after a first-order lag over travelled distance (mf87's
/// relaxation step), restarted at the span's first row, at every new run and at every
/// backward step in time. Without time and speed, no lag.
fn lagged_slip<T: Real>(data: &ChannelData, span: std::ops::Range<usize>, sigma_m: T) -> Vec<T> {
    let (Some(time), Some(speed)) = (&data.time, &data.speed) else {
        return data.slip[span].iter().map(|&s| T::from(s)).collect();
    };
    let mut out = Vec::with_capacity(span.len());
    let mut lagged = T::from(0.0);
    let first = span.start;
    for i in span {
        let restart = i == first || data.run[i] != data.run[i - 1] || time[i] <= time[i - 1];
        let slip = T::from(data.slip[i]);
        lagged = if restart {
            slip
        } else {
            let distance = speed[i].abs() * (time[i] - time[i - 1]);
            relaxation_step(lagged, slip, distance, sigma_m)
        };
        out.push(lagged);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Dataset;
    use num_dual::Dual64;

    fn dataset() -> Dataset {
        let n = 40;
        let alpha: Vec<f64> = (0..n)
            .map(|i| (i as f64 - 20.0).to_radians() * 0.5)
            .collect();
        let p = Params::paper_table();
        let mut fy = Vec::new();
        for a in &alpha {
            let o = mf87::evaluate(
                &p,
                &mf87::Inputs {
                    fz: 3000.0,
                    alpha: *a,
                    kappa: 0.0,
                    gamma: 0.0,
                },
                mf87::SignConvention::Paper,
            );
            fy.push(o.fy);
        }
        Dataset {
            source: "test".into(),
            run: vec![1; n].into(),
            fz: vec![3000.0; n].into(),
            alpha: Some(alpha.into()),
            fy: Some(fy.into()),
            ..Dataset::default()
        }
    }

    fn nominal() -> Nominal {
        Nominal {
            pressure_kpa: 220.0,
            speed_mps: 15.0,
            temperature_c: 40.0,
        }
    }

    #[test]
    fn base_model_with_the_table_reproduces_mf87() {
        let ds = dataset();
        let data = ChannelData::from_dataset(&ds, Channel::Fy).unwrap();
        assert!(ChannelData::from_dataset(&ds, Channel::Fx).is_none());
        let model = ChannelModel::new(
            Params::paper_table(),
            Channel::Fy,
            data.has_camber(),
            nominal(),
        );
        assert_eq!(
            model.free.len(),
            9,
            "camber coefficients held without camber data"
        );
        let mut out = vec![0.0; data.len()];
        model.predict(&model.theta(), &data, &mut out);
        for (a, b) in out.iter().zip(data.measured.iter()) {
            assert!((a - b).abs() < 1e-9 * b.abs().max(1.0));
        }
        assert_eq!(model.names()[0], "Fy.C");
        // Effects at neutral values change nothing; the relaxation lag needs time and speed.
        let with = model
            .with_effect(Extension::SpeedDependence)
            .with_effect(Extension::RelaxationLength);
        let mut out2 = vec![0.0; data.len()];
        with.predict(&with.theta(), &data, &mut out2);
        assert_eq!(out, out2);
        assert_eq!(with.names().last().unwrap(), "Fy.relaxation_length.sigma_m");
        let theta = with.theta();
        assert_eq!(with.updated(&theta).theta(), theta);
    }

    /// `n` rows of Fy with slip, load, camber, other slip, speed, pressure, temperature and
    /// time, in runs of 20.
    fn rich_data(n: usize) -> ChannelData {
        let f = |i: usize, a: f64, b: f64| a + b * ((i * 7919 % 61) as f64 / 61.0);
        ChannelData {
            channel: Channel::Fy,
            run: (0..n).map(|i| (i / 20) as i64).collect(),
            fz_kn: (0..n).map(|i| f(i, 1.5, 5.0)).collect(),
            slip: (0..n).map(|i| f(i, -12.0, 24.0)).collect(),
            gamma_deg: (0..n).map(|i| f(i, -4.0, 8.0)).collect(),
            measured: vec![0.0; n].into(),
            other_slip: Some((0..n).map(|i| f(i, -0.2, 0.4)).collect()),
            time: Some((0..n).map(|i| (i % 20) as f64 * 0.01).collect()),
            speed: Some((0..n).map(|i| f(i, 5.0, 25.0)).collect()),
            pressure: Some((0..n).map(|i| f(i, 180.0, 120.0)).collect()),
            temperature: Some((0..n).map(|i| f(i, 20.0, 70.0)).collect()),
            counted: None,
        }
    }

    #[test]
    fn predictions_of_a_span_are_those_of_its_rows_taken_alone() {
        let data = rich_data(60);
        let mut model = ChannelModel::new(Params::paper_table(), Channel::Fy, true, nominal())
            .with_effect(Extension::RelaxationLength)
            .with_effect(Extension::Temperature);
        let mut theta = model.theta();
        let names = model.names();
        for (v, name) in theta.iter_mut().zip(&names) {
            if name.contains("relaxation_length") {
                *v = 0.4;
            } else if name.contains("temperature") {
                *v += 0.1;
            }
        }
        model = model.updated(&theta);
        // Spans from a run's start, across runs, inside one and of one row: the lag starts
        // again at the span's first row, as in the rows copied out.
        for span in [0..60, 5..33, 20..40, 37..38] {
            let alone = model.predictions(&data.range(span.clone()));
            assert_eq!(model.predictions_in(&data, span.clone()), alone, "{span:?}");
        }
        assert_ne!(
            model.predictions_in(&data, 5..33)[..15],
            model.predictions(&data)[5..20],
            "the lag restarts at the span"
        );
    }

    #[test]
    fn spans_taken_side_by_side_give_the_values_of_the_rows_taken_alone() {
        // Rows over several spans, runs of 20, every third row not counted.
        let n = 255 * 20;
        assert!(n > 2 * SPAN_ROWS);
        let mut data = rich_data(n);
        data.counted = Some((0..n).map(|i| i % 3 != 0).collect());
        let base = ChannelModel::new(Params::paper_table(), Channel::Fy, true, nominal());
        let plain = base.with_effect(Extension::Temperature);
        let lagged = base
            .with_effect(Extension::RelaxationLength)
            .with_effect(Extension::CombinedSlip);
        for model in [plain, lagged] {
            let mut theta = model.theta();
            for (v, name) in theta.iter_mut().zip(model.names()) {
                if name.contains("relaxation_length") {
                    *v = 0.4;
                } else if name.contains('_') {
                    *v += 0.05;
                }
            }
            let free = model.free.len();
            // One pass (all but one coefficient with the effects) and the chain rule (a few
            // coefficients with the effects).
            let passes: [Vec<usize>; 2] = [
                (1..theta.len()).collect(),
                (0..4).chain(free..theta.len()).collect(),
            ];
            let mut residuals = vec![0.0; n];
            model.residuals(&theta, &data, &mut residuals);
            let jacobians = passes.clone().map(|seeded| {
                let mut jac = DMatrix::zeros(n, seeded.len());
                model.jacobian(&theta, &seeded, &data, &mut jac);
                jac
            });
            // Whole runs across a span's end, at the start and at the end.
            for rows in [0..40, 2020..2100, n - 100..n] {
                let alone = data.range(rows.clone());
                let mut r = vec![0.0; alone.len()];
                model.residuals(&theta, &alone, &mut r);
                assert_eq!(r, residuals[rows.clone()], "{:?} {rows:?}", model.effects);
                for (seeded, jac) in passes.iter().zip(&jacobians) {
                    let mut part = DMatrix::zeros(alone.len(), seeded.len());
                    model.jacobian(&theta, seeded, &alone, &mut part);
                    assert_eq!(part, jac.rows(rows.start, rows.len()), "{rows:?}");
                }
            }
            let uncounted = (0..n).filter(|i| i % 3 == 0);
            assert!(uncounted.clone().all(|i| residuals[i] == 0.0));
            assert!(uncounted.clone().all(|i| jacobians[0].row(i).amax() == 0.0));
            assert!((0..n).any(|i| jacobians[1].row(i).amax() > 0.0));
        }
    }

    #[test]
    fn exact_jacobian_matches_central_differences_of_the_predictions() {
        let n = 60;
        let data = rich_data(n);
        let mut model = ChannelModel::new(Params::paper_table(), Channel::Fy, true, nominal());
        for e in [
            Extension::CombinedSlip,
            Extension::RelaxationLength,
            Extension::InflationPressure,
            Extension::Temperature,
        ] {
            model = model.with_effect(e);
        }
        let mut theta = model.theta();
        // Away from the neutral starting values, with a negative fitted relaxation length.
        let names = model.names();
        for (v, name) in theta.iter_mut().zip(&names) {
            if name.contains("relaxation_length") {
                *v = -0.3;
            } else if name.contains('_') {
                *v += 0.05;
            }
        }
        let all: Vec<usize> = (0..theta.len()).collect();
        let mut jac = DMatrix::zeros(n, theta.len());
        assert!(model.jacobian(&theta, &all, &data, &mut jac));
        let mut worst: f64 = 0.0;
        for (k, name) in names.iter().enumerate() {
            let h = 1e-6 * theta[k].abs().max(1.0);
            let at = |d: f64| {
                let mut t = theta.clone();
                t[k] += d;
                let mut out = vec![0.0; n];
                model.predict(&t, &data, &mut out);
                out
            };
            let (up, down) = (at(h), at(-h));
            for i in 0..n {
                let fd = (up[i] - down[i]) / (2.0 * h);
                let err = (jac[(i, k)] - fd).abs() / fd.abs().max(1.0);
                assert!(err < 1e-4, "{name} row {i}: exact {} vs {fd}", jac[(i, k)]);
                worst = worst.max(err);
            }
        }
        // A subset of the parameters lands in the first columns.
        let some = [2, theta.len() - 1];
        let mut sub = DMatrix::zeros(n, 2);
        assert!(model.jacobian(&theta, &some, &data, &mut sub));
        for i in 0..n {
            assert_eq!(sub[(i, 0)], jac[(i, 2)]);
            assert_eq!(sub[(i, 1)], jac[(i, theta.len() - 1)]);
        }
        // Every width of dual number, the split into passes past MAX_SEEDED and the chain
        // rule through the factors give the same columns (to rounding: the chain rule sums
        // the same products in another order).
        assert!(theta.len() > MAX_SEEDED, "{} parameters", theta.len());
        let same = |a: &DMatrix<f64>, b: &DMatrix<f64>, what: &str| {
            let scale = b.amax().max(1.0);
            assert!(
                (a - b).amax() <= 1e-12 * scale,
                "{what}: {}",
                (a - b).amax()
            );
        };
        let mut chained = 0;
        for len in 1..=theta.len() {
            for seeded in [
                (0..len).collect::<Vec<usize>>(),
                (theta.len() - len..theta.len()).collect(),
            ] {
                let mut part = DMatrix::zeros(n, len);
                assert!(model.jacobian(&theta, &seeded, &data, &mut part));
                let mut forward = DMatrix::zeros(n, len);
                assert!(model.jacobian_forward(&theta, &seeded, &data, &mut forward));
                let expected = DMatrix::from_fn(n, len, |i, k| jac[(i, seeded[k])]);
                assert_eq!(forward, expected, "one pass, {seeded:?}");
                same(&part, &forward, &format!("{seeded:?}"));
                let coefficients = seeded.iter().filter(|&&p| p < model.free.len()).count();
                if coefficients <= 24 && FACTORS + len - coefficients <= 24 {
                    let mut by_factors = DMatrix::zeros(n, len);
                    model.jacobian_chained::<24, 24>(&theta, &seeded, &data, &mut by_factors);
                    same(&by_factors, &forward, &format!("chained {seeded:?}"));
                    chained += 1;
                }
            }
        }
        assert!(
            chained > theta.len(),
            "the chain rule tried {chained} times"
        );
        // The values of the dual path are the predictions themselves.
        let mut plain = vec![0.0; n];
        model.predict(&theta, &data, &mut plain);
        let dual: Vec<Dual64> = theta
            .iter()
            .map(|&v| Dual64::from(v).derivative())
            .collect();
        model.evaluate_rows(&dual, &data, Rows::All, |i, y| {
            assert!(
                (y.re - plain[i]).abs() <= 1e-9 * plain[i].abs().max(1.0),
                "row {i}"
            );
        });
        assert!(worst < 1e-4);
    }
}
