//! Rows, not programmes: the samples of a file that cannot be a steady tire test are left out
//! by stated rules before anything else, each with a note that counts them, and a channel
//! whose values a tire test cannot give is left out rather than the whole file refused.
//!
//! # Rules, in order
//!
//! 1. **Not rolling at a test speed** (with a speed channel on which most rows roll at
//!    1 m/s or more): rows at standstill (|V| < 1 m/s: the wheel before spin-up and after
//!    spin-down, where the speed reads a little below zero and the slip ratio divides by
//!    nearly nothing), and rows in spin-up, spin-down or a change of set speed (the speed
//!    changing by 1 m/s^2 or more over the second around the row, with a time channel). There
//!    is no steady slip in them. A programme whose rows mostly stand is left alone here (a
//!    slow rig, or a dead speed channel: `crate::method::prepare::sanity`).
//! 2. **A tire that failed while rolling** (with time, load and pressure channels): where,
//!    at a test speed, the load falls within half a second below [`FAILURE_LOAD_SHARE`] of
//!    its level over the second before, and the inflation pressure over the two seconds
//!    from one second later is [`FAILURE_PRESSURE_DROP`] (and at least
//!    [`FAILURE_PRESSURE_DROP_MIN`]) lower than over the two seconds before, the tire has
//!    lost its bead or its air (a low-pressure cornering run at high slip angle); the rows
//!    from there to the next standstill (where the tire can be seated again) or the end of
//!    the clock's stretch are no tire test. On the public TTC runs a change of set load
//!    moves the pressure by at most 2.3 %, a failure by 9 to 17 %.
//! 3. **Values no tire test gives** ([`Quantity::plausible`]: a speed below 0 or above
//!    150 m/s, a slip angle or camber beyond 90 deg, a slip ratio beyond 10, a load below
//!    -1 kN or above 100 kN, ...) on the rows left: on at most [`FEW_ROWS`] of them the rows
//!    are left out (a corrupt sample, a glitch); on more, the channel is (a mislabelled unit
//!    or a broken sensor), with the measured channels that need it as their slip. A load
//!    implausible on more than that is an error: the load is required.
//!
//! Row numbers in the notes count the file's samples from 1.

use std::ops::Range;

use crate::data::{Dataset, Quantity};

/// Below this speed [m/s] the wheel stands.
pub const STANDSTILL_SPEED: f64 = 1.0;
/// At or above this rate of change of speed [m/s^2] the rig is spinning up or down.
pub const SPEED_CHANGE: f64 = 1.0;
/// Half the window \[s\] over which the rate of change of speed is taken.
pub const SPEED_CHANGE_HALF_WINDOW: f64 = 0.5;
/// A failure: the load falls below this share of its level over the second before.
pub const FAILURE_LOAD_SHARE: f64 = 2.0 / 3.0;
/// A failure: the pressure falls by at least this share of its level...
pub const FAILURE_PRESSURE_DROP: f64 = 0.05;
/// ...and by at least this much \[kPa\].
pub const FAILURE_PRESSURE_DROP_MIN: f64 = 3.0;
/// At most this share of the rows implausible: the rows are left out, else the channel.
pub const FEW_ROWS: f64 = 0.05;

/// The rows to keep under rule 1, with the counts of those left out at standstill and in
/// a change of speed; `None` when the rule does not apply.
fn rolling_rows(ds: &Dataset) -> Option<(Vec<bool>, usize, usize)> {
    let speed = ds.speed.as_deref()?;
    let n = speed.len();
    let standing: Vec<bool> = speed.iter().map(|&v| stands(v)).collect();
    let stand = standing.iter().filter(|s| **s).count();
    if 2 * stand > n {
        return None;
    }
    let changing = match ds.time.as_deref() {
        Some(t) => speed_changing(t, speed),
        None => vec![false; n],
    };
    let keep: Vec<bool> = (0..n).map(|i| !standing[i] && !changing[i]).collect();
    let change = (0..n).filter(|&i| !standing[i] && changing[i]).count();
    Some((keep, stand, change))
}

