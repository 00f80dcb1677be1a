//! A programme recorded as one file (TTC): split into its test blocks, folds that keep
//! held-out blocks within their training conditions, and dead channels left out before
//! either. Programmes come from `synth::programme` (sweeps at stepped set points with ramps
//! between them and pauses in time, whose rows are known) and from hand-made signals.

use std::collections::BTreeSet;
use std::ops::Range;

use tire_gap::data::{Dataset, Quantity};
use tire_gap::front;
use tire_gap::io::input::{self, Format};
use tire_gap::method::prepare::cv::Folds;
use tire_gap::method::prepare::programme::{
    self, Block, Boundary, SetCondition, Split, Swept, split,
};
use tire_gap::synth::programme::{
    Programme, ProgrammeConfig, ProgrammeKind, generate_programme, write_ttc,
};

/// Checks that `s` covers `n` rows once, in order.
fn assert_partition(s: &Split, n: usize) {
    assert_eq!(s.blocks.len(), s.boundaries.len());
    assert_eq!(s.blocks.first().map(|b| b.start), Some(0));
    assert_eq!(s.blocks.last().map(|b| b.end), Some(n));
    for w in s.blocks.windows(2) {
        assert_eq!(w[0].end, w[1].start, "{:?}", s.blocks);
    }
    assert!(s.blocks.iter().all(|b| !b.is_empty()));
}

/// Checks that every block holds exactly one whole sweep (so every cut lies in a transition
/// or at a pause) and that its median conditions are the sweep's set point.
fn assert_one_sweep_per_block(p: &Programme, s: &Split) {
    assert_partition(s, p.dataset.len());
    assert_eq!(s.blocks.len(), p.sweeps.len(), "blocks {:?}", s.blocks);
    for (b, sw) in s.blocks.iter().zip(&p.sweeps) {
        assert!(
            b.start <= sw.rows.start && sw.rows.end <= b.end,
            "block {b:?} cuts sweep {:?}",
            sw.rows
        );
    }
    let ds = relabel(&p.dataset, &s.blocks);
    for (blk, sw) in programme::blocks(&ds).iter().zip(&p.sweeps) {
        let near = |c: SetCondition, want: f64| {
            let got = blk.level(c).unwrap_or(f64::NAN);
            assert!(
                (got - want).abs() <= c.tolerance(want),
                "run {}: {} {} for a set point of {}",
                blk.run,
                c.name(),
                c.format(got),
                c.format(want)
            );
        };
        near(SetCondition::Load, sw.fz);
        near(SetCondition::Pressure, sw.pressure);
        near(SetCondition::Camber, sw.gamma);
        if blk.swept == Swept::SlipRatio {
            near(SetCondition::HeldSlipAngle, sw.alpha);
        } else {
            assert_eq!(blk.swept, Swept::SlipAngle);
        }
    }
}

/// `ds` with run ids 1, 2, ... per block.
fn relabel(ds: &Dataset, blocks: &[Range<usize>]) -> Dataset {
    let mut run = Vec::new();
    for (k, b) in blocks.iter().enumerate() {
        run.extend(std::iter::repeat_n(k as i64 + 1, b.len()));
    }
    Dataset {
        run: run.into(),
        ..ds.clone()
    }
}

#[test]
fn a_cornering_programme_splits_into_its_48_sweeps() {
    for seed in [1, 2, 3] {
        let p = generate_programme(&ProgrammeConfig::cornering(seed));
        assert_eq!(p.sweeps.len(), 48);
        let s = split(&p.dataset);
        assert_eq!(s.window_rows, 101);
        assert_one_sweep_per_block(&p, &s);
        // Every pause is a cut; the other cuts are load or camber steps (pressure changes
        // come with a pause; the slip angle is swept, not held).
        assert_eq!(s.time_cuts(), p.pauses);
        assert_eq!(s.steps_of(SetCondition::Load), 48 - 1 - p.pauses);
        assert_eq!(s.steps_of(SetCondition::HeldSlipAngle), 0);
        assert_eq!(s.steps_of(SetCondition::Pressure), 0);
    }
}

