//! The method on synthetic rig data in which an effect is present but withheld from the
//! model: the diagnosis must name it on its own, close the held-out gap, and stay silent
//! when nothing is there. The data's effects use other forms than the candidates (see
//! `synth`), and every dataset varies every channel.

use mf87::Channel;
use tire_gap::data::Dataset;
use tire_gap::io::report::{self, Context, Provenance};
use tire_gap::method::diagnose::design::Condition;
use tire_gap::method::diagnose::{Diagnosis, Options, diagnose};
use tire_gap::method::fit::effects::Extension;
use tire_gap::method::observer::Unobserved;
use tire_gap::synth::{
    DrawnCondition, Forms, SynthConfig, TireKind, generate, generate_with_truth,
};

/// Rows per dataset: smaller than the 35k default to keep the suite quick.
const ROWS: usize = 20_000;

fn run(effects: &[Extension], tire: TireKind, seed: u64) -> Diagnosis {
    run_noisy(effects, tire, seed, 1.0)
}

/// As `run`, with the sensor noise scaled by `noise`.
fn run_noisy(effects: &[Extension], tire: TireKind, seed: u64, noise: f64) -> Diagnosis {
    let cfg = SynthConfig {
        seed,
        effects: effects.to_vec(),
        tire,
        rows_target: ROWS,
        noise,
        ..SynthConfig::default()
    };
    let ds = generate(&cfg);
    claims_cover_the_verdict(
        diagnose(&ds, &Options::default(), &Unobserved).expect("diagnosis runs"),
    )
}

/// Every effect of the verdict carries a claim with its signature, from a fold assignment that
/// selected it, on a driver the plan moves; `d` back.
fn claims_cover_the_verdict(d: Diagnosis) -> Diagnosis {
    for e in &d.verdict {
        let claims: Vec<_> = d.claims.iter().filter(|c| c.effect == *e).collect();
        assert!(!claims.is_empty(), "{e} in the verdict without a claim");
        for c in claims {
            assert!(c.plan_moves, "{e}: {}", c.plan);
            if let (Some(seed), Some(s)) = (c.seed, &d.stability) {
                assert!(
                    s.seeds.contains(&seed) && seed != d.options.seed,
                    "{e}: seed {seed}"
                );
            }
        }
    }
    for c in &d.claims {
        assert!(
            d.verdict.contains(&c.effect),
            "{} claimed outside the verdict",
            c.effect
        );
    }
    d
}

/// As `run` on the mf52 tire, with a programme whose `coupled` conditions move together
/// across runs and whose tire loses `drift` of its force from the first run to the last.
fn run_programme(
    effects: &[Extension],
    seed: u64,
    coupled: Option<[DrawnCondition; 2]>,
    drift: f64,
) -> Diagnosis {
    let ds = generate(&SynthConfig {
        seed,
        effects: effects.to_vec(),
        tire: TireKind::Mf52,
        rows_target: ROWS,
        coupled,
        drift,
        ..SynthConfig::default()
    });
    claims_cover_the_verdict(
        diagnose(&ds, &Options::default(), &Unobserved).expect("diagnosis runs"),
    )
}

/// The report's context for synthetic data.
fn context() -> Context {
    Context {
        provenance: Provenance {
            input: "synthetic".into(),
            input_sha256: String::new(),
            inputs: Vec::new(),
            split_seed: 1,
            folds: 5,
            tool: "tire-gap",
            version: "test",
        },
        notes: Vec::new(),
        outputs: Vec::new(),
    }
}

/// Held-out RMS of a channel before (base) and after (selected effects).
fn rms(d: &Diagnosis, channel: Channel) -> (f64, f64) {
    let before = d
        .baseline
        .iter()
        .find(|b| b.channel == channel)
        .unwrap()
        .heldout
        .rms;
    let after = d
        .remaining
        .iter()
        .find(|b| b.channel == channel)
        .unwrap()
        .heldout
        .rms;
    (before, after)
}

fn check_single(effect: Extension, channel: Channel) {
    check_found_alone(&run(&[effect], TireKind::Mf52, 11), effect, channel);
}

