//! Step 3, "where": the held-out residual split over operating regions, ranked by how much
//! more than their share of the data they hold of the squared error.

use mf87::Channel;
use serde::Serialize;

use crate::method::diagnose::design::{self, Condition};
use crate::method::prepare::channel_data::ChannelData;
use crate::quantiles::order_statistic_of;

/// Regions smaller than this share of the rows are not ranked (too few to say anything).
const MIN_SHARE: f64 = 0.01;

/// One operating region of one channel.
#[derive(Debug, Clone, Serialize)]
pub struct Region {
    pub channel: Channel,
    /// What the region splits on, e.g. "slip angle".
    pub dimension: &'static str,
    /// Which part, e.g. "saturated (|alpha| > 6 deg)".
    pub label: String,
    pub rows: usize,
    /// Share of the rows.
    pub share_rows: f64,
    /// Share of the squared held-out residual.
    pub share_squared_error: f64,
    /// share_squared_error / share_rows: above 1, the model is worse here than on average.
    pub concentration: f64,
    /// RMS residual in the region [N or N.m].
    pub rms: f64,
}

/// Labels each row along one dimension: the position of its label in `names` (None: the row
/// is not classified on it). One byte per row, not a string, so a million rows stay cheap.
struct Dimension {
    name: &'static str,
    names: Vec<String>,
    labels: Vec<Option<u8>>,
}

impl Dimension {
    /// The dimension labelling row `i` of `n` rows `label(i)`.
    fn new(
        name: &'static str,
        names: Vec<String>,
        n: usize,
        label: impl Fn(usize) -> Option<u8>,
    ) -> Dimension {
        Dimension {
            name,
            names,
            labels: (0..n).map(label).collect(),
        }
    }
}

/// Three labels for below `a`, between `a` and `b`, and from `b` on.
fn three_way(x: f64, a: f64, b: f64) -> Option<u8> {
    Some(if x < a {
        0
    } else if x < b {
        1
    } else {
        2
    })
}

/// The rows split at the terciles of the column whose value at row `i` of `n` is `value(i)`
/// (read in passes, not copied); `None` when it does not vary.
fn terciles(
    n: usize,
    value: impl Fn(usize) -> f64,
    name: &'static str,
    unit: &str,
    digits: usize,
) -> Option<Dimension> {
    let values = || (0..n).map(&value);
    let (lo, hi, count) = values().filter(|v| v.is_finite()).fold(
        (f64::INFINITY, f64::NEG_INFINITY, 0),
        |(lo, hi, count), v| (lo.min(v), hi.max(v), count + 1),
    );
    if count == 0 || hi - lo <= 1e-9 * hi.abs().max(1.0) {
        return None; // does not vary
    }
    let (third, two_thirds) = (count / 3, 2 * count / 3);
    let t2 = order_statistic_of(values, two_thirds)?;
    let t1 = order_statistic_of(values, third)?;
    let names = vec![
        format!("low (< {t1:.digits$} {unit})"),
        format!("middle ({t1:.digits$} to {t2:.digits$} {unit})"),
        format!("high (>= {t2:.digits$} {unit})"),
    ];
    Some(Dimension::new(name, names, n, |i| {
        three_way(value(i), t1, t2)
    }))
}

fn bands(
    values: &[f64],
    name: &'static str,
    symbol: &str,
    unit: &str,
    limits: (f64, f64),
    names: [&str; 3],
) -> Dimension {
    let (a, b) = limits;
    let labels = vec![
        format!("{} (|{symbol}| < {a} {unit})", names[0]),
        format!("{} ({a} to {b} {unit})", names[1]),
        format!("{} (|{symbol}| >= {b} {unit})", names[2]),
    ];
    Dimension::new(name, labels, values.len(), |i| {
        three_way(values[i].abs(), a, b)
    })
}

/// Owned label names.
fn owned(names: &[&str]) -> Vec<String> {
    names.iter().map(|n| n.to_string()).collect()
}

/// Each dimension of `data`'s rows, given to `each` in turn (one row labelling at a time).
fn dimensions(data: &ChannelData, mut each: impl FnMut(Dimension)) {
    let n = data.len();
    each_of(&mut each, terciles(n, |i| data.fz_kn[i], "load", "kN", 2));
    each(match data.channel {
        Channel::Fx => bands(
            &data.slip,
            "slip ratio",
            "sigma",
            "%",
            (3.0, 10.0),
            ["linear", "transition", "saturated"],
        ),
        _ => bands(
            &data.slip,
            "slip angle",
            "alpha",
            "deg",
            (2.0, 6.0),
            ["linear", "transition", "saturated"],
        ),
    });
    if data.channel != Channel::Fx && data.has_camber() {
        let names = owned(&[
            "positive (>= 0.5 deg)",
            "negative (<= -0.5 deg)",
            "zero (|gamma| < 0.5 deg)",
        ]);
        each(Dimension::new("camber", names, n, |i| {
            Some(match data.gamma_deg[i] {
                g if g >= 0.5 => 0,
                g if g <= -0.5 => 1,
                _ => 2,
            })
        }));
    }
    if let Some(other) = &data.other_slip {
        let threshold = match data.channel {
            Channel::Fx => 1f64.to_radians(),
            _ => 0.02,
        };
        let names = owned(&["combined slip", "pure slip"]);
        each(Dimension::new("slip mode", names, n, |i| {
            Some(if other[i].abs() > threshold { 0 } else { 1 })
        }));
    }
    // A condition that barely varies across the runs is not ranked: its terciles would split
    // the rig's wander around one set point (see `design::Spread`).
    for (column, condition, unit, digits) in [
        (&data.speed, Condition::Speed, "m/s", 1),
        (&data.pressure, Condition::Pressure, "kPa", 0),
        (&data.temperature, Condition::Temperature, "degC", 0),
    ] {
        let Some(v) = column else { continue };
        if design::spread_of(&data.run, v, condition).is_some_and(|s| s.identifiable()) {
            let value = |i: usize| v[i];
            each_of(
                &mut each,
                terciles(n, value, condition.name(), unit, digits),
            );
        }
    }
    slip_rate_dimensions(data, &mut each);
}

