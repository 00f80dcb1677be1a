//! Reading CSV and TYDEX files: values in internal units, notes, and errors that name
//! file, line and column.

mod common;

use common::{fixture, write};
use std::path::Path;
use tire_gap::front;
use tire_gap::io::input::{Format, InputError, Loaded};

/// A fresh file under cargo's per-test temporary directory.
fn csv(text: &str) -> Result<Loaded, InputError> {
    front::read_str(text, "data.csv", Format::Csv)
}

fn csv_err(text: &str) -> InputError {
    match csv(text) {
        Ok(l) => panic!("expected an error, got {} samples", l.dataset.len()),
        Err(e) => e,
    }
}

fn tdx_err(text: &str) -> InputError {
    match front::read_str(text, "t.tdx", Format::Tydex) {
        Ok(l) => panic!("expected an error, got {} samples", l.dataset.len()),
        Err(e) => e,
    }
}

fn close(a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{a:?} vs {b:?}");
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() <= 1e-12 * y.abs().max(1.0), "{a:?} vs {b:?}");
    }
}

fn has_note(l: &Loaded, part: &str) -> bool {
    l.notes.iter().any(|n| n.contains(part))
}

const GOOD: &str = "\
run,t_s,vx_mps,fz_N,alpha_deg,kappa,gamma_deg,p_kPa,temp_C,fx_N,fy_N,mz_Nm,comment
1,0.0,16.7,4000,-2,0.00,0,210,45.5,10,-1500,-32,start
1,0.1,16.7,4000,0,0.05,1,210,46,2000,0,0,
2,0.0,16.7,6000,2,-0.10,-1,210,47,-3000,1800,40,\"a, b\"
";

#[test]
fn good_csv_round_trips_to_internal_units() {
    let path = write("input-tests", "good.csv", GOOD);
    let l = front::load(&path).unwrap();
    let d = &l.dataset;
    assert_eq!(d.source, path.display().to_string());
    assert_eq!(d.len(), 3);
    assert_eq!(d.run, vec![1, 1, 2].into());
    assert_eq!(d.runs(), vec![1, 2]);
    assert_eq!(d.time.as_deref(), Some(&[0.0, 0.1, 0.0][..]));
    assert_eq!(d.speed.as_deref(), Some(&[16.7; 3][..]));
    assert_eq!(d.fz, vec![4000.0, 4000.0, 6000.0].into());
    close(
        d.alpha.as_deref().unwrap(),
        &[(-2.0f64).to_radians(), 0.0, 2.0f64.to_radians()],
    );
    assert_eq!(d.kappa.as_deref(), Some(&[0.0, 0.05, -0.10][..]));
    close(
        d.gamma.as_deref().unwrap(),
        &[0.0, 1.0f64.to_radians(), (-1.0f64).to_radians()],
    );
    assert_eq!(d.pressure.as_deref(), Some(&[210.0; 3][..]));
    assert_eq!(d.temperature.as_deref(), Some(&[45.5, 46.0, 47.0][..]));
    assert_eq!(d.fx.as_deref(), Some(&[10.0, 2000.0, -3000.0][..]));
    assert_eq!(d.fy.as_deref(), Some(&[-1500.0, 0.0, 1800.0][..]));
    assert_eq!(d.mz.as_deref(), Some(&[-32.0, 0.0, 40.0][..]));
    assert!(has_note(
        &l,
        "ignored column(s) tire-gap does not use: comment"
    ));
    assert_eq!(l.notes.len(), 1, "{:?}", l.notes);
}

