//! A test programme recorded as one file, split into its test blocks; and the set conditions
//! of every block of a data set.
//!
//! A Tire Test Consortium run file holds a whole programme: tens of slip-angle sweeps
//! (cornering) or slip-ratio sweeps (drive/brake), each at its own load, pressure, camber and
//! (drive/brake) slip angle, sometimes with a pause in the recording between two of them.
//! [`split`] finds the blocks from the data alone; [`split_into_blocks`] applies it to a data
//! set read from such a file and gives every block its own run id; [`blocks`] summarises the
//! blocks (runs) of any data set, for the report and for cross-validation (`crate::method::prepare::cv`).
//!
//! # The rule
//!
//! The window `W` is 1 s of rows (the median positive time step; 100 rows without a time
//! column), at least 5 rows, odd.
//!
//! 1. **Time.** A block ends where the run id changes, where time goes backwards, or where it
//!    jumps by more than 10 median time steps and at least 0.5 s (a pause in the recording).
//!    These cuts are always kept.
//! 2. **Set conditions.** Between time cuts, each set condition present is followed through its
//!    running median over `W` rows, `m`: load (tolerance 150 N or 10 % of the load, the
//!    larger), pressure (5 kPa), camber (0.5 deg), speed (0.8 m/s) and, where the slip angle
//!    is held, the slip angle (1 deg). The slip angle is held in a stretch between time cuts
//!    when fewer than a quarter of its `W`-row windows move it (10th to 90th percentile) by
//!    more than its tolerance (in
//!    a cornering programme it is swept and is no condition; in a drive/brake programme it is
//!    held while the slip ratio is swept). The slip ratio is never a set condition.
//! 3. **Steps.** A row moves a condition when the medians of the `W` rows before and after it
//!    differ by more than half the tolerance. Each stretch of moving rows (stretches closer
//!    than `W/2` joined) is one transition; it is a step when the levels `W` rows before and
//!    after it differ by more than the tolerance (a transition at the start or end of the
//!    stretch between time cuts has no level on one side and is no step: its rows go with
//!    the level it reaches or leaves), and it is cut once, at its first row closer
//!    to the new level than to the old one (the midpoint of a ramp), so a ramp never becomes
//!    a row of small blocks and its rows go to the level they are nearer. Cuts of several
//!    conditions within `W` rows of each other are one cut (the largest step's, in units of
//!    its tolerance).
//! 4. **Slow ramps.** A block in which a condition's `m` spreads (5th to 95th percentile) over
//!    more than twice its tolerance, and which holds two levels, each settled (within half a
//!    tolerance of its median) for at least `W` rows, is cut where it splits into the two
//!    parts whose means differ most; repeated on the parts.
//! 5. **Clean-up.** A block shorter than `W` rows joins the neighbour (between the same time
//!    cuts) whose median conditions are nearer; then, while two neighbouring blocks differ in
//!    no condition by more than its tolerance (block medians), the closest pair is joined.
//! 6. **Repeated sweeps.** A block whose swept slip (the slip angle if swept, else the slip
//!    ratio) passes upward through the middle of its range at least twice (a warm-up or
//!    break-in: the same sweep cycled at one load for a minute or more) is cut at each such
//!    pass, into one block per cycle; see `sweep_cycles`. A single sweep, even there and
//!    back, passes at most once and stays whole.
//!
//! Every row belongs to exactly one block; blocks are consecutive rows.
//!
//! In a TTC file ([`split_into_blocks`]) a file's blocks get run ids `1000 r + 1`,
//! `1000 r + 2`, ... where `r` is the file's run number; a file of one block keeps `r`.

use std::collections::BTreeMap;
use std::ops::Range;

use mf87::units::{degrees_to_radians, radians_to_degrees};
use serde::Serialize;

use crate::data::{Dataset, Quantity};
use crate::quantiles::{median, quantile};

/// Length of the running-median window \[s\].
pub const WINDOW_S: f64 = 1.0;
/// Rows in the window when the data has no time column.
pub const WINDOW_ROWS_WITHOUT_TIME: usize = 100;
/// Fewest rows in the window.
const MIN_WINDOW_ROWS: usize = 5;
/// A time step longer than this many median steps (and [`MIN_GAP_S`]) is a pause.
pub const GAP_STEPS: f64 = 10.0;
/// The shortest pause in the recording that ends a block \[s\].
pub const MIN_GAP_S: f64 = 0.5;
/// The slip angle is held where fewer than this fraction of its windows move it by more than
/// its tolerance.
pub const HELD_WINDOW_FRACTION: f64 = 0.25;
/// A block sweeps the slip angle when its interquartile range is at least this \[deg\] (a
/// transition's ramp, on fewer than a quarter of the rows, does not count).
pub const SWEPT_SLIP_ANGLE_DEG: f64 = 2.0;
/// A block sweeps the slip ratio when its interquartile range is at least this.
pub const SWEPT_SLIP_RATIO: f64 = 0.05;
/// Run ids of a file's blocks: `BLOCK_ID_BASE * run + k`.
pub const BLOCK_ID_BASE: i64 = 1000;

