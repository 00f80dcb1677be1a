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

#[test]
fn write_files() {
    use tire_gap::synth::programme::write_ttc;
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("prog-scratch");
    std::fs::create_dir_all(&dir).unwrap();
    let mut c = ProgrammeConfig::cornering(3);
    c.run = 23;
    let p = generate_programme(&c);
    std::fs::write(dir.join("B1run23.dat"), write_ttc(&p.dataset, "Data from B1run23.mat")).unwrap();
    let mut c = ProgrammeConfig::drive_brake(4);
    c.run = 30; c.dead_slip_ratio = true;
    let p = generate_programme(&c);
    std::fs::write(dir.join("B1run30.dat"), write_ttc(&p.dataset, "Data from B1run30.mat")).unwrap();
    println!("{}", dir.display());
}