#[test]
fn other_units_are_converted() {
    let l = csv("\
RUN,T_ms,vx_kph,fz_kN,alpha_rad,kappa_pct,gamma_rad,p_bar,temp_K,fx_kN,fy_N,mz_N.m
3,1500,36,4.5,0.05,10,-0.02,2.1,300.15,1.5,-900,12.5
")
    .unwrap();
    let d = &l.dataset;
    assert_eq!(d.run, vec![3].into());
    close(d.time.as_deref().unwrap(), &[1.5]);
    close(d.speed.as_deref().unwrap(), &[10.0]);
    close(&d.fz, &[4500.0]);
    close(d.alpha.as_deref().unwrap(), &[0.05]);
    close(d.kappa.as_deref().unwrap(), &[0.1]);
    close(d.gamma.as_deref().unwrap(), &[-0.02]);
    close(d.pressure.as_deref().unwrap(), &[210.0]);
    close(d.temperature.as_deref().unwrap(), &[27.0]);
    close(d.fx.as_deref().unwrap(), &[1500.0]);
    close(d.mz.as_deref().unwrap(), &[12.5]);
}

#[test]
fn missing_optional_columns_are_none() {
    let l = csv("run,fz_N,alpha_deg,fy_N\n1,3000,1,500\n1,3000,2,900\n").unwrap();
    let d = &l.dataset;
    assert_eq!(d.fz, vec![3000.0, 3000.0].into());
    assert!(d.time.is_none() && d.speed.is_none() && d.kappa.is_none());
    assert!(d.gamma.is_none() && d.pressure.is_none() && d.temperature.is_none());
    assert!(d.fx.is_none() && d.mz.is_none());
    assert_eq!(d.fy.as_deref(), Some(&[500.0, 900.0][..]));
    assert!(l.notes.is_empty(), "{:?}", l.notes);
}

#[test]
fn measured_channel_without_its_slip_is_dropped_with_a_note() {
    let l = csv("run,fz_N,alpha_deg,fx_N,fy_N\n1,3000,1,50,500\n").unwrap();
    assert!(l.dataset.fx.is_none());
    assert_eq!(l.dataset.fy.as_deref(), Some(&[500.0][..]));
    assert!(has_note(
        &l,
        "fx_N ignored: it needs the slip kappa (kappa)"
    ));

    let e = csv_err("run,fz_N,alpha_deg,fx_N\n1,3000,1,50\n");
    assert_eq!((e.line, e.column.as_deref()), (None, None));
    assert!(e.message.starts_with("no measured force or moment"), "{e}");
}

#[test]
fn runs_split_where_time_resets() {
    let l = csv("t_s,fz_N,kappa,fx_N\n0,3000,0,0\n0.1,3000,0.1,900\n0,3000,0,0\n0.1,3000,0.1,950\n0.05,3000,0.1,950\n").unwrap();
    assert_eq!(l.dataset.run, vec![1, 1, 2, 2, 3].into());
    assert!(
        has_note(&l, "split into 3 runs where t_s decreases (at lines 4, 6)"),
        "{:?}",
        l.notes
    );

    let l = csv("t_s,fz_N,kappa,fx_N\n0,3000,0,0\n0.1,3000,0.1,900\n").unwrap();
    assert_eq!(l.dataset.run, vec![1, 1].into());
    assert!(has_note(&l, "cross-validation by run will not be possible"));

    let l = csv("fz_N,kappa,fx_N\n3000,0,0\n").unwrap();
    assert_eq!(l.dataset.run, vec![1].into());
    assert!(has_note(&l, "no run column and no time column"));
}

#[test]
fn lenient_layout() {
    // BOM, CRLF, semicolons, comment and blank lines, spaces around cells.
    let text = "\u{feff}# exported by a rig\r\nrun ; FZ_N ; Alpha_Deg ; fy_N\r\n\r\n1 ; 3000 ; 1 ; 500\r\n# pause\r\n2;3000;-1;-480\r\n";
    let l = front::load(&write("input-tests", "semi.txt", text)).unwrap();
    assert_eq!(l.dataset.run, vec![1, 2].into());
    assert_eq!(l.dataset.fy.as_deref(), Some(&[500.0, -480.0][..]));
    // Line numbers are physical lines, comments and blanks included.
    let e = csv_err("run,fz_N,alpha_deg,fy_N\n# note\n\n1,3000,x,500\n");
    assert_eq!(e.line, Some(4));
    let e = csv_err("# rig export\n\nrun,fz_N,alpha_dg,fy_N\n1,3000,1,500\n");
    assert_eq!((e.line, e.column.as_deref()), (Some(3), Some("alpha_dg")));
}

#[test]
fn kappa_above_one_gets_a_note() {
    let l = csv("run,fz_N,kappa,fx_N\n1,3000,5,900\n").unwrap();
    assert!(has_note(&l, "kappa_pct"), "{:?}", l.notes);
}

#[test]
fn unloaded_samples_get_a_note() {
    let l = csv("run,fz_N,kappa,fx_N\n1,-20,0,0\n1,3000,0.1,900\n").unwrap();
    assert!(has_note(&l, "1 of 2 samples have Fz <= 0"), "{:?}", l.notes);
}

/// (csv text, line, column, message start)
type Case = (
    &'static str,
    Option<usize>,
    Option<&'static str>,
    &'static str,
);

#[test]
fn bad_csv_names_line_and_column() {
    let cases: &[Case] = &[
        (
            "run,alpha_deg,fy_N\n1,1,500\n",
            None,
            Some("fz_N"),
            "missing required column: fz_N (or fz_kN)",
        ),
        (
            "run,fz_N,alpha_grad,fy_N\n1,3000,1,500\n",
            Some(1),
            Some("alpha_grad"),
            "unit \"grad\" is not accepted for alpha; accepted units: deg, degree, degrees, °, rad",
        ),
        (
            "run,fz,alpha_deg,fy_N\n1,3000,1,500\n",
            Some(1),
            Some("fz"),
            "Fz needs a unit suffix: write fz_N, fz_kN, fz_lbf",
        ),
        (
            "run,fz_N,alpha_deg,fy_N\n1,3000,1,500\n1,3000,abc,500\n",
            Some(3),
            Some("alpha_deg"),
            "\"abc\" is not a number",
        ),
        (
            "run,fz_N,alpha_deg,fy_N\n1,3000,1,NaN\n",
            Some(2),
            Some("fy_N"),
            "\"NaN\" is not a finite number",
        ),
        (
            "run,fz_N,alpha_deg,fy_N\n1,inf,1,5\n",
            Some(2),
            Some("fz_N"),
            "\"inf\" is not a finite number",
        ),
        (
            "run,fz_N,alpha_deg,fy_N\n1,3000,,5\n",
            Some(2),
            Some("alpha_deg"),
            "empty cell",
        ),
        ("", None, None, "the file is empty"),
        (" \n\n", None, None, "the file is empty"),
        (
            "run,fz_N,alpha_deg,fy_N\n",
            None,
            None,
            "no data rows: the file has only a header",
        ),
        (
            "run,fz_N,alpha_deg,fy_N\n1,3000,1,5\n1,3000,1\n",
            Some(3),
            None,
            "row has 3 fields but the header has 4",
        ),
        (
            "run,fz_N,alpha_deg,fy_N\n1,3000,1,5,6\n",
            Some(2),
            None,
            "row has 5 fields but the header has 4",
        ),
        (
            "run,fz_N,alpha_deg,fy_N,alpha_rad\n1,3000,1,5,0\n",
            Some(1),
            Some("alpha_rad"),
            "duplicate column: alpha_deg and alpha_rad both give alpha",
        ),
        (
            "run,fz_N,fz_N,alpha_deg,fy_N\n1,3000,3000,1,5\n",
            Some(1),
            Some("fz_N"),
            "duplicate column: fz_N and fz_N both give Fz",
        ),
        (
            "run,fz_N,alpha_deg,fy_N\n1.5,3000,1,5\n",
            Some(2),
            Some("run"),
            "\"1.5\" is not an integer run id",
        ),
        (
            "run,fz_N,alpha_deg,fy_N\nfirst,3000,1,5\n",
            Some(2),
            Some("run"),
            "\"first\" is not a number",
        ),
        (
            "run,fz_N,alpha_deg,fy_N\n1,\"3000,1,5\n",
            Some(2),
            None,
            "row has 2 fields",
        ),
    ];
    for &(text, line, column, start) in cases {
        let e = csv_err(text);
        assert_eq!(e.file, "data.csv", "{text:?}");
        assert_eq!(e.line, line, "{text:?}: {e}");
        assert_eq!(e.column.as_deref(), column, "{text:?}: {e}");
        assert!(e.message.starts_with(start), "{text:?}: {e}");
    }
}

#[test]
fn error_display_names_file_line_and_column() {
    let path = write(
        "input-tests",
        "data.csv",
        "run,fz_N,alpha_deg,fy_N\n1,3000,1,5\n1,3000,abc,5\n",
    );
    let e = front::load(&path).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}:3: column alpha_deg: \"abc\" is not a number",
            path.display()
        )
    );
    let e = front::load(Path::new("/nonexistent/dir/x.csv")).unwrap_err();
    assert!(e.message.starts_with("cannot read the file"), "{e}");
}