/// `d` names `effect` alone, first against the base model; it closes the held-out gap on
/// `channel` and predicts the runs at either end of its input.
fn check_found_alone(d: &Diagnosis, effect: Extension, channel: Channel) {
    assert_eq!(
        d.verdict,
        vec![effect],
        "{}: verdict {:?}",
        effect.name(),
        d.verdict
    );
    // The held-out gap closes: at least a tenth off the channel's held-out RMS.
    let (before, after) = rms(d, channel);
    assert!(
        after < 0.9 * before,
        "{}: {channel} held-out rms {before:.1} -> {after:.1}",
        effect.name()
    );
    let first = &d.rounds[0].trials[0];
    assert_eq!(
        first.effect, effect,
        "the effect ranks first against the base model"
    );
    // Refitted without the runs at one end of its input, the effect still predicts them:
    // never clearly worse than the model without it, and clearly better at some end.
    assert!(
        !d.extrapolation.is_empty(),
        "{}: no extrapolation check",
        effect.name()
    );
    for x in &d.extrapolation {
        assert!(
            x.rms_with <= 1.05 * x.rms_without,
            "{}: {} {}: {:.1} -> {:.1}",
            effect.name(),
            x.channel,
            x.held_out,
            x.rms_without,
            x.rms_with
        );
    }
    assert!(
        d.extrapolation
            .iter()
            .any(|x| x.rms_with < 0.9 * x.rms_without),
        "{}: {:?}",
        effect.name(),
        d.extrapolation
    );
}

#[test]
fn combined_slip_alone() {
    check_single(Extension::CombinedSlip, Channel::Fy);
}

/// The runs of `ds` a drive/brake grid holds: those that sweep the slip ratio, each at a held
/// slip angle, with every second one at zero slip angle dropped, so that most rows lie in
/// combined slip (as on a rig's grid at 0, -3 and -6 deg).
fn drive_brake_grid(ds: &Dataset) -> Dataset {
    let (alpha, kappa) = (ds.alpha.as_deref().unwrap(), ds.kappa.as_deref().unwrap());
    let largest = |run: i64, x: &[f64]| {
        (0..ds.len())
            .filter(|&i| ds.run[i] == run)
            .fold(0.0_f64, |m, i| m.max(x[i].abs()))
    };
    let mut pure = 0;
    let kept: Vec<i64> = ds
        .runs()
        .into_iter()
        .filter(|&r| largest(r, kappa) > 0.1)
        .filter(|&r| {
            let at_zero = largest(r, alpha) < 0.5_f64.to_radians();
            pure += usize::from(at_zero);
            !at_zero || pure % 2 == 1
        })
        .collect();
    let rows: Vec<usize> = (0..ds.len())
        .filter(|&i| kept.contains(&ds.run[i]))
        .collect();
    ds.select(&rows)
}

/// On a drive/brake grid the base model's pure-slip curves bend towards the combined-slip
/// rows, so that combined slip gains much where one slip is zero too; it is named all the
/// same, closes most of the gap, and nothing is named when the tire has no combined slip.
#[test]
fn combined_slip_on_a_drive_brake_grid() {
    for effects in [vec![Extension::CombinedSlip], vec![]] {
        let ds = generate(&SynthConfig {
            seed: 11,
            effects: effects.clone(),
            tire: TireKind::Mf52,
            rows_target: 60_000,
            ..SynthConfig::default()
        });
        let grid = drive_brake_grid(&ds);
        assert!(
            grid.len() > 10_000 && grid.runs().len() >= 15,
            "{}",
            grid.len()
        );
        let d = diagnose(&grid, &Options::default(), &Unobserved).expect("diagnosis runs");
        let d = claims_cover_the_verdict(d);
        assert_eq!(d.verdict, effects, "{:?}", d.signature_refusals);
        for channel in [Channel::Fx, Channel::Fy] {
            let (before, after) = rms(&d, channel);
            let most = match effects.is_empty() {
                true => after > 0.9 * before,
                false => after < 0.3 * before,
            };
            assert!(most, "{channel} held-out rms {before:.1} -> {after:.1}");
        }
    }
}

