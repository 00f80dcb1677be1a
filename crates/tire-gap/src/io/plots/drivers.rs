//! The residual binned over the input that drives a candidate effect, before and after the
//! effect is added: a candidate that explains the gap flattens the curve.

use plotters::prelude::*;

use super::View;
use super::bins::{Bin, binned_means, edges};
use super::draw::{
    Area, BASE, DESC_SIZE, DrawResult, EXTENDED, FONT, LABEL_SIZE, Mark, entry, padded, span, svg,
    tick,
};
use crate::method::fit::effects::{self, Extension};
use crate::quantiles::quantile;

const BINS: usize = 16;
/// Bins with fewer rows are not drawn.
const MIN_BIN_ROWS: usize = 20;

/// Bins with enough rows to show.
fn shown(x: &[f64], residuals: &[f64], edges: &[f64]) -> Vec<Bin> {
    binned_means(x, residuals, edges)
        .into_iter()
        .filter(|b| b.count >= MIN_BIN_ROWS && b.std_err.is_finite())
        .collect()
}

/// Binned residual against the driving input of `effect`: the base model's and, from
/// `residuals`, the base model plus that candidate's.
pub fn plot(v: &View, effect: Extension, residuals: &[f64]) -> Result<String, String> {
    let data = &v.data;
    if residuals.len() != data.len() {
        return Err("the candidate's residuals do not match the rows".into());
    }
    let drv = effects::of(effect).row_driver(data)?;
    let (lo, hi) = match drv.range {
        Some(r) => r,
        None => match (quantile(&drv.x, 0.005), quantile(&drv.x, 0.995)) {
            (Some(lo), Some(hi)) => (lo, hi),
            _ => return Err("the driving input has no finite value".into()),
        },
    };
    if hi - lo <= 1e-9 * lo.abs().max(hi.abs()).max(1.0) {
        return Err(format!("{} does not vary", drv.axis));
    }
    let e = edges(lo, hi, BINS);
    let before = shown(&drv.x, &v.base, &e);
    let after = shown(&drv.x, residuals, &e);
    if before.len() < 2 {
        return Err(format!(
            "fewer than two bins of {} with {MIN_BIN_ROWS} rows",
            drv.axis
        ));
    }
    let id = effect.name();
    let selected = if v.effects.contains(&effect) {
        "selected"
    } else {
        "not selected"
    };
    let title = format!(
        "{}: held-out residual against {}, without and with {id} ({selected})",
        v.name,
        drv.axis.split(" [").next().unwrap_or(&drv.axis)
    );
    let legend = [
        entry("base model: bin mean +- 1 standard error", BASE, Mark::Band),
        entry(
            format!("base + {id} (first round): bin mean +- 1 standard error"),
            EXTENDED,
            Mark::Band,
        ),
    ];
    let ys = span(
        before
            .iter()
            .chain(&after)
            .flat_map(|b| [b.mean - b.std_err, b.mean + b.std_err])
            .chain([0.0]),
    )
    .unwrap_or((-1.0, 1.0));
    // The x axis spans the bins drawn.
    let xs = span(before.iter().chain(&after).flat_map(|b| [b.lo, b.hi])).unwrap_or((lo, hi));
    let (xs, ys) = (padded(xs, 0.02), padded(ys, 0.08));
    let axes = (drv.axis.as_str(), format!("mean {}", v.residual_label()));
    svg((1200, 820), &title, &legend, |area| {
        bins_panel(area, (xs, ys), axes, &before, &after)
    })
}

/// The chart of the binned residual over the ranges `xs`, `ys` with the axis labels
/// `axes`: the bands and lines of the base model's bins (`before`) and the candidate's.
fn bins_panel(
    area: &Area,
    ((x0, x1), (y0, y1)): ((f64, f64), (f64, f64)),
    (x_desc, y_desc): (&str, String),
    before: &[Bin],
    after: &[Bin],
) -> DrawResult {
    let mut chart = ChartBuilder::on(area)
        .margin(16)
        .x_label_area_size(60)
        .y_label_area_size(95)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style((FONT, LABEL_SIZE))
        .axis_desc_style((FONT, DESC_SIZE))
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .draw()?;
    chart.draw_series(LineSeries::new(
        [(x0, 0.0), (x1, 0.0)],
        BLACK.mix(0.6).stroke_width(1),
    ))?;
    for (bins, color) in [(before, BASE), (after, EXTENDED)] {
        let upper = bins.iter().map(|b| (b.x_mean, b.mean + b.std_err));
        let lower = bins.iter().rev().map(|b| (b.x_mean, b.mean - b.std_err));
        chart.draw_series(std::iter::once(Polygon::new(
            upper.chain(lower).collect::<Vec<_>>(),
            color.mix(0.2).filled(),
        )))?;
    }
    // The base line wider and under the candidate's, so both show where they agree.
    for (bins, color, width, dot) in [(before, BASE, 5, 5), (after, EXTENDED, 2, 3)] {
        chart.draw_series(LineSeries::new(
            bins.iter().map(|b| (b.x_mean, b.mean)),
            color.stroke_width(width),
        ))?;
        chart.draw_series(
            bins.iter()
                .map(|b| Circle::new((b.x_mean, b.mean), dot, color.filled())),
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use mf87::Channel;

    use super::*;
    use crate::data::Dataset;
    use crate::method::prepare::channel_data::ChannelData;

    #[test]
    fn slip_rate_is_a_central_difference_within_runs() {
        // Run 1: alpha 0, 1, 3 deg at 0, 0.1, 0.2 s; run 2: one row.
        let ds = Dataset {
            run: vec![1, 1, 1, 2].into(),
            fz: vec![4000.0; 4].into(),
            alpha: Some([0.0f64, 1.0, 3.0, 5.0].map(f64::to_radians).to_vec().into()),
            fy: Some(vec![0.0; 4].into()),
            time: Some(vec![0.0, 0.1, 0.2, 0.0].into()),
            ..Dataset::default()
        };
        let data = ChannelData::from_dataset(&ds, Channel::Fy).unwrap();
        let rate = data.slip_rate().unwrap();
        let want = [10.0, 15.0, 20.0, 0.0];
        for (r, w) in rate.iter().zip(want) {
            assert!((r - w).abs() < 1e-9, "{rate:?}");
        }
        let no_time = ChannelData { time: None, ..data };
        let driver = |e| effects::of(e).row_driver(&no_time);
        assert!(driver(Extension::RelaxationLength).is_err());
        let near_zero = driver(Extension::PlySteerConicity).unwrap();
        assert_eq!(near_zero.x[1], 1.0);
        assert!(near_zero.x[2].is_nan(), "3 deg is not near zero");
    }
}
