//! The region ranking as a horizontal bar chart: per region, its share of the channel's
//! squared held-out error beside its share of the rows.

use mf87::Channel;
use plotters::prelude::*;

use super::draw::{
    DESC_SIZE, ERROR, FONT, LABEL_SIZE, Mark, ROWS, entry, left_text, right_text, short, svg, tick,
};
use crate::method::diagnose::regions::Region;

/// Width of the label column [px].
const LABEL_WIDTH: u32 = 470;

fn label(r: &Region) -> String {
    format!("{} {}: {}", r.channel, r.dimension, r.label)
}

/// The first `top` of the ranked `regions`.
pub fn chart(regions: &[Region], top: usize) -> Result<String, String> {
    let shown = &regions[..regions.len().min(top)];
    if shown.is_empty() {
        return Err("no region ranked".into());
    }
    let n = shown.len();
    let title = format!("Where the base model's held-out error lies: the top {n} regions");
    let legend = [
        entry("share of the channel's squared error", ERROR, Mark::Bar),
        entry("share of the channel's rows", ROWS, Mark::Bar),
    ];
    let most = shown
        .iter()
        .map(|r| r.share_squared_error.max(r.share_rows))
        .fold(0.0, f64::max);
    // Room on the right for the value labels.
    let x_max = (100.0 * most * 1.3).clamp(10.0, 130.0);
    let height = 200 + 48 * n as u32;
    svg((1500, height), &title, &legend, |area| {
        let mut chart = ChartBuilder::on(area)
            .margin(16)
            .margin_right(30)
            .x_label_area_size(60)
            .y_label_area_size(LABEL_WIDTH)
            .build_cartesian_2d(0.0..x_max, 0.0..n as f64)?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .disable_y_axis()
            .x_desc("share [%]")
            // Shares stop at 100 %; the axis runs on only to make room for the values.
            .x_label_formatter(&|v| if *v <= 100.0 { tick(v) } else { String::new() })
            .label_style((FONT, LABEL_SIZE))
            .axis_desc_style((FONT, DESC_SIZE))
            .draw()?;
        let base = area.get_base_pixel();
        for (k, r) in shown.iter().enumerate() {
            // The first region on top.
            let y = (n - k) as f64 - 0.5;
            let (err, rows) = (100.0 * r.share_squared_error, 100.0 * r.share_rows);
            chart.draw_series([
                Rectangle::new([(0.0, y + 0.03), (err, y + 0.36)], ERROR.filled()),
                Rectangle::new([(0.0, y - 0.36), (rows, y - 0.03)], ROWS.filled()),
            ])?;
            let at = |p: (f64, f64)| {
                let c = chart.backend_coord(&p);
                (c.0 - base.0, c.1 - base.1)
            };
            let (lx, ly) = at((0.0, y));
            area.draw(&Text::new(label(r), (lx - 10, ly), right_text(LABEL_SIZE)))?;
            let unit = if r.channel == Channel::Mz { "N.m" } else { "N" };
            area.draw(&Text::new(
                format!("{err:.0} % of error, RMS {} {unit}", short(r.rms)),
                {
                    let (x, y) = at((err, y + 0.2));
                    (x + 6, y)
                },
                left_text(LABEL_SIZE - 2.0),
            ))?;
            area.draw(&Text::new(
                format!("{rows:.0} % of rows ({})", r.rows),
                {
                    let (x, y) = at((rows, y - 0.2));
                    (x + 6, y)
                },
                left_text(LABEL_SIZE - 2.0),
            ))?;
        }
        Ok(())
    })
}
