//! The diagnosis as a terminal report and as one JSON object.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use crate::diagnose::{Diagnosis, Trial};
use crate::effects::EffectId;

/// Where the result came from.
#[derive(Debug, Clone, Serialize)]
pub struct Provenance {
    pub input: String,
    /// SHA-256 of the input file's bytes.
    pub input_sha256: String,
    pub split_seed: u64,
    pub folds: usize,
    pub tool: &'static str,
    pub version: &'static str,
}

/// One entry of the `effects` list: a candidate tested against the base model (round 1).
#[derive(Debug, Clone, Serialize)]
pub struct EffectEntry {
    pub effect: EffectId,
    pub form: &'static str,
    /// Held-out RMS per channel without and with the effect [N or N.m].
    pub heldout_before: BTreeMap<&'static str, f64>,
    pub heldout_after: BTreeMap<&'static str, f64>,
    /// Fraction of the gap above the noise floor closed, on the channel where it helps most.
    pub gap_closed: f64,
    pub gap_closed_by_channel: BTreeMap<&'static str, f64>,
    /// Significant against the base model (Holm-corrected sign-flip test plus minimum gains).
    pub significant: bool,
    /// Whether forward selection kept it (see `verdict`).
    pub selected: bool,
    pub p_adjusted: BTreeMap<&'static str, f64>,
    /// Fitted effect parameters on all data, per channel.
    pub params: BTreeMap<String, f64>,
}

fn entry(trial: &Trial, verdict: &[EffectId]) -> EffectEntry {
    let by = |f: fn(&crate::diagnose::ChannelTrial) -> f64| {
        trial.channels.iter().map(|c| (c.channel, f(c))).collect()
    };
    EffectEntry {
        effect: trial.effect,
        form: trial.form,
        heldout_before: by(|c| c.heldout_before),
        heldout_after: by(|c| c.heldout_after),
        gap_closed: trial
            .channels
            .iter()
            .map(|c| c.gap_closed)
            .fold(f64::NEG_INFINITY, f64::max),
        gap_closed_by_channel: by(|c| c.gap_closed),
        significant: trial.significant,
        selected: verdict.contains(&trial.effect),
        p_adjusted: by(|c| c.p_adjusted),
        params: trial
            .channels
            .iter()
            .flat_map(|c| c.params.clone())
            .collect(),
    }
}

/// The JSON report.
#[derive(Debug, Clone, Serialize)]
pub struct JsonReport<'a> {
    pub provenance: &'a Provenance,
    pub rows: usize,
    pub runs: usize,
    pub baseline: &'a [crate::diagnose::ChannelBaseline],
    pub regions: &'a [crate::regions::Region],
    pub effects: Vec<EffectEntry>,
    pub verdict: Vec<&'static str>,
    pub confounding: &'a [crate::diagnose::Confounding],
    pub untestable: &'a [crate::diagnose::Untestable],
    pub remaining: &'a [crate::diagnose::ChannelBaseline],
    pub remaining_regions: &'a [crate::regions::Region],
    pub extrapolation: &'a [crate::extrapolate::Extrapolation],
    pub rounds: &'a [crate::diagnose::Round],
    pub nominal: &'a crate::effects::Nominal,
    pub options: &'a crate::diagnose::Options,
}

/// The `effects` list: every candidate tested in the first round, best first.
pub fn effect_entries(d: &Diagnosis) -> Vec<EffectEntry> {
    d.rounds
        .first()
        .map(|r| r.trials.iter().map(|t| entry(t, &d.verdict)).collect())
        .unwrap_or_default()
}

pub fn json(d: &Diagnosis, provenance: &Provenance) -> String {
    let report = JsonReport {
        provenance,
        rows: d.rows,
        runs: d.runs,
        baseline: &d.baseline,
        regions: &d.regions,
        effects: effect_entries(d),
        verdict: d.verdict.iter().map(|e| e.id()).collect(),
        confounding: &d.confounding,
        untestable: &d.untestable,
        remaining: &d.remaining,
        remaining_regions: &d.remaining_regions,
        extrapolation: &d.extrapolation,
        rounds: &d.rounds,
        nominal: &d.nominal,
        options: &d.options,
    };
    serde_json::to_string_pretty(&report).expect("the report serializes")
}

/// Regions shown in the terminal report.
const TOP_REGIONS: usize = 8;

fn regions_table(out: &mut String, regions: &[crate::regions::Region]) {
    let _ = writeln!(
        out,
        "  {:<4} {:<16} {:<34} {:>7} {:>8} {:>8} {:>10}",
        "", "dimension", "region", "rows", "data %", "error %", "rms"
    );
    for r in regions.iter().take(TOP_REGIONS) {
        let _ = writeln!(
            out,
            "  {:<4} {:<16} {:<34} {:>7} {:>8.1} {:>8.1} {:>10.1}",
            r.channel,
            r.dimension,
            r.label,
            r.rows,
            100.0 * r.share_rows,
            100.0 * r.share_squared_error,
            r.rms
        );
    }
}

