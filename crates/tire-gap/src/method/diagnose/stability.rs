//! Stability of the verdict over re-drawn fold assignments. Which runs a fold holds out is
//! chance; an effect whose selection hangs on it is not established. Forward selection runs on
//! `stability_draws` fixed assignments of runs to folds (split seeds 1, 2, ..., whatever
//! `--seed` is) and an effect enters the verdict only if most of them (more than half) select
//! it. Assignments are drawn in order until the ones left could not change the verdict (with
//! 3, two that select the same effects settle it). The verdict is therefore the same for every
//! `--seed`: the seed picks the assignment whose rounds, held-out errors and figures the report
//! shows (the primary; when it is one of the draws, that draw). Effects selected in some draws
//! only are reported as unstable, with their share. The final model holds the verdict's effects: the primary's when it selected exactly
//! those, else the verdict's effects fitted anew on the primary's folds, each on the channels
//! where a draw that selected it added it.

use serde::Serialize;

use super::Options;
use super::base::refold;
use super::candidate::fit_candidate;
use super::pairs::Pair;
use super::plausibility::Plausibility;
use super::selection::{FullFits, Selection, select};
use super::state::ChannelState;
use crate::method::diagnose::design::DesignConfounding;
use crate::method::fit::effects::Extension;
use crate::method::observer::Observer;
use crate::method::prepare::cv::Folds;

/// What the draws selected.
#[derive(Debug, Clone, Serialize)]
pub struct Stability {
    /// The split seed of each draw made.
    pub seeds: Vec<u64>,
    /// The draws the majority is counted over (`seeds` may stop short: see the rule).
    pub planned: usize,
    /// Each draw's selections, in order.
    pub selected: Vec<Vec<Extension>>,
    /// Every effect selected in some draw, with how many selected it.
    pub effects: Vec<EffectStability>,
    /// The rule, in words.
    pub rule: String,
}

/// One effect over the draws.
#[derive(Debug, Clone, Serialize)]
pub struct EffectStability {
    pub effect: Extension,
    pub selected_in: usize,
    pub draws: usize,
    /// Selected in more than half of the planned draws: in the verdict.
    pub stable: bool,
}

/// The split seeds of the draws.
pub(super) fn draw_seeds(options: &Options) -> Vec<u64> {
    (1..=options.stability_draws.max(1) as u64).collect()
}

/// A selection, its verdict, and its stability over fold assignments (when drawn).
pub(super) type Selected = (Selection, Vec<Extension>, Option<Stability>);

/// Forward selection on the primary assignment `folds` and on every draw; returns the
/// primary's selection with its states holding the verdict's effects, the verdict, and the
/// draws' record (`None` with a single draw: the primary's selection is the verdict).
#[allow(clippy::too_many_arguments)]
pub(super) fn select_stably(
    base: Vec<ChannelState>,
    pairs: Vec<Pair>,
    folds: &Folds,
    new_folds: impl Fn(u64) -> Folds,
    options: &Options,
    design: &[DesignConfounding],
    plausibility: &Plausibility,
    observer: &dyn Observer,
) -> Selected {
    let seeds = draw_seeds(options);
    let mut fulls = FullFits::new();
    let primary = select(
        base.clone(),
        pairs.clone(),
        &mut fulls,
        folds,
        options,
        design,
        plausibility,
        options.candidate_figures,
        observer,
    );
    if options.stability_draws <= 1 {
        let verdict = primary.verdict.clone();
        return (primary, verdict, None);
    }
    // Each draw's selections, with the channels each effect was added on; drawn until the
    // draws left could not change the verdict.
    let planned = seeds.len();
    let mut draws: Vec<Vec<(Extension, Vec<usize>)>> = Vec::new();
    let mut other_rounds = Vec::new();
    for &seed in &seeds {
        if decided(&draws, planned) || observer.cancelled() {
            break;
        }
        if seed == folds.seed {
            draws.push(primary.adopted.clone());
            continue;
        }
        let f = new_folds(seed);
        let states = refold(&base, &f, plausibility, observer);
        let s = select(
            states,
            pairs.clone(),
            &mut fulls,
            &f,
            options,
            design,
            plausibility,
            false,
            observer,
        );
        draws.push(s.adopted);
        other_rounds.push((seed, s.rounds));
    }
    let seeds = &seeds[..draws.len()];
    let (verdict, stability) = record(&primary.verdict, &draws, seeds, planned);
    let mut primary = primary;
    primary.other_rounds = other_rounds;
    if primary.verdict != verdict {
        primary.states = with_effects(
            base,
            &verdict,
            &primary.adopted,
            &draws,
            folds,
            plausibility,
        );
    }
    (primary, verdict, Some(stability))
}

