//! Shared drawing pieces: palette, the frame of every figure (title and a legend strip above
//! the plot, so no legend hides data), ranges and a diverging colour scale.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

pub type DrawResult<T = ()> = Result<T, Box<dyn std::error::Error>>;
pub type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

pub const FONT: &str = "sans-serif";
pub const TITLE_SIZE: f64 = 26.0;
pub const CAPTION_SIZE: f64 = 18.0;
pub const LABEL_SIZE: f64 = 16.0;
pub const DESC_SIZE: f64 = 18.0;

pub const MEASURED: RGBColor = RGBColor(40, 40, 40);
pub const BASE: RGBColor = RGBColor(230, 97, 1);
pub const EXTENDED: RGBColor = RGBColor(31, 120, 180);
pub const ROWS: RGBColor = RGBColor(170, 170, 170);
pub const ERROR: RGBColor = RGBColor(178, 24, 43);

/// How a legend entry shows its series.
#[derive(Debug, Clone, Copy)]
pub enum Mark {
    Line,
    LineDots,
    Dots,
    /// A line inside a translucent band.
    Band,
    Bar,
    /// An empty box: cells without enough rows.
    Empty,
}

#[derive(Debug, Clone)]
pub struct LegendEntry {
    pub label: String,
    pub color: RGBColor,
    pub mark: Mark,
}

pub fn entry(label: impl Into<String>, color: RGBColor, mark: Mark) -> LegendEntry {
    LegendEntry {
        label: label.into(),
        color,
        mark,
    }
}

const LEGEND_ROW: i32 = 26;
const SAMPLE: i32 = 28;

/// An SVG of `size` pixels: white, `title` on top, the legend strip under it, and `body`
/// drawing into the rest.
pub fn svg(
    size: (u32, u32),
    title: &str,
    legend: &[LegendEntry],
    body: impl FnOnce(&Area) -> DrawResult,
) -> Result<String, String> {
    let mut out = String::new();
    frame(&mut out, size, title, legend, body).map_err(|e| format!("drawing failed: {e}"))?;
    Ok(out)
}

fn frame(
    out: &mut String,
    size: (u32, u32),
    title: &str,
    legend: &[LegendEntry],
    body: impl FnOnce(&Area) -> DrawResult,
) -> DrawResult {
    let root = SVGBackend::with_string(out, size).into_drawing_area();
    root.fill(&WHITE)?;
    let area = root.titled(title, (FONT, TITLE_SIZE))?;
    let rows = legend_layout(&area, legend)?;
    let height = rows.iter().map(|r| r.1).max().map_or(0, |r| r + 1) * LEGEND_ROW + 6;
    let (strip, rest) = area.split_vertically(height);
    for ((x, row), e) in rows.iter().zip(legend) {
        legend_item(&strip, *x, row * LEGEND_ROW + LEGEND_ROW / 2, e)?;
    }
    body(&rest)?;
    root.present()?;
    Ok(())
}

fn text_style(size: f64) -> TextStyle<'static> {
    TextStyle::from((FONT, size).into_font()).color(&BLACK)
}

/// Left-aligned, vertically centred text.
pub fn left_text(size: f64) -> TextStyle<'static> {
    text_style(size).pos(Pos::new(HPos::Left, VPos::Center))
}

/// Right-aligned, vertically centred text.
pub fn right_text(size: f64) -> TextStyle<'static> {
    text_style(size).pos(Pos::new(HPos::Right, VPos::Center))
}

/// (x, row) of each legend entry, wrapping to a new row when the strip is full.
fn legend_layout(area: &Area, legend: &[LegendEntry]) -> DrawResult<Vec<(i32, i32)>> {
    let width = area.dim_in_pixel().0 as i32;
    let (mut x, mut row) = (20, 0);
    let mut out = Vec::new();
    for e in legend {
        let w = SAMPLE
            + 8
            + area
                .estimate_text_size(&e.label, &text_style(LABEL_SIZE))?
                .0 as i32;
        if x > 20 && x + w > width - 20 {
            (x, row) = (20, row + 1);
        }
        out.push((x, row));
        x += w + 30;
    }
    Ok(out)
}