#[test]
fn tydex_fixture_scaling_constants_and_axes() {
    let l = front::load(&fixture("lateral.tdx")).unwrap();
    let d = &l.dataset;
    assert_eq!(d.len(), 3);
    // MEASID is the run id.
    assert_eq!(d.run, vec![7, 7, 7].into());
    // RUNTIME: raw * 0.01 s.
    close(d.time.as_deref().unwrap(), &[0.0, 0.1, 0.2]);
    // LONGVEL 60 km/h.
    close(d.speed.as_deref().unwrap(), &[60.0 / 3.6; 3]);
    // SLIPANGL: raw * 0.1 deg, sign kept.
    close(
        d.alpha.as_deref().unwrap(),
        &[(-2.0f64).to_radians(), 0.0, 2.0f64.to_radians()],
    );
    close(
        d.gamma.as_deref().unwrap(),
        &[0.0, 0.0, 1.0f64.to_radians()],
    );
    // FZW: -4500 * 0.001 + 0.5 = -4 kN, negative (z up), so negated to 4000 N.
    close(&d.fz, &[4000.0; 3]);
    // FYW: raw * 10 N, then negated (ISO y left -> paper y right).
    close(d.fy.as_deref().unwrap(), &[-1500.0, 50.0, 1600.0]);
    // MZW: raw * 1 - 2 N.m, then negated.
    close(d.mz.as_deref().unwrap(), &[32.0, 0.0, -32.0]);
    // INFLPRES is a constant: 2.2 bar for every sample.
    close(d.pressure.as_deref().unwrap(), &[220.0; 3]);
    assert!(d.kappa.is_none() && d.fx.is_none() && d.temperature.is_none());
    assert!(has_note(&l, "FYW and MZW negated"), "{:?}", l.notes);
    assert!(has_note(&l, "FZW is mostly negative (z up): negated"));
    assert!(has_note(&l, "pressure held at the constant INFLPRES"));
    assert!(has_note(
        &l,
        "ignored TYDEX channel(s) tire-gap does not use: MEASNUMB"
    ));
}