/// The verdict (the effects more than half of the `planned` draws select) and the record
/// of the draws made with split `seeds`; effects in order of first selection, the
/// primary's (`primary_verdict`) then the draws'.
fn record(
    primary_verdict: &[Extension],
    draws: &[Vec<(Extension, Vec<usize>)>],
    seeds: &[u64],
    planned: usize,
) -> (Vec<Extension>, Stability) {
    let mut order: Vec<Extension> = primary_verdict.to_vec();
    for d in draws {
        for (e, _) in d {
            if !order.contains(e) {
                order.push(*e);
            }
        }
    }
    let effects: Vec<EffectStability> = order
        .iter()
        .map(|&effect| {
            let selected_in = selected_in(draws, effect);
            EffectStability {
                effect,
                selected_in,
                draws: draws.len(),
                stable: 2 * selected_in > planned,
            }
        })
        .collect();
    let verdict: Vec<Extension> = effects
        .iter()
        .filter(|e| e.stable)
        .map(|e| e.effect)
        .collect();
    let stability = Stability {
        seeds: seeds.to_vec(),
        planned,
        selected: draws
            .iter()
            .map(|d| d.iter().map(|(e, _)| *e).collect())
            .collect(),
        effects,
        rule: format!(
            "forward selection on up to {planned} assignments of runs to folds; an effect \
             enters the verdict only if more than half of the {planned} select it, and \
             assignments are drawn only until the rest could not change that (here {}: split \
             seeds {})",
            seeds.len(),
            seeds
                .iter()
                .map(u64::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    (verdict, stability)
}

/// How many of `draws` selected `effect`.
fn selected_in(draws: &[Vec<(Extension, Vec<usize>)>], effect: Extension) -> usize {
    draws
        .iter()
        .filter(|d| d.iter().any(|(e, _)| *e == effect))
        .count()
}

/// Whether the verdict over `planned` draws is settled by `draws`: every effect selected so
/// far is already in more than half of them or can no longer get there, and one not yet
/// selected could not get there in the draws left.
fn decided(draws: &[Vec<(Extension, Vec<usize>)>], planned: usize) -> bool {
    let left = planned - draws.len().min(planned);
    let settled = |n: usize| 2 * n > planned || 2 * (n + left) <= planned;
    settled(0)
        && draws
            .iter()
            .flatten()
            .all(|(e, _)| settled(selected_in(draws, *e)))
}

/// The base states with `verdict`'s effects added in order, each fitted on `folds` on the
/// channels where the primary (`adopted`), else the first draw that selected it, added it.
fn with_effects(
    mut states: Vec<ChannelState>,
    verdict: &[Extension],
    adopted: &[(Extension, Vec<usize>)],
    draws: &[Vec<(Extension, Vec<usize>)>],
    folds: &Folds,
    plausibility: &Plausibility,
) -> Vec<ChannelState> {
    for &e in verdict {
        let channels = std::iter::once(adopted)
            .chain(draws.iter().map(Vec::as_slice))
            .find_map(|d| d.iter().find(|(x, _)| *x == e))
            .map(|(_, c)| c.clone())
            .unwrap_or_default();
        for ci in channels {
            if let Some(fit) = fit_candidate(&states[ci], e, folds, plausibility) {
                let s = &mut states[ci];
                s.full = fit.full;
                if let Some(models) = fit.fold_models {
                    s.fold_models = models;
                }
                if let Some(r) = fit.residuals {
                    s.residuals = r;
                }
            }
        }
    }
    states
}

#[cfg(test)]
mod tests {
    use super::*;
    use Extension::*;

    fn draw(effects: &[Extension]) -> Vec<(Extension, Vec<usize>)> {
        effects.iter().map(|e| (*e, vec![0])).collect()
    }

    #[test]
    fn draws_stop_once_the_majority_is_settled() {
        // Nothing drawn yet: an effect could still be selected by all.
        assert!(!decided(&[], 3));
        // Two of three agree: the third cannot change the verdict.
        let agree = [draw(&[CombinedSlip]), draw(&[CombinedSlip])];
        assert!(decided(&agree, 3));
        assert!(decided(&[draw(&[]), draw(&[])], 3));
        // They disagree on one effect: the third decides it.
        let split = [draw(&[CombinedSlip, Temperature]), draw(&[CombinedSlip])];
        assert!(!decided(&split, 3));
        assert!(decided(&[split[0].clone(), split[1].clone(), draw(&[])], 3));
        // Out of five, two agreeing draws settle nothing: three more could select another.
        assert!(!decided(&agree, 5));
        // One draw is its own majority.
        assert!(decided(&[draw(&[Temperature])], 1));
        assert_eq!(selected_in(&split, CombinedSlip), 2);
        assert_eq!(selected_in(&split, Temperature), 1);
    }
}
