#!/usr/bin/env python3
"""Benchmark: a full `tire-gap diagnose` (base fit, all candidates, cross-validation) against a
plain scipy.optimize.least_squares fit of the base 1987 model alone on the same data, and how
the diagnosis grows with the number of rows (wall time and peak memory of each process).

Usage (from the repository root, after `cargo build --release` and scripts/python-env.sh):
    .venv/bin/python benchmarks/gap_vs_scipy.py [--rows 10000 35000 100000] [--effects temperature]

Each measurement runs in its own process; peak memory is that process's maximum resident set.
The scipy fit uses the independent formula of tests/python/magic_formula.py, starts from the
paper's table (one start), fits each channel's coefficients (all of them) with the default
trust-region method and a 2-point Jacobian.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
TIRE_GAP = REPO / "target" / "release" / "tire-gap"


def measured_child(cmd):
    """Runs `cmd`; returns (wall seconds, the child's own peak RSS in MiB, stdout)."""
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    elapsed = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed")
    return elapsed, usage.ru_maxrss / 1024, out.decode()


def scipy_fit(csv_path):
    """The plain base fit; prints its own timing as JSON (run in a child process)."""
    import numpy as np
    from scipy.optimize import least_squares

    sys.path.insert(0, str(REPO / "tests" / "python"))
    import magic_formula as mf

    data = np.genfromtxt(csv_path, delimiter=",", names=True)
    fz_kn = data["fz_N"] / 1000.0
    alpha, gamma, sigma = data["alpha_deg"], data["gamma_deg"], 100.0 * data["kappa"]
    table = mf.paper_table()
    start = time.perf_counter()
    channels = {
        "Fx": (lambda p: mf.fx_paper(p, fz_kn, sigma), data["fx_N"]),
        "Fy": (lambda p: mf.fy_paper(p, fz_kn, alpha, gamma), data["fy_N"]),
        "Mz": (lambda p: mf.mz_paper(p, fz_kn, alpha, gamma), data["mz_Nm"]),
    }
    result = {}
    for name, (model, measured_values) in channels.items():
        keys = list(table[name])
        x0 = np.array([table[name][k] for k in keys])

        def residuals(x, name=name, keys=keys, model=model, y=measured_values):
            p = mf.paper_table()
            p[name] = dict(zip(keys, x))
            return model(p) - y

        fit = least_squares(residuals, x0)
        result[name] = {"rms": float(np.sqrt(np.mean(fit.fun**2))), "nfev": int(fit.nfev)}
    result["seconds"] = time.perf_counter() - start
    print(json.dumps(result))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rows", type=int, nargs="+", default=[10_000, 35_000, 100_000])
    parser.add_argument("--effects", default="temperature")
    parser.add_argument("--scipy-fit", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.scipy_fit:
        return scipy_fit(args.scipy_fit)
    if not TIRE_GAP.is_file():
        sys.exit(f"{TIRE_GAP} is missing: run `cargo build --release` first")
    print(f"{'rows':>8} {'tire-gap diagnose':>20} {'peak MiB':>9} {'scipy base fit':>16} {'peak MiB':>9} {'ratio':>6}")
    with tempfile.TemporaryDirectory() as tmp:
        for rows in args.rows:
            csv_path = Path(tmp) / f"rig{rows}.csv"
            subprocess.run(
                [TIRE_GAP, "synth", "--seed", "1", "--rows", str(rows), "--effects", args.effects, "--out", csv_path],
                check=True,
            )
            t_gap, rss_gap, _ = measured_child([TIRE_GAP, "diagnose", csv_path, "--json"])
            t_py, rss_py, out = measured_child([sys.executable, __file__, "--scipy-fit", csv_path])
            fit_seconds = json.loads(out)["seconds"]
            print(
                f"{rows:>8} {t_gap:>18.1f} s {rss_gap:>9.0f} {t_py:>11.1f} s ({fit_seconds:.1f} fit) {rss_py:>9.0f}"
                f" {t_gap / t_py:>6.2f}",
                flush=True,
            )


if __name__ == "__main__":
    main()
