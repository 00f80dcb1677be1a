#!/usr/bin/env python3
"""Benchmark: a full `tire-gap diagnose` (base fit, all candidates, cross-validation) against a
plain scipy.optimize.least_squares fit of the base 1987 model alone on the same data, and how
the diagnosis grows with the number of rows (wall time and peak memory of each process).

Usage (from the repository root, after `cargo build --release` and scripts/python-env.sh):
    .venv/bin/python benches/python/gap_vs_scipy.py [--rows 10000 35000 100000] [--effects temperature]

Each measurement runs in its own process; peak memory is that process's maximum resident set.
Above 2M rows the programme is written as run files of 2M rows each (a directory, diagnosed
together; e.g. --rows 10000000 gives five files).
With --profile, each diagnosis is also run under `perf record` (Linux perf, if installed) and
the functions with the largest share of its samples are printed: what dominates at that size.
The scipy fits use the independent formula of tests/python/magic_formula.py, start from the
paper's table (one start) and fit each channel's coefficients (all of them), once on all rows
(the rows the diagnosis fits) and once on the pure-slip rows only, set
up as scipy's documentation recommends for badly scaled problems: the trust-region reflective
method with the Jacobian's column norms as parameter scales (`method="trf", x_scale="jac"`),
2-point Jacobian. Their time is the fits' alone (data loading left out); in brackets, the
residual evaluations of Fx/Fy/Mz (scipy's `nfev`).
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
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


# Pure-slip rows: the other slip near zero (|kappa| < 1 % for Fy and Mz, |alpha| < 0.5 deg for Fx).
PURE_KAPPA, PURE_ALPHA_DEG = 0.01, 0.5


def scipy_fit(csv_path, rows):
    """The plain base fit on `rows` ("all" or "pure"); prints its own timing as JSON (run in
    a child process)."""
    import numpy as np
    from scipy.optimize import least_squares

    sys.path.insert(0, str(REPO / "tests" / "python"))
    import magic_formula as mf

    data = np.genfromtxt(csv_path, delimiter=",", names=True)
    everywhere = np.ones(len(data), dtype=bool)
    lateral = np.abs(data["kappa"]) < PURE_KAPPA if rows == "pure" else everywhere
    longitudinal = np.abs(data["alpha_deg"]) < PURE_ALPHA_DEG if rows == "pure" else everywhere
    fz_kn = data["fz_N"] / 1000.0
    alpha, gamma, sigma = data["alpha_deg"], data["gamma_deg"], 100.0 * data["kappa"]
    table = mf.paper_table()
    start = time.perf_counter()
    channels = {
        "Fx": (lambda p, m: mf.fx_paper(p, fz_kn[m], sigma[m]), data["fx_N"], longitudinal),
        "Fy": (lambda p, m: mf.fy_paper(p, fz_kn[m], alpha[m], gamma[m]), data["fy_N"], lateral),
        "Mz": (lambda p, m: mf.mz_paper(p, fz_kn[m], alpha[m], gamma[m]), data["mz_Nm"], lateral),
    }
    result = {}
    for name, (model, measured_values, m) in channels.items():
        keys = list(table[name])
        x0 = np.array([table[name][k] for k in keys])

        def residuals(x, name=name, keys=keys, model=model, y=measured_values[m], m=m):
            p = mf.paper_table()
            p[name] = dict(zip(keys, x))
            return model(p, m) - y

        fit = least_squares(residuals, x0, method="trf", x_scale="jac")
        result[name] = {
            "rows": int(m.sum()),
            "rms": float(np.sqrt(np.mean(fit.fun**2))),
            "nfev": int(fit.nfev),
            "status": int(fit.status),
        }
    result["seconds"] = time.perf_counter() - start
    print(json.dumps(result))


def profile(csv_path, top=6):
    """The functions taking the largest shares of a diagnosis's CPU samples (perf)."""
    import shutil

    if shutil.which("perf") is None:
        return ["perf is not installed: no profile"]
    with tempfile.TemporaryDirectory() as tmp:
        data = Path(tmp) / "perf.data"
        subprocess.run(
            ["perf", "record", "-F", "99", "-o", data, TIRE_GAP, "diagnose", csv_path, "--json"],
            check=True,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        report = subprocess.run(
            ["perf", "report", "-i", data, "--no-children", "--sort", "symbol", "--stdio"],
            check=True,
            capture_output=True,
            text=True,
        ).stdout
    lines = []
    for line in report.splitlines():
        parts = line.split()
        if len(parts) >= 3 and parts[0].endswith("%") and not line.startswith("#"):
            lines.append(f"{parts[0]:>7} {' '.join(parts[2:])[:90]}")
        if len(lines) == top:
            break
    return lines


# Above this many rows a programme is written as run files of this size (seeds 1, 2, ...) in
# one directory and diagnosed together, as a season of test data would be.
ROWS_PER_FILE = 2_000_000


def synthetic_programme(tmp, rows, effects):
    """A synthetic programme of `rows` rows: one CSV file, or a directory of CSV files."""
    if rows <= ROWS_PER_FILE:
        path = tmp / f"rig{rows}.csv"
        files = [(path, rows, 1)]
    else:
        path = tmp / f"rig{rows}"
        path.mkdir()
        count = -(-rows // ROWS_PER_FILE)
        files = [(path / f"part{k + 1}.csv", rows // count, k + 1) for k in range(count)]
    for file, n, seed in files:
        subprocess.run(
            [TIRE_GAP, "synth", "--seed", str(seed), "--rows", str(n), "--effects", effects, "--out", file],
            check=True,
        )
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rows", type=int, nargs="+", default=[10_000, 35_000, 100_000])
    parser.add_argument("--effects", default="temperature")
    parser.add_argument(
        "--scipy-max-rows",
        type=int,
        default=1_000_000,
        help="skip the scipy fits above this many rows (they hold the data several times in memory)",
    )
    parser.add_argument(
        "--scipy-fits",
        choices=["both", "pure"],
        default="both",
        help="the scipy fits to run: on all rows and on the pure-slip rows, or on the pure-slip rows only",
    )
    parser.add_argument("--profile", action="store_true", help="also profile each diagnosis with perf")
    parser.add_argument("--scipy-fit", help=argparse.SUPPRESS)
    parser.add_argument("--scipy-rows", choices=["all", "pure"], default="all", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.scipy_fit:
        return scipy_fit(args.scipy_fit, args.scipy_rows)
    if not TIRE_GAP.is_file():
        sys.exit(f"{TIRE_GAP} is missing: run `cargo build --release` first")
    print(
        f"{'rows':>9} {'tire-gap diagnose':>18} {'peak MiB':>9}"
        f" {'scipy fit, all rows':>20} {'scipy fit, pure slip':>21}"
    )
    with tempfile.TemporaryDirectory() as tmp:
        for rows in args.rows:
            csv_path = synthetic_programme(Path(tmp), rows, args.effects)
            t_gap, rss_gap, _ = measured_child([TIRE_GAP, "diagnose", csv_path, "--json"])
            fits = []
            for which in ["all", "pure"]:
                if (
                    rows > args.scipy_max_rows
                    or csv_path.is_dir()
                    or (which == "all" and args.scipy_fits == "pure")
                ):
                    fits.append("skipped")
                    continue
                _, _, out = measured_child(
                    [sys.executable, __file__, "--scipy-fit", csv_path, "--scipy-rows", which]
                )
                fit = json.loads(out)
                nfev = "/".join(str(fit[c]["nfev"]) for c in ["Fx", "Fy", "Mz"])
                fits.append(f"{fit['seconds']:.1f} s ({nfev})")
            print(f"{rows:>9} {t_gap:>16.1f} s {rss_gap:>9.0f} {fits[0]:>20} {fits[1]:>21}", flush=True)
            if args.profile:
                for line in profile(csv_path):
                    print(f"{'':>9} {line}", flush=True)


if __name__ == "__main__":
    main()
