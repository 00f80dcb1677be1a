//! A slip ratio the test plan does not move is not a driver. In a programme none of whose
//! test blocks sweeps the slip ratio, and whose Fx stays near free rolling, the slip-ratio channel reads the offset of the radius the rig computes it
//! with (`SR`, from the effective rolling radius, reads -0.02 to -0.05 through a cornering
//! run) and noise. Read as a slip, it would hand combined slip and a slip-ratio shift a
//! driver the test never set, and Fx a "curve" of noise. It is taken as zero (free rolling),
//! with a note; the same run with a slip ratio that reads zero there (`SL`) gives the same
//! data.

use crate::data::{Dataset, Quantity};
use crate::method::prepare::programme::{self, SWEPT_SLIP_RATIO};
use crate::quantiles::{median_of, quantile_of};

/// Fx stays near free rolling when the 95th percentile of |Fx| / Fz on the loaded rows is at
/// most this: cornering runs give 0.06 to 0.25 (the drag of the slip angle), a drive or
/// brake sweep reaches the friction limit, about 1.
pub const FREE_ROLLING_FX_SHARE: f64 = 0.3;
/// Rows with at least this share of the median load count as loaded.
const LOADED_SHARE: f64 = 0.25;
/// A file with fewer loaded rows than this holds no test plan to judge (a TTC run logs 100
/// rows a second, a block lasts seconds): its slip ratio is kept as read.
pub const PLAN_ROWS: usize = 200;

/// Takes the slip ratio of `ds` as zero when the plan does not move it and Fx stays near free
/// rolling (see the module), with a note; else leaves it. A file of fewer than [`PLAN_ROWS`]
/// loaded rows is left as read: it holds no plan to judge.
pub fn apply(ds: &mut Dataset, notes: &mut Vec<String>) {
    let Some(kappa) = ds.kappa.clone() else {
        return;
    };
    if kappa.iter().all(|k| *k == 0.0) {
        return;
    }
    // Blocks held at slip ratios apart would be a test of slip too, but then Fx leaves free
    // rolling (a held slip of 0.05 drives or brakes the tire hard): the load moves the
    // offset of `SR` by several hundredths from block to block.
    if programme::sweeps(&programme::blocks(ds), Quantity::Kappa) {
        return;
    }
    let fz = &ds.fz;
    let Some(fz_median) = median_of(|| fz.iter().copied().filter(|f| *f > 0.0)) else {
        return;
    };
    let loaded = |i: usize| fz[i] > LOADED_SHARE * fz_median;
    if (0..fz.len()).filter(|&i| loaded(i)).count() < PLAN_ROWS {
        return;
    }
    let fx_share = match ds.column(Quantity::Fx) {
        None => None,
        Some(fx) => {
            let share = || {
                (0..fz.len())
                    .filter(|&i| loaded(i))
                    .map(|i| fx[i].abs() / fz[i])
            };
            quantile_of(share, 0.95)
        }
    };
    if fx_share.is_some_and(|s| s > FREE_ROLLING_FX_SHARE) {
        return;
    }
    let offset = median_of(|| (0..fz.len()).filter(|&i| loaded(i)).map(|i| kappa[i]));
    notes.push(format!(
        "slip ratio taken as 0 (free rolling): no test block sweeps it (an interquartile range \
         of {SWEPT_SLIP_RATIO} or more within a block), and {}; the channel reads an offset of \
         the radius it was computed with (median {}) and noise, not a slip the test set. No \
         effect of the slip ratio can be claimed from this file, and Fx, whose slip it is, has \
         no slip to be fitted on",
        match fx_share {
            Some(s) => format!(
                "Fx stays near free rolling (95th percentile of |Fx| / Fz {s:.2}, at most \
                 {FREE_ROLLING_FX_SHARE})"
            ),
            None => "there is no Fx channel".to_string(),
        },
        offset.map_or_else(|| "unknown".to_string(), |m| format!("{m:.3}"))
    ));
    ds.kappa = Some(vec![0.0; kappa.len()].into());
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ten runs of 100 rows; slip ratio per row, Fx a share of the 4 kN load per row.
    fn programme(kappa: impl Fn(usize) -> f64, fx_share: f64) -> Dataset {
        let n = 1000;
        let col = |f: &dyn Fn(usize) -> f64| -> Option<crate::data::Column> {
            Some((0..n).map(f).collect())
        };
        Dataset {
            source: "free rolling test".into(),
            run: (0..n).map(|i| (i / 100) as i64).collect(),
            fz: vec![4000.0; n].into(),
            kappa: col(&kappa),
            alpha: col(&|i| ((i % 100) as f64 - 50.0) * 0.004),
            fx: col(&|i| {
                if i % 2 == 0 {
                    fx_share * 4000.0
                } else {
                    -fx_share * 4000.0
                }
            }),
            ..Dataset::default()
        }
    }

    #[test]
    fn an_unswept_slip_ratio_at_free_rolling_is_taken_as_zero() {
        let mut ds = programme(|i| -0.036 + 0.001 * ((i % 7) as f64 - 3.0), 0.05);
        let mut notes = Vec::new();
        apply(&mut ds, &mut notes);
        assert!(ds.kappa.as_ref().unwrap().iter().all(|k| *k == 0.0));
        assert_eq!(notes.len(), 1);
        assert!(
            notes[0].contains("(95th percentile of |Fx| / Fz 0.05, at most 0.3)")
                && notes[0].contains("(median -0.036)"),
            "{}",
            notes[0]
        );
    }

    #[test]
    fn a_file_too_short_to_hold_a_plan_keeps_its_slip_ratio() {
        // The programme's first `keep` rows.
        let first = |keep: usize| {
            let mut ds = programme(|_| -0.036, 0.05);
            ds.fz = ds.fz[..keep].to_vec().into();
            ds.run = ds.run[..keep].to_vec().into();
            for c in [&mut ds.kappa, &mut ds.alpha, &mut ds.fx] {
                *c = c.as_ref().map(|v| v[..keep].to_vec().into());
            }
            ds
        };
        let mut ds = first(PLAN_ROWS - 1);
        let mut notes = Vec::new();
        apply(&mut ds, &mut notes);
        assert!(ds.kappa.as_ref().unwrap().iter().all(|k| *k == -0.036));
        assert!(notes.is_empty(), "{notes:?}");
        // One row more and the same data is judged a plan.
        let mut ds = first(PLAN_ROWS);
        apply(&mut ds, &mut notes);
        assert!(ds.kappa.as_ref().unwrap().iter().all(|k| *k == 0.0));
    }

    #[test]
    fn a_swept_slip_ratio_or_a_driven_tire_keeps_its_slip_ratio() {
        // Swept: -0.2 to 0.2 within every run.
        let swept = |i: usize| ((i % 100) as f64 - 50.0) * 0.004;
        for (mut ds, why) in [
            (programme(swept, 0.05), "swept"),
            (programme(|_| -0.036, 0.6), "Fx far from free rolling"),
        ] {
            let before = ds.kappa.clone();
            let mut notes = Vec::new();
            apply(&mut ds, &mut notes);
            assert_eq!(ds.kappa, before, "{why}");
            assert!(notes.is_empty(), "{why}: {notes:?}");
        }
    }
}