/// A fixed-column TYDEX channel line.
fn channel(name: &str, unit: &str, numbers: &str) -> String {
    format!("{name:<10}{:<30}{unit:<10}{numbers}", "some description")
}

fn tydex(channels: &[String], rows: &[&str]) -> String {
    format!(
        "**HEADER\nRELEASE 1.3\n**MEASURCHANNELS\n{}\n**MEASURDATA\n{}\n**END\n",
        channels.join("\n"),
        rows.join("\n")
    )
}

#[test]
fn tydex_longitudinal_percent_slip_and_h_axes() {
    let text = tydex(
        &[
            channel("LONGSLIP", "%", "1"),
            channel("FZH", "N", "1"),
            channel("FXH", "N", "1"),
            channel("FX", "N", "1"),
            channel("TREADTMP", "deg C", "1"),
            channel("INFLPRES", "kPa", "1"),
        ],
        &["-5 3000 -900 -901 60 200", "5 3000 910 911 61 200"],
    );
    let l = front::read_str(&text, "long.tdx", Format::Tydex).unwrap();
    let d = &l.dataset;
    close(d.kappa.as_deref().unwrap(), &[-0.05, 0.05]);
    // FX is preferred to FXH; Fx keeps its sign; positive FZ stays.
    assert_eq!(d.fx.as_deref(), Some(&[-901.0, 911.0][..]));
    assert_eq!(d.fz, vec![3000.0, 3000.0].into());
    assert_eq!(d.temperature.as_deref(), Some(&[60.0, 61.0][..]));
    assert_eq!(d.run, vec![1, 1].into());
    assert!(d.alpha.is_none() && d.fy.is_none());
    assert!(has_note(&l, "Fz taken from FZH (H axes"), "{:?}", l.notes);
    assert!(has_note(&l, "does not use: FXH"), "{:?}", l.notes);
    assert!(has_note(&l, "no Fy or Mz channel to negate"));
    assert!(!has_note(&l, "mostly negative"));
}

