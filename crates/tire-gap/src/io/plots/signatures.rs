//! Where each claim's held-out gain lies: per claim and channel, its gain per row where its
//! driver acts beside its gain per row where the driver is idle, and the same for the
//! candidates refused for their signature (their gain lies where their driver is idle).

use mf87::Channel;
use plotters::prelude::*;

use super::draw::{
    DESC_SIZE, ERROR, FONT, LABEL_SIZE, Mark, ROWS, entry, left_text, right_text, short, svg,
};
use crate::method::diagnose::Diagnosis;
use crate::method::diagnose::signature::SignatureTest;

/// Width of the label column [px].
const LABEL_WIDTH: u32 = 520;

/// One line of the chart: what it is and its split gain.
struct Row<'a> {
    label: String,
    channel: Channel,
    test: &'a SignatureTest,
}

/// The chart of `d`'s claims and signature refusals.
pub fn chart(d: &Diagnosis) -> Result<String, String> {
    let rows = rows_of(d);
    if rows.is_empty() {
        return Err("no claim or signature refusal with a tested signature".into());
    }
    draw(&rows)
}

/// The lines of the chart: each claimed channel, then each signature refusal, with a tested
/// signature.
fn rows_of(d: &Diagnosis) -> Vec<Row<'_>> {
    let mut rows: Vec<Row> = Vec::new();
    for c in &d.claims {
        let with = c
            .with
            .map_or(String::new(), |w| format!(" (over {w} alone)"));
        for ch in &c.channels {
            rows.push(Row {
                label: format!("claimed: {} {}{with}", c.effect, ch.channel),
                channel: ch.channel,
                test: &ch.signature,
            });
        }
    }
    for r in &d.signature_refusals {
        rows.push(Row {
            label: format!("refused: {} {} (round {})", r.effect, r.channel, r.round),
            channel: r.channel,
            test: &r.signature,
        });
    }
    rows.into_iter()
        .filter(|r| r.test.not_testable.is_none())
        .collect()
}

/// The chart of `rows`, one line each.
fn draw(rows: &[Row]) -> Result<String, String> {
    let n = rows.len();
    let title =
        "Where each claim's held-out gain lies: per row where its driver acts and where it is idle";
    let legend = [
        entry("gain per row where the driver acts", ERROR, Mark::Bar),
        entry("gain per row where the driver is idle", ROWS, Mark::Bar),
    ];
    let height = 200 + 48 * n as u32;
    svg((1500, height), title, &legend, |area| {
        let mut chart = ChartBuilder::on(area)
            .margin(16)
            .margin_right(30)
            .x_label_area_size(60)
            .y_label_area_size(LABEL_WIDTH)
            .build_cartesian_2d(-0.3..1.45, 0.0..n as f64)?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .disable_y_axis()
            .x_desc("gain per row, as a share of the larger of the two (each line its own scale)")
            .x_label_formatter(&|v| match (0.0..=1.0).contains(v) {
                true => format!("{v:.1}"),
                false => String::new(),
            })
            .label_style((FONT, LABEL_SIZE))
            .axis_desc_style((FONT, DESC_SIZE))
            .draw()?;
        let base = area.get_base_pixel();
        for (k, r) in rows.iter().enumerate() {
            let y = (n - k) as f64 - 0.5;
            let t = r.test;
            let scale = t.gain_per_row_active.abs().max(t.gain_per_row_idle.abs());
            let share = |g: f64| {
                if scale > 0.0 {
                    (g / scale).clamp(-0.3, 1.0)
                } else {
                    0.0
                }
            };
            let (act, idle) = (share(t.gain_per_row_active), share(t.gain_per_row_idle));
            chart.draw_series([
                Rectangle::new([(0.0, y + 0.03), (act, y + 0.36)], ERROR.filled()),
                Rectangle::new([(0.0, y - 0.36), (idle, y - 0.03)], ROWS.filled()),
            ])?;
            let at = |p: (f64, f64)| {
                let c = chart.backend_coord(&p);
                (c.0 - base.0, c.1 - base.1)
            };
            let (lx, ly) = at((-0.3, y));
            let p = t
                .p_value
                .map_or("not tested".into(), |p| format!("p={p:.1e}"));
            area.draw(&Text::new(
                format!("{} ({p})", r.label),
                (lx - 10, ly),
                right_text(LABEL_SIZE),
            ))?;
            let unit = if r.channel == Channel::Mz {
                "(N.m)^2"
            } else {
                "N^2"
            };
            for (value, rows_n, bar, dy) in [
                (t.gain_per_row_active, t.active_rows, act, 0.2),
                (t.gain_per_row_idle, t.idle_rows, idle, -0.2),
            ] {
                let (x, yy) = at((bar.max(0.0), y + dy));
                area.draw(&Text::new(
                    format!("{} {unit} a row, {rows_n} rows", short(value)),
                    (x + 6, yy),
                    left_text(LABEL_SIZE - 2.0),
                ))?;
            }
        }
        Ok(())
    })
}