/// Whether the test plan moves a slip (`Quantity::Alpha` or `Quantity::Kappa`): some block
/// sweeps it, or the blocks that hold it hold it at levels that spread by a sweep's amount
/// ([`SWEPT_SLIP_ANGLE_DEG`], [`SWEPT_SLIP_RATIO`]), from the second lowest to the second
/// highest (one odd block is no step). A slip no block moves is an offset and noise, not a
/// driver of any effect.
pub fn moves(blocks: &[Block], slip: Quantity) -> bool {
    let (held, step): (fn(&Block) -> Option<f64>, f64) = match slip {
        Quantity::Alpha => (
            |b| b.held_slip_angle,
            degrees_to_radians(SWEPT_SLIP_ANGLE_DEG),
        ),
        Quantity::Kappa => (|b| b.held_slip_ratio, SWEPT_SLIP_RATIO),
        _ => return false,
    };
    if sweeps(blocks, slip) {
        return true;
    }
    let mut levels: Vec<f64> = blocks.iter().filter_map(held).collect();
    levels.sort_by(f64::total_cmp);
    levels.len() >= 4 && levels[levels.len() - 2] - levels[1] >= step
}

/// Whether some block sweeps a slip (`Quantity::Alpha` or `Quantity::Kappa`).
pub fn sweeps(blocks: &[Block], slip: Quantity) -> bool {
    let swept: &[Swept] = match slip {
        Quantity::Alpha => &[Swept::SlipAngle, Swept::Both],
        Quantity::Kappa => &[Swept::SlipRatio, Swept::Both],
        _ => return false,
    };
    blocks.iter().any(|b| swept.contains(&b.swept))
}

/// A condition the rig sets per test block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SetCondition {
    Load,
    Pressure,
    Camber,
    Speed,
    /// The slip angle of a block that sweeps the slip ratio.
    HeldSlipAngle,
}

impl SetCondition {
    pub const ALL: [SetCondition; 5] = [
        SetCondition::Load,
        SetCondition::Pressure,
        SetCondition::Camber,
        SetCondition::Speed,
        SetCondition::HeldSlipAngle,
    ];

    pub fn name(self) -> &'static str {
        match self {
            SetCondition::Load => "load",
            SetCondition::Pressure => "pressure",
            SetCondition::Camber => "camber",
            SetCondition::Speed => "speed",
            SetCondition::HeldSlipAngle => "held slip angle",
        }
    }

    /// The data set's column of this condition.
    pub fn quantity(self) -> Quantity {
        match self {
            SetCondition::Load => Quantity::Fz,
            SetCondition::Pressure => Quantity::Pressure,
            SetCondition::Camber => Quantity::Gamma,
            SetCondition::Speed => Quantity::Speed,
            SetCondition::HeldSlipAngle => Quantity::Alpha,
        }
    }

    /// The largest difference of two levels that is still one level (internal units): how
    /// closely a rig holds and measures the set point.
    pub fn tolerance(self, level: f64) -> f64 {
        match self {
            SetCondition::Load => (0.1 * level.abs()).max(150.0),
            SetCondition::Pressure => 5.0,
            SetCondition::Camber => degrees_to_radians(0.5),
            SetCondition::Speed => 0.8,
            SetCondition::HeldSlipAngle => degrees_to_radians(1.0),
        }
    }

    /// A level in the unit a report shows (deg for angles, else internal units).
    pub fn shown(self, v: f64) -> f64 {
        match self {
            SetCondition::Camber | SetCondition::HeldSlipAngle => radians_to_degrees(v),
            _ => v,
        }
    }

    /// The unit of [`SetCondition::shown`].
    pub fn shown_unit(self) -> &'static str {
        match self {
            SetCondition::Load => "N",
            SetCondition::Pressure => "kPa",
            SetCondition::Camber | SetCondition::HeldSlipAngle => "deg",
            SetCondition::Speed => "m/s",
        }
    }

    /// `1100`, `2.00`: a level in the unit of [`SetCondition::shown_unit`], without it.
    pub fn number(self, v: f64) -> String {
        let x = self.shown(v);
        match self {
            SetCondition::Load => format!("{x:.0}"),
            SetCondition::Pressure => format!("{x:.1}"),
            SetCondition::Camber | SetCondition::HeldSlipAngle | SetCondition::Speed => {
                format!("{x:.2}")
            }
        }
    }

    /// `1100 N`, `2.00 deg`.
    pub fn format(self, v: f64) -> String {
        format!("{} {}", self.number(v), self.shown_unit())
    }
}

