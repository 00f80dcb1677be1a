use tire_gap::programme::{self, split};
use tire_gap::synth::programme::{ProgrammeConfig, generate_programme};

#[test]
fn explore() {
    for cfg in [ProgrammeConfig::cornering(1), ProgrammeConfig::drive_brake(2)] {
        let p = generate_programme(&cfg);
        let t = std::time::Instant::now();
        let s = split(&p.dataset);
        println!("rows {} sweeps {} pauses {} -> blocks {} in {:?}", p.dataset.len(), p.sweeps.len(), p.pauses, s.blocks.len(), t.elapsed());
        for (b, why) in s.blocks.iter().zip(&s.boundaries).take(20) {
            println!("  {:?} {:?}", b, why);
        }
        for sw in p.sweeps.iter().take(10) { println!("  sweep {:?}", sw.rows); }
        let _ = programme::blocks(&p.dataset);
    }
}
