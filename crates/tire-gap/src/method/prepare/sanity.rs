//! Channel sanity before any fit: a channel that reads a value the others show to be
//! impossible, or is constant where it cannot be, is a dead or disconnected sensor. It is
//! left out (its column set to `None`, with a note naming it, the rows and why), and so is a
//! measured channel that needs it as its slip; the diagnosis then proceeds exactly as if the
//! file had not had it. Runs before a programme is split into blocks, so a dead channel
//! cannot shape the blocks.
//!
//! # Rules
//!
//! - **Slip ratio at lock or spin that the forces contradict.** On the rows that carry load
//!   (Fz > 0) and, when speed is known, roll at 1 m/s or more: if `|kappa| >= 0.9` on at least
//!   half of them, and the longitudinal force is not a sliding tire's (`Fx sign(kappa) >=
//!   0.3 Fz`) on at least 90 % of those, or there is no Fx channel to show it, `kappa` is left
//!   out (and Fx with it). A wheel-speed channel reading ~0 gives SR = -1 throughout: a locked
//!   wheel, which a tire test never holds for most of its rows and which would brake at the
//!   sliding friction on every one of them, not sweep through small and opposite forces.
//! - **Speed at standstill while the forces vary.** If the speed is below 0.5 m/s on at least
//!   half the loaded rows and on those rows Fx or Fy spans (5th to 95th percentile) half the
//!   median load or more, `speed` is left out: a standing tire does not sweep through such
//!   forces.
//! - **Time that does not move.** A time column with one value on every row (two rows or
//!   more) is left out.
//! - **A force flat while its slip sweeps.** Fx when the slip ratio spans (5th to 95th
//!   percentile) 0.05 or more, Fy and Mz when the slip angle spans 2 deg or more, are left out
//!   if they span (1st to 99th percentile) less than 1 % of the median load (Mz: 1 % of the
//!   median load times 0.01 m): a tire swept through its slip cannot hold its force constant.
//!
//! A set condition that is constant (one pressure, one camber) is legitimate and kept: what
//! it means for the effects is decided later (`crate::method::prepare::adequacy`, `crate::method::diagnose`).

use mf87::units::degrees_to_radians;

use crate::data::{Dataset, Quantity};
use crate::quantiles::{median, quantile};

/// `|kappa|` at or beyond this is a locked or spinning wheel.
pub const LOCKED_SLIP: f64 = 0.9;
/// Fraction of rows that is "most".
pub const MOST: f64 = 0.5;
/// Fraction of the locked rows on which a sliding tire's force must show.
pub const SLIDING_ROWS: f64 = 0.9;
/// Rows at or above this speed roll [m/s].
pub const ROLLING_SPEED: f64 = 1.0;
/// A sliding tire's longitudinal force, as a fraction of the load.
pub const SLIDING_FX: f64 = 0.3;
/// Below this speed the wheel stands [m/s].
pub const STANDSTILL_SPEED: f64 = 0.5;
/// Force span, as a fraction of the median load, that a standing tire does not show.
pub const STANDSTILL_FORCE_SPAN: f64 = 0.5;
/// A force spanning less than this fraction of the median load is flat.
pub const FLAT_FORCE: f64 = 0.01;
/// Lever arm turning [`FLAT_FORCE`] into a flat moment \[m\].
pub const FLAT_MZ_ARM: f64 = 0.01;
/// The slip ratio sweeps when it spans this much.
pub const SWEPT_SLIP_RATIO: f64 = 0.05;
/// The slip angle sweeps when it spans this much \[deg\].
pub const SWEPT_SLIP_ANGLE_DEG: f64 = 2.0;

/// A channel left out, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct LeftOut {
    pub channel: Quantity,
    /// The rows the finding rests on (of those looked at).
    pub rows: usize,
    /// Rows looked at.
    pub of: usize,
    pub reason: String,
}

impl LeftOut {
    /// The note for the report.
    pub fn note(&self, n: usize) -> String {
        format!(
            "{} left out (all {n} rows): {}; the diagnosis proceeds as if the file had no {} channel",
            self.channel.name(),
            self.reason,
            self.channel.name()
        )
    }
}

