//! `diagnose --plots DIR`: SVG figures of a diagnosis and an `index.html` listing them.
//!
//! Figures (file names are stable):
//! - `regions.svg`: the ranked regions, share of squared error against share of rows;
//! - `worst_sweeps_<ch>.svg`: measured, base and extended model over slip on the runs where
//!   the base model does worst;
//! - `residual_map_<ch>.svg`: mean residual over slip and load, base and final model;
//! - `driver_<effect>_<ch>.svg`: binned residual against each top candidate's driving input,
//!   before and after adding it;
//! - `friction_circle.svg`: Fy against Fx on combined-slip rows;
//! - `signatures.svg`: each claim's held-out gain per row where its driver acts and where it
//!   is idle, and the same for the candidates refused for it.
//!
//! All residuals are held-out and shown as model minus measurement. Figures that lack data
//! are skipped with a note; nothing here panics on odd data.

mod bins;
mod draw;
mod drivers;
mod maps;
mod ranking;
mod signatures;
mod sweeps;

use std::path::Path;

use mf87::Channel;

use crate::io::output::{Failure, check_dir_target, output_failure, write_whole};
use crate::method::diagnose::Diagnosis;
use crate::method::fit::effects::{self, Extension};
use crate::method::prepare::channel_data::ChannelData;
use crate::method::stats::CompactResiduals;

/// Regions shown in `regions.svg`.
const TOP_REGIONS: usize = 15;
/// Runs shown per channel in `worst_sweeps_<ch>.svg`.
const WORST_RUNS: usize = 4;

/// One rendered figure.
#[derive(Debug, Clone)]
pub struct Figure {
    pub file: String,
    pub caption: String,
    pub svg: String,
}

/// The figures of a diagnosis, and a note for each one that could not be drawn.
#[derive(Debug, Clone, Default)]
pub struct Figures {
    pub figures: Vec<Figure>,
    pub skipped: Vec<String>,
}

impl Figures {
    fn add(&mut self, file: String, caption: String, svg: Result<String, String>) {
        match svg {
            Ok(svg) => self.figures.push(Figure { file, caption, svg }),
            Err(why) => self.skipped.push(format!("{file} skipped: {why}")),
        }
    }
}

/// One channel's rows and held-out residuals as the figures use them.
struct View<'a> {
    data: &'a ChannelData,
    name: &'static str,
    unit: &'static str,
    /// Effects in the final model of this channel, in the order selected.
    effects: Vec<Extension>,
    /// Held-out residuals, model minus measurement: of the base model, the final model and
    /// each top first-round candidate. A model's prediction is measured + residual.
    base: Vec<f64>,
    last: Vec<f64>,
    candidates: Vec<(Extension, Vec<f64>)>,
}

impl View<'_> {
    fn slip_label(&self) -> &'static str {
        match self.data.channel {
            Channel::Fx => "slip ratio sigma [%]",
            Channel::Fy | Channel::Mz => "slip angle alpha [deg]",
        }
    }

    fn slip_name(&self) -> &'static str {
        match self.data.channel {
            Channel::Fx => "slip ratio",
            Channel::Fy | Channel::Mz => "slip angle",
        }
    }

    fn value_label(&self) -> String {
        let what = match self.data.channel {
            Channel::Fx => "longitudinal force",
            Channel::Fy => "lateral force",
            Channel::Mz => "aligning moment",
        };
        format!("{what} {} [{}]", self.name, self.unit)
    }

    fn residual_label(&self) -> String {
        format!("residual, model - measured [{}]", self.unit)
    }

    /// "base + a + b", or `None` when no effect was selected for this channel.
    fn extended_name(&self) -> Option<String> {
        (!self.effects.is_empty()).then(|| {
            let ids: Vec<&str> = self.effects.iter().map(|e| e.name()).collect();
            format!("base + {}", ids.join(" + "))
        })
    }
}

/// The held-out residuals of the diagnosis are measured minus predicted (they come from
/// `channel_fit::cross_validate`); the figures show model minus measurement, so that a positive
/// residual is a model above the data.
pub fn model_minus_measured(heldout: &CompactResiduals) -> Vec<f64> {
    heldout.iter().map(|r| -r).collect()
}

fn views<'a>(d: &'a Diagnosis, skipped: &mut Vec<String>) -> Vec<View<'a>> {
    let mut out = Vec::new();
    for detail in &d.detail {
        let channel = detail.data.channel;
        let n = detail.data.len();
        if detail.base_residuals.len() != n || detail.final_residuals.len() != n {
            skipped.push(format!(
                "{channel} figures skipped: the held-out residuals do not match the rows"
            ));
            continue;
        }
        out.push(View {
            data: &detail.data,
            name: channel.name(),
            unit: if channel == Channel::Mz { "N.m" } else { "N" },
            effects: d
                .models
                .iter()
                .find(|m| m.channel == channel)
                .map(|m| m.effects.iter().map(|(e, _)| *e).collect())
                .unwrap_or_default(),
            base: model_minus_measured(&detail.base_residuals),
            last: model_minus_measured(&detail.final_residuals),
            candidates: detail
                .candidates
                .iter()
                .map(|(e, r)| (*e, model_minus_measured(r)))
                .collect(),
        });
    }
    out
}