/// As `check_single`, with the effect in MF 6.1's own form (the form the candidate fits).
fn check_single_mf61(effect: Extension, channel: Channel, seed: u64) {
    let ds = generate(&SynthConfig {
        seed,
        effects: vec![effect],
        tire: TireKind::Mf52,
        rows_target: ROWS,
        forms: Forms::Mf61,
        ..SynthConfig::default()
    });
    let d = diagnose(&ds, &Options::default(), &Unobserved).expect("diagnosis runs");
    check_found_alone(&d, effect, channel);
}

#[test]
fn combined_slip_in_mf61_form_alone() {
    check_single_mf61(Extension::CombinedSlip, Channel::Fy, 12);
}

#[test]
fn inflation_pressure_in_mf61_form_alone() {
    check_single_mf61(Extension::InflationPressure, Channel::Fy, 12);
}

#[test]
fn camber_peak_alone() {
    check_single(Extension::CamberPeak, Channel::Fy);
}

#[test]
fn relaxation_length_alone() {
    check_single(Extension::RelaxationLength, Channel::Fy);
}

#[test]
fn inflation_pressure_alone() {
    check_single(Extension::InflationPressure, Channel::Fy);
}

/// The speed effect of this programme shows mostly in the few runs far from the nominal
/// speed: it leads the first round and closes most of Fx's gap, but its combined p-value after
/// Holm's correction sits near 0.05 (0.04 to 0.5 depending on the fold assignment), so it is
/// not selected on most fold assignments and the verdict does not claim it. What must hold:
/// nothing else is claimed, and it is the candidate that explains the gap.
#[test]
fn speed_dependence_alone() {
    let d = run(&[Extension::SpeedDependence], TireKind::Mf52, 11);
    assert!(
        d.verdict.is_empty() || d.verdict == vec![Extension::SpeedDependence],
        "verdict {:?}",
        d.verdict
    );
    let first = &d.rounds[0].trials[0];
    assert_eq!(first.effect, Extension::SpeedDependence);
    let fx = first
        .channels
        .iter()
        .find(|c| c.channel == Channel::Fx)
        .unwrap();
    assert!(fx.gap_closed.unwrap() > 0.5, "{fx:?}");
}

/// A speed candidate linear in speed left half of Fy's gap on this seed (101 -> 54 N held
/// out), of which camber_peak took a part; with the curvature in speed it leaves 31 N. Speed
/// then lowers Mz's held-out error without significance; not in Mz's model, it left a misfit
/// that grows with the camber, which a camber term on Mz's peak took (0.18 of its gap).
#[test]
fn speed_dependence_alone_on_a_second_seed() {
    let d = run(&[Extension::SpeedDependence], TireKind::Mf52, 31);
    assert_eq!(d.verdict, vec![Extension::SpeedDependence]);
}

#[test]
fn ply_steer_conicity_alone() {
    check_single(Extension::PlySteerConicity, Channel::Fy);
}

#[test]
fn rolling_resistance_alone() {
    check_single(Extension::RollingResistance, Channel::Fx);
}

#[test]
fn temperature_alone() {
    check_single(Extension::Temperature, Channel::Fy);
}

/// The rig's slip ratio from a rolling radius about 1 % off the effective one, and its Fx load
/// cell's crosstalk from Fz (synth's form, not the candidate's): named as a shift of the slip
/// ratio and not as rolling resistance, which could take the force the shift makes at free
/// rolling but not its fading beyond the peak.
#[test]
fn slip_ratio_shift_alone() {
    let (ds, truth) = generate_with_truth(&SynthConfig {
        seed: 11,
        effects: vec![Extension::SlipRatioShift],
        tire: TireKind::Mf52,
        rows_target: ROWS,
        ..SynthConfig::default()
    });
    let d = diagnose(&ds, &Options::default(), &Unobserved).expect("diagnosis runs");
    check_found_alone(&d, Extension::SlipRatioShift, Channel::Fx);
    assert!(
        d.confounding
            .fits
            .iter()
            .all(|c| ![c.winner, c.runner_up].contains(&Extension::RollingResistance)),
        "told apart from rolling resistance: {:?}",
        d.confounding.fits
    );
    // The rig reads (1 + kappa) r - 1 with r = Re / R: the tire is at kappa_m / r + 1 / r - 1,
    // a shift of 1 / r - 1 (and a stretch of the slip, which the stiffness takes).
    let r = truth.effects[0].params["radius_ratio_Re_over_R"];
    let fitted = &d.rounds[0].trials[0].channels[0].params;
    let shift = fitted["Fx.slip_ratio_shift.Sh"] + 4.0 * fitted["Fx.slip_ratio_shift.Sh_per_kN"];
    let want = 1.0 / r - 1.0;
    assert!(
        (shift - want).abs() < 0.1 * want.abs(),
        "shift at 4 kN {shift} vs 1 / r - 1 = {want}"
    );
}

