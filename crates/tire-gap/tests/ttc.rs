//! Reading Tire Test Consortium ASCII run files: units, the SAE sign convention, run ids,
//! detection, errors that name line and channel, and several files as one data set. The
//! expected values are converted by hand from the files in tests/data/ttc.

mod common;

use common::{fixture, write};
use std::path::{Path, PathBuf};
use tire_gap::data::Quantity;
use tire_gap::front;
use tire_gap::io::input::{Format, InputError, Loaded};

fn ttc_fixture(name: &str) -> PathBuf {
    fixture(&format!("ttc/{name}"))
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
    match front::read_str(text, "B1run1.dat", Format::Ttc) {
        Ok(l) => panic!("expected an error, got {} samples", l.dataset.len()),
        Err(e) => e,
    }
}

#[test]
fn si_file_in_internal_units_and_the_paper_s_axes() {
    let l = front::load(&ttc_fixture("B1464run23.dat")).unwrap();
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
        "channels not used: N RL RE MX NFX NFY RST AMBTMP"
    ));
}

#[test]
fn a_lateral_sweep_reads_as_the_paper_s_signs() {
    // In SAE a positive slip angle pulls the tire to the left (FY < 0) and the aligning moment
    // turns it back (MZ > 0); in the paper's axes alpha > 0 gives Fy > 0 and Mz < 0.
    let l = front::load(&ttc_fixture("B1464run23.dat")).unwrap();
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
    let l = front::load(&ttc_fixture("B1654run5.dat")).unwrap();
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
    let text = std::fs::read_to_string(ttc_fixture("B1464run23.dat")).unwrap();
    let path = write("ttc-detect", "B1464run23.txt", &text);
    let l = front::load(&path).unwrap();
    assert_eq!(l.sources[0].format, Format::Ttc);
    assert_eq!(l.dataset.run, vec![23; 5].into());
}

#[test]
fn several_run_files_are_one_programme() {
    let a = std::fs::read_to_string(ttc_fixture("B1464run23.dat")).unwrap();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ttc-programme");
    let _ = std::fs::remove_dir_all(&dir);
    write("ttc-programme", "B1464run23.dat", &a);
    write(
        "ttc-programme",
        "B1464run24.dat",
        a.replace("run23", "run24").replace("\t36.0\t", "\t72.0\t"),
    );
    write("ttc-programme", "readme.txt", "rig log");
    let (files, notes) = tire_gap::io::input::expand(std::slice::from_ref(&dir)).unwrap();
    assert_eq!(files.len(), 2);
    assert!(notes[0].contains("1 other entry ignored"), "{notes:?}");
    let l = front::load_many(&files).unwrap();
    assert_eq!(l.dataset.len(), 10);
    // Run ids from the file names.
    assert_eq!(l.dataset.runs(), vec![23, 24]);
    let speed = column(&l, Quantity::Speed);
    assert!(near(speed[0], 10.0) && near(speed[5], 20.0));
    assert_eq!(l.sources[1].runs, vec![24]);
    // Two run files without a run number are both run 1: renumbered, noted.
    let plain = a.replace("Data from B1464run23.mat", "cornering");
    let p1 = write("ttc-plain", "first.dat", &plain);
    let p2 = write("ttc-plain", "second.dat", plain.replace("1200.0", "1260.0"));
    let l = front::load_many(&[p1.clone(), p2]).unwrap();
    assert_eq!(l.dataset.runs(), vec![1, 2]);
    assert!(has_note(&l, "renumbered"));
    // The same rows under another name (one run saved twice): read once, noted.
    let p3 = write("ttc-plain", "third.dat", &plain);
    let l = front::load_many(&[p1, p3]).unwrap();
    assert_eq!(l.dataset.runs(), vec![1]);
    assert_eq!(l.dataset.len(), 5);
    assert!(
        has_note(&l, "third.dat holds the same 5 rows as"),
        "{:?}",
        l.notes
    );
    assert!(!has_note(&l, "renumbered"));
}