/// Why a block begins where it does.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Boundary {
    /// The first row.
    Start,
    /// The run id changes.
    RunChange,
    /// Time goes backwards.
    TimeBackwards,
    /// A pause in the recording of this many seconds.
    TimeGap(f64),
    /// These set conditions step (each by more than its tolerance).
    Step(Vec<SetCondition>),
    /// A new cycle of a sweep repeated at the same conditions.
    SweepCycle,
}

/// A programme's rows split into test blocks.
#[derive(Debug, Clone, PartialEq)]
pub struct Split {
    /// Consecutive row ranges covering every row once, in order.
    pub blocks: Vec<Range<usize>>,
    /// Why each block begins (one per block).
    pub boundaries: Vec<Boundary>,
    /// The running-median window \[rows\].
    pub window_rows: usize,
}

impl Split {
    /// Number of blocks beginning at a pause in time or where time goes backwards.
    pub fn time_cuts(&self) -> usize {
        self.boundaries
            .iter()
            .filter(|b| matches!(b, Boundary::TimeGap(_) | Boundary::TimeBackwards))
            .count()
    }

    /// Number of blocks beginning at a new cycle of a repeated sweep.
    pub fn cycle_cuts(&self) -> usize {
        self.boundaries
            .iter()
            .filter(|b| matches!(b, Boundary::SweepCycle))
            .count()
    }

    /// Number of blocks beginning where `c` steps.
    pub fn steps_of(&self, c: SetCondition) -> usize {
        self.boundaries
            .iter()
            .filter(|b| matches!(b, Boundary::Step(cs) if cs.contains(&c)))
            .count()
    }
}

/// Which slip a block sweeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Swept {
    SlipAngle,
    SlipRatio,
    Both,
    Neither,
}

impl Swept {
    pub fn name(self) -> &'static str {
        match self {
            Swept::SlipAngle => "alpha",
            Swept::SlipRatio => "kappa",
            Swept::Both => "both",
            Swept::Neither => "none",
        }
    }
}

/// One test block (one run of a data set) and the levels of its set conditions (medians over
/// its rows, internal units).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Block {
    pub run: i64,
    pub rows: usize,
    /// First and last row of the data set (0-based) holding the run.
    pub first_row: usize,
    pub last_row: usize,
    /// Time at its first and last row \[s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<[f64; 2]>,
    pub swept: Swept,
    pub load: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pressure: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub camber: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed: Option<f64>,
    /// The slip angle, when the block does not sweep it \[rad\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_slip_angle: Option<f64>,
    /// The slip ratio, when the block does not sweep it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_slip_ratio: Option<f64>,
    /// The cross-validation fold holding it out, once folds are dealt.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fold: Option<usize>,
}

impl Block {
    /// The block's level of `c`, if it has one: the held slip angle only for a block that
    /// sweeps the slip ratio alone (the condition of a drive/brake sweep).
    pub fn level(&self, c: SetCondition) -> Option<f64> {
        match c {
            SetCondition::Load => Some(self.load),
            SetCondition::Pressure => self.pressure,
            SetCondition::Camber => self.camber,
            SetCondition::Speed => self.speed,
            SetCondition::HeldSlipAngle => match self.swept {
                Swept::SlipRatio => self.held_slip_angle,
                _ => None,
            },
        }
    }
}

/// The blocks (runs) of a data set in order of first appearance, with their conditions.
pub fn blocks(ds: &Dataset) -> Vec<Block> {
    let mut rows_of: BTreeMap<i64, Vec<usize>> = BTreeMap::new();
    let mut order = Vec::new();
    for (i, r) in ds.run.iter().enumerate() {
        rows_of
            .entry(*r)
            .or_insert_with(|| {
                order.push(*r);
                Vec::new()
            })
            .push(i);
    }
    let pick = |col: &[f64], rows: &[usize]| -> Vec<f64> { rows.iter().map(|&i| col[i]).collect() };
    order
        .into_iter()
        .map(|run| {
            let rows = &rows_of[&run];
            let (first, last) = (rows[0], rows[rows.len() - 1]);
            let level = |q: Quantity| ds.column(q).and_then(|c| median(&pick(c, rows)));
            let load = level(Quantity::Fz).unwrap_or(0.0);
            let (pressure, camber, speed) = (
                level(Quantity::Pressure),
                level(Quantity::Gamma),
                level(Quantity::Speed),
            );
            let alpha = ds.alpha.as_deref().map(|c| pick(c, rows));
            let kappa = ds.kappa.as_deref().map(|c| pick(c, rows));
            let alpha_swept = alpha
                .as_deref()
                .is_some_and(|a| span(a, 0.25) >= degrees_to_radians(SWEPT_SLIP_ANGLE_DEG));
            let kappa_swept = kappa
                .as_deref()
                .is_some_and(|k| span(k, 0.25) >= SWEPT_SLIP_RATIO);
            let swept = match (alpha_swept, kappa_swept) {
                (true, true) => Swept::Both,
                (true, false) => Swept::SlipAngle,
                (false, true) => Swept::SlipRatio,
                (false, false) => Swept::Neither,
            };
            Block {
                run,
                rows: rows.len(),
                first_row: first,
                last_row: last,
                time: ds.time.as_deref().map(|t| [t[first], t[last]]),
                swept,
                load,
                pressure,
                camber,
                speed,
                held_slip_angle: alpha.filter(|_| !alpha_swept).and_then(|a| median(&a)),
                held_slip_ratio: kappa.filter(|_| !kappa_swept).and_then(|k| median(&k)),
                fold: None,
            }
        })
        .collect()
}

