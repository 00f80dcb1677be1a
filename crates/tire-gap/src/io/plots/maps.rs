//! Residual heat maps: the mean held-out residual over slip and load, one panel for the base
//! model and one for the final model, on one diverging colour scale.

use plotters::prelude::*;

use super::View;
use super::bins::{binned_means_2d, edges};
use super::draw::{
    Area, CAPTION_SIZE, DESC_SIZE, DrawResult, FONT, LABEL_SIZE, Mark, diverging, entry, padded,
    svg, tick,
};
use crate::quantiles::quantile;

const SLIP_BINS: usize = 24;
const LOAD_BINS: usize = 8;
/// Cells with fewer rows are left blank.
pub const MIN_CELL_ROWS: usize = 10;

struct Panel {
    caption: String,
    /// `cells[ix][iy]`: rows and mean residual.
    cells: Vec<Vec<(usize, f64)>>,
}

/// The heat map of one channel, or why it cannot be drawn.
pub fn residual_map(v: &View) -> Result<String, String> {
    let data = &v.data;
    let (Some(s0), Some(s1)) = (quantile(&data.slip, 0.005), quantile(&data.slip, 0.995)) else {
        return Err("no finite slip".into());
    };
    let (Some(f0), Some(f1)) = (quantile(&data.fz_kn, 0.0), quantile(&data.fz_kn, 1.0)) else {
        return Err("no finite load".into());
    };
    if s1 - s0 <= 1e-9 {
        return Err(format!("the {} does not vary", v.slip_name()));
    }
    let x_edges = edges(s0, s1, SLIP_BINS);
    let y_edges = if f1 - f0 > 1e-6 {
        edges(f0, f1, LOAD_BINS)
    } else {
        let (lo, hi) = padded((f0, f1), 0.0);
        edges(lo, hi, 1)
    };
    let grid = |res: &[f64]| binned_means_2d(&data.slip, &data.fz_kn, res, &x_edges, &y_edges);
    let mut panels = vec![Panel {
        caption: "base model".into(),
        cells: grid(&v.base),
    }];
    if let Some(e) = v.extended_name() {
        panels.push(Panel {
            caption: e,
            cells: grid(&v.last),
        });
    }
    let limit = panels
        .iter()
        .flat_map(|p| p.cells.iter().flatten())
        .filter(|c| c.0 >= MIN_CELL_ROWS)
        .map(|c| c.1.abs())
        .fold(0.0, f64::max);
    if limit <= 0.0 || !limit.is_finite() {
        return Err(format!("no cell with at least {MIN_CELL_ROWS} rows"));
    }
    let legend = [
        entry("model above measurement", diverging(0.8), Mark::Bar),
        entry("model below measurement", diverging(-0.8), Mark::Bar),
        entry(
            format!("blank: fewer than {MIN_CELL_ROWS} rows"),
            RGBColor(150, 150, 150),
            Mark::Empty,
        ),
    ];
    let title = format!(
        "{}: mean held-out residual over {} and load",
        v.name,
        v.slip_name()
    );
    let width = 260 + 620 * panels.len() as u32;
    svg((width, 760), &title, &legend, |area| {
        let (w, _) = area.dim_in_pixel();
        let (left, bar) = area.split_horizontally(w - 190);
        for (p, a) in panels.iter().zip(left.split_evenly((1, panels.len()))) {
            panel(&a, v, p, &x_edges, &y_edges, limit)?;
        }
        colour_bar(&bar, v, limit)
    })
}

fn panel(
    area: &Area,
    v: &View,
    p: &Panel,
    x_edges: &[f64],
    y_edges: &[f64],
    limit: f64,
) -> DrawResult {
    let (x0, x1) = (x_edges[0], x_edges[x_edges.len() - 1]);
    let (y0, y1) = (y_edges[0], y_edges[y_edges.len() - 1]);
    let mut chart = ChartBuilder::on(area)
        .caption(&p.caption, (FONT, CAPTION_SIZE))
        .margin(14)
        .x_label_area_size(60)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(v.slip_label())
        .y_desc("vertical load Fz [kN]")
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style((FONT, LABEL_SIZE))
        .axis_desc_style((FONT, DESC_SIZE))
        .draw()?;
    let mut cells = Vec::new();
    for (ix, col) in p.cells.iter().enumerate() {
        for (iy, &(n, mean)) in col.iter().enumerate() {
            if n >= MIN_CELL_ROWS {
                cells.push(Rectangle::new(
                    [
                        (x_edges[ix], y_edges[iy]),
                        (x_edges[ix + 1], y_edges[iy + 1]),
                    ],
                    diverging(mean / limit).filled(),
                ));
            }
        }
    }
    chart.draw_series(cells)?;
    // A frame around the map (blank cells are white).
    chart.draw_series(std::iter::once(Rectangle::new(
        [(x0, y0), (x1, y1)],
        RGBColor(150, 150, 150).stroke_width(1),
    )))?;
    Ok(())
}

fn colour_bar(area: &Area, v: &View, limit: f64) -> DrawResult {
    const STEPS: usize = 100;
    let mut chart = ChartBuilder::on(area)
        .caption(format!("[{}]", v.unit), (FONT, CAPTION_SIZE))
        .margin(14)
        .margin_left(10)
        .x_label_area_size(60)
        .right_y_label_area_size(110)
        .build_cartesian_2d(0.0..1.0, -limit..limit)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(v.residual_label())
        .label_style((FONT, LABEL_SIZE))
        .axis_desc_style((FONT, DESC_SIZE))
        .y_labels(9)
        .y_label_formatter(&tick)
        .draw()?;
    let step = 2.0 * limit / STEPS as f64;
    chart.draw_series((0..STEPS).map(|k| {
        let lo = -limit + k as f64 * step;
        Rectangle::new(
            [(0.0, lo), (1.0, lo + step)],
            diverging((lo + 0.5 * step) / limit).filled(),
        )
    }))?;
    Ok(())
}