/// Whether the speed changes by [`SPEED_CHANGE`] or more over the window around each row:
/// the rate between the window's first and last row within the stretch where time
/// increases.
fn speed_changing(t: &[f64], v: &[f64]) -> Vec<bool> {
    let mut changing = vec![false; t.len()];
    for stretch in stretches(t) {
        let (mut lo, mut hi) = (stretch.start, stretch.start);
        for i in stretch.clone() {
            while t[i] - t[lo] > SPEED_CHANGE_HALF_WINDOW {
                lo += 1;
            }
            hi = hi.max(i);
            while hi + 1 < stretch.end && t[hi + 1] - t[i] <= SPEED_CHANGE_HALF_WINDOW {
                hi += 1;
            }
            let dt = t[hi] - t[lo];
            changing[i] = dt > 0.0 && ((v[hi] - v[lo]) / dt).abs() >= SPEED_CHANGE;
        }
    }
    changing
}

/// Whether the wheel stands at speed `v` (an unread speed counts as standing).
fn stands(v: f64) -> bool {
    v.abs() < STANDSTILL_SPEED || v.is_nan()
}

/// The stretches of rows where time increases: a restart of the clock begins a new one.
fn stretches(t: &[f64]) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut start = 0;
    for i in 1..=t.len() {
        // A time not after the one before (or unread) ends the stretch.
        let goes_on =
            i < t.len() && t[i].partial_cmp(&t[i - 1]) == Some(std::cmp::Ordering::Greater);
        if !goes_on {
            out.push(start..i);
            start = i;
        }
    }
    out
}

/// A tire failure found by rule 2.
struct Failure {
    /// The row where it begins, in the file.
    at: usize,
    time: f64,
    /// Mean load [N] over the second before and the half second after.
    load: (f64, f64),
    /// Mean pressure [kPa] over the two seconds before and the two seconds from one second
    /// after the load began to fall.
    pressure: (f64, f64),
}

/// Means of a channel over windows of time within one stretch of increasing time, from
/// running sums of its finite values.
struct Windows<'a> {
    t: &'a [f64],
    sum: Vec<f64>,
    count: Vec<usize>,
}

impl<'a> Windows<'a> {
    fn new(t: &'a [f64], x: &[f64]) -> Self {
        let mut sum = vec![0.0; x.len() + 1];
        let mut count = vec![0; x.len() + 1];
        for (i, v) in x.iter().enumerate() {
            let finite = v.is_finite();
            sum[i + 1] = sum[i] + if finite { *v } else { 0.0 };
            count[i + 1] = count[i] + usize::from(finite);
        }
        Windows { t, sum, count }
    }

    /// The mean over the rows of `stretch` with `from <= t < to`; `None` when there are none.
    fn mean(&self, stretch: &Range<usize>, from: f64, to: f64) -> Option<f64> {
        let (s, e) = (stretch.start, stretch.end);
        let lo = s + self.t[s..e].partition_point(|&x| x < from);
        let hi = s + self.t[s..e].partition_point(|&x| x < to);
        let n = self.count[hi] - self.count[lo.min(hi)];
        (n > 0).then(|| (self.sum[hi] - self.sum[lo.min(hi)]) / n as f64)
    }
}

/// Rule 2: the rows after a tire failure, and the failures.
fn failed_rows(ds: &Dataset) -> (Vec<bool>, Vec<Failure>) {
    let n = ds.len();
    let mut failed = vec![false; n];
    let mut failures = Vec::new();
    let (Some(t), Some(p)) = (ds.time.as_deref(), ds.pressure.as_deref()) else {
        return (failed, failures);
    };
    let standing = |i: usize| ds.speed.as_deref().is_some_and(|v| stands(v[i]));
    let load = Windows::new(t, &ds.fz);
    let pressure = Windows::new(t, p);
    for stretch in stretches(t) {
        let (first, last) = (t[stretch.start], t[stretch.end - 1]);
        let mut i = stretch.start;
        while i < stretch.end {
            let rolling = !standing(i) && first <= t[i] - 0.5 && last >= t[i] + 1.5;
            let found = if rolling {
                failure_at(i, t[i], &stretch, &load, &pressure)
            } else {
                None
            };
            match found {
                Some(f) => {
                    failures.push(f);
                    while i < stretch.end && !standing(i) {
                        failed[i] = true;
                        i += 1;
                    }
                }
                None => i += 1,
            }
        }
    }
    (failed, failures)
}

