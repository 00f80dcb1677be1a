//! The terminal report.

use std::fmt::Write as _;

use super::{BlockRow, Context, blocks_report, effect_entries};
use crate::method::diagnose::Diagnosis;
use crate::method::diagnose::signature::Against;

/// Regions shown in the terminal report.
const TOP_REGIONS: usize = 8;

fn regions_table(out: &mut String, regions: &[crate::method::diagnose::regions::Region]) {
    if regions.is_empty() {
        let _ = writeln!(out, "  none to rank: no channel has a measurable gap");
        return;
    }
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
        let single = round
            .selected
            .and_then(|w| round.trials.iter().find(|t| t.effect == w));
        let pair = round
            .selected_pair
            .and_then(|p| round.pairs.iter().find(|t| t.effects == p));
        let (name, lines, p): (String, Vec<Line>, Option<f64>) = match (single, pair) {
            (Some(t), _) => (
                t.effect.name().to_string(),
                t.channels
                    .iter()
                    .filter(|c| c.significant)
                    .map(|c| Line {
                        channel: c.channel,
                        before: c.heldout_before,
                        after: c.heldout_after,
                        gap_closed: c.gap_closed,
                        base_gap_closed: c.base_gap_closed,
                    })
                    .collect(),
                t.channels.iter().find_map(|c| c.p_adjusted),
            ),
            (None, Some(t)) => (
                format!(
                    "{} + {} (fitted jointly)",
                    t.effects[0].name(),
                    t.effects[1].name()
                ),
                t.channels
                    .iter()
                    .filter(|c| c.significant)
                    .map(|c| Line {
                        channel: c.channel,
                        before: c.heldout_before,
                        after: c.heldout_after,
                        gap_closed: c.gap_closed,
                        base_gap_closed: None,
                    })
                    .collect(),
                t.channels.iter().find_map(|c| c.p_adjusted),
            ),
            (None, None) => continue,
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
        let channels: Vec<String> = lines.iter().map(Line::text).collect();
        let _ = writeln!(
            out,
            "  round {}: {name} added to {on_top} (p={}): {}",
            k + 1,
            p_text(p),
            channels.join("; ")
        );
        match (single, pair) {
            (Some(t), _) => kept.push(t.effect.name()),
            (None, Some(t)) => kept.extend(t.effects.iter().map(|e| e.name())),
            (None, None) => {}
        }
    }
}

/// One channel of a selection round's line.
struct Line {
    channel: mf87::Channel,
    before: f64,
    after: f64,
    gap_closed: Option<f64>,
    base_gap_closed: Option<f64>,
}

impl Line {
    /// The channel's held-out error before and after, and the gap it closes.
    fn text(&self) -> String {
        let base = self.base_gap_closed.map_or(String::new(), |b| {
            format!(", {} of the base gap", share(Some(b)))
        });
        format!(
            "{} {:.1} -> {:.1} (closes {} of the gap left{base})",
            self.channel,
            self.before,
            self.after,
            share(self.gap_closed),
        )
    }
}

/// The pairs of effects fitted jointly in rounds no single effect won, and why those not
/// selected were not.
fn pairs_tried(out: &mut String, d: &Diagnosis) {
    for (k, round) in d.rounds.iter().enumerate() {
        if round.pairs.is_empty() {
            continue;
        }
        let _ = writeln!(
            out,
            "  round {}: no single effect won; pairs of effects fitted jointly:",
            k + 1
        );
        for t in &round.pairs {
            let mark = match round.selected_pair == Some(t.effects) {
                true => "SELECTED",
                false => "-",
            };
            let channels: Vec<String> = t
                .channels
                .iter()
                .map(|c| {
                    let why = c
                        .not_their_signatures
                        .as_deref()
                        .or(c.implausible.as_deref())
                        .map_or(String::new(), |w| format!("; not claimed: {w}"));
                    format!(
                        "{} {:.1} -> {:.1} (closes {}, p={}{why})",
                        c.channel,
                        c.heldout_before,
                        c.heldout_after,
                        share(c.gap_closed),
                        p_text(c.p_adjusted),
                    )
                })
                .collect();
            let _ = writeln!(
                out,
                "    {} + {} {mark}: {}",
                t.effects[0].name(),
                t.effects[1].name(),
                channels.join("; ")
            );
        }
    }
}

