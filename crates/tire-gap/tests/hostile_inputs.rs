//! Hostile inputs to `tire-gap`: real-world file layouts and mistakes. Each case asserts the
//! exit code, the message, and that nothing is written or lost. (The FMU's hostile inputs:
//! `tests/c_abi.rs` and `crates/mf87/tests/bounds.rs` at the workspace root.)

mod common;

use common::{listing, scratch, tire_gap};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;
use tire_gap::method::observer::Unobserved;

use tire_gap::data::Dataset;
use tire_gap::front::Finished;
use tire_gap::io::report::Provenance;
use tire_gap::method::diagnose::{Options, diagnose};
use tire_gap::method::fit::effects::Extension;
use tire_gap::synth::{SynthConfig, TireKind, generate, write_csv};

/// A fresh, empty directory under cargo's per-test temporary directory.
fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Small synthetic rig data: the 1987 family (so the base model fits to the noise floor)
/// unless effects are asked for.
fn rig(effects: Vec<Extension>, tire: TireKind) -> Dataset {
    generate(&SynthConfig {
        seed: 5,
        effects,
        tire,
        rows_target: 4000,
        noise: 1.0,
        ..SynthConfig::default()
    })
}

fn write_as_csv(dir: &Path, name: &str, ds: &Dataset) -> PathBuf {
    let path = dir.join(name);
    let mut csv = Vec::new();
    write_csv(ds, &mut csv).unwrap();
    std::fs::write(&path, csv).unwrap();
    path
}