/// A failure beginning at row `i` (time `ti`) of `stretch`, if the load and the pressure
/// around it fall as rule 2 says.
fn failure_at(
    i: usize,
    ti: f64,
    stretch: &Range<usize>,
    load: &Windows,
    pressure: &Windows,
) -> Option<Failure> {
    let before = load.mean(stretch, ti - 1.0, ti)?;
    let after = load.mean(stretch, ti, ti + 0.5 + 1e-9)?;
    if !(before > 0.0 && after < FAILURE_LOAD_SHARE * before) {
        return None;
    }
    let p0 = pressure.mean(stretch, ti - 2.0, ti)?;
    let p1 = pressure.mean(stretch, ti + 1.0, ti + 3.0)?;
    (p0 - p1 >= (FAILURE_PRESSURE_DROP * p0).max(FAILURE_PRESSURE_DROP_MIN)).then_some(Failure {
        at: i,
        time: ti,
        load: (before, after),
        pressure: (p0, p1),
    })
}

/// The quantities whose values are judged, in this order (the load last: it is required).
const JUDGED: [Quantity; 11] = [
    Quantity::Time,
    Quantity::Speed,
    Quantity::Alpha,
    Quantity::Kappa,
    Quantity::Gamma,
    Quantity::Pressure,
    Quantity::Temperature,
    Quantity::Fx,
    Quantity::Fy,
    Quantity::Mz,
    Quantity::Fz,
];

/// What rule 3 found in one channel.
struct Implausible {
    rows: Vec<usize>,
    first: String,
}

fn implausible(ds: &Dataset, q: Quantity) -> Option<Implausible> {
    let col = ds.column(q)?;
    let rows: Vec<usize> = (0..col.len())
        .filter(|&i| q.plausible(col[i]).is_err())
        .collect();
    let first = q.plausible(col[*rows.first()?]).err()?;
    Some(Implausible { rows, first })
}

/// Applies the rules to `ds`, noting what was left out. Errs when the load is implausible
/// on more than a few rows, or when no row is left.
/// A data set the row rules refuse (e.g. the load implausible on more rows than they leave
/// out, or nothing left).
#[derive(Debug, Clone, PartialEq)]
pub struct Refused {
    pub message: String,
    /// The rows at fault, as positions in the file's rows (from 0).
    pub rows: Vec<usize>,
}

pub fn apply(ds: &mut Dataset, notes: &mut Vec<String>) -> Result<(), Refused> {
    let total = ds.len();
    let before = notes.len();
    // Positions in the file, for the notes.
    let mut origin: Vec<usize> = (0..total).collect();
    not_a_tire_test(ds, &mut origin, notes);
    for q in JUDGED {
        let Some(found) = implausible(ds, q) else {
            continue;
        };
        let n = ds.len();
        let at = format!("row {} of the file", origin[found.rows[0]] + 1);
        if found.rows.len() as f64 <= FEW_ROWS * n as f64 {
            let mut keep = vec![true; n];
            found.rows.iter().for_each(|&i| keep[i] = false);
            keep_rows(ds, &mut origin, &keep);
            notes.push(format!(
                "{} of {n} rows left out: {} outside what a tire test gives (first at {at}: {})",
                found.rows.len(),
                q.name(),
                found.first
            ));
        } else if q == Quantity::Fz {
            return Err(Refused {
                message: format!(
                    "the load is implausible on {} of {n} rows (first at {at}: {}): is FZ in \
                     the unit it names?",
                    found.rows.len(),
                    found.first
                ),
                rows: found.rows.iter().map(|&i| origin[i]).collect(),
            });
        } else {
            leave_out_channel(
                ds,
                q,
                notes,
                &format!(
                    "{} of {n} rows outside what a tire test gives (first at {at}: {}): a unit \
                 that is not the one named, or a broken sensor",
                    found.rows.len(),
                    found.first
                ),
            );
        }
    }
    if ds.is_empty() {
        return Err(Refused {
            message: format!("no row is left of the {total} once the rules above are applied"),
            rows: Vec::new(),
        });
    }
    if ds.fx.is_none() && ds.fy.is_none() && ds.mz.is_none() {
        let left_out: Vec<&str> = notes[before..]
            .iter()
            .map(String::as_str)
            .filter(|n| n.contains(" left out"))
            .collect();
        return Err(Refused {
            message: format!(
                "no measured force or moment with its slip is left: {}",
                left_out.join("; ")
            ),
            rows: Vec::new(),
        });
    }
    Ok(())
}

