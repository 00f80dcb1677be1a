//! Which candidates can be tested: each (effect, channel) pair where the effect acts on the
//! channel, the channel has a measurable gap, and the data has what the effect needs.

use mf87::Channel;

use super::state::ChannelState;
use super::{ChannelBaseline, Options, Untestable};
use crate::data::{Dataset, Quantity};
use crate::method::diagnose::design;
use crate::method::fit::effects::{self, Extension};
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
            match untestable_reason(ds, effect, ch) {
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
/// is missing or constant, or the condition it depends on varies too little across the runs
/// to be told from a constant ([`design::Spread::identifiable`]).
fn untestable_reason(ds: &Dataset, effect: Extension, channel: Channel) -> Option<String> {
    for q in effects::of(effect).needs(channel) {
        if !ds.has(*q) {
            return Some(format!("no {} column", q.name()));
        }
        if *q != Quantity::Time && !varies(ds, *q) {
            return Some(format!("{} does not vary in the data", q.name()));
        }
    }
    let spread = driver_column(effect)
        .and_then(design::condition_of)
        .and_then(|c| design::spread(ds, c))?;
    (!spread.identifiable()).then(|| spread.reason())
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
    fn speed_effects_are_untestable_on_a_constant_speed_programme() {
        // 40.0 to 40.4 km/h: the rig's wander around one set point.
        let ds = programme(|r| (40.0 + 0.02 * r as f64) / 3.6);
        for effect in [Extension::SpeedDependence, Extension::RollingResistance] {
            let why = untestable_reason(&ds, effect, Channel::Fx).unwrap();
            assert!(why.contains("speed barely varies"), "{effect}: {why}");
        }
        // Pressure varies by 40 kPa: testable. Relaxation uses speed only for distance.
        assert_eq!(
            untestable_reason(&ds, Extension::InflationPressure, Channel::Fy),
            None
        );
        assert_eq!(
            untestable_reason(&ds, Extension::RelaxationLength, Channel::Fy),
            None
        );
        // Speeds of 5 to 25 m/s: testable.
        let ds = programme(|r| 5.0 + r as f64);
        assert_eq!(
            untestable_reason(&ds, Extension::SpeedDependence, Channel::Fy),
            None
        );
    }
}