/// The rows carrying load.
fn loaded(ds: &Dataset) -> Vec<usize> {
    (0..ds.len()).filter(|&i| ds.fz[i] > 0.0).collect()
}

fn span(v: &[f64], q: f64) -> f64 {
    match (quantile(v, q), quantile(v, 1.0 - q)) {
        (Some(lo), Some(hi)) => hi - lo,
        _ => 0.0,
    }
}

fn pick(col: &[f64], rows: &[usize]) -> Vec<f64> {
    rows.iter().map(|&i| col[i]).collect()
}

/// Slip ratio at lock or spin that the forces contradict.
fn dead_slip_ratio(ds: &Dataset) -> Option<LeftOut> {
    let kappa = ds.kappa.as_deref()?;
    let rolling: Vec<usize> = loaded(ds)
        .into_iter()
        .filter(|&i| ds.speed.as_deref().is_none_or(|v| v[i] >= ROLLING_SPEED))
        .collect();
    let locked: Vec<usize> = rolling
        .iter()
        .copied()
        .filter(|&i| kappa[i].abs() >= LOCKED_SLIP)
        .collect();
    if rolling.is_empty() || (locked.len() as f64) < MOST * rolling.len() as f64 {
        return None;
    }
    let level = median(&pick(kappa, &locked)).unwrap_or(0.0);
    let at = if ds.speed.is_some() {
        "rolling loaded rows (Fz > 0, speed >= 1 m/s)"
    } else {
        "loaded rows"
    };
    let force = match ds.fx.as_deref() {
        Some(fx) => {
            let sliding = locked
                .iter()
                .filter(|&&i| fx[i] * kappa[i].signum() >= SLIDING_FX * ds.fz[i])
                .count();
            if sliding as f64 >= SLIDING_ROWS * locked.len() as f64 {
                return None;
            }
            format!(
                "yet Fx is a sliding tire's (Fx sign(kappa) >= {SLIDING_FX} Fz) on only {sliding} \
                 of them (a locked or spinning wheel gives it on nearly all)"
            )
        }
        None => "and no Fx channel shows a wheel sliding".to_string(),
    };
    Some(LeftOut {
        channel: Quantity::Kappa,
        rows: locked.len(),
        of: rolling.len(),
        reason: format!(
            "|kappa| >= {LOCKED_SLIP} (a locked or spinning wheel; median {level:.3}) on {} of \
             {} {at}, {force}: a dead wheel-speed or slip channel, not the tire",
            locked.len(),
            rolling.len()
        ),
    })
}

/// Speed at standstill while the forces vary.
fn dead_speed(ds: &Dataset) -> Option<LeftOut> {
    let speed = ds.speed.as_deref()?;
    let rows = loaded(ds);
    let still: Vec<usize> = rows
        .iter()
        .copied()
        .filter(|&i| speed[i] < STANDSTILL_SPEED)
        .collect();
    if rows.is_empty() || (still.len() as f64) < MOST * rows.len() as f64 {
        return None;
    }
    let load = median(&pick(&ds.fz, &still))?;
    let (name, widest) = [(Quantity::Fx, &ds.fx), (Quantity::Fy, &ds.fy)]
        .into_iter()
        .filter_map(|(q, c)| Some((q.name(), span(&pick(c.as_deref()?, &still), 0.05))))
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    if widest < STANDSTILL_FORCE_SPAN * load {
        return None;
    }
    Some(LeftOut {
        channel: Quantity::Speed,
        rows: still.len(),
        of: rows.len(),
        reason: format!(
            "speed < {STANDSTILL_SPEED} m/s on {} of {} loaded rows, while {name} spans \
             {widest:.0} N there (at least {STANDSTILL_FORCE_SPAN} of the median load \
             {load:.0} N), which a standing tire does not give: a dead speed channel",
            still.len(),
            rows.len()
        ),
    })
}