/// `diagnose FILE --params DIR/fitted.json --plots DIR/figures` must exit 2 with `message`
/// on stderr, print no report and leave DIR holding only the input.
fn refused(name: &str, ds_or_text: Result<&Dataset, &str>, message: &str) {
    let dir = scratch(&format!("hostile-inputs/{name}"));
    let input = match ds_or_text {
        Ok(ds) => write_as_csv(&dir, "data.csv", ds),
        Err(csv) => {
            let p = dir.join("data.csv");
            std::fs::write(&p, csv).unwrap();
            p
        }
    };
    let out = tire_gap::<&OsStr>(&[
        "diagnose".as_ref(),
        input.as_os_str(),
        "--params".as_ref(),
        dir.join("fitted.json").as_os_str(),
        "--plots".as_ref(),
        dir.join("figures").as_os_str(),
    ]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
    assert!(stderr.contains(message), "{name}: {stderr}");
    assert!(out.stdout.is_empty(), "{name}: {}", text(&out.stdout));
    assert_eq!(listing(&dir), vec!["data.csv"], "{name}");
}

#[test]
fn three_rows_are_refused_not_diagnosed() {
    let csv = "run,t_s,fz_N,alpha_deg,fy_N\n1,0,4000,1,900\n2,0,4000,2,1700\n3,0,4000,3,2300\n";
    refused(
        "three-rows",
        Err(csv),
        "holds 3 run(s); 5-fold cross-validation",
    );
    refused("three-rows-hint", Err(csv), "use --folds 3");
}

#[test]
fn one_row_per_run_has_no_noise_floor() {
    let mut ds = rig(Vec::new(), TireKind::Mf87Perturbed);
    ds.run = (1..=ds.len() as i64).collect();
    refused(
        "row-runs",
        Ok(&ds),
        "the noise floor cannot be measured: most rows sit in runs of fewer than 10 rows (median 1 rows per run",
    );
}

#[test]
fn no_slip_variation_is_not_a_clean_bill() {
    let mut ds = rig(Vec::new(), TireKind::Mf52);
    ds.alpha = ds.alpha.map(|a| vec![0.0; a.len()].into());
    ds.kappa = ds.kappa.map(|k| vec![0.0; k.len()].into());
    refused("no-slip", Ok(&ds), "no channel can be diagnosed");
    refused(
        "no-slip-why",
        Ok(&ds),
        "only 0 rows have a slip angle of at least 1 deg",
    );
}

#[test]
fn no_load_is_refused() {
    let mut ds = rig(Vec::new(), TireKind::Mf52);
    ds.fz = ds.fz.iter().map(|f| -0.1 * f).collect();
    refused("no-load", Ok(&ds), "no row has a load (Fz > 0)");
}

#[test]
fn radians_under_a_degree_header_leave_the_slip_angle_s_channels_out() {
    let ds = rig(Vec::new(), TireKind::Mf52);
    let dir = scratch("hostile-inputs/radians-src");
    let csv = std::fs::read_to_string(write_as_csv(&dir, "src.csv", &ds)).unwrap();
    // The slip angle in radians, its header still saying degrees.
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "alpha_deg").unwrap();
    let mut out = header.join(",") + "\n";
    for line in lines {
        let mut cells: Vec<String> = line.split(',').map(str::to_string).collect();
        let deg: f64 = cells[col].parse().unwrap();
        cells[col] = deg.to_radians().to_string();
        out += &(cells.join(",") + "\n");
    }
    // Fy's sweeps doubt the slip angle's unit: Fy and Mz (which shares it) are not
    // diagnosed, named; the file is not refused, and Fx is diagnosed.
    std::fs::write(dir.join("radians.csv"), out).unwrap();
    let run = tire_gap::<&OsStr>(&[
        "diagnose".as_ref(),
        dir.join("radians.csv").as_os_str(),
        "--json".as_ref(),
        "--stability-draws".as_ref(),
        "1".as_ref(),
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    let json: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let limitation = |subject: &str| {
        json["limitations"]
            .as_array()
            .unwrap()
            .iter()
            .find(|l| l["subject"] == subject)
            .map(|l| l["reason"].as_str().unwrap().to_string())
            .unwrap_or_default()
    };
    assert!(
        limitation("Fy").contains("the slip angle looks like radians under a degree unit"),
        "{}",
        limitation("Fy")
    );
    assert!(
        limitation("Mz").contains("its slip angle is Fy's"),
        "{}",
        limitation("Mz")
    );
    let diagnosed: Vec<&str> = json["baseline"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b["channel"].as_str().unwrap())
        .collect();
    assert_eq!(diagnosed, vec!["Fx"]);
}

#[test]
fn a_channel_at_its_noise_floor_has_no_share_of_a_gap() {
    let dir = scratch("hostile-inputs/no-gap");
    // The base tire is of the 1987 family: every channel fits to its noise floor.
    let input = write_as_csv(&dir, "data.csv", &rig(Vec::new(), TireKind::Mf87Perturbed));
    let out = tire_gap::<&OsStr>(&["diagnose".as_ref(), input.as_os_str(), "--json".as_ref()]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for b in json["baseline"].as_array().unwrap() {
        let reason = b["no_gap"].as_str().expect("a reason");
        assert!(reason.starts_with("no measurable gap"), "{reason}");
        assert!(b["noise_floor"].as_f64().unwrap() > 0.0);
    }
    // Nothing tested, ranked or confounded on a gap that is not there.
    assert_eq!(json["effects"].as_array().unwrap().len(), 0);
    assert_eq!(json["confounding"]["fits"].as_array().unwrap().len(), 0);
    assert_eq!(json["confounding"]["design"].as_array().unwrap().len(), 0);
    assert_eq!(json["gap_unexplained"].as_array().unwrap().len(), 0);
    assert_eq!(json["regions"].as_array().unwrap().len(), 0);
    for u in json["untestable"].as_array().unwrap() {
        assert!(
            u["reason"].as_str().unwrap().contains("no measurable gap"),
            "{u}"
        );
    }
    assert_eq!(json["limitations"].as_array().unwrap().len(), 3);
    assert_no_unexplained_null(&json, "");
    let out = tire_gap::<&OsStr>(&["diagnose".as_ref(), input.as_os_str()]);
    assert!(
        text(&out.stdout).contains(
            "Verdict: no diagnosed channel has a gap above its noise floor; there is nothing for an effect to explain."
        ),
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn input_notes_reach_the_report_and_the_json() {
    let dir = scratch("hostile-inputs/notes");
    let ds = rig(Vec::new(), TireKind::Mf87Perturbed);
    // No run column: runs are found where the time restarts (a note).
    let csv = std::fs::read_to_string(write_as_csv(&dir, "src.csv", &ds)).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let run = header.iter().position(|h| *h == "run").unwrap();
    let drop_run = |line: &str| {
        line.split(',')
            .enumerate()
            .filter(|(i, _)| *i != run)
            .map(|(_, c)| c)
            .collect::<Vec<_>>()
            .join(",")
    };
    let mut out = drop_run(&header.join(",")) + "\n";
    for line in lines {
        out += &(drop_run(line) + "\n");
    }
    let input = dir.join("no-run.csv");
    std::fs::write(&input, out).unwrap();
    std::fs::remove_file(dir.join("src.csv")).unwrap();
    let note = "no run column: split into 36 runs where t_s decreases";
    // stderr is a pipe here, not a terminal: the note is still everywhere.
    let report = tire_gap::<&OsStr>(&["diagnose".as_ref(), input.as_os_str()]);
    assert_eq!(report.status.code(), Some(0), "{}", text(&report.stderr));
    assert!(
        text(&report.stderr).contains(note),
        "{}",
        text(&report.stderr)
    );
    // ... and the progress bar is not: the notes are all stderr holds.
    assert!(
        text(&report.stderr)
            .lines()
            .all(|l| l.starts_with("tire-gap: note: ")),
        "{}",
        text(&report.stderr)
    );
    assert!(text(&report.stdout).contains("Notes on the input"));
    assert!(
        text(&report.stdout).contains(note),
        "{}",
        text(&report.stdout)
    );
    let json = tire_gap::<&OsStr>(&["diagnose".as_ref(), input.as_os_str(), "--json".as_ref()]);
    let json: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let notes = json["notes"].as_array().unwrap();
    assert!(
        notes.iter().any(|n| n.as_str().unwrap().contains(note)),
        "{notes:?}"
    );
    assert_no_unexplained_null(&json, "");
}

/// A `null` in the JSON report only where a field is documented as optional: never a number
/// that could not be computed (serde writes NaN as `null`).
fn assert_no_unexplained_null(v: &serde_json::Value, path: &str) {
    const OPTIONAL: [&str; 13] = [
        "no_gap",
        "reference",
        "reference_closes",
        "verdict_closes",
        "share_of_reference",
        "not_scored",
        "gap_closed",
        "base_gap_closed",
        "p_adjusted",
        "selected",
        "error",
        "correction_correlation",
        "in_sample_rms",
    ];
    match v {
        serde_json::Value::Null => {
            let mut segments = path.rsplit('.');
            let key = segments.next().unwrap_or("");
            // Per-channel maps of optional values: `gap_closed_by_channel.Fy`.
            let parent = segments.next().unwrap_or("");
            let per_channel = ["gap_closed_by_channel", "p_adjusted"].contains(&parent);
            assert!(OPTIONAL.contains(&key) || per_channel, "null at {path}");
            if key == "in_sample_rms" {
                assert!(path.starts_with(".remaining"), "null at {path}");
            }
        }
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                assert_no_unexplained_null(x, &format!("{path}.{k}"));
            }
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                assert_no_unexplained_null(x, &format!("{path}[{i}]"));
            }
        }
        _ => {}
    }
}

#[test]
fn output_paths_are_checked_before_the_work() {
    let dir = scratch("hostile-inputs/outputs");
    let input = write_as_csv(&dir, "data.csv", &rig(Vec::new(), TireKind::Mf87Perturbed));
    let before = std::fs::read(&input).unwrap();
    let run = |params: &Path| {
        tire_gap::<&OsStr>(&[
            "diagnose".as_ref(),
            input.as_os_str(),
            "--params".as_ref(),
            params.as_os_str(),
        ])
    };
    // A directory: refused, and no DIR.partial beside it.
    let sub = dir.join("fitted");
    std::fs::create_dir(&sub).unwrap();
    let out = run(&sub);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("is a directory"),
        "{}",
        text(&out.stderr)
    );
    assert!(out.stdout.is_empty());
    // The input itself, also by another name: refused, the data untouched.
    for same in [input.clone(), dir.join(".").join("data.csv")] {
        let out = run(&same);
        assert_eq!(out.status.code(), Some(2));
        assert!(
            text(&out.stderr).contains("is the input file"),
            "{}",
            text(&out.stderr)
        );
        assert!(out.stdout.is_empty());
    }
    assert_eq!(std::fs::read(&input).unwrap(), before);
    // A missing directory: refused before any work.
    let out = run(&dir.join("missing/fitted.json"));
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("does not exist"),
        "{}",
        text(&out.stderr)
    );
    assert!(out.stdout.is_empty());
    assert_eq!(listing(&dir), vec!["data.csv", "fitted"]);
    assert!(listing(&sub).is_empty());
}