/// Where each claim's held-out gain lies (its signature), and the candidates that passed
/// every rule but that.
fn signatures(out: &mut String, d: &Diagnosis) {
    if !d.claims.is_empty() {
        let _ = writeln!(
            out,
            "  Signatures: each claim's held-out gain per row (fall of the systematic squared \
             error) where its driver acts against where it is idle"
        );
    }
    for c in &d.claims {
        let with = c
            .with
            .map_or(String::new(), |w| format!(" (jointly with {})", w.name()));
        let with = match c.seed {
            Some(seed) => format!("{with} (on split seed {seed})"),
            None => with,
        };
        for ch in &c.channels {
            let s = &ch.signature;
            let _ = writeln!(
                out,
                "    {} {}{with}: {} where {} ({} rows, {} runs) against {} where idle, {} \
                 ({} rows, {} runs): p={}",
                c.effect.name(),
                ch.channel,
                gain_text(s.gain_per_row_active, ch.channel),
                s.active,
                s.active_rows,
                s.active_runs,
                gain_text(s.gain_per_row_idle, ch.channel),
                s.idle,
                s.idle_rows,
                s.idle_runs,
                p_text(s.p_value)
            );
            let _ = writeln!(
                out,
                "      as the test weighs it, per run over the load's mean square: {} where it \
                 acts against {} where idle",
                load_gain_text(s.run_gain_active, ch.channel),
                load_gain_text(s.run_gain_idle, ch.channel)
            );
            if let Some(against @ Against::IdleFit) = s.against {
                let _ = writeln!(out, "      (the gain against {})", against.words());
            }
        }
    }
    if !d.signature_refusals.is_empty() {
        let _ = writeln!(
            out,
            "  Not claimed for their signature (every other rule passed):"
        );
    }
    for r in &d.signature_refusals {
        let _ = writeln!(
            out,
            "    {} {} (round {}): {}",
            r.effect.name(),
            r.channel,
            r.round,
            r.reason
        );
    }
}

/// A gain per row with its unit.
fn gain_text(g: f64, channel: mf87::Channel) -> String {
    let unit = match channel {
        mf87::Channel::Mz => "(N.m)^2",
        _ => "N^2",
    };
    format!("{g:.3e} {unit}")
}

/// A gain per row over the load's mean square with its unit.
fn load_gain_text(g: f64, channel: mf87::Channel) -> String {
    let unit = match channel {
        mf87::Channel::Mz => "(N.m/kN)^2",
        _ => "(N/kN)^2",
    };
    format!("{g:.3e} {unit}")
}

/// A share as a percentage; a share of a gap that cannot be told from the noise is not one.
fn share(x: Option<f64>) -> String {
    x.map_or_else(
        || "no measurable gap".to_string(),
        |v| format!("{:.0}%", 100.0 * v),
    )
}

fn p_text(p: Option<f64>) -> String {
    p.map_or_else(|| "not tested".to_string(), |p| format!("{p:.2e}"))
}

/// Run ids as ranges of consecutive ids: `1..3, 7`.
pub fn run_list(runs: &[i64]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < runs.len() {
        let mut j = i;
        while j + 1 < runs.len() && runs[j + 1] == runs[j] + 1 {
            j += 1;
        }
        parts.push(if j > i {
            format!("{}..{}", runs[i], runs[j])
        } else {
            runs[i].to_string()
        });
        i = j + 1;
    }
    parts.join(", ")
}

