//! The JSON report: its schema (the serialized structs) and how it is built.

use std::collections::BTreeMap;

use mf87::Channel;
use serde::Serialize;

use super::{Context, OutputStatus, Provenance};
use crate::method::diagnose::{ChannelTrial, Diagnosis, Trial};
use crate::method::fit::effects::Extension;

/// One entry of the `effects` list: a candidate tested against the base model (round 1).
#[derive(Debug, Clone, Serialize)]
pub struct EffectEntry {
    pub effect: Extension,
    pub form: &'static str,
    /// Held-out RMS per channel without and with the effect [N or N.m].
    pub heldout_before: BTreeMap<&'static str, f64>,
    pub heldout_after: BTreeMap<&'static str, f64>,
    /// Fraction of the gap above the noise floor closed, on the channel where it helps most;
    /// `null` when no channel it acts on has a measurable gap.
    pub gap_closed: Option<f64>,
    /// Per channel; `null` where the channel has no measurable gap (`not_scored` says why).
    pub gap_closed_by_channel: BTreeMap<&'static str, Option<f64>>,
    pub not_scored: BTreeMap<&'static str, String>,
    /// Per channel where it was screened out (not refitted per fold), why.
    pub screened: BTreeMap<&'static str, String>,
    /// Significant against the base model (Holm-corrected sign-flip test plus minimum gains).
    pub significant: bool,
    /// Whether forward selection kept it (see `verdict`).
    pub selected: bool,
    pub p_adjusted: BTreeMap<&'static str, Option<f64>>,
    /// Fitted effect parameters on all data, per channel.
    pub params: BTreeMap<String, f64>,
}

fn by_channel<T>(trial: &Trial, f: impl Fn(&ChannelTrial) -> T) -> BTreeMap<&'static str, T> {
    trial
        .channels
        .iter()
        .map(|c| (c.channel.name(), f(c)))
        .collect()
}