#[test]
fn tydex_load_is_negated_only_when_more_than_half_of_it_is_negative() {
    let load = |rows: &[&str]| {
        let text = tydex(
            &[
                channel("SLIPANGL", "deg", "1"),
                channel("FZW", "N", "1"),
                channel("FYW", "N", "1"),
            ],
            rows,
        );
        front::read_str(&text, "fz.tdx", Format::Tydex).unwrap()
    };
    // Two of three negative: the median (-600) is negative, every sample negated.
    let l = load(&["0 -800 0", "1 -600 0", "2 500 0"]);
    assert_eq!(l.dataset.fz, vec![800.0, 600.0, -500.0].into());
    assert!(has_note(&l, "FZW is mostly negative (z up): negated"));
    // One of two negative is not most: the median is the upper middle value, 500.
    let l = load(&["0 -900 0", "1 500 0"]);
    assert_eq!(l.dataset.fz, vec![-900.0, 500.0].into());
    assert!(!has_note(&l, "mostly negative"));
}

#[test]
fn tydex_blank_separated_channels() {
    let text = "**MEASURCHANNELS\nSLIPANGL slip angle deg 1 0\nFZW load kN 1\nFYW lateral force N 1 0\n**MEASURDATA\n1 4 -100\n";
    let l = front::read_str(text, "loose.tdx", Format::Tydex).unwrap();
    close(l.dataset.alpha.as_deref().unwrap(), &[1.0f64.to_radians()]);
    close(&l.dataset.fz, &[4000.0]);
    close(l.dataset.fy.as_deref().unwrap(), &[100.0]);

    // A numeric unit ("1") followed by factor and offset; a negative load constant.
    let text = "**CONSTANTS\nFZW nominal load kN -3\n**MEASURCHANNELS\nLONGSLIP slip 1 0.01 0\nFXW force N 1 0\n**MEASURDATA\n5 -700\n";
    let l = front::read_str(text, "loose.tdx", Format::Tydex).unwrap();
    close(l.dataset.kappa.as_deref().unwrap(), &[0.05]);
    close(&l.dataset.fz, &[3000.0]);
    assert_eq!(l.dataset.fx.as_deref(), Some(&[-700.0][..]));
    assert!(has_note(&l, "Fz held at the constant FZW"), "{:?}", l.notes);
    assert!(has_note(&l, "constant FZW is negative"), "{:?}", l.notes);
}

