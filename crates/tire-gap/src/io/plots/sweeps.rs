//! Measured against modelled, run by run: the worst sweeps of a channel, and the friction
//! circle on combined-slip rows.

use mf87::{Channel, units};
use plotters::prelude::*;

use super::View;
use super::draw::{
    Area, BASE, CAPTION_SIZE, DESC_SIZE, DrawResult, EXTENDED, FONT, LABEL_SIZE, MEASURED, Mark,
    entry, padded, span, svg, thinned, tick,
};
use crate::method::fit::channel_fit::per_run_mse;
use crate::method::prepare::channel_data::Column;

/// Most points per drawn line, and per set of markers.
const MAX_LINE_POINTS: usize = 4000;
const MAX_MARKERS: usize = 500;
/// Combined slip for the friction circle: |alpha| and |sigma| above these (deg, percent).
const COMBINED_ALPHA_DEG: f64 = 1.0;
const COMBINED_SIGMA_PCT: f64 = 2.0;

/// The `k` runs with the largest mean squared residual (finite rows only), largest first, with
/// that mean; ties go to the smaller run id.
pub fn worst_runs(run: &[i64], residuals: &[f64], k: usize) -> Vec<(i64, f64)> {
    let mut runs: Vec<(i64, f64)> = per_run_mse(run, residuals).into_iter().collect();
    runs.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    runs.truncate(k);
    runs
}

/// The rows of `run`, in time order when time is known (else in file order).
fn rows_of(v: &View, run: i64) -> Vec<usize> {
    let data = &v.data;
    let mut rows: Vec<usize> = (0..data.len()).filter(|&i| data.run[i] == run).collect();
    if let Some(t) = &data.time {
        rows.sort_by(|&a, &b| t[a].total_cmp(&t[b]));
    }
    rows
}

fn rms(rows: &[usize], residuals: &[f64]) -> f64 {
    let v: Vec<f64> = rows
        .iter()
        .map(|&i| residuals[i])
        .filter(|r| r.is_finite())
        .collect();
    (v.iter().map(|r| r * r).sum::<f64>() / v.len().max(1) as f64).sqrt()
}

fn mean(rows: &[usize], values: &[f64]) -> f64 {
    rows.iter().map(|&i| values[i]).sum::<f64>() / rows.len().max(1) as f64
}

/// The input a run sweeps, for its x axis.
struct Swept {
    label: &'static str,
    /// Per row of the channel.
    x: Column,
    /// Whether it is the other slip (e.g. Fy over a slip-ratio sweep at fixed slip angle).
    other: bool,
}

fn width(rows: &[usize], values: &[f64]) -> f64 {
    span(rows.iter().map(|&i| values[i])).map_or(0.0, |(lo, hi)| hi - lo)
}

/// The channel's own slip, unless the other slip varies more in this run relative to its range
/// over all rows.
fn swept(v: &View, rows: &[usize]) -> Swept {
    let data = &v.data;
    let own = Swept {
        label: v.slip_label(),
        x: data.slip.clone(),
        other: false,
    };
    let Some(other) = &data.other_slip else {
        return own;
    };
    let all: Vec<usize> = (0..data.len()).collect();
    let relative = |values: &[f64]| width(rows, values) / width(&all, values).max(1e-12);
    if relative(other) <= relative(&data.slip) {
        return own;
    }
    match data.channel {
        Channel::Fx => Swept {
            label: "slip angle alpha [deg]",
            x: other
                .iter()
                .map(|a| units::radians_to_degrees(*a))
                .collect(),
            other: true,
        },
        Channel::Fy | Channel::Mz => Swept {
            label: "slip ratio kappa [-]",
            x: other.clone(),
            other: true,
        },
    }
}

/// What the panel of one run says about its conditions.
fn run_caption(v: &View, run: i64, rows: &[usize], sw: &Swept) -> String {
    let data = &v.data;
    let mut s = format!(
        "run {run}: Fz {:.1} kN, camber {:.1} deg",
        mean(rows, &data.fz_kn),
        mean(rows, &data.gamma_deg)
    );
    let fx = data.channel == Channel::Fx;
    if sw.other {
        // The channel's own slip is (about) fixed in this run.
        let own = mean(rows, &data.slip);
        s += &if fx {
            format!(", sigma {own:.1} %")
        } else {
            format!(", alpha {own:.1} deg")
        };
    } else if let Some(other) = &data.other_slip {
        let most = rows.iter().map(|&i| other[i].abs()).fold(0.0, f64::max);
        if fx && units::radians_to_degrees(most) > 0.2 {
            s += &format!(", |alpha| up to {:.1} deg", units::radians_to_degrees(most));
        } else if !fx && most > 0.005 {
            s += &format!(", |kappa| up to {most:.2}");
        }
    }
    s += &format!("; RMS base {:.0}", rms(rows, &v.base));
    if !v.effects.is_empty() {
        s += &format!(", extended {:.0}", rms(rows, &v.last));
    }
    s + &format!(" {}", v.unit)
}

