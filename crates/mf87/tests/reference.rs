//! The model against the independent reference values (`tests/data/mf87_reference.csv`,
//! computed independently of this code from the reading of the paper in docs/errata.md).

use std::path::PathBuf;

use mf87::{Inputs, Params, SignConvention, evaluate, units};

fn reference_csv() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/mf87_reference.csv")
}

#[test]
fn every_reference_row_within_1e8_relative() {
    let path = reference_csv();
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("reference values {} not readable: {e}", path.display()));
    let mut lines = text.lines();
    assert_eq!(
        lines.next().map(str::trim),
        Some("fz_N,alpha_deg,gamma_deg,kappa_pct,fx_N,fy_N,mz_Nm")
    );
    let params = Params::paper_table();
    let mut rows = 0;
    for (n, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let v: Vec<f64> = line.split(',').map(|c| c.trim().parse().unwrap()).collect();
        let [fz, alpha_deg, gamma_deg, kappa_pct, fx, fy, mz] = v[..] else {
            panic!("line {}: expected 7 columns", n + 2);
        };
        let inputs = Inputs {
            fz,
            alpha: units::degrees_to_radians(alpha_deg),
            kappa: units::percent_to_slip_ratio(kappa_pct),
            gamma: units::degrees_to_radians(gamma_deg),
        };
        let out = evaluate(&params, &inputs, SignConvention::Paper);
        for (what, got, want, floor) in [
            ("Fx", out.fx, fx, 1.0),
            ("Fy", out.fy, fy, 1.0),
            ("Mz", out.mz, mz, 0.01),
        ] {
            let err = (got - want).abs() / want.abs().max(floor);
            assert!(
                err <= 1e-8,
                "line {}: {what} = {got}, reference {want} (relative error {err:e}) at {line}",
                n + 2
            );
        }
        rows += 1;
    }
    assert_eq!(rows, 455, "the reference file holds 455 points");
}