fn entry(trial: &Trial, verdict: &[Extension]) -> EffectEntry {
    EffectEntry {
        effect: trial.effect,
        form: trial.form,
        heldout_before: by_channel(trial, |c| c.heldout_before),
        heldout_after: by_channel(trial, |c| c.heldout_after),
        gap_closed: trial
            .channels
            .iter()
            .filter_map(|c| c.gap_closed)
            .reduce(f64::max),
        gap_closed_by_channel: by_channel(trial, |c| c.gap_closed),
        not_scored: trial
            .channels
            .iter()
            .filter_map(|c| Some((c.channel.name(), c.not_scored.clone()?)))
            .collect(),
        screened: trial
            .channels
            .iter()
            .filter_map(|c| Some((c.channel.name(), c.screened.clone()?)))
            .collect(),
        significant: trial.significant,
        selected: verdict.contains(&trial.effect),
        p_adjusted: by_channel(trial, |c| c.p_adjusted),
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
    pub notes: &'a [String],
    pub limitations: &'a [crate::method::prepare::adequacy::Limitation],
    pub outputs: &'a [OutputStatus],
    pub rows: usize,
    pub runs: usize,
    pub blocks: BlocksReport,
    pub baseline: &'a [crate::method::diagnose::ChannelBaseline],
    pub regions: &'a [crate::method::diagnose::regions::Region],
    pub effects: Vec<EffectEntry>,
    pub verdict: Vec<&'static str>,
    /// The claimed effects with where their held-out gain lies (split by their driver's
    /// activity), per channel.
    pub claims: &'a [crate::method::diagnose::Claim],
    /// Candidates that passed every rule but their signature: not claimed, with where their
    /// gain lies.
    pub signature_refusals: &'a [crate::method::diagnose::SignatureRefusal],
    pub stability: &'a Option<crate::method::diagnose::Stability>,
    pub confounding: &'a crate::method::diagnose::Confounding,
    pub untestable: &'a [crate::method::diagnose::Untestable],
    pub remaining: &'a [crate::method::diagnose::ChannelBaseline],
    pub remaining_regions: &'a [crate::method::diagnose::regions::Region],
    /// The channels whose remaining gap no selected effect explains (still measurable).
    pub gap_unexplained: Vec<Channel>,
    pub remaining_over_runs: &'a [crate::method::diagnose::run_order::ResidualOverRuns],
    pub extrapolation: &'a [crate::method::diagnose::extrapolate::Extrapolation],
    /// Per channel: the held-out error of the 1987 model, of the verdict's model, of a complete
    /// MF 6.1 fitted on the same folds, and the per-sweep floor.
    pub ceiling: &'a [crate::method::diagnose::reference::Ceiling],
    pub rounds: &'a [crate::method::diagnose::Round],
    pub nominal: &'a crate::method::fit::effects::Nominal,
    pub options: &'a crate::method::diagnose::Options,
}

/// The `effects` list: every candidate tested in the first round, best first.
pub fn effect_entries(d: &Diagnosis) -> Vec<EffectEntry> {
    d.rounds
        .first()
        .map(|r| r.trials.iter().map(|t| entry(t, &d.verdict)).collect())
        .unwrap_or_default()
}

pub fn json(d: &Diagnosis, context: &Context) -> String {
    let report = JsonReport {
        provenance: &context.provenance,
        notes: &context.notes,
        limitations: &d.limitations,
        outputs: &context.outputs,
        rows: d.rows,
        runs: d.runs,
        blocks: blocks_report(d, context),
        baseline: &d.baseline,
        regions: &d.regions,
        effects: effect_entries(d),
        verdict: d.verdict.iter().map(|e| e.name()).collect(),
        claims: &d.claims,
        signature_refusals: &d.signature_refusals,
        stability: &d.stability,
        confounding: &d.confounding,
        untestable: &d.untestable,
        remaining: &d.remaining,
        remaining_regions: &d.remaining_regions,
        gap_unexplained: d.remaining_over_runs.iter().map(|r| r.channel).collect(),
        remaining_over_runs: &d.remaining_over_runs,
        extrapolation: &d.extrapolation,
        ceiling: &d.ceiling,
        rounds: &d.rounds,
        nominal: &d.nominal,
        options: &d.options,
    };
    serde_json::to_string_pretty(&report).expect("the report serializes")
}

// Test blocks: the runs with their conditions and folds, and the held-out blocks outside
// their training conditions.

/// The `blocks` entry of the JSON report.
#[derive(Debug, Clone, Serialize)]
pub struct BlocksReport {
    /// Every run (test block) in order of first appearance.
    pub blocks: Vec<BlockRow>,
    /// Held-out blocks outside the conditions of their training blocks (see `cv`).
    pub not_covered: Vec<NotCoveredRow>,
}

/// One test block: medians of its set conditions in the units the names give.
#[derive(Debug, Clone, Serialize)]
pub struct BlockRow {
    pub run: i64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    pub rows: usize,
    /// First and last row of the data set holding it (0-based).
    pub first_row: usize,
    pub last_row: usize,
    /// Time at its first and last row.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_s: Option<[f64; 2]>,
    /// The slip it sweeps: `alpha`, `kappa`, `both` or `none`.
    pub swept: &'static str,
    pub fz_n: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p_kpa: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub camber_deg: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_mps: Option<f64>,
    /// The slip angle or slip ratio it holds (the one it does not sweep).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_alpha_deg: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_kappa: Option<f64>,
    /// The fold holding it out (1-based); absent when it has no loaded row.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fold: Option<usize>,
}

/// A held-out block outside its training conditions, levels in `unit`.
#[derive(Debug, Clone, Serialize)]
pub struct NotCoveredRow {
    pub run: i64,
    /// 1-based.
    pub fold: usize,
    pub condition: &'static str,
    pub unit: &'static str,
    pub level: f64,
    /// The training blocks' range; absent when no training block has the condition.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub training_min: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub training_max: Option<f64>,
    pub text: String,
}

fn file_of(run: i64, context: &Context) -> Option<String> {
    let f = context
        .provenance
        .inputs
        .iter()
        .find(|f| f.runs.contains(&run))?;
    Some(
        std::path::Path::new(&f.file)
            .file_name()
            .map_or_else(|| f.file.clone(), |n| n.to_string_lossy().into_owned()),
    )
}

pub fn blocks_report(d: &Diagnosis, context: &Context) -> BlocksReport {
    let deg = mf87::units::radians_to_degrees::<f64>;
    BlocksReport {
        blocks: d
            .blocks
            .iter()
            .map(|b| BlockRow {
                run: b.run,
                file: file_of(b.run, context),
                rows: b.rows,
                first_row: b.first_row,
                last_row: b.last_row,
                t_s: b.time,
                swept: b.swept.name(),
                fz_n: b.load,
                p_kpa: b.pressure,
                camber_deg: b.camber.map(deg),
                speed_mps: b.speed,
                held_alpha_deg: b.held_slip_angle.map(deg),
                held_kappa: b.held_slip_ratio,
                fold: b.fold.map(|f| f + 1),
            })
            .collect(),
        not_covered: d
            .not_covered
            .iter()
            .map(|x| {
                let c = x.condition;
                NotCoveredRow {
                    run: x.run,
                    fold: x.fold + 1,
                    condition: c.name(),
                    unit: c.shown_unit(),
                    level: c.shown(x.level),
                    training_min: x.training.map(|r| c.shown(r[0])),
                    training_max: x.training.map(|r| c.shown(r[1])),
                    text: x.describe(),
                }
            })
            .collect(),
    }
}