#[test]
fn calspan_header_titles_name_no_tire_and_one_tire_spelt_two_ways_is_one_tire() {
    let a = std::fs::read_to_string(ttc_fixture("B1464run23.dat")).unwrap();
    // Round 8's header: the project, run, date, time and an export id; no tire.
    let header = |run: &str, id: &str| {
        a.replace(
            "Data from B1464run23.mat",
            &format!(
                "TIRF Data File: Project 1965; Run {run}; Date 08-01-2018; Time 19:19; ISO False; ID {id}"
            ),
        )
    };
    let p1 = write("ttc-calspan", "B1965run51.dat", header("051", "3Scoi1N"));
    // Another run: at another speed (a run read twice would be read once).
    let p2 = write(
        "ttc-calspan",
        "B1965run56.dat",
        header("056", "c1wP2-o").replace("\t36.0\t", "\t72.0\t"),
    );
    let l = front::load_many(&[p1, p2]).unwrap();
    assert_eq!(l.dataset.runs(), vec![51, 56]);
    assert!(l.sources.iter().all(|s| s.tire.is_none()));
    assert!(has_note(&l, "none of the 2 TTC run files names its tire"));
    // Round 9's spellings of one tire: a MAT-file's tireid (with the maker's item number) and
    // the ASCII file's Tire_Name and Rim_Width.
    let named = |name: &str| a.replace("Data from B1464run23.mat", name);
    let p1 = write(
        "ttc-one-tire",
        "B2356run71.dat",
        named("Hoosier 43100 18.0x6.0-10 R20, 7 inch rim Run 71"),
    );
    let p2 = write(
        "ttc-one-tire",
        "B2356run72.dat",
        named("Tire_Name=Hoosier 18.0X6.0-10, R20; Rim_Width=7.0; Run 072")
            .replace("\t36.0\t", "\t72.0\t"),
    );
    let l = front::load_many(&[p1.clone(), p2]).unwrap();
    assert_eq!(l.dataset.runs(), vec![71, 72]);
    let p3 = write(
        "ttc-one-tire",
        "B2356run62.dat",
        named("Tire_Name=MRF 18.0X6.0-10, ZTD1; Rim_Width=6.0; Run 062")
            .replace("\t36.0\t", "\t72.0\t"),
    );
    let e = front::load_many(&[p1, p3]).unwrap_err();
    assert!(e.message.contains("2 different tires"), "{e}");
}

