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
//!    slow rig, or a dead speed channel: `crate::method::sanity`).
//! 2. **Values no tire test gives** ([`Quantity::plausible`]: a speed below 0 or above
//!    150 m/s, a slip angle or camber beyond 90 deg, a slip ratio beyond 10, a load below
//!    -1 kN or above 100 kN, ...) on the rows left: on at most [`FEW_ROWS`] of them the rows
//!    are left out (a corrupt sample, a glitch); on more, the channel is (a mislabelled unit
//!    or a broken sensor), with the measured channels that need it as their slip. A load
//!    implausible on more than that is an error: the load is required.
//!
//! Row numbers in the notes count the file's samples from 1.

use crate::data::{Dataset, Quantity};

/// Below this speed [m/s] the wheel stands.
pub const STANDSTILL_SPEED: f64 = 1.0;
/// At or above this rate of change of speed [m/s^2] the rig is spinning up or down.
pub const SPEED_CHANGE: f64 = 1.0;
/// Half the window [s] over which the rate of change of speed is taken.
pub const SPEED_CHANGE_HALF_WINDOW: f64 = 0.5;
/// At most this share of the rows implausible: the rows are left out, else the channel.
pub const FEW_ROWS: f64 = 0.05;

/// The rows to keep under rule 1, with the counts of those left out at standstill and in
/// a change of speed; `None` when the rule does not apply.
fn rolling_rows(ds: &Dataset) -> Option<(Vec<bool>, usize, usize)> {
    let speed = ds.speed.as_deref()?;
    let n = speed.len();
    let standing: Vec<bool> = speed
        .iter()
        .map(|v| v.abs() < STANDSTILL_SPEED || v.is_nan())
        .collect();
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
    let n = t.len();
    if n == 0 {
        return Vec::new();
    }
    // Stretches of increasing time: a restart of the clock begins a new one.
    let mut start_of = vec![0usize; n];
    for i in 1..n {
        start_of[i] = if t[i] > t[i - 1] { start_of[i - 1] } else { i };
    }
    let mut end_of = vec![n - 1; n];
    for i in (0..n.saturating_sub(1)).rev() {
        end_of[i] = if t[i + 1] > t[i] { end_of[i + 1] } else { i };
    }
    let (mut lo, mut hi) = (0usize, 0usize);
    (0..n)
        .map(|i| {
            lo = lo.max(start_of[i]);
            while t[i] - t[lo] > SPEED_CHANGE_HALF_WINDOW {
                lo += 1;
            }
            hi = hi.max(i);
            while hi < end_of[i] && t[hi + 1] - t[i] <= SPEED_CHANGE_HALF_WINDOW {
                hi += 1;
            }
            let dt = t[hi] - t[lo];
            dt > 0.0 && ((v[hi] - v[lo]) / dt).abs() >= SPEED_CHANGE
        })
        .collect()
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

/// What rule 2 found in one channel.
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
    if let Some((keep, stand, change)) = rolling_rows(ds)
        && stand + change > 0
    {
        keep_rows(ds, &mut origin, &keep);
        notes.push(format!(
            "{} of {total} rows left out, where the wheel does not roll at a test speed: {stand} \
             at standstill (|V| < {STANDSTILL_SPEED} m/s) and {change} in spin-up, spin-down or a \
             change of speed (by {SPEED_CHANGE} m/s^2 or more over {} s): no steady slip there \
             (rule in docs/ttc-data.md)",
            stand + change,
            2.0 * SPEED_CHANGE_HALF_WINDOW
        ));
    }
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