/// Draws every figure of `d` in memory.
pub fn render(d: &Diagnosis) -> Figures {
    let mut figs = Figures::default();
    figs.add(
        "regions.svg".into(),
        "Where the base model's held-out error lies: the top regions by share of squared error \
         against share of rows (shares within each channel)."
            .into(),
        ranking::chart(&d.regions, TOP_REGIONS),
    );
    figs.add(
        "signatures.svg".into(),
        "Where each claim's held-out gain lies: its gain per row (fall of the systematic squared \
         error) where its driver acts and where it is idle, and the same for the candidates \
         refused because their gain lies where their driver is idle."
            .into(),
        signatures::chart(d),
    );
    let views = views(d, &mut figs.skipped);
    let find = |ch: Channel| views.iter().find(|v| v.data.channel == ch);
    match (find(Channel::Fx), find(Channel::Fy)) {
        (Some(fx), Some(fy)) => figs.add(
            "friction_circle.svg".into(),
            "Friction circle: Fy against Fx on the combined-slip rows, measured and as the base \
             and extended models predict them on held-out runs."
                .into(),
            sweeps::friction_circle(fx, fy),
        ),
        _ => figs.skipped.push(
            "friction_circle.svg skipped: needs both Fx and Fy measured, with slip ratio and \
             slip angle"
                .into(),
        ),
    }
    for v in &views {
        channel_figures(&mut figs, v);
    }
    figs
}

/// The figures of one channel's view: its worst sweeps, its residual map and each
/// candidate's residual over its driving input.
fn channel_figures(figs: &mut Figures, v: &View) {
    let ch = v.name;
    let extended = v
        .extended_name()
        .map_or("no effect selected".to_string(), |e| {
            format!("extended: {e}")
        });
    figs.add(
        format!("worst_sweeps_{ch}.svg"),
        format!(
            "{ch}: the {WORST_RUNS} runs with the largest mean squared held-out residual of \
                 the base model, against the slip each run sweeps: measured (in time order, so \
                 loops show hysteresis), base and extended model ({extended})."
        ),
        sweeps::worst_sweeps(v, WORST_RUNS),
    );
    figs.add(
        format!("residual_map_{ch}.svg"),
        format!(
            "{ch}: mean held-out residual (model - measured) binned over {} and load; red \
                 where the model is above the measurement ({extended}).",
            v.slip_name()
        ),
        maps::residual_map(v),
    );
    for (effect, residuals) in &v.candidates {
        let id = effect.name();
        let selected = if v.effects.contains(effect) {
            "selected"
        } else {
            "not selected"
        };
        let input = effects::of(*effect)
            .row_driver(v.data)
            .map_or("its driving input".into(), |d| {
                d.axis.split(" [").next().unwrap_or_default().to_string()
            });
        figs.add(
            format!("driver_{id}_{ch}.svg"),
            format!(
                "{ch}: held-out residual binned over {input}, the input that drives {id}: \
                     base model and base + {id} (first-round candidate, {selected}); bands are \
                     +-1 standard error of the bin mean, rows taken as independent."
            ),
            drivers::plot(v, *effect, residuals),
        );
    }
}

/// Fails early, before a long diagnosis, when figures cannot be written into `dir`: it, or
/// the nearest of its ancestors that exists, is not a writable directory, or an input file
/// in it has the name of a figure.
pub fn check_dir(dir: &Path, inputs: &[std::path::PathBuf]) -> Result<(), Failure> {
    check_dir_target(dir, "--plots", inputs, |name| {
        name == "index.html" || name.ends_with(".svg")
    })
}

/// Writes the figures and `index.html` (headed `heading`) into `dir`, creating it; each file
/// whole or not at all.
pub fn write(dir: &Path, figs: &Figures, heading: &str) -> Result<(), Failure> {
    std::fs::create_dir_all(dir).map_err(|e| {
        output_failure(format!(
            "cannot create the plot directory {}: {e}",
            dir.display()
        ))
    })?;
    for f in &figs.figures {
        write_whole(&dir.join(&f.file), f.svg.as_bytes())?;
    }
    write_whole(
        &dir.join("index.html"),
        index_html(figs, heading).as_bytes(),
    )
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A page listing the figures with their captions, then showing them.
pub fn index_html(figs: &Figures, heading: &str) -> String {
    let mut s =
        String::from("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    s += &format!("<title>{}</title>\n", escape(heading));
    s += "<style>body{font-family:sans-serif;max-width:72em;margin:2em auto;padding:0 1em}\
          img{max-width:100%;border:1px solid #ddd}figure{margin:2em 0}</style>\n</head>\n<body>\n";
    s += &format!("<h1>{}</h1>\n<ul>\n", escape(heading));
    for f in &figs.figures {
        let (file, caption) = (escape(&f.file), escape(&f.caption));
        s += &format!("<li><a href=\"{file}\">{file}</a>: {caption}</li>\n");
    }
    s += "</ul>\n";
    if !figs.skipped.is_empty() {
        s += "<h2>Not drawn</h2>\n<ul>\n";
        for note in &figs.skipped {
            s += &format!("<li>{}</li>\n", escape(note));
        }
        s += "</ul>\n";
    }
    for f in &figs.figures {
        let (file, caption) = (escape(&f.file), escape(&f.caption));
        s += &format!(
            "<figure id=\"{file}\"><img src=\"{file}\" alt=\"{file}\">\
             <figcaption><a href=\"{file}\">{file}</a>: {caption}</figcaption></figure>\n"
        );
    }
    s += "</body>\n</html>\n";
    s
}