#[test]
fn a_drive_brake_programme_also_cuts_at_the_held_slip_angle() {
    for seed in [4, 5] {
        let mut cfg = ProgrammeConfig::drive_brake(seed);
        // Two slip angles at one load: consecutive sweeps differ only in the held slip angle.
        cfg.loads_n = vec![3000.0];
        cfg.slip_angles_deg = vec![0.0, -3.0, -6.0, -3.0];
        let p = generate_programme(&cfg);
        let s = split(&p.dataset);
        assert_one_sweep_per_block(&p, &s);
        let only_alpha = s
            .boundaries
            .iter()
            .filter(|b| **b == Boundary::Step(vec![SetCondition::HeldSlipAngle]))
            .count();
        assert!(only_alpha >= 3, "{:?}", s.boundaries);
        let p = generate_programme(&ProgrammeConfig::drive_brake(seed));
        assert_eq!(p.sweeps.len(), 72);
        assert_one_sweep_per_block(&p, &split(&p.dataset));
    }
}

#[test]
fn noisier_and_longer_sweeps_split_the_same_way() {
    let mut cfg = ProgrammeConfig::cornering(7);
    cfg.noise = 5.0;
    cfg.sweep_s = 20.0;
    cfg.ramp_s = 2.5;
    cfg.dwell_s = 0.0;
    cfg.pause_probability = 0.5;
    let p = generate_programme(&cfg);
    assert_one_sweep_per_block(&p, &split(&p.dataset));
}

/// A hand-made programme: 100 Hz, load `fz(i)`, the slip angle swept once from -12 to +12
/// deg over all rows, everything else constant.
fn signal(n: usize, fz: impl Fn(usize) -> f64) -> Dataset {
    let col = |f: &dyn Fn(usize) -> f64| Some((0..n).map(f).collect());
    Dataset {
        source: "hand-made".into(),
        run: vec![1; n].into(),
        time: col(&|i| i as f64 * 0.01),
        speed: col(&|_| 11.1),
        fz: (0..n).map(fz).collect(),
        alpha: col(&|i| (24.0 * i as f64 / n as f64 - 12.0).to_radians()),
        gamma: col(&|_| 0.0),
        pressure: col(&|_| 83.0),
        fy: col(&|i| i as f64),
        ..Dataset::default()
    }
}

fn starts(s: &Split) -> Vec<usize> {
    s.blocks.iter().skip(1).map(|b| b.start).collect()
}

#[test]
fn sharp_steps_are_cut_where_they_are() {
    let ds = signal(1500, |i| match i {
        0..500 => 1000.0,
        500..1000 => 1600.0,
        _ => 1000.0,
    });
    let s = split(&ds);
    assert_partition(&s, 1500);
    assert_eq!(starts(&s), vec![500, 1000]);
    assert_eq!(s.boundaries[1], Boundary::Step(vec![SetCondition::Load]));
    // Steps below the tolerance (150 N or 10 % of the load) are one level.
    let s = split(&signal(1500, |i| if i < 700 { 1000.0 } else { 1120.0 }));
    assert_eq!(s.blocks, vec![0..1500]);
    let s = split(&signal(1500, |i| if i < 700 { 3000.0 } else { 3320.0 }));
    assert_eq!(s.blocks, vec![0..1500]);
    let s = split(&signal(1500, |i| if i < 700 { 3000.0 } else { 3400.0 }));
    assert_eq!(starts(&s), vec![700]);
}

