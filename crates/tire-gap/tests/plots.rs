//! `diagnose --plots`: the figures of a diagnosis of small synthetic data with combined slip,
//! checked as SVG documents against values computed here from the diagnosis itself.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;
use tire_gap::method::observer::Unobserved;

use mf87::Channel;
use tire_gap::io::plots::{self, Figures};
use tire_gap::method::diagnose::{ChannelDetail, Diagnosis, Options, diagnose};
use tire_gap::method::fit::effects::Extension;
use tire_gap::method::stats::CompactResiduals;
use tire_gap::synth::{SynthConfig, TireKind, generate};

/// The small synthetic programme the figures are drawn from.
fn programme() -> SynthConfig {
    SynthConfig {
        seed: 3,
        effects: vec![Extension::CombinedSlip],
        tire: TireKind::Mf52,
        rows_target: 6000,
        noise: 1.0,
        ..SynthConfig::default()
    }
}

/// One diagnosis shared by the tests (it takes some seconds).
fn diagnosis() -> &'static Diagnosis {
    static D: OnceLock<Diagnosis> = OnceLock::new();
    D.get_or_init(|| {
        diagnose(&generate(&programme()), &Options::default(), &Unobserved).expect("diagnosis runs")
    })
}

/// A fresh, empty directory path under the system's temporary directory.
fn fresh_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tire-gap-plots-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Parses an SVG document (panics if it is not well-formed XML with an `svg` root) and
/// returns the text of its `text` elements, trimmed.
fn svg_texts(path: &Path) -> Vec<String> {
    let svg = std::fs::read_to_string(path).unwrap();
    assert!(svg.starts_with("<svg"), "{}", path.display());
    assert!(svg.trim_end().ends_with("</svg>"), "{}", path.display());
    let doc = roxmltree::Document::parse(&svg)
        .unwrap_or_else(|e| panic!("{} is not well-formed: {e}", path.display()));
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(|t| t.trim().to_string())
        .collect()
}

fn has_text(texts: &[String], part: &str) -> bool {
    texts.iter().any(|t| t.contains(part))
}

fn detail(d: &Diagnosis, ch: Channel) -> &ChannelDetail {
    d.detail.iter().find(|c| c.data.channel == ch).unwrap()
}

/// Runs by mean squared residual, largest first.
fn runs_by_mse(d: &ChannelDetail) -> Vec<(i64, f64)> {
    let mut acc: BTreeMap<i64, (f64, usize)> = BTreeMap::new();
    for (r, e) in d.data.run.iter().zip(d.base_residuals.iter()) {
        if e.is_finite() {
            let a = acc.entry(*r).or_default();
            a.0 += e * e;
            a.1 += 1;
        }
    }
    let mut v: Vec<(i64, f64)> = acc
        .into_iter()
        .map(|(r, (s, n))| (r, s / n as f64))
        .collect();
    v.sort_by(|a, b| b.1.partial_cmp(&a.1).unwrap());
    v
}

#[test]
fn every_figure_is_written_as_svg_and_listed_in_the_index() {
    let d = diagnosis();
    let figs = plots::render(d);
    let dir = fresh_dir("all").join("nested");
    plots::write(&dir, &figs, "test heading").unwrap();

    let mut expected = vec!["regions.svg".to_string(), "friction_circle.svg".to_string()];
    for c in &d.detail {
        let ch = c.data.channel.name();
        expected.push(format!("worst_sweeps_{ch}.svg"));
        expected.push(format!("residual_map_{ch}.svg"));
        for (e, _) in &c.candidates {
            expected.push(format!("driver_{}_{ch}.svg", e.name()));
        }
    }
    // The signature chart, when a claim or a refusal has a tested signature.
    let tested = d
        .claims
        .iter()
        .flat_map(|c| c.channels.iter().map(|ch| &ch.signature))
        .chain(d.signature_refusals.iter().map(|r| &r.signature))
        .any(|t| t.not_testable.is_none());
    assert!(
        tested,
        "the fixture's diagnosis claims with a tested signature"
    );
    expected.push("signatures.svg".to_string());
    assert_eq!(d.detail.len(), 3);
    assert!(figs.skipped.is_empty(), "{:?}", figs.skipped);
    let mut written: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    written.sort();
    let mut want = expected.clone();
    want.push("index.html".into());
    want.sort();
    assert_eq!(written, want, "no temporary files left, nothing missing");

    let index = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(index.contains("<h1>test heading</h1>"));
    for f in &expected {
        assert!(
            index.contains(&format!("<li><a href=\"{f}\">{f}</a>: ")),
            "{f}"
        );
    }

    for f in &expected {
        let texts = svg_texts(&dir.join(f));
        assert!(!texts.is_empty(), "{f}: no text");
    }
    let t = svg_texts(&dir.join("worst_sweeps_Fy.svg"));
    assert!(has_text(
        &t,
        "Fy: the 4 runs where the base model's held-out error is largest"
    ));
    assert!(has_text(&t, "lateral force Fy [N]"));
    assert!(has_text(&t, "measured (line in time order)"));
    assert!(has_text(&t, "base + combined_slip (held-out)"));
    let t = svg_texts(&dir.join("worst_sweeps_Fx.svg"));
    assert!(has_text(&t, "slip ratio sigma [%]"));
    let t = svg_texts(&dir.join("residual_map_Mz.svg"));
    assert!(has_text(
        &t,
        "Mz: mean held-out residual over slip angle and load"
    ));
    assert!(has_text(&t, "vertical load Fz [kN]"));
    assert!(has_text(&t, "residual, model - measured [N.m]"));
    assert!(
        has_text(&t, "base + combined_slip"),
        "the final model's panel"
    );
    let t = svg_texts(&dir.join("driver_combined_slip_Fy.svg"));
    assert!(has_text(&t, "slip ratio kappa [-]"));
    assert!(has_text(&t, "mean residual, model - measured [N]"));
    assert!(has_text(&t, "(selected)"));
    let t = svg_texts(&dir.join("friction_circle.svg"));
    assert!(has_text(&t, "longitudinal force Fx [N]"));
    assert!(has_text(&t, "lateral force Fy [N]"));
    let t = svg_texts(&dir.join("regions.svg"));
    assert!(has_text(&t, "share [%]"));
    for r in d.regions.iter().take(15) {
        let label = format!("{} {}: {}", r.channel, r.dimension, r.label);
        assert!(t.contains(&label), "{label}");
    }
    std::fs::remove_dir_all(dir.parent().unwrap()).unwrap();
}