/// Forward selection round by round: each kept effect with its gain over the effects kept
/// before it (the table above compares every candidate with the base model alone).
fn selection_rounds(out: &mut String, d: &Diagnosis) {
    let mut kept: Vec<&str> = Vec::new();
    for (k, round) in d.rounds.iter().enumerate() {
        let Some(trial) = round
            .selected
            .and_then(|w| round.trials.iter().find(|t| t.effect == w))
        else {
            continue;
        };
        if kept.is_empty() {
            let _ = writeln!(
                out,
                "\nForward selection (gain over the effects kept before)"
            );
        }
        let on_top = if kept.is_empty() {
            "the base model".to_string()
        } else {
            kept.join(" + ")
        };
        let channels: Vec<String> = trial
            .channels
            .iter()
            .filter(|c| c.significant)
            .map(|c| {
                format!(
                    "{} {:.1} -> {:.1} (closes {:.0}% of the gap left, {:.0}% of the base gap)",
                    c.channel,
                    c.heldout_before,
                    c.heldout_after,
                    100.0 * c.gap_closed,
                    100.0 * c.base_gap_closed
                )
            })
            .collect();
        let p = trial
            .channels
            .first()
            .map(|c| c.p_adjusted)
            .unwrap_or(f64::NAN);
        let _ = writeln!(
            out,
            "  round {}: {} added to {} (p={p:.2e}): {}",
            k + 1,
            trial.effect.id(),
            on_top,
            channels.join("; ")
        );
        kept.push(trial.effect.id());
    }
}

/// The human-readable report.
pub fn text(d: &Diagnosis, provenance: &Provenance) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "tire-gap {}: {} ({} rows, {} runs; sha256 {}; {}-fold cross-validation by run, seed {})\n",
        provenance.version,
        provenance.input,
        d.rows,
        d.runs,
        &provenance.input_sha256[..16.min(provenance.input_sha256.len())],
        provenance.folds,
        provenance.split_seed
    );
    let _ = writeln!(
        out,
        "Baseline: the 1987 model fitted to the data, scored on held-out runs"
    );
    let _ = writeln!(
        out,
        "  {:<4} {:>12} {:>12} {:>12} {:>12} {:>10}",
        "", "held-out rms", "rms / load", "noise floor", "gap", "in-sample"
    );
    for b in &d.baseline {
        let _ = writeln!(
            out,
            "  {:<4} {:>8.1} {:<3} {:>11.2}% {:>8.1} {:<3} {:>8.1} {:<3} {:>10.1}",
            b.channel,
            b.heldout.rms,
            b.unit,
            100.0 * b.heldout.rms_per_load,
            b.noise_floor,
            b.unit,
            b.gap,
            b.unit,
            b.in_sample_rms
        );
    }
    let _ = writeln!(
        out,
        "\nWhere: regions holding more than their share of the held-out squared error"
    );
    regions_table(&mut out, &d.regions);

    let _ = writeln!(
        out,
        "\nWhich: candidate effects against the base model (held-out rms before -> after)"
    );
    for e in effect_entries(d) {
        let channels: Vec<String> = e
            .heldout_before
            .iter()
            .map(|(c, b)| {
                format!(
                    "{c} {b:.1} -> {:.1} (closes {:.0}%, p={:.2e})",
                    e.heldout_after[c],
                    100.0 * e.gap_closed_by_channel[c],
                    e.p_adjusted[c]
                )
            })
            .collect();
        let mark = match (e.selected, e.significant) {
            (true, _) => "SELECTED",
            (false, true) => "significant",
            _ => "-",
        };
        let _ = writeln!(
            out,
            "  {:<20} {:<12} {}",
            e.effect.id(),
            mark,
            channels.join("; ")
        );
    }
    for u in &d.untestable {
        let _ = writeln!(
            out,
            "  {:<20} {:<12} not testable: {}",
            u.effect.id(),
            "-",
            u.reason
        );
    }
    selection_rounds(&mut out, d);
    let _ = writeln!(out);
    if d.verdict.is_empty() {
        let _ = writeln!(
            out,
            "Verdict: no candidate effect closes a significant part of the gap; the 1987 model needs nothing more here."
        );
    } else {
        let ids: Vec<&str> = d.verdict.iter().map(|e| e.id()).collect();
        let _ = writeln!(out, "Verdict: {}", ids.join(", "));
    }
    for c in &d.confounding {
        let _ = writeln!(
            out,
            "  Note: {} explains {:.0}% as much as {}{}; only {} is claimed. To separate them: {}.",
            c.runner_up.id(),
            100.0 * c.score_ratio,
            c.winner.id(),
            c.correction_correlation
                .map(|r| format!(" (corrections correlate, r = {r:.2})"))
                .unwrap_or_default(),
            c.winner.id(),
            c.separating_test
        );
    }
    let _ = writeln!(out, "\nRemaining gap with the selected effects (held-out)");
    for (b, r) in d.baseline.iter().zip(&d.remaining) {
        let _ = writeln!(
            out,
            "  {:<4} {:>8.1} -> {:>8.1} {:<3} (noise floor {:.1}, gap {:.1} -> {:.1})",
            b.channel, b.heldout.rms, r.heldout.rms, b.unit, b.noise_floor, b.gap, r.gap
        );
    }
    if !d.verdict.is_empty() {
        let _ = writeln!(out, "  where it now lies:");
        regions_table(&mut out, &d.remaining_regions);
    }
    if let Some(first) = d.extrapolation.first() {
        let _ = writeln!(
            out,
            "\nExtrapolation: {} with one end of its input ({}) held out, refitted on the other runs",
            first.effect.id(),
            first.driver
        );
        for x in &d.extrapolation {
            let _ = writeln!(
                out,
                "  {:<4} {:<32} {:>3} runs  held-out rms without {:>8.1} -> with {:>8.1}",
                x.channel, x.held_out, x.runs, x.rms_without, x.rms_with
            );
        }
    }
    out
}