/// Measured, base and extended model against the swept slip on the `k` runs where the base
/// model's held-out residual is largest.
pub fn worst_sweeps(v: &View, k: usize) -> Result<String, String> {
    let runs = worst_runs(&v.data.run, &v.base, k);
    if runs.is_empty() {
        return Err("no finite held-out residual".into());
    }
    let mut legend = vec![
        entry("measured (line in time order)", MEASURED, Mark::LineDots),
        entry("base model (held-out)", BASE, Mark::Line),
    ];
    match v.extended_name() {
        Some(e) => legend.push(entry(format!("{e} (held-out)"), EXTENDED, Mark::Line)),
        None => legend.push(entry(
            format!("no effect selected for {}", v.name),
            WHITE,
            Mark::Empty,
        )),
    }
    let title = format!(
        "{}: the {} runs where the base model's held-out error is largest",
        v.name,
        runs.len()
    );
    let grid = if runs.len() == 1 {
        (1, 1)
    } else {
        (runs.len().div_ceil(2), 2)
    };
    let height = 190 + 470 * grid.0 as u32;
    svg((1500, height), &title, &legend, |area| {
        for (panel, (run, _)) in area.split_evenly(grid).iter().zip(&runs) {
            sweep_panel(panel, v, *run)?;
        }
        Ok(())
    })
}

fn sweep_panel(area: &Area, v: &View, run: i64) -> DrawResult {
    let rows = rows_of(v, run);
    let sw = swept(v, &rows);
    let line = thinned(&rows, MAX_LINE_POINTS);
    let series = |res: Option<&[f64]>| -> Vec<(f64, f64)> {
        line.iter()
            .map(|&i| (sw.x[i], v.data.measured[i] + res.map_or(0.0, |r| r[i])))
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect()
    };
    let measured = series(None);
    let base = series(Some(&v.base));
    let extended = (!v.effects.is_empty()).then(|| series(Some(&v.last)));
    let all = || {
        measured
            .iter()
            .chain(&base)
            .chain(extended.iter().flatten())
    };
    let (Some(xs), Some(ys)) = (span(all().map(|p| p.0)), span(all().map(|p| p.1))) else {
        return Ok(()); // nothing finite to draw in this run
    };
    let ((x0, x1), (y0, y1)) = (padded(xs, 0.03), padded(ys, 0.06));
    let mut chart = ChartBuilder::on(area)
        .caption(run_caption(v, run, &rows, &sw), (FONT, CAPTION_SIZE))
        .margin(14)
        .x_label_area_size(55)
        .y_label_area_size(85)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc(sw.label)
        .y_desc(v.value_label())
        .label_style((FONT, LABEL_SIZE))
        .axis_desc_style((FONT, DESC_SIZE))
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .x_labels(8)
        .y_labels(8)
        .draw()?;
    chart.draw_series(LineSeries::new(
        measured.iter().copied(),
        MEASURED.stroke_width(1),
    ))?;
    let markers = thinned(&(0..measured.len()).collect::<Vec<_>>(), MAX_MARKERS);
    chart.draw_series(
        markers
            .iter()
            .map(|&j| Circle::new(measured[j], 2, MEASURED.filled())),
    )?;
    // The extended line is wider and under the base line, so both show where they agree.
    if let Some(e) = extended {
        chart.draw_series(LineSeries::new(e, EXTENDED.stroke_width(4)))?;
    }
    chart.draw_series(LineSeries::new(base, BASE.stroke_width(2)))?;
    Ok(())
}

/// Fy against Fx where both slips are well away from zero: measured points, and the base and
/// extended models' held-out predictions as lines along each run.
pub fn friction_circle(fx: &View, fy: &View) -> Result<String, String> {
    let (x, y) = (fx, fy);
    let rows = combined_rows(x, y)?;
    let point = |i: usize, rx: Option<&[f64]>, ry: Option<&[f64]>| {
        (
            x.data.measured[i] + rx.map_or(0.0, |r| r[i]),
            y.data.measured[i] + ry.map_or(0.0, |r| r[i]),
        )
    };
    let segments = run_segments(&rows, &x.data.run);
    let lines = |rx: &[f64], ry: &[f64]| -> Vec<Vec<(f64, f64)>> {
        segments
            .iter()
            .map(|s| {
                s.iter()
                    .map(|&i| point(i, Some(rx), Some(ry)))
                    .filter(|p| p.0.is_finite() && p.1.is_finite())
                    .collect()
            })
            .collect()
    };
    let measured: Vec<(f64, f64)> = thinned(&rows, 3000)
        .into_iter()
        .map(|i| point(i, None, None))
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .collect();
    let base = lines(&x.base, &y.base);
    let extended_name = combined_extended_name(fx, fy);
    let extended = extended_name.is_some().then(|| lines(&x.last, &y.last));
    let mut legend = vec![
        entry("measured", MEASURED, Mark::Dots),
        entry("base model (held-out)", BASE, Mark::Line),
    ];
    match &extended_name {
        Some(e) => legend.push(entry(format!("{e} (held-out)"), EXTENDED, Mark::Line)),
        None => legend.push(entry("no effect selected for Fx or Fy", WHITE, Mark::Empty)),
    }
    let points = || {
        measured
            .iter()
            .chain(base.iter().flatten())
            .chain(extended.iter().flatten().flatten())
            .copied()
            .chain([(0.0, 0.0)])
    };
    // The data's box with the origin in it; equal scales are set when the plot size is known.
    let (Some(xs), Some(ys)) = (span(points().map(|p| p.0)), span(points().map(|p| p.1))) else {
        return Err("no finite force".into());
    };
    let (xs, ys) = (padded(xs, 0.05), padded(ys, 0.05));
    let title = format!(
        "Friction circle: Fy against Fx in combined slip (|alpha| > {COMBINED_ALPHA_DEG} deg, \
         |kappa| > {}), {} rows",
        COMBINED_SIGMA_PCT / 100.0,
        rows.len()
    );
    let lines = CircleLines {
        measured: &measured,
        base: &base,
        extended: extended.as_deref(),
    };
    svg((1100, 1120), &title, &legend, |area| {
        circle_panel(area, xs, ys, &lines)
    })
}