/// Time with one value on every row.
fn dead_time(ds: &Dataset) -> Option<LeftOut> {
    let t = ds.time.as_deref()?;
    let first = *t.first()?;
    if t.len() < 2 || t.iter().any(|v| *v != first) {
        return None;
    }
    Some(LeftOut {
        channel: Quantity::Time,
        rows: t.len(),
        of: t.len(),
        reason: format!("time is {first} s on every row: it does not run"),
    })
}

/// A force or moment flat while its slip sweeps.
fn flat_force(ds: &Dataset, q: Quantity) -> Option<LeftOut> {
    let values = ds.column(q)?;
    let (slip, swept, shown) = match q {
        Quantity::Fx => (
            Quantity::Kappa,
            SWEPT_SLIP_RATIO,
            format!("{SWEPT_SLIP_RATIO}"),
        ),
        _ => (
            Quantity::Alpha,
            degrees_to_radians(SWEPT_SLIP_ANGLE_DEG),
            format!("{SWEPT_SLIP_ANGLE_DEG} deg"),
        ),
    };
    let slip_span = span(ds.column(slip)?, 0.05);
    if slip_span < swept {
        return None;
    }
    let load = median(&ds.fz)?;
    let (limit, unit) = match q {
        Quantity::Mz => (FLAT_FORCE * load * FLAT_MZ_ARM, "N.m"),
        _ => (FLAT_FORCE * load, "N"),
    };
    let own = span(values, 0.01);
    if load <= 0.0 || own >= limit {
        return None;
    }
    Some(LeftOut {
        channel: q,
        rows: values.len(),
        of: values.len(),
        reason: format!(
            "{} spans only {own:.3} {unit} (1st to 99th percentile; flat below {limit:.3} {unit}) \
             while {} sweeps over {} or more: a dead or disconnected sensor",
            q.name(),
            slip.name(),
            shown
        ),
    })
}

/// One rule: the channel it leaves out, if any.
type Rule = dyn Fn(&Dataset) -> Option<LeftOut>;

/// The channels the rules leave out, in the order they are applied (each rule sees the data
/// set without the channels left out before it).
pub fn check(ds: &Dataset) -> Vec<LeftOut> {
    let mut ds = ds.clone();
    let mut found = Vec::new();
    let rules: [&Rule; 6] = [
        &dead_slip_ratio,
        &dead_speed,
        &dead_time,
        &|d| flat_force(d, Quantity::Fx),
        &|d| flat_force(d, Quantity::Fy),
        &|d| flat_force(d, Quantity::Mz),
    ];
    for rule in rules {
        if let Some(l) = rule(&ds) {
            remove(&mut ds, l.channel);
            found.push(l);
        }
    }
    found
}

fn remove(ds: &mut Dataset, q: Quantity) {
    if let Some(slot) = ds.column_slot(q) {
        *slot = None;
    }
}