#[test]
fn a_fit_the_fmu_rejects_is_reported_with_the_report() {
    let dir = scratch("hostile-inputs/rejected-fit");
    let ds = rig(Vec::new(), TireKind::Mf87Perturbed);
    let mut d = diagnose(&ds, &Options::default(), &Unobserved).unwrap();
    // A camber coefficient past its singularity inside the camber range.
    let fy = d
        .models
        .iter_mut()
        .find(|m| m.channel == mf87::Channel::Fy)
        .unwrap();
    let a13 = fy.names().iter().position(|n| n == "Fy.a13").unwrap();
    let mut theta = fy.theta();
    theta[a13] = 0.5;
    *fy = fy.updated(&theta);
    let finished = Finished {
        diagnosis: d,
        dataset: ds,
        provenance: Provenance {
            input: "data.csv".into(),
            input_sha256: String::new(),
            inputs: Vec::new(),
            split_seed: 1,
            folds: 5,
            tool: "tire-gap",
            version: "test",
        },
        notes: Vec::new(),
    };
    let status = finished.write_params(&dir.join("fitted.json"));
    let error = status.error.clone().unwrap();
    assert!(!status.written);
    assert!(
        error.starts_with("the fitted model is not a parameter file the FMU accepts")
            && error.contains("parameter Fy.a13 = 0.5"),
        "{error}"
    );
    assert!(listing(&dir).is_empty());
    // The report names it, in text and JSON.
    let report = finished.text(vec![status.clone()]);
    assert!(
        report.contains(&format!(
            "params {}: NOT WRITTEN: {error}",
            dir.join("fitted.json").display()
        )),
        "{report}"
    );
    let json: serde_json::Value = serde_json::from_str(&finished.json(vec![status])).unwrap();
    assert_eq!(json["outputs"][0]["written"], false);
    assert_eq!(json["outputs"][0]["error"], error);
}

