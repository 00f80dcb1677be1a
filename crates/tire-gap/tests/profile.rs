//! `tire-gap diagnose --profile`: where the time went, on stderr, beside an unchanged report.

mod common;

use common::{scratch, tire_gap};

#[test]
fn a_profile_counts_the_rows_evaluated_and_prices_them_beside_the_report() {
    let dir = scratch("profile-tests");
    let csv = dir.join("rig.csv");
    let made = tire_gap(&[
        "synth",
        "--seed",
        "5",
        "--rows",
        "3000",
        "--effects",
        "inflation_pressure",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert!(made.status.success());
    let args = [
        "diagnose",
        csv.to_str().unwrap(),
        "--json",
        "--stability-draws",
        "1",
        "--effects",
        "inflation_pressure",
    ];
    let plain = tire_gap(&args);
    let profiled = tire_gap(&[&args[..], &["--profile"]].concat());
    assert!(profiled.status.success());
    // The report is the same with or without a profile (bar the input's path, which is).
    let report = |o: &std::process::Output| -> serde_json::Value {
        let mut v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        v.as_object_mut().unwrap().remove("provenance");
        v
    };
    assert_eq!(report(&plain), report(&profiled));
    let err = String::from_utf8_lossy(&profiled.stderr);
    assert!(!String::from_utf8_lossy(&plain.stderr).contains("profile:"));
    assert!(err.contains("fitting the 1987 model"), "{err}");
    // Every fit evaluates each of the 3000 rows at least once for values and once for
    // derivatives.
    let millions = |label: &str| -> f64 {
        let after = err.split("1987 model: rows").nth(1).unwrap();
        let cell = after.split(label).nth(1).unwrap();
        cell.split([',', '\n', '('])
            .next()
            .unwrap()
            .trim()
            .parse()
            .unwrap()
    };
    assert!(millions("values ") >= 0.003, "{err}");
    let share: f64 = err
        .split("thread-seconds: ")
        .nth(1)
        .and_then(|t| t.split(" %").next())
        .and_then(|t| t.parse().ok())
        .unwrap();
    // Its size depends on the machine's load (the bare rate is timed at the end); it is a
    // share of real time spent.
    assert!(share > 0.0 && share.is_finite(), "{err}");
}