/// Applies [`check`]: the channels found are set to `None`, and so is a measured channel
/// whose slip is gone (Fx needs kappa; Fy and Mz need alpha); each with a note. Errs when no
/// measured channel with its slip is left.
pub fn apply(ds: &mut Dataset, notes: &mut Vec<String>) -> Result<Vec<LeftOut>, String> {
    let found = check(ds);
    for l in &found {
        remove(ds, l.channel);
        notes.push(l.note(ds.len()));
    }
    for (measured, slip) in [
        (Quantity::Fx, Quantity::Kappa),
        (Quantity::Fy, Quantity::Alpha),
        (Quantity::Mz, Quantity::Alpha),
    ] {
        if ds.has(measured) && !ds.has(slip) {
            remove(ds, measured);
            notes.push(format!(
                "{} left out with {}: it needs that slip",
                measured.name(),
                slip.name()
            ));
        }
    }
    if !found.is_empty() && ds.fx.is_none() && ds.fy.is_none() && ds.mz.is_none() {
        let names: Vec<&str> = found.iter().map(|l| l.channel.name()).collect();
        return Err(format!(
            "no measured force or moment with its slip is left once the implausible channel(s) \
             {} are left out: {}",
            names.join(", "),
            found
                .iter()
                .map(|l| l.reason.as_str())
                .collect::<Vec<_>>()
                .join("; ")
        ));
    }
    Ok(found)
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
            alpha: col(&|i| degrees_to_radians(((i % 100) as f64 - 50.0) / 5.0)),
            kappa: col(&|_| -1.0),
            fx: col(&|i| (i % 7) as f64 * 3.0),
            fy: col(&|i| ((i % 100) as f64 - 50.0) * 30.0),
            mz: col(&|i| ((i % 100) as f64 - 50.0) * 0.5),
            ..Dataset::default()
        }
    }

    #[test]
    fn a_dead_slip_ratio_goes_with_fx() {
        let mut ds = rig(400);
        let mut notes = Vec::new();
        let found = apply(&mut ds, &mut notes).unwrap();
        assert_eq!(found.len(), 1);
        assert_eq!(
            (found[0].channel, found[0].rows, found[0].of),
            (Quantity::Kappa, 400, 400)
        );
        assert!(ds.kappa.is_none() && ds.fx.is_none() && ds.fy.is_some());
        assert!(
            notes[0].starts_with("kappa left out (all 400 rows)"),
            "{notes:?}"
        );
        assert!(notes[1].starts_with("Fx left out with kappa"), "{notes:?}");
    }

    #[test]
    fn a_braking_programme_under_a_dead_slip_ratio_is_no_locked_wheel() {
        // Every 100 rows: 25 at -100 N (between sweeps), 75 braking at -1200 N (1.2 Fz): a
        // braking force on most rows, but a locked wheel would slide on all of them.
        let mut ds = rig(400);
        ds.fx = Some(
            (0..400)
                .map(|i| if i % 100 < 25 { -100.0 } else { -1200.0 })
                .collect(),
        );
        let found = check(&ds);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].channel, Quantity::Kappa);
        assert!(
            found[0].reason.contains("on only 300 of them"),
            "{}",
            found[0].reason
        );
    }

    #[test]
    fn a_wheel_that_brakes_at_lock_keeps_its_slip() {
        // Fx = -0.8 Fz at kappa = -1: a locked wheel sliding, consistent with the slip.
        let mut ds = rig(400);
        ds.fx = Some(vec![-800.0; 400].into());
        assert!(check(&ds).is_empty());
        // At standstill the slip ratio is not judged (no rolling row).
        let mut ds = rig(400);
        ds.speed = Some(vec![0.2; 400].into());
        ds.fy = Some(vec![0.0; 400].into());
        assert!(check(&ds).iter().all(|l| l.channel != Quantity::Kappa));
    }

    #[test]
    fn speed_time_and_flat_forces() {
        let mut ds = rig(400);
        ds.kappa = Some((0..400).map(|i| (i % 50) as f64 * 0.004 - 0.1).collect());
        ds.fx = Some(vec![0.0; 400].into());
        ds.speed = Some(vec![0.0; 400].into());
        ds.time = Some(vec![3.0; 400].into());
        let found: Vec<Quantity> = check(&ds).iter().map(|l| l.channel).collect();
        assert_eq!(found, vec![Quantity::Speed, Quantity::Time, Quantity::Fx]);
        // Fy and Mz sweep: kept; a flat Mz while alpha sweeps is not.
        ds.mz = Some(vec![0.05; 400].into());
        let found: Vec<Quantity> = check(&ds).iter().map(|l| l.channel).collect();
        assert_eq!(found.last(), Some(&Quantity::Mz));
        // With every measured channel gone, applying is an error naming the channels.
        ds.fy = Some(vec![1.0; 400].into());
        let e = apply(&mut ds.clone(), &mut Vec::new()).unwrap_err();
        assert!(e.contains("Fx, Fy, Mz"), "{e}");
    }

    #[test]
    fn constant_set_conditions_are_kept() {
        let mut ds = rig(400);
        ds.kappa = Some(vec![0.0; 400].into());
        ds.pressure = Some(vec![82.7; 400].into());
        ds.gamma = Some(vec![0.0; 400].into());
        ds.temperature = Some(vec![30.0; 400].into());
        assert!(check(&ds).is_empty());
    }
}