#[test]
fn a_tydex_programme_in_a_directory_is_one_data_set_with_each_run_named() {
    let dir = scratch("hostile-inputs/programme");
    let prog = dir.join("prog");
    let out = tire_gap::<&OsStr>(&[
        "synth".as_ref(),
        "--tire".as_ref(),
        "mf87_perturbed".as_ref(),
        "--rows".as_ref(),
        "4000".as_ref(),
        "--format".as_ref(),
        "tydex".as_ref(),
        "--out".as_ref(),
        prog.as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    // A file named twice is refused: its runs would count twice.
    let first = prog.join("run_0001.tdx");
    let out = tire_gap::<&OsStr>(&["diagnose".as_ref(), prog.as_os_str(), first.as_os_str()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("the same file is given twice"));
    // The directory: every file, each its own run, named in the report.
    let out = tire_gap::<&OsStr>(&["diagnose".as_ref(), prog.as_os_str(), "--json".as_ref()]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let inputs = json["provenance"]["inputs"].as_array().unwrap();
    let files = listing(&prog);
    assert_eq!(inputs.len(), files.len());
    assert_eq!(json["runs"].as_u64().unwrap() as usize, files.len());
    for (i, f) in inputs.iter().enumerate() {
        assert!(f["file"].as_str().unwrap().ends_with(&files[i]));
        assert_eq!(f["format"], "tydex");
        assert_eq!(f["runs"].as_array().unwrap().len(), 1);
    }
    // A directory without data files is an error, not an empty data set.
    let empty = dir.join("empty");
    std::fs::create_dir(&empty).unwrap();
    let out = tire_gap::<&OsStr>(&["diagnose".as_ref(), empty.as_os_str()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("holds no .csv, .tdx or .dat file"));
}

#[test]
fn a_pipe_is_not_read() {
    let dir = scratch("hostile-inputs/fifo");
    let fifo = dir.join("data.csv");
    let status = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(status.success());
    // Would block forever if opened for reading.
    let out = tire_gap::<&OsStr>(&["diagnose".as_ref(), fifo.as_os_str()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("not a regular file"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn an_unknown_candidate_effect_is_refused_before_any_work() {
    let out = tire_gap::<&OsStr>(&[
        "diagnose".as_ref(),
        "missing.csv".as_ref(),
        "--effects".as_ref(),
        "temperature,warp".as_ref(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = text(&out.stderr);
    assert!(
        err.contains("unknown effect `warp`; known: combined_slip, relaxation_length"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

/// An observer that asks the work to stop after `after` steps, and counts the steps made.
struct StopAfter {
    after: usize,
    steps: std::sync::atomic::AtomicUsize,
}

impl tire_gap::method::observer::Observer for StopAfter {
    fn step(&self) {
        self.steps
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }

    fn cancelled(&self) -> bool {
        self.steps.load(std::sync::atomic::Ordering::Relaxed) >= self.after
    }
}

#[test]
fn a_cancelled_diagnosis_ends_early_with_its_own_outcome() {
    use tire_gap::method::diagnose::Stopped;
    let ds = rig(Vec::new(), TireKind::Mf87Perturbed);
    let run = |after| {
        let observer = StopAfter {
            after,
            steps: std::sync::atomic::AtomicUsize::new(0),
        };
        let outcome = diagnose(&ds, &Options::default(), &observer);
        (outcome, observer.steps.into_inner())
    };
    let (outcome, all) = run(usize::MAX);
    assert!(outcome.is_ok() && all > 20, "{all} steps");
    // Stopped within the base fit, halfway, or at the last step: the outcome is the
    // cancellation, not a failure or a report of part of the work.
    for after in [3, all / 2, all] {
        let (outcome, _) = run(after);
        assert!(
            matches!(outcome, Err(Stopped::Cancelled)),
            "stopped after {after} of {all} steps: not cancelled"
        );
    }
}
