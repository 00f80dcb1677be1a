//! Reading Tire Test Consortium ASCII run files: units, the SAE sign convention, run ids,
//! detection, errors that name line and channel, and several files as one data set. The
//! expected values are converted by hand from the files in tests/data/ttc.

use std::path::{Path, PathBuf};
use tire_gap::data::Quantity;
use tire_gap::input::{self, Format, InputError, Loaded};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/ttc")
        .join(name)
}

/// A fresh file under cargo's per-test temporary directory.
fn write(dir: &str, name: &str, contents: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, contents).unwrap();
    path
}

fn column(l: &Loaded, q: Quantity) -> Vec<f64> {
    l.dataset
        .column(q)
        .unwrap_or_else(|| panic!("no {q:?}"))
        .to_vec()
}

fn near(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

fn has_note(l: &Loaded, part: &str) -> bool {
    l.notes.iter().any(|n| n.contains(part))
}

fn ttc_err(text: &str) -> InputError {
    match input::read_str(text, "B1run1.dat", Format::Ttc) {
        Ok(l) => panic!("expected an error, got {} samples", l.dataset.len()),
        Err(e) => e,
    }
}

#[test]
fn si_file_in_internal_units_and_the_paper_s_axes() {
    let l = input::load(&fixture("B1464run23.dat")).unwrap();
    assert_eq!(l.sources[0].format, Format::Ttc);
    let ds = &l.dataset;
    assert_eq!(ds.len(), 5);
    assert_eq!(ds.run, vec![23; 5].into());
    // 36 kph = 10 m/s; FZ -1000 N is a load of 1000 N; 82.7 kPa; tread 50/60/70 degC -> 60.
    assert!(column(&l, Quantity::Speed).iter().all(|v| near(*v, 10.0)));
    assert_eq!(ds.fz, vec![1000.0; 5].into());
    assert!(
        column(&l, Quantity::Pressure)
            .iter()
            .all(|v| near(*v, 82.7))
    );
    assert!(
        column(&l, Quantity::Temperature)
            .iter()
            .all(|v| near(*v, 60.0))
    );
    // SA -4 deg is alpha +4 deg = 0.0698132 rad; IA keeps its sign; SR (not SL) is kappa.
    assert!(near(column(&l, Quantity::Alpha)[0], 4f64.to_radians()));
    assert!(near(
        column(&l, Quantity::Alpha)[0],
        0.069_813_170_079_773_18
    ));
    assert!(near(column(&l, Quantity::Gamma)[0], 1f64.to_radians()));
    assert_eq!(column(&l, Quantity::Kappa), vec![0.05; 5]);
    assert_eq!(
        column(&l, Quantity::Time),
        vec![0.0, 0.01, 0.02, 0.03, 0.04]
    );
    // Forces and moment keep their values.
    assert_eq!(column(&l, Quantity::Fy)[0], 1200.0);
    assert_eq!(column(&l, Quantity::Mz)[0], -20.0);
    assert_eq!(column(&l, Quantity::Fx)[0], 10.0);
    assert!(has_note(&l, "alpha = -SA"));
    assert!(has_note(&l, "SR (effective rolling radius)"));
    assert!(has_note(&l, "mean of TSTI, TSTC and TSTO"));
    assert!(has_note(
        &l,
        "channels not used: N RL RE MX NFX NFY RST AMBTMP SL"
    ));
}

#[test]
fn a_lateral_sweep_reads_as_the_paper_s_signs() {
    // In SAE a positive slip angle pulls the tire to the left (FY < 0) and the aligning moment
    // turns it back (MZ > 0); in the paper's axes alpha > 0 gives Fy > 0 and Mz < 0.
    let l = input::load(&fixture("B1464run23.dat")).unwrap();
    let (alpha, fy, mz) = (
        column(&l, Quantity::Alpha),
        column(&l, Quantity::Fy),
        column(&l, Quantity::Mz),
    );
    for i in 0..alpha.len() {
        if alpha[i] != 0.0 {
            assert!(
                fy[i] * alpha[i] > 0.0,
                "row {i}: alpha {} Fy {}",
                alpha[i],
                fy[i]
            );
            assert!(
                mz[i] * alpha[i] < 0.0,
                "row {i}: alpha {} Mz {}",
                alpha[i],
                mz[i]
            );
        }
    }
}

#[test]
fn us_units_file() {
    let l = input::load(&fixture("B1654run5.dat")).unwrap();
    let ds = &l.dataset;
    assert_eq!(ds.run, vec![5, 5].into());
    // 25 mph = 11.176 m/s; 200 lb = 889.64432305 N; 12 psi = 82.7370875 kPa; 140 degF = 60 degC;
    // 10 ft-lb = 13.5581794833 N m.
    assert!(near(column(&l, Quantity::Speed)[0], 11.176));
    assert!(near(ds.fz[0], 889.644_323_052_1));
    assert!(near(
        column(&l, Quantity::Pressure)[0],
        82.737_087_518_020_33
    ));
    assert!(near(column(&l, Quantity::Temperature)[0], 60.0));
    assert!(near(column(&l, Quantity::Mz)[1], 27.116_358_966_628_01));
    assert!(near(column(&l, Quantity::Fy)[0], -222.411_080_763_025));
    assert!(near(column(&l, Quantity::Alpha)[1], -(2f64.to_radians())));
    // SL only: the slip ratio comes from it, said so; TSTC alone is the tread temperature.
    assert_eq!(column(&l, Quantity::Kappa), vec![-0.02, -0.02]);
    assert!(has_note(&l, "from SL (loaded radius)"));
    assert!(has_note(&l, "TSTC (not all of TSTI, TSTC, TSTO present)"));
}

#[test]
fn errors_name_the_line_and_the_channel() {
    let head = "title\nET FZ SA FY\ns N deg N\n";
    let ragged = ttc_err(&format!("{head}0 -1000 1 -50\n0.1 -1000 2\n"));
    assert_eq!(ragged.line, Some(5));
    assert!(
        ragged.message.starts_with("3 values for 4 channels"),
        "{ragged}"
    );
    let word = ttc_err(&format!("{head}0 -1000 abc -50\n"));
    assert_eq!((word.line, word.column.as_deref()), (Some(4), Some("SA")));
    assert_eq!(word.message, "\"abc\" is not a number");
    let no_load = ttc_err("title\nET SA FY\ns deg N\n0 1 -50\n");
    assert_eq!(no_load.column.as_deref(), Some("FZ"));
    assert!(
        no_load.message.contains("missing required column"),
        "{no_load}"
    );
    let units = ttc_err("title\nET FZ SA FY\ns N deg\n0 -1000 1 -50\n");
    assert_eq!(units.line, Some(3));
    let unit = ttc_err("title\nET FZ SA FY\ns N furlong N\n0 -1000 1 -50\n");
    assert_eq!((unit.line, unit.column.as_deref()), (Some(3), Some("SA")));
    assert!(
        unit.message
            .contains("\"furlong\" is not accepted for alpha"),
        "{unit}"
    );
    // A slip angle in radians under a degree unit is caught by the range check.
    let range = ttc_err(&format!("{head}0 -1000 120 -50\n"));
    assert!(
        range.message.contains("outside the plausible range"),
        "{range}"
    );
}

#[test]
fn detected_by_content_under_another_extension() {
    let text = std::fs::read_to_string(fixture("B1464run23.dat")).unwrap();
    let path = write("ttc-detect", "B1464run23.txt", &text);
    let l = input::load(&path).unwrap();
    assert_eq!(l.sources[0].format, Format::Ttc);
    assert_eq!(l.dataset.run, vec![23; 5].into());
}

#[test]
fn several_run_files_are_one_programme() {
    let a = std::fs::read_to_string(fixture("B1464run23.dat")).unwrap();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ttc-programme");
    let _ = std::fs::remove_dir_all(&dir);
    write("ttc-programme", "B1464run23.dat", &a);
    write(
        "ttc-programme",
        "B1464run24.dat",
        &a.replace("run23", "run24").replace("\t36.0\t", "\t72.0\t"),
    );
    write("ttc-programme", "readme.txt", "rig log");
    let (files, notes) = input::expand(std::slice::from_ref(&dir)).unwrap();
    assert_eq!(files.len(), 2);
    assert!(notes[0].contains("1 other entry ignored"), "{notes:?}");
    let l = input::load_many(&files).unwrap();
    assert_eq!(l.dataset.len(), 10);
    // Run ids from the file names.
    assert_eq!(l.dataset.runs(), vec![23, 24]);
    let speed = column(&l, Quantity::Speed);
    assert!(near(speed[0], 10.0) && near(speed[5], 20.0));
    assert_eq!(l.sources[1].runs, vec![24]);
    // Two run files without a run number are both run 1: renumbered, noted.
    let plain = a.replace("Data from B1464run23.mat", "cornering");
    let p1 = write("ttc-plain", "first.dat", &plain);
    let p2 = write("ttc-plain", "second.dat", &plain);
    let l = input::load_many(&[p1, p2]).unwrap();
    assert_eq!(l.dataset.runs(), vec![1, 2]);
    assert!(has_note(&l, "renumbered"));
}

#[test]
fn a_positive_load_keeps_its_sign_and_the_title_gives_the_run() {
    let l = input::read_str(
        "Data from run2\nSA FZ FY\ndeg N N\n1 1000 -5\n2 1100 -9\n",
        "x.dat",
        Format::Ttc,
    )
    .unwrap();
    assert_eq!(l.dataset.fz, vec![1000.0, 1100.0].into());
    assert_eq!(l.dataset.run, vec![2, 2].into());
    assert!(has_note(&l, "FZ is mostly positive"), "{:?}", l.notes);
}

#[test]
fn crlf_byte_order_mark_blank_lines_and_lower_case() {
    let l = input::read_str(
        "\u{feff}Data from B9run4.mat\r\n\r\nsa\tfz\tfy\r\ndeg\tN\tN\r\n\r\n1\t-1000\t-5\r\n",
        "B9run4.dat",
        Format::Ttc,
    )
    .unwrap();
    assert_eq!(l.dataset.run, vec![4].into());
    assert!(near(column(&l, Quantity::Alpha)[0], -(1f64.to_radians())));
    assert_eq!(l.dataset.fz, vec![1000.0].into());
    // Line numbers stay the file's own.
    let e = ttc_err("t\n\nSA FZ FY\ndeg N N\n\n1 -1000 x\n");
    assert_eq!((e.line, e.column.as_deref()), (Some(6), Some("FY")));
}

#[test]
fn mangled_files_give_an_error_or_a_whole_data_set_never_a_panic() {
    let seed = std::fs::read_to_string(fixture("B1464run23.dat")).unwrap();
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    let junk = [
        '-', '.', 'e', '\n', '\t', ' ', 'r', 'u', 'n', '9', 'N', 'x', '\u{b0}',
    ];
    for _ in 0..400 {
        let mut chars: Vec<char> = seed.chars().collect();
        for _ in 0..1 + next(6) {
            let i = next(chars.len()).min(chars.len().saturating_sub(1));
            match next(3) {
                0 => {
                    chars.remove(i);
                }
                1 => chars.insert(i, junk[next(junk.len())]),
                _ => chars[i] = junk[next(junk.len())],
            }
        }
        let text: String = chars.into_iter().collect();
        let _ = Format::detect(Path::new("m"), &text);
        if let Ok(l) = input::read_str(&text, "m.dat", Format::Ttc) {
            let d = &l.dataset;
            assert_eq!(d.run.len(), d.len());
            for q in Quantity::ALL {
                if let Some(c) = d.column(q) {
                    assert_eq!(c.len(), d.len());
                    assert!(c.iter().all(|v| v.is_finite()));
                }
            }
        }
    }
}