#[test]
fn no_effect_gives_an_empty_verdict_on_two_tires() {
    for tire in [TireKind::Mf52, TireKind::Mf87Perturbed] {
        let d = run(&[], tire, 5);
        assert!(
            d.verdict.is_empty(),
            "{tire:?}: false alarm {:?}",
            d.verdict
        );
        // Conditions drawn independently, no wear: nothing confounded, no drift.
        assert!(
            d.confounding.design.is_empty(),
            "{:?}",
            d.confounding.design
        );
        for c in &d.remaining_over_runs {
            assert!(c.trend.as_ref().is_none_or(|t| !t.significant), "{c:?}");
        }
    }
}

#[test]
fn a_design_that_moves_pressure_with_temperature_is_named_whichever_wins() {
    let coupled = Some([DrawnCondition::Temperature, DrawnCondition::Pressure]);
    for (truth, seed) in [
        (Extension::Temperature, 21),
        (Extension::InflationPressure, 23),
    ] {
        let d = run_programme(&[truth], seed, coupled, 0.0);
        let c = d
            .confounding
            .design
            .iter()
            .find(|c| c.conditions == [Condition::Pressure, Condition::Temperature])
            .unwrap_or_else(|| panic!("{truth}: not named: {:?}", d.confounding.design));
        assert!(c.run_correlation > 0.95, "{c:?}");
        assert_eq!(c.effects[0], vec![Extension::InflationPressure]);
        assert_eq!(c.effects[1], vec![Extension::Temperature]);
        // One of the two is claimed, and named as the one the fit chose; the other is not
        // claimed on top of it.
        assert_eq!(d.verdict.len(), 1, "{truth}: {:?}", d.verdict);
        assert!(
            [Extension::Temperature, Extension::InflationPressure].contains(&d.verdict[0]),
            "{truth}: {:?}",
            d.verdict
        );
        assert_eq!(c.selected, d.verdict);
        let other = if d.verdict[0] == Extension::Temperature {
            Extension::InflationPressure
        } else {
            Extension::Temperature
        };
        let closed = d.untestable.iter().find(|u| u.effect == other);
        assert!(
            closed.is_some_and(|u| u.reason.starts_with("confounded by design")),
            "{truth}: {:?}",
            d.untestable
        );
    }
}

#[test]
fn wear_over_the_programme_stays_unexplained_and_shows_as_a_drift() {
    // 8 % less force in the last run than in the first.
    let d = run_programme(&[], 22, None, 0.08);
    assert!(d.verdict.is_empty(), "claimed {:?}", d.verdict);
    let fy = d
        .remaining_over_runs
        .iter()
        .find(|c| c.channel == Channel::Fy)
        .expect("Fy's gap is left unexplained");
    let t = fy.trend.as_ref().expect("a trend is judged");
    assert!(t.significant && t.p_value < 1e-3, "{t:?}");
    assert!((-0.12..-0.05).contains(&t.change), "{t:?}");
    // The report says so instead of "nothing more needed".
    let text = report::text(&d, &context());
    assert!(text.contains("it stays unexplained"), "{text}");
    assert!(text.contains("a drift over the programme"), "{text}");
}