/// The sweep direction and the slip rate's terciles of `data`'s rows, given to `each`, when
/// the data have time.
fn slip_rate_dimensions(data: &ChannelData, each: &mut impl FnMut(Dimension)) {
    let n = data.len();
    if let Some(rate) = data.slip_rate_at() {
        let steady = 0.05 * (0..n).map(|i| rate(i).abs()).fold(0.0, f64::max);
        let names = owned(&["slip increasing", "slip decreasing", "slip steady"]);
        each(Dimension::new("sweep direction", names, n, |i| {
            Some(match rate(i) {
                r if r > steady => 0,
                r if r < -steady => 1,
                _ => 2,
            })
        }));
        let unit = if data.channel == Channel::Fx {
            "%/s"
        } else {
            "deg/s"
        };
        each_of(each, terciles(n, |i| rate(i).abs(), "slip rate", unit, 1));
    }
}

/// Every region of every dimension for one channel's held-out residuals, unranked; within a
/// dimension in the order of their labels.
/// The residuals may be stored in single precision; the sums are taken in double.
pub fn regions<R: Copy + Into<f64>>(data: &ChannelData, residuals: &[R]) -> Vec<Region> {
    let total_sq: f64 = residuals
        .iter()
        .map(|r| (*r).into())
        .filter(|r: &f64| r.is_finite())
        .map(|r| r * r)
        .sum();
    let n = residuals.len();
    let mut out = Vec::new();
    dimensions(data, |dim| {
        let mut groups = vec![(0usize, 0.0f64); dim.names.len()];
        for (label, r) in dim.labels.iter().zip(residuals) {
            let r: f64 = (*r).into();
            if let (Some(l), true) = (label, r.is_finite()) {
                let g = &mut groups[*l as usize];
                g.0 += 1;
                g.1 += r * r;
            }
        }
        let mut order: Vec<usize> = (0..dim.names.len()).filter(|&k| groups[k].0 > 0).collect();
        order.sort_by(|&a, &b| dim.names[a].cmp(&dim.names[b]));
        for k in order {
            let (rows, sq) = groups[k];
            let share_rows = rows as f64 / n.max(1) as f64;
            let share_squared_error = if total_sq > 0.0 { sq / total_sq } else { 0.0 };
            out.push(Region {
                channel: data.channel,
                dimension: dim.name,
                label: dim.names[k].clone(),
                rows,
                share_rows,
                share_squared_error,
                concentration: if share_rows > 0.0 {
                    share_squared_error / share_rows
                } else {
                    0.0
                },
                rms: (sq / rows.max(1) as f64).sqrt(),
            });
        }
    });
    out
}

/// Gives `dim` to `each`, if there is one.
fn each_of(each: &mut impl FnMut(Dimension), dim: Option<Dimension>) {
    if let Some(d) = dim {
        each(d);
    }
}

/// Regions ranked by excess share of the squared error (share of error minus share of rows).
pub fn rank(mut regions: Vec<Region>) -> Vec<Region> {
    regions.retain(|r| r.share_rows >= MIN_SHARE);
    regions.sort_by(|a, b| {
        (b.share_squared_error - b.share_rows).total_cmp(&(a.share_squared_error - a.share_rows))
    });
    regions
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Dataset;

    #[test]
    fn error_concentrated_at_large_slip_ranks_first() {
        let n = 300;
        let alpha: Vec<f64> = (0..n)
            .map(|i| (i as f64 / 10.0 - 15.0).to_radians())
            .collect();
        let ds = Dataset {
            run: (0..n).map(|i| (i / 100) as i64).collect(),
            fz: (0..n).map(|i| 2000.0 + (i % 3) as f64 * 1500.0).collect(),
            alpha: Some(alpha.clone().into()),
            fy: Some(vec![0.0; n].into()),
            time: Some((0..n).map(|i| (i % 100) as f64 * 0.01).collect()),
            ..Dataset::default()
        };
        let data = ChannelData::from_dataset(&ds, Channel::Fy).unwrap();
        // Residual 100 N beyond 6 deg, 10 N elsewhere.
        let res: Vec<f64> = alpha
            .iter()
            .map(|a| {
                if a.to_degrees().abs() >= 6.0 {
                    100.0
                } else {
                    10.0
                }
            })
            .collect();
        let ranked = rank(regions(&data, &res));
        assert_eq!(ranked[0].dimension, "slip angle");
        assert!(ranked[0].label.starts_with("saturated"), "{:?}", ranked[0]);
        assert!(ranked[0].concentration > 1.5);
        let shares: f64 = ranked
            .iter()
            .filter(|r| r.dimension == "slip angle")
            .map(|r| r.share_squared_error)
            .sum();
        assert!((shares - 1.0).abs() < 1e-12);
        // Load varies: three load regions with a third of the rows each.
        let load: Vec<&Region> = ranked.iter().filter(|r| r.dimension == "load").collect();
        assert_eq!(load.len(), 3);
        assert!(load.iter().all(|r| (r.share_rows - 1.0 / 3.0).abs() < 0.01));
    }
}