/// The input files with their runs (when there are several), the readers' notes and the
/// diagnosis's limitations.
fn input_and_limitations(out: &mut String, d: &Diagnosis, context: &Context) {
    let inputs = &context.provenance.inputs;
    if inputs.len() > 1 {
        let _ = writeln!(out, "Input: {} files, each run from one file", inputs.len());
        for f in inputs {
            let _ = writeln!(
                out,
                "  run{} {}: {} ({} rows)",
                if f.runs.len() == 1 { "" } else { "s" },
                run_list(&f.runs),
                f.file,
                f.rows
            );
        }
        let _ = writeln!(out);
    }
    if !context.notes.is_empty() {
        let _ = writeln!(out, "Notes on the input");
        for n in &context.notes {
            let _ = writeln!(out, "  - {n}");
        }
        let _ = writeln!(out);
    }
    if !d.limitations.is_empty() {
        let _ = writeln!(out, "Limitations: what this data cannot support");
        for l in &d.limitations {
            let _ = writeln!(out, "  - {}: {}", l.subject, l.reason);
        }
        let _ = writeln!(out);
    }
}

fn outputs(out: &mut String, context: &Context) {
    if context.outputs.is_empty() {
        return;
    }
    let _ = writeln!(out, "\nOutputs");
    for o in &context.outputs {
        let status = match &o.error {
            None => "written".to_string(),
            Some(e) => format!("NOT WRITTEN: {e}"),
        };
        let _ = writeln!(out, "  {} {}: {status}", o.output, o.path);
        for n in &o.notes {
            let _ = writeln!(out, "    - {n}");
        }
    }
}

/// The human-readable report.
pub fn text(d: &Diagnosis, context: &Context) -> String {
    let provenance = &context.provenance;
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
    input_and_limitations(&mut out, d, context);
    blocks_text(&mut out, d, context);
    baseline_table(&mut out, d);
    let _ = writeln!(
        out,
        "\nWhere: regions holding more than their share of the held-out squared error"
    );
    regions_table(&mut out, &d.regions);
    candidates(&mut out, d);
    selection_rounds(&mut out, d);
    pairs_tried(&mut out, d);
    let _ = writeln!(out);
    verdict(&mut out, d);
    signatures(&mut out, d);
    fit_confounding(&mut out, d);
    design_confounding(&mut out, d);
    remaining(&mut out, d);
    over_runs(&mut out, d);
    extrapolation(&mut out, d);
    ceiling(&mut out, d);
    outputs(&mut out, context);
    out
}

/// The base model's held-out error per channel against its noise floor.
fn baseline_table(out: &mut String, d: &Diagnosis) {
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
            "  {:<4} {:>8.1} {:<3} {:>11.2}% {:>8.1} {:<3} {:>8.1} {:<3} {:>10}{}",
            b.channel,
            b.heldout.rms,
            b.unit,
            100.0 * b.heldout.rms_per_load,
            b.noise_floor,
            b.unit,
            b.gap,
            b.unit,
            b.in_sample_rms
                .map_or_else(String::new, |r| format!("{r:.1}")),
            if b.no_gap.is_some() {
                "  (not measurable: at the noise floor)"
            } else {
                ""
            }
        );
    }
}