#[test]
fn a_ramp_between_two_levels_is_cut_once_near_its_midpoint() {
    // 1000 N, a 1.5 s ramp to 2000 N (rows 500..650), 2000 N.
    let ramp = |i: usize| match i {
        0..500 => 1000.0,
        500..650 => 1000.0 + 1000.0 * (i - 500) as f64 / 150.0,
        _ => 2000.0,
    };
    let s = split(&signal(1500, ramp));
    assert_eq!(s.blocks.len(), 2, "{:?}", s.blocks);
    let cut = s.blocks[1].start;
    assert!((570..=580).contains(&cut), "cut at {cut}");
    // A slow ramp (20 s for 1000 N): no block spans more than two tolerances and none is
    // shorter than the window; the two plateaus are in different blocks.
    let slow = |i: usize| match i {
        0..1000 => 1000.0,
        1000..3000 => 1000.0 + 1000.0 * (i - 1000) as f64 / 2000.0,
        _ => 2000.0,
    };
    let ds = signal(4000, slow);
    let s = split(&ds);
    assert_partition(&s, 4000);
    assert!(s.blocks.len() >= 2);
    assert!(
        !s.blocks
            .iter()
            .any(|b| b.contains(&900) && b.contains(&3100))
    );
    for b in &s.blocks {
        assert!(b.len() >= s.window_rows, "{:?}", s.blocks);
        let v = &ds.fz[b.clone()];
        let (lo, hi) = v
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, z), x| (a.min(*x), z.max(*x)));
        // Within a block the load spans at most about two tolerances (200 N at 2000 N),
        // plus the rows of the window at its ends.
        assert!(hi - lo <= 2.0 * 200.0 + 100.0, "{b:?}: {lo}..{hi}");
    }
}

#[test]
fn short_excursions_and_spikes_make_no_block() {
    let ds = signal(1500, |i| match i {
        300 => 5000.0,
        800..830 => 2500.0,
        _ => 1000.0,
    });
    assert_eq!(split(&ds).blocks, vec![0..1500]);
}

#[test]
fn conditions_stepping_together_are_one_cut() {
    let mut ds = signal(1500, |i| if i < 600 { 1000.0 } else { 1600.0 });
    ds.gamma = Some(
        (0..1500)
            .map(|i| if i < 620 { 0.0 } else { 2f64.to_radians() })
            .collect(),
    );
    let s = split(&ds);
    assert_eq!(starts(&s).len(), 1);
    assert!((600..=620).contains(&starts(&s)[0]));
    assert_eq!(
        s.boundaries[1],
        Boundary::Step(vec![SetCondition::Load, SetCondition::Camber])
    );
    // Pressure: 4 kPa is one level, 6 kPa two.
    for (dp, blocks) in [(4.0, 1), (6.0, 2)] {
        let mut ds = signal(1500, |_| 1000.0);
        ds.pressure = Some(
            (0..1500)
                .map(|i| if i < 900 { 83.0 } else { 83.0 + dp })
                .collect(),
        );
        assert_eq!(split(&ds).blocks.len(), blocks, "{dp} kPa");
    }
}

#[test]
fn pauses_and_time_going_backwards_are_cuts() {
    let mut ds = signal(1200, |_| 1000.0);
    let t: Vec<f64> = (0..1200)
        .map(|i| match i {
            0..300 => i as f64 * 0.01,
            300..700 => 5.0 + i as f64 * 0.01,
            _ => (i - 700) as f64 * 0.01,
        })
        .collect();
    ds.time = Some(t.into());
    let s = split(&ds);
    assert_eq!(starts(&s), vec![300, 700]);
    match s.boundaries[1] {
        Boundary::TimeGap(dt) => assert!((dt - 5.01).abs() < 1e-9),
        ref b => panic!("{b:?}"),
    }
    assert_eq!(s.boundaries[2], Boundary::TimeBackwards);
    // 0.4 s is no pause (below 0.5 s), 0.6 s is.
    for (gap, blocks) in [(0.4, 1), (0.6, 2)] {
        let mut ds = signal(1200, |_| 1000.0);
        ds.time = Some(
            (0..1200)
                .map(|i| i as f64 * 0.01 + if i >= 600 { gap } else { 0.0 })
                .collect(),
        );
        assert_eq!(split(&ds).blocks.len(), blocks, "pause {gap} s");
    }
}

/// Reads `ds` written as a TTC file named `name`.
fn read_ttc(ds: &Dataset, name: &str) -> input::Loaded {
    let title = format!("Data from {}", name.replace(".dat", ".mat"));
    front::read_str(&write_ttc(ds, &title), name, Format::Ttc).unwrap()
}