#[test]
fn without_candidate_figures_the_report_is_the_same_and_no_driver_figure_is_drawn() {
    let d = diagnosis();
    assert!(d.detail.iter().any(|c| !c.candidates.is_empty()));
    let options = Options {
        candidate_figures: false,
        ..Options::default()
    };
    let lean = diagnose(&generate(&programme()), &options, &Unobserved).expect("diagnosis runs");
    assert_eq!(
        serde_json::to_string(&lean).unwrap(),
        serde_json::to_string(d).unwrap()
    );
    assert!(lean.detail.iter().all(|c| c.candidates.is_empty()));
    let figs = plots::render(&lean);
    assert!(files(&figs).iter().all(|f| !f.starts_with("driver_")));
    assert!(files(&figs).iter().any(|f| f.starts_with("worst_sweeps_")));
}

#[test]
fn worst_sweeps_show_the_runs_with_the_largest_base_error() {
    let d = diagnosis();
    let figs = plots::render(d);
    for ch in [Channel::Fx, Channel::Fy, Channel::Mz] {
        let ranked = runs_by_mse(detail(d, ch));
        let file = format!("worst_sweeps_{}.svg", ch.name());
        let svg = &figs.figures.iter().find(|f| f.file == file).unwrap().svg;
        let texts: Vec<String> = roxmltree::Document::parse(svg)
            .unwrap()
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .filter_map(|n| n.text().map(|t| t.trim().to_string()))
            .collect();
        let panels: Vec<&String> = texts.iter().filter(|t| t.starts_with("run ")).collect();
        assert_eq!(panels.len(), 4, "{file}: {panels:?}");
        for (k, (run, mse)) in ranked.iter().take(4).enumerate() {
            // In order, with the run's RMS of the base model.
            assert!(
                panels[k].starts_with(&format!("run {run}: ")),
                "{file}: {panels:?}"
            );
            assert!(
                panels[k].contains(&format!("RMS base {:.0}", mse.sqrt())),
                "{file}: {}",
                panels[k]
            );
        }
        let fifth = ranked[4].0;
        assert!(
            !panels
                .iter()
                .any(|p| p.starts_with(&format!("run {fifth}: ")))
        );
    }
}

#[test]
fn heldout_residuals_are_measured_minus_predicted() {
    // The figures turn the diagnosis's residuals into model minus measurement
    // (`plots::model_minus_measured`); this pins the convention they rely on.
    let d = diagnosis();
    for c in &d.detail {
        let predicted = c.base_model.predictions(&c.data);
        let in_sample: Vec<f64> = predicted
            .iter()
            .zip(c.data.measured.iter())
            .map(|(p, m)| p - m)
            .collect();
        let heldout = plots::model_minus_measured(&c.base_residuals);
        let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
        for (a, b) in in_sample.iter().zip(&heldout) {
            if b.is_finite() {
                sab += a * b;
                saa += a * a;
                sbb += b * b;
            }
        }
        let corr = sab / (saa * sbb).sqrt();
        assert!(corr > 0.8, "{}: correlation {corr}", c.data.channel);
    }
}

fn without(d: &Diagnosis, ch: Channel) -> Diagnosis {
    let mut d = d.clone();
    d.detail.retain(|c| c.data.channel != ch);
    d.models.retain(|m| m.channel != ch);
    d
}

fn files(figs: &Figures) -> Vec<&str> {
    figs.figures.iter().map(|f| f.file.as_str()).collect()
}