fn check_pair(pair: [Extension; 2], seed: u64) {
    check_pair_on(pair, TireKind::Mf52, seed);
}

fn check_pair_on(pair: [Extension; 2], tire: TireKind, seed: u64) {
    let d = run(&pair, tire, seed);
    let mut found = d.verdict.clone();
    found.sort();
    let mut want = pair.to_vec();
    want.sort();
    assert_eq!(found, want, "verdict {:?}", d.verdict);
    // The report shows the second effect's gain over the first, not only over the base model.
    let text = report::text(&d, &context());
    let (first, second) = (d.verdict[0].name(), d.verdict[1].name());
    assert!(
        text.contains(&format!("round 1: {first} added to the base model"))
            && text.contains(&format!("round 2: {second} added to {first} ")),
        "{text}"
    );
    for (b, r) in d.baseline.iter().zip(&d.remaining) {
        assert!(
            r.heldout.rms <= 1.02 * b.heldout.rms,
            "{}: held-out rms {:.1} -> {:.1}",
            b.channel,
            b.heldout.rms,
            r.heldout.rms
        );
    }
}

#[test]
fn rolling_resistance_with_temperature() {
    check_pair([Extension::RollingResistance, Extension::Temperature], 7);
}

#[test]
fn combined_slip_with_inflation_pressure() {
    check_pair([Extension::CombinedSlip, Extension::InflationPressure], 7);
}

/// Speed, second after the relaxation length, was not claimed with a form linear in speed: its
/// signature rested on too few runs (p = 0.16).
#[test]
fn relaxation_length_with_speed_dependence() {
    check_pair([Extension::RelaxationLength, Extension::SpeedDependence], 7);
}

#[test]
fn ply_steer_conicity_with_temperature() {
    check_pair([Extension::PlySteerConicity, Extension::Temperature], 7);
}

// Cases a first run on fresh seeds got wrong, kept so they stay right.

/// At twice the nominal noise, once the speed effect is in, combined-slip weighting closed a
/// fifth of the small gap left on Fx (0.8 N rms, 0.04 noise variances): not a finding.
#[test]
fn speed_dependence_alone_at_double_noise() {
    let d = run_noisy(&[Extension::SpeedDependence], TireKind::Mf52, 41, 2.0);
    assert_eq!(d.verdict, vec![Extension::SpeedDependence]);
    let (before, after) = rms(&d, Channel::Fx);
    assert!(
        after < 0.9 * before,
        "Fx held-out rms {before:.1} -> {after:.1}"
    );
}

/// On the brush tire the speed effect shows on Fy alone once temperature is in; Fisher's
/// combination with its two untouched channels had diluted it below Holm's threshold. On two
/// of three fold assignments temperature is not significant on Fx; refitted without the
/// runs of the highest third of temperatures it predicts them worse than the model without it
/// (Fx held-out RMS 167.9 -> 589.0 N), so it does not join Fx's model, and speed is then not
/// selected there.
#[test]
#[ignore = "open: speed_dependence is selected on one fold assignment of three; on the others \
            temperature does not extrapolate on Fx, stays out of its model, and speed is not \
            selected"]
fn speed_dependence_with_temperature_on_the_brush_tire() {
    check_pair_on(
        [Extension::SpeedDependence, Extension::Temperature],
        TireKind::Brush,
        41,
    );
}

/// After ply steer and speed, combined-slip weighting took 0.57 noise variances off the
/// brush tire's Fx shape misfit: below what a later effect must bring. With the speed
/// candidate's curvature, speed (second after ply steer) closes 0.80 of Fx's gap and 0.82 of
/// Fy's held out, but its signature over the three channels is p = 0.061 (Fx 0.015, Fy 0.31,
/// Mz 0.78), so it is not claimed.
#[test]
#[ignore = "open: speed_dependence, second after ply steer, is refused for its signature \
            (p = 0.061 over its channels, needs < 0.05)"]
fn ply_steer_conicity_with_speed_dependence_on_the_brush_tire() {
    check_pair_on(
        [Extension::PlySteerConicity, Extension::SpeedDependence],
        TireKind::Brush,
        41,
    );
}