#[test]
fn ttc_files_become_one_run_per_block_unique_across_files() {
    let mut cfg = ProgrammeConfig::cornering(11);
    cfg.pressures_kpa = vec![180.0, 240.0];
    let a = generate_programme(&cfg);
    let loaded = read_ttc(&a.dataset, "B1run23.dat");
    let runs = loaded.dataset.runs();
    assert_eq!(runs, (23001..=23024).collect::<Vec<i64>>());
    assert_eq!(loaded.sources[0].runs, runs);
    assert!(
        loaded
            .notes
            .iter()
            .any(|n| n.starts_with("a programme of 24 test blocks (runs 23001..23024)")),
        "{:?}",
        loaded.notes
    );
    // The same file as CSV keeps its single run: only TTC files are split.
    let mut csv = Vec::new();
    tire_gap::synth::write_csv(&a.dataset, &mut csv).unwrap();
    let l = front::read_str(std::str::from_utf8(&csv).unwrap(), "a.csv", Format::Csv).unwrap();
    assert_eq!(l.dataset.runs(), vec![1]);
    // Two files: each file's blocks keep their ids (no clash).
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("programme-files");
    std::fs::create_dir_all(&dir).unwrap();
    let b = generate_programme(&ProgrammeConfig {
        pressures_kpa: vec![200.0],
        ..ProgrammeConfig::drive_brake(12)
    });
    for (name, ds) in [("B1run23.dat", &a.dataset), ("B1run24.dat", &b.dataset)] {
        let title = format!("Data from {name}");
        std::fs::write(dir.join(name), write_ttc(ds, &title)).unwrap();
    }
    let l = front::load_paths(&[dir]).unwrap();
    let ids = l.dataset.runs();
    assert_eq!(ids.len(), 24 + 24);
    assert_eq!(ids.iter().collect::<BTreeSet<_>>().len(), ids.len());
    assert_eq!(l.sources[1].runs, (24001..=24024).collect::<Vec<i64>>());
    assert_eq!(l.dataset.len(), a.dataset.len() + b.dataset.len());
}

#[test]
fn a_dead_slip_ratio_channel_gives_the_data_set_without_it() {
    for kind in [ProgrammeKind::Cornering, ProgrammeKind::DriveBrake] {
        let mut cfg = match kind {
            ProgrammeKind::Cornering => ProgrammeConfig::cornering(21),
            ProgrammeKind::DriveBrake => ProgrammeConfig::drive_brake(22),
        };
        cfg.dead_slip_ratio = true;
        let dead = generate_programme(&cfg).dataset;
        assert!(dead.kappa.as_deref().unwrap().iter().all(|k| *k == -1.0));
        let without = Dataset {
            kappa: None,
            ..dead.clone()
        };
        let a = read_ttc(&dead, "B1run30.dat");
        let b = read_ttc(&without, "B1run30.dat");
        assert_eq!(a.dataset, b.dataset, "{kind:?}");
        assert!(a.dataset.kappa.is_none() && a.dataset.fx.is_none());
        assert_eq!(a.dataset.runs().len(), cfg.sweeps(), "{kind:?}");
        let note = a
            .notes
            .iter()
            .find(|n| n.starts_with("kappa left out (all"))
            .unwrap_or_else(|| panic!("{:?}", a.notes));
        assert!(note.contains("median -1.000"), "{note}");
        assert!(
            !b.notes.iter().any(|n| n.contains("left out")),
            "{:?}",
            b.notes
        );
    }
    // A live channel is kept.
    let live = read_ttc(
        &generate_programme(&ProgrammeConfig::drive_brake(22)).dataset,
        "B1run30.dat",
    );
    assert!(live.dataset.kappa.is_some() && live.dataset.fx.is_some());
}

#[test]
fn a_constant_pressure_programme_keeps_its_pressure() {
    let mut cfg = ProgrammeConfig::cornering(31);
    cfg.pressures_kpa = vec![240.0];
    let p = generate_programme(&cfg);
    let l = read_ttc(&p.dataset, "B1run5.dat");
    assert!(l.dataset.pressure.is_some());
    assert!(l.dataset.gamma.is_some() && l.dataset.speed.is_some());
    assert_eq!(l.dataset.runs().len(), 12);
    assert!(
        !l.notes.iter().any(|n| n.contains("left out")),
        "{:?}",
        l.notes
    );
}