/// The span from the `q` to the `1 - q` quantile.
fn span(v: &[f64], q: f64) -> f64 {
    match (quantile(v, q), quantile(v, 1.0 - q)) {
        (Some(lo), Some(hi)) => hi - lo,
        _ => 0.0,
    }
}

/// The median of the positive time steps.
fn median_step(t: &[f64]) -> Option<f64> {
    let steps: Vec<f64> = t
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .collect();
    median(&steps)
}

/// The window \[rows\] of the rule for a data set: 1 s of rows, odd, at least 5.
pub fn window_rows(ds: &Dataset) -> usize {
    let rows = match ds.time.as_deref().and_then(median_step) {
        Some(dt) => (WINDOW_S / dt).round().clamp(1.0, 1e6) as usize,
        None => WINDOW_ROWS_WITHOUT_TIME,
    };
    let rows = rows.max(MIN_WINDOW_ROWS);
    rows | 1
}

/// Splits the rows of `ds` into test blocks by the rule of the module doc. Run ids matter
/// only where they change (a block never spans two runs).
pub fn split(ds: &Dataset) -> Split {
    let n = ds.len();
    let window = window_rows(ds);
    if n == 0 {
        return Split {
            blocks: Vec::new(),
            boundaries: Vec::new(),
            window_rows: window,
        };
    }
    // 1. Time cuts.
    let mut segments: Vec<(usize, Boundary)> = vec![(0, Boundary::Start)];
    let time = ds.time.as_deref();
    let gap = time
        .and_then(median_step)
        .map(|dt| (GAP_STEPS * dt).max(MIN_GAP_S));
    for i in 1..n {
        let cut = if ds.run[i] != ds.run[i - 1] {
            Some(Boundary::RunChange)
        } else if let (Some(t), Some(gap)) = (time, gap) {
            let dt = t[i] - t[i - 1];
            if dt < 0.0 {
                Some(Boundary::TimeBackwards)
            } else if dt > gap {
                Some(Boundary::TimeGap(dt))
            } else {
                None
            }
        } else {
            None
        };
        if let Some(b) = cut {
            segments.push((i, b));
        }
    }
    let mut blocks = Vec::new();
    let mut boundaries = Vec::new();
    for (k, (start, why)) in segments.iter().enumerate() {
        let end = segments.get(k + 1).map_or(n, |s| s.0);
        let conds = conditions(ds, *start..end, window);
        let pieces = segment_pieces(&conds, end - start, window);
        for (j, p) in pieces.into_iter().enumerate() {
            let rows = start + p.rows.start..start + p.rows.end;
            let cycles = sweep_cycles(ds, rows.clone(), window);
            for (c, cycle) in cycles.into_iter().enumerate() {
                boundaries.push(match (j, c) {
                    (0, 0) => why.clone(),
                    (_, 0) => Boundary::Step(p.steps.clone()),
                    _ => Boundary::SweepCycle,
                });
                blocks.push(cycle);
            }
        }
    }
    Split {
        blocks,
        boundaries,
        window_rows: window,
    }
}

/// Fewest upward passes of the swept slip through the middle of its range for a block to be a
/// repeated sweep (cut into its cycles).
pub const MIN_REPEATED_CYCLES: usize = 2;