#[test]
fn bad_tydex_names_line_and_channel() {
    let ok_channels = [
        channel("SLIPANGL", "deg", "1"),
        channel("FZW", "N", "1"),
        channel("FYW", "N", "1"),
    ];
    // Channel lines start at line 4 (after **HEADER, RELEASE, **MEASURCHANNELS);
    // data rows at line 8.
    let cases: Vec<(String, Option<usize>, Option<&str>, &str)> = vec![
        (
            tydex(&ok_channels, &["1 3000 -500", "2 3000 x"]),
            Some(9),
            Some("FYW"),
            "\"x\" is not a number",
        ),
        (
            tydex(&ok_channels, &["1 3000 -500", "2 3000"]),
            Some(9),
            None,
            "row has 2 values but **MEASURCHANNELS defines 3 channels",
        ),
        (
            tydex(&ok_channels, &["nan 3000 -500"]),
            Some(8),
            Some("SLIPANGL"),
            "\"nan\" is not a finite number",
        ),
        (
            tydex(
                &[
                    channel("SLIPANGL", "grad", "1"),
                    channel("FZW", "N", "1"),
                    channel("FYW", "N", "1"),
                ],
                &["1 3000 -500"],
            ),
            Some(4),
            Some("SLIPANGL"),
            "unit \"grad\" is not accepted for alpha",
        ),
        (
            tydex(
                &[
                    channel("SLIPANGL", "deg", "1"),
                    channel("FZW", "N", "1 2 3"),
                    channel("FYW", "N", "1"),
                ],
                &["1 3000 -500"],
            ),
            Some(5),
            Some("FZW"),
            "factor followed by two offsets",
        ),
        (
            tydex(
                &[
                    channel("SLIPANGL", "deg", "1"),
                    channel("FYW", "N", "1"),
                    channel("fyw", "N", "1"),
                ],
                &["1 3000 -500"],
            ),
            Some(6),
            Some("fyw"),
            "duplicate channel (first defined at line 5)",
        ),
        (
            tydex(
                &[channel("SLIPANGL", "deg", "1"), channel("FYW", "N", "1")],
                &["1 -500"],
            ),
            None,
            Some("FZW"),
            "missing required column: channel FZW",
        ),
        (
            tydex(
                &[channel("FZW", "N", "1"), channel("FYW", "N", "1")],
                &["3000 -500"],
            ),
            None,
            None,
            "no measured force or moment with the slip it depends on",
        ),
        (tydex(&ok_channels, &[]), None, None, "no data rows"),
        (
            "**HEADER\n**MEASURDATA\n1 2 3\n".to_string(),
            None,
            None,
            "no **MEASURCHANNELS section",
        ),
        (
            format!("**MEASURCHANNELS\n{}\n", ok_channels.join("\n")),
            None,
            None,
            "no **MEASURDATA section",
        ),
        (String::new(), None, None, "the file is empty"),
        (
            format!(
                "**HEADER\nMEASID  id  run7\n**MEASURCHANNELS\n{}\n**MEASURDATA\n1 3000 -5\n",
                ok_channels.join("\n")
            ),
            Some(2),
            Some("MEASID"),
            "MEASID: \"run7\" is not a number",
        ),
    ];
    for (text, line, column, start) in &cases {
        let e = tdx_err(text);
        assert_eq!(e.line, *line, "{text}\n{e}");
        assert_eq!(e.column.as_deref(), *column, "{text}\n{e}");
        assert!(e.message.starts_with(start), "{text}\n{e}");
    }
}

#[test]
fn format_is_sniffed_without_a_known_extension() {
    let text = std::fs::read_to_string(fixture("lateral.tdx")).unwrap();
    let l = front::load(&write("input-tests", "lateral.txt", &text)).unwrap();
    assert_eq!(l.dataset.run, vec![7, 7, 7].into());
    // Extension wins over content.
    let e = front::load(&write("input-tests", "lateral_as.csv", &text)).unwrap_err();
    assert_eq!(e.line, Some(1));
    assert!(e.message.ends_with("give it the .tdx extension)"), "{e}");
}

#[test]
fn latin1_files_are_read_with_a_note() {
    // "°" as the single Latin-1 byte 0xB0 in a description.
    let mut bytes = b"run,fz_N,alpha_deg,fy_N,note\n1,3000,1,5,".to_vec();
    bytes.extend_from_slice(&[b'4', 0xB0]);
    bytes.push(b'\n');
    let l = front::load(&write("input-tests", "latin1.csv", bytes)).unwrap();
    assert!(has_note(&l, "read as Latin-1"));
    assert_eq!(l.dataset.fy.as_deref(), Some(&[5.0][..]));
}

#[test]
fn runs_shared_by_files_are_numbered_in_order_of_appearance_a_run_that_comes_back_too() {
    let rows = |runs: &[i64]| {
        let mut text = String::from("run,fz_N,alpha_deg,fy_N\n");
        for (i, r) in runs.iter().enumerate() {
            text += &format!("{r},3000,{i},{}\n", 100 * i);
        }
        text
    };
    let a = write("input-tests", "shared_a.csv", rows(&[3, 3, 1, 1, 3, 8]));
    let b = write("input-tests", "shared_b.csv", rows(&[1, 2, 2, 1]));
    let l = front::load_many(&[&a, &b]).unwrap();
    // a: 3 -> 1, 1 -> 2, 8 -> 3; b: 1 -> 4, 2 -> 5.
    assert_eq!(l.dataset.run, vec![1, 1, 2, 2, 1, 3, 4, 5, 5, 4].into());
    let runs: Vec<Vec<i64>> = l.sources.iter().map(|s| s.runs.clone()).collect();
    assert_eq!(runs, vec![vec![1, 2, 3], vec![4, 5]]);
    assert!(
        has_note(&l, "runs renumbered in file order"),
        "{:?}",
        l.notes
    );
}