/// The rows in combined slip (both slips well away from zero); at least 10 are needed.
fn combined_rows(x: &View, y: &View) -> Result<Vec<usize>, String> {
    let n = x.data.len();
    if y.data.len() != n {
        return Err("Fx and Fy hold different rows".into());
    }
    let rows: Vec<usize> = (0..n)
        .filter(|&i| {
            y.data.slip[i].abs() > COMBINED_ALPHA_DEG && x.data.slip[i].abs() > COMBINED_SIGMA_PCT
        })
        .collect();
    if rows.len() < 10 {
        return Err(format!(
            "{} rows with |alpha| > {COMBINED_ALPHA_DEG} deg and |kappa| > {}; at least 10 needed",
            rows.len(),
            COMBINED_SIGMA_PCT / 100.0
        ));
    }
    Ok(rows)
}

/// `rows` cut into runs of consecutive rows in one run: each model line is drawn along
/// one of these.
fn run_segments(rows: &[usize], run: &[i64]) -> Vec<Vec<usize>> {
    let mut segments: Vec<Vec<usize>> = Vec::new();
    for &i in rows {
        match segments.last_mut() {
            Some(s) if s.last().is_some_and(|&j| j + 1 == i && run[j] == run[i]) => s.push(i),
            _ => segments.push(vec![i]),
        }
    }
    segments
}

/// The extended model's name in the friction circle: the effects selected for Fx and Fy,
/// named per channel when they differ; `None` when neither has one.
fn combined_extended_name(fx: &View, fy: &View) -> Option<String> {
    match (fx.extended_name(), fy.extended_name()) {
        (None, None) => None,
        (a, b) if a == b => a,
        (a, b) => Some(format!(
            "extended (Fx: {}; Fy: {})",
            a.unwrap_or("base".into()),
            b.unwrap_or("base".into())
        )),
    }
}

/// What the friction circle draws: measured points and the models' lines along each run.
struct CircleLines<'a> {
    measured: &'a [(f64, f64)],
    base: &'a [Vec<(f64, f64)>],
    extended: Option<&'a [Vec<(f64, f64)>]>,
}

/// The friction circle's chart over the box `xs` by `ys`, widened to equal scales.
fn circle_panel(area: &Area, xs: (f64, f64), ys: (f64, f64), lines: &CircleLines) -> DrawResult {
    // Equal scales on both axes: widen the narrower range about its middle.
    let (w, h) = area.dim_in_pixel();
    let (pw, ph) = (w as f64 - 2.0 * 14.0 - 95.0, h as f64 - 2.0 * 14.0 - 60.0);
    let per_px = ((xs.1 - xs.0) / pw).max((ys.1 - ys.0) / ph);
    let widen = |(lo, hi): (f64, f64), px: f64| {
        let (mid, half) = (0.5 * (lo + hi), 0.5 * per_px * px);
        (mid - half, mid + half)
    };
    let ((x0, x1), (y0, y1)) = (widen(xs, pw), widen(ys, ph));
    let mut chart = ChartBuilder::on(area)
        .margin(14)
        .x_label_area_size(60)
        .y_label_area_size(95)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc("longitudinal force Fx [N]")
        .y_desc("lateral force Fy [N]")
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style((FONT, LABEL_SIZE))
        .axis_desc_style((FONT, DESC_SIZE))
        .draw()?;
    chart.draw_series(
        lines
            .measured
            .iter()
            .map(|p| Circle::new(*p, 2, MEASURED.mix(0.6).filled())),
    )?;
    for s in lines.extended.iter().copied().flatten() {
        chart.draw_series(LineSeries::new(s.iter().copied(), EXTENDED.stroke_width(2)))?;
    }
    for s in lines.base {
        chart.draw_series(LineSeries::new(s.iter().copied(), BASE.stroke_width(2)))?;
    }
    Ok(())
}