/// Rule 6: `rows` cut into the cycles of its sweep when the swept slip (the slip angle if it
/// is swept, else the slip ratio) passes upward through the middle of its range (5th to 95th
/// percentile, with a hysteresis of a quarter of it each side) at least
/// [`MIN_REPEATED_CYCLES`] times: cut at each such pass. A piece at either end shorter than
/// half the median cycle, or than `window`, joins its neighbour. Otherwise `rows` whole.
fn sweep_cycles(ds: &Dataset, rows: Range<usize>, window: usize) -> Vec<Range<usize>> {
    let whole = vec![rows.clone()];
    fn swept<'a>(col: Option<&'a [f64]>, rows: &Range<usize>, min: f64) -> Option<&'a [f64]> {
        col.map(|c| &c[rows.clone()])
            .filter(|v| span(v, 0.25) >= min)
    }
    let Some(slip) = swept(
        ds.alpha.as_deref(),
        &rows,
        degrees_to_radians(SWEPT_SLIP_ANGLE_DEG),
    )
    .or_else(|| swept(ds.kappa.as_deref(), &rows, SWEPT_SLIP_RATIO)) else {
        return whole;
    };
    let smooth = running_median(slip, (window / 10).max(1));
    let (Some(lo), Some(hi)) = (quantile(&smooth, 0.05), quantile(&smooth, 0.95)) else {
        return whole;
    };
    let (mid, band) = (0.5 * (lo + hi), 0.25 * (hi - lo));
    let mut cuts = Vec::new();
    let mut low = false;
    let mut crossing = None;
    for (i, &v) in smooth.iter().enumerate() {
        if v < mid - band {
            low = true;
            crossing = None;
        } else if low && v >= mid && crossing.is_none() {
            crossing = Some(i);
        }
        if low && v > mid + band {
            cuts.extend(crossing);
            low = false;
        }
    }
    if cuts.len() < MIN_REPEATED_CYCLES {
        return whole;
    }
    let lengths: Vec<f64> = cuts.windows(2).map(|w| (w[1] - w[0]) as f64).collect();
    let cycle = median(&lengths).unwrap_or(f64::INFINITY);
    let short = |len: usize| len < window || (len as f64) < 0.5 * cycle;
    if short(cuts[0]) {
        cuts.remove(0);
    }
    if cuts.last().is_some_and(|&c| short(slip.len() - c)) {
        cuts.pop();
    }
    let mut bounds = vec![0];
    bounds.extend(cuts);
    bounds.push(slip.len());
    bounds
        .windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| rows.start + w[0]..rows.start + w[1])
        .collect()
}

/// A set condition over one stretch of rows.
struct Signal<'a> {
    cond: SetCondition,
    values: &'a [f64],
    /// Running median over the window.
    smooth: Vec<f64>,
}

/// The set conditions present in `rows`, with their running medians.
fn conditions(ds: &Dataset, rows: Range<usize>, window: usize) -> Vec<Signal<'_>> {
    let h = window / 2;
    SetCondition::ALL
        .into_iter()
        .filter_map(|c| {
            let values = &ds.column(c.quantity())?[rows.clone()];
            if c == SetCondition::HeldSlipAngle && !is_held(values, window, c) {
                return None;
            }
            Some(Signal {
                cond: c,
                values,
                smooth: running_median(values, h),
            })
        })
        .collect()
}

/// Whether fewer than [`HELD_WINDOW_FRACTION`] of the `window`-row windows move `v` by more
/// than the tolerance of `c` (10th to 90th percentile, so that noise spikes do not count).
fn is_held(v: &[f64], window: usize, c: SetCondition) -> bool {
    let mut windows = 0usize;
    let mut moving = 0usize;
    let mut sorted = Vec::with_capacity(window);
    for w in v.chunks(window) {
        sorted.clear();
        sorted.extend_from_slice(w);
        sorted.sort_by(f64::total_cmp);
        let last = sorted.len() - 1;
        let (lo, hi) = (sorted[last / 10], sorted[last - last / 10]);
        windows += 1;
        if hi - lo > c.tolerance(0.5 * (lo + hi)) {
            moving += 1;
        }
    }
    (moving as f64) < HELD_WINDOW_FRACTION * windows as f64
}

/// The running median over the centred window `[i - h, i + h]` (cut at the ends).
fn running_median(x: &[f64], h: usize) -> Vec<f64> {
    let n = x.len();
    let mut out = Vec::with_capacity(n);
    let mut window: Vec<f64> = Vec::with_capacity(2 * h + 1);
    let position = |w: &[f64], v: f64| w.partition_point(|y| y.total_cmp(&v).is_lt());
    let (mut lo, mut hi) = (0usize, 0usize);
    for i in 0..n {
        let (want_lo, want_hi) = (i.saturating_sub(h), (i + h + 1).min(n));
        while hi < want_hi {
            let at = position(&window, x[hi]);
            window.insert(at, x[hi]);
            hi += 1;
        }
        while lo < want_lo {
            let at = position(&window, x[lo]);
            window.remove(at);
            lo += 1;
        }
        let m = window.len();
        out.push(0.5 * (window[(m - 1) / 2] + window[m / 2]));
    }
    out
}

/// One block of a stretch between time cuts, and the conditions stepping at its start.
struct Piece {
    rows: Range<usize>,
    steps: Vec<SetCondition>,
}