#[test]
fn load_many_gives_each_file_its_run_and_keeps_shared_columns() {
    let a = tydex(
        &[
            channel("SLIPANGL", "deg", "1"),
            channel("FZW", "N", "1"),
            channel("FYW", "N", "1"),
            channel("RUNTIME", "s", "1"),
        ],
        &["1 3000 -500 0", "2 3000 -900 0.1"],
    );
    let b = tydex(
        &[
            channel("SLIPANGL", "deg", "1"),
            channel("FZW", "N", "1"),
            channel("FYW", "N", "1"),
        ],
        &["-1 5000 700"],
    );
    let pa = write("input-tests", "many_a.tdx", a);
    let pb = write("input-tests", "many_b.tdx", b);
    let l = front::load_many(&[&pa, &pb]).unwrap();
    let d = &l.dataset;
    assert_eq!(d.run, vec![1, 1, 2].into());
    assert_eq!(d.fz, vec![3000.0, 3000.0, 5000.0].into());
    assert_eq!(d.fy.as_deref(), Some(&[500.0, 900.0, -700.0][..]));
    assert!(d.time.is_none());
    assert!(
        has_note(&l, "runs renumbered in file order"),
        "{:?}",
        l.notes
    );
    assert!(has_note(&l, "time dropped: missing in"), "{:?}", l.notes);
    assert_eq!(d.source, format!("{}, {}", pa.display(), pb.display()));

    // Distinct ids are kept.
    let c = write(
        "input-tests",
        "many_c.csv",
        "run,fz_N,alpha_deg,fy_N\n5,3000,1,5\n",
    );
    let e = write(
        "input-tests",
        "many_e.csv",
        "run,fz_N,alpha_deg,fy_N\n9,3000,1,7\n",
    );
    let l = front::load_many(&[c, e]).unwrap();
    assert_eq!(l.dataset.run, vec![5, 9].into());
    assert!(!has_note(&l, "renumbered"));

    let none: [&Path; 0] = [];
    assert_eq!(
        front::load_many(&none).unwrap_err().message,
        "no input files"
    );
}

#[test]
fn no_panic_on_mangled_input() {
    let tdx = std::fs::read_to_string(fixture("lateral.tdx")).unwrap();
    let seeds = [GOOD.to_string(), tdx];
    // A small deterministic generator: delete, duplicate or replace characters.
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    let junk = [
        '-', '.', 'e', '\n', ',', ' ', '*', '!', '9', 'N', '"', '\u{b0}', ';',
    ];
    for seed in &seeds {
        for _ in 0..300 {
            let mut chars: Vec<char> = seed.chars().collect();
            for _ in 0..1 + next(6) {
                let i = next(chars.len().max(1));
                match next(3) {
                    0 if !chars.is_empty() => {
                        chars.remove(i.min(chars.len() - 1));
                    }
                    1 => chars.insert(i.min(chars.len()), junk[next(junk.len())]),
                    _ if !chars.is_empty() => {
                        let j = i.min(chars.len() - 1);
                        chars[j] = junk[next(junk.len())];
                    }
                    _ => {}
                }
            }
            let text: String = chars.into_iter().collect();
            for format in [Format::Csv, Format::Tydex] {
                if let Ok(l) = front::read_str(&text, "m", format) {
                    // Whatever is accepted is complete and consistent.
                    let d = &l.dataset;
                    assert_eq!(d.run.len(), d.len());
                    for q in tire_gap::data::Quantity::ALL {
                        if let Some(c) = d.column(q) {
                            assert_eq!(c.len(), d.len());
                            assert!(c.iter().all(|v| v.is_finite()));
                        }
                    }
                }
            }
        }
    }
}