fn legend_item(area: &Area, x: i32, y: i32, e: &LegendEntry) -> DrawResult {
    let c = e.color;
    let line = |w| PathElement::new(vec![(x, y), (x + SAMPLE, y)], c.stroke_width(w));
    match e.mark {
        Mark::Line => area.draw(&line(3))?,
        Mark::LineDots => {
            area.draw(&line(1))?;
            for dx in [6, 14, 22] {
                area.draw(&Circle::new((x + dx, y), 3, c.filled()))?;
            }
        }
        Mark::Dots => {
            for dx in [6, 14, 22] {
                area.draw(&Circle::new((x + dx, y), 3, c.filled()))?;
            }
        }
        Mark::Band => {
            area.draw(&Rectangle::new(
                [(x, y - 7), (x + SAMPLE, y + 7)],
                c.mix(0.25).filled(),
            ))?;
            area.draw(&line(2))?;
        }
        Mark::Bar => area.draw(&Rectangle::new(
            [(x, y - 7), (x + SAMPLE, y + 7)],
            c.filled(),
        ))?,
        Mark::Empty => area.draw(&Rectangle::new(
            [(x, y - 7), (x + SAMPLE, y + 7)],
            c.stroke_width(1),
        ))?,
    }
    area.draw(&Text::new(
        e.label.clone(),
        (x + SAMPLE + 8, y),
        left_text(LABEL_SIZE),
    ))?;
    Ok(())
}

/// Smallest and largest finite value.
pub fn span(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
}

/// `(lo, hi)` widened by `frac` of its width on each side, and never empty.
pub fn padded((lo, hi): (f64, f64), frac: f64) -> (f64, f64) {
    let w = hi - lo;
    if w > 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
        (lo - frac * w, hi + frac * w)
    } else {
        let d = 0.5 * lo.abs().max(1.0);
        (lo - d, hi + d)
    }
}

/// Diverging blue-white-red scale: `t` in [-1, 1], clamped; 0 is near-white.
pub fn diverging(t: f64) -> RGBColor {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (-1.0, [33.0, 102.0, 172.0]),
        (-0.5, [146.0, 197.0, 222.0]),
        (0.0, [247.0, 247.0, 247.0]),
        (0.5, [244.0, 165.0, 130.0]),
        (1.0, [178.0, 24.0, 43.0]),
    ];
    let t = if t.is_finite() {
        t.clamp(-1.0, 1.0)
    } else {
        0.0
    };
    let k = STOPS
        .windows(2)
        .position(|w| t <= w[1].0)
        .unwrap_or(STOPS.len() - 2);
    let ((t0, a), (t1, b)) = (STOPS[k], STOPS[k + 1]);
    let f = (t - t0) / (t1 - t0);
    let mix = |i: usize| (a[i] + f * (b[i] - a[i])).round() as u8;
    RGBColor(mix(0), mix(1), mix(2))
}

/// Every `len / max`-th index (all of them when there are at most `max`).
pub fn thinned(indices: &[usize], max: usize) -> Vec<usize> {
    let step = indices.len().div_ceil(max.max(1)).max(1);
    indices.iter().copied().step_by(step).collect()
}

/// An axis tick: no trailing zeros ("6000", "0.25"), and no "-0".
pub fn tick(v: &f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// A number with about three significant digits, for labels.
pub fn short(v: f64) -> String {
    let a = v.abs();
    if a >= 100.0 || a == 0.0 {
        format!("{v:.0}")
    } else if a >= 10.0 {
        format!("{v:.1}")
    } else if a >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diverging_scale_ends_and_middle() {
        assert_eq!(diverging(-1.0), RGBColor(33, 102, 172));
        assert_eq!(diverging(0.0), RGBColor(247, 247, 247));
        assert_eq!(diverging(1.0), RGBColor(178, 24, 43));
        assert_eq!(diverging(7.0), RGBColor(178, 24, 43));
        assert_eq!(diverging(f64::NAN), RGBColor(247, 247, 247));
        // Halfway between white and the light red stop.
        assert_eq!(diverging(0.25), RGBColor(246, 206, 189));
    }

    #[test]
    fn padded_never_returns_an_empty_range() {
        assert_eq!(padded((0.0, 10.0), 0.1), (-1.0, 11.0));
        let (lo, hi) = padded((5.0, 5.0), 0.1);
        assert!(lo < 5.0 && hi > 5.0);
        assert_eq!(span([3.0, f64::NAN, -2.0]), Some((-2.0, 3.0)));
        assert_eq!(span([f64::NAN]), None);
    }

    #[test]
    fn ticks_drop_trailing_zeros() {
        assert_eq!(tick(&6000.0), "6000");
        assert_eq!(tick(&0.25), "0.25");
        assert_eq!(tick(&(0.1 + 0.2)), "0.3");
        assert_eq!(tick(&-0.0), "0");
        assert_eq!(tick(&-2.5), "-2.5");
    }

    #[test]
    fn thinning_keeps_at_most_max() {
        let idx: Vec<usize> = (0..1001).collect();
        let t = thinned(&idx, 100);
        assert!(t.len() <= 100 && t.len() >= 50, "{}", t.len());
        assert_eq!(t[0], 0);
        assert_eq!(thinned(&idx[..10], 100).len(), 10);
    }
}