/// The blocks of a programme, split.
fn programme_blocks(cfg: &ProgrammeConfig) -> Vec<Block> {
    let p = generate_programme(cfg);
    let s = split(&p.dataset);
    programme::blocks(&relabel(&p.dataset, &s.blocks))
}

#[test]
fn folds_cover_the_conditions_of_their_held_out_blocks() {
    let cornering = programme_blocks(&ProgrammeConfig::cornering(41));
    let drive = programme_blocks(&ProgrammeConfig::drive_brake(42));
    // Extremes held by two blocks each: covered only if the two are in different folds.
    let mut rare = cornering.clone();
    rare[5].camber = Some(6f64.to_radians());
    rare[30].camber = Some(6f64.to_radians());
    rare[12].load = 9000.0;
    rare[40].load = 9000.0;
    let mut naive_misses = 0;
    for blocks in [&cornering, &drive, &rare] {
        let rows: usize = blocks.iter().map(|b| b.rows).sum();
        for seed in 0..40 {
            let folds = Folds::stratified(blocks, 5, seed);
            assert_eq!(folds.runs(), blocks.len());
            assert_eq!(folds.coverage(blocks), Vec::new(), "seed {seed}");
            // Every fold holds blocks, rows within 40 % of the mean, and each level of each
            // condition in at least 3 folds (or in as many as it has blocks).
            let mut fold_rows = [0usize; 5];
            for b in blocks.iter() {
                fold_rows[folds.fold_of(b.run)] += b.rows;
            }
            for r in fold_rows {
                let mean = rows as f64 / 5.0;
                assert!((r as f64 - mean).abs() <= 0.4 * mean, "{fold_rows:?}");
            }
            for c in SetCondition::ALL {
                // The set points: loads 1500 N apart, pressures 30-40 kPa, angles 2-3 deg.
                let step = match c {
                    SetCondition::Load => 500.0,
                    SetCondition::Pressure => 10.0,
                    _ => 1.0,
                };
                let level = |b: &Block| b.level(c).map(|v| (c.shown(v) / step).round() as i64);
                let levels: BTreeSet<i64> = blocks.iter().filter_map(level).collect();
                for l in levels {
                    let with: Vec<&Block> = blocks.iter().filter(|b| level(b) == Some(l)).collect();
                    let folds_with: BTreeSet<usize> =
                        with.iter().map(|b| folds.fold_of(b.run)).collect();
                    assert!(
                        folds_with.len() >= with.len().min(3),
                        "{} level {l}: {folds_with:?}",
                        c.name()
                    );
                }
            }
            // Dealing by rows alone leaves some held-out block outside its training now
            // and then: the check above can fail.
            let runs: Vec<i64> = blocks
                .iter()
                .flat_map(|b| std::iter::repeat_n(b.run, b.rows))
                .collect();
            naive_misses += usize::from(!Folds::new(&runs, 5, seed).coverage(blocks).is_empty());
        }
    }
    assert!(naive_misses > 0);
}

#[test]
fn a_level_only_one_block_holds_is_reported_with_its_training_range() {
    let mut blocks = programme_blocks(&ProgrammeConfig::cornering(43));
    // One block at 6 deg camber: held out, nothing in training reaches it.
    blocks[10].camber = Some(6f64.to_radians());
    let folds = Folds::stratified(&blocks, 5, 1);
    let missing = folds.coverage(&blocks);
    assert_eq!(missing.len(), 1, "{missing:?}");
    let m = &missing[0];
    assert_eq!((m.run, m.condition), (blocks[10].run, SetCondition::Camber));
    assert_eq!(m.fold, folds.fold_of(blocks[10].run));
    let [lo, hi] = m.training.unwrap();
    assert!(lo.to_degrees().abs() < 0.1 && (hi.to_degrees() - 4.0).abs() < 0.1);
    assert!(
        m.describe()
            .contains("camber 6.00 deg lies outside its training blocks'"),
        "{}",
        m.describe()
    );
}

