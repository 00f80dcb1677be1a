//! Which candidates can be tested: each (effect, channel) pair where the effect acts on the
//! channel, the channel has a measurable gap, and the data has what the effect needs.

use mf87::Channel;

use super::state::ChannelState;
use super::{ChannelBaseline, Options, Untestable};
use crate::data::{Dataset, Quantity};
use crate::method::diagnose::design;
use crate::method::fit::effects::{self, Extension};
use crate::method::prepare::programme::{self, Block};
use mf87::ConditionVar;

/// A candidate effect on one channel; `channel` is the channel's position among the states.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Pair {
    pub(super) effect: Extension,
    pub(super) channel: usize,
}

/// The pairs to test, and the effects with none, with why.
pub(super) struct Testable {
    pub(super) pairs: Vec<Pair>,
    pub(super) untestable: Vec<Untestable>,
}

/// Every pair that can be tested, effects in `Extension::ALL` order, channels in the states'
/// order; `baseline` is the states' base error summary. Effects left out of
/// `options.effects` are untestable.
pub(super) fn testable_pairs(
    ds: &Dataset,
    blocks: &[Block],
    states: &[ChannelState],
    baseline: &[ChannelBaseline],
    options: &Options,
) -> Testable {
    let mut untestable = Vec::new();
    let mut pairs: Vec<Pair> = Vec::new();
    for effect in Extension::ALL {
        if let Some(asked) = &options.effects
            && !asked.contains(&effect)
        {
            untestable.push(Untestable {
                effect,
                reason: "not among the candidate effects asked for".to_string(),
            });
            continue;
        }
        let mut reasons = Vec::new();
        for (ci, state) in states.iter().enumerate() {
            let ch = state.data.channel;
            if !effect.applies_to(ch) {
                continue;
            }
            if baseline[ci].no_gap.is_some() {
                reasons.push(format!("{ch}: no measurable gap above the noise floor"));
                continue;
            }
            match untestable_reason(ds, blocks, effect, ch) {
                None => pairs.push(Pair {
                    effect,
                    channel: ci,
                }),
                Some(r) => reasons.push(format!("{ch}: {r}")),
            }
        }
        if !pairs.iter().any(|p| p.effect == effect) {
            let reason = if reasons.is_empty() {
                "none of the channels it acts on is measured".to_string()
            } else {
                reasons.join("; ")
            };
            untestable.push(Untestable { effect, reason });
        }
    }
    Testable { pairs, untestable }
}

/// Whether a column varies enough to test an effect driven by it.
fn varies(ds: &Dataset, q: Quantity) -> bool {
    let Some(v) = ds.column(q) else { return false };
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(*x), hi.max(*x))
        });
    hi - lo > 1e-6 * hi.abs().max(1.0)
}

/// The column of the operating condition an effect depends on, if any.
fn driver_column(effect: Extension) -> Option<Quantity> {
    Some(match effect.condition()? {
        ConditionVar::Speed => Quantity::Speed,
        ConditionVar::Pressure => Quantity::Pressure,
        ConditionVar::Temperature => Quantity::Temperature,
    })
}

/// Why `effect` cannot be tested on `channel` with this data, if it cannot: a column it needs
/// is missing or constant, the test plan (`blocks`) does not move a slip it needs (no block
/// sweeps it or steps it: a noisy channel is no driver), the camber it needs spreads too
/// little across the runs, or the condition it depends on varies too little across the runs
/// to be told from a constant ([`design::Spread::identifiable`]).
fn untestable_reason(
    ds: &Dataset,
    blocks: &[Block],
    effect: Extension,
    channel: Channel,
) -> Option<String> {
    for q in effects::of(effect).needs(channel) {
        if !ds.has(*q) {
            return Some(format!("no {} column", q.name()));
        }
        if *q != Quantity::Time && !varies(ds, *q) {
            return Some(format!("{} does not vary in the data", q.name()));
        }
        if matches!(q, Quantity::Alpha | Quantity::Kappa) && !programme::moves(blocks, *q) {
            return Some(format!(
                "the test plan does not move {}: no test block sweeps it or holds it at levels \
                 a sweep apart, so what the channel reads is an offset and noise, not a driver",
                q.name()
            ));
        }
        if *q == Quantity::Gamma
            && let Some(s) = design::spread(ds, design::Condition::Camber)
            && !s.identifiable()
        {
            return Some(s.reason());
        }
    }
    let spread = driver_column(effect)
        .and_then(design::condition_of)
        .and_then(|c| design::spread(ds, c))?;
    (!spread.identifiable()).then(|| spread.reason())
}