/// A CSV of 100 rows sweeping the slip angle and the slip ratio, with `edit(row, cells)`
/// applied to each row's cells (run, t_s, vx_mps, fz_N, alpha_deg, kappa, fx_N, fy_N,
/// p_kPa, temp_C).
fn sweep_csv(header: &str, edit: impl Fn(usize, &mut Vec<String>)) -> String {
    let mut text = format!("{header}\n");
    for i in 0..100 {
        let a = (i as f64 / 10.0).sin() * 8.0;
        let k = (i as f64 / 7.0).cos() * 0.1;
        let mut cells: Vec<String> = [
            (i / 25 + 1) as f64,
            i as f64 * 0.01,
            11.1,
            3000.0,
            a,
            k,
            30000.0 * k,
            400.0 * a,
            200.0,
            50.0,
        ]
        .iter()
        .map(|v| v.to_string())
        .collect();
        edit(i, &mut cells);
        text += &(cells.join(",") + "\n");
    }
    text
}

const SWEEP: &str = "run,t_s,vx_mps,fz_N,alpha_deg,kappa,fx_N,fy_N,p_kPa,temp_C";

#[test]
fn implausible_values_leave_out_rows_or_the_channel_not_the_file() {
    // A few implausible samples: their rows go, noted with the first.
    let l = csv(&sweep_csv(SWEEP, |i, c| {
        if i == 9 {
            c[4] = "95".into();
        }
        if i == 30 {
            c[5] = "11".into();
        }
        if i == 50 {
            c[3] = "-2000".into();
        }
    }))
    .unwrap();
    assert_eq!(l.dataset.len(), 97, "{:?}", l.notes);
    for part in [
        "1 of 100 rows left out: alpha outside what a tire test gives (first at row 10 of the \
         file: alpha = 95.000 deg is outside the plausible range -90..90 deg)",
        "1 of 99 rows left out: kappa outside what a tire test gives (first at row 31 of the \
         file: kappa = 11 is outside the plausible range -10..10)",
        "1 of 98 rows left out: Fz outside what a tire test gives (first at row 51 of the file: \
         Fz = -2000 N is outside",
    ] {
        assert!(has_note(&l, part), "{part}: {:?}", l.notes);
    }
    // A channel implausible throughout goes, with the measured channel that needs it.
    for (column, value, named) in [
        (
            4,
            "120",
            "alpha left out, and with it Fy (which needs it): 100 of 100 rows",
        ),
        (8, "0", "pressure left out: 100 of 100 rows"),
        (8, "2500", "pressure = 2500 kPa is outside"),
        (9, "400", "temperature left out: 100 of 100 rows"),
        (9, "-70", "temperature = -70 degC is outside"),
        (2, "200", "speed = 200 m/s is outside"),
        (2, "-1", "speed left out: 100 of 100 rows"),
    ] {
        let l = csv(&sweep_csv(SWEEP, |_, c| c[column] = value.into()))
            .unwrap_or_else(|e| panic!("{named}: {e}"));
        assert_eq!(l.dataset.len(), 100);
        assert!(has_note(&l, named), "{named}: {:?}", l.notes);
        assert!(l.dataset.fx.is_some());
    }
    // The load is required: implausible on more than a few rows, the file is refused.
    let e = csv_err(&sweep_csv(&SWEEP.replace("fz_N", "fz_kN"), |_, c| {
        c[3] = "200".into();
    }));
    assert!(
        e.message.starts_with(
            "the load is implausible on 100 of 100 rows (first at row 1 of the file: Fz = \
             200000 N is outside the plausible range"
        ),
        "{e}"
    );
    // With no measured channel left, nothing is diagnosed: the message says why.
    let e = csv_err(&sweep_csv(
        "run,t_s,vx_mps,fz_N,alpha_deg,x1,x2,fy_N,p_kPa,temp_C",
        |_, c| {
            c[4] = "150".into();
        },
    ));
    assert!(
        e.message
            .starts_with("no measured force or moment with its slip is left: alpha left out"),
        "{e}"
    );
}
