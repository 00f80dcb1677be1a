//! The verdict on a programme shaped like a real rig's (one TTC run file holding many sweeps
//! at one speed): no effect of a condition the programme does not vary, the same verdict for
//! every split seed, and a fitted model that always exports. (A dead slip-ratio channel is
//! tested in `programme.rs`.)

use tire_gap::front;
use tire_gap::io::input::{Format, Loaded};
use tire_gap::method::diagnose::{Diagnosis, Options, diagnose};
use tire_gap::method::export::fitted_parameters;
use tire_gap::method::fit::effects::Extension;
use tire_gap::method::observer::Unobserved;
use tire_gap::synth::programme::{ProgrammeConfig, generate_programme, write_ttc};

/// A cornering programme with a pressure effect, at 40 km/h, as one TTC run file.
fn programme() -> Loaded {
    let mut cfg = ProgrammeConfig::cornering(23);
    cfg.effects = vec![Extension::InflationPressure];
    cfg.cambers_deg = vec![0.0, 3.0];
    cfg.sweep_s = 5.0;
    let ds = generate_programme(&cfg).dataset;
    let text = write_ttc(&ds, "Tire_Name=Synthetic 205/55R16; Rim_Width=7.0; Run 023");
    front::read_str(&text, "B9999run23.dat", Format::Ttc).expect("the run file reads")
}

fn run(l: &Loaded, seed: u64) -> Diagnosis {
    let options = Options {
        seed,
        ..Options::default()
    };
    diagnose(&l.dataset, &options, &Unobserved).expect("diagnosis runs")
}

#[test]
fn a_constant_speed_programme_gives_one_verdict_for_every_seed_and_no_speed_effect() {
    let l = programme();
    assert!(
        l.dataset.runs().len() >= 24,
        "{} blocks",
        l.dataset.runs().len()
    );
    let (a, b) = (run(&l, 1), run(&l, 2));
    assert_eq!(a.verdict, b.verdict);
    // The draws are the same whatever the seed, so is their record.
    let (sa, sb) = (a.stability.as_ref().unwrap(), b.stability.as_ref().unwrap());
    assert_eq!(sa.selected, sb.selected);
    for d in [&a, &b] {
        for e in [Extension::SpeedDependence, Extension::RollingResistance] {
            assert!(!d.verdict.contains(&e), "{:?}", d.verdict);
        }
        // Fx is not diagnosed here (no slip-ratio sweep), so rolling resistance has no channel;
        // the speed effect on Fy and Mz is untestable for the spread of speed.
        let u = d
            .untestable
            .iter()
            .find(|u| u.effect == Extension::SpeedDependence)
            .expect("speed_dependence is untestable");
        assert!(u.reason.contains("speed barely varies"), "{}", u.reason);
        assert!(
            d.regions.iter().all(|r| r.dimension != "speed"),
            "a speed region was ranked"
        );
        // Whatever the verdict, its model exports.
        fitted_parameters(&d.models, &d.verdict, &l.dataset).expect("the fitted model exports");
    }
    assert_eq!(a.verdict, vec![Extension::InflationPressure]);
}