#[test]
fn a_positive_load_keeps_its_sign_and_the_title_gives_the_run() {
    let l = front::read_str(
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
    let l = front::read_str(
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
    let seeds = [
        std::fs::read_to_string(ttc_fixture("B1464run23.dat")).unwrap(),
        std::fs::read_to_string(ttc_fixture("B2356run5.dat")).unwrap(),
    ];
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    let junk = [
        '-', '.', 'e', '\n', '\t', ' ', 'r', 'u', 'n', '9', 'N', 'x', '\u{b0}', 'c', 'g', '=', ';',
    ];
    for k in 0..800 {
        let mut chars: Vec<char> = seeds[k % 2].chars().collect();
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
        if let Ok(l) = front::read_str(&text, "m.dat", Format::Ttc) {
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

// ---- Run files as the TTC ships them: tab-separated headers, multi-word units, MAT-files,
// ---- the tire each file names.

/// The first header style: tab-separated, `deg c` temperatures, `SAE` slip ratio.
const SHIPPED_SI: &str = "Tire_Name=Hoosier 43075 16x7.5-10 R25B; Rim_Width=7; Run 071\n\
ET\tV\tN\tSA\tIA\tRL\tRE\tP\tFX\tFY\tFZ\tMX\tMZ\tNFX\tNFY\tRST\tTSTI\tTSTC\tTSTO\tAmbTmp\tSR\n\
s\tkph\trpm\tdeg\tdeg\tcm\tcm\tkPa\tN\tN\tN\tNm\tNm\tnone\tnone\tdeg c\tdeg c\tdeg c\tdeg c\tdeg c\tSAE\n\
0.00\t72.0\t400\t-3.0\t2.0\t22.9\t23.6\t68.9\t-20.0\t900.0\t-1500.0\t4.0\t-25.0\t-0.01\t0.6\t40\t45.0\t48.0\t54.0\t22.0\t-0.03\n\
0.01\t72.0\t400\t3.0\t2.0\t22.9\t23.6\t68.9\t-20.0\t-900.0\t-1500.0\t4.0\t25.0\t-0.01\t-0.6\t40\t45.0\t48.0\t54.0\t22.0\t-0.03\n";

#[test]
fn shipped_si_header_tabs_deg_c_and_sae() {
    let l = front::read_str(SHIPPED_SI, "cornering.dat", Format::Ttc).unwrap();
    let ds = &l.dataset;
    // Run from the title's "Run 071"; the tire from Tire_Name and Rim_Width.
    assert_eq!(ds.run, vec![71, 71].into());
    assert_eq!(
        l.sources[0].tire.as_deref(),
        Some("Hoosier 43075 16x7.5-10 R25B, 7 inch rim")
    );
    // 72 kph = 20 m/s; FZ -1500 N is a 1500 N load; alpha = -SA; SAE slip ratio as a ratio.
    assert!(near(column(&l, Quantity::Speed)[0], 20.0));
    assert_eq!(ds.fz, vec![1500.0, 1500.0].into());
    let alpha = column(&l, Quantity::Alpha);
    assert!(near(alpha[0], 3f64.to_radians()) && near(alpha[1], -(3f64.to_radians())));
    assert!(near(column(&l, Quantity::Gamma)[0], 2f64.to_radians()));
    assert_eq!(column(&l, Quantity::Kappa), vec![-0.03, -0.03]);
    // "deg c" tread temperatures: the mean of 45, 48 and 54.
    assert!(near(column(&l, Quantity::Temperature)[0], 49.0));
    // Fx, Fy, Mz keep their signs: alpha > 0 with Fy > 0 and Mz < 0 in the paper's axes.
    assert_eq!(column(&l, Quantity::Fy), vec![900.0, -900.0]);
    assert_eq!(column(&l, Quantity::Mz), vec![-25.0, 25.0]);
    assert_eq!(column(&l, Quantity::Fx), vec![-20.0, -20.0]);
    assert!(has_note(
        &l,
        "channels not used: N RL RE MX NFX NFY RST AmbTmp"
    ));
    assert!(has_note(
        &l,
        "tire: Hoosier 43075 16x7.5-10 R25B, 7 inch rim"
    ));
    // Detected by content too.
    assert_eq!(Format::detect(Path::new("x"), SHIPPED_SI), Format::Ttc);
    // The tire reaches the JSON record of the input.
    let json = serde_json::to_value(&l.sources[0]).unwrap();
    assert_eq!(json["tire"], "Hoosier 43075 16x7.5-10 R25B, 7 inch rim");
    assert_eq!(json["format"], "ttc");
}

/// The second header style: `sec`, `N-m`, `deg C`, and `none none` for SR and SL.
fn second_style(separator: &str) -> String {
    let head = [
        "ET V N SA IA RL RE P FX FY FZ MX MZ NFX NFY RST TSTI TSTC TSTO AmbTmp SR SL",
        "sec kph rpm deg deg cm cm kPa N N N N-m N-m none none deg C deg C deg C deg C deg C none none",
    ];
    let names: Vec<&str> = head[0].split(' ').collect();
    // Unit entries, each kept whole ("deg C").
    let mut units: Vec<String> = Vec::new();
    let words: Vec<&str> = head[1].split(' ').collect();
    let mut i = 0;
    while i < words.len() {
        if words[i] == "deg" && words.get(i + 1) == Some(&"C") {
            units.push(format!("deg {}", words[i + 1]));
            i += 2;
        } else {
            units.push(words[i].to_string());
            i += 1;
        }
    }
    assert_eq!(units.len(), names.len());
    let row = "0.0 36.0 300 2.0 0.0 22.9 23.6 82.7 150.0 -700.0 -1000.0 3.0 15.0 0.15 -0.7 40 50.0 60.0 70.0 22.0 0.04 0.05";
    format!(
        "Tire_Name=Avon 7.0/16.0-13; Rim_Width=6.5\n{}\n{}\n{}\n",
        names.join(separator),
        units.join(separator),
        row.replace(' ', separator)
    )
}

#[test]
fn second_header_style_sec_n_m_deg_c_and_sr_sl() {
    // Tab-separated as shipped, and the same with blanks: the unit words are grouped.
    for sep in ["\t", " ", "  "] {
        let text = second_style(sep);
        let l = front::read_str(&text, "B1800run12.dat", Format::Ttc)
            .unwrap_or_else(|e| panic!("separator {sep:?}: {e}"));
        assert_eq!(l.dataset.run, vec![12].into());
        assert_eq!(
            l.sources[0].tire.as_deref(),
            Some("Avon 7.0/16.0-13, 6.5 inch rim")
        );
        // SR (not SL) is kappa; N-m is N m; deg C; sec.
        assert_eq!(column(&l, Quantity::Kappa), vec![0.04]);
        assert_eq!(column(&l, Quantity::Mz), vec![15.0]);
        assert!(near(column(&l, Quantity::Temperature)[0], 60.0));
        assert_eq!(column(&l, Quantity::Time), vec![0.0]);
        assert!(near(column(&l, Quantity::Alpha)[0], -(2f64.to_radians())));
        assert!(has_note(
            &l,
            "channels not used: N RL RE MX NFX NFY RST AmbTmp"
        ));
    }
}

#[test]
fn us_units_as_shipped_mph_lb_ft_lb_psi_deg_f() {
    let text = "Tire_Name=Goodyear D2692; Rim_Width=8\n\
        ET\tV\tSA\tIA\tP\tFX\tFY\tFZ\tMZ\tTSTI\tTSTC\tTSTO\tSR\n\
        s\tmph\tdeg\tdeg\tpsi\tlb\tlb\tlb\tft-lb\tdeg F\tdeg F\tdeg F\tSAE\n\
        0\t45.0\t-1.0\t0.0\t10.0\t5.0\t100.0\t-300.0\t-4.0\t131.0\t140.0\t149.0\t0.0\n";
    let l = front::read_str(text, "B1700run3.dat", Format::Ttc).unwrap();
    // 10 psi = 68.9476 kPa; 45 mph = 20.1168 m/s; 300 lb = 1334.4665 N; 140 degF = 60 degC;
    // 4 ft-lb = 5.4233 N m; 100 lb = 444.8222 N.
    assert!(near(
        column(&l, Quantity::Pressure)[0],
        68.947_572_931_683_61
    ));
    assert!(
        (column(&l, Quantity::Pressure)[0] - 68.9476).abs() < 1e-4,
        "10 psi"
    );
    assert!(near(column(&l, Quantity::Speed)[0], 20.1168));
    assert!(near(l.dataset.fz[0], 1_334.466_484_578_15));
    assert!(near(column(&l, Quantity::Temperature)[0], 60.0));
    assert!(near(column(&l, Quantity::Mz)[0], -5.423_271_793_325_602));
    assert!(near(column(&l, Quantity::Fy)[0], 444.822_161_526_05));
    assert!(near(column(&l, Quantity::Alpha)[0], 1f64.to_radians()));
}

#[test]
fn bad_unit_lines_name_the_entry_and_its_text() {
    // A unit no vocabulary knows, in a line that is not one word per channel.
    let e = ttc_err("t\nET\tFZ\tSA\tRST\tTSTC\ns N deg Kelvinish deg C\n0 -1000 1 20 30\n");
    assert_eq!(e.line, Some(3));
    assert!(
        e.message
            .contains("\"Kelvinish\" (word 4) is not a known unit")
            && e.message.contains("channel RST (entry 4)"),
        "{e}"
    );
    // Known units, too few of them.
    let e = ttc_err("t\nET FZ SA FY MZ\ns N deg N\n0 -1000 1 -50 3\n");
    assert_eq!(e.line, Some(3));
    assert!(e.message.contains("gives 4 units for 5 channels"), "{e}");
    // Tab-separated with a unit that fits no quantity of its channel.
    let e = ttc_err("t\nET\tFZ\tSA\tFY\ns\tN\tdeg c\tN\n0\t-1000\t1\t-50\n");
    assert_eq!((e.line, e.column.as_deref()), (Some(3), Some("SA")));
    assert!(
        e.message.contains("\"deg c\" is not accepted for alpha"),
        "{e}"
    );
    // Two tabs in a row in the name line.
    let e = ttc_err("t\nET\t\tFZ\tSA\ns\tN\tN\tdeg\n");
    assert_eq!(e.line, Some(2));
    assert!(e.message.contains("channel 2 has no name"), "{e}");
    // A title in other axes than SAE.
    let e = ttc_err("Tire_Name=X; Coordinate_System=ISO\nFZ\tSA\tFY\nN\tdeg\tN\n-1\t1\t1\n");
    assert_eq!(e.line, Some(1));
    assert!(e.message.contains("SAE axes only"), "{e}");
}

#[test]
fn mat_file_reads_as_its_ascii_twin() {
    for run in ["B2356run4", "B2356run5"] {
        let dat = front::load(&ttc_fixture(&format!("{run}.dat"))).unwrap();
        let mat = front::load(&ttc_fixture(&format!("{run}.mat"))).unwrap();
        assert_eq!(mat.sources[0].format, Format::Mat);
        assert_eq!(dat.sources[0].format, Format::Ttc);
        let (a, b) = (&dat.dataset, &mat.dataset);
        assert_eq!(a.len(), b.len(), "{run}");
        assert_eq!(a.run, b.run, "{run}");
        assert_eq!(a.fz, b.fz, "{run}");
        for q in Quantity::ALL {
            assert_eq!(a.column(q), b.column(q), "{run} {q:?}");
        }
        assert_eq!(dat.sources[0].tire, mat.sources[0].tire, "{run}");
        assert_eq!(
            mat.sources[0].tire.as_deref(),
            Some("Hoosier 43075 16x7.5-10 R25B, 7 inch rim")
        );
        // The same channel notes, whichever the format.
        // (The .mat names the ambient temperature AMBTMP, the .dat AmbTmp.)
        for part in [
            "channels not used",
            "alpha = -SA",
            "tread temperature",
            "tire: ",
        ] {
            let pick = |l: &Loaded| {
                l.notes
                    .iter()
                    .find(|n| n.contains(part))
                    .map(|n| n.to_ascii_uppercase())
            };
            assert_eq!(pick(&dat), pick(&mat), "{run}: {part}");
        }
        assert!(
            has_note(&mat, "test: Cornering (testid)"),
            "{:?}",
            mat.notes
        );
    }
    // Values after conversion, from the .mat alone: run 4 row 1 is SA -6 deg, FZ -1112.1 N,
    // FY 1500.2 N; run 5 row 1 is 25 mph, 12 psi, FZ -250 lb, tread 113/117/121 degF.
    let si = front::load(&ttc_fixture("B2356run4.mat")).unwrap();
    assert_eq!(si.dataset.run, vec![4; 8].into());
    assert!(near(column(&si, Quantity::Alpha)[0], 6f64.to_radians()));
    assert_eq!(si.dataset.fz[0], 1112.1);
    assert_eq!(column(&si, Quantity::Fy)[0], 1500.2);
    assert_eq!(column(&si, Quantity::Kappa)[0], 0.002);
    assert!(near(column(&si, Quantity::Temperature)[0], 47.3));
    let us = front::load(&ttc_fixture("B2356run5.mat")).unwrap();
    assert!(near(column(&us, Quantity::Speed)[0], 11.176));
    assert!(near(
        column(&us, Quantity::Pressure)[0],
        82.737_087_518_020_33
    ));
    assert!(near(us.dataset.fz[0], 1_112.055_403_815_125));
    assert!(near(
        column(&us, Quantity::Temperature)[0],
        47.222_222_222_222_22
    ));
    assert_eq!(column(&us, Quantity::Kappa)[0], 0.01);
    assert!(has_note(&us, "from SR (effective rolling radius)"));
}

#[test]
fn mat_file_without_channel_units_assumes_ttc_si_units() {
    let twin = front::load(&ttc_fixture("B2356run4.mat")).unwrap();
    let l = front::load(&ttc_fixture("B2356run6_nochannel.mat")).unwrap();
    assert_eq!(l.dataset.run, vec![6; 8].into());
    assert!(has_note(&l, "there is no struct channel"), "{:?}", l.notes);
    assert!(has_note(&l, "TTC's SI units (assumed: ET s, V kph"));
    for q in Quantity::ALL {
        assert_eq!(l.dataset.column(q), twin.dataset.column(q), "{q:?}");
    }
}

#[test]
fn mat_files_are_found_by_header_and_in_directories() {
    let bytes = std::fs::read(ttc_fixture("B2356run4.mat")).unwrap();
    // Under another extension: by its header text.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ttc-mat-dir");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let odd = dir.join("B2356run4.bin");
    std::fs::write(&odd, &bytes).unwrap();
    let l = front::load(&odd).unwrap();
    assert_eq!(l.sources[0].format, Format::Mat);
    std::fs::remove_file(&odd).unwrap();
    // A header text in scipy's wording (no comma after "MAT-file") reads the same.
    let mut scipy = bytes.clone();
    scipy[19] = b' ';
    let again = front::load_bytes(&ttc_fixture("B2356run4.mat"), scipy.clone()).unwrap();
    assert_eq!(
        again.dataset,
        front::load(&ttc_fixture("B2356run4.mat")).unwrap().dataset
    );
    std::fs::write(dir.join("B2356run4.mat"), &scipy).unwrap();
    // Not a MAT-file at all, under the .mat extension.
    let e = front::load_bytes(Path::new("x.mat"), b"ET V FZ\n".to_vec()).unwrap_err();
    assert!(e.message.contains("not a MATLAB MAT-file"), "{e}");
    // A directory: the .mat is listed beside the .dat files; a run present as both .dat and
    // .mat is read once, from the .mat.
    std::fs::copy(ttc_fixture("B2356run4.dat"), dir.join("B2356run4.dat")).unwrap();
    std::fs::copy(ttc_fixture("B2356run5.dat"), dir.join("B2356run5.dat")).unwrap();
    let (files, notes) = tire_gap::io::input::expand(std::slice::from_ref(&dir)).unwrap();
    let names: Vec<String> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["B2356run4.mat", "B2356run5.dat"]);
    assert!(notes[0].contains("as both .dat and .mat"), "{notes:?}");
    let l = front::load_many(&files).unwrap();
    assert_eq!(l.dataset.runs(), vec![4, 5]);
    assert_eq!(l.sources[0].format, Format::Mat);
    assert!(
        has_note(&l, "every file (2): tire: Hoosier"),
        "{:?}",
        l.notes
    );
    // Both forms of one run named on the command line: refused.
    let both = [dir.join("B2356run4.dat"), dir.join("B2356run4.mat")];
    let e = tire_gap::io::input::expand(&both).unwrap_err();
    assert!(e.message.contains("same TTC run in MATLAB form"), "{e}");
}

#[test]
fn two_tires_in_one_folder_are_refused_naming_both() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ttc-two-tires");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(ttc_fixture("B2356run4.mat"), dir.join("B2356run4.mat")).unwrap();
    std::fs::copy(ttc_fixture("B2356run5.dat"), dir.join("B2356run5.dat")).unwrap();
    std::fs::write(dir.join("B1800run12.dat"), second_style("\t")).unwrap();
    let e = front::load_paths(std::slice::from_ref(&dir)).unwrap_err();
    assert!(
        e.message.contains("2 different tires")
            && e.message.contains("\"Avon 7.0/16.0-13, 6.5 inch rim\" (")
            && e.message.contains("B1800run12.dat")
            && e.message
                .contains("\"Hoosier 43075 16x7.5-10 R25B, 7 inch rim\" (")
            && e.message.contains("B2356run4.mat, ")
            && e.message.contains("B2356run5.dat")
            && e.message.contains("diagnose each tire's files separately"),
        "{e}"
    );
    // The command line: bad input, exit 2, both tires named.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_tire-gap"))
        .arg("diagnose")
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("Avon 7.0/16.0-13") && stderr.contains("Hoosier 43075"),
        "{stderr}"
    );
    // Files naming no tire beside named ones: a note, not a refusal.
    std::fs::remove_file(dir.join("B1800run12.dat")).unwrap();
    let plain = std::fs::read_to_string(ttc_fixture("B1464run23.dat")).unwrap();
    std::fs::write(dir.join("B1464run23.dat"), plain).unwrap();
    let l = front::load_paths(std::slice::from_ref(&dir)).unwrap();
    assert_eq!(l.dataset.runs(), vec![23, 4, 5]);
    assert!(
        has_note(&l, "no tire name in")
            && has_note(
                &l,
                "B1464run23.dat: taken as the same tire as the other files"
            ),
        "{:?}",
        l.notes
    );
    assert_eq!(l.sources[0].tire, None);
    assert!(l.sources[1].tire.is_some());
}

#[test]
fn mangled_mat_files_give_an_error_or_a_whole_data_set_never_a_panic() {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    let bytes = [0u8, 1, 2, 8, 14, 15, 16, 255];
    let (mut read, mut refused) = (0, 0);
    // Any edit anywhere (mostly caught by the element framing), and byte changes inside the
    // uncompressed arrays (which reach the array decoder).
    for (seed, inside) in [
        ("B2356run4.mat", false),
        ("B2356run7_plain.mat", false),
        ("B2356run7_plain.mat", true),
    ] {
        let seed = std::fs::read(ttc_fixture(seed)).unwrap();
        for _ in 0..600 {
            let mut b = seed.clone();
            for _ in 0..1 + next(4) {
                let i = next(b.len());
                match (inside, next(3)) {
                    (true, _) => {
                        let at = 136 + next(b.len() - 136);
                        b[at] = bytes[next(bytes.len())];
                    }
                    (false, 0) => {
                        b.remove(i);
                    }
                    (false, 1) => b.insert(i, bytes[next(bytes.len())]),
                    (false, _) => b[i] = bytes[next(bytes.len())],
                }
            }
            if !inside && next(6) == 0 {
                b.truncate(next(b.len()));
            }
            match front::load_bytes(Path::new("B9run1.mat"), b) {
                Ok(l) => {
                    read += 1;
                    let d = &l.dataset;
                    assert!(!d.is_empty());
                    assert_eq!(d.run.len(), d.len());
                    for q in Quantity::ALL {
                        if let Some(c) = d.column(q) {
                            assert_eq!(c.len(), d.len());
                            assert!(c.iter().all(|v| v.is_finite()));
                        }
                    }
                }
                Err(e) => {
                    refused += 1;
                    assert!(!e.message.is_empty());
                }
            }
        }
    }
    // Both outcomes occur: the mutations are not all fatal, nor all harmless.
    assert!(read > 0 && refused > 0, "read {read}, refused {refused}");
}

/// A file with both slip ratios: SL is taken where it reads zero at free rolling and SR does
/// not; SL saved as zeros (a dead channel) is never taken where SR is swept, whatever it reads
/// at free rolling; in a cornering run, where SR only wanders, the zero SL is the slip held.
#[test]
fn of_two_slip_ratios_the_one_at_zero_at_free_rolling_is_read_but_never_a_dead_one_where_sr_is_swept()
 {
    let file = |name: &str, sl_of: fn(f64) -> f64| {
        let mut text = String::from("title\nET V FZ SA SR SL FX FY\ns kph N deg none none N N\n");
        for i in 0..41 {
            let sl = -0.2 + 0.01 * i as f64;
            let (sr, fx) = (sl - 0.02, 2000.0 * sl);
            text.push_str(&format!(
                "{} 40 -1000 0 {sr} {} {fx} 0\n",
                0.1 * i as f64,
                sl_of(sl)
            ));
        }
        write("two_slip_ratios", name, &text)
    };
    let offset = front::load(&file("offset.dat", |sl| sl)).unwrap();
    assert!(
        has_note(&offset, "from SL (loaded radius), not SR"),
        "{:?}",
        offset.notes
    );
    assert!(near(column(&offset, Quantity::Kappa)[20], 0.0));
    let dead = front::load(&file("dead.dat", |_| 0.0)).unwrap();
    assert!(
        has_note(&dead, "SL (loaded radius) not used: it barely varies"),
        "{:?}",
        dead.notes
    );
    assert!(near(column(&dead, Quantity::Kappa)[20], -0.02));
    // A cornering run: SL held at zero, SR wandering a few percent with the slip angle (as
    // Round 3-9 cornering files read). SR is not swept, so the zero SL is the slip ratio held.
    let mut text = String::from("title\nET V FZ SA SR SL FX FY\ns kph N deg none none N N\n");
    for i in 0..201 {
        let sa = -10.0 + 0.1 * i as f64;
        let sr = -0.01 - 0.004 * f64::abs(sa);
        let fx = 30.0 * f64::abs(sa);
        text.push_str(&format!(
            "{} 40 -1000 {sa} {sr} 0 {fx} {}\n",
            0.1 * i as f64,
            150.0 * sa
        ));
    }
    let cornering = front::load(&write("two_slip_ratios", "cornering.dat", &text)).unwrap();
    assert!(
        has_note(&cornering, "from SL (loaded radius), not SR"),
        "{:?}",
        cornering.notes
    );
    assert!(
        column(&cornering, Quantity::Kappa)
            .iter()
            .all(|k| *k == 0.0)
    );
}

#[test]
fn one_run_as_dat_and_mat_under_other_names_is_read_once() {
    // B2356run4 in both forms, the .dat renamed so that no name pairs them.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ttc-renamed-twin");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let dat = dir.join("B2356run4_export.dat");
    std::fs::copy(ttc_fixture("B2356run4.dat"), &dat).unwrap();
    let mat = ttc_fixture("B2356run4.mat");
    let l = front::load_many(&[mat.clone(), dat]).unwrap();
    let alone = front::load(&mat).unwrap();
    assert_eq!(l.dataset.len(), alone.dataset.len());
    assert_eq!(l.dataset.runs(), alone.dataset.runs());
    assert!(
        has_note(&l, "B2356run4_export.dat holds the same 8 rows as"),
        "{:?}",
        l.notes
    );
}