#[test]
fn friction_circle_needs_both_fx_and_fy() {
    let d = diagnosis();
    assert!(files(&plots::render(d)).contains(&"friction_circle.svg"));
    for ch in [Channel::Fx, Channel::Fy] {
        let figs = plots::render(&without(d, ch));
        let f = files(&figs);
        assert!(!f.contains(&"friction_circle.svg"), "{ch}: {f:?}");
        assert!(!f.contains(&format!("worst_sweeps_{}.svg", ch.name()).as_str()));
        assert!(f.contains(&"worst_sweeps_Mz.svg"));
        assert!(
            figs.skipped
                .iter()
                .any(|s| s.starts_with("friction_circle.svg skipped: needs both Fx and Fy")),
            "{:?}",
            figs.skipped
        );
    }
}

#[test]
fn missing_inputs_skip_figures_with_a_note() {
    let mut d = diagnosis().clone();
    let fy = d
        .detail
        .iter_mut()
        .find(|c| c.data.channel == Channel::Fy)
        .unwrap();
    let residuals = fy.base_residuals.to_vec();
    fy.candidates = vec![
        (
            Extension::RelaxationLength,
            CompactResiduals::new(&residuals),
        ),
        (Extension::Temperature, CompactResiduals::new(&residuals)),
        (
            Extension::CombinedSlip,
            CompactResiduals::new(&residuals[1..]),
        ),
    ];
    fy.data.time = None;
    fy.data.temperature = None;
    let figs = plots::render(&d);
    let f = files(&figs);
    assert!(
        !f.iter()
            .any(|f| f.starts_with("driver_") && f.ends_with("_Fy.svg")),
        "{f:?}"
    );
    for note in [
        "driver_relaxation_length_Fy.svg skipped: no time column",
        "driver_temperature_Fy.svg skipped: no temperature column",
        "driver_combined_slip_Fy.svg skipped: the candidate's residuals do not match the rows",
    ] {
        assert!(
            figs.skipped.iter().any(|s| s == note),
            "{note}: {:?}",
            figs.skipped
        );
    }

    // Nothing at all to draw: notes, no figure, no panic.
    d.detail.clear();
    d.regions.clear();
    d.claims.clear();
    d.signature_refusals.clear();
    let figs = plots::render(&d);
    assert!(figs.figures.is_empty());
    assert!(
        figs.skipped
            .iter()
            .any(|s| s.starts_with("signatures.svg skipped: no claim"))
    );
    assert!(
        figs.skipped
            .iter()
            .any(|s| s.starts_with("regions.svg skipped"))
    );
}

/// A file standing where the plot directory's parent should be.
fn blocking_file(name: &str) -> PathBuf {
    let dir = fresh_dir(name);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("not-a-directory");
    std::fs::write(&file, "x").unwrap();
    file
}

#[test]
fn writing_under_a_file_fails_naming_the_path() {
    let target = blocking_file("write").join("figures");
    let err = plots::write(&target, &Figures::default(), "x").unwrap_err();
    assert_eq!(err.kind, tire_gap::io::output::FailureKind::Output);
    assert!(
        err.message.contains(&target.display().to_string()),
        "{}",
        err.message
    );
    let err = plots::check_dir(&target, &[]).unwrap_err();
    assert_eq!(err.kind, tire_gap::io::output::FailureKind::Output);
    assert!(
        err.message.contains(&target.display().to_string()),
        "{}",
        err.message
    );
    assert!(
        err.message.contains("is not a directory"),
        "{}",
        err.message
    );
    assert!(plots::check_dir(&fresh_dir("absent").join("a/b"), &[]).is_ok());
    std::fs::remove_dir_all(target.parent().unwrap().parent().unwrap()).unwrap();
}

/// Two rows in two runs: loads, but too few runs for a diagnosis.
const TINY: &str = "\
run,t_s,fz_N,alpha_deg,fy_N
1,0.0,4000,1,900
2,0.0,4000,2,1700
";

#[test]
fn cli_plots_into_an_unwritable_path_exits_1_naming_it() {
    let blocker = blocking_file("cli");
    let csv = blocker.with_file_name("tiny.csv");
    std::fs::write(&csv, TINY).unwrap();
    let target = blocker.join("figures");
    let out = Command::new(env!("CARGO_BIN_EXE_tire-gap"))
        .arg("diagnose")
        .arg(&csv)
        .arg("--plots")
        .arg(&target)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains(&target.display().to_string()), "{stderr}");
    assert!(out.stdout.is_empty());
    std::fs::remove_dir_all(blocker.parent().unwrap()).unwrap();
}

#[test]
fn cli_failed_diagnosis_writes_no_figures() {
    let dir = fresh_dir("failed");
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("tiny.csv");
    std::fs::write(&csv, TINY).unwrap();
    let target = dir.join("figures");
    let out = Command::new(env!("CARGO_BIN_EXE_tire-gap"))
        .arg("diagnose")
        .arg(&csv)
        .arg("--plots")
        .arg(&target)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("cross-validation by run needs at least 5 runs"),
        "{stderr}"
    );
    assert!(!target.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