/// Rules 1 and 2: leaves out the rows where the wheel does not roll at a test speed and
/// those after a tire failure, noting each.
fn not_a_tire_test(ds: &mut Dataset, origin: &mut Vec<usize>, notes: &mut Vec<String>) {
    let total = ds.len();
    let (failed, failures) = failed_rows(ds);
    let rolling = rolling_rows(ds);
    let mut keep: Vec<bool> = match &rolling {
        Some((keep, _, _)) => keep.clone(),
        None => vec![true; total],
    };
    let after_failure = (0..total).filter(|&i| keep[i] && failed[i]).count();
    keep.iter_mut().zip(&failed).for_each(|(k, f)| *k &= !f);
    if keep.iter().any(|k| !k) {
        keep_rows(ds, origin, &keep);
    }
    if let Some((_, stand, change)) = rolling
        && stand + change > 0
    {
        notes.push(format!(
            "{} of {total} rows left out, where the wheel does not roll at a test speed: {stand} \
             at standstill (|V| < {STANDSTILL_SPEED} m/s) and {change} in spin-up, spin-down or a \
             change of speed (by {SPEED_CHANGE} m/s^2 or more over {} s): no steady slip there \
             (rule in docs/ttc-data.md)",
            stand + change,
            2.0 * SPEED_CHANGE_HALF_WINDOW
        ));
    }
    if after_failure > 0 {
        let each: Vec<String> = failures
            .iter()
            .map(|f| {
                format!(
                    "at {:.2} s (row {} of the file) the load fell from {:.0} to {:.0} N within \
                     half a second and the pressure from {:.1} to {:.1} kPa",
                    f.time,
                    f.at + 1,
                    f.load.0,
                    f.load.1,
                    f.pressure.0,
                    f.pressure.1
                )
            })
            .collect();
        notes.push(format!(
            "{after_failure} of {total} rows left out where the tire had failed while rolling: \
             {}: a bead unseated or air lost; the rows from there to the next standstill are no \
             tire test (rule in docs/programmes.md)",
            each.join("; ")
        ));
    }
}

/// Keeps the rows where `keep` is true, in `ds` and in `origin`.
fn keep_rows(ds: &mut Dataset, origin: &mut Vec<usize>, keep: &[bool]) {
    let rows: Vec<usize> = (0..keep.len()).filter(|&i| keep[i]).collect();
    *ds = ds.select(&rows);
    *origin = rows.iter().map(|&i| origin[i]).collect();
}