#[test]
fn a_programme_is_diagnosed_block_by_block() {
    use tire_gap::method::diagnose::{Options, diagnose};
    use tire_gap::method::observer::Unobserved;
    let mut cfg = ProgrammeConfig::drive_brake(51);
    cfg.pressures_kpa = vec![200.0, 260.0];
    cfg.sweep_s = 4.0;
    let l = read_ttc(&generate_programme(&cfg).dataset, "B1run7.dat");
    let d = diagnose(&l.dataset, &Options::default(), &Unobserved).unwrap();
    assert_eq!(d.runs, 48);
    assert_eq!(d.blocks.len(), 48);
    assert!(d.blocks.iter().all(|b| b.fold.is_some()));
    assert_eq!(d.not_covered, Vec::new());
    assert!(
        d.blocks
            .iter()
            .all(|b| b.swept == programme::Swept::SlipRatio)
    );
    let held: BTreeSet<i64> = d
        .blocks
        .iter()
        .map(|b| b.held_slip_angle.unwrap().to_degrees().round() as i64)
        .collect();
    assert_eq!(held, BTreeSet::from([-6, -3, 0]));
    assert!(l.dataset.has(Quantity::Kappa));
}

/// A cornering programme whose only slip-ratio channel reads the offset of the effective
/// rolling radius and noise (as `SR` does through a cornering run: about -0.02 to -0.05,
/// growing with the load) is read as free rolling: the same data as the same programme with a
/// slip ratio that reads zero there (`SL`), and no effect of the slip ratio is tested. A
/// drive/brake programme keeps its slip ratio.
#[test]
fn a_slip_ratio_no_block_sweeps_at_free_rolling_is_taken_as_zero() {
    use tire_gap::method::diagnose::{Options, diagnose};
    use tire_gap::method::fit::effects::Extension;
    use tire_gap::method::observer::Unobserved;
    let mut cfg = ProgrammeConfig::cornering(61);
    cfg.pressures_kpa = vec![200.0, 260.0];
    cfg.cambers_deg = vec![0.0];
    cfg.sweep_s = 4.0;
    let p = generate_programme(&cfg);
    let n = p.dataset.len();
    // Noise of +-0.003 from a fixed hash of the row.
    let noise = |i: usize| 0.006 * ((i as f64 * 12.9898).sin() * 43_758.545).fract().abs() - 0.003;
    let offset: Vec<f64> = (0..n)
        .map(|i| -0.013 - 0.0066 * p.dataset.fz[i] / 1000.0 + noise(i))
        .collect();
    let sr = Dataset {
        kappa: Some(offset.into()),
        ..p.dataset.clone()
    };
    let sl = Dataset {
        kappa: Some(vec![0.0; n].into()),
        ..p.dataset.clone()
    };
    let (a, b) = (read_ttc(&sr, "B1run6.dat"), read_ttc(&sl, "B1run6.dat"));
    let note = a
        .notes
        .iter()
        .find(|n| n.starts_with("slip ratio taken as 0 (free rolling)"))
        .unwrap_or_else(|| panic!("{:?}", a.notes));
    assert!(note.contains("95th percentile of |Fx| / Fz"), "{note}");
    assert_eq!(
        a.dataset, b.dataset,
        "the same data as with a slip ratio at zero"
    );
    let d = diagnose(&a.dataset, &Options::default(), &Unobserved).unwrap();
    for e in [Extension::CombinedSlip, Extension::SlipRatioShift] {
        assert!(!d.verdict.contains(&e), "{:?}", d.verdict);
        assert!(
            d.untestable.iter().any(|u| u.effect == e),
            "{:?}",
            d.untestable
        );
    }
    // A drive/brake programme sweeps its slip ratio: kept as read.
    let mut cfg = ProgrammeConfig::drive_brake(62);
    cfg.pressures_kpa = vec![200.0];
    cfg.sweep_s = 4.0;
    let db = generate_programme(&cfg).dataset;
    let l = read_ttc(&db, "B1run7.dat");
    assert!(
        l.notes
            .iter()
            .all(|n| !n.starts_with("slip ratio taken as 0"))
    );
    assert!(l.dataset.kappa.unwrap().iter().any(|k| k.abs() > 0.05));
}