/// Every candidate effect against the base model, then the untestable ones and the fits
/// not claimed for being unphysical.
fn candidates(out: &mut String, d: &Diagnosis) {
    let _ = writeln!(
        out,
        "\nWhich: candidate effects against the base model (held-out rms before -> after)"
    );
    let entries = effect_entries(d);
    for e in &entries {
        let channels: Vec<String> = e
            .heldout_before
            .iter()
            .map(|(c, b)| {
                format!(
                    "{c} {b:.1} -> {:.1} (closes {}, p={}{})",
                    e.heldout_after[c],
                    share(e.gap_closed_by_channel[c]),
                    p_text(e.p_adjusted[c]),
                    if e.screened.contains_key(c) {
                        ", screened out"
                    } else {
                        ""
                    }
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
            e.effect.name(),
            mark,
            channels.join("; ")
        );
    }
    if entries.iter().any(|e| !e.screened.is_empty()) {
        let _ = writeln!(
            out,
            "  screened out: its fit on all data gains too little to reach the least held-out \
             gain, so it is not refitted per fold (held-out figures with its all-data \
             parameters) and not claimed"
        );
    }
    for u in &d.untestable {
        let _ = writeln!(
            out,
            "  {:<20} {:<12} not testable: {}",
            u.effect.name(),
            "-",
            u.reason
        );
    }
    for round in &d.rounds {
        for t in &round.trials {
            for c in &t.channels {
                let reasons = [
                    ("not claimed, not physical", &c.implausible),
                    ("not claimed", &c.overshadowed),
                ];
                for (what, why) in reasons {
                    if let Some(why) = why {
                        let _ = writeln!(
                            out,
                            "  {:<20} {:<12} {} {what}: {why}",
                            t.effect.name(),
                            "-",
                            c.channel
                        );
                    }
                }
            }
        }
    }
}

/// The verdict: the selected effects, or why there are none, with the unstable ones and
/// the stability rule.
fn verdict(out: &mut String, d: &Diagnosis) {
    let unexplained: Vec<String> = d
        .remaining
        .iter()
        .filter(|r| r.no_gap.is_none())
        .map(|r| {
            format!(
                "{} {:.1} {} above its noise floor of {:.1}",
                r.channel, r.gap, r.unit, r.noise_floor
            )
        })
        .collect();
    let unstable: Vec<String> = d
        .stability
        .iter()
        .flat_map(|s| &s.effects)
        .filter(|e| !e.stable)
        .map(|e| format!("{} ({} of {})", e.effect, e.selected_in, e.draws))
        .collect();
    if d.verdict.is_empty() && !unstable.is_empty() {
        let _ = writeln!(
            out,
            "Verdict: no effect is selected on most fold assignments; selected on fewer \
             (unstable, not claimed): {}. The gap stays unexplained ({}).",
            unstable.join(", "),
            unexplained.join("; ")
        );
    } else if d.verdict.is_empty() && d.baseline.iter().all(|b| b.no_gap.is_some()) {
        let _ = writeln!(
            out,
            "Verdict: no diagnosed channel has a gap above its noise floor; there is nothing for an effect to explain."
        );
    } else if d.verdict.is_empty() {
        let _ = writeln!(
            out,
            "Verdict: none of the candidate effects closes a significant part of the gap; it stays unexplained ({}). See where it lies and how it evolves over the run order below.",
            unexplained.join("; ")
        );
    } else {
        let ids: Vec<&str> = d.verdict.iter().map(|e| e.name()).collect();
        let _ = writeln!(out, "Verdict: {}", ids.join(", "));
        if !unstable.is_empty() {
            let _ = writeln!(
                out,
                "  Unstable, not claimed (selected on half the fold assignments or fewer): {}",
                unstable.join(", ")
            );
        }
    }
    if let Some(s) = &d.stability {
        let _ = writeln!(out, "  Stability: {}.", s.rule);
    }
}

/// The effects that explain nearly as much as the one claimed, and how to separate them.
fn fit_confounding(out: &mut String, d: &Diagnosis) {
    for c in &d.confounding.fits {
        let _ = writeln!(
            out,
            "  Note: {} explains {:.0}% as much as {}{}; only {} is claimed. To separate them: {}.",
            c.runner_up.name(),
            100.0 * c.score_ratio,
            c.winner.name(),
            c.correction_correlation
                .map(|r| format!(" (corrections correlate, r = {r:.2})"))
                .unwrap_or_default(),
            c.winner.name(),
            c.separating_test
        );
    }
}

/// The held-out gap left with the selected effects, and where it now lies.
fn remaining(out: &mut String, d: &Diagnosis) {
    let _ = writeln!(out, "\nRemaining gap with the selected effects (held-out)");
    for (b, r) in d.baseline.iter().zip(&d.remaining) {
        let _ = writeln!(
            out,
            "  {:<4} {:>8.1} -> {:>8.1} {:<3} (noise floor {:.1}, gap {:.1} -> {:.1}{})",
            b.channel,
            b.heldout.rms,
            r.heldout.rms,
            b.unit,
            b.noise_floor,
            b.gap,
            r.gap,
            if r.no_gap.is_some() {
                ", at the noise floor"
            } else {
                ""
            }
        );
    }
    if !d.verdict.is_empty() || !d.remaining_over_runs.is_empty() {
        let _ = writeln!(out, "  where it now lies:");
        regions_table(out, &d.remaining_regions);
    }
}

/// How much of the gap any Magic Formula explains, how much of it the named effects explain,
/// and the per-sweep floor.
fn ceiling(out: &mut String, d: &Diagnosis) {
    if d.ceiling.is_empty() {
        return;
    }
    let model = crate::method::diagnose::reference::REFERENCE_MODEL;
    let _ = writeln!(
        out,
        "\nCeiling: held-out RMS of the 1987 model, the verdict's model and a complete {model} \
         fitted on the same folds, and the per-sweep floor (a spline through each run)"
    );
    for c in &d.ceiling {
        let reference = c
            .reference
            .as_ref()
            .map_or("-".to_string(), |r| format!("{:.1}", r.heldout_rms));
        let _ = writeln!(
            out,
            "  {:<4} 1987 {:>8.1}  verdict {:>8.1}  {model} {:>8}  floor {:>8.1} {}",
            c.channel, c.baseline_rms, c.verdict_rms, reference, c.floor.rms, c.unit
        );
    }
    for c in &d.ceiling {
        let _ = writeln!(out, "  {}", c.words);
    }
}

/// The extrapolation check of the first selected effect, when it was made.
fn extrapolation(out: &mut String, d: &Diagnosis) {
    if let Some(first) = d.extrapolation.first() {
        let _ = writeln!(
            out,
            "\nExtrapolation: {} with one end of its input ({}) held out, refitted on the other runs",
            first.effect.name(),
            first.driver
        );
        for x in &d.extrapolation {
            let _ = writeln!(
                out,
                "  {:<4} {:<32} {:>3} runs  held-out rms without {:>8.1} -> with {:>8.1}  {}",
                x.channel, x.held_out, x.runs, x.rms_without, x.rms_with, x.outcome
            );
        }
        if let Some(words) = crate::method::diagnose::extrapolate::summary(&d.extrapolation) {
            let _ = writeln!(out, "  {words}.");
        }
    }
}

/// The conditions the design moves together, whatever the fits chose.
fn design_confounding(out: &mut String, d: &Diagnosis) {
    for c in &d.confounding.design {
        let [a, b] = c.conditions;
        let chose = if c.selected.is_empty() {
            String::new()
        } else {
            let names: Vec<&str> = c.selected.iter().map(|e| e.name()).collect();
            format!(
                " The fit chose {}; the other explains the same runs, so it was not claimed.",
                names.join(", ")
            )
        };
        let _ = writeln!(
            out,
            "  Design: {} and {} move together across the {} runs (r = {:.2}): the data cannot tell {}.{} To separate them: {}.",
            a.name(),
            b.name(),
            c.runs,
            c.run_correlation,
            c.cannot_tell_apart,
            chose,
            c.separating_experiment
        );
    }
}

/// Runs shown at each end of the run order.
const RUNS_SHOWN: usize = 4;

/// The remaining residual per run, in run order, with its trend.
fn over_runs(out: &mut String, d: &Diagnosis) {
    for c in &d.remaining_over_runs {
        let _ = writeln!(
            out,
            "  {} over the run order (measured force / model's - 1, per run; mean residual [{}]):",
            c.channel, c.unit
        );
        let shown: Vec<String> = c
            .runs
            .iter()
            .enumerate()
            .filter(|(k, _)| *k < RUNS_SHOWN || *k + RUNS_SHOWN >= c.runs.len())
            .map(|(k, r)| {
                let scale = r
                    .force_scale
                    .map(|s| format!("{:+.1}%", 100.0 * s))
                    .unwrap_or_else(|| "-".into());
                let gap = if k == RUNS_SHOWN && c.runs.len() > 2 * RUNS_SHOWN {
                    " ..."
                } else {
                    ""
                };
                format!("{gap} run {} {scale} ({:+.1})", r.run, r.mean)
            })
            .collect();
        let _ = writeln!(out, "    {}", shown.join(","));
        match (&c.trend, &c.no_trend) {
            (Some(t), _) => {
                let _ = writeln!(
                    out,
                    "    trend: {:+.1}% of force from the first run to the last over {} runs (r = {:.2}, p = {}){}",
                    100.0 * t.change,
                    t.runs,
                    t.correlation,
                    p_text(Some(t.p_value)),
                    if t.significant {
                        ": a drift over the programme (wear, rig or tire warm-up)"
                    } else {
                        ": no significant drift"
                    }
                );
            }
            (None, Some(why)) => {
                let _ = writeln!(out, "    trend: not judged: {why}");
            }
            (None, None) => {}
        }
    }
}

/// Blocks listed in the terminal report (the JSON lists all).
const BLOCKS_SHOWN: usize = 120;

/// The test blocks with their conditions and folds, and the held-out blocks outside
/// their training conditions.
fn blocks_text(out: &mut String, d: &Diagnosis, context: &Context) {
    let r = blocks_report(d, context);
    let _ = writeln!(
        out,
        "Test blocks: {} runs, each one block (medians; folds dealt by condition level)",
        r.blocks.len()
    );
    let _ = writeln!(
        out,
        "  {:>8} {:<18} {:>6} {:>17} {:<5} {:>7} {:>7} {:>7} {:>6} {:<14} {:>4}",
        "run",
        "file",
        "rows",
        "time [s]",
        "swept",
        "Fz [N]",
        "p [kPa]",
        "camber",
        "V [m/s]",
        "held slip",
        "fold"
    );
    for b in r.blocks.iter().take(BLOCKS_SHOWN) {
        block_line(out, b);
    }
    if r.blocks.len() > BLOCKS_SHOWN {
        let _ = writeln!(
            out,
            "  ... {} more (the JSON report lists every block)",
            r.blocks.len() - BLOCKS_SHOWN
        );
    }
    if r.not_covered.is_empty() {
        let _ = writeln!(
            out,
            "  Every held-out block lies within the conditions its training blocks cover."
        );
    } else {
        let _ = writeln!(
            out,
            "  Held-out blocks outside their training conditions (scored, but their error \
             there is an extrapolation, not a gap):"
        );
        for x in &r.not_covered {
            let _ = writeln!(out, "    - {}", x.text);
        }
    }
    let _ = writeln!(out);
}

/// `v` with `p` decimals, without a sign on a value that rounds to zero.
fn fixed(v: f64, p: usize) -> String {
    let s = format!("{v:.p$}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

/// [`fixed`], or `-` when there is no value.
fn opt(v: Option<f64>, p: usize) -> String {
    v.map_or_else(|| "-".to_string(), |v| fixed(v, p))
}

/// One row of the test-block table.
fn block_line(out: &mut String, b: &BlockRow) {
    let held = match (b.held_alpha_deg, b.held_kappa, b.swept) {
        (Some(a), _, "kappa") => format!("alpha {}", fixed(a, 2)),
        (_, Some(k), _) => format!("kappa {}", fixed(k, 3)),
        (Some(a), None, _) => format!("alpha {}", fixed(a, 2)),
        _ => "-".to_string(),
    };
    let _ = writeln!(
        out,
        "  {:>8} {:<18} {:>6} {:>17} {:<5} {:>7.0} {:>7} {:>7} {:>6} {:<14} {:>4}",
        b.run,
        b.file.as_deref().unwrap_or("-"),
        b.rows,
        b.t_s
            .map_or_else(|| "-".to_string(), |[a, z]| format!("{a:.1}..{z:.1}")),
        b.swept,
        b.fz_n,
        opt(b.p_kpa, 1),
        opt(b.camber_deg, 2),
        opt(b.speed_mps, 2),
        held,
        b.fold.map_or_else(|| "-".to_string(), |f| f.to_string())
    );
}