/// Leaves the channel `q` out, and the measured channels that need it as their slip.
fn leave_out_channel(ds: &mut Dataset, q: Quantity, notes: &mut Vec<String>, why: &str) {
    if let Some(slot) = ds.column_slot(q) {
        *slot = None;
    }
    let needing: &[Quantity] = match q {
        Quantity::Alpha => &[Quantity::Fy, Quantity::Mz],
        Quantity::Kappa => &[Quantity::Fx],
        _ => &[],
    };
    let mut gone = Vec::new();
    for m in needing {
        if let Some(slot) = ds.column_slot(*m)
            && slot.take().is_some()
        {
            gone.push(m.name());
        }
    }
    let with = if gone.is_empty() {
        String::new()
    } else {
        format!(", and with it {} (which needs it)", gone.join(" and "))
    };
    notes.push(format!(
        "{} left out{with}: {why}; the diagnosis proceeds as if the file had no {} channel",
        q.name(),
        q.name()
    ));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rig(n: usize) -> Dataset {
        let col = |f: &dyn Fn(usize) -> f64| Some((0..n).map(f).collect());
        Dataset {
            source: "t".into(),
            run: vec![1; n].into(),
            time: col(&|i| i as f64 * 0.01),
            speed: col(&|_| 11.1),
            fz: (0..n).map(|_| 1000.0).collect(),
            alpha: col(&|i| ((i % 100) as f64 - 50.0).to_radians() / 5.0),
            kappa: col(&|i| ((i % 40) as f64 - 20.0) / 200.0),
            fx: col(&|i| ((i % 40) as f64 - 20.0) * 100.0),
            fy: col(&|i| ((i % 100) as f64 - 50.0) * 30.0),
            ..Dataset::default()
        }
    }

    #[test]
    fn standstill_and_spin_up_rows_are_left_out_and_counted() {
        // 100 rows standing (reading a little below zero, slip ratio meaningless), a 4 s
        // spin-up at 2.775 m/s^2 (400 rows), then 1500 rows at 11.1 m/s.
        let mut ds = rig(2000);
        let speed: Vec<f64> = (0..2000)
            .map(|i| match i {
                0..100 => -0.011,
                100..500 => (i - 100) as f64 * 0.02775,
                _ => 11.1,
            })
            .collect();
        ds.speed = Some(speed.into());
        ds.kappa = Some(
            (0..2000)
                .map(|i| if i < 130 { 10.089 } else { 0.0 })
                .collect(),
        );
        let mut notes = Vec::new();
        apply(&mut ds, &mut notes).unwrap();
        // Standing: the first 100 rows and the spin-up's first 37 (below 1 m/s); changing:
        // the rest of the spin-up up to half a second into the steady speed.
        let left = 2000 - ds.len();
        assert!((500..=560).contains(&left), "{left} {notes:?}");
        assert!(ds.speed.as_ref().unwrap().iter().all(|v| *v >= 1.0));
        assert!(notes[0].contains("137 at standstill"), "{notes:?}");
        // The meaningless slip ratio went with the standing rows: no channel left out.
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(ds.kappa.is_some());
    }

    #[test]
    fn a_programme_that_mostly_stands_is_left_alone() {
        let mut ds = rig(400);
        ds.speed = Some(vec![0.2; 400].into());
        let mut notes = Vec::new();
        apply(&mut ds, &mut notes).unwrap();
        assert_eq!((ds.len(), notes.len()), (400, 0));
    }

    #[test]
    fn a_few_implausible_samples_go_as_rows_many_as_the_channel() {
        let mut ds = rig(1000);
        let mut alpha = ds.alpha.as_ref().unwrap().to_vec();
        alpha[10] = 7.0;
        alpha[20] = -9.0;
        ds.alpha = Some(alpha.into());
        let mut notes = Vec::new();
        apply(&mut ds, &mut notes).unwrap();
        assert_eq!(ds.len(), 998);
        assert!(
            notes[0].starts_with("2 of 1000 rows left out: alpha outside")
                && notes[0].contains("row 11 of the file"),
            "{notes:?}"
        );
        // A slip angle in degrees under a radian unit: the channel goes, with Fy.
        let mut ds = rig(1000);
        let deg: Vec<f64> = ds
            .alpha
            .as_ref()
            .unwrap()
            .iter()
            .map(|a| a.to_degrees())
            .collect();
        ds.alpha = Some(deg.into());
        let mut notes = Vec::new();
        apply(&mut ds, &mut notes).unwrap();
        assert_eq!(ds.len(), 1000);
        assert!(ds.alpha.is_none() && ds.fy.is_none());
        assert!(
            notes[0].starts_with("alpha left out, and with it Fy (which needs it):"),
            "{notes:?}"
        );
    }

    #[test]
    fn a_load_implausible_on_many_rows_is_an_error() {
        let mut ds = rig(100);
        ds.fz = (0..100)
            .map(|i| if i < 50 { 400_000.0 } else { 1000.0 })
            .collect();
        let e = apply(&mut ds, &mut Vec::new()).unwrap_err();
        assert!(
            e.message
                .starts_with("the load is implausible on 50 of 100 rows"),
            "{e:?}"
        );
        assert_eq!(e.rows, (0..50).collect::<Vec<_>>());
    }

    /// A low-pressure cornering run at 50 Hz: 20 s at 1500 N and 55 kPa; at 12 s the load
    /// steps to 700 N (a change of set load, the pressure barely moving); at 16 s the tire
    /// unseats: the load collapses to 400 N and the pressure falls to 47 kPa; standstill
    /// from 19 s, and a second run after it.
    fn failing_run() -> Dataset {
        let n = 1500;
        let mut ds = rig(n);
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.02).collect();
        let fz: Vec<f64> = t
            .iter()
            .map(|&t| match t {
                t if t < 12.0 => 1500.0,
                t if t < 16.0 => 700.0,
                t if t < 16.2 => 700.0 - (t - 16.0) * 1500.0,
                t if t < 22.0 => 400.0,
                _ => 1500.0,
            })
            .collect();
        let p: Vec<f64> = t
            .iter()
            .map(|&t| match t {
                t if t < 12.0 => 55.0,
                t if t < 16.3 => 54.5,
                t if t < 17.3 => 54.5 - (t - 16.3) * 7.5,
                t if t < 22.0 => 47.0,
                _ => 55.0,
            })
            .collect();
        let v: Vec<f64> = t
            .iter()
            .map(|&t| if (19.0..22.0).contains(&t) { 0.0 } else { 11.1 })
            .collect();
        ds.time = Some(t.into());
        ds.fz = fz.into();
        ds.pressure = Some(p.into());
        ds.speed = Some(v.into());
        ds
    }

    #[test]
    fn rows_after_a_tire_failure_go_to_the_next_standstill() {
        let mut ds = failing_run();
        let mut notes = Vec::new();
        apply(&mut ds, &mut notes).unwrap();
        let t = ds.time.as_deref().unwrap();
        // Left out: from about 16 s (the onset, found within the half second before the
        // load falls) to the standstill at 19 s; the standstill itself by rule 1.
        assert!(t.iter().all(|&t| !(16.0..22.0).contains(&t)), "{notes:?}");
        assert!(t.iter().any(|&t| (15.0..15.5).contains(&t)));
        assert!(t.iter().any(|&t| t >= 22.5));
        let failure = notes
            .iter()
            .find(|n| n.contains("the tire had failed while rolling"))
            .expect("a failure note");
        assert!(
            failure.contains("the pressure from 54.5 to 4")
                && failure.contains("the load fell from 700 to"),
            "{failure}"
        );
        // The change of set load at 12 s is no failure: its rows stay.
        assert!(t.iter().any(|&t| (12.0..12.5).contains(&t)));
    }

    #[test]
    fn a_load_step_with_the_pressure_held_is_no_failure() {
        let mut ds = failing_run();
        let p: Vec<f64> = vec![55.0; ds.len()];
        ds.pressure = Some(p.into());
        let (failed, failures) = failed_rows(&ds);
        assert!(failures.is_empty() && failed.iter().all(|f| !f));
        // Without a pressure channel the rule cannot tell a failure: nothing is left out.
        let mut ds = failing_run();
        ds.pressure = None;
        assert!(failed_rows(&ds).1.is_empty());
    }

    #[test]
    fn the_rate_of_speed_change_restarts_with_the_clock() {
        // Two stretches of time, each at its own steady speed: no change is seen across the
        // restart.
        let t: Vec<f64> = (0..200).map(|i| (i % 100) as f64 * 0.01).collect();
        let v: Vec<f64> = (0..200)
            .map(|i| if i < 100 { 10.0 } else { 20.0 })
            .collect();
        assert!(speed_changing(&t, &v).iter().all(|c| !c));
        let ramp: Vec<f64> = (0..200).map(|i| 10.0 + 0.02 * i as f64).collect();
        let t2: Vec<f64> = (0..200).map(|i| i as f64 * 0.01).collect();
        assert!(speed_changing(&t2, &ramp).iter().all(|c| *c));
    }
}