/// A candidate cut: row and the size of its step in tolerances.
#[derive(Clone, Copy)]
struct Cut {
    row: usize,
    strength: f64,
}

/// Steps 2-5 of the rule on one stretch of `n` rows between time cuts.
fn segment_pieces(signals: &[Signal<'_>], n: usize, window: usize) -> Vec<Piece> {
    if n < 2 * window || signals.is_empty() {
        return vec![Piece {
            rows: 0..n,
            steps: Vec::new(),
        }];
    }
    let mut bounds = step_bounds(signals, n, window);
    // 4. Slow ramps.
    let mut refined = vec![0];
    for w in bounds.windows(2) {
        refine(signals, w[0]..w[1], window, 0, &mut refined);
        refined.push(w[1]);
    }
    bounds = refined;
    // 5. Short blocks join their nearer neighbour; neighbours at one level are joined.
    let mut pieces: Vec<Range<usize>> = bounds.windows(2).map(|w| w[0]..w[1]).collect();
    let mut levels: Vec<Vec<f64>> = pieces.iter().map(|p| medians(signals, p)).collect();
    while pieces.len() > 1 {
        let Some((k, _)) = pieces
            .iter()
            .enumerate()
            .filter(|(_, p)| p.len() < window)
            .min_by_key(|(k, p)| (p.len(), *k))
        else {
            break;
        };
        let left = k
            .checked_sub(1)
            .map(|j| distance(signals, &levels[j], &levels[k]));
        let right = (k + 1 < pieces.len()).then(|| distance(signals, &levels[k], &levels[k + 1]));
        let j = match (left, right) {
            (Some(l), Some(r)) if r < l => k,
            (Some(_), _) => k - 1,
            _ => k,
        };
        join(&mut pieces, &mut levels, signals, j);
    }
    loop {
        let closest = (0..pieces.len().saturating_sub(1))
            .map(|j| (j, distance(signals, &levels[j], &levels[j + 1])))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match closest {
            Some((j, d)) if d <= 1.0 => join(&mut pieces, &mut levels, signals, j),
            _ => break,
        }
    }
    pieces
        .iter()
        .enumerate()
        .map(|(k, p)| Piece {
            rows: p.clone(),
            steps: if k == 0 {
                Vec::new()
            } else {
                stepping(signals, &levels[k - 1], &levels[k])
            },
        })
        .collect()
}

/// The bounds of the stretch's pieces at the steps of the signals (0 and `n` included):
/// cuts within a window of each other are one, the strongest.
fn step_bounds(signals: &[Signal<'_>], n: usize, window: usize) -> Vec<usize> {
    let h = window / 2;
    let mut cuts: Vec<Cut> = signals
        .iter()
        .flat_map(|s| step_cuts(&s.smooth, h, s.cond))
        .filter(|c| c.row > 0 && c.row < n)
        .collect();
    cuts.sort_by_key(|c| c.row);
    // Cuts within a window of each other are one: the strongest.
    let mut joined: Vec<Cut> = Vec::new();
    for c in cuts {
        match joined.last_mut() {
            Some(last) if c.row - last.row < window => {
                if c.strength > last.strength {
                    *last = c;
                }
            }
            _ => joined.push(c),
        }
    }
    std::iter::once(0)
        .chain(joined.iter().map(|c| c.row))
        .chain(std::iter::once(n))
        .collect()
}

/// Joins piece `j` with piece `j + 1`.
fn join(pieces: &mut Vec<Range<usize>>, levels: &mut Vec<Vec<f64>>, s: &[Signal<'_>], j: usize) {
    let next = pieces.remove(j + 1);
    levels.remove(j + 1);
    pieces[j].end = next.end;
    levels[j] = medians(s, &pieces[j]);
}

/// Each signal's median over `rows`.
fn medians(signals: &[Signal<'_>], rows: &Range<usize>) -> Vec<f64> {
    signals
        .iter()
        .map(|s| median(&s.values[rows.clone()]).unwrap_or(0.0))
        .collect()
}

/// Difference of two levels in units of the condition's tolerance at the larger one.
fn tolerances(c: SetCondition, a: f64, b: f64) -> f64 {
    (a - b).abs() / c.tolerance(a.abs().max(b.abs()))
}

/// The largest difference of two pieces' levels over the conditions, in tolerances.
fn distance(signals: &[Signal<'_>], a: &[f64], b: &[f64]) -> f64 {
    signals
        .iter()
        .zip(a.iter().zip(b))
        .map(|(s, (x, y))| tolerances(s.cond, *x, *y))
        .fold(0.0, f64::max)
}

/// The conditions whose levels differ by more than their tolerance.
fn stepping(signals: &[Signal<'_>], a: &[f64], b: &[f64]) -> Vec<SetCondition> {
    signals
        .iter()
        .zip(a.iter().zip(b))
        .filter(|(s, (x, y))| tolerances(s.cond, **x, **y) > 1.0)
        .map(|(s, _)| s.cond)
        .collect()
}

/// Step 3 on one condition's running median `m` (half-window `h`).
fn step_cuts(m: &[f64], h: usize, c: SetCondition) -> Vec<Cut> {
    let n = m.len();
    let d = |i: usize| m[(i + h).min(n - 1)] - m[i.saturating_sub(h)];
    let moving: Vec<bool> = (0..n)
        .map(|i| d(i).abs() > 0.5 * c.tolerance(m[i]))
        .collect();
    // Stretches of moving rows, those closer than h rows joined.
    let mut stretches: Vec<Range<usize>> = Vec::new();
    let mut i = 0;
    while i < n {
        if !moving[i] {
            i += 1;
            continue;
        }
        let start = i;
        while i < n && moving[i] {
            i += 1;
        }
        match stretches.last_mut() {
            Some(last) if start - last.end < h => last.end = i,
            _ => stretches.push(start..i),
        }
    }
    stretches
        .into_iter()
        .filter_map(|s| {
            // A transition at either end of the stretch has no level on that side: its rows
            // go with the level it reaches or leaves.
            let before = m[s.start.checked_sub(h + 1)?];
            let after = *m.get(s.end + h)?;
            let strength = tolerances(c, before, after);
            if strength <= 1.0 {
                return None;
            }
            let row = s
                .clone()
                .find(|&j| (m[j] - after).abs() < (m[j] - before).abs())
                .unwrap_or((s.start + s.end) / 2);
            Some(Cut { row, strength })
        })
        .collect()
}

/// Step 4 on `rows`: pushes the inner cuts found (in order) to `out`.
fn refine(
    signals: &[Signal<'_>],
    rows: Range<usize>,
    window: usize,
    depth: usize,
    out: &mut Vec<usize>,
) {
    if depth > 32 || rows.len() < 2 * window {
        return;
    }
    for s in signals {
        let m = &s.smooth[rows.clone()];
        let Some(level) = median(m) else { continue };
        let tol = s.cond.tolerance(level);
        if span(m, 0.05) <= 2.0 * tol {
            continue;
        }
        let Some(k) = largest_mean_split(m, window) else {
            continue;
        };
        let (left, right) = (&m[..k], &m[k..]);
        if !(settled(left, s.cond, window) && settled(right, s.cond, window)) {
            continue;
        }
        let cut = rows.start + k;
        refine(signals, rows.start..cut, window, depth + 1, out);
        out.push(cut);
        refine(signals, cut..rows.end, window, depth + 1, out);
        return;
    }
}

/// Whether at least `window` values lie within half a tolerance of their median.
fn settled(v: &[f64], c: SetCondition, window: usize) -> bool {
    let Some(level) = median(v) else {
        return false;
    };
    let half = 0.5 * c.tolerance(level);
    v.iter().filter(|x| (*x - level).abs() <= half).count() >= window
}

/// The split of `m` into two parts of at least `min` values whose means differ most
/// (weighted by `sqrt(n_left n_right / n)`: the CUSUM statistic).
fn largest_mean_split(m: &[f64], min: usize) -> Option<usize> {
    let n = m.len();
    if n < 2 * min {
        return None;
    }
    let total: f64 = m.iter().sum();
    let mut left = 0.0;
    let mut best: Option<(usize, f64)> = None;
    for (k, v) in m.iter().enumerate().take(n - min) {
        left += v;
        let k = k + 1;
        if k < min {
            continue;
        }
        let stat = (left - total * k as f64 / n as f64).abs();
        if best.is_none_or(|(_, b)| stat > b) {
            best = Some((k, stat));
        }
    }
    best.map(|(k, _)| k)
}

/// Splits a data set read from one programme file into its test blocks (see the module doc)
/// and gives them run ids: `1000 r + k` for block `k` (from 1) of the file's run `r` (the run
/// id of the block's first row); a file of one block keeps its run id. Notes how many blocks
/// it found, where and by which rule.
pub fn split_into_blocks(ds: &mut Dataset, notes: &mut Vec<String>) -> Split {
    let s = split(ds);
    if s.blocks.len() <= 1 {
        notes.push(format!(
            "one test block: no pause in time and no step of a set condition (load, pressure, \
             camber, speed, held slip angle; rule in docs/programmes.md, window {} rows)",
            s.window_rows
        ));
        return s;
    }
    let mut counter: BTreeMap<i64, i64> = BTreeMap::new();
    let ids: Option<Vec<i64>> = s
        .blocks
        .iter()
        .map(|b| {
            let base = ds.run[b.start];
            let k = counter.entry(base).or_insert(0);
            *k += 1;
            if *k >= BLOCK_ID_BASE {
                return None;
            }
            base.checked_mul(BLOCK_ID_BASE)?.checked_add(*k)
        })
        .collect();
    let ids = ids.unwrap_or_else(|| (1..=s.blocks.len() as i64).collect());
    let mut run = Vec::with_capacity(ds.len());
    for (b, id) in s.blocks.iter().zip(&ids) {
        run.extend(std::iter::repeat_n(*id, b.len()));
    }
    ds.run = run.into();
    let steps: Vec<String> = SetCondition::ALL
        .into_iter()
        .map(|c| (c, s.steps_of(c)))
        .filter(|(_, k)| *k > 0)
        .map(|(c, k)| format!("{} {k}", c.name()))
        .collect();
    notes.push(format!(
        "a programme of {} test blocks (runs {}..{}), one per sweep: cut at {} pause(s) in time, \
         {} new cycle(s) of repeated sweeps and where a set condition steps ({}); rule in \
         docs/programmes.md (window {} rows)",
        s.blocks.len(),
        ids[0],
        ids[ids.len() - 1],
        s.time_cuts(),
        s.cycle_cuts(),
        if steps.is_empty() {
            "none".to_string()
        } else {
            steps.join(", ")
        },
        s.window_rows
    ));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_median_ignores_a_spike_and_follows_a_step() {
        let mut x = vec![1.0; 20];
        x[5] = 100.0;
        for v in &mut x[12..] {
            *v = 3.0;
        }
        let m = running_median(&x, 2);
        assert_eq!(m[5], 1.0);
        assert_eq!(m[11], 1.0);
        assert_eq!(m[12], 3.0);
        assert_eq!(m[19], 3.0);
        assert_eq!(running_median(&[2.0], 3), vec![2.0]);
    }

    #[test]
    fn tolerances_follow_the_rule() {
        assert_eq!(SetCondition::Load.tolerance(1000.0), 150.0);
        assert_eq!(SetCondition::Load.tolerance(-4000.0), 400.0);
        assert!((SetCondition::Camber.tolerance(0.0).to_degrees() - 0.5).abs() < 1e-12);
        assert_eq!(
            SetCondition::Camber.format(degrees_to_radians(2.0)),
            "2.00 deg"
        );
    }

    #[test]
    fn the_largest_mean_split_is_at_the_step() {
        let m: Vec<f64> = (0..100).map(|i| if i < 37 { 0.0 } else { 5.0 }).collect();
        assert_eq!(largest_mean_split(&m, 10), Some(37));
        assert_eq!(largest_mean_split(&m[..15], 10), None);
    }

    /// One run at 100 Hz, one load, with the slip angle `alpha(t)` [deg].
    fn sweeping(seconds: f64, alpha: impl Fn(f64) -> f64) -> Dataset {
        let n = (seconds * 100.0) as usize;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.01).collect();
        Dataset {
            source: "sweep cycles".into(),
            run: vec![1; n].into(),
            alpha: Some(t.iter().map(|t| degrees_to_radians(alpha(*t))).collect()),
            fz: vec![1100.0; n].into(),
            time: Some(t.into()),
            ..Dataset::default()
        }
    }

    #[test]
    fn a_repeated_sweep_is_cut_into_its_cycles_and_a_single_sweep_is_not() {
        // A warm-up: +-12 deg triangles of 6.5 s, twelve times at one load.
        let period = 6.5;
        let triangle = move |t: f64| {
            let x = (t / period).fract();
            12.0 * if x < 0.25 {
                4.0 * x
            } else if x < 0.75 {
                2.0 - 4.0 * x
            } else {
                4.0 * x - 4.0
            }
        };
        let warm_up = split(&sweeping(12.0 * period, triangle));
        assert_eq!(warm_up.blocks.len(), 12, "{:?}", warm_up.blocks);
        assert_eq!(warm_up.cycle_cuts(), 11);
        for b in &warm_up.blocks[1..11] {
            assert!((b.len() as f64 - 650.0).abs() <= 2.0, "{b:?}");
        }
        // One sweep there and back (0 -> +12 -> -12 -> 0) and one the other way: whole.
        assert_eq!(split(&sweeping(period, triangle)).blocks.len(), 1);
        assert_eq!(split(&sweeping(period, |t| -triangle(t))).blocks.len(), 1);
        // Two cycles pass upward through zero once: whole; three pass twice: cut in three.
        assert_eq!(split(&sweeping(2.0 * period, triangle)).blocks.len(), 1);
        let three = split(&sweeping(3.0 * period, triangle));
        assert_eq!(three.blocks.len(), 3, "{:?}", three.blocks);
    }
}