/// How the test plan (`blocks`) moves what drives `effect` on `channel`, in words, and
/// whether it moves it enough for a claim: each slip it needs swept in some block (or held at
/// levels a sweep apart), each condition it needs spread across the runs as the
/// identifiability rule asks; for an effect that needs neither (the shifts), the channel's
/// own slip swept.
pub(super) fn plan_of(
    ds: &Dataset,
    blocks: &[Block],
    effect: Extension,
    channel: Channel,
) -> (String, bool) {
    let own = match channel {
        Channel::Fx => Quantity::Kappa,
        Channel::Fy | Channel::Mz => Quantity::Alpha,
    };
    // What drives it: the slips and camber it needs and its own operating condition, not a
    // column it needs for something else (the speed that turns time into distance).
    let condition = driver_column(effect);
    let needs: Vec<Quantity> = effects::of(effect)
        .needs(channel)
        .iter()
        .copied()
        .filter(|q| {
            matches!(q, Quantity::Alpha | Quantity::Kappa | Quantity::Gamma)
                || Some(*q) == condition
        })
        .collect();
    let needs = if needs.is_empty() { vec![own] } else { needs };
    let mut words = Vec::new();
    let mut moves = true;
    for q in needs {
        match q {
            Quantity::Alpha | Quantity::Kappa => {
                let swept = blocks
                    .iter()
                    .filter(|b| programme::sweeps(std::slice::from_ref(*b), q))
                    .count();
                let moved = programme::moves(blocks, q);
                moves &= moved;
                words.push(format!(
                    "{} swept in {swept} of {} blocks{}",
                    q.name(),
                    blocks.len(),
                    match (moved, swept) {
                        (false, _) => " (not moved)",
                        (true, 0) => ", held at levels a sweep apart",
                        (true, _) => "",
                    }
                ));
            }
            q => match design::condition_of(q).and_then(|c| design::spread(ds, c)) {
                Some(s) => {
                    moves &= s.identifiable();
                    let (unit, scale) = match q {
                        Quantity::Gamma => ("deg", mf87::units::radians_to_degrees(1.0)),
                        q => (q.unit(), 1.0),
                    };
                    words.push(format!(
                        "{} levels {:.1} to {:.1} {unit} over {} runs{}",
                        q.name(),
                        s.p10 * scale,
                        s.p90 * scale,
                        s.runs,
                        if s.identifiable() { "" } else { " (not moved)" }
                    ));
                }
                None => {
                    moves = false;
                    words.push(format!("no {}", q.name()));
                }
            },
        }
    }
    (words.join("; "), moves)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 20 runs of 50 rows; `speed(run)` per run, pressure two levels.
    fn programme(speed: impl Fn(i64) -> f64) -> Dataset {
        let run: Vec<i64> = (0..1000).map(|i| i / 50).collect();
        let col = |f: &dyn Fn(i64) -> f64| -> Option<crate::data::Column> {
            Some(run.iter().map(|&r| f(r)).collect())
        };
        Dataset {
            source: "pairs test".into(),
            fz: run
                .iter()
                .map(|&r| 3000.0 + 100.0 * (r % 4) as f64)
                .collect(),
            speed: col(&speed),
            pressure: col(&|r| if r % 2 == 0 { 180.0 } else { 220.0 }),
            time: col(&|r| r as f64),
            run: run.into(),
            ..Dataset::default()
        }
    }

    #[test]
    fn a_claims_plan_names_what_drives_it_and_how_the_blocks_move_it() {
        // Drive/brake sweeps (slip ratio -0.2 to 0.2 in every run) at slip angles held at 0,
        // 2, 4 and 6 deg from run to run.
        let mut ds = programme(|_| 11.0);
        let n = ds.len();
        ds.kappa = Some((0..n).map(|i| ((i % 50) as f64 - 25.0) * 0.008).collect());
        ds.alpha = Some(
            ds.run
                .iter()
                .map(|r| (2.0 * (r % 4) as f64).to_radians())
                .collect(),
        );
        let blocks = programme::blocks(&ds);
        let (plan, moves) = plan_of(&ds, &blocks, Extension::CombinedSlip, Channel::Fx);
        assert!(moves, "{plan}");
        assert_eq!(
            plan,
            "alpha swept in 0 of 20 blocks, held at levels a sweep apart"
        );
        // Relaxation needs speed to turn time into distance; its driver is the slip's change.
        let (plan, moves) = plan_of(&ds, &blocks, Extension::RelaxationLength, Channel::Fx);
        assert!(moves && plan == "kappa swept in 20 of 20 blocks", "{plan}");
        // One slip angle throughout: not moved.
        ds.alpha = Some(vec![0.01; n].into());
        let blocks = programme::blocks(&ds);
        let (plan, moves) = plan_of(&ds, &blocks, Extension::CombinedSlip, Channel::Fx);
        assert!(!moves && plan.ends_with("(not moved)"), "{plan}");
    }

    #[test]
    fn speed_effects_are_untestable_on_a_constant_speed_programme() {
        // 40.0 to 40.4 km/h: the rig's wander around one set point.
        let ds = programme(|r| (40.0 + 0.02 * r as f64) / 3.6);
        for effect in [Extension::SpeedDependence, Extension::RollingResistance] {
            let why = untestable_reason(&ds, &[], effect, Channel::Fx).unwrap();
            assert!(why.contains("speed barely varies"), "{effect}: {why}");
        }
        // Pressure varies by 40 kPa: testable. Relaxation uses speed only for distance.
        assert_eq!(
            untestable_reason(&ds, &[], Extension::InflationPressure, Channel::Fy),
            None
        );
        assert_eq!(
            untestable_reason(&ds, &[], Extension::RelaxationLength, Channel::Fy),
            None
        );
        // Speeds of 5 to 25 m/s: testable.
        let ds = programme(|r| 5.0 + r as f64);
        assert_eq!(
            untestable_reason(&ds, &[], Extension::SpeedDependence, Channel::Fy),
            None
        );
    }
}
